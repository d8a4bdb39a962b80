"""The planner's cheaper paths give the profiles the plain construction gives, bit for bit
(D-323): a velocity change through zero with acceleration != deceleration builds only the
fastest of its candidates, timed first from their phases; ruckig's phases are flattened
with floats instead of a compiled pass over an array; the FB inputs take a fast path for
plain floats. The references below are the plain constructions, kept here."""

from __future__ import annotations

import numpy as np
import pytest

import openmotion as om
from openmotion.trajectory import plan
from openmotion.trajectory.plan import Limits, plan_position, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

CASES = 300  #: seeded random states per test


def _reference_turn_velocity(start: KinematicState, velocity: float, limits: Limits,
                             heading: int) -> Profile:
    """Every candidate built in full, the fastest chosen (ties: the first in the list)."""
    low = min(limits.acceleration, limits.deceleration)
    jerk = limits.jerk
    speed = max(start.velocity * heading, 0.0)
    push = start.acceleration * heading
    top = min(low, np.sqrt(2.0 * jerk * speed + push * push),
              np.sqrt(2.0 * jerk * min(abs(velocity), limits.velocity))) \
        * (1.0 - plan._CROSSING_MARGIN)
    bottom = np.sqrt(max(push * push - 2.0 * jerk * speed, 0.0)) if push < 0.0 else 0.0
    candidates = [plan._velocity_profile(start, velocity, Limits(limits.velocity, low, low, jerk))]
    brake = plan.plan_velocity(start, 0.0, limits)
    candidates.append(Profile.concatenate(
        brake, plan._velocity_profile(KinematicState(brake.end.position), velocity, limits)))
    if bottom <= top:
        turn = plan._braked_to_crossing(start, float(top), heading, limits)
        if turn is not None:
            crossing = KinematicState(float(turn.p[-1]), 0.0, -heading * float(top))
            onward = plan._velocity_profile(crossing, velocity, limits)
            if not plan._reverses(onward, -heading):
                candidates.insert(0, Profile.concatenate(turn, onward))
    return min(candidates, key=lambda c: c.duration)


def _reference_flatten(profile) -> Profile:  # noqa: ANN001 - ruckig.Profile
    """ruckig's brake and main phases as one array, empty phases dropped, with numpy."""
    brake = profile.brake
    t, j, p, v, a = profile.t, profile.j, profile.p[:7], profile.v[:7], profile.a[:7]
    if brake.duration > 0.0:
        t, j, p, v, a = brake.t + t, brake.j + j, brake.p + p, brake.v + v, brake.a + a
    raw = np.array((t, j, p, v, a))
    kept = raw[:, raw[0] > plan._MIN_SEGMENT]
    n = kept.shape[1]
    out = np.zeros((5, n + 1))
    total = 0.0
    for k in range(n):
        out[1:, k] = kept[2, k], kept[3, k], kept[4, k], kept[1, k]
        out[0, k] = total
        total += kept[0, k]
    out[0, n] = total
    if n:
        dt = out[0, n] - out[0, n - 1]
        p0, v0, a0, j0 = out[1:, n - 1]
        out[1, n] = p0 + dt * (v0 + dt * (a0 / 2.0 + dt * j0 / 6.0))
        out[2, n] = v0 + dt * (a0 + dt * j0 / 2.0)
    else:
        out[1, 0], out[2, 0] = raw[2, 0], raw[3, 0]
    return Profile.from_data(out)


def _random_state(rng: np.random.Generator, limits: Limits) -> KinematicState:
    return KinematicState(float(rng.uniform(-100.0, 100.0)),
                          float(rng.uniform(-1.2, 1.2) * limits.velocity),
                          float(rng.uniform(-1.0, 1.0) * min(limits.acceleration,
                                                             limits.deceleration)))


def _random_limits(rng: np.random.Generator) -> Limits:
    return Limits(float(rng.uniform(50.0, 500.0)), float(rng.uniform(500.0, 5000.0)),
                  float(rng.uniform(500.0, 5000.0)), float(rng.uniform(5000.0, 50000.0)))


