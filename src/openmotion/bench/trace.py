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
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable, Sequence
from typing import Any

import openmotion as om
from openmotion.bench import peers
from openmotion.bench.axes import build_runtime, issue_plan
from openmotion.planar import MC_PlanarMover, MoverVector, PlanarMoverParameters
from openmotion.trace import TraceRecorder

Progress = Callable[[str], None] | None
CYCLE_TIME = 0.001
GOAL_AXES = 100
GOAL_SIGNALS = 100
DECIMATION = 10  #: the third variant records every 10th cycle
REPEATS = 3
SAMPLE_VALUES = 4_000_000  #: values one sampling run writes at most


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


def run_trace(samples: int = 20_000, counts: Sequence[int] = (10, 100, 1000),
              cycles: int = 3000, seed: int = 0, progress: Progress = None) -> dict[str, Any]:
    """Part 1 for each kind (kernel signals for each of ``counts``), then the goal run."""
    sampling = []
    for kind, count in [*(("kernel", n) for n in counts), ("axis state", 100), ("planar", 30)]:
        if progress is not None:
            progress(f"trace: sampling {count} {kind} signals")
        sampling.append(_sampling(kind, count, samples))
    return {"sampling": sampling, "goal": _goal(cycles, seed, progress), "seed": seed,
            "repeats": REPEATS}
