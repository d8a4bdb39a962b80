"""Superimposed motion: MC_MoveSuperImposed, MC_MoveSuperImposedExt, MC_AbortSuperposition
(TcMC §3.9-3.12)."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import SuperpositionMode
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.kernel.handshake import ExecuteBlock

_INPUTS: dict[str, Any] = {
    "distance": MC_INVALID, "velocity_diff": MC_INVALID, "acceleration": MC_DEFAULT,
    "deceleration": MC_DEFAULT, "jerk": 0.0, "velocity_process": MC_INVALID,
}


class MC_MoveSuperImposed(ExecuteBlock):
    """Catch up (``distance`` > 0) or fall back on the running motion within
    ``max_distance`` of the axis' own travel, as fast as ``velocity_diff`` allows
    (LENGTHREDUCTION_LIMITEDMOTION, D-041). ``jerk`` is unused, as in TcMC.

    Busy while the superimposed motion runs; error 0x4243 when only part of the distance
    fits (the axis still moves that part).
    """

    INPUTS: ClassVar[dict[str, Any]] = {**_INPUTS, "max_distance": MC_INVALID}

    def _issue(self, axis: Axis) -> Command:
        return axis.move_superimposed(self.distance, self.velocity_diff, self.velocity_process,
                                      self.max_distance,
                                      SuperpositionMode.LENGTHREDUCTION_LIMITEDMOTION,
                                      self.acceleration, self.deceleration)


class MC_MoveSuperImposedExt(ExecuteBlock):
    """As MC_MoveSuperImposed with ``mode`` (E_SuperpositionMode) and ``length``; outputs
    ``actual_velocity_diff``, ``actual_distance`` and ``actual_length`` from the start."""

    INPUTS: ClassVar[dict[str, Any]] = {
        **_INPUTS, "mode": SuperpositionMode.VELOREDUCTION_ADDITIVEMOTION, "length": MC_INVALID,
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.actual_velocity_diff = self.actual_distance = self.actual_length = 0.0

    def _issue(self, axis: Axis) -> Command:
        command = axis.move_superimposed(self.distance, self.velocity_diff,
                                         self.velocity_process, self.length, self.mode,
                                         self.acceleration, self.deceleration)
        if command.value is not None:
            self.actual_velocity_diff, self.actual_distance, self.actual_length = command.value
        return command


class MC_AbortSuperposition(ExecuteBlock):
    """End the superimposed motion; the base motion continues unchanged (TcMC §3.12)."""

    def _issue(self, axis: Axis) -> Command:
        return axis.abort_superposition()
