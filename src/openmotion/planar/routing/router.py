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
  lengthened in motion when the steps after it are released or the area ahead clears (a
  run the group would refuse whole starts as far along it as the group admits, D-373);
  any-angle legs skip the grid's staircases where the plan leaves room;
- before sending, the router asks the group whether it would admit the leg's swept area
  now (``ReservationRegistry.blocker``) and waits a cycle if not: the group's own check
  still decides every command, so safety never rests on the plan.

A new target mid-route, a mover that stops driving and a part that moves re-plan only the
movers concerned around the routes the others keep (rerouting.py, D-344 to D-346). The
routes in execution (drives.py) are shared with it; movers become the planner's agents in
agents.py.

Movers not routed, static obstacles given to the router, the stator surface (parts where
they stand) are kept out of the plan; an unreachable or occupied target ends the mover's
command with ``PLANAR_COLLISION`` and a message naming the blocker, and the other movers are
routed around it standing where it is (docs/planar-routing.md).
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING

import shapely
from shapely.geometry.base import BaseGeometry

from openmotion.core.errors import ConfigError, ErrorId
from openmotion.kernel.command import CommandStatus
from openmotion.planar.enums import PlanarState
from openmotion.planar.options import ST_MoveToPositionOptions
from openmotion.planar.positions import PositionXYC
from openmotion.planar.reservation import footprint
from openmotion.planar.routing.agents import (
    TURN_MARGIN,
    TURN_TOLERANCE,
    Blocked,
    angle,
    check_pairs,
    cut_off,
    finite,
    make_agent,
    not_routable,
    routing_field,
)
from openmotion.planar.routing.drives import (
    Drive,
    Execution,
    Leg,
    RouteCommand,
    RouterStats,
    dependencies,
)
from openmotion.planar.routing.grid import CLEARANCE, RoutingGrid, meets
from openmotion.planar.routing.planner import FOREVER, Agent, Plan, Planner, PlanningFailed
from openmotion.planar.routing.rerouting import Rerouting

if TYPE_CHECKING:
    from openmotion.planar.environment import MC_PlanarEnvironment
    from openmotion.planar.group import MC_PlanarGroup
    from openmotion.planar.mover import MC_PlanarMover
    from openmotion.planar.options import IPlcDynamicConstraint

