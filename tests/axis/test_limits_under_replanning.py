"""Axis limits hold when a plan starts from a running state, and software limits (issue 19).

Point 1: every planner that starts from a running state - MC_Stop, MC_Halt, a new move -
takes the jerk that releases the running acceleration before the axis maximum velocity
(D-020, D-177), so the setpoint keeps |v| <= max_velocity, |a| <= the acceleration maxima,
|j| <= max_jerk and steps at most max|a|·cycle per cycle (``openmotion.testing.REL``
relative tolerance). Point 8: an axis beyond a software limit may move back towards the
range, and a limit written during a motion holds for that motion (TcMC §6.1, D-016, D-179).
"""

from __future__ import annotations

from collections.abc import Callable

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

import openmotion as om
from openmotion.plcopen import MC_MoveAbsolute, MC_Reset, MC_Stop, MC_WriteParameter
from openmotion.testing import REL, SetpointRecorder, assert_continuous
from openmotion.trajectory.plan import plan_stop
from openmotion.trajectory.segments import KinematicState

ErrorId = om.ErrorId
S = om.AxisState
POS, NEG = om.Direction.POSITIVE, om.Direction.NEGATIVE
SOFT_MAX, SOFT_MIN = 1018, 1016  #: MC_AxisPara numbers (TcMC §6.1)
ENABLE_SOFT_MAX = 1017

pytestmark = pytest.mark.filterwarnings("ignore:mypy_extensions.TypedDict:DeprecationWarning")


# -- point 1: stops and halts from a running state -------------------------------------------


def issue_axis() -> tuple[om.Runtime, om.Axis]:
    """Issue 19 point 1: max velocity 1000, acceleration, deceleration and jerk 10 000."""
    rt = om.Runtime()
    axis = rt.add_axis("x", max_velocity=1000.0, acceleration=10000.0, deceleration=10000.0,
                       jerk=10000.0, max_jerk=1e6)
    assert axis.power()
    return rt, axis


def hard_then_soft(rt: om.Runtime, axis: om.Axis) -> None:
    """Accelerate with jerk 1e6, then re-plan with jerk 1e4 at 300 mm/s, 5 ms later: the
    running profile uses more than its nominal jerk to stay below 1000 mm/s (D-020)."""
    axis.move_velocity(1000.0, acceleration=10000.0, jerk=1e6)
    while axis.set_velocity < 300.0:
        rt.step()
    axis.move_velocity(400.0, jerk=10000.0)
    rt.run(0.005)
    assert axis.set_acceleration > 9000.0  # still far from releasing the acceleration


def peak_velocity_until_rest(rt: om.Runtime, axis: om.Axis) -> float:
    peak = abs(axis.set_velocity)
    for _ in range(5000):
        rt.step()
        peak = max(peak, abs(axis.set_velocity))
        if axis.state is S.STANDSTILL and axis.set_velocity == 0.0:
            return peak
    raise AssertionError(f"not at rest: {axis!r}")


@pytest.mark.parametrize("brake", [
    lambda axis: axis.stop(),
    lambda axis: axis.stop(10000.0, 10000.0),
    lambda axis: axis.halt(),
    lambda axis: axis.halt(10000.0, 10000.0),
], ids=["stop", "stop_given", "halt", "halt_given"])
def test_stop_after_a_stiffened_replan_keeps_max_velocity(
        brake: Callable[[om.Axis], om.Command]) -> None:
    """Issue 19 point 1, D-177: the stop took the move's nominal jerk and peaked at
    4998 mm/s; now it takes the jerk that releases the acceleration by 1000 mm/s."""
    rt, axis = issue_axis()
    hard_then_soft(rt, axis)
    command = brake(axis)
    assert not command.error
    assert peak_velocity_until_rest(rt, axis) <= 1000.0 * (1 + REL)
    assert command.done
    follow = axis.move_absolute(0.0, velocity=500.0)  # the axis stays usable
    rt.run_until(follow, timeout=10.0)
    assert follow.done and axis.set_position == 0.0


def test_mc_stop_block_after_a_stiffened_replan_keeps_max_velocity() -> None:
    """Issue 19 point 1 through MC_Stop (TcMC §3.15): the stop keeps the axis maximum
    velocity (D-177) and ends Done at rest."""
    rt, axis = issue_axis()
    hard_then_soft(rt, axis)
    stop = MC_Stop(axis)
    stop(execute=True)
    peak = 0.0
    while not stop.done:
        rt.step()
        stop(execute=True)
        peak = max(peak, abs(axis.set_velocity))
    assert peak <= 1000.0 * (1 + REL)
    assert axis.set_velocity == 0.0 and axis.state is S.STOPPING


