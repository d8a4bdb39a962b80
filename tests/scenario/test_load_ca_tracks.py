"""Loading the tracks and geo-compensation of CA groups (parts, tracks, geometry, templates),
activate_track, register_compensation, the reference systems of CA moves and the mover
signals track_position and tcp_position, and their errors (file:line: field)."""

from __future__ import annotations

import inspect
import math

import pytest

from openmotion.runtime.runtime import Runtime
from openmotion.scenario import ScenarioError, parse_scenario
from openmotion.scenario.schema import COMMANDS
from openmotion.scenario.tracks import configure
from openmotion.scenario.transport import (
    CA_ENTRIES,
    ActivateTrack,
    MoveAbsoluteCa,
    MoveRelativeCa,
    RegisterCompensation,
)
from openmotion.transport import CaGroup
from openmotion.transport.geo import STARTER_KIT_CURVE_RADIUS, GeoCompensation
from openmotion.transport.tracks import TrackTable

VALID = """\
name: tracks
axes: [{name: a}, {name: b}, {name: x}]
ca_groups:
  - name: ring
    axes: [a, b]
    parameters: {rail_length: 3000}
    parts:
      - {id: 11, start: 500, end: 2000}
      - {id: 12, start: 2000, end: 500}
    tracks: [{id: 21, parts: [11, 12]}, {id: 22, parts: [12]}]
    geometry: {rail_offset: 10}
    templates: [{id: 31, y_shift: 50}, {id: 32}]
timeline:
  - {id: on, at: 0, axis: a, command: activate_track, track: 21}
  - {id: reg, at: 0, axis: b, command: register_compensation, template: 31}
  - {id: m, at: 0, axis: b, command: move_absolute_ca, position: 100, velocity: 10,
     position_reference_system: 31, dynamics_reference_system: 31}
  - {id: r, at: 0, axis: b, command: move_relative_ca, distance: 5, velocity: 10,
     dynamics_reference_system: 31}
  - {when: a.track_position >= 50, axis: x, command: power}
  - {when: b.tcp_position > 10, axis: x, command: reset}
record: {signals: [a.track_position, b.tcp_position]}
checks:
  - {signal: a.track_position, expect: 0}
  - {signal: b.tcp_position, min: 0, at: always}
"""


def test_tracks_and_templates_load_with_their_defaults() -> None:
    scenario = parse_scenario(VALID)
    (ring,) = scenario.ca_groups
    assert [(p.id, p.start, p.end) for p in ring.parts] == [(11, 500.0, 2000.0),
                                                            (12, 2000.0, 500.0)]
    assert [(t.id, t.parts) for t in ring.tracks] == [(21, [11, 12]), (22, [12])]
    assert (ring.geometry.curve_radius, ring.geometry.rail_offset) == (
        STARTER_KIT_CURVE_RADIUS, 10.0)
    assert [(t.id, t.y_shift) for t in ring.templates] == [(31, 50.0), (32, 100.0)]
    on, reg, move, relative = scenario.timeline[:4]
    assert isinstance(on, ActivateTrack) and on.arguments() == {"track_id": 21}
    assert isinstance(reg, RegisterCompensation) and reg.arguments() == {"template_id": 31}
    assert isinstance(move, MoveAbsoluteCa) and isinstance(relative, MoveRelativeCa)
    assert (move.arguments()["position_reference_system"],
            move.arguments()["dynamics_reference_system"]) == (31, 31)
    assert (relative.arguments()["position_reference_system"],
            relative.arguments()["dynamics_reference_system"]) == (0, 31)
    condition = scenario.timeline[4].when
    assert (condition.subject, condition.attribute, condition.value) == (
        "a", "track_position", 50.0)


def test_configure_builds_the_same_table_as_the_python_api() -> None:
    (spec,) = parse_scenario(VALID).ca_groups
    group = CaGroup(Runtime(), "ring", spec.parameters.build())
    assert list(configure(spec, group)) == []
    table = group.tracks
    assert sorted(table.parts) == [11, 12] and table.parts[12].length == 1500.0
    closed, open_ = table.tracks[21], table.tracks[22]
    assert (closed.length, closed.offsets, closed.closed, closed.start) == (
        3000.0, (0.0, 1500.0), True, 500.0)
    assert (open_.length, open_.closed) == (1500.0, False)
    geometry = table.geo.geometry
    assert (geometry.rail_length, geometry.curve_radius, geometry.rail_offset) == (
        3000.0, STARTER_KIT_CURVE_RADIUS, 10.0)
    assert table.geo.templates[31].y_shift == 50.0 and table.geo.templates[32].y_shift == 100.0
    # one TCP lap of template 31 is rail_length + 2 pi y
    assert geometry.tcp_lap(50.0) == pytest.approx(3000.0 + 100.0 * math.pi)


