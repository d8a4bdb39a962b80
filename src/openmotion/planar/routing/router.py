"""The planar router: plans routes for a group's movers and drives them with TF5430 commands.

``Router(group)`` joins the runtime as a program. ``route({mover: target, ...})`` plans at
once (planner.py) and returns one ``RouteCommand`` per mover with PLCopen-style outputs
(busy, done, error, error_id, command_aborted, message). Each cycle the router then sends
every mover whose next leg may start a MoveToPosition (MoveC for a final turn):

- the plan's order is kept: a leg starts only when the movers that the plan lets through
  its cells before it have passed them or are on the leg that passes them (an action
  dependency graph of the plan), so the movers cannot wait on each other in a circle,
  whatever their real speeds;
- consecutive moves in one direction become one leg, planned time-optimally by the mover,
  lengthened in motion when the steps after it are released; any-angle legs skip the
  grid's staircases where the plan leaves room;
- before sending, the router asks the group whether it would admit the leg's swept area
  now (``ReservationRegistry.blocker``) and waits a cycle if not: the group's own check
  still decides every command, so safety never rests on the plan.

A new target mid-route, a mover that stops driving and a part that moves re-plan only the
movers concerned around the routes the others keep (``plan_around``, D-344 to D-346).

Movers not routed, static obstacles given to the router, the stator surface (parts where
they stand) are kept out of the plan; an unreachable or occupied target ends the mover's
command with ``PLANAR_COLLISION`` and a message naming the blocker, and the other movers are
routed around it standing where it is (docs/planar-routing.md).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import shapely
from shapely.geometry.base import BaseGeometry

from openmotion.core.errors import ConfigError, ErrorId
from openmotion.kernel.command import Command, CommandStatus
from openmotion.planar.enums import PlanarState
from openmotion.planar.options import ST_MoveToPositionOptions
from openmotion.planar.positions import PositionXYC
from openmotion.planar.reservation import footprint
from openmotion.planar.routing.grid import (
    CLEARANCE,
    RoutingGrid,
    build_grid,
    half_extents,
    meets,
)
from openmotion.planar.routing.planner import (
    FOREVER,
    Agent,
    Plan,
    Planner,
    PlanningFailed,
    Route,
    plan_around,
)

if TYPE_CHECKING:
    from openmotion.planar.environment import MC_PlanarEnvironment
    from openmotion.planar.group import MC_PlanarGroup
    from openmotion.planar.mover import MC_PlanarMover
    from openmotion.planar.options import IPlcDynamicConstraint

PLANNING_LIMIT = 5.0  #: a route call gives up on the movers left after this long [s]
DEFAULT_TIME_BUDGET = 0.05  #: planning time a route call may spend improving its plan [s]
AT_POSE = 1e-6  #: a mover this close to a point stands on it [mm]
TURN_TOLERANCE = 1e-6  #: a target c this close to the mover's c needs no turn [°]
TURN_MARGIN = 2.0  #: a turning footprint is kept inside its disc grown by this [mm]
CANDIDATE_RINGS = 2  #: start and goal cells are looked for this many cells around a pose
_TRANSLATE = ST_MoveToPositionOptions(use_orientation=False)
_TURN = ST_MoveToPositionOptions(use_orientation=True)


class RouteCommand(Command):
    """The handle of one mover's route: Busy until it stands on its target (Done), or Error
    with ``error_id`` and a ``message`` naming the blocker, or CommandAborted when another
    command took the mover or the group stopped it."""

    __slots__ = ("mover", "target", "blocker", "route")

    def __init__(self, mover: MC_PlanarMover, target: PositionXYC, issued_at: float) -> None:
        super().__init__("Route", issued_at)
        self.mover = mover
        self.target = target
        self.blocker: str | None = None  #: what keeps it from its target, when it failed
        self.route: list[tuple[float, float]] = []  #: the planned way (centres) [mm]

    @property
    def command_aborted(self) -> bool:
        """PLCopen's CommandAborted."""
        return self.aborted

    def __repr__(self) -> str:
        detail = f" {self.error_id.name}: {self.message}" if self.error else ""
        return f"<RouteCommand {self.mover.name} {self.status.name}{detail}>"


@dataclass
class _Leg:
    command: object  #: the mover's PlanarCommand
    first: int  #: the route point it starts from
    last: int  #: the route point it ends on (-1: the final turn)
    start: tuple[float, float]
    end: tuple[float, float]
    shortcut: bool = False  #: off the plan's cells order: its points count when it ends
    previous: _Leg | None = None  #: the leg in motion it carries on (kept if it is refused)


@dataclass
class _Drive:
    """The execution of one mover's route."""

    handle: RouteCommand
    route: Route
    deps: list[list[tuple[int, int]]]  #: per step: (agent, points it must have reached)
    index: int = 0  #: its agent number in the plan
    reached: int = 0
    leg: _Leg | None = None
    turned: bool = False
    waits: int = 0

    @property
    def mover(self) -> MC_PlanarMover:
        return self.handle.mover


