"""The jobs of one axis: the running one, the buffered ones behind it and a finished MC_Stop
that still holds the axis; how they start, are re-planned and end (TcMC §3, buffer modes
PLCopen Part 1 §2.4.2).

The axis validates a command and hands its ``Job`` here; the kernel events (a profile ended)
come here through the axis system. Gearing, superposition and external setpoints are the
axis' other collaborators: this queue ends them through their public methods when a new
command takes over.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

from openmotion.axis.commands import Command, CommandStatus, Job
from openmotion.axis.jobs import (
    blend_velocity,
    check_soft_limits,
    plan_job,
    sign,
)
from openmotion.axis.superposition import room_beside
from openmotion.axis.tolerances import LIMIT_TOLERANCE, MIN_OVERRIDE, TIME_TOLERANCE
from openmotion.core.enums import AxisState, BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

MAX_BUFFERED = 16  #: commands an axis queues behind the active one (docs/decisions.md D-008)
BLEND_SPEED = {  #: the blend velocity of each blending buffer mode from (previous, next)
    BufferMode.BLENDING_LOW: min,
    BufferMode.BLENDING_HIGH: max,
    BufferMode.BLENDING_PREVIOUS: lambda previous, _next: previous,
    BufferMode.BLENDING_NEXT: lambda _previous, following: following,
}
_STATE_OF_JOB = {
    "position": AxisState.DISCRETE_MOTION, "halt": AxisState.DISCRETE_MOTION,
    "velocity": AxisState.CONTINUOUS_MOTION, "stop": AxisState.STOPPING,
}


class JobQueue:
    """The running job of an axis and the ones buffered behind it (at most MAX_BUFFERED)."""

    def __init__(self, axis: Axis) -> None:
        self.axis = axis
        self.kernel, self.row, self.runtime = axis.kernel, axis.row, axis.runtime
        self.active: Job | None = None  #: the job that runs (or has just finished)
        self.buffered: list[Job] = []  #: the jobs waiting behind it, in order
        self.hold: Command | None = None  #: a finished MC_Stop that still holds the axis
        #: the override that applies (0 while the feed enable of the direction is off)
        self.override = 1.0

    def jobs(self) -> list[Job]:
        """The running job (if any) and the buffered ones."""
        return ([self.active] if self.active else []) + self.buffered

    def shift_targets(self, offset: float) -> None:
        """Move every target by ``offset`` (shifted coordinates, a folded superposition)."""
        for job in self.jobs():
            if job.target is not None:
                job.target += offset

    def new(self, kind: str) -> Command:
        """A command issued now."""
        return Command(kind, self.runtime.now)

    def finish(self, command: Command) -> None:
        """``command`` is Done now."""
        command.end(CommandStatus.DONE, self.runtime.now)

    def reject(self, command: Command, error_id: ErrorId, message: str) -> Command:
        """``command`` ends now with an error; returned for the caller to hand back."""
        command.end(CommandStatus.ERROR, self.runtime.now, error_id, message)
        return command

    def fail(self, job: Job, error_id: ErrorId, message: str) -> None:
        """``job``'s command ends now with an error (the job itself stays)."""
        job.command.end(CommandStatus.ERROR, self.runtime.now, error_id, message)

    def install(self, profile: Profile, has_job: bool = True, time: float | None = None) -> None:
        """The setpoint follows ``profile`` from ``time`` (default: the last sample);
        ``has_job``: the kernel reports the profile's end as an event."""
        k = self.kernel
        k.segments.install(self.row, profile, k.sample_time if time is None else time)
        k.has_job[self.row] = has_job

    def submit(self, job: Job) -> None:
        """Start ``job`` now (Aborting, or nothing running) or queue it behind the others."""
        current = self.active
        if (job.buffer_mode is not BufferMode.ABORTING and current is not None
                and current.kind == "velocity" and current.command.in_velocity
                and not self.buffered):  # PLCopen: buffered behind MoveVelocity starts InVelocity
            if job.target is None and "target_of" in job.extra:
                job.target = job.extra["target_of"](self.axis.set_position)
            self.buffered.append(job)
            self.start_next(self.kernel.sample_time)
            return
        if job.buffer_mode is BufferMode.ABORTING or current is None or self.idle():
            if job.target is None and "target_of" in job.extra:
                job.target = job.extra["target_of"](self.axis.set_position)
            profile = self.plan(job, whole=True)  # it ends the superposition (D-041)
            check_soft_limits(self.axis.parameters, profile, job.target)
            self.abort_all(f"aborted by {job.command.kind}")
            self.hold = None
            self.start(job, profile)
            return
        if len(self.buffered) >= MAX_BUFFERED:
            raise CommandRejected(ErrorId.BUFFER_FULL, f"{MAX_BUFFERED} commands already queued")
        previous = self.buffered[-1] if self.buffered else current
        if job.target is None and "target_of" in job.extra:
            job.target = job.extra["target_of"](self._end_position_of(previous))
        self.buffered.append(job)
        job.command.status = CommandStatus.BUFFERED
        if job.buffer_mode in BLEND_SPEED and previous.kind == "position" and \
                job.kind == "position" and previous.target is not None:
            self._blend(previous, job)

    def _blend(self, previous: Job, following: Job) -> None:
        assert following.target is not None
        magnitude = BLEND_SPEED[following.buffer_mode](previous.limits.velocity,
                                                       following.limits.velocity)
        running = previous is self.active and self.axis.has_job
        if running:
            start = self.kernel.base_state(self.row)
        elif previous is self.active:
            start = KinematicState(self.axis.set_position)
        else:  # queued: it will start where the job before it ends
            before = self.buffered[-3] if len(self.buffered) >= 3 else self.active
            start = KinematicState(self._end_position_of(before), before.end_velocity)
        previous.end_velocity = blend_velocity(start, previous, following.target,
                                               following.limits, magnitude)
        if running and previous.end_velocity != 0.0:
            self.install(self.plan(previous))

    def idle(self) -> bool:
        """Nothing runs: a finished hold or halt at rest counts as idle."""
        job = self.active
        return job is None or (job.command.finished and not self.axis.has_job)

    def plan(self, job: Job, whole: bool = False) -> Profile:
        """Plan ``job`` from the last sample. ``whole``: from the whole setpoint, for a command
        that ends a running superposition; otherwise from the base motion, which the
        superposition keeps riding on (D-180)."""
        k = self.kernel
        start = k.state(self.row) if whole else k.base_state(self.row)
        job.extra["start"] = start.position
        if whole:
            return plan_job(job, start, self.override, self.axis.parameters)
        return self.plan_base(job, start)

    def plan_base(self, job: Job, start: KinematicState) -> Profile:
        """Plan the base motion; beside a running superposition only in the room its rest
        leaves (D-180), or, where there is none, after folding it into the base."""
        k, p, override = self.kernel, self.axis.parameters, self.override
        if not k.superimposed[self.row]:
            return plan_job(job, start, override, p)
        room = room_beside(p, k.overlay.remaining(self.row, k.sample_time))
        direction = sign(job.velocity) if job.kind == "velocity" else (
            sign((job.target if job.target is not None else start.position) - start.position)
            or sign(start.velocity))
        if not room.fits(p, direction):
            self.axis.superposition.fold(CommandStatus.ABORTED, "the base motion was re-planned "
                                         "where the axis limits leave no room beside the "
                                         "superposition")
            return plan_job(job, k.state(self.row), override, p)
        cap = room.velocity(direction) / max(override, MIN_OVERRIDE)
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
        return plan_job(trial, start, override, caps)

    def start(self, job: Job, profile: Profile, time: float | None = None) -> None:
        self.active = job
        job.command.status = CommandStatus.ACTIVE
        self.install(profile, time=time)
        self.axis.state = _STATE_OF_JOB[job.kind]
        if job.soft_limit_stop:  # a MoveVelocity that will stop at a software limit
            self.axis.state = AxisState.CONTINUOUS_MOTION
            self.axis.system.watch(self, lambda now: self._cruise_check(job))

    def _cruise_check(self, job: Job) -> bool:
        """InVelocity for a velocity job planned as a stop at a software limit (D-016)."""
        if job is not self.active or job.command.finished or not job.soft_limit_stop:
            return False
        commanded = job.velocity * self.override
        k, row = self.kernel, self.row
        job.command.in_velocity = bool(
            k.set_a[row] == 0.0
            and abs(k.set_v[row] - commanded) <= LIMIT_TOLERANCE * abs(commanded)
        )
        return True

    def modify(self, job: Job, target: float | None, speed: float | None) -> None:
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
        profile = self.plan(trial)
        check_soft_limits(self.axis.parameters, profile, trial.target)
        job.kind, job.limits, job.target, job.velocity = (trial.kind, trial.limits, trial.target,
                                                          trial.velocity)
        job.soft_limit_stop, job.settle_time, job.settling_for = trial.soft_limit_stop, 0.0, 0.0
        keep_room_mark(trial, job)
        job.command.in_velocity = False
        self.install(profile)
        if job.kind == "position" and self.axis.state is AxisState.CONTINUOUS_MOTION:
            self.axis.state = AxisState.DISCRETE_MOTION

    def profile_ended(self, end_time: float) -> None:
        """Kernel event: the setpoint reached the end state of the job's profile."""
        self.kernel.has_job[self.row] = False
        job = self.active
        if job is None or self.override < MIN_OVERRIDE and job.kind in (
                "position", "velocity"):
            return  # override 0 paused the job; it resumes when the override returns
        if job.kind == "velocity":
            job.command.in_velocity = True
            self.start_next(end_time)
        elif job.kind == "position":
            if job.soft_limit_stop:
                self.axis.fault(ErrorId.SOFT_LIMIT_REACHED,
                                f"stopped at the software limit {job.target}",
                                time=end_time)
            elif self.buffered and self.buffered[0].buffer_mode in BLEND_SPEED:
                self.finish(job.command)
                self.start_next(end_time)
            elif not job.extra.get("settling"):
                job.extra["settling"] = True
                self.axis.system.watch(self, _Settle(self, job))
        elif job.kind in ("halt", "stop") and not self.kernel.superimposed[self.row]:
            self.end_stop(job)
        # a halt whose base came to rest under a superposition ends with it (D-181)

    def end_stop(self, job: Job) -> None:
        """A halt or stop has brought the axis to rest."""
        self.finish(job.command)
        if job.kind == "stop" and job.command.hold:
            self.hold = job.command
            self.axis.system.watch(self, self._release_stop)
        else:
            self.active = None
            self.axis.state = AxisState.STANDSTILL
            self.start_next(self.kernel.sample_time)

    def _settle(self, job: Job, now: float) -> bool:
        """TcMC §7.1: Done once the monitors enabled by 1022/1024 agree; False = stop watching."""
        if job is not self.active or job.command.finished:
            return False
        if self.axis.has_job or self.kernel.superimposed[self.row]:
            # re-planned (override, MC_NewPos) or still superimposed (D-181): settle after
            # the motion has ended
            job.settle_time = job.settling_for = 0.0
            return True
        p = self.axis.parameters
        cycle = self.runtime.cycle_time
        job.settling_for += cycle
        error = abs(self.axis.position - job.target)
        job.settle_time = job.settle_time + cycle if error <= p.target_position_window else 0.0
        at_target = job.settle_time >= p.target_position_monitoring_time - TIME_TOLERANCE
        if p.enable_target_position_monitoring:
            ready = at_target
        elif p.enable_position_range_monitoring:
            ready = error <= p.position_range_window
        else:
            ready = True
        if ready:
            self.finish(job.command)
            self.active = None
            self.axis.state = AxisState.STANDSTILL
            self.start_next(now)
            return False
        if p.enable_in_target_timeout and job.settling_for > p.in_target_timeout:
            self.axis.fault(ErrorId.IN_TARGET_TIMEOUT,
                            f"not in the target window {p.in_target_timeout} s after the profile")
            return False
        return True

    def _release_stop(self, now: float) -> bool:
        hold = self.hold
        if hold is None or hold.hold:
            return hold is not None
        self.hold = None
        if self.axis.state is AxisState.STOPPING:
            self.active = None
            self.axis.state = AxisState.STANDSTILL
        return False

    def start_next(self, time: float) -> None:
        """Start the first buffered job, exactly where the previous one ended."""
        if not self.buffered:
            if self.active is not None and self.active.command.finished:
                self.active = None
                if self.axis.state in (AxisState.DISCRETE_MOTION, AxisState.CONTINUOUS_MOTION) \
                        and not self.axis.has_job and self.axis.set_velocity == 0.0 \
                        and not self.kernel.superimposed[self.row]:
                    self.axis.state = AxisState.STANDSTILL
            return
        job = self.buffered.pop(0)
        time = max(time, self.kernel.sample_time)  # never rewrite a sample already taken
        previous = self.active
        if previous is not None and previous.kind == "velocity":  # never Done by itself (D-178)
            previous.command.end(CommandStatus.ABORTED, self.runtime.now,
                                 message=f"taken over by the buffered {job.command.kind}")
        start = self.kernel.segments.state(self.row, time)
        job.extra["start"] = start.position
        try:
            try:
                profile = self.plan_base(job, start)
            except CommandRejected:
                if job.end_velocity == 0.0:
                    raise
                job.end_velocity = 0.0  # the blend is not plannable from here: stop at the target
                profile = self.plan_base(job, start)
            check_soft_limits(self.axis.parameters, profile, job.target)
        except CommandRejected as rejected:
            job.command.end(CommandStatus.ERROR, time, rejected.error_id, rejected.message)
            self.active = None
            self.start_next(time)
            return
        self.start(job, profile, time=time)

    def abort_all(self, reason: str) -> None:
        now = self.runtime.now
        if self.kernel.superimposed[self.row]:  # MC_Stop and new moves end it too (§3.12)
            self.axis.superposition.fold(CommandStatus.ABORTED, reason)
        if self.active is not None:
            self.active.command.end(CommandStatus.ABORTED, now, message=reason)
            if self.active.kind == "home":
                self.axis.calibration_state = 0
            if self.active.kind == "gear":
                self.active = None
                self.axis.gearing.release()  # the new command starts from the coupled state
            if self.active is not None and self.active.kind == "external":
                self.axis.external.release()  # the new command starts from the fed state
            self.active = None
        for job in self.buffered:
            job.command.end(CommandStatus.ABORTED, now, message=reason)
        self.buffered.clear()

    def _end_position_of(self, job: Job) -> float:
        return job.target if job.target is not None else self.axis.set_position

    def direction_of(self, job: Job) -> int:
        if job.kind == "velocity" and not job.soft_limit_stop:
            return sign(job.velocity)
        if job.target is not None:
            return sign(job.target - self.axis.set_position) or sign(self.axis.set_velocity)
        return sign(self.axis.set_velocity)



