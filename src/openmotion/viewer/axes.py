"""The single axes: one bar per axis that is not a CA mover (those ride on their rail)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from openmotion.viewer.layers import Layer, Row, error_text, finite, number

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.runtime.runtime import Runtime


class AxesLayer(Layer):
    """Every axis of the runtime; the bars show those outside a CA group."""

    kind = "axes"

    def __init__(self, runtime: Runtime) -> None:
        self.name = "axes"
        self._rt = runtime

    def _free(self) -> list[Axis]:
        return [axis for axis in self._rt.axes.values() if axis.group is None]

    def panel(self) -> dict[str, Any]:
        return {"axes": [_bar(axis) for axis in self._free()]}

    def rows(self) -> list[Row]:
        return [axis_row(axis, "axis") for axis in self._free()]


def _bar(axis: Axis) -> dict[str, Any]:
    parameters = axis.parameters
    return {"name": axis.name, "state": axis.state.name, "error": axis.error,
            "set_position": finite(axis.set_position), "position": finite(axis.position),
            "velocity": finite(axis.set_velocity),
            "min": parameters.min_soft_limit if parameters.enable_min_soft_limit else None,
            "max": parameters.max_soft_limit if parameters.enable_max_soft_limit else None}


def axis_row(axis: Axis, kind: str, detail: str = "") -> Row:
    """The table row of an axis (or of a CA mover, which is one)."""
    command = axis.active_command
    return Row(kind, axis.name, axis.state.name.lower(), number(axis.set_position),
               number(axis.set_velocity), command.kind if command is not None else "",
               detail or f"lag {number(axis.following_error, 4)}",
               error_text(axis.axis_error_id, axis.axis_error_message))


def axes_layers(runtime: Runtime) -> list[Layer]:
    """The axes layer, when the runtime has axes."""
    return [AxesLayer(runtime)] if runtime.axes else []
