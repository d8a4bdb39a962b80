"""Gear couplings: MC_GearIn, MC_GearInFloat, MC_GearInDyn, MC_GearOut, MC_GearOutExt
(TcMC §3.17-3.21, digest rules 84-99)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.special_values import MC_INVALID
from openmotion.plcopen import MC_MoveVelocity, MC_Stop
from openmotion.plcopen.gear import (
    MC_GearIn,
    MC_GearInDyn,
    MC_GearInFloat,
    MC_GearOut,
    MC_GearOutExt,
)

E, S, D = om.ErrorId, om.AxisState, om.DecoupleMode


def pair(**slave: float) -> tuple[om.Runtime, om.Axis, om.Axis]:
    rt = om.Runtime()
    master = rt.add_axis("m", max_velocity=2000.0)
    follower = rt.add_axis("s", **slave)
    master.power()
    follower.power()
    return rt, master, follower


def test_gear_in_one_to_three_follows_a_third_and_a_negative_numerator_reverses() -> None:
    """Rule 85 (§3.17 example 1:3): master +3 -> slave +1; numerator -1 -> slave -1."""
    for numerator, expected in ((1, 100.0), (-1, -100.0)):
        rt, master, slave = pair()
        gear = MC_GearIn(slave)
        gear(execute=True, master=master, ratio_numerator=numerator, ratio_denominator=3)
        assert gear.in_gear and slave.state is S.SYNCHRONIZED_MOTION
        move = master.move_relative(300.0, velocity=200.0)
        rt.run_until(move, 5.0)
        assert slave.set_position == pytest.approx(expected, abs=1e-9)


COUPLINGS = [
    (MC_GearIn, {"ratio_numerator": 2, "ratio_denominator": 1}),
    (MC_GearInFloat, {"gear_ratio": 2.0}),
    (MC_GearInDyn, {"gear_ratio": 2.0, "acceleration": 1000.0}),
]
COUPLING_IDS = ["MC_GearIn", "MC_GearInFloat", "MC_GearInDyn"]


@pytest.mark.parametrize("moving", ["slave", "master"])
@pytest.mark.parametrize(("cls", "ratio"), COUPLINGS, ids=COUPLING_IDS)
def test_coupling_needs_standstill_of_slave_and_master(cls: type, ratio: dict,
                                                        moving: str) -> None:
    """Rule 84, Q34 (D-039), TcMC §3.17-3.19: a moving slave or master cannot be coupled
    (the flying saw is separate): Error, no InGear, and the slave does not follow."""
    rt, master, slave = pair()
    (slave if moving == "slave" else master).move_velocity(50.0)
    rt.run(0.1)
    gear = cls(slave)
    gear(execute=True, master=master, **ratio)
    assert gear.error and gear.error_id == E.AXIS_NOT_STANDSTILL
    assert not gear.in_gear and not gear.busy
    assert slave.state is not S.SYNCHRONIZED_MOTION
    before = slave.set_position
    master_before = master.set_position
    rt.run(0.5)
    slave_travel = slave.set_position - before
    master_travel = master.set_position - master_before
    assert slave_travel == pytest.approx(25.0 if moving == "slave" else 0.0, abs=1e-9)
    assert master_travel == pytest.approx(0.0 if moving == "slave" else 25.0, abs=1e-9)


@pytest.mark.parametrize(("numerator", "denominator"), [(1, 0), (1, -2), (1.5, 2), (True, 1)])
def test_bad_ratios_are_errors(numerator: object, denominator: object) -> None:
    """Rule 86: denominator 0 (and non-integers for INT/UINT) -> error, no coupling."""
    rt, master, slave = pair()
    gear = MC_GearIn(slave)
    gear(execute=True, master=master, ratio_numerator=numerator, ratio_denominator=denominator)
    assert gear.error and gear.error_id == E.INVALID_GEAR_RATIO
    assert slave.state is S.STANDSTILL


def test_float_ratio_nan_is_an_error_and_the_master_must_be_an_axis() -> None:
    rt, master, slave = pair()
    gear = MC_GearInFloat(slave)
    gear(execute=True, master=master, gear_ratio=math.nan)
    assert gear.error and gear.error_id == E.INVALID_GEAR_RATIO
    gear = MC_GearInFloat(slave)
    gear(execute=True, master=None, gear_ratio=1.0)
    assert gear.error and gear.error_id == E.INVALID_MODE


@pytest.mark.parametrize(("cls", "ratio"), [
    (MC_GearIn, {"ratio_numerator": 1, "ratio_denominator": 2}),
    (MC_GearInFloat, {"gear_ratio": 0.5}),
], ids=["MC_GearIn", "MC_GearInFloat"])
def test_dynamics_inputs_of_gear_in_have_no_effect(cls: type, ratio: dict) -> None:
    """Rule 87, TcMC §3.17, §3.18: Acceleration, Deceleration and Jerk are not used."""
    traces = []
    for dyn in (0.0, 1.0, 1e6):
        rt, master, slave = pair()
        cls(slave)(execute=True, master=master, acceleration=dyn, deceleration=dyn, jerk=dyn,
                   **ratio)
        master.move_absolute(100.0, velocity=300.0)
        samples = []
        for _ in range(600):
            rt.step()
            samples.append((slave.set_position, slave.set_velocity, slave.set_acceleration))
        traces.append(samples)
    assert traces[0] == traces[1] == traces[2]
    assert traces[0][-1][0] == pytest.approx(50.0, abs=1e-9)  # ratio 1/2 of the 100 mm


@given(ratio=st.floats(-4.0, 4.0).filter(lambda r: abs(r) > 1e-3),
       target=st.floats(-500.0, 500.0), start=st.floats(-100.0, 100.0))
def test_slave_equals_ratio_times_master_plus_offset(ratio: float, target: float,
                                                     start: float) -> None:
    """Rule 88 (property): once InGear, slave = ratio * master + offset within 1e-9, every
    cycle, with velocity and acceleration scaled alike."""
    rt = om.Runtime()
    master = rt.add_axis("m", max_velocity=2000.0, position=10.0)
    slave = rt.add_axis("s", max_velocity=1e4, max_acceleration=1e6, max_deceleration=1e6,
                        position=start)
    master.power()
    slave.power()
    gear = slave.gear_in(master, ratio)
    assert gear.active
    offset = start - ratio * 10.0
    master.move_absolute(target, velocity=400.0)
    for _ in range(1500):
        rt.step()
        assert slave.set_position == pytest.approx(ratio * master.set_position + offset,
                                                   abs=1e-9 * max(1.0, abs(master.set_position)))
        assert slave.set_velocity == pytest.approx(ratio * master.set_velocity, abs=1e-9)


def test_gear_in_dyn_takes_new_ratios_with_limited_acceleration() -> None:
    """Rules 89, 90: a new ratio applies from the next cycle; the ratio slews at
    Acceleration / master max velocity, so the slave's acceleration from the change is at most
    Acceleration at the master's maximum velocity; the slave position stays continuous."""
    rt, master, slave = pair(max_velocity=5000.0, max_acceleration=1e5, max_deceleration=1e5)
    gear = MC_GearInDyn(slave)
    gear(execute=True, master=master, gear_ratio=1.0, acceleration=2000.0)
    master.move_velocity(2000.0)  # the master's maximum velocity
    rt.run_until(lambda: master.set_velocity == 2000.0, 5.0)
    previous = slave.set_position
    accelerations = []
    for _ in range(1500):
        gear(execute=True, gear_ratio=2.0)
        rt.step()
        accelerations.append(slave.set_acceleration)
        assert abs(slave.set_position - previous) <= 2.0 * 2000.0 * 0.001 * (1 + 1e-9) + 1e-9
        previous = slave.set_position
    assert slave.set_velocity == pytest.approx(4000.0)
    assert max(accelerations) == pytest.approx(2000.0, rel=1e-6)  # 1 ratio/s * 2000 mm/s
    assert gear.in_gear


