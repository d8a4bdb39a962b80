"""Routing in scenario files: ``planar.router`` and the ``route`` timeline entry.

``planar.router`` gives the options of the one router a scenario has (planar/routing,
docs/planar-routing.md): its planar group, the routing cells' ``pitch``, the planning
``time_budget``, the ``seed`` of its orders, the dynamics of its legs and the static
``obstacles`` it keeps the movers away from (fixtures standing on the field, which the
planar group does not know). A ``route`` entry routes a set of movers to target poses with
one ``Router.route`` call, so they are planned together; its row is Busy until every mover
has ended its route, then Done, or Error (Aborted) with each failed mover's message and
blocker (D-349).

The run makes the router after the planar setup when the file has ``planar.router`` or a
``route`` entry (planar_machine.py) and notes its plans for the plot and the viewer
(``RoutePlans``). A scenario plans with ``time_budget: 0`` by default: the first plan only,
which reads no wall clock, so two runs stay bit-identical (D-350).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal

import shapely
from pydantic import AfterValidator, Field, StrictInt, StrictStr, model_validator

from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.errors import ErrorId
from openmotion.core.special_values import MC_DEFAULT
from openmotion.planar import DynamicConstraint_PathXY
from openmotion.scenario.schema import Identifier, InputValue, Number, Seconds, _Model
from openmotion.scenario.transport import _Timed

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from openmotion.planar.routing import RouteCommand
    from openmotion.scenario.planar import PlanarSpec

Loc = tuple[str | int, ...]


def _check_group(name: str) -> str:
    """A planar group of the file (planar.py imports this module: its checks come late)."""
    from openmotion.scenario.planar import _check_planar_group

    return _check_planar_group(name)


def _check_mover(name: str) -> str:
    from openmotion.scenario.planar import _check_planar_mover

    return _check_planar_mover(name)
Point = tuple[Number, Number]
PositiveNumber = Annotated[Number, Field(gt=0.0)]


class ObstacleSpec(_Model):
    """A static obstacle on the field: a rectangle (``x``, ``y``, ``width``, ``height``,
    ``c``) or a polygon (``points``), in the group's frame [mm]."""

    name: Identifier
    """Unique among the obstacles; an error names it as the blocker."""
    x: Number | None = None
    """Centre of the rectangle [mm]."""
    y: Number | None = None
    """Centre of the rectangle [mm]."""
    width: PositiveNumber | None = None
    """Side along x before turning [mm]."""
    height: PositiveNumber | None = None
    """Side along y before turning [mm]."""
    c: Number = 0.0
    """Rotation of the rectangle about its centre [°]."""
    points: Annotated[list[Point], Field(min_length=3)] | None = None
    """Instead of a rectangle: the corners of a simple polygon [mm]."""

    @model_validator(mode="after")
    def _one_shape(self) -> ObstacleSpec:
        rectangle = [self.x, self.y, self.width, self.height]
        if self.points is None and None in rectangle:
            raise ValueError("give 'x', 'y', 'width' and 'height' (a rectangle), or 'points'")
        if self.points is not None and any(v is not None for v in rectangle):
            raise ValueError("give a rectangle ('x', 'y', 'width', 'height') or 'points', "
                             "not both")
        if self.points is not None and not shapely.Polygon(self.points).is_valid:
            raise ValueError("points: the polygon crosses itself")
        return self

    def geometry(self) -> BaseGeometry:
        from openmotion.planar.reservation import footprint

        if self.points is not None:
            return shapely.Polygon(self.points)
        assert self.x is not None and self.y is not None  # _one_shape
        return footprint(self.x, self.y, self.c, self.width, self.height)


def _unique_names(obstacles: list[ObstacleSpec]) -> list[ObstacleSpec]:
    seen: set[str] = set()
    for obstacle in obstacles:
        if obstacle.name in seen:
            raise ValueError(f"obstacle name {obstacle.name!r} is used twice")
        seen.add(obstacle.name)
    return obstacles


