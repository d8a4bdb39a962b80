"""External setpoint generation: MC_ExtSetPointGenEnable / Disable / Feed (TcMC §4.16-4.18,
digest rules 116-119, decisions D-040)."""

from __future__ import annotations

import math

import pytest

import openmotion as om
from openmotion.plcopen import MC_MoveAbsolute
from openmotion.plcopen.external import (
    MC_ExtSetPointGenDisable,
    MC_ExtSetPointGenEnable,
    MC_ExtSetPointGenFeed,
)

E, S = om.ErrorId, om.AxisState


def cosine(t: float) -> tuple[float, float, float]:
    """A smooth 100 mm move in 1 s: position, velocity, acceleration at ``t``."""
    w = math.pi
    return 50.0 * (1 - math.cos(w * t)), 50.0 * w * math.sin(w * t), 50.0 * w * w * math.cos(w * t)


def enabled_axis(**inputs: object) -> tuple[om.Runtime, om.Axis, MC_ExtSetPointGenEnable]:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    enable = MC_ExtSetPointGenEnable(axis)
    enable(execute=True, **inputs)
    return rt, axis, enable


def test_enabled_axis_follows_the_fed_values_exactly() -> None:
    """Rule 116: after the enable, the set position is the fed position every cycle."""
    rt, axis, enable = enabled_axis(position=100.0)
    assert enable.done and enable.enabled and axis.state is S.CONTINUOUS_MOTION
    for k in range(1, 1001):
        p, v, a = cosine(k * 0.001)
        assert MC_ExtSetPointGenFeed(p, v, a, 1, axis) is False  # rule 119
        rt.step()
        assert (axis.set_position, axis.set_velocity, axis.set_acceleration) == (p, v, a)
    assert axis.in_external_target and axis.set_position == pytest.approx(100.0)


def test_in_target_only_when_the_position_is_reached() -> None:
    """Rule 116: "in target position" TRUE when the given Position is reached; the axis
    does not go there by itself."""
    rt, axis, _ = enabled_axis(position=100.0)
    for k in range(1, 400):
        MC_ExtSetPointGenFeed(*cosine(k * 0.001), 1, axis)
        rt.step()
        assert not axis.in_external_target
    for _ in range(5):  # hold still: nothing moves the axis towards 100
        MC_ExtSetPointGenFeed(axis.set_position, 0.0, 0.0, 0, axis)
        rt.step()
    assert axis.set_position < 50.0 and not axis.in_external_target


def test_relative_target_refers_to_the_set_position_at_the_enable() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x", position=20.0)
    axis.power()
    axis.enable_external_setpoints(10.0, om.TargetPositionType.RELATIVE)
    MC_ExtSetPointGenFeed(30.0, 0.0, 0.0, 0, axis)
    rt.step()
    assert axis.in_external_target


def test_disable_ignores_further_feeds_and_enabled_reports_the_state() -> None:
    """Rules 117, 118: Enabled FALSE after the disable; later feeds change nothing; the
    Enabled output of an idle block still shows the generator state."""
    rt, axis, enable = enabled_axis()
    MC_ExtSetPointGenFeed(5.0, 0.0, 0.0, 0, axis)
    rt.step()
    disable = MC_ExtSetPointGenDisable(axis)
    disable(execute=True)
    assert disable.done and not disable.enabled
    enable(execute=False)
    enable(execute=False)
    assert not enable.enabled  # idle block, current state
    MC_ExtSetPointGenFeed(50.0, 0.0, 0.0, 0, axis)
    rt.run(0.1)
    assert axis.set_position == 5.0 and axis.state is S.STANDSTILL


