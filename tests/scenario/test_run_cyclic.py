"""Running the block entries: MC_Jog, external setpoints, the override filter, MC_PowerStepper
with its terminal, the reference flag and the axis components."""

from __future__ import annotations

import math

import numpy as np
import pytest

import openmotion as om
from openmotion.scenario import CommandRow, ScenarioResult, parse_scenario, run_scenario

CYCLE = 0.001


def run(text: str) -> ScenarioResult:
    return run_scenario(parse_scenario(text))


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


def at(result: ScenarioResult, signal: str, time: float) -> float:
    """The recorded value of ``signal`` at ``time`` (every cycle recorded)."""
    index = round(time / CYCLE)
    assert result.trace.time[index] == pytest.approx(time)
    return float(result.trace[signal][index])


# -- jog -----------------------------------------------------------------------------------

JOG = """\
name: jog
axes:
  - name: x
    parameters: {max_velocity: 500, acceleration: 2000, deceleration: 2000, jerk: 100000}
timeline:
  - {at: 0, axis: x, command: power}
  - {id: cont, at: 0.1, axis: x, command: jog, mode: continuous, velocity: 100, hold: 0.5}
  - {id: inch, when: cont.done, axis: x, command: jog, mode: inching, position: 2.5,
     velocity: 50, direction: backwards}
  - {id: fast, when: inch.done, axis: x, command: jog, mode: standard_fast,
     release_when: x.position >= 150}
  - {id: no_velocity, when: fast.done, axis: x, command: jog, mode: continuous}
record: {signals: [x.set_position, x.set_velocity]}
checks:
  - {command: cont, result: done}
  - {name: 50 mm after 0.5 s at 100 mm/s, signal: x.set_position, expect: 50, at: 0.669}
  - {name: one inching step back, signal: x.set_position, expect: 47.5, at: 0.783}
  - {command: no_velocity, result: error, error_id: INVALID_VELOCITY}
"""


@pytest.fixture(scope="module")
def jog() -> ScenarioResult:
    return run(JOG)


def test_a_continuous_jog_held_half_a_second_moves_velocity_times_hold(
        jog: ScenarioResult) -> None:
    assert jog.passed, jog.checks
    cont = rows(jog)["cont"]
    assert (cont.result, cont.issued_at) == ("DONE", 0.1)
    # symmetric ramps: the released key brakes as the pressed one accelerated
    assert at(jog, "x.set_velocity", 0.599) == pytest.approx(100.0)
    assert at(jog, "x.set_velocity", 0.6) < 100.0  # released in the cycle of 0.1 + 0.5 s
    assert at(jog, "x.set_position", cont.ended_at) == pytest.approx(50.0, abs=1e-9)
    assert at(jog, "x.set_velocity", cont.ended_at) == 0.0


def test_inching_moves_exactly_one_step_and_conditions_see_the_jog(jog: ScenarioResult) -> None:
    by_id = rows(jog)
    inch = by_id["inch"]
    assert inch.result == "DONE"
    assert inch.issued_at == pytest.approx(by_id["cont"].ended_at + CYCLE)  # like a move's
    assert at(jog, "x.set_position", inch.ended_at) == pytest.approx(47.5, abs=1e-9)


def test_release_when_releases_the_key_in_the_cycle_after_the_condition(
        jog: ScenarioResult) -> None:
    fast_velocity = om.AxisParameters().manual_velocity_fast
    trace = jog.trace
    fast = rows(jog)["fast"]
    during = (trace.time > fast.issued_at) & (trace.time <= fast.ended_at)
    first = trace.time[during][np.argmax(trace["x.set_position"][during] >= 150.0)]
    assert at(jog, "x.set_velocity", first) == pytest.approx(fast_velocity)
    assert at(jog, "x.set_velocity", first + CYCLE) < fast_velocity  # braking
    assert fast.result == "DONE"


def test_a_jog_the_axis_refuses_is_an_error_row(jog: ScenarioResult) -> None:
    refused = rows(jog)["no_velocity"]
    assert (refused.result, refused.error) == ("ERROR", "INVALID_VELOCITY")
    assert refused.issued_at == refused.ended_at


