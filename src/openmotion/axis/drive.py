"""Drive and encoder model: ideal, or a first-order lag behind a dead time.

The lag gives a real following error, so the §7.1 Done windows, following-error monitoring and
MC_Reset's "set position := actual position" (TcMC §3.5) mean something.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from openmotion.core.checks import non_negative_number
from openmotion.core.errors import ConfigError


@dataclass(frozen=True)
class DriveModel:
    model: Literal["ideal", "lag"] = "ideal"
    time_constant: float = 0.0  #: first-order lag of the closed position loop [s]
    dead_time: float = 0.0  #: transport delay, rounded to whole cycles [s]

    def __post_init__(self) -> None:
        if self.model not in ("ideal", "lag"):
            raise ConfigError(f"model: must be 'ideal' or 'lag', got {self.model!r}")
        for name in ("time_constant", "dead_time"):
            non_negative_number(getattr(self, name), name)

    def coefficients(self, cycle_time: float) -> tuple[float, int]:
        """Lag factor per cycle and dead time in cycles."""
        if self.model == "ideal":
            return 1.0, 0
        alpha = 1.0 if self.time_constant == 0.0 else -math.expm1(-cycle_time / self.time_constant)
        return alpha, round(self.dead_time / cycle_time)
