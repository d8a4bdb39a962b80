"""Plan the profile of a job from the axis' current setpoint state.

Kept apart from ``Axis`` so that every way a job can (re)start - new command, override
change, blend, MC_NewPos, MC_ChangeDynParam - goes through one function.
"""

from __future__ import annotations

import math

from openmotion.axis.commands import Job
from openmotion.axis.dynamics import require_position
from openmotion.axis.parameters import AxisParameters
from openmotion.axis.tolerances import MIN_OVERRIDE, POSITION_TOLERANCE
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.trajectory.plan import (
    Limits,
    jerk_within_velocity,
    plan_position,
    plan_stop,
    plan_velocity,
)
from openmotion.trajectory.segments import KinematicState, Profile

BLEND_ITERATIONS = 12  #: bisection steps when a blend velocity cannot be reached


def plan_job(job: Job, start: KinematicState, override: float,
             parameters: AxisParameters | None = None) -> Profile:
    """The profile that carries out ``job`` from ``start`` under ``override`` (0..1).

    With ``parameters``, the axis maximum velocity is a hard limit: a command whose jerk is too
    low to release the running acceleration before it is exceeded gets the jerk it needs, up
    to ``max_jerk`` (D-020, D-177).
    """
    profile = _plan_job(job, start, override)  # a command the planner refuses stays refused
    if parameters is None:
        return profile
    jerk = jerk_within_velocity(start, job.limits.jerk, parameters.max_velocity,
                                parameters.max_jerk)
    if jerk == job.limits.jerk:
        return profile
    old = job.limits
    harder = Job(job.kind, job.command, Limits(old.velocity, old.acceleration, old.deceleration,
                                               jerk),
                 job.target, job.velocity, job.buffer_mode, job.end_velocity, job.soft_limit_stop)
    return _plan_job(harder, start, override)


def plan_brake(start: KinematicState, deceleration: float, jerk: float,
               parameters: AxisParameters) -> Profile:
    """Brake to rest from ``start`` (MC_Stop, MC_Halt, error and end-of-mode reactions) within
    the axis maximum velocity: the jerk is raised as ``plan_job`` raises it (D-177)."""
    jerk = jerk_within_velocity(start, jerk, parameters.max_velocity, parameters.max_jerk)
    return plan_stop(start, deceleration, jerk)


def _plan_job(job: Job, start: KinematicState, override: float) -> Profile:
    limits = job.limits
    if job.kind in ("stop", "halt"):
        return plan_stop(start, limits.deceleration, limits.jerk)
    if override < MIN_OVERRIDE:  # TcMC §4.23.1: override 0 halts the profile, the job stays
        return plan_stop(start, limits.deceleration, limits.jerk)
    if job.kind == "velocity" and not job.soft_limit_stop:
        return plan_velocity(start, job.velocity * override, limits)
    assert job.target is not None
    if job.soft_limit_stop and (job.target - start.position) * job.velocity < 0.0:
        raise CommandRejected(ErrorId.PATH_BEYOND_SOFT_LIMIT,
                              f"the axis at {start.position:.6g} lies beyond the software limit "
                              f"{job.target}: it may only move back towards it (D-179)")
    end_velocity = job.end_velocity * override
    limits = limits.scaled_velocity(override)
    if abs(end_velocity) > limits.velocity:  # BlendingNext/High: speed up towards the blend
        limits = Limits(abs(end_velocity), limits.acceleration, limits.deceleration, limits.jerk)
    return plan_position(start, job.target, limits, end_velocity)


def soft_range(parameters: AxisParameters) -> tuple[float, float]:
    """The enabled software end positions (TcMC §6.1, 1015-1018); infinite where disabled."""
    lo = parameters.min_soft_limit if parameters.enable_min_soft_limit else -math.inf
    hi = parameters.max_soft_limit if parameters.enable_max_soft_limit else math.inf
    return lo, hi


