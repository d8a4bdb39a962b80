"""External setpoint generation (TcMC §4.16-4.18): the PLC feeds the setpoint every cycle."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import TargetPositionType
from openmotion.core.special_values import MC_INVALID
from openmotion.kernel.handshake import ExecuteBlock


class _Generator(ExecuteBlock):
    """``enabled`` shows the generator state on every call, also when the block is idle."""

    def __call__(self, axis: Axis | None = None, /, **inputs: Any) -> None:
        super().__call__(axis, **inputs)
        self.enabled = self.axis.external_setpoints if self.axis is not None else False

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.enabled = False


class MC_ExtSetPointGenEnable(_Generator):
    """Switch the axis to fed setpoints; ``position`` is only watched (``in_target``)."""

    INPUTS: ClassVar[dict[str, Any]] = {
        "position": MC_INVALID, "position_type": TargetPositionType.ABSOLUTE,
    }

    def _issue(self, axis: Axis) -> Command:
        return axis.enable_external_setpoints(self.position, self.position_type)


class MC_ExtSetPointGenDisable(_Generator):
    """Stop taking fed setpoints; a moving axis brakes to rest with its default dynamics."""

    def _issue(self, axis: Axis) -> Command:
        return axis.disable_external_setpoints()


def MC_ExtSetPointGenFeed(position: float, velocity: float, acceleration: float,  # noqa: N802
                          direction: int, axis: Axis) -> bool:
    """Write the setpoint of the next motion step (TcMC §4.18); always returns False.

    Call it every cycle while the generator is enabled: a cycle without a feed is an axis
    error (D-040).
    """
    return axis.feed_setpoint(position, velocity, acceleration, direction)