@pytest.mark.parametrize(("model", "owner"), [(ActivateTrack, TrackTable),
                                              (RegisterCompensation, GeoCompensation)])
def test_track_entries_call_the_track_table_with_its_parameter_names(model: type,
                                                                     owner: type) -> None:
    assert model in CA_ENTRIES and COMMANDS[model.model_fields["command"].annotation
                                            .__args__[0]] is model
    parameters = list(inspect.signature(getattr(owner, model.method)).parameters)
    entry = model.model_construct(track=1, template=1)
    assert parameters[:2] == ["self", "axis"]
    assert set(entry.arguments()) <= set(parameters[2:])
    assert {"tracks": TrackTable, "tracks.geo": GeoCompensation}[model.owner] is owner


def test_the_reference_systems_are_move_absolute_and_move_relative_parameters() -> None:
    for name in ("move_absolute", "move_relative"):
        parameters = inspect.signature(getattr(CaGroup, name)).parameters
        assert parameters["position_reference_system"].default == 0
        assert parameters["dynamics_reference_system"].default == 0


def problems(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, "bad.yaml")
    return [str(problem) for problem in info.value.problems]


BASE = "name: t\naxes: [{name: a}, {name: b}]\nca_groups:\n  - name: g\n    axes: [a]\n"
#                                                               line 4 ^        line 5 ^


