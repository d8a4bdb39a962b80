"""Positioning and velocity blocks (TcMC §3.1-3.6, with PLCopen Part 1 BufferMode)."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import BufferMode, Direction
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.kernel.handshake import ExecuteBlock

_DYNAMICS: dict[str, Any] = {
    "velocity": MC_INVALID,
    "acceleration": MC_DEFAULT,
    "deceleration": MC_DEFAULT,
    "jerk": MC_DEFAULT,
    "buffer_mode": BufferMode.ABORTING,
}


class MC_MoveAbsolute(ExecuteBlock):
    """Move to an absolute ``position`` [mm] at up to ``velocity`` [mm/s] (TcMC §3.1).

    Inputs: execute, position, velocity (> 0), acceleration, deceleration, jerk (0 or
    MC_DEFAULT = axis default, MC_MAXIMUM = axis maximum), buffer_mode.
    Outputs: done (target reached, §7.1 windows), busy, active, command_aborted, error,
    error_id.

    >>> import openmotion as om
    >>> rt = om.Runtime(); x = rt.add_axis("x"); x.power()
    True
    >>> move = MC_MoveAbsolute(x)
    >>> while not move.done:
    ...     move(execute=True, position=100.0, velocity=250.0); rt.step()
    >>> x.set_position
    100.0
    """

    INPUTS: ClassVar[dict[str, Any]] = {"position": MC_INVALID, **_DYNAMICS}

    def _issue(self, axis: Axis) -> Command:
        return axis.move_absolute(self.position, self.velocity, self.acceleration,
                                  self.deceleration, self.jerk, self.buffer_mode)


class MC_MoveRelative(ExecuteBlock):
    """Move ``distance`` [mm] from the set position at the start (TcMC §3.2, §3.5)."""

    INPUTS: ClassVar[dict[str, Any]] = {"distance": MC_INVALID, **_DYNAMICS}

    def _issue(self, axis: Axis) -> Command:
        return axis.move_relative(self.distance, self.velocity, self.acceleration,
                                  self.deceleration, self.jerk, self.buffer_mode)


class MC_MoveModulo(ExecuteBlock):
    """Modulo positioning with direction and tolerance window (TcMC §3.4, §3.5).

    ``position`` in [0, period) is reached in less than a turn; each full period more adds
    a turn. MC_Shortest_Way accepts only targets inside [0, period).
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "position": MC_INVALID, "direction": Direction.POSITIVE, **_DYNAMICS,
    }

    def _issue(self, axis: Axis) -> Command:
        return axis.move_modulo(self.position, self.velocity, self.direction, self.acceleration,
                                self.deceleration, self.jerk, self.buffer_mode)


class MC_MoveVelocity(ExecuteBlock):
    """Endless motion at ``velocity`` [mm/s] in ``direction`` (TcMC §3.3).

    ``in_velocity`` is TRUE while the commanded velocity is held. The command never ends Done
    by itself: a command buffered behind it takes over at InVelocity and it shows
    CommandAborted (D-178); ``done`` rises only when MC_NewPos turned it into a positioning
    that reached its target (D-015).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"direction": Direction.POSITIVE, **_DYNAMICS}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.in_velocity = False

    def _issue(self, axis: Axis) -> Command:
        return axis.move_velocity(self.velocity, self.direction, self.acceleration,
                                  self.deceleration, self.jerk, self.buffer_mode)

    def _show_progress(self, command: Command) -> None:
        self.in_velocity = command.in_velocity

    def _show_result(self, command: Command | None) -> None:
        self.in_velocity = False


class MC_MoveAbsoluteOrRestart(MC_MoveAbsolute):
    """MC_MoveAbsolute whose new rising edge retargets the running move (TcMC §3.6).

    On a restart only ``position`` and ``velocity`` change; the dynamics of the start stay.
    """

    retriggerable: ClassVar[bool] = True

    def _retrigger(self, command: Command) -> bool:
        return self._axis().restart(command, self.position, self.velocity)
