"""Running gearing, oriented-stop, on-the-fly and touch-probe entries, and value checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

import openmotion as om
from openmotion.scenario import ScenarioResult, examples_dir, parse_scenario, run_scenario

GEARING = """\
name: gearing
axes:
  - name: m
    parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000, jerk: 50000}
  - name: s
  - name: t
timeline:
  - {at: 0, axis: m, command: power}
  - {at: 0, axis: s, command: power}
  - {at: 0, axis: t, command: power}
  - {id: not_coupled, at: 0, axis: s, command: gear_out}
  - {id: couple, at: 0.01, axis: s, command: gear_in, master: m, ratio: 0.5,
     acceleration: 5000}
  - {id: run, when: couple.in_gear, axis: m, command: move_velocity, velocity: 200}
  - {id: master_moves, when: run.in_velocity, axis: t, command: gear_in, master: m, ratio: 1}
  - {id: faster, when: run.in_velocity, axis: s, command: set_gear_ratio, ratio: 1.5}
  - {id: out, at: 1.0, axis: s, command: gear_out}
  - {id: ratio_after, at: 1.1, axis: s, command: set_gear_ratio, ratio: 1}
  - {at: 1.2, axis: m, command: halt}
  - {at: 1.2, axis: s, command: halt}
record: {signals: [m.set_velocity, s.set_velocity, s.state]}
checks:
  - {name: ratio 0.5, signal: s.set_velocity, expect: 100, when: run.in_velocity}
  - {name: ratio 1.5 after the slew, signal: s.set_velocity, expect: 300, at: 0.9}
  - {name: keeps its velocity after gear_out, signal: s.set_velocity, expect: 300, at: 1.05}
"""


def rows(result: ScenarioResult) -> dict[str, om.scenario.CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def gearing() -> ScenarioResult:
    return run_scenario(parse_scenario(GEARING))


def test_gear_in_couples_and_in_gear_holds_while_coupled(gearing: ScenarioResult) -> None:
    by_id = rows(gearing)
    assert by_id["couple"].issued_at == by_id["run"].issued_at == 0.01  # in_gear at once
    assert (by_id["couple"].result, by_id["couple"].ended_at) == ("ABORTED", 1.0)
    assert "MC_GearOut" in by_id["couple"].message
    trace = gearing.trace
    coupled = (trace.time > 0.01) & (trace.time < 1.0)
    assert np.all(trace["s.state"][coupled] == float(om.AxisState.SYNCHRONIZED_MOTION))


def test_dynamic_ratio_slews_and_gear_out_keeps_the_velocity(gearing: ScenarioResult) -> None:
    assert gearing.passed, gearing.checks
    trace = gearing.trace
    ratio = trace["s.set_velocity"] / np.where(trace["m.set_velocity"] == 0, 1,
                                               trace["m.set_velocity"])
    slewing = (trace.time > rows(gearing)["faster"].issued_at) & (trace.time < 0.9)
    # acceleration 5000 / master max_velocity 1000: at most 5 per second, 0.005 per cycle
    assert np.all(np.abs(np.diff(ratio[slewing])) <= 0.005 + 1e-9)
    assert rows(gearing)["faster"].result == "DONE"


def test_gearing_refusals_are_command_errors(gearing: ScenarioResult) -> None:
    by_id = rows(gearing)
    assert (by_id["not_coupled"].result, by_id["not_coupled"].error) == ("ERROR", "NOT_COUPLED")
    assert (by_id["ratio_after"].result, by_id["ratio_after"].error) == ("ERROR", "NOT_COUPLED")
    assert (by_id["master_moves"].result, by_id["master_moves"].error) == \
        ("ERROR", "AXIS_NOT_STANDSTILL")


GEAR_OUT_EXT = """\
name: gear out ext
duration: 1.5
axes:
  - name: m
  - name: s
    parameters: {{modulo_period: 360}}
timeline:
  - {{at: 0, axis: m, command: power}}
  - {{at: 0, axis: s, command: power}}
  - {{id: couple, at: 0, axis: s, command: gear_in, master: m, ratio: 1}}
  - {{id: run, at: 0.01, axis: m, command: move_velocity, velocity: 100}}
  - {{id: ext, at: 0.5, axis: s, command: gear_out_ext, mode: {mode}, {arguments}}}
