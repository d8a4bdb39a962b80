"""Administrative execute blocks: reset, set position, override, dynamics (TcMC §4)."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.kernel.handshake import ExecuteBlock


class MC_Reset(ExecuteBlock):
    """Leave ErrorStop: clear the axis error, set position := actual (TcMC §4.2, §3.5)."""

    def _issue(self, axis: Axis) -> Command:
        return axis.reset()


class MC_SetActualPosition(ExecuteBlock):
    """Shift the coordinates so the actual position reads ``position`` (TcMC §4.12)."""

    INPUTS: ClassVar[dict[str, Any]] = {"position": MC_INVALID}

    def _issue(self, axis: Axis) -> Command:
        return axis.set_actual_position(self.position)


class MC_SetOverride(ExecuteBlock):
    """Set the velocity override [%], applied to the running move without a jump."""

    INPUTS: ClassVar[dict[str, Any]] = {"override": 100.0}

    def _issue(self, axis: Axis) -> Command:
        return axis.set_override(self.override)


class MC_ChangeDynParam(ExecuteBlock):
    """New acceleration, deceleration and jerk for the running move (TcMC §4.20).

    Re-triggerable. Refused, with the manual's error ids, where the change is unsafe; the
    running profile then keeps its dynamics.
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT,
    }
    retriggerable: ClassVar[bool] = True

    def _issue(self, axis: Axis) -> Command:
        return axis.change_dynamics(self.acceleration, self.deceleration, self.jerk)
