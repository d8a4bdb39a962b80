"""`ca` benchmark: N movers on a ring in one CA group, random modulo targets (performance.md).

N movers start evenly spread on a ring of 300 mm per mover (3000 mm for 10), gap 100 mm.
Each mover gets a MoveAbsoluteCA to a random modulo position (direction positive, random
velocity) whenever its last command ended, and at random times in between (aborting), so
queues form and dissolve all the time. Every cycle is timed (``Runtime.step``, gap control
included) and checked: no setpoint gap below the gap, no mover beyond its own limits.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import openmotion as om
from openmotion.transport import UDINT_TO_IDENTINGROUP, CaGroup, ModuloDirection

DEFAULT_COUNTS = (10, 100, 1000)
GAP = 100.0
SPACING = 300.0  #: rail length per mover [mm]
LIMITS = {"max_velocity": 4000.0, "acceleration": 10000.0, "deceleration": 10000.0,
          "jerk": 100000.0, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
          "max_jerk": 100000.0}


def build(n: int) -> tuple[om.Runtime, CaGroup, list[om.Axis]]:
    rt = om.Runtime(0.001)
    group = CaGroup(rt, "ca", rail_length=SPACING * n, default_gap=GAP)
    axes = []
    for i in range(n):
        axis = rt.add_axis(f"m{i}", position=i * SPACING, **LIMITS)
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
        axes.append(axis)
    group.enable()
    return rt, group, axes


def run_one(n: int, cycles: int, seed: int = 0) -> dict[str, Any]:
    rng = np.random.default_rng(seed)
    rt, group, axes = build(n)
    length = group.parameters.rail_length
    commands: list[om.Command | None] = [None] * n
    renew = rng.integers(1, 2000, n)  # cycle of the next aborting command per mover
    issued = done = 0
    rows = np.array([a.row for a in axes])
    k = rt._kernel
    vmax = np.array([a.parameters.max_velocity for a in axes])
    amax = np.array([a.parameters.max_acceleration for a in axes])
    dmax = np.array([a.parameters.max_deceleration for a in axes])
    jmax = np.array([a.parameters.max_jerk for a in axes])
    min_gap, limit_violations = np.inf, 0
    times = np.zeros(cycles)
    for cycle in range(cycles):
        for i, axis in enumerate(axes):
            command = commands[i]
            if command is None or command.finished or cycle >= renew[i]:
                done += command is not None and command.done
                commands[i] = group.move_absolute(
                    axis, float(rng.uniform(0.0, length)), float(rng.uniform(500.0, 3000.0)),
                    direction=ModuloDirection.POSITIVE)
                issued += 1
                renew[i] = cycle + rng.integers(200, 2000)
        start = time.perf_counter()
        rt.step()
        times[cycle] = time.perf_counter() - start
        min_gap = min(min_gap, float(group.gaps().min()))
        v, a, j = k.set_v[rows], k.set_a[rows], k.set_j[rows]
        braking = a * v < 0.0
        limit_violations += int(np.count_nonzero(
            (np.abs(v) > vmax * (1 + 1e-9)) | (np.abs(j) > jmax * (1 + 1e-9))
            | (~braking & (np.abs(a) > amax * (1 + 1e-9)))
            | (braking & (np.abs(a) > dmax * (1 + 1e-9)))))
    us = times[cycles // 10:] * 1e6  # after a warm-up tenth
    return {"movers": n, "cycles": cycles, "commands": issued, "done": done,
            "cycle_us_p50": float(np.percentile(us, 50)),
            "cycle_us_p99": float(np.percentile(us, 99)),
            "min_gap": min_gap, "gap_violations": int(min_gap < GAP - 1e-9),
            "limit_violations": limit_violations}


def run_ca(counts: Sequence[int] = DEFAULT_COUNTS, cycles: int = 3000, seed: int = 0,
           progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    by_n = {}
    for n in counts:
        if progress is not None:
            progress(f"ca: {n} movers, {cycles} cycles")
        by_n[str(n)] = run_one(n, cycles, seed)
    return {"by_n": by_n, "gap": GAP, "spacing": SPACING}
