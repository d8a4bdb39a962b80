"""Planar parts and coordinate systems (TF5430 §5, §6.6; MC_PlanarPart §7.2.2.9).

A part is a rigid, contiguous set of 240 mm stators with one or more possible positions; each
position places the part's own frame (origin at its lower-left corner) in a coordinate system.
``Part`` holds one part's geometry, active position and PlanarState; ``PartLayout`` holds all
parts and coordinate systems of a processing unit, as the environment reads them (§5.2). It
resolves ReferenceIds (§5.3), activates part positions, switches parts with the movers (§6.6)
and tells whether a move stays on the parts where they actually meet.

Object ids are OTCIDs (UDINT), written 16#01010030 in messages as the manual prints them.
"""

from __future__ import annotations

import contextlib
from collections.abc import Collection, Iterable, Sequence
from dataclasses import dataclass
from itertools import pairwise
from typing import ClassVar, NamedTuple

import shapely
from shapely.affinity import affine_transform
from shapely.geometry import LineString, Point, Polygon, box
from shapely.geometry.base import BaseGeometry

from openmotion.core.checks import finite_number, finite_pair
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.kernel.model import Kind
from openmotion.planar.enums import PlanarState
from openmotion.planar.frames import Pose
from openmotion.planar.kind import PLANAR_PART
from openmotion.planar.tolerances import PART_TOLERANCE

STATOR_SIZE = 240.0  #: side of a square stator [mm] (§5.1)
_MAX_OID = 0xFFFF_FFFF  #: an OTCID is a UDINT
_ERROR_STATES = (PlanarState.ERROR_PENDING, PlanarState.ERROR, PlanarState.RESETTING)


def _hex(oid: int) -> str:
    """An object id as the manual prints it (16#01010030)."""
    return f"16#{oid:08X}"


def _check_oid(oid: int, field: str) -> int:
    if isinstance(oid, bool) or not isinstance(oid, int) or not 0 < oid <= _MAX_OID:
        raise ConfigError(f"{field}: {oid!r} is not an object id (an integer in 1..16#FFFFFFFF)")
    return oid


@dataclass(frozen=True)
class PartPosition:
    """One possible position of a part: its frame placed in a coordinate system (§5.1)."""

    coordinate_system: int  #: OID of the coordinate system
    pose: Pose  #: the part's lower-left corner [mm] and rotation [°] in that system

    def __post_init__(self) -> None:
        _check_oid(self.coordinate_system, "coordinate_system")
        pose = self.pose
        if isinstance(pose, str | bytes) or not hasattr(pose, "__len__") or len(pose) != 3:
            raise ConfigError(f"pose: must be a Pose (x, y, c), got {pose!r}")
        object.__setattr__(self, "pose", Pose(*(finite_number(value, f"pose.{name}")
                                                for value, name in zip(pose, "xyc",
                                                                       strict=True))))


