"""`routing` benchmark: the planar router on MagBotSim's planning layouts and at 78 movers.

Instances:

- MagBotSim's ten planning layouts B0-B9 (planar/layouts.py, 3 to 5 movers): the movers stand
  on distinct random stator centres and get distinct random stator centres as targets (c = 0);
  the router's cells are the stators (``pitch`` 240 mm). ``SEEDS`` instances per layout.
- A Planar-Motor-scale case: 78 movers on a 10 x 10 stator field (2.4 m square), starts and
  distinct targets drawn from the router's default cells (15 x 15 of 160 mm), with a
  planning budget of ``BIG_TIME_BUDGET`` (the first plan comes much earlier, D-341).

Per instance: whether every mover arrived, the planner's time to its first plan (wall and
the planning thread's CPU time) and in all (its budget ``TIME_BUDGET``), the makespan (the
route call to the last arrival, in runtime time) against the lower bound (the slowest
mover's own time-optimal move with its default dynamics, alone on the field: one profile over
the shortest way round the field's holes, D-355; the straight line's is reported beside it),
the commands the group
refused and, checked after every cycle on the set positions, overlapping footprints and
footprints off the stator surface.
"""

from __future__ import annotations

import heapq
import math
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

import openmotion as om
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    MoverVector,
    PlanarMoverParameters,
    PlanarState,
)
from openmotion.planar.layouts import MAGBOTSIM_LAYOUTS, Layout, square
from openmotion.planar.routing import Router
from openmotion.planar.routing.grid import build_grid
from openmotion.planar.stators import STATOR_SIZE
from openmotion.trajectory.double_s import rest_to_rest

CYCLE_TIME = 0.001  #: [s]
SEEDS = 3  #: instances per MagBotSim layout
BIG_MOVERS = 78  #: Planar Motor plans routes for up to this many movers per command
BIG_SIDE = 10  #: stators a side of the big field
TIME_BUDGET = 0.05  #: the router's planning budget per instance [s]
BIG_TIME_BUDGET = 0.5  #: the planning budget at Planar Motor's scale (D-341) [s]
TIMEOUT = 60.0  #: runtime seconds an instance may take before it counts as failed
OVERLAP_TOLERANCE = 1e-6  #: [mm]
WAY_SLACK = 1e-6  #: [mm] the free space grows by this: a centre on its edge is inside

Progress = Callable[[str], None] | None


def lower_bound(mover: MC_PlanarMover, target: tuple[float, float],
                free: BaseGeometry | None = None) -> float:
    """[s] of the mover's own time-optimal move to ``target`` with its default dynamics,
    alone on the field: one rest-to-rest profile over the shortest way its centre can take
    (``free``: where its centre may be, see ``free_space``; None: the straight line)."""
    x, y, _ = mover.pose
    d = math.hypot(target[0] - x, target[1] - y) if free is None else shortest_way(
        free, (x, y), target)
    limits = mover.parameters.default_dynamic_xy
    profile = rest_to_rest(0.0, d, limits.velocity, limits.acceleration, limits.jerk, 0.0)
    return float(profile[0, -1])


def free_space(surface: BaseGeometry, mover: MC_PlanarMover) -> BaseGeometry:
    """Where the centre of ``mover`` (turned as it stands, c = 0 here) keeps its footprint on
    ``surface``: the surface shrunk by half the footprint, with square corners."""
    half = 0.5 * max(mover.parameters.mover_width, mover.parameters.mover_height)
    free = shapely.buffer(surface, -half + WAY_SLACK, join_style="mitre")
    shapely.prepare(free)
    return free


def shortest_way(free: BaseGeometry, start: tuple[float, float],
                 goal: tuple[float, float]) -> float:
    """[mm] of the shortest way from ``start`` to ``goal`` inside ``free`` (a polygon or
    several): Dijkstra over the visibility graph of the two points and the corners of
    ``free``, where shortest ways in a polygon bend. The straight line where it lies inside;
    inf where no way joins them."""
    direct = math.dist(start, goal)
    if free.covers(shapely.LineString([start, goal])):
        return direct
    points = [tuple(start), tuple(goal)]
    for polygon in getattr(free, "geoms", [free]):
        for ring in (polygon.exterior, *polygon.interiors):
            points += [tuple(c) for c in list(ring.coords)[:-1]]
    best = {0: 0.0}
    heap, done = [(0.0, 0)], set()
    while heap:
        length, u = heapq.heappop(heap)
        if u in done:
            continue
        if u == 1:
            return length
        done.add(u)
        for v in range(len(points)):
            if v in done:
                continue
            further = length + math.dist(points[u], points[v])
            if further < best.get(v, math.inf) and free.covers(
                    shapely.LineString([points[u], points[v]])):
                best[v] = further
                heapq.heappush(heap, (further, v))
    return math.inf


