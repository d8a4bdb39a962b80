"""Entries that scenario files had but no scenario test ran (issue 20, "Scenario files reach
every block": each with a scenario test): MC_Power off, MC_ChangeDynParam (TcMC §4.20),
MC_NewPos (§3.7), MC_NewPosAndVelo (§3.8); MC_GroupSetPosition (Part 4 §5.9),
MC_SetKinTransform (§5.8.1), MC_MoveCircularRelative (§5.23), MC_MoveDirectRelative (§5.25),
MC_SetDynCoordTransform (§6.5) and MC_TrackRotaryTable (§6.7)."""

from __future__ import annotations

import pytest

from openmotion.scenario import CommandRow, ScenarioResult, parse_scenario, run_scenario

AXIS = """\
name: axis entries
axes:
  - name: x
    parameters: {max_velocity: 500, acceleration: 2000, deceleration: 2000, jerk: 20000}
timeline:
  - {id: on, at: 0, axis: x, command: power}
  - {id: go, at: 0, axis: x, command: move_absolute, position: 200, velocity: 100}
  - {id: soft, at: 0.3, axis: x, command: change_dynamics, acceleration: 500,
     deceleration: 500, jerk: 5000}
  - {id: there, at: 0.5, axis: x, command: new_position, position: 100}
  - {id: faster, when: go.done, axis: x, command: move_velocity, velocity: 50}
  - {id: stop_at, when: faster.in_velocity, axis: x, command: new_position_and_velocity,
     mode: change_pos_and_velo, position: 150, velocity: 80}
  - {id: off, when: x.set_position >= 140, axis: x, command: power_off}
checks:
  - {command: soft, result: done}
  - {command: there, result: done}
  - {command: go, result: done}
  - {command: stop_at, result: done}
  - {command: faster, result: aborted}
  - {command: off, result: done}
  - {signal: x.state, expect: disabled}
"""

PART4 = """\
name: part4 entries
axes:
  - {name: a1, parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000}}
  - {name: a2, parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000}}
  - {name: b1, parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000}}
  - {name: b2, parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000}}
  - {name: table, parameters: {max_velocity: 100}}
axes_groups:
  - {name: xy, axes: [a1, a2]}
  - {name: uv, axes: [b1, b2]}
timeline:
  - {at: 0, axis: table, command: power}
  - {id: here, at: 0, group: xy, command: group_set_position, position: [10, 0]}
  - {id: gantry, at: 0, group: xy, command: set_kinematics,
     kinematics: {model: cartesian, mapping: [x, y], offset: [5, 0]}}
  - {id: arc, when: gantry.done, group: xy, command: move_circular_relative,
     aux_point: [20, 0], end_point: [20, 20], circ_mode: center}
  - {id: direct, when: arc.done, group: xy, command: move_direct_relative, distance: [-10, 5]}
  - {id: ride, at: 0, group: uv, command: set_dyn_coord_transform, master: xy}
  - {id: turn, at: 0, group: uv, command: track_rotary_table, table: table,
     origin: [0, 0, 0, 0, 0, 0]}
checks:
  - {command: here, result: done}
  - {command: gantry, result: done}
  - {command: arc, result: done}
  - {command: direct, result: done}
  - {signal: xy.x, expect: 25, tolerance: 1e-6}
  - {signal: xy.y, expect: 25, tolerance: 1e-6}
  - {command: ride, result: aborted}
  - {command: turn, result: busy}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


def test_axis_entries_change_the_running_move_and_power_off_ends_it() -> None:
    """§4.20: the new dynamics take effect; §3.7: the move ends at the new target 100, never
    at 200; §3.8: a new target and velocity at speed; power off aborts the running move."""
    result = run_scenario(parse_scenario(AXIS))
    assert result.passed, [check for check in result.checks if not check.passed]
    position = result.trace["x.set_position"]
    ended = round(rows(result)["go"].ended_at / 0.001)
    assert position[ended] == pytest.approx(100.0, abs=1e-9) and max(position[:ended]) < 200.0
    assert max(abs(result.trace["x.set_acceleration"][400:ended])) <= 500.0 + 1e-6


def test_part4_entries_set_position_kinematics_relative_moves_and_tracking() -> None:
    """§5.9, §5.8.1: the ACS (10, 0) with the gantry's offset 5 is MCS (15, 0); §5.23: a
    quarter circle about (35, 0) to (35, 20); §5.25: (-10, 5) in ACS to MCS (25, 25); §6.5,
    §6.7: a tracking FB replaces another on the same PCS and stays Busy."""
    result = run_scenario(parse_scenario(PART4))
    assert result.passed, [check for check in result.checks if not check.passed]
    assert rows(result)["ride"].message == "replaced by MC_TrackRotaryTable"