@st.composite
def running_then_brake(draw: st.DrawFn) -> dict[str, object]:
    """Axis maxima, a MoveVelocity with a stiff jerk, an optional re-plan with a soft one
    (velocity or position), then MC_Stop or MC_Halt with their own valid dynamics."""
    v_max = draw(st.floats(50.0, 2000.0))
    a_max, d_max = (v_max * draw(st.floats(2.0, 50.0)) for _ in range(2))
    j_max = max(a_max, d_max) * draw(st.floats(5.0, 1000.0))

    def dynamics(maximum: float) -> float:
        return maximum * draw(st.floats(0.05, 1.0))

    def jerk() -> float:
        return max(a_max, d_max) * draw(st.floats(1.0, j_max / max(a_max, d_max)))

    first = dict(velocity=v_max * draw(st.floats(0.05, 1.0)),
                 direction=draw(st.sampled_from([POS, NEG])),
                 acceleration=dynamics(a_max), deceleration=dynamics(d_max), jerk=jerk())
    second_kind = draw(st.sampled_from(["none", "velocity", "absolute"]))
    second: dict[str, object] = dict(acceleration=dynamics(a_max),
                                     deceleration=dynamics(d_max), jerk=jerk())
    if second_kind == "velocity":
        second.update(velocity=v_max * draw(st.floats(0.05, 1.0)),
                      direction=draw(st.sampled_from([POS, NEG])))
    elif second_kind == "absolute":
        second.update(position=v_max * draw(st.floats(-1.0, 1.0)),
                      velocity=v_max * draw(st.floats(0.05, 1.0)))
    brake_kind = draw(st.sampled_from(["stop", "halt"]))
    with_dynamics = draw(st.booleans())
    brake = dict(deceleration=dynamics(d_max), jerk=jerk()) if with_dynamics else {}
    return dict(
        axis=dict(max_velocity=v_max, max_acceleration=a_max, max_deceleration=d_max,
                  max_jerk=j_max, acceleration=a_max / 2, deceleration=d_max / 2,
                  jerk=min(j_max, max(a_max, d_max) * 10.0)),
        first=first, first_cycles=draw(st.integers(1, 300)),
        second_kind=second_kind, second=second, second_cycles=draw(st.integers(0, 60)),
        brake_kind=brake_kind, brake=brake,
    )


ISSUE_CASE = dict(
    axis=dict(max_velocity=1000.0, max_acceleration=20000.0, max_deceleration=20000.0,
              max_jerk=1e6, acceleration=10000.0, deceleration=10000.0, jerk=10000.0),
    first=dict(velocity=1000.0, direction=POS, acceleration=10000.0, deceleration=10000.0,
               jerk=1e6),
    first_cycles=40, second_kind="velocity",
    second=dict(velocity=400.0, direction=POS, acceleration=10000.0, deceleration=10000.0,
                jerk=10000.0),
    second_cycles=5, brake_kind="stop", brake={},
)


#: found by this test: a halt from a hard deceleration near zero velocity with a soft jerk
#: passes zero and overshot the maximum the other way (D-177)
REVERSING_CASE = dict(
    axis=dict(max_velocity=50.0, max_acceleration=100.0, max_deceleration=250.0,
              max_jerk=104250.0, acceleration=50.0, deceleration=125.0, jerk=2500.0),
    first=dict(velocity=50.0, direction=POS, acceleration=50.0, deceleration=250.0,
               jerk=5750.0),
    first_cycles=9, second_kind="velocity",
    second=dict(velocity=50.0, direction=NEG, acceleration=100.0, deceleration=250.0,
                jerk=104250.0),
    second_cycles=2, brake_kind="halt", brake=dict(deceleration=250.0, jerk=250.0),
)


