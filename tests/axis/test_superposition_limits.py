"""Issue 19 points 2, 3, 4 and 7: superposition, re-planning and gearing keep the axis maxima.

Rules: the sum of base and superimposed motion honours the axis maximum velocity,
acceleration and jerk (D-180, TcMC §3.9-3.11: VelocityDiff is the velocity *reserve*); a
re-plan of the base under a running superposition starts from the base state, so the
setpoint never moves by more than the limits allow in one cycle (D-180); the axis reports the
PLCopen state of its motion while a superposition moves it (D-181); a geared slave never
outputs a sample beyond its maxima: the fault comes in the cycle before (D-182).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.enums import AxisState, BufferMode, Direction, NewPosAndVeloMode
from openmotion.plcopen import (
    MC_MoveAbsolute,
    MC_MoveSuperImposed,
    MC_MoveVelocity,
    MC_Power,
    MC_SetOverride,
)
from openmotion.plcopen.jog import JogMode, MC_Jog

E = om.ErrorId
CYCLE = 0.001
TOLERANCE = 1e-6  #: relative slack of every limit check below (rounding of the cubic)
LIMITS = {"max_velocity": 500.0, "max_acceleration": 20000.0, "max_deceleration": 20000.0,
          "max_jerk": 1.0e6}


class Samples:
    """Setpoint samples of one axis, one per cycle."""

    def __init__(self) -> None:
        self.rows: list[tuple[float, float, float, float, AxisState]] = []

    def take(self, axis: om.Axis) -> None:
        self.rows.append((axis.set_position, axis.set_velocity, axis.set_acceleration,
                          axis.set_jerk, axis.state))

    def column(self, i: int) -> np.ndarray:
        return np.array([row[i] for row in self.rows])

    def assert_state_matches_motion(self) -> None:
        """D-181: never StandStill while the setpoint moves."""
        moving = [row for row in self.rows if row[4] is AxisState.STANDSTILL and row[1] != 0.0]
        assert not moving, f"{len(moving)} samples in StandStill at up to " \
            f"{max(abs(row[1]) for row in moving)} mm/s"

    def assert_within(self, v_max: float, a_max: float, j_max: float) -> None:
        """Every sample within the maxima; no velocity step larger than a_max allows."""
        p, v, a, j = (self.column(i) for i in range(4))
        slack = 1.0 + TOLERANCE
        assert np.abs(v).max() <= v_max * slack, f"velocity {np.abs(v).max()}"
        assert np.abs(a).max() <= a_max * slack, f"acceleration {np.abs(a).max()}"
        assert np.abs(j).max() <= j_max * slack, f"jerk {np.abs(j).max()}"
        assert np.abs(np.diff(v)).max(initial=0.0) <= a_max * CYCLE * slack, "velocity step"
        assert np.abs(np.diff(p)).max(initial=0.0) <= v_max * CYCLE * slack, "position step"


def run(rt: om.Runtime, axis: om.Axis, cycles: int, samples: Samples) -> None:
    for _ in range(cycles):
        rt.step()
        samples.take(axis)


def cruising_at_maximum() -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x", **LIMITS)
    axis.power()
    axis.move_velocity(500.0)
    rt.run(1.0)
    return rt, axis


# -- point 2: the sum keeps the maxima -------------------------------------------------------

def test_superposition_on_an_axis_at_maximum_velocity_cannot_speed_it_up() -> None:
    """Issue 19 point 2, D-180: cruising at the maximum 500 mm/s, move_superimposed(50, 400,
    500, 1000) used to reach 815 mm/s. There is no velocity reserve: the command reports
    0x4243 (nothing of the distance fits, TcMC §3.9 note) and the axis stays at 500 mm/s."""
    rt, axis = cruising_at_maximum()
    command = axis.move_superimposed(50.0, 400.0, 500.0, 1000.0)
    assert command.error and command.error_id is E.SUPERPOSITION_INCOMPLETE
    assert "no room" in command.message
    samples = Samples()
    run(rt, axis, 2000, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert axis.set_velocity == 500.0
    slower = axis.move_superimposed(-50.0, 400.0, 500.0, 1000.0)  # falling back still works
    assert slower.busy
    rt.run_until(lambda: not slower.busy, timeout=5.0)
    assert slower.done


def test_superposition_uses_only_the_velocity_reserve() -> None:
    """D-180 (§3.11: the reserve is the maximum minus the set velocity): at 400 of 500 mm/s a
    superposition asking 400 mm/s more gets 100; the part that does not fit is 0x4243."""
    rt = om.Runtime()
    axis = rt.add_axis("x", **LIMITS)
    axis.power()
    axis.move_velocity(400.0)
    rt.run(1.0)
    command = axis.move_superimposed(200.0, 400.0, 400.0, 300.0)
    assert command.busy and command.value[0] <= 100.0 * (1 + 1e-9)
    samples = Samples()
    while command.busy:
        rt.step()
        samples.take(axis)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert command.error_id is E.SUPERPOSITION_INCOMPLETE and command.value[1] < 200.0


def test_superposition_jerk_leaves_room_for_the_base_jerk() -> None:
    """D-180: the superimposed jerk (the axis default, TcMC §3.9) is cut to what the base
    leaves below the maximum jerk; here the base accelerates with 0.99 of it."""
    rt = om.Runtime()
    axis = rt.add_axis("x", jerk=500000.0, **LIMITS)
    axis.power()
    axis.move_velocity(100.0)
    rt.run(0.5)
    axis.move_velocity(450.0, acceleration=20000.0, jerk=990000.0)
    rt.step()
    command = axis.move_superimposed(10.0, 40.0, 200.0, 400.0)
    samples = Samples()
    run(rt, axis, 600, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert command.done


# -- point 3: re-planning under a superposition is continuous ---------------------------------

def superimposed_velocity_axis() -> tuple[om.Runtime, om.Axis, om.Command]:
    rt = om.Runtime()
    axis = rt.add_axis("x", **LIMITS)
    axis.power()
    axis.set_override(50.0)
    axis.move_velocity(400.0)
    rt.run(1.0)
    command = axis.move_superimposed(50.0, 200.0, 200.0, 400.0)
    rt.run(0.05)
    assert command.busy and axis.set_velocity > 200.0
    return rt, axis, command


def test_override_change_under_a_superposition_keeps_the_setpoint_continuous() -> None:
    """Issue 19 point 3, D-180: an override change re-plans the base from the base state;
    the superposition goes on beside it. The step stays within max_acceleration * cycle and
    the sum within the maximum velocity (it used to reach 600 mm/s)."""
    rt, axis, command = superimposed_velocity_axis()
    samples = Samples()
    samples.take(axis)
    axis.set_override(100.0)
    run(rt, axis, 1500, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert command.done and axis.set_velocity == pytest.approx(400.0)


def test_blending_command_under_a_superposition_keeps_the_setpoint_continuous() -> None:
    """Issue 19 point 3, D-180: a blending command re-plans the running move from the base
    state (it used to start from base + superimposed while the superposition went on)."""
    rt = om.Runtime()
    axis = rt.add_axis("x", **LIMITS)
    axis.power()
    axis.move_absolute(2000.0, 300.0)
    rt.run(1.0)
    command = axis.move_superimposed(50.0, 200.0, 200.0, 400.0)
    rt.run(0.05)
    samples = Samples()
    samples.take(axis)
    following = axis.move_absolute(4000.0, 400.0, buffer_mode=BufferMode.BLENDING_NEXT)
    run(rt, axis, 1500, samples)
    assert command.done
    while not following.active and len(samples.rows) < 10000:  # the blend into the next move
        run(rt, axis, 1, samples)
    run(rt, axis, 100, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert following.active and axis.set_velocity == pytest.approx(400.0)


def test_feed_enable_restored_under_jog_and_superposition_does_not_jump() -> None:
    """Issue 19 point 3 (the storm case), D-180: jerk parameter 900 795, override 50, MC_Jog
    at -466.69, MoveSuperImposed(-169.37, 499.98, 92.38, 1394.43, acceleration 20 280.5),
    negative feed enable off, then back with 100 % override 114 ms later: the velocity used
    to jump from -500 to -1499 mm/s and the position by 91.9 mm in one cycle."""
    rt = om.Runtime()
    axis = rt.add_axis("x", jerk=900795.0, **LIMITS)
    power, jog = MC_Power(axis), MC_Jog(axis)
    power(enable=True, override=50.0)
    samples = Samples()
    superposition = None
    for i in range(3000):
        jog(mode=JogMode.CONTINUOUS, velocity=466.69, jog_backwards=True)
        if i == 300:
            superposition = axis.move_superimposed(-169.37, 499.98, 92.38, 1394.43,
                                                   acceleration=20280.5)
        if i == 310:
            power(enable=True, enable_negative=False, override=50.0)
        elif i == 424:
            power(enable=True, enable_negative=True, override=100.0)
        else:
            power()
        rt.step()
        samples.take(axis)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert superposition is not None and superposition.finished
    assert jog.busy and axis.set_velocity == pytest.approx(-466.69)  # the jog goes on


def test_base_capped_beside_a_superposition_gets_its_velocity_when_it_ends() -> None:
    """D-180: MC_NewPosAndVelo raises the base to 450 mm/s while a superposition adds up to
    150 mm/s on a 500 mm/s axis: the base is held at what the sum allows, and reaches 450
    mm/s once the superposition is done."""
    rt = om.Runtime()
    axis = rt.add_axis("x", **LIMITS)
    axis.power()
    axis.move_velocity(300.0)
    rt.run(1.0)
    superposition = axis.move_superimposed(100.0, 150.0, 300.0, 600.0)
    rt.run(0.05)
    change = axis.new_position_and_velocity(NewPosAndVeloMode.CHANGE_VELO, 0.0, 450.0)
    assert change.done
    samples = Samples()
    while superposition.busy:
        run(rt, axis, 1, samples)
    run(rt, axis, 500, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert superposition.done and axis.set_velocity == pytest.approx(450.0)


# -- point 4: the state matches the motion ---------------------------------------------------

def test_halt_under_a_superposition_ends_with_it() -> None:
    """Issue 19 point 4, D-181: move_velocity(100), halt(), 4 ms later
    move_superimposed(47, 200, 80, 900): the axis used to say StandStill (and the halt Done)
    for 276 cycles while still moving. It stays in DiscreteMotion until the superimposed
    motion has ended; then the halt is Done and the axis in StandStill."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    axis.move_velocity(100.0)
    rt.run(1.0)
    halt = axis.halt()
    rt.run(0.004)
    superposition = axis.move_superimposed(47.0, 200.0, 80.0, 900.0)
    assert superposition.busy
    moving_at_standstill = 0
    for _ in range(3000):
        rt.step()
        standstill = axis.state is AxisState.STANDSTILL
        moving_at_standstill += standstill and axis.set_velocity != 0.0
        assert not halt.done or not superposition.busy
    assert moving_at_standstill == 0
    assert halt.done and superposition.done and axis.state is AxisState.STANDSTILL
    assert axis.move_relative(10.0, 100.0).active  # usable afterwards


