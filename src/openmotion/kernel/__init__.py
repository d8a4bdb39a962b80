"""The kernel every system shares: the cyclic runtime with virtual time and the System contract."""
