"""The cyclic task with virtual time."""
