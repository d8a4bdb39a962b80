"""Moves that turn back with acceleration != deceleration (docs/decisions.md D-201).

PLCopen (TcMC §3.1) bounds |a| by the acceleration while |v| rises and by the deceleration
while it falls. A move whose velocity passes through zero towards its target is planned
through that zero without stopping; it is never slower than the plan with both limits at
min(acc, dec) (which keeps every bound), and it stays within 1 % + 1 cycle of the optimum the
brute-force oracle (openmotion.bench.otg_oracle) finds.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, reject, settings
from hypothesis import strategies as st
from ruckig import RuckigError

from openmotion.bench.otg_oracle import optimal_duration
from openmotion.core.enums import Direction
from openmotion.core.errors import CommandRejected
from openmotion.testing import (
    REL,
    MoveCase,
    SetpointRecorder,
    SetpointTrace,
    assert_within_limits,
    ceil_to_cycle,
    moves,
    ruckig_duration,
    run_single_move,
    single_axis,
    within_limits,
)
from openmotion.trajectory.plan import Limits, jerk_within_velocity, plan_position
from openmotion.trajectory.segments import KinematicState, Profile

CYCLE = 0.001
ORACLE_GRACE = 0.01  #: relative: within 1 % + 1 cycle of the oracle (the bench's goal)
ORACLE_CASES = 24  #: seeded cases against the oracle (each takes it ~0.1 s)

pytestmark = pytest.mark.filterwarnings("ignore:mypy_extensions.TypedDict:DeprecationWarning")


def _lower(limits: Limits) -> Limits:
    low = min(limits.acceleration, limits.deceleration)
    return Limits(limits.velocity, low, low, limits.jerk)


def _back_to_where_it_is(limits: Limits) -> tuple[int, SetpointTrace]:
    """Cycles an axis cruising at its maximum velocity takes when it is commanded back to
    the position it is at (MC_MoveAbsolute) until its setpoint rests there, and the setpoint
    trace of that move (run until the command is Done)."""
    rt, axis = single_axis(limits)
    axis.move_velocity(limits.velocity, Direction.POSITIVE)
    rt.run_until(lambda: axis.set_velocity == limits.velocity and axis.set_acceleration == 0.0,
                 timeout=5.0)
    recorder = SetpointRecorder(rt, axis)
    target = axis.set_position
    command = axis.move_absolute(target, limits.velocity, limits.acceleration,
                                 limits.deceleration, limits.jerk)
    while not command.done:
        assert not command.error, command.message
        rt.step()
    trace = recorder.trace()
    assert trace.reached(target)
    return round(trace.duration / CYCLE), trace


def test_turn_back_at_full_speed_is_no_slower_than_the_lower_limit_alone():
    """The issue's example (D-201): at 10 mm/s, commanded back to where it is, acc 200,
    dec 4000, jerk 500 took 732 cycles as brake-to-rest then move (D-002), against 583 with
    acc = dec = 200. Raising the deceleration may not make the move slower."""
    limits = Limits(10.0, 200.0, 4000.0, 500.0)
    cycles, trace = _back_to_where_it_is(limits)
    lower_cycles, _ = _back_to_where_it_is(_lower(limits))
    assert lower_cycles == 583
    assert cycles <= lower_cycles + 1
    assert_within_limits(trace, limits)
    swapped = Limits(10.0, 4000.0, 200.0, 500.0)  # the strong limit on speeding up instead
    swapped_cycles, trace = _back_to_where_it_is(swapped)
    assert swapped_cycles <= lower_cycles + 1
    assert_within_limits(trace, swapped)


def test_turn_back_gains_from_a_higher_deceleration():
    """With a strong deceleration the turn brakes harder than min(acc, dec) allows and keeps
    the lower acceleration only after the zero crossing (D-201): faster than the lower-limit
    plan (0.2281 s) and than brake-to-rest then move (D-002's plan: 0.2112 s)."""
    limits = Limits(10.0, 100.0, 1000.0, 5000.0)
    start = KinematicState(0.0, 8.0, 0.0)
    turn = plan_position(start, 0.0, limits)
    lower = plan_position(start, 0.0, _lower(limits))
    assert lower.duration == pytest.approx(0.22806, abs=1e-5)
    assert turn.duration < 0.2112 - 0.02
    assert turn.end == KinematicState(0.0, 0.0, 0.0)
    _assert_profile_within(turn, limits)


@given(case=moves())
@example(case=MoveCase(KinematicState(0.0, 10.0, 0.0), 0.0, Limits(10.0, 200.0, 4000.0, 500.0)))
@example(case=MoveCase(KinematicState(0.0, -3.0, 0.0), 5.0, Limits(10.0, 400.0, 200.0, 500.0)))
def test_unequal_limits_are_never_slower_than_the_lower_limit(case):
    """acc != dec: the move reaches its target, keeps the direction-dependent bound at every
    sample (|a| <= dec while |v| falls, <= acc while it rises) and arrives no later than the
    plan with both limits at min(acc, dec) plus one cycle (D-201)."""
    assume(case.limits.acceleration != case.limits.deceleration)
    assume(within_limits(case.start, case.limits))
    try:
        lower = ruckig_duration(replace(case, limits=_lower(case.limits)))
    except RuckigError:
        reject()
    assume(math.isfinite(lower))
    trace = run_single_move(case, CYCLE)
    assert trace.reached(case.target)
    assert_within_limits(trace, case.limits)
    assert trace.duration <= ceil_to_cycle(lower, CYCLE) + CYCLE * (1 + 1e-9)


def test_velocity_reversal_at_full_speed_is_no_slower_than_the_lower_limit():
    """MC_MoveVelocity the other way at full speed, acc 200, dec 4000, jerk 500 (D-203):
    brake-to-rest then speed up took 0.566 s; with acc = dec = 200 it takes 0.4 s, and so
    does the turn through zero."""
    limits = Limits(10.0, 200.0, 4000.0, 500.0)
    rt, axis = single_axis(limits)
    axis.move_velocity(10.0, Direction.POSITIVE)
    rt.run_until(lambda: axis.set_velocity == 10.0 and axis.set_acceleration == 0.0,
                 timeout=5.0)
    recorder = SetpointRecorder(rt, axis)
    command = axis.move_velocity(10.0, Direction.NEGATIVE)
    rt.run_until(lambda: command.in_velocity, timeout=5.0)
    rt.run(0.01)
    trace = recorder.trace()
    assert trace.duration <= 0.4 + 2 * CYCLE
    assert trace.velocity[-1] == -10.0
    assert_within_limits(trace, limits)


@given(case=moves(kind="velocity"))
@example(case=MoveCase(KinematicState(0.0, 10.0, 0.0), -10.0, Limits(10.0, 200.0, 4000.0,
                                                                      500.0), "velocity"))
def test_unequal_limits_velocity_change_is_never_slower_than_the_lower_limit(case):
    """acc != dec, MC_MoveVelocity through zero: within the direction-dependent bound at
    every sample, and no slower than both limits at min(acc, dec) plus one cycle (D-203)."""
    assume(case.limits.acceleration != case.limits.deceleration)
    assume(within_limits(case.start, case.limits))
    try:
        lower = ruckig_duration(replace(case, limits=_lower(case.limits)))
    except RuckigError:
        reject()
    trace = run_single_move(case, CYCLE)
    assert trace.velocity[-1] == case.target
    assert_within_limits(trace, case.limits)
    assert trace.duration <= ceil_to_cycle(lower, CYCLE) + CYCLE * (1 + 1e-9)


def _oracle_cases() -> list[tuple[KinematicState, float, Limits]]:
    """Seeded reversals within the limits: the start heads away from the target, or runs
    towards it too fast to stop; limits 0.1 to 16, acc != dec."""
    rng = np.random.default_rng(20)
    cases: list[tuple[KinematicState, float, Limits]] = []
    while len(cases) < ORACLE_CASES:
        velocity, acceleration, deceleration, jerk = (float(x) for x in rng.uniform(0.1, 16, 4))
        limits = Limits(velocity, acceleration, deceleration, jerk)
        low = min(acceleration, deceleration)
        start = KinematicState(0.0, float(rng.uniform(-velocity, velocity)),
                               float(rng.uniform(-low, low)) * float(rng.integers(0, 2)))
        target = float(rng.normal(0.0, 2.0))
        if not within_limits(start, limits) or start.velocity == 0.0:
            continue
        if start.velocity * target > 0.0 and len(cases) % 2 == 0:
            target = -target  # half of them head away from the target
        cases.append((start, target, limits))
    return cases


@pytest.mark.parametrize("index", range(ORACLE_CASES))
def test_turn_back_is_within_the_oracle(index):
    """Against the brute-force optimum (grid and golden sections over the crossing state,
    ruckig on each side, D-201): within 1 % + 1 cycle, never slower than min(acc, dec), and
    within the direction-dependent bound everywhere on the profile."""
    start, target, limits = _oracle_cases()[index]
    profile = plan_position(start, target, limits)
    optimum = optimal_duration(start, target, limits)
    lower = plan_position(start, target, _lower(limits))
    assert profile.duration <= optimum.duration * (1 + ORACLE_GRACE) + CYCLE
    assert profile.duration <= lower.duration + 1e-9
    assert profile.end.position == target
    _assert_profile_within(profile, limits)


@settings(suppress_health_check=[HealthCheck.filter_too_much])
@given(case=moves(high=False), share=st.floats(0.05, 1.0))
@example(case=MoveCase(  # from the axes benchmark: heading away faster than the new command
    KinematicState(-51.370033467799395, -295.57866262742874, 555.1573983439121),
    152.0394147032689, Limits(295.6, 4894.430324299196, 3823.380719357494,
                              12847.749393019078)), share=223.9305463445349 / 295.6)
def test_turn_back_slower_than_the_start_keeps_the_new_velocity(case, share):
    """A command slower than the axis runs (its velocity a ``share`` of the limits the state
    was drawn in): after the turn through zero |v| stays within the command's velocity,
    the acceleration within the direction-dependent bound (D-201). Releasing the crossing
    acceleration a_c carries the speed on by a_c²/2j, so |a_c| must be small enough."""
    assume(case.limits.acceleration != case.limits.deceleration)
    assume(within_limits(case.start, case.limits))
    heading = np.sign(case.start.velocity) or np.sign(case.start.acceleration)
    assume(heading != 0.0)
    # the target behind the axis, so that it has to turn back
    target = case.start.position - heading * abs(case.target - case.start.position)
    assume(target != case.start.position)
    case = replace(case, target=target)
    lim = case.limits
    command = Limits(lim.velocity * share, lim.acceleration, lim.deceleration, lim.jerk)
    # where releasing the start's acceleration passes the new velocity whatever the plan,
    # the axis raises the jerk first (D-177): not this planner's case
    assume(jerk_within_velocity(case.start, lim.jerk, command.velocity, lim.jerk) == lim.jerk)
    # braking so hard already that releasing it alone carries the axis past the command's
    # velocity the other way (a²/2j > |v| + v_cmd): no plan with this jerk can keep it
    if case.start.acceleration * heading < 0.0:
        assume(case.start.acceleration ** 2 / (2.0 * lim.jerk)
               < (abs(case.start.velocity) + command.velocity) * (1.0 - 1e-6))
    try:
        profile = plan_position(case.start, case.target, command)
    except CommandRejected:
        reject()
    crossing = _first_zero(profile, heading)
    assume(crossing is not None)
    after = Profile.from_data(profile.data[:, crossing:].copy())
    lo, hi = after.velocity_extrema()
    assert max(-lo, hi) <= command.velocity * (1 + REL)
    assert profile.end.position == case.target
    _assert_profile_within(after, command)


def _first_zero(profile: Profile, heading: float) -> int | None:
    """Index of the first segment after the start that begins at or past zero velocity
    (against ``heading``): where the turn has crossed."""
    for k in range(1, len(profile.v)):
        if profile.v[k] * heading <= 0.0:
            return k
    return None


def test_blending_turn_back_keeps_the_bounds():
    """A turn towards a target passed with a velocity (blending) takes the same rule: no
    slower than min(acc, dec), within the direction-dependent bound (D-201)."""
    limits = Limits(10.0, 300.0, 120.0, 900.0)
    start = KinematicState(0.0, 6.0, 50.0)
    profile = plan_position(start, -2.0, limits, -4.0)
    lower = plan_position(start, -2.0, _lower(limits), -4.0)
    assert profile.duration <= lower.duration + 1e-9
    assert (profile.end.position, profile.end.velocity) == (-2.0, -4.0)
    _assert_profile_within(profile, limits)


def _assert_profile_within(profile: Profile, limits: Limits) -> None:
    """Every segment's ends and 50 points inside keep |v| <= velocity, |j| <= jerk and
    |a| <= deceleration while |v| falls (a·v < 0), <= acceleration otherwise."""
    times = np.unique(np.concatenate([
        np.linspace(t0, t1, 52) for t0, t1 in zip(profile.t[:-1], profile.t[1:], strict=True)
    ] + [profile.t]))
    for t in times:
        _, v, a, j = profile.at(float(t))
        bound = limits.deceleration if a * v < 0.0 else limits.acceleration
        assert abs(v) <= limits.velocity * (1 + REL) + 1e-12, (t, v)
        assert abs(a) <= bound * (1 + REL), (t, v, a, bound)
        assert abs(j) <= limits.jerk * (1 + REL), (t, j)
