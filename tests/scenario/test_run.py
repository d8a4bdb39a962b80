"""Running scenarios: when entries fire, how checks judge, and bit-identical repeat runs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import openmotion as om
from openmotion.scenario import parse_scenario, run_scenario
from openmotion.trace import StreamedTrace, read_csv, read_trace, write_csv

CYCLE = 0.001

MOVE = """\
name: move
axes:
  - name: x
    parameters: {max_velocity: 500, acceleration: 2000, deceleration: 2000, jerk: 20000}
    drive: {model: lag, time_constant: 0.004, dead_time: 0.002}
timeline:
  - {id: on, at: 0, axis: x, command: power}
  - {id: out, at: 0.0105, axis: x, command: move_absolute, position: 100, velocity: 250}
  - {id: half, when: x.set_position >= 50, axis: x, command: set_override, override: 50}
  - {id: back, when: out.done, axis: x, command: move_relative, distance: -100,
     velocity: 400}
record:
  signals: [x.set_position, x.position, x.set_velocity, x.state]
"""


def cycle(seconds: float | None) -> int:
    assert seconds is not None
    return round(seconds / CYCLE)


def rows(result: om.scenario.ScenarioResult) -> dict[str, om.scenario.CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def move_result() -> om.scenario.ScenarioResult:
    return run_scenario(parse_scenario(MOVE))


def test_at_fires_in_the_first_cycle_at_or_after_its_time(move_result) -> None:
    by_id = rows(move_result)
    assert by_id["on"].issued_at == 0.0  # at: 0 acts before the first cycle
    assert cycle(by_id["out"].issued_at) == 11  # 0.0105 s -> cycle 11 (0.011 s)


def test_when_fires_once_in_the_cycle_after_the_condition_became_true(move_result) -> None:
    by_id = rows(move_result)
    # out ends in the motion phase of cycle k; entries are looked at in cycle k + 1
    assert cycle(by_id["back"].issued_at) == cycle(by_id["out"].ended_at) + 1
    trace = move_result.trace
    first = int(np.argmax(trace["x.set_position"] >= 50.0))
    assert cycle(by_id["half"].issued_at) == cycle(trace.time[first]) + 1
    assert [row.result for row in move_result.commands] == ["DONE"] * 4


def test_run_ends_a_settle_time_after_the_last_command(move_result) -> None:
    ended = max(cycle(row.ended_at) for row in move_result.commands)
    assert move_result.cycles == ended + round(0.1 / CYCLE)
    assert move_result.end_time == move_result.cycles * CYCLE
    assert len(move_result.trace) == move_result.cycles + 1  # t = 0 and every cycle
    assert move_result.trace["x.state"][-1] == float(om.AxisState.STANDSTILL)


def test_same_scenario_twice_gives_bit_identical_traces(tmp_path: Path) -> None:
    first, second = (run_scenario(parse_scenario(MOVE)) for _ in range(2))
    assert first.trace.columns == second.trace.columns
    assert np.array_equal(first.trace.data, second.trace.data)
    assert first.summary() == second.summary() and first.to_dict() == second.to_dict()
    path = write_csv(first.trace, tmp_path / "trace.csv")
    again = read_csv(path)
    assert again.equals(first.trace)  # repr floats: the CSV is bit-exact too
    assert path.read_text() == write_csv(second.trace, tmp_path / "again.csv").read_text()


def test_checks_pass_and_fail_with_the_value_seen() -> None:
    result = run_scenario(parse_scenario(MOVE + """\
checks:
  - {signal: x.set_position, expect: 100, when: out.done}
  - {signal: x.set_position, expect: 99, tolerance: 0.5, when: out.done}
  - {signal: x.set_velocity, max: 200, at: always}
  - {signal: x.set_position, min: -1, max: 1}
  - {signal: x.state, expect: standstill, at: 0.001}
  - {command: out, result: done}
  - {command: back, result: aborted}
  - {command: out, result: error, error_id: INVALID_VELOCITY}
  - {name: late, signal: x.position, expect: 0, at: 5}
max_duration: 3
"""))
    assert [check.passed for check in result.checks] == \
        [True, False, False, True, True, True, False, False, False]
    assert not result.passed
    names = [check.name for check in result.checks]
    assert names[0] == "x.set_position == 100 ± 1e-09 when out.done"
    assert names[3] == "-1 <= x.set_position <= 1 at end"
    details = [check.detail for check in result.checks]
    assert details[1] == "100, off by 1"
    assert details[2].startswith("t=") and details[2].endswith("> max 200")
    assert details[6] == "DONE" and details[7] == "DONE"
    assert details[8] == "the run ended at 3 s, before 5 s"  # it waited until max_duration
    assert "FAILED" in result.summary()


def test_command_errors_and_entries_that_never_fire_are_rows_not_exceptions() -> None:
    result = run_scenario(parse_scenario("""\