class Part:
    """One part: stators, possible positions, the active one and its PlanarState (§5.1, §6.6).

    The state is driven by MC_PlanarPart's AllowEnable / ForceDisable / Reset and, through
    ``PartLayout.follow_movers``, by the movers of its coordinate system. Transitional states
    (Enabling, Disabling, ErrorPending, Resetting) end at the next ``update``.
    """

    MACHINE: ClassVar[Kind] = PLANAR_PART  #: its signals and commands in the machine model

    def __init__(self, oid: int, stators: Iterable[tuple[float, float]],
                 positions: Sequence[PartPosition], position_index: int = 1) -> None:
        self.oid = _check_oid(oid, "part oid")
        cells = _stator_cells(self.name, stators)
        #: lower-left corners of the stators in the part frame [mm]
        self.stators = tuple((col * STATOR_SIZE, row * STATOR_SIZE) for col, row in cells)
        self.positions = tuple(positions)
        for index, position in enumerate(self.positions, start=1):
            if not isinstance(position, PartPosition):
                raise ConfigError(f"{self.name}: positions[{index}]: must be a PartPosition, "
                                  f"got {type(position).__name__}")
        if not self.positions:
            raise ConfigError(f"{self.name}: positions: a part needs at least one position")
        if problem := _index_problem(position_index, len(self.positions)):
            raise ConfigError(f"{self.name}: position_index: {problem}")
        self._position_index = position_index
        local = shapely.union_all([_stator_box(cell) for cell in cells])
        self._surfaces = tuple(affine_transform(local, p.pose.affine()) for p in self.positions)
        shapely.prepare(self._surfaces)
        self.state = PlanarState.DISABLED
        self.disable_forced = False  #: ForceDisable holds until the next AllowEnable (§6.6)
        self._reset_to = PlanarState.DISABLED

    @property
    def name(self) -> str:
        return f"part {_hex(self.oid)}"

    @property
    def position_index(self) -> int:
        """The active position, 1-based as ActivatePosition counts (§6.6.1)."""
        return self._position_index

    @position_index.setter
    def position_index(self, index: int) -> None:
        """Move the part (ActivatePosition: the layout and the environment check first)."""
        self._position_index = index

    @property
    def active_position(self) -> PartPosition:
        """What MC_PlanarPart.GetPosition reports: the system and the pose of the part frame."""
        return self.positions[self._position_index - 1]

    @property
    def is_static(self) -> bool:
        return len(self.positions) == 1

    def surface(self, position_index: int | None = None) -> Polygon:
        """The stator surface in the coordinate system of a position (default: the active one)."""
        return self._surfaces[(position_index or self._position_index) - 1]

    def covers(self, x: float, y: float, position_index: int | None = None) -> bool:
        """Whether a point of the position's coordinate system is on the part (edges count)."""
        low_x, low_y, high_x, high_y = self.surface(position_index).bounds
        if not (low_x - PART_TOLERANCE <= x <= high_x + PART_TOLERANCE
                and low_y - PART_TOLERANCE <= y <= high_y + PART_TOLERANCE):
            return False  # far off (also no overflow in the distance of a huge coordinate)
        return shapely.dwithin(self.surface(position_index), Point(x, y), PART_TOLERANCE)

    def allow_enable(self) -> None:
        """AllowEnable: the part may be enabled again after a ForceDisable (§6.6)."""
        self.disable_forced = False

    def force_disable(self) -> None:
        """ForceDisable: switch off and stay off until AllowEnable (§6.6)."""
        self.disable_forced = True
        self.disable()

    def reset(self) -> None:
        """Reset: clear a part error; ends Enabled unless the reaction was escalated (§4.1)."""
        if self.state is not PlanarState.ERROR:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{self.name}: Reset needs state ERROR, not {self.state.name}")
        self.state = PlanarState.RESETTING

    def enable(self) -> None:
        """Switch the stators on, when a mover of its system needs them (§6.6)."""
        if self.disable_forced or self.state in _ERROR_STATES:
            why = "is force-disabled" if self.disable_forced else f"is in {self.state.name}"
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE, f"{self.name} {why}")
        if self.state in (PlanarState.DISABLED, PlanarState.DISABLING):
            self.state = PlanarState.ENABLING

    def disable(self) -> None:
        """Switch off; during an error only make the reset end Disabled (Abort, §4.1)."""
        if self.state in (PlanarState.ENABLED, PlanarState.ENABLING):
            self.state = PlanarState.DISABLING
        self._reset_to = PlanarState.DISABLED

    def fail(self) -> None:
        """The stators report an error. During Resetting the reset fails (§4.1 has no arrow)."""
        if self.state is PlanarState.RESETTING:
            self.state = PlanarState.ERROR
        elif self.state not in _ERROR_STATES:
            enabled = self.state in (PlanarState.ENABLED, PlanarState.ENABLING)
            self._reset_to = PlanarState.ENABLED if enabled else PlanarState.DISABLED
            self.state = PlanarState.ERROR_PENDING

    def update(self) -> None:
        """End a transitional state: one cycle, the time the environment needs to answer."""
        self.state = {
            PlanarState.ENABLING: PlanarState.ENABLED,
            PlanarState.DISABLING: PlanarState.DISABLED,
            PlanarState.ERROR_PENDING: PlanarState.ERROR,
            PlanarState.RESETTING: self._reset_to,
        }.get(self.state, self.state)


def _index_problem(index: int, count: int) -> str | None:
    """Why ``index`` names none of ``count`` positions (1-based), or None."""
    if isinstance(index, bool) or not isinstance(index, int) or not 1 <= index <= count:
        return f"position index {index!r} is not in 1..{count}"
    return None


