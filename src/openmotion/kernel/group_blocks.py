"""The blocks of an axes group that both kinds of group share: the CA group of TF5410
(transport/group.py) and the Part 4 AxesGroup (coordinated/group.py), D-113.

A group block takes the group first, ``fb(group, ...)``, and calls the group's Python
method of the same meaning (``GROUP_API``); the handshake is kernel/handshake.py's. The
administration blocks (Tc3_McCoordinatedMotion §9.3.1.1, Part 4 §5) and the read blocks
live here; each system adds its own motion blocks on ``GroupCommand`` and ``GroupRead``.
"""

# ruff: noqa: N801 - the manuals' block names

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.core.errors import ErrorId
from openmotion.core.special_values import MC_DEFAULT
from openmotion.kernel.command import Command
from openmotion.kernel.handshake import EnableBlock, ExecuteBlock, FunctionBlock

#: what the group blocks call: CaGroup (TF5410) and AxesGroup (Part 4) both offer it
GROUP_API = ("add_axis", "remove_axis", "ungroup_all", "enable", "disable", "reset", "halt",
              "stop", "state", "error_id")


class OnGroup(FunctionBlock):
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

    def __init__(self, axes_group: Any | None = None, /, **inputs: Any) -> None:
        super().__init__(None, **inputs)
        if axes_group is not None:
            self.axes_group = axes_group

    def __call__(self, axes_group: Any | None = None, /, **inputs: Any) -> None:
        if axes_group is not None:
            inputs["axes_group"] = axes_group
        super().__call__(None, **inputs)  # type: ignore[misc] - ExecuteBlock/EnableBlock

    def _axis(self) -> Any:  # the reference the handshake hands to _issue/_enabled
        group = self.axes_group
        if not all(hasattr(group, name) for name in GROUP_API):
            raise TypeError(f"{type(self).__name__} needs an axes group (a CA group or a "
                            "Part 4 AxesGroup): call it as fb(group, ...)")
        return group


class GroupCommand(OnGroup, ExecuteBlock):
    """An execute block that calls one ``CaGroup`` method."""

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        raise NotImplementedError


class MC_AddAxisToGroup(GroupCommand):
    """Add the standing ``axis`` to the group as ``ident_in_group`` (§9.3.1.1.1).

    ``ident_in_group`` comes from ``UDINT_TO_IDENTINGROUP(n)``; it does not decide the CA
    order, the positions do (§8.1.1). Allowed while the group moves (V3.1.10).
    Outputs: done, busy, error, error_id. Error ids: INVALID_IDENT, IDENT_IN_USE,
    AXIS_IN_OTHER_GROUP, AXIS_MOVING.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"axis": None, "ident_in_group": None}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        if not all(hasattr(self.axis, name) for name in ("name", "row", "parameters")):
            raise TypeError("MC_AddAxisToGroup needs an axis: fb(group, axis=..., ...)")
        return group.add_axis(self.axis, self.ident_in_group)


class MC_RemoveAxisFromGroup(GroupCommand):
    """Remove the member with ``ident_in_group`` (§9.3.1.1.8); Done also when no member has it.

    Error id: AXIS_MOVING (the member moves or has a command).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"ident_in_group": None}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return group.remove_axis(self.ident_in_group)


class MC_UngroupAllAxes(GroupCommand):
    """Remove every axis and disable the group (§9.3.1.1.12); commands are aborted."""

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return group.ungroup_all()


class MC_GroupEnable(GroupCommand):
    """Enable the group (§9.3.1.1.3): Standby once every member is powered, else NotReady.

    Error ids: GROUP_EMPTY, GROUP_IN_ERROR.
    """

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return group.enable()


class MC_GroupDisable(GroupCommand):
    """Disable the group (§9.3.1.1.2). A moving group stands still in the same cycle, beyond
    any deceleration limit (the manual warns: halt or stop first); the command then carries a
    warning."""

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return group.disable()


