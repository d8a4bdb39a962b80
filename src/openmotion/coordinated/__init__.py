"""PLCopen Part 4 coordinated motion: frames and kinematics for axes groups."""
