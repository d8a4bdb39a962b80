"""`ca` benchmark: N movers on a ring in one CA group, random modulo targets (performance.md).

N movers start evenly spread on a ring of 300 mm per mover (3000 mm for 10), gap 100 mm.
Each mover gets a MoveAbsoluteCA to a random modulo position (direction positive, random
velocity) whenever its last command ended, and at random times in between (aborting), so
queues form and dissolve all the time. Every cycle is timed (``Runtime.step``, gap control
included) and checked: no setpoint gap below the gap, no mover beyond its own limits.

Each N runs in three gap control modes (TF5410 §8.1.2): every command Standard, every
command Fast, and mixed (the mode is chosen per command, so per mover: every second mover
Fast, the others Standard, and both kinds of pair occur). The three groups run side by side
in one process, one cycle of each in turn, with the same random draws: a load on the machine
slows all three alike, so their ratios hold where the absolute times drift (D-187).

Every N runs at the 1 ms cycle and at the XTS task's 250 us cycle (TF5410 §3). Beside the
three groups, in the same turn, runs the reference a rail costs at least without collision
avoidance: one ruckig OTG per mover, every mover updated every cycle, with the same kind of
commands (a random target ahead on the ring, a random velocity, renewed when the last one
ended and at random cycles in between) and no gap kept (D-280).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import ruckig

import openmotion as om
from openmotion.bench.peers import _retry_ruckig
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GapControlMode,
    ModuloDirection,
)

DEFAULT_COUNTS = (10, 50, 100, 1000)
CYCLE_TIMES = {"1ms": 0.001, "250us": 0.00025}  #: result key -> cycle time [s]
MODES = ("standard", "fast", "mixed")  #: gap control of the commands, see ``mode_of``
GAP = 100.0
SPACING = 300.0  #: rail length per mover [mm]
LIMITS = {"max_velocity": 4000.0, "acceleration": 10000.0, "deceleration": 10000.0,
          "jerk": 100000.0, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
          "max_jerk": 100000.0}
LIMIT_SLACK = 1e-9  #: relative float slack of the limit check
WARM_UP = 10  #: the first 1/WARM_UP of the cycles is not timed


def mode_of(mode: str, mover: int) -> GapControlMode:
    """The gap control mode of every command of ``mover`` in a run of ``mode``."""
    if mode == "standard" or (mode == "mixed" and mover % 2 == 0):
        return GapControlMode.STANDARD
    return GapControlMode.FAST


def build(n: int, cycle_time: float = 0.001) -> tuple[om.Runtime, CaGroup, list[om.Axis]]:
    rt = om.Runtime(cycle_time)
    group = CaGroup(rt, "ca", rail_length=SPACING * n, default_gap=GAP)
    axes = []
    for i in range(n):
        axis = rt.add_axis(f"m{i}", position=i * SPACING, **LIMITS)
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
        axes.append(axis)
    group.enable()
    return rt, group, axes


class _Run:
    """One group of N movers whose commands all use one mode: its commands, timings and
    checks, advanced one cycle at a time."""

    def __init__(self, n: int, cycles: int, seed: int, mode: str,
                 cycle_time: float = 0.001) -> None:
        self.rng = np.random.default_rng(seed)
        self.rt, self.group, self.axes = build(n, cycle_time)
        self.modes = [mode_of(mode, i) for i in range(n)]
        self.commands: list[om.Command | None] = [None] * n
        self.renew = self.rng.integers(1, 2000, n)  # cycle of the next aborting command
        self.issued = self.done = 0
        self.rows = np.array([a.row for a in self.axes])
        self.vmax, self.amax, self.dmax, self.jmax = (
            np.array([getattr(a.parameters, name) for a in self.axes])
            for name in ("max_velocity", "max_acceleration", "max_deceleration", "max_jerk"))
        self.min_gap, self.limit_violations = np.inf, 0
        self.wall, self.cpu = np.zeros(cycles), np.zeros(cycles)

    def cycle(self, cycle: int) -> None:
        length = self.group.parameters.rail_length
        for i, axis in enumerate(self.axes):
            command = self.commands[i]
            if command is None or command.finished or cycle >= self.renew[i]:
                self.done += command is not None and command.done
                self.commands[i] = self.group.move_absolute(
                    axis, float(self.rng.uniform(0.0, length)),
                    float(self.rng.uniform(500.0, 3000.0)), direction=ModuloDirection.POSITIVE,
                    gap_control_mode=self.modes[i])
                self.issued += 1
                self.renew[i] = cycle + self.rng.integers(200, 2000)
        cpu, start = time.thread_time(), time.perf_counter()
        self.rt.step()
        self.wall[cycle] = time.perf_counter() - start
        self.cpu[cycle] = time.thread_time() - cpu
        self.min_gap = min(self.min_gap, float(self.group.gaps().min()))
        k, slack = self.rt.axis_system.kernel, 1 + LIMIT_SLACK
        v, a, j = k.set_v[self.rows], k.set_a[self.rows], k.set_j[self.rows]
        braking = a * v < 0.0
        self.limit_violations += int(np.count_nonzero(
            (np.abs(v) > self.vmax * slack) | (np.abs(j) > self.jmax * slack)
            | (~braking & (np.abs(a) > self.amax * slack))
            | (braking & (np.abs(a) > self.dmax * slack))))

    def result(self) -> dict[str, Any]:
        cycles = self.wall.size
        wall, cpu = self.wall[cycles // WARM_UP:] * 1e6, self.cpu[cycles // WARM_UP:] * 1e6
        return {"movers": len(self.axes), "cycles": cycles, "commands": self.issued,
                "done": self.done,
                "cycle_us_p50": float(np.percentile(wall, 50)),
                "cycle_us_p99": float(np.percentile(wall, 99)),
                "cpu_us_p50": float(np.percentile(cpu, 50)),
                "cpu_us_p99": float(np.percentile(cpu, 99)),
                "min_gap": self.min_gap, "gap_violations": int(self.min_gap < GAP - 1e-9),
                "limit_violations": self.limit_violations}


class _RuckigRun:
    """The reference without collision avoidance: one ruckig OTG per mover, updated every
    cycle, the same kind of commands as ``_Run`` and no gap kept (D-280)."""

    def __init__(self, n: int, cycles: int, seed: int, cycle_time: float = 0.001) -> None:
        self.rng = np.random.default_rng(seed)
        self.length = SPACING * n
        self.otgs = [ruckig.Ruckig(1, cycle_time) for _ in range(n)]
        self.inps = [ruckig.InputParameter(1) for _ in range(n)]
        self.outs = [ruckig.OutputParameter(1) for _ in range(n)]
        for i, inp in enumerate(self.inps):
            inp.current_position = [i * SPACING]
            inp.max_acceleration = [LIMITS["acceleration"]]
            inp.min_acceleration = [-LIMITS["deceleration"]]
            inp.max_jerk = [LIMITS["jerk"]]
        self.finished = np.ones(n, dtype=bool)
        self.started = np.zeros(n, dtype=bool)
        self.renew = self.rng.integers(1, 2000, n)
        self.issued = self.done = self.reissued = 0
        self.wall, self.cpu = np.zeros(cycles), np.zeros(cycles)

    def cycle(self, cycle: int) -> None:
        for i, inp in enumerate(self.inps):
            if not self.started[i] or self.finished[i] or cycle >= self.renew[i]:
                self.done += bool(self.started[i] and self.finished[i])
                p = inp.current_position[0] % self.length  # a modulo axis: on the ring
                ahead = (float(self.rng.uniform(0.0, self.length)) - p) % self.length
                inp.current_position = [p]
                inp.target_position = [p + ahead]  # reached in the positive direction
                inp.max_velocity = [float(self.rng.uniform(500.0, 3000.0))]
                self.started[i], self.finished[i] = True, False
                self.issued += 1
                self.renew[i] = cycle + self.rng.integers(200, 2000)
        finished = ruckig.Result.Finished
        states = []
        cpu, start = time.thread_time(), time.perf_counter()
        for otg, inp, out in zip(self.otgs, self.inps, self.outs, strict=True):
            try:
                states.append(otg.update(inp, out) == finished)
            except ruckig.RuckigError:  # its numerical step 1: as bench axes' ruckig peer
                self.reissued += 1
                states.append(False)
                if not _retry_ruckig(otg, inp, out):
                    continue  # no plan at all this cycle: the mover holds its state
            out.pass_to_input(inp)
        self.wall[cycle] = time.perf_counter() - start
        self.cpu[cycle] = time.thread_time() - cpu
        self.finished[:] = states

    def result(self) -> dict[str, Any]:
        cycles = self.wall.size
        wall, cpu = self.wall[cycles // WARM_UP:] * 1e6, self.cpu[cycles // WARM_UP:] * 1e6
        return {"movers": len(self.otgs), "cycles": cycles, "commands": self.issued,
                "done": self.done,
                "cycle_us_p50": float(np.percentile(wall, 50)),
                "cycle_us_p99": float(np.percentile(wall, 99)),
                "cpu_us_p50": float(np.percentile(cpu, 50)),
                "cpu_us_p99": float(np.percentile(cpu, 99)),
                "us_per_mover_cycle": float(np.percentile(wall, 50)) / len(self.otgs),
                "reissued": self.reissued}


def run_one(n: int, cycles: int, seed: int = 0, modes: Sequence[str] = MODES,
            cycle_time: float = 0.001) -> dict[str, Any]:
    """Every mode of ``modes`` with N movers and the ruckig reference, one cycle of each in
    turn; per mode its figures and the ratios of its cycle times to Standard's and to the
    reference's."""
    runs: dict[str, _Run | _RuckigRun] = {
        mode: _Run(n, cycles, seed, mode, cycle_time) for mode in modes}
    runs["ruckig"] = _RuckigRun(n, cycles, seed, cycle_time)
    for cycle in range(cycles):
        for run in runs.values():
            run.cycle(cycle)
    out: dict[str, Any] = {mode: run.result() for mode, run in runs.items()}
    reference = out["ruckig"]
    for mode in modes:
        out[f"{mode}_over_ruckig"] = {
            key: out[mode][f"cycle_us_{key}"] / reference[f"cycle_us_{key}"]
            for key in ("p50", "p99")}
    if "standard" in out:
        base = out["standard"]
        for mode in modes:
            if mode != "standard":
                out[f"{mode}_over_standard"] = {
                    key: out[mode][f"cycle_us_{key}"] / base[f"cycle_us_{key}"]
                    for key in ("p50", "p99")}
    return out


def run_ca(counts: Sequence[int] = DEFAULT_COUNTS, cycles: int = 3000, seed: int = 0,
           progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """``by_n``: the 1 ms cycle; ``by_n_250us``: the 250 us cycle, the same N."""
    out: dict[str, Any] = {}
    for key, cycle_time in CYCLE_TIMES.items():
        by_n = {}
        for n in counts:
            if progress is not None:
                progress(f"ca: {n} movers, {cycles} cycles of {key}, gap control "
                         f"{'/'.join(MODES)} and the ruckig reference")
            by_n[str(n)] = run_one(n, cycles, seed, cycle_time=cycle_time)
        out["by_n" if key == "1ms" else f"by_n_{key}"] = by_n
    return {**out, "modes": list(MODES), "gap": GAP, "spacing": SPACING,
            "cycle_times": dict(CYCLE_TIMES)}