class MC_GroupReset(GroupCommand):
    """Clear the errors of the group and of its members (§9.3.1.1.6); without an error it
    is Done and changes nothing."""

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return group.reset()


class MC_GroupHalt(GroupCommand):
    """Brake every member to rest (§9.3.1.2.1); the group is not locked.

    Inputs: deceleration [mm/s²] (>= 1, MC_DEFAULT, MC_MAXIMUM), jerk [mm/s³] (>= 100 or
    MC_DEFAULT). Outputs: done at standstill, busy, active, command_aborted, error, error_id.
    Error ids: GROUP_NOT_ENABLED, GROUP_STOPPING, GROUP_IN_ERROR, INVALID_DECELERATION,
    INVALID_JERK.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return group.halt(self.deceleration, self.jerk)


class MC_GroupStop(GroupCommand):
    """Brake every member to rest and lock the group (§9.3.1.2.2).

    Done at standstill. Unlike other blocks, busy and active stay TRUE with done while
    ``execute`` stays TRUE, and the group stays Stopping: motion commands fail with
    GROUP_STOPPING. The falling edge of ``execute`` releases the lock (Standby).
    command_aborted: a member lost power or the group was disabled during the stop.
    Inputs and error ids as MC_GroupHalt.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
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


class GroupRead(OnGroup, EnableBlock):
    """An enable block over the group: ``valid`` and ``busy`` while ``enable`` is TRUE."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.valid = self.busy = False

    def _enabled(self, group: Any, rising: bool) -> None:  # type: ignore[override]
        self.valid = False  # a read that fails shows Error, not an old value as valid
        self._read(group)
        self.valid = self.busy = True

    def _read(self, group: Any) -> None:
        raise NotImplementedError

    def _disabled(self) -> None:
        super()._disabled()
        self._reset_outputs()


class MC_GroupReadStatus(GroupRead):
    """The group state as flags, plus ``all_axes_standing`` (§9.3.1.1.5).

    Outputs: valid, busy, group_moving, group_homing, group_error_stop, group_not_ready,
    group_standby, group_stopping, group_disabled, all_axes_standing (no member moves:
    v = 0 and a = 0, command or not), error, error_id; constant_velocity, accelerating,
    decelerating and in_position of the path (Part 4 §5.17) for a Part 4 AxesGroup. TF5410
    does not support those four, so they stay FALSE for a CA group.
    """

    #: by state name: TF5410's GroupState and Part 4's AxesGroupState name (and number)
    #: their common states alike
    STATE_FLAGS: ClassVar[dict[str, str]] = {
        "MOVING": "group_moving", "HOMING": "group_homing", "ERROR_STOP": "group_error_stop",
        "NOT_READY": "group_not_ready", "STANDBY": "group_standby",
        "STOPPING": "group_stopping", "DISABLED": "group_disabled",
    }

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        for flag in self.STATE_FLAGS.values():
            setattr(self, flag, False)
        self.all_axes_standing = False
        self.constant_velocity = self.accelerating = self.decelerating = False
        self.in_position = False

    def _read(self, group: Any) -> None:
        name = group.state.name
        for state, flag in self.STATE_FLAGS.items():
            setattr(self, flag, name == state)
        self.all_axes_standing = group.all_axes_standing
        flags = getattr(group, "status_flags", None)  # Part 4's motion flags (§5.17)
        if flags is not None:
            values = flags()
            self.constant_velocity = values["ConstantVelocity"]
            self.accelerating = values["Accelerating"]
            self.decelerating = values["Decelerating"]
            self.in_position = values["InPosition"]


class MC_GroupReadError(GroupRead):
    """``group_error_id``: the group's error (GroupErrorId), e.g. the member error behind a
    GroupErrorStop (§9.3.1.1.4). Errors of blocks are not reported here."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.group_error_id = ErrorId.NO_ERROR

    def _read(self, group: Any) -> None:
        self.group_error_id = group.error_id
