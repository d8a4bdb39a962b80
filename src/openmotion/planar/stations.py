"""Stations on planar tracks: movers on a track network visit them by MC_MoveOnTrack.

``add_planar_stations`` adds a ``StationLine`` (rail/stations.py) whose movers travel with
MoveOnTrack (TF5430 §6.2.2): along the network to the station's track and arc length,
keeping the gap to the mover ahead, so a mover sent to a busy station queues on its track. A
station names its track (``Station.path``); a mover takes part once it is on a track (its
command mode is OnTrack), so a scenario's JoinTrack entries run first.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

from openmotion.core.errors import ConfigError
from openmotion.planar.enums import ModuloDirection, MoverCommandMode, TrackOperationMode
from openmotion.planar.feedback import PlanarCommand
from openmotion.planar.mover import MC_PlanarMover
from openmotion.planar.options import IPlcDynamicConstraint, ST_MoveOnTrackOptions
from openmotion.planar.track import MC_PlanarTrack
from openmotion.rail.stations import Route, Station, StationLine

if TYPE_CHECKING:
    from openmotion.kernel.runtime import CyclicRuntime

__all__ = ["PlanarTrackPort", "add_planar_stations"]

#: a mover stands when its path velocity is at most this [mm/s]
STANDING = 1e-9
#: a mover stands at its target within this arc length [mm]
AT_TARGET = 1e-6
#: on a closed loop a mover within this of its target stays, instead of a lap [mm]
MODULO_WINDOW = 0.5
#: the track operation modes in which a track takes MoveOnTrack (§4.3)
_MOVING_MODES = frozenset({TrackOperationMode.STANDING, TrackOperationMode.MOVING})


class PlanarTrackPort:
    """One planar mover on a track network as a station line drives it."""

    def __init__(self, mover: MC_PlanarMover, tracks: Mapping[str, MC_PlanarTrack],
                 constraint: IPlcDynamicConstraint | None = None,
                 options: ST_MoveOnTrackOptions | None = None) -> None:
        self.mover, self.tracks = mover, dict(tracks)
        self.name = mover.name
        self.constraint, self.options = constraint, options
        self.target: tuple[int, float] = (0, math.nan)  #: (track OID, arc length [mm])

    def ready(self) -> bool:
        """On a track and free to take MoveOnTrack: not joining or leaving, and no track of
        the line configuring (a track takes no motion while a mover joins it, §4.3)."""
        return self.mover.command_mode is MoverCommandMode.ON_TRACK and all(
            track.operation_mode in _MOVING_MODES for track in self.tracks.values())

    def go(self, station: Station, position: float) -> PlanarCommand:
        track = self.tracks[station.path]
        self.target = (track.oid, position)
        options = self.options
        if track.closed_loop and (options is None or
                                  options.direction is ModuloDirection.NON_MODULO):
            # forwards round a loop, never back into the mover behind
            options = replace(options or ST_MoveOnTrackOptions(),
                              direction=ModuloDirection.POSITIVE,
                              modulo_tolerance=max(MODULO_WINDOW, (options or
                                                   ST_MoveOnTrackOptions()).modulo_tolerance))
        return self.mover.move_on_track(track, position, self.constraint, options)

    def queued(self) -> bool:
        state = self.mover.mc_to_plc
        velocity = state.set.set_velo
        if math.hypot(velocity.x, velocity.y) > STANDING:
            return False
        track, position = self.target
        on_track = state.set_on_track
        return on_track.track_oid != track or abs(on_track.set_pos - position) > AT_TARGET


def add_planar_stations(runtime: CyclicRuntime, movers: Sequence[MC_PlanarMover],
                        tracks: Mapping[str, MC_PlanarTrack], stations: Sequence[Station],
                        routes: Route | Mapping[str, Route], *,
                        constraint: IPlcDynamicConstraint | None = None,
                        options: ST_MoveOnTrackOptions | None = None,
                        name: str = "stations") -> StationLine:
    """A station line of planar ``movers`` on the named ``tracks``, added to ``runtime``
    after the planar system (the line needs the planar objects made first).

    ``routes``: one route for every mover, or one per mover name. Each station names its
    track in ``path``; MoveOnTrack takes the mover there with ``constraint`` and ``options``
    (None: the mover's defaults and ST_MoveOnTrackOptions' gap; on a closed loop direction
    Positive, so that no mover backs up round the loop into the one behind it)."""
    if not movers:
        raise ConfigError("planar stations: no movers")
    by_name = {mover.name: mover for mover in movers}
    if isinstance(routes, Route):
        routes = dict.fromkeys(by_name, routes)
    unknown = sorted(set(routes).difference(by_name))
    if unknown:
        raise ConfigError(f"planar stations: {unknown[0]!r} is not one of the movers "
                          f"{', '.join(by_name)}")
    for station in stations:
        track = tracks.get(station.path)
        if track is None:
            raise ConfigError(f"station {station.name!r}: no track {station.path!r}; one of "
                              f"{', '.join(tracks) or 'none'}")
    line = StationLine(stations, [(PlanarTrackPort(by_name[mover], tracks, constraint, options),
                                   route) for mover, route in routes.items()],
                       runtime.cycle_time, name)
    runtime.add_system(line)
    return line