name: errors
axes: [{name: x}]
timeline:
  - {id: cold, at: 0, axis: x, command: move_absolute, position: 10, velocity: 10}
  - {id: on, at: 0.01, axis: x, command: power}
  - {id: bad, at: 0.02, axis: x, command: move_absolute, position: 10, velocity: -5}
  - {id: never, when: bad.done, axis: x, command: halt}
checks:
  - {command: cold, result: error, error_id: AXIS_DISABLED}
  - {command: bad, result: error, error_id: INVALID_VELOCITY}
  - {signal: x.position, expect: 0, when: never.done}
"""))
    by_id = rows(result)
    assert (by_id["cold"].result, by_id["cold"].error) == ("ERROR", "AXIS_DISABLED")
    assert by_id["bad"].error == "INVALID_VELOCITY" and by_id["bad"].message
    assert by_id["never"].result == "NOT ISSUED" and by_id["never"].issued_at is None
    assert [check.passed for check in result.checks] == [True, True, False]
    assert result.checks[2].detail == "'never.done' never held"
    assert result.end_time < 1.0  # nothing moves: no waiting for max_duration


def test_duration_runs_exactly_and_move_velocity_at_speed_counts_as_settled() -> None:
    text = """\
name: endless
axes: [{name: x}]
timeline:
  - {at: 0, axis: x, command: power}
  - {id: run, at: 0, axis: x, command: move_velocity, velocity: 100}
"""
    fixed = run_scenario(parse_scenario(text + "duration: 0.25\n"))
    assert fixed.cycles == 250 and rows(fixed)["run"].result == "BUSY"
    open_ended = run_scenario(parse_scenario(text))
    assert open_ended.end_time < 1.0 and rows(open_ended)["run"].result == "BUSY"
    capped = run_scenario(parse_scenario(text.replace("velocity: 100", "velocity: 1")
                                         + "max_duration: 0.05\nsettle_time: 1\n"))
    assert capped.cycles == 50


def test_progress_reports_simulated_time_and_finishes_at_the_end() -> None:
    calls: list[tuple[float, float | None]] = []
    result = run_scenario(parse_scenario(MOVE), progress=lambda now, total: calls.append(
        (now, total)))
    times = [now for now, _ in calls]
    assert times == sorted(times) and len(calls) > 2
    assert calls[-1] == (result.end_time, result.end_time)
    assert all(total is None for _, total in calls[:-1])  # open-ended: total unknown


def test_record_every_n_cycles_and_to_dict_is_plain_data() -> None:
    result = run_scenario(parse_scenario(MOVE.replace(
        "record:\n", "duration: 0.1\nrecord:\n  every: 10\n")))
    assert np.allclose(np.diff(result.trace.time), 0.01) and len(result.trace) == 11
    data = result.to_dict()
    assert data["trace"] == {"rows": 11, "columns": list(result.trace.columns)}
    assert data["commands"][1]["issued_at"] == 0.011 and data["passed"] is True


def test_blending_previous_passes_the_first_target_at_the_previous_velocity() -> None:
    result = run_scenario(parse_scenario("""\
name: blending previous
axes:
  - name: x
    parameters: {max_velocity: 800, acceleration: 4000, deceleration: 4000, jerk: 40000}
timeline:
  - {at: 0, axis: x, command: power}
  - {id: fast, at: 0, axis: x, command: move_absolute, position: 200, velocity: 500}
  - {id: slow, at: 0, axis: x, command: move_absolute, position: 300, velocity: 200,
     buffer_mode: blending_previous}
checks:
  - {signal: x.set_velocity, expect: 500, tolerance: 1, when: fast.done}
"""))
    assert result.passed, result.checks


def test_record_keep_and_stream_give_the_end_of_the_run_and_all_of_it(tmp_path: Path,
                                                                      move_result) -> None:
    """D-188: the record section's keep holds the last rows, its stream every row on disk;
    run_scenario's keep/stream replace the section's mode; both read back bit for bit."""
    full = move_result.trace
    kept = run_scenario(parse_scenario(MOVE + "  keep: 25\n"))
    assert kept.trace.data.tobytes() == full.data[-25:].tobytes()
    assert [e.result for e in kept.trace.events] == []  # all commands ended before
    stream = tmp_path / "streamed"
    streamed = run_scenario(parse_scenario(MOVE + "  keep: 25\n"), stream=stream, chunk=100)
    assert isinstance(streamed.trace, StreamedTrace)
    assert streamed.to_dict()["trace"] == {"rows": len(full), "columns": list(full.columns)}
    assert read_trace(stream).equals(full) and read_trace(stream).events == full.events
    again = run_scenario(parse_scenario(MOVE), keep=10)
    assert again.trace.data.tobytes() == full.data[-10:].tobytes()
