"""The group blocks that scenario files reach since issue 20 ("Scenario files reach every
block"): the Part 4 reads (§5.4, §5.10-§5.12, §5.8.3-§5.8.6), the membership blocks and the
status and error reads both kinds of group share (Part 4 §5.1-§5.3, §5.17, §5.18; TF5410
§9.3.1.1), and the TF5410 reads MC_ReadTrackPositions (§9.1.1.1.5) and
MC_TransformPosition (§9.2.1.2). Outputs are read with ``output`` (D-218)."""

from __future__ import annotations

import pytest

from openmotion.scenario import CommandRow, ScenarioResult, parse_scenario, run_scenario

PART4 = """\
name: part4 reads
axes:
  - {name: a1, parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000}}
  - {name: a2, parameters: {max_velocity: 1000, acceleration: 5000, deceleration: 5000}}
  - {name: spare}
axes_groups:
  - name: xy
    axes: [a1, a2]
    kinematics: {model: cartesian, mapping: [x, y], offset: [10, 0]}
    dynamics: {velocity: 100, acceleration: 1000, deceleration: 1000}
timeline:
  - {at: 0, axis: spare, command: power}
  - {id: status0, at: 0, group: xy, command: group_read_status}
  - {id: move, at: 0.01, group: xy, command: move_linear_absolute, position: [110, 50]}
  - {id: moving, at: 0.5, group: xy, command: group_read_status}
  - {id: speed, at: 0.5, group: xy, command: group_read_actual_velocity, coord_system: mcs}
  - {id: ramp, at: 0.5, group: xy, command: group_read_actual_acceleration}
  - {id: acs, when: move.done, group: xy, command: group_read_actual_position}
  - {id: mcs, when: move.done, group: xy, command: group_read_actual_position,
     coord_system: mcs}
  - {id: member2, when: move.done, group: xy, command: group_read_configuration,
     ident_in_group: 2}
  - {id: y_view, when: move.done, group: xy, command: group_read_configuration,
     coord_system: mcs, ident_in_group: 2}
  - {id: kin, when: move.done, group: xy, command: read_kin_transform}
  - {id: place, when: move.done, group: xy, command: set_coordinate_transform,
     frame: [5, 0, 0, 0, 0, 90]}
  - {id: cart, when: place.done, group: xy, command: read_cartesian_transform}
  - {id: coord, when: place.done, group: xy, command: read_coordinate_transform}
  - {id: pcs, when: place.done, group: xy, command: group_read_actual_position,
     coord_system: pcs}
  - {id: no_error, when: place.done, group: xy, command: group_read_error}
  - {id: third, when: place.done, group: xy, command: add_axis_to_group, axis: spare,
     ident_in_group: 3}
  - {id: remove, when: third.done, group: xy, command: remove_axis_from_group,
     ident_in_group: 3}
  - {id: ungroup, when: remove.done, group: xy, command: ungroup_all_axes}
  - {id: empty, when: ungroup.done, group: xy, command: group_read_status}
  - {id: bad, when: ungroup.done, group: xy, command: group_read_configuration, ident_in_group: 1}
checks:
  - {command: status0, result: done, output: group_standby, value: 1}
  - {command: moving, result: done, output: group_moving, value: 1}
  - {command: moving, result: done, output: constant_velocity, value: 1}
  - {command: speed, result: done, output: path_velocity, value: 100, tolerance: 1e-6}
  - {command: ramp, result: done, output: path_acceleration, value: 0, tolerance: 1e-6}
  - {command: acs, result: done, output: position_1, value: 100, tolerance: 1e-6}
  - {command: acs, result: done, output: position_2, value: 50, tolerance: 1e-6}
  - {command: mcs, result: done, output: position_1, value: 110, tolerance: 1e-6}
  - {command: member2, result: done, output: position, value: 50, tolerance: 1e-6}
  - {command: y_view, result: done, output: position, value: 50, tolerance: 1e-6}
  - {command: cart, result: done, output: trans_x, value: 5}
  - {command: cart, result: done, output: rot_z, value: 90, tolerance: 1e-9}
  - {command: coord, result: done, output: rot_z, value: 90, tolerance: 1e-9}
  - {command: pcs, result: done, output: position_1, value: 50, tolerance: 1e-6}
  - {command: pcs, result: done, output: position_2, value: -105, tolerance: 1e-6}
  - {command: no_error, result: done, output: group_error_id, value: 0}
  - {command: third, result: done}
  - {command: remove, result: done}
  - {command: ungroup, result: done}
  - {command: empty, result: done, output: group_disabled, value: 1}
  - {command: bad, result: error, error_id: AXIS_NOT_IN_GROUP}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def part4() -> ScenarioResult:
    return run_scenario(parse_scenario(PART4))


def test_part4_reads_and_membership_pass_their_checks(part4: ScenarioResult) -> None:
    """Part 4 §5.1-§5.4, §5.8.3-§5.8.6, §5.10-§5.12, §5.17, §5.18 from a scenario."""
    assert part4.passed, [check for check in part4.checks if not check.passed]


def test_text_outputs_name_the_member_and_the_model(part4: ScenarioResult) -> None:
    """§5.4: the member with IdentInGroup 2 is a2; in MCS it is the group's y coordinate;
    §5.8.4: the kinematics in force is the Cartesian gantry."""
    by_id = rows(part4)
    assert by_id["member2"].value_detail.startswith("axis a2, position 50")
    assert by_id["y_view"].value_detail.startswith("axis xy.MCS.y, position 50")
    assert by_id["kin"].value_detail == "kin_transform CartesianGantry"


def test_the_group_moves_the_member_added_and_leaves_the_removed_one(part4) -> None:
    """§5.1, §5.2: spare joins as IdentInGroup 3 and leaves again; the group stands."""
    by_id = rows(part4)
    assert by_id["third"].ended_at <= by_id["remove"].issued_at
    assert by_id["ungroup"].result == "DONE"


CA = """\
name: ca reads
axes:
  - {name: m1, position: 0}
  - {name: m2, position: 300}
  - {name: m3, position: 600}
