"""`tracks` benchmark: movers circulating on a track network with four switches.

The network (``build_network``) is an oval: two straights of ``STRAIGHT`` mm joined by half
circles of radius ``RADIUS``, each straight split into three tracks so that a siding can leave
it at one switch and come back at another, 400 mm beside it: four switches (two diverging,
two merging), ten tracks, closed in one direction of travel.

M movers (default 100) stand on the straights and sidings ``SPACING`` mm apart, at least
``CLEAR`` from the track ends, turned along the track, and join it; from a random
cycle in the first ``START_SPREAD`` on, a mover whose last command ended gets a MoveOnTrack
to a random position on a random track (gap ``GAP``): the route goes forward through the
network, by the sidings where they are shorter, so movers queue behind each other and meet
at the switches. Every ``Runtime.step`` is timed (p50/p99 after a warm-up tenth); the
traffic's compiled loops are all loaded before (``traffic_kernels.warm``), so no cycle pays
for loading one.

Checked every cycle on the published setpoints: no two movers on one track closer than the
follower's gap along it, and no two footprints (155 mm squares turned by c) overlapping
anywhere (``overlaps``; switches included). Both must be 0.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import shapely

import openmotion as om
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
OVERLAP_TOLERANCE = 1e-6  #: [mm²] of overlap area that is rounding


def _p(x: float, y: float) -> PositionXYC:
    return PositionXYC(x, y)


def build_network(rt: om.Runtime) -> list[MC_PlanarTrack]:
    """The oval with two sidings; returns the tracks, the loop's in travel order first."""
    third = STRAIGHT / 3.0
    top = 2.0 * RADIUS
    names = ("bottom1", "bottom2", "bottom3", "right", "top1", "top2", "top3", "left",
             "siding_bottom", "siding_top")
    tracks = {name: MC_PlanarTrack(rt, name) for name in names}
    t = tracks
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
    tracks = build_network(rt)
    straight = [t for t in tracks if t.name not in ("left", "right")]  # c 0 or 180: in a window
    fleet = []
    for track in straight:  # outside the collision ranges: no two footprints meet
        first, last = (max(CLEAR, r + GAP) for r in track.collision_ranges)
        s = first
        while s <= track.get_length() - last and len(fleet) < movers:
            where = track.get_position_at(s)  # c: in the C window nearest to the heading
            fleet.append((MC_PlanarMover(rt, PlanarMoverParameters(
                initial_position=MoverVector(where.x, where.y, c=90.0 * round(where.c / 90.0))),
                name=f"m{len(fleet)}"), track))
            s += SPACING
    if len(fleet) < movers:
        raise ValueError(f"{movers} movers {SPACING:g} mm apart do not fit the straights")
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
                track = tracks[int(rng.integers(len(tracks)))]
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
    return {"movers": movers, "tracks": len(tracks), "switches": 4, "cycles": cycles,
            "network_mm": total, **counts,
            "cycle_us_p50": float(np.percentile(us, 50)),
            "cycle_us_p99": float(np.percentile(us, 99)),
            "cycle_us_max": float(us.max()),
            "overlaps": overlaps, "gap_violations": gap_violations,
            "closest_centres_mm": closest}


def _check(fleet: list[tuple[MC_PlanarMover, MC_PlanarTrack]]) -> tuple[int, int, float]:
    """Overlapping footprints, gap violations on one track, and the closest two centres."""
    status = [mover.mc_to_plc for mover, _ in fleet]
    xy = np.array([(s.set.set_pos.x, s.set.set_pos.y) for s in status])
    diff = xy[:, None, :] - xy[None, :, :]
    distance = np.hypot(diff[..., 0], diff[..., 1])
    np.fill_diagonal(distance, np.inf)
    near = np.argwhere(np.triu(distance < FOOTPRINT * math.sqrt(2.0)))
    overlaps = 0
    for i, j in near.tolist():
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
    return overlaps, violations, float(distance.min())


def _footprint(position: Any) -> Any:
    half = FOOTPRINT / 2.0
    box = shapely.box(-half, -half, half, half)
    c, s = math.cos(math.radians(position.c)), math.sin(math.radians(position.c))
    return shapely.affinity.affine_transform(box, [c, -s, s, c, position.x, position.y])


def run_tracks(movers: int = 100, cycles: int = 5000, seed: int = 0,
               progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    if progress is not None:
        progress(f"tracks: {movers} movers on 10 tracks with 4 switches, {cycles} cycles")
    return {"by_n": {str(movers): run_one(movers, cycles, seed, progress)},
            "gap": GAP, "spacing": SPACING, "pause": PAUSE}
