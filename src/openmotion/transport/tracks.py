"""Track management of a CA group: parts, tracks and each mover's active track
(TF5410 §8.3, §9.1.1.1.5-6; docs/collision-avoidance.md, D-074).

A *part* is a stretch ``[start, end)`` of the rail's absolute motor path; parts do not
overlap. A *track* is an ordered list of adjacent parts; it is *closed* when it covers the
whole ring. A mover's *active track* (0 = none: the absolute frame) is the frame of the
positions of its later MC_MoveAbsoluteCA commands. The track position is the arc length along
the track from the start of its first part, modulo the track length on a closed track.

The group holds one ``TrackTable`` as ``group.tracks``; it also holds the rail's
geo-compensation (``group.tracks.geo``, transport/geo.py)::

    group.tracks.add_part(11, 0.0, 1000.0)
    group.tracks.add_part(12, 1000.0, 2000.0)
    group.tracks.add_track(21, [11, 12])
    group.tracks.activate_track(axis, 21)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.checks import finite_number
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.transport.enums import ModuloDirection
from openmotion.transport.geo import GeoCompensation, MoverTemplate, StarterKitGeometry
from openmotion.transport.tolerances import JOINT_TOLERANCE

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.transport.group import CaGroup, CaJob


@dataclass(frozen=True)
class Part:
    """An XTS part: ``[start, end)`` on the absolute motor path; it may wrap on a ring."""

    part_id: int  #: its OTCID (> 0)
    start: float  #: [mm], in [0, rail_length)
    end: float  #: [mm], in [0, rail_length]; end == start on a ring: the whole ring
    length: float  #: [mm]


@dataclass(frozen=True)
class Track:
    """An XTS track: adjacent parts in order; closed when it covers the whole ring."""

    track_id: int  #: its OTCID (> 0)
    parts: tuple[Part, ...]
    offsets: tuple[float, ...]  #: track position of each part's start [mm]
    length: float  #: [mm]
    closed: bool

    @property
    def start(self) -> float:
        """Absolute motor position of track position 0 [mm]."""
        return self.parts[0].start


class TrackPositions(NamedTuple):
    """The outputs of MC_ReadTrackPositions (§9.1.1.1.5)."""

    track_position: float  #: set position in the active track's frame [mm]
    track_id: int  #: the active track (0: the absolute frame)
    part_position: float  #: set position on the current part [mm]
    part_id: int  #: the current part (0: no active track)


def _oid(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value > 0


class TrackTable:
    """Parts, tracks and the active track of every mover of one CA group."""

    def __init__(self, group: CaGroup) -> None:
        self._group = group
        self.parts: dict[int, Part] = {}
        self.tracks: dict[int, Track] = {}
        self.geo = GeoCompensation(group)
        self._active: dict[int, int] = {}  #: axis row -> track id

    # -- configuration -------------------------------------------------------------------------

    def add_part(self, part_id: int, start: float, end: float) -> Part:
        """A part from ``start`` to ``end`` on the absolute motor path (positive direction)."""
        length_, ring = self._rail()
        if not _oid(part_id) or part_id in self.parts or part_id in self.tracks:
            raise ConfigError(f"part {part_id!r}: a new OTCID > 0 is needed")
        for name, value in (("start", start), ("end", end)):
            finite_number(value, f"part {part_id}: {name}")
            if not 0.0 <= value <= length_ or (name == "start" and value == length_):
                raise ConfigError(f"part {part_id}: {name} {value!r} outside [0, {length_:g})")
        if ring:
            length = (end - start) % length_ or length_
        elif end <= start:
            raise ConfigError(f"part {part_id}: end {end:g} <= start {start:g} on an open rail")
        else:
            length = float(end - start)
        part = Part(part_id, float(start), float(end), float(length))
        for other in self.parts.values():
            if self._overlap(part, other):
                raise ConfigError(f"part {part_id} overlaps part {other.part_id}")
        self.parts[part_id] = part
        return part

    def add_track(self, track_id: int, part_ids: Sequence[int]) -> Track:
        """A track of adjacent parts, in the order the positions count."""
        length_, ring = self._rail()
        if not _oid(track_id) or track_id in self.tracks or track_id in self.parts:
            raise ConfigError(f"track {track_id!r}: a new OTCID > 0 is needed")
        missing = [p for p in part_ids if p not in self.parts]
        if not part_ids or missing or len(set(part_ids)) != len(part_ids):
            raise ConfigError(f"track {track_id}: parts {list(part_ids)!r} must be distinct "
                              f"existing parts (unknown: {missing})")
        parts = tuple(self.parts[p] for p in part_ids)
        for a, b in zip(parts, parts[1:], strict=False):
            gap = (b.start - a.end) % length_ if ring else b.start - a.end
            if abs(gap) > JOINT_TOLERANCE and abs(gap - length_) > JOINT_TOLERANCE:
                raise ConfigError(f"track {track_id}: part {b.part_id} does not start where "
                                  f"part {a.part_id} ends")
        offsets = [0.0]
        for part in parts[:-1]:
            offsets.append(offsets[-1] + part.length)
        total = offsets[-1] + parts[-1].length
        track = Track(track_id, parts, tuple(offsets), total,
                      ring and math.isclose(total, length_, rel_tol=0.0, abs_tol=JOINT_TOLERANCE))
        self.tracks[track_id] = track
        return track

    # -- per mover -------------------------------------------------------------------------------

    def activate_track(self, axis: Axis, track_id: int) -> Command:
        """MC_ActivateTrack (§9.1.1.1.6): ``track_id`` becomes the frame of the mover's later
        positions; the set position must lie on a part of the track. 0: the absolute frame."""
        command = Command("activate_track", self._group.runtime.now)
        try:
            self._member(axis)
            if not (isinstance(track_id, int) and not isinstance(track_id, bool) and
                    (track_id == 0 or track_id in self.tracks)):
                raise CommandRejected(ErrorId.UNKNOWN_TRACK,
                                      f"TrackId {track_id!r}: no such track in the group")
            if track_id:
                self._position_on(self.tracks[track_id], axis.set_position)
        except CommandRejected as rejected:
            command.end(CommandStatus.ERROR, command.issued_at, rejected.error_id,
                         rejected.message)
            return command
        if track_id:
            self._active[axis.row] = track_id
        else:
            self._active.pop(axis.row, None)
        command.end(CommandStatus.DONE, command.issued_at)
        return command

    def active_track(self, axis: Axis) -> Track | None:
        track_id = self._active.get(axis.row)
        return None if track_id is None else self.tracks[track_id]

    def part_at(self, position: float) -> Part | None:
        """The part the absolute ``position`` lies on, if any."""
        return next((p for p in self.parts.values() if self._contains(p, position)), None)

    def read_track_positions(self, axis: Axis) -> TrackPositions:
        """MC_ReadTrackPositions (§9.1.1.1.5), from the set position. Without an active track:
        the absolute set position and ids 0. Raises CommandRejected: AXIS_NOT_IN_GROUP, or
        NOT_ON_TRACK when the mover left its active track."""
        self._member(axis)
        p = axis.set_position
        track = self.active_track(axis)
        if track is None:
            return TrackPositions(p, 0, p, 0)
        part, on_part = self._position_on(track, p)
        index = track.parts.index(part)
        return TrackPositions(track.offsets[index] + on_part, track.track_id, on_part,
                              part.part_id)

    def to_absolute(self, axis: Axis, position: float,
                    direction: ModuloDirection = ModuloDirection.NON_MODULO,
                    position_reference_system: int = 0) -> float:
        """A MoveAbsoluteCA ``position`` of ``axis`` on the absolute motor path.

        The frame is the mover's active track (else the absolute frame), measured on the
        motor path or, with PositionReferenceSystem = its registered template, on the TCP path.
        Modulo directions: ``position`` in [0, frame period], the result in [0, rail_length]
        (open tracks take NonModulo only, §9.4.1.3). NonModulo on a track: relative to where
        the mover is now in that frame, so the mover moves by ``position - track position``
        (D-074).
        """
        template = self.geo.reference(axis, position_reference_system)
        forward, inverse, period = self._metric(template)
        track = self.active_track(axis)
        length_, _ = self._rail()
        modulo = direction is not ModuloDirection.NON_MODULO
        if track is not None and modulo and not track.closed:
            raise CommandRejected(ErrorId.INVALID_DIRECTION,
                                  f"track {track.track_id} is open: NonModulo only (§9.4.1.3)")
        if modulo and not 0.0 <= position <= period:
            raise CommandRejected(ErrorId.INVALID_TARGET_POSITION,
                                  f"modulo target {position:g} outside [0, {period:g}]")
        if track is None:
            x = inverse(position)
            return min(max(x, 0.0), length_) if modulo else x
        origin = forward(track.start)
        if modulo:
            x = inverse(origin + position)
            return x - length_ if x > length_ else x
        p = axis.set_position
        self._position_on(track, p)
        here = (forward(p) - origin) % period
        if not track.closed:
            span = forward(track.start + track.length) - origin
            if not 0.0 <= position <= span:
                raise CommandRejected(ErrorId.TARGET_OFF_TRACK,
                                      f"track position {position:g} outside [0, {span:g}] of "
                                      f"open track {track.track_id}")
        return inverse(forward(p) + position - here)

    def gap_paths(self, slots: np.ndarray
                  ) -> tuple[np.ndarray | None, StarterKitGeometry | None]:
        """The y-shift of the template each mover of ``slots`` registered (0: none) and the
        geometry: gaps of registered successors are measured on their TCP path (D-073).
        (None, None) when no mover of the group registered one."""
        geo = self.geo
        if geo.geometry is None or not geo.any_registered:
            return None, None
        movers = self._group.movers
        y = np.array([getattr(geo.registered(movers[slot].axis), "y_shift", 0.0)
                      for slot in slots.tolist()])
        return (y, geo.geometry) if (y > 0.0).any() else (None, None)

    def compensate(self, axis: Axis, job: CaJob, dynamics_reference_system: int) -> None:
        """DynamicsReferenceSystem of a CA job (transport/geo.py, D-072)."""
        self.geo.compensate(axis, job, dynamics_reference_system)

    # -- internals -------------------------------------------------------------------------------

    def _rail(self) -> tuple[float, bool]:
        parameters = self._group.parameters
        return parameters.rail_length, parameters.rail_is_ring

    def _member(self, axis: Axis) -> None:
        if axis.group is not self._group:
            raise CommandRejected(ErrorId.AXIS_NOT_IN_GROUP,
                                  f"{axis.name} is not in CA group {self._group.name!r}")

    def _metric(self, template: MoverTemplate | None
                ) -> tuple[Callable[[float], float], Callable[[float], float], float]:
        """Motor path -> frame path, its inverse, and the lap of the frame path."""
        length_, _ = self._rail()
        if template is None:
            return (lambda x: x), (lambda x: x), length_
        geo = self.geo
        assert geo.geometry is not None
        return (lambda x: geo.to_tcp(template, x)), (lambda t: geo.to_motor(template, t)), \
            geo.geometry.tcp_lap(template.y_shift)

    def _contains(self, part: Part, position: float) -> bool:
        length_, ring = self._rail()
        if ring:
            return (position - part.start) % length_ < part.length
        return part.start <= position < part.end or position == part.end == length_

    def _position_on(self, track: Track, position: float) -> tuple[Part, float]:
        """The part of ``track`` under ``position`` and the position on it, or NOT_ON_TRACK."""
        part = next((p for p in track.parts if self._contains(p, position)), None)
        if part is None:
            raise CommandRejected(ErrorId.NOT_ON_TRACK,
                                  f"set position {position:g} is on no part of track "
                                  f"{track.track_id}")
        length_, ring = self._rail()
        return part, ((position - part.start) % length_ if ring else position - part.start)

    def _overlap(self, a: Part, b: Part) -> bool:
        length_, ring = self._rail()
        if not ring:
            return a.start < b.end and b.start < a.end
        return (b.start - a.start) % length_ < a.length or \
            (a.start - b.start) % length_ < b.length
