"""Single moves from random states through the axis API, with ruckig as the oracle.

style.md §4.2 and performance.md (``otg``): from any state within the limits a move keeps
every limit to 1e-9 relative at every cycle sample, reaches its target bit-exactly and stays
there, and takes at most ruckig's time-optimal duration rounded up to the cycle, plus one
cycle. The command is issued between cycles, so it is planned from the last sample and its
first own sample is one cycle later: ``ceil(duration / cycle)`` cycles from issue to target.

Limits with acceleration != deceleration are checked per sample in PLCopen's sense: while
speeding up (a·v > 0, or from rest) |a| <= acceleration, while slowing down |a| <=
deceleration. A start state that lies beyond the limits, or from which a limit must be
exceeded, is rejected with ``assume(within_limits(...))``.
"""

from __future__ import annotations

import pytest
from hypothesis import assume, example, given, reject
from ruckig import RuckigError

from openmotion.testing import (
    MoveCase,
    assert_within_limits,
    ceil_to_cycle,
    moves,
    ruckig_duration,
    ruckig_reverses,
    run_single_move,
    within_limits,
)
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import KinematicState

CYCLE = 0.001

# hypothesis writes a patch for a failing example with libcst, whose import warns; under
# filterwarnings = error that would turn the falsifying example into a pytest INTERNALERROR.
pytestmark = pytest.mark.filterwarnings("ignore:mypy_extensions.TypedDict:DeprecationWarning")


def _oracle(case) -> tuple[float, bool]:  # noqa: ANN001
    """ruckig's duration for ``case`` and whether its profile reverses direction.

    Where ruckig itself cannot plan the input there is no oracle and the draw is rejected;
    whether openmotion still moves there is ``..._reaches_target_exactly_and_stays``' job.
    """
    try:
        return ruckig_duration(case), ruckig_reverses(case)
    except RuckigError:
        reject()


def _assert_time_optimal(trace, case) -> None:  # noqa: ANN001
    oracle, _ = _oracle(case)
    bound = ceil_to_cycle(oracle, CYCLE) + CYCLE
    assert trace.duration <= bound * (1 + 1e-12), (
        f"motion took {trace.duration:.6g} s, ruckig needs {oracle!r} s (bound {bound:.6g} s)"
    )


# -- position moves ---------------------------------------------------------------------------


@given(case=moves())
@example(case=MoveCase(  # at rest with an acceleration: its sign is the heading (fixed)
    KinematicState(760.3888364049114, 0.0, -1009.9899), 760.3888364049114,
    Limits(161.0, 1010.0, 682.0, 50800.0)))
def test_move_keeps_limits(case):
    """Every sample keeps velocity, jerk, and acceleration/deceleration (acc != dec drawn in
    80 % of the cases, reversals included: the turn through zero must keep both, D-201)."""
    assume(within_limits(case.start, case.limits))
    assert_within_limits(run_single_move(case, CYCLE), case.limits)


@given(case=moves())
@example(case=MoveCase(  # ruckig's step 1 failed from rest: NO_PROFILE (fixed, D-021)
    KinematicState(0.0), 93.1, Limits(93.1, 93100.0, 181000.0, 181000000.0)))
@example(case=MoveCase(  # open: a 1 nm move from rest with acc != dec is NO_PROFILE
    KinematicState(0.0), 1e-6, Limits(10.0, 10.0, 100.0, 1e6)))
@example(case=MoveCase(  # open: the return move after braking from v_max is NO_PROFILE
    KinematicState(0.0, 3420.0), 0.0, Limits(3420.0, 430000.0, 860000.0, 434000000.0)))
def test_move_reaches_target_exactly_and_stays(case):
    assume(within_limits(case.start, case.limits))
    trace = run_single_move(case, CYCLE)
    assert trace.reached(case.target), (
        f"ends at {trace.position[-1]!r}, v={trace.velocity[-1]!r}, a={trace.acceleration[-1]!r}"
    )
    assert trace.velocity[-1] == 0.0 and trace.acceleration[-1] == 0.0


@given(case=moves(symmetric=True))
def test_symmetric_move_is_time_optimal(case):
    """With acceleration == deceleration one ruckig call is exact: nothing may be slower."""
    assume(within_limits(case.start, case.limits))
    _assert_time_optimal(run_single_move(case, CYCLE), case)


