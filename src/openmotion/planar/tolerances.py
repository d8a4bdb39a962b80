"""The planar layer's tolerances, each named once with its unit, as ruckig names its
precisions (``p_precision``, ``v_precision``): the quantity first, then what it absorbs.

A tolerance says how close two values may be and still count as the same: float residue of an
evaluated profile, rounding of a shapely operation, a corner that snaps to the stator grid.
The value of each is part of the behaviour (golden traces depend on it); change one only with
a decision in docs/decisions.md.

The float slack of the gap checks between movers on tracks is the rail's
(``openmotion.rail.gap_control.TOLERANCE``, 1e-9 mm): the same checks, so the same value
under one name, imported from there. A relative velocity slack of the plans is the
trajectory's (``openmotion.trajectory.plan.VELOCITY_TOLERANCE``).
"""

from __future__ import annotations

# -- geometry: parts, stators, footprints, tracks ----------------------------------------------
PART_TOLERANCE = 1e-6  #: a point this close [mm] is on a part; a smaller overlap [mm²] is none
GRID_TOLERANCE = 1e-6  #: how far a corner may lie off the stator grid and still snap [mm]
SURFACE_TOLERANCE = 1e-6  #: how far a footprint may overhang the stators (rounding) [mm]
DISTANCE_NOISE = 1e-9  #: distances below this are rounding noise [mm]
MEET_DISTANCE = 1e-3  #: [mm] track ends on two parts this close meet (boundaries touch)

# -- time ----------------------------------------------------------------------------------------
SAMPLE_TIME_PRECISION = 1e-12  #: [s] sample times closer than this to the one before are one
SYNC_TIME_PRECISION = 1e-9  #: [s] path and C ending this close together end together
PREDICTION_MARGIN = 1e-6  #: [s] closed-form durations further apart tell the faster motion
PREDICTION_TIME = 1e-3  #: [s] moves quicker than this are planned both ways (no prediction)
PREDICTION_DISTANCE = 1e-6  #: [mm], [°] shorter moves are planned both ways (no prediction)

# -- relative to a limit or a peak ---------------------------------------------------------------
REST_PRECISION = 1e-12  #: relative to its limit, a smaller velocity or acceleration is rest
ACROSS_PRECISION = 1e-9  #: relative to its limit, a smaller component across the line is residue
PATH_PRECISION = 1e-9  #: relative: float residue of an extremum is no position-limit breach
VELOCITY_PRECISION = 1e-9  #: relative: an external setpoint this far above its maximum is residue
COUNTER_RESIDUE = 1e-9  #: relative to its peak, a velocity against the motion is float residue

# -- rotation ------------------------------------------------------------------------------------
ANGLE_PRECISION = 1e-9  #: [°] float residue of evaluated setpoints is not a C window exit

# -- movers on tracks (traffic) -------------------------------------------------------------
#: [mm] a motion on a track that ends no further than this past the end of its way (or
#: before its start) stays on it; legs of two routes that start this close are one place
WAY_PRECISION = 1e-6
#: [mm] a rider this close to the end of its track's leg has passed onto the next leg
TRACK_END_PRECISION = 1e-12
#: relative: a state within its limits times (1 + this) is within them (the tracking step
#: of a held rider and the release check of its fresh profile)
LIMIT_PRECISION = 1e-12
#: relative to the velocity (acceleration) limit: a tracking step this slow is rest (float
#: residue of the constant-jerk steps), and a release this far below 0 does not turn round
TRACKING_REST_PRECISION = 1e-9
#: [mm/s] the smallest velocity limit of a stop planned to the end of a way
MIN_STOP_VELOCITY = 1e-9