ca_groups:
  - name: ring
    axes: [m1, m2]
    parameters: {default_gap: 100}
timeline:
  - {at: 0, axis: m3, command: power}
  - {id: join, at: 0, group: ring, command: add_axis_to_group, axis: m3, ident_in_group: 3}
  - {id: go, when: join.done, axis: m3, command: move_absolute_ca, position: 650,
     velocity: 200}
  - {id: where, when: go.done, axis: m3, command: read_track_positions}
  - {id: status, when: go.done, group: ring, command: group_read_status}
  - {id: error, when: go.done, group: ring, command: group_read_error}
  - {id: same, when: go.done, group: ring, command: transform_position, origin_position: 42}
  - {id: leave, when: go.done, group: ring, command: remove_axis_from_group, ident_in_group: 3}
  - {id: after, when: leave.done, axis: m3, command: read_track_positions}
  - {id: all, when: leave.done, group: ring, command: ungroup_all_axes}
  - {id: gone, when: all.done, group: ring, command: group_read_status}
checks:
  - {command: go, result: done}
  - {command: where, result: done, output: track_position, value: 650, tolerance: 1e-6}
  - {command: where, result: done, output: track_id, value: 0}
  - {command: status, result: done, output: group_standby, value: 1}
  - {command: status, result: done, output: all_axes_standing, value: 1}
  - {command: error, result: done, output: group_error_id, value: 0}
  - {command: same, result: done, output: destination_position, value: 42}
  - {command: leave, result: done}
  - {command: after, result: error, error_id: AXIS_NOT_IN_GROUP}
  - {command: gone, result: done, output: group_disabled, value: 1}
"""


def test_ca_membership_and_reads_pass_their_checks() -> None:
    """TF5410 §9.3.1.1.1/.4/.5/.8/.12, §9.1.1.1.5, §9.2.1.2: an axis the timeline adds takes
    CA moves; the reads show where it is and how the group stands."""
    result = run_scenario(parse_scenario(CA))
    assert result.passed, [check for check in result.checks if not check.passed]


def test_an_axis_added_by_the_timeline_takes_ca_entries_and_others_do_not() -> None:
    """The schema counts add_axis_to_group as membership (a CA entry for an axis no group
    has is refused when the file loads)."""
    parse_scenario(CA)
    with pytest.raises(Exception, match="'m3' is in no CA group"):
        parse_scenario(CA.replace("command: add_axis_to_group, axis: m3",
                                  "command: add_axis_to_group, axis: m2"))