@example(case=ISSUE_CASE)
@example(case=REVERSING_CASE)
@example(case={**ISSUE_CASE, "brake": dict(deceleration=10000.0, jerk=10000.0)})
@given(case=running_then_brake())
def test_stop_and_halt_from_any_running_state_keep_the_axis_limits(
        case: dict[str, object]) -> None:
    """Issue 19 point 1, D-020/D-177: from any state a MoveVelocity (and a re-plan of it)
    reaches, MC_Stop and MC_Halt with any valid dynamics keep |v| <= max_velocity,
    |a| <= max(max_acceleration, max_deceleration), |j| <= max_jerk, and no sample steps
    further than those limits allow in one cycle (``assert_continuous``)."""
    rt = om.Runtime()
    axis = rt.add_axis("x", **case["axis"])  # type: ignore[arg-type]
    assert axis.power()
    recorder = SetpointRecorder(rt, axis)
    assert not axis.move_velocity(**case["first"]).error  # type: ignore[arg-type]
    rt.run(case["first_cycles"] * rt.cycle_time)  # type: ignore[operator]
    if case["second_kind"] == "velocity":
        assert not axis.move_velocity(**case["second"]).error  # type: ignore[arg-type]
    elif case["second_kind"] == "absolute":
        assert not axis.move_absolute(**case["second"]).error  # type: ignore[arg-type]
    rt.run(case["second_cycles"] * rt.cycle_time)  # type: ignore[operator]
    brake = axis.stop if case["brake_kind"] == "stop" else axis.halt
    command = brake(**case["brake"])  # type: ignore[arg-type]
    assert not command.error, command
    rt.run_until(lambda: command.done and axis.set_velocity == 0.0, timeout=30.0)
    p = axis.parameters
    trace = recorder.trace()
    acceleration = max(p.max_acceleration, p.max_deceleration)
    assert trace.peak("velocity") <= p.max_velocity * (1 + REL)
    assert trace.peak("acceleration") <= acceleration * (1 + REL)
    assert trace.peak("jerk") <= p.max_jerk * (1 + REL)
    assert_continuous(trace, acceleration, p.max_jerk)


# -- point 8: software limits ----------------------------------------------------------------


def limited_axis(position: float = 0.0, max_soft_limit: float = 100.0,
                 **overrides: object) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x", position=position, enable_max_soft_limit=True,
                       max_soft_limit=max_soft_limit, **overrides)
    assert axis.power()
    return rt, axis


def test_axis_enabled_beyond_a_soft_limit_moves_back_inside() -> None:
    """Issue 19 point 8, D-179: enabled at 150 with the limit at 100, MoveAbsolute(0) was
    refused with PATH_BEYOND_SOFT_LIMIT; motion back towards the range is allowed."""
    rt, axis = limited_axis(position=150.0)
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=0.0, velocity=200.0)
    assert not move.error, move.message
    while not move.done:
        rt.step()
        move(execute=True)
    assert axis.set_position == 0.0 and axis.state is S.STANDSTILL


def test_axis_beyond_a_soft_limit_may_not_go_further_out() -> None:
    """D-179: from beyond the limit, a target further out is TARGET_BEYOND_SOFT_LIMIT and a
    MoveVelocity outwards PATH_BEYOND_SOFT_LIMIT; a target between the axis and the limit
    is a move back and is accepted."""
    rt, axis = limited_axis(position=150.0)
    further = axis.move_absolute(160.0, velocity=100.0)
    assert further.error and further.error_id == ErrorId.TARGET_BEYOND_SOFT_LIMIT
    outwards = axis.move_velocity(50.0, POS)
    assert outwards.error and outwards.error_id == ErrorId.PATH_BEYOND_SOFT_LIMIT
    assert axis.set_position == 150.0 and axis.state is S.STANDSTILL
    closer = axis.move_absolute(120.0, velocity=100.0)
    rt.run_until(closer, timeout=5.0)
    assert closer.done and axis.set_position == 120.0
    inwards = axis.move_velocity(50.0, NEG)  # no lower limit: cruises on
    rt.run_until(lambda: inwards.in_velocity, timeout=5.0)
    assert axis.set_velocity == -50.0


def write(axis: om.Axis, number: int, value: float) -> None:
    """MC_WriteParameter for one cycle (TcMC §4.10)."""
    block = MC_WriteParameter(axis)
    block(enable=True, parameter_number=number, value=value)
    assert block.done and not block.error, block.message