@pytest.mark.parametrize("seed", range(3))
def test_a_velocity_turn_is_the_fastest_candidate_built_in_full(seed):
    rng = np.random.default_rng(seed)
    turns = 0
    for _ in range(CASES):
        limits = _random_limits(rng)
        start = _random_state(rng, limits)
        if start.velocity == 0.0:
            continue
        heading = 1 if start.velocity > 0.0 else -1
        velocity = -heading * float(rng.uniform(0.1, 1.0)) * limits.velocity
        got = plan_velocity(start, velocity, limits)
        turns += 1
        want = _reference_turn_velocity(start, velocity, limits, heading)
        assert got.data.tobytes() == want.data.tobytes(), (start, velocity, limits)
    assert turns > CASES // 2


@pytest.mark.parametrize("seed", range(3))
def test_ruckig_phases_flatten_as_the_array_pass_does(seed):
    """Position plans from random states (faster than the limit: ruckig's brake phases)."""
    rng = np.random.default_rng(100 + seed)
    braked = 0
    for _ in range(CASES):
        limits = _random_limits(rng)
        plan._load_state(_random_state(rng, limits), limits, 1)
        plan._input.target_position = [float(rng.uniform(-200.0, 200.0))]
        plan._input.target_velocity = [0.0]
        try:
            plan._otg.calculate(plan._input, plan._trajectory)
        except Exception:  # noqa: BLE001 - ruckig's numerical step 1: not this test's subject
            continue
        profile = plan._trajectory.profiles[0][0]
        braked += profile.brake.duration > 0.0
        assert plan._segments(profile).data.tobytes() == \
            _reference_flatten(profile).data.tobytes()
    assert braked > 0


def test_the_same_plan_again_gives_the_same_bits_after_other_plans():
    """The turn's inputs keep what they hold between plans: a plan after others is the plan
    made first, -0.0 and 0.0 alike."""
    limits = Limits(300.0, 4000.0, 1500.0, 30000.0)
    start = KinematicState(5.0, 250.0, -800.0)
    first = plan_position(start, -40.0, limits).data.tobytes()
    plan_velocity(KinematicState(0.0, -0.0, 0.0), 100.0, limits)
    plan_position(KinematicState(1.0, -200.0, 300.0), 80.0, limits)
    assert plan_position(KinematicState(5.0, 250.0, -800.0), -40.0, limits).data.tobytes() \
        == first


def test_fb_inputs_as_plain_floats_or_not_resolve_alike():
    rt = om.Runtime()
    axis = rt.add_axis("x", max_velocity=200.0, max_acceleration=2000.0,
                       max_deceleration=2000.0, max_jerk=20000.0, acceleration=1000.0,
                       deceleration=1000.0, jerk=10000.0)
    axis.power()
    at_maximum = axis.move_absolute(10.0, 200.0, 2000.0, 2000.0, 20000.0)
    as_ints = axis.move_absolute(10, 200, 2000, 2000, 20000)
    assert not at_maximum.warnings and not as_ints.warnings and as_ints.busy
    clamped = axis.move_absolute(10.0, 250.0, 2500.0, 2000.0, 20000.0)
    assert clamped.busy and clamped.warnings == [
        "velocity 250.0 clamped to the axis maximum 200.0",
        "acceleration 2500.0 clamped to the axis maximum 2000.0"]
    refused = axis.move_absolute(float("nan"), 100.0)
    assert refused.error and refused.error_id is om.ErrorId.INVALID_POSITION
    too_jerky = axis.move_absolute(10.0, 100.0, 1000.0, 1000.0, 30000.0)
    assert too_jerky.error and too_jerky.error_id is om.ErrorId.INVALID_JERK
    done = axis.move_absolute(10.0, 100.0, 1000.0, 1000.0, 10000.0)  # still usable
    rt.run(1.0)
    assert done.done and axis.set_position == 10.0
