"""Axes groups (PLCopen Part 4) in scenario files: loading, errors (file:line: field) and a run
whose group ends where its checks say."""

from __future__ import annotations

import inspect
import re
from pathlib import Path

import numpy as np
import pytest

from openmotion.coordinated.frames import Frame
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem, TransitionMode
from openmotion.coordinated.kinematics import CartesianGantry, Scara
from openmotion.coordinated.states import AxesGroupState, ExecutionMode
from openmotion.core.enums import BufferMode
from openmotion.core.special_values import MC_DEFAULT
from openmotion.geometry.path import CircMode, PathChoice
from openmotion.scenario import ScenarioError, parse_scenario, run_scenario
from openmotion.scenario.coordinated import (
    COORDINATED_COMMANDS,
    MoveCircularAbsolute,
    MovePath,
    SetCartesianTransform,
    TrackConveyorBelt,
)
from openmotion.scenario.queries import Called
from openmotion.scenario.schema import TIMELINE_COMMANDS

VALID = """\
name: groups
axes: [{name: a1}, {name: a2}, {name: a3}, {name: a4}, {name: belt}, {name: s}]
axes_groups:
  - name: arm
    axes: [a1, a2, a3, a4]
    kinematics: {model: scara, l1: 300, l2: 200, z_axis: true, c_axis: true,
                 limits: [[-150, 150], null, [-100, 0], null]}
    dynamics: {velocity: 150, max_velocity: 500}
    cartesian_transform: [100, 0, 0, 0, 0, 90]
  - {name: gantry, axes: [belt], kinematics: {model: cartesian, mapping: [x]}, enable: false}
timeline:
  - {id: arc, at: 0, group: arm, command: move_circular_absolute, aux_point: [0, 0, 0, 0],
     end_point: [1, 1, 0, 0], circ_mode: center, path_choice: clockwise, coord_system: pcs,
     buffer_mode: blending_low, transition_mode: tm_max_corner_deviation,
     transition_parameter: 0.5}
  - {id: p, at: 0, group: arm, command: move_path, velocity: 100,
     path: [{line: [1, 2]}, {arc: [3, 0], aux: [2, 0], circ_mode: center,
            transition_mode: tm_corner_distance, transition_parameter: 2}],
     select: {coord_system: pcs, transition_mode: tm_none}}
  - {id: t, at: 0, group: arm, command: set_cartesian_transform, frame: [1, 2, 3, 0, 0, 45],
     mode: queued}
  - {id: belt_track, at: 0, group: arm, command: track_conveyor_belt, belt: belt,
     origin: [0, 300, 0, 0, 0, 0]}
  - {at: 1, group: arm, command: sync_axis_to_group, slave: s, ratio_numerator: 2}
  - {at: 1, group: arm, command: group_stop, hold: 0.5}
  - {when: arm.state == standby, group: gantry, command: group_enable}
  - {when: arm.path_velocity > 10, group: arm, command: group_interrupt}
record: {signals: [arm.x, arm.path_velocity, a1.set_position]}
checks:
  - {signal: arm.state, expect: standby}
  - {signal: arm.z, max: 0, at: always}
"""


