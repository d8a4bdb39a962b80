"""`planar` admission benchmark: free moves of M movers in one planar group (performance.md).

M movers (155 mm) stand at the centres of distinct stators of a square field with four stators
per mover, the environment in the group. Time runs on in steps of ``1000 // M`` cycles of 1 ms
between two commands, so each mover gets a command about once a second. Every step, the moving
movers advance along their sampled paths and release the area behind them; then one standing
mover, drawn at random, is sent to a random point up to two stators away in x and y, with a
random c in [-15, 15] degrees (a straight, smoothstep-timed MoveToPosition at 1 m/s, sampled
every cycle).

Timed separately: building the swept area (``area_us``), the admission check itself,
``ReservationRegistry.request`` (``admission_us``, the performance goal), and the release calls
(``release_us``). Checked: every sampled admission agrees with ``reference_blocker`` (shapely on
whole areas, member by member), and no two reserved areas ever overlap.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from openmotion.planar.enums import PlanarObjectType
from openmotion.planar.reservation import (
    MemberId,
    ReservationRegistry,
    SweptArea,
    footprint,
    swept_area,
)
from openmotion.planar.stators import STATOR_SIZE, StatorField

DEFAULT_COUNTS = (10, 100, 1000)
CYCLE_TIME = 0.001  #: path sample step [s]
VELOCITY = 1000.0  #: travel speed of the benchmark moves [mm/s]
C_VELOCITY = 360.0  #: turning speed of the benchmark moves [deg/s]
C_RANGE = 15.0  #: targets turn the mover within [-15, 15] degrees (the first C window)
REACH = 2 * STATOR_SIZE  #: targets lie within this distance of the start in x and in y [mm]
ENVIRONMENT = MemberId(PlanarObjectType.ENVIRONMENT, 0x05120010)
CHECKS = 200  #: admissions compared with the reference, spread over the run
OVERLAP_CHECKS = 10  #: times the whole registry is searched for overlapping areas


@dataclass
class _Mover:
    member: MemberId
    pose: np.ndarray  #: x, y, c where it stands or where its path ends
    path: np.ndarray | None = None  #: the path being followed, None when standing
    sample: int = 0  #: index of the sample reached


def reference_blocker(registry: ReservationRegistry, owner: MemberId,
                      area: SweptArea) -> MemberId | None:
    """The slow oracle: each member's whole area, in member order, with plain shapely."""
    geometry = area.geometry
    for member in registry.members:
        if member == owner:
            continue
        reserved = registry.reserved(member)
        if member.object_type == PlanarObjectType.ENVIRONMENT:
            if not reserved.is_empty and not reserved.covers(geometry):
                return member
        elif geometry.intersects(reserved) and not geometry.touches(reserved):
            return member
    return None


def overlapping_pairs(registry: ReservationRegistry) -> int:
    """Pairs of reserved areas (environment aside) whose interiors meet."""
    areas = [registry.reserved(m) for m in registry.members
             if m.object_type != PlanarObjectType.ENVIRONMENT]
    return sum(a.intersects(b) and not a.touches(b)
               for i, a in enumerate(areas) for b in areas[i + 1:])


