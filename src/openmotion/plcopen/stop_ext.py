"""MC_OrientedStop (TcMC §3.16) and MC_SetActualPositionOnTheFly (TcMC §4.13)."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.special_values import MC_INVALID
from openmotion.kernel.handshake import ExecuteBlock


class MC_OrientedStop(ExecuteBlock):
    """Stop at the next reachable position whose modulo value is ``position``.

    ``deceleration`` and ``jerk`` are accepted but unused, as in TcMC: the running move's
    values brake. Busy from the edge until the axis stands; a new edge only then. On an error
    the axis still stops, possibly not oriented.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"position": MC_INVALID, "deceleration": 0.0,
                                         "jerk": 0.0}

    def _rising_edge(self) -> None:
        if self._command is not None and self._command.busy:
            return  # TcMC §3.16: a new edge is accepted only when Busy is FALSE
        super()._rising_edge()

    def _issue(self, axis: Axis) -> Command:
        return axis.oriented_stop(self.position)


class MC_SetActualPositionOnTheFly(ExecuteBlock):
    """Shift the coordinates of a moving axis by ``actual_position - previous_position``."""

    INPUTS: ClassVar[dict[str, Any]] = {"actual_position": MC_INVALID,
                                         "previous_position": MC_INVALID}

    def _issue(self, axis: Axis) -> Command:
        return axis.set_actual_position_on_the_fly(self.actual_position, self.previous_position)
