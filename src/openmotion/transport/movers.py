"""What a CA group holds per mover: identity, commands, modes (TF5410 §9.1, §9.3)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

from openmotion.axis.commands import Command
from openmotion.core.enums import BufferMode, convert_enum
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import InputValue
from openmotion.kernel.model import Kind
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import KinematicState, Profile
from openmotion.transport.enums import GapControlMode, GroupState, GroupType
from openmotion.transport.kind import CA_MOVER

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

IDLE, FOLLOW, HELD, GEAR = 0, 1, 2, 3  #: mover modes: no command, on its profile, held by
#: CA, coupled to a master (MC_GearInPosCA)
POSITION, HALT, STANDBY = "position", "halt", "standby"  #: CaJob kinds
MOVING_STATES = (GroupState.STANDBY, GroupState.MOVING, GroupState.STOPPING)


@dataclass(frozen=True)
class IdentInGroup:
    """IDENT_IN_GROUP_REF of a CA member: made by ``UDINT_TO_IDENTINGROUP(n)`` (§9.3.1.1.13)."""

    value: int


def UDINT_TO_IDENTINGROUP(value: int) -> IdentInGroup:  # noqa: N802 - the manual's name
    """The identity an axis has in a CA group; it does not decide the CA order (§8.1.1)."""
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 0xFFFFFFFF:
        raise ValueError(f"UDINT_TO_IDENTINGROUP: a UDINT is needed, got {value!r}")
    return IdentInGroup(value)


@dataclass(frozen=True)
class GroupInterface:
    """NcToPlc of AXES_GROUP_REF (§11.1): what a PLC reads every cycle."""

    group_oid: int
    group_type: GroupType
    group_state: GroupState  #: GroupStatus.State
    is_enable_requested: bool  #: GroupStatus.Flags.IsEnableRequested
    group_error_id: int
    group_axes_count: int


@dataclass
class CaJob:
    """One CA motion command of a mover (active or buffered)."""

    kind: str  #: "position", "halt", "standby" or "gear"
    command: Command
    limits: Limits
    gap: float
    gap_mode: GapControlMode  #: resolved: STANDARD, FAST or NONE
    buffer_mode: BufferMode = BufferMode.ABORTING
    target_of: Callable[[float], float] | None = None  #: start position -> absolute target
    target: float = math.nan
    continuous_update: bool = False
    extra: Any = None  #: the GearSync of a "gear" job


@dataclass
class FaultBrake:
    """A mover's brake to rest after a group error or a power loss (faults.py, D-183)."""

    start: float  #: absolute time of the state the brake starts from [s]
    profile: Profile  #: the brake with the mover's maximum deceleration and jerk
    end: float = math.nan  #: the segment table's end time of the row once installed [s]


@dataclass
class Mover:
    """A member of the group: its axis, identity and commands."""

    MACHINE: ClassVar[Kind] = CA_MOVER  #: its signals in the machine model

    axis: Axis
    ident: IdentInGroup
    added: int  #: insertion serial (ties in the CA order: the last added is first)
    job: CaJob | None = None
    queue: list[CaJob] = field(default_factory=list)
    gap: float = 0.0  #: the last valid gap (§9.1.2.5: kept after a None command)
    slot: int = -1  #: index in the group's arrays (CA order)
    brake: FaultBrake | None = None  #: running brake after a fault, until the mover rests

    @property
    def name(self) -> str:
        """The name of the axis it is."""
        return self.axis.name


def hold(position: float) -> Profile:
    return Profile.hold(KinematicState(position))


def enum_input(kind: Any, value: Any, error_id: ErrorId, name: str) -> Any:
    try:
        if isinstance(value, bool):
            raise ValueError(value)
        return convert_enum(kind, value)
    except (ValueError, TypeError):
        raise CommandRejected(error_id, f"{name}: {value!r} is not a {kind.__name__}") from None


def position_input(name: str, value: InputValue) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise CommandRejected(ErrorId.INVALID_POSITION, f"{name}: must be set, got {value!r}")
    return float(value)
