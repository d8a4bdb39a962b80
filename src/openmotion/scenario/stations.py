"""Stations and routes in a scenario file: a CA group's ``stations`` and ``routes``.

Each station is a ``rail.stations.Station`` on the group's rail; each route sends movers of
the group round its stations at its velocity (``transport.stations.add_stations``). The run
adds the line after the group, and the summary shows a table of the stations' metrics.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Annotated, Any

from pydantic import AfterValidator, Field, StrictInt, StrictStr

from openmotion.core.errors import ConfigError
from openmotion.core.special_values import MC_DEFAULT
from openmotion.rail.stations import Route, Station, StationLine, StationRow
from openmotion.scenario.schema import (
    _NAMES,
    Identifier,
    InputValue,
    Number,
    Seconds,
    _Model,
    _unique,
)
from openmotion.transport.group import CaGroup
from openmotion.transport.stations import CaMoverPort, station_line

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime

__all__ = ["RouteSpec", "StationSpec", "build_line", "routes_of", "station_problems",
           "station_table"]


def _not_an_axis(name: str) -> str:
    names = _NAMES.get()
    if names is not None and (name in names.axes or name in names.groups):
        raise ValueError(f"{name!r} names an axis or a CA group; a station needs a name of "
                         "its own")
    return name


class StationSpec(_Model):
    """A station on the group's rail (rail/stations.py)."""

    name: Annotated[Identifier, _unique("stations"), AfterValidator(_not_an_axis)]
    """Unique among the objects of the scenario; its signals are ``<name>.queue_length`` ..."""
    position: Number
    """Where the first slot stops a mover [mm on the rail]."""
    process_time: Seconds
    """Time a mover stays in its slot [s]."""
    capacity: Annotated[StrictInt, Field(ge=1)] = 1
    """Movers processed at once, one per slot."""
    pitch: Annotated[float, Field(ge=0.0, allow_inf_nan=False)] = 0.0
    """Distance between two slots [mm], behind the first one; needed with capacity > 1."""

    def build(self) -> Station:
        return Station(self.name, self.position, self.process_time, self.capacity, self.pitch)


class RouteSpec(_Model):
    """Movers of the group that visit stations in order, round and round."""

    stations: Annotated[list[StrictStr], Field(min_length=1)]
    """The stations in the order they are visited; after the last, the first again."""
    movers: list[StrictStr] | None = None
    """Axes of the group on this route; default: every mover of the group without a route."""
    velocity: InputValue
    """Travel velocity [mm/s] (MC_MoveAbsoluteCA's Velocity)."""
    acceleration: InputValue = MC_DEFAULT
    deceleration: InputValue = MC_DEFAULT
    jerk: InputValue = MC_DEFAULT
    laps: Annotated[StrictInt, Field(ge=1)] | None = None
    """Rounds through the route, then the mover stays; none: forever."""

    def build(self) -> Route:
        return Route(tuple(self.stations), self.laps)


class PlanarStationSpec(StationSpec):
    """A station on a planar track (its ``position`` is the arc length on ``track``)."""

    track: StrictStr
    """The planar track the station stands on."""

    def build(self) -> Station:
        return Station(self.name, self.position, self.process_time, self.capacity, self.pitch,
                       self.track)


class PlanarRouteSpec(_Model):
    """Planar movers that visit stations in order with MoveOnTrack (TF5430 §6.2.2)."""

    stations: Annotated[list[StrictStr], Field(min_length=1)]
    """The stations in the order they are visited; after the last, the first again."""
    movers: list[StrictStr] | None = None
    """Planar movers on this route; default: every mover without a route."""
    gap: Annotated[float, Field(ge=0.0, allow_inf_nan=False)] = 200.0
    """Gap to the mover ahead [mm] (ST_MoveOnTrackOptions.gap)."""
    laps: Annotated[StrictInt, Field(ge=1)] | None = None
    """Rounds through the route, then the mover stays; none: forever."""

    def build(self) -> Route:
        return Route(tuple(self.stations), self.laps)


def planar_station_problems(stations: list[PlanarStationSpec], routes: list[PlanarRouteSpec],
                            movers: list[str], tracks: list[str]) -> list[tuple[tuple, str]]:
    """What would stop the run from building the planar line: (location, message) pairs."""
    problems = [loc_message for loc_message in station_problems(
        stations, routes, movers, 0.0, False)]  # type: ignore[arg-type]
    for index, spec in enumerate(stations):
        if spec.track not in tracks:
            problems.append((("stations", index, "track"),
                             f"no track {spec.track!r}; one of {', '.join(tracks) or 'none'}"))
    return [(loc, message.replace("not a mover of the group", "not a planar mover"))
            for loc, message in problems]


