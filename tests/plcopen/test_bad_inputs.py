"""Bad input values (rules 10, 11; TcMC §1.9 "≥0"/">0"; style §2): each gives the FB's
``error`` with a specific ``error_id`` and a message, in the call of the rising edge; no
exception leaves a cycle; the axis does not move and stays usable afterwards.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

import openmotion as om
from openmotion.plcopen import (
    MC_ChangeDynParam,
    MC_Halt,
    MC_MoveAbsolute,
    MC_MoveAbsoluteOrRestart,
    MC_MoveModulo,
    MC_MoveRelative,
    MC_MoveVelocity,
    MC_NewPos,
    MC_NewPosAndVelo,
    MC_ReadBoolParameter,
    MC_ReadParameter,
    MC_SetActualPosition,
    MC_Stop,
    MC_WriteBoolParameter,
    MC_WriteParameter,
)

E = om.ErrorId
NAN, INF = math.nan, math.inf

#: the blocks with Position/Distance, Velocity, Acceleration, Deceleration, Jerk inputs
MOVES = {
    "MC_MoveAbsolute": (MC_MoveAbsolute, {"position": 10.0}),
    "MC_MoveRelative": (MC_MoveRelative, {"distance": 10.0}),
    "MC_MoveModulo": (MC_MoveModulo, {"position": 10.0}),
    "MC_MoveAbsoluteOrRestart": (MC_MoveAbsoluteOrRestart, {"position": 10.0}),
    "MC_MoveVelocity": (MC_MoveVelocity, {}),
}


def powered_axis() -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    assert axis.power()
    return rt, axis


def assert_refused(rt: om.Runtime, axis: om.Axis, fb: Any, error_id: E) -> None:
    """The FB shows the error at once; the axis neither moves nor breaks; a good move works."""
    assert fb.error, f"no error for {type(fb).__name__}"
    assert fb.error_id == error_id, (fb.error_id, fb.message)
    assert fb.message
    assert not fb.busy and not fb.done and not fb.command_aborted
    start = axis.set_position
    for _ in range(20):
        fb(execute=True)
        assert fb.error and fb.error_id == error_id
        rt.step()
    assert axis.set_position == start and axis.set_velocity == 0.0
    assert axis.state is om.AxisState.STANDSTILL
    good = MC_MoveRelative(axis)
    good(execute=True, distance=5.0, velocity=100.0)
    for _ in range(2000):
        if good.done:
            break
        rt.step()
        good(execute=True)
    assert good.done and axis.set_position == pytest.approx(start + 5.0, abs=1e-12)


def _issue(name: str, **inputs: Any) -> tuple[om.Runtime, om.Axis, Any]:
    rt, axis = powered_axis()
    cls, base = MOVES[name]
    fb = cls(axis)
    fb(execute=True, **{"velocity": 100.0, **base, **inputs})
    return rt, axis, fb


# -- velocity (rule 10) ----------------------------------------------------------------------


@pytest.mark.parametrize("velocity", [0.0, -1.0, -1e-12, NAN, INF, -INF, om.MC_INVALID,
                                      om.MC_DEFAULT, om.MC_IGNORE, "fast", True, None],
                         ids=repr)
@pytest.mark.parametrize("name", list(MOVES))
def test_bad_velocity(name: str, velocity: Any) -> None:
    """Rule 10, TcMC §3.1-3.6: Velocity must be > 0 and finite → INVALID_VELOCITY."""
    rt, axis, fb = _issue(name, velocity=velocity)
    assert_refused(rt, axis, fb, E.INVALID_VELOCITY)


def test_velocity_not_given_at_all() -> None:
    """An input left at MC_INVALID (no default) is an error, not a silent 0."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=10.0)
    assert_refused(rt, axis, move, E.INVALID_VELOCITY)


# -- dynamics (rule 11) ---------------------------------------------------------------------


@pytest.mark.parametrize("value", [-1.0, -1e-9, NAN, INF, -INF, om.MC_INVALID, "x"], ids=repr)
@pytest.mark.parametrize(("field", "error_id"), [
    ("acceleration", E.INVALID_ACCELERATION), ("deceleration", E.INVALID_DECELERATION),
    ("jerk", E.INVALID_JERK),
])
@pytest.mark.parametrize("name", list(MOVES))
def test_bad_dynamics(name: str, field: str, error_id: E, value: Any) -> None:
    """Rule 11, TcMC §1.9 (≥ 0): negative, non-finite or non-numeric dynamics → error."""
    rt, axis, fb = _issue(name, **{field: value})
    assert_refused(rt, axis, fb, error_id)


