"""``openmotion bench axes``: N independent axes under a random command stream, vs the peers.

Every implementation gets the same ``peers.random_command_stream`` and does the same per-cycle
work: issue that cycle's commands, then advance every axis by one cycle. Ours issues the
commands from a PLC-style program (``Runtime.add_program``), so the figure includes what a
user pays for the Python layer, not just the kernel.

Two modes (issue 24):

* *stepped*: one ``Runtime.step()`` per cycle, the commands issued from a PLC-style program,
  as a PLC program needs; pyplcopen and the ruckig loop advance every axis one cycle per call.
* *bulk*: the stretch between two cycles with commands advances in one call on both sides:
  ours ``Runtime.run`` (quiet stretches in bulk, D-275; the commands issued between the
  runs), pyplcopen one ``cycle(n)`` per axis. The final setpoints must be those of the
  stepped run bit for bit (``bulk_equal``).

Per N: one untimed *check* run (it also warms up; it counts setpoint limit violations and
rejected commands), then ``repeats`` rounds in which ours with trace off, ours with a trace
observer (set position and velocity of all axes copied into a preallocated array each
cycle; in bulk a block observer copies a stretch at once), ours in bulk, pyplcopen (both
modes) and the ruckig loop take turns on the same stream. Only the loops are timed; figures
are medians over the rounds. Apart: ``step()`` of one moving axis alone (the runtime's fixed
cost per cycle).

The stream starts with every axis at rest and commands arrive at 2 per axis and second, so
runs of a few hundred cycles (N = 10000) see fewer moving axes than long ones.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np
import ruckig

import openmotion as om
from openmotion.bench import peers
from openmotion.bench.peers import ABSOLUTE, StreamCommand

DEFAULT_COUNTS = (1, 10, 100, 1000, 10000)
WORK = 4_000_000  #: axis-cycles per N for the timed runs (before the clamps below)
MIN_CYCLES = 200
MAX_CYCLES = 20_000
RELATIVE_TOLERANCE = 1e-9
REPEATS = 3  #: timed runs per implementation and N; the median is reported

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


def _program(plan: list[list[Issue]]) -> Callable[[], None]:
    """The PLC task body: issue this cycle's commands (one slot of the plan per cycle)."""
    slots: Iterator[list[Issue]] = iter(plan)

    def program() -> None:
        for method, args in next(slots):
            method(*args)

    return program


def forced_speed(velocity: np.ndarray | float, acceleration: np.ndarray | float,
                 jerk: np.ndarray | float) -> np.ndarray | float:
    """Highest |v| any profile must reach from (v, a) when |jerk| is limited to ``jerk``.

    Bringing ``a`` to zero at full jerk changes v monotonically by a*|a|/(2j); a command whose
    jerk cannot absorb the current acceleration therefore overshoots the velocity limit
    whatever the planner does (pyplcopen rejects such commands, ruckig and we take them).
    """
    return np.maximum(np.abs(velocity),
                      np.abs(velocity + acceleration * np.abs(acceleration) / (2.0 * jerk)))


def command_limits(c: StreamCommand, velocity: float,
                   acceleration: float) -> tuple[float, float, float]:
    """|v|, |a|, |j| bounds for an axis after command ``c``, issued at (velocity, acceleration).

    Every command aborts the one before, so from its issue on the setpoint keeps to that
    command's limits, except where the start state forces more:

    * |v| <= max(velocity, ``forced_speed`` with the command's jerk), and, the axis maximum
      being a hard limit (docs/decisions.md D-020), <= max(max_velocity, ``forced_speed``
      with max_jerk);
    * |a| <= max(acceleration, deceleration, |a| at issue);
    * |j| <= jerk, or, where that jerk would let the velocity pass max_velocity (still
      speeding up, or braking hard through zero and on the other way), the smallest jerk
      that does not, up to max_jerk (D-020, D-177; the kernel adds 1e-6 relative, so do
      we). A move that turns through zero without stopping (D-201) meets the second case.
    """
    v_max, j_max = AXIS_LIMITS["max_velocity"], AXIS_LIMITS["max_jerk"]
    speed = min(max(c.velocity, float(forced_speed(velocity, acceleration, c.jerk))),
                max(v_max, float(forced_speed(velocity, acceleration, j_max))))
    jerk = c.jerk
    if acceleration != 0.0 and forced_speed(velocity, acceleration, c.jerk) > v_max:
        room = v_max - (velocity if acceleration > 0.0 else -velocity)  # less v ahead
        needed = acceleration**2 / (2.0 * room) * (1.0 + 1e-6) if room > 0.0 else j_max
        jerk = max(c.jerk, min(needed, j_max))
    return speed, max(c.acceleration, c.deceleration, abs(acceleration)), jerk


