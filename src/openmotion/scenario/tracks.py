"""Tracks and geo-compensation of a CA group in scenario files (TF5410 §4.1, §8.2, §8.3).

A ``ca_groups`` entry (CaGroupSpec) may declare ``parts``, ``tracks``, a starter-kit
``geometry`` and mover ``templates``; ``configure`` sets them up on ``group.tracks``
(transport/tracks.py, transport/geo.py) right after the run builds the group. The scenario
validates by doing the same on a scratch group, so a file that loads also builds, and each
problem names its field: the numbers of a part, an unknown part in a track, a template id
used twice.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Annotated

from pydantic import Field, StrictInt

from openmotion.core.errors import ConfigError
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.schema import Number, _Model
from openmotion.transport.geo import STARTER_KIT_CURVE_RADIUS, MoverTemplate, StarterKitGeometry
from openmotion.transport.group import CaGroup

if TYPE_CHECKING:
    from openmotion.scenario.transport import CaGroupSpec

Oid = Annotated[StrictInt, Field(gt=0, le=0xFFFFFFFF)]
"""An OTCID: an integer > 0 (UDINT)."""
Loc = tuple[str | int, ...]


class PartSpec(_Model):
    """An XTS part: ``[start, end)`` of the absolute motor path, counted in the positive
    direction; on a ring it may wrap over the rail end (``start == end``: the whole ring)."""

    id: Oid
    """Its OTCID; unique among the group's parts and tracks."""
    start: Number
    """[mm], 0 <= start < rail_length."""
    end: Number
    """[mm], 0 <= end <= rail_length; > start on an open rail."""


class TrackSpec(_Model):
    """An XTS track: adjacent parts in order; track position 0 is the start of the first."""

    id: Oid
    """Its OTCID; unique among the group's parts and tracks."""
    parts: Annotated[list[StrictInt], Field(min_length=1)]
    """Ids of the group's parts, each starting where the one before ends."""


class GeometrySpec(_Model):
    """The starter-kit geometry (StarterKitGeometry): two 180° curves joined by two straights;
    its rail length is the group's ``rail_length`` and the rail must be a ring."""

    curve_radius: Annotated[Number, Field(gt=0.0)] = STARTER_KIT_CURVE_RADIUS
    """Radius of the motor path in the curves [mm]; default 500/pi (a 500 mm arc)."""
    rail_offset: Number = 0.0
    """Zero shift of the absolute position along the path [mm] (D-070)."""


class TemplateSpec(_Model):
    """A mover template (MoverTemplate): the TCP lies ``y_shift`` outward of the motor path."""

    id: Oid
    """Its OTCID; unique among the group's templates."""
    y_shift: Annotated[Number, Field(ge=0.0)] = 100.0
    """TCP displacement outward [mm], >= 0."""


def problems(spec: CaGroupSpec) -> list[tuple[Loc, str]]:
    """What is wrong with the tracks and geo-compensation of ``spec``, as (field path,
    message): found by configuring a scratch group with the spec's parameters."""
    if not (spec.parts or spec.tracks or spec.geometry or spec.templates):
        return []
    return list(configure(spec, CaGroup(Runtime(), spec.name, spec.parameters.build())))


def configure(spec: CaGroupSpec, group: CaGroup) -> Iterator[tuple[Loc, str]]:
    """Add the spec's parts, tracks, geometry and templates to ``group.tracks``; yield a
    problem (field path, message) for each that cannot be added, and go on with the rest."""
    yield from _parts(spec.parts, group)
    yield from _tracks(spec.tracks, spec.parts, group)
    if spec.geometry is not None:
        yield from _geometry(spec.geometry, group)
    if spec.templates and spec.geometry is None:
        yield ("templates",), "mover templates need the group's geometry (geometry: " \
                              "curve_radius, rail_offset; both have defaults)"
    elif group.tracks.geo.geometry is not None:  # else the geometry's problem says it
        yield from _templates(spec.templates, group)


def _parts(parts: list[PartSpec], group: CaGroup) -> Iterator[tuple[Loc, str]]:
    length, ring = group.parameters.rail_length, group.parameters.rail_is_ring
    seen: set[int] = set()
    for index, part in enumerate(parts):
        loc: Loc = ("parts", index)
        found = _clash(loc, part.id, seen, "part")
        if not 0.0 <= part.start < length:
            found.append(((*loc, "start"), f"must be in [0, {length:g}), got {part.start:g}"))
        if not 0.0 <= part.end <= length:
            found.append(((*loc, "end"), f"must be in [0, {length:g}], got {part.end:g}"))
        elif not ring and part.end <= part.start:
            found.append(((*loc, "end"), f"must be > start {part.start:g} on an open rail, "
                                         f"got {part.end:g}"))
        yield from found or _added(loc, group.tracks.add_part, part.id, part.start, part.end)


def _tracks(tracks: list[TrackSpec], parts: list[PartSpec], group: CaGroup) \
        -> Iterator[tuple[Loc, str]]:
    seen = {part.id for part in parts}
    declared = ", ".join(str(part.id) for part in parts) or "none"
    for index, track in enumerate(tracks):
        loc: Loc = ("tracks", index)
        found = _clash(loc, track.id, seen, "part or track")
        for number, part_id in enumerate(track.parts):
            if part_id in track.parts[:number]:
                found.append(((*loc, "parts", number), f"part {part_id} is listed twice"))
            elif all(part.id != part_id for part in parts):
                found.append(((*loc, "parts", number),
                              f"unknown part {part_id} (parts: {declared})"))
        yield from found
        if not found and set(track.parts) <= set(group.tracks.parts):  # else: a bad part
            yield from _added((*loc, "parts"), group.tracks.add_track, track.id, track.parts)


def _geometry(spec: GeometrySpec, group: CaGroup) -> Iterator[tuple[Loc, str]]:
    length = group.parameters.rail_length
    if not group.parameters.rail_is_ring:
        yield ("geometry",), "the starter-kit geometry needs a ring rail " \
                             "(parameters.rail_is_ring: true)"
    elif 2.0 * math.pi * spec.curve_radius >= length:
        yield ("geometry", "curve_radius"), "must leave straights: 2 pi curve_radius < " \
            f"rail_length {length:g}, got {spec.curve_radius:g}"
    else:
        yield from _added(("geometry",), group.tracks.geo.set_geometry,
                          StarterKitGeometry(length, spec.curve_radius, spec.rail_offset))


def _templates(templates: list[TemplateSpec], group: CaGroup) -> Iterator[tuple[Loc, str]]:
    geo = group.tracks.geo
    seen: set[int] = set()
    for index, template in enumerate(templates):
        loc: Loc = ("templates", index)
        found = _clash(loc, template.id, seen, "template")
        yield from found or _added(loc, geo.add_template,
                                   MoverTemplate(template.id, template.y_shift))


def _clash(loc: Loc, oid: int, seen: set[int], kind: str) -> list[tuple[Loc, str]]:
    """An id used before (``seen``) in the group: a problem; else it is now seen."""
    if oid in seen:
        return [((*loc, "id"), f"{oid} is already the id of a {kind} of this group")]
    seen.add(oid)
    return []


def _added(loc: Loc, add: Callable[..., object], *arguments: object) \
        -> Iterator[tuple[Loc, str]]:
    """Call ``add``; its ConfigError (an overlap, parts that do not join) as a problem."""
    try:
        add(*arguments)
    except ConfigError as exc:
        yield loc, str(exc)