@pytest.mark.parametrize("master_velocity", [500.0, 1000.0, 2000.0])
def test_gear_in_dyn_acceleration_limit_scales_with_the_master_velocity(
        master_velocity: float) -> None:
    """Rule 90, TcMC §3.19: "the maximum acceleration will be reached when the master is
    moving at its maximum velocity; the slave acceleration may be lower if the master is
    moving at slower speed". The ratio slews at Acceleration / master max velocity (D-039),
    so a ratio step 1 -> 2 with the master at v takes 1 s at any v and accelerates the
    slave at Acceleration * v / v_max (master max velocity 2000 mm/s)."""
    rt, master, slave = pair(max_velocity=5000.0, max_acceleration=1e5, max_deceleration=1e5)
    gear = MC_GearInDyn(slave)
    gear(execute=True, master=master, gear_ratio=1.0, acceleration=2000.0)
    master.move_velocity(master_velocity)
    rt.run_until(lambda: master.set_velocity == master_velocity, 5.0)
    accelerations = []
    for _ in range(1500):
        gear(execute=True, gear_ratio=2.0)
        rt.step()
        accelerations.append(slave.set_acceleration)
    limit = 2000.0 * master_velocity / 2000.0
    assert max(accelerations) == pytest.approx(limit, rel=1e-9)
    slewing = sum(1 for a in accelerations if a > 0.0)
    assert slewing == pytest.approx(1000, abs=2)  # 1 s at 1 ratio/s, whatever the master speed
    assert slave.set_velocity == pytest.approx(2.0 * master_velocity, rel=1e-9)
    assert gear.in_gear