def _field(layout: Layout) -> tuple[om.Runtime, MC_PlanarEnvironment, MC_PlanarGroup]:
    rt = om.Runtime(CYCLE_TIME)
    environment = MC_PlanarEnvironment(rt)
    for x, y in layout.stators():
        environment.add_stator(x, y)
    environment.create_boundary()
    group = MC_PlanarGroup(rt)
    group.enable()
    return rt, environment, group


def run_instance(layout: Layout, starts: Sequence[tuple[float, float]],
                 targets: Sequence[tuple[float, float]], pitch: float | None,
                 time_budget: float = TIME_BUDGET) -> dict[str, Any]:
    """Route movers from ``starts`` to ``targets`` on ``layout``; measure and check."""
    rt, environment, group = _field(layout)
    movers = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(*s)),
                             name=f"m{k}") for k, s in enumerate(starts)]
    for mover in movers:
        mover.enable()
    rt.run(2 * CYCLE_TIME)
    for mover in movers:
        mover.add_to_group(group)
    environment.add_to_group(group)
    rt.step()
    rt.step()
    if any(m.state is not PlanarState.ENABLED or m.group is not group for m in movers):
        raise RuntimeError(f"{layout.name}: benchmark set-up failed")
    free = free_space(environment.surface, movers[0])
    bound = max(lower_bound(m, t, free) for m, t in zip(movers, targets, strict=True))
    straight = max(lower_bound(m, t) for m, t in zip(movers, targets, strict=True))
    router = Router(group, environment, time_budget=time_budget, pitch=pitch)
    rejected_before = 0
    started = time.perf_counter()
    handles = router.route({m: (*t, 0.0) for m, t in zip(movers, targets, strict=True)})
    call_s = time.perf_counter() - started
    plan = router.stats.plans[-1] if router.stats.plans else None
    begin = rt.now
    surface = shapely.buffer(environment.surface, 1e-6, join_style="mitre")
    shapely.prepare(surface)
    safety = {"overlaps": 0, "off_surface": 0}
    while router.busy and rt.now - begin < TIMEOUT:
        rt.step()
        _check(movers, surface, safety)
    arrived = sum(h.done for h in handles.values())
    makespan = rt.now - begin
    rejected = router.stats.rejected - rejected_before
    return {
        "layout": layout.name, "movers": len(movers), "arrived": arrived,
        "success": arrived == len(movers),
        "first_plan_ms": None if plan is None else 1e3 * plan.first_time,
        # the planning thread's CPU time: what the wall time would be on an idle core
        "first_plan_cpu_ms": None if plan is None else 1e3 * plan.first_cpu,
        "plan_ms": None if plan is None else 1e3 * plan.time,
        "route_call_ms": 1e3 * call_s,
        "orders_tried": None if plan is None else plan.tried,
        "makespan_s": makespan, "lower_bound_s": bound, "straight_bound_s": straight,
        "ratio": (makespan / bound if bound > 0 else 1.0) if arrived == len(movers) else None,
        "legs": router.stats.legs, "held_back": router.stats.held_back,
        "rejected": rejected, **safety,
        "errors": [h.message for h in handles.values() if h.error][:3],
    }


def _check(movers: list[MC_PlanarMover], surface: Any, safety: dict[str, int]) -> None:
    poses = np.array([tuple(m.pose) for m in movers])
    prints = [m.footprint() for m in movers]
    off = ~shapely.covers(surface, prints)
    safety["off_surface"] += int(np.count_nonzero(off))
    diagonal = math.hypot(movers[0].parameters.mover_width, movers[0].parameters.mover_height)
    delta = poses[:, None, :2] - poses[None, :, :2]
    i, j = np.nonzero(np.triu(np.hypot(delta[..., 0], delta[..., 1]) < diagonal, 1))
    for a, b in zip(i.tolist(), j.tolist(), strict=True):
        if shapely.area(shapely.intersection(prints[a], prints[b])) > OVERLAP_TOLERANCE:
            safety["overlaps"] += 1


