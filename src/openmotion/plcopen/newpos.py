"""MC_NewPos and MC_NewPosAndVelo: modify the running move (TcMC §3.7, §3.8)."""

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import NewPosAndVeloMode
from openmotion.core.special_values import MC_INVALID
from openmotion.kernel.handshake import ExecuteBlock


class MC_NewPos(ExecuteBlock):
    """A new target for the moving axis; Done means accepted, not arrived."""

    INPUTS: ClassVar[dict[str, Any]] = {"new_pos": MC_INVALID}

    def _issue(self, axis: Axis) -> Command:
        return axis.new_position(self.new_pos)


class MC_NewPosAndVelo(ExecuteBlock):
    """New target and/or velocity, at once or when passing ``activation_pos``."""

    INPUTS: ClassVar[dict[str, Any]] = {
        "mode": NewPosAndVeloMode.CHANGE_POS_AND_VELO, "new_pos": MC_INVALID,
        "new_velo": MC_INVALID, "activation_pos": 0.0,
    }

    def _issue(self, axis: Axis) -> Command:
        return axis.new_position_and_velocity(self.mode, self.new_pos, self.new_velo,
                                              self.activation_pos)