@given(case=moves(onward=True))
def test_asymmetric_move_without_reversal_is_time_optimal(case):
    """With acceleration != deceleration, only moves whose mapped ruckig profile keeps its
    direction are held to ruckig's duration.

    ruckig bounds the signed acceleration (``max_acceleration``/``min_acceleration``); plan.py
    maps "speeding up" and "slowing down" onto that pair for the direction of the move. A
    profile that reverses (start velocity pointing away from the target, or an overshoot)
    would need the other bound after the reversal, so it is planned as a turn through zero
    velocity (docs/decisions.md D-201), which no single ruckig call plans: those moves are
    held to the brute-force oracle and to the min(acc, dec) plan in
    tests/trajectory/test_turn_back.py, and here to ``test_move_keeps_limits`` and
    ``test_move_reaches_target_exactly_and_stays``.
    """
    assume(case.limits.acceleration != case.limits.deceleration)
    assume(within_limits(case.start, case.limits))
    assume(not _oracle(case)[1])
    _assert_time_optimal(run_single_move(case, CYCLE), case)


@given(case=moves(high=True))
def test_high_limit_move_keeps_limits_reaches_target_in_time(case):
    """ruckig's high-limit distribution: short moves, often within one or two cycles."""
    assume(within_limits(case.start, case.limits))
    trace = run_single_move(case, CYCLE)
    assert_within_limits(trace, case.limits)
    assert trace.reached(case.target)
    if case.limits.acceleration == case.limits.deceleration or not _oracle(case)[1]:
        _assert_time_optimal(trace, case)


# -- velocity moves ---------------------------------------------------------------------------


@given(case=moves(kind="velocity"))
@example(case=MoveCase(  # reversal caused by the start acceleration (fixed)
    KinematicState(0.0, 0.0, 10.0), -1.0, Limits(1.0, 10.0, 3.16, 100.0), "velocity"))
def test_velocity_move_keeps_limits(case):
    assume(within_limits(case.start, case.limits))
    assert_within_limits(run_single_move(case, CYCLE), case.limits)


@given(case=moves(kind="velocity"))
@example(case=MoveCase(  # ruckig's step 1 failed: NO_PROFILE (fixed, D-021)
    KinematicState(0.0, 0.0, 3125000.0), -10000.0, Limits(1e4, 1e7, 1e7, 1e9), "velocity"))
def test_velocity_move_reaches_signed_velocity_exactly(case):
    assume(within_limits(case.start, case.limits))
    trace = run_single_move(case, CYCLE)
    assert trace.reached(case.target, "velocity"), f"ends at v={trace.velocity[-1]!r}"
    assert trace.reached(0.0, "acceleration")


@given(case=moves(kind="velocity"))
def test_velocity_move_without_reversal_is_time_optimal(case):
    """Symmetric limits, or asymmetric ones where the mapped profile keeps its direction
    (see ``test_asymmetric_move_without_reversal_is_time_optimal``)."""
    assume(within_limits(case.start, case.limits))
    assume(case.limits.acceleration == case.limits.deceleration or not _oracle(case)[1])
    _assert_time_optimal(run_single_move(case, CYCLE), case)


# -- stops ------------------------------------------------------------------------------------


@given(case=moves(kind="stop"))
def test_stop_ends_at_rest_within_its_limits(case):
    """MC_Stop with its own deceleration and jerk: |a| <= deceleration both ways, |j| <= jerk,
    no speed gained beyond what the start acceleration forces, at rest exactly, in time."""
    stop = case.stop_limits
    assume(within_limits(case.start, stop))
    trace = run_single_move(case, CYCLE)
    assert_within_limits(trace, stop)
    v0, a0 = case.start.velocity, case.start.acceleration
    forced = max(abs(v0), abs(v0 + a0 * abs(a0) / (2.0 * stop.jerk)))
    assert trace.peak("velocity") <= forced * (1 + 1e-9)
    assert trace.reached(0.0, "velocity") and trace.reached(0.0, "acceleration")
    assert trace.reached(float(trace.position[-1]))
    _assert_time_optimal(trace, case)
