"""Planning of superimposed motion (TcMC §3.9-3.11, §6.5; digest §1.8).

A superposition adds ``distance`` on top of the running motion within a time budget that
comes from a length: ADDITIVE modes measure ``length`` on the reference (the master or the
workpiece, moving at ``velocity_process``), LIMITED modes on the compensated axis itself, so
the budget is length / v (ADDITIVE) or (length - distance) / v (LIMITED). VELOREDUCTION uses
the whole budget with the smallest velocity change; LENGTHREDUCTION is as fast as the velocity
change allows. What cannot be done in the budget is done as far as possible: the result says
so and the command reports 0x4243 (SUPERPOSITION_INCOMPLETE).

The sum of base and superimposed motion keeps the axis maxima (D-180): the superimposed
motion is planned in the room the rest of the base profile leaves, and a base re-planned
while it runs in the room the rest of the superimposed profile leaves (``room_beside``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.axis.dynamics import require_position, resolve
from openmotion.axis.jobs import sign
from openmotion.axis.parameters import AxisParameters
from openmotion.axis.tolerances import BUDGET_TOLERANCE, ROOM_FLOOR
from openmotion.core.enums import AxisState, SuperpositionMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT, InputValue
from openmotion.trajectory.plan import Limits, plan_in_time, plan_stop, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

BISECTION_STEPS = 40
#: parameters without a velocity cap: a velocity *difference* is checked, not clamped
_UNBOUNDED = AxisParameters(max_velocity=1e300)


@dataclass(frozen=True)
class SuperpositionPlan:
    profile: Profile  #: the superimposed motion, from 0 to ``distance``
    distance: float  #: ActualDistance [mm]
    velocity_diff: float  #: ActualVelocityDiff: peak velocity change used [mm/s]
    length: float  #: ActualLength [mm]
    complete: bool  #: the whole distance fits


def plan_superposition(mode: SuperpositionMode, distance: float, velocity_diff: float,
                       acceleration: float, deceleration: float, jerk: float,
                       velocity_process: float, length: float,
                       base_velocity: float) -> SuperpositionPlan:
    v0 = abs(velocity_process)
    additive = mode in (SuperpositionMode.VELOREDUCTION_ADDITIVEMOTION,
                        SuperpositionMode.LENGTHREDUCTION_ADDITIVEMOTION)
    velo = mode in (SuperpositionMode.VELOREDUCTION_ADDITIVEMOTION,
                    SuperpositionMode.VELOREDUCTION_LIMITEDMOTION)
    def budget_for(d: float) -> float:
        """Time the superposition may take: Length at the process velocity, less (LIMITED)
        what the superimposed distance itself covers of it (§3.9)."""
        return abs(length) / v0 if additive else (abs(length) - d) / v0

    budget = budget_for(distance)
    if budget <= 0.0:
        raise CommandRejected(ErrorId.SUPERPOSITION_INCOMPLETE,
                              f"length {length} leaves no time for distance {distance}")
    dv = abs(velocity_diff)
    if distance < 0.0:  # slowing down cannot go below standstill (§3.11 conveyor example)
        dv = min(dv, abs(base_velocity)) if base_velocity else dv
    limits = Limits(dv, acceleration, deceleration, jerk)
    fastest = plan_in_time(distance, limits, None)
    complete = fastest.duration <= budget * (1 + BUDGET_TOLERANCE)
    if not complete:  # the largest distance that fits the time its own Length leaves
        distance = _reachable(distance, limits, budget_for)
        budget = budget_for(distance)
        fastest = plan_in_time(distance, limits, None)
    profile = plan_in_time(distance, limits, budget) if velo and complete else fastest
    lo, hi = profile.velocity_extrema()
    used = profile.duration
    travelled = v0 * used + (0.0 if additive else distance)
    return SuperpositionPlan(profile, float(profile.end.position), max(abs(lo), abs(hi)),
                             travelled, complete)


def _reachable(distance: float, limits: Limits, budget_for: Callable[[float], float]
               ) -> float:
    """The largest part of ``distance`` whose fastest profile fits the time budget that
    part leaves (LIMITED modes: a shorter distance leaves more of Length)."""
    lo, hi = 0.0, abs(distance)
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        part = math.copysign(mid, distance)
        if mid == 0.0 or plan_in_time(part, limits, None).duration <= budget_for(part):
            lo = mid
        else:
            hi = mid
    return math.copysign(lo, distance)


@dataclass(frozen=True)
class Room:
    """What the axis maxima leave beside the other part of a superimposed motion (D-180)."""

    up: float  #: velocity that may still be added in the positive direction [mm/s]
    down: float  #: velocity that may still be added in the negative direction [mm/s]
    acceleration: float  #: [mm/s²]
    jerk: float  #: [mm/s³]

    def velocity(self, direction: int) -> float:
        return self.up if direction >= 0 else self.down

    def fits(self, parameters: AxisParameters, direction: int) -> bool:
        """Enough room left to plan in at all, moving in ``direction`` (ruckig needs
        positive limits)."""
        return (self.velocity(direction) > ROOM_FLOOR * parameters.max_velocity
                and self.acceleration > ROOM_FLOOR * _max_acceleration(parameters)
                and self.jerk > ROOM_FLOOR * parameters.max_jerk)


def room_beside(parameters: AxisParameters, other: Profile) -> Room:
    """The room the axis maxima leave beside ``other`` for the rest of its course."""
    lo, hi = other.velocity_extrema()
    a = float(np.abs(other.a).max())
    j = float(np.abs(other.j).max())
    v_max = parameters.max_velocity
    return Room(v_max - max(hi, 0.0), v_max + min(lo, 0.0),
                _max_acceleration(parameters) - a, parameters.max_jerk - j)


def _max_acceleration(parameters: AxisParameters) -> float:
    return min(parameters.max_acceleration, parameters.max_deceleration)


class Superposition:
    """The superimposed motion of one axis (MC_MoveSuperImposed, MC_AbortSuperposition): a
    second profile the kernel adds to the base setpoint, planned in the room the base leaves
    within the axis maxima (D-180)."""

    def __init__(self, axis: Axis) -> None:
        self.axis, self.queue = axis, axis.queue
        self.kernel, self.row, self.runtime = axis.kernel, axis.row, axis.runtime
        self.command: Command | None = None  #: the running MC_MoveSuperImposed

    def start(self, distance: InputValue, velocity_diff: InputValue,
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
        command = self.queue.new("move_superimposed")
        try:
            self.axis.admit("modify")
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
            acc = resolve("acceleration", acceleration, self.axis.parameters, w)
            dec = resolve("deceleration", deceleration, self.axis.parameters, w)
            if self.kernel.superimposed[self.row]:
                raise CommandRejected(ErrorId.SUPERPOSITION_ACTIVE,
                                      "a superposition runs already (D-041)")
            room = room_beside(self.axis.parameters, self.base_rest())
            if not room.fits(self.axis.parameters, sign(d)):
                raise CommandRejected(ErrorId.SUPERPOSITION_INCOMPLETE,
                                      "the base motion leaves no room within the axis "
                                      "maxima for a superimposed motion (D-180)")
            jerk = min(self.axis.parameters.jerk, room.jerk)
            plan = plan_superposition(mode, d, min(dv, room.velocity(sign(d))),
                                      min(acc, room.acceleration), min(dec, room.acceleration),
                                      jerk, v0, span, self.axis.set_velocity)
        except CommandRejected as rejected:
            return self.queue.reject(command, rejected.error_id, rejected.message)
        k = self.kernel
        k.set_superimposed(self.row, True)
        k.overlay.install(self.row, plan.profile, k.sample_time)
        command.value = (plan.velocity_diff, plan.distance, plan.length)
        command.status = CommandStatus.ACTIVE
        command.in_velocity = plan.complete
        self.command = command
        return command

    def base_rest(self) -> Profile:
        """The rest of the base motion as planned now: the profile of a free axis; a geared
        or fed axis only knows its present state (its limits are watched every cycle)."""
        k, row = self.kernel, self.row
        if row in k.couplings or k.external[row]:
            return Profile.hold(k.base_state(row))
        return k.segments.remaining(row, k.sample_time)

    def abort(self) -> Command:
        """MC_AbortSuperposition (TcMC §3.12): end the superimposed part; the base continues.

        The superimposed velocity brakes to zero with the axis default deceleration; the
        superposition command shows CommandAborted.
        """
        command = self.queue.new("abort_superposition")
        k = self.kernel
        if self.command is not None and k.superimposed[self.row]:
            state = k.overlay.state(self.row, k.sample_time)
            p = self.axis.parameters
            room = room_beside(p, self.base_rest())  # D-180: the brake keeps the maxima too
            profile = plan_stop(state, max(min(p.deceleration, room.acceleration),
                                           abs(state.acceleration)),
                                max(min(p.jerk, room.jerk), p.jerk * ROOM_FLOOR))
            k.overlay.install(self.row, profile, k.sample_time)
            self.command.end(CommandStatus.ABORTED, self.runtime.now,
                             message="aborted by MC_AbortSuperposition")
            self.command = None
        self.queue.finish(command)
        return command

    def ended(self) -> None:
        """Kernel event: the superimposed motion is complete; fold it into the base."""
        command = self.command
        if command is not None:
            complete = command.in_velocity
            command.in_velocity = False
            if complete:
                self.fold(CommandStatus.DONE, "", ended=True)
            else:
                self.fold(CommandStatus.ERROR, "the distance was compensated only "
                          "partly (TcMC §3.9)", ErrorId.SUPERPOSITION_INCOMPLETE,
                          ended=True)
        else:
            self.fold(CommandStatus.DONE, "", ended=True)

    def fold(self, status: CommandStatus, message: str,
             error_id: ErrorId = ErrorId.NO_ERROR, ended: bool = False) -> None:
        """End the superposition. ``ended``: it reached its end, so its final offset moves
        the base; otherwise the base takes over the combined state for a new plan."""
        k, row = self.kernel, self.row
        if not k.superimposed[row]:
            return
        extra = k.overlay.state(row, k.sample_time)
        if ended or (extra.velocity == 0.0 and extra.acceleration == 0.0):
            offset = k.overlay.end_position(row)
            if row in k.couplings:  # a geared slave keeps the correction in its offset
                k.couplings.shift(row, offset)
            else:
                k.segments.shift(row, offset)  # the base continues, shifted by what was added
            self.queue.shift_targets(offset)
        else:  # still moving: the base takes over the combined state (a new plan follows)
            self.queue.install(self._carry_on(k.state(row)), has_job=False)
        k.set_superimposed(row, False)
        if self.command is not None:
            self.command.end(status, self.runtime.now, error_id, message)
            self.command = None
        if ended:
            self._after()

    def _carry_on(self, state: KinematicState) -> Profile:
        """Go on from ``state`` with its acceleration released at the maximum jerk: the next
        plan starts from the whole state, acceleration included, so nothing jumps."""
        a = state.acceleration
        if a == 0.0:
            return Profile.hold(state)
        p = self.axis.parameters
        cruise = state.velocity + a * abs(a) / (2.0 * p.max_jerk)
        return plan_velocity(state, cruise, Limits(math.inf, max(p.max_acceleration, abs(a)),
                                                   max(p.max_deceleration, abs(a)), p.max_jerk))

    def _after(self) -> None:
        """The superposition has ended: a base planned in the room beside it gets its own
        limits back, and a base that came to rest meanwhile ends now (D-180, D-181)."""
        job = self.queue.active
        if job is None and self.axis.state is AxisState.DISCRETE_MOTION and not self.axis.has_job:
            self.axis.state = AxisState.STANDSTILL  # decoupled at rest beneath it (D-181)
            return
        if job is None or job.command.finished:
            return
        if job.extra.pop("beside_superposition", False) and job.kind in (
                "position", "velocity") and (self.axis.has_job or job.kind == "velocity"):
            try:
                self.queue.install(self.queue.plan(job))
                job.command.in_velocity = False
            except CommandRejected as rejected:
                self.axis.fault(rejected.error_id, rejected.message)
        elif job.kind in ("halt", "stop") and not self.axis.has_job:
            self.queue.end_stop(job)
