"""The axis: a thin view onto kernel row ``row``, plus its commands and PLCopen state.

Every way of moving an axis - FB, Python call, scenario line - ends in one of the public
methods here and gets a ``Command`` back. Bad input and wrong state never raise: the command
comes back with ``error`` set (architecture: "an FB never raises during a cycle").
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, ClassVar

from openmotion.axis import jobs
from openmotion.axis.commands import Command, CommandStatus, Job
from openmotion.axis.drive import DriveModel
from openmotion.axis.dynamics import require_position, resolve, resolve_limits
from openmotion.axis.homing import HomingSequence
from openmotion.axis.kind import AXIS
from openmotion.axis.parameters import PARAMETERS, AxisPara, AxisParameters
from openmotion.axis.state_machine import admit
from openmotion.axis.superposition import ROOM_FLOOR, plan_superposition, room_beside
from openmotion.core.checks import is_finite
from openmotion.core.enums import (
    AxisState,
    BufferMode,
    DecoupleMode,
    Direction,
    NewPosAndVeloMode,
    SuperpositionMode,
    TargetPositionType,
    convert_enum,
)
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.modulo import modulo_target, snap_to_period
from openmotion.core.special_values import (
    DEFAULT_HOME_POSITION,
    MC_DEFAULT,
    MC_INVALID,
    InputValue,
)
from openmotion.trajectory.plan import Limits, jerk_within_velocity, plan_stop, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.kernel import AxisKernel
    from openmotion.axis.system import AxisSystem
    from openmotion.kernel.model import Kind

MAX_BUFFERED = 16  #: commands an axis queues behind the active one (docs/decisions.md D-008)
_BLEND_SPEED = {
    BufferMode.BLENDING_LOW: min,
    BufferMode.BLENDING_HIGH: max,
    BufferMode.BLENDING_PREVIOUS: lambda previous, _next: previous,
    BufferMode.BLENDING_NEXT: lambda _previous, following: following,
}


_STATE_OF_JOB = {
    "position": AxisState.DISCRETE_MOTION, "halt": AxisState.DISCRETE_MOTION,
    "velocity": AxisState.CONTINUOUS_MOTION, "stop": AxisState.STOPPING,
}


class Axis:
    """One simulated NC axis. Units: mm (or °) and s."""

    MACHINE: ClassVar[Kind] = AXIS  #: its signals and commands in the machine model

    def __init__(self, system: AxisSystem, name: str, row: int, parameters: AxisParameters,
                 drive: DriveModel) -> None:
        self.name = name
        self.row = row
        self.parameters = parameters
        self.drive = drive
        self.system = system  #: the runtime's AxisSystem: kernel row, events and watchers
        self._rt = system.runtime
        self._k = system.kernel
        self.state = AxisState.DISABLED
        self.axis_error_id = ErrorId.NO_ERROR  #: the axis error behind ErrorStop
        self.axis_error_message = ""
        self.homed = False
        self.powered = False
        self.drive_ready = True  #: set False to simulate a drive that is not ready
        self.enable_positive = True  #: feed enable, positive direction (TcMC §4.1)
        self.enable_negative = True
        self.override = 1.0  #: velocity override as a fraction (MC_Power.Override / 100)
        self.calibration_state = 0  #: homing phase (TcMC §3.14 nCalibrationState)
        self.cam_input: bool | None = None  #: MC_Home.bCalibrationCam, None = simulated cam
        self.raw_offset = 0.0  #: shift between displayed and machine coordinates [mm]
        self._external_goal: tuple[float | None, TargetPositionType] = (
            None, TargetPositionType.ABSOLUTE)
        self._external_target_reached = False
        self._external_direction = 0
        self._superposition: Command | None = None
        self._job: Job | None = None
        self._queue: list[Job] = []
        self._hold: Command | None = None  #: a finished MC_Stop that still holds the axis
        self._effective_override = 1.0
        self.group: object | None = None  #: the CA group the axis is a member of
        self.apply_parameters()

    # -- reading -----------------------------------------------------------------------------

    @property
    def position(self) -> float:
        """Actual position [mm] (encoder)."""
        return float(self._k.act_p[self.row])

    @property
    def velocity(self) -> float:
        """Actual velocity [mm/s]."""
        return float(self._k.act_v[self.row])

    @property
    def set_position(self) -> float:
        """Setpoint position [mm] (TcMC fPosSoll); all positioning refers to it (§3.5)."""
        return float(self._k.set_p[self.row])

    @property
    def set_velocity(self) -> float:
        return float(self._k.set_v[self.row])

    @property
    def set_acceleration(self) -> float:
        return float(self._k.set_a[self.row])

    @property
    def set_jerk(self) -> float:
        return float(self._k.set_j[self.row])

    @property
    def following_error(self) -> float:
        """Set minus actual position [mm]."""
        return float(self._k.set_p[self.row] - self._k.act_p[self.row])

    @property
    def has_job(self) -> bool:
        """The setpoint generator still works on a job (TcMC §7.1 AxisHasJob)."""
        return bool(self._k.has_job[self.row])

    @property
    def override_value(self) -> int:
        """The override as the PlcToNc interface DWORD (TcMC §4.1): 0...1 000 000 for
        0...100 %, so MC_Power's Override 50.0 gives 500 000."""
        return round(self.override * 1_000_000)

    @property
    def error(self) -> bool:
        return self.state is AxisState.ERROR_STOP

    @property
    def target_position(self) -> float:
        job = self._job
        if job is not None and job.target is not None:
            return job.target
        return self.set_position

    @property
    def remaining_time(self) -> float:
        if not self.has_job:
            return 0.0
        return max(float(self._k.segments.end[self.row]) - self._k.sample_time, 0.0)

    @property
    def remaining_distance(self) -> float:
        return abs(self.target_position - self.set_position)

    @property
    def axis_id(self) -> float:
        return float(self.row + 1)

    @property
    def in_position_window(self) -> bool:
        return abs(self.position - self.target_position) <= self.parameters.position_range_window

    @property
    def modulo_set_position(self) -> float:
        period = self.parameters.modulo_period
        return self.set_position % period

    @property
    def moving(self) -> bool:
        return self.set_velocity != 0.0 or self.has_job

    @property
    def active_command(self) -> Command | None:
        return self._job.command if self._job else None

    def __repr__(self) -> str:
        return f"<Axis {self.name} {self.state.name} at {self.set_position:.6g}>"

    # -- parameters --------------------------------------------------------------------------

    def apply_parameters(self) -> None:
        """Copy monitoring parameters into the kernel arrays (after any write)."""
        p, k, row = self.parameters, self._k, self.row
        k.lag_on[row] = p.enable_position_lag_monitoring
        k.lag_max[row] = p.max_position_lag
        k.lag_filter[row] = p.position_lag_filter_time
        k.v_max[row], k.j_max[row] = p.max_velocity, p.max_jerk
        k.a_max[row] = max(p.max_acceleration, p.max_deceleration)
        self._enforce_soft_limits()

    def _enforce_soft_limits(self) -> None:
        """A software limit enabled or moved during a motion holds for that motion (D-179).

        A position or velocity move that would now pass it becomes a stop at the limit that
        ends in ErrorStop SOFT_LIMIT_REACHED, as a velocity move towards a limit does (D-016):
        with its own dynamics, or the axis maxima where those would overshoot. Where even the
        maxima cannot stop at the limit, or another motion (stop, halt, a brake without a
        job, a superimposed motion) would pass it, the axis error comes at once and brakes
        with the maxima. A job paused by override 0 counts with the way it resumes on.
        """
        k, row, p = self._k, self.row, self.parameters
        lo, hi = jobs.soft_range(p)
        if (math.isinf(lo) and math.isinf(hi)) or not self.powered or row in k.couplings \
                or k.external[row] or self.state in (AxisState.ERROR_STOP, AxisState.HOMING):
            return  # geared and fed setpoints follow their source; homing takes none (§3.14)
        start = k.state(row)
        low, high = _way_ahead(k, row)
        job = self._job
        if job is not None and not job.command.finished:  # a paused job resumes on its way
            if job.kind == "velocity" and not job.soft_limit_stop:
                low, high = (low, math.inf) if job.velocity > 0.0 else (-math.inf, high)
            elif job.kind == "position" and job.target is not None:
                low, high = min(low, job.target), max(high, job.target)
        tolerance = 1e-9 * max(1.0, abs(lo) if math.isfinite(lo) else 1.0,
                               abs(hi) if math.isfinite(hi) else 1.0)
        past_high = high > max(hi, start.position) + tolerance
        if not past_high and low >= min(lo, start.position) - tolerance:
            return
        limit = hi if past_high else lo
        if job is not None and job.kind in ("position", "velocity") \
                and not job.command.finished and lo <= start.position <= hi \
                and not k.superimposed[row] and self._stop_job_at(job, start, limit):
            return
        self.fault(ErrorId.SOFT_LIMIT_REACHED,
                    f"the motion would pass the software limit {limit} written during it")

    def _stop_job_at(self, job: Job, start: KinematicState, limit: float) -> bool:
        """Turn ``job`` into a stop at ``limit`` (D-016); False when it cannot stop there."""
        p = self.parameters
        direction = _sign(limit - start.position)
        hardest = Limits(max(job.limits.velocity, abs(start.velocity)), p.max_acceleration,
                         p.max_deceleration, p.max_jerk)
        for limits in (job.limits, hardest):
            trial = Job("position", job.command, limits, target=limit,
                        velocity=direction * limits.velocity, soft_limit_stop=True)
            try:
                profile = self._plan(trial)
                jobs.check_soft_limits(p, profile, limit)
            except CommandRejected:
                continue
            job.kind, job.target, job.limits = "position", limit, limits
            job.velocity, job.end_velocity, job.soft_limit_stop = trial.velocity, 0.0, True
            job.command.in_velocity = False
            self._install(profile)
            return True
        return False

    def read_parameter(self, number: int, kind: type = float) -> float | bool:
        spec = _parameter_spec(number)
        if (spec.kind is bool) != (kind is bool):
            raise CommandRejected(
                ErrorId.PARAMETER_TYPE_MISMATCH,
                f"parameter {number} is {spec.kind.__name__}, read as {kind.__name__}",
            )
        value = getattr(self, spec.source) if spec.status else getattr(self.parameters,
                                                                       spec.source)
        return bool(value) if kind is bool else float(value)

    def write_parameter(self, number: int, value: float | bool, kind: type = float) -> None:
        spec = _parameter_spec(number)
        if spec.read_only:
            raise CommandRejected(ErrorId.PARAMETER_READ_ONLY, f"parameter {number} is read-only")
        if (spec.kind is bool) != (kind is bool):
            raise CommandRejected(
                ErrorId.PARAMETER_TYPE_MISMATCH,
                f"parameter {number} is {spec.kind.__name__}, written as {kind.__name__}",
            )
        if kind is not bool and not is_finite(value):
            raise CommandRejected(ErrorId.INVALID_PARAMETER_VALUE,
                                  f"parameter {number}: {value!r} is not a finite number")
        old = getattr(self.parameters, spec.source)
        new = bool(value) if kind is bool else (int(value) if spec.kind is int else float(value))
        setattr(self.parameters, spec.source, new)
        try:
            self.parameters.validate()
        except ValueError as exc:
            setattr(self.parameters, spec.source, old)
            raise CommandRejected(ErrorId.INVALID_PARAMETER_VALUE, str(exc)) from None
        self.apply_parameters()

    # -- power, reset, override ----------------------------------------------------------------

    def power(self, enable: bool = True, enable_positive: bool = True,
              enable_negative: bool = True) -> bool:
        """MC_Power: returns the power status (enable AND drive ready)."""
        self.enable_positive, self.enable_negative = enable_positive, enable_negative
        status = enable and self.drive_ready
        was_powered = self.powered
        if status and not self.powered:
            self.powered = True
            self._k.reset_setpoint_to_actual(self.row)
            self._install(Profile.hold(KinematicState(self.position)), has_job=False)
            self._k.monitored[self.row] = self.state is not AxisState.ERROR_STOP
            if self.state is AxisState.DISABLED:
                self.state = AxisState.STANDSTILL
        elif not status and self.powered:
            self.powered = False
            for slave in self._slaves():  # they must not follow the frozen setpoint (D-199)
                slave.fault(ErrorId.MASTER_DISABLED,
                             f"its master {self.name} was disabled while coupled")
            self._abort_all("the axis was disabled")
            self._k.reset_setpoint_to_actual(self.row)
            self._install(Profile.hold(KinematicState(self.position)), has_job=False)
            self._k.monitored[self.row] = False
            self._hold = None
            if self.state is not AxisState.ERROR_STOP:
                self.state = AxisState.DISABLED
        member_power = getattr(self.group, "member_power_changed", None)  # CA groups
        if member_power is not None and self.powered != was_powered:
            member_power(self)  # a moving CA mover stays on its brake (D-183)
        self._update_override()
        return status

    def _slaves(self) -> list[Axis]:
        """The axes geared to this one."""
        couplings = self._k.couplings
        rows = set(couplings.slaves[couplings.masters == self.row].tolist())
        return [axis for axis in self._rt.axes.values() if axis.row in rows]

    def reset(self) -> Command:
        """MC_Reset: leave ErrorStop once the error reaction has stopped the axis."""
        command = self._new("reset")
        if self.state is not AxisState.ERROR_STOP:
            self._finish(command)
            return command
        command.status = CommandStatus.ACTIVE
        self.system.watch(self, lambda now: self._try_reset(command, now))
        return command

    def set_override(self, percent: float) -> Command:
        """MC_SetOverride: velocity override in percent, 0-100, applied without a jump."""
        command = self._new("override")
        if isinstance(percent, bool) or not isinstance(percent, int | float) or not (
            math.isfinite(percent) and 0.0 <= percent <= 100.0
        ):
            return self._reject(command, ErrorId.INVALID_OVERRIDE,
                                f"override must be within 0..100 %, got {percent!r}")
        self.override = percent / 100.0
        self._update_override()
        self._finish(command)
        return command

    # -- motion commands -----------------------------------------------------------------------

    def move_absolute(self, position: InputValue, velocity: InputValue,
                      acceleration: InputValue = MC_DEFAULT, deceleration: InputValue = MC_DEFAULT,
                      jerk: InputValue = MC_DEFAULT,
                      buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_MoveAbsolute (TcMC §3.1): move the set position to ``position``."""
        return self._move("move_absolute", lambda start: require_position("position", position),
                          velocity, acceleration, deceleration, jerk, buffer_mode)

    def move_relative(self, distance: InputValue, velocity: InputValue,
                      acceleration: InputValue = MC_DEFAULT, deceleration: InputValue = MC_DEFAULT,
                      jerk: InputValue = MC_DEFAULT,
                      buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_MoveRelative (TcMC §3.2): ``distance`` from the set position where it starts."""
        return self._move("move_relative",
                          lambda start: start + require_position("distance", distance),
                          velocity, acceleration, deceleration, jerk, buffer_mode)

    def move_modulo(self, position: InputValue, velocity: InputValue,
                    direction: Direction = Direction.POSITIVE,
                    acceleration: InputValue = MC_DEFAULT, deceleration: InputValue = MC_DEFAULT,
                    jerk: InputValue = MC_DEFAULT,
                    buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_MoveModulo (TcMC §3.4, §3.5): modulo target, extra turns for targets >= period."""
        p = self.parameters

        def target(start: float) -> float:
            value = require_position("position", position)
            try:
                way = convert_enum(Direction, direction)
            except ValueError:
                raise CommandRejected(ErrorId.INVALID_DIRECTION,
                                      f"direction {direction!r} is not an MC_Direction") from None
            return modulo_target(start, value, p.modulo_period, p.modulo_tolerance_window, way)

        return self._move("move_modulo", target, velocity, acceleration, deceleration, jerk,
                          buffer_mode)

    def move_velocity(self, velocity: InputValue, direction: Direction = Direction.POSITIVE,
                      acceleration: InputValue = MC_DEFAULT, deceleration: InputValue = MC_DEFAULT,
                      jerk: InputValue = MC_DEFAULT,
                      buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_MoveVelocity (TcMC §3.3): endless motion; ``in_velocity`` once at speed."""
        command = self._new("move_velocity")
        try:
            self._admit("move")
            mode = _buffer_mode(buffer_mode)
            limits = resolve_limits(self.parameters, command.warnings, velocity, acceleration,
                                    deceleration, jerk)
            sign = self._direction_sign(direction)
            job = Job("velocity", command, limits, velocity=sign * limits.velocity,
                      buffer_mode=mode)
            limit = jobs.soft_limit_in_direction(self.parameters, sign)
            if limit is not None:  # stop exactly at the limit instead of running past it
                job.kind, job.target, job.soft_limit_stop = "position", limit, True
            self._submit(job)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        return command

    def halt(self, deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
             buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_Halt (PLCopen Part 1): a stop that other commands may abort."""
        command = self._new("halt")
        try:
            self._admit("move")
            dec = resolve("deceleration", deceleration, self.parameters, command.warnings)
            j = resolve("jerk", jerk, self.parameters, command.warnings)
            limits = Limits(self.parameters.max_velocity, dec, dec, j)
            self._submit(Job("halt", command, limits, buffer_mode=_buffer_mode(buffer_mode)))
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        return command

    def stop(self, deceleration: InputValue = 0.0, jerk: InputValue = 0.0,
             hold: bool = False) -> Command:
        """MC_Stop (TcMC §3.15): brake to rest; with ``hold`` the axis stays in Stopping.

        0 keeps the running move's deceleration and jerk; a non-zero value is taken only with a
        non-zero partner. Softer values than the running ones apply unless one of the manual's
        four safety cases holds, where the stricter values are kept without an error.
        """
        command = self._new("stop")
        try:
            self._admit("stop")
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        bad: CommandRejected | None = None
        try:
            limits = self._stop_limits(deceleration, jerk, command)
        except CommandRejected as rejected:  # a stop always stops (D-023)
            bad, limits = rejected, self._stop_limits(0.0, 0.0, command)
        command.hold = hold
        profile = self._stop_profile(limits)  # needs the running job for the safety cases
        self._abort_all("aborted by MC_Stop")
        self._hold = None
        self._start(Job("stop", command, limits), profile)
        if bad is not None:
            self._reject(command, bad.error_id, bad.message + "; stopped with the running "
                         "move's dynamics")
        return command

    def home(self, position: InputValue = DEFAULT_HOME_POSITION) -> Command:
        """MC_Home (TcMC §3.14): reference the axis with the configured reference mode."""
        command = self._new("home")
        try:
            self._admit("home")
            home = (self.parameters.calibration_value if position is DEFAULT_HOME_POSITION
                    else require_position("position", position))
            sequence = HomingSequence(self, home)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self._abort_all("aborted by MC_Home")
        limits = Limits(self.parameters.max_velocity, self.parameters.acceleration,
                        self.parameters.deceleration, self.parameters.jerk)
        job = Job("home", command, limits)
        job.extra["sequence"] = sequence
        self._job = job
        command.status = CommandStatus.ACTIVE
        self.state = AxisState.HOMING
        self.system.watch(self, lambda now: sequence.step(now))
        return command

    def set_actual_position(self, position: InputValue) -> Command:
        """MC_SetActualPosition (TcMC §4.12): shift the coordinates so actual = position."""
        command = self._new("set_position")
        try:
            self._admit("set_position")
            if self.has_job or self.set_velocity != 0.0:
                raise CommandRejected(ErrorId.AXIS_NOT_STANDSTILL, "the axis is still moving")
            self.shift_coordinates(require_position("position", position) - self.position)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self._finish(command)
        return command

    def set_actual_position_on_the_fly(self, actual_position: InputValue,
                                       previous_position: InputValue) -> Command:
        """MC_SetActualPositionOnTheFly (TcMC §4.13): shift the coordinates of a moving axis.

        Set position, actual position and the running move's target all move by
        ``actual_position - previous_position``: the move covers the same distance and ends
        at its old target plus that shift.
        """
        command = self._new("set_position_on_the_fly")
        try:
            if self.state in (AxisState.DISABLED, AxisState.ERROR_STOP, AxisState.HOMING):
                self._admit("move")
            offset = require_position("actual_position", actual_position) - require_position(
                "previous_position", previous_position)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self.shift_coordinates(offset)
        self._finish(command)
        return command

    def oriented_stop(self, position: InputValue) -> Command:
        """MC_OrientedStop (TcMC §3.16): stop at the next reachable modulo ``position``.

        Braking uses the running move's deceleration and jerk; the stop point is the first
        position with the requested modulo value not before the normal stopping point, so the
        travel may be up to one modulo period longer. Where that is impossible (a stop runs
        already, a software limit lies before it) the axis stops normally and the command
        reports the error.
        """
        command = self._new("oriented_stop")
        period = self.parameters.modulo_period
        try:
            self._admit("stop")
            target = self._oriented_target(position)
            if self.state in (AxisState.STANDSTILL, AxisState.HOMING):
                raise CommandRejected(ErrorId.AXIS_NOT_MOVING, "oriented stop needs motion")
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        limits = self._stop_limits(0.0, 0.0, command)
        start = self._k.state(self.row)
        normal = jobs.plan_brake(start, limits.deceleration, limits.jerk, self.parameters)
        failure: CommandRejected | None = None
        profile = normal
        if self.state is AxisState.STOPPING:
            failure = CommandRejected(ErrorId.AXIS_STOPPING, "a stop runs already")
        else:
            direction = _sign(start.velocity) or _sign(start.acceleration) or 1
            end = normal.end.position
            offset = (target - end % period) % period if direction > 0 else \
                -((end % period - target) % period)
            goal = snap_to_period(end + offset, target, period)
            speed = Limits(max(abs(start.velocity), 1e-9), limits.acceleration,
                           limits.deceleration, limits.jerk)
            try:
                profile = jobs.plan_job(Job("position", command, speed, target=goal), start,
                                        1.0, self.parameters)
                jobs.check_soft_limits(self.parameters, profile, goal)
            except CommandRejected as rejected:
                failure, profile = rejected, normal
        self._abort_all("aborted by MC_OrientedStop")
        self._hold = None
        self._start(Job("stop", command, limits), profile)
        if failure is not None:
            self._reject(command, failure.error_id,
                         failure.message + "; stopped without orientation")
        return command

    def _oriented_target(self, position: InputValue) -> float:
        """MC_OrientedStop's Position: a modulo value in [0, period)."""
        target = require_position("position", position)
        period = self.parameters.modulo_period
        if not 0.0 <= target < period:
            raise CommandRejected(ErrorId.INVALID_MODULO_TARGET,
                                  f"position must lie in [0, {period}), got {target}")
        return target

    # -- gearing (TcMC §3.17-3.21) -------------------------------------------------------------

    def gear_in(self, master: Axis, ratio: float, acceleration: InputValue | None = None
                ) -> Command:
        """MC_GearIn / MC_GearInFloat / MC_GearInDyn: couple this slave to ``master``.

        Only at standstill (TcMC §3.17): the slave in StandStill and the master at rest. With
        ``acceleration`` (MC_GearInDyn) later ratio changes slew at most at
        ``acceleration / master max_velocity`` per second (§3.19).
        """
        command = self._new("gear_in")
        try:
            if master is self or not isinstance(master, Axis):
                raise CommandRejected(ErrorId.INVALID_MODE, "the master must be another axis")
            self._admit("move")
            if self.state is not AxisState.STANDSTILL:
                raise CommandRejected(ErrorId.AXIS_NOT_STANDSTILL,
                                      "coupling only at standstill (TcMC §3.17)")
            if master.set_velocity != 0.0 or master.set_acceleration != 0.0:
                raise CommandRejected(ErrorId.AXIS_NOT_STANDSTILL,
                                      "the master moves: coupling only at standstill")
            if self.row in self._k.couplings.masters_of(master.row):
                raise CommandRejected(ErrorId.COUPLING_LOOP,
                                      f"{master.name} follows {self.name} already (D-191)")
            ratio = _gear_ratio(ratio)
            rate = math.inf
            if acceleration is not None:
                dyn = resolve("acceleration", acceleration, self.parameters, command.warnings)
                rate = dyn / master.parameters.max_velocity
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self._abort_all("aborted by MC_GearIn")
        self._hold = None
        self._k.couplings.couple(self.row, master.row, ratio, master.set_position,
                                 self.set_position)
        p = self.parameters
        job = Job("gear", command, Limits(p.max_velocity, p.acceleration, p.deceleration, p.jerk))
        job.extra.update(master=master, target_ratio=ratio, ratio_rate=rate)
        self._job = job
        command.status = CommandStatus.ACTIVE
        self.state = AxisState.SYNCHRONIZED_MOTION
        self.system.watch(self, lambda now: self._gear_cycle(job))
        return command

    def dynamic_coupling(self, master: Axis) -> Command | None:
        """The running coupling of this slave to ``master``, if there is one: a new edge of
        MC_GearInDyn takes it over instead of coupling again (TcMC §3.19, D-196)."""
        job = self._job
        if job is None or job.kind != "gear" or job.command.finished \
                or job.extra.get("master") is not master:
            return None
        return job.command

    def set_gear_acceleration(self, acceleration: InputValue) -> Command:
        """MC_GearInDyn's Acceleration for the running coupling: the ratio slews at most at
        ``acceleration / master max_velocity`` per second (§3.19)."""
        command = self._new("gear_acceleration")
        job = self._job
        try:
            if job is None or job.kind != "gear":
                raise CommandRejected(ErrorId.NOT_COUPLED, "the axis is not a geared slave")
            dyn = resolve("acceleration", acceleration, self.parameters, command.warnings)
            job.extra["ratio_rate"] = dyn / job.extra["master"].parameters.max_velocity
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self._finish(command)
        return command

    def set_gear_ratio(self, ratio: float) -> Command:
        """A new target ratio for a dynamic coupling (MC_GearInDyn, re-read every cycle)."""
        command = self._new("gear_ratio")
        job = self._job
        try:
            if job is None or job.kind != "gear":
                raise CommandRejected(ErrorId.NOT_COUPLED, "the axis is not a geared slave")
            job.extra["target_ratio"] = _gear_ratio(ratio)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        self._finish(command)
        return command

    def gear_out(self) -> Command:
        """MC_GearOut (TcMC §3.20): decouple; a moving slave releases its acceleration and
        cruises at constant velocity until another command, like after MC_MoveVelocity."""
        command = self._new("gear_out")
        job = self._job
        if job is None or job.kind != "gear":
            return self._reject(command, ErrorId.NOT_COUPLED, "the axis is not a geared slave")
        job.command.end(CommandStatus.ABORTED, self._rt.now, message="decoupled by MC_GearOut")
        self._job = None
        self._release_coupling()
        self._finish(command)
        return command

    def gear_out_ext(self, mode: DecoupleMode, position: InputValue = MC_INVALID,
                     velocity: InputValue = MC_INVALID, acceleration: InputValue = MC_DEFAULT,
                     deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT
                     ) -> Command:
        """MC_GearOutExt (TcMC §3.21): decouple, then the follow-up ``mode`` if moving.

        Returns the follow-up command (Done at its target or constant velocity); at
        standstill there is no follow-up and the returned command is Done at once. A follow-up
        input that its command would refuse fails the whole command: the slave stays coupled.
        """
        try:
            mode = DecoupleMode(mode)
        except ValueError:
            command = self._new("gear_out_ext")
            return self._reject(command, ErrorId.INVALID_MODE, f"mode {mode!r} is unknown")
        moving = self.set_velocity != 0.0 or self.set_acceleration != 0.0
        speed = abs(self.set_velocity)
        if mode is DecoupleMode.ENDLESS:
            velocity = speed or MC_INVALID
        elif mode is DecoupleMode.NEW_POSITION:
            velocity = max(speed, 1e-9)
        if moving and self._job is not None and self._job.kind == "gear":
            try:  # a rejected command leaves the slave coupled
                self._check_follow_up(mode, position, velocity, acceleration, deceleration, jerk)
            except CommandRejected as rejected:
                return self._reject(self._new("gear_out_ext"), rejected.error_id,
                                    rejected.message)
        out = self.gear_out()
        if out.error or not moving:
            return out
        direction = Direction.NEGATIVE if self.set_velocity < 0.0 else Direction.POSITIVE
        if mode is DecoupleMode.STOP:
            return self.stop(deceleration, jerk)
        if mode is DecoupleMode.ORIENTED_STOP:
            return self.oriented_stop(position)
        if mode in (DecoupleMode.ENDLESS, DecoupleMode.ENDLESS_NEW_VELOCITY):
            return self.move_velocity(velocity, direction, acceleration, deceleration, jerk)
        if mode in (DecoupleMode.NEW_POSITION, DecoupleMode.NEW_POSITION_AND_VELOCITY):
            return self.move_absolute(position, velocity, acceleration, deceleration, jerk)
        halt = self._new("instantaneous_stop")  # the velocity jumps to zero (§3.21)
        self._install(Profile.hold(KinematicState(self.set_position)), has_job=False)
        self._job = None
        self.state = AxisState.STANDSTILL
        self._finish(halt)
        return halt

    def _check_follow_up(self, mode: DecoupleMode, position: InputValue, velocity: InputValue,
                         acceleration: InputValue, deceleration: InputValue,
                         jerk: InputValue) -> None:
        """MC_GearOutExt: reject the follow-up's inputs before decoupling, in the order its
        command checks them (MC_Stop always stops; the instantaneous stop takes none)."""
        if mode is DecoupleMode.ORIENTED_STOP:
            self._oriented_target(position)
        elif mode not in (DecoupleMode.STOP, DecoupleMode.INSTANTANEOUS_STOP):
            resolve_limits(self.parameters, [], velocity, acceleration, deceleration, jerk)
        if mode in (DecoupleMode.NEW_POSITION, DecoupleMode.NEW_POSITION_AND_VELOCITY):
            target = require_position("position", position)
            jobs.check_soft_limits(self.parameters, Profile.hold(KinematicState(target)), target,
                                   start=self.set_position)

    def _gear_cycle(self, job: Job) -> bool:
        """Per cycle while coupled: slew a dynamic ratio, watch the slave's limits."""
        if job is not self._job or job.command.finished:
            return False
        couplings, master = self._k.couplings, job.extra["master"]
        ratio, target = couplings.ratio_of(self.row), job.extra["target_ratio"]
        if ratio != target:
            cycle = self._rt.cycle_time
            step = min(abs(target - ratio), job.extra["ratio_rate"] * cycle)
            new = target if step == abs(target - ratio) else ratio + math.copysign(step,
                                                                                   target - ratio)
            couplings.set_ratio(self.row, new, master.set_position, (new - ratio) / cycle)
        elif couplings.ratio_rate[couplings.slaves == self.row].any():
            couplings.set_ratio(self.row, ratio, master.set_position, 0.0)
        return True  # the kernel watches the slave's limits in every sample (D-182)

    def gear_limit_fault(self) -> None:
        """Kernel event: this slave's new sample would pass its maximum velocity,
        acceleration or jerk (or brake beyond its maximum velocity). ErrorStop, decoupled,
        braking with the maximum deceleration and jerk from the previous sample, the last
        one within the limits, so that no sample beyond them is ever output (D-182)."""
        v, a, j = self.set_velocity, self.set_acceleration, self.set_jerk
        time, start = self._k.previous_sample(self.row)
        self.fault(ErrorId.GEAR_LIMIT_EXCEEDED,
                    f"the geared slave would reach {v:.6g} mm/s, {a:.6g} mm/s², {j:.6g} mm/s³ "
                    "beyond its maxima")
        p = self.parameters
        self._install(plan_stop(start, p.max_deceleration, p.max_jerk), has_job=False,
                      time=time)

    def _release_coupling(self) -> None:
        """Decouple: continue from the coupled state, releasing the acceleration (§3.20)."""
        k = self._k
        if self.row not in k.couplings:
            return
        start = k.base_state(self.row)  # a superposition keeps riding on top (D-180)
        k.couplings.decouple(self.row)
        p = self.parameters
        jerk = jerk_within_velocity(start, p.jerk, p.max_velocity, p.max_jerk)  # D-177
        cruise = start.velocity + start.acceleration * abs(start.acceleration) / (2.0 * jerk)
        profile = plan_velocity(start, cruise, Limits(p.max_velocity, p.max_acceleration,
                                                      p.max_deceleration, jerk))
        self._install(profile, has_job=False)
        if cruise != 0.0:  # keeps moving like after MC_MoveVelocity
            p = self.parameters
            motion = self._new("decoupled")
            job = Job("velocity", motion, Limits(abs(cruise), p.acceleration, p.deceleration,
                                                 p.jerk), velocity=cruise)
            self._job = job
            motion.status = CommandStatus.ACTIVE
            motion.in_velocity = profile.duration == 0.0
            self._k.has_job[self.row] = profile.duration > 0.0
            self.state = AxisState.CONTINUOUS_MOTION
        elif k.superimposed[self.row]:  # the superposition still moves it (D-181)
            self.state = AxisState.DISCRETE_MOTION
        else:
            self.state = AxisState.STANDSTILL

    # -- superposition (TcMC §3.9-3.12) -------------------------------------------------------

    def move_superimposed(self, distance: InputValue, velocity_diff: InputValue,
                          velocity_process: InputValue, length: InputValue,
                          mode: SuperpositionMode = SuperpositionMode.LENGTHREDUCTION_LIMITEDMOTION,
                          acceleration: InputValue = MC_DEFAULT,
                          deceleration: InputValue = MC_DEFAULT) -> Command:
        """MC_MoveSuperImposed(Ext): add ``distance`` on top of the running motion.

        The command's ``value`` holds (ActualVelocityDiff, ActualDistance, ActualLength). When
        the distance cannot be reached it is done as far as possible and the command ends
        with SUPERPOSITION_INCOMPLETE (0x4243) - a warning or an error, as the application
        decides (§3.9).
        """
        command = self._new("move_superimposed")
        try:
            self._admit("modify")
            try:
                mode = SuperpositionMode(mode)
            except ValueError:
                raise CommandRejected(ErrorId.INVALID_MODE, f"mode {mode!r} is unknown") from None
            d = require_position("distance", distance)
            if d == 0.0:
                raise CommandRejected(ErrorId.INVALID_POSITION, "distance must not be 0")
            w = command.warnings
            dv = resolve("velocity", abs(velocity_diff) if isinstance(velocity_diff, float)
                         else velocity_diff, _UNBOUNDED, w)
            v0 = resolve("velocity", abs(velocity_process) if isinstance(velocity_process, float)
                         else velocity_process, _UNBOUNDED, w)
            span = require_position("length", length)
            if span == 0.0:
                raise CommandRejected(ErrorId.INVALID_POSITION, "length must not be 0")
            acc = resolve("acceleration", acceleration, self.parameters, w)
            dec = resolve("deceleration", deceleration, self.parameters, w)
            if self._k.superimposed[self.row]:
                raise CommandRejected(ErrorId.SUPERPOSITION_ACTIVE,
                                      "a superposition runs already (D-041)")
            room = room_beside(self.parameters, self._base_rest())
            if not room.fits(self.parameters, _sign(d)):
                raise CommandRejected(ErrorId.SUPERPOSITION_INCOMPLETE,
                                      "the base motion leaves no room within the axis "
                                      "maxima for a superimposed motion (D-180)")
            jerk = min(self.parameters.jerk, room.jerk)
            plan = plan_superposition(mode, d, min(dv, room.velocity(_sign(d))),
                                      min(acc, room.acceleration), min(dec, room.acceleration),
                                      jerk, v0, span, self.set_velocity)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        k = self._k
        k.set_superimposed(self.row, True)
        k.overlay.install(self.row, plan.profile, k.sample_time)
        command.value = (plan.velocity_diff, plan.distance, plan.length)
        command.status = CommandStatus.ACTIVE
        command.in_velocity = plan.complete
        self._superposition = command
        return command

    def _base_rest(self) -> Profile:
        """The rest of the base motion as planned now: the profile of a free axis; a geared
        or fed axis only knows its present state (its limits are watched every cycle)."""
        k, row = self._k, self.row
        if row in k.couplings or k.external[row]:
            return Profile.hold(k.base_state(row))
        return k.segments.remaining(row, k.sample_time)

    def abort_superposition(self) -> Command:
        """MC_AbortSuperposition (TcMC §3.12): end the superimposed part; the base continues.

        The superimposed velocity brakes to zero with the axis default deceleration; the
        superposition command shows CommandAborted.
        """
        command = self._new("abort_superposition")
        k = self._k
        if self._superposition is not None and k.superimposed[self.row]:
            state = k.overlay.state(self.row, k.sample_time)
            p = self.parameters
            room = room_beside(p, self._base_rest())  # D-180: the brake keeps the maxima too
            profile = plan_stop(state, max(min(p.deceleration, room.acceleration),
                                           abs(state.acceleration)),
                                max(min(p.jerk, room.jerk), p.jerk * ROOM_FLOOR))
            k.overlay.install(self.row, profile, k.sample_time)
            self._superposition.end(CommandStatus.ABORTED, self._rt.now,
                                     message="aborted by MC_AbortSuperposition")
            self._superposition = None
        self._finish(command)
        return command

    def superposition_ended(self) -> None:
        """Kernel event: the superimposed motion is complete; fold it into the base."""
        command = self._superposition
        if command is not None:
            complete = command.in_velocity
            command.in_velocity = False
            if complete:
                self._fold_overlay(CommandStatus.DONE, "", ended=True)
            else:
                self._fold_overlay(CommandStatus.ERROR, "the distance was compensated only "
                                   "partly (TcMC §3.9)", ErrorId.SUPERPOSITION_INCOMPLETE,
                                   ended=True)
        else:
            self._fold_overlay(CommandStatus.DONE, "", ended=True)

    def _fold_overlay(self, status: CommandStatus, message: str,
                      error_id: ErrorId = ErrorId.NO_ERROR, ended: bool = False) -> None:
        """End the superposition. ``ended``: it reached its end, so its final offset moves
        the base; otherwise the base takes over the combined state for a new plan."""
        k, row = self._k, self.row
        if not k.superimposed[row]:
            return
        extra = k.overlay.state(row, k.sample_time)
        if ended or (extra.velocity == 0.0 and extra.acceleration == 0.0):
            offset = k.overlay.end_position(row)
            if row in k.couplings:  # a geared slave keeps the correction in its offset
                k.couplings.shift(row, offset)
            else:
                k.segments.shift(row, offset)  # the base continues, shifted by what was added
            for job in ([self._job] if self._job else []) + self._queue:
                if job.target is not None:
                    job.target += offset
        else:  # still moving: the base takes over the combined state (a new plan follows)
            self._install(self._carry_on(k.state(row)), has_job=False)
        k.set_superimposed(row, False)
        if self._superposition is not None:
            self._superposition.end(status, self._rt.now, error_id, message)
            self._superposition = None
        if ended:
            self._after_superposition()

    def _carry_on(self, state: KinematicState) -> Profile:
        """Go on from ``state`` with its acceleration released at the maximum jerk: the next
        plan starts from the whole state, acceleration included, so nothing jumps."""
        a = state.acceleration
        if a == 0.0:
            return Profile.hold(state)
        p = self.parameters
        cruise = state.velocity + a * abs(a) / (2.0 * p.max_jerk)
        return plan_velocity(state, cruise, Limits(math.inf, max(p.max_acceleration, abs(a)),
                                                   max(p.max_deceleration, abs(a)), p.max_jerk))

    def _after_superposition(self) -> None:
        """The superposition has ended: a base planned in the room beside it gets its own
        limits back, and a base that came to rest meanwhile ends now (D-180, D-181)."""
        job = self._job
        if job is None and self.state is AxisState.DISCRETE_MOTION and not self.has_job:
            self.state = AxisState.STANDSTILL  # decoupled at rest beneath it (D-181)
            return
        if job is None or job.command.finished:
            return
        if job.extra.pop("beside_superposition", False) and job.kind in (
                "position", "velocity") and (self.has_job or job.kind == "velocity"):
            try:
                self._install(self._plan(job))
                job.command.in_velocity = False
            except CommandRejected as rejected:
                self.fault(rejected.error_id, rejected.message)
        elif job.kind in ("halt", "stop") and not self.has_job:
            self._end_stop(job)

    # -- external setpoint generation (TcMC §4.16-4.18) -----------------------------------------

    @property
    def external_setpoints(self) -> bool:
        """The external setpoint generator is enabled (MC_ExtSetPointGen* ``Enabled``)."""
        return bool(self._k.external[self.row])

    @property
    def in_external_target(self) -> bool:
        """The set position reached the external generator's target (§4.16)."""
        return bool(self._external_target_reached)

    def enable_external_setpoints(self, position: InputValue = MC_INVALID,
                                  position_type: TargetPositionType = TargetPositionType.ABSOLUTE
                                  ) -> Command:
        """MC_ExtSetPointGenEnable: from now on the fed values are the setpoint (D-040).

        ``position`` is only watched ("in target position"); the axis does not go there by
        itself. A cycle without a feed, or a fed velocity or acceleration beyond the axis
        maxima, is an axis error with a controlled stop.
        """
        command = self._new("ext_setpoint_enable")
        try:
            self._admit("move")
            kind = TargetPositionType(position_type)
            target = None if position is MC_INVALID else require_position("position", position)
            if target is not None and kind is TargetPositionType.RELATIVE:
                target += self.set_position
        except ValueError:
            return self._reject(command, ErrorId.INVALID_MODE,
                                f"position type {position_type!r} is unknown")
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        if self.external_setpoints:
            self._external_goal = (target, kind)
            self._finish(command)
            return command
        self._abort_all("aborted by MC_ExtSetPointGenEnable")
        self._hold = None
        self._k.set_external(self.row, True)
        p = self.parameters
        job = Job("external", command, Limits(p.max_velocity, p.acceleration, p.deceleration,
                                              p.jerk))
        self._job = job
        self._external_goal = (target, kind)
        self._external_target_reached = False
        self.state = AxisState.CONTINUOUS_MOTION
        self._finish(command)  # Done = command issued (§4.16)
        self._job.command = self._new("external_motion")
        self._job.command.status = CommandStatus.ACTIVE
        grace = [True]  # the feed may start in the cycle after the enable
        self.system.watch(self, lambda now: self._external_cycle(job, grace))
        return command

    def disable_external_setpoints(self) -> Command:
        """MC_ExtSetPointGenDisable: ignore fed values; a moving axis brakes to rest."""
        command = self._new("ext_setpoint_disable")
        if self.external_setpoints:
            self._end_external("disabled by MC_ExtSetPointGenDisable")
        self._finish(command)
        return command

    def feed_setpoint(self, position: float, velocity: float, acceleration: float,
                      direction: int) -> bool:
        """MC_ExtSetPointGenFeed (§4.18): the setpoint of the next motion step; returns False."""
        k, row = self._k, self.row
        k.ext_p[row], k.ext_v[row], k.ext_a[row] = position, velocity, acceleration
        k.fed[row] = True
        self._external_direction = direction
        return False

    def _external_cycle(self, job: Job, grace: list[bool]) -> bool:
        if job is not self._job or job.command.finished:
            return False
        k, row, p = self._k, self.row, self.parameters
        if not k.fed[row] and not grace[0]:
            self.fault(ErrorId.EXT_SETPOINT_MISSING, "no external setpoint fed this cycle")
            return False
        grace[0] = False
        k.fed[row] = False
        v, a = abs(self.set_velocity), abs(self.set_acceleration)
        if not (math.isfinite(self.set_position) and v <= p.max_velocity * (1 + 1e-9)
                and a <= max(p.max_acceleration, p.max_deceleration) * (1 + 1e-9)):
            self.fault(ErrorId.EXT_SETPOINT_LIMIT,
                        f"fed setpoint {v:.6g} mm/s, {a:.6g} mm/s² beyond the axis maxima")
            return False
        target, kind = self._external_goal
        if target is not None:
            if kind is TargetPositionType.MODULO:
                period = p.modulo_period
                error = abs((self.set_position - target + period / 2) % period - period / 2)
            else:
                error = abs(self.set_position - target)
            self._external_target_reached = error <= p.target_position_window
        return True

    def _end_external(self, reason: str) -> None:
        """Leave external setpoints: continue from the fed state and brake to rest."""
        k, row = self._k, self.row
        start = k.state(row)
        k.set_external(row, False)
        if self._job is not None and self._job.kind == "external":
            self._job.command.end(CommandStatus.DONE, self._rt.now, message=reason)
            self._job = None
        p = self.parameters
        self._install(jobs.plan_brake(start, p.deceleration, p.jerk, p), has_job=False)
        self.state = AxisState.STANDSTILL if start.velocity == 0.0 else self.state
        if start.velocity != 0.0:
            halt = self._new("external_stop")
            job = Job("halt", halt, Limits(p.max_velocity, p.deceleration, p.deceleration,
                                           p.jerk))
            self._job = job
            halt.status = CommandStatus.ACTIVE
            self._k.has_job[row] = True
            self.state = AxisState.DISCRETE_MOTION

    def new_position(self, position: InputValue) -> Command:
        """MC_NewPos (TcMC §3.7): a new target for the running move; Done = accepted."""
        return self.new_position_and_velocity(NewPosAndVeloMode.CHANGE_POS, position, 0.0)

    def new_position_and_velocity(self, mode: NewPosAndVeloMode, position: InputValue,
                                  velocity: InputValue,
                                  activation_position: float = 0.0) -> Command:
        """MC_NewPosAndVelo (TcMC §3.8): change target and/or velocity, now or at a position."""
        command = self._new("new_position")
        try:
            self._admit("modify")
            job = self._job
            if job is None or job.kind not in ("position", "velocity"):
                raise CommandRejected(ErrorId.NOTHING_TO_DO, "no running move to modify")
            try:
                mode = NewPosAndVeloMode(mode)
            except ValueError:
                raise CommandRejected(ErrorId.INVALID_MODE, f"mode {mode!r} is unknown") from None
            change_pos = mode in (NewPosAndVeloMode.CHANGE_POS,
                                  NewPosAndVeloMode.CHANGE_POS_AND_VELO,
                                  NewPosAndVeloMode.CHANGE_POS_AT_SWITCHPOS,
                                  NewPosAndVeloMode.CHANGE_POS_AND_VELO_AT_SWITCHPOS)
            change_velo = mode not in (NewPosAndVeloMode.CHANGE_POS,
                                       NewPosAndVeloMode.CHANGE_POS_AT_SWITCHPOS)
            target = require_position("position", position) if change_pos else None
            speed = resolve("velocity", velocity, self.parameters, command.warnings) \
                if change_velo else None
            switch = mode >= NewPosAndVeloMode.CHANGE_POS_AT_SWITCHPOS
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        if not switch:
            try:
                self._modify(job, target, speed)
            except CommandRejected as rejected:
                return self._reject(command, rejected.error_id, rejected.message)
            self._finish(command)
            return command
        reach = mode is NewPosAndVeloMode.REACH_VELO_AT_POS and speed is not None
        self._arm_switch(command, job, float(activation_position), target, speed, reach)
        return command

    def change_dynamics(self, acceleration: InputValue = MC_DEFAULT,
                        deceleration: InputValue = MC_DEFAULT,
                        jerk: InputValue = MC_DEFAULT) -> Command:
        """MC_ChangeDynParam (TcMC §4.20): new acc/dec/jerk for the running move."""
        command = self._new("change_dynamics")
        try:
            if self.state is AxisState.STOPPING:
                raise CommandRejected(ErrorId.DYN_STRICTER_STOP_ACTIVE,
                                      "a stop with its own dynamics is in progress")
            self._admit("modify")
            job = self._job
            if job is None or job.kind not in ("position", "velocity"):
                raise CommandRejected(ErrorId.NOTHING_TO_DO, "no running move to modify")
            w = command.warnings
            limits = Limits(job.limits.velocity,
                            resolve("acceleration", acceleration, self.parameters, w),
                            resolve("deceleration", deceleration, self.parameters, w),
                            resolve("jerk", jerk, self.parameters, w))
            trial = Job(job.kind, job.command, limits, job.target, job.velocity,
                        job.buffer_mode, job.end_velocity, job.soft_limit_stop)
            profile = self._plan_dynamics_change(trial)
            _check_dynamics_change(job, profile, self._k.base_state(self.row))
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        job.limits = limits
        _keep_room_mark(trial, job)
        self._install(profile)
        self._finish(command)
        return command

    def _plan_dynamics_change(self, trial: Job) -> Profile:
        """A planner failure under the new dynamics is TcMC §4.20's "internal optimisation
        not possible" (D-050)."""
        try:
            return self._plan(trial)
        except CommandRejected as rejected:
            if rejected.error_id is not ErrorId.NO_PROFILE:
                raise
            raise CommandRejected(ErrorId.DYN_OPTIMISATION_FAILED,
                                  f"no profile with the new dynamics ({rejected.message})"
                                  ) from None

    def restart(self, command: Command, position: InputValue, velocity: InputValue) -> bool:
        """MC_MoveAbsoluteOrRestart (TcMC §3.6): retarget ``command`` if it still runs.

        The start dynamics stay; returns False when ``command`` no longer runs, so that the
        caller issues a fresh move.
        """
        job = self._job
        if job is None or job.command is not command or job.kind != "position":
            return False
        try:
            target = require_position("position", position)
            speed = resolve("velocity", velocity, self.parameters, command.warnings)
            self._modify(job, target, speed)
        except CommandRejected as rejected:
            self._fail_job(job, rejected.error_id, rejected.message)
        return True

    # -- internals: starting, replacing and ending jobs ---------------------------------------

    def _admit(self, family: str) -> None:
        """PLCopen state check; a group member only moves through its group (TF5410; Part 4
        §3.2 option 1). A Part 4 group decides for its members (``AxesGroup._admit_member``:
        MC_Stop and MC_Home pass and make it GroupMoving, §3.2)."""
        if self.group is not None:
            admit_member = getattr(self.group, "_admit_member", None)
            if admit_member is None:
                raise CommandRejected(ErrorId.AXIS_IN_GROUP,
                                      f"the axis is in group "
                                      f"{getattr(self.group, 'name', '')!r}: use the group's "
                                      "blocks")
            admit_member(self, family)
            return
        admit(self.state, family)

    def _move(self, kind: str, target_of: Callable[[float], float], velocity: InputValue,
              acceleration: InputValue, deceleration: InputValue, jerk: InputValue,
              buffer_mode: BufferMode) -> Command:
        command = self._new(kind)
        try:
            self._admit("move")
            mode = _buffer_mode(buffer_mode)
            limits = resolve_limits(self.parameters, command.warnings, velocity, acceleration,
                                    deceleration, jerk)
            job = Job("position", command, limits, buffer_mode=mode)
            job.extra["target_of"] = target_of
            self._submit(job)
        except CommandRejected as rejected:
            return self._reject(command, rejected.error_id, rejected.message)
        return command

    def _submit(self, job: Job) -> None:
        """Start ``job`` now (Aborting, or nothing running) or queue it behind the others."""
        current = self._job
        if (job.buffer_mode is not BufferMode.ABORTING and current is not None
                and current.kind == "velocity" and current.command.in_velocity
                and not self._queue):  # PLCopen: buffered behind MoveVelocity starts InVelocity
            if job.target is None and "target_of" in job.extra:
                job.target = job.extra["target_of"](self.set_position)
            self._queue.append(job)
            self._start_next(self._k.sample_time)
            return
        if job.buffer_mode is BufferMode.ABORTING or current is None or self._idle():
            if job.target is None and "target_of" in job.extra:
                job.target = job.extra["target_of"](self.set_position)
            profile = self._plan(job, whole=True)  # it ends the superposition (D-041)
            jobs.check_soft_limits(self.parameters, profile, job.target)
            self._abort_all(f"aborted by {job.command.kind}")
            self._hold = None
            self._start(job, profile)
            return
        if len(self._queue) >= MAX_BUFFERED:
            raise CommandRejected(ErrorId.BUFFER_FULL, f"{MAX_BUFFERED} commands already queued")
        previous = self._queue[-1] if self._queue else current
        if job.target is None and "target_of" in job.extra:
            job.target = job.extra["target_of"](self._end_position_of(previous))
        self._queue.append(job)
        job.command.status = CommandStatus.BUFFERED
        if job.buffer_mode in _BLEND_SPEED and previous.kind == "position" and \
                job.kind == "position" and previous.target is not None:
            self._blend(previous, job)

    def _blend(self, previous: Job, following: Job) -> None:
        assert following.target is not None
        magnitude = _BLEND_SPEED[following.buffer_mode](previous.limits.velocity,
                                                         following.limits.velocity)
        running = previous is self._job and self.has_job
        if running:
            start = self._k.base_state(self.row)
        elif previous is self._job:
            start = KinematicState(self.set_position)
        else:  # queued: it will start where the job before it ends
            before = self._queue[-3] if len(self._queue) >= 3 else self._job
            start = KinematicState(self._end_position_of(before), before.end_velocity)
        previous.end_velocity = jobs.blend_velocity(start, previous, following.target,
                                                    following.limits, magnitude)
        if running and previous.end_velocity != 0.0:
            self._install(self._plan(previous))

    def _idle(self) -> bool:
        """Nothing runs: a finished hold or halt at rest counts as idle."""
        job = self._job
        return job is None or (job.command.finished and not self.has_job)

    def _plan(self, job: Job, whole: bool = False) -> Profile:
        """Plan ``job`` from the last sample. ``whole``: from the whole setpoint, for a command
        that ends a running superposition; otherwise from the base motion, which the
        superposition keeps riding on (D-180)."""
        k = self._k
        start = k.state(self.row) if whole else k.base_state(self.row)
        job.extra["start"] = start.position
        if whole:
            return jobs.plan_job(job, start, self._effective_override, self.parameters)
        return self._plan_base(job, start)

    def _plan_base(self, job: Job, start: KinematicState) -> Profile:
        """Plan the base motion; beside a running superposition only in the room its rest
        leaves (D-180), or, where there is none, after folding it into the base."""
        k, p, override = self._k, self.parameters, self._effective_override
        if not k.superimposed[self.row]:
            return jobs.plan_job(job, start, override, p)
        room = room_beside(p, k.overlay.remaining(self.row, k.sample_time))
        direction = _sign(job.velocity) if job.kind == "velocity" else (
            _sign((job.target if job.target is not None else start.position) - start.position)
            or _sign(start.velocity))
        if not room.fits(p, direction):
            self._fold_overlay(CommandStatus.ABORTED, "the base motion was re-planned where "
                               "the axis limits leave no room beside the superposition")
            return jobs.plan_job(job, k.state(self.row), override, p)
        cap = room.velocity(direction) / max(override, jobs.MIN_OVERRIDE)
        limits = job.limits
        capped = Limits(min(limits.velocity, cap), min(limits.acceleration, room.acceleration),
                        min(limits.deceleration, room.acceleration),
                        min(limits.jerk, room.jerk))
        trial = Job(job.kind, job.command, capped, job.target,
                    math.copysign(min(abs(job.velocity), cap), job.velocity), job.buffer_mode,
                    math.copysign(min(abs(job.end_velocity), cap), job.end_velocity),
                    job.soft_limit_stop)
        job.extra["beside_superposition"] = True  # re-planned in full when it ends
        j_max = min(p.max_jerk, room.jerk)  # D-020 raises a jerk at most to what is left
        caps = replace(p, max_velocity=min(p.max_velocity, room.velocity(direction)),
                       max_jerk=j_max, jerk=min(p.jerk, j_max))
        return jobs.plan_job(trial, start, override, caps)

    def _start(self, job: Job, profile: Profile, time: float | None = None) -> None:
        self._job = job
        job.command.status = CommandStatus.ACTIVE
        self._install(profile, time=time)
        self.state = _STATE_OF_JOB[job.kind]
        if job.soft_limit_stop:  # a MoveVelocity that will stop at a software limit
            self.state = AxisState.CONTINUOUS_MOTION
            self.system.watch(self, lambda now: self._cruise_check(job))

    def _cruise_check(self, job: Job) -> bool:
        """InVelocity for a velocity job planned as a stop at a software limit (D-016)."""
        if job is not self._job or job.command.finished or not job.soft_limit_stop:
            return False
        commanded = job.velocity * self._effective_override
        k, row = self._k, self.row
        job.command.in_velocity = bool(
            k.set_a[row] == 0.0 and abs(k.set_v[row] - commanded) <= 1e-9 * abs(commanded)
        )
        return True

    def _install(self, profile: Profile, has_job: bool = True, time: float | None = None) -> None:
        k = self._k
        k.segments.install(self.row, profile, k.sample_time if time is None else time)
        k.has_job[self.row] = has_job

    def _modify(self, job: Job, target: float | None, speed: float | None) -> None:
        """Retarget or re-speed the running job from where the setpoint is now."""
        trial = Job(job.kind, job.command, job.limits, job.target, job.velocity, job.buffer_mode,
                    job.end_velocity, job.soft_limit_stop)
        if speed is not None:
            trial.limits = Limits(speed, job.limits.acceleration, job.limits.deceleration,
                                  job.limits.jerk)
            if trial.kind == "velocity":
                trial.velocity = math.copysign(speed, job.velocity)
        if target is not None:
            trial.kind, trial.target, trial.soft_limit_stop = "position", target, False
        profile = self._plan(trial)
        jobs.check_soft_limits(self.parameters, profile, trial.target)
        job.kind, job.limits, job.target, job.velocity = (trial.kind, trial.limits, trial.target,
                                                          trial.velocity)
        job.soft_limit_stop, job.settle_time, job.settling_for = trial.soft_limit_stop, 0.0, 0.0
        _keep_room_mark(trial, job)
        job.command.in_velocity = False
        self._install(profile)
        if job.kind == "position" and self.state is AxisState.CONTINUOUS_MOTION:
            self.state = AxisState.DISCRETE_MOTION

    def profile_ended(self, end_time: float) -> None:
        """Kernel event: the setpoint reached the end state of the job's profile."""
        self._k.has_job[self.row] = False
        job = self._job
        if job is None or self._effective_override < jobs.MIN_OVERRIDE and job.kind in (
                "position", "velocity"):
            return  # override 0 paused the job; it resumes when the override returns
        if job.kind == "velocity":
            job.command.in_velocity = True
            self._start_next(end_time)
        elif job.kind == "position":
            if job.soft_limit_stop:
                self.fault(ErrorId.SOFT_LIMIT_REACHED,
                            f"stopped at the software limit {job.target}",
                            time=end_time)
            elif self._queue and self._queue[0].buffer_mode in _BLEND_SPEED:
                self._finish(job.command)
                self._start_next(end_time)
            elif not job.extra.get("settling"):
                job.extra["settling"] = True
                self.system.watch(self, lambda now: self._settle(job, now))
        elif job.kind in ("halt", "stop") and not self._k.superimposed[self.row]:
            self._end_stop(job)
        # a halt whose base came to rest under a superposition ends with it (D-181)

    def _end_stop(self, job: Job) -> None:
        """A halt or stop has brought the axis to rest."""
        self._finish(job.command)
        if job.kind == "stop" and job.command.hold:
            self._hold = job.command
            self.system.watch(self, self._release_stop)
        else:
            self._job = None
            self.state = AxisState.STANDSTILL
            self._start_next(self._k.sample_time)

    def _settle(self, job: Job, now: float) -> bool:
        """TcMC §7.1: Done once the monitors enabled by 1022/1024 agree; False = stop watching."""
        if job is not self._job or job.command.finished:
            return False
        if self.has_job or self._k.superimposed[self.row]:  # re-planned (override, MC_NewPos),
            job.settle_time = job.settling_for = 0.0  # or still superimposed (D-181): settle
            return True  # after the motion has ended
        p = self.parameters
        cycle = self._rt.cycle_time
        job.settling_for += cycle
        error = abs(self.position - job.target)
        job.settle_time = job.settle_time + cycle if error <= p.target_position_window else 0.0
        at_target = job.settle_time >= p.target_position_monitoring_time - 1e-9
        if p.enable_target_position_monitoring:
            ready = at_target
        elif p.enable_position_range_monitoring:
            ready = error <= p.position_range_window
        else:
            ready = True
        if ready:
            self._finish(job.command)
            self._job = None
            self.state = AxisState.STANDSTILL
            self._start_next(now)
            return False
        if p.enable_in_target_timeout and job.settling_for > p.in_target_timeout:
            self.fault(ErrorId.IN_TARGET_TIMEOUT,
                        f"not in the target window {p.in_target_timeout} s after the profile")
            return False
        return True

    def _release_stop(self, now: float) -> bool:
        hold = self._hold
        if hold is None or hold.hold:
            return hold is not None
        self._hold = None
        if self.state is AxisState.STOPPING:
            self._job = None
            self.state = AxisState.STANDSTILL
        return False

    def _start_next(self, time: float) -> None:
        """Start the first buffered job, exactly where the previous one ended."""
        if not self._queue:
            if self._job is not None and self._job.command.finished:
                self._job = None
                if self.state in (AxisState.DISCRETE_MOTION, AxisState.CONTINUOUS_MOTION) \
                        and not self.has_job and self.set_velocity == 0.0 \
                        and not self._k.superimposed[self.row]:
                    self.state = AxisState.STANDSTILL
            return
        job = self._queue.pop(0)
        time = max(time, self._k.sample_time)  # never rewrite a sample already taken
        previous = self._job
        if previous is not None and previous.kind == "velocity":  # never Done by itself (D-178)
            previous.command.end(CommandStatus.ABORTED, self._rt.now,
                                  message=f"taken over by the buffered {job.command.kind}")
        start = self._k.segments.state(self.row, time)
        job.extra["start"] = start.position
        try:
            try:
                profile = self._plan_base(job, start)
            except CommandRejected:
                if job.end_velocity == 0.0:
                    raise
                job.end_velocity = 0.0  # the blend is not plannable from here: stop at the target
                profile = self._plan_base(job, start)
            jobs.check_soft_limits(self.parameters, profile, job.target)
        except CommandRejected as rejected:
            job.command.end(CommandStatus.ERROR, time, rejected.error_id, rejected.message)
            self._job = None
            self._start_next(time)
            return
        self._start(job, profile, time=time)

    def _finish(self, command: Command) -> None:
        command.end(CommandStatus.DONE, self._rt.now)

    def _reject(self, command: Command, error_id: ErrorId, message: str) -> Command:
        command.end(CommandStatus.ERROR, self._rt.now, error_id, message)
        return command

    def _fail_job(self, job: Job, error_id: ErrorId, message: str) -> None:
        job.command.end(CommandStatus.ERROR, self._rt.now, error_id, message)

    def _abort_all(self, reason: str) -> None:
        now = self._rt.now
        if self._k.superimposed[self.row]:  # MC_Stop and new moves end it too (§3.12)
            self._fold_overlay(CommandStatus.ABORTED, reason)
        if self._job is not None:
            self._job.command.end(CommandStatus.ABORTED, now, message=reason)
            if self._job.kind == "home":
                self.calibration_state = 0
            if self._job.kind == "gear":
                self._job = None
                self._release_coupling()  # the new command starts from the coupled state
            if self._job is not None and self._job.kind == "external":
                start = self._k.state(self.row)  # the new command starts from the fed state
                self._k.set_external(self.row, False)
                p = self.parameters
                jerk = jerk_within_velocity(start, p.jerk, p.max_velocity, p.max_jerk)  # D-177
                self._install(plan_velocity(start, start.velocity, Limits(
                    math.inf, p.max_acceleration, p.max_deceleration, jerk)), has_job=False)
            self._job = None
        for job in self._queue:
            job.command.end(CommandStatus.ABORTED, now, message=reason)
        self._queue.clear()

    def fault(self, error_id: ErrorId, message: str, time: float | None = None) -> None:
        """An axis error: ErrorStop, the commands are aborted, a controlled stop follows.

        The stop is planned from the setpoint at ``time`` (default: the last sample).
        """
        if self.state is AxisState.ERROR_STOP:
            return
        self._abort_all(f"axis error {error_id.name}: {message}")
        self._hold = None
        self.axis_error_id, self.axis_error_message = error_id, message
        self.state = AxisState.ERROR_STOP
        self._k.monitored[self.row] = False
        p = self.parameters
        time = self._k.sample_time if time is None else time
        start = self._k.segments.state(self.row, time)
        self._install(jobs.plan_brake(start, p.max_deceleration, p.max_jerk, p), has_job=False,
                      time=time)

    def _try_reset(self, command: Command, now: float) -> bool:
        if command.finished:
            return False
        if self._k.set_v[self.row] != 0.0 or self._k.segments.end[self.row] > now:
            return True  # the error reaction still brakes: reset once at rest
        self.axis_error_id, self.axis_error_message = ErrorId.NO_ERROR, ""
        self._k.reset_setpoint_to_actual(self.row)
        self._install(Profile.hold(KinematicState(self.position)), has_job=False)
        self._k.monitored[self.row] = self.powered
        self.state = AxisState.STANDSTILL if self.powered else AxisState.DISABLED
        self._finish(command)
        return False

    def shift_coordinates(self, offset: float) -> None:
        """Shift set and actual position, profile and targets by ``offset`` (homing, §4.12)."""
        self._k.shift(self.row, offset)
        self.raw_offset += offset
        for job in ([self._job] if self._job else []) + self._queue:
            if job.target is not None:
                job.target += offset

    # -- internals: override, switches, stop dynamics ------------------------------------------

    def _update_override(self) -> None:
        job = self._job
        direction = self._direction_of(job) if job else 0
        feed = not ((direction > 0 and not self.enable_positive)
                    or (direction < 0 and not self.enable_negative))
        effective = self.override if feed else 0.0
        if effective == self._effective_override:
            return
        was_paused = self._effective_override < jobs.MIN_OVERRIDE
        self._effective_override = effective
        if job is None or job.kind not in ("position", "velocity") or job.command.finished:
            return
        if job.kind == "position" and not self.has_job and not was_paused:
            return  # the profile has ended: the job is settling at its target
        try:
            profile = self._plan(job)
        except CommandRejected as rejected:
            self.fault(rejected.error_id, rejected.message)
            return
        job.command.in_velocity = False
        self._install(profile)

    def _direction_of(self, job: Job) -> int:
        if job.kind == "velocity" and not job.soft_limit_stop:
            return _sign(job.velocity)
        if job.target is not None:
            return _sign(job.target - self.set_position) or _sign(self.set_velocity)
        return _sign(self.set_velocity)

    def _direction_sign(self, direction: Direction) -> int:
        try:
            direction = convert_enum(Direction, direction)
        except ValueError:
            raise CommandRejected(ErrorId.INVALID_DIRECTION,
                                  f"direction {direction!r} is not an MC_Direction") from None
        if direction is Direction.POSITIVE:
            return 1
        if direction is Direction.NEGATIVE:
            return -1
        if direction is Direction.CURRENT:
            return -1 if self.set_velocity < 0.0 else 1
        raise CommandRejected(ErrorId.INVALID_DIRECTION,
                              "MC_MoveVelocity takes positive, negative or current direction")

    def _distance_to_change_speed(self, job: Job, speed: float, direction: int) -> float:
        """Travel the velocity change to ``speed`` needs from the current setpoint state."""
        start = KinematicState(0.0, self.set_velocity * direction,
                               self.set_acceleration * direction)
        return plan_velocity(start, speed, job.limits).end.position

    def _arm_switch(self, command: Command, job: Job, switch_at: float, target: float | None,
                    speed: float | None, reach: bool = False) -> None:
        """Apply the change when the set position passes ``switch_at``; with ``reach``
        (REACH_VELO_AT_POS), early enough that ``speed`` holds there, re-checked every cycle
        from the current state (D-015)."""
        command.status = CommandStatus.ACTIVE
        direction = self._direction_of(job) or 1
        activation = switch_at

        def check(now: float) -> bool:
            if command.finished:
                return False
            if job is not self._job:
                command.end(CommandStatus.ABORTED, now, message="the move ended before the "
                             "switch position")
                return False
            position = self.set_position
            if reach and speed is not None:  # look one cycle ahead: the change starts there
                lead = self._distance_to_change_speed(job, speed, direction)
                position += direction * (lead + abs(self.set_velocity) * self._rt.cycle_time)
            if (position - activation) * direction < 0.0:
                return True
            try:
                self._modify(job, target, speed)
            except CommandRejected as rejected:
                self._reject(command, rejected.error_id, rejected.message)
                return False
            self._finish(command)
            return False

        self.system.watch(self, check)

    def _stop_limits(self, deceleration: InputValue, jerk: InputValue,
                     command: Command) -> Limits:
        p = self.parameters
        job = self._job
        running = job.limits if job is not None and not job.command.finished else None
        base_dec = running.deceleration if running else p.deceleration
        base_jerk = running.jerk if running else p.jerk
        given = not _is_zero(deceleration) and not _is_zero(jerk)
        if not given:
            for name, value in (("deceleration", deceleration), ("jerk", jerk)):
                if not _is_zero(value):  # unused without its partner, but never NaN or text
                    resolve(name, value, p, [])
            if _is_zero(deceleration) != _is_zero(jerk):
                command.warnings.append("MC_Stop takes deceleration and jerk only together; "
                                        "the running move's values are used")
            return Limits(p.max_velocity, base_dec, base_dec, base_jerk)
        dec = resolve("deceleration", deceleration, p, command.warnings)
        j = resolve("jerk", jerk, p, command.warnings)
        return Limits(p.max_velocity, dec, dec, j)

    def _stop_profile(self, limits: Limits) -> Profile:
        """Plan the stop; keep stricter dynamics in the safety cases of TcMC §3.15."""
        start = self._k.state(self.row)
        p = self.parameters
        profile = jobs.plan_brake(start, limits.deceleration, limits.jerk, p)
        stricter = self._stricter_stop_limits(limits)
        if stricter is None:
            return profile
        lo, hi = profile.velocity_extrema()
        direction = _sign(start.velocity) or _sign(start.acceleration)
        unsafe = (direction > 0 and lo < -1e-9) or (direction < 0 and hi > 1e-9)  # reversal
        job = self._job
        unsafe |= job is not None and job.kind == "stop"  # a stricter stop runs already
        if job is not None and job.kind in ("position", "velocity"):
            peak = max(abs(lo), abs(hi))
            unsafe |= peak > job.limits.velocity * (1 + 1e-9) and peak > abs(start.velocity)
            if job.target is not None and job.kind == "position" and direction:
                end = profile.end.position
                unsafe |= (end - job.target) * direction > 1e-9  # would overshoot the target
        if not unsafe:
            return profile
        return jobs.plan_brake(start, stricter.deceleration, stricter.jerk, p)

    def _stricter_stop_limits(self, limits: Limits) -> Limits | None:
        job = self._job
        if job is None or job.command.finished:
            return None
        current = job.limits
        if current.deceleration <= limits.deceleration and current.jerk <= limits.jerk:
            return None
        dec = max(current.deceleration, limits.deceleration)
        return Limits(limits.velocity, dec, dec, max(current.jerk, limits.jerk))

    def _end_position_of(self, job: Job) -> float:
        return job.target if job.target is not None else self.set_position

    def _new(self, kind: str) -> Command:
        return Command(kind, self._rt.now)


def _keep_room_mark(trial: Job, job: Job) -> None:
    """A trial planned beside a superposition marks the job it becomes (D-180)."""
    if trial.extra.get("beside_superposition"):
        job.extra["beside_superposition"] = True


def _way_ahead(kernel: AxisKernel, row: int) -> tuple[float, float]:
    """Lowest and highest set position the installed motion still reaches (infinite in the
    direction of an endless cruise)."""
    way = kernel.segments.remaining(row, kernel.sample_time)
    low, high = way.position_extrema()
    cruise = float(way.v[-1])
    if kernel.superimposed[row]:  # the added motion may go either way: widen by its extent
        extra = kernel.overlay.remaining(row, kernel.sample_time)
        extra_low, extra_high = extra.position_extrema()
        low, high = low + min(extra_low, 0.0), high + max(extra_high, 0.0)
        cruise = cruise or float(extra.v[-1])
    if cruise > 0.0:
        high = math.inf
    elif cruise < 0.0:
        low = -math.inf
    return low, high


def _check_dynamics_change(job: Job, profile: Profile, start: KinematicState) -> None:
    """TcMC §4.20: refuse new dynamics in the manual's four unsafe situations."""
    lo, hi = profile.velocity_extrema()
    direction = _sign(start.velocity) or _sign(job.velocity)
    if job.target is not None:  # a position job at rest (set velocity 0): towards its target
        direction = direction or _sign(job.target - start.position)
    if job.kind == "position" and job.target is not None:
        p_lo, p_hi = profile.position_extrema()
        over = (p_hi - job.target) if direction > 0 else (job.target - p_lo)
        if over > 1e-9 * max(1.0, abs(job.target)):
            raise CommandRejected(ErrorId.DYN_TARGET_OVERSHOT, "the target would be overshot")
    if (direction > 0 and lo < -1e-9) or (direction < 0 and hi > 1e-9):
        raise CommandRejected(ErrorId.DYN_DIRECTION_REVERSAL, "braking would reverse direction")
    peak = max(abs(lo), abs(hi))
    if peak > job.limits.velocity * (1 + 1e-9) and peak > abs(start.velocity) * (1 + 1e-9):
        raise CommandRejected(ErrorId.DYN_VELOCITY_EXCEEDED,
                              "the travel velocity would be exceeded")


#: parameters without a velocity cap: a velocity *difference* is checked, not clamped
_UNBOUNDED = AxisParameters(max_velocity=1e300)


def _gear_ratio(ratio: object) -> float:
    if isinstance(ratio, bool) or not isinstance(ratio, int | float) or not math.isfinite(ratio):
        raise CommandRejected(ErrorId.INVALID_GEAR_RATIO, f"gear ratio {ratio!r} is not finite")
    return float(ratio)


def _parameter_spec(number: int):  # noqa: ANN202 - ParameterSpec
    try:
        return PARAMETERS[AxisPara(number)]
    except ValueError:
        raise CommandRejected(ErrorId.INVALID_PARAMETER_NUMBER,
                              f"parameter number {number} does not exist (TcMC §6.1)") from None


def _buffer_mode(mode: BufferMode) -> BufferMode:
    try:
        return BufferMode(mode)
    except ValueError:
        raise CommandRejected(ErrorId.INVALID_BUFFER_MODE,
                              f"buffer mode {mode!r} is not an MC_BUFFER_MODE") from None


def _is_zero(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and value == 0


def _sign(value: float) -> int:
    return (value > 0.0) - (value < 0.0)