class RouterSpec(_Model):
    """The scenario's router (planar/routing): its group and options, given once."""

    group: Annotated[StrictStr, AfterValidator(_check_group)] | None = None
    """The planar group whose movers it routes; default: the only planar group."""
    pitch: PositiveNumber | None = None
    """Side of a routing cell [mm], at least the largest mover's side (240: one cell per
    stator); default: the largest mover's side + 2 mm."""
    time_budget: Seconds = 0.0
    """Wall time [s] a route call may spend improving its first plan; 0: the first plan
    only, the same on every machine (D-350)."""
    seed: Annotated[StrictInt, Field(ge=0)] = 0
    """Seed of the priority orders tried after the first."""
    velocity: InputValue = MC_DEFAULT
    """Dynamics of every leg (DynamicConstraint_PathXY) [mm/s]; MC_DEFAULT: the mover's
    default dynamics."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    obstacles: Annotated[list[ObstacleSpec], AfterValidator(_unique_names)] = []
    """Static obstacles the routes keep clear of (the planar group does not know them)."""

    def constraint(self) -> DynamicConstraint_PathXY | None:
        """None (each mover's default dynamics) unless a limit is given."""
        given = {"velocity", "acceleration", "deceleration", "jerk"} & self.model_fields_set
        return DynamicConstraint_PathXY(self.velocity, self.acceleration, self.deceleration,
                                        self.jerk) if given else None


def router_problems(spec: PlanarSpec) -> list[tuple[Loc, str]]:
    """What keeps ``planar.router`` from being made: no environment, no group chosen, a
    pitch smaller than a mover of its group."""
    router = spec.router
    if router is None:
        return []
    problems: list[tuple[Loc, str]] = []
    if spec.environment is None:
        problems.append((("router",), "the router plans on the stator surface: give "
                                      "planar.environment"))
    group = router_group(spec)
    if group is None:
        known = ", ".join(g.name for g in spec.groups) or "none"
        problems.append((("router", "group"), f"name the planar group whose movers it routes "
                                              f"(planar.groups: {known})"))
        return problems
    index = [g.name for g in spec.groups].index(group)
    names = {name for _, name in spec.members(index)}
    sides = [max(m.parameters.mover_width, m.parameters.mover_height)  # type: ignore[attr-defined]
             for m in spec.movers if m.name in names]
    if router.pitch is not None and sides and router.pitch < max(sides):
        problems.append((("router", "pitch"), f"{router.pitch:g} mm is less than the side of "
                                              f"the largest mover of group {group!r} "
                                              f"({max(sides):g} mm)"))
    return problems


def router_group(spec: PlanarSpec) -> str | None:
    """The name of the router's group: its ``group``, else the only planar group."""
    router = spec.router
    if router is not None and router.group is not None:
        return router.group
    return spec.groups[0].name if len(spec.groups) == 1 else None


# -- the entry -----------------------------------------------------------------------------------


class RouteTarget(_Model):
    """A target pose of one mover, in the group's frame."""

    x: Number
    """[mm]."""
    y: Number
    """[mm]."""
    c: Number | None = None
    """[°]; default: the mover's c when the entry fires (no turn)."""


def _some_targets(targets: dict[str, RouteTarget]) -> dict[str, RouteTarget]:
    """At least one target, each of a planar mover of the file."""
    if not targets:
        raise ValueError("name at least one mover and its target")
    for name in targets:
        _check_mover(name)
    return targets


class Route(_Timed):
    """Router.route: plan routes of the movers in ``targets`` together and drive them
    there around each other, the surface's edges, the movers it does not route and the
    router's obstacles (docs/planar-routing.md)."""

    method = "route"
    command: Literal["route"]
    targets: Annotated[dict[StrictStr, RouteTarget], AfterValidator(_some_targets)]
    """Mover name -> {x, y, c}: where it goes."""
    time_budget: Seconds | None = None
    """Wall time [s] to improve the first plan; default: planar.router's."""

    @property
    def axis(self) -> str:
        """The routed movers, for the summary's axis column."""
        return ", ".join(self.targets)


def route_problems(planar: PlanarSpec | None, timeline: list[Any]) -> list[tuple[Loc, str]]:
    """A route entry needs a router: planar.environment and a planar group it can take."""
    routes = [k for k, entry in enumerate(timeline) if isinstance(entry, Route)]
    if not routes or planar is not None and planar.router is not None:
        return []  # planar.router's own problems are planar's
    if planar is None or planar.environment is None:
        problem = "a route needs planar.environment: the router plans on the stator surface"
    elif router_group(planar) is None:
        known = ", ".join(g.name for g in planar.groups) or "none"
        problem = "a route needs planar.router with the 'group' whose movers it routes " \
                  f"(planar.groups: {known})"
    else:
        return []
    return [(("timeline", k), problem) for k in routes]


def follow_route(row: Command, handles: dict[str, RouteCommand], now: float) -> None:
    """Show the route handles on the entry's row: Active once one runs; when every one has
    ended: Error (the first error's id) if one failed, else Aborted if one was aborted,
    else Done; the message names each mover that failed and what blocked it."""
    if row.finished:
        return
    if any(handle.active or handle.finished for handle in handles.values()):
        row.start()
    if not all(handle.finished for handle in handles.values()):
        return
    errors = [h for h in handles.values() if h.error]
    aborted = [h for h in handles.values() if h.aborted]
    status = CommandStatus.ERROR if errors else CommandStatus.ABORTED if aborted \
        else CommandStatus.DONE
    message = "; ".join(outcome_text(h) for h in (*errors, *aborted))
    row.end(status, now, errors[0].error_id if errors else ErrorId.NO_ERROR, message)


def outcome_text(handle: RouteCommand) -> str:
    """A failed route as a row shows it: its message, and its blocker when it has one; an
    abort without a message (a new target) says so."""
    if handle.aborted and not handle.message:
        return f"{handle.mover.name}: aborted"
    blocker = f" (blocker: {handle.blocker})" if handle.error and handle.blocker else ""
    return f"{handle.message}{blocker}"
