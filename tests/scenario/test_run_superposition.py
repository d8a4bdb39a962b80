"""Loading and running move_superimposed and abort_superposition entries."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

import openmotion as om
from openmotion.core.special_values import MC_DEFAULT
from openmotion.scenario import (
    ScenarioError,
    ScenarioResult,
    load_scenario,
    parse_scenario,
    run_scenario,
)
from openmotion.scenario.schema import AbortSuperposition, MoveSuperimposed

LOADS = """\
name: superposition
axes: [{name: x}]
timeline:
  - {id: s, at: 0, axis: x, command: move_superimposed, distance: -2.5, velocity_diff: 50,
     velocity_process: 300, length: 100, mode: veloreduction_limitedmotion, deceleration: 900}
  - {id: d, at: 0, axis: x, command: move_superimposed, distance: 1, velocity_diff: MC_DEFAULT,
     velocity_process: 1, length: 1}
  - {at: 1, axis: x, command: abort_superposition}
checks:
  - {command: s, result: done, value: -2.5}
"""


def test_entries_load_with_api_names_and_values() -> None:
    scenario = parse_scenario(LOADS)
    move, default, abort = scenario.timeline
    assert isinstance(move, MoveSuperimposed) and move.arguments() == {
        "distance": -2.5, "velocity_diff": 50.0, "velocity_process": 300.0, "length": 100.0,
        "mode": om.SuperpositionMode.VELOREDUCTION_LIMITEDMOTION, "acceleration": MC_DEFAULT,
        "deceleration": 900.0}
    assert default.arguments()["mode"] is om.SuperpositionMode.LENGTHREDUCTION_LIMITEDMOTION
    assert default.arguments()["velocity_diff"] is MC_DEFAULT
    assert isinstance(abort, AbortSuperposition) and abort.arguments() == {}


def problems(tmp_path: Path, text: str) -> list[str]:
    path = tmp_path / "scenario.yaml"
    path.write_text(textwrap.dedent(text))
    with pytest.raises(ScenarioError) as caught:
        load_scenario(path)
    return [str(problem) for problem in caught.value.problems]


@pytest.mark.parametrize(("entry", "path", "message"), [
    pytest.param("{at: 0, axis: x, command: move_superimposed, distance: 1, velocity_diff: 5,"
                 " velocity_process: 1, length: 1, mode: additive}", "mode",
                 "must be one of veloreduction_additivemotion, veloreduction_limitedmotion, "
                 "lengthreduction_additivemotion, lengthreduction_limitedmotion", id="mode"),
    pytest.param("{at: 0, axis: x, command: move_superimposed, distance: 1, velocity_diff: 5,"
                 " velocity_process: 1}", "length", "required field is missing",
                 id="missing-length"),
    pytest.param("{at: 0, axis: x, command: move_superimposed, distance: far, velocity_diff: 5,"
                 " velocity_process: 1, length: 1}", "distance", "must be a number",
                 id="distance-type"),
    pytest.param("{at: 0, axis: x, command: move_superimposed, distance: 1, velocity_diff: 5,"
                 " velocity_process: 1, length: 1, jerk: 3}", "jerk", "unknown field",
                 id="no-jerk"),
    pytest.param("{at: 0, axis: x, command: abort_superposition, distance: 1}", "distance",
                 "unknown field", id="abort-arguments"),
    pytest.param("{at: 0, axis: y, command: abort_superposition}", "axis", "unknown axis 'y'",
                 id="abort-axis"),
])
def test_invalid_entries_name_line_and_field(tmp_path: Path, entry: str, path: str,
                                             message: str) -> None:
    found = problems(tmp_path, f"""\
        name: t
        axes: [{{name: x}}]
        timeline:
          - {{at: 0, axis: x, command: power}}
          - {entry}
        """)
    where = f"{tmp_path / 'scenario.yaml'}:5: timeline[1]."
    assert any(p.startswith(where) and f".{path}: " in p and message in p for p in found), found


# TcMC §3.9, the drilling example: a drill cruising at 200 mm/s must gain 250 mm within the
# next 400 mm of its base motion, at most 500 mm/s faster.
DRILL = """\
name: drill
axes:
  - name: drill
    parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000, jerk: 100000}
timeline:
  - {at: 0, axis: drill, command: power}
  - {id: cruise, at: 0, axis: drill, command: move_velocity, velocity: 200}
  - {id: catch_up, when: cruise.in_velocity, axis: drill, command: move_superimposed,
     distance: 250, length: 400, mode: veloreduction_additivemotion, velocity_diff: 500,
     velocity_process: 200}
  - {id: stop, when: catch_up.done, axis: drill, command: halt}
