"""Loading the planar block, the planar entries, signals and conditions, and their errors
(file:line: field: message)."""

from __future__ import annotations

import inspect

import pytest

from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE
from openmotion.planar import (
    DynamicConstraint_PathXY,
    ExternalSetPositionMode,
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarPart,
    MC_PlanarTrack,
    ModuloDirection,
    PartPosition,
    PlanarState,
    Pose,
    PositionXYC,
    ST_ExternalSetpointGenerationOptions,
    ST_MoveCOptions,
    ST_MoveToPositionOptions,
)
from openmotion.scenario import ScenarioError, parse_scenario
from openmotion.scenario.planar import PLANAR_COMMANDS, PlanarGroupEntry
from openmotion.scenario.planar_objects import EnvironmentEntry, TrackEntry
from openmotion.scenario.planar_parts import PartEntry
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


#: TF5430 §6.6.1's processing unit: part 3 moves between CS 1 and CS 2; all part entries
PARTS = """\
name: parts
axes: [{name: gen}]
planar:
  environment:
    coordinate_systems: [16#01010060, 0x010100A0]
    parts:
      - {oid: 16#01010020, stators: [[0, 0]], positions: [{coordinate_system: 16#01010060}]}
      - {oid: 16#0101_0030, stators: [[0, 0]], positions: [{coordinate_system: 16#010100A0}]}
      - oid: 16#01010080
        stators: [[0, 0]]
        positions:
          - {coordinate_system: 16#01010060, x: 0, y: 240}
          - {coordinate_system: 16#010100A0, x: 0, y: 240, c: 180}
        position_index: 2
  movers:
    - {name: m, part: 16#01010020, x: 120, y: 120}
timeline:
  - {id: go, at: 0, mover: m, command: move_to_position, x: 1, y: 2, reference_id: 16#01010080}
  - {at: 0, mover: m, command: set_position, x: 1, y: 2, reference_id: 16842848}
  - {at: 0, part: 16#01010080, command: activate_part_position, position_index: 1}
  - id: ext
    at: 0
    mover: m
    command: start_external_setpoint_generation
    mode: relative
    reference_id: 16#01010060
    feed_for: 0.5
    feed:
      x: {ramp: {velocity: 100}}
      y: {sine: {amplitude: 10, period: 2, offset: 1}}
      c: {axis: gen}
  - {at: 1, mover: m, command: start_external_setpoint_generation}
  - {at: 1, mover: m, command: stop_external_setpoint_generation}
  - {when: m.coordinate_system == 16#010100A0, mover: m, command: mover_halt}
checks:
  - {signal: m.coordinate_system, expect: 16#010100A0}
"""


def test_parts_and_coordinate_systems_load() -> None:
    """OIDs as the manual prints them (16#..., with _ too) or as YAML integers."""
    scenario = parse_scenario(PARTS)
    environment = scenario.planar.environment
    assert environment.coordinate_systems == [0x01010060, 0x010100A0]
    assert environment.part_oids() == [0x01010020, 0x01010030, 0x01010080]
    assert environment.corners() == [] and not environment.is_static
    layout = environment.layout()
    elevator = layout.part(0x01010080)
    assert elevator.positions == (PartPosition(0x01010060, Pose(0.0, 240.0)),
                                  PartPosition(0x010100A0, Pose(0.0, 240.0, 180.0)))
    assert elevator.position_index == 2 and layout.part(0x01010030).is_static
    assert environment.layout() is not layout  # each run moves its own parts
    parameters = scenario.planar.movers[0].build()
    assert parameters.part_oid == 0x01010020 and parameters.initial_position.x == 120.0


def test_part_entries_build_the_method_arguments() -> None:
    timeline = parse_scenario(PARTS).timeline
    assert timeline[0].arguments()[0] == PositionXYC(1.0, 2.0, 0.0, 0x01010080)
    assert timeline[1].arguments() == (PositionXYC(1.0, 2.0, 0.0, 0x01010060),)
    assert timeline[2].arguments() == (1,) and timeline[2].axis == "16#01010080"
    external = timeline[3]
    assert external.arguments() == (
        ST_ExternalSetpointGenerationOptions(ExternalSetPositionMode.RELATIVE),)
    assert (external.reference_id, external.feed_for) == (0x01010060, 0.5)
    assert list(external.sources()) == ["x", "y", "c"]
    assert external.feed.y.sine.offset == 1.0 and external.feed.c.axis == "gen"
    assert timeline[4].arguments()[0].mode is ExternalSetPositionMode.ABSOLUTE
    assert timeline[4].sources() == {} and timeline[4].reference_id == 0
    when = timeline[6].when
    assert (when.attribute, when.value) == ("coordinate_system", float(0x010100A0))
    assert parse_scenario(PARTS).checks[0].expected == float(0x010100A0)