def test_axes_groups_and_their_entries_load() -> None:
    scenario = parse_scenario(VALID)
    arm, gantry = scenario.axes_groups
    assert (arm.name, arm.axes, arm.enable, gantry.enable) == ("arm", ["a1", "a2", "a3", "a4"],
                                                               True, False)
    scara = arm.kinematics.build()
    assert isinstance(scara, Scara) and (scara.l1, scara.l2, scara.n_axes) == (300, 200, 4)
    assert isinstance(gantry.kinematics.build(), CartesianGantry)
    dynamics = arm.dynamics.build()
    assert (dynamics.velocity, dynamics.max_velocity, dynamics.jerk) == (150.0, 500.0, 10000.0)
    arc = scenario.timeline[0]
    assert isinstance(arc, MoveCircularAbsolute) and arc.axis == "arm"
    assert arc.arguments() == {
        "velocity": MC_DEFAULT, "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT,
        "jerk": MC_DEFAULT, "buffer_mode": BufferMode.BLENDING_LOW,
        "transition_mode": TransitionMode.TM_MAX_CORNER_DEVIATION, "transition_parameter": 0.5,
        "coord_system": CoordSystem.PCS, "aux_point": [0.0, 0.0, 0.0, 0.0],
        "end_point": [1.0, 1.0, 0.0, 0.0], "circ_mode": CircMode.CENTER,
        "path_choice": PathChoice.CLOCKWISE}
    path = scenario.timeline[1]
    assert isinstance(path, MovePath)
    assert path.description() == [
        {"line": [1.0, 2.0]},
        {"arc": [3.0, 0.0], "aux": [2.0, 0.0], "circ_mode": CircMode.CENTER,
         "transition_mode": TransitionMode.TM_CORNER_DISTANCE, "transition_parameter": 2.0}]
    assert path.select.coord_system is CoordSystem.PCS
    assert path.select.transition_mode is TransitionMode.TM_NONE
    assert "path" not in path.arguments() and path.arguments()["velocity"] == 100.0
    transform = scenario.timeline[2]
    assert isinstance(transform, SetCartesianTransform)
    arguments = transform.arguments()
    assert arguments["mode"] is ExecutionMode.QUEUED
    assert np.allclose(arguments["frame"].translation, (1, 2, 3))
    track = scenario.timeline[3]
    assert isinstance(track, TrackConveyorBelt) and track.belt == "belt"
    assert track.arguments()["initial_object"].cartesian() == Frame().cartesian()
    condition = scenario.timeline[6].when
    assert (condition.subject, condition.value) == ("arm", float(AxesGroupState.STANDBY))
    assert scenario.timeline[7].when.value == 10.0
    assert scenario.signals == ["arm.x", "arm.path_velocity", "a1.set_position"]


def test_without_record_the_trace_holds_each_groups_tcp_and_path_velocity() -> None:
    scenario = parse_scenario(VALID.replace(
        "record: {signals: [arm.x, arm.path_velocity, a1.set_position]}\n", ""))
    assert scenario.signals[-8:] == [f"{group}.{prop}" for group in ("arm", "gantry")
                                     for prop in ("x", "y", "z", "path_velocity")]


@pytest.mark.parametrize("command", sorted(COORDINATED_COMMANDS))
def test_entry_arguments_are_the_group_method_parameters(command: str) -> None:
    """(The reads call their block: their fields are its inputs, D-218.)"""
    model = COORDINATED_COMMANDS[command]
    fields = set(model.model_fields) - {"id", "at", "when", "group", "command", "select"}
    if issubclass(model, Called):
        assert fields <= set(model.block_type.INPUTS)
        return
    parameters = set(inspect.signature(getattr(AxesGroup, model.method)).parameters)
    assert fields - {"path", "rows"} <= parameters, fields - parameters  # rows: D-213
    assert TIMELINE_COMMANDS[command] is model


def problems(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, "bad.yaml")
    return [str(problem) for problem in info.value.problems]


BASE = "name: t\naxes: [{name: a}, {name: b}, {name: c}]\n"
GROUP = "axes_groups: [{name: g, axes: [a, b]}]\ntimeline:\n"


