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

import numpy as np

from openmotion.axis.parameters import AxisParameters
from openmotion.core.enums import SuperpositionMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.trajectory.plan import Limits, plan_in_time
from openmotion.trajectory.segments import Profile

BISECTION_STEPS = 40
ROOM_FLOOR = 1e-6  #: less room than this fraction of a maximum counts as none (D-180)


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
    complete = fastest.duration <= budget * (1 + 1e-12)
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
