"""``openmotion bench axes``: N independent axes under a random command stream, vs the peers.

Every implementation gets the same ``peers.random_command_stream`` and does the same per-cycle
work: issue that cycle's commands, then advance every axis by one cycle. Ours issues the
commands from a PLC-style program (``Runtime.add_program``), so the figure includes what a
user pays for the Python layer, not just the kernel.

Per N the order is: one untimed *check* run (the warm-up; it counts setpoint limit violations
and rejected commands), one timed run with trace off, optionally one timed run with a trace
observer that copies set position and velocity of all axes into a preallocated array, then
pyplcopen and the ruckig loop on the same stream. Only the stepped loops are timed.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np

import openmotion as om
from openmotion.bench import peers
from openmotion.bench.peers import ABSOLUTE, StreamCommand

DEFAULT_COUNTS = (1, 10, 100, 1000, 10000)
WORK = 4_000_000  #: axis-cycles per N for the timed runs (before the clamps below)
MIN_CYCLES = 200
MAX_CYCLES = 20_000
RELATIVE_TOLERANCE = 1e-9

#: Axis maxima = the stream's upper bounds, so no command is clamped and none is rejected.
AXIS_LIMITS = {
    "max_velocity": peers.VELOCITY_RANGE[1],
    "acceleration": peers.ACCELERATION_RANGE[1],
    "deceleration": peers.ACCELERATION_RANGE[1],
    "jerk": peers.JERK_RANGE[1],
    "max_acceleration": peers.ACCELERATION_RANGE[1],
    "max_deceleration": peers.ACCELERATION_RANGE[1],
    "max_jerk": peers.JERK_RANGE[1],
}

Issue = tuple[Callable[..., om.Command], tuple[Any, ...]]


def cycles_for(n_axes: int) -> int:
    """Cycles for N axes: a fixed budget of axis-cycles, at least 200 and at most 20000."""
    return int(min(MAX_CYCLES, max(MIN_CYCLES, WORK // max(n_axes, 1))))


def build_runtime(n_axes: int) -> tuple[om.Runtime, list[om.Axis]]:
    """A runtime with ``n_axes`` powered axes whose maxima cover the stream's ranges."""
    rt = om.Runtime(cycle_time=0.001)
    axes = [rt.add_axis(f"a{i}", **AXIS_LIMITS) for i in range(n_axes)]
    for axis in axes:
        axis.power()
    return rt, axes


def issue_plan(axes: Sequence[om.Axis], stream: list[StreamCommand],
               cycles: int) -> list[list[Issue]]:
    """Bound methods and arguments per cycle, prepared outside the timed loop like the peers."""
    plan: list[list[Issue]] = [[] for _ in range(cycles)]
    for c in stream:
        if not 0 <= c.cycle < cycles:
            continue
        axis = axes[c.axis]
        if c.kind == ABSOLUTE:
            issue: Issue = (axis.move_absolute,
                            (c.value, c.velocity, c.acceleration, c.deceleration, c.jerk))
        else:
            direction = om.Direction.POSITIVE if c.value > 0.0 else om.Direction.NEGATIVE
            issue = (axis.move_velocity,
                     (c.velocity, direction, c.acceleration, c.deceleration, c.jerk))
        plan[c.cycle].append(issue)
    return plan


def _program(plan: list[list[Issue]], issued: list[om.Command] | None) -> Callable[[], None]:
    """The PLC task body: issue this cycle's commands (one slot of the plan per cycle)."""
    slots: Iterator[list[Issue]] = iter(plan)
    if issued is None:
        def program() -> None:
            for method, args in next(slots):
                method(*args)
    else:
        def program() -> None:
            for method, args in next(slots):
                issued.append(method(*args))
    return program


def check_run(n_axes: int, stream: list[StreamCommand], cycles: int) -> dict[str, Any]:
    """Untimed run (doubles as warm-up): setpoint limit violations and rejected commands.

    Checks every cycle, vectorised over the kernel arrays: |v| <= max_velocity,
    |a| <= max(max_acceleration, max_deceleration), |j| <= max_jerk, each within 1e-9 relative.
    """
    rt, axes = build_runtime(n_axes)
    issued: list[om.Command] = []
    rt.add_program(_program(issue_plan(axes, stream, cycles), issued))
    v_lim = AXIS_LIMITS["max_velocity"] * (1 + RELATIVE_TOLERANCE)
    a_lim = max(AXIS_LIMITS["max_acceleration"], AXIS_LIMITS["max_deceleration"]) * (
        1 + RELATIVE_TOLERANCE)
    j_lim = AXIS_LIMITS["max_jerk"] * (1 + RELATIVE_TOLERANCE)
    counts = {"velocity": 0, "acceleration": 0, "jerk": 0}
    peak = {"velocity": 0.0, "acceleration": 0.0, "jerk": 0.0}
    first: list[dict[str, Any]] = []

    def check(runtime: om.Runtime) -> None:
        kernel = runtime._kernel
        for name, values, limit in (("velocity", kernel.set_v[:n_axes], v_lim),
                                    ("acceleration", kernel.set_a[:n_axes], a_lim),
                                    ("jerk", kernel.set_j[:n_axes], j_lim)):
            magnitude = np.abs(values)
            top = float(magnitude.max())
            peak[name] = max(peak[name], top)
            if top > limit:
                rows = np.flatnonzero(magnitude > limit)
                counts[name] += int(rows.size)
                if len(first) < 5:
                    first.append({"cycle": runtime.cycle, "axis": int(rows[0]), "what": name,
                                  "value": float(values[rows[0]])})

    rt.add_observer(check)
    for _ in range(cycles):
        rt.step()
    errors = [c for c in issued if c.error]
    moving = int(np.count_nonzero(rt._kernel.set_v[:n_axes]))
    return {
        "commands": len(issued),
        "rejected": len(errors),
        "rejections": [f"{c.kind}: {c.error_id.name}: {c.message}" for c in errors[:5]],
        "clamped": sum(1 for c in issued if c.warnings),
        "violations": sum(counts.values()),
        "violations_by_kind": counts,
        "first_violations": first,
        "peak": peak,
        "moving_at_end": moving,
        "final_positions_checksum": float(np.sum(rt._kernel.set_p[:n_axes])),
    }


