"""`planar` benchmark: M movers in one planar group on a stator field, random free moves.

Two figures of performance.md, per M (10, 100, 1000):

(a) The admission check per command: ``planar_admission.measure_admission`` (the group's
    ``ReservationRegistry.request`` on the swept area of a free move, timed alone, on a field
    with four stators per mover).

(b) The runtime cycle: M enabled movers (155 mm) in one enabled ``MC_PlanarGroup`` with the
    ``MC_PlanarEnvironment`` of a square field of ``side_for(M)`` stators a side (about 1.44
    stators per mover: 12 x 12 for 100, 4 x 4 for 10), each standing at the centre of its own
    stator. From a random cycle in the first ``START_SPREAD`` on, a mover whose last command
    ended gets a ``MoveToPosition`` (default dynamics, with c) to a random free stator up to
    ``REACH`` stators away in x and y: its centre moved by up to ``JITTER`` in x and y, at a
    random c in [-15, 15] degrees. Free: no mover stands there or is sent there, and no
    standing mover is in the rectangle of stators between start and target. Moving movers
    may be in the way, and a jittered, turned target may meet a neighbour or overhang the
    field's edge: the group then rejects the command (PLANAR_COLLISION), and the mover sends
    the same stator again after a random pause of up to ``RETRY_PAUSE`` cycles (another one
    if it is no longer free). A mover that finds no free stator waits such a pause too.

    Every ``Runtime.step`` is timed (p50/p99 after a warm-up tenth): all a cycle costs, the
    planning, swept areas and admission of the new commands included; also split into cycles
    in which no command was sent ("idle") and cycles with commands. The admissions inside
    the runtime are timed as well (``ReservationRegistry.request`` wrapped on the group's
    registry, ``request_us``), and so is reading every mover's published position after the
    cycle (``status_read_us``, what a PLC program pays that polls them all; not in the
    cycle). The run is repeated with translations only (target c = 0, kept: the exact and
    cheap swept area of a straight move).

Checked after every cycle, on the published set positions: no two footprints overlap by more
than ``OVERLAP_TOLERANCE`` (separating axes of the two rectangles; ``closest_gap_mm`` is the
smallest separation seen between two footprints whose centres came within a diagonal), and
no footprint leaves the stator surface. Both counts must be 0. Trace recording does not
cover planar movers yet, so the cycle is measured without it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

import openmotion as om
from openmotion.bench.planar_admission import measure_admission
from openmotion.core.errors import ErrorId
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    MoverVector,
    PlanarCommand,
    PlanarMoverParameters,
    PlanarObjectType,
    PlanarState,
    PositionXYC,
)
from openmotion.planar.stators import STATOR_SIZE

DEFAULT_COUNTS = (10, 100, 1000)
CYCLE_TIME = 0.001  #: [s]
STATORS_PER_MOVER = 1.44  #: field area per mover: 100 movers on 12 x 12 stators
REACH = 2  #: targets lie up to this many stators away in x and in y
C_RANGE = 15.0  #: target c within [-15, 15] degrees (the first C window)
JITTER = 30.0  #: targets lie up to this far from the stator centre in x and in y [mm]
OVERLAP_TOLERANCE = 1e-6  #: footprints may overlap by rounding only [mm]
SURFACE_TOLERANCE = 1e-6  #: how far a footprint may overhang the surface (rounding) [mm]
START_SPREAD = 300  #: movers get their first command at random in the first this many cycles
RETRY_PAUSE = 100  #: after a rejection a mover waits 1 to this many cycles


def side_for(movers: int) -> int:
    """Stators per side of the square field for ``movers`` movers."""
    return max(2, math.ceil(math.sqrt(STATORS_PER_MOVER * movers)))


@dataclass
class Fleet:
    """A built set-up: runtime, group, environment and movers with their stator cells."""

    runtime: om.Runtime
    group: MC_PlanarGroup
    environment: MC_PlanarEnvironment
    movers: list[MC_PlanarMover]
    side: int
    cells: list[int]  #: the stator cell each mover stands on (or last stood on)


def build(movers: int, seed: int = 0) -> Fleet:
    """Movers standing on distinct random stators of a ``side_for(movers)`` square field,
    enabled, in one enabled group with the environment."""
    rng = np.random.default_rng(seed)
    side = side_for(movers)
    rt = om.Runtime(CYCLE_TIME)
    environment = MC_PlanarEnvironment(rt)
    for i in range(side):
        for j in range(side):
            environment.add_stator(STATOR_SIZE * i, STATOR_SIZE * j)
    environment.create_boundary()
    group = MC_PlanarGroup(rt)
    group.enable()
    cells = sorted(int(c) for c in rng.choice(side * side, size=movers, replace=False))
    fleet = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(
        *_centre(cell, side))), name=f"m{i}") for i, cell in enumerate(cells)]
    for mover in fleet:
        mover.enable()
    rt.run(2 * CYCLE_TIME)
    joins = [mover.add_to_group(group) for mover in fleet]
    joins.append(environment.add_to_group(group))
    rt.step()
    rt.step()
    failed = [c for c in joins if not c.done]
    if failed or any(m.state is not PlanarState.ENABLED for m in fleet):
        raise RuntimeError(f"benchmark set-up failed: {failed[:3]}")
    return Fleet(rt, group, environment, fleet, side, cells)


def run_one(movers: int, cycles: int, seed: int = 0, c_range: float = C_RANGE
            ) -> dict[str, Any]:
    """Time ``cycles`` runtime cycles of ``movers`` movers with random free moves; target c
    uniform in [-c_range, c_range] (0: the movers keep c = 0, every move a translation)."""
    fleet = build(movers, seed)
    rng = np.random.default_rng(seed + 1)
    rt, side = fleet.runtime, fleet.side
    admissions = _time_admissions(fleet.group)
    commands: list[PlanarCommand | None] = [None] * movers
    targets: list[int | None] = [None] * movers  #: the cell a mover is sent to
    retry: list[int | None] = [None] * movers  #: the target of a rejected command
    ready = rng.integers(0, START_SPREAD, movers)  #: cycle from which a mover may be sent
    counts = {"commands": 0, "accepted": 0, "rejected_by_mover": 0,
              "rejected_by_environment": 0, "rejected_other": 0, "done": 0, "no_free_target": 0}
    safety = {"overlaps": 0, "off_surface": 0, "closest": math.inf}
    times = np.zeros(cycles)
    sent = np.zeros(cycles, dtype=np.int64)  #: commands sent before each cycle
    reads = np.zeros(cycles)  #: reading every mover's published set position
    issued = 0
    for cycle in range(cycles):
        for i in range(movers):  # the commands decided or ended in the last cycle
            command = commands[i]
            if command is None or command.busy:
                continue
            _count(counts, command, accepted=command.done)
            if command.done:
                fleet.cells[i] = targets[i]  # type: ignore[assignment]
            else:  # rejected: the same target again after a pause, if still free
                retry[i] = targets[i]
                ready[i] = cycle + rng.integers(1, RETRY_PAUSE + 1)
            commands[i] = targets[i] = None
        standing = {c for c, t in zip(fleet.cells, targets, strict=True) if t is None}
        claimed = set(fleet.cells) | {t for t in targets if t is not None}
        for i, mover in enumerate(fleet.movers):
            if commands[i] is not None or cycle < ready[i]:
                continue
            target, retry[i] = retry[i], None
            if target is None or target in claimed or \
                    not _route_free(fleet.cells[i], target, side, standing):
                target = _free_target(rng, fleet.cells[i], side, claimed, standing)
            if target is None:
                counts["no_free_target"] += 1
                ready[i] = cycle + rng.integers(1, RETRY_PAUSE + 1)
                continue
            claimed.add(target)
            standing.discard(fleet.cells[i])
            targets[i] = target
            x, y = np.add(_centre(target, side), rng.uniform(-JITTER, JITTER, 2))
            commands[i] = mover.move_to_position(
                PositionXYC(float(x), float(y),
                            float(rng.uniform(-c_range, c_range)) if c_range else 0.0))
            counts["commands"] += 1
        sent[cycle] = counts["commands"] - issued
        issued = counts["commands"]
        start = time.perf_counter()
        rt.step()
        times[cycle] = time.perf_counter() - start
        start = time.perf_counter()
        positions = [mover.position for mover in fleet.movers]  # what a PLC program reads
        reads[cycle] = time.perf_counter() - start
        _check(fleet, positions, safety)
    for command in commands:  # the last ones: running (accepted) or just decided
        if command is not None:
            _count(counts, command, accepted=command.done or command.active)
    warm = slice(cycles // 10, None)  # after a warm-up tenth
    us, busy = times[warm] * 1e6, sent[warm] > 0
    rejected = (counts["rejected_by_mover"] + counts["rejected_by_environment"]
                + counts["rejected_other"])
    return {"movers": movers, "stators": side * side, "cycles": cycles, **counts,
            "rejected": rejected, **_stats("cycle_us", us),
            "cycle_us_max": float(us.max()), "cycle_us_mean": float(us.mean()),
            **_stats("idle_cycle_us", us[~busy]), **_stats("command_cycle_us", us[busy]),
            "command_cycles": int(np.count_nonzero(busy)),
            **_stats("request_us", np.asarray(admissions) * 1e6),
            **_stats("status_read_us", reads[warm] * 1e6),
            "overlaps": safety["overlaps"], "off_surface": safety["off_surface"],
            "closest_gap_mm": None if math.isinf(safety["closest"]) else safety["closest"]}


def run_planar(counts: Sequence[int] = DEFAULT_COUNTS, cycles: int = 5000,
               commands: int = 2000, seed: int = 0,
               progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Per mover count: the admission figures of ``planar_admission`` (``commands``
    admissions), the runtime cycle over ``cycles`` cycles with turning moves (the figures
    judged), and the same with translations only (target c kept: the cheap exact area)."""
    by_n, translation = {}, {}
    for n in counts:
        if progress is not None:
            progress(f"planar: {n} movers, admission check, {commands} commands")
        admission = measure_admission(n, commands, seed)
        if progress is not None:
            progress(f"planar: {n} movers, {cycles} cycles, moves with c")
        by_n[str(n)] = {**run_one(n, cycles, seed), "admission": admission}
        if progress is not None:
            progress(f"planar: {n} movers, {cycles} cycles, translations")
        translation[str(n)] = run_one(n, cycles, seed, c_range=0.0)
    return {"by_n": by_n, "translation": translation, "reach": REACH, "c_range": C_RANGE,
            "stators_per_mover": STATORS_PER_MOVER, "retry_pause": RETRY_PAUSE}


