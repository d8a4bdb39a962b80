"""Turn FB dynamics inputs into limits: special values, TcMC's 0 = default, clamping.

TcMC §1.9: an acceleration, deceleration or jerk of 0 means the axis default (1004-1006).
TF5410 §11.2: MC_DEFAULT means the default, MC_MAXIMUM the maximum. Velocity and acceleration
above the axis maxima are clamped with a warning (TF5410 D4.1); jerk above the maximum is
rejected, as everywhere the manuals do not say "clamp".
"""

from __future__ import annotations

import math

from openmotion.axis.parameters import AxisParameters
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID, MC_MAXIMUM, SpecialValue
from openmotion.trajectory.plan import Limits

_SPEC = {
    #  name: (default field, maximum field, error id, clamp above maximum)
    "velocity": (None, "max_velocity", ErrorId.INVALID_VELOCITY, True),
    "acceleration": ("acceleration", "max_acceleration", ErrorId.INVALID_ACCELERATION, True),
    "deceleration": ("deceleration", "max_deceleration", ErrorId.INVALID_DECELERATION, True),
    "jerk": ("jerk", "max_jerk", ErrorId.INVALID_JERK, False),
}


def resolve(
    name: str, value: float | SpecialValue, parameters: AxisParameters, warnings: list[str]
) -> float:
    """The number a dynamics input stands for, or ``CommandRejected`` with its error id."""
    default_field, maximum_field, error_id, clamp = _SPEC[name]
    maximum = getattr(parameters, maximum_field)
    if type(value) is float and 0.0 < value <= maximum:  # the common case, checked first
        return value
    if value is MC_MAXIMUM:
        return maximum
    if value is MC_DEFAULT or (default_field and _is_zero(value)):
        if default_field is None:
            raise CommandRejected(error_id, f"{name}: there is no default {name}; give a value")
        return getattr(parameters, default_field)
    if value is MC_INVALID:
        raise CommandRejected(error_id, f"{name}: must be set (MC_INVALID)")
    if isinstance(value, SpecialValue):
        raise CommandRejected(error_id, f"{name}: {value!r} is not allowed here")
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise CommandRejected(error_id, f"{name}: must be a number, got {value!r}")
    if not math.isfinite(value) or value <= 0.0:
        raise CommandRejected(error_id, f"{name}: must be > 0, got {value}")
    if value > maximum:
        if not clamp:
            raise CommandRejected(error_id, f"{name}: {value} exceeds the axis maximum {maximum}")
        warnings.append(f"{name} {value} clamped to the axis maximum {maximum}")
        return maximum
    return float(value)


def resolve_limits(
    parameters: AxisParameters,
    warnings: list[str],
    velocity: float | SpecialValue,
    acceleration: float | SpecialValue,
    deceleration: float | SpecialValue,
    jerk: float | SpecialValue,
) -> Limits:
    p = parameters
    if type(velocity) is float and type(acceleration) is float \
            and type(deceleration) is float and type(jerk) is float \
            and 0.0 < velocity <= p.max_velocity and 0.0 < acceleration <= p.max_acceleration \
            and 0.0 < deceleration <= p.max_deceleration and 0.0 < jerk <= p.max_jerk:
        return Limits(velocity, acceleration, deceleration, jerk)  # what ``resolve`` gives
    return Limits(
        resolve("velocity", velocity, parameters, warnings),
        resolve("acceleration", acceleration, parameters, warnings),
        resolve("deceleration", deceleration, parameters, warnings),
        resolve("jerk", jerk, parameters, warnings),
    )


def require_position(name: str, value: float | SpecialValue) -> float:
    """A position input: any finite number; MC_INVALID and other sentinels are rejected."""
    if type(value) is float and math.isfinite(value):  # the common case
        return value
    if isinstance(value, SpecialValue | bool) or not isinstance(value, int | float):
        raise CommandRejected(ErrorId.INVALID_POSITION, f"{name}: must be set, got {value!r}")
    if not math.isfinite(value):
        raise CommandRejected(ErrorId.INVALID_POSITION, f"{name}: must be finite, got {value}")
    return float(value)


def _is_zero(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and value == 0
