"""The public helpers of openmotion.testing check what they claim (they guard every other
property test, so they get their own)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from ruckig import RuckigError

from openmotion.testing import (
    MoveCase,
    SetpointTrace,
    assert_continuous,
    assert_traces_equal,
    assert_within_limits,
    ceil_to_cycle,
    high_limits,
    kinematic_states,
    limits,
    moves,
    ruckig_duration,
    ruckig_reverses,
    run_single_move,
    within_limits,
)
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import KinematicState

LIM = Limits(1.0, 10.0, 5.0, 100.0)


def _trace(position, velocity, acceleration, jerk=None) -> SetpointTrace:  # noqa: ANN001
    n = len(position)
    jerk = np.zeros(n) if jerk is None else np.asarray(jerk, float)
    return SetpointTrace(0.001, np.asarray(position, float), np.asarray(velocity, float),
                         np.asarray(acceleration, float), jerk, np.asarray(position, float))


def test_traces_equal_is_bit_exact():
    a = _trace([0.0, 1.0], [0.0, 0.0], [0.0, 0.0])
    assert_traces_equal(a, _trace([0.0, 1.0], [0.0, 0.0], [0.0, 0.0]))
    with pytest.raises(AssertionError, match="position differs first at sample 1"):
        assert_traces_equal(a, _trace([0.0, np.nextafter(1.0, 2.0)], [0.0, 0.0], [0.0, 0.0]))
    with pytest.raises(AssertionError, match="velocity"):
        assert_traces_equal(a, _trace([0.0, 1.0], [-0.0, 0.0], [0.0, 0.0]))


def test_within_limits_distinguishes_speeding_up_and_slowing_down():
    assert_within_limits(_trace([0, 0], [0.5, 0.5], [-5.0, 10.0]), LIM)
    with pytest.raises(AssertionError, match="slowing down"):
        assert_within_limits(_trace([0, 0], [0.5, 0.5], [-6.0, 0.0]), LIM)
    with pytest.raises(AssertionError, match="speeding up"):
        assert_within_limits(_trace([0, 0], [0.0, 0.0], [0.0, -10.5]), LIM)
    with pytest.raises(AssertionError, match=r"\|jerk\|"):
        assert_within_limits(_trace([0, 0], [0, 0], [0, 0], [0.0, 101.0]), LIM)


def test_continuous_flags_jumps_and_passes_a_jerk_limited_ramp():
    dt, j = 0.001, 100.0
    t = np.arange(6) * dt
    ramp = _trace(j * t**3 / 6, j * t**2 / 2, j * t, np.full(6, j))
    assert_continuous(ramp, acceleration=10.0, jerk=j)
    jumped = _trace(ramp.position + np.r_[0, 0, 0, 1e-6, 1e-6, 1e-6], ramp.velocity,
                    ramp.acceleration)
    with pytest.raises(AssertionError, match="position jumps between samples 2 and 3"):
        assert_continuous(jumped, acceleration=10.0, jerk=j)
    with pytest.raises(AssertionError, match="acceleration jumps"):
        assert_continuous(ramp, acceleration=10.0, jerk=j / 2)


def test_trace_arrival_reached_and_duration():
    trace = _trace([0.0, 0.5, 1.0, 1.0, 1.0], [0.0, 1.0, 0.0, 0.0, 0.0], [0.0] * 5)
    assert trace.arrival(1.0) == pytest.approx(0.002)
    assert trace.reached(1.0) and not trace.reached(0.5)
    assert trace.duration == pytest.approx(0.002)
    assert trace.peak("velocity") == 1.0
    assert ceil_to_cycle(0.0021) == pytest.approx(0.003) and ceil_to_cycle(0.002) == 0.002


def test_within_limits_rejects_states_bound_to_exceed_a_limit():
    assert within_limits(KinematicState(0.0, 0.5, 5.0), LIM)
    assert not within_limits(KinematicState(0.0, 0.9, 10.0), LIM)  # 0.9 + 100/200 > 1
    assert not within_limits(KinematicState(0.0, 0.5, -5.5), LIM)  # slowing harder than dec
    # slowing with 5 > acceleration 4: crosses v = 0 while |a| > 4 unless |v| >= 9/200
    tight = Limits(1.0, 4.0, 5.0, 100.0)
    assert within_limits(KinematicState(0.0, 0.05, -5.0), tight)
    assert not within_limits(KinematicState(0.0, 0.04, -5.0), tight)


@given(lim=limits(), high=high_limits(symmetric=True), sym=limits(symmetric=True))
def test_limit_strategies(lim, high, sym):
    for value in (*vars_of(lim), *vars_of(high), *vars_of(sym)):
        assert math.isfinite(value) and value > 0.0
    assert 0.1 <= lim.velocity <= 1e4 and 10.0 <= high.velocity <= 1e6
    assert sym.acceleration == sym.deceleration and high.acceleration == high.deceleration


def vars_of(lim: Limits) -> tuple[float, ...]:
    return lim.velocity, lim.acceleration, lim.deceleration, lim.jerk


@given(state=kinematic_states(LIM))
def test_kinematic_states_lie_within_the_limits(state):
    assert abs(state.velocity) <= LIM.velocity
    bound = LIM.deceleration if state.acceleration * state.velocity < 0 else LIM.acceleration
    assert abs(state.acceleration) <= bound


@given(case=moves())
def test_oracle_agrees_with_itself(case):
    """ruckig_duration is finite and non-negative; a move from rest never reverses."""
    rest = MoveCase(KinematicState(case.start.position), case.target, case.limits)
    try:
        duration = ruckig_duration(rest)
    except RuckigError:  # ruckig's own step-1 failures are not ours to judge
        return
    assert math.isfinite(duration) and duration >= 0.0
    assert not ruckig_reverses(rest)


def test_run_single_move_starts_exactly_at_the_start_state():
    case = MoveCase(KinematicState(3.0, 0.4, -2.0), 5.0, LIM)
    trace = run_single_move(case)
    assert (trace.position[0], trace.velocity[0], trace.acceleration[0]) == (3.0, 0.4, -2.0)
    assert trace.reached(5.0)
