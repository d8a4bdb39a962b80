"""MC_Jog (TcMC §3.13; digest rules 54-63, open question Q16).

Every test runs like a PLC program: the block is called once per cycle, then ``rt.step()``.
Default axis: manual slow 100 mm/s (1010), manual fast 500 mm/s (1009), acceleration /
deceleration 5000 mm/s², jerk 50000 mm/s³.
"""

from __future__ import annotations

from typing import Any

import pytest

import openmotion as om
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.plcopen import MC_MoveAbsolute, MC_Stop
from openmotion.plcopen.jog import JogMode, MC_Jog

ErrorId = om.ErrorId
S = om.AxisState
POS, NEG = om.Direction.POSITIVE, om.Direction.NEGATIVE


@pytest.fixture(autouse=True)
def _strict(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(MC_Jog, "strict", True)


def setup(**overrides: Any) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x", **overrides)
    assert axis.power()
    return rt, axis


def cycle(rt: om.Runtime, jog: MC_Jog, n: int = 1, **inputs: Any) -> None:
    """Call the block with ``inputs`` and step, ``n`` times."""
    for _ in range(n):
        jog(**inputs)
        rt.step()


def until_idle(rt: om.Runtime, jog: MC_Jog, max_cycles: int = 5000, **inputs: Any) -> int:
    """Call and step until ``busy`` is FALSE after a call; return the cycles used."""
    for n in range(1, max_cycles):
        jog(**inputs)
        if not jog.busy:
            return n
        rt.step()
    raise AssertionError("MC_Jog stayed busy")


# -- E_JogMode ------------------------------------------------------------------------------


def test_jog_mode_values_and_beckhoff_alias() -> None:
    assert [int(m) for m in JogMode] == [0, 1, 2, 3]
    assert JogMode.CONTINOUS is JogMode.CONTINUOUS
    assert JogMode["CONTINOUS"] is JogMode(2)


# -- rules 54 / 55: direction from the edge, forward priority -------------------------------


def test_rule54_forward_edge_moves_positive() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.STANDARD_SLOW)
    cycle(rt, jog, 300, jog_forward=True)
    jog(jog_forward=True)
    assert x.set_velocity == pytest.approx(100.0)
    assert x.state is S.CONTINUOUS_MOTION
    assert jog.busy and jog.active and not jog.done


def test_rule54_backwards_edge_moves_negative() -> None:
    rt, x = setup()
    jog = MC_Jog(x)
    cycle(rt, jog, 300, jog_backwards=True)
    assert x.set_velocity == pytest.approx(-100.0)
    assert x.set_position < -15.0


def test_rule55_simultaneous_edges_forward_wins() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.CONTINUOUS, velocity=50.0)
    cycle(rt, jog, 300, jog_forward=True, jog_backwards=True)
    assert x.set_velocity == pytest.approx(50.0)
    # releasing forward while backwards stays TRUE brakes; backwards had no accepted edge
    until_idle(rt, jog, jog_forward=False, jog_backwards=True)
    assert jog.done and x.set_velocity == 0.0
    cycle(rt, jog, 100, jog_forward=False, jog_backwards=True)
    assert x.set_velocity == 0.0 and x.state is S.STANDSTILL


def test_rule55_inching_forward_wins() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=3.0, velocity=100.0)
    until_idle(rt, jog, jog_forward=True, jog_backwards=True)
    assert jog.done and x.set_position == pytest.approx(3.0, abs=1e-9)


# -- rule 56: edges ignored while busy -------------------------------------------------------


def test_rule56_backwards_edges_while_jogging_forward_are_ignored() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.STANDARD_SLOW)
    cycle(rt, jog, 200, jog_forward=True)
    for _ in range(5):  # pulses on the other key: no reversal, no restart
        cycle(rt, jog, 10, jog_forward=True, jog_backwards=True)
        cycle(rt, jog, 10, jog_forward=True, jog_backwards=False)
        assert x.set_velocity == pytest.approx(100.0)
        assert jog.busy and jog.command is not None and jog.command.kind == "move_velocity"


def test_rule56_repress_during_braking_is_ignored() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.STANDARD_FAST)
    cycle(rt, jog, 300, jog_forward=True)
    cycle(rt, jog, 5, jog_forward=False)  # braking starts
    assert jog.busy and x.state is S.DISCRETE_MOTION
    n = until_idle(rt, jog, jog_forward=True)  # pressed again while braking
    assert n > 1 and jog.done and x.set_velocity == 0.0
    cycle(rt, jog, 100, jog_forward=True)  # no new edge: the axis stays at rest
    assert x.set_velocity == 0.0 and x.state is S.STANDSTILL and not jog.busy
    assert jog.done  # the key that started the jog is TRUE again: Done persists