def _stator_cells(name: str, stators: Iterable[tuple[float, float]]) -> list[tuple[int, int]]:
    """Stator corners as grid cells; a part is one edge-connected set without overlaps (§5.1)."""
    cells = [_grid_cell(name, *finite_pair(corner, f"{name}: stators[{k}]"))
             for k, corner in enumerate(stators)]
    if not cells:
        raise ConfigError(f"{name}: stators: a part needs at least one stator")
    if len(set(cells)) < len(cells):
        twice = next(cell for cell in cells if cells.count(cell) > 1)
        raise ConfigError(f"{name}: stators: two stators overlap at {_corner(twice)}")
    if min(col for col, _ in cells) != 0 or min(row for _, row in cells) != 0:
        raise ConfigError(f"{name}: stators: the part frame's origin must be the part's "
                          "lower-left corner (lowest x and lowest y both 0)")
    if stray := _not_connected(cells):
        raise ConfigError(f"{name}: stators: {_corner(stray)} shares no edge with the rest")
    return cells


def _grid_cell(name: str, x: float, y: float) -> tuple[int, int]:
    col, row = round(x / STATOR_SIZE), round(y / STATOR_SIZE)
    if abs(x - col * STATOR_SIZE) > PART_TOLERANCE or abs(y - row * STATOR_SIZE) > PART_TOLERANCE:
        raise ConfigError(f"{name}: stators: corner ({x}, {y}) is not on the "
                          f"{STATOR_SIZE:g} mm grid of the part frame")
    return col, row


def _not_connected(cells: list[tuple[int, int]]) -> tuple[int, int] | None:
    """A cell not reachable from the first one across shared edges, if there is one."""
    todo, seen, present = [cells[0]], {cells[0]}, set(cells)
    while todo:
        col, row = todo.pop()
        for cell in ((col + 1, row), (col - 1, row), (col, row + 1), (col, row - 1)):
            if cell in present and cell not in seen:
                seen.add(cell)
                todo.append(cell)
    return next((cell for cell in cells if cell not in seen), None)


def _corner(cell: tuple[int, int]) -> str:
    return f"({cell[0] * STATOR_SIZE:g}, {cell[1] * STATOR_SIZE:g})"


def _stator_box(cell: tuple[int, int]) -> Polygon:
    col, row = cell
    return box(col * STATOR_SIZE, row * STATOR_SIZE, (col + 1) * STATOR_SIZE,
               (row + 1) * STATOR_SIZE)


class _Piece(NamedTuple):
    """Where a straight segment runs over one part: arc lengths lo..hi from its start [mm]."""

    part: Part
    lo: float
    hi: float