def measure_admission(movers: int, commands: int, seed: int) -> dict[str, Any]:
    """Run ``commands`` admissions with ``movers`` movers; figures in µs, counts, checks."""
    rng = np.random.default_rng(seed)
    side = 2 * math.ceil(math.sqrt(movers))
    field = StatorField.rectangular(side, side)
    registry = ReservationRegistry()
    registry.add_member(ENVIRONMENT, field.create_boundary().surface)
    fleet = _place(registry, rng, movers, side)
    cycles = max(1, 1000 // movers)
    check_every = max(1, commands // CHECKS)
    times: dict[str, list[float]] = {"area": [], "admission": [], "release": []}
    counts = {"accepted": 0, "rejected_by_mover": 0, "rejected_by_environment": 0,
              "checked": 0, "mismatches": 0, "overlaps": 0}
    pieces = []
    issued = 0
    while issued < commands:
        _advance(registry, fleet, cycles, times["release"])
        standing = [m for m in fleet if m.path is None]
        if not standing:
            continue
        mover = standing[int(rng.integers(len(standing)))]
        path = _path(mover.pose, _target(rng, mover.pose, side))
        pieces.append(registry.piece_count)
        check = issued % check_every == 0
        _admit(registry, mover, path, times, counts, check)
        issued += 1
        if issued % max(1, commands // OVERLAP_CHECKS) == 0:
            counts["overlaps"] += overlapping_pairs(registry)
    rejected = counts["rejected_by_mover"] + counts["rejected_by_environment"]
    return {"movers": movers, "commands": commands, "stators": side * side,
            "cycles_per_command": cycles, **_percentiles(times),
            "rejected": rejected, **counts,
            "pieces_mean": float(np.mean(pieces))}


def run_planar_admission(counts: Sequence[int] = DEFAULT_COUNTS, commands: int = 2000,
                         seed: int = 0,
                         progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    by_n = {}
    for n in counts:
        if progress is not None:
            progress(f"planar admission: {n} movers, {commands} commands")
        by_n[str(n)] = measure_admission(n, commands, seed)
    return {"by_n": by_n}


def _place(registry: ReservationRegistry, rng: np.random.Generator, movers: int,
           side: int) -> list[_Mover]:
    cells = rng.choice(side * side, size=movers, replace=False)
    fleet = []
    for i, cell in enumerate(sorted(int(c) for c in cells)):
        pose = np.array([(cell % side + 0.5) * STATOR_SIZE, (cell // side + 0.5) * STATOR_SIZE,
                         0.0])
        member = MemberId(PlanarObjectType.MOVER, 0x05110010 + 0x10 * i)
        if registry.add_member(member, footprint(*pose)) is not None:
            raise RuntimeError(f"benchmark set-up: {member} blocked at its start")
        fleet.append(_Mover(member, pose))
    return fleet


def _target(rng: np.random.Generator, start: np.ndarray, side: int) -> np.ndarray:
    """A random pose within REACH of ``start`` on which any c keeps the footprint on the field."""
    edge = math.hypot(155.0, 155.0) / 2
    x, y = np.clip(start[:2] + rng.uniform(-REACH, REACH, size=2), edge,
                   side * STATOR_SIZE - edge)
    return np.array([x, y, rng.uniform(-C_RANGE, C_RANGE)])


def _path(start: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Straight move at about VELOCITY (or C_VELOCITY), smoothstep timing, a sample a cycle."""
    distance = float(np.hypot(*(target[:2] - start[:2])))
    turn = abs(float(target[2] - start[2]))
    samples = max(2, math.ceil(max(distance / VELOCITY, turn / C_VELOCITY) / CYCLE_TIME) + 1)
    s = np.linspace(0.0, 1.0, samples)
    s = s * s * (3.0 - 2.0 * s)
    return start + s[:, None] * (target - start)


def _advance(registry: ReservationRegistry, fleet: list[_Mover], cycles: int,
             release_times: list[float]) -> None:
    for mover in fleet:
        if mover.path is None:
            continue
        mover.sample = min(mover.sample + cycles, len(mover.path) - 1)
        if mover.sample == len(mover.path) - 1:
            registry.settle(mover.member, footprint(*mover.pose))
            mover.path = None
            continue
        start = time.perf_counter()
        registry.release(mover.member, mover.sample)
        release_times.append(time.perf_counter() - start)


def _admit(registry: ReservationRegistry, mover: _Mover, path: np.ndarray,
           times: dict[str, list[float]], counts: dict[str, int], check: bool) -> None:
    start = time.perf_counter()
    area = swept_area(path)
    built = time.perf_counter()
    expected = reference_blocker(registry, mover.member, area) if check else None
    before = time.perf_counter()
    blocker = registry.request(mover.member, area)
    times["area"].append(built - start)
    times["admission"].append(time.perf_counter() - before)
    if check:
        counts["checked"] += 1
        counts["mismatches"] += blocker != expected
    if blocker is None:
        counts["accepted"] += 1
        mover.path, mover.sample, mover.pose = path, 0, path[-1].copy()
    elif blocker.object_type == PlanarObjectType.ENVIRONMENT:
        counts["rejected_by_environment"] += 1
    else:
        counts["rejected_by_mover"] += 1


def _percentiles(times: dict[str, list[float]]) -> dict[str, float]:
    out = {}
    for name, values in times.items():
        us = np.asarray(values) * 1e6 if values else np.zeros(1)
        out[f"{name}_us_p50"] = float(np.percentile(us, 50))
        out[f"{name}_us_p99"] = float(np.percentile(us, 99))
    return out

