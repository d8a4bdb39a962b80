"""Parts and coordinate systems in scenario files (TF5430 §5, §6.6): ``planar.environment``'s
``coordinate_systems`` and ``parts``, and the part entries (``activate_part_position``,
``part_allow_enable``, ``part_force_disable``, ``part_reset``).

A part lists its stators by their lower-left corners in the part frame and its possible
positions, each the part frame's placement (x, y, c) in a coordinate system; the first is
active unless ``position_index`` says otherwise. ``build_layout`` makes the ``PartLayout`` that
``MC_PlanarEnvironment(rt, layout=...)`` takes; ``layout_problems`` says, field by field, what
would keep it from being built. Object ids are written as the manual prints them
(``16#01010060``) or as YAML integers (``0x01010060``).

planar.py puts the fields into its ``EnvironmentSpec`` and the entry into ``PLANAR_ENTRIES``.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Sequence
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, Field, PlainSerializer, PlainValidator, StrictInt

from openmotion.core.errors import ConfigError
from openmotion.planar import Part, PartLayout, PartPosition, Pose
from openmotion.planar.stators import STATOR_SIZE
from openmotion.scenario.schema import _NAMES, Number, _Model
from openmotion.scenario.transport import _Timed

Loc = tuple[str | int, ...]
_IEC_HEX = re.compile(r"^16#([0-9A-Fa-f](?:_?[0-9A-Fa-f])*)$")  #: 16#0101_0060 allowed
_MAX_OID = 0xFFFF_FFFF  #: an OTCID is a UDINT
_GRID = 1e-6  #: [mm] a corner this close to the grid is on it


def oid_text(oid: int) -> str:
    """An object id as the manual prints it: 16#01010060."""
    return f"16#{oid:08X}"


def parse_oid(value: object) -> int | None:
    """An object id from YAML: an integer, or ``16#...`` text; None when it is neither."""
    if isinstance(value, str) and (match := _IEC_HEX.match(value)):
        value = int(match.group(1).replace("_", ""), 16)
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= _MAX_OID:
        return None
    return value


def _reference_id(value: object) -> int:
    oid = parse_oid(value)
    if oid is None:
        raise ValueError("must be an object id (an integer in 0..16#FFFFFFFF, written "
                         f"16#01010060 or 0x01010060), got {value!r}")
    return oid


def _object_id(value: object) -> int:
    oid = _reference_id(value)
    if oid == 0:
        raise ValueError("must be an object id, not 0")
    return oid


_AS_TEXT = PlainSerializer(oid_text, when_used="json")
#: the OID of a part or a coordinate system
ObjectId = Annotated[int, PlainValidator(_object_id), _AS_TEXT]
#: a ReferenceId (§5.3): a part, a coordinate system, or 0 (the one static coordinate system)
ReferenceId = Annotated[int, PlainValidator(_reference_id), _AS_TEXT]


def part_oids(planar: object) -> set[int]:
    """The part OIDs in raw ``planar`` input, however malformed the rest of it is."""
    environment = planar.get("environment") if isinstance(planar, dict) else None
    parts = environment.get("parts") if isinstance(environment, dict) else None
    return {oid for part in parts if isinstance(part, dict)
            and (oid := parse_oid(part.get("oid"))) is not None} \
        if isinstance(parts, list) else set()


def _check_planar_part(oid: int) -> int:
    names = _NAMES.get()
    if names is not None and oid not in names.planar_parts:
        known = ", ".join(map(oid_text, sorted(names.planar_parts))) or "none"
        raise ValueError(f"{oid_text(oid)} is no part of planar.environment.parts "
                         f"(parts: {known})")
    return oid


# -- planar.environment.parts ----------------------------------------------------------------