def magbotsim_instances(seeds: int = SEEDS) -> list[tuple[Layout, list, list]]:
    """(layout, starts, targets) per layout and seed: distinct random stator centres."""
    out = []
    for layout in MAGBOTSIM_LAYOUTS:
        centres = [(float(x), float(y)) for x, y in layout.centres()]
        for seed in range(seeds):
            rng = np.random.default_rng(seed)
            starts = rng.choice(len(centres), layout.movers, replace=False)
            targets = rng.choice(len(centres), layout.movers, replace=False)
            out.append((layout, [centres[k] for k in starts], [centres[k] for k in targets]))
    return out


def big_instance(movers: int = BIG_MOVERS, side: int = BIG_SIDE, seed: int = 0
                 ) -> tuple[Layout, list, list]:
    """``movers`` random starts and distinct random targets on the router's default cells
    of a ``side`` x ``side`` stator field."""
    layout = square(side, movers, name=f"square{side}x{side}")
    surface = shapely.box(0.0, 0.0, side * STATOR_SIZE, side * STATOR_SIZE)
    grid = build_grid(surface, max(PlanarMoverParameters().mover_width,
                                   PlanarMoverParameters().mover_height))
    cells = [c for c in range(grid.size) if grid.free[c]]
    rng = np.random.default_rng(seed)
    starts = rng.choice(len(cells), movers, replace=False)
    targets = rng.choice(len(cells), movers, replace=False)
    return (layout, [grid.centre(cells[k]) for k in starts],
            [grid.centre(cells[k]) for k in targets])


def run_routing(seeds: int = SEEDS, big: Sequence[int] = (BIG_MOVERS,), big_seeds: int = 1,
                progress: Progress = None) -> dict[str, Any]:
    say = progress or (lambda _: None)
    rows = []
    for layout, starts, targets in magbotsim_instances(seeds):
        say(f"routing: {layout.name} ({layout.movers} movers)")
        rows.append(run_instance(layout, starts, targets, pitch=STATOR_SIZE))
    big_rows = []
    for movers in big:
        for seed in range(big_seeds):
            say(f"routing: {movers} movers on {BIG_SIDE} x {BIG_SIDE} stators (seed {seed})")
            layout, starts, targets = big_instance(movers, seed=seed)
            big_rows.append(run_instance(layout, starts, targets, pitch=None,
                                         time_budget=BIG_TIME_BUDGET))
    return {"magbotsim": rows, "big": big_rows, "summary": _summary(rows, big_rows)}


def _summary(rows: list[dict[str, Any]], big_rows: list[dict[str, Any]]) -> dict[str, Any]:
    def part(items: list[dict[str, Any]]) -> dict[str, Any]:
        if not items:
            return {}
        planned = [r for r in items if r["first_plan_ms"] is not None]
        arrived = [r["ratio"] for r in items if r["ratio"] is not None]
        return {
            "instances": len(items),
            "success_rate": sum(r["success"] for r in items) / len(items),
            # None: some instance found no plan (or none arrived): the goal is not met
            "first_plan_ms_max": max(r["first_plan_ms"] for r in planned)
            if len(planned) == len(items) else None,
            "first_plan_cpu_ms_max": max(r["first_plan_cpu_ms"] for r in planned)
            if len(planned) == len(items) else None,
            "plan_ms_max": max(r["plan_ms"] for r in planned)
            if len(planned) == len(items) else None,
            "ratio_max": max(arrived) if len(arrived) == len(items) else None,
            "ratio_mean": sum(arrived) / len(arrived) if arrived else None,
            "rejected": sum(r["rejected"] for r in items),
            "overlaps": sum(r["overlaps"] for r in items),
            "off_surface": sum(r["off_surface"] for r in items),
        }
    return {"magbotsim": part(rows), "big": part(big_rows)}
