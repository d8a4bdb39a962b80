"""The PLCopen blocks of the CA group: Tc3_McCollisionAvoidance (TF5410 §9.1) and the group
blocks of Tc3_McCoordinatedMotion (§9.3), over the ``CaGroup`` Python API.

The handshake is kernel/handshake.py's: each block supplies only its policy. The motion
blocks take the axis first, as the TcMC blocks do, and find its group through ``axis.group``;
the group blocks take the ``CaGroup`` first (``axes_group``)::

    enable = MC_GroupEnable(group)
    move = MC_MoveAbsoluteCA(x)
    enable(execute=True)
    move(execute=True, position=2500.0, velocity=500.0, gap=120.0)

MC3 inputs: 0 is an ordinary (mostly invalid) value; ``MC_DEFAULT`` means the default and
``velocity`` has none (transport/inputs.py). Reference systems (geo-compensation,
transport/geo.py): MC_MoveAbsoluteCA takes 0 (the motor path) or the mover template the axis
registered with MC_RegisterCompensation; MC_MoveRelativeCA and MC_HaltCA take only 0 so far
(INVALID_MODE otherwise).
"""

# ruff: noqa: N801 - the manual's block and structure names

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.kernel.group_blocks import (  # the group blocks of §9.3.1, shared (D-113)
    MC_AddAxisToGroup,
    MC_GroupDisable,
    MC_GroupEnable,
    MC_GroupHalt,
    MC_GroupReadError,
    MC_GroupReadStatus,
    MC_GroupReset,
    MC_GroupStop,
    MC_RemoveAxisFromGroup,
    MC_UngroupAllAxes,
)
from openmotion.kernel.handshake import ExecuteBlock
from openmotion.transport.enums import GapControlMode, ModuloDirection
from openmotion.transport.group import CaGroup

# -- options (§9.1.2.2-9.1.2.4) ----------------------------------------------------------------


@dataclass(frozen=True)
class ST_MoveAbsoluteCAOptions:
    """Options of MC_MoveAbsoluteCA (§9.1.2.2). Reference systems: 0 = the motor path, or the
    OTCID of the mover template the axis registered (MC_RegisterCompensation): the position
    is then on its TCP path, or the dynamics refer to it (transport/geo.py).

    ``additional_turns`` [UDINT]: full turns more, with a Positive or Negative direction only
    (M = 360, start 5, target 10, 2 turns, Positive: end 730).
    """

    gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT
    position_reference_system: int = 0
    dynamics_reference_system: int = 0
    additional_turns: int = 0


@dataclass(frozen=True)
class ST_MoveRelativeCAOptions:
    """Options of MC_MoveRelativeCA (§9.1.2.3); fields as ST_MoveAbsoluteCAOptions."""

    gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT
    position_reference_system: int = 0
    dynamics_reference_system: int = 0


@dataclass(frozen=True)
class ST_HaltCAOptions:
    """Options of MC_HaltCA (§9.1.2.4); fields as ST_MoveAbsoluteCAOptions."""

    gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT
    dynamics_reference_system: int = 0


def _checked(block: Any, kind: type) -> Any:
    """The block's ``options``, which must be the block's own struct."""
    options = block.options
    if not isinstance(options, kind):
        raise TypeError(f"{type(block).__name__}.options must be a {kind.__name__}, "
                        f"got {type(options).__name__}")
    return options


def _group_of(axis: Axis) -> CaGroup:
    if not isinstance(axis.group, CaGroup):
        raise CommandRejected(ErrorId.AXIS_NOT_IN_GROUP, f"{axis.name} is in no CA group")
    return axis.group


# -- motion blocks (§9.1.1.1) -------------------------------------------------------------------

_DYNAMICS: dict[str, Any] = {
    "velocity": MC_INVALID,
    "acceleration": MC_DEFAULT,
    "deceleration": MC_DEFAULT,
    "jerk": MC_DEFAULT,
    "gap": MC_DEFAULT,
    "buffer_mode": BufferMode.ABORTING,
}


class _ContinuousUpdate(ExecuteBlock):
    """ContinuousUpdate (§9.1.1.1.1): while ``execute`` and ``continuous_update`` stay TRUE,
    each call hands the current ``gap`` [mm] to the running command (only the gap, as the
    manual says for this version)."""

    INPUTS: ClassVar[dict[str, Any]] = {"continuous_update": False}
    _group: CaGroup | None = None

    def _show_progress(self, command: Command) -> None:
        if self.execute and self.continuous_update and self._group is not None:
            self._group.set_gap(command, self.gap)


