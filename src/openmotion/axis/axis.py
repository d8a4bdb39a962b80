"""The axis: a thin view onto kernel row ``row``, plus its commands and PLCopen state.

Every way of moving an axis - FB, Python call, scenario line - ends in one of the public
methods here and gets a ``Command`` back. Bad input and wrong state never raise: the command
comes back with ``error`` set (architecture: "an FB never raises during a cycle").
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, ClassVar

from openmotion.axis import jobs
from openmotion.axis.commands import Command, CommandStatus, Job
from openmotion.axis.coupling import GearCoupling
from openmotion.axis.drive import DriveModel
from openmotion.axis.dynamics import require_position, resolve, resolve_limits
from openmotion.axis.external import ExternalSetpoints
from openmotion.axis.homing import HomingSequence
from openmotion.axis.kind import AXIS
from openmotion.axis.parameters import PARAMETERS, AxisPara, AxisParameters
from openmotion.axis.queue import JobQueue, keep_room_mark
from openmotion.axis.state_machine import admit
from openmotion.axis.superposition import Superposition
from openmotion.axis.tolerances import (
    LIMIT_TOLERANCE,
    MIN_OVERRIDE,
    MIN_SPEED,
    POSITION_TOLERANCE,
    VELOCITY_TOLERANCE,
)
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
from openmotion.core.override import dword_from_fraction, fraction_from_percent
from openmotion.core.special_values import (
    DEFAULT_HOME_POSITION,
    MC_DEFAULT,
    MC_INVALID,
    InputValue,
)
from openmotion.trajectory.plan import Limits, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.kernel import AxisKernel
    from openmotion.axis.system import AxisSystem
    from openmotion.kernel.model import Kind

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
        self.runtime = system.runtime  #: the runtime the axis runs in (now, cycle_time)
        self.kernel = system.kernel  #: the axes' kernel arrays; this axis is row ``row``
        self.state = AxisState.DISABLED
        self.axis_error_id = ErrorId.NO_ERROR  #: the axis error behind ErrorStop
        self.axis_error_message = ""
        self.homed = False
        self.powered = False
        self.drive_ready = True  #: set False to simulate a drive that is not ready
        self.enable_positive = True  #: feed enable, positive direction (TcMC §4.1)
        self.enable_negative = True
        self.override = 1.0  #: velocity override, a fraction 0...1 (core/override.py)
        self.calibration_state = 0  #: homing phase (TcMC §3.14 nCalibrationState)
        self.cam_input: bool | None = None  #: MC_Home.bCalibrationCam, None = simulated cam
        self.raw_offset = 0.0  #: shift between displayed and machine coordinates [mm]
        self.queue = JobQueue(self)  #: the running job, the buffered ones, a holding stop
        self.gearing = GearCoupling(self)  #: this axis as a geared slave (TcMC §3.17-3.21)
        self.superposition = Superposition(self)  #: the superimposed motion (TcMC §3.9-3.12)
        self.external = ExternalSetpoints(self)  #: fed setpoints (TcMC §4.16-4.18)
        self.group: object | None = None  #: the CA group the axis is a member of
        self.apply_parameters()

    # -- reading -----------------------------------------------------------------------------

    @property
    def position(self) -> float:
        """Actual position [mm] (encoder)."""
        return float(self.kernel.act_p[self.row])

    @property
    def velocity(self) -> float:
        """Actual velocity [mm/s]."""
        return float(self.kernel.act_v[self.row])

    @property
    def set_position(self) -> float:
        """Setpoint position [mm] (TcMC fPosSoll); all positioning refers to it (§3.5)."""
        return float(self.kernel.set_p[self.row])

    @property
    def set_velocity(self) -> float:
        return float(self.kernel.set_v[self.row])

    @property
    def set_acceleration(self) -> float:
        return float(self.kernel.set_a[self.row])

    @property
    def set_jerk(self) -> float:
        return float(self.kernel.set_j[self.row])

    @property
    def following_error(self) -> float:
        """Set minus actual position [mm]."""
        return float(self.kernel.set_p[self.row] - self.kernel.act_p[self.row])

    @property
    def has_job(self) -> bool:
        """The setpoint generator still works on a job (TcMC §7.1 AxisHasJob)."""
        return bool(self.kernel.has_job[self.row])

    @property
    def override_value(self) -> int:
        """The override as the PlcToNc interface DWORD (TcMC §4.1): 0...1 000 000 for
        0...100 %, so MC_Power's Override 50.0 gives 500 000."""
        return dword_from_fraction(self.override)

    @property
    def error(self) -> bool:
        return self.state is AxisState.ERROR_STOP

    @property
    def target_position(self) -> float:
        job = self.queue.active
        if job is not None and job.target is not None:
            return job.target
        return self.set_position

    @property
    def remaining_time(self) -> float:
        if not self.has_job:
            return 0.0
        return max(float(self.kernel.segments.end[self.row]) - self.kernel.sample_time, 0.0)

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
        return self.queue.active.command if self.queue.active else None

    def __repr__(self) -> str:
        return f"<Axis {self.name} {self.state.name} at {self.set_position:.6g}>"

    # -- parameters --------------------------------------------------------------------------

    def apply_parameters(self) -> None:
        """Copy monitoring parameters into the kernel arrays (after any write)."""
        p, k, row = self.parameters, self.kernel, self.row
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
        k, row, p = self.kernel, self.row, self.parameters
        lo, hi = jobs.soft_range(p)
        if (math.isinf(lo) and math.isinf(hi)) or not self.powered or row in k.couplings \
                or k.external[row] or self.state in (AxisState.ERROR_STOP, AxisState.HOMING):
            return  # geared and fed setpoints follow their source; homing takes none (§3.14)
        start = k.state(row)
        low, high = _way_ahead(k, row)
        job = self.queue.active
        if job is not None and not job.command.finished:  # a paused job resumes on its way
            if job.kind == "velocity" and not job.soft_limit_stop:
                low, high = (low, math.inf) if job.velocity > 0.0 else (-math.inf, high)
            elif job.kind == "position" and job.target is not None:
                low, high = min(low, job.target), max(high, job.target)
        tolerance = POSITION_TOLERANCE * max(1.0, abs(lo) if math.isfinite(lo) else 1.0,
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
        direction = jobs.sign(limit - start.position)
        hardest = Limits(max(job.limits.velocity, abs(start.velocity)), p.max_acceleration,
                         p.max_deceleration, p.max_jerk)
        for limits in (job.limits, hardest):
            trial = Job("position", job.command, limits, target=limit,
                        velocity=direction * limits.velocity, soft_limit_stop=True)
            try:
                profile = self.queue.plan(trial)
                jobs.check_soft_limits(p, profile, limit)
            except CommandRejected:
                continue
            job.kind, job.target, job.limits = "position", limit, limits
            job.velocity, job.end_velocity, job.soft_limit_stop = trial.velocity, 0.0, True
            job.command.in_velocity = False
            self.queue.install(profile)
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
            self.kernel.reset_setpoint_to_actual(self.row)
            self.queue.install(Profile.hold(KinematicState(self.position)), has_job=False)
            self.kernel.monitored[self.row] = self.state is not AxisState.ERROR_STOP
            if self.state is AxisState.DISABLED:
                self.state = AxisState.STANDSTILL
        elif not status and self.powered:
            self.powered = False
            for slave in self.gearing.slaves():  # they must not follow the frozen setpoint (D-199)
                slave.fault(ErrorId.MASTER_DISABLED,
                            f"its master {self.name} was disabled while coupled")
            self.queue.abort_all("the axis was disabled")
            self.kernel.reset_setpoint_to_actual(self.row)
            self.queue.install(Profile.hold(KinematicState(self.position)), has_job=False)
            self.kernel.monitored[self.row] = False
            self.queue.hold = None
            if self.state is not AxisState.ERROR_STOP:
                self.state = AxisState.DISABLED
        member_power = getattr(self.group, "member_power_changed", None)  # CA groups
        if member_power is not None and self.powered != was_powered:
            member_power(self)  # a moving CA mover stays on its brake (D-183)
        self._update_override()
        return status

    def reset(self) -> Command:
        """MC_Reset: leave ErrorStop once the error reaction has stopped the axis."""
        command = self.queue.new("reset")
        if self.state is not AxisState.ERROR_STOP:
            self.queue.finish(command)
            return command
        command.status = CommandStatus.ACTIVE
        self.system.watch(self, lambda now: self._try_reset(command, now))
        return command

    def set_override(self, percent: float) -> Command:
        """MC_SetOverride: velocity override in percent, 0-100, applied without a jump."""
        command = self.queue.new("override")
        if isinstance(percent, bool) or not isinstance(percent, int | float) or not (
            math.isfinite(percent) and 0.0 <= percent <= 100.0
        ):
            return self.queue.reject(command, ErrorId.INVALID_OVERRIDE,
                                     f"override must be within 0..100 %, got {percent!r}")
        self.override = fraction_from_percent(percent)
        self._update_override()
        self.queue.finish(command)
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
        command = self.queue.new("move_velocity")
        try:
            self.admit("move")
            mode = _buffer_mode(buffer_mode)
            limits = resolve_limits(self.parameters, command.warnings, velocity, acceleration,
                                    deceleration, jerk)
            sign = self._direction_sign(direction)
            job = Job("velocity", command, limits, velocity=sign * limits.velocity,
                      buffer_mode=mode)
            limit = jobs.soft_limit_in_direction(self.parameters, sign)
            if limit is not None:  # stop exactly at the limit instead of running past it
                job.kind, job.target, job.soft_limit_stop = "position", limit, True
            self.queue.submit(job)
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        return command

    def halt(self, deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT,
             buffer_mode: BufferMode = BufferMode.ABORTING) -> Command:
        """MC_Halt (PLCopen Part 1): a stop that other commands may abort."""
        command = self.queue.new("halt")
        try:
            self.admit("move")
            dec = resolve("deceleration", deceleration, self.parameters, command.warnings)
            j = resolve("jerk", jerk, self.parameters, command.warnings)
            limits = Limits(self.parameters.max_velocity, dec, dec, j)
            self.queue.submit(Job("halt", command, limits, buffer_mode=_buffer_mode(buffer_mode)))
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        return command

    def stop(self, deceleration: InputValue = 0.0, jerk: InputValue = 0.0,
             hold: bool = False) -> Command:
        """MC_Stop (TcMC §3.15): brake to rest; with ``hold`` the axis stays in Stopping.

        0 keeps the running move's deceleration and jerk; a non-zero value is taken only with a
        non-zero partner. Softer values than the running ones apply unless one of the manual's
        four safety cases holds, where the stricter values are kept without an error.
        """
        command = self.queue.new("stop")
        try:
            self.admit("stop")
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        bad: CommandRejected | None = None
        try:
            limits = self._stop_limits(deceleration, jerk, command)
        except CommandRejected as rejected:  # a stop always stops (D-023)
            bad, limits = rejected, self._stop_limits(0.0, 0.0, command)
        command.hold = hold
        profile = self._stop_profile(limits)  # needs the running job for the safety cases
        self.queue.abort_all("aborted by MC_Stop")
        self.queue.hold = None
        self.queue.start(Job("stop", command, limits), profile)
        if bad is not None:
            self.queue.reject(command, bad.error_id, bad.message + "; stopped with the running "
                              "move's dynamics")
        return command

    def home(self, position: InputValue = DEFAULT_HOME_POSITION) -> Command:
        """MC_Home (TcMC §3.14): reference the axis with the configured reference mode."""
        command = self.queue.new("home")
        try:
            self.admit("home")
            home = (self.parameters.calibration_value if position is DEFAULT_HOME_POSITION
                    else require_position("position", position))
            sequence = HomingSequence(self, home)
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        self.queue.abort_all("aborted by MC_Home")
        limits = Limits(self.parameters.max_velocity, self.parameters.acceleration,
                        self.parameters.deceleration, self.parameters.jerk)
        job = Job("home", command, limits)
        job.extra["sequence"] = sequence
        self.queue.active = job
        command.status = CommandStatus.ACTIVE
        self.state = AxisState.HOMING
        self.system.watch(self, lambda now: sequence.step(now))
        return command

    def set_actual_position(self, position: InputValue) -> Command:
        """MC_SetActualPosition (TcMC §4.12): shift the coordinates so actual = position."""
        command = self.queue.new("set_position")
        try:
            self.admit("set_position")
            if self.has_job or self.set_velocity != 0.0:
                raise CommandRejected(ErrorId.AXIS_NOT_STANDSTILL, "the axis is still moving")
            self.shift_coordinates(require_position("position", position) - self.position)
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        self.queue.finish(command)
        return command

    def set_actual_position_on_the_fly(self, actual_position: InputValue,
                                       previous_position: InputValue) -> Command:
        """MC_SetActualPositionOnTheFly (TcMC §4.13): shift the coordinates of a moving axis.

        Set position, actual position and the running move's target all move by
        ``actual_position - previous_position``: the move covers the same distance and ends
        at its old target plus that shift.
        """
        command = self.queue.new("set_position_on_the_fly")
        try:
            if self.state in (AxisState.DISABLED, AxisState.ERROR_STOP, AxisState.HOMING):
                self.admit("move")
            offset = require_position("actual_position", actual_position) - require_position(
                "previous_position", previous_position)
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        self.shift_coordinates(offset)
        self.queue.finish(command)
        return command

    def oriented_stop(self, position: InputValue) -> Command:
        """MC_OrientedStop (TcMC §3.16): stop at the next reachable modulo ``position``.

        Braking uses the running move's deceleration and jerk; the stop point is the first
        position with the requested modulo value not before the normal stopping point, so the
        travel may be up to one modulo period longer. Where that is impossible (a stop runs
        already, a software limit lies before it) the axis stops normally and the command
        reports the error.
        """
        command = self.queue.new("oriented_stop")
        period = self.parameters.modulo_period
        try:
            self.admit("stop")
            target = jobs.oriented_target(self.parameters, position)
            if self.state in (AxisState.STANDSTILL, AxisState.HOMING):
                raise CommandRejected(ErrorId.AXIS_NOT_MOVING, "oriented stop needs motion")
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        limits = self._stop_limits(0.0, 0.0, command)
        start = self.kernel.state(self.row)
        normal = jobs.plan_brake(start, limits.deceleration, limits.jerk, self.parameters)
        failure: CommandRejected | None = None
        profile = normal
        if self.state is AxisState.STOPPING:
            failure = CommandRejected(ErrorId.AXIS_STOPPING, "a stop runs already")
        else:
            direction = jobs.sign(start.velocity) or jobs.sign(start.acceleration) or 1
            end = normal.end.position
            offset = (target - end % period) % period if direction > 0 else \
                -((end % period - target) % period)
            goal = snap_to_period(end + offset, target, period)
            speed = Limits(max(abs(start.velocity), MIN_SPEED), limits.acceleration,
                           limits.deceleration, limits.jerk)
            try:
                profile = jobs.plan_job(Job("position", command, speed, target=goal), start,
                                        1.0, self.parameters)
                jobs.check_soft_limits(self.parameters, profile, goal)
            except CommandRejected as rejected:
                failure, profile = rejected, normal
        self.queue.abort_all("aborted by MC_OrientedStop")
        self.queue.hold = None
        self.queue.start(Job("stop", command, limits), profile)
        if failure is not None:
            self.queue.reject(command, failure.error_id,
                              failure.message + "; stopped without orientation")
        return command

    # -- gearing, superposition, external setpoints: their collaborators do the work ---------

    def gear_in(self, master: Axis, ratio: float, acceleration: InputValue | None = None
                ) -> Command:
        """MC_GearIn / MC_GearInFloat / MC_GearInDyn (TcMC §3.17-3.19)."""
        return self.gearing.gear_in(master, ratio, acceleration)

    def dynamic_coupling(self, master: Axis) -> Command | None:
        """The running coupling of this slave to ``master`` (MC_GearInDyn, D-196)."""
        return self.gearing.dynamic_coupling(master)

    def set_gear_acceleration(self, acceleration: InputValue) -> Command:
        """MC_GearInDyn's Acceleration for the running coupling (§3.19)."""
        return self.gearing.set_acceleration(acceleration)

    def set_gear_ratio(self, ratio: float) -> Command:
        """A new target ratio for a dynamic coupling (MC_GearInDyn)."""
        return self.gearing.set_ratio(ratio)

    def gear_out(self) -> Command:
        """MC_GearOut (TcMC §3.20)."""
        return self.gearing.gear_out()

    def gear_out_ext(self, mode: DecoupleMode, position: InputValue = MC_INVALID,
                     velocity: InputValue = MC_INVALID, acceleration: InputValue = MC_DEFAULT,
                     deceleration: InputValue = MC_DEFAULT, jerk: InputValue = MC_DEFAULT
                     ) -> Command:
        """MC_GearOutExt (TcMC §3.21): decouple, then the follow-up ``mode`` if moving."""
        return self.gearing.gear_out_ext(mode, position, velocity, acceleration, deceleration,
                                         jerk)

    def move_superimposed(self, distance: InputValue, velocity_diff: InputValue,
                          velocity_process: InputValue, length: InputValue,
                          mode: SuperpositionMode = SuperpositionMode.LENGTHREDUCTION_LIMITEDMOTION,
                          acceleration: InputValue = MC_DEFAULT,
                          deceleration: InputValue = MC_DEFAULT) -> Command:
        """MC_MoveSuperImposed(Ext) (TcMC §3.9-3.11): add ``distance`` on top of the motion."""
        return self.superposition.start(distance, velocity_diff, velocity_process, length, mode,
                                        acceleration, deceleration)

    def abort_superposition(self) -> Command:
        """MC_AbortSuperposition (TcMC §3.12): end the superimposed part; the base continues."""
        return self.superposition.abort()

    @property
    def external_setpoints(self) -> bool:
        """The external setpoint generator is enabled (MC_ExtSetPointGen* ``Enabled``)."""
        return self.external.enabled

    @property
    def in_external_target(self) -> bool:
        """The set position reached the external generator's target (§4.16)."""
        return bool(self.external.target_reached)

    def enable_external_setpoints(self, position: InputValue = MC_INVALID,
                                  position_type: TargetPositionType = TargetPositionType.ABSOLUTE
                                  ) -> Command:
        """MC_ExtSetPointGenEnable (TcMC §4.16, D-040)."""
        return self.external.enable(position, position_type)

    def disable_external_setpoints(self) -> Command:
        """MC_ExtSetPointGenDisable (TcMC §4.17)."""
        return self.external.disable()

    def feed_setpoint(self, position: float, velocity: float, acceleration: float,
                      direction: int) -> bool:
        """MC_ExtSetPointGenFeed (TcMC §4.18): the setpoint of the next motion step."""
        return self.external.feed(position, velocity, acceleration, direction)

    def new_position(self, position: InputValue) -> Command:
        """MC_NewPos (TcMC §3.7): a new target for the running move; Done = accepted."""
        return self.new_position_and_velocity(NewPosAndVeloMode.CHANGE_POS, position, 0.0)

    def new_position_and_velocity(self, mode: NewPosAndVeloMode, position: InputValue,
                                  velocity: InputValue,
                                  activation_position: float = 0.0) -> Command:
        """MC_NewPosAndVelo (TcMC §3.8): change target and/or velocity, now or at a position."""
        command = self.queue.new("new_position")
        try:
            self.admit("modify")
            job = self.queue.active
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
            return self.queue.reject(command, rejected.error_id, rejected.message)
        if not switch:
            try:
                self.queue.modify(job, target, speed)
            except CommandRejected as rejected:
                return self.queue.reject(command, rejected.error_id, rejected.message)
            self.queue.finish(command)
            return command
        reach = mode is NewPosAndVeloMode.REACH_VELO_AT_POS and speed is not None
        self._arm_switch(command, job, float(activation_position), target, speed, reach)
        return command

    def change_dynamics(self, acceleration: InputValue = MC_DEFAULT,
                        deceleration: InputValue = MC_DEFAULT,
                        jerk: InputValue = MC_DEFAULT) -> Command:
        """MC_ChangeDynParam (TcMC §4.20): new acc/dec/jerk for the running move."""
        command = self.queue.new("change_dynamics")
        try:
            if self.state is AxisState.STOPPING:
                raise CommandRejected(ErrorId.DYN_STRICTER_STOP_ACTIVE,
                                      "a stop with its own dynamics is in progress")
            self.admit("modify")
            job = self.queue.active
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
            _check_dynamics_change(job, profile, self.kernel.base_state(self.row))
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        job.limits = limits
        keep_room_mark(trial, job)
        self.queue.install(profile)
        self.queue.finish(command)
        return command

    def _plan_dynamics_change(self, trial: Job) -> Profile:
        """A planner failure under the new dynamics is TcMC §4.20's "internal optimisation
        not possible" (D-050)."""
        try:
            return self.queue.plan(trial)
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
        job = self.queue.active
        if job is None or job.command is not command or job.kind != "position":
            return False
        try:
            target = require_position("position", position)
            speed = resolve("velocity", velocity, self.parameters, command.warnings)
            self.queue.modify(job, target, speed)
        except CommandRejected as rejected:
            self.queue.fail(job, rejected.error_id, rejected.message)
        return True

    # -- internals: starting, replacing and ending jobs ---------------------------------------

    def admit(self, family: str) -> None:
        """PLCopen state check; a group member only moves through its group (TF5410; Part 4
        §3.2 option 1). A Part 4 group decides for its members (``AxesGroup.admit_member``:
        MC_Stop and MC_Home pass and make it GroupMoving, §3.2)."""
        if self.group is not None:
            admit_member = getattr(self.group, "admit_member", None)
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
        command = self.queue.new(kind)
        try:
            self.admit("move")
            mode = _buffer_mode(buffer_mode)
            limits = resolve_limits(self.parameters, command.warnings, velocity, acceleration,
                                    deceleration, jerk)
            job = Job("position", command, limits, buffer_mode=mode)
            job.extra["target_of"] = target_of
            self.queue.submit(job)
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        return command

    def fault(self, error_id: ErrorId, message: str, time: float | None = None) -> None:
        """An axis error: ErrorStop, the commands are aborted, a controlled stop follows.

        The stop is planned from the setpoint at ``time`` (default: the last sample).
        """
        if self.state is AxisState.ERROR_STOP:
            return
        self.queue.abort_all(f"axis error {error_id.name}: {message}")
        self.queue.hold = None
        self.axis_error_id, self.axis_error_message = error_id, message
        self.state = AxisState.ERROR_STOP
        self.kernel.monitored[self.row] = False
        p = self.parameters
        time = self.kernel.sample_time if time is None else time
        start = self.kernel.segments.state(self.row, time)
        self.queue.install(jobs.plan_brake(start, p.max_deceleration, p.max_jerk, p), has_job=False,
                           time=time)

    def _try_reset(self, command: Command, now: float) -> bool:
        if command.finished:
            return False
        if self.kernel.set_v[self.row] != 0.0 or self.kernel.segments.end[self.row] > now:
            return True  # the error reaction still brakes: reset once at rest
        self.axis_error_id, self.axis_error_message = ErrorId.NO_ERROR, ""
        self.kernel.reset_setpoint_to_actual(self.row)
        self.queue.install(Profile.hold(KinematicState(self.position)), has_job=False)
        self.kernel.monitored[self.row] = self.powered
        self.state = AxisState.STANDSTILL if self.powered else AxisState.DISABLED
        self.queue.finish(command)
        return False

    def shift_coordinates(self, offset: float) -> None:
        """Shift set and actual position, profile and targets by ``offset`` (homing, §4.12)."""
        self.kernel.shift(self.row, offset)
        self.raw_offset += offset
        self.queue.shift_targets(offset)

    # -- internals: override, switches, stop dynamics ------------------------------------------

    def _update_override(self) -> None:
        job = self.queue.active
        direction = self.queue.direction_of(job) if job else 0
        feed = not ((direction > 0 and not self.enable_positive)
                    or (direction < 0 and not self.enable_negative))
        effective = self.override if feed else 0.0
        if effective == self.queue.override:
            return
        was_paused = self.queue.override < MIN_OVERRIDE
        self.queue.override = effective
        if job is None or job.kind not in ("position", "velocity") or job.command.finished:
            return
        if job.kind == "position" and not self.has_job and not was_paused:
            return  # the profile has ended: the job is settling at its target
        try:
            profile = self.queue.plan(job)
        except CommandRejected as rejected:
            self.fault(rejected.error_id, rejected.message)
            return
        job.command.in_velocity = False
        self.queue.install(profile)

    def _direction_sign(self, direction: Direction) -> int:
        if direction is Direction.POSITIVE:  # the common cases first
            return 1
        if direction is Direction.NEGATIVE:
            return -1
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
        direction = self.queue.direction_of(job) or 1
        activation = switch_at

        def check(now: float) -> bool:
            if command.finished:
                return False
            if job is not self.queue.active:
                command.end(CommandStatus.ABORTED, now, message="the move ended before the "
                            "switch position")
                return False
            position = self.set_position
            if reach and speed is not None:  # look one cycle ahead: the change starts there
                lead = self._distance_to_change_speed(job, speed, direction)
                position += direction * (lead + abs(self.set_velocity) * self.runtime.cycle_time)
            if (position - activation) * direction < 0.0:
                return True
            try:
                self.queue.modify(job, target, speed)
            except CommandRejected as rejected:
                self.queue.reject(command, rejected.error_id, rejected.message)
                return False
            self.queue.finish(command)
            return False

        self.system.watch(self, check)

    def _stop_limits(self, deceleration: InputValue, jerk: InputValue,
                     command: Command) -> Limits:
        p = self.parameters
        job = self.queue.active
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
        start = self.kernel.state(self.row)
        p = self.parameters
        profile = jobs.plan_brake(start, limits.deceleration, limits.jerk, p)
        stricter = self._stricter_stop_limits(limits)
        if stricter is None:
            return profile
        lo, hi = profile.velocity_extrema()
        direction = jobs.sign(start.velocity) or jobs.sign(start.acceleration)
        unsafe = (direction > 0 and lo < -VELOCITY_TOLERANCE) or (
            direction < 0 and hi > VELOCITY_TOLERANCE)  # reversal
        job = self.queue.active
        unsafe |= job is not None and job.kind == "stop"  # a stricter stop runs already
        if job is not None and job.kind in ("position", "velocity"):
            peak = max(abs(lo), abs(hi))
            unsafe |= peak > job.limits.velocity * (1 + LIMIT_TOLERANCE) \
                and peak > abs(start.velocity)
            if job.target is not None and job.kind == "position" and direction:
                end = profile.end.position
                # would overshoot the target
                unsafe |= (end - job.target) * direction > POSITION_TOLERANCE
        if not unsafe:
            return profile
        return jobs.plan_brake(start, stricter.deceleration, stricter.jerk, p)

    def _stricter_stop_limits(self, limits: Limits) -> Limits | None:
        job = self.queue.active
        if job is None or job.command.finished:
            return None
        current = job.limits
        if current.deceleration <= limits.deceleration and current.jerk <= limits.jerk:
            return None
        dec = max(current.deceleration, limits.deceleration)
        return Limits(limits.velocity, dec, dec, max(current.jerk, limits.jerk))


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
    direction = jobs.sign(start.velocity) or jobs.sign(job.velocity)
    if job.target is not None:  # a position job at rest (set velocity 0): towards its target
        direction = direction or jobs.sign(job.target - start.position)
    if job.kind == "position" and job.target is not None:
        p_lo, p_hi = profile.position_extrema()
        over = (p_hi - job.target) if direction > 0 else (job.target - p_lo)
        if over > POSITION_TOLERANCE * max(1.0, abs(job.target)):
            raise CommandRejected(ErrorId.DYN_TARGET_OVERSHOT, "the target would be overshot")
    if (direction > 0 and lo < -VELOCITY_TOLERANCE) or (
            direction < 0 and hi > VELOCITY_TOLERANCE):
        raise CommandRejected(ErrorId.DYN_DIRECTION_REVERSAL, "braking would reverse direction")
    peak = max(abs(lo), abs(hi))
    slack = 1 + LIMIT_TOLERANCE
    if peak > job.limits.velocity * slack and peak > abs(start.velocity) * slack:
        raise CommandRejected(ErrorId.DYN_VELOCITY_EXCEEDED,
                              "the travel velocity would be exceeded")


def _parameter_spec(number: int):  # noqa: ANN202 - ParameterSpec
    try:
        return PARAMETERS[AxisPara(number)]
    except ValueError:
        raise CommandRejected(ErrorId.INVALID_PARAMETER_NUMBER,
                              f"parameter number {number} does not exist (TcMC §6.1)") from None


def _buffer_mode(mode: BufferMode) -> BufferMode:
    if type(mode) is BufferMode:
        return mode
    try:
        return BufferMode(mode)
    except ValueError:
        raise CommandRejected(ErrorId.INVALID_BUFFER_MODE,
                              f"buffer mode {mode!r} is not an MC_BUFFER_MODE") from None


def _is_zero(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and value == 0
