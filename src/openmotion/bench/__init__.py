"""Benchmarks for openmotion and the peer implementations it is measured against."""
