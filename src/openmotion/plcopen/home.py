"""MC_Home (TcMC §3.14)."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.special_values import DEFAULT_HOME_POSITION
from openmotion.kernel.handshake import ExecuteBlock


class MC_Home(ExecuteBlock):
    """Reference the axis; the reference mode is an axis parameter, not an input.

    ``position`` is assigned at the reference event (DEFAULT_HOME_POSITION: the axis'
    calibration value). ``calibration_cam`` is the cam signal wired through the PLC; None
    uses the axis' simulated cam. Progress shows in ``axis.calibration_state``.
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "position": DEFAULT_HOME_POSITION, "calibration_cam": None,
    }

    def __call__(self, axis: Axis | None = None, /, **inputs: Any) -> None:
        super().__call__(axis, **inputs)
        if self.axis is not None and self.busy:
            self.axis.cam_input = self.calibration_cam

    def _issue(self, axis: Axis) -> Command:
        axis.cam_input = self.calibration_cam
        return axis.home(self.position)
