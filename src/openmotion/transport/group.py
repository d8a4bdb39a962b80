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

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.enums import AxisState, BufferMode, convert_enum
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.core.modulo import mc3_modulo_target
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE, MC_INVALID, InputValue
from openmotion.rail.gear import GearSync
from openmotion.trajectory.plan import Limits, plan_position, plan_stop
from openmotion.trajectory.segments import KinematicState
from openmotion.transport.cycle import GroupCycle
from openmotion.transport.enums import (
    GapControlMode,
    GearInPosDefaultDynamicsAfterSync,
    GroupState,
    GroupType,
    MasterSignalCorrection,
    ModuloDirection,
    SyncMode,
    SyncStrategy,
)
from openmotion.transport.faults import GroupFaults
from openmotion.transport.inputs import ca_gap, ca_limits, ca_value, halt_limits
from openmotion.transport.kind import CA_GROUP
from openmotion.transport.movers import (
    FOLLOW,
    GEAR,
    HALT,
    IDLE,
    MOVING_STATES,
    POSITION,
    UDINT_TO_IDENTINGROUP,
    CaJob,
    GroupInterface,
    IdentInGroup,
    Mover,
    enum_input,
    hold,
    position_input,
)
from openmotion.transport.parameters import PARAMETER_FIELDS, CaGroupParameters
from openmotion.transport.tracks import TrackTable

__all__ = ["UDINT_TO_IDENTINGROUP", "CaGroup", "CaJob", "GroupInterface", "IdentInGroup",
           "Mover"]

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.kernel.model import Kind
    from openmotion.runtime.runtime import Runtime