@dataclass
class RouterStats:
    """What the router did since it was made."""

    legs: int = 0  #: commands sent
    rejected: int = 0  #: commands the group refused (the router retries them)
    held_back: int = 0  #: legs kept for a cycle because the group would refuse them
    extended: int = 0  #: legs sent in motion to carry on along the same line
    replans: int = 0  #: movers' routes re-planned around the others' (D-344)
    plans: list[Plan] = field(default_factory=list)


class Router:
    """Routes movers of ``group`` around each other, the surface's edges, parts, movers it
    does not route and ``obstacles`` (shapely geometries in the group's frame, with names
    from ``obstacle_names``). ``pitch`` sets the routing cells' side (e.g. 240 mm: one cell
    per stator, their centres the stators' centres); by default the cells are as small as the
    largest mover allows, which leaves the most room between movers."""

    def __init__(self, group: MC_PlanarGroup, environment: MC_PlanarEnvironment | None = None,
                 *, obstacles: Sequence[BaseGeometry] = (),
                 obstacle_names: Sequence[str] | None = None,
                 constraint: IPlcDynamicConstraint | None = None,
                 time_budget: float = DEFAULT_TIME_BUDGET, pitch: float | None = None,
                 seed: int = 0) -> None:
        self.group = group
        self.system = group.system
        self.environment = environment or self.system.environment()
        if self.environment is None:
            raise ConfigError("Router: the runtime has no MC_PlanarEnvironment")
        self.obstacles = tuple(obstacles)
        names = list(obstacle_names or [])
        self.obstacle_names = tuple(names[i] if i < len(names) else f"obstacle {i}"
                                    for i in range(len(self.obstacles)))
        self.constraint = constraint
        self.time_budget = time_budget
        #: the routing cell's side [mm]; None: the smallest that holds the largest mover
        self.pitch = pitch
        self.seed = seed
        self.stats = RouterStats()
        self.grid: RoutingGrid | None = None
        self._drives: list[_Drive] = []
        self._visits: dict[int, list[tuple[int, int, int]]] = {}
        #: the prepared stator surface and the obstacles of the last plan (for shortcuts)
        self._static: tuple[BaseGeometry | None, list[BaseGeometry]] = (None, [])
        self._replan_when_standing: tuple[dict[MC_PlanarMover, RouteCommand], float] | None = None
        #: movers to re-plan around the routes the others keep, once they stand (D-344)
        self._pending: dict[MC_PlanarMover, RouteCommand] = {}
        self._stopped: list[_Drive] = []  #: stopped drives to stand for good where they stop
        self._surface: BaseGeometry | None = None  #: the stator surface the plan was made on
        self._budget = time_budget  #: planning time of the re-plans waiting [s]
        self.system.runtime.add_program(self._cycle)

    # -- planning ---------------------------------------------------------------------------

    @property
    def busy(self) -> bool:
        return any(d.handle.busy for d in self._drives)

    @property
    def routes(self) -> dict[str, list[tuple[float, float]]]:
        """The planned way of every mover routed last, by mover name (for plots)."""
        return {d.mover.name: list(d.handle.route) for d in self._drives}

    def route(self, targets: Mapping[MC_PlanarMover, PositionXYC | Sequence[float]],
              time_budget: float | None = None) -> dict[MC_PlanarMover, RouteCommand]:
        """Plan routes of ``targets``' movers to their poses (x, y, c) and start them in the
        next cycle. While other routes run, only these movers (and those whose remaining
        routes meet where they stand or go) are re-planned around the routes the others
        keep, once they stand; the others go on (D-344)."""
        now = self.system.now
        budget = self.time_budget if time_budget is None else time_budget
        wanted: dict[MC_PlanarMover, PositionXYC] = {}
        for mover, target in targets.items():
            wanted[mover] = target if isinstance(target, PositionXYC) else PositionXYC(
                *[float(v) for v in target])
            _finite(wanted[mover])  # a bad target is a Python error before anything changes
        running = {d.mover: d for d in self._drives if d.handle.busy}
        handles: dict[MC_PlanarMover, RouteCommand] = {}
        for mover, target in wanted.items():
            drive = running.get(mover)
            if drive is not None and drive.handle.target is target:  # the same route goes on
                handles[mover] = drive.handle
                continue
            old = self._pending.pop(mover, None)
            for replaced in (old, drive and drive.handle):
                if replaced is not None and replaced.busy:
                    replaced.end(CommandStatus.ABORTED, now, ErrorId.NO_ERROR,
                                 f"{mover.name}: a new route replaced it")
            handles[mover] = RouteCommand(mover, target, now)
        if not running and not self._pending and self._replan_when_standing is None:
            self._plan(handles, budget)
            return handles
        for mover, handle in handles.items():
            drive = running.get(mover)
            if drive is not None and drive.handle is handle:
                continue
            problem = _not_routable(mover, self.group, moving=drive is not None)
            if problem:
                handle.end(CommandStatus.ERROR, now, ErrorId.PLANAR_WRONG_STATE,
                           f"{mover.name}: {problem}")
                if drive is not None:  # it stays where it stops: the others go around it
                    drive.leg = None
                    self._stop(drive)
                continue
            if drive is not None:  # it ends the leg it is on and is re-planned standing
                drive.handle = handle
            self._pending[mover] = handle
        self._budget = budget
        if self._replan_when_standing is not None:  # a full plan waits: join it
            waiting, _ = self._replan_when_standing
            waiting.update(self._pending)
            self._pending = {}
        else:
            self._replan_around()
        return handles

    def _plan(self, handles: dict[MC_PlanarMover, RouteCommand], budget: float) -> None:
        """Plan ``handles``' movers once every one of them stands (a moving one first ends
        its leg: ``_cycle`` calls again)."""
        if any(d.leg is not None for d in self._drives):
            self._replan_when_standing = (handles, budget)  # no new leg until all stand
            return
        self._replan_when_standing = None
        failed: dict[MC_PlanarMover, str] = {}
        active = {m: h for m, h in handles.items() if h.busy}
        for m, h in active.items():
            problem = _not_routable(m, self.group)
            if problem:
                failed[m] = problem
                h.blocker = None
                h.end(CommandStatus.ERROR, self.system.now, ErrorId.PLANAR_WRONG_STATE,
                      f"{m.name}: {problem}")
        routed = {m: h for m, h in active.items() if m not in failed}
        plan = None
        started = time.perf_counter()
        for _ in range(len(routed) + 1):
            if not routed:
                break
            if time.perf_counter() - started > PLANNING_LIMIT:  # give up on the rest
                for m, h in routed.items():
                    h.blocker = "other movers"
                    h.end(CommandStatus.ERROR, self.system.now, ErrorId.PLANAR_COLLISION,
                          f"{m.name}: no route found within {PLANNING_LIMIT:g} s of planning")
                routed = {}
                break
            try:
                plan, agents = self._plan_once(routed, budget)
            except _Blocked as blocked:
                handle = routed.pop(blocked.mover)
                handle.blocker = blocked.blocker
                handle.end(CommandStatus.ERROR, self.system.now, ErrorId.PLANAR_COLLISION,
                           f"{blocked.mover.name}: {blocked.reason}")
                continue
            break
        self._drives = []
        self._pending, self._stopped = {}, []
        if plan is None:
            return
        self.stats.plans.append(plan)
        movers = list(routed)
        deps, self._visits = _dependencies(plan.routes)
        for k, route in enumerate(plan.routes):
            handle = routed[movers[k]]
            handle.route = list(route.points)
            handle.start()
            self._drives.append(_Drive(handle, route, deps[k], k))

    def _field(self, routed: Mapping[MC_PlanarMover, RouteCommand]
               ) -> tuple[RoutingGrid, BaseGeometry, list[BaseGeometry], list[str], float]:
        """The grid for ``routed`` movers (the group's other movers and the obstacles kept
        out), the grown stator surface, the obstacles with their labels, the cells' side."""
        group_movers = [m for m in self.system.movers if m.group is self.group]
        side = max(max(m.parameters.mover_width, m.parameters.mover_height)
                   for m in (*routed, *group_movers))
        labels: list[str] = list(self.obstacle_names)
        geometries: list[BaseGeometry] = list(self.obstacles)
        for m in group_movers:
            if m not in routed:
                labels.append(_mover_label(m))
                geometries.append(m.footprint())
        surface = self.environment.surface
        grid = build_grid(surface, side, geometries, self.pitch)
        grown = shapely.buffer(surface, 1e-6, join_style="mitre")
        shapely.prepare(grown)
        return grid, grown, geometries, labels, side

    def _plan_once(self, routed: dict[MC_PlanarMover, RouteCommand], budget: float
                   ) -> tuple[Plan, list[Agent]]:
        grid, grown, geometries, labels, side = self._field(routed)
        surface = self.environment.surface
        self.grid = grid
        self._surface = surface
        self._static = (grown, list(self.obstacles))
        agents: list[Agent] = []
        targets: list[tuple[MC_PlanarMover, BaseGeometry]] = []
        for mover, handle in routed.items():
            agent = self._agent(mover, handle.target, grid, grown, geometries, labels, targets)
            targets.append((mover, footprint(*agent.target, mover.parameters.mover_width,
                                             mover.parameters.mover_height)))
            agents.append(agent)
        _check_pairs(agents, list(routed))
        planner = Planner(grid, agents)
        for mover, agent in zip(routed, agents, strict=True):
            if agent.start_cell not in planner.distance(agent):
                blocker = self._cut_off(agent, surface, side, labels, geometries)
                raise _Blocked(mover, blocker, f"its target cannot be reached: {blocker} "
                                               f"cuts it off")
        try:
            plan = planner.plan(budget, self.seed)
        except PlanningFailed as failed:
            mover = list(routed)[agents.index(failed.agent)]
            raise _Blocked(mover, "other movers", f"no route found: {failed.reason}") from None
        return plan, agents

    def _agent(self, mover: MC_PlanarMover, target: PositionXYC, grid: RoutingGrid,
               surface: BaseGeometry, geometries: list[BaseGeometry], labels: list[str],
               targets: list[tuple[MC_PlanarMover, BaseGeometry]]) -> Agent:
        p = mover.parameters
        w, h = p.mover_width, p.mover_height
        x, y, c = mover.pose
        tx, ty, tc = _finite(target)
        goal_print = footprint(tx, ty, tc, w, h)
        if not surface.covers(goal_print):
            raise _Blocked(mover, "the stator surface",
                           f"its target ({tx:g}, {ty:g}, {tc:g}) leaves the stator surface")
        for label, geometry in zip(labels, geometries, strict=True):
            if meets(goal_print, geometry):
                raise _Blocked(mover, label, f"its target ({tx:g}, {ty:g}) is occupied by "
                                             f"{label}")
        for other, geometry in targets:
            if meets(goal_print, geometry):
                raise _Blocked(mover, _mover_label(other),
                               f"its target ({tx:g}, {ty:g}) overlaps the target of "
                               f"{_mover_label(other)}")
        hx, hy = half_extents(w, h, c)
        turn = abs(_angle(tc - c)) > TURN_TOLERANCE
        radius = math.hypot(w, h) / 2.0 + TURN_MARGIN

        def sweep_ok(a: tuple[float, float], b: tuple[float, float], turning: bool) -> bool:
            if turning:
                area = shapely.buffer(shapely.linestrings([a, b]) if a != b else
                                      shapely.points(a), radius)
            else:
                area = shapely.convex_hull(shapely.union(footprint(*a, c, w, h),
                                                         footprint(*b, c, w, h)))
            return surface.covers(area) and not any(meets(area, g) for g in geometries)

        start_cell = self._nearest(grid, (x, y), lambda cen: sweep_ok((x, y), cen, False))
        if start_cell is None:
            raise _Blocked(mover, "the stator surface", "its start pose lies on no free "
                                                       "routing cell")
        goal_cell = self._nearest(grid, (tx, ty), lambda cen: sweep_ok(cen, (tx, ty), turn)
                                  and (not turn or sweep_ok((tx, ty), (tx, ty), True)))
        if goal_cell is None:
            raise _Blocked(mover, "the stator surface", f"no routing cell leads to its target "
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

    @staticmethod
    def _nearest(grid: RoutingGrid, point: tuple[float, float], ok) -> int | None:  # noqa: ANN001
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

    def _cut_off(self, agent: Agent, surface: BaseGeometry,
                 side: float, labels: list[str], geometries: list[BaseGeometry]) -> str:
        """What separates the mover from its target: the first obstacle or mover whose
        removal opens a way, else the stator surface."""
        from openmotion.planar.routing.planner import distances

        for k in range(len(geometries)):
            rest = geometries[:k] + geometries[k + 1:]
            grid = build_grid(surface, side, rest, self.pitch)
            if agent.start_cell in distances(grid, agent.goal_cell):
                return labels[k]
        return "the stator surface"

    # -- execution --------------------------------------------------------------------------

    def _cycle(self) -> None:
        """The router's program: follow the legs sent, re-plan what a new target, a stopped
        mover or a moved part affects, send the next legs (phase 1)."""
        if not self._drives:
            return
        now = self.system.now
        for drive in self._drives:
            self._follow(drive, now)
        pending = self._replan_when_standing
        if pending is not None:
            if all(d.leg is None for d in self._drives):
                self._plan(*pending)
            return
        self._watch_surface()
        if self._stopped:
            self._settle_stopped()
        if self._pending:
            self._replan_around()
            if self._replan_when_standing is not None:
                return
        sent: list[BaseGeometry] = []
        # a mover in motion counts the points its leg ends on: those waiting for it may
        # send as soon as the group admits their leg, i.e. once it actually cleared the area
        reached = [d.leg.last if d.leg is not None and d.leg.last >= 0 else d.reached
                   for d in self._drives]
        for drive in self._drives:
            if not drive.handle.busy or drive.mover in self._pending:
                continue
            if drive.leg is None:
                self._next_leg(drive, reached, sent)
            else:
                self._extend(drive, reached, sent)

    # -- re-routing -------------------------------------------------------------------------

    def _progress(self, drive: _Drive) -> int:
        """The first step of the drive's route still ahead of it."""
        return drive.leg.first if drive.leg is not None and drive.leg.last >= 0 else \
            drive.reached

    def _remaining(self, drive: _Drive) -> set[int]:
        """The cells the drive's route still occupies."""
        occupied = drive.route.occupied
        return {cell for cells in occupied[2 * self._progress(drive):] for cell in cells}

    def _standing_route(self, drive: _Drive) -> Route:
        """The route of a mover that stands where it is for good (stopped, or arrived)."""
        assert self.grid is not None
        mover = drive.mover
        x, y, c = mover.pose
        hx, hy = half_extents(mover.parameters.mover_width, mover.parameters.mover_height, c)
        return Route(drive.route.agent, [(x, y)], [self.grid.touched((x, y), (x, y), hx, hy)],
                     [-1])

    def _rebuild(self) -> None:
        """The plan's order of passage per cell again, from every drive's route (the movers
        that no longer drive stand where they are for good)."""
        for drive in self._drives:
            if not drive.handle.busy and drive not in self._stopped and \
                    not drive.mover.in_motion and len(drive.route.points) > 1:
                drive.route = self._standing_route(drive)
                drive.reached = 0
        routes = [d.route for d in self._drives]
        deps, self._visits = _dependencies(routes)
        standing = {k for k, d in enumerate(self._drives) if not d.handle.busy}
        for index, drive in enumerate(self._drives):
            drive.index = index
            # nobody waits for a mover that no longer drives: the grid and the group keep
            # the others off it (its cells are counted generously here)
            drive.deps = [[(a, need) for a, need in step if a not in standing]
                          for step in deps[index]]

    def _settle_stopped(self) -> None:
        """A stopped mover stands where it stopped for good: the routes that still meet the
        cells under it are re-planned around it (D-345)."""
        settled = [d for d in self._stopped if not d.mover.in_motion]
        if not settled or self.grid is None:
            return
        for drive in settled:
            self._stopped.remove(drive)
            self._pending.pop(drive.mover, None)
            drive.leg = None
            drive.route = self._standing_route(drive)
            drive.reached = 0
            cells = set(drive.route.occupied[0])
            for other in self._drives:
                if other.handle.busy and other.mover not in self._pending and \
                        cells & self._remaining(other):
                    self._pending[other.mover] = other.handle
        self._rebuild()

    def _watch_surface(self) -> None:
        """A part moved (the surface changed): movers it carried and routes over stators that
        left are re-planned on the surface as it is now (D-346)."""
        surface = self.environment.surface
        if surface is self._surface or surface is None or self.grid is None:
            return
        self._surface = surface
        grown = shapely.buffer(surface, 1e-6, join_style="mitre")
        shapely.prepare(grown)
        self._static = (grown, list(self.obstacles))
        old = self.grid
        movers = {d.mover for d in self._drives} | {m for m in self.system.movers
                                                     if m.group is self.group}
        side = max(max(m.parameters.mover_width, m.parameters.mover_height) for m in movers)
        grid = build_grid(surface, side, self.obstacles, self.pitch)
        if (grid.bounds, grid.nx, grid.ny) != (old.bounds, old.nx, old.ny):  # all again
            handles = {d.mover: d.handle for d in self._drives if d.handle.busy}
            handles.update(self._pending)
            self._pending = {}
            if handles:
                self._replan_when_standing = (handles, self._budget)
            return
        gone = {cell for cell in range(grid.size) if old.free[cell] and not grid.free[cell]}
        for drive in self._drives:
            if not drive.handle.busy or drive.mover in self._pending:
                continue
            x, y, _ = drive.mover.pose
            here = drive.route.points[min(self._progress(drive), len(drive.route.points) - 1)]
            carried = drive.leg is None and math.hypot(x - here[0], y - here[1]) > AT_POSE
            if carried or gone & self._remaining(drive):
                self._pending[drive.mover] = drive.handle
        self._rebuild()

    def _replan_around(self) -> None:
        """Plan the pending movers, once they stand, around the routes the others keep
        (``plan_around``); a kept route that meets where a pending mover stands or ends joins
        them. Without a plan, every mover on its way is planned again together (D-303)."""
        pending = self._pending
        for mover in [m for m, h in pending.items() if not h.busy]:
            del pending[mover]
        while pending:
            if any(m.in_motion for m in pending):
                return
            kept = [d for d in self._drives if d.handle.busy and d.mover not in pending]
            planned = self._around(kept)
            if planned is None:  # joined by kept movers, or failed: next cycle
                return
            if planned:
                break
        else:
            return
        self._pending = {}
        self._rebuild()

    def _around(self, kept: list[_Drive]) -> bool | None:
        """One attempt of ``_replan_around``: True when planned, False when kept movers
        joined the pending ones (try again), None to wait or after the fall-back."""
        pending = self._pending
        now = self.system.now
        routed = {**pending, **{d.mover: d.handle for d in kept}}
        try:
            grid, grown, geometries, labels, side = self._field(routed)
        except ConfigError:
            grid = None
        if grid is None or self.grid is None or \
                (grid.bounds, grid.nx, grid.ny) != (self.grid.bounds, self.grid.nx, self.grid.ny):
            self._fall_back()
            return None
        prints = [(d.mover, footprint(*d.route.agent.target, d.mover.parameters.mover_width,
                                      d.mover.parameters.mover_height)) for d in kept]
        agents: dict[MC_PlanarMover, Agent] = {}
        planner = None
        for mover, handle in list(pending.items()):
            try:
                agent = self._agent(mover, handle.target, grid, grown, geometries, labels, prints)
                planner = Planner(grid, [agent])
                if agent.start_cell not in planner.distance(agent):
                    blocker = self._cut_off(agent, self.environment.surface, side, labels,
                                            geometries)
                    raise _Blocked(mover, blocker, f"its target cannot be reached: {blocker} "
                                                   f"cuts it off")
            except _Blocked as blocked:
                del pending[mover]
                handle.blocker = blocked.blocker
                handle.end(CommandStatus.ERROR, now, ErrorId.PLANAR_COLLISION,
                           f"{mover.name}: {blocked.reason}")
                drive = next((d for d in self._drives if d.mover is mover), None)
                if drive is not None:  # it stays where it is: the others go around it
                    self._stop(drive)
                continue
            agents[mover] = agent
            prints.append((mover, footprint(*agent.target, mover.parameters.mover_width,
                                            mover.parameters.mover_height)))
        if not agents:
            return True
        mine: set[int] = set()
        for agent in agents.values():
            mine |= set(agent.start_cells) | set(agent.final_cells) | set(
                grid.touched_cells(agent.goal_cell, agent.goal_cell, agent.hx, agent.hy))
        joined = [d for d in kept if mine & self._remaining(d)]
        if joined:
            for drive in joined:
                pending[drive.mover] = drive.handle
            return False
        progress = [self._progress(d) for d in kept]
        start = max(progress, default=0)
        planner = Planner(grid, list(agents.values()))
        started = time.perf_counter()
        try:
            routes = plan_around(planner, [d.route for d in kept], progress, start)
        except PlanningFailed:
            self._fall_back()
            return None
        self.grid = grid
        self.stats.replans += 1
        self.stats.plans.append(Plan(routes, list(range(len(routes))),
                                     first_time=time.perf_counter() - started,
                                     time=time.perf_counter() - started, tried=1))
        drives = {d.mover: d for d in self._drives}
        for mover, route in zip(agents, routes, strict=True):
            handle = pending[mover]
            handle.route = list(route.points[start:])
            handle.start()
            drive = drives.get(mover)
            if drive is None:
                self._drives.append(_Drive(handle, route, [], len(self._drives)))
                continue
            drive.handle, drive.route, drive.reached = handle, route, 0
            drive.leg, drive.turned, drive.waits = None, False, 0
        return True

    def _fall_back(self) -> None:
        """Every mover still on its way is planned again together once all stand (D-303)."""
        handles = {d.mover: d.handle for d in self._drives if d.handle.busy}
        handles.update(self._pending)
        self._pending = {}
        self._replan_when_standing = (handles, self._budget)

    def _follow(self, drive: _Drive, now: float) -> None:
        leg = drive.leg
        handle = drive.handle
        if not handle.busy:
            return
        mover = drive.mover
        if mover.state is not PlanarState.ENABLED or mover.group is not self.group:
            drive.leg = None
            handle.end(CommandStatus.ABORTED, now, ErrorId.NO_ERROR,
                       f"{mover.name} is {mover.state.name} or left the group")
            self._stop(drive)
            return
        if leg is None:
            return
        command = leg.command
        if command.done:  # type: ignore[attr-defined]
            drive.leg = None
            if leg.last < 0:
                drive.turned = True
            else:
                drive.reached = leg.last
        elif command.error:  # type: ignore[attr-defined]
            drive.leg = leg.previous  # a refused extension leaves the leg in motion going
            self.stats.rejected += 1
            if drive.leg is not None:
                return
        elif command.aborted:  # type: ignore[attr-defined]
            drive.leg = None
            handle.end(CommandStatus.ABORTED, now, ErrorId.NO_ERROR,
                       f"{mover.name}: its leg was aborted by another command")
            self._stop(drive)
            return
        elif leg.last >= 0 and not leg.shortcut:  # passed points count as it moves
            x, y, _ = mover.pose
            sx, sy = leg.start
            ex, ey = leg.end
            length = math.hypot(ex - sx, ey - sy)
            if length > 0.0:
                travelled = ((x - sx) * (ex - sx) + (y - sy) * (ey - sy)) / length
                points = drive.route.points
                k = drive.reached
                while k + 1 < leg.last and math.hypot(points[k + 1][0] - sx,
                                                      points[k + 1][1] - sy) <= travelled:
                    k += 1
                drive.reached = k
        if drive.leg is None and mover not in self._pending and self._arrived(drive):
            handle.end(CommandStatus.DONE, now)

    def _stop(self, drive: _Drive) -> None:
        """The mover left the route (halted, stopped, disabled, in error, taken by another
        command): once it stands, the routes it is in the way of are re-planned."""
        self._pending.pop(drive.mover, None)
        if drive not in self._stopped:
            self._stopped.append(drive)

    def _arrived(self, drive: _Drive) -> bool:
        if drive.reached < len(drive.route.points) - 1:
            return False
        return not self._needs_turn(drive) or drive.turned

    def _needs_turn(self, drive: _Drive) -> bool:
        return abs(_angle(drive.route.agent.target[2] - drive.mover.pose.c)) > TURN_TOLERANCE

    def _ready(self, drive: _Drive, step: int, reached: list[int]) -> bool:
        return all(reached[a] >= need for a, need in drive.deps[step])

    def _straight_end(self, drive: _Drive, k: int, reached: list[int]) -> int:
        """The last route point of the straight run from point ``k`` whose steps the plan's
        order lets start now (waits inside the run are skipped once they are released)."""
        points = drive.route.points
        last = len(points) - 1
        direction = _unit(points[k], points[k + 1])
        end = k + 1
        while end < last and self._ready(drive, end, reached):
            if points[end + 1] == points[end]:
                nxt = end + 1
                while nxt < last and points[nxt + 1] == points[nxt]:
                    nxt += 1
                if nxt == last or _unit(points[nxt], points[nxt + 1]) != direction or \
                        not all(self._ready(drive, s, reached) for s in range(end, nxt + 1)):
                    break
                end = nxt
                continue
            if _unit(points[end], points[end + 1]) != direction:
                break
            end += 1
        return end

    def _next_leg(self, drive: _Drive, reached: list[int], sent: list[BaseGeometry]) -> None:
        points = drive.route.points
        k = drive.reached
        last = len(points) - 1
        while k < last and points[k + 1] == points[k] and self._ready(drive, k, reached):
            k += 1  # a wait of the plan: the movers it waited for have passed
        drive.reached = k
        if k == last:
            if self._needs_turn(drive) and not drive.turned:
                self._send_turn(drive, sent)
            elif self._arrived(drive):
                drive.handle.end(CommandStatus.DONE, self.system.now)
            return
        if not self._ready(drive, k, reached):
            return
        end = self._straight_end(drive, k, reached)
        shortcut = self._shortcut(drive, k, end, reached)
        for last_point in (shortcut, end):
            if last_point is not None and self._send(drive, k, last_point,
                                                     last_point is shortcut, sent):
                return
        self.stats.held_back += 1  # the group would refuse even the plan's own leg: wait
        drive.waits += 1

    def _extend(self, drive: _Drive, reached: list[int], sent: list[BaseGeometry]) -> None:
        """A leg in motion along the plan's cells goes on along the same line when the steps
        after its end are released now: the longer MoveToPosition starts from the mover's
        motion on that line, so it does not stop at the old end (§7.2.2.8.1)."""
        leg = drive.leg
        if leg is None or leg.last < 0 or leg.shortcut or leg.last >= len(drive.route.points) - 1:
            return
        if not self._ready(drive, leg.last, reached):
            return
        end = self._straight_end(drive, leg.first, reached)
        if end > leg.last and self._send(drive, leg.first, end, False, sent):
            self.stats.extended += 1

    def _send(self, drive: _Drive, k: int, last_point: int, off_plan: bool,
              sent: list[BaseGeometry]) -> bool:
        """Send a MoveToPosition from where the mover is to route point ``last_point`` when
        the group would admit its swept area now (and no leg sent this cycle meets it). The
        last leg turns to the target's c on the way when the turn stays in one C window
        (§4.2): no MoveC at standstill after it."""
        mover = drive.mover
        x, y, c = mover.pose
        p = mover.parameters
        target = drive.route.points[last_point]
        turn = self._turn_on_the_way(drive, last_point, c)
        if turn is not None:
            area = shapely.buffer(shapely.linestrings([(x, y), target]) if (x, y) != target
                                  else shapely.points(x, y),
                                  math.hypot(p.mover_width, p.mover_height) / 2.0 + TURN_MARGIN)
            if not self._static[0] or not self._static[0].covers(area) or \
                    any(meets(area, o) for o in self.obstacles):
                turn = None
        if turn is None:
            area = shapely.convex_hull(shapely.union(
                footprint(x, y, c, p.mover_width, p.mover_height),
                footprint(*target, c, p.mover_width, p.mover_height)))
        if self.group.registry.blocker(mover.member, area) is not None or \
                any(meets(area, other) for other in sent):
            return False
        sent.append(area)
        command = mover.move_to_position(
            PositionXYC(target[0], target[1], c if turn is None else turn,
                        mover.coordinate_system), self.constraint,
            _TRANSLATE if turn is None else _TURN)
        self.stats.legs += 1
        start = (x, y) if drive.leg is None else drive.leg.start
        if drive.leg is not None:
            drive.leg.previous = None
        drive.leg = _Leg(command, k, last_point, start, target, off_plan, drive.leg)
        return True

    def _turn_on_the_way(self, drive: _Drive, last_point: int, c: float) -> float | None:
        """The target's c when the leg to ``last_point`` ends the route and may turn there on
        the way (the turn stays inside one C window, §4.2), else None."""
        if last_point != len(drive.route.points) - 1 or not self._needs_turn(drive):
            return None
        end = c + _angle(drive.route.agent.target[2] - c)
        if not drive.mover.parameters.c_windows.contains_interval(min(c, end), max(c, end)):
            return None
        return end

    def _shortcut(self, drive: _Drive, k: int, straight_end: int, reached: list[int]
                  ) -> int | None:
        """The farthest route point beyond ``straight_end`` that a straight leg from point
        ``k`` may reach (any angle). The leg's swept area stays on the surface and off the
        obstacles; where it ends the mover stands early, so the cells under it there are
        held by no other mover in the plan from step k to that point and whoever held them
        before has passed. The cells it only sweeps need no more than the group's own check
        at sending: another mover coming there later waits for the leg to pass, and a
        mover in motion never waits for anyone (docs/planar-routing.md)."""
        points = drive.route.points
        last = len(points) - 1
        if self.grid is None or straight_end >= last:
            return None
        agent = drive.route.agent
        me = drive.index
        start = points[k]
        for end in range(last, straight_end, -1):
            if points[end] == points[end - 1] and end < last:
                continue
            if not all(self._ready(drive, s, reached) for s in range(k, end)):
                continue
            stand = self.grid.touched(points[end], points[end], agent.hx, agent.hy)
            if self._clear(stand, 2 * k, 2 * end, me, reached) and \
                    self._on_surface(drive, start, points[end]):
                return end
        return None

    def _on_surface(self, drive: _Drive, a: tuple[float, float], b: tuple[float, float]
                    ) -> bool:
        """Whether the footprint's sweep from a to b stays on the surface and meets none of
        the router's static obstacles (movers it does not route are the group's business)."""
        surface, obstacles = self._static
        if surface is None:
            return False
        p = drive.mover.parameters
        c = drive.route.agent.start[2]
        area = shapely.convex_hull(shapely.union(footprint(*a, c, p.mover_width, p.mover_height),
                                                 footprint(*b, c, p.mover_width, p.mover_height)))
        return bool(surface.covers(area)) and not any(meets(area, o) for o in obstacles)

    def _clear(self, cells: tuple[int, ...], first: int, last: int, me: int,
               reached: list[int]) -> bool:
        """Whether the mover may stand on ``cells`` from half-step ``first`` of its plan
        until ``last``: every other mover the plan lets through them until then has passed
        (or is on the leg that passes them: the group holds the leg back until it has), and
        none parks on them."""
        for cell in cells:
            for start, end, agent in self._visits.get(cell, ()):
                if agent == me or start > last + 1:
                    continue
                if end >= FOREVER or reached[agent] < end // 2 + 1:
                    return False
        return True

    def _send_turn(self, drive: _Drive, sent: list[BaseGeometry]) -> None:
        mover = drive.mover
        x, y, _ = mover.pose
        p = mover.parameters
        area = shapely.buffer(shapely.points(x, y), math.hypot(p.mover_width, p.mover_height)
                              / 2.0 + TURN_MARGIN)
        if self.group.registry.blocker(mover.member, area) is not None or \
                any(meets(area, other) for other in sent):
            self.stats.held_back += 1
            return
        sent.append(area)
        command = mover.move_c(drive.route.agent.target[2])
        self.stats.legs += 1
        drive.leg = _Leg(command, drive.reached, -1, (x, y), (x, y))


class _Blocked(Exception):
    def __init__(self, mover: MC_PlanarMover, blocker: str, reason: str) -> None:
        super().__init__(reason)
        self.mover = mover
        self.blocker = blocker
        self.reason = reason


def _dependencies(routes: list[Route]) -> tuple[list[list[list[tuple[int, int]]]],
                                                dict[int, list[tuple[int, int, int]]]]:
    """Per agent and step: (other agent, points it must have reached) before the step may
    start, from the order in which the plan lets agents through each cell; and the visits
    per cell: (first, last half-step, agent), in order."""
    visits: dict[int, list[tuple[int, int, int]]] = {}  # cell -> (first, last half, agent)
    for a, route in enumerate(routes):
        open_: dict[int, int] = {}
        for half, cells in enumerate(route.occupied):
            current = set(cells)
            for cell in list(open_):
                if cell not in current:
                    visits.setdefault(cell, []).append((open_.pop(cell), half - 1, a))
            for cell in cells:
                open_.setdefault(cell, half)
        for cell, first in open_.items():
            visits.setdefault(cell, []).append((first, 1 << 30, a))
    deps: list[list[list[tuple[int, int]]]] = [
        [[] for _ in range(max(1, len(r.points)))] for r in routes]
    for cell_visits in visits.values():
        cell_visits.sort()
        for (_, last, a), (first, _, b) in zip(cell_visits, cell_visits[1:], strict=False):
            if a == b:
                continue
            step = max(0, (first - 1) // 2)  # the step whose move or arrival takes the cell
            deps[b][step].append((a, last // 2 + 1))
    return deps, visits


def _check_pairs(agents: list[Agent], movers: list[MC_PlanarMover]) -> None:
    starts: dict[int, int] = {}
    for k, agent in enumerate(agents):
        for cell in agent.start_cells:
            if cell in starts:
                raise _Blocked(movers[k], _mover_label(movers[starts[cell]]),
                               f"it stands too close to {_mover_label(movers[starts[cell]])} "
                               f"for the routing grid (one cell each)")
            starts[cell] = k
    goals: dict[int, int] = {}
    for k, agent in enumerate(agents):
        for cell in agent.final_cells:
            if cell in goals:
                raise _Blocked(movers[k], _mover_label(movers[goals[cell]]),
                               f"its target is too close to the target of "
                               f"{_mover_label(movers[goals[cell]])} for the routing grid "
                               f"(one cell each)")
            goals[cell] = k


def _not_routable(mover: MC_PlanarMover, group: MC_PlanarGroup, moving: bool = False
                  ) -> str | None:
    """Why ``mover`` cannot be routed (``moving``: it may be on a leg of the router)."""
    if mover.group is not group:
        return "is not in the router's group"
    if mover.state is not PlanarState.ENABLED:
        return f"is {mover.state.name}, not Enabled"
    if mover.in_motion and not moving:
        return "is moving: a route starts from standstill"
    return None


def _mover_label(mover: MC_PlanarMover) -> str:
    return f"mover {mover.name} (16#{mover.oid:08X})"


def _finite(target: PositionXYC) -> tuple[float, float, float]:
    values = (target.x, target.y, target.c)
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
        raise ConfigError(f"route target {target}: x, y and c must be finite numbers")
    return float(target.x), float(target.y), float(target.c)


def _angle(d: float) -> float:
    return (d + 180.0) % 360.0 - 180.0


def _unit(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    return round(dx / length, 6), round(dy / length, 6)


__all__ = ["CLEARANCE", "RouteCommand", "Router", "RouterStats"]