def check_run(n_axes: int, stream: list[StreamCommand], cycles: int) -> dict[str, Any]:
    """Untimed run (doubles as warm-up): setpoint limit violations and rejected commands.

    Each cycle, vectorised over the kernel arrays, every axis' |v|, |a|, |j| is checked
    against the bounds ``command_limits`` set at its last command, within 1e-9 relative.
    Velocities beyond the axis' max_velocity (only possible when even max_jerk cannot take the
    acceleration away in time) are counted apart, as are commands allowed a raised jerk.
    """
    rt, axes = build_runtime(n_axes)
    kernel = rt.axis_system.kernel
    plan = issue_plan(axes, stream, cycles)
    commands: list[list[StreamCommand]] = [[] for _ in range(cycles)]
    for c in stream:
        if 0 <= c.cycle < cycles:
            commands[c.cycle].append(c)
    v_max = AXIS_LIMITS["max_velocity"]
    tolerance = 1 + RELATIVE_TOLERANCE
    limit = {  # per axis, set at each command; before any command the axis must rest
        "velocity": np.zeros(n_axes), "acceleration": np.zeros(n_axes), "jerk": np.zeros(n_axes),
    }
    issued: list[om.Command] = []
    jerk_raise_allowed = [0]
    slots = iter(zip(plan, commands, strict=True))

    def program() -> None:
        issues, stream_commands = next(slots)
        for (method, args), c in zip(issues, stream_commands, strict=True):
            bounds = command_limits(c, float(kernel.set_v[c.axis]), float(kernel.set_a[c.axis]))
            for name, bound in zip(limit, bounds, strict=True):
                limit[name][c.axis] = bound
            jerk_raise_allowed[0] += bounds[2] > c.jerk
            issued.append(method(*args))

    counts = {"velocity": 0, "acceleration": 0, "jerk": 0}
    peak = {"velocity": 0.0, "acceleration": 0.0, "jerk": 0.0}
    forced = {"axis_cycles": 0, "peak_velocity": 0.0}
    first: list[dict[str, Any]] = []

    def check(runtime: om.Runtime) -> None:
        values = {"velocity": kernel.set_v[:n_axes], "acceleration": kernel.set_a[:n_axes],
                  "jerk": kernel.set_j[:n_axes]}
        for name, value in values.items():
            magnitude = np.abs(value)
            top = float(magnitude.max())
            peak[name] = max(peak[name], top)
            if name == "velocity" and top > v_max * tolerance:
                forced["axis_cycles"] += int(np.count_nonzero(magnitude > v_max * tolerance))
                forced["peak_velocity"] = max(forced["peak_velocity"], top)
            over = magnitude > limit[name] * tolerance
            if over.any():
                rows = np.flatnonzero(over)
                counts[name] += int(rows.size)
                if len(first) < 5:
                    row = int(rows[0])
                    first.append({"cycle": runtime.cycle, "axis": row, "what": name,
                                  "value": float(value[row]), "limit": float(limit[name][row])})

    rt.add_program(program)
    rt.add_observer(check)
    for _ in range(cycles):
        rt.step()
    errors = [c for c in issued if c.error]
    return {
        "commands": len(issued),
        "rejected": len(errors),
        "rejections": [f"{c.kind}: {c.error_id.name}: {c.message}" for c in errors[:5]],
        "clamped": sum(1 for c in issued if c.warnings),
        "violations": sum(counts.values()),
        "violations_by_kind": counts,
        "first_violations": first,
        "forced_overshoot": forced,
        "jerk_raise_allowed": jerk_raise_allowed[0],
        "peak": peak,
        "moving_at_end": int(np.count_nonzero(kernel.set_v[:n_axes])),
    }