@pytest.mark.parametrize(("text", "expected"), [
    ("axes_groups:\n  - {name: g, axes: [a, q]}\n",
     "bad.yaml:4: axes_groups[0].axes[1]: unknown axis 'q' (axes: a, b, c)"),
    ("axes_groups:\n  - {name: g, axes: [a]}\n  - {name: h, axes: [b, a]}\n",
     "bad.yaml:5: axes_groups[1].axes[1]: 'a' is listed 2 times in axes_groups (g, h); an "
     "axis is in one axes group only"),
    ("ca_groups: [{name: ring, axes: [a]}]\naxes_groups: [{name: g, axes: [a]}]\n",
     "bad.yaml:4: axes_groups[0].axes[0]: 'a' is in CA group 'ring' already"),
    ("axes_groups: [{name: b, axes: [a]}]\n",
     "bad.yaml:3: axes_groups[0].name: 'b' is already the name of an axis"),
    ("axes_groups:\n  - name: g\n    axes: [a, b]\n    kinematics: {model: scara, l1: 300}\n",
     "bad.yaml:6: axes_groups[0].kinematics.l2: required for the scara model"),
    ("axes_groups:\n  - name: g\n    axes: [a, b]\n"
     "    kinematics: {model: cartesian, mapping: [x, y], l1: 3}\n",
     "bad.yaml:6: axes_groups[0].kinematics.l1: not a field of the cartesian model (fields: "
     "mapping, sign, offset)"),
    ("axes_groups:\n  - name: g\n    axes: [a, b]\n"
     "    kinematics: {model: scara, l1: -1, l2: 2}\n",
     "bad.yaml:6: axes_groups[0].kinematics.l1: must be a finite number > 0, got -1.0"),
    ("axes_groups:\n  - name: g\n    axes: [a, b, c]\n"
     "    kinematics: {model: scara, l1: 1, l2: 2}\n",
     "bad.yaml:6: axes_groups[0].kinematics: the scara model drives 2 axes, the group has 3"),
    ("axes_groups:\n  - name: g\n    axes: [a, b]\n    kinematics: {model: robot}\n",
     "bad.yaml:6: axes_groups[0].kinematics.model: must be 'cartesian', 'scara' or 'delta'"),
    ("axes_groups:\n  - name: g\n    axes: [a]\n    dynamics: {velocity: 0}\n",
     "bad.yaml:6: axes_groups[0].dynamics.velocity: must be > 0, got 0.0"),
    ("axes_groups:\n  - name: g\n    axes: [a]\n    dynamics: {velocity: 5000}\n",
     "bad.yaml:6: axes_groups[0].dynamics.velocity: 5000.0 is above max_velocity 1000.0"),
    ("axes_groups:\n  - name: g\n    axes: [a]\n    dynamcs: {velocity: 5}\n",
     "bad.yaml:6: axes_groups[0].dynamcs: unknown field 'dynamcs' (did you mean 'dynamics'?)"),
    ("axes_groups:\n  - name: g\n    axes: [a]\n    cartesian_transform: [1, 2, 3]\n",
     "bad.yaml:6: axes_groups[0].cartesian_transform: give six values: trans_x, trans_y, "
     "trans_z [mm], rot_angle1, rot_angle2, rot_angle3 [°]; got 3"),
    (GROUP + "  - {at: 0, group: h, command: move_linear_absolute, position: [1, 2]}\n",
     "bad.yaml:5: timeline[0].group: unknown axes group 'h' (axes_groups: g)"),
    (GROUP + "  - {at: 0, group: h, command: group_halt}\n",
     "bad.yaml:5: timeline[0].group: unknown group 'h' (ca_groups: none; axes_groups: g)"),
    (GROUP + "  - {at: 0, group: g, command: move_linear_absolute, position: [1, 2],\n"
             "     buffer_mode: blending_low, transition_mode: tm_corner}\n",
     "bad.yaml:6: timeline[0].transition_mode: must be one of tm_none, tm_start_velocity, "
     "tm_constant_velocity, tm_corner_distance, tm_max_corner_deviation, got 'tm_corner'"),
    (GROUP + "  - {at: 0, group: g, command: move_linear_absolute, position: [1, 2],\n"
             "     coord_system: wcs}\n",
     "bad.yaml:6: timeline[0].coord_system: must be one of acs, mcs, pcs, got 'wcs'"),
    (GROUP + "  - {at: 0, group: g, command: move_linear_absolute, positon: [1, 2]}\n",
     "bad.yaml:5: timeline[0].positon: unknown field 'positon' (did you mean 'position'?)"),
    (GROUP + "  - {at: 0, group: g, command: move_path, path: [{line: [1, 2], arc: [3, 4]}]}\n",
     "bad.yaml:5: timeline[0].path[0]: give 'line' or 'arc' (a point), not both"),
    (GROUP + "  - {at: 0, group: g, command: move_path, path: [{arc: [3, 4]}]}\n",
     "bad.yaml:5: timeline[0].path[0]: aux: an arc needs its aux point"),
    (GROUP + "  - {at: 0, group: g, command: move_path, path: [{line: [1, 2, 3, 4]}]}\n",
     "bad.yaml:5: timeline[0].path[0].line: List should have at most 3 items"),
    (GROUP + "  - {at: 0, group: g, command: track_conveyor_belt, belt: q, origin: [0, 0]}\n",
     "bad.yaml:5: timeline[0].belt: unknown axis 'q' (axes: a, b, c)"),
    (GROUP + "  - {when: g.state == flying, group: g, command: group_halt}\n",
     "bad.yaml:5: timeline[0].when: 'g.state == flying': an axes group's state condition is "
     "'<group>.state == <state>' (states: disabled, standby, moving, stopping, error_stop, "
     "homing)"),
    (GROUP + "  - {when: g.speed > 3, group: g, command: group_halt}\n",
     "bad.yaml:5: timeline[0].when: 'g.speed': an axes group's signal is one of x, y, z, "
     "path_velocity, path_acceleration, state"),
    ("axes_groups: [{name: g, axes: [a]}]\ncheckss: []\n",
     "bad.yaml:4: checkss: unknown field 'checkss' (did you mean 'checks'?)"),
    ("axes_groups: [{name: g, axes: [a]}]\nchecks:\n  - {signal: g.state, expect: moved}\n",
     "bad.yaml:5: checks[0].expect: 'moved' is not a number or an axes group state name"),
])
def test_bad_axes_group_input_names_file_line_and_field(text: str, expected: str) -> None:
    found = problems(BASE + text)
    assert any(problem.startswith(expected) for problem in found), found