def test_rule56_edge_in_the_call_that_ends_busy_is_ignored() -> None:
    """The gate is the Busy the program saw: an edge while Busy was TRUE is lost."""
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=1.0, velocity=100.0)
    jog(jog_forward=True)
    rt.step()
    for _ in range(5000):
        jog(jog_forward=False)
        assert jog.busy
        rt.step()
        if not x.has_job and x.state is S.STANDSTILL:  # done is due in the next call
            break
    jog(jog_forward=True)  # an edge in the call that reports Done
    assert jog.done and not jog.busy
    cycle(rt, jog, 200, jog_forward=True)
    assert x.set_position == pytest.approx(1.0, abs=1e-9)


# -- rules 57 / 58: standard modes use 1010 / 1009 and the axis defaults -----------------------


@pytest.mark.parametrize(("mode", "number", "alias"), [
    (JogMode.STANDARD_SLOW, 1010, 1001),
    (JogMode.STANDARD_FAST, 1009, 1002),
])
def test_rules57_58_standard_velocity_and_default_dynamics(mode: JogMode, number: int,
                                                           alias: int) -> None:
    rt = om.Runtime()
    x = rt.add_axis("x")
    ref = rt.add_axis("ref")
    assert x.power() and ref.power()
    x.write_parameter(number, 40.0)
    assert x.read_parameter(alias) == 40.0  # Q16: the TcMC aliases are the same parameter
    # FB velocity, dynamics and step have no effect in the standard modes
    jog = MC_Jog(x, mode=mode, velocity=-999.0, acceleration=1.0, deceleration=1.0, jerk=1.0,
                 position=5.0)
    dones = 0
    for n in range(400):
        jog(jog_forward=n < 200)
        dones += jog.done
        if n == 0:
            ref.move_velocity(40.0, POS)  # axis-default dynamics
        if n == 200:
            ref.halt()
        assert x.set_velocity == ref.set_velocity
        assert x.set_position == ref.set_position
        rt.step()
    assert x.set_velocity == 0.0 and dones == 1 and not jog.busy
    assert x.set_position == ref.set_position > 7.0
    assert not jog.error


def test_rule57_slow_default_parameter_value() -> None:
    rt, x = setup(manual_velocity_slow=25.0, manual_velocity_fast=250.0)
    slow = MC_Jog(x, mode=JogMode.STANDARD_SLOW)
    cycle(rt, slow, 300, jog_backwards=True)
    assert x.set_velocity == pytest.approx(-25.0)
    until_idle(rt, slow, jog_backwards=False)
    fast = MC_Jog(x, mode=JogMode.STANDARD_FAST)
    cycle(rt, fast, 300, jog_forward=True)
    assert x.set_velocity == pytest.approx(250.0)


# -- rule 59: move while TRUE, brake on release, Done at rest --------------------------------


def test_rule59_release_brakes_to_rest_then_done_for_one_call() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.CONTINUOUS, velocity=200.0)
    cycle(rt, jog, 300, jog_forward=True)
    assert x.set_velocity == pytest.approx(200.0) and not jog.done
    jog(jog_forward=False)
    assert jog.busy and jog.active and x.state is S.DISCRETE_MOTION  # a halt, not a stop
    rt.step()
    velocities = []
    while True:
        jog(jog_forward=False)
        if jog.done:
            break
        assert jog.busy
        velocities.append(x.set_velocity)
        rt.step()
    assert velocities and velocities[0] > 0.0 and min(velocities) > 0.0
    assert x.set_velocity == 0.0 and not x.has_job and x.state is S.STANDSTILL
    assert not jog.busy and not jog.active
    rt.step()
    jog(jog_forward=False)  # input already FALSE: Done shows for exactly one call
    assert not jog.done and not jog.busy


def test_rule59_release_leaves_the_axis_free() -> None:
    """The jog brakes with MC_Halt semantics: no Stopping lock for the next command."""
    rt, x = setup()
    jog = MC_Jog(x)
    cycle(rt, jog, 100, jog_forward=True)
    until_idle(rt, jog, jog_forward=False)
    assert x.state is S.STANDSTILL
    move = MC_MoveAbsolute(x)
    for _ in range(2000):
        move(execute=True, position=0.0, velocity=100.0)
        if move.done or move.error:
            break
        rt.step()
    assert move.done and x.set_position == pytest.approx(0.0, abs=1e-9)


# -- rule 60: CONTINUOUS uses the FB's velocity and dynamics ---------------------------------