def timed_run(n_axes: int, stream: list[StreamCommand], cycles: int,
              trace: bool = False) -> dict[str, float]:
    """Wall time of the stepped loop (setup excluded), plus per-cycle p50/p99.

    One ``perf_counter`` stamp per cycle (~0.1 us) gives the cycle-time distribution; the
    headline figure is the whole loop divided by axis-cycles, like the peers'.
    """
    rt, axes = build_runtime(n_axes)
    rt.add_program(_program(issue_plan(axes, stream, cycles), None))
    if trace:
        buffer = np.empty((cycles, 2, n_axes))
        kernel = rt._kernel

        def record(runtime: om.Runtime) -> None:
            row = buffer[runtime.cycle - 1]
            row[0] = kernel.set_p[:n_axes]
            row[1] = kernel.set_v[:n_axes]

        rt.add_observer(record)
    stamps = [0.0] * (cycles + 1)
    clock, step = time.perf_counter, rt.step
    stamps[0] = clock()
    for c in range(1, cycles + 1):
        step()
        stamps[c] = clock()
    seconds = stamps[-1] - stamps[0]
    per_cycle = np.diff(np.array(stamps)) * 1e6
    return {
        "seconds": seconds,
        "us_per_axis_cycle": seconds / (n_axes * cycles) * 1e6,
        "cycle_us_p50": float(np.percentile(per_cycle, 50)),
        "cycle_us_p99": float(np.percentile(per_cycle, 99)),
        "cycle_us_max": float(per_cycle.max()),
    }


def warm_up(seed: int = 0) -> None:
    """Import, allocate and JIT-free first calls for all three implementations, untimed."""
    n, cycles = 10, 300
    stream = peers.random_command_stream(n, cycles, seed + 10_000)
    timed_run(n, stream, cycles)
    peers.run_pyplcopen(n, stream, cycles)
    peers.run_ruckig_loop(n, stream, cycles)


def run_one(n_axes: int, cycles: int, seed: int = 0, trace: bool = False) -> dict[str, Any]:
    """All figures for one N from one stream."""
    stream = peers.random_command_stream(n_axes, cycles, seed)
    result: dict[str, Any] = {"axes": n_axes, "cycles": cycles, "commands": len(stream)}
    result["check"] = check_run(n_axes, stream, cycles)
    off = timed_run(n_axes, stream, cycles)
    result["ours"] = off
    result["ours_us"] = off["us_per_axis_cycle"]
    if trace:
        on = timed_run(n_axes, stream, cycles, trace=True)
        result["ours_trace"] = on
        result["ours_trace_us"] = on["us_per_axis_cycle"]
    scale = 1e6 / (n_axes * cycles)
    plc = peers.run_pyplcopen(n_axes, stream, cycles)
    result["pyplcopen_us"] = None if plc is None else plc * scale
    result["ruckig_us"] = peers.run_ruckig_loop(n_axes, stream, cycles) * scale
    for peer in ("pyplcopen", "ruckig"):
        figure = result[f"{peer}_us"]
        result[f"ratio_{peer}"] = None if not figure else result["ours_us"] / figure
        if trace:
            result[f"ratio_{peer}_trace"] = None if not figure else result["ours_trace_us"] / figure
    result["violations"] = result["check"]["violations"]
    return result


def run_axes(counts: Sequence[int] = DEFAULT_COUNTS, cycles: int | None = None, seed: int = 0,
             trace: bool = False,
             progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Figures per N (keys are str(N) so the dict stays JSON-shaped).

    ``cycles=None`` picks ``cycles_for(N)``: 4M axis-cycles clamped to [200, 20000] cycles.
    """
    warm_up(seed)
    by_n: dict[str, Any] = {}
    for n in counts:
        c = cycles if cycles is not None else cycles_for(n)
        if progress is not None:
            progress(f"axes: N={n}, {c} cycles")
        by_n[str(n)] = run_one(n, c, seed, trace)
    return {"trace": trace, "seed": seed, "by_n": by_n}
