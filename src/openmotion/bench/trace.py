"""``openmotion bench trace``: what recording costs per signal-sample, and whether 100 axes
with 100 recorded signals at a 1 ms cycle stay faster than real time.

Part 1, the recorder alone: ``TraceRecorder.sample`` called ``samples`` times on a standing
runtime, per kind of signal (the buffer is preallocated, so growing it is not counted):

- ``kernel``: axis set_position (the kinematic axis signals are read from the kernel's arrays
  in one numpy gather per signal name), for 10, 100 and 1000 signals;
- ``axis state``: one reader call per signal (state, override, gap, ... of an axis);
- ``planar``: x, y, c of planar movers, one reader call per signal.

Part 2, the goal: 100 axes under the random command stream of ``bench axes`` (2 commands per
axis and second, issued from a program), ``cycles`` cycles of 1 ms, without a recorder, with
100 signals every cycle, and with the same 100 every 10th cycle. The 100 signals are what a
scope of a busy machine shows: set position and set velocity of 40 axes, following error of
10, state of 10. Figures are wall-time medians of ``repeats`` interleaved rounds (each
variant goes first once); the real-time factor is the cycle time over the wall time of one
cycle. The recorder's own time in the every-cycle runs (``sample_us``) is timed around each
call, so its per-signal figure does not drown in the noise of two whole runs.

Part 3, memory over a long run (issue 19 point 10, D-189): 100 signals (set position and
set velocity of 50 axes: the recorder's memory depends on the number of signals, not their
kind, and these are the cheapest to read) sampled ``memory_cycles`` times by calling
``TraceRecorder.sample`` directly (no motion, so that 10**7 samples take minutes), in
the bounded mode (``keep``: the last minute at 1 kHz, at most a tenth of the run), in the
streaming mode (chunks into a temporary directory, removed afterwards; a chunk is at most a
tenth of the run) and, for contrast, unbounded (at most UNBOUNDED_CYCLES samples), each in
a process of its own. That process's resident memory (RSS) above what it held before the
recorder was built is read at CHECKPOINTS even intervals; memory is flat when
it grows by less than FLAT_MB after the first tenth of the run (the ring or the first chunk
has filled by then).
"""

from __future__ import annotations

import gc
import multiprocessing
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import openmotion as om
from openmotion.bench import peers
from openmotion.bench.axes import build_runtime, issue_plan
from openmotion.planar import MC_PlanarMover, MoverVector, PlanarMoverParameters
from openmotion.trace import TraceRecorder
from openmotion.trace.stream import default_chunk

Progress = Callable[[str], None] | None
CYCLE_TIME = 0.001
GOAL_AXES = 100
GOAL_SIGNALS = 100
DECIMATION = 10  #: the third variant records every 10th cycle
REPEATS = 3
SAMPLE_VALUES = 4_000_000  #: values one sampling run writes at most
MEMORY_SIGNALS = 100  #: signals of the memory part
MEMORY_CYCLES = 1_000_000  #: samples of the memory part by default (``--cycles``)
KEEP_ROWS = 60_000  #: the bounded mode keeps the last minute at 1 kHz
UNBOUNDED_CYCLES = 200_000  #: the unbounded contrast stops here (it grows with the run)
CHECKPOINTS = 20  #: RSS readings per run
WARM_FRACTION = 0.1  #: memory must be flat after this part of the run
FLAT_MB = 16.0  #: growth after the warm part that still counts as flat [MiB]
MIB = 1 << 20


def goal_signals(axes: Sequence[str]) -> list[str]:
    """The goal's 100 signals over the first 60 of ``axes`` (see the module docstring)."""
    return ([f"{name}.{prop}" for name in axes[:40] for prop in ("set_position", "set_velocity")]
            + [f"{name}.following_error" for name in axes[40:50]]
            + [f"{name}.state" for name in axes[50:60]])