def test_a_held_jog_keeps_the_run_going_and_another_command_aborts_it() -> None:
    result = run("""\
name: t
axes: [{name: x}]
timeline:
  - {at: 0, axis: x, command: power}
  - {id: j, at: 0, axis: x, command: jog, mode: continuous, velocity: 10,
     release_when: x.position > 1000}
  - {id: h, at: 2, axis: x, command: halt}
checks:
  - {command: j, result: aborted}
  - {command: j, result: busy, at: 1.5}
""")
    assert result.passed, result.checks
    assert rows(result)["j"].ended_at == 2.0
    assert result.end_time > 2.0


# -- external setpoints --------------------------------------------------------------------

FEED = """\
name: external setpoints
axes: [{name: g}, {name: x}]
timeline:
  - {at: 0, axis: g, command: power}
  - {at: 0, axis: x, command: power}
  - {id: ext, at: 0.01, axis: x, command: enable_external_setpoints, feed: {axis: g}}
  - {id: m, at: 0.02, axis: g, command: move_absolute, position: 100, velocity: 200}
  - {id: off, at: 0.8, axis: x, command: disable_external_setpoints}
  - {id: sine, at: 1.0, axis: x, command: enable_external_setpoints,
     feed: {sine: {amplitude: 10, period: 0.5}}, feed_for: 0.3}
record: {signals: [g.set_position, x.set_position, x.set_velocity, x.state, x.axis_error_id]}
checks:
  - {command: ext, result: busy, at: 0.5}
  - {command: ext, result: done}
  - {command: sine, result: error, error_id: EXT_SETPOINT_MISSING}
  - {signal: x.state, expect: error_stop}
  - {signal: x.axis_error_id, expect: EXT_SETPOINT_MISSING}
"""


@pytest.fixture(scope="module")
def feed() -> ScenarioResult:
    return run(FEED)


def test_a_slave_fed_from_a_generator_axis_follows_it_one_cycle_later(
        feed: ScenarioResult) -> None:
    assert feed.passed, feed.checks
    trace = feed.trace
    generator, slave = trace["g.set_position"], trace["x.set_position"]
    fed = (trace.time >= 0.01 - 1e-12) & (trace.time < 0.8 - 1e-12)
    index = np.flatnonzero(fed)
    assert np.array_equal(slave[index], generator[index - 1])  # bit for bit, one cycle late
    assert generator[index].max() == 100.0


def test_the_enable_entry_lasts_while_fed_and_disable_ends_it(feed: ScenarioResult) -> None:
    ext = rows(feed)["ext"]
    assert (ext.result, ext.issued_at, ext.ended_at) == ("DONE", 0.01, 0.8)
    assert "MC_ExtSetPointGenDisable" in ext.message
    assert rows(feed)["off"].result == "DONE"


def test_a_sine_feed_starts_at_rest_where_the_axis_is(feed: ScenarioResult) -> None:
    start = at(feed, "x.set_position", 0.999)
    assert start == 100.0
    for tau in (0.0, 0.05, 0.125, 0.25, 0.299):
        expected = start + 10.0 * (1.0 - math.cos(2.0 * math.pi * tau / 0.5)) / 2.0
        assert at(feed, "x.set_position", 1.0 + tau) == pytest.approx(expected, abs=1e-9)
    assert at(feed, "x.set_velocity", 1.0) == 0.0
    assert at(feed, "x.set_velocity", 1.125) == pytest.approx(10.0 / 2 * 2 * math.pi / 0.5)


def test_feeding_stops_after_feed_for_and_the_axis_fails_with_the_missing_feed(
        feed: ScenarioResult) -> None:
    sine = rows(feed)["sine"]
    assert (sine.result, sine.error, sine.ended_at) == ("ERROR", "EXT_SETPOINT_MISSING", 1.3)
    assert at(feed, "x.state", 1.299) == float(om.AxisState.CONTINUOUS_MOTION)
    assert at(feed, "x.state", 1.3) == float(om.AxisState.ERROR_STOP)
    assert at(feed, "x.axis_error_id", 1.3) == float(om.ErrorId.EXT_SETPOINT_MISSING)


