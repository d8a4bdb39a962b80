"""Path geometry for coordinated motion: lines, arcs and blend contours (PLCopen Part 4)."""
