"""TF5410 §9.3's path tables: the *Preparation blocks, MC_PATH_DATA_REF and its run.

Tc3_McCoordinatedMotion (TF5410 §9.3, shared with TF5420's coordinated-motion group) builds
a path as a table first: MC_MoveLinearAbsolutePreparation, MC_MoveCircularAbsolutePreparation,
MC_BlockerPreparation, MC_DwellTimePreparation and MC_SetCoordinateTransformPreparation each
append one row to an ``MC_PATH_DATA_REF`` (at most 30, §9.3.2.4) and complete in the call;
MC_MovePath then runs the table on an axes group. Example (the centre-point sample of
§9.3.1.2.4)::

    path = MC_PATH_DATA_REF()
    line, arc = MC_MoveLinearAbsolutePreparation(), MC_MoveCircularAbsolutePreparation()
    line(path, position=[200, 0, 0], velocity=3000, buffer_mode=BufferMode.BUFFERED)
    arc(path, circ_mode=McCircMode.CENTER, aux_point=[200, -100, 0],
        end_point=[300, -100, 0], velocity=1000, buffer_mode=BufferMode.BUFFERED)
    move = MC_MovePath(group)
    move(execute=True, path_data=path)

The run (``PathTableRun``) is no second planner: it hands the table's segments to the group
as the Part 4 moves (moves.py), so that geometry, contours and timing are the engine's. It
feeds them up to the next blocker or dwell; the engine blends what the transition modes
ask for and stops where the table ends. There it holds the group in GroupMoving (§9.3.1.2.6)
until MC_ReleaseBlocker, or for the dwell time, and feeds the rest. A blocker released
before the path reaches it is passed without a stop where the segments still blend
(§9.3.1.2.7). A coordinate transform row changes the frame of the rows after it: they are
placed in the MCS through its frame when fed, and the group's PCS is set when the segments
before it are over (ExecutionMode Queued, Part 4 §3.3), so the path does not stop there
(decisions D-213).

Values follow this manual, not Part 4: MC_BUFFER_MODE as TcMC numbers it (§9.4.1.1),
MC_TRANSITION_MODE 16#1000..16#100A, MC_CIRC_MODE 16#2000..16#2002 with Invalid 0,
MC_CIRC_PATHCHOICE 16#3000..16#3003 (§9.3.2.2-§9.3.2.5).
"""

# ruff: noqa: N801, N802 - the manual's names (MC_PATH_DATA_REF.ClearPath)

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.coordinated.frames import CartesianTransform, Frame
from openmotion.coordinated.inputs import CoordSystem, TransitionMode
from openmotion.coordinated.states import ExecutionMode
from openmotion.coordinated.tolerances import DWELL_SLACK
from openmotion.core.checks import is_finite
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE, MC_INVALID, MC_MAXIMUM
from openmotion.geometry.path import Arc, CircMode, PathChoice
from openmotion.kernel.group_blocks import GroupCommand, GroupRead
from openmotion.kernel.handshake import FunctionBlock

if TYPE_CHECKING:
    from openmotion.coordinated.group import AxesGroup

__all__ = [
    "MAX_ROWS", "MC_COORD_REF", "MC_PATH_DATA_REF", "MC_BlockerPreparation",
    "MC_DwellTimePreparation", "MC_GroupReadBlockerStatus",
    "MC_MoveCircularAbsolutePreparation", "MC_MoveLinearAbsolutePreparation",
    "MC_ReleaseBlocker", "MC_SetCoordinateTransformPreparation", "McCircMode",
    "McCircPathChoice", "McTransitionMode", "PathTableRun",
]

MAX_ROWS = 30  #: rows an MC_PATH_DATA_REF holds (§9.3.1.2.3, §9.3.2.4)
ROW_BYTES = 128  #: buffer bytes one row occupies (ours: OccupiedBuffer = rows x this)
DEFAULT_BUFFER = 4096  #: [bytes] the buffer of the manual's samples (ARRAY[1..4096] OF BYTE)
MIN_ACCELERATION = 1.0  #: [mm/s²] Acceleration and Deceleration must be >= 1 (§9.3.1.2.3)
MIN_JERK = 100.0  #: [mm/s³] Jerk must be >= 100 (§9.3.1.2.3)
JERK_MAXIMUM_FACTOR = 100.0  #: MC_MAXIMUM jerk = 100 x MC_DEFAULT (§9.3.1.2.3, V3.2.27)
AUX_POINT_COUNT = 3  #: AuxPoint is always (x, y, z) (§9.3.1.2.4)


