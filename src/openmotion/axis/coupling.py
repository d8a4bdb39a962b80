"""One axis as a geared slave (TcMC §3.17-3.21): coupling, a dynamic ratio that slews every
cycle, decoupling with or without a follow-up motion, and the reaction when a geared sample
would pass the slave's maxima (D-182). The couplings themselves are kernel arrays
(gearing.py); this collaborator of the axis runs the commands around them."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from openmotion.axis.commands import Command, CommandStatus, Job
from openmotion.axis.dynamics import require_position, resolve, resolve_limits
from openmotion.axis.jobs import check_soft_limits, oriented_target
from openmotion.axis.tolerances import MIN_SPEED
from openmotion.core.enums import AxisState, DecoupleMode, Direction
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID, InputValue
from openmotion.trajectory.plan import Limits, jerk_within_velocity, plan_stop, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis


class GearCoupling:
    """The coupling of one slave axis to its master (MC_GearIn*, MC_GearOut*)."""

    def __init__(self, axis: Axis) -> None:
        self.axis, self.queue = axis, axis.queue
        self.kernel, self.row, self.runtime = axis.kernel, axis.row, axis.runtime

    def slaves(self) -> list[Axis]:
        """The axes geared to this one."""
        couplings = self.kernel.couplings
        rows = set(couplings.slaves[couplings.masters == self.row].tolist())
        return [axis for axis in self.runtime.axes.values() if axis.row in rows]

    def gear_in(self, master: Axis, ratio: float, acceleration: InputValue | None = None
                ) -> Command:
        """MC_GearIn / MC_GearInFloat / MC_GearInDyn: couple this slave to ``master``.

        Only at standstill (TcMC §3.17): the slave in StandStill and the master at rest. With
        ``acceleration`` (MC_GearInDyn) later ratio changes slew at most at
        ``acceleration / master max_velocity`` per second (§3.19).
        """
        command = self.queue.new("gear_in")
        try:
            if master is self.axis or not isinstance(master, type(self.axis)):
                raise CommandRejected(ErrorId.INVALID_MODE, "the master must be another axis")
            self.axis.admit("move")
            if self.axis.state is not AxisState.STANDSTILL:
                raise CommandRejected(ErrorId.AXIS_NOT_STANDSTILL,
                                      "coupling only at standstill (TcMC §3.17)")
            if master.set_velocity != 0.0 or master.set_acceleration != 0.0:
                raise CommandRejected(ErrorId.AXIS_NOT_STANDSTILL,
                                      "the master moves: coupling only at standstill")
            if self.row in self.kernel.couplings.masters_of(master.row):
                raise CommandRejected(ErrorId.COUPLING_LOOP,
                                      f"{master.name} follows {self.axis.name} already (D-191)")
            ratio = _gear_ratio(ratio)
            rate = math.inf
            if acceleration is not None:
                dyn = resolve("acceleration", acceleration, self.axis.parameters, command.warnings)
                rate = dyn / master.parameters.max_velocity
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        self.queue.abort_all("aborted by MC_GearIn")
        self.queue.hold = None
        self.kernel.couplings.couple(self.row, master.row, ratio, master.set_position,
                                     self.axis.set_position)
        p = self.axis.parameters
        job = Job("gear", command, Limits(p.max_velocity, p.acceleration, p.deceleration, p.jerk))
        job.extra.update(master=master, target_ratio=ratio, ratio_rate=rate)
        self.queue.active = job
        command.status = CommandStatus.ACTIVE
        self.axis.state = AxisState.SYNCHRONIZED_MOTION
        self.axis.system.watch(self, lambda now: self._cycle(job))
        return command

    def dynamic_coupling(self, master: Axis) -> Command | None:
        """The running coupling of this slave to ``master``, if there is one: a new edge of
        MC_GearInDyn takes it over instead of coupling again (TcMC §3.19, D-196)."""
        job = self.queue.active
        if job is None or job.kind != "gear" or job.command.finished \
                or job.extra.get("master") is not master:
            return None
        return job.command

    def set_acceleration(self, acceleration: InputValue) -> Command:
        """MC_GearInDyn's Acceleration for the running coupling: the ratio slews at most at
        ``acceleration / master max_velocity`` per second (§3.19)."""
        command = self.queue.new("gear_acceleration")
        job = self.queue.active
        try:
            if job is None or job.kind != "gear":
                raise CommandRejected(ErrorId.NOT_COUPLED, "the axis is not a geared slave")
            dyn = resolve("acceleration", acceleration, self.axis.parameters, command.warnings)
            job.extra["ratio_rate"] = dyn / job.extra["master"].parameters.max_velocity
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        self.queue.finish(command)
        return command

    def set_ratio(self, ratio: float) -> Command:
        """A new target ratio for a dynamic coupling (MC_GearInDyn, re-read every cycle)."""
        command = self.queue.new("gear_ratio")
        job = self.queue.active
        try:
            if job is None or job.kind != "gear":
                raise CommandRejected(ErrorId.NOT_COUPLED, "the axis is not a geared slave")
            job.extra["target_ratio"] = _gear_ratio(ratio)
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        self.queue.finish(command)
        return command

    def gear_out(self) -> Command:
        """MC_GearOut (TcMC §3.20): decouple; a moving slave releases its acceleration and
        cruises at constant velocity until another command, like after MC_MoveVelocity."""
        command = self.queue.new("gear_out")
        job = self.queue.active
        if job is None or job.kind != "gear":
            return self.queue.reject(command, ErrorId.NOT_COUPLED, "the axis is not a geared slave")
        job.command.end(CommandStatus.ABORTED, self.runtime.now, message="decoupled by MC_GearOut")
        self.queue.active = None
        self.release()
        self.queue.finish(command)
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
            command = self.queue.new("gear_out_ext")
            return self.queue.reject(command, ErrorId.INVALID_MODE, f"mode {mode!r} is unknown")
        moving = self.axis.set_velocity != 0.0 or self.axis.set_acceleration != 0.0
        speed = abs(self.axis.set_velocity)
        if mode is DecoupleMode.ENDLESS:
            velocity = speed or MC_INVALID
        elif mode is DecoupleMode.NEW_POSITION:
            velocity = max(speed, MIN_SPEED)
        if moving and self.queue.active is not None and self.queue.active.kind == "gear":
            try:  # a rejected command leaves the slave coupled
                self._check_follow_up(mode, position, velocity, acceleration, deceleration, jerk)
            except CommandRejected as rejected:
                return self.queue.reject(self.queue.new("gear_out_ext"), rejected.error_id,
                                         rejected.message)
        out = self.gear_out()
        if out.error or not moving:
            return out
        direction = Direction.NEGATIVE if self.axis.set_velocity < 0.0 else Direction.POSITIVE
        if mode is DecoupleMode.STOP:
            return self.axis.stop(deceleration, jerk)
        if mode is DecoupleMode.ORIENTED_STOP:
            return self.axis.oriented_stop(position)
        if mode in (DecoupleMode.ENDLESS, DecoupleMode.ENDLESS_NEW_VELOCITY):
            return self.axis.move_velocity(velocity, direction, acceleration, deceleration, jerk)
        if mode in (DecoupleMode.NEW_POSITION, DecoupleMode.NEW_POSITION_AND_VELOCITY):
            return self.axis.move_absolute(position, velocity, acceleration, deceleration, jerk)
        halt = self.queue.new("instantaneous_stop")  # the velocity jumps to zero (§3.21)
        self.queue.install(Profile.hold(KinematicState(self.axis.set_position)), has_job=False)
        self.queue.active = None
        self.axis.state = AxisState.STANDSTILL
        self.queue.finish(halt)
        return halt

    def _check_follow_up(self, mode: DecoupleMode, position: InputValue, velocity: InputValue,
                         acceleration: InputValue, deceleration: InputValue,
                         jerk: InputValue) -> None:
        """MC_GearOutExt: reject the follow-up's inputs before decoupling, in the order its
        command checks them (MC_Stop always stops; the instantaneous stop takes none)."""
        if mode is DecoupleMode.ORIENTED_STOP:
            oriented_target(self.axis.parameters, position)
        elif mode not in (DecoupleMode.STOP, DecoupleMode.INSTANTANEOUS_STOP):
            resolve_limits(self.axis.parameters, [], velocity, acceleration, deceleration, jerk)
        if mode in (DecoupleMode.NEW_POSITION, DecoupleMode.NEW_POSITION_AND_VELOCITY):
            target = require_position("position", position)
            check_soft_limits(self.axis.parameters, Profile.hold(KinematicState(target)), target,
                              start=self.axis.set_position)

    def _cycle(self, job: Job) -> bool:
        """Per cycle while coupled: slew a dynamic ratio, watch the slave's limits."""
        if job is not self.queue.active or job.command.finished:
            return False
        couplings, master = self.kernel.couplings, job.extra["master"]
        ratio, target = couplings.ratio_of(self.row), job.extra["target_ratio"]
        if ratio != target:
            cycle = self.runtime.cycle_time
            step = min(abs(target - ratio), job.extra["ratio_rate"] * cycle)
            new = target if step == abs(target - ratio) else ratio + math.copysign(step,
                                                                                   target - ratio)
            couplings.set_ratio(self.row, new, master.set_position, (new - ratio) / cycle)
        elif couplings.ratio_rate[couplings.slaves == self.row].any():
            couplings.set_ratio(self.row, ratio, master.set_position, 0.0)
        return True  # the kernel watches the slave's limits in every sample (D-182)

    def limit_fault(self) -> None:
        """Kernel event: this slave's new sample would pass its maximum velocity,
        acceleration or jerk (or brake beyond its maximum velocity). ErrorStop, decoupled,
        braking with the maximum deceleration and jerk from the previous sample, the last
        one within the limits, so that no sample beyond them is ever output (D-182)."""
        v, a, j = self.axis.set_velocity, self.axis.set_acceleration, self.axis.set_jerk
        time, start = self.kernel.previous_sample(self.row)
        self.axis.fault(ErrorId.GEAR_LIMIT_EXCEEDED,
                        f"the geared slave would reach {v:.6g} mm/s, {a:.6g} mm/s², {j:.6g} mm/s³ "
                        "beyond its maxima")
        p = self.axis.parameters
        self.queue.install(plan_stop(start, p.max_deceleration, p.max_jerk), has_job=False,
                           time=time)

    def release(self) -> None:
        """Decouple: continue from the coupled state, releasing the acceleration (§3.20)."""
        k = self.kernel
        if self.row not in k.couplings:
            return
        start = k.base_state(self.row)  # a superposition keeps riding on top (D-180)
        k.couplings.decouple(self.row)
        p = self.axis.parameters
        jerk = jerk_within_velocity(start, p.jerk, p.max_velocity, p.max_jerk)  # D-177
        cruise = start.velocity + start.acceleration * abs(start.acceleration) / (2.0 * jerk)
        profile = plan_velocity(start, cruise, Limits(p.max_velocity, p.max_acceleration,
                                                      p.max_deceleration, jerk))
        self.queue.install(profile, has_job=False)
        if cruise != 0.0:  # keeps moving like after MC_MoveVelocity
            p = self.axis.parameters
            motion = self.queue.new("decoupled")
            job = Job("velocity", motion, Limits(abs(cruise), p.acceleration, p.deceleration,
                                                 p.jerk), velocity=cruise)
            self.queue.active = job
            motion.status = CommandStatus.ACTIVE
            motion.in_velocity = profile.duration == 0.0
            self.kernel.has_job[self.row] = profile.duration > 0.0
            self.axis.state = AxisState.CONTINUOUS_MOTION
        elif k.superimposed[self.row]:  # the superposition still moves it (D-181)
            self.axis.state = AxisState.DISCRETE_MOTION
        else:
            self.axis.state = AxisState.STANDSTILL


def _gear_ratio(ratio: object) -> float:
    if isinstance(ratio, bool) or not isinstance(ratio, int | float) or not math.isfinite(ratio):
        raise CommandRejected(ErrorId.INVALID_GEAR_RATIO, f"gear ratio {ratio!r} is not finite")
    return float(ratio)