def timed_run(n_axes: int, stream: list[StreamCommand], cycles: int,
              trace: bool = False) -> tuple[float, float, np.ndarray]:
    """Wall and CPU seconds of the stepped loop (setup excluded), each cycle's wall µs.

    CPU time (this thread only) shows how much of the wall time other load on the machine
    took; the peers report wall time only, so ratios use wall time.

    One ``perf_counter`` stamp per cycle (~0.1 us) gives the cycle-time distribution. The
    trace buffer is allocated and touched before the loop, as a real-time recorder would,
    so page faults of a fresh allocation are not counted as the trace's cost.
    """
    rt, axes = build_runtime(n_axes)
    rt.add_program(_program(issue_plan(axes, stream, cycles)))
    if trace:
        buffer = np.zeros((cycles, 2, n_axes))
        buffer.fill(1.0)
        kernel = rt.axis_system.kernel

        def record(runtime: om.Runtime) -> None:
            row = buffer[runtime.cycle - 1]
            row[0] = kernel.set_p[:n_axes]
            row[1] = kernel.set_v[:n_axes]

        rt.add_observer(record)
    stamps = [0.0] * (cycles + 1)
    clock, step = time.perf_counter, rt.step
    cpu = time.thread_time()
    stamps[0] = clock()
    for c in range(1, cycles + 1):
        step()
        stamps[c] = clock()
    cpu = time.thread_time() - cpu
    return stamps[-1] - stamps[0], cpu, np.diff(np.array(stamps)) * 1e6


class _BlockTrace:
    """The trace observer of ``bulk_run``: set position and velocity of every cycle into a
    preallocated buffer, a cycle at a time when stepped, a stretch at a time in bulk."""

    def __init__(self, buffer: np.ndarray, kernel: Any, n_axes: int) -> None:
        self.buffer, self.kernel, self.n = buffer, kernel, n_axes

    def __call__(self, runtime: om.Runtime) -> None:
        row = self.buffer[runtime.cycle - 1]
        row[0] = self.kernel.set_p[: self.n]
        row[1] = self.kernel.set_v[: self.n]

    def observe_block(self, runtime: om.Runtime, blocks: dict[str, Any]) -> None:
        block = blocks["axes"]
        rows = self.buffer[runtime.cycle - block.times.shape[0]: runtime.cycle]
        rows[:, 0] = block.set_p
        rows[:, 1] = block.set_v


def bulk_run(n_axes: int, stream: list[StreamCommand], cycles: int,
             trace: bool = False) -> tuple[float, np.ndarray]:
    """Wall seconds of the bulk loop (setup excluded) and the final set positions.

    The commands of cycle index c are issued when the runtime has run c cycles, as the
    stepped run's program issues them in cycle c + 1: both plan from the sample of cycle c.
    """
    rt, axes = build_runtime(n_axes)
    plan = issue_plan(axes, stream, cycles)
    busy = [(index, issued) for index, issued in enumerate(plan) if issued]
    kernel = rt.axis_system.kernel
    if trace:
        buffer = np.zeros((cycles, 2, n_axes))
        buffer.fill(1.0)
        rt.add_observer(_BlockTrace(buffer, kernel, n_axes))
    run, cycle_time = rt.run, rt.cycle_time
    start = time.perf_counter()
    for index, issued in busy:
        if index > rt.cycle:
            run((index - rt.cycle) * cycle_time)
        for method, args in issued:
            method(*args)
    run((cycles - rt.cycle) * cycle_time)
    elapsed = time.perf_counter() - start
    return elapsed, kernel.set_p[:n_axes].copy()


