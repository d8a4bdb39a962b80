"""Gear-in on tracks in scenario files (TF5430 §6.2.8, §6.2.9, §6.2.12, §6.8):
``gear_in_pos_on_track`` couples a mover on a track to an axis, and
``gear_in_pos_on_track_with_master_mover`` to another mover on a track.

They call the MC_PlanarMover methods of the same names (planar/gearing.py runs them). The
master is named: ``master`` is one of ``axes``, ``master_mover`` one of ``planar.movers``;
tracks are named as in planar_riding.py, and ``trail`` lists the track names of an
MC_PlanarTrackTrail that the run builds (AddTrack, §6.8) just before the call. The load
checks that each track of the trail starts where the one before ends, by the links of
``planar.tracks``, so a wrong order is a file:line error rather than a failed row.

The run passes the specialised feedbacks (MC_PlanarFeedbackGearInPosOnTrack, ...WithMasterMover),
whose ``in_sync`` a condition or a check reads as ``<id>.in_sync``; a gear-in has no Done and
stays Active until another command (a move_on_track, a halt) aborts it or an error ends it.
Option values the engine refuses (a negative gap, a modulo tolerance with non_modulo) are
issued, and the row ends with the engine's error, as for the other planar entries.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Annotated, Any, ClassVar, Literal, NamedTuple

from pydantic import AfterValidator, Field, StrictStr, model_validator

from openmotion.planar import (
    MC_PlanarFeedbackGearInPosOnTrack,
    MC_PlanarFeedbackGearInPosOnTrackWithMasterMover,
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
)
from openmotion.planar.feedback import MC_PlanarFeedbackInSync
from openmotion.scenario.planar import _check_planar_mover, _Constrained
from openmotion.scenario.planar_tracks import TrackName, TrackRef, starts_where_ends
from openmotion.scenario.schema import Number, _check_axis, with_options

#: a trail (``trail``) is built for each entry: Clear, then AddTrack for each track
TRAIL_METHODS = ("MC_PlanarTrackTrail.clear", "MC_PlanarTrackTrail.add_track")


class AxisRef(NamedTuple):
    """An axis argument of an entry, by name; the run passes the Axis of that name."""

    name: str


class MoverRef(NamedTuple):
    """A planar mover argument, by name; the run passes the MC_PlanarMover of that name."""

    name: str


class TrailRef(NamedTuple):
    """A trail argument, by its track names; the run builds the MC_PlanarTrackTrail."""

    tracks: tuple[str, ...]


def _check_trail(trail: list[str]) -> list[str]:
    """No track twice, each one starting where the one before ends (§6.8)."""
    for k, name in enumerate(trail):
        if name in trail[:k]:
            raise ValueError(f"{name!r} is in the trail twice (§6.8)")
        if k and not starts_where_ends(trail[k - 1], name):
            raise ValueError(f"{name!r} does not start where {trail[k - 1]!r} ends: a trail "
                             "follows the track links in order (§6.8)")
    return trail


Trail = Annotated[list[TrackName], Field(min_length=1), AfterValidator(_check_trail)]


class _GearIn(_Constrained):
    """The fields both gear-ins share: the path and the slave's sync. Each gear-in takes the
    fields of its options struct from the struct (schema.with_options, D-235)."""

    feedback: ClassVar[type[MC_PlanarFeedbackInSync]]  #: what the run passes for in_sync
    options: ClassVar[type]  #: the options struct, whose fields the entry has
    trail: Trail | None = None
    """Track names of the MC_PlanarTrackTrail: the slave's track and the tracks after it that
    it may take (§6.8); omitted: the slave stays on its track."""
    master_sync_position: Number
    """The master's position [mm] at which the slave is to be in sync."""
    slave_sync_position: Number
    """The slave's arc length on ``slave_sync_track`` [mm] at that moment."""
    slave_sync_track: TrackName
    """The track of the slave's sync position: its own track or one of its trail."""

    def _options(self) -> Any:
        """The options struct, from the fields of the same names."""
        return self.options(**{f.name: getattr(self, f.name) for f in fields(self.options)})

    def _trail(self) -> TrailRef | None:
        return None if self.trail is None else TrailRef(tuple(self.trail))

    def _sync_on_trail(self) -> None:
        """Without followMover the slave's path is the trail: the sync track must be on it."""
        if self.trail is not None and self.slave_sync_track not in self.trail:
            raise ValueError(f"slave_sync_track: {self.slave_sync_track!r} is not in the trail "
                             f"{self.trail}: the slave's path is its track and the trail after "
                             "it (§6.8)")


