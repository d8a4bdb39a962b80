"""Options, dynamic constraints, status structures and mover parameters (TF5430 §7.2.1.2,
§6.1.1, §6.1.9).

* The ``ST_...Options`` structs keep the manual's field order and defaults. Passing ``None``
  instead of an options struct means all defaults, as PLC 0 does (§6.1.9). ``check()`` raises
  ``CommandRejected`` for a value the manual forbids, and the owner turns that into the
  command's feedback error: bad values are never exceptions out of a cycle.
* A constraint limits the dynamics of the command it is passed to. ``None`` (PLC 0) means the
  mover's default dynamics (§6.1.9).
* The ``CDT_MCTOPLC_...`` structs are frozen snapshots that an object publishes in
  ``update()``. §7 names only the mover's reference tree; the sub-struct fields come from the
  manual's watch windows (docs/decisions.md).
* ``PlanarMoverParameters`` holds the mover's init parameters (§6.1.1). Where the manual
  prints "...", the values are ours (docs/decisions.md).
"""

# ruff: noqa: N801 - the manual's structure names

from __future__ import annotations

import enum
import math
import typing
from abc import ABC, abstractmethod
from contextlib import suppress
from dataclasses import dataclass, fields
from functools import cache, cached_property

from openmotion.core.checks import (
    finite_number,
    flag,
    is_finite,
    is_number,
    limit_number,
    non_negative_number,
    positive_number,
)
from openmotion.core.enums import convert_enum
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE, InputValue
from openmotion.planar.enums import (
    CoordinateMode,
    ExternalSetPositionMode,
    ModuloDirection,
    MoverCommandMode,
    PlanarState,
    SyncDirections,
    TrackOperationMode,
)
from openmotion.planar.rotation import CWindows
from openmotion.trajectory.plan import Limits

_INVALID = ErrorId.PLANAR_INVALID_INPUT
_UDINT_MAX = 0xFFFFFFFF


def _check_non_negative(name: str, value: float) -> None:
    if not (is_finite(value) and value >= 0.0):
        raise CommandRejected(_INVALID, f"{name}: must be a finite number >= 0, got {value!r}")


def _check_udint(name: str, value: int) -> None:
    if not (isinstance(value, int) and not isinstance(value, bool)
            and 0 <= value <= _UDINT_MAX):
        raise CommandRejected(_INVALID, f"{name}: must be a UDINT (0..2**32-1), got {value!r}")


def _check_modulo(prefix: str, direction: ModuloDirection, additional_turns: int = 0,
                  tolerance: float = 0.0) -> None:
    """The modulo rules of §6.1.9: turns only with Positive/Negative, no tolerance with
    NonModulo."""
    try:
        if isinstance(direction, bool):
            raise ValueError(direction)
        direction = convert_enum(ModuloDirection, direction)
    except (ValueError, TypeError):
        raise CommandRejected(_INVALID,
                              f"{prefix}direction: not an MC_DIRECTION: {direction!r}") from None
    _check_udint(f"{prefix}additional_turns", additional_turns)
    _check_non_negative(f"{prefix}modulo_tolerance", tolerance)
    if additional_turns and direction not in (ModuloDirection.POSITIVE, ModuloDirection.NEGATIVE):
        raise CommandRejected(ErrorId.INVALID_MODULO_OPTIONS,
                              f"{prefix}additional_turns: {additional_turns} needs direction "
                              f"Positive or Negative, not {direction.name} (§6.1.9)")
    if tolerance and direction is ModuloDirection.NON_MODULO:
        raise CommandRejected(ErrorId.INVALID_MODULO_OPTIONS,
                              f"{prefix}modulo tolerance: must be 0 with NonModulo (§6.1.9)")


# -- command options (§7.2.1.2.4-14) -----------------------------------------------------------


