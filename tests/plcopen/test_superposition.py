"""Superposition (TcMC §3.9-3.12, digest rules 41-53) with the manual's examples of §3.11."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.enums import SuperpositionMode as M
from openmotion.plcopen import MC_MoveAbsolute, MC_Stop
from openmotion.plcopen.superposition import (
    MC_AbortSuperposition,
    MC_MoveSuperImposed,
    MC_MoveSuperImposedExt,
)

E = om.ErrorId


def cruising(velocity: float, **parameters: float) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x", max_velocity=2000.0, acceleration=2000.0, deceleration=2000.0,
                       jerk=40000.0, **parameters)
    axis.power()
    axis.move_velocity(velocity)
    rt.run(1.0)
    assert axis.set_velocity == velocity
    return rt, axis


def run(rt: om.Runtime, fb: MC_MoveSuperImposedExt, limit: int = 20000) -> int:
    cycles = 0
    while fb.busy and cycles < limit:
        rt.step()
        fb(execute=True)
        cycles += 1
    return cycles


def test_conveyor_gap_correction_travels_exactly_the_length() -> None:
    """§3.11 example 1, rule 47: 300 mm gained within 1000 mm of belt travel,
    VELOREDUCTION_LIMITEDMOTION, velocity reserve 500 mm/s (belt at 500 mm/s)."""
    rt, belt = cruising(500.0)
    start = belt.set_position
    fb = MC_MoveSuperImposedExt(belt)
    fb(execute=True, mode=M.VELOREDUCTION_LIMITEDMOTION, distance=300.0, length=1000.0,
       velocity_diff=500.0, velocity_process=500.0)
    assert fb.busy and fb.actual_distance == 300.0 and fb.actual_length == pytest.approx(1000.0)
    assert 0.0 < fb.actual_velocity_diff < 500.0  # rule 48: the velocity change is reduced
    cycles = run(rt, fb)
    assert fb.done and not fb.error
    travelled = belt.set_position - start
    assert travelled == pytest.approx(1000.0, abs=500.0 * 0.001)  # within one cycle's travel
    assert cycles * 0.001 == pytest.approx((1000.0 - 300.0) / 500.0, abs=0.0015)


def test_conveyor_slowing_belt_two_instead() -> None:
    """§3.11 example 1, alternative: a negative distance slows the belt; the velocity
    reserve is the current velocity, so the belt may be braked down to zero but not below."""
    rt, belt = cruising(200.0)
    start = belt.set_position
    fb = MC_MoveSuperImposedExt(belt)
    fb(execute=True, mode=M.VELOREDUCTION_LIMITEDMOTION, distance=-300.0, length=600.0,
       velocity_diff=200.0, velocity_process=200.0)
    velocities = []
    while fb.busy:
        rt.step()
        fb(execute=True)
        velocities.append(belt.set_velocity)
    assert fb.done and min(velocities) >= -1e-9
    assert belt.set_position - start == pytest.approx(600.0, abs=0.3)


@pytest.mark.parametrize("mode", [M.LENGTHREDUCTION_LIMITEDMOTION,
                                  M.LENGTHREDUCTION_ADDITIVEMOTION])
def test_print_roller_fast_correction(mode: M) -> None:
    """§3.11 example 2, rules 49, 50: 7.1° within 360° (LIMITED) or 367.1° (ADDITIVE) at
    30°/s reserve: both give the same, shortest correction; not longer than VELOREDUCTION."""
    results = []
    for m in (mode, M.VELOREDUCTION_LIMITEDMOTION):
        rt, roller = cruising(360.0)
        fb = MC_MoveSuperImposedExt(roller)
        fb(execute=True, mode=m, distance=7.1, length=360.0 if m is not
           M.LENGTHREDUCTION_ADDITIVEMOTION else 367.1 - 7.1, velocity_diff=30.0,
           velocity_process=360.0)
        results.append((run(rt, fb), fb.done, fb.actual_velocity_diff))
    (fast, done, dv), (slow, _, dv_slow) = results
    assert done and fast <= slow
    assert dv == pytest.approx(30.0, rel=1e-9) and dv_slow < 30.0


def test_both_length_reduction_modes_give_the_same_shortest_correction() -> None:
    """§3.11 example 2: LENGTHREDUCTION_LIMITED over 360° == LENGTHREDUCTION_ADDITIVE."""
    durations = []
    for mode, length in ((M.LENGTHREDUCTION_LIMITEDMOTION, 360.0),
                         (M.LENGTHREDUCTION_ADDITIVEMOTION, 360.0)):
        rt, roller = cruising(360.0)
        fb = MC_MoveSuperImposedExt(roller)
        fb(execute=True, mode=mode, distance=7.1, length=length, velocity_diff=30.0,
           velocity_process=360.0)
        durations.append(run(rt, fb))
    assert durations[0] == durations[1]


def test_drilling_unit_travels_length_plus_distance() -> None:
    """§3.11 example 3, rule 46: the workpiece travels 400 mm, the drill 650 mm
    (VELOREDUCTION_ADDITIVEMOTION, 250 mm, reserve 500 mm/s)."""
    rt, drill = cruising(200.0)
    start = drill.set_position
    fb = MC_MoveSuperImposedExt(drill)
    fb(execute=True, mode=M.VELOREDUCTION_ADDITIVEMOTION, distance=250.0, length=400.0,
       velocity_diff=500.0, velocity_process=200.0)
    cycles = run(rt, fb)
    assert fb.done and fb.actual_length == pytest.approx(400.0)
    assert cycles * 0.001 == pytest.approx(400.0 / 200.0, abs=0.0015)  # workpiece: 400 mm
    assert drill.set_position - start == pytest.approx(650.0, abs=0.2)


def test_partial_compensation_reports_0x4243_and_moves_what_it_can() -> None:
    """Rule 44: only part of the distance fits: error 16#4243 (16963), the axis is shifted by
    the achievable distance, ActualDistance < Distance."""
    rt, drill = cruising(200.0)
    start = drill.set_position
    fb = MC_MoveSuperImposedExt(drill)
    fb(execute=True, mode=M.LENGTHREDUCTION_ADDITIVEMOTION, distance=250.0, length=400.0,
       velocity_diff=50.0, velocity_process=200.0)
    assert 0.0 < fb.actual_distance < 250.0
    run(rt, fb)
    assert fb.error and fb.error_id == E.SUPERPOSITION_INCOMPLETE == 0x4243 == 16963
    rt.run(1.0)
    base = 200.0 * (rt.now - 1.0)
    assert drill.set_position - start == pytest.approx(base + fb.actual_distance, abs=1e-6)


@pytest.mark.parametrize("mode", [M.LENGTHREDUCTION_LIMITEDMOTION,
                                  M.VELOREDUCTION_LIMITEDMOTION])
def test_limited_partial_compensation_uses_the_whole_length(mode: M) -> None:
    """Issue 20 point 1, TcMC §3.9/§3.10, §6.5: in the LIMITED modes the axis itself travels
    Length, so a smaller distance leaves more time for itself. At 500 mm/s, distance 250,
    Length 400, VelocityDiff 500, acc/dec 5000: 150 mm fit, the axis travels exactly 400 mm
    and 0x4243 says the rest is missing (D-200; the time budget used to stay that of the full
    250 mm: 42.19 mm in 192.19 mm)."""
    rt = om.Runtime()
    axis = rt.add_axis("x", max_velocity=2000.0)  # the default dynamics otherwise
    axis.power()
    axis.move_velocity(500.0)
    rt.run(1.0)
    start = axis.set_position
    fb = MC_MoveSuperImposedExt(axis)
    fb(execute=True, mode=mode, distance=250.0, length=400.0, velocity_diff=500.0,
       velocity_process=500.0, acceleration=5000.0, deceleration=5000.0)
    assert fb.actual_distance == pytest.approx(150.0, rel=1e-6)
    assert fb.actual_length == pytest.approx(400.0, rel=1e-6)
    run(rt, fb)
    assert fb.error and fb.error_id == E.SUPERPOSITION_INCOMPLETE
    base = 500.0 * (rt.now - 1.0)
    assert axis.set_position - start == pytest.approx(base + fb.actual_distance, abs=1e-6)
    assert base + fb.actual_distance == pytest.approx(400.0, abs=0.5)  # within a cycle


@pytest.mark.parametrize("inputs", [
    {"distance": 0.0}, {"velocity_diff": 0.0}, {"velocity_process": 0.0}, {"length": 0.0},
], ids=["distance", "velocity_diff", "velocity_process", "length"])
def test_zero_inputs_are_errors(inputs: dict) -> None:
    """Rule 41."""
    rt, axis = cruising(200.0)
    fb = MC_MoveSuperImposedExt(axis)
    fb(execute=True, **{"distance": 10.0, "velocity_diff": 50.0, "velocity_process": 200.0,
                        "length": 400.0, **inputs})
    assert fb.error and fb.error_id in (E.INVALID_POSITION, E.INVALID_VELOCITY)


def test_jerk_input_has_no_effect() -> None:
    """Rule 42."""
    ends = []
    for jerk in (0.0, 1.0, 1e9):
        rt, axis = cruising(200.0)
        fb = MC_MoveSuperImposed(axis)
        fb(execute=True, distance=20.0, velocity_diff=100.0, velocity_process=200.0,
           max_distance=200.0, jerk=jerk)
        run(rt, fb)
        ends.append((rt.now, axis.set_position))
    assert ends[0] == ends[1] == ends[2]


def test_positioning_base_move_ends_shifted_by_the_distance() -> None:
    """Rules 43, 51: Busy during the catch-up; the base target is shifted by Distance."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=1000.0, velocity=200.0)
    for _ in range(1000):
        rt.step()
        move(execute=True)
    fb = MC_MoveSuperImposed(axis)
    fb(execute=True, distance=50.0, velocity_diff=100.0, velocity_process=200.0,
       max_distance=500.0)
    assert fb.busy
    while not move.done:
        rt.step()
        move(execute=True)
        fb(execute=True)
    assert fb.done and axis.set_position == pytest.approx(1050.0, abs=1e-9)