#: the track commands of a mover (test_planar_tracks.py and test_planar_gearing.py test them
#: in depth)
TRACKS = """\
name: tracks
axes: [{name: belt}]
planar:
  movers: [{name: a}, {name: b, x: 300, y: 0}]
  tracks: [{name: t, geometry: [{line: [[0, 0], [400, 0]]}]}]
timeline:
  - {at: 0, mover: a, command: join_track, track: t}
  - {at: 1, mover: a, command: move_on_track, position: 100}
  - {at: 2, mover: a, command: leave_track, x: 0, y: 240}
  - {at: 3, mover: a, command: gear_in_pos_on_track, master: belt, master_sync_position: 0,
     slave_sync_position: 50, slave_sync_track: t}
  - {at: 4, mover: a, command: gear_in_pos_on_track_with_master_mover, master_mover: b,
     master_sync_position: 300, master_sync_track: t, slave_sync_position: 50,
     slave_sync_track: t}
"""


#: the part commands besides ActivatePosition, AdoptTrackOrientation, the track and
#: environment entries and the Get queries (test_planar_objects.py runs them)
MORE = (PARTS.split("timeline:")[0] + """\
timeline:
  - {at: 0, part: 16#01010080, command: part_allow_enable}
  - {at: 0, part: 16#01010080, command: part_force_disable}
  - {at: 0, part: 16#01010080, command: part_reset}
  - {at: 0, part: 16#01010080, command: part_get_position}
  - {at: 0, mover: m, command: get_position_on_current_part}
""", (TRACKS + """\
  - {at: 5, mover: a, command: adopt_track_orientation, direction: positive, velocity: 90}
  - {at: 5, mover: a, command: mover_get_planar_object_info}
  - {at: 5, track: t, command: track_enable}
  - {at: 5, track: t, command: track_disable}
  - {at: 5, track: t, command: track_reset}
  - {at: 5, track: t, command: track_clear}
  - {at: 5, track: t, command: track_add_to_group, group: g}
  - {at: 5, track: t, command: track_remove_from_group}
  - {at: 5, track: t, command: track_get_length}
  - {at: 5, track: t, command: track_get_position_at, arc_length: 10}
  - {at: 5, track: t, command: track_get_arc_length_closest_to, x: 10, y: 5}
  - {at: 5, track: t, command: track_get_planar_object_info}
  - {at: 5, command: environment_add_to_group, group: g}
  - {at: 5, command: environment_remove_from_group}
  - {at: 5, command: environment_clear}
  - {at: 5, command: environment_get_planar_object_info}
""").replace("planar:\n", "planar:\n  environment: {columns: 4, rows: 3, origin: [-240, -240]}"
                          "\n  groups: [{name: g, enable: false}]\n"))


@pytest.mark.parametrize("command", sorted(PLANAR_COMMANDS))
def test_planar_entry_arguments_fit_the_method(command: str) -> None:
    """Each entry's arguments bind to the MC_PlanarMover (MC_PlanarGroup, MC_PlanarPart)
    method."""
    entry = next(e for text in (VALID, PARTS, TRACKS, *MORE)
                 for e in parse_scenario(text).timeline if e.command == command)
    owner = MC_PlanarGroup if isinstance(entry, PlanarGroupEntry) else MC_PlanarPart \
        if isinstance(entry, PartEntry) else MC_PlanarTrack if isinstance(entry, TrackEntry) \
        else MC_PlanarEnvironment if isinstance(entry, EnvironmentEntry) else MC_PlanarMover
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


CS1, CS2 = "16#01010060", "16#010100A0"


def layout(*parts: str, systems: str = f"[{CS1}]", movers: str = "[{name: m}]") -> str:
    """A planar block with ``parts`` (flow mappings) in ``systems``."""
    return ("planar:\n  environment:\n    coordinate_systems: " + systems + "\n    parts:\n"
            + "".join(f"      - {part}\n" for part in parts) + f"  movers: {movers}\n")


ONE = f"{{oid: 16#01010020, stators: [[0, 0]], positions: [{{coordinate_system: {CS1}}}]}}"
ELEVATOR = (f"{{oid: 16#01010080, stators: [[0, 0]], positions: [{{coordinate_system: {CS1}, "
            f"y: 240}}, {{coordinate_system: {CS2}}}]}}")
