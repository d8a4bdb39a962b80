"""What the machine model shows of an axis: its signals, and its commands from its methods.

Declared once here (``Axis.MACHINE``), read by every edge (kernel/model.py, D-226). Every
value is the float a trace records: the state as its AxisState number, the override in percent
(0-100), homed as 0 or 1, the axis error as its ErrorId number (0: none). Lengths are in the
axis unit: mm, or ° on a rotary axis.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from openmotion.core.enums import AxisState
from openmotion.core.errors import ErrorId
from openmotion.core.override import percent_from_fraction
from openmotion.kernel.model import BulkReader, Kind, SignalSpec, compact_index

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

#: kinematic signals kept in the axis kernel's arrays, read for all axes at once
_KERNEL_FIELDS = {"set_position": "set_p", "set_velocity": "set_v",
                  "set_acceleration": "set_a", "set_jerk": "set_j", "position": "act_p",
                  "velocity": "act_v"}


def _gather(prop: str):  # noqa: ANN202 - a bulk reader factory
    """All given axes' values of one kernel signal in one numpy gather per sample."""
    def bulk(axes: Sequence[Axis]) -> BulkReader:
        kernel = axes[0].system.kernel  # every axis of a runtime shares it
        rows = compact_index([axis.row for axis in axes])
        if prop == "following_error":
            return lambda: kernel.set_p[rows] - kernel.act_p[rows]
        field = _KERNEL_FIELDS[prop]
        return lambda: getattr(kernel, field)[rows]  # arrays are replaced when they grow

    return bulk


def _number(prop: str):  # noqa: ANN202 - a reader factory
    return lambda axis: float(getattr(axis, prop))


def _whole(prop: str):  # noqa: ANN202 - a reader factory
    return lambda axis: float(int(getattr(axis, prop)))


def _kinematic(name: str, unit: str, doc: str, **more: object) -> SignalSpec:
    return SignalSpec(name, unit, float, _number(name), doc, bulk=_gather(name),
                      **more)  # type: ignore[arg-type]


AXIS = Kind(
    "axis",
    signals=(
        _kinematic("set_position", "mm", "setpoint position (TcMC fPosSoll, §3.5)",
                   default=True, scope=True, actual="position"),
        _kinematic("set_velocity", "mm/s", "setpoint velocity", default=True, scope=True,
                   actual="velocity"),
        _kinematic("set_acceleration", "mm/s²", "setpoint acceleration", default=True,
                   scope=True),
        _kinematic("set_jerk", "mm/s³", "setpoint jerk"),
        _kinematic("position", "mm", "actual position (encoder)", default=True, scope=True),
        _kinematic("velocity", "mm/s", "actual velocity", scope=True),
        _kinematic("following_error", "mm", "set minus actual position", scope=True),
        SignalSpec("state", "", AxisState, _whole("state"), "PLCopen axis state"),
        SignalSpec("override", "%", float, lambda axis: percent_from_fraction(float(axis.override)),
                   "velocity override, 0-100 %"),
        SignalSpec("homed", "", bool, _whole("homed"), "the axis is referenced"),
        SignalSpec("axis_error_id", "", ErrorId, _whole("axis_error_id"),
                   "the axis error behind ErrorStop (0: none)"),
    ),
    handles=("Command",),
    levels=("power",),  # MC_Power: Enable is a level, Status follows at once
    identify=lambda axis: axis.row + 1,  # AxisId: rows count from 0, ids from 1
)