record: {{signals: [s.set_position, s.set_velocity, s.state]}}
"""


@pytest.mark.parametrize(("mode", "arguments", "velocity", "position"), [
    ("stop", "deceleration: 2000", 0.0, None),
    ("oriented_stop", "position: 90", 0.0, 90.0),
    ("endless", "jerk: MC_DEFAULT", 100.0, None),
    ("endless_new_velocity", "velocity: 40", 40.0, None),
    ("new_position", "position: 0", 0.0, 0.0),
    ("new_position_and_velocity", "position: 150, velocity: 300", 0.0, 150.0),
    ("instantaneous_stop", "jerk: MC_DEFAULT", 0.0, None),
])
def test_gear_out_ext_runs_its_follow_up(mode: str, arguments: str, velocity: float,
                                         position: float | None) -> None:
    result = run_scenario(parse_scenario(GEAR_OUT_EXT.format(mode=mode, arguments=arguments)))
    row = rows(result)["ext"]
    assert row.result == "DONE" or (row.result == "BUSY" and velocity != 0.0), row
    assert rows(result)["couple"].result == "ABORTED"
    trace = result.trace
    assert trace["s.set_velocity"][-1] == pytest.approx(velocity, abs=1e-9)
    if position is not None:
        final = trace["s.set_position"][-1]
        assert (final % 360.0 if mode == "oriented_stop" else final) == \
            pytest.approx(position, abs=1e-9)
    if mode == "instantaneous_stop":  # the velocity jumps to zero in one cycle
        after = trace.time >= 0.5
        assert np.all(trace["s.set_velocity"][after] == 0.0)


def test_gear_out_ext_at_standstill_is_done_at_once() -> None:
    result = run_scenario(parse_scenario(
        "name: t\naxes: [{name: m}, {name: s}]\ntimeline:\n"
        "  - {at: 0, axis: m, command: power}\n  - {at: 0, axis: s, command: power}\n"
        "  - {at: 0, axis: s, command: gear_in, master: m, ratio: 1}\n"
        "  - {id: ext, at: 0.01, axis: s, command: gear_out_ext, mode: new_position,"
        " position: 50}\n"))
    row = rows(result)["ext"]
    assert (row.result, row.issued_at, row.ended_at) == ("DONE", 0.01, 0.01)


ORIENT_AND_SHIFT = """\
name: oriented stop and on-the-fly
axes:
  - name: r
    parameters: {modulo_period: 360, max_velocity: 720}
  - name: x
timeline:
  - {at: 0, axis: r, command: power}
  - {at: 0, axis: x, command: power}
  - {id: still, at: 0, axis: r, command: oriented_stop, position: 90}
  - {id: spin, at: 0.01, axis: r, command: move_velocity, velocity: 360}
  - {id: bad, when: spin.in_velocity, axis: r, command: oriented_stop, position: 400}
  - {id: orient, when: bad.error, axis: r, command: oriented_stop, position: 90}
  - {id: feed, at: 0.01, axis: x, command: move_absolute, position: 100, velocity: 100}
  - {id: shift, when: x.set_position >= 50, axis: x, command: set_actual_position_on_the_fly,
     actual_position: 1050, previous_position: 50}
checks:
  - {command: still, result: error, error_id: AXIS_NOT_MOVING}
  - {command: bad, result: error, error_id: INVALID_MODULO_TARGET}
  - {command: orient, result: done}
  - {command: spin, result: aborted}
  - {command: shift, result: done}
  - {command: feed, result: done}
  - {name: ends 1000 beyond the old target, signal: x.set_position, expect: 1100}
  - {signal: r.velocity, expect: 0, tolerance: 1e-6}
"""


def test_oriented_stop_and_set_actual_position_on_the_fly() -> None:
    result = run_scenario(parse_scenario(ORIENT_AND_SHIFT))
    assert result.passed, result.checks
    assert result.trace["r.set_position"][-1] % 360.0 == pytest.approx(90.0, abs=1e-9)
    assert np.max(result.trace["x.set_position"]) == pytest.approx(1100.0, abs=1e-9)


PROBE = """\
name: probe
cycle_time: 0.001
axes:
  - name: x
    parameters: {{max_velocity: 500, acceleration: 2000, deceleration: 2000, jerk: 20000}}
    probe: {probe}
timeline:
  - {{at: 0, axis: x, command: power}}
  - {{id: p, at: 0, axis: x, command: touch_probe, {arguments}}}
  - {{id: feed, at: 0.01, axis: x, command: {move}}}
checks:
  - {{command: p, result: done}}
"""
FEED = "move_absolute, position: 200, velocity: 100"


def probe_run(probe: str, arguments: str = "edge: rising", move: str = FEED) -> ScenarioResult:
    return run_scenario(parse_scenario(PROBE.format(probe=probe, arguments=arguments,
                                                    move=move)))


def probe_value(result: ScenarioResult) -> float:
    value = rows(result)["p"].value
    assert rows(result)["p"].result == "DONE" and value is not None, rows(result)["p"]
    return value


def test_a_time_defined_edge_records_the_position_at_that_instant() -> None:
    result = probe_run("{times: [[1.0005, 1.2]]}")
    trace = result.trace
    i = int(np.searchsorted(trace.time, 1.0005))
    assert trace.time[i - 1] < 1.0005 < trace.time[i]
    low, high = trace["x.position"][i - 1], trace["x.position"][i]
    assert probe_value(result) == pytest.approx((low + high) / 2.0, abs=1e-9)
    assert f"value {probe_value(result):.6f}".rstrip("0") in result.summary()


def test_a_falling_edge_and_a_modulo_window() -> None:
    falling = probe_run("{positions: [[50.03, 60.07]]}", "edge: falling")
    assert probe_value(falling) == 60.07
    rotary = probe_run("{positions: [[370.25, 380.0], [10.0, 20.0]]}",
                       "window_only: true, first_position: 10.1, last_position: 15, "
                       "modulo_positions: true", "move_absolute, position: 400, velocity: 500")
    assert probe_value(rotary) == pytest.approx(10.25, abs=1e-9)  # 10.0 is outside the window


def test_moving_backwards_the_rising_edge_is_the_upper_bound() -> None:
    result = run_scenario(parse_scenario("""\
