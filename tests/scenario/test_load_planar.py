"""Loading the planar block, the planar entries, signals and conditions, and their errors
(file:line: field: message)."""

from __future__ import annotations

import inspect

import pytest

from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE
from openmotion.planar import (
    DynamicConstraint_PathXY,
    MC_PlanarGroup,
    MC_PlanarMover,
    ModuloDirection,
    PlanarState,
    PositionXYC,
    ST_MoveCOptions,
    ST_MoveToPositionOptions,
)
from openmotion.scenario import ScenarioError, parse_scenario
from openmotion.scenario.planar import PLANAR_COMMANDS, PlanarGroupEntry
from openmotion.scenario.schema import COMMANDS, TIMELINE_COMMANDS
from openmotion.trajectory.plan import Limits

VALID = """\
name: planar
planar:
  environment: {columns: 3, rows: 2, origin: [-240, 0]}
  movers:
    - {name: a, x: 0, y: 120}
    - name: b
      x: 360
      y: 120
      c: 90
      enable: false
      parameters:
        mover_width: 120
        default_dynamic_xy: {velocity: 1000}
        maximum_position: {z: 4}
  groups:
    - {name: g, movers: [b, a]}
timeline:
  - {id: go, at: 0, mover: a, command: move_to_position, x: 0, y: 240, velocity: 500,
     jerk: MC_IGNORE}
  - {at: 0, mover: b, command: move_to_position, x: 1, y: 2, c: 90}
  - {at: 0, mover: b, command: move_to_position, x: 1, y: 2, c: 90, use_orientation: false}
  - {id: turn, when: go.done, mover: a, command: move_c, position: 180, direction: positive,
     additional_turns: 1}
  - {when: a.x >= 10, mover: a, command: move_z, position: 2}
  - {when: b.state == enabled, mover: a, command: move_a, position: 1, velocity: 10}
  - {when: g.state == enabled, mover: a, command: move_b, position: -1}
  - {at: 1, mover: a, command: mover_halt, deceleration: 5000}
  - {at: 1, mover: b, command: mover_enable}
  - {at: 1, mover: b, command: mover_disable}
  - {at: 1, mover: b, command: mover_reset}
  - {at: 1, mover: b, command: set_position, x: 5, y: 6}
  - {at: 1, mover: b, command: remove_from_group}
  - {at: 1, mover: b, command: add_to_group, group: g}
  - {at: 1, group: g, command: planar_group_enable}
  - {at: 1, group: g, command: planar_group_disable}
  - {at: 1, group: g, command: planar_group_reset}
checks:
  - {signal: a.state, expect: enabled}
  - {signal: b.z, max: 4}
"""


def test_the_planar_block_loads() -> None:
    scenario = parse_scenario(VALID)
    planar = scenario.planar
    assert scenario.axes == [] and planar is not None
    assert planar.environment.corners() == [(-240.0, 0.0), (0.0, 0.0), (240.0, 0.0),
                                            (-240.0, 240.0), (0.0, 240.0), (240.0, 240.0)]
    a, b = planar.movers
    assert (a.enable, b.enable) == (True, False)
    parameters = b.build()
    assert parameters.mover_width == 120.0 and parameters.mover_height == 155.0
    assert parameters.default_dynamic_xy == Limits(1000.0, 10000.0, 10000.0, 200000.0)
    assert parameters.maximum_position.z == 4.0 and parameters.maximum_position.c == 15.0
    assert (parameters.initial_position.x, parameters.initial_position.c) == (360.0, 90.0)
    assert a.build() == type(parameters)(initial_position=a.build().initial_position)
    assert planar.members(0) == [(("groups", 0, "movers", 0), "b"),
                                 (("groups", 0, "movers", 1), "a")]
    assert planar.has_environment(0)
    assert scenario.signals == ["a.x", "a.y", "a.c", "b.x", "b.y", "b.c"]


def test_planar_entries_build_the_method_arguments() -> None:
    timeline = parse_scenario(VALID).timeline
    target, constraint, options = timeline[0].arguments()
    assert target == PositionXYC(0.0, 240.0, 0.0)
    assert constraint == DynamicConstraint_PathXY(500.0, MC_DEFAULT, MC_DEFAULT, MC_IGNORE)
    assert options == ST_MoveToPositionOptions(use_orientation=False)  # no c: keep it
    assert timeline[1].arguments() == (PositionXYC(1.0, 2.0, 90.0), None,
                                       ST_MoveToPositionOptions(use_orientation=True))
    assert timeline[2].arguments()[2] == ST_MoveToPositionOptions(use_orientation=False)
    assert timeline[3].arguments() == (180.0, None, ST_MoveCOptions(1, ModuloDirection.POSITIVE))
    assert timeline[4].arguments() == (2.0, None)
    assert timeline[7].arguments() == (DynamicConstraint_PathXY(deceleration=5000.0),)
    assert timeline[0].axis == "a" and timeline[-1].axis == "g"  # the summary's column


