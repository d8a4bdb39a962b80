"""Parameter blocks: MC_AxisPara numbers read and written (TcMC §4.6-4.11)."""

from __future__ import annotations

from dataclasses import asdict
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.enums import ReadMode
from openmotion.kernel.handshake import EnableBlock, ExecuteBlock


class MC_ReadParameter(EnableBlock):
    """``value`` of LREAL parameter ``parameter_number``; once per enable or every cycle."""

    INPUTS: ClassVar[dict[str, Any]] = {"parameter_number": 0, "read_mode": ReadMode.CYCLIC}
    kind: ClassVar[type] = float

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.value = self.kind()

    def _enabled(self, axis: Axis, rising: bool) -> None:
        if rising or self.read_mode != ReadMode.ONCE:
            self.value = axis.read_parameter(self.parameter_number, self.kind)
        self.done = True


class MC_ReadBoolParameter(MC_ReadParameter):
    """As MC_ReadParameter for BOOL parameters; ``value`` is a bool (D-006)."""

    kind: ClassVar[type] = bool


class MC_WriteParameter(EnableBlock):
    """Write ``value`` to LREAL parameter ``parameter_number`` while enabled."""

    INPUTS: ClassVar[dict[str, Any]] = {"parameter_number": 0, "value": 0.0}
    kind: ClassVar[type] = float

    def _enabled(self, axis: Axis, rising: bool) -> None:
        axis.write_parameter(self.parameter_number, self.value, self.kind)
        self.done = True


class MC_WriteBoolParameter(MC_WriteParameter):
    kind: ClassVar[type] = bool


class MC_ReadParameterSet(ExecuteBlock):
    """``parameter``: the whole parameter set of the axis as a dict (ST_AxisParameterSet)."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.parameter: dict[str, Any] = {}

    def _issue(self, axis: Axis) -> Command:
        command = Command("read_parameter_set", 0.0)
        command.value = asdict(axis.parameters)
        command.end(CommandStatus.DONE, 0.0)
        return command

    def _show_result(self, command: Command | None) -> None:
        if command is not None and command.done:
            self.parameter = dict(command.value)