class PartLayout:
    """The parts and coordinate systems of one processing unit (§5.2).

    Coordinate systems are unrelated frames, known only by their OIDs (§5.1): nothing moves
    from one to another except on a part that changes position.
    """

    def __init__(self, coordinate_systems: Iterable[int], parts: Iterable[Part]) -> None:
        self.coordinate_systems = tuple(
            _check_oid(oid, "coordinate_systems") for oid in coordinate_systems)
        if not self.coordinate_systems:
            raise ConfigError("coordinate_systems: a layout needs at least one")
        part_list = list(parts)
        for part in part_list:
            if not isinstance(part, Part):
                raise ConfigError(f"parts: must be Part objects, got {type(part).__name__}")
        self.parts = {part.oid: part for part in part_list}
        _check_unique([*self.coordinate_systems, *(part.oid for part in part_list)])
        for part in part_list:
            self._check_positions(part)

    @property
    def is_static(self) -> bool:
        """One coordinate system and no movable part: the only case that allows ReferenceId 0."""
        return len(self.coordinate_systems) == 1 and all(p.is_static for p in self.parts.values())

    def part(self, oid: int) -> Part:
        if oid not in self.parts:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID, f"{_hex(oid)} names no part")
        return self.parts[oid]

    def parts_in(self, coordinate_system: int) -> list[Part]:
        """The parts whose active position lies in a coordinate system, in configuration order."""
        return [part for part in self.parts.values()
                if part.active_position.coordinate_system == coordinate_system]

    def surface(self, coordinate_system: int) -> BaseGeometry:
        """The union of the parts in their active positions in a coordinate system."""
        return shapely.union_all([part.surface() for part in self.parts_in(coordinate_system)])

    def to_coordinate_system(self, reference_id: int, pose: Pose) -> tuple[int, Pose]:
        """A pose given with a ReferenceId, as (coordinate system, pose in it) (§5.3)."""
        if reference_id == 0:
            return self._sole_system(), pose
        if reference_id in self.coordinate_systems:
            return reference_id, pose
        if reference_id not in self.parts:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID, f"ReferenceId {_hex(reference_id)}"
                                  " names no part and no coordinate system (§5.3)")
        position = self.parts[reference_id].active_position
        return position.coordinate_system, position.pose.compose(pose)

    def resolve_target(self, reference_id: int, pose: Pose,
                       coordinate_system: int | None = None) -> tuple[int, Pose]:
        """A command's target as (coordinate system, pose in it), or ``CommandRejected``.

        ``coordinate_system`` is the mover's, when the target must be reachable from it. A
        target given on a part must lie on that part (§6.1.7); every target must lie on a part
        in its active position (PLANAR_PART_NOT_ENABLED).
        """
        system, target = self.to_coordinate_system(reference_id, pose)
        if reference_id in self.parts:
            self._check_on_part(self.parts[reference_id], target, coordinate_system)
        elif coordinate_system is not None and coordinate_system != system:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID, f"coordinate system {_hex(system)}"
                                  f" is not the mover's ({_hex(coordinate_system)}): "
                                  "coordinate systems are not connected (§5.1)")
        if self.part_under(system, target) is None:
            raise self._not_on_active_part(system, target)
        return system, target

    def position_on_current_part(self, coordinate_system: int, pose: Pose,
                                 current_part: int | None = None) -> tuple[int, Pose]:
        """GetPositionOnCurrentPart (§5.2): (part OID, pose in the part frame).

        On an edge shared by two parts ``current_part`` wins, so that a mover belongs to its
        old part until it has crossed; otherwise the first part in configuration order.
        """
        part = self.part_under(coordinate_system, pose, current_part)
        if part is None:
            raise self._not_on_active_part(coordinate_system, pose)
        return part.oid, part.active_position.pose.inverse().compose(pose)

    def path_stays_on_surface(self, coordinate_system: int,
                              path: Sequence[tuple[float, float]]) -> bool:
        """Whether a mover centre following ``path`` (a straight move: two points) stays on the
        active parts, passing from one part to another only across an edge they share (§6.2.3).

        Parts that touch at a corner only, or not at all in their active positions, are not
        connected.
        """
        parts = self.parts_in(coordinate_system)
        here = {part.oid for part in parts if part.covers(*path[0])}
        for start, end in pairwise(path):
            here = _reach(parts, LineString([start, end]), here)
        return bool(here)

    def activate_position(self, part_oid: int, position_index: int) -> None:
        """ActivatePosition (§7.2.2.9.2): move a part. The movers on it are the environment's
        business (it carries them, §6.6.1)."""
        self.check_activation(part_oid, position_index)
        self.parts[part_oid].position_index = position_index

    def check_activation(self, part_oid: int, position_index: int) -> Part:
        """The part, if it may go to ``position_index``; else ``CommandRejected``. Split from
        ``activate_position`` so that the environment can add its own checks in between."""
        part = self.part(part_oid)
        if problem := _index_problem(position_index, len(part.positions)):
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, f"{part.name}: {problem}")
        if part.state in _ERROR_STATES:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{part.name} cannot move in state {part.state.name}")
        if other := self._overlapping(part, position_index):
            raise CommandRejected(ErrorId.PLANAR_COLLISION, f"{part.name} in position "
                                  f"{position_index} would overlap {other.name}")
        return part

    def follow_movers(self, active_coordinate_systems: Collection[int]) -> None:
        """Enable the parts of the systems that hold an active mover and disable the others.

        §6.6: the first mover of a system switches all its parts on, the last one off; parts
        that cannot be enabled (force-disabled, in error) do not stop the others.
        """
        for part in self.parts.values():
            if part.active_position.coordinate_system in active_coordinate_systems:
                with contextlib.suppress(CommandRejected):
                    part.enable()
            else:
                part.disable()

    def update(self) -> None:
        """The environment's Update: part commands take effect (§6.6.1)."""
        for part in self.parts.values():
            part.update()

    def _sole_system(self) -> int:
        if not self.is_static:
            movable = [part.name for part in self.parts.values() if not part.is_static]
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID, "ReferenceId 0 needs one static "
                                  f"coordinate system (§5.3); there are "
                                  f"{len(self.coordinate_systems)} and movable parts {movable}")
        return self.coordinate_systems[0]

    def _check_on_part(self, part: Part, target: Pose, coordinate_system: int | None) -> None:
        system = part.active_position.coordinate_system
        if coordinate_system is not None and coordinate_system != system:
            raise CommandRejected(ErrorId.PLANAR_PART_NOT_ENABLED, f"{part.name} is in position "
                                  f"{part.position_index}, in coordinate system {_hex(system)}, "
                                  f"not in the mover's ({_hex(coordinate_system)})")
        if not part.covers(target.x, target.y):
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID, f"target ({target.x:g}, "
                                  f"{target.y:g}) lies off {part.name}: give the part it lies on"
                                  " or the coordinate system (§6.1.7)")

    def part_under(self, system: int, pose: Pose, preferred: int | None = None) -> Part | None:
        under = [part for part in self.parts_in(system) if part.covers(pose.x, pose.y)]
        return next((part for part in under if part.oid == preferred), under[0] if under else None)

    def _not_on_active_part(self, system: int, pose: Pose) -> CommandRejected:
        where = f"({pose.x:g}, {pose.y:g}) in coordinate system {_hex(system)}"
        for part in self.parts.values():
            for index, position in enumerate(part.positions, start=1):
                if position.coordinate_system == system and part.covers(pose.x, pose.y, index):
                    return CommandRejected(ErrorId.PLANAR_PART_NOT_ENABLED, f"{where} lies on "
                                           f"{part.name} in position {index}, but position "
                                           f"{part.position_index} is active")
        return CommandRejected(ErrorId.PLANAR_PART_NOT_ENABLED, f"{where} lies on no part")

    def _overlapping(self, part: Part, position_index: int) -> Part | None:
        system = part.positions[position_index - 1].coordinate_system
        surface = part.surface(position_index)
        return next((other for other in self.parts_in(system) if other is not part and
                     shapely.intersection(other.surface(), surface).area > PART_TOLERANCE), None)

    def _check_positions(self, part: Part) -> None:
        for index, position in enumerate(part.positions, start=1):
            if position.coordinate_system not in self.coordinate_systems:
                raise ConfigError(f"{part.name}: positions[{index}]: coordinate system "
                                  f"{_hex(position.coordinate_system)} is not configured")
        if other := self._overlapping(part, part.position_index):
            raise ConfigError(f"{part.name}: position_index: overlaps {other.name} (§5.1)")