RUN = """\
name: square, then halted
cycle_time: 0.002
axes: [{name: x}, {name: y}, {name: conveyor}]
axes_groups:
  - name: xy
    axes: [x, y]
    dynamics: {velocity: 200, acceleration: 2000, deceleration: 2000, jerk: 40000}
timeline:
  - {id: out, at: 0, group: xy, command: move_linear_absolute, position: [50, 0]}
  - {id: up, at: 0, group: xy, command: move_linear_relative, distance: [0, 50],
     buffer_mode: buffered}
  - {id: back, at: 0, group: xy, command: move_path, buffer_mode: buffered,
     path: [{line: [0, 50]}, {line: [0, 0]}], select: {transition_mode: tm_none}}
  - {id: bad, at: 0, group: xy, command: move_path, buffer_mode: buffered,
     path: [{arc: [10, 0], aux: [5, 0], circ_mode: center}, {arc: [20, 0], aux: [15, 0],
            circ_mode: center}]}
  - {id: late, when: back.done, group: xy, command: move_direct_absolute, position: [40, 20],
     velocity: 100}
  - {id: wrong, when: back.done, group: xy, command: move_linear_absolute, position: [1, 2, 3]}
  - {id: halt, at: 1.7, group: xy, command: group_halt}
checks:
  - {command: back, result: done}
  - {command: bad, result: error, error_id: INVALID_PATH_GEOMETRY}
  - {command: wrong, result: error, error_id: INVALID_POSITION}
  - {command: late, result: aborted}
  - {command: halt, result: done}
  - {name: at the corner, signal: xy.y, expect: 50, tolerance: 1e-9, when: up.done}
  - {signal: xy.state, expect: standby}
  - {signal: xy.path_velocity, min: 0, max: 200.000001, at: always}
"""


@pytest.fixture(scope="module")
def square():
    return run_scenario(parse_scenario(RUN))


def test_a_run_moves_the_group_and_ends_where_the_checks_say(square) -> None:
    assert square.passed, [check for check in square.checks if not check.passed]
    rows = {row.id: row for row in square.commands}
    assert rows["out"].result == rows["up"].result == rows["back"].result == "DONE"
    assert rows["out"].axis == "xy" and rows["back"].command == "move_path"
    assert rows["bad"].message.startswith("element 1: CENTER")  # MC_PathSelect's error
    (group,) = square.axes_groups
    assert group.group == "xy" and group.state == "standby"
    assert [name for name, _ in group.axes] == ["x", "y"]
    assert group.x == pytest.approx(square.trace["x.set_position"][-1])
    assert 5.0 < group.x < 10.0 and group.y == pytest.approx(group.x / 2)  # halted on the way
    assert group.z == 0.0


