"""Drive and encoder model: ideal, or a first-order lag behind a dead time.

The lag gives a real following error, so the §7.1 Done windows, following-error monitoring and
MC_Reset's "set position := actual position" (TcMC §3.5) mean something.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal


@dataclass(frozen=True)
class DriveModel:
    model: Literal["ideal", "lag"] = "ideal"
    time_constant: float = 0.0  #: first-order lag of the closed position loop [s]
    dead_time: float = 0.0  #: transport delay, rounded to whole cycles [s]

    def __post_init__(self) -> None:
        if self.model not in ("ideal", "lag"):
            raise ValueError(f"model: must be 'ideal' or 'lag', got {self.model!r}")
        for name in ("time_constant", "dead_time"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name}: must be a finite number >= 0, got {value!r}")

    def coefficients(self, cycle_time: float) -> tuple[float, int]:
        """Lag factor per cycle and dead time in cycles."""
        if self.model == "ideal":
            return 1.0, 0
        alpha = 1.0 if self.time_constant == 0.0 else -math.expm1(-cycle_time / self.time_constant)
        return alpha, round(self.dead_time / cycle_time)
