"""The coordinated-motion layer's tolerances, each named once (ruckig names its precisions by
quantity in the same way): round-off within these is no event. Units: mm, s, rad."""

# -- the path time law (timing.py, timing_kernels.py) ----------------------------------------
RELATIVE_TOLERANCE = 1e-9  #: relative slack of the checks on ruckig's profiles, caps and brakes
SPEED_FLOOR = 1e-9  #: [mm/s] a reversal check scales with the speed, at least this one
ABSOLUTE_SLACK = 1e-12  #: [mm or mm/s] added where a relative check meets zero
LENGTH_TOLERANCE = 1e-12  #: relative: a speed change may end this far past its length
ZERO_ACCELERATION = 1e-10  #: |a| below this share of the caps is round-off, not a state

# -- path commands (moves.py, requests.py, path_table.py, tracking.py) -----------------------
ORIENTATION_TOLERANCE = 1e-9  #: a path move changing a, b or c by less keeps the orientation
TAKE_OVER_TOLERANCE = 1e-6  #: tangent [1] and curvature [1/mm] a halted path is taken over at
JOIN_SLACK = 1e-9  #: relative: the speed now may lie this far above the lead-out's cap
MIN_CORNER_DISTANCE = 1e-6  #: [mm] a TM_START_VELOCITY contour leaves the corner this far at least
CLOSED_PATH_TOLERANCE = 1e-6  #: [mm] a periodic cam's path ends this close to its start
DWELL_SLACK = 1e-9  #: [s] a dwell is over once the clock is within this of its end
LOCK_SLACK = 1e-9  #: a ramp-in that ends within this share past the cycle ends in it

# -- frames and kinematics (frames.py, kinematics.py, limits.py) -------------------------------
ORTHONORMAL_TOLERANCE = 1e-9  #: how far R^T R may be from the identity for a Frame
GIMBAL_LOCK = 1e-12  #: cos(rot_angle2) below this: rot_angle1 and rot_angle3 share one axis
REACH_TOLERANCE = 1e-9  #: [mm] rounding beyond the workspace border still counts as inside
AXIS_LIMIT_TOLERANCE = 1e-9  #: [mm or °] rounding beyond an axis limit counts as on it
UNDRIVEN = 1e-9  #: largest |tangent| along a coordinate that no axis drives