def step_one_axis(cycles: int = 20_000, repeats: int = REPEATS) -> dict[str, float]:
    """µs per ``step()`` of a runtime with one axis in constant motion and nothing else (the
    fixed cost per cycle), median and fastest of ``repeats`` (pyplcopen's stepped figure
    for N = 1 is in ``by_n``)."""
    rt, (axis,) = build_runtime(1)
    axis.move_velocity(100.0, om.Direction.POSITIVE, 1000.0, 1000.0, 10000.0)
    rt.run(0.5)  # past the ramp: constant velocity
    step, clock, ours = rt.step, time.perf_counter, []
    for _ in range(repeats):
        begin = clock()
        for _ in range(cycles):
            step()
        ours.append((clock() - begin) / cycles * 1e6)
    return {"cycles": cycles, "ours_us": float(np.median(ours)), "ours_best_us": min(ours)}


def _final_positions(n_axes: int, stream: list[StreamCommand], cycles: int) -> np.ndarray:
    """The set positions after the stepped run (the program issues the commands)."""
    rt, axes = build_runtime(n_axes)
    rt.add_program(_program(issue_plan(axes, stream, cycles)))
    for _ in range(cycles):
        rt.step()
    return rt.axis_system.kernel.set_p[:n_axes].copy()


def warm_up(seed: int = 0) -> None:
    """First calls of all three implementations (imports, allocations, caches), untimed."""
    n, cycles = 10, 300
    stream = peers.random_command_stream(n, cycles, seed + 10_000)
    timed_run(n, stream, cycles)
    bulk_run(n, stream, cycles, trace=True)
    peers.run_pyplcopen(n, stream, cycles)
    peers.run_pyplcopen(n, stream, cycles, bulk=True)
    _ruckig_seconds(n, stream, cycles)


def _ruckig_seconds(n_axes: int, stream: list[StreamCommand], cycles: int) -> float | str:
    """The ruckig peer's seconds, or its error text (it has no fallback for step-1 failures)."""
    try:
        return peers.run_ruckig_loop(n_axes, stream, cycles)
    except ruckig.RuckigError as exc:
        return " ".join(str(exc).split())


def _cycle_stats(per_cycle: list[np.ndarray]) -> dict[str, float]:
    joined = np.concatenate(per_cycle)
    return {"cycle_us_p50": float(np.percentile(joined, 50)),
            "cycle_us_p99": float(np.percentile(joined, 99)),
            "cycle_us_max": float(joined.max())}


