"""The 1-D multi-mover engine's tolerances (gap control, braking, gear sync), each named once
(ruckig names its precisions by quantity in the same way). Units: mm and s."""

TOLERANCE = 1e-9  #: [mm] float slack of the gap and pair checks
BOUND_MARGIN = 1e-6  #: [mm] a lower bound this far above a threshold settles the check
LIMIT_SLACK = 1 + 1e-12  #: relative float slack of the brake envelope's limit checks
PHASE_END_TOLERANCE = 1e-15  #: [s] a brake phase this close to its end has ended
RELATIVE_TOLERANCE = 1e-9  #: relative slack of the gear sync's velocity and signal checks
SIGNAL_TOLERANCE = 1e-9  #: relative: the master signal check's slack on top of its jerk (D-205)
PROFILE_END_TOLERANCE = 1e-12  #: [s] a sync profile this close to its end has ended
SAMPLE_TIME_TOLERANCE = 1e-6  #: share of a cycle: a master sample this close is the cycle's