def test_gear_in_dyn_finishes_on_the_falling_edge_and_the_coupling_stays() -> None:
    """Issue 20 point 2, TcMC §3.19 ("the command finishes its execution after a falling
    edge"; Busy falls when the block has finished), D-196: Busy and InGear fall with Execute;
    the slave stays coupled at the last ratio and follows the master."""
    rt, master, slave = pair(max_velocity=5000.0)
    gear = MC_GearInDyn(slave)
    gear(execute=True, master=master, gear_ratio=1.5)
    assert gear.busy and gear.in_gear
    master.move_velocity(400.0)
    rt.run(0.5)
    gear(execute=False)
    assert not gear.busy and not gear.in_gear and not gear.error and not gear.command_aborted
    for _ in range(3000):
        rt.step()
        gear(execute=False)
        assert not gear.busy and not gear.in_gear
    assert slave.state is om.AxisState.SYNCHRONIZED_MOTION
    assert slave.set_velocity == pytest.approx(1.5 * master.set_velocity)


def test_gear_in_dyn_new_edge_takes_the_running_coupling_over() -> None:
    """Issue 20 point 2, TcMC §3.19, D-196: a rising edge on a slave still coupled to the same
    master (both moving) used to fail with AXIS_NOT_STANDSTILL and drop InGear. It takes the
    coupling over: InGear again and the ratio follows the input; a bad ratio on that edge is
    an error that leaves the coupling as it was, and the next edge works."""
    rt, master, slave = pair(max_velocity=5000.0)
    gear = MC_GearInDyn(slave)
    gear(execute=True, master=master, gear_ratio=1.0, acceleration=2000.0)
    master.move_velocity(400.0)
    rt.run(0.5)
    gear(execute=False)
    gear(execute=True, gear_ratio=float("nan"))
    assert gear.error and gear.error_id == om.ErrorId.INVALID_GEAR_RATIO
    rt.step()
    assert slave.state is om.AxisState.SYNCHRONIZED_MOTION
    assert slave.set_velocity == pytest.approx(400.0)
    gear(execute=False)
    gear(execute=True, gear_ratio=2.0)
    assert gear.busy and gear.in_gear and not gear.error
    for _ in range(2000):
        rt.step()
        gear(execute=True, gear_ratio=2.0)
    assert gear.in_gear and slave.set_velocity == pytest.approx(800.0)


def test_gear_in_dyn_new_edge_with_another_master_needs_standstill() -> None:
    """TcMC §3.19 note: coupling (to another master) only at standstill; the running coupling
    is not touched by the refused edge (D-196)."""
    rt, master, slave = pair(max_velocity=5000.0)
    other = rt.add_axis("o")
    other.power()
    gear = MC_GearInDyn(slave)
    gear(execute=True, master=master, gear_ratio=1.0)
    master.move_velocity(400.0)
    rt.run(0.5)
    gear(execute=False)
    gear(execute=True, master=other, gear_ratio=1.0)
    assert gear.error and gear.error_id == om.ErrorId.AXIS_NOT_STANDSTILL
    rt.step()
    assert slave.state is om.AxisState.SYNCHRONIZED_MOTION
    assert slave.set_velocity == pytest.approx(master.set_velocity)