def test_soft_limit_lowered_during_a_move_stops_it_at_the_limit() -> None:
    """Issue 19 point 8, D-179: a move to 450 ended Done at 450 with the limit lowered to
    200 on the way; now it stops exactly at 200 and the axis reports SOFT_LIMIT_REACHED
    (as a MoveVelocity towards a limit does, D-016); the move shows CommandAborted."""
    rt, axis = limited_axis(max_soft_limit=500.0)
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=450.0, velocity=200.0)
    for _ in range(500):
        rt.step()
        move(execute=True)
    assert 50.0 < axis.set_position < 200.0
    write(axis, SOFT_MAX, 200.0)
    peak = axis.set_position
    while move.busy:
        rt.step()
        move(execute=True)
        peak = max(peak, axis.set_position)
    assert move.command_aborted and not move.done
    assert peak <= 200.0 and axis.set_position == 200.0
    assert axis.state is S.ERROR_STOP and axis.axis_error_id == ErrorId.SOFT_LIMIT_REACHED
    reset = MC_Reset(axis)
    reset(execute=True)
    while not reset.done:
        rt.step()
        reset(execute=True)
    back = axis.move_absolute(0.0, velocity=200.0)
    rt.run_until(back, timeout=5.0)
    assert back.done and axis.set_position == 0.0


def test_soft_limit_enabled_ahead_of_a_move_velocity_stops_it_there() -> None:
    """D-179 with D-016: a limit enabled during a MoveVelocity stops it at the limit."""
    rt = om.Runtime()
    axis = rt.add_axis("x", max_soft_limit=300.0)
    axis.power()
    cruise = axis.move_velocity(200.0)
    rt.run(0.5)
    axis.write_parameter(ENABLE_SOFT_MAX, True, bool)
    rt.run_until(lambda: axis.state is S.ERROR_STOP and axis.set_velocity == 0.0,
                 timeout=5.0)
    assert cruise.aborted and axis.set_position == 300.0
    assert axis.axis_error_id == ErrorId.SOFT_LIMIT_REACHED


def test_soft_limit_lowered_too_close_to_brake_faults_at_once() -> None:
    """D-179: when not even the axis maxima stop the motion at the new limit, the axis
    error comes in the cycle of the write and brakes with max_deceleration and max_jerk:
    the shortest stop there is."""
    rt, axis = limited_axis(max_soft_limit=1000.0)
    move = axis.move_absolute(900.0, velocity=500.0)
    rt.run(0.6)
    start = KinematicState(axis.set_position, axis.set_velocity, axis.set_acceleration)
    assert start.velocity == 500.0
    write(axis, SOFT_MAX, start.position + 5.0)
    assert axis.state is S.ERROR_STOP and axis.axis_error_id == ErrorId.SOFT_LIMIT_REACHED
    assert move.aborted
    p = axis.parameters
    rt.run_until(lambda: axis.set_velocity == 0.0 and not axis.has_job, timeout=5.0)
    shortest = plan_stop(start, p.max_deceleration, p.max_jerk).end.position
    assert axis.set_position == pytest.approx(shortest, rel=1e-12)


def test_soft_limit_written_at_rest_beyond_the_axis_changes_nothing() -> None:
    """D-179: an axis at rest beyond a newly written limit stays where it is, without an
    error (the limit only refuses motion further out)."""
    rt, axis = limited_axis(max_soft_limit=500.0)
    move = axis.move_absolute(300.0, velocity=500.0)
    rt.run_until(move, timeout=5.0)
    write(axis, SOFT_MAX, 200.0)
    rt.run(0.1)
    assert axis.state is S.STANDSTILL and axis.set_position == 300.0


def test_soft_limit_written_while_override_pauses_a_move_holds_when_it_resumes() -> None:
    """D-179: a MoveVelocity paused by override 0 (D-007) counts with the way it resumes
    on: a limit written during the pause stops it there once the override returns."""
    rt = om.Runtime()
    axis = rt.add_axis("x", max_soft_limit=400.0)
    axis.power()
    cruise = axis.move_velocity(200.0)
    rt.run(0.5)
    axis.set_override(0.0)
    rt.run(0.5)
    assert axis.set_velocity == 0.0 and cruise.busy
    axis.write_parameter(ENABLE_SOFT_MAX, True, bool)
    assert axis.state is S.CONTINUOUS_MOTION  # no error while it stands inside the range
    axis.set_override(100.0)
    rt.run_until(lambda: axis.state is S.ERROR_STOP and axis.set_velocity == 0.0,
                 timeout=5.0)
    assert cruise.aborted and axis.set_position == 400.0
    assert axis.axis_error_id == ErrorId.SOFT_LIMIT_REACHED