# -- helpers ---------------------------------------------------------------------------------


def _centre(cell: int, side: int) -> tuple[float, float]:
    return (cell % side + 0.5) * STATOR_SIZE, (cell // side + 0.5) * STATOR_SIZE


def _free_target(rng: np.random.Generator, cell: int, side: int, claimed: set[int],
                 standing: set[int]) -> int | None:
    """A random cell within REACH of ``cell`` that no mover stands on or is sent to, with a
    route free of standing movers (moving ones may be in the way: the group decides)."""
    column, row = cell % side, cell // side
    free = [r * side + c
            for r in range(max(0, row - REACH), min(side, row + REACH + 1))
            for c in range(max(0, column - REACH), min(side, column + REACH + 1))
            if r * side + c not in claimed and _route_free(cell, r * side + c, side, standing)]
    return None if not free else free[int(rng.integers(len(free)))]


def _route_free(cell: int, target: int, side: int, standing: set[int]) -> bool:
    """No other mover stands in the rectangle of stators that ``cell`` and ``target`` span."""
    (c0, r0), (c1, r1) = (cell % side, cell // side), (target % side, target // side)
    return not any(r * side + c in standing and r * side + c != cell
                   for r in range(min(r0, r1), max(r0, r1) + 1)
                   for c in range(min(c0, c1), max(c0, c1) + 1))


def near_pairs(xy: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Index pairs (i, j) of the points ``xy`` (n, 2) closer than ``reach``, and their
    distances: a sweep along x (the pairs within ``reach`` in x), not all n² pairs."""
    order = np.argsort(xy[:, 0], kind="stable")
    x = xy[order, 0]
    ends = np.searchsorted(x, x + reach, side="right")
    index = np.arange(len(x))
    firsts, seconds = [], []
    for k in range(1, int((ends - index).max(initial=1))):
        i = index[index + k < ends]
        firsts.append(order[i])
        seconds.append(order[i + k])
    if not firsts:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, np.zeros(0)
    i, j = np.concatenate(firsts), np.concatenate(seconds)
    distance = np.hypot(*(xy[i] - xy[j]).T)
    close = distance < reach
    return i[close], j[close], distance[close]


def _stats(name: str, us: np.ndarray) -> dict[str, float | None]:
    """p50 and p99 of ``us`` as ``name_p50``, ``name_p99`` (None when there is no sample)."""
    if us.size == 0:
        return {f"{name}_p50": None, f"{name}_p99": None}
    return {f"{name}_p50": float(np.percentile(us, 50)),
            f"{name}_p99": float(np.percentile(us, 99))}


def _count(counts: dict[str, int], command: PlanarCommand, accepted: bool) -> None:
    if accepted:
        counts["accepted"] += 1
        counts["done"] += command.done
    elif command.error and command.error_id == ErrorId.PLANAR_COLLISION:
        kind = command.object_info.object_type
        counts["rejected_by_environment" if kind is PlanarObjectType.ENVIRONMENT
               else "rejected_by_mover"] += 1
    elif command.error:
        counts["rejected_other"] += 1
    else:  # aborted: the benchmark never aborts, but count it as accepted
        counts["accepted"] += 1


def _time_admissions(group: MC_PlanarGroup) -> list[float]:
    """Time every ``request`` the group's registry answers (instance attribute, no edit)."""
    registry = group.registry
    request = registry.request
    times: list[float] = []

    def timed(*args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        result = request(*args, **kwargs)
        times.append(time.perf_counter() - start)
        return result

    registry.request = timed  # type: ignore[method-assign]
    return times


def _check(fleet: Fleet, positions: list[MoverVector], safety: dict[str, Any]) -> None:
    """Count overlapping footprint pairs and footprints off the surface (set positions)."""
    pose = np.array([(p.x, p.y, p.c) for p in positions])
    width = fleet.movers[0].parameters.mover_width
    height = fleet.movers[0].parameters.mover_height
    angle = np.radians(pose[:, 2])
    cos, sin = np.cos(angle), np.sin(angle)
    axes = np.stack([np.stack([cos, sin], 1), np.stack([-sin, cos], 1)], 1)  # (n, 2, 2)
    half = np.array([width / 2, height / 2])
    # corners against the field's sides (the surface is the whole square)
    reach = np.abs(axes[:, 0, :]) * half[0] + np.abs(axes[:, 1, :]) * half[1]  # (n, 2)
    size = fleet.side * STATOR_SIZE
    off = ((pose[:, :2] - reach < -SURFACE_TOLERANCE)
           | (pose[:, :2] + reach > size + SURFACE_TOLERANCE)).any(1)
    safety["off_surface"] += int(np.count_nonzero(off))
    # pairs whose centres are closer than a diagonal may overlap: separating axes
    i, j, _ = near_pairs(pose[:, :2], math.hypot(width, height))
    if i.size == 0:
        return
    d = pose[i, :2] - pose[j, :2]  # (k, 2)
    test = np.concatenate([axes[i], axes[j]], 1)  # (k, 4, 2): each rectangle's edge normals
    # each rectangle's half extent along every test axis
    extent_i = (np.abs(np.einsum("kad,kbd->kab", test, axes[i])) * half).sum(-1)
    extent_j = (np.abs(np.einsum("kad,kbd->kab", test, axes[j])) * half).sum(-1)
    gap = (np.abs(np.einsum("kad,kd->ka", test, d)) - extent_i - extent_j).max(1)
    safety["overlaps"] += int(np.count_nonzero(gap < -OVERLAP_TOLERANCE))
    safety["closest"] = min(safety["closest"], float(gap.min()))