def test_rule60_continuous_uses_fb_velocity_and_dynamics() -> None:
    rt = om.Runtime()
    x = rt.add_axis("x")
    ref = rt.add_axis("ref")
    assert x.power() and ref.power()
    jog = MC_Jog(x, mode=JogMode.CONTINUOUS, velocity=150.0, acceleration=1000.0,
                 deceleration=2000.0, jerk=20000.0, position=7.0)  # position ignored
    for n in range(600):
        jog(jog_backwards=n < 300)
        if n == 0:
            ref.move_velocity(150.0, NEG, 1000.0, 2000.0, 20000.0)
        if n == 300:
            ref.halt(2000.0, 20000.0)
        assert x.set_velocity == ref.set_velocity
        assert x.set_position == ref.set_position
        rt.step()
    assert x.set_velocity == 0.0 and x.set_position < -30.0


def test_rule60_zero_dynamics_mean_axis_defaults() -> None:
    rt = om.Runtime()
    x = rt.add_axis("x")
    ref = rt.add_axis("ref")
    assert x.power() and ref.power()
    jog = MC_Jog(x, mode=JogMode.CONTINUOUS, velocity=80.0, acceleration=0.0,
                 deceleration=0.0, jerk=0.0)
    for n in range(300):
        jog(jog_forward=n < 150)
        if n == 0:
            ref.move_velocity(80.0, POS)
        if n == 150:
            ref.halt()
        assert x.set_position == ref.set_position
        rt.step()


def test_rule60_inputs_are_taken_at_the_edge() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.CONTINUOUS, velocity=60.0)
    cycle(rt, jog, 300, jog_forward=True)
    cycle(rt, jog, 300, jog_forward=True, velocity=300.0, mode=JogMode.INCHING)
    assert x.set_velocity == pytest.approx(60.0)


# -- rule 61: INCHING moves exactly Position per edge --------------------------------------


def test_rule61_inching_step_is_exact_and_stops_while_held() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=2.5, velocity=50.0)
    until_idle(rt, jog, jog_forward=True)
    assert jog.done and x.set_position == pytest.approx(2.5, abs=1e-9)
    cycle(rt, jog, 300, jog_forward=True)  # still held: no further motion, Done stays
    assert jog.done and x.set_position == pytest.approx(2.5, abs=1e-9)
    assert x.state is S.STANDSTILL
    cycle(rt, jog, 1, jog_forward=False)
    assert not jog.done
    until_idle(rt, jog, jog_forward=True)  # a new edge: a second step
    assert x.set_position == pytest.approx(5.0, abs=1e-9)


@pytest.mark.parametrize("position", [2.5, -2.5])
def test_rule61_inching_direction_comes_from_the_key(position: float) -> None:
    """Q16: the sign of Position is ignored; backwards moves -|Position|."""
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=position, velocity=50.0)
    until_idle(rt, jog, jog_backwards=True)
    assert jog.done and x.set_position == pytest.approx(-2.5, abs=1e-9)
    cycle(rt, jog, 1, jog_forward=False, jog_backwards=False)
    until_idle(rt, jog, jog_forward=True)
    assert x.set_position == pytest.approx(0.0, abs=1e-9)


def test_rule61_inching_uses_fb_velocity() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=100.0, velocity=40.0)
    peak = 0.0
    for _ in range(5000):
        jog(jog_forward=True)
        peak = max(peak, x.set_velocity)
        if jog.done:
            break
        rt.step()
    assert peak == pytest.approx(40.0) and x.set_position == pytest.approx(100.0, abs=1e-9)


def _inching_step(acceleration: float, deceleration: float, jerk: float) -> list[tuple]:
    rt, x = setup(acceleration=1500.0, deceleration=2500.0, jerk=20000.0)
    jog = MC_Jog(x, mode=JogMode.INCHING, position=300.0, velocity=400.0,
                 acceleration=acceleration, deceleration=deceleration, jerk=jerk)
    samples = []
    for _ in range(5000):
        jog(jog_forward=True)
        samples.append((x.set_position, x.set_velocity, x.set_acceleration))
        if jog.done:
            break
        rt.step()
    assert jog.done and x.set_position == pytest.approx(300.0, abs=1e-9)
    return samples


