"""MC_Jog: manual jogging with two keys (TcMC §3.13; digest rules 54-63).

A rising edge of ``jog_forward`` starts positive motion, of ``jog_backwards`` negative motion;
edges on both inputs in the same call start forward motion. While the block is busy, edges on
either input are ignored (not queued); ``busy`` falls only once the axis is at rest and the
block is back in its initial state, and only then is the next edge accepted.

* STANDARD_SLOW / STANDARD_FAST: move at the axis' manual slow / fast velocity (parameters
  1010 / 1009, aliases 1001 / 1002) with the axis' default dynamics while the initiating input
  stays TRUE; the FB's position, velocity and dynamics inputs have no effect.
* CONTINUOUS: the same with the FB's ``velocity`` (> 0) and dynamics (0 or MC_DEFAULT = axis
  default); ``position`` has no effect.
* INCHING: each accepted rising edge moves by ``position`` (relative; forward +|position|,
  backwards -|position|) with the FB's velocity and dynamics and stops there, whatever the
  input level. ``position`` = MC_DEFAULT takes the axis' jog increments (1013 / 1014).

In the level modes the falling edge of the initiating input brakes the axis with MC_Halt
semantics (the jog's deceleration and jerk), not MC_Stop: a stop would lock the axis in
Stopping, which a released jog key must not do. ``done`` is reported once the axis is at rest.
Another command that replaces the jog motion (MC_Stop, a move of another block) gives
``command_aborted``. ``done``, ``command_aborted`` and ``error`` stay TRUE while the initiating
input stays TRUE and show for exactly one call otherwise (as Execute blocks, handshake.py).

>>> import openmotion as om
>>> rt = om.Runtime(); x = rt.add_axis("x"); x.power()
True
>>> jog = MC_Jog(x, mode=JogMode.INCHING, position=2.5, velocity=50.0)
>>> jog(jog_forward=True); rt.step()
>>> while jog.busy:
...     jog(); rt.step()
>>> jog.done, x.set_position
(True, 2.5)
"""

from __future__ import annotations

from enum import IntEnum
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.enums import Direction
from openmotion.core.errors import ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID, InputValue
from openmotion.kernel.handshake import FunctionBlock

_NO_ERROR = ErrorId.NO_ERROR


class JogMode(IntEnum):
    """E_JogMode (TcMC §3.13); numeric values as in Tc2_MC2 (the manual gives none)."""

    STANDARD_SLOW = 0
    STANDARD_FAST = 1
    CONTINUOUS = 2
    CONTINOUS = 2  # Beckhoff's spelling MC_JOGMODE_CONTINOUS (an alias of CONTINUOUS)
    INCHING = 3


_IDLE, _MOVING, _BRAKING = 0, 1, 2