name: backwards
axes:
  - name: x
    position: 100
    probe: {positions: [[50.03, 60.07]]}
timeline:
  - {at: 0, axis: x, command: power}
  - {id: p, at: 0, axis: x, command: touch_probe}
  - {id: q, at: 0, axis: x, command: touch_probe, edge: falling}
  - {at: 0.01, axis: x, command: move_absolute, position: 0, velocity: 100}
checks:
  - {command: p, result: done, value: 60.07}
  - {command: q, result: done, value: 50.03}
"""))
    assert result.passed, result.checks


def test_probe_refusals_and_abort_trigger() -> None:
    result = run_scenario(parse_scenario("""\
name: probe errors
axes:
  - name: x
    probe: {positions: [[5, 6]]}
timeline:
  - {at: 0, axis: x, command: power}
  - {id: empty, at: 0, axis: x, command: touch_probe, window_only: true, first_position: 2,
     last_position: 1}
  - {id: early, at: 0, axis: x, command: abort_trigger, probe: armed}
  - {id: armed, at: 0, axis: x, command: touch_probe, window_only: true, first_position: 100,
     last_position: 200}
  - {id: disarm, at: 0.05, axis: x, command: abort_trigger, probe: armed}
  - {id: again, at: 0.06, axis: x, command: abort_trigger, probe: armed}
  - {at: 0.01, axis: x, command: move_absolute, position: 10, velocity: 100}
checks:
  - {command: empty, result: error, error_id: INVALID_POSITION}
  - {command: early, result: done}
  - {command: armed, result: aborted}
  - {command: disarm, result: done}
  - {command: again, result: done}
"""))
    assert result.passed, result.checks
    assert rows(result)["armed"].ended_at == 0.05 and rows(result)["armed"].value is None


VALUE_CHECKS = """\
name: value checks
axes:
  - name: x
    probe: {positions: [[5.5, 6]]}
timeline:
  - {at: 0, axis: x, command: power}
  - {id: p, at: 0, axis: x, command: touch_probe}
  - {id: m, at: 0.01, axis: x, command: move_absolute, position: 10, velocity: 100}
checks:
  - {command: p, result: done, value: 5.5}
  - {command: p, result: done, value: 5.6, tolerance: 0.05}
  - {command: p, result: done, value: 5.6, tolerance: 0.2}
  - {command: m, result: done, value: 10}
  - {command: p, result: aborted, value: 5.5}
  - {command: p, result: done, value: 5.5, when: p.done}
"""


def test_value_checks_compare_the_command_value() -> None:
    result = run_scenario(parse_scenario(VALUE_CHECKS))
    got = [(check.name, check.passed, check.detail) for check in result.checks]
    assert got == [
        ("p done value 5.5 ± 1e-09 at end", True, "DONE 5.5"),
        ("p done value 5.6 ± 0.05 at end", False, "DONE 5.5, off by -0.1"),
        ("p done value 5.6 ± 0.2 at end", True, "DONE 5.5"),
        ("m done value 10 ± 1e-09 at end", False, "DONE, no value"),
        ("p aborted value 5.5 ± 1e-09 at end", False, "DONE 5.5"),
        ("p done value 5.5 ± 1e-09 when p.done", True, "DONE 5.5"),
    ]
    assert rows(result)["p"].value == 5.5 and rows(result)["m"].value is None
    commands = {row["id"]: row for row in result.to_dict()["commands"]}
    assert commands["p"]["value"] == 5.5 and commands["m"]["value"] is None
    assert "value 5.5" in result.summary()


@pytest.mark.parametrize("name", ["flying_saw", "touch_probe"])
def test_new_examples_are_bit_identical_on_a_second_run(name: str) -> None:
    path = examples_dir() / f"{name}.yaml"
    first, second = run_scenario(path), run_scenario(path)
    assert first.summary() == second.summary()
    for column in first.trace.columns:
        assert np.array_equal(first.trace[column], second.trace[column]), column
    assert all(math.isfinite(row.value) for row in first.commands if row.value is not None)
