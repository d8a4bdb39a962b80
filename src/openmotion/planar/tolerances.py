"""The planar system's tolerances, each named once with its unit, as ruckig names its
precisions (``p_precision``, ``v_precision``): the quantity first, then what it absorbs.

The float slack of the gap checks between movers on tracks is the rail's
(``openmotion.rail.gap_control.TOLERANCE``, 1e-9 mm): the same checks, so the same value
under one name, imported from there. A relative velocity slack of the plans is the
trajectory's (``openmotion.trajectory.plan.VELOCITY_TOLERANCE``).
"""

from __future__ import annotations

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
REST_PRECISION = 1e-9
#: [mm/s] the smallest velocity limit of a stop planned to the end of a way
MIN_STOP_VELOCITY = 1e-9
