"""Modulo positioning, TcMC §3.4 and §3.5 (digest §1.7; rules 28-40).

The two tables of §3.5 are data: each row is (direction, absolute start set position, modulo
target, relative travel, absolute end). Period 360°, tolerance window (TW) 1° as in the manual.
Every row is checked through ``modulo_target`` and end-to-end through MC_MoveModulo.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import pytest

import openmotion as om
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.modulo import modulo_position, modulo_target, modulo_turns
from openmotion.plcopen import (
    MC_MoveAbsolute,
    MC_MoveModulo,
    MC_MoveVelocity,
    MC_Power,
    MC_Reset,
    MC_SetActualPosition,
    MC_WriteBoolParameter,
    MC_WriteParameter,
)

POS, NEG, SHORT = om.Direction.POSITIVE, om.Direction.NEGATIVE, om.Direction.SHORTEST_WAY
PERIOD = 360.0
TW = 1.0


class Row(NamedTuple):
    table: str
    direction: om.Direction
    start: float
    target: float
    travel: float
    end: float

    def __str__(self) -> str:
        return f"§3.5-{self.table}-{self.direction.name}-{self.start}->{self.target}"


def _rows(table: str, data: list[tuple]) -> list[Row]:
    return [Row(table, *row) for row in data]


#: TcMC §3.5 "Modulo positioning by less than one turn" (TW irrelevant)
TABLE_A = _rows("A", [
    (POS, 90.00, 0.0, 270.00, 360.0),
    (POS, 90.00, 360.0, 630.00, 720.0),
    (POS, 90.00, 720.0, 990.00, 1080.0),
    (NEG, 90.00, 0.0, -90.00, 0.0),
    (NEG, 90.00, 360.0, -450.00, -360.0),
    (NEG, 90.00, 720.0, -810.00, -720.0),
    (SHORT, 90.00, 0.0, -90.00, 0.0),
])

#: TcMC §3.5 "Modulo positioning with full turns", TW = 1°
TABLE_B = _rows("B", [
    (POS, 90.00, 90.0, 0.00, 90.0),
    (POS, 90.90, 90.0, -0.90, 90.0),
    (POS, 91.10, 90.0, 358.90, 450.0),  # outside TW
    (POS, 89.10, 90.0, 0.90, 90.0),
    (POS, 88.90, 90.0, 1.10, 90.0),  # outside TW
    (POS, 90.00, 450.0, 360.00, 450.0),
    (POS, 90.90, 450.0, 359.10, 450.0),
    (POS, 91.10, 450.0, 718.90, 810.0),  # outside TW
    (POS, 89.10, 450.0, 360.90, 450.0),
    (POS, 88.90, 450.0, 361.10, 450.0),  # outside TW
    (POS, 90.00, 810.0, 720.00, 810.0),
    (POS, 90.90, 810.0, 719.10, 810.0),
    (POS, 91.10, 810.0, 1078.90, 1170.0),  # outside TW
    (POS, 89.10, 810.0, 720.90, 810.0),
    (POS, 88.90, 810.0, 721.10, 810.0),  # outside TW
    (NEG, 90.00, 90.0, 0.00, 90.0),
    (NEG, 90.90, 90.0, -0.90, 90.0),
    (NEG, 91.10, 90.0, -1.10, 90.0),  # outside TW
    (NEG, 89.10, 90.0, 0.90, 90.0),
    (NEG, 88.90, 90.0, -358.90, -270.0),  # outside TW
    (NEG, 90.00, 450.0, -360.00, -270.0),
    (NEG, 90.90, 450.0, -360.90, -270.0),
    (NEG, 91.10, 450.0, -361.10, -270.0),  # outside TW
    (NEG, 89.10, 450.0, -359.10, -270.0),
    (NEG, 88.90, 450.0, -718.90, -630.0),  # outside TW
    (NEG, 90.00, 810.0, -720.00, -630.0),
    (NEG, 90.90, 810.0, -720.90, -630.0),
    (NEG, 91.10, 810.0, -721.10, -630.0),  # outside TW
    (NEG, 89.10, 810.0, -719.10, -630.0),
    (NEG, 88.90, 810.0, -1078.90, -990.0),  # outside TW
])

ALL_ROWS = TABLE_A + TABLE_B


def test_the_tables_have_the_manuals_37_rows() -> None:
    assert (len(TABLE_A), len(TABLE_B)) == (7, 30)
    for row in ALL_ROWS:  # the tables are self-consistent: start + travel = end
        assert row.start + row.travel == pytest.approx(row.end, abs=1e-9)
        assert modulo_position(row.end, PERIOD) == pytest.approx(row.target % PERIOD, abs=1e-9)


# -- rule 28: the function --------------------------------------------------------------------


@pytest.mark.parametrize("tolerance", [0.0, TW], ids=["TW0", "TW1"])
@pytest.mark.parametrize("row", TABLE_A, ids=str)
def test_table_a_through_modulo_target(row: Row, tolerance: float) -> None:
    """Table A: less than a turn, TW irrelevant (TcMC §3.5)."""
    end = modulo_target(row.start, row.target, PERIOD, tolerance, row.direction)
    assert end == pytest.approx(row.end, abs=1e-9)
    assert end - row.start == pytest.approx(row.travel, abs=1e-9)


@pytest.mark.parametrize("row", TABLE_B, ids=str)
def test_table_b_through_modulo_target(row: Row) -> None:
    """Table B: full turns with TW = 1° (TcMC §3.5)."""
    end = modulo_target(row.start, row.target, PERIOD, TW, row.direction)
    assert end == pytest.approx(row.end, abs=1e-9)
    assert end - row.start == pytest.approx(row.travel, abs=1e-9)


# -- rule 28: end to end through MC_MoveModulo --------------------------------------------------


def _modulo_axis(rt: om.Runtime, start: float, tolerance: float = TW, **overrides) -> om.Axis:
    overrides.setdefault("max_velocity", 5000.0)
    overrides.setdefault("max_acceleration", 100000.0)
    overrides.setdefault("max_deceleration", 100000.0)
    return rt.add_axis("rotary", position=start, modulo_period=PERIOD,
                       modulo_tolerance_window=tolerance, **overrides)


def _run_modulo(rt: om.Runtime, axis: om.Axis, target: float, direction: om.Direction,
                velocity: float = 3000.0, max_cycles: int = 5000) -> tuple[MC_MoveModulo, list]:
    """Call MC_MoveModulo every cycle until it ends; returns the FB and the set positions."""
    move = MC_MoveModulo(axis)
    trace = [axis.set_position]
    for _ in range(max_cycles):
        move(execute=True, position=target, velocity=velocity, acceleration=50000.0,
             deceleration=50000.0, jerk=1.0e6, direction=direction)
        if move.done or move.error or move.command_aborted:
            return move, trace
        rt.step()
        trace.append(axis.set_position)
    raise AssertionError(f"MC_MoveModulo to {target} did not end within {max_cycles} cycles")


@pytest.mark.parametrize("row", ALL_ROWS, ids=str)
def test_table_rows_end_to_end_with_add_axis(row: Row) -> None:
    """The axis starts at the row's set position (add_axis + power) and ends at its end."""
    rt = om.Runtime()
    axis = _modulo_axis(rt, row.start)
    assert axis.power()
    assert axis.set_position == row.start
    move, trace = _run_modulo(rt, axis, row.target, row.direction)
    assert move.done, (move.error_id, move.message)
    assert axis.set_position == pytest.approx(row.end, abs=1e-9)
    # the travel never went beyond the end in the commanded sense (no overshoot)
    lo, hi = min(trace), max(trace)
    assert lo >= min(row.start, row.end) - 1e-9
    assert hi <= max(row.start, row.end) + 1e-9


