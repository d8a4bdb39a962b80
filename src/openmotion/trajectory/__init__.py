"""Time-optimal jerk-limited planning (ruckig) and bulk evaluation of stored segments."""