def test_abort_superposition_keeps_the_base_motion() -> None:
    """Rule 52: the superposition ends; the base velocity is unchanged afterwards."""
    rt, axis = cruising(200.0)
    fb = MC_MoveSuperImposedExt(axis)
    fb(execute=True, mode=M.VELOREDUCTION_ADDITIVEMOTION, distance=250.0, length=400.0,
       velocity_diff=500.0, velocity_process=200.0)
    rt.run(0.5)
    abort = MC_AbortSuperposition(axis)
    abort(execute=True)
    fb(execute=True)
    assert abort.done and fb.command_aborted
    rt.run(1.0)
    assert axis.set_velocity == pytest.approx(200.0, abs=1e-9)


def test_stop_stops_base_and_superposition() -> None:
    """Rule 53: MC_Stop stops the whole axis; no MC_AbortSuperposition needed."""
    rt, axis = cruising(200.0)
    fb = MC_MoveSuperImposedExt(axis)
    fb(execute=True, mode=M.VELOREDUCTION_ADDITIVEMOTION, distance=250.0, length=400.0,
       velocity_diff=500.0, velocity_process=200.0)
    rt.run(0.5)
    before = axis.set_velocity
    stop = MC_Stop(axis)
    stop(execute=True)
    fb(execute=True)
    assert fb.command_aborted
    velocities = []
    for _ in range(2000):
        rt.step()
        velocities.append(axis.set_velocity)
    assert velocities[-1] == 0.0
    steps = [abs(b - a) for a, b in zip([before, *velocities], velocities, strict=False)]
    assert max(steps) <= 20000.0 * 0.001 * (1 + 1e-9)  # no velocity jump at the switch