ON_ONE = "[{name: m, part: 16#01010020, x: 120, y: 120}]"


@pytest.mark.parametrize(("text", "expected"), [
    (f"planar:\n  environment: {{parts: [{ONE}]}}\n  movers: [{{name: a}}]\n",
     "bad.yaml:3: planar.environment: 'parts' and 'coordinate_systems' go together"),
    (f"planar:\n  environment: {{columns: 1, rows: 1, coordinate_systems: [{CS1}], parts: "
     f"[{ONE}]}}\n  movers: [{{name: a}}]\n",
     "bad.yaml:3: planar.environment: give 'columns' and 'rows', or 'stators' (a list of "
     "[x, y]), or 'parts' with 'coordinate_systems'"),
    ("planar:\n  environment:\n    origin: [0, 0]\n    coordinate_systems: [1]\n"
     f"    parts: [{ONE.replace(CS1, '1')}]\n  movers: [{{name: a}}]\n",
     "bad.yaml:3: planar.environment: 'origin' goes with columns and rows"),
    (layout(ONE, systems="[16#0101006G]"),
     "bad.yaml:4: planar.environment.coordinate_systems[0]: must be an object id (an integer "
     "in 0..16#FFFFFFFF, written 16#01010060 or 0x01010060), got '16#0101006G'"),
    (layout(ONE, systems="[0]"),
     "bad.yaml:4: planar.environment.coordinate_systems[0]: must be an object id, not 0"),
    (layout(ONE, systems="[0x1FFFFFFFF]"),
     "bad.yaml:4: planar.environment.coordinate_systems[0]: must be an object id"),
    (layout(ONE, systems="[]"),
     "bad.yaml:4: planar.environment.coordinate_systems: must hold at least 1 item(s)"),
    (layout(ONE, ONE.replace("16#01010020", CS1)),
     "bad.yaml:7: planar.environment.parts[1].oid: 16#01010060 is used twice: parts and "
     "coordinate systems share one id space (§5.3)"),
    (layout(ONE.replace(f"coordinate_system: {CS1}", f"coordinate_system: {CS2}")),
     "bad.yaml:6: planar.environment.parts[0].positions[0].coordinate_system: 16#010100A0 is "
     "not one of coordinate_systems"),
    (layout(ONE.replace("[[0, 0]]", "[[0, 0], [100, 0]]")),
     "bad.yaml:6: planar.environment.parts[0].stators: corner (100.0, 0.0) is not on the 240 "
     "mm grid of the part frame"),
    (layout(ONE.replace("[[0, 0]]", "[[0, 0], [480, 0]]")),
     "bad.yaml:6: planar.environment.parts[0].stators: (480, 0) shares no edge with the rest"),
    (layout(ONE.replace("[[0, 0]]", "[[240, 0]]")),
     "bad.yaml:6: planar.environment.parts[0].stators: the part frame's origin must be the "
     "part's lower-left corner"),
    (layout(ONE.replace("stators: [[0, 0]]", "stators: []")),
     "bad.yaml:6: planar.environment.parts[0].stators: must hold at least 1 item(s)"),
    (layout(ONE.replace("]}", "], position_index: 2}")),
     "bad.yaml:6: planar.environment.parts[0].position_index: position index 2 is not in 1..1"),
    (layout(ONE.replace(f"{CS1}}}", f"{CS1}, c: 45}}")),
     "bad.yaml:6: planar.environment.parts[0].positions[0].c: must be a multiple of 90°, got 45"),
    (layout(ONE, ONE.replace("20,", "30,").replace(f"{CS1}}}", f"{CS1}, x: 250}}")),
     "bad.yaml:7: planar.environment.parts[1].positions[0]: the part's stators at (250, 0) are "
     "off the 240 mm grid of coordinate system 16#01010060 (anchored at (0, 0))"),
    (layout(ONE, ELEVATOR.replace("y: 240", "y: 0"), systems=f"[{CS1}, {CS2}]"),
     "bad.yaml:7: planar.environment.parts[1].position_index: overlaps part 16#01010020 (§5.1)"),
    (layout(ONE, movers="[{name: m, part: 16#01010030}]"),
     "bad.yaml:7: planar.movers[0].part: 16#01010030 is no part of planar.environment.parts "
     "(parts: 16#01010020)"),
    ("planar:\n  movers: [{name: m, part: 16#01010030}]\n",
     "bad.yaml:3: planar.movers[0].part: planar.environment has no parts"),
    (layout(ONE, ELEVATOR, systems=f"[{CS1}, {CS2}]", movers="[{name: m, x: 120, y: 120}]"),
     "bad.yaml:8: planar.movers[0]: give the 'part' it starts on: with 2 coordinate systems x "
     "and y alone are no place (§5.1)"),
    (layout(ONE, movers="[{name: m, part: 16#01010020, x: 300, y: 120}]"),
     "bad.yaml:7: planar.movers[0]: (300, 120) lies off part 16#01010020: x and y are in the "
     "part frame"),
    (layout(ONE, movers="[{name: m, x: 120, y: 360}]"),
     "bad.yaml:7: planar.movers[0]: the start (120, 360) in coordinate system 16#01010060 lies "
     "on no part"),
    (layout(ONE, ELEVATOR, systems=f"[{CS1}, {CS2}]", movers=ON_ONE)
     + "  groups: [{name: g, environment: true}]\n",
     "bad.yaml:9: planar.groups[0].environment: its boundary would not follow the parts"),
    (layout(ONE, movers=ON_ONE) + "timeline:\n"
     "  - {at: 0, part: 16#01010080, command: activate_part_position, position_index: 1}\n",
     "bad.yaml:9: timeline[0].part: 16#01010080 is no part of planar.environment.parts "
     "(parts: 16#01010020)"),
    (layout(ONE, movers=ON_ONE) + "timeline:\n"
     "  - {at: 0, part: 16#01010020, command: activate_part_position}\n",
     "bad.yaml:9: timeline[0].position_index: required field is missing"),
    (MOVER + "timeline:\n"
     "  - {at: 0, mover: a, command: move_to_position, x: 1, y: 1, reference_id: part2}\n",
     "bad.yaml:5: timeline[0].reference_id: must be an object id"),
    (MOVER + "timeline:\n"
     "  - {at: 0, mover: a, command: start_external_setpoint_generation, mode: sideways}\n",
     "bad.yaml:5: timeline[0].mode: must be 'absolute' or 'relative'"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: start_external_setpoint_generation,\n"
     "     feed: {x: {ramp: {velocity: 1}, sine: {amplitude: 1, period: 1}}}}\n",
     "bad.yaml:6: timeline[0].feed.x: give exactly one of 'sine', 'ramp' or 'axis'"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: start_external_setpoint_generation,\n"
     "     feed: {w: {ramp: {velocity: 1}}}}\n",
     "bad.yaml:6: timeline[0].feed.w: unknown field 'w'"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: start_external_setpoint_generation,\n"
     "     feed: {x: {ramp: {speed: 1}}}}\n",
     "bad.yaml:6: timeline[0].feed.x.ramp.speed: unknown field 'speed'"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: start_external_setpoint_generation,\n"
     "     feed: {x: {axis: q}}}\n",
     "bad.yaml:6: timeline[0].feed.x.axis: unknown axis 'q' (axes: none)"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: start_external_setpoint_generation,\n"
     "     feed: {c: {sine: {amplitude: 1, period: 0}}}}\n",
     "bad.yaml:6: timeline[0].feed.c.sine.period: must be greater than 0"),
    (MOVER + "timeline:\n  - {at: 0, mover: a, command: start_external_setpoint_generation,"
     " feed_for: -1}\n",
     "bad.yaml:5: timeline[0].feed_for: must be greater than or equal to 0"),
    (MOVER + "timeline:\n  - {at: 0, mover: q, command: stop_external_setpoint_generation}\n",
     "bad.yaml:5: timeline[0].mover: unknown planar mover 'q' (planar.movers: a)"),
    (MOVER + "checks:\n  - {signal: a.coordinate_system, expect: 16#0101006G}\n",
     "bad.yaml:5: checks[0].expect: '16#0101006G' is not a number"),
])
def test_bad_part_and_setpoint_input_names_file_line_and_field(text: str, expected: str) -> None:
    found = problems(BASE + text)
    assert any(problem.startswith(expected) for problem in found), found


def test_every_problem_is_listed_at_once() -> None:
    found = problems(BASE + "planar:\n  movers: [{name: a, x: nope}]\n  groups: [{name: 1}]\n"
                            "timeline:\n  - {at: 0, mover: q, command: move_z, position: 1}\n")
    assert [problem.split(":")[1:3] for problem in found] == [
        ["3", " planar.movers[0].x"], ["4", " planar.groups[0].name"],
        ["6", " timeline[0].mover"]]
