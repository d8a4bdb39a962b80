"""Checks of the numbers a constructor, an ``add_...`` call or a run call is given.

Configuration calls refuse a value that is no number, or NaN or infinite, with a
``ConfigError`` naming the field at once: such a value would otherwise surface much later,
as an axis that fails every move or a mover that collision avoidance cannot see. A bool is
no number here, though Python counts it as an int. Commands (FB inputs) do not raise: they
use ``is_finite`` and report their block's error id. These run at configuration time only,
never inside a cycle.
"""

from __future__ import annotations

import math
from numbers import Real

from openmotion.core.errors import ConfigError


def is_number(value: object) -> bool:
    """A real number (int, float, numpy scalar); not a bool, not a string."""
    return isinstance(value, Real) and not isinstance(value, bool)


def is_finite(value: object) -> bool:
    """A real number that is neither NaN nor infinite."""
    return is_number(value) and math.isfinite(value)  # type: ignore[arg-type]


def _number(value: object, field: str) -> float:
    if not is_number(value):
        raise ConfigError(f"{field}: must be a number, got {value!r}")
    return float(value)  # type: ignore[arg-type]


def finite_number(value: object, field: str) -> float:
    """``value`` as a float, or ``ConfigError("field: must be a finite number, got nan")``."""
    number = _number(value, field)
    if not math.isfinite(number):
        raise ConfigError(f"{field}: must be a finite number, got {value!r}")
    return number


def positive_number(value: object, field: str) -> float:
    """A finite number > 0 (a length, a period, a maximum velocity)."""
    number = _number(value, field)
    if not (math.isfinite(number) and number > 0.0):
        raise ConfigError(f"{field}: must be a finite number > 0, got {value!r}")
    return number


def non_negative_number(value: object, field: str) -> float:
    """A finite number >= 0 (a duration, a window, a margin)."""
    number = _number(value, field)
    if not (math.isfinite(number) and number >= 0.0):
        raise ConfigError(f"{field}: must be a finite number >= 0, got {value!r}")
    return number


def limit_number(value: object, field: str) -> float:
    """A number that may be infinite but not NaN: a position limit, where ±inf is none."""
    number = _number(value, field)
    if math.isnan(number):
        raise ConfigError(f"{field}: must be a number or ±inf, got {value!r}")
    return number


def finite_pair(value: object, field: str) -> tuple[float, float]:
    """Two finite numbers, e.g. a point (x, y) [mm]."""
    if isinstance(value, str | bytes) or not hasattr(value, "__len__") or len(value) != 2:  # type: ignore[arg-type]
        raise ConfigError(f"{field}: must be two numbers, got {value!r}")
    first, second = value  # type: ignore[misc]
    return finite_number(first, f"{field}[0]"), finite_number(second, f"{field}[1]")


def flag(value: object, field: str) -> bool:
    """A bool, not a number that happens to be 0 or 1."""
    if not isinstance(value, bool):
        raise ConfigError(f"{field}: must be True or False, got {value!r}")
    return value