@dataclass(frozen=True)
class _Options:
    def __post_init__(self) -> None:
        """An enumeration field given as its number (a PLC passes MC_DIRECTION and the like
        as UINT) holds the member, so that the engine's comparisons see it; a number that
        names no member stays as given and ``check`` refuses it."""
        for name, kind in _enum_fields(type(self)):
            value = getattr(self, name)
            if isinstance(value, int) and not isinstance(value, bool | kind):
                with suppress(ValueError):  # no such member: ``check`` refuses it
                    object.__setattr__(self, name, convert_enum(kind, value))

    def check(self) -> None:
        """Raise ``CommandRejected`` for a value the manual forbids (nothing to check here)."""


@cache
def _enum_fields(cls: type) -> tuple[tuple[str, type[enum.Enum]], ...]:
    """The fields of an options class whose declared type is an enumeration."""
    hints = typing.get_type_hints(cls)
    return tuple((f.name, hints[f.name]) for f in fields(cls)
                 if isinstance(hints.get(f.name), type) and issubclass(hints[f.name], enum.Enum))


@dataclass(frozen=True)
class ST_MoveToPositionOptions(_Options):
    """Options of MoveToPosition (§7.2.1.2.13): also reach the target's C (§6.1.9)."""

    use_orientation: bool = True


@dataclass(frozen=True)
class ST_JoinTrackOptions(_Options):
    """Options of JoinTrack (§7.2.1.2.9): also take the orientation at the end of the join."""

    use_orientation: bool = True


@dataclass(frozen=True)
class ST_LeaveTrackOptions(_Options):
    """Options of LeaveTrack (§7.2.1.2.10): also reach the target's C."""

    use_orientation: bool = True


@dataclass(frozen=True)
class ST_MoveCOptions(_Options):
    """Options of MoveC (§7.2.1.2.11). Turns count in the mover's C modulus (§6.1.9)."""

    additional_turns: int = 0  #: UDINT; the sign comes from ``direction``
    direction: ModuloDirection = ModuloDirection.NON_MODULO

    def check(self) -> None:
        _check_modulo("", self.direction, self.additional_turns)


@dataclass(frozen=True)
class ST_AdoptTrackOrientationOptions(_Options):
    """Options of AdoptTrackOrientation (§7.2.1.2.4); unlike MoveC it defaults to ShortestWay."""

    additional_turns: int = 0  #: UDINT; the sign comes from ``direction``
    direction: ModuloDirection = ModuloDirection.SHORTEST_WAY

    def check(self) -> None:
        _check_modulo("", self.direction, self.additional_turns)


@dataclass(frozen=True)
class ST_MoveOnTrackOptions(_Options):
    """Options of MoveOnTrack (§7.2.1.2.12). The gap is the arc-length distance, centre to
    centre, to the mover ahead; it holds until the next track command (§6.1.9)."""

    gap: float = 200.0  #: [mm]
    direction: ModuloDirection = ModuloDirection.NON_MODULO
    additional_turns: int = 0  #: extra laps of a closed track
    modulo_tolerance: float = 0.0  #: [mm]

    def check(self) -> None:
        _check_non_negative("gap", self.gap)
        _check_modulo("", self.direction, self.additional_turns, self.modulo_tolerance)


@dataclass(frozen=True)
class ST_GearInPosOnTrackOptions(_Options):
    """Options of GearInPosOnTrack (§7.2.1.2.7). The sync-position modulo options read as
    MoveC's, with the track length as modulus (§6.1.9); a closed-loop sync track only
    (gearing.py, D-148)."""

    gap: float = 200.0  #: [mm]
    in_sync_tolerance_distance: float = 0.0  #: |slave - master| that still counts as inSync [mm]
    direction_slave_sync_position: ModuloDirection = ModuloDirection.NON_MODULO
    modulo_tolerance_slave_sync_position: float = 0.0  #: [mm]
    allowed_slave_sync_directions: SyncDirections = SyncDirections.POSITIVE

    def check(self) -> None:
        _check_non_negative("gap", self.gap)
        _check_non_negative("in_sync_tolerance_distance", self.in_sync_tolerance_distance)
        _check_modulo("slave sync position ", self.direction_slave_sync_position,
                      tolerance=self.modulo_tolerance_slave_sync_position)
        if isinstance(self.allowed_slave_sync_directions, bool) or \
                self.allowed_slave_sync_directions not in set(SyncDirections):
            raise CommandRejected(_INVALID, "allowed_slave_sync_directions: not an "
                                  f"MC_SYNC_DIRECTIONS: {self.allowed_slave_sync_directions!r}")