@pytest.mark.parametrize("row", ALL_ROWS, ids=str)
def test_table_rows_end_to_end_with_set_actual_position(row: Row) -> None:
    """Same rows, the start set position put in place with MC_SetActualPosition (§4.12)."""
    rt = om.Runtime()
    axis = _modulo_axis(rt, 0.0)
    power = MC_Power(axis)
    power(enable=True)
    set_position = MC_SetActualPosition(axis)
    set_position(execute=True, position=row.start)
    assert set_position.done
    assert axis.set_position == pytest.approx(row.start, abs=1e-12)
    rt.step()
    move, _ = _run_modulo(rt, axis, row.target, row.direction)
    assert move.done, (move.error_id, move.message)
    assert axis.set_position == pytest.approx(row.end, abs=1e-9)


# -- rules 29-35 --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("start", "target", "travel"),
    [(90.0, 90.0, 0.0), (90.0, 450.0, 360.0), (90.0, 810.0, 720.0)],
    ids=["90->90 no motion", "90->450 one turn", "90->810 two turns"],
)
def test_without_window_exact_set_position(start: float, target: float, travel: float) -> None:
    """Rule 29, TcMC §3.4: TW = 0 at exactly 90°: target 90 → no motion; 450 → one turn."""
    assert modulo_target(start, target, PERIOD, 0.0, POS) - start == pytest.approx(travel,
                                                                                   abs=1e-12)
    rt = om.Runtime()
    axis = _modulo_axis(rt, start, tolerance=0.0)
    axis.power()
    move, trace = _run_modulo(rt, axis, target, POS)
    assert move.done
    assert axis.set_position - start == pytest.approx(travel, abs=1e-9)
    if travel == 0.0:
        assert set(trace) == {start}  # no motion at all