def run_one(n_axes: int, cycles: int, seed: int = 0, trace: bool = False,
            repeats: int = REPEATS) -> dict[str, Any]:
    """All figures for one N from one stream.

    The implementations take turns within each repeat, so drift on a shared machine hits all
    of them alike; figures are medians over the repeats (``*_best_us``: the fastest repeat,
    least disturbed by other load), spreads are (max - min) / median.
    """
    stream = peers.random_command_stream(n_axes, cycles, seed)
    result: dict[str, Any] = {"axes": n_axes, "cycles": cycles, "commands": len(stream),
                              "repeats": repeats}
    result["check"] = check_run(n_axes, stream, cycles)
    seconds: dict[str, list[float]] = {"ours": [], "ours_trace": [], "pyplcopen": [],
                                       "ruckig": [], "ours_bulk": [], "ours_bulk_trace": [],
                                       "pyplcopen_bulk": []}
    bulk_equal = True
    stepped_final = _final_positions(n_axes, stream, cycles)
    per_cycle: dict[str, list[np.ndarray]] = {"ours": [], "ours_trace": []}
    cpu_seconds: dict[str, list[float]] = {"ours": [], "ours_trace": []}
    ruckig_error = ""
    for _ in range(repeats):
        for name, with_trace in (("ours", False), ("ours_trace", True))[: 1 + trace]:
            elapsed, cpu, cycle_us = timed_run(n_axes, stream, cycles, with_trace)
            seconds[name].append(elapsed)
            cpu_seconds[name].append(cpu)
            per_cycle[name].append(cycle_us)
        for name, with_trace in (("ours_bulk", False), ("ours_bulk_trace", True))[: 1 + trace]:
            elapsed, final = bulk_run(n_axes, stream, cycles, with_trace)
            seconds[name].append(elapsed)
            bulk_equal &= final.tobytes() == stepped_final.tobytes()
        plc = peers.run_pyplcopen(n_axes, stream, cycles)
        if plc is not None:
            seconds["pyplcopen"].append(plc)
        plc = peers.run_pyplcopen(n_axes, stream, cycles, bulk=True)
        if plc is not None:
            seconds["pyplcopen_bulk"].append(plc)
        if not ruckig_error:
            outcome = _ruckig_seconds(n_axes, stream, cycles)
            if isinstance(outcome, str):
                ruckig_error = outcome
            else:
                seconds["ruckig"].append(outcome)
    scale = 1e6 / (n_axes * cycles)
    result["bulk_equal"] = bulk_equal
    for name, values in seconds.items():
        if values and (name != "ruckig" or not ruckig_error):
            result[f"{name}_us"] = float(np.median(values)) * scale
            result[f"{name}_best_us"] = min(values) * scale  # least disturbed by other load
            result[f"{name}_spread"] = (max(values) - min(values)) / float(np.median(values))
        else:
            result[f"{name}_us"] = result[f"{name}_best_us"] = None
    for name in ("ours", "ours_trace")[: 1 + trace]:
        result[name] = _cycle_stats(per_cycle[name])
        result[f"{name}_cpu_us"] = float(np.median(cpu_seconds[name])) * scale
    if ruckig_error:
        result["ruckig_error"] = ruckig_error
    for peer in ("pyplcopen", "ruckig"):
        for stat in ("", "best_"):
            figure = result[f"{peer}_{stat}us"]
            for ours in ("ours", "ours_trace")[: 1 + trace]:
                key = f"ratio_{stat}{peer}{'_trace' if ours == 'ours_trace' else ''}"
                result[key] = None if not figure else result[f"{ours}_{stat}us"] / figure
    for stat in ("", "best_"):
        figure = result[f"pyplcopen_bulk_{stat}us"]
        for ours in ("ours_bulk", "ours_bulk_trace")[: 1 + trace]:
            key = f"ratio_{stat}bulk_pyplcopen{'_trace' if ours == 'ours_bulk_trace' else ''}"
            result[key] = None if not figure else result[f"{ours}_{stat}us"] / figure
    result["violations"] = result["check"]["violations"]
    return result


def run_axes(counts: Sequence[int] = DEFAULT_COUNTS, cycles: int | None = None, seed: int = 0,
             trace: bool = False, repeats: int = REPEATS,
             progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Figures per N (keys are str(N) so the dict stays JSON-shaped).

    ``cycles=None`` picks ``cycles_for(N)``: 4M axis-cycles clamped to [200, 20000] cycles.
    """
    warm_up(seed)
    if progress is not None:
        progress("axes: step() of one moving axis")
    one_axis = step_one_axis(repeats=repeats)
    by_n: dict[str, Any] = {}
    for n in counts:
        c = cycles if cycles is not None else cycles_for(n)
        if progress is not None:
            progress(f"axes: N={n}, {c} cycles")
        by_n[str(n)] = run_one(n, c, seed, trace, repeats)
    return {"trace": trace, "seed": seed, "repeats": repeats, "step_one_axis": one_axis,
            "by_n": by_n}