def test_the_summary_shows_the_groups_table_and_json_the_rows(square) -> None:
    text = square.summary()
    assert "square, then halted: 3 axes, 1 axes group," in text
    assert "Axes groups" in text and "axes (set position)" in text
    data = square.to_dict()
    assert data["axes_groups"][0]["group"] == "xy"
    assert data["axes_groups"][0]["state"] == "standby"


def test_the_default_trace_has_the_groups_signals(square) -> None:
    assert {"xy.x", "xy.y", "xy.z", "xy.path_velocity"} <= set(square.trace.signals)
    corner = np.flatnonzero(square.trace["xy.y"] == 50.0)
    assert corner.size and square.trace["xy.x"][corner[0]] == pytest.approx(50.0)


def test_the_docs_example_runs_as_described() -> None:
    """docs/scenarios.md#axes-groups: a blended corner, a path back, checks that pass."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "scenarios.md").read_text()
    block = re.search(r"## Axes groups\n\n```yaml\n(.*?)```", text, re.S)
    assert block is not None
    result = run_scenario(parse_scenario("name: docs\n" + block.group(1)))
    assert result.passed, result.checks
    assert [row.result for row in result.commands] == ["DONE"] * 3


STOPS = """\
name: stops
cycle_time: 0.002
axes: [{name: x}, {name: y}]
axes_groups: [{name: xy, axes: [x, y]}]
timeline:
  - {id: go, at: 0, group: xy, command: move_linear_absolute, position: [100, 0]}
  - {id: stop, at: 0.3, group: xy, command: group_stop, hold: 0.5}
  - {id: refused, at: 0.5, group: xy, command: move_linear_absolute, position: [0, 0]}
  - {id: again, at: 1.0, group: xy, command: move_linear_absolute, position: [0, 50]}
  - {id: pause, at: 1.2, group: xy, command: group_interrupt}
  - {id: resume, at: 1.6, group: xy, command: group_continue}
  - {id: slow, at: 1.6, group: xy, command: group_set_override, velocity: 0.5}
  - {id: off, when: again.done, group: xy, command: group_disable}
checks:
  - {command: go, result: aborted}
  - {command: refused, result: error, error_id: GROUP_STOPPING}
  - {name: held Stopping while Execute is TRUE, signal: xy.state, expect: stopping, at: 0.7}
  - {name: interrupted, signal: xy.path_velocity, expect: 0, when: pause.done}
  - {command: resume, result: done}
  - {signal: xy.y, expect: 50.0, when: again.done}
  - {signal: xy.state, expect: disabled}
"""


def test_group_stop_holds_then_interrupt_and_continue_finish_the_move() -> None:
    result = run_scenario(parse_scenario(STOPS))
    assert result.passed, [check for check in result.checks if not check.passed]
    rows = {row.id: row for row in result.commands}
    assert rows["stop"].ended_at == pytest.approx(0.5)  # Done at rest, held until 0.8
    assert rows["again"].ended_at > rows["resume"].issued_at


CAM = """\
name: cam
axes: [{name: x}, {name: y}, {name: m}]
axes_groups: [{name: xy, axes: [x, y]}]
timeline:
  - {id: sync, at: 0, group: xy, command: sync_group_to_axis, master: m,
     path: [{line: [100, 0]}, {line: [100, 50]}], tuc_numerator: 2}
  - {at: 0, axis: m, command: power}
  - {id: go, at: 0.1, axis: m, command: move_absolute, position: TARGET, velocity: 50}
checks:
  - {command: go, result: done}
