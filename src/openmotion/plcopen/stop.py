"""MC_Stop (TcMC §3.15) and MC_Halt (PLCopen Part 1)."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import BufferMode
from openmotion.core.special_values import MC_DEFAULT
from openmotion.kernel.handshake import ExecuteBlock


class MC_Stop(ExecuteBlock):
    """Brake to rest; while ``execute`` stays TRUE the axis stays in Stopping (PLCopen).

    ``deceleration``/``jerk`` of 0 keep the running move's values; a non-zero value applies
    only with a non-zero partner. Softer values than the running ones are ignored in the four
    safety cases of §3.15, without an error. Other motion commands are rejected with
    AXIS_STOPPING while the stop holds (docs/decisions.md D-005).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"deceleration": 0.0, "jerk": 0.0}

    def _issue(self, axis: Axis) -> Command:
        return axis.stop(self.deceleration, self.jerk, hold=True)

    def _falling_edge(self) -> None:
        if self._command is not None:
            self._command.release()


class MC_Halt(ExecuteBlock):
    """Brake to rest in DiscreteMotion; any later motion command may abort it."""

    INPUTS: ClassVar[dict[str, Any]] = {
        "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT, "buffer_mode": BufferMode.ABORTING,
    }

    def _issue(self, axis: Axis) -> Command:
        return axis.halt(self.deceleration, self.jerk, self.buffer_mode)