record: {signals: [drill.set_position, drill.set_velocity]}
checks:
  - {command: catch_up, result: done, value: 250}
  - {name: back at the base velocity, signal: drill.set_velocity, expect: 200,
     tolerance: 1e-6, when: catch_up.done}
"""


@pytest.fixture(scope="module")
def drill() -> ScenarioResult:
    return run_scenario(parse_scenario(DRILL))


def test_drilling_example_adds_the_distance_within_the_length(drill: ScenarioResult) -> None:
    assert drill.passed, drill.summary()
    row = {row.id: row for row in drill.commands}["catch_up"]
    assert (row.result, row.error, row.value) == ("DONE", "", 250.0)
    assert row.issued_at is not None and row.ended_at is not None
    trace = drill.trace
    start = np.searchsorted(trace.time, row.issued_at - 1e-9)
    end = np.searchsorted(trace.time, row.ended_at - 1e-9)
    travel = trace["drill.set_position"][end] - trace["drill.set_position"][start]
    # 400 mm of base motion at 200 mm/s (2 s) plus the superimposed 250 mm
    assert row.ended_at - row.issued_at == pytest.approx(2.0, abs=2e-3)
    assert travel == pytest.approx(650.0, abs=0.5)
    # the velocity difference is reduced so that the distance takes the whole length
    velocity = trace["drill.set_velocity"]
    assert 200.0 + 100.0 < velocity.max() < 200.0 + 500.0
    assert "distance 250, velocity diff 129.669345, length 400" in " ".join(
        drill.summary().split())


def test_the_run_waits_for_a_superposition_over_a_base_at_speed() -> None:
    text = DRILL.replace("  - {id: stop, when: catch_up.done, axis: drill, command: halt}\n", "")
    result = run_scenario(parse_scenario(text))
    row = {row.id: row for row in result.commands}["catch_up"]
    assert row.result == "DONE" and result.end_time >= row.ended_at  # type: ignore[operator]


ERRORS = """\
name: superposition errors
axes:
  - name: x
    parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000, jerk: 100000}
timeline:
  - {at: 0, axis: x, command: power}
  - {id: early, at: 0, axis: x, command: move_superimposed, distance: 10, velocity_diff: 50,
     velocity_process: 100, length: 100}
  - {id: cruise, at: 0, axis: x, command: move_velocity, velocity: 100}
  - {id: short, when: cruise.in_velocity, axis: x, command: move_superimposed, distance: 500,
     velocity_diff: 50, velocity_process: 100, length: 100}
  - {id: long, when: cruise.in_velocity, axis: x, command: move_superimposed, distance: 50,
     velocity_diff: 20, velocity_process: 100, length: 1000,
     mode: veloreduction_limitedmotion}
  - {id: twice, when: long.active, axis: x, command: move_superimposed, distance: 5,
     velocity_diff: 20, velocity_process: 100, length: 1000}
  - {id: abort, at: 2.0, axis: x, command: abort_superposition}
  - {id: zero, at: 2.0, axis: x, command: move_superimposed, distance: 0, velocity_diff: 20,
     velocity_process: 100, length: 1000}
  - {id: stop, at: 3.0, axis: x, command: halt}
checks:
  - {command: early, result: error, error_id: AXIS_NOT_MOVING}
  - {command: short, result: error, error_id: SUPERPOSITION_INCOMPLETE}
  - {command: long, result: aborted, value: 50}
  - {command: twice, result: error, error_id: SUPERPOSITION_ACTIVE}
  - {command: abort, result: done}
  - {command: zero, result: error, error_id: INVALID_POSITION}
  - {name: the base motion continues, signal: x.set_velocity, expect: 100, tolerance: 1e-6,
     at: 2.5}
"""


def test_rejections_and_abort_superposition() -> None:
    result = run_scenario(parse_scenario(ERRORS))
    assert result.passed, result.summary()
    row = {row.id: row for row in result.commands}["long"]
    assert row.ended_at == 2.0 and "MC_AbortSuperposition" in row.message
    assert row.value_detail.startswith("distance 50, velocity diff ")
    shown = {row["id"]: row for row in result.to_dict()["commands"]}["long"]
    assert (shown["value"], shown["value_detail"]) == (50.0, row.value_detail)