def test_rule9_inching_zero_dynamics_mean_axis_defaults() -> None:
    """Rule 9, TcMC §3.13: an INCHING step with Acceleration/Deceleration/Jerk = 0 runs with
    AxisAcc/AxisDec/AxisJerk (1004-1006), the same profile as with them given explicitly."""
    zero = _inching_step(0.0, 0.0, 0.0)
    accelerations = [a for _, _, a in zero]
    assert max(accelerations) == pytest.approx(1500.0, rel=1e-9)
    assert min(accelerations) == pytest.approx(-2500.0, rel=1e-9)
    jerk = max(abs(b - a) for a, b in zip(accelerations, accelerations[1:], strict=False))
    assert jerk / 0.001 == pytest.approx(20000.0, rel=1e-3)
    assert zero == _inching_step(1500.0, 2500.0, 20000.0)


def test_inching_default_step_uses_jog_increments_1013_1014() -> None:
    rt, x = setup()
    x.write_parameter(1013, 0.75)
    x.write_parameter(1014, 0.5)
    jog = MC_Jog(x, mode=JogMode.INCHING, velocity=20.0)  # position = MC_DEFAULT
    until_idle(rt, jog, jog_forward=True)
    assert x.set_position == pytest.approx(0.75, abs=1e-9)
    cycle(rt, jog, 1, jog_forward=False, jog_backwards=False)
    until_idle(rt, jog, jog_backwards=True)
    assert x.set_position == pytest.approx(0.25, abs=1e-9)


# -- rule 62: Busy until at rest and back in the initial state ------------------------------


def test_rule62_busy_gate_inching() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=4.0, velocity=100.0)
    jog(jog_forward=True)
    rt.step()
    pulses = 0
    while True:  # tap both keys during the step: every edge is lost
        pulses += 1
        jog(jog_forward=pulses % 2 == 0, jog_backwards=pulses % 3 == 0)
        if not jog.busy:
            break
        assert x.moving or x.state is not S.STANDSTILL
        rt.step()
    assert pulses > 20
    assert x.set_velocity == 0.0 and not x.has_job and x.state is S.STANDSTILL
    assert x.set_position == pytest.approx(4.0, abs=1e-9)
    cycle(rt, jog, 1, jog_forward=False, jog_backwards=False)  # released: the outputs clear
    assert not (jog.busy or jog.done)
    until_idle(rt, jog, jog_backwards=True)  # now the next edge is accepted
    assert x.set_position == pytest.approx(0.0, abs=1e-9)


def test_rule62_busy_true_from_edge_to_rest() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.STANDARD_SLOW)
    assert not jog.busy
    jog(jog_forward=True)
    assert jog.busy and jog.active
    rt.step()
    cycle(rt, jog, 50, jog_forward=True)
    busy_moving = []
    while True:
        jog(jog_forward=False)
        busy_moving.append((jog.busy, x.set_velocity != 0.0 or x.has_job))
        if not jog.busy:
            break
        rt.step()
    assert all(busy for busy, _ in busy_moving[:-1]) and busy_moving[-1] == (False, False)


# -- rule 63: MC_Stop during jogging -> CommandAborted ---------------------------------------


def test_rule63_stop_while_jogging_aborts() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.CONTINUOUS, velocity=200.0)
    stop = MC_Stop(x)
    cycle(rt, jog, 200, jog_forward=True)
    stop(execute=True)
    rt.step()
    jog(jog_forward=True)
    assert jog.command_aborted and not jog.busy and not jog.done and not jog.error
    for _ in range(300):  # persists while the key stays TRUE
        stop(execute=True)
        rt.step()
        jog(jog_forward=True)
        assert jog.command_aborted
    assert x.state is S.STOPPING and x.set_velocity == 0.0
    stop(execute=False)
    rt.step()
    jog(jog_forward=False)
    assert not jog.command_aborted


def test_rule63_aborted_for_one_call_when_released() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=50.0, velocity=100.0)
    jog(jog_forward=True)
    rt.step()
    cycle(rt, jog, 50, jog_forward=False)  # key released, the step continues
    assert jog.busy
    x.stop()
    rt.step()
    jog(jog_forward=False, jog_backwards=False)
    assert jog.command_aborted
    rt.step()
    jog(jog_forward=False, jog_backwards=False)
    assert not jog.command_aborted and not jog.busy


def test_rule63_stop_while_braking_aborts() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.STANDARD_FAST)
    cycle(rt, jog, 300, jog_backwards=True)
    cycle(rt, jog, 5, jog_backwards=False)  # braking
    assert jog.busy
    x.stop(hold=False)
    rt.step()
    jog(jog_forward=False, jog_backwards=False)
    assert jog.command_aborted and not jog.done


def test_other_move_replacing_the_jog_aborts_it() -> None:
    rt, x = setup()
    jog = MC_Jog(x)
    move = MC_MoveAbsolute(x)
    cycle(rt, jog, 100, jog_forward=True)
    move(execute=True, position=0.0, velocity=100.0)
    rt.step()
    jog(jog_forward=True)
    assert jog.command_aborted and not jog.busy