class CaGroup(GroupCycle, GroupFaults):
    """A CA group on a rail; create with ``CaGroup(runtime, "ca", rail_length=...)``."""

    MACHINE: ClassVar[Kind] = CA_GROUP  #: its signals and commands in the machine model

    def __init__(self, runtime: Runtime, name: str = "ca",
                 parameters: CaGroupParameters | None = None, **overrides: Any) -> None:
        unknown = set(overrides) - PARAMETER_FIELDS
        if unknown:
            raise ConfigError(f"CA group {name!r}: unknown parameter(s) {sorted(unknown)}")
        if parameters is not None and not isinstance(parameters, CaGroupParameters):
            raise ConfigError(f"CA group {name!r}: parameters must be a CaGroupParameters, got "
                              f"{type(parameters).__name__}")
        # a copy with the overrides: a refused value leaves the caller's object as it was
        parameters = parameters or CaGroupParameters()
        if overrides:
            parameters = replace(parameters, **overrides)
        try:
            parameters.validate()
        except (TypeError, ValueError) as exc:
            raise ConfigError(f"CA group {name!r}: {exc}") from None
        self.name = name
        self.oid = 0x05030000 + runtime.serial("ca_group")  #: TcCOM-like object id (ours)
        self.parameters = parameters
        self.runtime = runtime
        self.kernel = runtime.axis_system.kernel
        self.state = GroupState.DISABLED
        self.error_disabled = False  #: internal GroupErrorDisabled (not visible, §7.2)
        self.error_id = ErrorId.NO_ERROR  #: GroupErrorId of the cyclic interface
        self._power_lost: str | None = None  #: a member lost power since the last cycle
        self.movers: list[Mover] = []  #: in CA order once enabled
        #: the station lines on this rail (transport/stations.py): plots and viewer draw them
        self.station_lines: list[Any] = []
        self._serial = 0
        self._stop: Command | None = None  #: MC_GroupStop holding the group
        self._halt: Command | None = None  #: MC_GroupHalt in progress
        self._halt_parts: list[Command] = []  #: its per-mover halts
        self._reset: Command | None = None  #: MC_GroupReset waiting for the members' MC_Reset
        self._reset_parts: list[Command] = []
        self._arrays(0)
        self.tracks = TrackTable(self)  #: parts, tracks and geo-compensation (tracks.py)
        runtime.add_system(self)

    def objects(self) -> tuple[CaGroup]:
        """The group itself; its movers are axes, objects of the runtime's AxisSystem."""
        return (self,)

    # -- reading -------------------------------------------------------------------------------

    @property
    def axes_count(self) -> int:
        """GroupAxesCount of the cyclic interface."""
        return len(self.movers)

    @property
    def all_axes_standing(self) -> bool:
        """MC_GroupReadStatus.AllAxesStanding: no member moves (v = 0 and a = 0)."""
        self._fresh()
        k, rows = self.kernel, self.rows
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
        k = self.kernel
        p = k.set_p[self.rows] if self.rows.size else np.zeros(0)
        gaps = np.full(len(self.movers), np.inf)
        has = self.pred >= 0
        gaps[has] = p[self.pred[has]] + self.offset[has] - p[has]
        y, path = self.tracks.gap_paths(np.arange(len(self.movers)))
        if y is not None and path is not None:  # on the successor's TCP path (D-073)
            for slot in np.flatnonzero(has & (y > 0.0)).tolist():
                ahead = p[self.pred[slot]] + self.offset[slot]
                gaps[slot] = float(path.motor_to_tcp(ahead, y[slot])
                                   - path.motor_to_tcp(p[slot], y[slot]))
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
        """MC_RemoveAxisFromGroup: Done also when no member has ``ident`` (§9.3.1.1.8).

        A standing mover leaves also while the group moves (§7.2, V3.1.10), with a command
        that waits (a queue place): that command and its buffered ones end CommandAborted
        (D-209). A moving or still braking mover is refused with AXIS_MOVING."""
        command = self._command("remove_axis")
        mover = next((m for m in self.movers if m.ident == ident), None)
        if mover is None:
            return self._finish(command)
        if self._moving(mover):
            return self._reject(command, ErrorId.AXIS_MOVING, f"{mover.axis.name} is moving")
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
        if command is None or any(part.busy for part in self._reset_parts) or self._braking:
            return  # MC_Reset of a member waits for rest; so does the group (D-184)
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
        if self.state not in MOVING_STATES and self.state is not GroupState.NOT_READY:
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
            direction_ = enum_input(ModuloDirection, direction, ErrorId.INVALID_DIRECTION,
                               "direction")
            if direction_ is not ModuloDirection.NON_MODULO and not self.parameters.rail_is_ring:
                raise CommandRejected(ErrorId.MODULO_ON_OPEN_RAIL,
                                      "modulo directions need a rail that is a ring")
            target = position_input("position", position)
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
            mc3_modulo_target(0.0, target, direction_, turns, length, window)  # validate
            job = self._job(mover, POSITION, command, velocity, acceleration, deceleration,
                            jerk, gap, buffer_mode, gap_control_mode, continuous_update)
            job.target_of = lambda start: mc3_modulo_target(start, target, direction_,
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
            step = position_input("distance", distance)
            job = self._job(mover, POSITION, command, velocity, acceleration, deceleration,
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
                  gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT,
                  dynamics_reference_system: int = 0) -> Command:
        """MC_HaltCA: brake to rest; the axis is not locked (§9.1.1.1.3). With a mover
        template as ``dynamics_reference_system`` the deceleration and jerk hold for its TCP."""
        command = self._command("halt_ca")
        try:
            self._admit_motion()
            mover = self._member(axis)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self._issue_halt(mover, command, deceleration, jerk, gap, gap_control_mode,
                         dynamics_reference_system)
        return command

    def gear_in_pos(self, master: Axis, slave: Axis, ratio_numerator: float = 1.0,
                    ratio_denominator: int = 1,
                    master_sync_position: InputValue = MC_INVALID,
                    slave_sync_position: InputValue = MC_INVALID,
                    sync_strategy: SyncStrategy = SyncStrategy.LATE,
                    sync_mode: SyncMode = SyncMode.NON_MODULO,
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
                    minimal_slave_position: InputValue = MC_IGNORE,
                    direction_reversal_allowed: bool = True,
                    override_slave_dynamic_restrictions: bool = False,
                    gap_control_mode: GapControlMode = GapControlMode.GROUP_DEFAULT,
                    continuous_update: bool = False,
                    master_signal_correction: MasterSignalCorrection = (
                        MasterSignalCorrection.AUTO),
                    slave_sync_position_reference_system: int = 0,
                    dynamics_reference_system: int = 0) -> Command:
        """MC_GearInPosCA (§9.1.1.1.4): couple ``slave`` to ``master``'s set values.

        The command never ends Done: another command (aborting) decouples. ``sync_state``
        gives StartSync and InSync. The options' restrictions hold for the profile driven
        (D-204); ``master_signal_correction`` as D-205 describes.
        """
        command = self._command("gear_in_pos_ca")

        def build(mover: Mover) -> CaJob:
            for name, oid in (("slave_sync_position_reference_system",
                               slave_sync_position_reference_system),
                              ("dynamics_reference_system", dynamics_reference_system)):
                if oid != 0:  # a template's TCP path: not for a coupled slave yet (D-207)
                    raise CommandRejected(ErrorId.INVALID_MODE,
                                          f"{name}: only 0 (the motor path) for now")
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
            numerator = position_input("ratio_numerator", ratio_numerator)
            strategy = enum_input(SyncStrategy, sync_strategy, ErrorId.INVALID_MODE,
                                  "sync_strategy")
            msp = position_input("master_sync_position", master_sync_position)
            ssp = position_input("slave_sync_position", slave_sync_position)
            mode = enum_input(SyncMode, sync_mode, ErrorId.INVALID_MODE, "sync_mode")
            if mode is not SyncMode.NON_MODULO:  # §9.4.1.4: SSP is a position on the ring
                if not self.parameters.rail_is_ring:
                    raise CommandRejected(ErrorId.MODULO_ON_OPEN_RAIL,
                                          "a modulo sync mode needs a rail that is a ring")
                # the next such position from the slave in the sync mode's direction
                ssp = mc3_modulo_target(float(self.p[mover.slot]), ssp,
                                        convert_enum(ModuloDirection, mode), 0,
                                        self.parameters.rail_length, 0.0)
            start = None if master_start_distance is MC_IGNORE else \
                position_input("master_start_distance", master_start_distance)
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
            minimum = None if minimal_slave_position is MC_IGNORE else \
                position_input("minimal_slave_position", minimal_slave_position)
            correction = enum_input(MasterSignalCorrection, master_signal_correction,
                                    ErrorId.INVALID_MODE, "master_signal_correction")
            maxima = Limits(params.max_velocity, params.max_acceleration,
                            params.max_deceleration, params.max_jerk)
            job.extra = GearSync(master.row, numerator / denominator, msp, ssp, strategy, start,
                                 job.limits, after_sync, bool(override_slave_dynamic_restrictions),
                                 bool(master_velocity_undershoot_allowed),
                                 bool(master_velocity_overshoot_allowed),
                                 bool(direction_reversal_allowed), minimum, correction,
                                 master.parameters.max_jerk, maxima)
            k = self.kernel
            row = master.row
            job.extra.seed(self.runtime.now, (float(k.set_p[row]), float(k.set_v[row]),
                                              float(k.set_a[row]), float(k.set_j[row])))
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
                    self.pairs_changed()
                return

    # -- internals: commands --------------------------------------------------------------------

    def _command(self, kind: str) -> Command:
        return Command(kind, self.runtime.now)

    def _finish(self, command: Command) -> Command:
        command.end(CommandStatus.DONE, self.runtime.now)
        return command

    def _reject(self, command: Command, error_id: ErrorId, message: str) -> Command:
        command.end(CommandStatus.ERROR, self.runtime.now, error_id, message)
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
        mode = enum_input(BufferMode, buffer_mode, ErrorId.INVALID_BUFFER_MODE, "buffer_mode")
        if mode not in (BufferMode.ABORTING, BufferMode.BUFFERED):
            raise CommandRejected(ErrorId.INVALID_BUFFER_MODE,
                                  f"the CA blocks take Aborting or Buffered, not {mode.name}")
        limits = ca_limits(mover.axis.parameters, command.warnings, velocity, acceleration,
                           deceleration, jerk)
        return CaJob(kind, command, limits, ca_gap(gap, self.parameters.default_gap),
                     self._gap_mode(gap_control_mode), mode,
                     continuous_update=bool(continuous_update))

    def _gap_mode(self, value: GapControlMode) -> GapControlMode:
        mode = enum_input(GapControlMode, value, ErrorId.INVALID_MODE, "gap_control_mode")
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
                    jerk: InputValue, gap: InputValue, gap_control_mode: GapControlMode,
                    dynamics_reference_system: int = 0) -> None:
        try:
            limits = halt_limits(mover.axis.parameters, command.warnings, deceleration, jerk)
            if dynamics_reference_system != 0:
                slot = mover.slot
                start = KinematicState(float(self.p[slot]), float(self.v[slot]),
                                       float(self.a[slot]))
                limits = self.tracks.geo.compensate_halt(mover.axis, limits, start,
                                                         dynamics_reference_system,
                                                         command.warnings)
            job = CaJob(HALT, command, limits, ca_gap(gap, self.parameters.default_gap),
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
            elif job.kind == HALT:
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
            self.kernel.segments.install(mover.axis.row, profile, self.kernel.sample_time)
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
        self._set_gap_mode(slot, int(job.gap_mode))
        lim = job.limits
        self.target[slot] = job.target
        self.lim[:, slot] = (lim.velocity, lim.acceleration, lim.deceleration, lim.jerk)
        self.halting[slot] = job.kind == HALT
        self.pairs_changed()

    def _set_gap_mode(self, slot: int, mode: int) -> None:
        """A mover's gap control mode changes. From FAST to STANDARD its pair may be safe only
        in the FAST sense (both braking together); it stays checked as FAST until it is safe
        in the STANDARD sense too, so the switch never breaks the invariant (D-106)."""
        if self.gmode[slot] == GapControlMode.FAST and mode == GapControlMode.STANDARD:
            self.fast_grace[slot] = True
        elif mode != GapControlMode.STANDARD:
            self.fast_grace[slot] = False
        self.gmode[slot] = mode

    def _abort(self, mover: Mover, reason: str) -> None:
        now = self.runtime.now
        if mover.job is not None:
            mover.job.command.end(CommandStatus.ABORTED, now, message=reason)
            mover.job = None
        for job in mover.queue:
            job.command.end(CommandStatus.ABORTED, now, message=reason)
        mover.queue.clear()

    def _finish_job(self, mover: Mover) -> None:
        job = mover.job
        assert job is not None
        job.command.end(CommandStatus.DONE, self.runtime.now)
        mover.job = None
        slot = mover.slot
        self.mode[slot] = IDLE
        self._set_gap_mode(slot, int(self.parameters.default_gap_control_mode))
        self.pairs_changed()
        if mover.queue:
            self._start(mover, mover.queue.pop(0))
        elif mover.axis.state is AxisState.DISCRETE_MOTION:
            mover.axis.state = AxisState.STANDSTILL

    # -- internals: membership and order --------------------------------------------------------

    def _moving(self, mover: Mover) -> bool:
        row = mover.axis.row
        return mover.brake is not None or bool(self.kernel.set_v[row] != 0.0
                                               or self.kernel.set_a[row] != 0.0)

    def _drop(self, mover: Mover) -> None:
        self._abort(mover, "removed from the group")
        self._stand(mover)  # it rests (removal waits for that): StandStill, its brake is over
        mover.axis.group = None
        row = mover.axis.row
        k = self.kernel
        k.segments.install(row, hold(float(k.set_p[row])), k.sample_time)
        self.movers.remove(mover)
        self._reorder()
        if not self.movers and self.state is not GroupState.DISABLED:
            self.state = GroupState.DISABLED

    def _disable(self) -> None:
        for mover in self.movers:
            self._abort(mover, "the group was disabled")
            row = mover.axis.row
            k = self.kernel
            k.set_v[row] = k.set_a[row] = k.set_j[row] = 0.0
            k.segments.install(row, hold(float(k.set_p[row])), k.sample_time)
            self._stand(mover)
        for command in (self._stop, self._halt):
            if command is not None:
                command.end(CommandStatus.ABORTED, self.runtime.now,
                            message="the group was disabled")
        self._stop = self._halt = None
        if self.state is GroupState.ERROR_STOP:
            self.error_disabled = True
        self.state = GroupState.DISABLED
        self.mode[:] = IDLE

    def _reorder(self) -> None:
        """CA order by position (§8.1.1): the largest first; equal: the last added first."""
        length = self.parameters.rail_length
        ring = self.parameters.rail_is_ring
        k = self.kernel

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
        grace = {id(m): (self.gmode[m.slot], self.fast_grace[m.slot]) for m in ordered
                 if 0 <= m.slot < self.mode.size}
        self.movers = ordered
        self._arrays(len(ordered))
        for slot, mover in enumerate(ordered):
            mover.slot = slot
            self.gap[slot] = mover.gap
            if mover.job is not None:  # keeps following its profile, or stays held
                self._load_job(mover)
                self.mode[slot], self.goal[slot] = running.get(id(mover), (FOLLOW, np.nan))
            if id(mover) in grace:  # the gap mode as it was, before and after a reorder
                self.gmode[slot], self.fast_grace[slot] = grace[id(mover)]
        self._sync_states()
        self.pairs_changed()

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
        self.fast_grace = np.zeros(n, dtype=bool)  #: STANDARD pairs still checked as FAST
        self.bdec = np.array([m.axis.parameters.max_deceleration for m in self.movers]) \
            if n else np.zeros(0)
        self.bjerk = np.array([m.axis.parameters.max_jerk for m in self.movers]) \
            if n else np.zeros(0)
        self.pred = np.full(n, -1, dtype=np.int64)
        self.succ = np.full(n, -1, dtype=np.int64)
        self.offset = np.zeros(n)
        self._env: tuple[np.ndarray, np.ndarray] | None = None
        #: envelope arrays the compiled cycle writes the next envelope into (cycle.py)
        self._spare_env: tuple[np.ndarray, np.ndarray] | None = None
        self._slot_buf, self._goal_buf = np.empty(0, dtype=np.int64), np.empty((0, 5))
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
        k, rows = self.kernel, self.rows
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
        self.pairs_changed()
        self._env = None

    def _check_ready(self) -> None:
        """NotReady ends once every member is powered and no mover brakes after a fault."""
        if self.state is GroupState.NOT_READY and all(m.axis.powered for m in self.movers) \
                and not self._braking:
            self._sync_states()
            self.state = GroupState.MOVING if any(m.job for m in self.movers) \
                else GroupState.STANDBY