class PartPositionSpec(_Model):
    """One possible position of a part: its frame (origin at its lower-left corner) placed in
    a coordinate system (§5.1)."""

    coordinate_system: ObjectId
    """OID of the coordinate system, one of ``coordinate_systems``."""
    x: Number = 0.0
    """The part's lower-left corner in the coordinate system [mm]."""
    y: Number = 0.0
    """[mm]."""
    c: Number = 0.0
    """Rotation of the part frame [°], a multiple of 90 (stators stay on the grid)."""

    def build(self) -> PartPosition:
        return PartPosition(self.coordinate_system, Pose(self.x, self.y, self.c))


class PartSpec(_Model):
    """One part (§5.1): contiguous stators that move together, with their possible positions."""

    blocks = ("MC_PlanarPart.initialize",)  #: the run's MC_PlanarPart of it, before t = 0

    oid: ObjectId
    """Its object id; parts and coordinate systems share one id space (§5.3)."""
    stators: Annotated[list[tuple[Number, Number]], Field(min_length=1)]
    """Lower-left corners [mm] in the part frame: on its 240 mm grid, the lowest x and the
    lowest y 0, each stator sharing an edge with another."""
    positions: Annotated[list[PartPositionSpec], Field(min_length=1)]
    """Where the part can be; a part with one position is static."""
    position_index: StrictInt = 1
    """The active position at the start, 1-based as ActivatePosition counts."""

    def build(self) -> Part:
        return Part(self.oid, [(float(x), float(y)) for x, y in self.stators],
                    [position.build() for position in self.positions], self.position_index)


def build_layout(coordinate_systems: Sequence[int], parts: Sequence[PartSpec]) -> PartLayout:
    """A new PartLayout (each run needs its own: parts change position)."""
    return PartLayout(coordinate_systems, [part.build() for part in parts])


def layout_problems(coordinate_systems: Sequence[int],
                    parts: Sequence[PartSpec]) -> list[tuple[Loc, str]]:
    """What keeps the layout from being built, as (field path, message)."""
    problems = list(_oid_problems(coordinate_systems, parts))
    for index, part in enumerate(parts):
        problems += [(("parts", index, *loc), message) for loc, message in _part_problems(part)]
        for k, position in enumerate(part.positions):
            if position.coordinate_system not in coordinate_systems:
                problems.append((("parts", index, "positions", k, "coordinate_system"),
                                 f"{oid_text(position.coordinate_system)} is not one of "
                                 "coordinate_systems"))
    problems += _grid_problems(parts)
    if not problems:
        try:
            build_layout(coordinate_systems, parts)
        except ConfigError as exc:  # "part 16#01010080: position_index: overlaps part ..."
            problems.append(_located(str(exc), parts))
    return problems


def _oid_problems(coordinate_systems: Sequence[int],
                  parts: Sequence[PartSpec]) -> Iterator[tuple[Loc, str]]:
    seen: set[int] = set()
    named: list[tuple[Loc, int]] = [(("coordinate_systems", k), oid)
                                    for k, oid in enumerate(coordinate_systems)]
    named += [(("parts", k, "oid"), part.oid) for k, part in enumerate(parts)]
    for loc, oid in named:
        if oid in seen:
            yield loc, f"{oid_text(oid)} is used twice: parts and coordinate systems share " \
                       "one id space (§5.3)"
        seen.add(oid)


def _part_problems(part: PartSpec) -> list[tuple[Loc, str]]:
    """The part's own problems: stators, position index ("part 16#..: stators: ...")."""
    try:
        part.build()
    except ConfigError as exc:
        field, _, message = str(exc).partition(": ")[2].partition(": ")
        return [((field,), message)]
    return []


