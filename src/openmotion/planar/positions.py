"""PositionXYC: a target or position in the plane with the frame it is given in (TF5430 §5.3,
§7.2.1.2; Tc3_Physics).

The reference id names a part or a coordinate system (§5.3); 0 is accepted only where one
static coordinate system exists. The setters keep the manual's method names in snake_case.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from openmotion.core.checks import is_finite
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.frames import Pose


@dataclass
class PositionXYC:
    """x, y [mm], c [°] and the OID of the frame they are given in (0: the only one)."""

    x: float = 0.0
    y: float = 0.0
    c: float = 0.0
    reference_id: int = 0

    def set_values_xy(self, x: float, y: float) -> PositionXYC:
        self.x, self.y = x, y
        return self

    def set_values_xyc(self, x: float, y: float, c: float) -> PositionXYC:
        self.x, self.y, self.c = x, y, c
        return self

    def set_values_xyc_reference_id(self, x: float, y: float, c: float,
                                    reference_id: int) -> PositionXYC:
        self.x, self.y, self.c, self.reference_id = x, y, c, reference_id
        return self

    @property
    def pose(self) -> Pose:
        return Pose(float(self.x), float(self.y), float(self.c))


def finite(value: object, name: str) -> float:
    """A command's number input, or PLANAR_INVALID_INPUT (no exception leaves a cycle)."""
    if type(value) is float and math.isfinite(value):  # the usual input, without the ABC test
        return value
    if not is_finite(value):
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"{name}: must be a finite number, got {value!r}")
    return float(value)


def reference_id(value: object) -> int:
    """An object id is a UDINT: a wrong type is a Python error at the call (a value that
    names nothing is an error id when the command runs)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise TypeError(f"a reference id must be an int (an object id), got "
                        f"{type(value).__name__}")
    return int(value)