def test_a_refused_enable_is_the_entry_error_and_nothing_is_fed() -> None:
    result = run("""\
name: t
axes: [{name: g}, {name: x}]
timeline:
  - {id: ext, at: 0, axis: x, command: enable_external_setpoints, feed: {axis: g}}
""")
    ext = rows(result)["ext"]
    assert (ext.result, ext.error) == ("ERROR", "AXIS_DISABLED")
    assert result.end_time == pytest.approx(0.1)  # nothing kept the run going


# -- override filter -----------------------------------------------------------------------

FILTER = """\
name: override filter
axes:
  - name: x
    parameters: {max_velocity: 500, acceleration: 10000, deceleration: 10000, jerk: 1000000}
  - name: y
timeline:
  - {at: 0, axis: x, command: power}
  - {id: f, at: 0, axis: x, command: override_filter,
     raw: [[0.1, 32767], [0.5, 16384], [0.6, 8192], [0.7, 0], [0.8, 32767]]}
  - {id: bad, at: 0, axis: y, command: override_filter, raw: [[0, 100]], override_steps: 1}
  - {id: v, at: 0, axis: x, command: move_velocity, velocity: 100}
  - {at: 1.2, axis: x, command: halt}
record: {signals: [x.set_velocity, x.override, y.override]}
checks:
  - {command: f, result: busy, value: 100}
  - {command: bad, result: error, error_id: INVALID_PARAMETER_VALUE}
  - {signal: x.override, expect: 25, at: 0.65}
"""


@pytest.fixture(scope="module")
def override_filter() -> ScenarioResult:
    return run(FILTER)


@pytest.mark.parametrize(("time", "percent"), [
    (0.499, 100.0), (0.5, 50.0),  # 16384 of 32767 in 200 steps: step 100, at once
    (0.6, 50.0), (0.649, 50.0), (0.65, 25.0),  # 0.15 s recovery after the change at 0.5 s
    (0.7, 0.0),  # 0 % is applied at once, whatever the recovery time
    (0.8, 100.0),  # and 100 % too
])
def test_the_filtered_override_follows_the_raw_steps(override_filter: ScenarioResult,
                                                     time: float, percent: float) -> None:
    assert at(override_filter, "x.override", time) == percent


def test_the_axis_velocity_follows_the_filtered_override(
        override_filter: ScenarioResult) -> None:
    assert override_filter.passed, override_filter.checks
    assert at(override_filter, "x.set_velocity", 0.499) == 100.0
    assert at(override_filter, "x.set_velocity", 0.6) == pytest.approx(50.0)
    assert at(override_filter, "x.set_velocity", 0.699) == pytest.approx(25.0)
    assert at(override_filter, "x.set_velocity", 0.799) == 0.0
    assert at(override_filter, "x.set_velocity", 1.199) == pytest.approx(100.0)


def test_bad_filter_parameters_end_the_row_with_the_block_error(
        override_filter: ScenarioResult) -> None:
    bad = rows(override_filter)["bad"]
    assert (bad.result, bad.error, bad.ended_at) == ("ERROR", "INVALID_PARAMETER_VALUE", 0.0)
    assert "override_steps must be > 1" in bad.message
    assert at(override_filter, "y.override", 1.0) == 100.0  # nothing applied


def test_a_running_filter_or_stepper_does_not_keep_an_open_ended_run_alive(
        override_filter: ScenarioResult) -> None:
    halt_end = rows(override_filter)["#5"].ended_at
    assert override_filter.end_time == pytest.approx(halt_end + 0.1)  # settle_time
    assert rows(override_filter)["f"].result == "BUSY"


# -- stepper ---------------------------------------------------------------------------------

STEPPER = """\
name: stepper
axes:
  - name: x
    parameters: {enable_position_lag_monitoring: false, max_position_lag: 5,
                 position_lag_filter_time: 0.02}
    drive: {model: lag, time_constant: 0.01, dead_time: 0.002}
timeline:
  - {at: 0, axis: x, command: set_reference_flag, reference_flag: true}
  - {id: ps, at: 0, axis: x, command: power_stepper, override: 80, destall_enable: true,
     destall_detect_mode: DETECT, destall_mode: MODE}
  - {id: m, when: ps.active, axis: x, command: move_absolute, position: 100, velocity: 100}
  - {id: stall, at: 0.3, axis: x, command: inject_stall, duration: 0.2}
record: {signals: [x.set_velocity, x.override, x.homed, x.state, x.axis_error_id]}
"""


