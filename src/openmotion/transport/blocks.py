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
from openmotion.kernel.handshake import EnableBlock, ExecuteBlock, FunctionBlock
from openmotion.transport.enums import GapControlMode, GroupState, ModuloDirection
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


# -- group blocks (§9.3.1) ----------------------------------------------------------------------


#: what the group blocks call: CaGroup (TF5410) and AxesGroup (Part 4) both offer it
_GROUP_API = ("add_axis", "remove_axis", "ungroup_all", "enable", "disable", "reset", "halt",
              "stop", "state", "error_id")


class _OnGroup(FunctionBlock):
    """A block whose reference is an axes group, given first: ``fb(group, ...)``.

    One set of group blocks serves both kinds of group: the CA group of TF5410 and the
    coordinated-motion group of PLCopen Part 4 (coordinated/group.py).

    The group is the input ``axes_group`` (AXES_GROUP_REF); ``axis`` is no input unless the
    block names one (MC_AddAxisToGroup).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"axes_group": None}

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls._names = frozenset(cls.INPUTS)

    def __init__(self, axes_group: CaGroup | None = None, /, **inputs: Any) -> None:
        super().__init__(None, **inputs)
        if axes_group is not None:
            self.axes_group = axes_group

    def __call__(self, axes_group: CaGroup | None = None, /, **inputs: Any) -> None:
        if axes_group is not None:
            inputs["axes_group"] = axes_group
        super().__call__(None, **inputs)  # type: ignore[misc] - ExecuteBlock/EnableBlock

    def _axis(self) -> Any:  # the reference the handshake hands to _issue/_enabled
        group = self.axes_group
        if not all(hasattr(group, name) for name in _GROUP_API):
            raise TypeError(f"{type(self).__name__} needs an axes group (a CA group or a "
                            "Part 4 AxesGroup): call it as fb(group, ...)")
        return group


class _GroupCommand(_OnGroup, ExecuteBlock):
    """An execute block that calls one ``CaGroup`` method."""

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        raise NotImplementedError


class MC_AddAxisToGroup(_GroupCommand):
    """Add the standing ``axis`` to the group as ``ident_in_group`` (§9.3.1.1.1).

    ``ident_in_group`` comes from ``UDINT_TO_IDENTINGROUP(n)``; it does not decide the CA
    order, the positions do (§8.1.1). Allowed while the group moves (V3.1.10).
    Outputs: done, busy, error, error_id. Error ids: INVALID_IDENT, IDENT_IN_USE,
    AXIS_IN_OTHER_GROUP, AXIS_MOVING.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"axis": None, "ident_in_group": None}

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        if not isinstance(self.axis, Axis):
            raise TypeError("MC_AddAxisToGroup needs an axis: fb(group, axis=..., ...)")
        return group.add_axis(self.axis, self.ident_in_group)


class MC_RemoveAxisFromGroup(_GroupCommand):
    """Remove the member with ``ident_in_group`` (§9.3.1.1.8); Done also when no member has it.

    Error id: AXIS_MOVING (the member moves or has a command).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"ident_in_group": None}

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        return group.remove_axis(self.ident_in_group)


class MC_UngroupAllAxes(_GroupCommand):
    """Remove every axis and disable the group (§9.3.1.1.12); commands are aborted."""

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        return group.ungroup_all()


class MC_GroupEnable(_GroupCommand):
    """Enable the group (§9.3.1.1.3): Standby once every member is powered, else NotReady.

    Error ids: GROUP_EMPTY, GROUP_IN_ERROR.
    """

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        return group.enable()


class MC_GroupDisable(_GroupCommand):
    """Disable the group (§9.3.1.1.2). A moving group stands still in the same cycle, beyond
    any deceleration limit (the manual warns: halt or stop first); the command then carries a
    warning."""

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        return group.disable()


class MC_GroupReset(_GroupCommand):
    """Clear the errors of the group and of its members (§9.3.1.1.6); without an error it
    is Done and changes nothing."""

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        return group.reset()


class MC_GroupHalt(_GroupCommand):
    """Brake every member to rest (§9.3.1.2.1); the group is not locked.

    Inputs: deceleration [mm/s²] (>= 1, MC_DEFAULT, MC_MAXIMUM), jerk [mm/s³] (>= 100 or
    MC_DEFAULT). Outputs: done at standstill, busy, active, command_aborted, error, error_id.
    Error ids: GROUP_NOT_ENABLED, GROUP_STOPPING, GROUP_IN_ERROR, INVALID_DECELERATION,
    INVALID_JERK.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        return group.halt(self.deceleration, self.jerk)


