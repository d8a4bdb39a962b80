"""`tracks` benchmark: movers circulating on a track network with four switches per oval.

The network (``build_network``) is an oval: two straights of ``STRAIGHT`` mm joined by half
circles of radius ``RADIUS``, each straight split into three tracks so that a siding can leave
it at one switch and come back at another, 400 mm beside it: four switches (two diverging,
two merging), ten tracks, closed in one direction of travel.

M movers (default counts 10, 100, 1000) run on ``ovals_for(M)`` such ovals, ``OVAL_PITCH``
apart in y, in one planar system: up to ``OVAL_MOVERS`` movers an oval, so every oval is as
crowded as the single oval of 100 (D-285: a longer oval would not do, since the curvature
blend at the start of a straight after a half circle grows with the straight's length and
bends it back across the other straight). The movers of an oval stand on its straights and
sidings ``SPACING`` mm apart, at least ``CLEAR`` from the track ends, turned along the track,
and join it; from a random cycle in the first ``START_SPREAD`` on, a mover whose last command
ended gets a MoveOnTrack to a random position on a random track of its oval (gap ``GAP``):
the route goes forward through the network, by the sidings where they are shorter, so movers
queue behind each other and meet at the switches. Every ``Runtime.step`` is timed (p50/p99
after a warm-up tenth); the traffic's compiled loops are all loaded before
(``traffic_kernels.warm``), so no cycle pays for loading one.

Checked every cycle on the published setpoints: no two movers on one track closer than the
follower's gap along it, and no two footprints (155 mm squares turned by c) overlapping
anywhere (``overlaps``; switches included). Both must be 0.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import shapely

import openmotion as om
from openmotion.bench.planar import near_pairs
from openmotion.planar import (
    MC_PlanarMover,
    MC_PlanarTrack,
    MoverVector,
    PlanarMoverParameters,
    PlanarState,
    PositionXYC,
    ST_MoveOnTrackOptions,
)
from openmotion.planar.traffic_kernels import warm

CYCLE_TIME = 0.001  #: [s]
STRAIGHT = 12000.0  #: [mm] length of each straight of the oval
RADIUS = 600.0  #: [mm] of the half circles
SIDING = 400.0  #: [mm] between a straight and its siding
SPACING = 210.0  #: [mm] between the movers at the start
CLEAR = 450.0  #: [mm] movers start this far from the ends of their tracks (outside the zones)
GAP = 200.0  #: [mm] gap of every MoveOnTrack (footprints stay apart on the half circles)
START_SPREAD = 300  #: movers get their first command in the first this many cycles
PAUSE = 200  #: a mover waits 1 to this many cycles between commands
FOOTPRINT = 155.0  #: [mm]
OVAL_MOVERS = 100  #: movers an oval carries at most (D-285)
OVAL_PITCH = 3000.0  #: [mm] between two ovals in y (sidings and footprints well apart)
DEFAULT_COUNTS = (10, 100, 1000)
CLOSE_REACH = 2 * SPACING  #: [mm] the closest centres are looked for among pairs this close
OVERLAP_TOLERANCE = 1e-6  #: [mm²] of overlap area that is rounding


def ovals_for(movers: int) -> int:
    """Ovals for ``movers`` movers: one per ``OVAL_MOVERS`` (D-285)."""
    return max(1, math.ceil(movers / OVAL_MOVERS))


def build_network(rt: om.Runtime, oval: int = 0) -> list[MC_PlanarTrack]:
    """Oval number ``oval`` (``OVAL_PITCH`` * ``oval`` up in y) with two sidings; returns the
    tracks, the loop's in travel order first."""
    third = STRAIGHT / 3.0
    base = OVAL_PITCH * oval
    top = 2.0 * RADIUS
    names = ("bottom1", "bottom2", "bottom3", "right", "top1", "top2", "top3", "left",
             "siding_bottom", "siding_top")
    suffix = f"_{oval}" if oval else ""
    tracks = {name: MC_PlanarTrack(rt, name + suffix) for name in names}
    t = tracks

    def _p(x: float, y: float) -> PositionXYC:
        return PositionXYC(x, base + y)

    t["bottom1"].append_line(_p(0.0, 0.0), _p(third, 0.0))
    t["bottom2"].start_from_track(t["bottom1"])
    t["bottom2"].append_line(_p(third, 0.0), _p(2 * third, 0.0))
    t["bottom3"].start_from_track(t["bottom2"])
    t["bottom3"].append_line(_p(2 * third, 0.0), _p(STRAIGHT, 0.0))
    t["right"].start_from_track(t["bottom3"])
    t["right"].append_circle(_p(STRAIGHT, 0.0), _p(STRAIGHT, top), _p(STRAIGHT, RADIUS), False)
    t["top1"].start_from_track(t["right"])
    t["top1"].append_line(_p(STRAIGHT, top), _p(2 * third, top))
    t["top2"].start_from_track(t["top1"])
    t["top2"].append_line(_p(2 * third, top), _p(third, top))
    t["top3"].start_from_track(t["top2"])
    t["top3"].append_line(_p(third, top), _p(0.0, top))
    t["left"].start_from_track(t["top3"])
    t["left"].append_circle(_p(0.0, top), _p(0.0, 0.0), _p(0.0, RADIUS), False)
    t["left"].end_at_track(t["bottom1"])
    shift = 0.25 * third
    t["siding_bottom"].start_from_track(t["bottom1"])
    t["siding_bottom"].append_line(_p(third + shift, -SIDING), _p(2 * third - shift, -SIDING))
    t["siding_bottom"].end_at_track(t["bottom3"])
    t["siding_top"].start_from_track(t["top1"])
    t["siding_top"].append_line(_p(2 * third - shift, top + SIDING),
                                _p(third + shift, top + SIDING))
    t["siding_top"].end_at_track(t["top3"])
    for track in tracks.values():
        track.enable()
    rt.run(3 * CYCLE_TIME)
    failed = [n for n, track in tracks.items() if track.state is not PlanarState.ENABLED]
    if failed:
        raise RuntimeError(f"benchmark set-up failed: tracks {failed} not enabled")
    return list(tracks.values())