def build_planar_line(rt: Runtime, movers: Mapping[str, Any], tracks: Mapping[str, Any],
                      stations: list[PlanarStationSpec],
                      routes: list[PlanarRouteSpec]) -> StationLine | None:
    """The planar station line of a scenario, added to ``rt`` after the planar system."""
    from openmotion.planar.options import ST_MoveOnTrackOptions
    from openmotion.planar.stations import PlanarTrackPort

    if not stations:
        return None
    ports = []
    for route, names in routes_of(routes, list(movers)):  # type: ignore[arg-type]
        for name in names:
            options = ST_MoveOnTrackOptions(gap=route.gap)
            ports.append((PlanarTrackPort(movers[name], tracks, options=options),
                          route.build()))
    line = StationLine([spec.build() for spec in stations], ports, rt.cycle_time,
                       "planar.stations")
    rt.add_system(line)
    return line


def station_problems(stations: list[StationSpec], routes: list[RouteSpec], axes: list[str],
                     rail_length: float, ring: bool) -> list[tuple[tuple, str]]:
    """What would stop the run from building the line: (location, message) pairs."""
    problems: list[tuple[tuple, str]] = []
    built: dict[str, Station] = {}
    for index, spec in enumerate(stations):
        try:
            station = spec.build()
        except ConfigError as error:
            problems.append((("stations", index), str(error)))
            continue
        if spec.name in built:
            problems.append((("stations", index, "name"), f"station {spec.name!r} is defined "
                                                          "twice"))
        if ring and not 0.0 <= station.position < rail_length:
            problems.append((("stations", index, "position"),
                             f"{station.position:g} is off the ring [0, {rail_length:g})"))
        built[spec.name] = station
    if routes and not stations:
        problems.append((("routes",), "routes need stations"))
    claimed: dict[str, int] = {}
    for index, route in enumerate(routes):
        for name in route.stations:
            if name not in built and stations:
                problems.append((("routes", index, "stations"),
                                 f"no station {name!r}; one of {', '.join(built)}"))
        for mover in route.movers or ():
            if mover not in axes:
                problems.append((("routes", index, "movers"),
                                 f"{mover!r} is not a mover of the group; one of "
                                 f"{', '.join(axes)}"))
            elif mover in claimed:
                problems.append((("routes", index, "movers"),
                                 f"{mover!r} is on route {claimed[mover] + 1} already"))
            claimed.setdefault(mover, index)
    return problems


def routes_of(routes: list[RouteSpec], axes: list[str]) -> list[tuple[RouteSpec, list[str]]]:
    """Each route with its movers: those it names, or every mover no route names."""
    named = {mover for route in routes for mover in route.movers or ()}
    rest = [axis for axis in axes if axis not in named]
    found = []
    for route in routes:
        movers = list(route.movers) if route.movers is not None else rest
        if route.movers is None:
            rest = []
        found.append((route, movers))
    return found


def build_line(rt: Runtime, group: CaGroup, stations: list[StationSpec],
               routes: list[RouteSpec], axes: list[str]) -> StationLine | None:
    """The group's station line (all its routes), added to ``rt`` after the group; None
    without stations."""
    if not stations:
        return None
    members = {mover.axis.name: mover.axis for mover in group.movers}
    movers = [(CaMoverPort(group, members[name], route.velocity, route.acceleration,
                           route.deceleration, route.jerk), route.build())
              for route, names in routes_of(routes, axes) for name in names]
    return station_line(rt, group, [spec.build() for spec in stations], movers)


def station_table(rows: list[tuple[str, StationRow]]) -> Any:
    """The summary's table of stations: what each processed, how busy, how long the queue."""
    from rich import box
    from rich.table import Table
    from rich.text import Text

    table = Table(box=box.SIMPLE, title_justify="left", title="Stations")
    for name in ("station", "processed", "per minute", "utilisation", "mean wait [s]",
                 "mean queue", "max queue"):
        table.add_column(Text(name), justify="left" if name == "station" else "right",
                         no_wrap=True)
    for _, row in rows:
        table.add_row(row.name, str(row.processed), f"{row.parts_per_minute:.2f}",
                      f"{row.utilisation:.3f}", f"{row.mean_wait:.3f}",
                      f"{row.mean_queue:.3f}", str(row.max_queue))
    return table
