"""Movers and their targets as the planner's agents on a routing grid, and why a mover
cannot be routed (the errors of docs/planar-routing.md). Used by the router for a route
call and by re-routing for the movers it plans again.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Protocol

import shapely
from shapely.geometry.base import BaseGeometry

from openmotion.core.errors import ConfigError
from openmotion.planar.enums import PlanarState
from openmotion.planar.positions import PositionXYC
from openmotion.planar.reservation import footprint
from openmotion.planar.routing.grid import RoutingGrid, build_grid, half_extents, meets
from openmotion.planar.routing.planner import Agent

if TYPE_CHECKING:
    from openmotion.planar.environment import MC_PlanarEnvironment
    from openmotion.planar.group import MC_PlanarGroup
    from openmotion.planar.mover import MC_PlanarMover
    from openmotion.planar.system import PlanarSystem

AT_POSE = 1e-6  #: a mover this close to a point stands on it [mm]
TURN_TOLERANCE = 1e-6  #: a target c this close to the mover's c needs no turn [°]
TURN_MARGIN = 2.0  #: a turning footprint is kept inside its disc grown by this [mm]
CANDIDATE_RINGS = 2  #: start and goal cells are looked for this many cells around a pose


class Setup(Protocol):
    """What a routing field is made from: the router's options."""

    group: MC_PlanarGroup
    system: PlanarSystem
    environment: MC_PlanarEnvironment
    obstacles: Sequence[BaseGeometry]
    obstacle_names: Sequence[str]
    pitch: float | None


def routing_field(setup: Setup, routed: Mapping[MC_PlanarMover, object]
                  ) -> tuple[RoutingGrid, BaseGeometry, list[BaseGeometry], list[str], float]:
    """The grid for ``routed`` movers (the group's other movers and the obstacles kept
    out), the grown stator surface, the obstacles with their labels, the cells' side."""
    group_movers = [m for m in setup.system.movers if m.group is setup.group]
    side = max(max(m.parameters.mover_width, m.parameters.mover_height)
               for m in (*routed, *group_movers))
    labels: list[str] = list(setup.obstacle_names)
    geometries: list[BaseGeometry] = list(setup.obstacles)
    for m in group_movers:
        if m not in routed:
            labels.append(mover_label(m))
            geometries.append(m.footprint())
    surface = setup.environment.surface
    grid = build_grid(surface, side, geometries, setup.pitch)
    grown = shapely.buffer(surface, 1e-6, join_style="mitre")
    shapely.prepare(grown)
    return grid, grown, geometries, labels, side


def make_agent(mover: MC_PlanarMover, target: PositionXYC, grid: RoutingGrid,
               surface: BaseGeometry, geometries: list[BaseGeometry], labels: list[str],
               targets: list[tuple[MC_PlanarMover, BaseGeometry]]) -> Agent:
    """The planner's agent of ``mover`` going to ``target``; Blocked when the target is off
    the surface, occupied or unreachable from any routing cell."""
    p = mover.parameters
    w, h = p.mover_width, p.mover_height
    x, y, c = mover.pose
    tx, ty, tc = finite(target)
    goal_print = footprint(tx, ty, tc, w, h)
    if not surface.covers(goal_print):
        raise Blocked(mover, "the stator surface",
                      f"its target ({tx:g}, {ty:g}, {tc:g}) leaves the stator surface")
    for label, geometry in zip(labels, geometries, strict=True):
        if meets(goal_print, geometry):
            raise Blocked(mover, label, f"its target ({tx:g}, {ty:g}) is occupied by "
                                        f"{label}")
    for other, geometry in targets:
        if meets(goal_print, geometry):
            raise Blocked(mover, mover_label(other),
                          f"its target ({tx:g}, {ty:g}) overlaps the target of "
                          f"{mover_label(other)}")
    hx, hy = half_extents(w, h, c)
    turn = abs(angle(tc - c)) > TURN_TOLERANCE
    radius = math.hypot(w, h) / 2.0 + TURN_MARGIN

    def sweep_ok(a: tuple[float, float], b: tuple[float, float], turning: bool) -> bool:
        if turning:
            area = shapely.buffer(shapely.linestrings([a, b]) if a != b else
                                  shapely.points(a), radius)
        else:
            area = shapely.convex_hull(shapely.union(footprint(*a, c, w, h),
                                                     footprint(*b, c, w, h)))
        return surface.covers(area) and not any(meets(area, g) for g in geometries)

    start_cell = nearest(grid, (x, y), lambda cen: sweep_ok((x, y), cen, False))
    if start_cell is None:
        raise Blocked(mover, "the stator surface", "its start pose lies on no free "
                                                  "routing cell")
    goal_cell = nearest(grid, (tx, ty), lambda cen: sweep_ok(cen, (tx, ty), turn)
                        and (not turn or sweep_ok((tx, ty), (tx, ty), True)))
    if goal_cell is None:
        raise Blocked(mover, "the stator surface", f"no routing cell leads to its target "
                                                  f"({tx:g}, {ty:g}, {tc:g}): too close to "
                                                  f"an edge or an obstacle to turn there"
                      if turn else f"no routing cell leads to its target ({tx:g}, {ty:g})")
    sc, gc = grid.centre(start_cell), grid.centre(goal_cell)
    start_leg = math.hypot(x - sc[0], y - sc[1]) > AT_POSE
    final_leg = math.hypot(tx - gc[0], ty - gc[1]) > AT_POSE or turn
    start_cells = grid.touched((x, y), sc, hx, hy) if start_leg else \
        grid.touched_cells(start_cell, start_cell, hx, hy)
    if turn:
        final_cells = grid.touched(gc, (tx, ty), radius, radius)
    else:
        thx, thy = half_extents(w, h, tc)
        final_cells = grid.touched(gc, (tx, ty), max(hx, thx), max(hy, thy))
    return Agent(mover.name, (x, y, c), (tx, ty, tc), hx, hy, start_cell, goal_cell,
                 start_cells, final_cells, start_leg, final_leg)


