"""CA block inputs to numbers: MC3 special values, bounds and clamping (TF5410 §9.1, §11.2).

Unlike TcMC, 0 is an ordinary (and invalid) value here: only MC_DEFAULT means the default.
Velocity > 0 (no default exists), acceleration and deceleration >= 1, jerk >= 100 (MC_MAXIMUM
is invalid for jerk). Values above the axis maxima are clamped with a warning, as the manual
says; jerk is clamped to ``max_jerk`` the same way (the manual knows no maximum jerk).
"""

from __future__ import annotations

import math

from openmotion.axis.parameters import AxisParameters
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID, MC_MAXIMUM, InputValue
from openmotion.trajectory.plan import Limits

_SPEC = {
    #  name: (default field, maximum field, lower bound, error id, MC_MAXIMUM allowed)
    "velocity": (None, "max_velocity", 0.0, ErrorId.INVALID_VELOCITY, True),
    "acceleration": ("acceleration", "max_acceleration", 1.0, ErrorId.INVALID_ACCELERATION,
                     True),
    "deceleration": ("deceleration", "max_deceleration", 1.0, ErrorId.INVALID_DECELERATION,
                     True),
    "jerk": ("jerk", "max_jerk", 100.0, ErrorId.INVALID_JERK, False),
}


def ca_value(name: str, value: InputValue, parameters: AxisParameters,
             warnings: list[str]) -> float:
    """The number a CA dynamics input stands for, or ``CommandRejected``."""
    default_field, maximum_field, lower, error_id, maximum_ok = _SPEC[name]
    maximum = getattr(parameters, maximum_field)
    if value is MC_MAXIMUM and maximum_ok:
        return float(maximum)
    if value is MC_DEFAULT and default_field is not None:
        return min(float(getattr(parameters, default_field)), maximum)
    if value is MC_INVALID:
        raise CommandRejected(error_id, f"{name}: must be set (MC_INVALID)")
    if not isinstance(value, int | float) or isinstance(value, bool):
        raise CommandRejected(error_id, f"{name}: {value!r} is not allowed here")
    if not math.isfinite(value) or value < lower or (lower == 0.0 and value == 0.0):
        bound = "> 0" if lower == 0.0 else f">= {lower:g}"
        raise CommandRejected(error_id, f"{name}: must be {bound}, got {value!r}")
    if value > maximum:
        warnings.append(f"{name} {value:g} clamped to the axis maximum {maximum:g}")
        return float(maximum)
    return float(value)


def ca_limits(parameters: AxisParameters, warnings: list[str], velocity: InputValue,
              acceleration: InputValue, deceleration: InputValue, jerk: InputValue) -> Limits:
    return Limits(ca_value("velocity", velocity, parameters, warnings),
                  ca_value("acceleration", acceleration, parameters, warnings),
                  ca_value("deceleration", deceleration, parameters, warnings),
                  ca_value("jerk", jerk, parameters, warnings))


def halt_limits(parameters: AxisParameters, warnings: list[str], deceleration: InputValue,
                jerk: InputValue) -> Limits:
    dec = ca_value("deceleration", deceleration, parameters, warnings)
    return Limits(parameters.max_velocity, dec, dec, ca_value("jerk", jerk, parameters, warnings))


def ca_gap(value: InputValue, default: float) -> float:
    """The Gap input: MC_DEFAULT = the group's default gap, else a finite number >= 0."""
    if value is MC_DEFAULT:
        return default
    if not isinstance(value, int | float) or isinstance(value, bool) or not (
            math.isfinite(value) and value >= 0.0):
        raise CommandRejected(ErrorId.INVALID_GAP,
                              f"gap: must be MC_DEFAULT or a finite number >= 0, got {value!r}")
    return float(value)
