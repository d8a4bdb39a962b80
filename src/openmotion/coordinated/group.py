"""The axes group of PLCopen Part 4: members, state, coordinate systems and the path cycle.

Members are ordinary axes. While the group moves it owns their setpoints: every cycle, right
after the profiles are evaluated, it samples its path time law (timing.py), turns the path
point into axis positions through the kinematics, and writes them into the kernel rows of
its members. Between motions the rows hold still on a profile of their own.

State: one ``GroupStateMachine`` (states.py) decides what may start; this class fires its
events and keeps the members' single-axis states coupled (§3.2, Table 5). Path commands are
built in moves.py; this module carries out what they planned.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.axis.state_machine import admit
from openmotion.coordinated.cam import CamLaw, PathMode, check_periodic
from openmotion.coordinated.frames import Frame
from openmotion.coordinated.inputs import (
    CoordSystem,
    PathDynamics,
    PathMoveOptions,
    TransitionMode,
    dynamic_value,
    enum_value,
)
from openmotion.coordinated.inputs import buffer_mode as part4_buffer_mode
from openmotion.coordinated.kind import AXES_GROUP
from openmotion.coordinated.kinematics import Kinematics
from openmotion.coordinated.members import GroupMembers
from openmotion.coordinated.moves import PathMotion
from openmotion.coordinated.requests import build_request
from openmotion.coordinated.spaces import Spaces, default_kinematics
from openmotion.coordinated.states import (
    AxesGroupState,
    ExecutionMode,
    GroupEvent,
    GroupStateMachine,
    check_member_accepts,
    member_command_event,
    member_event,
    member_state,
)
from openmotion.coordinated.tracking import (
    AxisSync,
    ConveyorFrame,
    GroupFrame,
    RotaryTableFrame,
    SyncInputs,
)
from openmotion.core.enums import AxisState, BufferMode
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.core.special_values import MC_DEFAULT, InputValue
from openmotion.geometry.path import CircMode, PathChoice
from openmotion.trajectory.plan import Limits

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.coordinated.path_table import PathTableRun
    from openmotion.kernel.model import Kind
    from openmotion.runtime.runtime import Runtime

G = AxesGroupState


def ident_number(ident: Any) -> int:
    """IdentInGroup as a number: an ``IdentInGroup`` (TF5410 style) or a plain int >= 0."""
    value = getattr(ident, "value", ident)
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise CommandRejected(ErrorId.INVALID_IDENT,
                              f"IdentInGroup must be an integer >= 0, got {ident!r}")
    return value


class AxesGroup:
    """An AXES_GROUP_REF (Part 4 §4): axes that move together on a path.

    ``AxesGroup(rt, "xy")`` makes an empty, disabled group; add axes, enable it, move it. The
    Python methods return a ``Command``, as the axis methods do; the FBs (blocks.py) call them.
    """

    MACHINE: ClassVar[Kind] = AXES_GROUP  #: its signals and commands in the machine model

    def __init__(self, runtime: Runtime, name: str = "group",
                 dynamics: PathDynamics | None = None) -> None:
        if dynamics is not None and not isinstance(dynamics, PathDynamics):
            raise ConfigError(f"axes group {name!r}: dynamics must be a PathDynamics, got "
                              f"{type(dynamics).__name__}")
        self.name = name
        self.runtime = runtime
        self.kernel = runtime.axis_system.kernel
        self.machine = GroupStateMachine()
        self.members = GroupMembers(self)  #: IdentInGroup -> axis; their setpoints
        self.dynamics = dynamics or PathDynamics()
        self.spaces = Spaces(default_kinematics(0))
        self.error_id = ErrorId.NO_ERROR  #: the group error behind GroupErrorStop
        self.error_message = ""
        self.factors = (1.0, 1.0, 1.0)  #: MC_GroupSetOverride: velocity, acceleration, jerk
        self.motion = PathMotion(self)
        self._stop: Command | None = None
        self._home: list[Command] = []
        self._home_command: Command | None = None
        self._pending: list[tuple[Command, set[int], Callable[[], None]]] = []
        self._syncs: dict[int, AxisSync] = {}  #: MC_SyncAxisToGroup slaves by kernel row
        #: Buffered MC_SyncAxisToGroup calls waiting for their slave's own command to end
        self._waiting_syncs: list[tuple[Axis, SyncInputs, Command]] = []
        self._reset: tuple[Command, list[Command]] | None = None
        #: commands buffered behind the motion: a Buffered MC_GroupHome or MC_GroupSetPosition
        #: (§5.7, §5.9), and the motions buffered behind those; (command, is_motion, start)
        self._queued: list[tuple[Command, bool, Callable[[], None]]] = []
        self.table: PathTableRun | None = None  #: TF5410 MC_MovePath over a path table
        self._feeding = False  #: the table run hands its own segments in (no self-abort)
        #: 1, 2, ... in the order the runtime's axes groups were made (its model id, D-223)
        self.group_id = runtime.serial("axes_group")
        runtime.add_system(self)

    # -- reading -------------------------------------------------------------------------------

    @property
    def state(self) -> AxesGroupState:
        return self.machine.state

    @property
    def axes(self) -> list[Axis]:
        """Members in IdentInGroup order (the ACS order, §5.10)."""
        return self.members.axes

    @property
    def rows(self) -> np.ndarray:
        """The members' kernel rows in IdentInGroup order (read-only)."""
        return self.members.rows

    @property
    def kinematics(self) -> Kinematics:
        return self.spaces.kinematics

    def acs_set(self) -> np.ndarray:
        return self.kernel.set_p[self.rows].copy()

    def position(self, coord_system: CoordSystem = CoordSystem.ACS, actual: bool = True
                 ) -> np.ndarray:
        """MC_GroupReadActualPosition (§5.10): one value per axis (ACS) or per coordinate."""
        rows = self.rows
        acs = (self.kernel.act_p if actual else self.kernel.set_p)[rows].copy()
        if coord_system is CoordSystem.ACS:
            return acs
        mcs = self.spaces.to_mcs(acs)
        return mcs if coord_system is CoordSystem.MCS else self.spaces.pcs_of(mcs, self.runtime.now)

    def velocity(self, coord_system: CoordSystem = CoordSystem.ACS) -> tuple[np.ndarray, float]:
        """MC_GroupReadActualVelocity (§5.11): velocities and the path velocity (TCP speed)."""
        rows = self.rows
        acs, vel = self.kernel.act_p[rows].copy(), self.kernel.act_v[rows].copy()
        mcs_v = self.kinematics.forward_velocity(acs, vel) if rows.size else np.zeros(0)
        path = float(np.linalg.norm(self.spaces.xyz(mcs_v))) if rows.size else 0.0
        if coord_system is CoordSystem.ACS:
            return vel, path
        if coord_system is CoordSystem.PCS:
            mcs_v = self.spaces.with_xyz(
                mcs_v, self.spaces.frame(self.runtime.now).inverse().rotate(self.spaces.xyz(mcs_v)))
        return mcs_v, path

    def acceleration(self, coord_system: CoordSystem = CoordSystem.ACS
                     ) -> tuple[np.ndarray, float]:
        """MC_GroupReadActualAcceleration (§5.12): set accelerations and the path
        acceleration (positive while the path speed grows). The drives report no
        acceleration, so the setpoint's is shown (decisions D-108)."""
        rows = self.rows
        acs, vel, acc = (self.kernel.set_p[rows].copy(), self.kernel.set_v[rows].copy(),
                         self.kernel.set_a[rows].copy())
        path_acc = self.motion.path_acceleration
        if coord_system is CoordSystem.ACS or not rows.size:
            return acc, path_acc
        mcs_a = self.kinematics.forward_velocity(acs, acc)  # exact for linear kinematics
        if coord_system is CoordSystem.PCS:
            mcs_a = self.spaces.with_xyz(
                mcs_a, self.spaces.frame(self.runtime.now).inverse().rotate(self.spaces.xyz(mcs_a)))
        del vel
        return mcs_a, path_acc

    @property
    def all_axes_standing(self) -> bool:
        return self.members.standing

    def status_flags(self) -> dict[str, bool]:
        """MC_GroupReadStatus (§5.17): one state flag, and the motion flags of the path."""
        flags = {state.spec_name: self.state is state for state in G}
        v, a = self.motion.path_velocity, self.motion.path_acceleration
        moving = v > 0.0 or a != 0.0
        flags["Accelerating"] = moving and a > 0.0
        flags["Decelerating"] = moving and a < 0.0
        flags["ConstantVelocity"] = moving and a == 0.0 and v > 0.0
        flags["InPosition"] = self.state is G.STANDBY and not moving
        return flags

    def __repr__(self) -> str:
        return f"<AxesGroup {self.name} {self.state.spec_name} {len(self.members)} axes>"

    # -- administration (§4, §5.1-§5.6) --------------------------------------------------------

    def add_axis(self, axis: Axis, ident: Any) -> Command:
        """MC_AddAxisToGroup (§5.1): accepted in GroupDisabled and GroupStandby."""
        command = self._command("add_axis")
        try:
            number = ident_number(ident)
            self.machine.accept("MC_AddAxisToGroup")
            if axis.group is self:
                raise CommandRejected(ErrorId.IDENT_IN_USE, f"{axis.name} is a member already")
            if axis.group is not None:
                raise CommandRejected(ErrorId.AXIS_IN_OTHER_GROUP,
                                      f"{axis.name} is in group "
                                      f"{getattr(axis.group, 'name', '?')!r}")
            if number in self.members:
                raise CommandRejected(ErrorId.IDENT_IN_USE, f"IdentInGroup {number} is taken")
            if axis.moving or axis.has_job:
                raise CommandRejected(ErrorId.AXIS_MOVING, f"{axis.name} is moving")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        self.machine.fire(GroupEvent.ADD_AXIS)
        self.members.add(number, axis)
        axis.group = self
        self._regrouped()
        return self._finish(command)

    def remove_axis(self, ident: Any) -> Command:
        """MC_RemoveAxisFromGroup (§5.2): not while the group moves, homes or stops."""
        command = self._command("remove_axis")
        try:
            number = ident_number(ident)
            self.machine.accept("MC_RemoveAxisFromGroup")
            if number not in self.members:
                raise CommandRejected(ErrorId.AXIS_NOT_IN_GROUP,
                                      f"no member has IdentInGroup {number}")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        self.members.release(self.members.pop(number))
        self.machine.fire(GroupEvent.REMOVE_AXIS)
        self._regrouped()
        return self._finish(command)

    def ungroup_all(self) -> Command:
        """MC_UngroupAllAxes (§5.3): every axis leaves, the group is GroupDisabled."""
        command = self._command("ungroup_all")
        try:
            self.machine.accept("MC_UngroupAllAxes")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        self.motion.abort_all("the axes were ungrouped")
        for axis in list(self.members.values()):
            self.members.release(axis)
        self.members.clear()
        self.machine.fire(GroupEvent.UNGROUP)
        self._regrouped()
        return self._finish(command)

    def enable(self) -> Command:
        """MC_GroupEnable (§5.5): GroupDisabled -> GroupStandby; member power is untouched."""
        command = self._command("enable")
        try:
            self.machine.accept("MC_GroupEnable")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        self.machine.fire(GroupEvent.ENABLE)
        self.members.last_states = {}
        self._check_members()
        return self._finish(command)

    def disable(self) -> Command:
        """MC_GroupDisable (§5.6, Note 6): from any state; a motion ends at once (avoid it)."""
        command = self._command("disable")
        if not self.all_axes_standing:
            command.warnings.append("the group was moving: its axes stopped at once")
        self.motion.abort_all("the group was disabled")
        self._home_abort("the group was disabled")
        self.members.hold()
        if self._stop is not None:
            self._stop.end(CommandStatus.ABORTED, self.runtime.now,
                           message="the group was disabled")
            self._stop = None
        self.machine.fire(GroupEvent.DISABLE)
        self._couple()
        return self._finish(command)

    def reset(self) -> Command:
        """MC_GroupReset (§5.19): GroupErrorStop -> GroupStandby, members reset like MC_Reset."""
        command = self._command("reset")
        try:
            self.machine.accept("MC_GroupReset")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        parts = []
        for axis in self.axes:
            if axis.state is AxisState.ERROR_STOP:
                with self.members.ungrouped(axis):
                    part = axis.reset()
                if part.error:
                    return self._reject(command, CommandRejected(part.error_id, part.message))
                parts.append(part)
        self._reset = (command, parts)
        command.status = CommandStatus.ACTIVE
        self._end_reset(self.runtime.now)
        return command

    def _end_reset(self, now: float) -> None:
        """MC_GroupReset is Done once every member's MC_Reset is (a cycle later, TcMC)."""
        if self._reset is None:
            return
        command, parts = self._reset
        if any(part.busy for part in parts):
            return
        self._reset = None
        failed = next((part for part in parts if part.error), None)
        if failed is not None:
            command.end(CommandStatus.ERROR, now, failed.error_id, failed.message)
            return
        if self.state is G.ERROR_STOP or self.state is G.STANDBY or self.state is G.DISABLED:
            self.error_id, self.error_message = ErrorId.NO_ERROR, ""
            self.machine.fire(GroupEvent.RESET)
            self.members.last_states = {}
            self._couple()
        command.end(CommandStatus.DONE, now)

    # -- coordinate systems (§5.8) -------------------------------------------------------------

    def set_kinematics(self, kinematics: Kinematics, mode: ExecutionMode = ExecutionMode.IMMEDIATELY
                       ) -> Command:
        """MC_SetKinTransform (§5.8.1): the model must fit the member count (rule 5)."""
        command = self._command("set_kin_transform")
        try:
            self.machine.accept("MC_SetKinTransform")
            if not isinstance(kinematics, Kinematics):
                raise CommandRejected(ErrorId.INVALID_MODE, "KinTransform: not a Kinematics")
            if kinematics.n_axes != len(self.members):
                raise CommandRejected(ErrorId.INVALID_CONFIGURATION,
                                      f"the model drives {kinematics.n_axes} axes, the group "
                                      f"has {len(self.members)}")
            mode = enum_value(ExecutionMode, mode, "ExecutionMode")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        return self._when(command, mode, lambda: self.spaces.set_kinematics(kinematics))

    def set_cartesian_transform(self, frame: Frame, mode: ExecutionMode = ExecutionMode.IMMEDIATELY
                                ) -> Command:
        """MC_SetCartesianTransform (§5.8.2): one more Cartesian transform, active together
        with those set before: composed with them, given in the frame they set up (D-133);
        MC_ReadCartesianTransform reads the result (§5.8.5). All zeros de-select the PCS
        (PCS = MCS). Ends a tracking FB on the PCS (§6.6)."""
        def place() -> None:
            cartesian = self.spaces.cartesian
            self.spaces.cartesian = Frame() if frame == Frame() else cartesian.compose(frame)
        return self._set_pcs("set_cartesian_transform", "MC_SetCartesianTransform", mode, place)

    def set_coordinate_transform(self, frame: Frame,
                                 mode: ExecutionMode = ExecutionMode.IMMEDIATELY) -> Command:
        """MC_SetCoordinateTransform (§5.8.3): the PCS placement as a whole; it replaces the
        transforms active before (the identity is the neutral one). Ends a tracking FB."""
        def place() -> None:
            self.spaces.cartesian = frame
        return self._set_pcs("set_coordinate_transform", "MC_SetCoordinateTransform", mode,
                             place)

    def _set_pcs(self, kind: str, block: str, mode: ExecutionMode, place: Callable[[], None]
                 ) -> Command:
        command = self._command(kind)
        try:
            self.machine.accept(block)
            mode = enum_value(ExecutionMode, mode, "ExecutionMode")
        except CommandRejected as rejected:
            return self._reject(command, rejected)

        def apply() -> None:
            self.motion.end_tracking("the PCS was set by a transform FB")
            place()
        return self._when(command, mode, apply)

    def _when(self, command: Command, mode: ExecutionMode, apply: Callable[[], None]) -> Command:
        """§3.3: apply now, when the active motion ends, or when every issued one ended."""
        wait = self.motion.commands_to_wait(mode)
        if not wait:
            apply()
            return self._finish(command)
        command.status = CommandStatus.ACTIVE
        self._pending.append((command, wait, apply))
        return command

    def set_position(self, position: Any, relative: bool = False,
                     coord_system: CoordSystem = CoordSystem.ACS,
                     buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_GroupSetPosition (§5.9): new coordinates without motion (rules 14-16). Aborting
        needs GroupStandby; any other BufferMode waits until the motion before it is over
        (decisions D-130)."""
        command = self._command("group_set_position")
        try:
            mode = part4_buffer_mode(buffer_mode)
            self.machine.accept("MC_GroupSetPosition", mode)
            coord_system = enum_value(CoordSystem, coord_system, "CoordSystem")
            size = len(self.members) if coord_system is CoordSystem.ACS else self.spaces.size
            from openmotion.coordinated.inputs import vector
            value = vector(position, size, "Position")
        except CommandRejected as rejected:
            return self._reject(command, rejected)

        def apply() -> None:
            self._set_position(value, relative, coord_system)
            command.end(CommandStatus.DONE, self.runtime.now)
        return self._after_motion(command, mode, apply)

    def _set_position(self, value: np.ndarray, relative: bool, coord_system: CoordSystem
                      ) -> None:
        if coord_system is CoordSystem.ACS:
            self._set_acs(value, relative)
            return
        old = self.position(coord_system, actual=False)
        new = old + value if relative else value
        if coord_system is CoordSystem.MCS:
            self.spaces.mcs_offset = self.spaces.mcs_offset + (new - old)
        else:
            shift = self.spaces.xyz(old) - self.spaces.xyz(new)
            frame = self.spaces.cartesian
            self.spaces.cartesian = Frame(frame.rotation,
                                          frame.translation + frame.rotate(shift))

    def _after_motion(self, command: Command, mode: BufferMode, start: Callable[[], None]
                      ) -> Command:
        """Start now (Aborting, or nothing runs), or wait in ``_queued`` until the motion
        issued before is over: §5.7 (MC_GroupHome: the Blending modes act as Buffered), §5.9
        (MC_GroupSetPosition: likewise). Stays Busy, not Active, while it waits."""
        if mode is BufferMode.ABORTING or (self.state is G.STANDBY and not self._queued):
            try:
                start()
            except CommandRejected as rejected:
                return self._reject(command, rejected)
            return command
        self._queued.append((command, False, start))
        return command

    def _run_queued(self) -> None:
        """Start what waits in ``_queued``, in order: an administrative command once the
        motion before it is over (the group passes GroupStandby on the way), a motion once
        no MC_GroupHome runs."""
        while self._queued:
            command, is_motion, start = self._queued[0]
            if command.finished:  # aborted while it waited
                self._queued.pop(0)
                continue
            if self._home_command is not None or self.state not in (G.STANDBY, G.MOVING):
                return
            if not is_motion:
                if not self.motion.finished or self.members.solo_running() \
                        or self.table is not None:
                    return
                if self.state is G.MOVING:
                    self.machine.fire(GroupEvent.MOTION_END)
                    self._couple()
            self._queued.pop(0)
            try:
                start()
            except CommandRejected as rejected:
                self._reject(command, rejected)

    def _abort_queued(self, reason: str) -> None:
        """An Aborting motion, a halt or stop, disable, an error: what waits is aborted."""
        queued, self._queued = self._queued, []
        for command, _, _ in queued:
            command.end(CommandStatus.ABORTED, self.runtime.now, message=reason)

    def _set_acs(self, value: np.ndarray, relative: bool) -> None:
        """Each member's setpoint reads ``value`` (or moves by it), its actual position
        shifts along: as MCS and PCS, the set position is the reference (a buffered call
        acts in the cycle the motion ends, before the drives caught up)."""
        for axis, new in zip(self.axes, value, strict=True):
            target = axis.set_position + new if relative else new
            with self.members.ungrouped(axis):
                part = axis.set_actual_position(axis.position + float(target)
                                                - axis.set_position)
            if part.error:
                raise CommandRejected(part.error_id, f"{axis.name}: {part.message}")

    # -- stopping (§5.13-§5.16) ----------------------------------------------------------------

    def stop(self, deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
             buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_GroupStop (§5.13): brake along the path, abort everything, hold GroupStopping
        until Done and the Execute input is low (``Command.release``). Buffered (and the
        Blending modes, which act as Buffered) waits, Busy and not Active, until the motion
        issued before it is over, then stops the group at rest (decisions D-194)."""
        command = self._command("group_stop")
        try:
            mode = part4_buffer_mode(buffer_mode)
            self.machine.accept("MC_GroupStop")
            dec, jerk_value = self._brake_limits(deceleration, jerk, command)
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        command.hold = True  # Execute is TRUE from now: a stop that waits may be released

        def start() -> None:
            self.motion.brake(dec, jerk_value, "aborted by MC_GroupStop")
            self.end_table("aborted by MC_GroupStop")
            self._home_abort("aborted by MC_GroupStop")
            self.machine.fire(GroupEvent.STOP)
            self._couple()
            command.status = CommandStatus.ACTIVE
            self._stop = command
        return self._after_motion(command, mode, start)

    def halt(self, deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
             buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_GroupHalt (§5.14): brake along the path to rest; any motion FB may abort it.
        Buffered (and the Blending modes) waits until the motion before it is over and is
        then Done at once (D-194)."""
        command = self._command("group_halt")
        try:
            mode = part4_buffer_mode(buffer_mode)
            self.machine.accept("MC_GroupHalt", mode)
            dec, jerk_value = self._brake_limits(deceleration, jerk, command)
        except CommandRejected as rejected:
            return self._reject(command, rejected)

        def start() -> None:
            self.machine.fire(GroupEvent.HALT)
            self._couple()
            self.motion.halt(command, dec, jerk_value)
            self.end_table("aborted by MC_GroupHalt")  # a blocker is released (§9.3.1.2.6)
            if mode is BufferMode.ABORTING:  # a buffered halt keeps what was issued after it
                self._abort_queued("aborted by MC_GroupHalt")
        return self._after_motion(command, mode, start)

    def interrupt(self, deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT
                  ) -> Command:
        """MC_GroupInterrupt (§5.15): brake along the path, keep what remains for Continue."""
        command = self._command("group_interrupt")
        try:
            self.machine.accept("MC_GroupInterrupt")
            dec, jerk_value = self._brake_limits(deceleration, jerk, command)
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        self.motion.interrupt(command, dec, jerk_value)
        return command

    def continue_(self) -> Command:
        """MC_GroupContinue (§5.16): resume what MC_GroupInterrupt kept; Done once resumed."""
        command = self._command("group_continue")
        try:
            self.machine.accept("MC_GroupContinue")
            self.motion.resume()
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        return self._finish(command)

    def set_override(self, velocity: float = 1.0, acceleration: float = 1.0,
                     jerk: float = 1.0) -> Command:
        """MC_GroupSetOverride (§5.28): factors on the commanded dynamics; velocity may be 0
        (the path pauses), the others must be > 0; all at most 1 (decisions D-109)."""
        command = self._command("group_set_override")
        values = (velocity, acceleration, jerk)
        names = ("VelFactor", "AccFactor", "JerkFactor")
        for name, value, low_ok in zip(names, values, (True, False, False), strict=True):
            if isinstance(value, bool) or not isinstance(value, int | float) \
                    or not math.isfinite(value) or value < 0.0 or (value == 0.0 and not low_ok):
                return self._reject(command, CommandRejected(
                    ErrorId.INVALID_OVERRIDE, f"{name} must be {'>=' if low_ok else '>'} 0, "
                    f"got {value!r} (§5.28)"))
            if value > 1.0:
                command.warnings.append(f"{name} {value:g} clamped to 1.0")
        factors = tuple(min(float(v), 1.0) for v in values)
        if factors != self.factors:
            self.factors = factors  # type: ignore[assignment]
            self.motion.set_factors(*self.factors)
        return self._finish(command)

    def home(self, position: Any = None, buffer_mode: BufferMode = BufferMode.ABORTING,
             coord_system: CoordSystem = CoordSystem.ACS) -> Command:
        """MC_GroupHome (§5.7): every member homes (its own MC_Home); GroupHoming until all
        are Done. ``position``: where the group is after homing in ``coord_system`` (one
        value per axis in ACS, per coordinate in MCS and PCS, taken back to ACS through the
        transforms in force when the call is accepted), or None for each axis' configured
        home position. Aborting needs GroupStandby; Buffered (and the Blending modes, which
        act as Buffered) waits until the motion before it is over."""
        command = self._command("group_home")
        try:
            mode = part4_buffer_mode(buffer_mode)
            self.machine.accept("MC_GroupHome", mode)
            coord = enum_value(CoordSystem, coord_system, "CoordSystem")
            if position is not None:
                values = self._home_values(position, coord)
            else:
                values = [None] * len(self.members)
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        return self._after_motion(command, mode, lambda: self._start_home(command, values))

    def _home_values(self, position: Any, coord: CoordSystem) -> list[Any]:
        """MC_GroupHome's Position as one reference value per member (D-194)."""
        from openmotion.coordinated.inputs import vector
        if coord is CoordSystem.ACS:
            return vector(position, len(self.members), "Position").tolist()
        value = vector(position, self.spaces.size, "Position")
        mcs = value if coord is CoordSystem.MCS else self.spaces.mcs_of(value, self.runtime.now)
        return [float(x) for x in self.spaces.to_acs(mcs, near=self.acs_set())]

    def _start_home(self, command: Command, values: list[Any]) -> None:
        self.machine.fire(GroupEvent.HOME_START)
        self._home = []
        for axis, value in zip(self.axes, values, strict=True):
            with self.members.ungrouped(axis):
                part = axis.home() if value is None else axis.home(value)
            self._home.append(part)
        self._couple()
        command.status = CommandStatus.ACTIVE
        self._home_command = command
        # after the members' homing sequences (watchers run by row, then by age): the group
        # is GroupStandby in the cycle its last member is homed, never StandStill under
        # GroupHoming (Table 5)
        self.runtime.axis_system.watch(max(self.axes, key=lambda a: a.row), self._watch_home)
        return command

    def _watch_home(self, now: float) -> bool:
        self._end_home(now)
        return self._home_command is not None

    # -- path moves (§5.20-§5.27) --------------------------------------------------------------

    def move_linear_absolute(self, position: Any, velocity: InputValue = MC_DEFAULT,
                             acceleration: InputValue = MC_DEFAULT,
                             deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                             coord_system: CoordSystem = CoordSystem.MCS,
                             buffer_mode: BufferMode = BufferMode.ABORTING,
                             transition_mode: TransitionMode = TransitionMode.TM_NONE,
                             transition_parameter: Any = None) -> Command:
        """MC_MoveLinearAbsolute (§5.20): a straight line to ``position`` in ``coord_system``."""
        options = PathMoveOptions(velocity, acceleration, deceleration, jerk, coord_system,
                                  buffer_mode, transition_mode, transition_parameter)
        return self._path("MC_MoveLinearAbsolute", "linear", position, None, options,
                          relative=False)

    def move_linear_relative(self, distance: Any, velocity: InputValue = MC_DEFAULT,
                             acceleration: InputValue = MC_DEFAULT,
                             deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                             coord_system: CoordSystem = CoordSystem.MCS,
                             buffer_mode: BufferMode = BufferMode.ABORTING,
                             transition_mode: TransitionMode = TransitionMode.TM_NONE,
                             transition_parameter: Any = None) -> Command:
        """MC_MoveLinearRelative (§5.21): ``distance`` from where the TCP is when the FB is
        accepted, or from the end of the queue when it is buffered."""
        options = PathMoveOptions(velocity, acceleration, deceleration, jerk, coord_system,
                                  buffer_mode, transition_mode, transition_parameter)
        return self._path("MC_MoveLinearRelative", "linear", distance, None, options,
                          relative=True)

    def move_circular_absolute(self, aux_point: Any, end_point: Any,
                               circ_mode: CircMode = CircMode.BORDER,
                               path_choice: PathChoice = PathChoice.COUNTERCLOCKWISE,
                               velocity: InputValue = MC_DEFAULT,
                               acceleration: InputValue = MC_DEFAULT,
                               deceleration: InputValue = MC_DEFAULT,
                               jerk: InputValue = MC_DEFAULT,
                               coord_system: CoordSystem = CoordSystem.MCS,
                               buffer_mode: BufferMode = BufferMode.ABORTING,
                               transition_mode: TransitionMode = TransitionMode.TM_NONE,
                               transition_parameter: Any = None) -> Command:
        """MC_MoveCircularAbsolute (§5.22): BORDER, CENTER or RADIUS, see geometry/path.py."""
        options = PathMoveOptions(velocity, acceleration, deceleration, jerk, coord_system,
                                  buffer_mode, transition_mode, transition_parameter)
        circle = (aux_point, circ_mode, path_choice)
        return self._path("MC_MoveCircularAbsolute", "circular", end_point, circle, options,
                          relative=False)

    def move_circular_relative(self, aux_point: Any, end_point: Any,
                               circ_mode: CircMode = CircMode.BORDER,
                               path_choice: PathChoice = PathChoice.COUNTERCLOCKWISE,
                               velocity: InputValue = MC_DEFAULT,
                               acceleration: InputValue = MC_DEFAULT,
                               deceleration: InputValue = MC_DEFAULT,
                               jerk: InputValue = MC_DEFAULT,
                               coord_system: CoordSystem = CoordSystem.MCS,
                               buffer_mode: BufferMode = BufferMode.ABORTING,
                               transition_mode: TransitionMode = TransitionMode.TM_NONE,
                               transition_parameter: Any = None) -> Command:
        """MC_MoveCircularRelative (§5.23): AuxPoint and EndPoint are offsets from the start."""
        options = PathMoveOptions(velocity, acceleration, deceleration, jerk, coord_system,
                                  buffer_mode, transition_mode, transition_parameter)
        circle = (aux_point, circ_mode, path_choice)
        return self._path("MC_MoveCircularRelative", "circular", end_point, circle, options,
                          relative=True)

    def move_direct_absolute(self, position: Any, velocity: InputValue = MC_DEFAULT,
                             acceleration: InputValue = MC_DEFAULT,
                             deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                             coord_system: CoordSystem = CoordSystem.ACS,
                             buffer_mode: BufferMode = BufferMode.ABORTING,
                             transition_mode: TransitionMode = TransitionMode.TM_NONE,
                             transition_parameter: Any = None) -> Command:
        """MC_MoveDirectAbsolute (§5.24): point to point in joint space, every axis within its
        own limits and all ending together; the dynamics inputs are in ACS units."""
        options = PathMoveOptions(velocity, acceleration, deceleration, jerk, coord_system,
                                  buffer_mode, transition_mode, transition_parameter)
        return self._path("MC_MoveDirectAbsolute", "direct", position, None, options,
                          relative=False)

    def move_direct_relative(self, distance: Any, velocity: InputValue = MC_DEFAULT,
                             acceleration: InputValue = MC_DEFAULT,
                             deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                             coord_system: CoordSystem = CoordSystem.ACS,
                             buffer_mode: BufferMode = BufferMode.ABORTING,
                             transition_mode: TransitionMode = TransitionMode.TM_NONE,
                             transition_parameter: Any = None) -> Command:
        """MC_MoveDirectRelative (§5.25)."""
        options = PathMoveOptions(velocity, acceleration, deceleration, jerk, coord_system,
                                  buffer_mode, transition_mode, transition_parameter)
        return self._path("MC_MoveDirectRelative", "direct", distance, None, options,
                          relative=True)

    def move_path(self, path: Any, velocity: InputValue = MC_DEFAULT,
                  acceleration: InputValue = MC_DEFAULT, deceleration: InputValue = MC_DEFAULT,
                  jerk: InputValue = MC_DEFAULT, coord_system: CoordSystem = CoordSystem.MCS,
                  buffer_mode: BufferMode = BufferMode.ABORTING,
                  transition_mode: TransitionMode = TransitionMode.TM_NONE,
                  transition_parameter: Any = None) -> Command:
        """MC_MovePath (§5.27): run a path prepared by MC_PathSelect (``PathData``)."""
        options = PathMoveOptions(velocity, acceleration, deceleration, jerk, coord_system,
                                  buffer_mode, transition_mode, transition_parameter)
        return self._path("MC_MovePath", "path", path, None, options,
                          relative=False)

    def move_path_table(self, path_data: Any) -> Command:
        """MC_MovePath of TF5410 §9.3.1.2.5: run the rows of an ``MC_PATH_DATA_REF``
        (coordinated/path_table.py). The first row's BufferMode says whether it aborts what
        runs (a table that runs included) or follows it; Done when the last row is over."""
        from openmotion.coordinated.path_table import (
            MC_PATH_DATA_REF,
            PathTableRun,
            Segment,
            check_rows,
        )
        command = self._command("MC_MovePath")
        try:
            if not isinstance(path_data, MC_PATH_DATA_REF):
                raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY,
                                      "MC_MovePath needs an MC_PATH_DATA_REF or the PathData "
                                      "of a Done MC_PathSelect")
            rows = path_data.rows  # a copy: the table may be cleared while this runs
            check_rows(self, rows)
            self.machine.accept("MC_MovePath")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        first = getattr(rows[0], "buffer_mode", BufferMode.BUFFERED)
        run = PathTableRun(self, rows, command)

        def start() -> None:
            self.table = run
            if self.state is G.STANDBY:
                self.machine.start("MC_MovePath")
                self._couple()
            if first is BufferMode.ABORTING and not isinstance(rows[0], Segment):
                self._abort_queued("aborted by MC_MovePath")
                if self.motion.running:  # a blocker or dwell first: brake to it
                    self.motion.brake(self.dynamics.deceleration, self.dynamics.jerk,
                                      "aborted by MC_MovePath")
            run.start()
        if self.table is not None:
            if first is not BufferMode.ABORTING:
                self.table.defer(command, start)
                return command
            self.end_table("aborted by MC_MovePath")
        start()
        return command

    def release_blocker(self, blocker_id: Any) -> Command:
        """MC_ReleaseBlocker (TF5410 §9.3.1.2.7): Done at once; UNKNOWN_BLOCKER when the
        running table has no such blocker ahead."""
        from openmotion.coordinated.path_table import _blocker_id
        command = self._command("MC_ReleaseBlocker")
        try:
            number = _blocker_id(blocker_id)
            if self.table is None:
                raise CommandRejected(ErrorId.UNKNOWN_BLOCKER,
                                      f"no path table runs: blocker {number} is unknown "
                                      "(§9.3.1.2.7)")
            self.table.release(number)
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        return self._finish(command)

    def blocker_status(self) -> tuple[bool, int]:
        """MC_GroupReadBlockerStatus (TF5410 §9.3.1.2.8): (blocked, blocker id or 0)."""
        return (False, 0) if self.table is None else self.table.blocker_status()

    @contextmanager
    def feeding_table(self) -> Iterator[None]:
        """The path table run hands in its own segments: they do not end it."""
        self._feeding = True
        try:
            yield
        finally:
            self._feeding = False

    def end_table(self, reason: str, error: tuple[ErrorId, str] | None = None) -> None:
        """A halt, stop, disable, group error or an Aborting motion ends a running path
        table: MC_MovePath CommandAborted (Error for a group error), blockers released."""
        table, self.table = self.table, None
        if table is not None and table.command.busy:
            table.end(reason, error)

    def _path(self, block: str, kind: str, target: Any, circle: Any, options: PathMoveOptions,
              relative: bool) -> Command:
        command = self._command(block)
        try:
            buffer_mode = part4_buffer_mode(options.buffer_mode)
            self.machine.accept(block, buffer_mode)
            request = build_request(self, command, kind, target, circle, options, buffer_mode,
                                    relative)
            if self.table is not None and not self._feeding:  # a path table runs (D-213)
                if buffer_mode is not BufferMode.ABORTING:
                    self.table.defer(command, lambda: self._submit(block, request))
                    return command
                self.end_table(f"aborted by {block}")
            if self._queued and buffer_mode is not BufferMode.ABORTING:  # behind them
                self._queued.append((command, True, lambda: self._submit(block, request)))
                return command
            self._submit(block, request)
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        if buffer_mode is BufferMode.ABORTING:
            self._abort_queued(f"aborted by {block}")
        return command

    def _submit(self, block: str, request: Any) -> None:
        was = self.state
        self.motion.submit(request)
        if was is G.STANDBY or self.state is G.STANDBY:
            self.machine.start(block)
            self._couple()

    # -- synchronisation and tracking (§6) -----------------------------------------------------

    def sync_group_to_axis(self, master: Axis, path: Any, mode: PathMode = PathMode.NON_PERIODIC,
                           tuc_numerator: Any = 1, tuc_denominator: Any = 1,
                           acceleration: InputValue = MC_DEFAULT,
                           deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                           coord_system: CoordSystem = CoordSystem.MCS,
                           buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_SyncGroupToAxis (§6.4): the arc length along ``path`` (MC_PathSelect's
        PathData) follows ``master``: s = TuCNumerator / TuCDenominator x (master - master
        when the coupling starts). Aborting takes over a moving group as any Aborting motion
        does (it brakes along its path, the old commands CommandAborted at once) and couples
        from the rest point; Buffered (and the Blending modes, which act as Buffered) waits,
        Busy and not Active, until the motion before it is over (decisions D-193). Active
        while it runs, ``command.in_velocity`` is InSync; MC_GroupStop or any other motion
        command ends it (CommandAborted)."""
        command = self._command("MC_SyncGroupToAxis")
        try:
            queue_mode = part4_buffer_mode(buffer_mode)
            self.machine.accept("MC_SyncGroupToAxis", queue_mode)
            ratio = _conversion(tuc_numerator, tuc_denominator)
            mode = PathMode(mode)
            options = PathMoveOptions(MC_DEFAULT, acceleration, deceleration, jerk, coord_system)
            request = build_request(self, command, "path", path, None, options,
                                    BufferMode.ABORTING, False)
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        _, a, d, j = request.dynamics  # §6.4 has no velocity: the group's maximum
        limits = Limits(self.dynamics.max_velocity, a, d, j)

        def couple(start: np.ndarray) -> None:
            """The path's time law becomes the cam, from the rest point ``start``."""
            if mode is PathMode.PERIODIC:
                try:
                    check_periodic(tuple(start), tuple(request.end))
                except CommandRejected:
                    self.motion.clear()
                    raise
            assert self.motion.law is not None
            self.motion.law = CamLaw(self.motion.law, master, ratio, mode, limits, command,
                                     self.runtime.cycle_time)

        def start() -> None:
            request.extra["couple"] = couple
            self.motion.submit(request)
            self._abort_queued("aborted by MC_SyncGroupToAxis")
            command.status = CommandStatus.ACTIVE
            if self.state is G.STANDBY and not command.finished:
                self.machine.start("MC_SyncGroupToAxis")
                self._couple()
        return self._after_motion(command, queue_mode, start)

    def track_conveyor_belt(self, belt: Axis, origin: Frame, initial_object: Frame,
                            coord_system: CoordSystem = CoordSystem.PCS,
                            buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_TrackConveyorBelt (§6.6): the PCS rides on ``belt`` from the moment it is set
        (the belt's travel counts from there); Active while it tracks, CommandAborted when
        a transform FB replaces the PCS. Starts no motion. ``coord_system``: the PCS, the
        one system that can move; ``buffer_mode`` as for the other tracking FBs
        (``_set_tracking``)."""
        return self._set_tracking(
            "MC_TrackConveyorBelt", coord_system, buffer_mode,
            lambda command: ConveyorFrame(belt, origin, initial_object, belt.set_position,
                                          command))

    def track_rotary_table(self, table: Axis, origin: Frame, initial_object: Frame,
                           coord_system: CoordSystem = CoordSystem.PCS,
                           buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_TrackRotaryTable (§6.7): the PCS turns with ``table`` about the z axis of
        ``origin``; as ``track_conveyor_belt`` otherwise."""
        return self._set_tracking(
            "MC_TrackRotaryTable", coord_system, buffer_mode,
            lambda command: RotaryTableFrame(table, origin, initial_object,
                                             table.set_position, command))

    def set_dyn_coord_transform(self, master: AxesGroup, offset: Frame,
                                mode: PathMode = PathMode.NON_PERIODIC,
                                coord_system: CoordSystem = CoordSystem.PCS,
                                buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_SetDynCoordTransform (§6.5): this group's PCS rides on ``master``'s TCP.
        ``mode`` (MC_PathMode) is checked and changes nothing: the frame follows the master's
        TCP whatever its path does (decisions D-194)."""
        if master is self:
            command = self._command("MC_SetDynCoordTransform")
            return self._reject(command, CommandRejected(ErrorId.INVALID_MODE,
                                                         "a group cannot follow itself"))
        try:
            PathMode(mode)
        except ValueError:
            command = self._command("MC_SetDynCoordTransform")
            return self._reject(command, CommandRejected(
                ErrorId.INVALID_MODE, f"Mode: non_periodic (0) or periodic (1), got {mode!r}"))
        return self._set_tracking("MC_SetDynCoordTransform", coord_system, buffer_mode,
                                  lambda command: GroupFrame(master, offset, command))

    def _set_tracking(self, block: str, coord_system: Any, buffer_mode: Any,
                      frame: Callable[[Command], Any]) -> Command:
        """The tracking FBs (§6.5-§6.7): CoordSystem names the system that becomes dynamic,
        and only the PCS can (the MCS is the machine's, the ACS the axes'); Aborting sets the
        frame now, Buffered (and the Blending modes, which act as Buffered) when the motion
        issued before is over, Busy and not Active until then (decisions D-194). The frame
        is made when it is set: a belt's or table's travel counts from that cycle."""
        command = self._command(block)
        try:
            mode = part4_buffer_mode(buffer_mode)
            self.machine.accept(block)
            coord = enum_value(CoordSystem, coord_system, "CoordSystem")
            if coord is not CoordSystem.PCS:
                raise CommandRejected(ErrorId.INVALID_MODE, f"CoordSystem {coord.name}: only "
                                      "the PCS can follow a moving object (§2.1, D-194)")
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        return self._after_motion(command, mode, lambda: self._track(command, frame(command)))

    def _track(self, command: Command, frame: Any) -> Command:
        self.motion.end_tracking(f"replaced by {command.kind}")
        self.spaces.dynamic = frame
        command.status = CommandStatus.ACTIVE
        return command

    def sync_axis_to_group(self, slave: Axis, ratio_numerator: float = 1.0,
                           ratio_denominator: float = 1.0,
                           acceleration: InputValue = MC_DEFAULT,
                           deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                           coord_system: CoordSystem = CoordSystem.MCS,
                           buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_SyncAxisToGroup (§6.3): ``slave`` ramps in to numerator/denominator x path speed
        (in ``coord_system``) with ``acceleration``, ``deceleration`` and ``jerk`` (MC_DEFAULT:
        the slave's defaults), then counts the path length, locked in position;
        ``command.in_velocity`` is InSync. A new call replaces the ratio (rule 116). Aborting
        takes the slave over at once; Buffered (and the Blending modes, which act as
        Buffered) waits, Busy and not Active, until the slave's own command is over
        (decisions D-193)."""
        command = self._command("MC_SyncAxisToGroup")
        try:
            mode = part4_buffer_mode(buffer_mode)
            self.machine.accept("MC_SyncAxisToGroup")
            if slave.group is not None:
                raise CommandRejected(ErrorId.AXIS_IN_GROUP, f"{slave.name} is grouped")
            if not slave.powered or slave.state not in (
                    AxisState.STANDSTILL, AxisState.DISCRETE_MOTION,
                    AxisState.CONTINUOUS_MOTION, AxisState.SYNCHRONIZED_MOTION):
                raise CommandRejected(ErrorId.AXIS_DISABLED,
                                      f"{slave.name} is {slave.state.name}")
            inputs = _sync_inputs(slave, ratio_numerator, ratio_denominator, acceleration,
                                  deceleration, jerk, coord_system, command.warnings)
        except CommandRejected as rejected:
            return self._reject(command, rejected)
        if mode is not BufferMode.ABORTING and (slave.has_job or slave.row in self._syncs):
            self._waiting_syncs.append((slave, inputs, command))
            return command
        self._start_sync(slave, inputs, command)
        return command

    def _start_sync(self, slave: Axis, inputs: SyncInputs, command: Command) -> None:
        old = self._syncs.pop(slave.row, None)
        if old is not None:
            old.end(self.runtime.now, "replaced by a new MC_SyncAxisToGroup")
        if slave.has_job:
            slave.queue.abort_all("aborted by MC_SyncAxisToGroup")
            slave.kernel.has_job[slave.row] = False
        command.status = CommandStatus.ACTIVE
        self._syncs[slave.row] = AxisSync(self, slave, inputs, command)

    def _start_waiting_syncs(self) -> None:
        """Buffered MC_SyncAxisToGroup: start once the slave's own command is over."""
        keep = []
        for slave, inputs, command in self._waiting_syncs:
            if command.finished:
                continue
            if slave.has_job or slave.row in self._syncs or slave.state not in (
                    AxisState.STANDSTILL, AxisState.SYNCHRONIZED_MOTION):
                keep.append((slave, inputs, command))
                continue
            self._start_sync(slave, inputs, command)
        self._waiting_syncs = keep

    # -- the cycle -----------------------------------------------------------------------------

    def objects(self) -> tuple[AxesGroup]:
        return (self,)

    def advance(self, now: float) -> None:
        """The motion phase, after the member axes' profiles: the path, syncs, resets."""
        if not self.members:
            return
        self._end_reset(now)
        self._check_members()
        if self.state in (G.MOVING, G.STOPPING) or self.motion.running:
            self.motion.advance(now)
        table = self.table
        if table is not None:
            table.step(now)
            if self.table is table and not table.command.busy:
                self.table = None
        if self._waiting_syncs:
            self._start_waiting_syncs()
        if self._syncs:
            for row, sync in list(self._syncs.items()):
                sync.step(now, self.runtime.cycle_time)
                if sync.command.finished:
                    del self._syncs[row]
        self._end_home(now)
        self._end_stop(now)
        self._end_pending()
        self._run_queued()
        solo = self.members.solo_running()
        if self.state is G.MOVING and self.motion.finished and self._home_command is None \
                and not solo and self.table is None:
            self.machine.fire(GroupEvent.MOTION_END)
            self._couple()
        elif self.state is G.STANDBY and solo:  # a member's MC_Stop outlasted MC_GroupStop
            self.machine.fire(GroupEvent.MOTION_START)
            self._couple()

    def _end_stop(self, now: float) -> None:
        command = self._stop
        if command is None:
            return
        if command.busy and not self.motion.running and self.all_axes_standing:
            command.end(CommandStatus.DONE, now)
            command.hold = command.hold  # the FB keeps it until Execute falls
        if command.done and not command.hold:
            self._stop = None
            self.machine.fire(GroupEvent.STOP_RELEASED)
            self._couple()

    def _end_home(self, now: float) -> None:
        command = self._home_command
        if command is None:
            return
        if any(part.busy for part in self._home):
            self._couple()  # a member whose MC_Home is Done waits in SynchronizedMotion
            return
        self._home_command = None
        failed = next((part for part in self._home if part.error), None)
        self._home = []
        for axis in self.axes:
            axis.group = self
        if failed is not None:
            command.end(CommandStatus.ERROR, now, failed.error_id, failed.message)
            self.fault(failed.error_id, f"homing failed: {failed.message}")
            return
        if self.state is G.HOMING:
            command.end(CommandStatus.DONE, now)
            self.machine.fire(GroupEvent.HOME_END)
            self._couple()
        else:
            command.end(CommandStatus.ABORTED, now, message="the group left GroupHoming")

    def _home_abort(self, reason: str) -> None:
        """MC_GroupHome ends (its members stop); what waits in ``_queued`` ends too."""
        self._abort_queued(reason)
        if self._home_command is None:
            return
        for axis in self.axes:
            with self.members.ungrouped(axis):
                axis.stop()
            axis.group = self
        self._home_command.end(CommandStatus.ABORTED, self.runtime.now, message=reason)
        self._home_command, self._home = None, []

    def _end_pending(self) -> None:
        if not self._pending:
            return
        keep = []
        for command, wait, apply in self._pending:
            if not command.busy:  # aborted while it waited (a path table that ended)
                continue
            if self.motion.all_ended(wait):
                apply()
                command.end(CommandStatus.DONE, self.runtime.now)
            elif command.busy:
                keep.append((command, wait, apply))
        self._pending = keep

    def _check_members(self) -> None:
        """§3.2: a member in ErrorStop or unpowered changes the group's state."""
        if self.state is G.DISABLED:
            return
        for axis in self.axes:
            state = axis.state
            if self.members.last_states.get(axis.row) is state:
                continue
            self.members.last_states[axis.row] = state
            event = member_event(state)
            if event is GroupEvent.ERROR and self.state is not G.ERROR_STOP:
                self.fault(ErrorId.GROUP_ERROR,
                           f"member {axis.name} is in ErrorStop: {axis.axis_error_message}")
            elif event is GroupEvent.MEMBER_POWER_OFF and self.state in (
                    G.HOMING, G.MOVING, G.STOPPING):
                self.motion.abort_all(f"member {axis.name} lost power")
                self.members.hold()
                if self._stop is not None:
                    self._stop.end(CommandStatus.ABORTED, self.runtime.now,
                                    message=f"member {axis.name} lost power")
                    self._stop = None
                self._home_abort(f"member {axis.name} lost power")
                self.machine.fire(event)
                self._couple()

    def fault(self, error_id: ErrorId, message: str) -> None:
        """GroupErrorStop (§3.1): motion aborted, every healthy axis brakes on its own."""
        self.error_id, self.error_message = error_id, message
        self.motion.abort_all(f"group error: {message}", error=(error_id, message))
        self._home_abort(f"group error: {message}")
        if self._stop is not None:
            self._stop.end(CommandStatus.ABORTED, self.runtime.now, message=message)
            self._stop = None
        self.members.brake()
        self.machine.fire(GroupEvent.ERROR)

    # -- single-axis commands on members (§3.2) ----------------------------------------------

    def admit_member(self, axis: Axis, family: str) -> None:
        """``Axis._admit`` of a member: moves are refused (§3.2 option 1); MC_Stop always
        passes and MC_Home in GroupStandby, and the group is GroupMoving until that command
        is over and every member stands (§3.2 general rules; decisions D-129). A running
        group motion or MC_GroupHome ends (CommandAborted) and the other members brake on
        their own, as by an implicit MC_Halt."""
        check_member_accepts(self.state, family)
        admit(axis.state, family)
        if family not in ("stop", "home"):
            return
        reason = f"aborted by MC_{family.capitalize()} on member {axis.name}"
        if self.state is G.HOMING:
            self._home_abort(reason)
            self.machine.fire(GroupEvent.HOME_END)
        elif self.state in (G.MOVING, G.STOPPING) and (self.motion.running
                                                        or not self.all_axes_standing):
            self.motion.abort_all(reason)
            self.members.brake()
        self.members.solo[axis.row] = axis
        event = member_command_event(self.state, family)
        if event is not None:
            self.machine.fire(event)
            self._couple()

    # -- members' setpoints --------------------------------------------------------------------

    def _couple(self) -> None:
        """Table 5: members show SynchronizedMotion while the group moves, homes or stops
        (a member's own MC_Home, run by MC_GroupHome, included: D-104)."""
        for axis in self.axes:
            if axis.row in self.members.solo:  # its own MC_Stop or MC_Home shows (§3.2)
                continue
            axis.state = member_state(self.state, axis.state)
            self.members.last_states[axis.row] = axis.state

    def _regrouped(self) -> None:
        if not self.spaces.explicit or self.spaces.kinematics.n_axes != len(self.members):
            self.spaces.set_kinematics(default_kinematics(len(self.members)), explicit=False)

    # -- helpers -------------------------------------------------------------------------------

    def _brake_limits(self, deceleration: InputValue, jerk: InputValue,
                      command: Command) -> tuple[float, float]:
        return (dynamic_value("deceleration", deceleration, self.dynamics, command.warnings),
                dynamic_value("jerk", jerk, self.dynamics, command.warnings))

    def _command(self, kind: str) -> Command:
        return Command(kind, self.runtime.now)

    def _finish(self, command: Command) -> Command:
        command.end(CommandStatus.DONE, self.runtime.now)
        return command

    def _reject(self, command: Command, rejected: CommandRejected) -> Command:
        command.end(CommandStatus.ERROR, self.runtime.now, rejected.error_id, rejected.message)
        return command


def _conversion(numerator: Any, denominator: Any) -> float:
    """TuCNumerator / TuCDenominator as one factor of the path parameter: scalars, or arrays
    whose factors agree (the path is one curve; D-127)."""
    numerators = list(numerator) if isinstance(numerator, list | tuple) else [numerator]
    denominators = list(denominator) if isinstance(denominator, list | tuple) else [denominator]
    if len(numerators) != len(denominators) or not numerators:
        raise CommandRejected(ErrorId.INVALID_GEAR_RATIO, "TuCNumerator and TuCDenominator "
                              "need one value each per axis")
    factors = set()
    for n, d in zip(numerators, denominators, strict=True):
        if not isinstance(n, int | float) or not isinstance(d, int | float) or \
                not math.isfinite(n) or not math.isfinite(d) or d == 0 or n == 0:
            raise CommandRejected(ErrorId.INVALID_GEAR_RATIO,
                                  f"TuCNumerator {n!r} / TuCDenominator {d!r}")
        factors.add(n / d)
    if len(factors) != 1:
        raise CommandRejected(ErrorId.INVALID_GEAR_RATIO, "different conversions per axis do "
                              "not keep the path: one factor for all (D-127)")
    return factors.pop()



def _sync_inputs(slave: Axis, numerator: Any, denominator: Any, acceleration: InputValue,
                 deceleration: InputValue, jerk: InputValue, coord_system: Any,
                 warnings: list[str]) -> SyncInputs:
    """MC_SyncAxisToGroup's inputs checked: a finite ratio, dynamics > 0 (MC_DEFAULT: the
    slave's default, MC_MAXIMUM: its maximum), one of the three coordinate systems."""
    for name, value in (("RatioNumerator", numerator), ("RatioDenominator", denominator)):
        if isinstance(value, bool) or not isinstance(value, int | float) \
                or not math.isfinite(value):
            raise CommandRejected(ErrorId.INVALID_GEAR_RATIO, f"{name}: {value!r}")
    if denominator == 0:
        raise CommandRejected(ErrorId.INVALID_GEAR_RATIO, "RatioDenominator is 0")
    parameters = slave.parameters
    limits = PathDynamics(acceleration=parameters.acceleration,
                          deceleration=parameters.deceleration, jerk=parameters.jerk,
                          max_acceleration=parameters.max_acceleration,
                          max_deceleration=parameters.max_deceleration,
                          max_jerk=parameters.max_jerk)
    return SyncInputs(numerator / denominator,
                      dynamic_value("acceleration", acceleration, limits, warnings),
                      dynamic_value("deceleration", deceleration, limits, warnings),
                      dynamic_value("jerk", jerk, limits, warnings),
                      enum_value(CoordSystem, coord_system, "CoordSystem"))