# -- errors -------------------------------------------------------------------------------


@pytest.mark.parametrize("mode", [JogMode.CONTINUOUS, JogMode.INCHING])
@pytest.mark.parametrize("velocity", [0.0, -10.0, MC_INVALID, MC_DEFAULT, float("nan")])
def test_bad_velocity_is_invalid_velocity(mode: JogMode, velocity: Any) -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=mode, position=1.0, velocity=velocity)
    jog(jog_forward=True)
    assert jog.error and jog.error_id == ErrorId.INVALID_VELOCITY
    assert not jog.busy and not jog.done and jog.message
    cycle(rt, jog, 50, jog_forward=True)
    assert jog.error and x.set_position == 0.0 and x.state is S.STANDSTILL
    jog(jog_forward=False)  # shown while held; cleared on the first call after release
    assert not jog.error and jog.error_id == ErrorId.NO_ERROR


def test_standard_modes_ignore_a_bad_fb_velocity() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.STANDARD_SLOW, velocity=-1.0, acceleration=-5.0)
    cycle(rt, jog, 100, jog_forward=True)
    assert not jog.error and x.set_velocity > 0.0


@pytest.mark.parametrize("mode", [7, -1, True, "CONTINUOUS", 2.5])
def test_unknown_mode_is_invalid_mode(mode: Any) -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=mode, velocity=10.0)
    jog(jog_backwards=True)
    assert jog.error and jog.error_id == ErrorId.INVALID_MODE and not jog.busy
    rt.step()
    jog(jog_backwards=False)
    rt.step()
    jog(jog_backwards=False)
    assert not jog.error and x.set_position == 0.0


def test_unknown_mode_error_is_timed_at_the_runtime_now() -> None:
    """The error command carries the cycle time of the call, not 0.0."""
    rt, x = setup()
    rt.run(1.0)
    jog = MC_Jog(x, mode=7)
    jog(jog_forward=True)
    assert jog.error_id == ErrorId.INVALID_MODE
    assert jog.command.issued_at == jog.command.ended_at == rt.now == pytest.approx(1.0)


def test_mode_given_as_plain_int() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=2, velocity=30.0)
    cycle(rt, jog, 200, jog_forward=True)
    assert x.set_velocity == pytest.approx(30.0)


def test_negative_dynamics_in_continuous_is_an_error() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.CONTINUOUS, velocity=30.0, acceleration=-1.0)
    jog(jog_forward=True)
    assert jog.error and jog.error_id == ErrorId.INVALID_ACCELERATION


def test_bad_inching_position() -> None:
    rt, x = setup()
    jog = MC_Jog(x, mode=JogMode.INCHING, position=MC_INVALID, velocity=30.0)
    jog(jog_forward=True)
    assert jog.error and jog.error_id == ErrorId.INVALID_POSITION


def test_disabled_axis_gives_the_axis_error() -> None:
    rt = om.Runtime()
    x = rt.add_axis("x")
    expected = x.move_velocity(10.0).error_id
    assert expected != ErrorId.NO_ERROR
    jog = MC_Jog(x)
    jog(jog_forward=True)
    assert jog.error and jog.error_id == expected == ErrorId.AXIS_DISABLED


def test_axis_disabled_while_jogging() -> None:
    rt, x = setup()
    jog = MC_Jog(x)
    cycle(rt, jog, 100, jog_forward=True)
    x.power(False)
    rt.step()
    jog(jog_forward=True)
    assert not jog.busy and jog.command_aborted and not jog.error  # the axis aborts it
    assert "disabled" in jog.message


# -- the Python interface ---------------------------------------------------------------


def test_misspelt_input_is_a_type_error() -> None:
    rt, x = setup()
    jog = MC_Jog(x)
    with pytest.raises(TypeError, match="jog_backwards"):
        jog(jog_backward=True)
    with pytest.raises(TypeError, match="jog_forward"):
        MC_Jog(x, jogforward=True)
    with pytest.raises(TypeError):
        jog(execute=True)


def test_no_axis_is_a_type_error() -> None:
    jog = MC_Jog()
    jog()  # no edge: nothing to do
    with pytest.raises(TypeError, match="axis"):
        jog(jog_forward=True)


def test_axis_can_be_passed_on_the_call() -> None:
    rt, x = setup()
    jog = MC_Jog()
    for _ in range(100):
        jog(x, jog_forward=True)
        rt.step()
    assert x.set_velocity > 0.0 and jog.busy
