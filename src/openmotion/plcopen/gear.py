"""Gear coupling blocks (TcMC §3.17-3.21). Call them on the slave: ``gear(slave, master=m)``."""

from __future__ import annotations

import math
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import DecoupleMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.kernel.handshake import ExecuteBlock


class _Coupling(ExecuteBlock):
    """``in_gear`` while the coupling holds; ``done`` does not exist on these blocks."""

    INPUTS: ClassVar[dict[str, Any]] = {"master": None}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.in_gear = False

    def _show_progress(self, command: Command) -> None:
        self.in_gear = command.active

    def _show_result(self, command: Command | None) -> None:
        self.in_gear = self.done = False

    def _master(self) -> Axis:
        if not isinstance(self.master, Axis):
            raise CommandRejected(ErrorId.INVALID_MODE, "input master: give the master axis")
        return self.master


class MC_GearIn(_Coupling):
    """Couple at standstill with ratio ``ratio_numerator / ratio_denominator`` (TcMC §3.17).

    ``acceleration``, ``deceleration`` and ``jerk`` are accepted and unused, as in TcMC.
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "ratio_numerator": 1, "ratio_denominator": 1, "acceleration": 0.0,
        "deceleration": 0.0, "jerk": 0.0,
    }

    def _issue(self, axis: Axis) -> Command:
        numerator, denominator = self.ratio_numerator, self.ratio_denominator
        if not (isinstance(numerator, int) and isinstance(denominator, int)) or isinstance(
                numerator, bool) or denominator <= 0:
            raise CommandRejected(ErrorId.INVALID_GEAR_RATIO,
                                  f"ratio {numerator!r}/{denominator!r}: integers, denominator "
                                  "> 0 (INT / UINT)")
        return axis.gear_in(self._master(), numerator / denominator)


class MC_GearInFloat(_Coupling):
    """Couple at standstill with the real ratio ``gear_ratio`` (TcMC §3.18)."""

    INPUTS: ClassVar[dict[str, Any]] = {
        "gear_ratio": 1.0, "acceleration": 0.0, "deceleration": 0.0, "jerk": 0.0,
    }

    def _issue(self, axis: Axis) -> Command:
        return axis.gear_in(self._master(), self.gear_ratio)


class MC_GearInDyn(_Coupling):
    """Couple at standstill; ``gear_ratio`` is re-read every call while ``execute`` is TRUE,
    its changes limited by ``acceleration`` (TcMC §3.19).

    The falling edge finishes the block: Busy and InGear fall, the updates stop and the
    coupling keeps its last ratio. A new rising edge on a slave still coupled to the same
    master takes that coupling over and goes on updating the ratio (D-196).
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "gear_ratio": 1.0, "acceleration": MC_DEFAULT, "deceleration": 0.0, "jerk": 0.0,
    }

    def _issue(self, axis: Axis) -> Command:
        master = self._master()
        running = axis.dynamic_coupling(master)
        if running is None:
            return axis.gear_in(master, self.gear_ratio, self.acceleration)
        for change in (axis.set_gear_acceleration(self.acceleration),
                       axis.set_gear_ratio(self.gear_ratio)):
            if change.error:  # a bad input refuses the edge; the coupling goes on as it was
                raise CommandRejected(change.error_id, change.message)
        return running

    def _falling_edge(self) -> None:
        command = self._command
        if command is not None and not command.finished:  # finished; the coupling stays
            self._clear()
            self._show_result(None)
            self._command = None

    def _show_progress(self, command: Command) -> None:
        super()._show_progress(command)
        if self.execute and command.active and not (
                isinstance(self.gear_ratio, int | float) and not math.isfinite(self.gear_ratio)):
            self._axis().set_gear_ratio(self.gear_ratio)


class MC_GearOut(ExecuteBlock):
    """Decouple; a moving slave keeps its velocity until another command (TcMC §3.20)."""

    def _issue(self, axis: Axis) -> Command:
        return axis.gear_out()


class MC_GearOutExt(ExecuteBlock):
    """Decouple, then the follow-up ``mode`` (E_DecoupleMode) if moving (TcMC §3.21).

    Done once decoupled and the follow-up holds its target position or velocity.
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "mode": DecoupleMode.ENDLESS, "position": MC_INVALID, "velocity": MC_INVALID,
        "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT,
    }

    def _issue(self, axis: Axis) -> Command:
        return axis.gear_out_ext(self.mode, self.position, self.velocity, self.acceleration,
                                 self.deceleration, self.jerk)

    def _show_progress(self, command: Command) -> None:
        if command.in_velocity:  # an endless follow-up is done at its constant velocity
            self.busy, self.active, self.done = False, False, True