class McTransitionMode(IntEnum):
    """MC_TRANSITION_MODE as TF5410 §9.3.2.5 numbers it; only NONE, CORNER_DISTANCE and
    CORNER_DISTANCE_ADVANCED are implemented there, the others are refused."""

    NONE = 0x1000  #: no blending: the path stops at the transition
    START_VELOCITY = 0x1001
    CONSTANT_VELOCITY = 0x1002
    CORNER_DISTANCE = 0x1003  #: one parameter: the radius of the tolerance ball [mm]
    MAX_CORNER_DEVIATION = 0x1004
    CORNER_DISTANCE_ADVANCED = 0x100A  #: two parameters: r_in and r_out [mm]


class McCircMode(IntEnum):
    """MC_CIRC_MODE (§9.3.2.2): the meaning of AuxPoint."""

    INVALID = 0x0000  #: the default: an error wherever a circle needs a mode
    BORDER = 0x2000  #: AuxPoint lies on the arc
    CENTER = 0x2001  #: AuxPoint is the centre
    RADIUS = 0x2002  #: AuxPoint is the plane's normal vector, its length the radius


class McCircPathChoice(IntEnum):
    """MC_CIRC_PATHCHOICE (§9.3.2.3): which arc, for CENTER and RADIUS."""

    CLOCKWISE = 0x3000  #: the arc above 180° (RADIUS: turning left-handed about AuxPoint)
    COUNTERCLOCKWISE = 0x3001  #: the arc below 180°
    SHORT_SEGMENT = 0x3002  #: the smaller arc
    LONG_SEGMENT = 0x3003  #: the larger arc


@dataclass(frozen=True)
class MC_COORD_REF:
    """A coordinate system (§9.3.2.6: the object id of a node connector) and the frame it
    places in the MCS; ``MC_COORD_REF()`` is the MCS itself."""

    frame: Frame = field(default_factory=Frame)
    oid: int = 0  #: the object id, for reference only


# -- rows ----------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Segment:
    """A linear or circular row, as the run hands it to the group."""

    kind: str  #: "linear" or "circular"
    end: tuple[float, ...]  #: target in the table's coordinates, one value per MCS coordinate
    aux: tuple[float, float, float] | None  #: x, y, z handed to the engine (circular)
    circ_mode: CircMode | None
    path_choice: PathChoice | None
    dynamics: tuple[Any, Any, Any, Any]  #: velocity, acceleration, deceleration, jerk
    buffer_mode: BufferMode
    transition: McTransitionMode
    parameter: float  #: the engine's corner distance [mm], 0 without blending
    invoke_id: int


@dataclass(frozen=True)
class Blocker:
    blocker_id: int
    buffer_mode: BufferMode
    invoke_id: int


@dataclass(frozen=True)
class Dwell:
    seconds: float
    buffer_mode: BufferMode
    invoke_id: int


@dataclass(frozen=True)
class CoordTransform:
    coord: MC_COORD_REF
    invoke_id: int = 0


Row = Segment | Blocker | Dwell | CoordTransform