class MC_MoveAbsoluteCA(_ContinuousUpdate):
    """Move a CA group member to ``position`` [mm] under collision avoidance (§9.1.1.1.1).

    Inputs: execute, continuous_update (gap only), position (MC_INVALID: must be set; a modulo
    target in [0, rail_length] with a modulo ``direction``), velocity [mm/s] (> 0 or
    MC_MAXIMUM; above the axis maximum: clamped with a warning), acceleration, deceleration
    [mm/s²] (>= 1, MC_DEFAULT, MC_MAXIMUM), jerk [mm/s³] (>= 100 or MC_DEFAULT), gap [mm] to
    the predecessor (MC_DEFAULT = the group's default gap), buffer_mode (Aborting or
    Buffered), direction (``ModuloDirection``), options (``ST_MoveAbsoluteCAOptions``).
    Outputs: done (only at the target: a mover held back by CA stays busy and active), busy,
    active, command_aborted, error, error_id.

    Error ids: AXIS_NOT_IN_GROUP, AXIS_DISABLED, GROUP_NOT_ENABLED, GROUP_STOPPING,
    GROUP_IN_ERROR, INVALID_POSITION, INVALID_VELOCITY, INVALID_ACCELERATION,
    INVALID_DECELERATION, INVALID_JERK, INVALID_GAP, INVALID_BUFFER_MODE, INVALID_DIRECTION,
    MODULO_ON_OPEN_RAIL, INVALID_TARGET_POSITION, INVALID_ADDITIONAL_TURNS, INVALID_MODE (a
    gap control mode). With an active track (MC_ActivateTrack) ``position`` is a track
    position: NOT_ON_TRACK, TARGET_OFF_TRACK. Reference systems: UNKNOWN_TEMPLATE,
    COMPENSATION_NOT_REGISTERED.

    >>> import openmotion as om
    >>> from openmotion.transport import CaGroup, MC_AddAxisToGroup, MC_GroupEnable
    >>> from openmotion.transport import UDINT_TO_IDENTINGROUP
    >>> rt = om.Runtime(); x = rt.add_axis("m1"); x.power()
    True
    >>> group = CaGroup(rt, "ca", rail_length=3000.0)
    >>> MC_AddAxisToGroup(group)(execute=True, axis=x, ident_in_group=UDINT_TO_IDENTINGROUP(1))
    >>> MC_GroupEnable(group)(execute=True)
    >>> move = MC_MoveAbsoluteCA(x)
    >>> while not move.done:
    ...     move(execute=True, position=500.0, velocity=250.0); rt.step()
    >>> x.set_position
    500.0
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "position": MC_INVALID, **_DYNAMICS, "direction": ModuloDirection.NON_MODULO,
        "options": ST_MoveAbsoluteCAOptions(),
    }

    def _issue(self, axis: Axis) -> Command:
        options = _checked(self, ST_MoveAbsoluteCAOptions)
        self._group = _group_of(axis)
        return self._group.move_absolute(
            axis, self.position, self.velocity, self.acceleration, self.deceleration,
            self.jerk, self.gap, self.buffer_mode, self.direction, options.additional_turns,
            options.gap_control_mode, self.continuous_update,
            options.position_reference_system, options.dynamics_reference_system)


class MC_MoveRelativeCA(_ContinuousUpdate):
    """Move a CA group member by ``distance`` [mm] from its set position at the start, under
    collision avoidance (§9.1.1.1.2). Inputs and error ids as MC_MoveAbsoluteCA, without
    ``direction``; options: ``ST_MoveRelativeCAOptions``. Done once the distance is
    travelled."""

    INPUTS: ClassVar[dict[str, Any]] = {
        "distance": MC_INVALID, **_DYNAMICS, "options": ST_MoveRelativeCAOptions(),
    }

    def _issue(self, axis: Axis) -> Command:
        options = _checked(self, ST_MoveRelativeCAOptions)
        self._group = _group_of(axis)
        return self._group.move_relative(
            axis, self.distance, self.velocity, self.acceleration, self.deceleration,
            self.jerk, self.gap, self.buffer_mode, options.gap_control_mode,
            self.continuous_update, options.position_reference_system,
            options.dynamics_reference_system)


class MC_HaltCA(ExecuteBlock):
    """Brake a CA group member to rest, still under collision avoidance; the axis is not
    locked, a new command may follow at once (§9.1.1.1.3).

    Inputs: execute, deceleration [mm/s²] (>= 1, MC_DEFAULT, MC_MAXIMUM), jerk [mm/s³]
    (>= 100 or MC_DEFAULT), gap [mm], options (``ST_HaltCAOptions``). Always aborting.
    Outputs: done at standstill, busy, active, command_aborted, error, error_id.
    Error ids: AXIS_NOT_IN_GROUP, AXIS_DISABLED, GROUP_NOT_ENABLED, GROUP_STOPPING,
    GROUP_IN_ERROR, INVALID_DECELERATION, INVALID_JERK, INVALID_GAP,
    COMPENSATION_NOT_REGISTERED, UNKNOWN_TEMPLATE.
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT, "gap": MC_DEFAULT,
        "options": ST_HaltCAOptions(),
    }

    def _issue(self, axis: Axis) -> Command:
        options = _checked(self, ST_HaltCAOptions)
        return _group_of(axis).halt_axis(axis, self.deceleration, self.jerk, self.gap,
                                         options.gap_control_mode,
                                         options.dynamics_reference_system)


__all__ = [
    "MC_AddAxisToGroup", "MC_GroupDisable", "MC_GroupEnable", "MC_GroupHalt", "MC_GroupReadError",
    "MC_GroupReadStatus", "MC_GroupReset", "MC_GroupStop", "MC_HaltCA", "MC_MoveAbsoluteCA",
    "MC_MoveRelativeCA", "MC_RemoveAxisFromGroup", "MC_UngroupAllAxes", "ST_HaltCAOptions",
    "ST_MoveAbsoluteCAOptions", "ST_MoveRelativeCAOptions",
]
