"""MC_TouchProbe and MC_AbortTrigger (TcMC §4.21, §4.22; structures §6.3).

The probe cycle runs in the runtime after each motion step, so the latch catches its edge
even in cycles where the FB is not called. A cycle ends only with Done, Error or
CommandAborted; dropping Execute does not end it, and a new Execute edge of the same instance
while it is armed is ignored (Busy gate). MC_AbortTrigger with the same InputRef object
disarms it.
"""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.axis.probe import (
    InputRef,
    SignalEdge,
    TouchProbeSource,
    TouchProbeState,
    abort_probe,
    arm_probe,
)
from openmotion.kernel.handshake import ExecuteBlock

__all__ = [
    "InputRef", "MC_AbortTrigger", "MC_TouchProbe", "SignalEdge", "TouchProbeSource",
    "TouchProbeState",
]


def _trigger_input(block: ExecuteBlock) -> InputRef:
    ref = block.trigger_input  # type: ignore[attr-defined]
    if not isinstance(ref, InputRef):
        raise TypeError(f"{type(block).__name__} needs trigger_input=InputRef(...), got {ref!r}")
    return ref


class MC_TouchProbe(ExecuteBlock):
    """Record the axis position at a probe edge (TcMC §4.21).

    ``recorded_position`` is 0.0 from the accepted Execute edge until Done, then holds the
    recorded value (modulo the axis period when ``trigger_input.modulo_positions``).
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "window_only": False, "first_position": 0.0, "last_position": 0.0,
        "trigger_input": None,
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.recorded_position = 0.0

    def _rising_edge(self) -> None:
        command = self._command
        if command is not None and command.busy:
            return  # still armed: only MC_AbortTrigger ends the cycle (§4.21 note)
        super()._rising_edge()

    def _issue(self, axis: Axis) -> Command:
        self.recorded_position = 0.0
        return arm_probe(axis, _trigger_input(self), bool(self.window_only),
                         self.first_position, self.last_position)

    def _show_result(self, command: Command | None) -> None:
        if command is not None and command.done:
            self.recorded_position = float(command.value)  # type: ignore[arg-type]


class MC_AbortTrigger(ExecuteBlock):
    """Disarm the probe cycle armed on the same ``trigger_input`` (TcMC §4.22).

    Done also when no cycle is armed (nothing to interrupt, §4.22: not needed after a
    successful cycle).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"trigger_input": None}

    def _issue(self, axis: Axis) -> Command:
        ref = _trigger_input(self)
        now = axis.runtime.now
        command = Command("abort_trigger", now)
        abort_probe(ref, now)
        if ref.probe_state is TouchProbeState.ACTIVATED:  # written by the user: repair it
            ref.probe_state = TouchProbeState.INACTIVE
        command.end(CommandStatus.DONE, now)
        return command