def _check_unique(oids: list[int]) -> None:
    """A ReferenceId must name one object: parts and coordinate systems share one id space."""
    if twice := next((oid for oid in oids if oids.count(oid) > 1), None):
        raise ConfigError(f"object id {_hex(twice)} is used twice (§5.3)")


def _reach(parts: list[Part], segment: LineString, start: set[int]) -> set[int]:
    """The parts under the segment's end that can be reached from ``start`` along it."""
    if segment.length <= PART_TOLERANCE:
        return start
    pieces = [_Piece(part, lo, hi) for part in parts for lo, hi in _intervals(part, segment)]
    reached = [piece for piece in pieces if piece.part.oid in start and piece.lo <= PART_TOLERANCE]
    todo = list(reached)
    while todo:
        piece = todo.pop()
        for other in pieces:
            if other not in reached and _joined(piece, other, segment):
                reached.append(other)
                todo.append(other)
    return {piece.part.oid for piece in reached if piece.hi >= segment.length - PART_TOLERANCE}


def _intervals(part: Part, segment: LineString) -> list[tuple[float, float]]:
    """The stretches of the segment on the part, as arc lengths from its start."""
    hits = shapely.get_parts(shapely.intersection(part.surface(), segment))
    lengths = [[segment.project(Point(xy)) for xy in hit.coords] for hit in hits
               if not hit.is_empty]
    return [(min(ts), max(ts)) for ts in lengths]


def _joined(piece: _Piece, other: _Piece, segment: LineString) -> bool:
    """Whether the path passes from one piece to the other across a shared edge."""
    lo, hi = max(piece.lo, other.lo), min(piece.hi, other.hi)
    if lo > hi + PART_TOLERANCE:
        return False
    if piece.part is other.part:
        return True
    return shapely.dwithin(_shared_edges(piece.part, other.part),
                           segment.interpolate((lo + hi) / 2), PART_TOLERANCE)


def _shared_edges(part: Part, other: Part) -> BaseGeometry:
    """Where two parts meet along a line; a corner contact (a point) is left out."""
    near = shapely.intersection(part.surface().boundary, other.surface().buffer(PART_TOLERANCE))
    return shapely.union_all([line for line in shapely.get_parts(near)
                              if line.length > 10 * PART_TOLERANCE])