def test_planar_conditions_read_movers_and_groups() -> None:
    timeline = parse_scenario(VALID).timeline
    x, state, group = (timeline[i].when for i in (4, 5, 6))
    assert (x.subject, x.attribute, x.operator, x.value) == ("a", "x", ">=", 10.0)
    assert (state.subject, state.value) == ("b", float(PlanarState.ENABLED))
    assert (group.subject, group.attribute, group.value) == ("g", "state",
                                                             float(PlanarState.ENABLED))
    checks = parse_scenario(VALID).checks
    assert checks[0].expected == float(PlanarState.ENABLED)  # not AxisState's number


@pytest.mark.parametrize("command", sorted(PLANAR_COMMANDS))
def test_planar_entry_arguments_fit_the_method(command: str) -> None:
    """Each entry's arguments bind to the MC_PlanarMover (MC_PlanarGroup) method."""
    entry = next(e for e in parse_scenario(VALID).timeline if e.command == command)
    owner = MC_PlanarGroup if isinstance(entry, PlanarGroupEntry) else MC_PlanarMover
    signature = inspect.signature(getattr(owner, entry.method))
    signature.bind(None, *entry.arguments())  # self, then the inputs after the feedback


def test_planar_commands_are_timeline_commands_of_their_own() -> None:
    assert set(PLANAR_COMMANDS) <= set(TIMELINE_COMMANDS)
    assert not set(PLANAR_COMMANDS) & set(COMMANDS)  # no clash with axis and CA commands


def problems(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, "bad.yaml")
    return [str(problem) for problem in info.value.problems]


BASE = "name: t\n"
MOVER = "planar:\n  movers: [{name: a}]\n"