@pytest.mark.parametrize("epsilon", [1e-6, 0.01, 0.3])
def test_without_window_just_above_target_gives_almost_a_turn(epsilon: float) -> None:
    """Rule 30, TcMC §3.4/§3.5: TW = 0, set position 90 + ε → travel 360 − ε (positive)."""
    start = 90.0 + epsilon
    end = modulo_target(start, 90.0, PERIOD, 0.0, POS)
    assert end == pytest.approx(450.0, abs=1e-9)
    assert end - start == pytest.approx(360.0 - epsilon, abs=1e-9)


@pytest.mark.parametrize("epsilon", [1e-6, 0.01, 0.3])
def test_without_window_just_below_target_gives_a_tiny_move(epsilon: float) -> None:
    """Rule 30: TW = 0, set position 90 − ε → travel ε (positive)."""
    start = 90.0 - epsilon
    end = modulo_target(start, 90.0, PERIOD, 0.0, POS)
    assert end == pytest.approx(90.0, abs=1e-9)
    assert end - start == pytest.approx(epsilon, abs=1e-9)


@pytest.mark.parametrize(("target", "end"), [(0.0, 360.0), (360.0, 720.0)], ids=["0", "360"])
def test_from_270_positive_to_0_and_360(target: float, end: float) -> None:
    """Rule 31, TcMC §3.5: 270 → 0 positive is +90 (end 360); 360 adds a turn (+450)."""
    assert modulo_target(270.0, target, PERIOD, TW, POS) == pytest.approx(end, abs=1e-9)
    rt = om.Runtime()
    axis = _modulo_axis(rt, 270.0)
    axis.power()
    move, _ = _run_modulo(rt, axis, target, POS)
    assert move.done
    assert axis.set_position == pytest.approx(end, abs=1e-9)


@pytest.mark.parametrize("target", [360.0, 450.0, 720.0, 1000.0])
def test_shortest_way_outside_the_period_is_an_error(target: float) -> None:
    """Rule 32, TcMC §3.5: MC_Shortest_Way only accepts targets in [0, period)."""
    with pytest.raises(CommandRejected) as rejected:
        modulo_target(90.0, target, PERIOD, TW, SHORT)
    assert rejected.value.error_id == ErrorId.INVALID_MODULO_TARGET
    rt = om.Runtime()
    axis = _modulo_axis(rt, 90.0)
    axis.power()
    move = MC_MoveModulo(axis)
    move(execute=True, position=target, velocity=100.0, direction=SHORT)
    assert move.error and move.error_id == ErrorId.INVALID_MODULO_TARGET
    assert not move.busy
    for _ in range(5):
        move(execute=True)
        rt.step()
    assert axis.set_position == 90.0 and axis.state is om.AxisState.STANDSTILL  # no motion


@pytest.mark.parametrize(
    ("start", "target", "travel"),
    [(90.0, 0.0, -90.0), (90.0, 180.0, 90.0), (10.0, 350.0, -20.0), (350.0, 10.0, 20.0),
     (90.0, 90.0, 0.0)],
)
def test_shortest_way(start: float, target: float, travel: float) -> None:
    """Rule 33, TcMC §3.5 Table A: shortest way from 90 to 0 is −90; wraps across 0."""
    assert modulo_target(start, target, PERIOD, TW, SHORT) - start == pytest.approx(travel,
                                                                                    abs=1e-9)


