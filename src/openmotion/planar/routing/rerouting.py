"""Re-routing: the router's reactions while routes run (D-344 to D-346).

A new target for a mover on its way, a mover that stops driving (halted, disabled, in
error, taken by another command) and a part that moves re-plan only the movers concerned,
once they stand, around the routes the others keep (``planner.plan_around``); when that
finds no slot, every mover still on its way is planned again together (D-303).

The router (router.py) reports to a ``Rerouting`` what happened (``pending``: movers with a
new target, ``stop``: a mover that left its route) and calls ``react`` each cycle before it
sends legs; re-routing replaces routes in the shared ``Execution`` and rebuilds the plan's
order of passage. ``joint`` holds the movers to plan together once every mover stands,
which the router does.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING

import shapely

from openmotion.core.errors import ConfigError, ErrorId
from openmotion.kernel.command import CommandStatus
from openmotion.planar.reservation import footprint
from openmotion.planar.routing.agents import (
    AT_POSE,
    Blocked,
    Setup,
    cut_off,
    make_agent,
    routing_field,
)
from openmotion.planar.routing.drives import (
    Drive,
    Execution,
    RouteCommand,
    RouterStats,
    dependencies,
)
from openmotion.planar.routing.grid import build_grid, half_extents
from openmotion.planar.routing.planner import (
    Agent,
    Plan,
    Planner,
    PlanningFailed,
    Route,
    plan_around,
)

if TYPE_CHECKING:
    from openmotion.planar.mover import MC_PlanarMover


class Rerouting:
    """Re-plans the routes of ``execution`` that a new target, a stopped mover or a moved
    part affects, on the field of the router's options ``setup``."""

    def __init__(self, setup: Setup, execution: Execution, stats: RouterStats,
                 budget: float) -> None:
        self.setup = setup
        self.execution = execution
        self.stats = stats
        self.budget = budget  #: planning time of the re-plans waiting [s]
        #: movers to re-plan around the routes the others keep, once they stand (D-344)
        self.pending: dict[MC_PlanarMover, RouteCommand] = {}
        self.stopped: list[Drive] = []  #: stopped drives to stand for good where they stop
        #: movers to plan together once every mover stands (D-303), with the budget
        self.joint: tuple[dict[MC_PlanarMover, RouteCommand], float] | None = None

    def react(self) -> bool:
        """Once a cycle, before legs are sent: re-plan what a moved part, a stopped mover or
        a new target affects. True when no leg may be sent this cycle (a joint plan waits for
        every mover to stand)."""
        self.watch_surface()
        if self.stopped:
            self.settle_stopped()
        if self.pending:
            self.replan_around()
            if self.joint is not None:
                return True
        return False

    def _standing_route(self, drive: Drive) -> Route:
        """The route of a mover that stands where it is for good (stopped, or arrived)."""
        grid = self.execution.grid
        assert grid is not None
        mover = drive.mover
        x, y, c = mover.pose
        hx, hy = half_extents(mover.parameters.mover_width, mover.parameters.mover_height, c)
        return Route(drive.route.agent, [(x, y)], [grid.touched((x, y), (x, y), hx, hy)], [-1])

    def rebuild(self) -> None:
        """The plan's order of passage per cell again, from every drive's route (the movers
        that no longer drive stand where they are for good)."""
        for drive in self.execution.drives:
            if not drive.handle.busy and drive not in self.stopped and \
                    not drive.mover.in_motion and len(drive.route.points) > 1:
                drive.route = self._standing_route(drive)
                drive.reached = 0
        routes = [d.route for d in self.execution.drives]
        deps, self.execution.visits = dependencies(routes)
        standing = {k for k, d in enumerate(self.execution.drives) if not d.handle.busy}
        for index, drive in enumerate(self.execution.drives):
            drive.index = index
            # nobody waits for a mover that no longer drives: the grid and the group keep
            # the others off it (its cells are counted generously here)
            drive.deps = [[(a, need) for a, need in step if a not in standing]
                          for step in deps[index]]

    def settle_stopped(self) -> None:
        """A stopped mover stands where it stopped for good: the routes that still meet the
        cells under it are re-planned around it (D-345)."""
        settled = [d for d in self.stopped if not d.mover.in_motion]
        if not settled or self.execution.grid is None:
            return
        for drive in settled:
            self.stopped.remove(drive)
            self.pending.pop(drive.mover, None)
            drive.leg = None
            drive.route = self._standing_route(drive)
            drive.reached = 0
            cells = set(drive.route.occupied[0])
            for other in self.execution.drives:
                if other.handle.busy and other.mover not in self.pending and \
                        cells & _remaining(other):
                    self.pending[other.mover] = other.handle
        self.rebuild()

    def watch_surface(self) -> None:
        """A part moved (the surface changed): movers it carried and routes over stators that
        left are re-planned on the surface as it is now (D-346)."""
        surface = self.setup.environment.surface
        if surface is self.execution.surface or surface is None or self.execution.grid is None:
            return
        self.execution.surface = surface
        grown = shapely.buffer(surface, 1e-6, join_style="mitre")
        shapely.prepare(grown)
        self.execution.static = (grown, list(self.setup.obstacles))
        old = self.execution.grid
        movers = {d.mover for d in self.execution.drives} | {
            m for m in self.setup.system.movers if m.group is self.setup.group}
        side = max(max(m.parameters.mover_width, m.parameters.mover_height) for m in movers)
        grid = build_grid(surface, side, self.setup.obstacles, self.setup.pitch)
        if (grid.bounds, grid.nx, grid.ny) != (old.bounds, old.nx, old.ny):  # all again
            handles = {d.mover: d.handle for d in self.execution.drives if d.handle.busy}
            handles.update(self.pending)
            self.pending = {}
            if handles:
                self.joint = (handles, self.budget)
            return
        gone = {cell for cell in range(grid.size) if old.free[cell] and not grid.free[cell]}
        for drive in self.execution.drives:
            if not drive.handle.busy or drive.mover in self.pending:
                continue
            x, y, _ = drive.mover.pose
            here = drive.route.points[min(_progress(drive), len(drive.route.points) - 1)]
            carried = drive.leg is None and math.hypot(x - here[0], y - here[1]) > AT_POSE
            if carried or gone & _remaining(drive):
                self.pending[drive.mover] = drive.handle
        self.rebuild()

    def replan_around(self) -> None:
        """Plan the pending movers, once they stand, around the routes the others keep
        (``plan_around``); a kept route that meets where a pending mover stands or ends joins
        them. Without a plan, every mover on its way is planned again together (D-303)."""
        pending = self.pending
        for mover in [m for m, h in pending.items() if not h.busy]:
            del pending[mover]
        while pending:
            if any(m.in_motion for m in pending):
                return
            kept = [d for d in self.execution.drives
                    if d.handle.busy and d.mover not in pending]
            planned = self._around(kept)
            if planned is None:  # joined by kept movers, or failed: next cycle
                return
            if planned:
                break
        else:
            return
        self.pending = {}
        self.rebuild()

    def _around(self, kept: list[Drive]) -> bool | None:
        """One attempt of ``replan_around``: True when planned, False when kept movers
        joined the pending ones (try again), None to wait or after the fall-back."""
        pending = self.pending
        now = self.setup.system.now
        routed = {**pending, **{d.mover: d.handle for d in kept}}
        try:
            grid, grown, geometries, labels, side = routing_field(self.setup, routed)
        except ConfigError:
            grid = None
        old = self.execution.grid
        if grid is None or old is None or \
                (grid.bounds, grid.nx, grid.ny) != (old.bounds, old.nx, old.ny):
            self.fall_back()
            return None
        prints = [(d.mover, footprint(*d.route.agent.target, d.mover.parameters.mover_width,
                                      d.mover.parameters.mover_height)) for d in kept]
        agents: dict[MC_PlanarMover, Agent] = {}
        planner = None
        for mover, handle in list(pending.items()):
            try:
                agent = make_agent(mover, handle.target, grid, grown, geometries, labels, prints)
                planner = Planner(grid, [agent])
                if agent.start_cell not in planner.distance(agent):
                    blocker = cut_off(agent, self.setup.environment.surface, side, labels,
                                      geometries, self.setup.pitch)
                    raise Blocked(mover, blocker, f"its target cannot be reached: {blocker} "
                                                  f"cuts it off")
            except Blocked as blocked:
                del pending[mover]
                handle.blocker = blocked.blocker
                handle.end(CommandStatus.ERROR, now, ErrorId.PLANAR_COLLISION,
                           f"{mover.name}: {blocked.reason}")
                drive = next((d for d in self.execution.drives if d.mover is mover), None)
                if drive is not None:  # it stays where it is: the others go around it
                    self.stop(drive)
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
        joined = [d for d in kept if mine & _remaining(d)]
        if joined:
            for drive in joined:
                pending[drive.mover] = drive.handle
            return False
        progress = [_progress(d) for d in kept]
        start = max(progress, default=0)
        planner = Planner(grid, list(agents.values()))
        started = time.perf_counter()
        try:
            routes = plan_around(planner, [d.route for d in kept], progress, start)
        except PlanningFailed:
            self.fall_back()
            return None
        self.execution.grid = grid
        self.stats.replans += 1
        self.stats.plans.append(Plan(routes, list(range(len(routes))),
                                     first_time=time.perf_counter() - started,
                                     time=time.perf_counter() - started, tried=1))
        drives = {d.mover: d for d in self.execution.drives}
        for mover, route in zip(agents, routes, strict=True):
            handle = pending[mover]
            handle.route = list(route.points[start:])
            handle.start()
            drive = drives.get(mover)
            if drive is None:
                known = self.execution.drives
                known.append(Drive(handle, route, [], len(known)))
                continue
            drive.handle, drive.route, drive.reached = handle, route, 0
            drive.leg, drive.turned, drive.waits = None, False, 0
        return True

    def fall_back(self) -> None:
        """Every mover still on its way is planned again together once all stand (D-303)."""
        handles = {d.mover: d.handle for d in self.execution.drives if d.handle.busy}
        handles.update(self.pending)
        self.pending = {}
        self.joint = (handles, self.budget)

    def stop(self, drive: Drive) -> None:
        """The mover left the route (halted, stopped, disabled, in error, taken by another
        command): once it stands, the routes it is in the way of are re-planned."""
        self.pending.pop(drive.mover, None)
        if drive not in self.stopped:
            self.stopped.append(drive)


def _progress(drive: Drive) -> int:
    """The first step of the drive's route still ahead of it."""
    return drive.leg.first if drive.leg is not None and drive.leg.last >= 0 else \
        drive.reached


def _remaining(drive: Drive) -> set[int]:
    """The cells the drive's route still occupies."""
    occupied = drive.route.occupied
    return {cell for cells in occupied[2 * _progress(drive):] for cell in cells}


__all__ = ["Rerouting"]