"""


@pytest.mark.parametrize(("target", "end"), [(40.0, (80.0, 0.0)), (100.0, (100.0, 50.0))])
def test_sync_group_to_axis_follows_the_master_along_the_path_and_stops_at_its_end(
        target: float, end: tuple[float, float]) -> None:
    """MC_SyncGroupToAxis from a scenario (§6.4): the arc length is twice the master's travel,
    at every cycle (the group takes on the master's acceleration x 2, above its own default
    deceleration: that is no reason to run for the path's end); a master that goes on past
    the end leaves the group standing exactly on it, still Busy."""
    result = run_scenario(parse_scenario(CAM.replace("TARGET", str(target))))
    assert result.passed, result.checks
    rows = {row.id: row for row in result.commands}
    assert rows["sync"].result == "BUSY"
    trace = result.trace
    s = 2.0 * trace["m.set_position"]
    x, y = trace["xy.x"], trace["xy.y"]
    following = s <= (100.0 if target < 50.0 else 50.0)  # before it brakes for the end
    assert np.allclose(x[following], s[following], atol=1e-9)
    assert np.all(y[following] == 0.0) and np.all(x <= 100.0) and np.all(y <= 50.0 + 1e-9)
    assert (x[-1], y[-1]) == pytest.approx(end, abs=1e-9)


PART4_INPUTS = """\
name: part4 inputs
axes: [{name: x}, {name: y}, {name: m}, {name: s}, {name: belt}]
axes_groups: [{name: xy, axes: [x, y]}]
timeline:
  - {at: 0, axis: m, command: power}
  - {at: 0, axis: s, command: power}
  - {at: 0, axis: belt, command: power}
  - {id: odo, at: 0, group: xy, command: sync_axis_to_group, slave: s, deceleration: 500,
     jerk: 20000, coord_system: mcs, buffer_mode: aborting}
  - {id: go, at: 0, group: xy, command: move_linear_absolute, position: [0, 80]}
  - {id: halt, at: 0.2, group: xy, command: group_halt, buffer_mode: buffered}
  - {id: belt_on, at: 0.2, group: xy, command: track_conveyor_belt, belt: belt,
     origin: [0, 0, 0, 0, 0, 0], coord_system: pcs, buffer_mode: blending_next}
  - {id: sync, at: 0.3, group: xy, command: sync_group_to_axis, master: m,
     path: [{line: [100, 0]}], buffer_mode: buffered}
  - {id: pull, when: sync.active, axis: m, command: move_absolute, position: 40,
     velocity: 100}
checks:
  - {command: go, result: done}
  - {command: halt, result: done}
  - {command: pull, result: done}
"""


def test_the_optional_inputs_of_points_4_and_6_reach_the_group_from_a_scenario() -> None:
    """Part 4 §5.14, §6.3, §6.4, §6.6 from a scenario file (issue 20 points 4 and 6): the
    buffered halt, tracking and sync wait for the move, the sync then follows the master
    from (0, 80) towards (100, 0), and the odometer counts the whole path (D-193, D-194)."""
    result = run_scenario(parse_scenario(PART4_INPUTS))
    assert result.passed, [check for check in result.checks if not check.passed]
    rows = {row.id: row for row in result.commands}
    assert rows["halt"].ended_at == pytest.approx(rows["go"].ended_at)
    assert rows["sync"].result == "BUSY" and rows["belt_on"].result == "BUSY"
    trace = result.trace
    way = np.array([100.0, -80.0]) / np.hypot(100.0, 80.0)
    end = np.array([0.0, 80.0]) + 40.0 * way
    assert (trace["xy.x"][-1], trace["xy.y"][-1]) == pytest.approx(tuple(end), abs=1e-6)
    assert trace["s.set_position"][-1] == pytest.approx(120.0, abs=1e-3)  # 80 + 40 mm


@pytest.mark.parametrize("command", ["group_halt", "group_stop"])
def test_a_ca_groups_halt_and_stop_take_no_buffer_mode(command: str) -> None:
    text = ("name: t\naxes: [{name: a}]\nca_groups: [{name: ca, axes: [a]}]\ntimeline:\n"
            f"  - {{at: 0, group: ca, command: {command}, buffer_mode: buffered}}\n")
    found = problems(text)
    assert any("buffer_mode" in problem and "CA group" in problem for problem in found), found


def test_group_home_takes_a_coord_system_from_a_scenario() -> None:
    text = """\
name: home
axes: [{name: x, parameters: {reference_mode: direct}},
       {name: y, parameters: {reference_mode: direct}}]
axes_groups: [{name: xy, axes: [x, y], cartesian_transform: [10, 20, 0, 0, 0, 0]}]
timeline:
  - {id: home, at: 0, group: xy, command: group_home, position: [1, 2], coord_system: pcs}
checks:
  - {command: home, result: done}
  - {signal: x.set_position, expect: 11.0}
  - {signal: y.set_position, expect: 22.0}
"""
    result = run_scenario(parse_scenario(text))
    assert result.passed, [check for check in result.checks if not check.passed]
