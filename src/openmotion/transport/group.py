"""The CA group: movers on one rail that keep a gap to the mover ahead (TF5410).

Members are ordinary axes. While the group is enabled it owns their setpoints: every cycle,
right after the profiles are evaluated, the group lets each mover propose its next setpoint
and the gap filter (gap_control.py) makes the movers brake whose proposal is unsafe. A mover
that had to brake is *held*: it follows a tracking step towards its target until its way is
clear, then gets a fresh time-optimal profile again. Done only at the commanded target
(§9.1.1.1.1); a mover queued behind another stays Busy.

All per-mover numbers live in arrays in CA order (index 0 is the first mover, the one with
the largest position), so a cycle is a few numpy passes over the group.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.enums import AxisState, BufferMode
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.core.modulo import mc3_modulo_target
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE, MC_INVALID, InputValue
from openmotion.trajectory.plan import Limits, plan_position, plan_stop
from openmotion.trajectory.segments import KinematicState
from openmotion.transport.braking import brake_envelope, brake_state
from openmotion.transport.enums import (
    GapControlDirection,
    GapControlMode,
    GearInPosDefaultDynamicsAfterSync,
    GroupState,
    GroupType,
    ModuloDirection,
    SyncStrategy,
)
from openmotion.transport.gap_control import TOLERANCE, Pairs, filter_steps
from openmotion.transport.gear import GearSync
from openmotion.transport.inputs import ca_gap, ca_limits, ca_value, halt_limits
from openmotion.transport.parameters import PARAMETER_FIELDS, CaGroupParameters
from openmotion.transport.tracks import TrackTable

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.runtime.runtime import Runtime

IDLE, FOLLOW, HELD, GEAR = 0, 1, 2, 3  #: mover modes: no command, on its profile, held by
#: CA, coupled to a master (MC_GearInPosCA)
_POSITION, _HALT = "position", "halt"
_MOVING_STATES = (GroupState.STANDBY, GroupState.MOVING, GroupState.STOPPING)


@dataclass(frozen=True)
class IdentInGroup:
    """IDENT_IN_GROUP_REF of a CA member: made by ``UDINT_TO_IDENTINGROUP(n)`` (§9.3.1.1.13)."""

    value: int


def UDINT_TO_IDENTINGROUP(value: int) -> IdentInGroup:  # noqa: N802 - the manual's name
    """The identity an axis has in a CA group; it does not decide the CA order (§8.1.1)."""
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 0xFFFFFFFF:
        raise ValueError(f"UDINT_TO_IDENTINGROUP: a UDINT is needed, got {value!r}")
    return IdentInGroup(value)


@dataclass(frozen=True)
class GroupInterface:
    """NcToPlc of AXES_GROUP_REF (§11.1): what a PLC reads every cycle."""

    group_oid: int
    group_type: GroupType
    group_state: GroupState  #: GroupStatus.State
    is_enable_requested: bool  #: GroupStatus.Flags.IsEnableRequested
    group_error_id: int
    group_axes_count: int


@dataclass
class CaJob:
    """One CA motion command of a mover (active or buffered)."""

    kind: str  #: "position", "halt", "standby" or "gear"
    command: Command
    limits: Limits
    gap: float
    gap_mode: GapControlMode  #: resolved: STANDARD, FAST or NONE
    buffer_mode: BufferMode = BufferMode.ABORTING
    target_of: Callable[[float], float] | None = None  #: start position -> absolute target
    target: float = math.nan
    continuous_update: bool = False
    extra: Any = None  #: the GearSync of a "gear" job


@dataclass
class Mover:
    """A member of the group: its axis, identity and commands."""

    axis: Axis
    ident: IdentInGroup
    added: int  #: insertion serial (ties in the CA order: the last added is first)
    job: CaJob | None = None
    queue: list[CaJob] = field(default_factory=list)
    gap: float = 0.0  #: the last valid gap (§9.1.2.5: kept after a None command)
    slot: int = -1  #: index in the group's arrays (CA order)


class CaGroup:
    """A CA group on a rail; create with ``CaGroup(runtime, "ca", rail_length=...)``."""

    def __init__(self, runtime: Runtime, name: str = "ca",
                 parameters: CaGroupParameters | None = None, **overrides: Any) -> None:
        unknown = set(overrides) - PARAMETER_FIELDS
        if unknown:
            raise ConfigError(f"CA group {name!r}: unknown parameter(s) {sorted(unknown)}")
        parameters = parameters or CaGroupParameters()
        for key, value in overrides.items():
            setattr(parameters, key, value)
        try:
            parameters.validate()
        except (TypeError, ValueError) as exc:
            raise ConfigError(f"CA group {name!r}: {exc}") from None
        self.name = name
        self.oid = 0x05030000 + len(runtime._systems) + 1  #: TcCOM-like object id (ours)
        self.parameters = parameters
        self._rt = runtime
        self._k = runtime._kernel
        self.state = GroupState.DISABLED
        self.error_disabled = False  #: internal GroupErrorDisabled (not visible, §7.2)
        self.error_id = ErrorId.NO_ERROR  #: GroupErrorId of the cyclic interface
        self.movers: list[Mover] = []  #: in CA order once enabled
        self._serial = 0
        self._stop: Command | None = None  #: MC_GroupStop holding the group
        self._halt: Command | None = None  #: MC_GroupHalt in progress
        self._halt_parts: list[Command] = []  #: its per-mover halts
        self._reset: Command | None = None  #: MC_GroupReset waiting for the members' MC_Reset
        self._reset_parts: list[Command] = []
        self._arrays(0)
        self.tracks = TrackTable(self)  #: parts, tracks and geo-compensation (tracks.py)
        runtime._add_system(self._advance)

    # -- reading -------------------------------------------------------------------------------

    @property
    def axes_count(self) -> int:
        """GroupAxesCount of the cyclic interface."""
        return len(self.movers)

    @property
    def all_axes_standing(self) -> bool:
        """MC_GroupReadStatus.AllAxesStanding: no member moves (v = 0 and a = 0)."""
        self._fresh()
        k, rows = self._k, self.rows
        return bool(np.all(k.set_v[rows] == 0.0) and np.all(k.set_a[rows] == 0.0))

    def _fresh(self) -> None:
        """Order and arrays once members were added to a disabled group."""
        if self.rows.size != len(self.movers):
            self._reorder()

    @property
    def order(self) -> list[str]:
        """Axis names in CA order: the first mover first."""
        self._fresh()
        return [m.axis.name for m in self.movers]

    def mover_of(self, axis: Axis) -> Mover:
        for mover in self.movers:
            if mover.axis is axis:
                return mover
        raise KeyError(axis.name)

    def gaps(self) -> np.ndarray:
        """Setpoint gap of each mover to its predecessor, in CA order (inf: none)."""
        self._fresh()
        k = self._k
        p = k.set_p[self.rows] if self.rows.size else np.zeros(0)
        gaps = np.full(len(self.movers), np.inf)
        has = self.pred >= 0
        gaps[has] = p[self.pred[has]] + self.offset[has] - p[has]
        return gaps

    @property
    def nc_to_plc(self) -> GroupInterface:
        """The cyclic group interface NcToPlc (§11.1), as a PLC reads it."""
        enabled = self.state not in (GroupState.DISABLED,) and not self.error_disabled
        return GroupInterface(self.oid, GroupType.CA, self.state, enabled, int(self.error_id),
                              len(self.movers))

    def predecessor(self, axis: Axis) -> Axis | None:
        slot = self.mover_of(axis).slot
        return None if self.pred[slot] < 0 else self.movers[int(self.pred[slot])].axis

    # -- administration (Tc3_McCoordinatedMotion §9.3.1.1) -------------------------------------

    def add_axis(self, axis: Axis, ident: IdentInGroup) -> Command:
        """MC_AddAxisToGroup: standing axes only; the CA order follows the positions."""
        command = self._command("add_axis")
        if not isinstance(ident, IdentInGroup):
            return self._reject(command, ErrorId.INVALID_IDENT,
                                "IdentInGroup must come from UDINT_TO_IDENTINGROUP(n)")
        if axis.group is self:
            if self.mover_of(axis).ident == ident:
                return self._finish(command)
            return self._reject(command, ErrorId.IDENT_IN_USE,
                                f"{axis.name} is a member already")
        if axis.group is not None:
            return self._reject(command, ErrorId.AXIS_IN_OTHER_GROUP,
                                f"{axis.name} is in group {getattr(axis.group, 'name', '?')!r}")
        if any(m.ident == ident for m in self.movers):
            return self._reject(command, ErrorId.IDENT_IN_USE,
                                f"IdentInGroup {ident.value} is taken")
        if axis.moving or axis.has_job:
            return self._reject(command, ErrorId.AXIS_MOVING, f"{axis.name} is moving")
        self._serial += 1
        mover = Mover(axis, ident, self._serial, gap=self.parameters.default_gap)
        axis.group = self
        self.movers.append(mover)
        if self.state is not GroupState.DISABLED:
            self._reorder()
        else:
            mover.slot = len(self.movers) - 1
        if self.state is GroupState.STANDBY and not axis.powered:
            self.state = GroupState.NOT_READY
        return self._finish(command)

    def remove_axis(self, ident: IdentInGroup) -> Command:
        """MC_RemoveAxisFromGroup: Done also when no member has ``ident`` (§9.3.1.1.8)."""
        command = self._command("remove_axis")
        mover = next((m for m in self.movers if m.ident == ident), None)
        if mover is None:
            return self._finish(command)
        if mover.job is not None or self._moving(mover):
            return self._reject(command, ErrorId.AXIS_MOVING,
                                f"{mover.axis.name} is moving or has a command")
        self._drop(mover)
        return self._finish(command)

    def ungroup_all(self) -> Command:
        """MC_UngroupAllAxes: remove every axis and disable the group (§9.3.1.1.12)."""
        command = self._command("ungroup_all")
        self._disable()
        for mover in list(self.movers):
            self._drop(mover)
        return self._finish(command)

    def enable(self) -> Command:
        """MC_GroupEnable: Standby once every member is powered, else NotReady."""
        command = self._command("enable")
        if self.state in (GroupState.ERROR_STOP,) or self.error_disabled:
            return self._reject(command, ErrorId.GROUP_IN_ERROR,
                                "the group is in error: MC_GroupReset first")
        if not self.movers:
            return self._reject(command, ErrorId.GROUP_EMPTY, "the group has no axes")
        if self.state is GroupState.DISABLED:
            self._reorder()
            self._sync_states()
            self.state = GroupState.NOT_READY
            self._check_ready()
        return self._finish(command)

    def disable(self) -> Command:
        """MC_GroupDisable: a moving group stands still at once (§9.3.1.1.2: avoid that)."""
        command = self._command("disable")
        if not self.all_axes_standing:
            command.warnings.append("the group was moving: every mover stopped at once")
        self._disable()
        return self._finish(command)

    def reset(self) -> Command:
        """MC_GroupReset: clear group and member errors; no effect without an error.

        Busy until every member in ErrorStop has been reset (MC_Reset waits for rest)."""
        command = self._command("reset")
        if self.state is GroupState.ERROR_STOP or self.error_disabled:
            self._reset_parts = [m.axis.reset() for m in self.movers
                                 if m.axis.state is AxisState.ERROR_STOP]
            command.status = CommandStatus.ACTIVE
            self._reset = command
            self._end_reset()
            return command
        return self._finish(command)

    def _end_reset(self) -> None:
        command = self._reset
        if command is None or any(part.busy for part in self._reset_parts):
            return
        self._reset = None
        failed = next((part for part in self._reset_parts if part.error), None)
        if failed is not None:
            self._reject(command, failed.error_id, failed.message)
            return
        self.error_id = ErrorId.NO_ERROR
        if self.error_disabled:
            self.error_disabled = False
            self.state = GroupState.DISABLED
        else:
            self._sync_states()
            self.state = GroupState.NOT_READY
            self._check_ready()
        self._finish(command)

    def halt(self, deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT
             ) -> Command:
        """MC_GroupHalt: every mover brakes to rest; the group is not locked (§9.3.1.2.1)."""
        command = self._command("group_halt")
        try:
            self._admit_motion()
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        parts = []
        for mover in self.movers:
            inner = self._command("halt")
            self._issue_halt(mover, inner, deceleration, jerk, mover.gap,
                             GapControlMode.GROUP_DEFAULT)
            if inner.error:
                return self._reject(command, inner.error_id, inner.message)
            parts.append(inner)
        command.status = CommandStatus.ACTIVE
        self._halt, self._halt_parts = command, parts
        return command

    def stop(self, deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT
             ) -> Command:
        """MC_GroupStop: brake every mover and lock the group until ``release`` (§9.3.1.2.2).

        Done at standstill; the group stays Stopping until ``command.release()`` (the
        falling edge of Execute).
        """
        command = self._command("group_stop")
        if self.state not in _MOVING_STATES and self.state is not GroupState.NOT_READY:
            return self._reject(command, *self._refusal())
        for mover in self.movers:
            inner = self._command("stop")
            self._issue_halt(mover, inner, deceleration, jerk, mover.gap,
                             GapControlMode.GROUP_DEFAULT)
            if inner.error:
                return self._reject(command, inner.error_id, inner.message)
        command.status = CommandStatus.ACTIVE
        command.hold = True
        self._stop = command
        self.state = GroupState.STOPPING
        return command

    # -- mover commands (Tc3_McCollisionAvoidance §9.1.1.1) ------------------------------------

    def move_absolute(self, axis: Axis, position: InputValue, velocity: InputValue,
                      acceleration: InputValue = MC_DEFAULT,
                      deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                      gap: InputValue = MC_DEFAULT,
                      buffer_mode: BufferMode = BufferMode.ABORTING,
                      direction: ModuloDirection = ModuloDirection.NON_MODULO,
                      additional_turns: int = 0,
                      gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT,
                      continuous_update: bool = False, position_reference_system: int = 0,
                      dynamics_reference_system: int = 0) -> Command:
        """MC_MoveAbsoluteCA: to ``position`` (a modulo position with a modulo direction)."""
        command = self._command("move_absolute_ca")

        def build(mover: Mover) -> CaJob:
            direction_ = _enum(ModuloDirection, direction, ErrorId.INVALID_DIRECTION,
                               "direction")
            if direction_ is not ModuloDirection.NON_MODULO and not self.parameters.rail_is_ring:
                raise CommandRejected(ErrorId.MODULO_ON_OPEN_RAIL,
                                      "modulo directions need a rail that is a ring")
            target = _position("position", position)
            turns = additional_turns
            if isinstance(turns, bool) or not isinstance(turns, int) or turns < 0:
                raise CommandRejected(ErrorId.INVALID_ADDITIONAL_TURNS,
                                      f"additional_turns: a UDINT, got {turns!r}")
            length = self.parameters.rail_length
            window = mover.axis.parameters.modulo_tolerance_window
            # tracks and geo-compensation (transport/tracks.py): ``position`` is in the mover's
            # frame (its active track, PositionReferenceSystem); from here on the motor path
            target = self.tracks.to_absolute(mover.axis, target, direction_,
                                             position_reference_system)
            mc3_modulo_target(0.0, target, int(direction_), turns, length, window)  # validate
            job = self._job(mover, _POSITION, command, velocity, acceleration, deceleration,
                            jerk, gap, buffer_mode, gap_control_mode, continuous_update)
            job.target_of = lambda start: mc3_modulo_target(start, target, int(direction_),
                                                            turns, length, window)
            self.tracks.compensate(mover.axis, job, dynamics_reference_system)  # TCP dynamics
            return job

        return self._submit(axis, command, build)

    def move_relative(self, axis: Axis, distance: InputValue, velocity: InputValue,
                      acceleration: InputValue = MC_DEFAULT,
                      deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                      gap: InputValue = MC_DEFAULT,
                      buffer_mode: BufferMode = BufferMode.ABORTING,
                      gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT,
                      continuous_update: bool = False, position_reference_system: int = 0,
                      dynamics_reference_system: int = 0) -> Command:
        """MC_MoveRelativeCA: by ``distance`` from the set position where it starts; with a
        mover template as PositionReferenceSystem the distance is measured on its TCP path."""
        command = self._command("move_relative_ca")

        def build(mover: Mover) -> CaJob:
            step = _position("distance", distance)
            job = self._job(mover, _POSITION, command, velocity, acceleration, deceleration,
                            jerk, gap, buffer_mode, gap_control_mode, continuous_update)
            geo = self.tracks.geo
            template = geo.reference(mover.axis, position_reference_system)
            if template is None:
                job.target_of = lambda start: start + step
            else:
                job.target_of = lambda start: geo.to_motor(template,
                                                           geo.to_tcp(template, start) + step)
            self.tracks.compensate(mover.axis, job, dynamics_reference_system)  # TCP dynamics
            return job

        return self._submit(axis, command, build)

    def halt_axis(self, axis: Axis, deceleration: InputValue = MC_DEFAULT,
                  jerk: InputValue = MC_DEFAULT, gap: InputValue = MC_DEFAULT,
                  gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT) -> Command:
        """MC_HaltCA: brake to rest; the axis is not locked (§9.1.1.1.3)."""
        command = self._command("halt_ca")
        try:
            self._admit_motion()
            mover = self._member(axis)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self._issue_halt(mover, command, deceleration, jerk, gap, gap_control_mode)
        return command

    def gear_in_pos(self, master: Axis, slave: Axis, ratio_numerator: float = 1.0,
                    ratio_denominator: int = 1,
                    master_sync_position: InputValue = MC_INVALID,
                    slave_sync_position: InputValue = MC_INVALID,
                    sync_strategy: SyncStrategy = SyncStrategy.LATE,
                    master_start_distance: InputValue = MC_IGNORE,
                    velocity: InputValue = MC_INVALID, acceleration: InputValue = MC_DEFAULT,
                    deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
                    gap: InputValue = MC_DEFAULT, buffer_mode: BufferMode = BufferMode.ABORTING,
                    after_sync_velocity: InputValue = MC_DEFAULT,
                    after_sync_acceleration: InputValue = MC_DEFAULT,
                    after_sync_deceleration: InputValue = MC_DEFAULT,
                    after_sync_jerk: InputValue = MC_DEFAULT,
                    master_velocity_undershoot_allowed: bool = True,
                    master_velocity_overshoot_allowed: bool = True,
                    override_slave_dynamic_restrictions: bool = False,
                    gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT,
                    continuous_update: bool = False) -> Command:
        """MC_GearInPosCA (§9.1.1.1.4): couple ``slave`` to ``master``'s set values.

        The command never ends Done: another command (aborting) decouples. ``sync_state``
        gives StartSync and InSync.
        """
        command = self._command("gear_in_pos_ca")

        def build(mover: Mover) -> CaJob:
            if not master_velocity_undershoot_allowed and not master_velocity_overshoot_allowed:
                raise CommandRejected(ErrorId.INVALID_SYNC_OPTIONS, "master velocity under- "
                                      "and overshoot cannot both be forbidden")
            if master is slave:
                raise CommandRejected(ErrorId.INVALID_PARAMETER_VALUE,
                                      "a mover cannot be its own master")
            denominator = ratio_denominator
            if isinstance(denominator, bool) or not isinstance(denominator, int) or \
                    not 1 <= denominator <= 0xFFFF:
                raise CommandRejected(ErrorId.INVALID_GEAR_RATIO,
                                      f"ratio_denominator: a UINT > 0, got {denominator!r}")
            numerator = _position("ratio_numerator", ratio_numerator)
            strategy = _enum(SyncStrategy, sync_strategy, ErrorId.INVALID_MODE, "sync_strategy")
            msp = _position("master_sync_position", master_sync_position)
            ssp = _position("slave_sync_position", slave_sync_position)
            start = None if master_start_distance is MC_IGNORE else \
                _position("master_start_distance", master_start_distance)
            job = self._job(mover, "gear", command, velocity, acceleration, deceleration, jerk,
                            gap, buffer_mode, gap_control_mode, continuous_update)
            params = mover.axis.parameters
            if self.parameters.gear_in_pos_default_dynamics_after_sync is \
                    GearInPosDefaultDynamicsAfterSync.JOB_DYNAMICS:
                defaults = job.limits
            else:  # the slave's maxima, jerk unlimited (here: the axis' max_jerk)
                defaults = Limits(params.max_velocity, params.max_acceleration,
                                  params.max_deceleration, params.max_jerk)
            warnings = command.warnings

            def after(name: str, value: InputValue, default: float) -> float:
                return default if value is MC_DEFAULT else ca_value(name, value, params,
                                                                     warnings)

            after_sync = Limits(after("velocity", after_sync_velocity, defaults.velocity),
                                after("acceleration", after_sync_acceleration,
                                      defaults.acceleration),
                                after("deceleration", after_sync_deceleration,
                                      defaults.deceleration),
                                after("jerk", after_sync_jerk, defaults.jerk))
            job.extra = GearSync(master.row, numerator / denominator, msp, ssp, strategy, start,
                                 job.limits, after_sync, bool(override_slave_dynamic_restrictions))
            return job

        return self._submit(slave, command, build)

    def sync_state(self, command: Command) -> tuple[bool, bool]:
        """(StartSync, InSync) of a gear_in_pos command; (False, False) once it ended."""
        for mover in self.movers:
            job = mover.job
            if job is not None and job.command is command and isinstance(job.extra, GearSync):
                return job.extra.start_sync, job.extra.in_sync
        return False, False

    def set_gap(self, command: Command, gap: InputValue) -> None:
        """ContinuousUpdate: a running command with continuous_update takes a new gap."""
        for mover in self.movers:
            job = mover.job
            if job is not None and job.command is command and job.continuous_update:
                try:
                    job.gap = ca_gap(gap, self.parameters.default_gap)
                except CommandRejected:
                    return
                if job.gap_mode is not GapControlMode.NONE:
                    mover.gap = job.gap
                    self.gap[mover.slot] = job.gap
                    self._pairs_dirty = True
                    self._room_of = None
                return

    # -- internals: commands --------------------------------------------------------------------

    def _command(self, kind: str) -> Command:
        return Command(kind, self._rt.now)

    def _finish(self, command: Command) -> Command:
        command._end(CommandStatus.DONE, self._rt.now)
        return command

    def _reject(self, command: Command, error_id: ErrorId, message: str) -> Command:
        command._end(CommandStatus.ERROR, self._rt.now, error_id, message)
        return command

    def _refusal(self) -> tuple[ErrorId, str]:
        if self.state is GroupState.STOPPING:
            return ErrorId.GROUP_STOPPING, "MC_GroupStop holds the group"
        if self.state is GroupState.ERROR_STOP:
            return ErrorId.GROUP_IN_ERROR, "the group is in GroupErrorStop: MC_GroupReset first"
        return ErrorId.GROUP_NOT_ENABLED, f"the group is {self.state.name}: enable it first"

    def _admit_motion(self) -> None:
        if self.state not in (GroupState.STANDBY, GroupState.MOVING):
            raise CommandRejected(*self._refusal())

    def _member(self, axis: Axis) -> Mover:
        if axis.group is not self:
            raise CommandRejected(ErrorId.AXIS_NOT_IN_GROUP,
                                  f"{axis.name} is not in CA group {self.name!r}")
        mover = self.mover_of(axis)
        if not (axis.powered and axis.enable_positive and axis.enable_negative):
            raise CommandRejected(ErrorId.AXIS_DISABLED,
                                  f"{axis.name} is not enabled in both directions")
        return mover

    def _job(self, mover: Mover, kind: str, command: Command, velocity: InputValue,
             acceleration: InputValue, deceleration: InputValue, jerk: InputValue,
             gap: InputValue, buffer_mode: BufferMode, gap_control_mode: GapControlMode,
             continuous_update: bool) -> CaJob:
        mode = _enum(BufferMode, buffer_mode, ErrorId.INVALID_BUFFER_MODE, "buffer_mode")
        if mode not in (BufferMode.ABORTING, BufferMode.BUFFERED):
            raise CommandRejected(ErrorId.INVALID_BUFFER_MODE,
                                  f"the CA blocks take Aborting or Buffered, not {mode.name}")
        limits = ca_limits(mover.axis.parameters, command.warnings, velocity, acceleration,
                           deceleration, jerk)
        return CaJob(kind, command, limits, ca_gap(gap, self.parameters.default_gap),
                     self._gap_mode(gap_control_mode), mode,
                     continuous_update=bool(continuous_update))

    def _gap_mode(self, value: GapControlMode) -> GapControlMode:
        mode = _enum(GapControlMode, value, ErrorId.INVALID_MODE, "gap_control_mode")
        return self.parameters.default_gap_control_mode if mode is GapControlMode.GROUP_DEFAULT \
            else mode

    def _submit(self, axis: Axis, command: Command, build: Callable[[Mover], CaJob]) -> Command:
        try:
            self._admit_motion()
            mover = self._member(axis)
            job = build(mover)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        if job.buffer_mode is BufferMode.BUFFERED and mover.job is not None:
            job.command.status = CommandStatus.BUFFERED
            mover.queue.append(job)
            return command
        self._start(mover, job)
        return command

    def _issue_halt(self, mover: Mover, command: Command, deceleration: InputValue,
                    jerk: InputValue, gap: InputValue, gap_control_mode: GapControlMode) -> None:
        try:
            limits = halt_limits(mover.axis.parameters, command.warnings, deceleration, jerk)
            job = CaJob(_HALT, command, limits, ca_gap(gap, self.parameters.default_gap),
                        self._gap_mode(gap_control_mode))
        except CommandRejected as rejected:
            self._reject(command, rejected.error_id, rejected.message)
            return
        self._start(mover, job)

    def _start(self, mover: Mover, job: CaJob) -> None:
        """Make ``job`` the mover's command now: abort what runs or waits, plan from here."""
        slot = mover.slot
        start = KinematicState(float(self.p[slot]), float(self.v[slot]), float(self.a[slot]))
        try:
            if job.kind == "gear":
                profile = None
            elif job.kind == _HALT:
                profile = plan_stop(start, job.limits.deceleration, job.limits.jerk)
                job.target = profile.end.position
            else:
                assert job.target_of is not None
                job.target = job.target_of(start.position)
                profile = plan_position(start, job.target, job.limits)
        except CommandRejected as rejected:
            self._reject(job.command, rejected.error_id, rejected.message)
            return
        self._abort(mover, f"aborted by {job.command.kind}")
        mover.job = job
        job.command.status = CommandStatus.ACTIVE
        if profile is None:
            self.mode[slot] = GEAR
        else:
            self._k.segments.install(mover.axis.row, profile, self._k.sample_time)
            self.mode[slot] = FOLLOW
        self.goal[slot] = job.target
        self._load_job(mover)
        if mover.axis.state in (AxisState.STANDSTILL, AxisState.DISCRETE_MOTION):
            mover.axis.state = AxisState.DISCRETE_MOTION
        if self.state is GroupState.STANDBY:
            self.state = GroupState.MOVING

    def _load_job(self, mover: Mover) -> None:
        """Copy the job's numbers into the arrays the cycle reads."""
        job, slot = mover.job, mover.slot
        assert job is not None
        if job.gap_mode is not GapControlMode.NONE:
            mover.gap = job.gap
        self.gap[slot] = mover.gap
        self.gmode[slot] = int(job.gap_mode)
        lim = job.limits
        self.target[slot] = job.target
        self.lim[:, slot] = (lim.velocity, lim.acceleration, lim.deceleration, lim.jerk)
        self.halting[slot] = job.kind == _HALT
        self._pairs_dirty = True
        self._room_of = None

    def _abort(self, mover: Mover, reason: str) -> None:
        now = self._rt.now
        if mover.job is not None:
            mover.job.command._end(CommandStatus.ABORTED, now, message=reason)
            mover.job = None
        for job in mover.queue:
            job.command._end(CommandStatus.ABORTED, now, message=reason)
        mover.queue.clear()

    def _finish_job(self, mover: Mover) -> None:
        job = mover.job
        assert job is not None
        job.command._end(CommandStatus.DONE, self._rt.now)
        mover.job = None
        slot = mover.slot
        self.mode[slot] = IDLE
        self.gmode[slot] = int(self.parameters.default_gap_control_mode)
        self._pairs_dirty = True
        self._room_of = None
        if mover.queue:
            self._start(mover, mover.queue.pop(0))
        elif mover.axis.state is AxisState.DISCRETE_MOTION:
            mover.axis.state = AxisState.STANDSTILL

    # -- internals: membership and order --------------------------------------------------------

    def _moving(self, mover: Mover) -> bool:
        row = mover.axis.row
        return bool(self._k.set_v[row] != 0.0 or self._k.set_a[row] != 0.0)

    def _drop(self, mover: Mover) -> None:
        self._abort(mover, "removed from the group")
        mover.axis.group = None
        row = mover.axis.row
        self._k.segments.install(row, _hold(float(self._k.set_p[row])), self._k.sample_time)
        self.movers.remove(mover)
        self._reorder()
        if not self.movers and self.state is not GroupState.DISABLED:
            self.state = GroupState.DISABLED

    def _disable(self) -> None:
        for mover in self.movers:
            self._abort(mover, "the group was disabled")
            row = mover.axis.row
            k = self._k
            k.set_v[row] = k.set_a[row] = k.set_j[row] = 0.0
            k.segments.install(row, _hold(float(k.set_p[row])), k.sample_time)
            if mover.axis.state is AxisState.DISCRETE_MOTION:
                mover.axis.state = AxisState.STANDSTILL
        for command in (self._stop, self._halt):
            if command is not None:
                command._end(CommandStatus.ABORTED, self._rt.now, message="the group was disabled")
        self._stop = self._halt = None
        if self.state is GroupState.ERROR_STOP:
            self.error_disabled = True
        self.state = GroupState.DISABLED
        self.mode[:] = IDLE

    def _reorder(self) -> None:
        """CA order by position (§8.1.1): the largest first; equal: the last added first."""
        length = self.parameters.rail_length
        ring = self.parameters.rail_is_ring
        k = self._k

        def key(m: Mover) -> tuple[float, int]:
            p = float(k.set_p[m.axis.row])
            return (p % length if ring else p, m.added)

        ordered = sorted(self.movers, key=key, reverse=True)
        if ring and ordered:  # rotate: the first is the one with the largest absolute position
            first = max(range(len(ordered)),
                        key=lambda i: (float(k.set_p[ordered[i].axis.row]), ordered[i].added))
            ordered = ordered[first:] + ordered[:first]
        running = {id(m): (self.mode[m.slot], self.goal[m.slot]) for m in ordered
                   if m.job is not None and 0 <= m.slot < self.mode.size}
        self.movers = ordered
        self._arrays(len(ordered))
        for slot, mover in enumerate(ordered):
            mover.slot = slot
            self.gap[slot] = mover.gap
            if mover.job is not None:  # keeps following its profile, or stays held
                self._load_job(mover)
                self.mode[slot], self.goal[slot] = running.get(id(mover), (FOLLOW, np.nan))
        self._sync_states()
        self._pairs_dirty = True
        self._room_of = None

    def _arrays(self, n: int) -> None:
        self.rows = np.array([m.axis.row for m in self.movers], dtype=np.int64) if n else \
            np.zeros(0, dtype=np.int64)
        self.p, self.v, self.a = np.zeros(n), np.zeros(n), np.zeros(n)
        self.mode = np.zeros(n, dtype=np.int8)
        self.goal = np.full(n, np.nan)
        self.target = np.full(n, np.nan)
        self.lim = np.ones((4, n))  # velocity, acceleration, deceleration, jerk of the command
        self.halting = np.zeros(n, dtype=bool)
        self.gap = np.full(n, self.parameters.default_gap)
        self.gmode = np.full(n, int(self.parameters.default_gap_control_mode), dtype=np.int8)
        self.bdec = np.array([m.axis.parameters.max_deceleration for m in self.movers]) \
            if n else np.zeros(0)
        self.bjerk = np.array([m.axis.parameters.max_jerk for m in self.movers]) \
            if n else np.zeros(0)
        self.pred = np.full(n, -1, dtype=np.int64)
        self.succ = np.full(n, -1, dtype=np.int64)
        self.offset = np.zeros(n)
        self._env: tuple[np.ndarray, np.ndarray] | None = None
        self._room_of: object = None  #: the envelope ``_room_all`` was computed from
        self._room_all: tuple[np.ndarray, np.ndarray] = (np.zeros(0), np.zeros(0))
        if n:
            self.pred[1:] = np.arange(n - 1)
            if self.parameters.rail_is_ring:
                self.pred[0] = n - 1
            has = self.pred >= 0
            self.succ[self.pred[has]] = np.flatnonzero(has)

    def _sync_states(self) -> None:
        """Take the members' setpoints as the group's state (enable, reset, reorder)."""
        k, rows = self._k, self.rows
        if not rows.size:
            return
        self.p, self.v, self.a = k.set_p[rows].copy(), k.set_v[rows].copy(), \
            k.set_a[rows].copy()
        length = self.parameters.rail_length
        has = self.pred >= 0
        raw = self.p[self.pred[has]] - self.p[has]
        wrapped = np.mod(raw, length)
        if self.parameters.rail_is_ring:  # the wrap pair spans (0, L]: n = 1 sees itself at L
            first = np.flatnonzero(has) == 0
            wrapped = np.where(first & (wrapped == 0.0), length, wrapped)
            self.offset[has] = wrapped - raw
        self._pairs_dirty = True
        self._room_of = None
        self._env = None

    def _check_ready(self) -> None:
        if self.state is GroupState.NOT_READY and all(m.axis.powered for m in self.movers):
            self._sync_states()
            self.state = GroupState.MOVING if any(m.job for m in self.movers) \
                else GroupState.STANDBY

    # -- the cycle ------------------------------------------------------------------------------

    def _pairs(self) -> Pairs:
        if self._pairs_dirty:
            succ = np.flatnonzero((self.pred >= 0) & (self.gmode != GapControlMode.NONE))
            both = self.parameters.gap_control_direction is GapControlDirection.BOTH
            self._pair_cache = Pairs(succ, self.pred[succ], self.offset[succ], self.gap[succ],
                                     self.gmode[succ] == GapControlMode.FAST, both)
            self._pairs_dirty = False
        return self._pair_cache

    def _advance(self, now: float) -> None:
        """Phase 2, after the profiles: gap control and the movers' command events."""
        if self._reset is not None:
            self._end_reset()
        if not self.movers:
            return
        self._watch_members()
        if self.state not in _MOVING_STATES:
            return
        k, rows, dt = self._k, self.rows, self._rt.cycle_time
        nxt = [k.set_p[rows].copy(), k.set_v[rows].copy(), k.set_a[rows].copy(),
               k.set_j[rows].copy()]
        n = rows.size
        known = (np.zeros(n, dtype=bool), np.empty(n), np.empty(n))  # proposal envelopes
        held = np.flatnonzero(self.mode == HELD)
        if held.size:
            held = self._waiting(held, nxt, known)
        if held.size:
            for field_, value in zip(nxt, self._track(held, dt, known), strict=True):
                field_[held] = value
        idle = self.mode == IDLE
        if idle.any():  # no command: the mover rests where it is
            nxt[0][idle], nxt[1][idle], nxt[2][idle], nxt[3][idle] = self.p[idle], 0.0, 0.0, 0.0
            known[0][idle], known[1][idle], known[2][idle] = True, self.p[idle], self.p[idle]
        geared = np.flatnonzero(self.mode == GEAR)
        if geared.size:
            self._gear_steps(geared, now, nxt)
        cur = (self.p, self.v, self.a)
        braking, lo, hi = filter_steps(cur, self._envelope(), nxt, dt, self.bdec,
                                       self.bjerk, self._pairs(), known)
        k.set_p[rows], k.set_v[rows], k.set_a[rows], k.set_j[rows] = nxt
        self.p, self.v, self.a = nxt[0], nxt[1], nxt[2]
        self._env = (lo, hi)
        self.mode[braking & (self.mode == FOLLOW)] = HELD
        for slot in np.flatnonzero(braking & (self.mode == GEAR)).tolist():
            sync = self.movers[slot].job.extra  # type: ignore[union-attr]
            sync.held(now, (float(self.p[slot]), float(self.v[slot]), float(self.a[slot])),
                      self._master(sync))
        self._events(now)

    def _master(self, sync: GearSync) -> tuple[float, float, float, float]:
        k, row = self._k, sync.master_row
        return float(k.set_p[row]), float(k.set_v[row]), float(k.set_a[row]), float(k.set_j[row])

    def _gear_steps(self, slots: np.ndarray, now: float, nxt: list[np.ndarray]) -> None:
        """Proposals of coupled slaves (few: a loop); a failed sync ends in error and brakes."""
        dt = self._rt.cycle_time
        for slot in slots.tolist():
            mover = self.movers[slot]
            job = mover.job
            assert job is not None
            sync: GearSync = job.extra
            state = (float(self.p[slot]), float(self.v[slot]), float(self.a[slot]))
            try:
                proposal = sync.step(now, state, self._master(sync), dt)
            except CommandRejected as rejected:
                sync.error = (rejected.error_id, rejected.message)
                proposal = None
            if sync.error is not None:
                job.command._end(CommandStatus.ERROR, now, *sync.error)
                mover.job = None
                self._issue_halt(mover, self._command("halt"), MC_DEFAULT, MC_DEFAULT,
                                 mover.gap, GapControlMode.GROUP_DEFAULT)
                proposal = None
            if proposal is None:  # waiting (or stopping): brake to rest with the job's limits
                lim = job.limits
                step = brake_state(self.p[slot:slot + 1], self.v[slot:slot + 1],
                                   self.a[slot:slot + 1], np.array([lim.deceleration]),
                                   np.array([lim.jerk]), dt)
                proposal = tuple(float(x[0]) for x in step)
            for field_, value in zip(nxt, proposal, strict=True):
                field_[slot] = value

    def _waiting(self, held: np.ndarray, nxt: list[np.ndarray],
                 known: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
        """Held movers standing with no room at all towards their target stay as they are
        (a queue behind a mover that stands or waits itself); returns the others."""
        still = (self.v[held] == 0.0) & (self.a[held] == 0.0) & ~self.halting[held]
        if not still.any():
            return held
        room_hi, room_lo = self._room(held)
        p = self.p[held]
        room = np.where(self.target[held] >= p, room_hi - p, p - room_lo)
        stay = still & (room <= TOLERANCE)
        slots = held[stay]
        nxt[0][slots], nxt[1][slots], nxt[2][slots], nxt[3][slots] = self.p[slots], 0.0, 0.0, 0.0
        known[0][slots], known[1][slots], known[2][slots] = True, self.p[slots], self.p[slots]
        return held[~stay]

    def _envelope(self) -> tuple[np.ndarray, np.ndarray]:
        """Brake envelope of the current states (cached from the last cycle)."""
        if self._env is None:
            self._env = brake_envelope(self.p, self.v, self.a, self.bdec, self.bjerk)
        return self._env

    def _track(self, held: np.ndarray, dt: float,
               known: tuple[np.ndarray, np.ndarray, np.ndarray]) -> tuple[np.ndarray, ...]:
        """The next step of held movers: the most progressive constant-jerk step (jerk +J,
        0 or -J) that stays within the command's limits, does not pass the target and keeps
        clear of the neighbours as they are now; else a brake. Held movers never turn back.

        The candidates are tried in that order, each only for the movers the one before did
        not fit, so a cycle costs about one envelope per held mover."""
        m = held.size
        p, v, a = self.p[held], self.v[held], self.a[held]
        vmax, acc, dec, jmax = self.lim[:, held]
        bdec, bjerk = self.bdec[held], self.bjerk[held]
        target = self.target[held]
        sign = np.where(target >= p, 1.0, -1.0)
        room_hi, room_lo = self._room(held)
        lo_now, hi_now = self._envelope()
        room_hi = np.maximum(room_hi, hi_now[held])
        room_lo = np.minimum(room_lo, lo_now[held])
        out = [np.empty(m) for _ in range(4)]
        rows = np.flatnonzero(~self.halting[held])
        for step in (1.0, 0.0, -1.0):
            if not rows.size:
                break
            s, jm = sign[rows], jmax[rows]
            j = step * s * jm
            p0, v0, a0 = p[rows], v[rows], a[rows]
            p1 = p0 + dt * (v0 + dt * (0.5 * a0 + dt * j / 6.0))
            v1 = v0 + dt * (a0 + 0.5 * dt * j)
            a1 = a0 + dt * j
            u, b = s * v1, s * a1
            release = u + b * np.abs(b) / (2.0 * jm)  # velocity once b is taken away
            ok = (b <= acc[rows] * (1 + 1e-12)) & (b >= -dec[rows] * (1 + 1e-12))
            ok &= (release <= vmax[rows] * (1 + 1e-12)) & (u >= 0.0) & (release >= 0.0)
            # the target: a cheap bound on the command's stop distance first, exact if needed
            # (the velocity stays below max(u, release) while braking, which lasts at most
            # b+/J to take b away, 2 dec/J for the ramps and v/dec at full deceleration)
            top = np.maximum(u, release)
            t_stop = (np.maximum(b, 0.0) + 2.0 * dec[rows]) / jm + top / dec[rows]
            near = ok & (top * t_stop >= s * (target[rows] - p1))
            if near.any():
                i = np.flatnonzero(near)
                c_lo, c_hi = brake_envelope(p1[i], v1[i], a1[i], dec[rows][i], jm[i])
                ok[i] = np.where(s[i] > 0.0, c_hi <= target[rows][i] + TOLERANCE,
                                 c_lo >= target[rows][i] - TOLERANCE)
            i = np.flatnonzero(ok)  # the neighbours, with the mover's own (hardest) brake
            b_lo, b_hi = brake_envelope(p1[i], v1[i], a1[i], bdec[rows][i], bjerk[rows][i])
            fits = (b_hi <= room_hi[rows][i]) & (b_lo >= room_lo[rows][i])
            ok[i] = fits
            chosen = held[rows[i[fits]]]  # their envelope is the gap filter's too
            known[0][chosen], known[1][chosen], known[2][chosen] = True, b_lo[fits], b_hi[fits]
            for o, value in zip(out, (p1, v1, a1, j), strict=True):
                o[rows[ok]] = value[ok]
            rows = rows[~ok]
        lost = np.zeros(m, dtype=bool)
        lost[rows] = True
        lost |= self.halting[held]
        if lost.any():  # no step fits: the command's own brake, or the mover's hardest one
            # where gap control braked it beyond what the command's brake can take back
            # without turning round
            u, b = sign[lost] * v[lost], sign[lost] * a[lost]
            hard = (b < -dec[lost]) | (u + b * np.abs(b) / (2.0 * jmax[lost]) < 0.0)
            step = brake_state(p[lost], v[lost], a[lost],
                               np.where(hard, bdec[lost], dec[lost]),
                               np.where(hard, bjerk[lost], jmax[lost]), dt)
            for o, value in zip(out, step, strict=True):
                o[lost] = value
        # float residue of the steps (|v| ~ 1e-17) is rest: snap it, so standstill is exact
        still = (np.abs(out[1]) <= 1e-9 * vmax) & (np.abs(out[2]) <= 1e-9 * acc)
        out[1][still], out[2][still], out[3][still] = 0.0, 0.0, 0.0
        known[0][held[still]] = False  # snapped: the filter computes their envelope
        return tuple(out)

    def _room(self, slots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where each mover may stop, given its neighbours' current brake envelopes
        (computed for the whole group once per envelope)."""
        env = self._envelope()
        if self._room_of is not env:
            lo, hi = env
            n = lo.size
            room_hi, room_lo = np.full(n, np.inf), np.full(n, -np.inf)
            gated = (self.pred >= 0) & (self.gmode != GapControlMode.NONE)
            room_hi[gated] = lo[self.pred[gated]] + self.offset[gated] - self.gap[gated]
            if self.parameters.gap_control_direction is GapControlDirection.BOTH:
                behind = (self.succ >= 0)
                behind[behind] &= self.gmode[self.succ[behind]] != GapControlMode.NONE
                s = self.succ[behind]
                room_lo[behind] = hi[s] + self.gap[s] - self.offset[s]
            self._room_all = (room_hi, room_lo)
            self._room_of = env
        room_hi, room_lo = self._room_all
        return room_hi[slots], room_lo[slots]

    def _events(self, now: float) -> None:
        k = self._k
        ended = np.flatnonzero((self.mode == FOLLOW) & (k.segments.end[self.rows] <= now))
        for slot in ended.tolist():
            mover = self.movers[slot]
            if mover.job is None:
                self.mode[slot] = IDLE
            elif mover.job.kind == _HALT or self.goal[slot] == mover.job.target:
                self._finish_job(mover)
            else:
                self.mode[slot] = HELD  # a queue position: wait for the way to clear
        held = np.flatnonzero(self.mode == HELD)
        if held.size:
            self._resume(held)
        if self.parameters.standby_gap_control or self.parameters.active_gap_establishing:
            self._restore_gaps()
        idle = not self.mode.any()  # mode IDLE (0) exactly when the mover has no command
        if self._halt is not None:
            if any(part.aborted for part in self._halt_parts):  # a new command took over
                self._halt._end(CommandStatus.ABORTED, now,
                                message="a member took another command")
                self._halt = None
            elif all(part.done for part in self._halt_parts):
                self._halt._end(CommandStatus.DONE, now)
                self._halt = None
        if self._stop is not None:
            if self._stop.busy and idle:
                self._stop.status = CommandStatus.DONE
                self._stop.ended_at = now
            if self._stop.done and not self._stop.hold:
                self._stop = None
                self.state = GroupState.STANDBY
        if self.state is GroupState.MOVING and idle and self.all_axes_standing:
            self.state = GroupState.STANDBY

    def _resume(self, held: np.ndarray) -> None:
        """Held movers get a profile again: to the target once nothing can block it, or to
        the queue position once the neighbour in its way stands. Decided for all held movers
        at once; only the few that replan cost a ruckig call."""
        room_hi, room_lo = self._room(held)
        lo, hi = self._envelope()
        target, p = self.target[held], self.p[held]
        rest = self._resting(held)
        halting = self.halting[held]
        forward = target >= p
        free = ~halting & (room_lo <= target) & (target <= room_hi)
        succ = self.succ[held]
        other = np.where(forward, self.pred[held], succ)
        other_rests = other < 0
        has = ~other_rests
        other_rests[has] = self._resting(other[has])
        goal = np.minimum(np.maximum(target, room_lo), room_hi)
        queue = ~halting & ~free & other_rests
        # no closer to the target (CA never moves a mover back, §3)
        queue &= ~(rest & (((goal - p) * (target - p) <= 0.0) | (np.abs(goal - p) <= TOLERANCE)))
        # cannot stop there any more (a pair that started too close)
        queue &= np.where(forward, hi[held] <= goal + TOLERANCE, lo[held] >= goal - TOLERANCE)
        # head on: both want the same room; the mover moving forwards takes it
        waiting = succ >= 0
        waiting[waiting] = (self.mode[succ[waiting]] != IDLE) & \
            (self.target[succ[waiting]] > self.p[succ[waiting]] + TOLERANCE)
        queue &= forward | ~waiting
        for slot in held[halting & rest].tolist():
            self._finish_job(self.movers[slot])
        goals = np.where(free, target, goal)
        candidates = np.flatnonzero(free | queue)
        if candidates.size:  # a profile with the command's limits must be able to stop there
            slots = held[candidates]
            vmax, acc, dec, jerk = self.lim[:, slots]
            step = np.where(forward[candidates], 1.0, -1.0)
            b = step * self.a[slots]
            c_lo, c_hi = brake_envelope(self.p[slots], self.v[slots], self.a[slots], dec, jerk)
            fits = np.where(forward[candidates], c_hi <= goals[candidates] + TOLERANCE,
                            c_lo >= goals[candidates] - TOLERANCE)
            fits &= (b <= acc * (1 + 1e-12)) & (b >= -dec * (1 + 1e-12))
            u = step * self.v[slots]  # and stop without turning round
            fits &= (u >= 0.0) & (u + b * np.abs(b) / (2.0 * jerk) >= -1e-9 * vmax)
            fits &= np.abs(self.v[slots]) <= vmax * (1 + 1e-12)
            candidates = candidates[fits]
        for i in candidates.tolist():
            self._replan(self.movers[int(held[i])], float(goals[i]))

    def _restore_gaps(self) -> None:
        """Standby gap control (§6, §8.1.1): movers without a command give way.

        An idle mover closer to its predecessor than its last valid gap moves back to it with
        the group's default dynamics; idle movers behind it move back as far as that needs
        (the push goes down the row). Movers with a command never give way.
        """
        idle = self.mode == IDLE
        if not idle.any() or self.state is GroupState.STOPPING or self._halt is not None:
            return
        slots = np.flatnonzero(idle)
        room_hi, _ = self._room(slots)
        if not np.any(self.p[slots] > room_hi + 1e-6):
            return
        lo, _hi = self._envelope()
        desired = np.where(idle, self.p, lo)  # where each mover may end up, at most
        order = list(range(len(self.movers)))
        for _ in range(len(order)):  # push down the row until nothing changes (a ring too)
            changed = False
            for slot in order:
                k = int(self.pred[slot])
                if k < 0 or not idle[slot] or self.gmode[slot] == GapControlMode.NONE:
                    continue
                limit = desired[k] + self.offset[slot] - self.gap[slot]
                if limit < desired[slot] - 1e-9:
                    desired[slot] = limit
                    changed = True
            if not changed:
                break
        for slot in np.flatnonzero(idle & (desired < self.p - 1e-6)).tolist():
            self._standby(self.movers[slot], float(desired[slot]))

    def _standby(self, mover: Mover, target: float) -> None:
        p, group = mover.axis.parameters, self.parameters
        limits = Limits(min(group.default_velocity, p.max_velocity),
                        min(group.default_acceleration, p.max_acceleration),
                        min(group.default_deceleration, p.max_deceleration),
                        min(group.default_jerk, p.max_jerk))
        job = CaJob("standby", self._command("standby_gap_control"), limits, mover.gap,
                    self.parameters.default_gap_control_mode, target_of=lambda _start: target)
        self._start(mover, job)

    def _resting(self, slots: np.ndarray) -> np.ndarray:
        """At rest up to float residue of the tracking steps."""
        vmax, acc = self.lim[0, slots], self.lim[1, slots]
        return (np.abs(self.v[slots]) <= 1e-9 * vmax) & (np.abs(self.a[slots]) <= 1e-9 * acc)

    def _replan(self, mover: Mover, goal: float) -> None:
        slot = mover.slot
        job = mover.job
        assert job is not None
        start = KinematicState(float(self.p[slot]), float(self.v[slot]), float(self.a[slot]))
        try:
            profile = plan_position(start, goal, job.limits)
        except CommandRejected:
            return  # stay held; the tracking step goes on
        self._k.segments.install(mover.axis.row, profile, self._rt.now)
        self.mode[slot] = FOLLOW
        self.goal[slot] = goal

    def _watch_members(self) -> None:
        """Member errors stop the group; a member losing power makes it NotReady (§7)."""
        if self.state in (GroupState.DISABLED, GroupState.ERROR_STOP):
            return
        if self._k.monitored[self.rows].all():  # every member powered and free of errors
            if self.state is GroupState.NOT_READY:
                self._check_ready()
            return
        failed = [m for m in self.movers if m.axis.state is AxisState.ERROR_STOP]
        if failed:
            self._error(failed[0].axis.axis_error_id, f"{failed[0].axis.name}: "
                        f"{failed[0].axis.axis_error_message}")
            return
        if self.state is GroupState.NOT_READY:
            self._check_ready()
        elif any(not m.axis.powered for m in self.movers):
            off = next(m for m in self.movers if not m.axis.powered)
            self._brake_all(CommandStatus.ABORTED, f"{off.axis.name} was disabled")
            self.state = GroupState.NOT_READY

    def _error(self, error_id: ErrorId, message: str) -> None:
        """GroupErrorStop: every command ends in error, every mover brakes at its maximum."""
        self.error_id = ErrorId.GROUP_ERROR if error_id is ErrorId.NO_ERROR else error_id
        self._brake_all(CommandStatus.ERROR, f"group error: {message}")
        self.state = GroupState.ERROR_STOP

    def _brake_all(self, status: CommandStatus, message: str) -> None:
        """End every command and brake every powered mover with its maximum dynamics.

        All movers brake together from states that keep the gap invariant, so no gap is
        undershot although gap control pauses (docs/collision-avoidance.md)."""
        now = self._rt.now
        error_id = ErrorId.GROUP_ERROR if status is CommandStatus.ERROR else ErrorId.NO_ERROR
        for mover in self.movers:
            for job in ([mover.job] if mover.job else []) + mover.queue:
                job.command._end(status, now, error_id, message)
            mover.job = None
            mover.queue.clear()
            slot = mover.slot
            self.mode[slot] = IDLE
            if not mover.axis.powered:
                continue
            start = KinematicState(float(self.p[slot]), float(self.v[slot]), float(self.a[slot]))
            profile = plan_stop(start, float(self.bdec[slot]), float(self.bjerk[slot]))
            self._k.segments.install(mover.axis.row, profile, self._k.sample_time)
            if mover.axis.state is AxisState.DISCRETE_MOTION:
                mover.axis.state = AxisState.STANDSTILL
        for command in (self._stop, self._halt):
            if command is not None:
                command._end(status, now, error_id, message)
        self._stop = self._halt = None


def _hold(position: float) -> Any:
    from openmotion.trajectory.segments import Profile

    return Profile.hold(KinematicState(position))


def _enum(kind: Any, value: Any, error_id: ErrorId, name: str) -> Any:
    try:
        if isinstance(value, bool):
            raise ValueError(value)
        return kind(value)
    except (ValueError, TypeError):
        raise CommandRejected(error_id, f"{name}: {value!r} is not a {kind.__name__}") from None


def _position(name: str, value: InputValue) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise CommandRejected(ErrorId.INVALID_POSITION, f"{name}: must be set, got {value!r}")
    return float(value)