def run_one(movers: int, cycles: int, seed: int = 0,
            progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    rng = np.random.default_rng(seed)
    warm()
    rt = om.Runtime(CYCLE_TIME)
    ovals = ovals_for(movers)
    networks = [build_network(rt, k) for k in range(ovals)]
    fleet: list[tuple[MC_PlanarMover, MC_PlanarTrack]] = []
    oval_of: list[int] = []  #: the oval each mover runs on
    for k, tracks in enumerate(networks):  # as many movers on each (the first ones one more)
        share = movers // ovals + (k < movers % ovals)
        placed = _place(rt, tracks, share, len(fleet))
        if len(placed) < share:
            raise ValueError(f"{share} movers {SPACING:g} mm apart do not fit the straights")
        fleet += placed
        oval_of += [k] * len(placed)
    tracks = [t for network in networks for t in network]
    total = sum(t.get_length() for t in tracks)
    for mover, _ in fleet:
        mover.enable()
    rt.run(3 * CYCLE_TIME)
    joins = [mover.join_track(track) for mover, track in fleet]
    rt.run(0.5)
    if not all(j.done for j in joins):
        bad = [j.message for j in joins if not j.done][:3]
        raise RuntimeError(f"benchmark set-up failed: joins {bad}")
    commands: list[Any] = [None] * movers
    ready = rng.integers(0, START_SPREAD, movers)
    options = ST_MoveOnTrackOptions(gap=GAP)
    counts = {"commands": 0, "done": 0, "errors": 0}
    times = np.zeros(cycles)
    overlaps, gap_violations, closest = 0, 0, math.inf
    for cycle in range(cycles):
        for i, (mover, _) in enumerate(fleet):
            command = commands[i]
            if command is not None and not command.busy:
                counts["done" if command.done else "errors"] += 1
                commands[i] = None
                ready[i] = cycle + rng.integers(1, PAUSE + 1)
            if commands[i] is None and cycle >= ready[i]:
                network = networks[oval_of[i]]
                track = network[int(rng.integers(len(network)))]
                target = float(rng.uniform(0.0, track.get_length()))
                commands[i] = mover.move_on_track(track, target, options=options)
                counts["commands"] += 1
        start = time.perf_counter()
        rt.step()
        times[cycle] = time.perf_counter() - start
        o, g, c = _check(fleet)
        overlaps += o
        gap_violations += g
        closest = min(closest, c)
        if progress is not None and cycle % 1000 == 999:
            progress(f"tracks: {movers} movers, cycle {cycle + 1}/{cycles}")
    us = times[cycles // 10:] * 1e6
    return {"movers": movers, "ovals": ovals, "tracks": len(tracks), "switches": 4 * ovals,
            "cycles": cycles,
            "network_mm": total, **counts,
            "cycle_us_p50": float(np.percentile(us, 50)),
            "cycle_us_p99": float(np.percentile(us, 99)),
            "cycle_us_max": float(us.max()), "cycle_us_mean": float(us.mean()),
            "overlaps": overlaps, "gap_violations": gap_violations,
            "closest_centres_mm": closest}


def _place(rt: om.Runtime, tracks: list[MC_PlanarTrack], movers: int, first: int
           ) -> list[tuple[MC_PlanarMover, MC_PlanarTrack]]:
    """Up to ``movers`` movers on the straights and sidings of one oval, ``SPACING`` apart,
    outside the collision ranges (no two footprints meet); named from m``first`` on."""
    straight = [t for t in tracks if t.name.split("_")[0] not in ("left", "right")]
    fleet = []  # c 0 or 180 on the straights: in a C window
    for track in straight:
        start, last = (max(CLEAR, r + GAP) for r in track.collision_ranges)
        s = start
        while s <= track.get_length() - last and len(fleet) < movers:
            where = track.get_position_at(s)  # c: in the C window nearest to the heading
            fleet.append((MC_PlanarMover(rt, PlanarMoverParameters(
                initial_position=MoverVector(where.x, where.y, c=90.0 * round(where.c / 90.0))),
                name=f"m{first + len(fleet)}"), track))
            s += SPACING
    return fleet


def _check(fleet: list[tuple[MC_PlanarMover, MC_PlanarTrack]]) -> tuple[int, int, float]:
    """Overlapping footprints, gap violations on one track, and the closest two centres
    (within ``CLOSE_REACH``)."""
    status = [mover.mc_to_plc for mover, _ in fleet]
    xy = np.array([(s.set.set_pos.x, s.set.set_pos.y) for s in status])
    first, second, distance = near_pairs(xy, CLOSE_REACH)
    near = distance < FOOTPRINT * math.sqrt(2.0)
    overlaps = 0
    for i, j in zip(first[near].tolist(), second[near].tolist(), strict=True):
        a, b = (_footprint(status[k].set.set_pos) for k in (i, j))
        if shapely.intersection(a, b).area > OVERLAP_TOLERANCE:
            overlaps += 1
    by_track: dict[int, list[float]] = {}
    for s in status:
        by_track.setdefault(s.set_on_track.track_oid, []).append(s.set_on_track.set_pos)
    violations = 0
    for positions in by_track.values():
        positions.sort()
        violations += sum(1 for a, b in zip(positions, positions[1:], strict=False)
                          if b - a < GAP - 1e-6)
    return overlaps, violations, float(distance.min(initial=math.inf))


def _footprint(position: Any) -> Any:
    half = FOOTPRINT / 2.0
    box = shapely.box(-half, -half, half, half)
    c, s = math.cos(math.radians(position.c)), math.sin(math.radians(position.c))
    return shapely.affinity.affine_transform(box, [c, -s, s, c, position.x, position.y])


def run_tracks(counts: Sequence[int] = DEFAULT_COUNTS, cycles: int = 5000, seed: int = 0,
               progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    by_n = {}
    for movers in counts:
        if progress is not None:
            progress(f"tracks: {movers} movers on {ovals_for(movers)} oval(s) of 10 tracks "
                     f"with 4 switches, {cycles} cycles")
        by_n[str(movers)] = run_one(movers, cycles, seed, progress)
    return {"by_n": by_n, "gap": GAP, "spacing": SPACING, "pause": PAUSE,
            "oval_movers": OVAL_MOVERS}
