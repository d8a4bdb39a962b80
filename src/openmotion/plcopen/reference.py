"""Reference flag and axis components: MC_SetReferenceFlag (TcMC §4.15) and
MC_ReadAxisComponents (TcMC §4.9)."""

from __future__ import annotations

from dataclasses import asdict
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.kernel.handshake import ExecuteBlock


def _done(axis: Axis, kind: str, value: object = None) -> Command:
    now = axis.runtime.now
    command = Command(kind, now)
    command.value = value
    command.end(CommandStatus.DONE, now)
    return command


class MC_SetReferenceFlag(ExecuteBlock):
    """Set the axis' *homed* state to ``reference_flag`` (TRUE homed, FALSE not homed).

    For homing by other means than MC_Home (a move to a hard stop), together with
    MC_SetActualPosition. Done in the cycle of the rising edge; the axis does not move and its
    coordinates are not touched. Accepted in every axis state (the manual names no error).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"reference_flag": False}

    def _issue(self, axis: Axis) -> Command:
        axis.homed = bool(self.reference_flag)
        return _done(axis, "set_reference_flag")


class MC_ReadAxisComponents(ExecuteBlock):
    """Describe the axis' encoder, drive and controller in ``axis_components`` (a dict).

    The manual declares ``Parameter : ST_AxisParameterSet`` but documents
    ``AxisComponents : ST_AxisComponents`` without defining that struct (Open Q25): the output is
    named ``axis_components`` and holds a snapshot taken at the rising edge::

        {"encoder": {...}, "drive": {...}, "controller": {...}}

    * ``encoder``: scaling factor, offset, direction inverse, mask, sync pulse distance and
      offset, reference mode, homing direction, calibration value, reference cam.
    * ``drive``: the DriveModel fields (model, time_constant, dead_time).
    * ``controller``: position-lag (following-error) monitoring and the position/target
      window monitoring that judge the closed loop.

    Like MC_ReadParameterSet the values stay readable after Execute falls.
    """

    _ENCODER: ClassVar[tuple[tuple[str, str], ...]] = (
        ("scaling_factor", "encoder_scaling_factor"),
        ("offset", "encoder_offset"),
        ("direction_inverse", "encoder_direction_inverse"),
        ("mask", "encoder_mask"),
        ("sync_pulse_distance", "sync_pulse_distance"),
        ("sync_pulse_offset", "sync_pulse_offset"),
        ("reference_mode", "reference_mode"),
        ("homing_direction", "homing_direction"),
        ("calibration_value", "calibration_value"),
        ("reference_cam", "reference_cam"),
    )
    _CONTROLLER: ClassVar[tuple[str, ...]] = (
        "enable_position_lag_monitoring",
        "max_position_lag",
        "position_lag_filter_time",
        "enable_position_range_monitoring",
        "position_range_window",
        "enable_target_position_monitoring",
        "target_position_window",
        "target_position_monitoring_time",
    )

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.axis_components: dict[str, dict[str, Any]] = {}

    def _issue(self, axis: Axis) -> Command:
        p = axis.parameters
        components = {
            "encoder": {key: getattr(p, field) for key, field in self._ENCODER},
            "drive": asdict(axis.drive),
            "controller": {name: getattr(p, name) for name in self._CONTROLLER},
        }
        return _done(axis, "read_axis_components", components)

    def _show_result(self, command: Command | None) -> None:
        if command is not None and command.done:
            self.axis_components = dict(command.value)
