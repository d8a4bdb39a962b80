"""The track commands of a planar mover in scenario files (TF5430 §4.2, §6.1.9, §6.2.4):
``join_track``, ``leave_track`` and ``move_on_track``; ``mover_halt`` (planar.py) brakes a
mover on a track along it.

They call the MC_PlanarMover methods of the same names (planar/riding.py runs them). A track
is named in ``track``; the run passes the MC_PlanarTrack of that name (planar_tracks.py). The
acceptance rules are the engine's: JoinTrack and LeaveTrack only while the track is not
Moving, MoveOnTrack only while it is not Configuring (§4.3); a refused command's row says so.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import StrictBool, StrictInt

from openmotion.planar import ModuloDirection
from openmotion.planar.options import (
    ST_JoinTrackOptions,
    ST_LeaveTrackOptions,
    ST_MoveOnTrackOptions,
)
from openmotion.scenario.planar import ModuloDirectionName, _Constrained, _Target
from openmotion.scenario.planar_tracks import TrackName, TrackRef
from openmotion.scenario.schema import Number

_MOVE_ON_TRACK = ST_MoveOnTrackOptions()  #: the options' defaults


class JoinTrack(_Constrained):
    """JoinTrack (§7.2.2.8.2): a free move onto the point of ``track`` nearest to the mover,
    coupled to the track at its end; refused while the track is Moving."""

    method = "join_track"
    command: Literal["join_track"]
    track: TrackName
    """Name of the track (one of planar.tracks)."""
    use_orientation: StrictBool = True
    """ST_JoinTrackOptions: also turn to the track's heading, and follow it on the track."""

    def arguments(self) -> tuple[Any, ...]:
        return (TrackRef(self.track), self.constraint(),
                ST_JoinTrackOptions(use_orientation=self.use_orientation))


class LeaveTrack(_Target):
    """LeaveTrack (§7.2.2.8.3): uncouple from the track and move freely to (x, y), and to c
    with orientation; refused while the track is Moving."""

    method = "leave_track"
    command: Literal["leave_track"]

    def arguments(self) -> tuple[Any, ...]:
        return (self.target(), self.constraint(),
                ST_LeaveTrackOptions(use_orientation=self.orientation))


class MoveOnTrack(_Constrained):
    """MoveOnTrack (§7.2.2.8.4): travel along the network to ``position`` on ``track``,
    keeping ``gap`` to the mover ahead; queued movers wait (the row stays busy)."""

    method = "move_on_track"
    command: Literal["move_on_track"]
    track: TrackName | None = None
    """Name of the target track; default: the track the mover is on. Another track is
    reached by the shortest route through the network (end to start only)."""
    position: Number
    """Target arc length on that track [mm], 0 to its length."""
    gap: Number = _MOVE_ON_TRACK.gap
    """Arc-length distance, centre to centre, kept to the mover ahead [mm]."""
    direction: ModuloDirectionName = ModuloDirection.NON_MODULO  # type: ignore[valid-type]
    """non_modulo, positive, shortest_way or negative (the latter on a closed loop)."""
    additional_turns: StrictInt = 0
    """Extra laps of a closed loop with positive or negative."""
    modulo_tolerance: Number = 0.0
    """[mm] a target this close behind (or ahead) counts as reached (closed loop)."""

    def arguments(self) -> tuple[Any, ...]:
        track = None if self.track is None else TrackRef(self.track)
        return (track, self.position, self.constraint(),
                ST_MoveOnTrackOptions(self.gap, self.direction, self.additional_turns,
                                      self.modulo_tolerance))