def test_a_second_superposition_while_one_runs_is_refused() -> None:
    rt, axis = cruising(200.0)
    axis.move_superimposed(100.0, 100.0, 200.0, 400.0)
    second = axis.move_superimposed(10.0, 100.0, 200.0, 400.0)
    assert second.error and second.error_id == E.SUPERPOSITION_ACTIVE


def test_superposition_on_a_standing_axis_is_an_error() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    fb = MC_MoveSuperImposed(axis)
    fb(execute=True, distance=10.0, velocity_diff=10.0, velocity_process=10.0,
       max_distance=100.0)
    assert fb.error and fb.error_id == E.AXIS_NOT_MOVING


@settings(max_examples=40)
@given(velocity=st.floats(50.0, 800.0), distance=st.floats(-40.0, 300.0).filter(
    lambda d: abs(d) > 1e-3), mode=st.sampled_from(list(M)))
def test_superposition_adds_exactly_the_commanded_distance(velocity: float, distance: float,
                                                           mode: M) -> None:
    """Issue 3 property: with a budget that fits, the axis ends exactly ``distance`` ahead of
    (or behind) where the base motion alone would be, and no limit is exceeded."""
    rt, axis = cruising(velocity)
    start, t0 = axis.set_position, rt.now
    command = axis.move_superimposed(distance, 500.0, velocity, 4.0 * velocity + 2 * abs(distance),
                                     mode)
    assert command.active, command
    peak = 0.0
    while not command.finished:
        rt.step()
        peak = max(peak, abs(axis.set_velocity))
    assert command.done, command
    rt.step()
    base = velocity * (rt.now - t0)
    assert axis.set_position - start == pytest.approx(base + distance, abs=1e-6 * (1 + base))
    assert peak <= velocity + 500.0 + 1e-9 and axis.set_velocity == pytest.approx(velocity)


def test_a_geared_slave_takes_a_superimposed_correction_and_keeps_it() -> None:
    """Issue 3 flying saw: the slave gears to the conveyor, superimposes a correction and stays
    in gear, the correction kept; a master's own superposition is followed by its slave."""
    rt = om.Runtime()
    conveyor = rt.add_axis("conveyor", max_velocity=2000.0)
    saw = rt.add_axis("saw", max_velocity=2000.0)
    conveyor.power()
    saw.power()
    gear = saw.gear_in(conveyor, 1.0)
    conveyor.move_velocity(300.0)
    rt.run(1.0)
    correction = saw.move_superimposed(2.5, 100.0, 300.0, 100.0)
    rt.run_until(correction, 5.0)
    rt.run(0.1)
    assert correction.done and gear.active
    assert saw.set_position - conveyor.set_position == pytest.approx(2.5, abs=1e-9)
    assert saw.set_velocity == conveyor.set_velocity
    shift = conveyor.move_superimposed(10.0, 100.0, 300.0, 300.0)
    rt.run_until(shift, 5.0)
    rt.run(0.1)
    assert saw.set_position - conveyor.set_position == pytest.approx(2.5, abs=1e-9)