@pytest.mark.parametrize("block, inputs", COUPLINGS, ids=COUPLING_IDS)
def test_a_coupling_loop_is_refused(block: type, inputs: dict) -> None:
    """D-191 (found by the command storm): a master that follows the slave, directly or
    through another coupling, is refused with COUPLING_LOOP; the couplings in force stay and
    the slave can still be coupled to another master."""
    rt, master, slave = pair()
    third = rt.add_axis("t")
    third.power()
    MC_GearInFloat(slave)(execute=True, master=master, gear_ratio=2.0)
    MC_GearInFloat(third)(execute=True, master=slave, gear_ratio=1.0)
    for looping_master in (slave, third):
        gear = block(master)
        gear(execute=True, master=looping_master, **inputs)
        assert gear.error and gear.error_id == om.ErrorId.COUPLING_LOOP, gear.message
    assert master.state is om.AxisState.STANDSTILL
    master.move_velocity(100.0)
    rt.run(0.5)
    assert third.set_velocity == slave.set_velocity == pytest.approx(2.0 * master.set_velocity)
    free = rt.add_axis("f")
    free.power()
    other = rt.add_axis("o")
    other.power()
    gear = block(free)
    gear(execute=True, master=other, **inputs)
    assert gear.busy and gear.in_gear  # usable afterwards


def test_decoupling_a_dynamic_coupling_while_execute_is_true_aborts_it() -> None:
    """Rule 91."""
    rt, master, slave = pair()
    gear = MC_GearInDyn(slave)
    gear(execute=True, master=master, gear_ratio=1.0)
    out = MC_GearOut(slave)
    out(execute=True)
    gear(execute=True)
    assert out.done and gear.command_aborted and not gear.in_gear


def test_gear_out_in_motion_cruises_at_constant_velocity_in_continuous_motion() -> None:
    """Rule 92: no stop, no target; acceleration released, then constant velocity."""
    rt, master, slave = pair()
    MC_GearInFloat(slave)(execute=True, master=master, gear_ratio=0.5)
    master.move_velocity(400.0)
    rt.run(0.06)  # the master still accelerates
    assert slave.set_acceleration > 0.0
    out = MC_GearOut(slave)
    out(execute=True)
    assert out.done
    rt.run(0.5)
    velocity = slave.set_velocity
    rt.run(1.0)
    assert slave.set_velocity == velocity and slave.set_acceleration == 0.0
    assert slave.state is S.CONTINUOUS_MOTION
    master.stop()
    rt.run(1.0)
    assert slave.set_velocity == velocity  # decoupled for good
    stop = MC_Stop(slave)
    stop(execute=True)
    rt.run(1.0)
    assert slave.set_velocity == 0.0


def test_gear_out_of_an_uncoupled_axis_is_an_error() -> None:
    rt, master, slave = pair()
    out = MC_GearOut(slave)
    out(execute=True)
    assert out.error and out.error_id == E.NOT_COUPLED


def coupled_in_motion() -> tuple[om.Runtime, om.Axis, om.Axis]:
    rt, master, slave = pair()
    MC_GearInFloat(slave)(execute=True, master=master, gear_ratio=1.0)
    master.move_velocity(200.0)
    rt.run(0.5)
    return rt, master, slave


def finish(rt: om.Runtime, fb: MC_GearOutExt, cycles: int = 20000) -> None:
    for _ in range(cycles):
        if fb.done or fb.error:
            return
        rt.step()
        fb(execute=True)


def test_gear_out_ext_at_standstill_only_decouples() -> None:
    """Rule 93."""
    rt, master, slave = pair()
    MC_GearInFloat(slave)(execute=True, master=master, gear_ratio=1.0)
    out = MC_GearOutExt(slave)
    out(execute=True, mode=D.NEW_POSITION, position=50.0)
    assert out.done and slave.state is S.STANDSTILL and slave.set_position == 0.0
    master.move_absolute(100.0, velocity=100.0)
    rt.run(2.0)
    assert slave.set_position == 0.0