def nearest(grid: RoutingGrid, point: tuple[float, float], ok) -> int | None:  # noqa: ANN001
    """The free cell nearest to ``point`` (within CANDIDATE_RINGS) whose centre ``ok`` accepts."""
    px, py = grid.pitch
    cells = []
    x0, y0 = point
    for dj in range(-CANDIDATE_RINGS, CANDIDATE_RINGS + 1):
        for di in range(-CANDIDATE_RINGS, CANDIDATE_RINGS + 1):
            cell = grid.cell_at(x0 + di * px, y0 + dj * py)
            if cell is not None and grid.free[cell]:
                cx, cy = grid.centre(cell)
                cells.append((math.hypot(cx - x0, cy - y0), cell))
    for _, cell in sorted(set(cells)):
        if ok(grid.centre(cell)):
            return cell
    return None


def cut_off(agent: Agent, surface: BaseGeometry, side: float, labels: list[str],
            geometries: list[BaseGeometry], pitch: float | None) -> str:
    """What separates the mover from its target: the first obstacle or mover whose
    removal opens a way, else the stator surface."""
    from openmotion.planar.routing.planner import distances

    for k in range(len(geometries)):
        rest = geometries[:k] + geometries[k + 1:]
        grid = build_grid(surface, side, rest, pitch)
        if agent.start_cell in distances(grid, agent.goal_cell):
            return labels[k]
    return "the stator surface"


class Blocked(Exception):
    """A mover that cannot be routed: what blocks it and why."""

    def __init__(self, mover: MC_PlanarMover, blocker: str, reason: str) -> None:
        super().__init__(reason)
        self.mover = mover
        self.blocker = blocker
        self.reason = reason


def check_pairs(agents: list[Agent], movers: list[MC_PlanarMover]) -> None:
    """Refuse, naming the other mover, two movers whose starts or whose targets share a cell
    of the grid: the planner gives each mover one cell, so such a pair has no plan."""
    starts: dict[int, int] = {}
    for k, agent in enumerate(agents):
        for cell in agent.start_cells:
            if cell in starts:
                raise Blocked(movers[k], mover_label(movers[starts[cell]]),
                              f"it stands too close to {mover_label(movers[starts[cell]])} "
                              f"for the routing grid (one cell each)")
            starts[cell] = k
    goals: dict[int, int] = {}
    for k, agent in enumerate(agents):
        for cell in agent.final_cells:
            if cell in goals:
                raise Blocked(movers[k], mover_label(movers[goals[cell]]),
                              f"its target is too close to the target of "
                              f"{mover_label(movers[goals[cell]])} for the routing grid "
                              f"(one cell each)")
            goals[cell] = k


def not_routable(mover: MC_PlanarMover, group: MC_PlanarGroup, moving: bool = False
                  ) -> str | None:
    """Why ``mover`` cannot be routed (``moving``: it may be on a leg of the router)."""
    if mover.group is not group:
        return "is not in the router's group"
    if mover.state is not PlanarState.ENABLED:
        return f"is {mover.state.name}, not Enabled"
    if mover.in_motion and not moving:
        return "is moving: a route starts from standstill"
    return None


def mover_label(mover: MC_PlanarMover) -> str:
    return f"mover {mover.name} (16#{mover.oid:08X})"


def finite(target: PositionXYC) -> tuple[float, float, float]:
    values = (target.x, target.y, target.c)
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
        raise ConfigError(f"route target {target}: x, y and c must be finite numbers")
    return float(target.x), float(target.y), float(target.c)


def angle(d: float) -> float:
    return (d + 180.0) % 360.0 - 180.0


__all__ = ["AT_POSE", "CANDIDATE_RINGS", "TURN_MARGIN", "TURN_TOLERANCE", "Blocked", "Setup",
           "angle", "check_pairs", "cut_off", "finite", "make_agent", "mover_label", "nearest",
           "not_routable", "routing_field"]