class MC_GroupStop(_GroupCommand):
    """Brake every member to rest and lock the group (§9.3.1.2.2).

    Done at standstill. Unlike other blocks, busy and active stay TRUE with done while
    ``execute`` stays TRUE, and the group stays Stopping: motion commands fail with
    GROUP_STOPPING. The falling edge of ``execute`` releases the lock (Standby).
    command_aborted: a member lost power or the group was disabled during the stop.
    Inputs and error ids as MC_GroupHalt.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        return group.stop(self.deceleration, self.jerk)

    def _falling_edge(self) -> None:
        if self._command is not None:
            self._command.release()

    def _show_result(self, command: Command | None) -> None:
        if command is not None and command.done and command.hold:
            self.busy = self.active = True

    def _check_invariants(self) -> None:
        if self.done and self.busy:  # the hold: done, busy and active, nothing else
            assert self.active and not (self.error or self.command_aborted), "MC_GroupStop"
            return
        super()._check_invariants()


# -- read blocks (§9.3.1.1.4, §9.3.1.1.5) -------------------------------------------------------


class _GroupRead(_OnGroup, EnableBlock):
    """An enable block over the group: ``valid`` and ``busy`` while ``enable`` is TRUE."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.valid = self.busy = False

    def _enabled(self, group: CaGroup, rising: bool) -> None:  # type: ignore[override]
        self.valid = False  # a read that fails shows Error, not an old value as valid
        self._read(group)
        self.valid = self.busy = True

    def _read(self, group: CaGroup) -> None:
        raise NotImplementedError

    def _disabled(self) -> None:
        super()._disabled()
        self._reset_outputs()


class MC_GroupReadStatus(_GroupRead):
    """The group state as flags, plus ``all_axes_standing`` (§9.3.1.1.5).

    Outputs: valid, busy, group_moving, group_homing, group_error_stop, group_not_ready,
    group_standby, group_stopping, group_disabled, all_axes_standing (no member moves:
    v = 0 and a = 0, command or not), error, error_id; constant_velocity, accelerating,
    decelerating and in_position of the path (Part 4 §5.17) for a Part 4 AxesGroup. TF5410
    does not support those four, so they stay FALSE for a CA group.
    """

    _STATE_FLAG: ClassVar[dict[GroupState, str]] = {
        GroupState.MOVING: "group_moving", GroupState.HOMING: "group_homing",
        GroupState.ERROR_STOP: "group_error_stop", GroupState.NOT_READY: "group_not_ready",
        GroupState.STANDBY: "group_standby", GroupState.STOPPING: "group_stopping",
        GroupState.DISABLED: "group_disabled",
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        for flag in self._STATE_FLAG.values():
            setattr(self, flag, False)
        self.all_axes_standing = False
        self.constant_velocity = self.accelerating = self.decelerating = False
        self.in_position = False

    def _read(self, group: CaGroup) -> None:
        for state, flag in self._STATE_FLAG.items():  # both groups number their states alike
            setattr(self, flag, int(group.state) == int(state))
        self.all_axes_standing = group.all_axes_standing
        flags = getattr(group, "status_flags", None)  # Part 4's motion flags (§5.17)
        if flags is not None:
            values = flags()
            self.constant_velocity = values["ConstantVelocity"]
            self.accelerating = values["Accelerating"]
            self.decelerating = values["Decelerating"]
            self.in_position = values["InPosition"]


class MC_GroupReadError(_GroupRead):
    """``group_error_id``: the group's error (GroupErrorId), e.g. the member error behind a
    GroupErrorStop (§9.3.1.1.4). Errors of blocks are not reported here."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.group_error_id = ErrorId.NO_ERROR

    def _read(self, group: CaGroup) -> None:
        self.group_error_id = group.error_id
