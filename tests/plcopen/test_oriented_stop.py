"""MC_OrientedStop (TcMC §3.16, digest rules 77-83) and MC_SetActualPositionOnTheFly (§4.13,
rule 113)."""

from __future__ import annotations

import math

import pytest

import openmotion as om
from openmotion.plcopen import MC_MoveAbsolute, MC_Stop
from openmotion.plcopen.stop_ext import MC_OrientedStop, MC_SetActualPositionOnTheFly
from openmotion.trajectory.plan import plan_stop

E = om.ErrorId


def rotating(velocity: float = 720.0, **parameters: float) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("c", max_velocity=2000.0, **parameters)
    axis.power()
    axis.move_velocity(velocity)
    rt.run(0.5)
    return rt, axis


def until_idle(rt: om.Runtime, fb: MC_OrientedStop, limit: int = 10000) -> list[float]:
    positions = []
    for _ in range(limit):
        if not fb.busy:
            break
        rt.step()
        fb(execute=True)
        positions.append(fb.axis.set_position)
    return positions


@pytest.mark.parametrize("position", [0.0, 45.0, 90.0, 270.5, 359.9])
def test_stops_at_the_first_oriented_position_after_the_normal_stop(position: float) -> None:
    """Rules 77, 78: x mod period == Position, x is the first such position not before the
    normal braking end, so the travel exceeds a normal stop by less than one period."""
    rt, axis = rotating()
    p = axis.parameters
    normal_end = plan_stop(axis.kernel.state(axis.row), p.deceleration, p.jerk).end.position
    stop = MC_OrientedStop(axis)
    stop(execute=True, position=position)
    assert stop.busy and axis.state is om.AxisState.STOPPING
    path = until_idle(rt, stop)
    assert stop.done and not stop.error
    end = axis.set_position
    assert math.isclose(end % 360.0, position, abs_tol=1e-9) or (
        position == 0.0 and math.isclose(end % 360.0, 360.0, abs_tol=1e-9))
    assert normal_end - 1e-9 <= end < normal_end + 360.0
    assert all(b >= a - 1e-12 for a, b in zip(path, path[1:], strict=False))  # no reversal
    assert axis.set_velocity == 0.0 and axis.state is om.AxisState.STANDSTILL


@pytest.mark.parametrize("position", [-1.0, 360.0, 400.0, math.nan])
def test_position_outside_the_period_is_an_error(position: float) -> None:
    """Rule 79: 0 <= Position < period; 360 is invalid on a 360 axis."""
    rt, axis = rotating()
    stop = MC_OrientedStop(axis)
    stop(execute=True, position=position)
    assert stop.error and stop.error_id in (E.INVALID_MODULO_TARGET, E.INVALID_POSITION)
    assert axis.state is om.AxisState.CONTINUOUS_MOTION  # refused before it started


def test_software_limit_before_the_oriented_point_stops_normally_with_an_error() -> None:
    """Rule 80: the oriented point lies beyond an enabled software limit: error, safe stop."""
    rt, axis = rotating(velocity=360.0)
    p = axis.parameters
    normal_end = plan_stop(axis.kernel.state(axis.row), p.deceleration, p.jerk).end.position
    axis.write_parameter(om.AxisPara.AxisMaxSoftPosLimit, normal_end + 1.0)
    axis.write_parameter(om.AxisPara.AxisEnMaxSoftPosLimit, True, bool)
    target = (normal_end + 90.0) % 360.0  # 90 beyond the normal end, past the limit
    stop = MC_OrientedStop(axis)
    stop(execute=True, position=target)
    assert stop.error and stop.error_id == E.TARGET_BEYOND_SOFT_LIMIT
    for _ in range(2000):
        rt.step()
        stop(execute=True)
    assert axis.set_velocity == 0.0
    assert axis.set_position == pytest.approx(normal_end, abs=1e-9)


def test_after_a_normal_stop_it_is_an_error_and_the_axis_stops() -> None:
    """Rule 81."""
    rt, axis = rotating()
    MC_Stop(axis)(execute=True)
    rt.step()
    stop = MC_OrientedStop(axis)
    stop(execute=True, position=90.0)
    assert stop.error and stop.error_id == E.AXIS_STOPPING
    rt.run(2.0)
    assert axis.set_velocity == 0.0


def test_deceleration_and_jerk_inputs_are_ignored() -> None:
    """Rule 82: the running move's dynamics brake, whatever the inputs say."""
    ends = []
    for dec, jerk in ((0.0, 0.0), (100.0, 1000.0), (1e5, 1e6)):
        rt, axis = rotating()
        stop = MC_OrientedStop(axis)
        stop(execute=True, position=180.0, deceleration=dec, jerk=jerk)
        until_idle(rt, stop)
        ends.append((axis.set_position, rt.now))
    assert ends[0] == ends[1] == ends[2]


def test_busy_gates_new_edges() -> None:
    """Rule 83: a new edge while Busy is ignored; after Done a new edge is accepted."""
    rt, axis = rotating()
    stop = MC_OrientedStop(axis)
    stop(execute=True, position=90.0)
    first = stop.command
    stop(execute=False)
    stop(execute=True, position=180.0)  # ignored: still busy
    assert stop.command is first
    until_idle(rt, stop)
    assert axis.set_position % 360.0 == pytest.approx(90.0, abs=1e-9)


def test_at_standstill_it_is_an_error() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("c")
    axis.power()
    stop = MC_OrientedStop(axis)
    stop(execute=True, position=90.0)
    assert stop.error and stop.error_id == E.AXIS_NOT_MOVING


def test_on_the_fly_shift_keeps_the_distance_and_moves_the_end() -> None:
    """Rule 113: set position and target shift by Actual - Previous; the travelled distance
    is unchanged and the axis ends at the old target plus the shift, without a jump in
    velocity or acceleration."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=500.0, velocity=200.0)
    for _ in range(800):
        rt.step()
        move(execute=True)
    before = (axis.set_position, axis.set_velocity, axis.set_acceleration)
    travelled = before[0]
    fly = MC_SetActualPositionOnTheFly(axis)
    fly(execute=True, actual_position=1000.0, previous_position=990.0)
    assert fly.done and not move.command_aborted
    assert axis.set_position == pytest.approx(before[0] + 10.0, abs=1e-12)
    assert (axis.set_velocity, axis.set_acceleration) == before[1:]
    while not move.done:
        rt.step()
        move(execute=True)
    assert axis.set_position == 510.0
    assert axis.set_position - 10.0 - travelled == pytest.approx(500.0 - travelled)


def test_on_the_fly_on_a_disabled_axis_is_an_error() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    fly = MC_SetActualPositionOnTheFly(axis)
    fly(execute=True, actual_position=1.0, previous_position=0.0)
    assert fly.error and fly.error_id == E.AXIS_DISABLED
