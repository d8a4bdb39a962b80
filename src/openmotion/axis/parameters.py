"""Axis parameters modelled on MC_AxisPara (TcMC §6.1).

``AxisParameters`` is the configuration (the System Manager's axis dialog). Every parameter
number of §6.1 is reachable through ``PARAMETERS``: the attribute it maps to, its type and
unit, and whether it is read-only. Numbers 1-16 (PLCopen) alias Beckhoff numbers where both
name the same quantity (docs/decisions.md, D-006). Times are in seconds.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from enum import IntEnum

from openmotion.core.checks import (
    finite_number,
    finite_pair,
    flag,
    non_negative_number,
    positive_number,
)
from openmotion.core.enums import Direction, ReferenceMode
from openmotion.core.errors import ConfigError


@dataclass
class AxisParameters:
    """Configuration of one axis. Units: mm (or °), s."""

    max_velocity: float = 1000.0  #: physical maximum velocity [mm/s] (1003, 1007; PLCopen 8, 9)
    acceleration: float = 5000.0  #: default acceleration [mm/s²] (1004)
    deceleration: float = 5000.0  #: default deceleration [mm/s²] (1005)
    jerk: float = 50000.0  #: default jerk [mm/s³] (1006)
    max_acceleration: float = 20000.0  #: cap for acceleration inputs [mm/s²] (PLCopen 12, 13)
    max_deceleration: float = 20000.0  #: cap for deceleration inputs [mm/s²] (PLCopen 14, 15)
    max_jerk: float = 1.0e6  #: cap for jerk inputs [mm/s³] (PLCopen 16)
    rapid_traverse_velocity: float = 1000.0  #: [mm/s] (1008)
    manual_velocity_fast: float = 500.0  #: jog fast [mm/s] (1009, 1002)
    manual_velocity_slow: float = 100.0  #: jog slow [mm/s] (1010, 1001)
    calibration_velocity_forward: float = 100.0  #: homing, towards the cam [mm/s] (1011)
    calibration_velocity_backward: float = 10.0  #: homing, off the cam [mm/s] (1012)
    jog_increment_forward: float = 1.0  #: [mm] (1013)
    jog_increment_backward: float = 1.0  #: [mm] (1014)
    enable_min_soft_limit: bool = False  #: (1015; PLCopen 5)
    min_soft_limit: float = -1.0e6  #: [mm] (1016; PLCopen 3)
    enable_max_soft_limit: bool = False  #: (1017; PLCopen 4)
    max_soft_limit: float = 1.0e6  #: [mm] (1018; PLCopen 2)
    enable_position_lag_monitoring: bool = True  #: (1019; PLCopen 6)
    max_position_lag: float = 5.0  #: following-error limit [mm] (1020; PLCopen 7)
    position_lag_filter_time: float = 0.02  #: [s] (1021)
    enable_position_range_monitoring: bool = True  #: TcMC §7.1 (1022)
    position_range_window: float = 5.0  #: [mm] (1023)
    enable_target_position_monitoring: bool = True  #: TcMC §7.1 (1024)
    target_position_window: float = 2.0  #: [mm] (1025)
    target_position_monitoring_time: float = 0.02  #: [s] (1026)
    enable_in_target_timeout: bool = False  #: (1027)
    in_target_timeout: float = 5.0  #: [s] (1028)
    enable_motion_monitoring: bool = False  #: stored only (1029)
    motion_monitoring_window: float = 0.1  #: stored only [mm] (1030)
    motion_monitoring_time: float = 0.5  #: stored only [s] (1031)
    delay_time_velocity_position: float = 0.0  #: stored only [s] (1032)
    enable_looping_distance: bool = False  #: stored only (1033)
    looping_distance: float = 0.0  #: stored only [mm] (1034)
    enable_backlash_compensation: bool = False  #: stored only (1035)
    backlash: float = 0.0  #: stored only [mm] (1036)
    enable_data_persistence: bool = False  #: stored only (1037)
    reference_velocity_on_reference_output: float = 0.0  #: stored only (1038)
    override_type: float = 0.0  #: stored only (1039)
    encoder_scaling_factor: float = 1.0  #: stored only [mm/inc] (1040)
    encoder_offset: float = 0.0  #: stored only [mm] (1041)
    encoder_direction_inverse: bool = False  #: stored only (1042)
    encoder_mask: int = 0xFFFFFFFF  #: stored only (1043)
    modulo_period: float = 360.0  #: modulo factor [mm or °] (1044)
    modulo_tolerance_window: float = 0.0  #: TcMC §3.5 (1045)
    enable_actual_position_correction: bool = False  #: stored only (1046)
    actual_position_correction_filter_time: float = 0.0  #: stored only [s] (1047)
    unit_interpretation: float = 0.0  #: bit 2 = modulo flag; display only (1048)
    # configuration without a parameter number
    calibration_value: float = 0.0  #: position set by MC_Home with DEFAULT_HOME_POSITION [mm]
    reference_mode: ReferenceMode = ReferenceMode.CAM_AND_SYNC_PULSE
    homing_direction: Direction = Direction.NEGATIVE  #: towards the cam
    reference_cam: tuple[float, float] | None = None  #: simulated cam [from, to] in raw mm
    sync_pulse_distance: float = 10.0  #: raw distance between encoder sync pulses [mm]
    sync_pulse_offset: float = 0.0  #: raw position of one sync pulse [mm]

    def __post_init__(self) -> None:
        self.validate()

    def validate(self) -> None:
        """Raise ``ConfigError`` (a ``ValueError``) naming the first field that is out of
        range: every number must be a finite number (a bool is none), every flag a bool."""
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in _POSITIVE:
                positive_number(value, f.name)
            elif f.name in _NON_NEGATIVE:
                non_negative_number(value, f.name)
            elif f.type == "float":
                finite_number(value, f.name)
            elif f.type == "bool":
                flag(value, f.name)
        mask = self.encoder_mask
        if isinstance(mask, bool) or not isinstance(mask, int) or not 0 <= mask <= 0xFFFFFFFF:
            raise ConfigError(f"encoder_mask: must be a DWORD (0..2**32-1), got {mask!r}")
        if self.reference_cam is not None:
            finite_pair(self.reference_cam, "reference_cam")
        for name, kind in (("reference_mode", ReferenceMode), ("homing_direction", Direction)):
            if getattr(self, name) not in set(kind):
                raise ConfigError(f"{name}: must be a {kind.__name__}, got "
                                  f"{getattr(self, name)!r}")
        for name, maximum in (("acceleration", "max_acceleration"),
                              ("deceleration", "max_deceleration"), ("jerk", "max_jerk")):
            if getattr(self, name) > getattr(self, maximum):
                raise ConfigError(f"{name}: default {getattr(self, name)} exceeds {maximum}")
        if self.min_soft_limit >= self.max_soft_limit:
            raise ConfigError("min_soft_limit: must be below max_soft_limit")


_POSITIVE = frozenset((
    "max_velocity", "acceleration", "deceleration", "jerk", "max_acceleration",
    "max_deceleration", "max_jerk", "modulo_period", "sync_pulse_distance",
))
_NON_NEGATIVE = frozenset((
    "max_position_lag", "position_lag_filter_time", "position_range_window",
    "target_position_window", "target_position_monitoring_time", "in_target_timeout",
    "modulo_tolerance_window", "manual_velocity_fast", "manual_velocity_slow",
    "calibration_velocity_forward", "calibration_velocity_backward",
))


PARAMETER_FIELDS = {f.name for f in fields(AxisParameters)}


class AxisPara(IntEnum):
    """MC_AxisPara numbers (TcMC §6.1)."""

    CommandedPosition = 1
    SWLimitPos = 2
    SWLimitNeg = 3
    EnableLimitPos = 4
    EnableLimitNeg = 5
    EnablePosLagMonitoring = 6
    MaxPositionLag = 7
    MaxVelocitySystem = 8
    MaxVelocityAppl = 9
    ActualVelocity = 10
    CommandedVelocity = 11
    MaxAccelerationSystem = 12
    MaxAccelerationAppl = 13
    MaxDecelerationSystem = 14
    MaxDecelerationAppl = 15
    MaxJerk = 16
    AxisId = 1000
    AxisVeloManSlow = 1001
    AxisVeloManFast = 1002
    AxisVeloMax = 1003
    AxisAcc = 1004
    AxisDec = 1005
    AxisJerk = 1006
    AxisMaxVelocity = 1007
    AxisRapidTraverseVelocity = 1008
    AxisManualVelocityFast = 1009
    AxisManualVelocitySlow = 1010
    AxisCalibrationVelocityForward = 1011
    AxisCalibrationVelocityBackward = 1012
    AxisJogIncrementForward = 1013
    AxisJogIncrementBackward = 1014
    AxisEnMinSoftPosLimit = 1015
    AxisMinSoftPosLimit = 1016
    AxisEnMaxSoftPosLimit = 1017
    AxisMaxSoftPosLimit = 1018
    AxisEnPositionLagMonitoring = 1019
    AxisMaxPosLagValue = 1020
    AxisMaxPosLagFilterTime = 1021
    AxisEnPositionRangeMonitoring = 1022
    AxisPositionRangeWindow = 1023
    AxisEnTargetPositionMonitoring = 1024
    AxisTargetPositionWindow = 1025
    AxisTargetPositionMonitoringTime = 1026
    AxisEnInTargetTimeout = 1027
    AxisInTargetTimeout = 1028
    AxisEnMotionMonitoring = 1029
    AxisMotionMonitoringWindow = 1030
    AxisMotionMonitoringTime = 1031
    AxisDelayTimeVeloPosition = 1032
    AxisEnLoopingDistance = 1033
    AxisLoopingDistance = 1034
    AxisEnBacklashCompensation = 1035
    AxisBacklash = 1036
    AxisEnDataPersistence = 1037
    AxisRefVeloOnRefOutput = 1038
    AxisOverrideType = 1039
    AxisEncoderScalingFactor = 1040
    AxisEncoderOffset = 1041
    AxisEncoderDirectionInverse = 1042
    AxisEncoderEncoderMask = 1043
    AxisEncoderModuloValue = 1044
    AxisModuloToleranceWindow = 1045
    AxisEnActPosCorrection = 1046
    AxisActPosCorrectionFilterTime = 1047
    AxisUnitInterpretation = 1048
    AxisTargetPosition = 2000
    AxisRemainingTimeToGo = 2001
    AxisRemainingDistanceToGo = 2002


@dataclass(frozen=True, slots=True)
class ParameterSpec:
    """Where one parameter number lives and how it may be used."""

    source: str  #: an AxisParameters field, or a status name read from the axis
    kind: type  #: float, bool or int (dword)
    read_only: bool = False
    status: bool = False  #: read from the running axis, not from the configuration


def _config(name: str, kind: type = float) -> ParameterSpec:
    return ParameterSpec(name, kind)


def _status(name: str) -> ParameterSpec:
    return ParameterSpec(name, float, read_only=True, status=True)


P = AxisPara
PARAMETERS: dict[AxisPara, ParameterSpec] = {
    P.CommandedPosition: _status("set_position"),
    P.SWLimitPos: _config("max_soft_limit"),
    P.SWLimitNeg: _config("min_soft_limit"),
    P.EnableLimitPos: _config("enable_max_soft_limit", bool),
    P.EnableLimitNeg: _config("enable_min_soft_limit", bool),
    P.EnablePosLagMonitoring: _config("enable_position_lag_monitoring", bool),
    P.MaxPositionLag: _config("max_position_lag"),
    P.MaxVelocitySystem: _config("max_velocity"),
    P.MaxVelocityAppl: _config("max_velocity"),
    P.ActualVelocity: _status("velocity"),
    P.CommandedVelocity: _status("set_velocity"),
    P.MaxAccelerationSystem: _config("max_acceleration"),
    P.MaxAccelerationAppl: _config("max_acceleration"),
    P.MaxDecelerationSystem: _config("max_deceleration"),
    P.MaxDecelerationAppl: _config("max_deceleration"),
    P.MaxJerk: _config("max_jerk"),
    P.AxisId: _status("axis_id"),
    P.AxisVeloManSlow: _config("manual_velocity_slow"),
    P.AxisVeloManFast: _config("manual_velocity_fast"),
    P.AxisVeloMax: _config("max_velocity"),
    P.AxisAcc: _config("acceleration"),
    P.AxisDec: _config("deceleration"),
    P.AxisJerk: _config("jerk"),
    P.AxisMaxVelocity: _config("max_velocity"),
    P.AxisRapidTraverseVelocity: _config("rapid_traverse_velocity"),
    P.AxisManualVelocityFast: _config("manual_velocity_fast"),
    P.AxisManualVelocitySlow: _config("manual_velocity_slow"),
    P.AxisCalibrationVelocityForward: _config("calibration_velocity_forward"),
    P.AxisCalibrationVelocityBackward: _config("calibration_velocity_backward"),
    P.AxisJogIncrementForward: _config("jog_increment_forward"),
    P.AxisJogIncrementBackward: _config("jog_increment_backward"),
    P.AxisEnMinSoftPosLimit: _config("enable_min_soft_limit", bool),
    P.AxisMinSoftPosLimit: _config("min_soft_limit"),
    P.AxisEnMaxSoftPosLimit: _config("enable_max_soft_limit", bool),
    P.AxisMaxSoftPosLimit: _config("max_soft_limit"),
    P.AxisEnPositionLagMonitoring: _config("enable_position_lag_monitoring", bool),
    P.AxisMaxPosLagValue: _config("max_position_lag"),
    P.AxisMaxPosLagFilterTime: _config("position_lag_filter_time"),
    P.AxisEnPositionRangeMonitoring: _config("enable_position_range_monitoring", bool),
    P.AxisPositionRangeWindow: _config("position_range_window"),
    P.AxisEnTargetPositionMonitoring: _config("enable_target_position_monitoring", bool),
    P.AxisTargetPositionWindow: _config("target_position_window"),
    P.AxisTargetPositionMonitoringTime: _config("target_position_monitoring_time"),
    P.AxisEnInTargetTimeout: _config("enable_in_target_timeout", bool),
    P.AxisInTargetTimeout: _config("in_target_timeout"),
    P.AxisEnMotionMonitoring: _config("enable_motion_monitoring", bool),
    P.AxisMotionMonitoringWindow: _config("motion_monitoring_window"),
    P.AxisMotionMonitoringTime: _config("motion_monitoring_time"),
    P.AxisDelayTimeVeloPosition: _config("delay_time_velocity_position"),
    P.AxisEnLoopingDistance: _config("enable_looping_distance", bool),
    P.AxisLoopingDistance: _config("looping_distance"),
    P.AxisEnBacklashCompensation: _config("enable_backlash_compensation", bool),
    P.AxisBacklash: _config("backlash"),
    P.AxisEnDataPersistence: _config("enable_data_persistence", bool),
    P.AxisRefVeloOnRefOutput: _config("reference_velocity_on_reference_output"),
    P.AxisOverrideType: _config("override_type"),
    P.AxisEncoderScalingFactor: _config("encoder_scaling_factor"),
    P.AxisEncoderOffset: _config("encoder_offset"),
    P.AxisEncoderDirectionInverse: _config("encoder_direction_inverse", bool),
    P.AxisEncoderEncoderMask: _config("encoder_mask", int),
    P.AxisEncoderModuloValue: _config("modulo_period"),
    P.AxisModuloToleranceWindow: _config("modulo_tolerance_window"),
    P.AxisEnActPosCorrection: _config("enable_actual_position_correction", bool),
    P.AxisActPosCorrectionFilterTime: _config("actual_position_correction_filter_time"),
    P.AxisUnitInterpretation: _config("unit_interpretation"),
    P.AxisTargetPosition: _status("target_position"),
    P.AxisRemainingTimeToGo: _status("remaining_time"),
    P.AxisRemainingDistanceToGo: _status("remaining_distance"),
}
del P