def test_jerk_maximum_is_allowed_and_above_it_is_refused() -> None:
    """Jerk MC_MAXIMUM = the axis' max_jerk is allowed; a jerk above it is refused
    (dynamics.py: jerk is not clamped, unlike velocity and acceleration)."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=10.0, velocity=100.0, jerk=om.MC_MAXIMUM)
    assert move.busy and not move.error
    rt2, axis2 = powered_axis()
    above = MC_MoveAbsolute(axis2)
    above(execute=True, position=10.0, velocity=100.0,
          jerk=axis2.parameters.max_jerk * 1.5)
    assert_refused(rt2, axis2, above, E.INVALID_JERK)


def test_halt_bad_dynamics() -> None:
    rt, axis = powered_axis()
    halt = MC_Halt(axis)
    halt(execute=True, deceleration=-5.0)
    assert_refused(rt, axis, halt, E.INVALID_DECELERATION)


def test_change_dyn_param_bad_values() -> None:
    """TcMC §4.20 (≥ 0): a negative value is refused; the running move keeps its dynamics."""
    rt, axis = powered_axis()
    move = MC_MoveVelocity(axis)
    move(execute=True, velocity=100.0)
    for _ in range(200):
        rt.step()
        move(execute=True)
    for field, error_id in (("acceleration", E.INVALID_ACCELERATION),
                            ("deceleration", E.INVALID_DECELERATION), ("jerk", E.INVALID_JERK)):
        change = MC_ChangeDynParam(axis)
        change(execute=True, **{field: -1.0})
        assert change.error and change.error_id == error_id and change.message
    rt.step()
    move(execute=True)
    assert move.busy and move.in_velocity and axis.set_velocity == 100.0


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"deceleration": -100.0, "jerk": 1000.0}, E.INVALID_DECELERATION),
    ({"deceleration": 100.0, "jerk": -1000.0}, E.INVALID_JERK),
    ({"deceleration": NAN, "jerk": 1000.0}, E.INVALID_DECELERATION),
], ids=["negative-deceleration", "negative-jerk", "nan-deceleration"])
def test_stop_with_bad_dynamics_still_stops(inputs: dict, error_id: E) -> None:
    """§1.5 / TcMC §3.15: MC_Stop always brings the axis to rest; its own bad parameters
    are reported (error id) but do not fail the stop: the running dynamics are used."""
    rt, axis = powered_axis()
    move = MC_MoveVelocity(axis)
    move(execute=True, velocity=100.0)
    for _ in range(200):
        rt.step()
        move(execute=True)
    stop = MC_Stop(axis)
    stop(execute=True, **inputs)
    assert stop.error and stop.error_id == error_id and stop.message
    for _ in range(500):
        rt.step()
        stop(execute=True)
        move(execute=True)
    assert move.command_aborted
    assert axis.set_velocity == 0.0
    assert axis.state is om.AxisState.STOPPING  # held while Execute stays TRUE


# -- positions -------------------------------------------------------------------------------


@pytest.mark.parametrize("position", [NAN, INF, -INF, om.MC_INVALID, om.MC_DEFAULT, None, "0",
                                      False], ids=repr)
@pytest.mark.parametrize(("name", "field"), [
    ("MC_MoveAbsolute", "position"), ("MC_MoveRelative", "distance"),
    ("MC_MoveModulo", "position"), ("MC_MoveAbsoluteOrRestart", "position"),
])
def test_bad_position(name: str, field: str, position: Any) -> None:
    """A position must be a finite number (MC_INVALID = not given) → INVALID_POSITION."""
    rt, axis, fb = _issue(name, **{field: position})
    assert_refused(rt, axis, fb, E.INVALID_POSITION)


@pytest.mark.parametrize("name", ["MC_MoveAbsolute", "MC_MoveModulo", "MC_MoveRelative"])
def test_position_not_given_at_all(name: str) -> None:
    rt, axis = powered_axis()
    fb = MOVES[name][0](axis)
    fb(execute=True, velocity=100.0)
    assert_refused(rt, axis, fb, E.INVALID_POSITION)


@pytest.mark.parametrize("position", [-0.001, -360.0, NAN], ids=repr)
def test_bad_modulo_target(position: float) -> None:
    """TcMC §3.5: a modulo target is >= 0; NaN is not a position at all."""
    rt, axis, fb = _issue("MC_MoveModulo", position=position)
    expected = E.INVALID_POSITION if math.isnan(position) else E.INVALID_MODULO_TARGET
    assert_refused(rt, axis, fb, expected)


def test_set_actual_position_nan() -> None:
    rt, axis = powered_axis()
    setter = MC_SetActualPosition(axis)
    setter(execute=True, position=NAN)
    assert setter.error and setter.error_id == E.INVALID_POSITION
    assert axis.position == 0.0 and axis.set_position == 0.0


@pytest.mark.parametrize(("cls", "inputs", "error_id"), [
    (MC_NewPos, {"new_pos": NAN}, E.INVALID_POSITION),
    (MC_NewPos, {"new_pos": om.MC_INVALID}, E.INVALID_POSITION),
    (MC_NewPosAndVelo, {"new_pos": 50.0, "new_velo": -1.0}, E.INVALID_VELOCITY),
    (MC_NewPosAndVelo, {"new_pos": 50.0, "new_velo": 0.0}, E.INVALID_VELOCITY),
    (MC_NewPosAndVelo, {"new_pos": INF, "new_velo": 10.0}, E.INVALID_POSITION),
    (MC_NewPosAndVelo, {"mode": 5, "new_pos": 50.0, "new_velo": 10.0}, E.INVALID_MODE),
    (MC_NewPosAndVelo, {"mode": 99, "new_pos": 50.0, "new_velo": 10.0}, E.INVALID_MODE),
])
def test_bad_modifications(cls, inputs: dict, error_id: E) -> None:
    """TcMC §3.7/§3.8: a refused modification leaves the running move alone."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=100.0, velocity=100.0)
    for _ in range(100):
        rt.step()
        move(execute=True)
    fb = cls(axis)
    fb(execute=True, **inputs)
    assert fb.error and fb.error_id == error_id and fb.message
    for _ in range(3000):
        rt.step()
        move(execute=True)
        if move.done:
            break
    assert move.done and axis.set_position == 100.0