class MC_Jog(FunctionBlock):
    """Jog an axis with ``jog_forward`` / ``jog_backwards`` keys (TcMC §3.13).

    Inputs: jog_forward, jog_backwards, mode (JogMode), position (INCHING step [mm]),
    velocity (> 0; CONTINUOUS / INCHING), acceleration, deceleration, jerk (0 or MC_DEFAULT =
    axis default). Outputs: done, busy, active, command_aborted, error, error_id, message.
    The velocity, dynamics and step are taken at the accepted edge; later changes are ignored
    until the next accepted edge.
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "jog_forward": False,
        "jog_backwards": False,
        "mode": JogMode.STANDARD_SLOW,
        "position": MC_DEFAULT,
        "velocity": MC_INVALID,
        "acceleration": MC_DEFAULT,
        "deceleration": MC_DEFAULT,
        "jerk": MC_DEFAULT,
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.done = False
        self.busy = False
        self.active = False
        self.command_aborted = False
        self._command: Command | None = None
        self._phase = _IDLE
        self._level_mode = False  # the motion lasts while the initiating input is TRUE
        self._initiator = "jog_forward"
        self._halt_dynamics: tuple[InputValue, InputValue] = (MC_DEFAULT, MC_DEFAULT)
        self._shown = False
        self._last_forward = False
        self._last_backwards = False

    @property
    def command(self) -> Command | None:
        """The axis command behind the outputs: the jog move, then the braking halt."""
        return self._command

    def __call__(self, axis: Axis | None = None, /, **inputs: Any) -> None:
        if inputs:
            self._set_inputs(inputs)
        if axis is not None:
            self.axis = axis
        forward, backwards = bool(self.jog_forward), bool(self.jog_backwards)
        rise_forward = forward and not self._last_forward
        rise_backwards = backwards and not self._last_backwards
        self._last_forward, self._last_backwards = forward, backwards
        # the busy gate: an edge counts only if the block was not busy when it came (§3.13)
        if (rise_forward or rise_backwards) and not self.busy:
            self._start(forward=rise_forward)  # both edges at once: forward wins
        self._refresh()
        if self.strict:
            self._check_invariants()

    # -- starting ----------------------------------------------------------------------------

    def _start(self, forward: bool) -> None:
        self._clear()
        axis = self._axis()
        self._initiator = "jog_forward" if forward else "jog_backwards"
        direction = Direction.POSITIVE if forward else Direction.NEGATIVE
        mode = self.mode
        try:
            if isinstance(mode, bool):
                raise ValueError(mode)
            mode = JogMode(mode)
        except (ValueError, TypeError):
            self._fail(ErrorId.INVALID_MODE, f"mode {mode!r} is not an E_JogMode")
            return
        p = axis.parameters
        self._phase = _MOVING
        if mode is JogMode.INCHING:
            self._level_mode = False
            self._command = axis.move_relative(self._step(forward, axis), self.velocity,
                                               self.acceleration, self.deceleration, self.jerk)
            return
        self._level_mode = True
        if mode is JogMode.CONTINUOUS:
            self._halt_dynamics = (self.deceleration, self.jerk)
            self._command = axis.move_velocity(self.velocity, direction, self.acceleration,
                                               self.deceleration, self.jerk)
            return
        velocity = (p.manual_velocity_slow if mode is JogMode.STANDARD_SLOW
                    else p.manual_velocity_fast)
        self._halt_dynamics = (MC_DEFAULT, MC_DEFAULT)
        self._command = axis.move_velocity(velocity, direction, MC_DEFAULT, MC_DEFAULT,
                                           MC_DEFAULT)

    def _step(self, forward: bool, axis: Axis) -> InputValue:
        """The signed INCHING distance: +|position| forward, -|position| backwards."""
        step = self.position
        if step is MC_DEFAULT:
            p = axis.parameters
            step = p.jog_increment_forward if forward else p.jog_increment_backward
        if isinstance(step, int | float) and not isinstance(step, bool):
            return abs(float(step)) if forward else -abs(float(step))
        return step  # not a number: the axis rejects it with INVALID_POSITION

    def _fail(self, error_id: ErrorId, message: str) -> None:
        now = self._axis().runtime.now
        command = Command("MC_Jog", now)
        command.end(CommandStatus.ERROR, now, error_id, message)
        self._command = command
        self._phase = _MOVING

    # -- outputs -----------------------------------------------------------------------------

    def _refresh(self) -> None:
        command = self._command
        if command is None:
            return
        level = bool(getattr(self, self._initiator))
        if self._phase == _MOVING and self._level_mode and not level and not command.finished:
            # the key was released: brake to rest, leaving the axis free for other commands
            deceleration, jerk = self._halt_dynamics
            command = self._command = self._axis().halt(deceleration, jerk)
            self._phase = _BRAKING
        if not command.finished:
            self.busy = True
            self.active = command.active
            return
        if not self._shown:
            self._shown = True
            status = command.status
            self.busy = self.active = False
            self.done = status is CommandStatus.DONE
            self.command_aborted = status is CommandStatus.ABORTED
            self.error = status is CommandStatus.ERROR
            self.error_id = command.error_id if self.error else _NO_ERROR
            self.message = command.message
        elif not level:
            self._clear()
            self._command = None
            self._phase = _IDLE

    def _clear(self) -> None:
        self.done = self.busy = self.active = self.command_aborted = self.error = False
        self.error_id = _NO_ERROR
        self.message = ""
        self._shown = False

    def _check_invariants(self) -> None:
        terminal = self.done + self.command_aborted + self.error
        assert terminal <= 1, "MC_Jog: more than one of done/aborted/error"
        assert not (self.busy and terminal), "MC_Jog: busy with a result"
        assert self.error or self.error_id == _NO_ERROR, "MC_Jog: error_id without error"