@dataclass(frozen=True)
class ST_GearInPosOnTrackWithMasterMoverOptions(_Options):
    """Options of GearInPosOnTrackWithMasterMover (§7.2.1.2.8), in the manual's field order.
    ``follow_mover``: after the master passes its sync position the slave takes the master's
    way through the network; the trail then only leads the slave there."""

    gap: float = 200.0  #: [mm]
    in_sync_tolerance_distance: float = 0.0  #: [mm]
    direction_slave_sync_position: ModuloDirection = ModuloDirection.NON_MODULO
    modulo_tolerance_slave_sync_position: float = 0.0  #: [mm]
    direction_master_sync_position: ModuloDirection = ModuloDirection.NON_MODULO
    modulo_tolerance_master_sync_position: float = 0.0  #: [mm]
    allowed_slave_sync_directions: SyncDirections = SyncDirections.POSITIVE
    follow_mover: bool = False

    def check(self) -> None:
        ST_GearInPosOnTrackOptions(
            self.gap, self.in_sync_tolerance_distance, self.direction_slave_sync_position,
            self.modulo_tolerance_slave_sync_position, self.allowed_slave_sync_directions,
        ).check()
        _check_modulo("master sync position ", self.direction_master_sync_position,
                      tolerance=self.modulo_tolerance_master_sync_position)
        if not isinstance(self.follow_mover, bool):
            raise CommandRejected(_INVALID, f"follow_mover: must be a BOOL, got "
                                  f"{self.follow_mover!r}")


@dataclass(frozen=True)
class ST_ExternalSetpointGenerationOptions(_Options):
    """Options of StartExternalSetpointGeneration (§7.2.1.2.6). Absolute runs alone; Relative
    adds the setpoints as offsets to any other command (§4.2)."""

    mode: ExternalSetPositionMode = ExternalSetPositionMode.ABSOLUTE

    def check(self) -> None:
        if self.mode not in (ExternalSetPositionMode.ABSOLUTE, ExternalSetPositionMode.RELATIVE):
            raise CommandRejected(_INVALID, f"mode: Absolute or Relative, got {self.mode!r}")


@dataclass(frozen=True)
class _TrackConnectionOptions(_Options):
    this_track_part_position_index: int = 0  #: 0: any position of this track's part
    other_track_part_position_index: int = 0  #: 0: any position of the other track's part
    link_only_in_specified_part_positions: bool = False

    def check(self) -> None:
        _check_udint("this_track_part_position_index", self.this_track_part_position_index)
        _check_udint("other_track_part_position_index", self.other_track_part_position_index)


@dataclass(frozen=True)
class ST_StartFromTrackAdvancedOptions(_TrackConnectionOptions):
    """Options of StartFromTrackAdvanced (§7.2.1.2.14). All defaults behave like plain
    StartFromTrack (§6.2.13)."""


@dataclass(frozen=True)
class ST_EndAtTrackAdvancedOptions(_TrackConnectionOptions):
    """Options of EndAtTrackAdvanced (§7.2.1.2.5); fields as StartFromTrackAdvanced's."""


# -- dynamic constraints (§6.1.9; the types come from Tc3_Physics) -------------------------------


class IPlcDynamicConstraint(ABC):
    """What every constraint argument accepts. One constraint per command limits the dynamics
    along the direction of motion; values above the mover's maxima are clipped with a warning
    and the command still runs (§6.1.9)."""

    @abstractmethod
    def resolve(self, default: Limits, maximum: Limits, warnings: list[str]) -> Limits:
        """The limits the command runs with, or ``CommandRejected`` for an invalid value."""