class _Settle:
    """The watcher of a position job's Done window (``JobQueue._settle``), which also knows
    how long it stays quiet: while the axis rests, its drives ideal, the error to the target
    is a constant, so the cycle in which it becomes Done (or times out) is known ahead, and
    the cycles before it only add up the times (``skip``), bit for bit as they would."""

    def __init__(self, queue: JobQueue, job: Job) -> None:
        self.queue, self.job = queue, job

    def __call__(self, now: float) -> bool:
        return self.queue._settle(self.job, now)

    def _resting_error(self) -> float | None:
        """The constant error to the target, or None where it may change from cycle to cycle
        (or the watcher may end by another way than its own check)."""
        queue, job = self.queue, self.job
        k, row = queue.kernel, queue.row
        if job is not queue.active or job.command.finished or k.has_job[row] \
                or k.superimposed[row] or not k.quiet or k.set_v[row] != 0.0 \
                or k.set_a[row] != 0.0 or job.target is None:
            return None
        return abs(queue.axis.position - job.target)

    def quiet_until(self) -> float:
        """The time of the first cycle to come whose look ends the watcher: -inf when that
        is not known (the next cycle looks), +inf when none ever will."""
        error = self._resting_error()
        if error is None:
            return -math.inf
        p, cycle = self.queue.axis.parameters, self.queue.runtime.cycle_time
        if p.enable_target_position_monitoring and error <= p.target_position_window:
            limit = p.target_position_monitoring_time - TIME_TOLERANCE
        elif p.enable_target_position_monitoring or (
                p.enable_position_range_monitoring and error > p.position_range_window):
            limit = math.inf  # never ready while it rests there: only a timeout ends it
        else:
            return -math.inf  # ready at the next look
        settle_time, settling_for = self.job.settle_time, self.job.settling_for
        timeout = p.in_target_timeout if p.enable_in_target_timeout else math.inf
        if limit == math.inf and timeout == math.inf:
            return math.inf
        looks = 0
        while looks < _SETTLE_LOOKAHEAD:
            looks += 1
            settling_for += cycle
            settle_time = settle_time + cycle if limit != math.inf else 0.0
            if settle_time >= limit or settling_for > timeout:
                return (self.queue.runtime.cycle + looks) * cycle  # the runtime's clock
        return -math.inf  # too far to count ahead: looked at each cycle as before

    def skip(self, cycles: int) -> None:
        """``cycles`` quiet cycles passed without a look (all before ``quiet_until``): add up
        the times as each look would have."""
        error = self._resting_error()
        if error is None:
            return
        p, cycle, job = self.queue.axis.parameters, self.queue.runtime.cycle_time, self.job
        inside = error <= p.target_position_window
        for _ in range(cycles):
            job.settling_for += cycle
            job.settle_time = job.settle_time + cycle if inside else 0.0


_SETTLE_LOOKAHEAD = 100_000  #: cycles a Done window counts ahead to find its end


def keep_room_mark(trial: Job, job: Job) -> None:
    """A trial planned beside a superposition marks the job it becomes (D-180)."""
    if trial.extra.get("beside_superposition"):
        job.extra["beside_superposition"] = True
