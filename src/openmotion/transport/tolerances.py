"""The CA group's tolerances (TF5410 collision avoidance on a rail), each named once (ruckig
names its precisions by quantity in the same way). Units: mm and s. The gap checks
themselves use the engine's (rail/tolerances.py)."""

LIMIT_TOLERANCE = 1e-9  #: relative: a deceleration this far beyond its limit is on it
FIT_SLACK = 1 + 1e-12  #: relative float slack when a step is checked against the limits
REST_SHARE = 1e-9  #: velocity and acceleration below this share of their maxima is rest
STANDBY_DISTANCE = 1e-6  #: [mm] an idle mover further than this from its room moves aside
JOINT_TOLERANCE = 1e-9  #: [mm] parts of a track closer than this join