PLANNING_LIMIT = 5.0  #: a route call gives up on the movers left after this long [s]
DEFAULT_TIME_BUDGET = 0.05  #: planning time a route call may spend improving its plan [s]
#: shortcuts of one leg offered to the group, farthest first, before the plan's own leg (D-373)
SHORTCUT_TRIES = 3
_TRANSLATE = ST_MoveToPositionOptions(use_orientation=False)
_TURN = ST_MoveToPositionOptions(use_orientation=True)


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
        self._execution = Execution()
        self._rerouting = Rerouting(self, self._execution, self.stats, time_budget)
        self.system.runtime.add_program(self._cycle)

    # -- planning ---------------------------------------------------------------------------

    @property
    def grid(self) -> RoutingGrid | None:
        """The routing grid of the last plan."""
        return self._execution.grid

    @property
    def busy(self) -> bool:
        return any(d.handle.busy for d in self._execution.drives)

    @property
    def routes(self) -> dict[str, list[tuple[float, float]]]:
        """The planned way of every mover routed last, by mover name (for plots)."""
        return {d.mover.name: list(d.handle.route) for d in self._execution.drives}

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
            finite(wanted[mover])  # a bad target is a Python error before anything changes
        running = {d.mover: d for d in self._execution.drives if d.handle.busy}
        handles: dict[MC_PlanarMover, RouteCommand] = {}
        for mover, target in wanted.items():
            drive = running.get(mover)
            if drive is not None and drive.handle.target is target:  # the same route goes on
                handles[mover] = drive.handle
                continue
            old = self._rerouting.pending.pop(mover, None)
            for replaced in (old, drive and drive.handle):
                if replaced is not None and replaced.busy:
                    replaced.end(CommandStatus.ABORTED, now, ErrorId.NO_ERROR,
                                 f"{mover.name}: a new route replaced it")
            handles[mover] = RouteCommand(mover, target, now)
        if not running and not self._rerouting.pending and self._rerouting.joint is None:
            self._plan(handles, budget)
            return handles
        for mover, handle in handles.items():
            drive = running.get(mover)
            if drive is not None and drive.handle is handle:
                continue
            problem = not_routable(mover, self.group, moving=drive is not None)
            if problem:
                handle.end(CommandStatus.ERROR, now, ErrorId.PLANAR_WRONG_STATE,
                           f"{mover.name}: {problem}")
                if drive is not None:  # it stays where it stops: the others go around it
                    drive.leg = None
                    self._rerouting.stop(drive)
                continue
            if drive is not None:  # it ends the leg it is on and is re-planned standing
                drive.handle = handle
            self._rerouting.pending[mover] = handle
        self._rerouting.budget = budget
        if self._rerouting.joint is not None:  # a full plan waits: join it
            waiting, _ = self._rerouting.joint
            waiting.update(self._rerouting.pending)
            self._rerouting.pending = {}
        else:
            self._rerouting.replan_around()
        return handles

    def _plan(self, handles: dict[MC_PlanarMover, RouteCommand], budget: float) -> None:
        """Plan ``handles``' movers once every one of them stands (a moving one first ends
        its leg: ``_cycle`` calls again)."""
        if any(d.leg is not None for d in self._execution.drives):
            self._rerouting.joint = (handles, budget)  # no new leg until all stand
            return
        self._rerouting.joint = None
        failed: dict[MC_PlanarMover, str] = {}
        active = {m: h for m, h in handles.items() if h.busy}
        for m, h in active.items():
            problem = not_routable(m, self.group)
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
            except Blocked as blocked:
                handle = routed.pop(blocked.mover)
                handle.blocker = blocked.blocker
                handle.end(CommandStatus.ERROR, self.system.now, ErrorId.PLANAR_COLLISION,
                           f"{blocked.mover.name}: {blocked.reason}")
                continue
            break
        self._execution.drives = []
        self._rerouting.pending, self._rerouting.stopped = {}, []
        if plan is None:
            return
        self.stats.plans.append(plan)
        movers = list(routed)
        deps, self._execution.visits = dependencies(plan.routes)
        for k, route in enumerate(plan.routes):
            handle = routed[movers[k]]
            handle.route = list(route.points)
            handle.start()
            self._execution.drives.append(Drive(handle, route, deps[k], k))


    def _plan_once(self, routed: dict[MC_PlanarMover, RouteCommand], budget: float
                   ) -> tuple[Plan, list[Agent]]:
        grid, grown, geometries, labels, side = routing_field(self, routed)
        surface = self.environment.surface
        self._execution.grid = grid
        self._execution.surface = surface
        self._execution.static = (grown, list(self.obstacles))
        agents: list[Agent] = []
        targets: list[tuple[MC_PlanarMover, BaseGeometry]] = []
        for mover, handle in routed.items():
            agent = make_agent(mover, handle.target, grid, grown, geometries, labels, targets)
            targets.append((mover, footprint(*agent.target, mover.parameters.mover_width,
                                             mover.parameters.mover_height)))
            agents.append(agent)
        check_pairs(agents, list(routed))
        planner = Planner(grid, agents)
        for mover, agent in zip(routed, agents, strict=True):
            if agent.start_cell not in planner.distance(agent):
                blocker = cut_off(agent, surface, side, labels, geometries, self.pitch)
                raise Blocked(mover, blocker, f"its target cannot be reached: {blocker} "
                                               f"cuts it off")
        try:
            plan = planner.plan(budget, self.seed)
        except PlanningFailed as failed:
            mover = list(routed)[agents.index(failed.agent)]
            raise Blocked(mover, "other movers", f"no route found: {failed.reason}") from None
        return plan, agents

    # -- execution --------------------------------------------------------------------------

    def _cycle(self) -> None:
        """The router's program: follow the legs sent, re-plan what a new target, a stopped
        mover or a moved part affects, send the next legs (phase 1)."""
        if not self._execution.drives:
            return
        now = self.system.now
        for drive in self._execution.drives:
            self._follow(drive, now)
        pending = self._rerouting.joint
        if pending is not None:
            if all(d.leg is None for d in self._execution.drives):
                self._plan(*pending)
            return
        if self._rerouting.react():
            return
        sent: list[BaseGeometry] = []
        # a mover in motion counts the points its leg ends on: those waiting for it may
        # send as soon as the group admits their leg, i.e. once it actually cleared the area
        reached = [d.leg.last if d.leg is not None and d.leg.last >= 0 else d.reached
                   for d in self._execution.drives]
        for drive in self._execution.drives:
            if not drive.handle.busy or drive.mover in self._rerouting.pending:
                continue
            if drive.leg is None:
                self._next_leg(drive, reached, sent)
            else:
                self._extend(drive, reached, sent)


    def _follow(self, drive: Drive, now: float) -> None:
        leg = drive.leg
        handle = drive.handle
        if not handle.busy:
            return
        mover = drive.mover
        if mover.state is not PlanarState.ENABLED or mover.group is not self.group:
            drive.leg = None
            handle.end(CommandStatus.ABORTED, now, ErrorId.NO_ERROR,
                       f"{mover.name} is {mover.state.name} or left the group")
            self._rerouting.stop(drive)
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
            self._rerouting.stop(drive)
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
        if drive.leg is None and mover not in self._rerouting.pending and self._arrived(drive):
            handle.end(CommandStatus.DONE, now)


    def _arrived(self, drive: Drive) -> bool:
        if drive.reached < len(drive.route.points) - 1:
            return False
        return not self._needs_turn(drive) or drive.turned

    def _needs_turn(self, drive: Drive) -> bool:
        return abs(angle(drive.route.agent.target[2] - drive.mover.pose.c)) > TURN_TOLERANCE

    def _ready(self, drive: Drive, step: int, reached: list[int]) -> bool:
        return all(reached[a] >= need for a, need in drive.deps[step])

    def _straight_end(self, drive: Drive, k: int, reached: list[int]) -> int:
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

    def _next_leg(self, drive: Drive, reached: list[int], sent: list[BaseGeometry]) -> None:
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
        shortcuts = self._shortcuts(drive, k, end, reached)
        for _, shortcut in zip(range(SHORTCUT_TRIES), shortcuts, strict=False):
            if self._send(drive, k, shortcut, True, sent):
                return
        if self._send(drive, k, end, False, sent):
            return
        for last_point in _short_of(drive.route.points, k, end):  # D-373
            if self._send(drive, k, last_point, False, sent):
                self.stats.shortened += 1
                return
        self.stats.held_back += 1  # the group would refuse even the plan's first cell: wait
        drive.waits += 1

    def _extend(self, drive: Drive, reached: list[int], sent: list[BaseGeometry]) -> None:
        """A leg in motion along the plan's cells goes on along the same line when the steps
        after its end are released now, as far as the group admits: the longer
        MoveToPosition starts from the mover's motion on that line, so it does not stop at
        the old end (§7.2.2.8.1)."""
        leg = drive.leg
        if leg is None or leg.last < 0 or leg.shortcut or leg.last >= len(drive.route.points) - 1:
            return
        if not self._ready(drive, leg.last, reached):
            return
        end = self._straight_end(drive, leg.first, reached)
        if end <= leg.last:
            return
        # the whole run when the group admits it, else as far along it as it admits (D-373)
        for last_point in (end, *_short_of(drive.route.points, leg.last, end)):
            if self._send(drive, leg.first, last_point, False, sent):
                self.stats.extended += 1
                return

    def _send(self, drive: Drive, k: int, last_point: int, off_plan: bool,
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
            if not self._execution.static[0] or not self._execution.static[0].covers(area) or \
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
        drive.leg = Leg(command, k, last_point, start, target, off_plan, drive.leg)
        return True

    def _turn_on_the_way(self, drive: Drive, last_point: int, c: float) -> float | None:
        """The target's c when the leg to ``last_point`` ends the route and may turn there on
        the way (the turn stays inside one C window, §4.2), else None."""
        if last_point != len(drive.route.points) - 1 or not self._needs_turn(drive):
            return None
        end = c + angle(drive.route.agent.target[2] - c)
        if not drive.mover.parameters.c_windows.contains_interval(min(c, end), max(c, end)):
            return None
        return end

    def _shortcuts(self, drive: Drive, k: int, straight_end: int, reached: list[int]
                   ) -> Iterator[int]:
        """The route points beyond ``straight_end`` that a straight leg from point ``k`` may
        reach (any angle), farthest first. The leg's swept area stays on the surface and off the
        obstacles; where it ends the mover stands early, so the cells under it there are
        held by no other mover in the plan from step k to that point and whoever held them
        before has passed. The cells it only sweeps need no more than the group's own check
        at sending: another mover coming there later waits for the leg to pass, and a
        mover in motion never waits for anyone (docs/planar-routing.md)."""
        points = drive.route.points
        last = len(points) - 1
        if self._execution.grid is None or straight_end >= last:
            return
        agent = drive.route.agent
        me = drive.index
        start = points[k]
        for end in range(last, straight_end, -1):
            if points[end] == points[end - 1] and end < last:
                continue
            if not all(self._ready(drive, s, reached) for s in range(k, end)):
                continue
            stand = self._execution.grid.touched(points[end], points[end], agent.hx, agent.hy)
            if self._clear(stand, 2 * k, 2 * end, me, reached) and \
                    self._on_surface(drive, start, points[end]):
                yield end

    def _on_surface(self, drive: Drive, a: tuple[float, float], b: tuple[float, float]
                    ) -> bool:
        """Whether the footprint's sweep from a to b stays on the surface and meets none of
        the router's static obstacles (movers it does not route are the group's business)."""
        surface, obstacles = self._execution.static
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
            for start, end, agent in self._execution.visits.get(cell, ()):
                if agent == me or start > last + 1:
                    continue
                if end >= FOREVER or reached[agent] < end // 2 + 1:
                    return False
        return True

    def _send_turn(self, drive: Drive, sent: list[BaseGeometry]) -> None:
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
        drive.leg = Leg(command, drive.reached, -1, (x, y), (x, y))


def _short_of(points: Sequence[tuple[float, float]], k: int, end: int) -> list[int]:
    """The route points between ``k`` and ``end`` (excluded) where a leg on the straight run
    from ``k`` to ``end`` may stop short, farthest first: each place once, at its last
    index (a wait of the plan there is then behind the mover)."""
    return [j for j in range(end - 1, k, -1)
            if points[j] != points[j + 1] and points[j] != points[k]]


def _unit(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    return round(dx / length, 6), round(dy / length, 6)


__all__ = ["CLEARANCE", "RouteCommand", "Router", "RouterStats"]
