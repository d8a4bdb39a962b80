"""MC_Power (TcMC §4.1)."""

from __future__ import annotations

import math
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.core.errors import ErrorId
from openmotion.kernel.handshake import FunctionBlock


class MC_Power(FunctionBlock):
    """Controller and feed enables plus the override [%], level-triggered.

    ``status`` is TRUE while enabled and the drive is ready. Enabling takes the actual
    position as set position (TcMC §3.5). The override is written when it changes, so an
    MC_SetOverride in between stays in force until this input changes (D-007).
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "enable": False, "enable_positive": True, "enable_negative": True, "override": 100.0,
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.status = False
        self._last_override: float | None = None

    def __call__(self, axis: Axis | None = None, /, **inputs: Any) -> None:
        if inputs:
            self._set_inputs(inputs)
        if axis is not None:
            self.axis = axis
        axis = self._axis()
        self.status = axis.power(bool(self.enable), bool(self.enable_positive),
                                 bool(self.enable_negative))
        self.error, self.error_id, self.message = False, ErrorId.NO_ERROR, ""
        if self.enable and not axis.drive_ready:
            self.error, self.error_id = True, ErrorId.DRIVE_NOT_READY
            self.message = "the drive is not ready"
        override = self.override
        if override != self._last_override:
            if isinstance(override, int | float) and math.isfinite(override) \
                    and 0.0 <= override <= 100.0:
                axis.set_override(float(override))
                self._last_override = override
            else:
                self.error, self.error_id = True, ErrorId.INVALID_OVERRIDE
                self.message = f"override must be within 0..100 %, got {override!r}"