@pytest.mark.parametrize("mode", [D.NEW_POSITION, D.NEW_POSITION_AND_VELOCITY])
def test_gear_out_ext_to_a_position(mode: om.DecoupleMode) -> None:
    """Rules 94, 99: stops at Position; Done only there."""
    rt, master, slave = coupled_in_motion()
    out = MC_GearOutExt(slave)
    out(execute=True, mode=mode, position=500.0, velocity=300.0)
    assert out.busy and not out.done
    finish(rt, out)
    assert out.done and slave.set_position == 500.0 and slave.set_velocity == 0.0


@pytest.mark.parametrize("velocity", [120.0, 300.0])
def test_gear_out_ext_new_position_and_velocity_travels_at_velocity(velocity: float) -> None:
    """Rule 99, TcMC §3.21 MC_DECOUPLEMODE_NEWPOSANDVELO: after decoupling at 200 mm/s the
    slave moves at the Velocity input (slower or faster than at decoupling) and stops at
    Position; MC_DECOUPLEMODE_NEWPOS instead keeps the decoupling velocity."""
    for mode, plateau in ((D.NEW_POSITION_AND_VELOCITY, velocity), (D.NEW_POSITION, 200.0)):
        rt, master, slave = coupled_in_motion()
        out = MC_GearOutExt(slave)
        out(execute=True, mode=mode, position=500.0, velocity=velocity)
        velocities = []
        while not (out.done or out.error):
            rt.step()
            out(execute=True)
            velocities.append(slave.set_velocity)
        assert out.done and slave.set_position == 500.0
        cruising = [v for v in velocities if v == pytest.approx(plateau, abs=1e-9)]
        assert len(cruising) > 100, mode  # a plateau of at least 0.1 s
        assert max(velocities) <= max(plateau, 200.0) * (1 + 1e-9)


def _gear_out_ext_trace(**dynamics: float) -> list[tuple[float, float, float]]:
    rt, master, slave = pair(acceleration=1000.0, deceleration=1500.0, jerk=20000.0)
    MC_GearInFloat(slave)(execute=True, master=master, gear_ratio=1.0)
    master.move_velocity(200.0)
    rt.run(0.5)
    out = MC_GearOutExt(slave)
    out(execute=True, mode=D.NEW_POSITION_AND_VELOCITY, position=600.0, velocity=400.0,
        **dynamics)
    samples = []
    while not (out.done or out.error):
        rt.step()
        out(execute=True)
        samples.append((slave.set_position, slave.set_velocity, slave.set_acceleration))
    assert out.done and slave.set_position == 600.0
    return samples


def test_gear_out_ext_zero_dynamics_mean_the_axis_defaults() -> None:
    """Rule 9, TcMC §3.21: Acceleration/Deceleration/Jerk = 0 use the slave's AxisAcc,
    AxisDec, AxisJerk (1004-1006) for the follow-up, the same profile as given explicitly."""
    zero = _gear_out_ext_trace(acceleration=0.0, deceleration=0.0, jerk=0.0)
    accelerations = [a for _, _, a in zero]
    assert max(accelerations) == pytest.approx(1000.0, rel=1e-9)
    assert min(accelerations) == pytest.approx(-1500.0, rel=1e-9)
    jerk = max(abs(b - a) for a, b in zip(accelerations, accelerations[1:], strict=False))
    assert jerk / 0.001 == pytest.approx(20000.0, rel=1e-3)
    assert zero == _gear_out_ext_trace(acceleration=1000.0, deceleration=1500.0, jerk=20000.0)


@pytest.mark.parametrize("velocity", [0.0, -50.0])
@pytest.mark.parametrize("mode", [D.ENDLESS_NEW_VELOCITY, D.NEW_POSITION_AND_VELOCITY])
def test_gear_out_ext_velocity_not_above_zero_is_an_error(mode: om.DecoupleMode,
                                                          velocity: float) -> None:
    """Rule 10, TcMC §3.21 "Velocity: maximum travel velocity (>0)": Error with
    INVALID_VELOCITY, no Done, and the command is refused as a whole: the slave stays coupled
    and follows the master, also when the master stops."""
    rt, master, slave = coupled_in_motion()
    out = MC_GearOutExt(slave)
    out(execute=True, mode=mode, position=500.0, velocity=velocity)
    assert out.error and out.error_id == E.INVALID_VELOCITY
    assert not out.done and not out.busy
    assert slave.state is S.SYNCHRONIZED_MOTION
    for _ in range(500):
        rt.step()
        out(execute=True)
        assert slave.set_velocity == pytest.approx(200.0, abs=1e-9)
    offset = slave.set_position - master.set_position
    master.stop()
    rt.run(1.0)
    out(execute=True)
    assert out.error and not out.done
    assert slave.state is S.SYNCHRONIZED_MOTION
    assert master.set_velocity == slave.set_velocity == 0.0
    assert slave.set_position - master.set_position == pytest.approx(offset, abs=1e-9)