# -- directions and buffer modes --------------------------------------------------------------


@pytest.mark.parametrize("direction", [0, 5, -1, 99, "positive", None,
                                       om.Direction.SHORTEST_WAY], ids=repr)
def test_move_velocity_bad_direction(direction: Any) -> None:
    """TcMC §6.2: MC_MoveVelocity takes positive, negative or current direction."""
    rt, axis, fb = _issue("MC_MoveVelocity", direction=direction)
    assert_refused(rt, axis, fb, E.INVALID_DIRECTION)


@pytest.mark.parametrize("direction", [0, 5, -1, "negative", None, om.Direction.CURRENT],
                         ids=repr)
def test_move_modulo_bad_direction(direction: Any) -> None:
    """TcMC §3.4: MC_MoveModulo takes positive, negative or shortest way."""
    rt, axis, fb = _issue("MC_MoveModulo", direction=direction)
    assert_refused(rt, axis, fb, E.INVALID_DIRECTION)


@pytest.mark.parametrize("mode", [2, 0x11, 0x16, -1, 99, "Buffered", None], ids=repr)
@pytest.mark.parametrize("name", list(MOVES))
def test_bad_buffer_mode(name: str, mode: Any) -> None:
    """PLCopen MC_BUFFER_MODE: an unknown value → INVALID_BUFFER_MODE."""
    rt, axis, fb = _issue(name, buffer_mode=mode)
    assert_refused(rt, axis, fb, E.INVALID_BUFFER_MODE)


def test_bad_buffer_mode_on_halt() -> None:
    rt, axis = powered_axis()
    halt = MC_Halt(axis)
    halt(execute=True, buffer_mode=7)
    assert_refused(rt, axis, halt, E.INVALID_BUFFER_MODE)


# -- parameter numbers ---------------------------------------------------------------------


@pytest.mark.parametrize("number", [17, 999, 0, -1, 1049, 2003, 65535, 3.5, "1004", None],
                         ids=repr)
@pytest.mark.parametrize("cls", [MC_ReadParameter, MC_ReadBoolParameter, MC_WriteParameter,
                                 MC_WriteBoolParameter])
def test_parameter_numbers_that_do_not_exist(cls, number: Any) -> None:
    """TcMC §6.1: an unknown number → INVALID_PARAMETER_NUMBER, every cycle while enabled."""
    rt, axis = powered_axis()
    fb = cls(axis)
    inputs: dict[str, Any] = {"parameter_number": number}
    if cls in (MC_WriteParameter, MC_WriteBoolParameter):
        inputs["value"] = True if cls is MC_WriteBoolParameter else 1.0
    for _ in range(3):
        fb(enable=True, **inputs)
        assert fb.error and fb.error_id == E.INVALID_PARAMETER_NUMBER and fb.message
        assert not fb.done
        rt.step()
    fb(enable=True, parameter_number=om.AxisPara.AxisEnMaxSoftPosLimit
       if cls in (MC_ReadBoolParameter, MC_WriteBoolParameter) else om.AxisPara.AxisAcc)
    assert fb.done and not fb.error and fb.error_id == E.NO_ERROR  # usable again


@pytest.mark.parametrize("value", [NAN, INF, "1.0", None], ids=repr)
def test_write_parameter_non_numeric_value(value: Any) -> None:
    rt, axis = powered_axis()
    write = MC_WriteParameter(axis)
    write(enable=True, parameter_number=om.AxisPara.AxisAcc, value=value)
    assert write.error and write.error_id == E.INVALID_PARAMETER_VALUE
    assert axis.parameters.acceleration == 5000.0