@pytest.mark.parametrize("direction", [POS, NEG])
@pytest.mark.parametrize("start", [0.0, 0.5, 89.1, 90.0, 90.9, 180.0, 359.5, -725.25, 1234.5])
@pytest.mark.parametrize("target", [0.0, 0.5, 45.0, 90.0, 179.99, 270.0, 359.9])
def test_targets_inside_the_period_never_travel_a_turn(direction, start, target) -> None:
    """Rules 34/35, TcMC §3.5: |travel| < period; a move against the direction is within TW.

    Exactly at TW (boundary, digest Open Q8) either reading is allowed: hence ``<=``.
    """
    travel = modulo_target(start, target, PERIOD, TW, direction) - start
    assert abs(travel) < PERIOD
    sign = 1.0 if direction is POS else -1.0
    if travel * sign < 0.0:
        assert abs(travel) <= TW
    assert modulo_position(start + travel, PERIOD) == pytest.approx(target, abs=1e-9)


@pytest.mark.parametrize("flag", [0.0, 4.0], ids=["modulo-flag-off", "modulo-flag-on"])
def test_move_modulo_works_regardless_of_the_modulo_flag(flag: float) -> None:
    """Rule 36, TcMC §3.4 note: modulo positioning works on any axis (bit 2 of 1048)."""
    rt = om.Runtime()
    axis = _modulo_axis(rt, 90.0, unit_interpretation=flag)
    axis.power()
    move, _ = _run_modulo(rt, axis, 450.0, POS)
    assert move.done
    assert axis.set_position == pytest.approx(450.0, abs=1e-9)


# -- rules 37, 38, 40: reset and power on take the actual position ---------------------------

LAG = om.DriveModel(model="lag", time_constant=0.05, dead_time=0.002)


def _fault_near(target: float, approach_from: float, tolerance: float = 1.5):
    """An axis stopped by IN_TARGET_TIMEOUT just after its profile reached ``target``.

    The slow lag drive (0.05 s) leaves the actual position about 0.7° short of the target
    (the manual's 89.3 / 90.7 situation), so that a following MC_Reset takes a set position
    that is not exactly ``target``. The monitoring is put back to normal afterwards.
    """
    rt = om.Runtime()
    axis = rt.add_axis("rotary", drive=LAG, position=approach_from, modulo_period=PERIOD,
                       modulo_tolerance_window=tolerance, max_position_lag=50.0,
                       target_position_window=1e-6, enable_in_target_timeout=True,
                       in_target_timeout=0.0)
    axis.power()
    move = MC_MoveAbsolute(axis)
    for _ in range(5000):
        move(execute=True, position=target, velocity=20.0)
        if axis.state is om.AxisState.ERROR_STOP:
            break
        rt.step()
    assert axis.state is om.AxisState.ERROR_STOP
    assert axis.axis_error_id == ErrorId.IN_TARGET_TIMEOUT
    assert axis.set_position == pytest.approx(target, abs=1e-9)
    timeout, window = MC_WriteBoolParameter(axis), MC_WriteParameter(axis)
    timeout(enable=True, parameter_number=om.AxisPara.AxisEnInTargetTimeout, value=False)
    window(enable=True, parameter_number=om.AxisPara.AxisTargetPositionWindow, value=2.0)
    assert timeout.done and window.done
    return rt, axis


def _reset(rt: om.Runtime, axis: om.Axis) -> tuple[float, float]:
    """MC_Reset until Done; returns (actual position at the reset, set position after)."""
    reset = MC_Reset(axis)
    actual = math.nan
    for _ in range(1000):
        actual = axis.position
        reset(execute=True)
        if reset.done:
            return actual, axis.set_position
        rt.step()
    raise AssertionError("MC_Reset never done")


@pytest.mark.parametrize("approach_from", [0.0, 180.0], ids=["from-below", "from-above"])
def test_reset_makes_set_position_the_actual_position(approach_from: float) -> None:
    """Rule 37, TcMC §3.5: after MC_Reset, set position = actual position at the reset."""
    rt, axis = _fault_near(90.0, approach_from)
    _, set_after = _reset(rt, axis)
    assert axis.state is om.AxisState.STANDSTILL
    assert set_after == axis.position
    assert axis.following_error == 0.0
    assert 1e-3 < abs(set_after - 90.0) < 1.5  # the reset moved the set position off 90


