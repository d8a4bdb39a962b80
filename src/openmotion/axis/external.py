"""External setpoint generation for one axis (TcMC §4.16-4.18, D-040): while enabled, the
values fed every cycle are the axis setpoint; a missing feed or a fed value beyond the axis
maxima is an axis error. A collaborator of the axis."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from openmotion.axis.commands import Command, CommandStatus, Job
from openmotion.axis.dynamics import require_position
from openmotion.axis.jobs import plan_brake
from openmotion.axis.tolerances import LIMIT_TOLERANCE
from openmotion.core.enums import AxisState, TargetPositionType
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_INVALID, InputValue
from openmotion.trajectory.plan import Limits, jerk_within_velocity, plan_velocity

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis


class ExternalSetpoints:
    """MC_ExtSetPointGenEnable / Disable / Feed of one axis."""

    def __init__(self, axis: Axis) -> None:
        self.axis, self.queue = axis, axis.queue
        self.kernel, self.row, self.runtime = axis.kernel, axis.row, axis.runtime
        #: the watched target and how it counts (MC_ExtSetPointGenEnable Position, Type)
        self.goal: tuple[float | None, TargetPositionType] = (None, TargetPositionType.ABSOLUTE)
        self.target_reached = False  #: the set position is in the target window (§4.16)
        self.direction = 0  #: the direction of the last fed setpoint (MC_ExtSetPointGenFeed)

    @property
    def enabled(self) -> bool:
        """The external setpoint generator is enabled (MC_ExtSetPointGen* ``Enabled``)."""
        return bool(self.kernel.external[self.row])

    def enable(self, position: InputValue = MC_INVALID,
               position_type: TargetPositionType = TargetPositionType.ABSOLUTE) -> Command:
        """MC_ExtSetPointGenEnable: from now on the fed values are the setpoint (D-040).

        ``position`` is only watched ("in target position"); the axis does not go there by
        itself. A cycle without a feed, or a fed velocity or acceleration beyond the axis
        maxima, is an axis error with a controlled stop.
        """
        command = self.queue.new("ext_setpoint_enable")
        try:
            self.axis.admit("move")
            kind = TargetPositionType(position_type)
            target = None if position is MC_INVALID else require_position("position", position)
            if target is not None and kind is TargetPositionType.RELATIVE:
                target += self.axis.set_position
        except ValueError:
            return self.queue.reject(command, ErrorId.INVALID_MODE,
                                     f"position type {position_type!r} is unknown")
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        if self.enabled:
            self.goal = (target, kind)
            self.queue.finish(command)
            return command
        self.queue.abort_all("aborted by MC_ExtSetPointGenEnable")
        self.queue.hold = None
        self.kernel.set_external(self.row, True)
        p = self.axis.parameters
        job = Job("external", command, Limits(p.max_velocity, p.acceleration, p.deceleration,
                                              p.jerk))
        self.queue.active = job
        self.goal = (target, kind)
        self.target_reached = False
        self.axis.state = AxisState.CONTINUOUS_MOTION
        self.queue.finish(command)  # Done = command issued (§4.16)
        self.queue.active.command = self.queue.new("external_motion")
        self.queue.active.command.status = CommandStatus.ACTIVE
        grace = [True]  # the feed may start in the cycle after the enable
        self.axis.system.watch(self, lambda now: self._cycle(job, grace))
        return command

    def disable(self) -> Command:
        """MC_ExtSetPointGenDisable: ignore fed values; a moving axis brakes to rest."""
        command = self.queue.new("ext_setpoint_disable")
        if self.enabled:
            self.end("disabled by MC_ExtSetPointGenDisable")
        self.queue.finish(command)
        return command

    def feed(self, position: float, velocity: float, acceleration: float,
             direction: int) -> bool:
        """MC_ExtSetPointGenFeed (§4.18): the setpoint of the next motion step; returns False."""
        k, row = self.kernel, self.row
        k.ext_p[row], k.ext_v[row], k.ext_a[row] = position, velocity, acceleration
        k.fed[row] = True
        self.direction = direction
        return False

    def _cycle(self, job: Job, grace: list[bool]) -> bool:
        if job is not self.queue.active or job.command.finished:
            return False
        k, row, p = self.kernel, self.row, self.axis.parameters
        if not k.fed[row] and not grace[0]:
            self.axis.fault(ErrorId.EXT_SETPOINT_MISSING, "no external setpoint fed this cycle")
            return False
        grace[0] = False
        k.fed[row] = False
        v, a = abs(self.axis.set_velocity), abs(self.axis.set_acceleration)
        slack = 1 + LIMIT_TOLERANCE
        if not (math.isfinite(self.axis.set_position) and v <= p.max_velocity * slack
                and a <= max(p.max_acceleration, p.max_deceleration) * slack):
            self.axis.fault(ErrorId.EXT_SETPOINT_LIMIT,
                            f"fed setpoint {v:.6g} mm/s, {a:.6g} mm/s² beyond the axis maxima")
            return False
        target, kind = self.goal
        if target is not None:
            if kind is TargetPositionType.MODULO:
                period = p.modulo_period
                error = abs((self.axis.set_position - target + period / 2) % period - period / 2)
            else:
                error = abs(self.axis.set_position - target)
            self.target_reached = error <= p.target_position_window
        return True

    def end(self, reason: str) -> None:
        """Leave external setpoints: continue from the fed state and brake to rest."""
        k, row = self.kernel, self.row
        start = k.state(row)
        k.set_external(row, False)
        if self.queue.active is not None and self.queue.active.kind == "external":
            self.queue.active.command.end(CommandStatus.DONE, self.runtime.now, message=reason)
            self.queue.active = None
        p = self.axis.parameters
        self.queue.install(plan_brake(start, p.deceleration, p.jerk, p), has_job=False)
        self.axis.state = AxisState.STANDSTILL if start.velocity == 0.0 else self.axis.state
        if start.velocity != 0.0:
            halt = self.queue.new("external_stop")
            job = Job("halt", halt, Limits(p.max_velocity, p.deceleration, p.deceleration,
                                           p.jerk))
            self.queue.active = job
            halt.status = CommandStatus.ACTIVE
            self.kernel.has_job[row] = True
            self.axis.state = AxisState.DISCRETE_MOTION

    def release(self) -> None:
        """A new command takes over: it starts from the fed state, whose acceleration is
        released at a jerk that keeps the maximum velocity (D-177)."""
        k, row = self.kernel, self.row
        start = k.state(row)
        k.set_external(row, False)
        p = self.axis.parameters
        jerk = jerk_within_velocity(start, p.jerk, p.max_velocity, p.max_jerk)  # D-177
        self.queue.install(plan_velocity(start, start.velocity, Limits(
            math.inf, p.max_acceleration, p.max_deceleration, jerk)), has_job=False)