class MC_PATH_DATA_REF:
    """The table of a path (§9.3.2.4): rows appended by the *Preparation blocks, executed by
    MC_MovePath, never reset by it: ``ClearPath()`` empties it (§9.3.2.4.1).

    ``buffer_size`` [bytes] stands for the user buffer it is declared on; each row occupies
    ``ROW_BYTES`` of it, and at most ``MAX_ROWS`` rows fit whatever the buffer.
    """

    def __init__(self, buffer_size: int = DEFAULT_BUFFER) -> None:
        if isinstance(buffer_size, bool) or not isinstance(buffer_size, int) \
                or buffer_size < ROW_BYTES:
            raise ConfigError(f"MC_PATH_DATA_REF: buffer_size must be an integer >= "
                              f"{ROW_BYTES} bytes, got {buffer_size!r}")
        self.buffer_size = buffer_size
        self._rows: list[Row] = []

    @property
    def filled_rows(self) -> int:
        """FilledRows: the number of rows."""
        return len(self._rows)

    @property
    def occupied_buffer(self) -> int:
        """OccupiedBuffer [bytes]."""
        return len(self._rows) * ROW_BYTES

    @property
    def rows(self) -> tuple[Row, ...]:
        return tuple(self._rows)

    def ClearPath(self) -> None:
        """Delete every row (§9.3.2.4.1); a run that started keeps its own copy."""
        self._rows.clear()

    def append(self, row: Row) -> None:
        """Add a row at the end (the path-row FBs call this); a full table refuses it."""
        if len(self._rows) >= MAX_ROWS or self.occupied_buffer + ROW_BYTES > self.buffer_size:
            limit = min(MAX_ROWS, self.buffer_size // ROW_BYTES)
            raise CommandRejected(ErrorId.PATH_TABLE_FULL,
                                  f"the path table is full ({limit} rows; §9.3.2.4): "
                                  "ClearPath() first")
        self._rows.append(row)

    def __repr__(self) -> str:
        return f"<MC_PATH_DATA_REF {len(self._rows)} rows>"


# -- input checks --------------------------------------------------------------------------------


def _member(kind: type[IntEnum], value: Any, name: str, error: ErrorId) -> Any:
    """An enum member from a member, its number or its name (scenario files write names)."""
    if isinstance(value, str) and value in kind.__members__:
        return kind[value]
    try:
        if isinstance(value, bool):
            raise ValueError
        return kind(value)
    except (ValueError, TypeError):
        names = ", ".join(m.name for m in kind)
        raise CommandRejected(error, f"{name}: {value!r} is not one of {names}") from None


def _velocity(value: Any) -> float:
    if value is MC_INVALID or isinstance(value, bool) or not is_finite(value) or value <= 0:
        raise CommandRejected(ErrorId.INVALID_VELOCITY,
                              f"Velocity must be > 0, got {value!r} (§9.3.1.2.3)")
    return float(value)


def _limit(value: Any, name: str, minimum: float, error: ErrorId) -> Any:
    if value is MC_DEFAULT or value is MC_MAXIMUM:
        return value
    if isinstance(value, bool) or not is_finite(value) or value < minimum:
        raise CommandRejected(error, f"{name} must be >= {minimum:g}, MC_DEFAULT or "
                              f"MC_MAXIMUM, got {value!r} (§9.3.1.2.3)")
    return float(value)


def _dynamics(velocity: Any, acceleration: Any, deceleration: Any, jerk: Any
              ) -> tuple[Any, Any, Any, Any]:
    return (_velocity(velocity),
            _limit(acceleration, "Acceleration", MIN_ACCELERATION, ErrorId.INVALID_ACCELERATION),
            _limit(deceleration, "Deceleration", MIN_ACCELERATION, ErrorId.INVALID_DECELERATION),
            _limit(jerk, "Jerk", MIN_JERK, ErrorId.INVALID_JERK))


def _point(value: Any, name: str, size: int | None = None, ignore: bool = False
           ) -> tuple[float, ...]:
    """A vector of finite numbers (MC_IGNORE as 0 where ``ignore``); ``size`` if given."""
    if isinstance(value, str | bytes) or not hasattr(value, "__len__") or len(value) == 0:
        raise CommandRejected(ErrorId.INVALID_POSITION, f"{name}: a list of numbers, got "
                                                        f"{value!r}")
    values = [0.0 if ignore and v is MC_IGNORE else v for v in value]
    if not all(is_finite(v) and not isinstance(v, bool) for v in values):
        raise CommandRejected(ErrorId.INVALID_POSITION, f"{name}: finite numbers only, got "
                                                        f"{value!r}")
    if size is not None and len(values) != size:
        raise CommandRejected(ErrorId.INVALID_POSITION,
                              f"{name}: {len(values)} values, the table's rows have {size}")
    return tuple(float(v) for v in values)


#: §9.3.2.5: the buffer modes each implemented transition mode may be combined with
_ALLOWED: dict[McTransitionMode, tuple[BufferMode, ...]] = {
    McTransitionMode.NONE: (BufferMode.ABORTING, BufferMode.BUFFERED),
    McTransitionMode.CORNER_DISTANCE: (BufferMode.ABORTING, BufferMode.BLENDING_PREVIOUS),
    McTransitionMode.CORNER_DISTANCE_ADVANCED: (BufferMode.ABORTING,
                                                BufferMode.BLENDING_PREVIOUS),
}
_PARAMETERS = {McTransitionMode.CORNER_DISTANCE: 1, McTransitionMode.CORNER_DISTANCE_ADVANCED: 2}


def _buffer_mode(value: Any, table: MC_PATH_DATA_REF,
                 allowed: tuple[BufferMode, ...] = (BufferMode.ABORTING, BufferMode.BUFFERED)
                 ) -> BufferMode:
    mode = _member(BufferMode, value, "BufferMode", ErrorId.INVALID_BUFFER_MODE)
    if mode not in allowed:
        names = ", ".join(m.name for m in allowed)
        raise CommandRejected(ErrorId.INVALID_BUFFER_MODE,
                              f"BufferMode {mode.name} is not permitted here: {names} "
                              "(§9.3.2.5)")
    if mode is BufferMode.ABORTING and table.filled_rows:
        raise CommandRejected(ErrorId.INVALID_BUFFER_MODE,
                              "BufferMode ABORTING is permitted for the first row of a path "
                              "only (§9.3.2.5)")
    return mode


def _transition(table: MC_PATH_DATA_REF, buffer: Any, mode: Any, parameters: Any
                ) -> tuple[BufferMode, McTransitionMode, float]:
    """BufferMode x TransitionMode of §9.3.2.5 and the engine's corner distance (D-213)."""
    transition = _member(McTransitionMode, mode, "TransitionMode", ErrorId.INVALID_MODE)
    if transition not in _ALLOWED:
        raise CommandRejected(ErrorId.INVALID_MODE,
                              f"TransitionMode {transition.name} is not implemented: NONE, "
                              "CORNER_DISTANCE, CORNER_DISTANCE_ADVANCED (§9.3.2.5)")
    buffer_mode = _buffer_mode(buffer, table, _ALLOWED[transition])
    count = _PARAMETERS.get(transition, 0)
    if not count:
        return buffer_mode, transition, 0.0  # "no effect" (§9.3.2.5)
    values = parameters if hasattr(parameters, "__len__") and not isinstance(
        parameters, str | bytes) else [parameters]
    if parameters is None or len(values) < count or not all(
            is_finite(v) and not isinstance(v, bool) and v > 0 for v in values[:count]):
        raise CommandRejected(ErrorId.INVALID_TRANSITION_PARAMETER,
                              f"{transition.name} needs {count} TransitionParameter value(s) "
                              f"> 0 [mm], got {parameters!r} (§9.3.2.5)")
    # the engine's contours are symmetric: CORNER_DISTANCE_ADVANCED leaves the previous
    # segment at r_in and is done within r_out when r_in <= r_out (D-213)
    return buffer_mode, transition, float(min(values[:count]))


def _dimension(table: MC_PATH_DATA_REF) -> int | None:
    """The coordinate count of the table's segments (the first one fixes it)."""
    return next((len(r.end) for r in table.rows if isinstance(r, Segment)), None)


def _last_end(table: MC_PATH_DATA_REF) -> tuple[float, ...] | None:
    """The end of the last segment when no coordinate transform row follows it: the start
    of the next one, in the same coordinates."""
    for row in reversed(table.rows):
        if isinstance(row, CoordTransform):
            return None
        if isinstance(row, Segment):
            return row.end
    return None


def _xyz(values: tuple[float, ...]) -> np.ndarray:
    """x, y, z of a table point (the first three coordinates; fewer are padded with 0)."""
    point = np.zeros(3)
    point[: min(3, len(values))] = values[:3]
    return point


def _arc_choice(circ: McCircMode, choice: McCircPathChoice, aux: np.ndarray
                ) -> tuple[CircMode, PathChoice, np.ndarray]:
    """TF5410's PathChoice in the engine's terms (geometry/path.py: COUNTERCLOCKWISE = the
    short arc, RADIUS turning right-handed about the normal). §9.3.2.2-§9.3.2.3: CENTER:
    CLOCKWISE and LONG_SEGMENT take the long arc; RADIUS: COUNTERCLOCKWISE and SHORT_SEGMENT
    the short arc right-handed about AuxPoint, LONG_SEGMENT the long one, CLOCKWISE the long
    arc left-handed (right-handed about -AuxPoint)."""
    long = choice in (McCircPathChoice.CLOCKWISE, McCircPathChoice.LONG_SEGMENT)
    engine_choice = PathChoice.CLOCKWISE if long else PathChoice.COUNTERCLOCKWISE
    if circ is McCircMode.RADIUS and choice is McCircPathChoice.CLOCKWISE:
        aux = -aux
    return CircMode(int(circ)), engine_choice, aux


# -- the Preparation blocks ----------------------------------------------------------------------


class _Preparation(FunctionBlock):
    """Appends one row to ``path_data`` in the call (no Execute): ``error`` / ``error_id``
    tell whether it went in; a refused row leaves the table as it was."""

    INPUTS: ClassVar[dict[str, Any]] = {"path_data": None, "invoke_id": 0}

    def __init__(self, path_data: MC_PATH_DATA_REF | None = None, /, **inputs: Any) -> None:
        super().__init__(None, **inputs)
        if path_data is not None:
            self.path_data = path_data

    def __call__(self, path_data: MC_PATH_DATA_REF | None = None, /, **inputs: Any) -> None:
        if path_data is not None:
            inputs["path_data"] = path_data
        if inputs:
            self._set_inputs(inputs)
        table = self.path_data
        if not isinstance(table, MC_PATH_DATA_REF):
            raise TypeError(f"{type(self).__name__} needs a path table: call it as "
                            "fb(MC_PATH_DATA_REF(), ...)")
        self._reset_outputs()
        try:
            table.append(self._row(table))
        except CommandRejected as rejected:
            self.error, self.error_id, self.message = True, rejected.error_id, rejected.message

    def _invoke_id(self) -> int:
        value = self.invoke_id
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise CommandRejected(ErrorId.INVALID_MODE,
                                  f"InvokeId must be a UDINT (an integer >= 0), got {value!r}")
        return value

    def _row(self, table: MC_PATH_DATA_REF) -> Row:
        raise NotImplementedError


class _MovePreparation(_Preparation):
    INPUTS: ClassVar[dict[str, Any]] = {
        "velocity": MC_INVALID, "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT,
        "jerk": MC_DEFAULT, "buffer_mode": BufferMode.ABORTING,
        "transition_mode": McTransitionMode.NONE, "transition_parameter": None,
    }

    def _common(self, table: MC_PATH_DATA_REF) -> dict[str, Any]:
        dynamics = _dynamics(self.velocity, self.acceleration, self.deceleration, self.jerk)
        buffer_mode, transition, parameter = _transition(
            table, self.buffer_mode, self.transition_mode, self.transition_parameter)
        return {"dynamics": dynamics, "buffer_mode": buffer_mode, "transition": transition,
                "parameter": parameter, "invoke_id": self._invoke_id()}


class MC_MoveLinearAbsolutePreparation(_MovePreparation):
    """Append a straight line to ``position`` (§9.3.1.2.3): one value per coordinate of the
    group's MCS, in the coordinates in force at that row. ``velocity`` > 0 (no default),
    ``acceleration`` / ``deceleration`` >= 1 and ``jerk`` >= 100 or MC_DEFAULT / MC_MAXIMUM;
    ``buffer_mode`` and ``transition_mode`` as §9.3.2.5 combines them. Outputs: error,
    error_id (PATH_TABLE_FULL, INVALID_POSITION, INVALID_VELOCITY ... INVALID_JERK,
    INVALID_BUFFER_MODE, INVALID_MODE, INVALID_TRANSITION_PARAMETER)."""

    INPUTS: ClassVar[dict[str, Any]] = {"position": None}

    def _row(self, table: MC_PATH_DATA_REF) -> Row:
        end = _point(self.position, "Position", _dimension(table))
        return Segment("linear", end, None, None, None, **self._common(table))


class MC_MoveCircularAbsolutePreparation(_MovePreparation):
    """Append an arc to ``end_point`` (§9.3.1.2.4). ``circ_mode`` (McCircMode, no default)
    says what ``aux_point`` (always x, y, z; MC_IGNORE reads 0) is; ``path_choice`` picks
    the arc (McCircPathChoice). Where the row before is a segment in the same coordinates
    the circle is checked here (INVALID_PATH_GEOMETRY), else when MC_MovePath starts it.
    Other inputs and errors as MC_MoveLinearAbsolutePreparation."""

    INPUTS: ClassVar[dict[str, Any]] = {"circ_mode": McCircMode.INVALID, "aux_point": None,
                                        "end_point": None,
                                        "path_choice": McCircPathChoice.COUNTERCLOCKWISE}

    def _row(self, table: MC_PATH_DATA_REF) -> Row:
        circ = _member(McCircMode, self.circ_mode, "CircMode", ErrorId.INVALID_MODE)
        if circ is McCircMode.INVALID:
            raise CommandRejected(ErrorId.INVALID_MODE,
                                  "CircMode INVALID: BORDER, CENTER or RADIUS (§9.3.2.2)")
        choice = _member(McCircPathChoice, self.path_choice, "PathChoice", ErrorId.INVALID_MODE)
        aux = _point(self.aux_point, "AuxPoint", AUX_POINT_COUNT, ignore=True)
        end = _point(self.end_point, "EndPoint", _dimension(table))
        engine_circ, engine_choice, engine_aux = _arc_choice(circ, choice, np.array(aux))
        start = _last_end(table)
        if start is not None:  # the circle exists, else INVALID_PATH_GEOMETRY
            Arc.from_circ_mode(engine_circ, _xyz(start), engine_aux, _xyz(end), engine_choice)
        common = self._common(table)
        return Segment("circular", end, tuple(float(v) for v in engine_aux), engine_circ,
                       engine_choice, **common)


class MC_BlockerPreparation(_Preparation):
    """Append a blocker (§9.3.1.2.6): the path stops there until MC_ReleaseBlocker with the
    same ``blocker_id`` (an integer > 0). ``buffer_mode`` Buffered or Aborting (the first
    row only). Errors: INVALID_BLOCKER_ID, INVALID_BUFFER_MODE, PATH_TABLE_FULL."""

    INPUTS: ClassVar[dict[str, Any]] = {"blocker_id": 0, "buffer_mode": BufferMode.BUFFERED}

    def _row(self, table: MC_PATH_DATA_REF) -> Row:
        blocker = _blocker_id(self.blocker_id)
        return Blocker(blocker, _buffer_mode(self.buffer_mode, table), self._invoke_id())


class MC_DwellTimePreparation(_Preparation):
    """Append a standstill of ``dwell_time`` seconds (§9.3.1.2.9; >= 0, and 0 still stops
    the path exactly). ``buffer_mode`` Buffered or Aborting (the first row only). Errors:
    INVALID_DWELL_TIME, INVALID_BUFFER_MODE, PATH_TABLE_FULL."""

    INPUTS: ClassVar[dict[str, Any]] = {"dwell_time": 0.0, "buffer_mode": BufferMode.BUFFERED}

    def _row(self, table: MC_PATH_DATA_REF) -> Row:
        value = self.dwell_time
        if isinstance(value, bool) or not is_finite(value) or value < 0:
            raise CommandRejected(ErrorId.INVALID_DWELL_TIME,
                                  f"DwellTime must be >= 0 s, got {value!r} (§9.3.1.2.9)")
        return Dwell(float(value), _buffer_mode(self.buffer_mode, table), self._invoke_id())


class MC_SetCoordinateTransformPreparation(_Preparation):
    """Append a change of coordinate system (§9.3.1.1.10): the rows after it are given in
    ``coord_transform`` (an MC_COORD_REF, a Frame, or six numbers trans_x ... rot_z).
    Errors: INVALID_POSITION (no frame), PATH_TABLE_FULL."""

    INPUTS: ClassVar[dict[str, Any]] = {"coord_transform": None}

    def _row(self, table: MC_PATH_DATA_REF) -> Row:
        return CoordTransform(coord_ref(self.coord_transform), self._invoke_id())


def coord_ref(value: Any) -> MC_COORD_REF:
    """An MC_COORD_REF from itself, a Frame or six numbers."""
    if isinstance(value, MC_COORD_REF):
        return value
    if isinstance(value, Frame):
        return MC_COORD_REF(value)
    try:
        if isinstance(value, str | bytes) or len(value) != len(CartesianTransform._fields) \
                or any(isinstance(v, bool) or not is_finite(v) for v in value):
            raise TypeError
        return MC_COORD_REF(Frame.from_cartesian(*CartesianTransform(*value)))
    except (TypeError, ValueError):
        raise CommandRejected(ErrorId.INVALID_POSITION,
                              "CoordTransform: an MC_COORD_REF, a Frame or six numbers "
                              f"(trans_x, trans_y, trans_z, rot_x, rot_y, rot_z), got "
                              f"{value!r}") from None


def _blocker_id(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value <= 0 \
            or value > 0xFFFFFFFF:
        raise CommandRejected(ErrorId.INVALID_BLOCKER_ID,
                              f"BlockerId must be a UDINT > 0, got {value!r} (§9.3.1.2.6)")
    return int(value)


# -- the run -------------------------------------------------------------------------------------


class PathTableRun:
    """MC_MovePath over one table: feeds its rows to the group, holds at blockers and dwells.

    The group calls ``step`` every cycle right after its path motion advanced, and ``end``
    when a halt, stop, disable, error or an Aborting motion ends the path.
    """

    def __init__(self, group: AxesGroup, rows: tuple[Row, ...], command: Command) -> None:
        self.group = group
        self.rows = rows
        self.command = command
        self.index = 0  #: the next row to feed
        self.fed: list[Command] = []  #: the segment commands handed to the group
        self.transforms: list[Command] = []  #: queued MC_SetCoordinateTransform commands
        self.frame: Frame | None = None  #: the frame of the rows fed next (None: the PCS)
        self.released: list[int] = []  #: blockers released before the path reached them
        self.blocked_at: Blocker | None = None  #: the blocker the path stands at
        self.dwell_until: float | None = None
        self.deferred: list[tuple[Command, Any]] = []  #: moves issued behind the table

    # -- reading -------------------------------------------------------------------------------

    def blocker_status(self) -> tuple[bool, int]:
        blocker = self.blocked_at
        return (blocker is not None, 0 if blocker is None else blocker.blocker_id)

    # -- control -------------------------------------------------------------------------------

    def start(self) -> None:
        self._feed()

    def release(self, blocker_id: int) -> None:
        """MC_ReleaseBlocker: the blocker the path stands at or the next one with this id
        ahead of it; ``CommandRejected(UNKNOWN_BLOCKER)`` if there is none."""
        if self.blocked_at is not None and self.blocked_at.blocker_id == blocker_id:
            self.blocked_at = None
            self.index += 1
            self._feed()
            return
        ahead = [r.blocker_id for r in self.rows[self.index:] if isinstance(r, Blocker)]
        if ahead.count(blocker_id) <= self.released.count(blocker_id):
            raise CommandRejected(ErrorId.UNKNOWN_BLOCKER,
                                  f"no blocker {blocker_id} ahead on the running path "
                                  "(§9.3.1.2.7)")
        self.released.append(blocker_id)
        if self._at_unreached_blocker(blocker_id):
            self._feed()  # the segments after it join the path while it still runs

    def defer(self, command: Command, start: Any) -> None:
        """A motion issued with a BufferMode other than Aborting while the table runs
        starts when the table is over (D-213)."""
        self.deferred.append((command, start))

    def end(self, reason: str, error: tuple[ErrorId, str] | None = None) -> None:
        """The path ends early: CommandAborted (or Error), what waits is aborted too."""
        now = self.group.runtime.now
        for transform in self.transforms:
            transform.end(CommandStatus.ABORTED, now, message=reason)
        if error is None:
            self.command.end(CommandStatus.ABORTED, now, message=reason)
        else:
            self.command.end(CommandStatus.ERROR, now, error[0], error[1])
        self.blocked_at = None
        for command, _ in self.deferred:
            command.end(CommandStatus.ABORTED, now, message=reason)
        self.deferred = []

    # -- the cycle -----------------------------------------------------------------------------

    def step(self, now: float) -> None:
        if not self.command.busy:
            return
        failed = next((c for c in self.fed if c.error or c.aborted), None)
        if failed is not None:
            error = (failed.error_id, failed.message) if failed.error else None
            self.end(failed.message or "a segment of the path was aborted", error)
            return
        if any(c.active for c in self.fed):
            self.command.status = CommandStatus.ACTIVE
        at_rest = all(c.finished for c in self.fed) and self.group.motion.finished
        row = self.rows[self.index] if self.index < len(self.rows) else None
        if isinstance(row, Blocker) and at_rest and self.blocked_at is None:
            self.blocked_at = row
            self.command.status = CommandStatus.ACTIVE
        elif isinstance(row, Dwell) and at_rest:
            self.command.status = CommandStatus.ACTIVE
            if self.dwell_until is None:
                self.dwell_until = now + row.seconds
            if now >= self.dwell_until - DWELL_SLACK:
                self.dwell_until = None
                self.index += 1
                self._feed()
        if self.index >= len(self.rows) and at_rest and all(
                c.finished for c in self.transforms) and all(c.done for c in self.fed):
            self.command.end(CommandStatus.DONE, now)
            deferred, self.deferred = self.deferred, []
            for command, start in deferred:
                if command.busy:
                    start()

    def _at_unreached_blocker(self, blocker_id: int) -> bool:
        row = self.rows[self.index] if self.index < len(self.rows) else None
        return isinstance(row, Blocker) and row.blocker_id == blocker_id

    def _feed(self) -> None:
        """Hand the rows to the group up to the next blocker or dwell (or the end)."""
        group = self.group
        while self.index < len(self.rows):
            row = self.rows[self.index]
            if isinstance(row, Blocker):
                if row.blocker_id in self.released:
                    self.released.remove(row.blocker_id)
                    self.index += 1
                    continue
                return
            if isinstance(row, Dwell):
                return
            if isinstance(row, CoordTransform):
                frame = row.coord.frame
                self.frame = frame
                self.transforms.append(group.set_coordinate_transform(
                    frame, ExecutionMode.QUEUED))
                self.index += 1
                continue
            command = self._submit(row)
            self.fed.append(command)
            self.index += 1
            if command.error:
                return

    def _submit(self, row: Segment) -> Command:
        group = self.group
        spaces = group.spaces
        values = np.array(row.end)
        aux = None if row.aux is None else np.array(row.aux)
        coord = CoordSystem.PCS
        if self.frame is not None:  # placed through the row's frame (D-213)
            coord = CoordSystem.MCS
            values = spaces.with_xyz(values, self.frame.apply(spaces.xyz(values)))
            if aux is not None:
                aux = self.frame.rotate(aux) if row.circ_mode is CircMode.RADIUS \
                    else self.frame.apply(aux)
        v, a, d, j = row.dynamics
        if j is MC_MAXIMUM:
            j = JERK_MAXIMUM_FACTOR * group.dynamics.jerk
        mode = TransitionMode.TM_NONE if row.transition is McTransitionMode.NONE or \
            row.buffer_mode is BufferMode.ABORTING else TransitionMode.TM_CORNER_DISTANCE
        parameter = row.parameter if mode is TransitionMode.TM_CORNER_DISTANCE else None
        common: dict[str, Any] = {
            "velocity": v, "acceleration": a, "deceleration": d, "jerk": j,
            "coord_system": coord, "buffer_mode": row.buffer_mode,
            "transition_mode": mode, "transition_parameter": parameter}
        with group.feeding_table():
            if row.kind == "linear":
                return group.move_linear_absolute(values, **common)
            aux_point = spaces.with_xyz(np.zeros(spaces.size), aux)
            return group.move_circular_absolute(aux_point, values, row.circ_mode,
                                                row.path_choice, **common)


def check_rows(group: AxesGroup, rows: tuple[Row, ...]) -> None:
    """What MC_MovePath checks before anything moves: a table with rows, of the group's
    coordinate count."""
    if not rows:
        raise CommandRejected(ErrorId.PATH_TABLE_EMPTY,
                              "the path table has no rows: prepare the path first (§9.3.1.2.5)")
    size = group.spaces.size
    for number, row in enumerate(rows, 1):
        if isinstance(row, Segment) and len(row.end) != size:
            raise CommandRejected(ErrorId.INVALID_POSITION,
                                  f"row {number}: {len(row.end)} coordinates, the group's MCS "
                                  f"has {size} (§9.3.1.2.3)")


# -- the blocks on the group ---------------------------------------------------------------------


class MC_ReleaseBlocker(GroupCommand):
    """Release blocker ``blocker_id`` (§9.3.1.2.7): the one the path stands at, or the next
    one ahead (then the path passes it, blending where it still can). Done in the call.
    Errors: INVALID_BLOCKER_ID, UNKNOWN_BLOCKER (no running table has it ahead)."""

    INPUTS: ClassVar[dict[str, Any]] = {"blocker_id": 0}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _part4(group).release_blocker(self.blocker_id)


class MC_GroupReadBlockerStatus(GroupRead):
    """While ``enable``: ``blocked`` (the path stands at a blocker) and its ``blocker_id``
    (§9.3.1.2.8). ``valid`` only for a Part 4 AxesGroup: a CA group has no blockers."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.blocked = False
        self.blocker_id = 0

    def _enabled(self, group: Any, rising: bool) -> None:  # type: ignore[override]
        from openmotion.coordinated.group import AxesGroup
        if not isinstance(group, AxesGroup):
            self._reset_outputs()
            return
        super()._enabled(group, rising)

    def _read(self, group: Any) -> None:
        self.blocked, self.blocker_id = group.blocker_status()


def _part4(group: Any) -> AxesGroup:
    from openmotion.coordinated.group import AxesGroup
    if not isinstance(group, AxesGroup):
        raise TypeError("this block needs a Part 4 AxesGroup: call it as fb(group, ...)")
    return group