@pytest.mark.parametrize(("text", "expected"), [
    ("    parts:\n      - {id: 1, start: 0, end: 1000}\n      - {id: 2, start: 3500, end: 10}\n",
     ["bad.yaml:8: ca_groups[0].parts[1].start: must be in [0, 3000), got 3500"]),
    ("    parts: [{id: 1, start: 0, end: 3000.5}]\n",
     ["bad.yaml:6: ca_groups[0].parts[0].end: must be in [0, 3000], got 3000.5"]),
    ("    parameters: {rail_length: 1000}\n    parts: [{id: 1, start: 1000, end: 0}]\n",
     ["bad.yaml:7: ca_groups[0].parts[0].start: must be in [0, 1000), got 1000"]),
    ("    parameters: {rail_is_ring: false}\n    parts: [{id: 1, start: 200, end: 100}]\n",
     ["bad.yaml:7: ca_groups[0].parts[0].end: must be > start 200 on an open rail, got 100"]),
    ("    parts:\n      - {id: 1, start: 0, end: 1000}\n      - {id: 2, start: 500, end: 1500}\n",
     ["bad.yaml:8: ca_groups[0].parts[1]: part 2 overlaps part 1"]),
    ("    parts:\n      - {id: 1, start: 0, end: 1000}\n      - {id: 1, start: 1000, end: 0}\n",
     ["bad.yaml:8: ca_groups[0].parts[1].id: 1 is already the id of a part of this group"]),
    ("    parts: [{id: 0, start: 0, end: 1}]\n",
     ["bad.yaml:6: ca_groups[0].parts[0].id: must be greater than 0, got 0"]),
    ("    parts: [{id: 1, start: x, end: .nan}]\n",
     ["bad.yaml:6: ca_groups[0].parts[0].start: must be a valid number, got 'x'",
      "bad.yaml:6: ca_groups[0].parts[0].end: must be a finite number, got nan"]),
    ("    parts: [{id: 1, start: 0, end: 1000}, {id: 2, start: 1000, end: 0}]\n"
     "    tracks:\n      - {id: 3, parts: [1, 9]}\n      - {id: 4, parts: [2, 2]}\n"
     "      - {id: 2, parts: [1]}\n",
     ["bad.yaml:8: ca_groups[0].tracks[0].parts[1]: unknown part 9 (parts: 1, 2)",
      "bad.yaml:9: ca_groups[0].tracks[1].parts[1]: part 2 is listed twice",
      "bad.yaml:10: ca_groups[0].tracks[2].id: 2 is already the id of a part or track of "
      "this group"]),
    ("    tracks: [{id: 5, parts: []}]\n",
     ["bad.yaml:6: ca_groups[0].tracks[0].parts: must hold at least 1 item(s)"]),
    ("    parts: [{id: 1, start: 0, end: 1000}, {id: 2, start: 1500, end: 2000}]\n"
     "    tracks: [{id: 3, parts: [1, 2]}]\n",
     ["bad.yaml:7: ca_groups[0].tracks[0].parts: track 3: part 2 does not start where "
      "part 1 ends"]),
    ("    tracks: [{id: 3, parts: [1]}]\n",
     ["bad.yaml:6: ca_groups[0].tracks[0].parts[0]: unknown part 1 (parts: none)"]),
    ("    templates: [{id: 1}]\n",
     ["bad.yaml:6: ca_groups[0].templates: mover templates need the group's geometry"]),
    ("    parameters: {rail_is_ring: false}\n    geometry: {}\n",
     ["bad.yaml:7: ca_groups[0].geometry: the starter-kit geometry needs a ring rail "
      "(parameters.rail_is_ring: true)"]),
    ("    geometry: {curve_radius: 500}\n    templates: [{id: 1}]\n",
     ["bad.yaml:6: ca_groups[0].geometry.curve_radius: must leave straights: 2 pi "
      "curve_radius < rail_length 3000, got 500"]),
    ("    geometry: {curve_radius: 0, rail_offset: .inf, radius: 1}\n",
     ["bad.yaml:6: ca_groups[0].geometry.curve_radius: must be greater than 0, got 0",
      "bad.yaml:6: ca_groups[0].geometry.rail_offset: must be a finite number, got inf",
      "bad.yaml:6: ca_groups[0].geometry.radius: unknown field 'radius'"]),
    ("    geometry: {}\n    templates:\n      - {id: 5}\n      - {id: 6, y_shift: -1}\n"
     "      - {id: 5, y_shift: 3}\n",
     ["bad.yaml:9: ca_groups[0].templates[1].y_shift: must be greater than or equal to 0, "
      "got -1"]),
    ("    geometry: {}\n    templates:\n      - {id: 5}\n      - {id: 5, y_shift: 3}\n",
     ["bad.yaml:9: ca_groups[0].templates[1].id: 5 is already the id of a template of this "
      "group"]),
    ("timeline:\n  - {at: 0, axis: b, command: activate_track, track: 1}\n"
     "  - {at: 0, axis: a, command: activate_track, track: -1}\n"
     "  - {at: 0, axis: a, command: activate_track, track: 1.0}\n"
     "  - {at: 0, axis: a, command: register_compensation}\n"
     "  - {at: 0, axis: a, command: register_compensation, template: 1, track: 2}\n"
     "  - {at: 0, axis: a, command: move_absolute_ca, position: 1, velocity: 1,\n"
     "     position_reference_system: x}\n"
     "  - {at: 0, axis: a, command: move_relative_ca, distance: 1, velocity: 1,\n"
     "     dynamics_reference_system: true}\n"
     "  - {at: 0, axis: a, command: halt_ca, position_reference_system: 1}\n",
     ["bad.yaml:7: timeline[0].axis: 'b' is in no CA group (ca_groups[].axes)",
      "bad.yaml:8: timeline[1].track: must be greater than or equal to 0, got -1",
      "bad.yaml:9: timeline[2].track: must be a valid integer, got 1.0",
      "bad.yaml:10: timeline[3].template: required field is missing",
      "bad.yaml:11: timeline[4].track: unknown field 'track'",
      "bad.yaml:13: timeline[5].position_reference_system: must be a valid integer, got 'x'",
      "bad.yaml:15: timeline[6].dynamics_reference_system: must be a valid integer, got True",
      "bad.yaml:16: timeline[7].position_reference_system: unknown field"]),
    ("record: {signals: [b.track_position, b.tcp_position, a.tcp_position]}\n"
     "checks: [{signal: b.track_position, expect: 1}]\n"
     "timeline: [{when: b.tcp_position > 1, axis: a, command: halt_ca}]\n",
     ["bad.yaml:6: record.signals[0]: 'b' is in no CA group (ca_groups[].axes)",
      "bad.yaml:6: record.signals[1]: 'b' is in no CA group (ca_groups[].axes)",
      "bad.yaml:7: checks[0].signal: 'b' is in no CA group (ca_groups[].axes)",
      "bad.yaml:8: timeline[0].when: 'b' is in no CA group (ca_groups[].axes)"]),
])
def test_bad_track_input_names_file_line_and_field(text: str, expected: list[str]) -> None:
    found = problems(BASE + text)
    for line in expected:
        assert any(problem.startswith(line) for problem in found), (line, found)
    assert len(found) == len(expected), found


def test_every_problem_of_a_group_is_listed_at_once() -> None:
    found = problems(BASE + "    parts:\n      - {id: 1, start: -1, end: 4000}\n"
                            "      - {id: 2, start: 0, end: 10}\n"
                            "    tracks: [{id: 3, parts: [1, 2]}]\n"
                            "    templates: [{id: 4}]\n")
    assert found == [
        "bad.yaml:7: ca_groups[0].parts[0].start: must be in [0, 3000), got -1",
        "bad.yaml:7: ca_groups[0].parts[0].end: must be in [0, 3000], got 4000",
        "bad.yaml:10: ca_groups[0].templates: mover templates need the group's geometry "
        "(geometry: curve_radius, rail_offset; both have defaults)"]
