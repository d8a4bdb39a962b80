"""The closed-form rest-to-rest moves against ruckig, and their stretched form's guarantees."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from openmotion.trajectory.double_s import optimal_duration, rest_to_rest, synchronised
from openmotion.trajectory.plan import Limits, plan_position
from openmotion.trajectory.segments import KinematicState, Profile

REL = 1e-9


def _limits() -> st.SearchStrategy[Limits]:
    """Equal acceleration and deceleration over several decades (the planar defaults are
    2000 mm/s, 10000 mm/s², 200000 mm/s³ and 360 °/s, 3600 °/s², 72000 °/s³)."""
    decades = st.floats(0.0, 3.0).map(lambda e: 10.0 ** e)
    return st.builds(lambda v, a, j: Limits(10.0 * v, 100.0 * a, 100.0 * a, 1000.0 * j),
                     decades, decades, decades)


distances = st.floats(1e-3, 5000.0)
signs = st.sampled_from((-1.0, 1.0))


def _end_state(data: np.ndarray) -> tuple[float, float, float]:
    """Position, velocity, acceleration reached by integrating the last closed segment."""
    k = data.shape[1] - 2
    dt = data[0, k + 1] - data[0, k]
    p, v, a, j = data[1:, k]
    return (p + dt * (v + dt * (a / 2.0 + dt * j / 6.0)), v + dt * (a + dt * j / 2.0),
            a + dt * j)


def _check_move(data: np.ndarray, start: float, target: float, limits: Limits) -> None:
    """Starts at rest on ``start``, ends at rest on ``target`` (integrated, not only pinned),
    never beyond the limits, never turns back."""
    profile = Profile.from_data(data)
    assert data[1, 0] == start and data[2, 0] == 0.0 and data[3, 0] == 0.0
    assert data[1, -1] == target and data[2, -1] == 0.0 and data[3, -1] == 0.0
    p, v, a = _end_state(data)
    scale = max(1.0, abs(target - start))
    assert p == pytest.approx(target, abs=1e-9 * scale)
    # the phases are differences of absolute times: each is off by some eps * t_end, which
    # the jerk turns into an acceleration residue (1e6 mm/s³ over 2048 s: 2e-7 mm/s²)
    time_residue = 8 * np.finfo(float).eps * max(1.0, float(data[0, -1]))
    assert abs(v) <= 1e-9 * limits.velocity
    assert abs(a) <= 1e-9 * limits.acceleration + limits.jerk * time_residue
    low, high = profile.velocity_extrema()
    assert max(-low, high) <= limits.velocity * (1 + REL)
    assert min(-low, high) <= 1e-9 * limits.velocity  # one sign only: no turning back
    assert np.abs(data[3]).max() <= limits.acceleration * (1 + REL)
    assert np.abs(data[4]).max() <= limits.jerk * (1 + REL)
    assert np.all(np.diff(data[0]) > 0.0)


@given(limits=_limits(), distance=distances, sign=signs)
def test_the_optimum_is_ruckigs(limits, distance, sign):
    """Same duration and the same motion as ruckig's time-optimal plan (two jerk phases in a
    row may be one segment here, two there)."""
    target = 5.0 + sign * distance
    oracle = plan_position(KinematicState(5.0), target, limits)
    data = rest_to_rest(5.0, target, limits.velocity, limits.acceleration, limits.jerk, 0.0)
    assert data[0, -1] == pytest.approx(oracle.duration, rel=REL)
    assert optimal_duration(sign * distance, limits.velocity, limits.acceleration,
                            limits.jerk) == pytest.approx(oracle.duration, rel=REL)
    mine, theirs = Profile.from_data(data), oracle
    for time in np.linspace(0.0, oracle.duration, 41):
        p, v, a, _ = mine.at(time)
        p_ruckig, v_ruckig, a_ruckig, _ = theirs.at(time)
        assert p == pytest.approx(p_ruckig, abs=1e-8 * max(1.0, distance))
        assert v == pytest.approx(v_ruckig, abs=1e-8 * limits.velocity)
        assert a == pytest.approx(a_ruckig, abs=1e-6 * limits.acceleration)
    _check_move(data, 5.0, target, limits)


@given(limits=_limits(), distance=distances, sign=signs, stretch=st.floats(1.0, 20.0))
def test_a_longer_move_lasts_exactly_as_asked(limits, distance, sign, stretch):
    """Any duration above the optimum is met, with the limits kept and the target reached."""
    target = -3.0 + sign * distance
    optimum = optimal_duration(target + 3.0, limits.velocity, limits.acceleration, limits.jerk)
    duration = optimum * stretch
    data = rest_to_rest(-3.0, target, limits.velocity, limits.acceleration, limits.jerk,
                        duration)
    assert data[0, -1] == pytest.approx(duration, rel=REL)
    _check_move(data, -3.0, target, limits)


def test_a_longer_move_cruises_slower_with_the_same_ramps():
    """D-139: lasting longer lowers the cruise speed and keeps the acceleration peak (the
    path of a planar move synchronised with a slower rotation)."""
    v, a, j = 2000.0, 10000.0, 200000.0
    optimum = optimal_duration(400.0, v, a, j)
    data = rest_to_rest(0.0, 400.0, v, a, j, optimum + 0.1)
    assert data[0, -1] == pytest.approx(optimum + 0.1, rel=REL)
    assert np.abs(data[3]).max() == pytest.approx(a)
    cruise = data[2, 3]  # after jerk up, hold, jerk down
    assert data[4, 3] == 0.0 and data[3, 3] == pytest.approx(0.0, abs=1e-9)
    # cruise speed from T = d / v + v / a + a / j
    assert 400.0 / cruise + cruise / a + a / j == pytest.approx(optimum + 0.1, rel=REL)


def test_a_short_stretched_move_keeps_below_the_acceleration_limit():
    """A move too short to reach the acceleration limit stretches without reaching it."""
    v, a, j = 2000.0, 10000.0, 200000.0
    optimum = optimal_duration(1.0, v, a, j)
    data = rest_to_rest(0.0, 1.0, v, a, j, 3.0 * optimum)
    assert data[0, -1] == pytest.approx(3.0 * optimum, rel=REL)
    assert np.abs(data[3]).max() < a
    _check_move(data, 0.0, 1.0, Limits(v, a, a, j))


def test_no_distance_is_no_move():
    data = rest_to_rest(7.0, 7.0, 10.0, 100.0, 1000.0, 2.0)
    assert data.shape == (5, 1) and data[1, 0] == 7.0 and data[0, 0] == 0.0


@given(path_limits=_limits(), c_limits=_limits(), distance=distances,
       turn=st.floats(1e-3, 90.0), sign=signs)
def test_synchronised_moves_end_together(path_limits, c_limits, distance, turn, sign):
    """The slower of path and rotation is time-optimal, the other ends with it."""
    path, rotation = synchronised(distance, path_limits.velocity, path_limits.acceleration,
                                  path_limits.jerk, 10.0, 10.0 + sign * turn,
                                  c_limits.velocity, c_limits.acceleration, c_limits.jerk)
    slower = max(optimal_duration(distance, path_limits.velocity, path_limits.acceleration,
                                  path_limits.jerk),
                 optimal_duration(turn, c_limits.velocity, c_limits.acceleration,
                                  c_limits.jerk))
    assert path[0, -1] == pytest.approx(slower, rel=REL)
    assert rotation[0, -1] == pytest.approx(slower, rel=REL)
    assert math.isclose(path[0, -1], rotation[0, -1], rel_tol=REL)
    _check_move(path, 0.0, distance, path_limits)
    _check_move(rotation, 10.0, 10.0 + sign * turn, c_limits)


@given(limits=_limits(), distance=distances, sign=signs, speed=st.floats(-1.0, 1.0))
def test_plan_position_in_closed_form_only_from_rest(limits, distance, sign, speed):
    """``plan_position(closed_form=True)``: the double S from rest with equal acceleration and
    deceleration, and ruckig's plan bit for bit from any other state."""
    target = sign * distance
    rest = KinematicState(0.0)
    closed = plan_position(rest, target, limits, closed_form=True)
    assert np.array_equal(closed.data, rest_to_rest(0.0, target, limits.velocity,
                                                    limits.acceleration, limits.jerk, 0.0))
    assume(speed != 0.0)
    moving = KinematicState(0.0, speed * limits.velocity)
    assert np.array_equal(plan_position(moving, target, limits, closed_form=True).data,
                          plan_position(moving, target, limits).data)
