"""Part 4 block inputs to numbers: dynamics, positions and enums of the group FBs.

Part 4 asks for "always positive" Velocity, Acceleration, Deceleration and Jerk (§5.20) and
knows no special values; we also take ``MC_DEFAULT`` (the group's default dynamics) and
``MC_MAXIMUM`` (its maximum), as the TF5410 group blocks do. Values above the maximum are
clamped with a warning, the TcMC way (decisions D-107).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import Any

import numpy as np

from openmotion.core.checks import is_finite, positive_number
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_MAXIMUM, InputValue


class CoordSystem(IntEnum):
    """MC_COORD_REF (§2.1): the system a block's positions are given in."""

    ACS = 1  #: axis coordinates, one value per member axis in IdentInGroup order
    MCS = 2  #: machine coordinates, the kinematics' output
    PCS = 3  #: product coordinates, placed in the MCS by the Cartesian transform


class TransitionMode(IntEnum):
    """MC_TRANSITION_MODE (§2.4.3): the contour between two blended blocks."""

    TM_NONE = 0  #: no contour: the path stops at the corner (as Buffered)
    TM_START_VELOCITY = 1  #: contour starts when the pre-block slowed to TPStartVelocity %
    TM_CONSTANT_VELOCITY = 2  #: contour sized to run at TPVelocity % of the transition speed
    TM_CORNER_DISTANCE = 3  #: contour leaves and rejoins TPCornerDistance from the corner
    TM_MAX_CORNER_DEVIATION = 4  #: contour passes at most TPCornerDeviation from the corner


@dataclass(frozen=True)
class PathMoveOptions:
    """The inputs every path move of Part 4 shares (§5.20-§5.27), as the FB gives them: the
    dynamics (MC_DEFAULT: the group's PathDynamics), the coordinate system, the buffer mode
    and the transition to the motion before. Checked when the move is built (requests.py)."""

    velocity: InputValue = MC_DEFAULT  #: [mm/s] along the path (ACS units for MC_MoveDirect*)
    acceleration: InputValue = MC_DEFAULT  #: [mm/s²]
    deceleration: InputValue = MC_DEFAULT  #: [mm/s²]
    jerk: InputValue = MC_DEFAULT  #: [mm/s³]
    coord_system: CoordSystem = CoordSystem.MCS  #: ACS for MC_MoveDirect*
    buffer_mode: BufferMode = BufferMode.ABORTING
    transition_mode: TransitionMode = TransitionMode.TM_NONE
    transition_parameter: Any = None  #: TransitionParameter, per mode (§2.4.3)


@dataclass(frozen=True, slots=True)
class PathDynamics:
    """The group's dynamics on the path: defaults for MC_DEFAULT and caps (§5.20)."""

    velocity: float = 100.0  #: default path velocity [mm/s]
    acceleration: float = 1000.0  #: [mm/s²]
    deceleration: float = 1000.0  #: [mm/s²]
    jerk: float = 10000.0  #: [mm/s³]
    max_velocity: float = 1000.0
    max_acceleration: float = 10000.0
    max_deceleration: float = 10000.0
    max_jerk: float = 1.0e6

    def __post_init__(self) -> None:
        for name in self.__slots__:
            positive_number(getattr(self, name), name)


_ERRORS = {"velocity": ErrorId.INVALID_VELOCITY, "acceleration": ErrorId.INVALID_ACCELERATION,
           "deceleration": ErrorId.INVALID_DECELERATION, "jerk": ErrorId.INVALID_JERK}


def dynamic_value(name: str, value: InputValue, dynamics: PathDynamics,
                  warnings: list[str]) -> float:
    """One of Velocity/Acceleration/Deceleration/Jerk as a number, or ``CommandRejected``."""
    maximum = float(getattr(dynamics, f"max_{name}"))
    if value is MC_DEFAULT:
        return min(float(getattr(dynamics, name)), maximum)
    if value is MC_MAXIMUM:
        return maximum
    if isinstance(value, bool) or not isinstance(value, int | float) \
            or not math.isfinite(value) or value <= 0.0:
        raise CommandRejected(_ERRORS[name], f"{name}: must be > 0, got {value!r} (§5.20)")
    if value > maximum:
        warnings.append(f"{name} {value:g} clamped to the group maximum {maximum:g}")
        return maximum
    return float(value)