@pytest.mark.parametrize(("text", "expected"), [
    ("description: no axes\n",
     "bad.yaml:1: axes: give at least one axis (or planar movers)"),
    ("planar: {}\n", "bad.yaml:2: planar.movers: required field is missing"),
    ("planar:\n  movers: [{name: a, x: 0}, {name: b, x: 100}]\n  groups: [{name: g}]\n",
     "bad.yaml:3: planar.movers[1]: joining group g: PLANAR_COLLISION (33158): the footprint "
     "meets mover a (16#05110010)"),
    ("planar:\n  environment: {columns: 2, rows: 2}\n  movers: [{name: a, x: 10, y: 10}]\n"
     "  groups: [{name: g}]\n",
     "bad.yaml:4: planar.movers[0]: joining group g: PLANAR_COLLISION (33158): the footprint "
     "is not on the stators"),
    ("planar:\n  movers: [{name: a}, {name: b, x: 500}]\n"
     "  groups:\n    - {name: g, movers: [a]}\n    - {name: h, movers: [b, a]}\n",
     "bad.yaml:6: planar.groups[1].movers[1]: 'a' is in group 'g' already"),
    ("planar:\n  environment: {columns: 2}\n  movers: [{name: a}]\n",
     "bad.yaml:3: planar.environment: give both 'columns' and 'rows'"),
    ("planar:\n  environment: {columns: 2, rows: 1, stators: [[0, 0]]}\n  movers: [{name: a}]\n",
     "bad.yaml:3: planar.environment: give 'columns' and 'rows', or 'stators'"),
    ("planar:\n  environment:\n    stators: [[0, 0], [240, 0], [240, 0.5]]\n"
     "  movers: [{name: a}]\n",
     "bad.yaml:4: planar.environment.stators[2]: off the 240 mm stator grid anchored at "
     "(0.0, 0.0)"),
    ("planar:\n  environment:\n    stators: [[0, 0], [240, 0], [240, 0]]\n"
     "  movers: [{name: a}]\n",
     "bad.yaml:4: planar.environment.stators[2]: overlaps stators[1] (240.0, 0.0)"),
    ("planar:\n  environment: {columns: 0, rows: 1}\n  movers: [{name: a}]\n",
     "bad.yaml:3: planar.environment.columns: must be greater than or equal to 1, got 0"),
    ("planar:\n  movers:\n    - name: a\n      parameters: {mover_width: -1}\n",
     "bad.yaml:5: planar.movers[0].parameters.mover_width: must be a finite number > 0, "
     "got -1.0"),
    ("planar:\n  movers:\n    - name: a\n      parameters:\n"
     "        default_dynamic_xy: {velocity: 5000}\n",
     "bad.yaml:6: planar.movers[0].parameters.default_dynamic_xy.velocity: must be > 0 and at "
     "most the maximum 4000.0, got 5000.0"),
    ("planar:\n  movers:\n    - name: a\n      parameters: {mover_widht: 100}\n",
     "bad.yaml:5: planar.movers[0].parameters.mover_widht: unknown field 'mover_widht' "
     "(did you mean 'mover_width'?)"),
    ("axes: [{name: a}]\n" + MOVER,
     "bad.yaml:4: planar.movers[0].name: 'a' is already the name of an axis"),
    ("planar:\n  movers: [{name: a}, {name: a, x: 500}]\n",
     "bad.yaml:3: planar.movers[1].name: 'a' is used 2 times; it must be unique"),
    (MOVER + "  groups: [{name: a}]\n",
     "bad.yaml:4: planar.groups[0].name: 'a' is already the name of a planar mover"),
    (MOVER + "  groups: [{name: g, environment: true}]\n",
     "bad.yaml:4: planar.groups[0].environment: there is no planar.environment"),
    ("planar:\n  environment: {columns: 1, rows: 1}\n  movers: [{name: a}]\n"
     "  groups: [{name: g, environment: true, enable: false}]\n",
     "bad.yaml:5: planar.groups[0].environment: the environment joins in the setup, which "
     "needs enable: true"),
    (MOVER + "  groups: [{name: g, movers: [q]}]\n",
     "bad.yaml:4: planar.groups[0].movers[0]: unknown planar mover 'q' (planar.movers: a)"),
    (MOVER + "timeline:\n  - {at: 0, mover: q, command: move_to_position, x: 1, y: 2}\n",
     "bad.yaml:5: timeline[0].mover: unknown planar mover 'q' (planar.movers: a)"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: move_to_position, x: 1}\n",
     "bad.yaml:5: timeline[0].y: required field is missing"),
    (MOVER + "timeline:\n"
     "  - {at: 0, mover: a, command: move_to_position, x: 1, y: 1, use_orientation: true}\n",
     "bad.yaml:5: timeline[0].use_orientation: true needs c"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: move_to_positon, x: 1, y: 1}\n",
     "bad.yaml:5: timeline[0].command: unknown command 'move_to_positon' "
     "(did you mean 'move_to_position'?)"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: move_c, position: 1, direction: up}\n",
     "bad.yaml:5: timeline[0].direction: must be one of non_modulo, positive, shortest_way, "
     "negative, got 'up'"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: mover_halt, velocty: 1}\n",
     "bad.yaml:5: timeline[0].velocty: unknown field 'velocty' (did you mean 'velocity'?)"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: mover_halt, velocity: fast}\n",
     "bad.yaml:5: timeline[0].velocity: must be a number or one of MC_DEFAULT"),
    (MOVER + "timeline:\n  - {mover: a, command: mover_halt}\n",
     "bad.yaml:5: timeline[0]: give exactly one of 'at' (seconds) or 'when' (a condition)"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: add_to_group, group: g}\n",
     "bad.yaml:5: timeline[0].group: unknown planar group 'g' (planar.groups: none)"),
    (MOVER + "timeline:\n  - {at: 0, group: a, command: planar_group_enable}\n",
     "bad.yaml:5: timeline[0].group: unknown planar group 'a'"),
    (MOVER + "timeline:\n  - {when: a.speed > 3, mover: a, command: mover_halt}\n",
     "bad.yaml:5: timeline[0].when: 'a.speed': a planar mover's signal is one of x, y, z, a, "
     "b, c, velocity, state"),
    (MOVER + "timeline:\n  - {when: a.state == flying, mover: a, command: mover_halt}\n",
     "bad.yaml:5: timeline[0].when: 'a.state == flying': 'flying' is not a planar state "
     "(disabled, enabling, enabled"),
    (MOVER + "timeline:\n  - {when: a.x > far, mover: a, command: mover_halt}\n",
     "bad.yaml:5: timeline[0].when: 'a.x > far': 'far' is not a number"),
    (MOVER + "  groups: [{name: g}]\ntimeline:\n  - {when: g.x > 3, mover: a, command: "
     "mover_halt}\n",
     "bad.yaml:6: timeline[0].when: 'g.x > 3': a planar group's condition is "
     "'<group>.state == <state>'"),
    (MOVER + "record: {signals: [a.set_position]}\n",
     "bad.yaml:4: record.signals[0]: 'a.set_position': a planar mover's signal is one of"),
    (MOVER + "checks:\n  - {signal: a.state, expect: standstill}\n",
     "bad.yaml:5: checks[0].expect: 'standstill' is not a number or a planar state name"),
])
def test_bad_planar_input_names_file_line_and_field(text: str, expected: str) -> None:
    found = problems(BASE + text)
    assert any(problem.startswith(expected) for problem in found), found


def test_every_problem_is_listed_at_once() -> None:
    found = problems(BASE + "planar:\n  movers: [{name: a, x: nope}]\n  groups: [{name: 1}]\n"
                            "timeline:\n  - {at: 0, mover: q, command: move_z, position: 1}\n")
    assert [problem.split(":")[1:3] for problem in found] == [
        ["3", " planar.movers[0].x"], ["4", " planar.groups[0].name"],
        ["6", " timeline[0].mover"]]