def _grid_problems(parts: Sequence[PartSpec]) -> Iterator[tuple[Loc, str]]:
    """Every position turns its part by multiples of 90° and puts its stators on the 240 mm
    grid of the coordinate system, anchored at the first stator placed there."""
    anchors: dict[int, tuple[float, float]] = {}
    for index, part in enumerate(parts):
        for k, position in enumerate(part.positions):
            loc: Loc = ("parts", index, "positions", k)
            if position.c % 90.0:
                yield (*loc, "c"), f"must be a multiple of 90°, got {position.c:g}"
                continue
            pose = position.build().pose
            corner = pose.compose(Pose(*part.stators[0]))
            far = pose.compose(Pose(part.stators[0][0] + STATOR_SIZE,
                                    part.stators[0][1] + STATOR_SIZE))
            lower = (min(corner.x, far.x), min(corner.y, far.y))
            x0, y0 = anchors.setdefault(position.coordinate_system, lower)
            if not all(_on_grid(value - anchor) for value, anchor in zip(lower, (x0, y0),
                                                                           strict=True)):
                yield loc, f"the part's stators at ({position.x:g}, {position.y:g}) are off " \
                           f"the 240 mm grid of coordinate system " \
                           f"{oid_text(position.coordinate_system)} (anchored at ({x0:g}, " \
                           f"{y0:g}))"


def _on_grid(offset: float) -> bool:
    return abs(offset - STATOR_SIZE * round(offset / STATOR_SIZE)) <= _GRID


def _located(message: str, parts: Sequence[PartSpec]) -> tuple[Loc, str]:
    """A PartLayout error at its part's field: "part 16#..: field: message"; an overlap at
    the later of the two parts."""
    match = re.match(r"^part 16#([0-9A-F]{8}): ([a-z_]+): (.*)$", message, re.S)
    if match is None:
        return ("parts",), message
    oids = [part.oid for part in parts]
    index, field, text = oids.index(int(match.group(1), 16)), match.group(2), match.group(3)
    other = re.match(r"^overlaps part 16#([0-9A-F]{8})(.*)$", text, re.S)
    if other is not None and (later := oids.index(int(other.group(1), 16))) > index:
        index, text = later, f"overlaps part {oid_text(oids[index])}{other.group(2)}"
    return ("parts", index, field), text


def is_static(coordinate_systems: Sequence[int], parts: Sequence[PartSpec]) -> bool:
    """One coordinate system and no part with more than one position (PartLayout.is_static)."""
    return len(coordinate_systems) == 1 and all(len(part.positions) == 1 for part in parts)


# -- the timeline ------------------------------------------------------------------------------


class PartEntry(_Timed):
    """A command for one part: the run calls the MC_PlanarPart method ``method``.

    The run initialises one MC_PlanarPart per part before t = 0 (Initialize).
    """

    part: Annotated[ObjectId, AfterValidator(_check_planar_part)]
    """OID of the part (one of planar.environment.parts)."""

    @property
    def axis(self) -> str:
        """The part's OID, for the summary's axis column."""
        return oid_text(self.part)

    def arguments(self) -> tuple[Any, ...]:
        return ()


class ActivatePartPosition(PartEntry):
    """MC_PlanarPart.ActivatePosition (§7.2.2.9.2, §6.6.1): the part goes to another of its
    positions; movers standing on it ride along, into its coordinate system there."""

    method = "activate_position"
    command: Literal["activate_part_position"]
    position_index: StrictInt
    """1-based; one that names no position fails with PLANAR_INVALID_INPUT."""

    def arguments(self) -> tuple[Any, ...]:
        return (self.position_index,)


class PartAllowEnable(PartEntry):
    """MC_PlanarPart.AllowEnable (§7.2.2.9.3, §6.6): a part that was force-disabled may
    switch on again with the movers of its coordinate system."""

    method = "allow_enable"
    command: Literal["part_allow_enable"]


class PartForceDisable(PartEntry):
    """MC_PlanarPart.ForceDisable (§7.2.2.9.4, §6.6): the part switches off and stays off
    until AllowEnable."""

    method = "force_disable"
    command: Literal["part_force_disable"]


class PartReset(PartEntry):
    """MC_PlanarPart.Reset (§7.2.2.9.5): clear the part's error (PLANAR_WRONG_STATE
    outside Error)."""

    method = "reset"
    command: Literal["part_reset"]


PART_ENTRIES: tuple[type, ...] = (ActivatePartPosition, PartAllowEnable, PartForceDisable,
                                  PartReset)