@dataclass(frozen=True)
class DynamicConstraint_PathXY(IPlcDynamicConstraint):
    """Path limits V, A, D, J (§7.2.2.8.4). ``MC_DEFAULT`` takes the mover's default dynamics
    and ``MC_IGNORE`` sets no limit (up to the mover's maximum). Units are those of the
    coordinate the command moves: mm/s... for XY, Z and tracks, °/s... for A, B, C."""

    velocity: InputValue = MC_DEFAULT  #: V
    acceleration: InputValue = MC_DEFAULT  #: A
    deceleration: InputValue = MC_DEFAULT  #: D
    jerk: InputValue = MC_DEFAULT  #: J

    def resolve(self, default: Limits, maximum: Limits, warnings: list[str]) -> Limits:
        return Limits(*(self._value(f.name, getattr(default, f.name), getattr(maximum, f.name),
                                    warnings) for f in fields(self)))

    def _value(self, name: str, default: float, maximum: float, warnings: list[str]) -> float:
        value = getattr(self, name)
        if value is MC_DEFAULT:
            return default
        if value is MC_IGNORE:
            return maximum
        if not (is_finite(value) and value > 0.0):
            raise CommandRejected(_INVALID, f"constraint {name}: must be a finite number > 0, "
                                  f"MC_DEFAULT or MC_IGNORE, got {value!r}")
        if value > maximum:
            warnings.append(f"constraint {name} {value:g} clipped to the mover maximum "
                            f"{maximum:g} (§6.1.9)")
            return maximum
        return float(value)


def command_dynamics(constraint: IPlcDynamicConstraint | None, default: Limits,
                     maximum: Limits, warnings: list[str]) -> Limits:
    """The limits of one command: the mover's default when no constraint is given (PLC 0)."""
    return default if constraint is None else constraint.resolve(default, maximum, warnings)


# -- cyclic interface (§7.2.1.2.1-2 and the watch windows of §6) ---------------------------------