def check_soft_limits(parameters: AxisParameters, profile: Profile, target: float | None,
                      start: float | None = None) -> None:
    """Reject targets and paths beyond an enabled software end position (TcMC §6.1, D-016).

    An axis that stands beyond a limit (enabled there, or the limit moved) may move back
    towards the range, never further out: the range is widened to ``start`` (default: where
    ``profile`` starts) (D-179).
    """
    lo_limit, hi_limit = soft_range(parameters)
    if math.isinf(lo_limit) and math.isinf(hi_limit):
        return
    origin = float(profile.p[0]) if start is None else start
    lo_allowed, hi_allowed = min(lo_limit, origin), max(hi_limit, origin)
    if target is not None and not lo_allowed <= target <= hi_allowed:
        raise CommandRejected(
            ErrorId.TARGET_BEYOND_SOFT_LIMIT,
            f"target {target} lies outside the software limits [{lo_limit}, {hi_limit}]",
        )
    lo, hi = profile.position_extrema()
    tolerance = POSITION_TOLERANCE * max(1.0, abs(lo), abs(hi))
    if lo < lo_allowed - tolerance or hi > hi_allowed + tolerance:
        raise CommandRejected(
            ErrorId.PATH_BEYOND_SOFT_LIMIT,
            f"the motion would reach [{lo:.6g}, {hi:.6g}], beyond the software limits "
            f"[{lo_limit}, {hi_limit}]",
        )


def soft_limit_in_direction(parameters: AxisParameters, direction: int) -> float | None:
    """The enabled software limit a velocity move in ``direction`` would run into."""
    if direction > 0 and parameters.enable_max_soft_limit:
        return parameters.max_soft_limit
    if direction < 0 and parameters.enable_min_soft_limit:
        return parameters.min_soft_limit
    return None


def oriented_target(parameters: AxisParameters, position: object) -> float:
    """MC_OrientedStop's Position: a modulo value in [0, period) (TcMC §3.16)."""
    target = require_position("position", position)
    period = parameters.modulo_period
    if not 0.0 <= target < period:
        raise CommandRejected(ErrorId.INVALID_MODULO_TARGET,
                              f"position must lie in [0, {period}), got {target}")
    return target


def blend_velocity(
    start: KinematicState, first: Job, second_target: float, second_limits: Limits, magnitude: float
) -> float:
    """Signed velocity at the first target, lowered until both profiles stay monotonic.

    PLCopen Part 1 blending passes the first target at a velocity set by the buffer mode; a
    velocity that cannot be reached within the first move, or braked within the second, would
    make ruckig overshoot, so it is reduced by bisection.
    """
    assert first.target is not None
    direction = sign(first.target - start.position)
    if direction == 0 or sign(second_target - first.target) != direction or magnitude <= 0.0:
        return 0.0

    def feasible(speed: float) -> bool:
        v = direction * speed
        reach = first.limits
        if speed > reach.velocity:
            reach = Limits(speed, reach.acceleration, reach.deceleration, reach.jerk)
        try:
            a = plan_position(start, first.target, reach, v)
            b = plan_position(KinematicState(first.target, v), second_target, second_limits)
        except CommandRejected:
            return False
        return _monotonic(a, direction) and _monotonic(b, direction)

    speed = magnitude  # PLCopen: the next move brakes or speeds up from there
    if feasible(speed):
        return direction * speed
    lo, hi = 0.0, speed
    for _ in range(BLEND_ITERATIONS):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if feasible(mid) else (lo, mid)
    return direction * lo


def _monotonic(profile: Profile, direction: int) -> bool:
    lo, hi = profile.velocity_extrema()
    tolerance = POSITION_TOLERANCE * max(abs(lo), abs(hi), 1.0)
    return lo >= -tolerance if direction > 0 else hi <= tolerance


def sign(value: float) -> int:
    """-1, 0 or 1 as ``value`` is negative, zero or positive."""
    return (value > 0.0) - (value < 0.0)
