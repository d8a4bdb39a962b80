"""TF5410 §9.3's path tables from scenario files (issue 20 point 8, D-213): the
``move_path_table`` entry (the preparation blocks, then MC_MovePath), ``release_blocker``
(MC_ReleaseBlocker) and the group signal ``blocker_id`` (MC_GroupReadBlockerStatus)."""

from __future__ import annotations

import pytest

from openmotion.coordinated.path_table import McCircMode, McTransitionMode
from openmotion.core.enums import BufferMode
from openmotion.scenario import ScenarioError, parse_scenario, run_scenario
from openmotion.scenario.coordinated import MovePathTable

TABLE = """\
name: table
cycle_time: 0.002
axes: [{name: x}, {name: y}, {name: z}]
axes_groups:
  - name: g
    axes: [x, y, z]
    dynamics: {velocity: 200, acceleration: 5000, deceleration: 5000, jerk: 200000}
timeline:
  - id: run
    at: 0
    group: g
    command: move_path_table
    rows:
      - {linear: {position: [50, 0, 0], velocity: 200}}
      - {blocker: {blocker_id: 3}}
      - {circular: {circ_mode: center, aux_point: [25, 25, 0], end_point: [50, 50, 0],
                    path_choice: long_segment, velocity: 200}}
      - {dwell: {dwell_time: 0.1}}
      - {coord_transform: [0, 0, 10, 0, 0, 0]}
      - {linear: {position: [0, 50, 0], velocity: 200, buffer_mode: buffered}}
  - {id: early, at: 0.05, group: g, command: release_blocker, blocker_id: 4}
  - {id: status, when: g.blocker_id == 3, group: g, command: group_read_blocker_status}
  - {id: go, when: status.done, group: g, command: release_blocker, blocker_id: 3}
checks:
  - {command: run, result: done}
  - {command: early, result: error, error_id: UNKNOWN_BLOCKER}
  - {command: go, result: done}
  - {command: status, result: done, output: blocked, value: 1}
  - {command: status, result: done, output: blocker_id, value: 3}
  - {name: at the blocker, signal: g.x, expect: 50.0, tolerance: 1e-6,
     when: g.blocker_id == 3}
  # the long arc about (25, 25) swings left to x = -10.36; the short one would pass 60.36
  - {name: the long arc, signal: g.x, min: -10.4, max: 50.0, at: always}
  - {signal: g.x, expect: 0.0, tolerance: 1e-6}
  - {signal: g.y, expect: 50.0, tolerance: 1e-6}
  - {name: the last row in the new frame, signal: g.z, expect: 10.0, tolerance: 1e-6}
  - {signal: g.state, expect: standby}
"""


def test_a_path_table_runs_from_a_scenario_with_its_blocker_dwell_and_frame() -> None:
    """§9.3.1.2.5-§9.3.1.2.9, §9.3.1.1.10 from a scenario file: the path stands at the
    blocker until release_blocker; an unknown id is UNKNOWN_BLOCKER; the row after the
    coordinate transform lands in its frame (z + 10)."""
    result = run_scenario(parse_scenario(TABLE))
    assert result.passed, [check for check in result.checks if not check.passed]
    rows = {row.id: row for row in result.commands}
    assert rows["run"].command == "move_path_table" and rows["run"].result == "DONE"
    assert rows["go"].issued_at is not None and rows["go"].issued_at > 0.2


def test_rows_load_with_this_manuals_names() -> None:
    scenario = parse_scenario(TABLE)
    entry = next(e for e in scenario.timeline if isinstance(e, MovePathTable))
    kinds = [row.kind for row in entry.rows]
    assert kinds == ["linear", "blocker", "circular", "dwell", "coord_transform", "linear"]
    circular = entry.rows[2].inputs()
    assert circular["circ_mode"] is McCircMode.CENTER
    assert circular["transition_mode"] is McTransitionMode.NONE
    assert circular["buffer_mode"] is BufferMode.BUFFERED


@pytest.mark.parametrize(("row", "expected"), [
    ("{linear: {position: [1, 0, 0]}}", "velocity: required field is missing"),
    ("{linear: {position: [1, 0, 0], velocity: 10}, dwell: {dwell_time: 1}}",
     "give exactly one of linear, circular, blocker, dwell, coord_transform"),
    ("{blocker: {blocker_id: 0}}", "blocker_id"),
    ("{dwell: {dwell_time: -1}}", "dwell_time"),
    ("{circular: {circ_mode: middle, aux_point: [0, 0, 0], end_point: [1, 1, 0], "
     "velocity: 1}}", "circ_mode"),
    ("{coord_transform: [1, 2]}", "coord_transform"),
])
def test_a_bad_row_names_file_line_and_field(row: str, expected: str) -> None:
    text = TABLE.replace("      - {dwell: {dwell_time: 0.1}}", f"      - {row}")
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, "bad.yaml")
    messages = [str(problem) for problem in info.value.problems]
    assert any(expected in message and "bad.yaml:" in message for message in messages), \
        messages


def test_a_row_a_preparation_block_refuses_fails_the_entry_with_its_error() -> None:
    """A row the scenario schema lets through but the block refuses (Aborting after the
    first row, §9.3.2.5) ends the entry with the block's error; the run goes on."""
    text = TABLE.replace("buffer_mode: buffered}}", "buffer_mode: aborting}}")
    result = run_scenario(parse_scenario(text))
    rows = {row.id: row for row in result.commands}
    assert rows["run"].result == "ERROR"
    assert rows["run"].error == "INVALID_BUFFER_MODE"
    assert rows["run"].command == "move_path_table"
    assert "row 6" in rows["run"].message