def stepper(detect: str, mode: str) -> ScenarioResult:
    return run(STEPPER.replace("DETECT", detect).replace("MODE", mode))


def test_a_stall_with_set_error_is_the_stepper_stall_axis_error() -> None:
    result = stepper("lagging", "set_error")
    trace = result.trace
    fault = trace.time[np.argmax(trace["x.axis_error_id"] != 0)]
    assert at(result, "x.axis_error_id", fault) == om.ErrorId.STEPPER_STALL == 0x4636
    assert at(result, "x.state", fault) == float(om.AxisState.ERROR_STOP)
    assert 0.3 < fault < 0.4  # 5 mm of lag, then 21 cycles of the filter
    m = rows(result)["m"]
    assert (m.result, m.ended_at) == ("ABORTED", fault)
    assert "STEPPER_STALL" in m.message
    assert at(result, "x.homed", 0.6) == 1.0  # set_error keeps the reference
    assert rows(result)["ps"].result == "BUSY"  # the stall is no block error
    assert result.end_time >= 0.5  # the timed stall kept the run going


def test_an_encoderless_stall_with_set_err_non_ref_also_clears_homed() -> None:
    result = stepper("encoderless", "set_err_non_ref")
    # the stepper runs before the entries of a cycle: it sees the bits one cycle later
    assert at(result, "x.axis_error_id", 0.3) == 0.0
    assert at(result, "x.axis_error_id", 0.301) == float(om.ErrorId.STEPPER_STALL)
    assert at(result, "x.homed", 0.300) == 1.0 and at(result, "x.homed", 0.301) == 0.0


def test_use_override_holds_the_profile_and_restores_the_override() -> None:
    result = stepper("lagging", "use_override")
    trace = result.trace
    held = trace["x.override"] == 0.0
    assert held.any() and 0.3 < trace.time[held][0] < 0.4
    assert trace["x.override"][-1] == 80.0  # the application's override again (Q31)
    assert rows(result)["m"].result == "DONE"
    assert np.all(trace["x.axis_error_id"] == 0.0)


def test_release_stall_ends_an_untimed_stall() -> None:
    result = run("""\
name: t
axes: [{name: x}]
timeline:
  - {at: 0, axis: x, command: power}
  - {at: 0.1, axis: x, command: inject_stall}
  - {at: 0.1, axis: x, command: move_relative, distance: 10, velocity: 100}
  - {at: 0.2, axis: x, command: release_stall}
record: {signals: [x.position, x.set_position]}
""")
    assert at(result, "x.position", 0.15) == 0.0 < at(result, "x.set_position", 0.15)
    assert at(result, "x.position", 0.2) == at(result, "x.set_position", 0.2)


# -- reference flag and components -------------------------------------------------------------

def test_set_reference_flag_changes_homed_and_read_axis_components_shows_them() -> None:
    result = run("""\
name: t
axes:
  - name: x
    drive: {model: lag, time_constant: 0.004, dead_time: 0.002}
timeline:
  - {id: on, at: 0.01, axis: x, command: set_reference_flag, reference_flag: true}
  - {id: off, at: 0.02, axis: x, command: set_reference_flag, reference_flag: false}
  - {id: read, at: 0, axis: x, command: read_axis_components}
record: {signals: [x.homed]}
checks:
  - {signal: x.homed, expect: 1, at: 0.015}
  - {signal: x.homed, expect: 0}
  - {command: read, result: done}
""")
    assert result.passed, result.checks
    assert at(result, "x.homed", 0.009) == 0.0 and at(result, "x.homed", 0.01) == 1.0
    read = rows(result)["read"]
    assert read.value is None
    assert read.value_detail == (
        "encoder scaling 1, offset 0, reference cam_and_sync_pulse; drive lag (time constant "
        "0.004 s, dead time 0.002 s); lag monitoring 5 mm for 0.02 s")
    assert "encoder scaling 1" in result.summary()