def samples_for(count: int, samples: int) -> int:
    """Samples per run for ``count`` signals: ``samples``, fewer for wide traces (at most
    SAMPLE_VALUES values per run, so the preallocated buffer stays small)."""
    return max(100, min(samples, SAMPLE_VALUES // count))


def _sampling(kind: str, count: int, samples: int) -> dict[str, Any]:
    """µs per sample and per signal-sample for ``count`` signals of one kind (median of
    REPEATS runs of ``samples`` calls each into one preallocated buffer)."""
    rt = om.Runtime(cycle_time=CYCLE_TIME)
    objects: list[Any] = []
    if kind == "planar":
        movers = -(-count // 3)
        objects = [MC_PlanarMover(rt, PlanarMoverParameters(
            initial_position=MoverVector(200.0 * i, 0.0, 0.0, 0.0, 0.0, 0.0)), f"m{i}")
            for i in range(movers)]
        signals = [f"m{i}.{prop}" for i in range(movers) for prop in ("x", "y", "c")][:count]
    else:
        for i in range(count):
            rt.add_axis(f"a{i}")
        prop = "set_position" if kind == "kernel" else "state"
        signals = [f"a{i}.{prop}" for i in range(count)]
    samples = samples_for(count, samples)
    recorder = TraceRecorder(rt, signals, capacity=REPEATS * samples, objects=objects)
    timings = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        for _ in range(samples):
            recorder.sample(rt)
        timings.append((time.perf_counter() - start) / samples * 1e6)
    sample_us = statistics.median(timings)
    return {"kind": kind, "signals": count, "samples": samples, "sample_us": sample_us,
            "signal_sample_us": sample_us / count}


def _timed_cycles(cycles: int, every: int | None, seed: int) -> tuple[float, float]:
    """Wall seconds of ``cycles`` steps of the goal machine, and of them the seconds spent
    in the recorder (timed around each call); ``every`` None: no recorder."""
    rt, axes = build_runtime(GOAL_AXES)
    stream = peers.random_command_stream(GOAL_AXES, cycles, seed)
    slots = iter(issue_plan(axes, stream, cycles))

    def program() -> None:
        for method, args in next(slots):
            method(*args)

    rt.add_program(program)
    clock, recording = time.perf_counter, [0.0]
    if every is not None:
        recorder = TraceRecorder(rt, goal_signals([axis.name for axis in axes]), every,
                                 capacity=cycles // every + 2)
        recorder.sample(rt)

        def observe(runtime: om.Runtime) -> None:
            start = clock()
            recorder(runtime)
            recording[0] += clock() - start

        rt.add_observer(observe)
    step = rt.step
    start = clock()
    for _ in range(cycles):
        step()
    return clock() - start, recording[0]


def _goal(cycles: int, seed: int, progress: Progress) -> dict[str, Any]:
    variants = {"off": None, "every_cycle": 1, f"every_{DECIMATION}": DECIMATION}
    seconds: dict[str, list[float]] = {name: [] for name in variants}
    recording: list[float] = []
    _timed_cycles(min(cycles, 300), 1, seed + 1)  # warm-up: imports, caches, first plans
    for round_ in range(REPEATS):
        if progress is not None:
            progress(f"trace: {GOAL_AXES} axes, {cycles} cycles, round {round_ + 1}/{REPEATS}")
        names = list(variants)
        for name in names[round_ % 3:] + names[:round_ % 3]:  # each variant first once
            wall, spent = _timed_cycles(cycles, variants[name], seed)
            seconds[name].append(wall)
            if name == "every_cycle":
                recording.append(spent)
    cycle_us = {name: statistics.median(values) / cycles * 1e6
                for name, values in seconds.items()}
    sample_us = statistics.median(recording) / (cycles + 1) * 1e6
    on = cycle_us["every_cycle"]
    return {"axes": GOAL_AXES, "signals": GOAL_SIGNALS, "cycles": cycles,
            "cycle_time_us": CYCLE_TIME * 1e6, "cycle_us": cycle_us,
            "sample_us": sample_us, "signal_sample_us": sample_us / GOAL_SIGNALS,
            "real_time_factor": {name: CYCLE_TIME * 1e6 / value
                                 for name, value in cycle_us.items()},
            "faster_than_real_time": on < CYCLE_TIME * 1e6}


def rss_bytes() -> int:
    """The process's resident memory now (Linux: /proc/self/statm), else its peak so far."""
    import resource  # Unix only, as are the figures of this benchmark

    try:
        with open("/proc/self/statm", encoding="ascii") as file:
            return int(file.read().split()[1]) * resource.getpagesize()
    except (OSError, ValueError, IndexError):
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        return peak if sys.platform == "darwin" else peak * 1024


def _memory(mode: str, cycles: int, directory: Path) -> dict[str, Any]:
    """RSS over ``cycles`` samples of the goal's signals in one mode (the module docstring)."""
    rt, axes = build_runtime(MEMORY_SIGNALS // 2)
    signals = [f"{axis.name}.{prop}" for axis in axes for prop in ("set_position",
                                                                   "set_velocity")]
    rows = max(1, int(cycles * WARM_FRACTION))
    options: dict[str, Any] = {"keep": min(KEEP_ROWS, rows)} if mode == "bounded" else \
        {"stream": directory / "trace", "chunk": min(rows, default_chunk(len(signals) + 1))} \
        if mode == "streaming" else {}
    gc.collect()
    base = rss_bytes()
    recorder = TraceRecorder(rt, signals, **options)
    sample, every = recorder.sample, max(1, cycles // CHECKPOINTS)
    checkpoints: list[dict[str, float]] = []
    done, start = 0, time.perf_counter()
    while done < cycles:
        for _ in range(min(every, cycles - done)):
            sample(rt)
        done = min(cycles, done + every)
        checkpoints.append({"samples": done, "rss_mb": (rss_bytes() - base) / MIB,
                            "allocated_rows": recorder.allocated})
    seconds = time.perf_counter() - start
    recorder.flush()
    disk = sum(path.stat().st_size for path in directory.rglob("*") if path.is_file())
    warm = [point["rss_mb"] for point in checkpoints if point["samples"] >= rows] or \
        [checkpoints[-1]["rss_mb"]]
    options.pop("stream", None)  # a temporary directory: not a figure
    return {"mode": mode, "samples": cycles, "signals": len(signals), **options,
            "sample_us": seconds / cycles * 1e6, "rss_mb_warm": warm[0],
            "rss_mb_end": checkpoints[-1]["rss_mb"], "growth_mb": max(warm) - warm[0],
            "allocated_rows": recorder.allocated, "disk_mb": disk / MIB,
            "checkpoints": checkpoints}


def run_memory(cycles: int = MEMORY_CYCLES, progress: Progress = None) -> list[dict[str, Any]]:
    """Part 3: bounded, streaming and (at most UNBOUNDED_CYCLES) unbounded."""
    runs = []
    for mode, count in (("bounded", cycles), ("streaming", cycles),
                        ("unbounded", min(cycles, UNBOUNDED_CYCLES))):
        if progress is not None:
            progress(f"trace: memory, {mode}, {count} samples of {MEMORY_SIGNALS} signals")
        with multiprocessing.get_context("spawn").Pool(1) as pool:
            row = pool.apply(_memory_alone, (mode, count))
        row["flat"] = row["growth_mb"] < FLAT_MB
        runs.append(row)
    return runs


def _memory_alone(mode: str, cycles: int) -> dict[str, Any]:
    """``_memory`` in a process of its own (``run_memory`` spawns one per mode): what the
    modes before it or the other parts freed stays out of its RSS, and what it allocates
    cannot hide in memory they left to the allocator."""
    directory = Path(tempfile.mkdtemp(prefix="openmotion-trace-"))
    try:
        return _memory(mode, cycles, directory)
    finally:
        shutil.rmtree(directory, ignore_errors=True)


def run_trace(samples: int = 20_000, counts: Sequence[int] = (10, 100, 1000),
              cycles: int = 3000, seed: int = 0, progress: Progress = None,
              memory_cycles: int = MEMORY_CYCLES) -> dict[str, Any]:
    """Part 1 for each kind (kernel signals for each of ``counts``), the goal run, then the
    memory of a long run (``memory_cycles`` samples)."""
    sampling = []
    for kind, count in [*(("kernel", n) for n in counts), ("axis state", 100), ("planar", 30)]:
        if progress is not None:
            progress(f"trace: sampling {count} {kind} signals")
        sampling.append(_sampling(kind, count, samples))
    return {"sampling": sampling, "goal": _goal(cycles, seed, progress), "seed": seed,
            "repeats": REPEATS, "memory": run_memory(memory_cycles, progress)}