class _GearInPosOnTrack(_GearIn):
    """GearInPosOnTrack (§7.2.2.8.5): couple 1:1 to the axis ``master`` (§6.2.8); in sync
    the slave's arc length is slave sync + (master - master sync)."""

    method = "gear_in_pos_on_track"
    blocks = ("MC_PlanarFeedbackGearInPosOnTrack.update", "MC_PlanarFeedbackInSync.update",
              *TRAIL_METHODS)
    command: Literal["gear_in_pos_on_track"]
    feedback = MC_PlanarFeedbackGearInPosOnTrack
    options = ST_GearInPosOnTrackOptions
    master: Annotated[StrictStr, AfterValidator(_check_axis)]
    """Name of the master axis (one of axes): its set position drives the slave."""

    @model_validator(mode="after")
    def _sync_track(self) -> _GearInPosOnTrack:
        self._sync_on_trail()
        return self

    def arguments(self) -> tuple[Any, ...]:
        return (AxisRef(self.master), self._trail(), self.master_sync_position,
                self.slave_sync_position, TrackRef(self.slave_sync_track), self.constraint(),
                self._options())


#: with the fields of ST_GearInPosOnTrackOptions: gap (arc length, centre to centre, to the
#: mover ahead [mm]), in_sync_tolerance_distance [mm], direction_slave_sync_position (which
#: occurrence of the sync position on a closed-loop track counts, as MoveC picks its
#: target), modulo_tolerance_slave_sync_position [mm], allowed_slave_sync_directions
GearInPosOnTrack = with_options(_GearInPosOnTrack, ST_GearInPosOnTrackOptions)


class _GearInPosOnTrackWithMasterMover(_GearIn):
    """GearInPosOnTrackWithMasterMover (§7.2.2.8.6): couple 1:1 to another mover on a track
    (§6.2.9); with ``follow_mover`` the slave takes the master's way (§6.2.12)."""

    method = "gear_in_pos_on_track_with_master_mover"
    blocks = ("MC_PlanarFeedbackGearInPosOnTrackWithMasterMover.update",
              "MC_PlanarFeedbackInSync.update", *TRAIL_METHODS)
    command: Literal["gear_in_pos_on_track_with_master_mover"]
    feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover
    options = ST_GearInPosOnTrackWithMasterMoverOptions
    master_mover: Annotated[StrictStr, AfterValidator(_check_planar_mover)]
    """Name of the master mover (one of planar.movers, not the slave); its path coordinate
    drives the slave."""
    master_sync_track: TrackName
    """The track of the master's sync position."""

    @model_validator(mode="after")
    def _master_and_path(self) -> _GearInPosOnTrackWithMasterMover:
        if self.master_mover == self.mover:
            raise ValueError(f"master_mover: {self.mover!r} cannot be its own master (§6.2.9)")
        if not self.follow_mover:  # type: ignore[attr-defined]  # an option field
            self._sync_on_trail()
        return self

    def arguments(self) -> tuple[Any, ...]:
        return (MoverRef(self.master_mover), self._trail(), self.master_sync_position,
                TrackRef(self.master_sync_track), self.slave_sync_position,
                TrackRef(self.slave_sync_track), self.constraint(), self._options())


#: with the fields of ST_GearInPosOnTrackWithMasterMoverOptions: those of GearInPosOnTrack,
#: the master's direction_master_sync_position and modulo_tolerance_master_sync_position,
#: and follow_mover (the slave goes the shortest way to master_sync_track and then the
#: master's way; the trail then only leads it there)
GearInPosOnTrackWithMasterMover = with_options(_GearInPosOnTrackWithMasterMover,
                                               ST_GearInPosOnTrackWithMasterMoverOptions)