def path_dynamics(dynamics: PathDynamics, warnings: list[str], velocity: InputValue,
                  acceleration: InputValue, deceleration: InputValue,
                  jerk: InputValue) -> tuple[float, float, float, float]:
    return (dynamic_value("velocity", velocity, dynamics, warnings),
            dynamic_value("acceleration", acceleration, dynamics, warnings),
            dynamic_value("deceleration", deceleration, dynamics, warnings),
            dynamic_value("jerk", jerk, dynamics, warnings))


def vector(value: Any, size: int, name: str) -> np.ndarray:
    """A finite vector of ``size`` values (a position in some coordinate system); a bool or
    a text among them is no number (numpy would read True as 1)."""
    if isinstance(value, np.ndarray):
        ok = value.dtype.kind in "iuf" and value.shape == (size,) \
            and bool(np.all(np.isfinite(value)))
    else:
        ok = not isinstance(value, str | bytes) and hasattr(value, "__len__") \
            and len(value) == size and all(is_finite(v) for v in value)
    if not ok:
        raise CommandRejected(ErrorId.INVALID_POSITION,
                              f"{name}: needs {size} finite values, got {value!r}")
    return np.array(value, dtype=float)


#: Part 4's MC_BUFFER_MODE numbers (§2.4.2, Table 2); ``core.enums.BufferMode`` keeps TcMC's
_PART4_BUFFER_MODES = (BufferMode.ABORTING, BufferMode.BUFFERED, BufferMode.BLENDING_LOW,
                       BufferMode.BLENDING_PREVIOUS, BufferMode.BLENDING_NEXT,
                       BufferMode.BLENDING_HIGH)


def buffer_mode(value: Any) -> BufferMode:
    """A BufferMode member, or Part 4's number 0-5 for it (decisions D-107)."""
    if isinstance(value, BufferMode):
        return value
    if isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 5:
        return _PART4_BUFFER_MODES[value]
    raise CommandRejected(ErrorId.INVALID_MODE,
                          f"BufferMode: {value!r} is not one of 0-5 (Part 4 §2.4.2) or a "
                          "BufferMode member")


def enum_value(kind: type[IntEnum], value: Any, name: str) -> Any:
    """``kind(value)`` or ``CommandRejected(INVALID_MODE)`` naming the input."""
    try:
        if isinstance(value, bool):
            raise ValueError
        return kind(value)
    except (ValueError, TypeError):
        names = ", ".join(m.name for m in kind)
        raise CommandRejected(ErrorId.INVALID_MODE,
                              f"{name}: {value!r} is not one of {names}") from None


def transition_mode(value: Any) -> TransitionMode:
    """§2.4.3: 0-4 are defined, 5-9 reserved, 10 and above supplier modes (none here)."""
    if isinstance(value, int) and not isinstance(value, bool) and value >= 5:
        kind = "reserved" if value <= 9 else "a supplier mode this library does not offer"
        raise CommandRejected(ErrorId.INVALID_MODE, f"TransitionMode {value} is {kind} (§2.4.3)")
    return enum_value(TransitionMode, value, "TransitionMode")


def transition_parameter(mode: TransitionMode, values: Sequence[float] | float | None) -> float:
    """The one TransitionParameter value ``mode`` uses (§7.4), checked."""
    if mode is TransitionMode.TM_NONE:
        return 0.0
    if values is None:
        raise CommandRejected(ErrorId.INVALID_MODE,
                              f"{mode.name} needs a TransitionParameter (§7.4)")
    value = values if isinstance(values, int | float) else (list(values) or [math.nan])[0]
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise CommandRejected(ErrorId.INVALID_MODE,
                              f"TransitionParameter of {mode.name} must be > 0, got {value}")
    if mode in (TransitionMode.TM_START_VELOCITY, TransitionMode.TM_CONSTANT_VELOCITY) \
            and value > 100.0:
        raise CommandRejected(ErrorId.INVALID_MODE,
                              f"TransitionParameter of {mode.name} is a percentage <= 100")
    return value
