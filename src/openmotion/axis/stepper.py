"""A simulated KL2531/KL2541 stepper-motor terminal attached to an axis (TcMC §4.23).

The terminal only produces what MC_PowerStepper reads: the status byte (``KL_Status``, USINT)
and the status word (``KL_Status2``, UINT). A stall blocks the axis' mechanics in the kernel
(the actual position stops following the setpoint) and sets the stall bits 1-3 of the status
byte while it lasts. Everything runs on virtual time, so a stall of a given duration ends in
the same cycle on every run.

Bit layout (a simulator convention, see docs/decisions.md "MC_PowerStepper terminal bits";
the TcMC manual names only bits 1-3 of the status byte, §6.8):

=========  ==================================================================================
status     bit 0 READY (terminal ready), bits 1-3 STALL (set while stalled), bit 6 ERROR
           (set while any error bit of ``status2`` is set)
status2    bits 0-7 error bits (:data:`STATUS2_ERROR_MASK`: over-current A/B, open load A/B,
           under-voltage, over-temperature, ...), bits 8-15 warnings (not reported)
=========  ==================================================================================
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from openmotion.axis.tolerances import TIME_TOLERANCE

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

STATUS_READY = 0x01  #: status byte bit 0: the terminal is ready
STATUS_STALL_BITS = 0x0E  #: status byte bits 1-3: stall (PwStDetectMode_Encoderless, §6.8)
STATUS_ERROR = 0x40  #: status byte bit 6: an error bit of the status word is set
STATUS2_ERROR_MASK = 0x00FF  #: status word bits 0-7: terminal errors (StatusMonEnable)

STATUS2_OVERCURRENT_A = 0x0001
STATUS2_OVERCURRENT_B = 0x0002
STATUS2_OPEN_LOAD_A = 0x0004
STATUS2_OPEN_LOAD_B = 0x0008
STATUS2_UNDERVOLTAGE = 0x0010
STATUS2_OVERTEMPERATURE = 0x0020


class StepperTerminal:
    """KL2531/KL2541 simulation for one axis: stall injection and the status bits."""

    def __init__(self, axis: Axis) -> None:
        self.axis = axis
        self.stalled = False
        self._status2 = 0
        self._stall_serial = 0  #: tells a timed release which stall it belongs to

    # -- process image -----------------------------------------------------------------------

    @property
    def status(self) -> int:
        """The status byte (USINT) as MC_PowerStepper.KL_Status reads it."""
        value = STATUS_READY
        if self.stalled:
            value |= STATUS_STALL_BITS
        if self._status2 & STATUS2_ERROR_MASK:
            value |= STATUS_ERROR
        return value

    @property
    def status2(self) -> int:
        """The status word (UINT) as MC_PowerStepper.KL_Status2 reads it."""
        return self._status2

    # -- faults ------------------------------------------------------------------------------

    def inject_stall(self, duration: float | None = None) -> None:
        """Block the mechanics and set the stall bits; ``duration`` [s] ends it by itself.

        A timed stall is released by the motion step at the first instant ``now`` with
        ``now >= start + duration`` (virtual time, whole cycles).
        """
        if duration is not None and not (isinstance(duration, int | float) and duration >= 0.0):
            raise ValueError(f"duration: must be a number >= 0 or None, got {duration!r}")
        axis = self.axis
        self._stall_serial += 1
        serial = self._stall_serial
        self.stalled = True
        axis.kernel.set_blocked(axis.row, True)
        if duration is None:
            return
        end = axis.runtime.now + float(duration)
        eps = TIME_TOLERANCE * max(1.0, abs(end))

        def release_when_due(now: float) -> bool:
            if serial != self._stall_serial or not self.stalled:
                return False  # released or re-stalled meanwhile
            if now + eps >= end:
                self.release()
                return False
            return True

        axis.system.watch(axis, release_when_due)

    def release(self) -> None:
        """End a stall: the mechanics follow again, the stall bits clear."""
        self.stalled = False
        self._stall_serial += 1
        self.axis.kernel.set_blocked(self.axis.row, False)

    def set_error(self, bits: int) -> None:
        """Set bits of the status word (e.g. :data:`STATUS2_OVERTEMPERATURE`)."""
        self._status2 = (self._status2 | int(bits)) & 0xFFFF

    def clear_error(self, bits: int = 0xFFFF) -> None:
        """Clear bits of the status word (all by default)."""
        self._status2 &= ~int(bits) & 0xFFFF
