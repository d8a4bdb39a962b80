"""Angles in degrees, as the manuals give them."""

from __future__ import annotations

import math

_QUARTER_TURNS = ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))


def cos_sin(angle: float) -> tuple[float, float]:
    """cos and sin of ``angle`` [°]; exact at multiples of 90°, where libm is off by 6e-17, so
    that frames turned by quarter turns keep grid corners exactly."""
    turns, rest = divmod(angle, 90.0)
    if rest == 0.0:
        return _QUARTER_TURNS[int(turns) % 4]
    radians = math.radians(angle)
    return math.cos(radians), math.sin(radians)