@pytest.mark.parametrize("approach_from", [0.0, 180.0], ids=["from-below", "from-above"])
def test_application_example_after_reset(approach_from: float) -> None:
    """Rule 40, TcMC §3.5 application example: TW 1.5°; after a reset a MoveModulo(90,
    positive) moves by less than 1.5° to exactly 90; then 450 advances exactly +360."""
    rt, axis = _fault_near(90.0, approach_from, tolerance=1.5)
    _, start = _reset(rt, axis)
    assert start != 90.0
    move, trace = _run_modulo(rt, axis, 90.0, POS, velocity=100.0)
    assert move.done
    assert axis.set_position == pytest.approx(90.0, abs=1e-9)
    assert max(abs(p - start) for p in trace) < 1.5
    for turn in (1, 2, 3):
        rt.step()
        move, _ = _run_modulo(rt, axis, 450.0, POS, velocity=200.0)
        assert move.done
        assert axis.set_position == pytest.approx(90.0 + 360.0 * turn, abs=1e-9)


def test_application_example_cycle_advances_one_turn_each_time() -> None:
    """Rule 40: from exactly 90 with TW 1.5, MoveModulo(450, positive) is +360 per cycle."""
    rt = om.Runtime()
    axis = _modulo_axis(rt, 0.0, tolerance=1.5)
    axis.power()
    move, _ = _run_modulo(rt, axis, 90.0, POS)  # the basic positioning to the start
    assert axis.set_position == pytest.approx(90.0, abs=1e-9)
    again, trace = _run_modulo(rt, axis, 90.0, POS)  # already there: no motion
    assert again.done and set(trace) == {axis.set_position}
    for turn in range(1, 4):
        move, _ = _run_modulo(rt, axis, 450.0, POS)
        assert move.done
        assert axis.set_position == pytest.approx(90.0 + 360.0 * turn, abs=1e-9)


def test_power_on_makes_set_position_the_actual_position() -> None:
    """Rule 38, TcMC §3.5: enabling (MC_Power) takes the actual position as set position.

    A lag drive leaves a following error while moving; disabling in motion and enabling
    again must leave no following error and the set position where the actual one is.
    """
    rt = om.Runtime()
    axis = rt.add_axis("rotary", drive=om.DriveModel(model="lag", time_constant=0.01,
                                                     dead_time=0.002))
    power = MC_Power(axis)
    move = MC_MoveVelocity(axis)
    for _ in range(200):
        power(enable=True)
        move(execute=True, velocity=100.0)
        rt.step()
    assert axis.following_error > 0.5  # a real following error before the power cycle
    power(enable=False)
    rt.step()
    power(enable=True)
    assert power.status
    assert axis.set_position == axis.position
    assert axis.following_error == 0.0
    held = axis.position
    for _ in range(50):
        power(enable=True)
        rt.step()
    assert axis.position == pytest.approx(held, abs=1e-12)  # no jump back to the old set


# -- rule 39 ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("position", "modulo", "turns"),
    [(0.0, 0.0, 0), (90.0, 90.0, 0), (360.0, 0.0, 1), (450.0, 90.0, 1), (-90.0, 270.0, -1),
     (-360.0, 0.0, -1), (-720.5, 359.5, -3), (1170.0, 90.0, 3), (359.999, 359.999, 0)],
)
def test_modulo_position_and_turns(position: float, modulo: float, turns: int) -> None:
    """Rule 39, TcMC §3.5: MODABS in [0, period) and MODTURNS = floor(pos / period)."""
    assert modulo_position(position, PERIOD) == pytest.approx(modulo, abs=1e-9)
    assert 0.0 <= modulo_position(position, PERIOD) < PERIOD
    assert modulo_turns(position, PERIOD) == turns
    assert modulo_turns(position, PERIOD) * PERIOD + modulo_position(position, PERIOD) \
        == pytest.approx(position, abs=1e-9)


def test_axis_modulo_set_position_uses_the_set_position() -> None:
    """Rule 39: the axis' modulo set position is the set position modulo the period."""
    rt = om.Runtime()
    axis = _modulo_axis(rt, -450.0)
    axis.power()
    assert axis.modulo_set_position == pytest.approx(270.0, abs=1e-12)
