"""MC_GearInPosCA and its options (TF5410 §9.1.1.1.4, §9.1.2.1)."""

# ruff: noqa: N801 - the manual's names
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE, MC_INVALID, InputValue
from openmotion.transport.blocks import _ContinuousUpdate, _group_of
from openmotion.transport.enums import (
    GapControlMode,
    MasterSignalCorrection,
    SyncMode,
    SyncStrategy,
)


@dataclass(frozen=True)
class ST_GearInPosCAOptions:
    """Options of MC_GearInPosCA (§9.1.2.1), with the manual's defaults.

    MinimalSlavePosition, DirectionReversalAllowed and the master velocity under/overshoot
    flags hold for the profile the slave drives: when the fastest (or the strategy's timed)
    profile breaks one, the slave holds at rest and syncs once a compliant profile fits;
    SYNC_FAILED only when holding cannot lead to one (the manual's "synchronisation
    impossible", D-204). Both flags FALSE is an error at once, as the manual says.
    Reference systems other than 0 need geo-compensation.
    """

    after_sync_velocity: InputValue = MC_DEFAULT
    after_sync_acceleration: InputValue = MC_DEFAULT
    after_sync_deceleration: InputValue = MC_DEFAULT
    after_sync_jerk: InputValue = MC_DEFAULT
    master_velocity_undershoot_allowed: bool = True
    master_velocity_overshoot_allowed: bool = True
    minimal_slave_position: InputValue = MC_IGNORE
    direction_reversal_allowed: bool = True
    override_slave_dynamic_restrictions: bool = False
    gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT
    slave_sync_position_reference_system: int = 0
    dynamics_reference_system: int = 0
    master_signal_correction: MasterSignalCorrection = MasterSignalCorrection.AUTO  #: D-205


class MC_GearInPosCA(_ContinuousUpdate):
    """Couple a CA group member (the slave, given first) to ``master`` under collision
    avoidance (§9.1.1.1.4).

    Inputs: execute, continuous_update (gap only), master (any axis: its *set* values count),
    ratio_numerator (any real), ratio_denominator (UINT > 0), master_sync_position,
    slave_sync_position (MC_INVALID: must be set), sync_strategy (``SyncStrategy``: LATE,
    SLOW, EARLY), sync_mode (``SyncMode``), master_start_distance (MC_IGNORE: start when
    active; > 0: once master >= MSP - d; < 0: once master <= MSP - d), velocity,
    acceleration, deceleration, jerk (sync phase), gap, buffer_mode, options
    (``ST_GearInPosCAOptions``). Outputs: start_sync, in_sync, busy, active,
    command_aborted, error, error_id; there is no Done: another command decouples.
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "master": None, "ratio_numerator": 1.0, "ratio_denominator": 1,
        "master_sync_position": MC_INVALID, "slave_sync_position": MC_INVALID,
        "sync_strategy": SyncStrategy.LATE, "sync_mode": SyncMode.NON_MODULO,
        "master_start_distance": MC_IGNORE, "velocity": MC_INVALID,
        "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT,
        "gap": MC_DEFAULT, "buffer_mode": BufferMode.ABORTING,
        "options": ST_GearInPosCAOptions(),
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.start_sync = False
        self.in_sync = False

    def _issue(self, axis: Axis) -> Command:
        options = self.options
        if not isinstance(options, ST_GearInPosCAOptions):
            raise TypeError("MC_GearInPosCA.options must be a ST_GearInPosCAOptions, "
                            f"got {type(options).__name__}")
        if not isinstance(self.master, Axis):
            raise CommandRejected(ErrorId.INVALID_PARAMETER_VALUE,
                                  "master: an axis is needed")
        self._group = _group_of(axis)
        return self._group.gear_in_pos(
            self.master, axis, self.ratio_numerator, self.ratio_denominator,
            self.master_sync_position, self.slave_sync_position, self.sync_strategy,
            self.sync_mode, self.master_start_distance, self.velocity, self.acceleration,
            self.deceleration, self.jerk, self.gap, self.buffer_mode, options.after_sync_velocity,
            options.after_sync_acceleration, options.after_sync_deceleration,
            options.after_sync_jerk, options.master_velocity_undershoot_allowed,
            options.master_velocity_overshoot_allowed, options.minimal_slave_position,
            options.direction_reversal_allowed, options.override_slave_dynamic_restrictions,
            options.gap_control_mode, self.continuous_update, options.master_signal_correction,
            options.slave_sync_position_reference_system, options.dynamics_reference_system)

    def _show_progress(self, command: Command) -> None:
        super()._show_progress(command)
        if self._group is not None:
            self.start_sync, self.in_sync = self._group.sync_state(command)

    def _show_result(self, command: Command | None) -> None:
        super()._show_result(command)
        self.start_sync = self.in_sync = False
