"""MC_PowerStepper (TcMC §4.23, §4.23.1, §6.6-6.8; rules 136-141).

MC_Power plus stall detection and handling for stepper motors on a KL2531/KL2541 terminal.
The block is evaluated once per PLC cycle; it decides on what it sees at its call (the
following error of the last motion step, the status bits passed in).

Detection (``DestallDetectMode``, only while ``DestallEnable`` and the axis is powered and not
in ErrorStop):

* ``ENCODERLESS``: any of bits 1-3 of ``kl_status`` (§6.8). The terminal has filtered already,
  so the first call that sees a bit detects the stall.
* ``LAGGING``: ``|following error| > max_position_lag`` (1020) on consecutive calls for longer
  than ``position_lag_filter_time`` (1021), counted like the NC's own monitoring (which is to
  be switched off, 1019 FALSE, §4.23.1).

Handling (``DestallMode``):

* ``SET_ERROR``: axis error 16#4636 (ErrorStop, controlled stop, the commands are aborted).
* ``SET_ERR_NON_REF``: as SET_ERROR, and the axis is no longer homed.
* ``USE_OVERRIDE``: the override passed to MC_Power becomes 0 (the profile freezes; the job
  stays, no state changes) until the following error is back within 1020 (and, when detected
  by ENCODERLESS, the stall bits are clear); then the application's ``override`` is written
  again (Q31) and the remaining distance runs to the original target.

``StatusMonEnable``: bit 6 (ERROR) of ``kl_status`` or any of bits 0-7 of ``kl_status2`` is
reported as an axis error ``DRIVE_NOT_READY`` (openmotion.axis.stepper documents the bits).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.stepper import STATUS2_ERROR_MASK, STATUS_ERROR, STATUS_STALL_BITS
from openmotion.core.enums import AxisState
from openmotion.core.errors import ErrorId
from openmotion.kernel.handshake import FunctionBlock
from openmotion.plcopen.power import MC_Power


class DestallMode(IntEnum):
    """E_DestallMode (TcMC §6.7)."""

    NONE = 0
    SET_ERROR = 1
    SET_ERR_NON_REF = 2
    USE_OVERRIDE = 3


class DestallDetectMode(IntEnum):
    """E_DestallDetectMode (TcMC §6.8)."""

    NONE = 0
    ENCODERLESS = 1
    LAGGING = 2


@dataclass
class PowerStepperParams:
    """ST_PowerStepperStruct (TcMC §6.6)."""

    destall_detect_mode: DestallDetectMode = DestallDetectMode.NONE
    destall_mode: DestallMode = DestallMode.NONE
    destall_enable: bool = False
    status_mon_enable: bool = False


class MC_PowerStepper(FunctionBlock):
    """Enables and override like MC_Power, plus stepper stall detection and handling."""

    INPUTS: ClassVar[dict[str, Any]] = {
        "enable": False, "enable_positive": True, "enable_negative": True, "override": 100.0,
        "destall_params": None, "kl_status": 0, "kl_status2": 0,
    }

    def __init__(self, axis: Axis | None = None, **inputs: Any) -> None:
        super().__init__(axis, **inputs)
        if self.destall_params is None:
            self.destall_params = PowerStepperParams()  # one per block: safe to mutate

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.status = False
        self.stall_detected = False  #: the stall condition of this call (diagnostic output)
        self.override_held = False  #: USE_OVERRIDE holds the profile with override 0
        self._power = MC_Power()
        self._lag_since: float | None = None

    def __call__(self, axis: Axis | None = None, /, **inputs: Any) -> None:
        if inputs:
            self._set_inputs(inputs)
        if axis is not None:
            self.axis = axis
        axis = self._axis()
        problem = self._check_inputs()
        params = self.destall_params if problem is None else PowerStepperParams()
        status_byte = int(self.kl_status) if problem is None else 0
        status_word = int(self.kl_status2) if problem is None else 0

        watching = axis.powered and axis.state is not AxisState.ERROR_STOP
        active = bool(params.destall_enable) and watching
        detect = DestallDetectMode(params.destall_detect_mode)
        mode = DestallMode(params.destall_mode)
        stalled = active and self._stalled(axis, detect, status_byte)
        if not (active and detect is DestallDetectMode.LAGGING):
            self._lag_since = None
        self.stall_detected = stalled

        if active and mode is DestallMode.USE_OVERRIDE:
            if stalled:
                self.override_held = True
            elif self.override_held and self._recovered(axis, detect, status_byte):
                self.override_held = False
                self._lag_since = None  # a new stall needs the full filter time again
        else:
            self.override_held = False

        power = self._power
        power(axis, enable=self.enable, enable_positive=self.enable_positive,
              enable_negative=self.enable_negative,
              override=0.0 if self.override_held else self.override)
        self.status = power.status
        self.error, self.error_id, self.message = power.error, power.error_id, power.message
        if problem is not None:
            self.error, self.error_id, self.message = True, problem[0], problem[1]

        if stalled and mode in (DestallMode.SET_ERROR, DestallMode.SET_ERR_NON_REF):
            axis.fault(ErrorId.STEPPER_STALL, f"MC_PowerStepper(AxId:={int(axis.axis_id)}) "
                                               "reporting error 0x4636 (stall error)!")
            if mode is DestallMode.SET_ERR_NON_REF:
                axis.homed = False
            self._lag_since = None
        if params.status_mon_enable and watching:
            errors = status_word & STATUS2_ERROR_MASK
            if errors or status_byte & STATUS_ERROR:
                axis.fault(ErrorId.DRIVE_NOT_READY,
                            f"MC_PowerStepper(AxId:={int(axis.axis_id)}): terminal error, "
                            f"KL_Status 16#{status_byte:02X}, KL_Status2 16#{status_word:04X}")

    # -- internals ---------------------------------------------------------------------------

    def _check_inputs(self) -> tuple[ErrorId, str] | None:
        params = self.destall_params
        if not isinstance(params, PowerStepperParams):
            return ErrorId.INVALID_MODE, f"destall_params must be PowerStepperParams, " \
                                         f"got {params!r}"
        for enum, value in ((DestallDetectMode, params.destall_detect_mode),
                            (DestallMode, params.destall_mode)):
            if isinstance(value, bool) or value not in set(enum):
                return ErrorId.INVALID_MODE, f"not an {enum.__name__}: {value!r}"
        for name, limit in (("kl_status", 0xFF), ("kl_status2", 0xFFFF)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= limit:
                return ErrorId.INVALID_PARAMETER_VALUE, \
                    f"{name} must be an integer 0..{limit}, got {value!r}"
        return None

    def _stalled(self, axis: Axis, detect: DestallDetectMode, status_byte: int) -> bool:
        if detect is DestallDetectMode.ENCODERLESS:
            return bool(status_byte & STATUS_STALL_BITS)
        if detect is DestallDetectMode.LAGGING:
            p = axis.parameters
            if abs(axis.following_error) <= p.max_position_lag:
                self._lag_since = None
                return False
            now = axis.runtime.now
            if self._lag_since is None:
                self._lag_since = now
            # the kernel's timer counts the first cycle over the limit as one cycle time
            over_for = now - self._lag_since + axis.runtime.cycle_time
            return over_for > p.position_lag_filter_time + 1e-12
        return False

    def _recovered(self, axis: Axis, detect: DestallDetectMode, status_byte: int) -> bool:
        if detect is DestallDetectMode.ENCODERLESS and status_byte & STATUS_STALL_BITS:
            return False
        return abs(axis.following_error) <= axis.parameters.max_position_lag
