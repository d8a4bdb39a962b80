"""The parameters of a CA group with their defaults (TF5410 §6)."""

from __future__ import annotations

from dataclasses import dataclass, fields

from openmotion.core.checks import flag, non_negative_number, positive_number
from openmotion.core.errors import ConfigError
from openmotion.transport.enums import (
    GapControlDirection,
    GapControlMode,
    GearInPosDefaultDynamicsAfterSync,
)


@dataclass
class CaGroupParameters:
    """"Parameter (Init)" of a CA group (§6). Lengths in mm, dynamics in mm/s, mm/s², mm/s³."""

    rail_length: float = 3000.0  #: rail length, also the modulo factor of the movers [mm]
    rail_is_ring: bool = True  #: closed rail: the first mover keeps a gap to the last one
    default_gap_control_mode: GapControlMode = GapControlMode.STANDARD  #: STANDARD or FAST
    gap_control_direction: GapControlDirection = GapControlDirection.BOTH
    active_gap_establishing: bool = False  #: V3.3: FALSE = gap control only brakes
    standby_gap_control: bool = False  #: keep gaps on movers without a command as well
    default_gap: float = 100.0  #: gap of commands with Gap = MC_DEFAULT, and of standby [mm]
    default_velocity: float = 150.0  #: standby gap control only [mm/s]
    default_acceleration: float = 1000.0  #: standby gap control only [mm/s²]
    default_deceleration: float = 1000.0  #: standby gap control only [mm/s²]
    default_jerk: float = 10000.0  #: standby gap control only [mm/s³]
    gear_in_pos_default_dynamics_after_sync: GearInPosDefaultDynamicsAfterSync = (
        GearInPosDefaultDynamicsAfterSync.JOB_DYNAMICS)

    def validate(self) -> None:
        """``ConfigError`` (a ValueError) naming the first field that makes no sense."""
        for name in ("rail_length", "default_velocity", "default_acceleration",
                     "default_deceleration", "default_jerk"):
            positive_number(getattr(self, name), name)
        gap = non_negative_number(self.default_gap, "default_gap")
        if not gap < self.rail_length:
            raise ConfigError(f"default_gap: must be a number in [0, rail_length), got {gap!r}")
        for name in ("rail_is_ring", "active_gap_establishing", "standby_gap_control"):
            flag(getattr(self, name), name)
        mode = GapControlMode(self.default_gap_control_mode)
        if mode not in (GapControlMode.STANDARD, GapControlMode.FAST):
            raise ValueError(f"default_gap_control_mode: STANDARD or FAST, got {mode.name}")
        self.default_gap_control_mode = mode
        self.gap_control_direction = GapControlDirection(self.gap_control_direction)
        self.gear_in_pos_default_dynamics_after_sync = GearInPosDefaultDynamicsAfterSync(
            self.gear_in_pos_default_dynamics_after_sync)


PARAMETER_FIELDS = frozenset(f.name for f in fields(CaGroupParameters))
