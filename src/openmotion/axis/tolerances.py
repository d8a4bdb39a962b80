"""The single-axis layer's tolerances and floors, each named once (ruckig names its
precisions by quantity in the same way). Float round-off within these is no event: no limit
passed, no reversal, no overshoot. Units: mm (or °) and s."""

LIMIT_TOLERANCE = 1e-9  #: relative: a value this far beyond a maximum or a commanded value is on it
POSITION_TOLERANCE = 1e-9  #: [mm] per mm of position (at least 1): closer is at a target or limit
VELOCITY_TOLERANCE = 1e-9  #: [mm/s] against the direction of travel: less is no reversal
TIME_TOLERANCE = 1e-9  #: [s] per s of clock (at least 1): closer is at the instant
BUDGET_TOLERANCE = 1e-12  #: relative: a superposition this far over its time budget fits it
LAG_FILTER_TOLERANCE = 1e-12  #: [s] a following error lasting this much past its filter time
MIN_SPEED = 1e-9  #: [mm/s] a planned velocity limit is at least this (the planner needs > 0)
MIN_OVERRIDE = 1e-8  #: below 1e-6 % the override counts as 0: the job pauses (D-007)
ROOM_FLOOR = 1e-6  #: less room than this fraction of a maximum counts as none (D-180)
