"""Benchmarks for openmotion and the peer implementations it is measured against."""

#: every ``openmotion bench NAME`` (the runner holds their functions; this list stays cheap
#: to import so that the CLI's help and errors name them without loading the benchmarks)
BENCHMARK_NAMES = ("axes", "otg", "fbcall", "ca", "planar", "path", "tracks", "trace",
                   "startup", "sweep", "serve", "envs", "routing")