@pytest.mark.parametrize(("mode", "position", "error"), [
    (D.NEW_POSITION, MC_INVALID, E.INVALID_POSITION),
    (D.ORIENTED_STOP, 400.0, E.INVALID_MODULO_TARGET),
])
def test_gear_out_ext_bad_position_leaves_the_slave_coupled(mode: om.DecoupleMode,
                                                            position: object,
                                                            error: om.ErrorId) -> None:
    """A follow-up input the follow-up would refuse refuses MC_GearOutExt as a whole."""
    rt, master, slave = coupled_in_motion()
    out = MC_GearOutExt(slave)
    out(execute=True, mode=mode, position=position)
    assert out.error and out.error_id == error
    assert slave.state is S.SYNCHRONIZED_MOTION
    master.stop()
    rt.run(1.0)
    assert slave.set_velocity == 0.0 and slave.state is S.SYNCHRONIZED_MOTION


def test_gear_out_ext_endless_keeps_the_velocity() -> None:
    """Rule 95."""
    rt, master, slave = coupled_in_motion()
    out = MC_GearOutExt(slave)
    out(execute=True, mode=D.ENDLESS)
    finish(rt, out)
    assert out.done and slave.set_velocity == pytest.approx(200.0)
    master.stop()
    rt.run(1.0)
    assert slave.set_velocity == pytest.approx(200.0)


def test_gear_out_ext_endless_new_velocity() -> None:
    """Rule 96."""
    rt, master, slave = coupled_in_motion()
    out = MC_GearOutExt(slave)
    out(execute=True, mode=D.ENDLESS_NEW_VELOCITY, velocity=350.0)
    finish(rt, out)
    assert out.done and slave.set_velocity == 350.0


def test_gear_out_ext_instantaneous_stop() -> None:
    """Rule 97: the set velocity jumps to zero in one cycle."""
    rt, master, slave = coupled_in_motion()
    out = MC_GearOutExt(slave)
    out(execute=True, mode=D.INSTANTANEOUS_STOP)
    rt.step()
    assert out.done and slave.set_velocity == 0.0 and slave.state is S.STANDSTILL


def test_gear_out_ext_oriented_stop() -> None:
    """Rule 98."""
    rt, master, slave = coupled_in_motion()
    out = MC_GearOutExt(slave)
    out(execute=True, mode=D.ORIENTED_STOP, position=90.0)
    finish(rt, out)
    assert out.done and slave.set_position % 360.0 == pytest.approx(90.0, abs=1e-9)


def test_a_move_on_the_slave_aborts_the_coupling_without_a_jump() -> None:
    rt, master, slave = coupled_in_motion()
    gear_command = slave.active_command
    before = (slave.set_position, slave.set_velocity)
    move = MC_MoveVelocity(slave)
    move(execute=True, velocity=50.0)
    assert gear_command.aborted
    rt.step()
    assert abs(slave.set_position - before[0]) <= 0.2 + 1e-9
    assert abs(slave.set_velocity - before[1]) <= 5000.0 * 0.001 * (1 + 1e-9)


def test_a_slave_beyond_its_limits_is_an_axis_error() -> None:
    """§3.17 ff: the slave's limits are respected; a violation is an error (D-039)."""
    rt, master, slave = pair(max_velocity=100.0)
    gear = MC_GearInFloat(slave)
    gear(execute=True, master=master, gear_ratio=2.0)
    master.move_velocity(100.0)
    rt.run(1.0)
    gear(execute=True)
    assert slave.state is S.ERROR_STOP and slave.axis_error_id == E.GEAR_LIMIT_EXCEEDED
    assert gear.command_aborted
    assert abs(slave.set_velocity) < 200.0
