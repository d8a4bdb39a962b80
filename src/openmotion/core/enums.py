"""Enumerations with the manuals' numeric values (TcMC §6, TF5410 §9.4)."""

from __future__ import annotations

from enum import Enum, IntEnum
from typing import TypeVar

EnumT = TypeVar("EnumT", bound=Enum)


class AxisState(IntEnum):
    """PLCopen single-axis states (TcMC §4.4 names, PLCopen Part 1 diagram)."""

    DISABLED = 0
    STANDSTILL = 1
    HOMING = 2
    DISCRETE_MOTION = 3
    CONTINUOUS_MOTION = 4
    SYNCHRONIZED_MOTION = 5
    STOPPING = 6
    ERROR_STOP = 7


class Direction(IntEnum):
    """MC_Direction of the TcMC library (TcMC §6.2): MC_Positive_Direction, MC_Shortest_Way,
    MC_Negative_Direction, MC_Current_Direction.

    Not the MC3 libraries' MC_DIRECTION (``ModuloDirection``): a member of that one converts by
    its name at the boundary (``convert_enum``, D-225).
    """

    POSITIVE = 1
    SHORTEST_WAY = 2
    NEGATIVE = 3
    CURRENT = 4


class BufferMode(IntEnum):
    """MC_BUFFER_MODE (TF5410 §9.4.1.1; PLCopen Part 1 semantics)."""

    ABORTING = 0x00
    BUFFERED = 0x01
    BLENDING_LOW = 0x12
    BLENDING_PREVIOUS = 0x13
    BLENDING_NEXT = 0x14
    BLENDING_HIGH = 0x15


class ReadMode(IntEnum):
    """E_ReadMode (TcMC §6.4)."""

    ONCE = 1
    CYCLIC = 2


class ReferenceMode(IntEnum):
    """How MC_Home finds the reference (TcMC §3.14: configured at the encoder, not the FB)."""

    CAM_AND_SYNC_PULSE = 0  #: search the cam, leave it, latch the next encoder sync pulse
    CAM = 1  #: take the reference at the falling edge of the cam
    SYNC_PULSE = 2  #: latch the next sync pulse (the PLC simulates the cam, TcMC §3.14 note)
    DIRECT = 3  #: set the position where the axis stands, no motion


class NewPosAndVeloMode(IntEnum):
    """E_CmdTypeNewTargPosAndVelo (TcMC §3.8; values from the TcNC library)."""

    CHANGE_POS = 1
    CHANGE_VELO = 2
    CHANGE_POS_AND_VELO = 3
    CHANGE_POS_AT_SWITCHPOS = 9
    CHANGE_VELO_AT_SWITCHPOS = 10
    CHANGE_POS_AND_VELO_AT_SWITCHPOS = 11
    REACH_VELO_AT_POS = 14


class DecoupleMode(IntEnum):
    """E_DecoupleMode (TcMC §3.21): the follow-up command of MC_GearOutExt."""

    STOP = 0
    ORIENTED_STOP = 1
    ENDLESS = 2
    ENDLESS_NEW_VELOCITY = 3
    NEW_POSITION = 4
    NEW_POSITION_AND_VELOCITY = 5
    INSTANTANEOUS_STOP = 6


class TargetPositionType(IntEnum):
    """E_TargPosType of MC_ExtSetPointGenEnable (TcMC §4.16; values from the TcNC library)."""

    ABSOLUTE = 1
    RELATIVE = 2
    MODULO = 5


class SuperpositionMode(IntEnum):
    """E_SuperpositionMode (TcMC §6.5)."""

    VELOREDUCTION_ADDITIVEMOTION = 1
    VELOREDUCTION_LIMITEDMOTION = 2
    LENGTHREDUCTION_ADDITIVEMOTION = 3
    LENGTHREDUCTION_LIMITEDMOTION = 4


class ModuloDirection(IntEnum):
    """MC_DIRECTION of Tc3_Mc3Definitions (TF5410 §9.4.1.3, TF5430 §7.2.1.1.2):
    mcDirectionNonModulo, mcDirectionPositive, mcDirectionShortestWay, mcDirectionNegative.

    The MC3 libraries (CA group, planar movers) share it. TcMC's ``Direction`` is another
    type of the same manual name (the manual qualifies the namespace where both meet); a
    member of one given for the other converts by name (``convert_enum``, D-225).
    """

    NON_MODULO = 0
    POSITIVE = 1
    SHORTEST_WAY = 2
    NEGATIVE = 3


def convert_enum(kind: type[EnumT], value: object) -> EnumT:
    """``value`` as a member of ``kind``: a member of another enumeration by its name, which
    is what it means, anything else by its value (a PLC passes the number).

    The two direction types (``Direction``, ``ModuloDirection``) and MC_SYNC_MODE share the
    names Positive and Negative, and their numbers agree only because both manuals chose
    1 and 3: a conversion between them goes by name (D-225). Raises ``ValueError`` for a
    value that names or numbers no member.
    """
    if isinstance(value, Enum) and not isinstance(value, kind):
        try:
            return kind[value.name]
        except KeyError:
            raise ValueError(f"{value!r} is not a {kind.__name__}") from None
    return kind(value)
