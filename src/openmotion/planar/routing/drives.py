"""Routes in execution: each mover's drive along its planned route, the legs it is sent
as, and the plan's order of passage per cell that the legs keep (D-302, D-340).

The router (router.py) sends the legs; re-routing (rerouting.py) replaces the routes of some
drives while the others go on. Both work on one ``Execution``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from shapely.geometry.base import BaseGeometry

from openmotion.kernel.command import Command
from openmotion.planar.positions import PositionXYC
from openmotion.planar.routing.grid import RoutingGrid
from openmotion.planar.routing.planner import Plan, Route

if TYPE_CHECKING:
    from openmotion.planar.mover import MC_PlanarMover


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
class Leg:
    """One command sent for a drive: a MoveToPosition between route points, or the final
    turn."""

    command: object  #: the mover's PlanarCommand
    first: int  #: the route point it starts from
    last: int  #: the route point it ends on (-1: the final turn)
    start: tuple[float, float]
    end: tuple[float, float]
    shortcut: bool = False  #: off the plan's cells order: its points count when it ends
    previous: Leg | None = None  #: the leg in motion it carries on (kept if it is refused)


@dataclass
class Drive:
    """The execution of one mover's route."""

    handle: RouteCommand
    route: Route
    deps: list[list[tuple[int, int]]]  #: per step: (agent, points it must have reached)
    index: int = 0  #: its agent number in the plan
    reached: int = 0
    leg: Leg | None = None
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
    #: legs sent short of their straight run's end, the group holding back the rest (D-373)
    shortened: int = 0
    replans: int = 0  #: movers' routes re-planned around the others' (D-344)
    plans: list[Plan] = field(default_factory=list)


@dataclass
class Execution:
    """What the router and re-routing share: the drives of the last plan and what was
    planned on."""

    drives: list[Drive] = field(default_factory=list)
    #: per cell: (first, last half-step, agent) of every visit in the plan, in order
    visits: dict[int, list[tuple[int, int, int]]] = field(default_factory=dict)
    grid: RoutingGrid | None = None  #: the routing grid of the last plan
    #: the prepared stator surface and the obstacles of the last plan (for shortcuts)
    static: tuple[BaseGeometry | None, list[BaseGeometry]] = (None, [])
    surface: BaseGeometry | None = None  #: the stator surface the plan was made on


def dependencies(routes: list[Route]) -> tuple[list[list[list[tuple[int, int]]]],
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


__all__ = ["Drive", "Execution", "Leg", "RouteCommand", "RouterStats", "dependencies"]