def test_gear_out_at_rest_under_a_superposition_is_not_standstill() -> None:
    """Issue 19 point 4 (found by the command storm), D-181: a slave geared to a standing
    master gets a superimposed motion, then MC_GearOut. The decoupled base is at rest, but the
    superposition still moves the axis: DiscreteMotion until it ends, then StandStill."""
    rt = om.Runtime()
    master = rt.add_axis("x")
    slave = rt.add_axis("z", acceleration=10000.0, deceleration=10000.0, jerk=10000.0)
    master.power()
    slave.power()
    assert slave.gear_in(master, 2.0).busy
    rt.run(0.1)
    superposition = slave.move_superimposed(-200.0, 880.0, 315.0, 1100.0,
                                            acceleration=4000.0, deceleration=4000.0)
    assert superposition.busy
    rt.run(0.058)
    slave.gear_out()
    samples = Samples()
    for _ in range(3000):
        rt.step()
        samples.take(slave)
        if not superposition.busy:
            break
    samples.assert_state_matches_motion()
    assert not superposition.busy and slave.state is AxisState.STANDSTILL
    assert slave.move_relative(10.0, 100.0).active  # usable afterwards


def test_position_move_is_done_only_after_the_superposition() -> None:
    """D-181: a positioning whose base profile ends just after a superposition starts
    settles only when the superimposed motion is over too, at its target shifted by the
    distance (D-041); it used to be Done (and the axis StandStill) while the superimposed
    motion had hardly begun."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    move = axis.move_absolute(100.0, 200.0)
    rt.run_until(lambda: axis.remaining_time < 0.005, timeout=5.0)
    superposition = axis.move_superimposed(30.0, 100.0, 200.0, 400.0)
    assert superposition.busy
    while not move.done:
        rt.step()
        assert axis.state is not AxisState.STANDSTILL or axis.set_velocity == 0.0
    assert superposition.done and axis.set_position == pytest.approx(130.0)


# -- point 7: geared slaves ------------------------------------------------------------------

def geared(ratio: float) -> tuple[om.Runtime, om.Axis, om.Axis, om.Command]:
    rt = om.Runtime()
    master, slave = rt.add_axis("m"), rt.add_axis("s")
    master.power()
    slave.power()
    coupling = slave.gear_in(master, ratio)
    return rt, master, slave, coupling


def test_slave_jerk_beyond_its_maximum_is_a_gear_fault_before_it_is_output() -> None:
    """Issue 19 point 7, D-182: ratio 2 on a master jerking at 1e6 would give the slave 2e6
    against its maximum 1e6; the slave faults (GEAR_LIMIT_EXCEEDED) and no sample beyond its
    maxima is ever output; the master goes on."""
    rt, master, slave, coupling = geared(2.0)
    master.move_velocity(800.0, acceleration=20000.0, jerk=1.0e6)
    samples = Samples()
    run(rt, slave, 300, samples)
    samples.assert_within(1000.0, 20000.0, 1.0e6)
    assert slave.state is AxisState.ERROR_STOP
    assert slave.axis_error_id is E.GEAR_LIMIT_EXCEEDED and coupling.aborted
    assert master.set_velocity == pytest.approx(800.0)
    reset = slave.reset()
    rt.run_until(reset, timeout=1.0)
    assert reset.done and slave.state is AxisState.STANDSTILL


def test_slave_of_a_master_powered_off_brakes_on_its_own() -> None:
    """Found by the command storm (issue 19: a state change never moves the setpoint by more
    than the limits allow), D-199: the master's setpoint freezes when it is powered off
    (D-019); its geared slave used to follow it, stopping dead from 667 mm/s in one cycle.
    It goes to ErrorStop MASTER_DISABLED and brakes with its own maxima."""
    rt = om.Runtime()
    master, slave = rt.add_axis("x", **LIMITS), rt.add_axis("z", **LIMITS)
    master.power()
    slave.power()
    gear = slave.gear_in(master, -2.0 / 3.0)
    rt.run(0.1)
    master.move_velocity(450.0)
    rt.run(1.0)
    assert slave.set_velocity == pytest.approx(-300.0)
    samples = Samples()
    samples.take(slave)
    master.power(False)
    run(rt, slave, 200, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert gear.aborted and slave.state is AxisState.ERROR_STOP
    assert slave.axis_error_id == E.MASTER_DISABLED
    assert slave.set_velocity == 0.0
    reset = slave.reset()
    rt.step()
    assert reset.done and slave.state is AxisState.STANDSTILL
    assert slave.move_relative(10.0, 100.0).active  # usable afterwards


def test_chained_slave_follows_its_master_in_the_same_cycle() -> None:
    """Found by the command storm (issue 19: a state change never moves the setpoint by more
    than the limits allow): y geared to u before u was geared to x followed u's previous
    sample (the couplings were applied in the order they were made), and jumped by that
    cycle's lag (200 mm/s here) when u was stopped. Masters are applied before slaves (D-185)."""
    rt = om.Runtime()
    x, u, y = (rt.add_axis(name, **LIMITS) for name in "xuy")
    for axis in (x, u, y):
        axis.power()
    y.gear_in(u, 1.0)
    rt.step()
    u.gear_in(x, 2.0)
    rt.run(0.1)
    x.move_velocity(100.0)
    samples = Samples()
    for _ in range(300):
        rt.step()
        samples.take(y)
        assert y.set_position == u.set_position
    u.stop()
    run(rt, y, 300, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert u.set_velocity == y.set_velocity == 0.0


def test_slave_of_a_superimposed_slave_follows_its_whole_setpoint() -> None:
    """Found by the command storm (seed 1, operation 84630), D-185: u geared to m carries a
    superimposed motion and x is geared to u. x followed u without the superimposed part and
    jumped by it when the superposition was folded into u's base (a position step of 0.02 mm
    and 900 mm/s² in one cycle). Each slave in a chain now gets its superimposed motion before
    its own slaves are set."""
    rt = om.Runtime()
    m, u, x = (rt.add_axis(name, **LIMITS) for name in "mux")
    for axis in (m, u, x):
        axis.power()
    u.gear_in(m, 1.0)
    x.gear_in(u, 2.0)
    rt.step()
    assert u.move_superimposed(-14.6, 600.0, 1.0, 1500.0).busy
    samples = Samples()
    for _ in range(10):
        rt.step()
        samples.take(x)
        assert x.set_velocity == 2.0 * u.set_velocity and x.set_velocity != 0.0
    u.move_velocity(250.0, direction=Direction.NEGATIVE)  # folds the superposition
    run(rt, x, 300, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)


def test_error_reaction_under_a_superposition_keeps_the_acceleration() -> None:
    """Found by the command storm (seed 19, operation 39070): a following error while a
    superposition ran handed the error reaction the combined state without its acceleration,
    so the acceleration stepped by 1015 mm/s² in one cycle where the maximum jerk allows
    1000. The base now takes the whole state over, acceleration included."""
    rt = om.Runtime(0.001)
    u = rt.add_axis("u", position=-163.26055674083227, max_velocity=800.0,
                    max_position_lag=2.0,
                    drive=om.DriveModel(model="lag", time_constant=0.002, dead_time=0.001))
    power = MC_Power(u, enable=True)
    move, velocity = MC_MoveAbsolute(u), MC_MoveVelocity(u)
    override, superimposed = MC_SetOverride(u), MC_MoveSuperImposed(u)
    calls = {
        3: (move, dict(execute=True, position=-1176.3515524080658, velocity=1e-06,
                       jerk=5763.562890497276, buffer_mode=BufferMode.BUFFERED)),
        185: (override, dict(execute=True, override=60.84471613563194)),
        506: (velocity, dict(execute=True, velocity=929.0789183491115,
                             direction=Direction.CURRENT, jerk=85431.41930169753)),
        681: (superimposed, dict(execute=True, distance=-278.65480561343384,
                                 velocity_diff=462.2269630730124,
                                 velocity_process=486.75772908505553,
                                 max_distance=848.0900889736932,
                                 acceleration=16683.980157336486,
                                 deceleration=12971.95074673476)),
    }
    samples = Samples()
    for cycle in range(1, 900):
        power()
        for block in (move, velocity, override, superimposed):
            block(**(calls[cycle][1] if calls.get(cycle, (None,))[0] is block else {}))
        rt.step()
        samples.take(u)
    assert u.axis_error_id == E.FOLLOWING_ERROR  # the fault this case is about
    a = samples.column(2)
    assert np.abs(np.diff(a)).max() <= u.parameters.max_jerk * CYCLE * (1.0 + TOLERANCE)


def test_slave_velocity_fault_comes_in_time_to_brake_within_the_maxima() -> None:
    """Issue 19 point 7, D-182 (D-039 faulted one cycle late, past the maximum): the slave
    faults while braking with its maximum deceleration and jerk still stays within its
    maximum velocity; its velocity and acceleration are continuous."""
    rt, master, slave, coupling = geared(2.0)
    master.move_velocity(800.0, acceleration=10000.0, jerk=100000.0)
    samples = Samples()
    run(rt, slave, 600, samples)
    samples.assert_within(1000.0, 20000.0, 1.0e6)
    assert slave.axis_error_id is E.GEAR_LIMIT_EXCEEDED
    assert abs(slave.set_velocity) == 0.0


# -- property: random storms on one axis ------------------------------------------------------

operations = st.one_of(
    st.tuples(st.just("velocity"), st.floats(1.0, 500.0), st.sampled_from(
        [Direction.POSITIVE, Direction.NEGATIVE]), st.floats(500.0, 20000.0),
        st.floats(1.0e4, 1.0e6)),
    st.tuples(st.just("absolute"), st.floats(-2000.0, 2000.0), st.floats(1.0, 500.0),
              st.sampled_from([BufferMode.ABORTING, BufferMode.BUFFERED,
                               BufferMode.BLENDING_NEXT, BufferMode.BLENDING_HIGH])),
    st.tuples(st.just("superimposed"), st.floats(-200.0, 200.0).filter(lambda d: abs(d) > 0.1),
              st.floats(1.0, 1000.0), st.floats(10.0, 1000.0), st.floats(10.0, 2000.0),
              st.floats(0.0, 25000.0)),
    st.tuples(st.just("override"), st.floats(0.0, 100.0)),
    st.tuples(st.just("feed"), st.booleans(), st.booleans()),
    st.tuples(st.just("abort_superposition")),
    st.tuples(st.just("halt")),
    st.tuples(st.just("new_velocity"), st.floats(1.0, 500.0)),
    st.tuples(st.just("dynamics"), st.floats(500.0, 20000.0), st.floats(1.0e4, 1.0e6)),
    st.tuples(st.just("run"), st.integers(1, 300)),
)


def apply(axis: om.Axis, operation: tuple) -> None:
    kind, *values = operation
    if kind == "velocity":
        velocity, direction, acceleration, jerk = values
        axis.move_velocity(velocity, direction, acceleration, acceleration, jerk)
    elif kind == "absolute":
        position, velocity, mode = values
        axis.move_absolute(position, velocity, buffer_mode=mode)
    elif kind == "superimposed":
        distance, velocity_diff, velocity_process, length, acceleration = values
        axis.move_superimposed(distance, velocity_diff, velocity_process, length,
                               acceleration=acceleration, deceleration=acceleration)
    elif kind == "override":
        axis.set_override(values[0])
    elif kind == "feed":
        axis.power(True, enable_positive=values[0], enable_negative=values[1])
    elif kind == "abort_superposition":
        axis.abort_superposition()
    elif kind == "halt":
        axis.halt()
    elif kind == "new_velocity":
        axis.new_position_and_velocity(NewPosAndVeloMode.CHANGE_VELO, 0.0, values[0])
    elif kind == "dynamics":
        axis.change_dynamics(values[0], values[0], values[1])


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(operations, min_size=1, max_size=25), st.floats(2.0e4, 1.0e6))
def test_storm_keeps_the_maxima_and_the_velocity_continuous(program: list[tuple],
                                                            default_jerk: float) -> None:
    """Issue 19 points 2, 3 and 4, D-180, D-181: random base motion, halts, superpositions,
    override and feed-enable changes, MC_NewPosAndVelo and MC_ChangeDynParam: every cycle
    |v|, |a|, |j| within the axis maxima, no velocity step larger than max_acceleration *
    cycle, never StandStill while moving."""
    rt = om.Runtime()
    axis = rt.add_axis("x", jerk=default_jerk, **LIMITS)
    axis.power()
    samples = Samples()
    for operation in program:
        apply(axis, operation)
        cycles = operation[1] if operation[0] == "run" else 20
        run(rt, axis, cycles, samples)
    axis.power(True)
    axis.set_override(100.0)
    run(rt, axis, 400, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    samples.assert_state_matches_motion()
    assert not axis.error, axis.axis_error_message


master_operations = st.one_of(
    st.tuples(st.just("velocity"), st.floats(1.0, 500.0), st.sampled_from(
        [Direction.POSITIVE, Direction.NEGATIVE]), st.floats(500.0, 20000.0),
        st.floats(1.0e4, 1.0e6)),
    st.tuples(st.just("absolute"), st.floats(-2000.0, 2000.0), st.floats(1.0, 500.0),
              st.sampled_from([BufferMode.ABORTING, BufferMode.BLENDING_NEXT])),
    st.tuples(st.just("superimposed"), st.floats(-200.0, 200.0).filter(lambda d: abs(d) > 0.1),
              st.floats(1.0, 1000.0), st.floats(10.0, 1000.0), st.floats(10.0, 2000.0),
              st.floats(0.0, 25000.0)),
    st.tuples(st.just("override"), st.floats(0.0, 100.0)),
    st.tuples(st.just("run"), st.integers(1, 300)),
)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(master_operations, min_size=1, max_size=15),
       st.floats(-3.0, 3.0).filter(lambda r: abs(r) > 0.01), st.booleans())
def test_geared_slave_never_outputs_a_sample_beyond_its_maxima(
        program: list[tuple], ratio: float, superimpose_on_slave: bool) -> None:
    """Issue 19 point 7, D-182: whatever the master does, each sample of the slave keeps its
    maxima (master and slave have the same ones); where the coupling would break them the
    slave is in ErrorStop with GEAR_LIMIT_EXCEEDED instead."""
    rt = om.Runtime()
    master = rt.add_axis("m", **LIMITS)
    slave = rt.add_axis("s", **LIMITS)
    master.power()
    slave.power()
    coupling = slave.gear_in(master, ratio)
    samples = Samples()
    for operation in program:
        apply(master, operation)
        if superimpose_on_slave and slave.state is AxisState.SYNCHRONIZED_MOTION:
            apply(slave, ("superimposed", 20.0, 100.0, 200.0, 400.0, 0.0))
        cycles = operation[1] if operation[0] == "run" else 20
        run(rt, slave, cycles, samples)
    run(rt, slave, 300, samples)
    samples.assert_within(500.0, 20000.0, 1.0e6)
    assert coupling.active or slave.axis_error_id is E.GEAR_LIMIT_EXCEEDED