@dataclass(frozen=True, slots=True)
class MoverVector:
    """Six coordinates of a mover (Tc3_Physics MoverVector): x, y, z [mm]; a, b, c [°]."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0


@dataclass(frozen=True, slots=True)
class MoverBusy:
    """MoverBusy: the two members the examples poll (§6.2.7, §6.5)."""

    busy_mover: bool = False  #: any command of the mover runs
    busy_xyc: bool = False  #: a command moves x, y or c


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_MOVER_STD:
    """Standard data of a mover (§6.1.8 watch window)."""

    mover_oid: int = 0
    group_oid: int = 0  #: 0: in no group
    state: PlanarState = PlanarState.DISABLED
    command_mode: MoverCommandMode = MoverCommandMode.FREE_MOVEMENT
    busy: MoverBusy = MoverBusy()
    error_code: int = 0  #: HRESULT


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_MOVER_SET:
    """Setpoints of a mover (§6.7.1 watch window), in the coordinate system it is in."""

    set_pos: MoverVector = MoverVector()
    set_velo: MoverVector = MoverVector()
    set_acc: MoverVector = MoverVector()
    dc_time_stamp: int = 0  #: distributed-clock time [ns]
    physical_area_id: int = 0  #: the coordinate system's OID; 0 without parts


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_MOVER_ACT:
    """Actual values of a mover. The manual never opens this struct; ours mirrors SET."""

    act_pos: MoverVector = MoverVector()
    act_velo: MoverVector = MoverVector()
    act_acc: MoverVector = MoverVector()
    dc_time_stamp: int = 0  #: [ns]
    physical_area_id: int = 0


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_MOVER_COORDMODE:
    """Which coordinates a track drives (Dependent) and which are commanded alone (§6.2.7)."""

    xy_coordinate_mode: CoordinateMode = CoordinateMode.INDEPENDENT
    z_coordinate_mode: CoordinateMode = CoordinateMode.INDEPENDENT
    a_coordinate_mode: CoordinateMode = CoordinateMode.INDEPENDENT
    b_coordinate_mode: CoordinateMode = CoordinateMode.INDEPENDENT
    c_coordinate_mode: CoordinateMode = CoordinateMode.INDEPENDENT


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_MOVER_TRACK:
    """Setpoints on the current track (SETONTRACK, §6.2.8 watch window); arc length [mm]."""

    set_pos: float = 0.0
    set_velo: float = 0.0
    set_acc: float = 0.0
    set_jerk: float = 0.0
    track_oid: int = 0  #: the track the mover is on; 0: none


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_MOVER:
    """MC to PLC data of a mover (§7.2.1.2.1): STD, SET, ACT, COORDMODE, SETONTRACK."""

    std: CDT_MCTOPLC_PLANAR_MOVER_STD = CDT_MCTOPLC_PLANAR_MOVER_STD()
    set: CDT_MCTOPLC_PLANAR_MOVER_SET = CDT_MCTOPLC_PLANAR_MOVER_SET()
    act: CDT_MCTOPLC_PLANAR_MOVER_ACT = CDT_MCTOPLC_PLANAR_MOVER_ACT()
    coord_mode: CDT_MCTOPLC_PLANAR_MOVER_COORDMODE = CDT_MCTOPLC_PLANAR_MOVER_COORDMODE()
    set_on_track: CDT_MCTOPLC_PLANAR_MOVER_TRACK = CDT_MCTOPLC_PLANAR_MOVER_TRACK()


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_TRACK_STD:
    """MCTOPLC_STD of a track (§6.2.10 watch window)."""

    track_oid: int = 0
    group_oid: int = 0
    state: PlanarState = PlanarState.DISABLED
    operation_mode: TrackOperationMode = TrackOperationMode.UNINITIALIZED
    mover_count_on_track: int = 0  #: movers coupled to the track
    moving_mover_count: int = 0  #: movers with a movement planned on it


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_GROUP_STD:
    """MCTOPLC_STD of a group. The examples read GroupOID and State; the object count is the
    online parameter "Group object count" (§6.3.1)."""

    group_oid: int = 0
    state: PlanarState = PlanarState.DISABLED
    group_object_count: int = 0


@dataclass(frozen=True, slots=True)
class CDT_MCTOPLC_PLANAR_ENVIRONMENT_STD:
    """MCTOPLC_STD of an environment (§6.4.2 watch window)."""

    environment_oid: int = 0
    group_oid: int = 0
    stator_count: int = 0
    boundary_element_count: int = 0  #: outer stator sides; 2 x 2 stators give 8


# -- mover init parameters (§6.1.1) --------------------------------------------------------------

_INF = math.inf


@dataclass(frozen=True)
class PlanarMoverParameters:
    """Init parameters of a planar mover (§6.1.1), with the manual's defaults where it prints
    them. Dynamics are per coordinate group: mm for XY and Z, ° for A, B and C. Defaults apply
    when a command gets no constraint; maxima clip constraints (§6.1.9).

    ``minimum_position``/``maximum_position`` are the hidden limits. For C they set the four
    CRotation windows (``c_windows``, §4.2) rather than a travel limit.
    """

    mover_width: float = 155.0  #: footprint along x for collision checks [mm]
    mover_height: float = 155.0  #: footprint along y (a planar extent, not a height) [mm]
    c_coordinate_modulus: float = 360.0  #: [°]
    c_coordinate_modulo_tolerance_window: float = 0.0  #: [°]
    maximum_dynamic_xy: Limits = Limits(4000.0, 20000.0, 20000.0, 400000.0)
    maximum_dynamic_c: Limits = Limits(720.0, 7200.0, 7200.0, 144000.0)
    maximum_dynamic_z: Limits = Limits(50.0, 1000.0, 1000.0, 20000.0)
    maximum_dynamic_a: Limits = Limits(50.0, 1000.0, 1000.0, 20000.0)
    maximum_dynamic_b: Limits = Limits(50.0, 1000.0, 1000.0, 20000.0)
    default_dynamic_xy: Limits = Limits(2000.0, 10000.0, 10000.0, 200000.0)
    default_dynamic_c: Limits = Limits(360.0, 3600.0, 3600.0, 72000.0)
    default_dynamic_z: Limits = Limits(20.0, 500.0, 500.0, 10000.0)
    default_dynamic_a: Limits = Limits(20.0, 500.0, 500.0, 10000.0)
    default_dynamic_b: Limits = Limits(20.0, 500.0, 500.0, 10000.0)
    position_lag_monitoring_enabled: bool = True
    maximum_position_lag_value: MoverVector = MoverVector(5.0, 5.0, 2.0, 2.0, 2.0, 5.0)
    maximum_position_lag_filter_time: MoverVector = MoverVector(*(0.02,) * 6)  #: [s]
    minimum_position: MoverVector = MoverVector(-_INF, -_INF, 0.0, -5.0, -5.0, -15.0)
    maximum_position: MoverVector = MoverVector(_INF, _INF, 6.0, 5.0, 5.0, 15.0)
    simulation_mode: bool = False  #: hidden, group "Simulation"
    initial_position: MoverVector = MoverVector()  #: simulation start position
    part_oid: int = 0  #: the part the initial position lies on (V3.2.60); 0: none

    def __post_init__(self) -> None:
        for name in ("mover_width", "mover_height", "c_coordinate_modulus"):
            positive_number(getattr(self, name), name)
        window = non_negative_number(self.c_coordinate_modulo_tolerance_window,
                                     "c_coordinate_modulo_tolerance_window")
        if not window < self.c_coordinate_modulus / 2:
            raise ConfigError("c_coordinate_modulo_tolerance_window: must be in "
                              f"[0, c_coordinate_modulus / 2), got {window!r}")
        for group in ("xy", "c", "z", "a", "b"):
            self._check_dynamics(group)
        for name in ("position_lag_monitoring_enabled", "simulation_mode"):
            flag(getattr(self, name), name)
        for name in ("maximum_position_lag_value", "maximum_position_lag_filter_time",
                     "minimum_position", "maximum_position", "initial_position"):
            if not isinstance(getattr(self, name), MoverVector):
                raise ConfigError(f"{name}: must be a MoverVector, got "
                                  f"{type(getattr(self, name)).__name__}")
        part = self.part_oid
        if isinstance(part, bool) or not isinstance(part, int) or not 0 <= part <= _UDINT_MAX:
            raise ConfigError(f"part_oid: must be an object id (an int, 0: none), got {part!r}")
        for f in fields(MoverVector):
            # where the mover starts: NaN or inf would put it where no check can see it
            finite_number(getattr(self.initial_position, f.name), f"initial_position.{f.name}")
            low = limit_number(getattr(self.minimum_position, f.name),
                               f"minimum_position.{f.name}")
            high = limit_number(getattr(self.maximum_position, f.name),
                                f"maximum_position.{f.name}")
            if not low < high:
                raise ConfigError(f"minimum_position.{f.name}: must be below "
                                  f"maximum_position.{f.name}, got {low!r} >= {high!r}")
            for name in ("maximum_position_lag_value", "maximum_position_lag_filter_time"):
                non_negative_number(getattr(getattr(self, name), f.name), f"{name}.{f.name}")
        if not (math.isfinite(self.minimum_position.c) and math.isfinite(self.maximum_position.c)):
            raise ConfigError("minimum_position.c: the C limits must be finite; they set the "
                              "C windows (§4.2)")

    @cached_property
    def c_windows(self) -> CWindows:
        """The four C windows the C position limits give (§4.2); made once (the parameters
        are frozen), as every MoveToPosition with C checks its motion against them."""
        return CWindows(self.minimum_position.c, self.maximum_position.c)

    def _check_dynamics(self, group: str) -> None:
        maximum = getattr(self, f"maximum_dynamic_{group}")
        default = getattr(self, f"default_dynamic_{group}")
        for name, limits in ((f"maximum_dynamic_{group}", maximum),
                             (f"default_dynamic_{group}", default)):
            if not isinstance(limits, Limits):
                raise ConfigError(f"{name}: must be a Limits, got {type(limits).__name__}")
        for f in fields(Limits):
            top, value = getattr(maximum, f.name), getattr(default, f.name)
            positive_number(top, f"maximum_dynamic_{group}.{f.name}")
            if not (is_number(value) and 0.0 < value <= top):
                raise ConfigError(f"default_dynamic_{group}.{f.name}: must be > 0 and at most "
                                  f"the maximum {top!r}, got {value!r}")