def test_an_idle_disable_block_shows_the_generator_state() -> None:
    """Rule 118, TcMC §4.17: "Enabled shows the current state of the external set value
    generator, independent of the function execution": a disable block that is never
    executed follows the enables and disables done by other blocks."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    idle = MC_ExtSetPointGenDisable(axis)
    idle(execute=False)
    assert not idle.enabled and not idle.busy and not idle.done
    enable, disable = MC_ExtSetPointGenEnable(axis), MC_ExtSetPointGenDisable(axis)
    for _ in range(2):
        enable(execute=True)
        idle(execute=False)
        assert enable.enabled and idle.enabled and not idle.done
        MC_ExtSetPointGenFeed(0.0, 0.0, 0.0, 0, axis)
        rt.step()
        idle(execute=False)
        assert idle.enabled
        enable(execute=False)
        disable(execute=True)
        idle(execute=False)
        assert not disable.enabled and not idle.enabled and not idle.done
        disable(execute=False)
        rt.step()


def test_the_direction_input_of_the_feed_does_not_change_the_setpoint() -> None:
    """Rule 119, TcMC §4.18: Direction (-1, 0, 1) is copied with the other three values;
    the axis takes the fed position, velocity and acceleration verbatim whatever Direction
    says, even a Direction that contradicts the velocity: the sign of the fed velocity
    is the direction of travel. The function returns FALSE for every Direction."""
    traces = []
    for direction in (1, 0, -1):
        rt, axis, _ = enabled_axis()
        samples = []
        for k in range(1, 600):
            p, v, a = cosine(k * 0.001)
            assert MC_ExtSetPointGenFeed(p, v, a, direction, axis) is False
            rt.step()
            samples.append((axis.set_position, axis.set_velocity, axis.set_acceleration))
            assert samples[-1] == (p, v, a)
        assert axis.state is S.CONTINUOUS_MOTION and axis.set_velocity > 0.0
        traces.append(samples)
    assert traces[0] == traces[1] == traces[2]


def test_a_cycle_without_a_feed_is_an_axis_error_with_a_controlled_stop() -> None:
    """D-040: where the manual is silent, a missing feed stops the axis with an error."""
    rt, axis, _ = enabled_axis()
    for k in range(1, 300):
        MC_ExtSetPointGenFeed(*cosine(k * 0.001), 1, axis)
        rt.step()
    moving = axis.set_velocity
    assert moving > 0.0
    rt.step()  # no feed
    assert axis.state is S.ERROR_STOP and axis.axis_error_id == E.EXT_SETPOINT_MISSING
    assert not axis.external_setpoints
    velocities = []
    for _ in range(500):
        rt.step()
        velocities.append(axis.set_velocity)
    assert velocities[-1] == 0.0
    assert max(abs(b - a) for a, b in zip([moving, *velocities], velocities, strict=False)) \
        <= axis.parameters.max_deceleration * 0.001 * (1 + 1e-9)


def test_a_fed_velocity_beyond_the_maximum_is_an_axis_error() -> None:
    rt, axis, _ = enabled_axis()
    MC_ExtSetPointGenFeed(0.0, 2 * axis.parameters.max_velocity, 0.0, 1, axis)
    rt.step()
    assert axis.state is S.ERROR_STOP and axis.axis_error_id == E.EXT_SETPOINT_LIMIT


def test_a_move_takes_over_from_the_fed_state() -> None:
    """Q33 / D-040: a motion command ends the external generation and starts from the fed
    position, velocity and acceleration."""
    rt, axis, _ = enabled_axis()
    for k in range(1, 300):
        MC_ExtSetPointGenFeed(*cosine(k * 0.001), 1, axis)
        rt.step()
    before = (axis.set_position, axis.set_velocity)
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=200.0, velocity=300.0)
    assert not axis.external_setpoints
    rt.step()
    assert abs(axis.set_position - before[0]) < 0.5
    assert abs(axis.set_velocity - before[1]) < axis.parameters.max_acceleration * 0.001
    while not move.done:
        rt.step()
        move(execute=True)
    assert axis.set_position == 200.0


def test_enable_needs_an_enabled_axis_and_a_known_position_type() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    enable = MC_ExtSetPointGenEnable(axis)
    enable(execute=True)
    assert enable.error and enable.error_id == E.AXIS_DISABLED
    axis.power()
    enable = MC_ExtSetPointGenEnable(axis)
    enable(execute=True, position_type=3)
    assert enable.error and enable.error_id == E.INVALID_MODE
