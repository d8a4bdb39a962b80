"""Level-triggered read blocks (TcMC §4.3-4.5)."""

from __future__ import annotations

from openmotion.axis.axis import Axis
from openmotion.core.enums import AxisState
from openmotion.core.errors import ErrorId
from openmotion.kernel.handshake import EnableBlock


class MC_ReadActualPosition(EnableBlock):
    """``position``: the actual position [mm] while enabled."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.position = 0.0

    def _enabled(self, axis: Axis, rising: bool) -> None:
        self.position = axis.position
        self.done = True


class MC_ReadStatus(EnableBlock):
    """The PLCopen state as flags, plus the profile sub-states (TcMC §4.4).

    ``homing`` is TRUE once the axis is referenced, as §4.4 defines it (D-192);
    ``homing_busy`` (the Homing state, a reference search running) and ``disabled``
    are our additions, so every state has exactly one flag.
    """

    #: its status outputs, the state flags first
    FLAGS = ("error_stop", "disabled", "stopping", "standstill", "discrete_motion",
             "continuous_motion", "synchronized_motion", "homing_busy", "homing",
             "constant_velocity", "accelerating", "decelerating")
    _STATE_FLAG = {
        AxisState.ERROR_STOP: "error_stop", AxisState.DISABLED: "disabled",
        AxisState.STOPPING: "stopping", AxisState.STANDSTILL: "standstill",
        AxisState.DISCRETE_MOTION: "discrete_motion",
        AxisState.CONTINUOUS_MOTION: "continuous_motion",
        AxisState.SYNCHRONIZED_MOTION: "synchronized_motion", AxisState.HOMING: "homing_busy",
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        for flag in self.FLAGS:
            setattr(self, flag, False)

    def _enabled(self, axis: Axis, rising: bool) -> None:
        for flag in self.FLAGS:
            setattr(self, flag, False)
        setattr(self, self._STATE_FLAG[axis.state], True)
        self.homing = axis.homed
        v, a = axis.set_velocity, axis.set_acceleration
        moving = v != 0.0
        self.constant_velocity = moving and a == 0.0
        self.accelerating = moving and a * v > 0.0
        self.decelerating = moving and a * v < 0.0
        self.done = True

    def _disabled(self) -> None:
        super()._disabled()
        self._reset_outputs()


class MC_ReadAxisError(EnableBlock):
    """``axis_error_id``: the axis error behind ErrorStop (PLCopen's AxisErrorID, D-012)."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.axis_error_id = ErrorId.NO_ERROR
        self.axis_error_message = ""

    def _enabled(self, axis: Axis, rising: bool) -> None:
        self.axis_error_id = axis.axis_error_id
        self.axis_error_message = axis.axis_error_message
        self.done = True
