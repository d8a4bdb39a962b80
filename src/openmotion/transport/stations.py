"""Stations on a CA rail: the movers of a CA group visit them under collision avoidance.

``add_stations(runtime, group, stations, routes)`` adds a ``StationLine`` (rail/stations.py)
whose movers travel by MC_MoveAbsoluteCA (TF5410 §9.1.1.1): on a ring always forwards
(ModuloDirection.Positive, so a mover never backs up to a station behind it), on an open rail
to the absolute position. The group queues a mover behind a busy station at its gap; the move
ends Done once the mover stands in its slot.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from openmotion.core.errors import ConfigError
from openmotion.core.special_values import MC_DEFAULT, InputValue
from openmotion.kernel.command import Command
from openmotion.rail.stations import Route, Station, StationLine
from openmotion.transport.enums import ModuloDirection
from openmotion.transport.group import CaGroup

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.runtime.runtime import Runtime

__all__ = ["CaMoverPort", "add_stations", "station_line"]

#: a mover stands when |set velocity| <= STANDING * its max velocity (float residue of the
#: group's tracking steps does not count as motion)
STANDING = 1e-9
#: a mover stands at its target within this distance [mm]
AT_TARGET = 1e-6


class CaMoverPort:
    """One mover of a CA group as a station line drives it."""

    def __init__(self, group: CaGroup, axis: Axis, velocity: InputValue,
                 acceleration: InputValue = MC_DEFAULT, deceleration: InputValue = MC_DEFAULT,
                 jerk: InputValue = MC_DEFAULT) -> None:
        self.group, self.axis = group, axis
        self.name = axis.name
        self.velocity, self.acceleration = velocity, acceleration
        self.deceleration, self.jerk = deceleration, jerk
        self.target = axis.set_position  #: where it was last sent [mm on the rail]

    def go(self, station: Station, position: float) -> Command:
        parameters = self.group.parameters
        direction = ModuloDirection.NON_MODULO
        if parameters.rail_is_ring:
            position %= parameters.rail_length
            direction = ModuloDirection.POSITIVE
        self.target = position
        return self.group.move_absolute(
            self.axis, position, self.velocity, self.acceleration, self.deceleration,
            self.jerk, direction=direction)

    def queued(self) -> bool:
        axis, parameters = self.axis, self.group.parameters
        if abs(axis.set_velocity) > STANDING * axis.parameters.max_velocity:
            return False
        short = self.target - axis.set_position
        if parameters.rail_is_ring:
            length = parameters.rail_length
            short = (short + length / 2.0) % length - length / 2.0
        return abs(short) > AT_TARGET


def add_stations(runtime: Runtime, group: CaGroup, stations: Sequence[Station],
                 routes: Route | Mapping[str, Route], velocity: InputValue, *,
                 acceleration: InputValue = MC_DEFAULT, deceleration: InputValue = MC_DEFAULT,
                 jerk: InputValue = MC_DEFAULT, name: str | None = None) -> StationLine:
    """A station line on ``group``'s rail, added to ``runtime`` after the group.

    ``routes``: one route for every mover of the group (in CA order at the time of the
    call), or a route per axis name (movers without one stay out of the line). The movers
    travel at ``velocity`` with the given dynamics (MC_DEFAULT: the axis's defaults)."""
    axes = _movers(group)
    if isinstance(routes, Route):
        routes = dict.fromkeys(axes, routes)
    _check_movers(group, routes, axes)
    return station_line(runtime, group, stations, [
        (CaMoverPort(group, axes[axis_name], velocity, acceleration, deceleration, jerk), route)
        for axis_name, route in routes.items()], name)


def station_line(runtime: Runtime, group: CaGroup, stations: Sequence[Station],
                 movers: Sequence[tuple[CaMoverPort, Route]],
                 name: str | None = None) -> StationLine:
    """A station line of movers each with its own port (velocity, dynamics) and route."""
    _movers(group)
    for station in stations:
        if station.path:
            raise ConfigError(f"station {station.name!r}: a CA rail has no tracks to name "
                              f"({station.path!r})")
        if group.parameters.rail_is_ring and not 0.0 <= station.position < \
                group.parameters.rail_length:
            raise ConfigError(f"station {station.name!r}: position {station.position:g} is "
                              f"off the ring [0, {group.parameters.rail_length:g})")
    line = StationLine(stations, movers, runtime.cycle_time, name or f"{group.name}.stations")
    runtime.add_system(line)
    group.station_lines.append(line)
    return line


def _movers(group: CaGroup) -> dict[str, Axis]:
    if not group.movers:
        raise ConfigError(f"stations on {group.name!r}: the group has no movers")
    return {mover.axis.name: mover.axis for mover in group.movers}


def _check_movers(group: CaGroup, routes: Mapping[str, Route], axes: Mapping[str, Axis]) -> None:
    unknown = sorted(set(routes).difference(axes))
    if unknown:
        raise ConfigError(f"stations on {group.name!r}: {unknown[0]!r} is not a mover of "
                          f"the group; one of {', '.join(axes)}")
