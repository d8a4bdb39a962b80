"""Loading CA groups, the CA entries and the gap signal, and their errors (file:line: field)."""

from __future__ import annotations

import inspect

import pytest

from openmotion.core.enums import BufferMode
from openmotion.core.special_values import MC_DEFAULT
from openmotion.scenario import ScenarioError, parse_scenario
from openmotion.scenario.queries import Called
from openmotion.scenario.schema import COMMANDS
from openmotion.scenario.transport import (
    CA_ENTRIES,
    GroupEntry,
    GroupStop,
    MoveAbsoluteCa,
    SetGap,
)
from openmotion.transport import CaGroup, GapControlDirection, GapControlMode, ModuloDirection

VALID = """\
name: ca
axes: [{name: a}, {name: b}, {name: c}, {name: x}]
ca_groups:
  - name: ring
    axes: [b, a]
    parameters: {rail_length: 2000, default_gap: 50, default_gap_control_mode: fast,
                 gap_control_direction: positive, standby_gap_control: true}
  - {name: line, axes: [c], parameters: {rail_is_ring: false}, enable: false}
timeline:
  - {id: m, at: 0, axis: a, command: move_absolute_ca, position: 100, velocity: 10,
     direction: shortest_way, additional_turns: 1, gap: 60, buffer_mode: buffered,
     gap_control_mode: none, continuous_update: true}
  - {id: r, at: 0, axis: c, command: move_relative_ca, distance: 5, velocity: MC_MAXIMUM}
  - {at: 0.1, command: set_gap, move: m, gap: 80}
  - {at: 0.1, axis: b, command: halt_ca, deceleration: 100}
  - {id: s, at: 0.2, group: ring, command: group_stop, release_at: 0.5}
  - {when: ring.state == standby, group: line, command: group_enable}
  - {when: s.done, group: ring, command: group_halt}
  - {at: 1, group: ring, command: group_disable}
  - {at: 1, group: ring, command: group_reset}
  - {when: a.gap < 60, axis: x, command: power}
record: {signals: [a.gap, x.position]}
checks:
  - {signal: b.gap, min: 50, at: always}
"""


def test_ca_groups_and_entries_load() -> None:
    scenario = parse_scenario(VALID)
    ring, line = scenario.ca_groups
    assert (ring.name, ring.axes, ring.enable, line.enable) == ("ring", ["b", "a"], True, False)
    parameters = ring.parameters.build()
    assert (parameters.rail_length, parameters.default_gap, parameters.rail_is_ring) == (
        2000.0, 50.0, True)
    assert parameters.default_gap_control_mode is GapControlMode.FAST
    assert parameters.gap_control_direction is GapControlDirection.POSITIVE
    assert line.parameters.build().rail_is_ring is False
    move = scenario.timeline[0]
    assert isinstance(move, MoveAbsoluteCa)
    assert move.arguments() == {
        "velocity": 10.0, "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT,
        "jerk": MC_DEFAULT, "gap": 60.0, "buffer_mode": BufferMode.BUFFERED,
        "gap_control_mode": GapControlMode.NONE, "continuous_update": True, "position": 100.0,
        "direction": ModuloDirection.SHORTEST_WAY, "additional_turns": 1,
        "position_reference_system": 0, "dynamics_reference_system": 0}
    stop = scenario.timeline[4]
    assert isinstance(stop, GroupStop) and stop.axis == "ring" and stop.release_at == 0.5
    assert stop.arguments() == {"deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}
    condition = scenario.timeline[5].when
    assert (condition.subject, condition.attribute, condition.value) == ("ring", "state", 2.0)


@pytest.mark.parametrize("command", sorted(name for name, model in COMMANDS.items()
                                     if model in CA_ENTRIES and not getattr(model, "owner", "")
                                     and not issubclass(model, Called)))
def test_ca_entry_arguments_are_the_group_method_parameters(command: str) -> None:
    """(activate_track and register_compensation: test_load_ca_tracks.py; the entries that
    call their block themselves, add_axis_to_group ...: test_query_entries.py.)"""
    model = COMMANDS[command]
    parameters = set(inspect.signature(getattr(CaGroup, model.method)).parameters)
    fields = set(model.model_fields) - {"id", "at", "when", "axis", "group", "command",
                                        "move", "hold", "release_at"}
    if command in ("group_halt", "group_stop"):  # buffer_mode: axes groups only (D-194)
        fields.discard("buffer_mode")
    assert fields <= parameters
    if issubclass(model, GroupEntry | SetGap):
        assert "axis" not in model.model_fields


def problems(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, "bad.yaml")
    return [str(problem) for problem in info.value.problems]


BASE = "name: t\naxes: [{name: a}, {name: b}, {name: c}]\n"


@pytest.mark.parametrize(("text", "expected"), [
    ("ca_groups:\n  - {name: g, axes: [a, q]}\n",
     "bad.yaml:4: ca_groups[0].axes[1]: unknown axis 'q' (axes: a, b, c)"),
    ("ca_groups:\n  - {name: g, axes: [a, b]}\n  - {name: h, axes: [c, a]}\n",
     "bad.yaml:5: ca_groups[1].axes[1]: 'a' is listed 2 times in ca_groups (g, h); an axis is "
     "in one CA group only"),
    ("ca_groups:\n  - name: g\n    axes: [a]\n    parameters: {rail_lenght: 10}\n",
     "bad.yaml:6: ca_groups[0].parameters.rail_lenght: unknown field 'rail_lenght' "
     "(did you mean 'rail_length'?)"),
    ("ca_groups:\n  - name: g\n    axes: [a]\n    parameters: {rail_length: -1}\n",
     "bad.yaml:6: ca_groups[0].parameters.rail_length: must be a finite number > 0, got -1.0"),
    ("ca_groups:\n  - name: g\n    axes: [a]\n    parameters: {default_gap_control_mode: none}\n",
     "bad.yaml:6: ca_groups[0].parameters.default_gap_control_mode: STANDARD or FAST, got NONE"),
    ("ca_groups:\n  - {name: a, axes: [b]}\n",
     "bad.yaml:4: ca_groups[0].name: 'a' is an axis name; a CA group needs a name of its own"),
    ("ca_groups:\n  - {name: g, axes: []}\n",
     "bad.yaml:4: ca_groups[0].axes: must hold at least 1 item(s)"),
    ("ca_groups: [{name: g, axes: [a]}]\ntimeline:\n"
     "  - {at: 0, axis: b, command: move_absolute_ca, position: 1, velocity: 1}\n",
     "bad.yaml:5: timeline[0].axis: 'b' is in no CA group (ca_groups[].axes)"),
    ("ca_groups: [{name: g, axes: [a]}]\ntimeline:\n  - {at: 0, group: h, command: group_halt}\n",
     "bad.yaml:5: timeline[0].group: unknown CA group 'h' (ca_groups: g)"),
    ("ca_groups: [{name: g, axes: [a]}]\ntimeline:\n"
     "  - {at: 0, axis: a, group: g, command: group_halt}\n",
     "bad.yaml:5: timeline[0].axis: unknown field 'axis'"),
    ("ca_groups: [{name: g, axes: [a]}]\ntimeline:\n"
     "  - {id: p, at: 0, axis: a, command: power}\n"
     "  - {at: 0, command: set_gap, move: p, gap: 1}\n",
     "bad.yaml:6: timeline[1].move: 'p' is not the id of a move_absolute_ca or "
     "move_relative_ca entry"),
    ("ca_groups: [{name: g, axes: [a]}]\ntimeline:\n"
     "  - {at: 0, group: g, command: group_stop, hold: 1, release_at: 2}\n",
     "bad.yaml:5: timeline[0]: give 'hold' or 'release_at', not both"),
    ("ca_groups: [{name: g, axes: [a]}]\nrecord: {signals: [b.gap]}\n",
     "bad.yaml:4: record.signals[0]: 'b' is in no CA group (ca_groups[].axes)"),
    ("ca_groups: [{name: g, axes: [a]}]\ntimeline:\n"
     "  - {when: g.state == flying, group: g, command: group_halt}\n",
     "bad.yaml:5: timeline[0].when: 'g.state == flying': a CA group's condition is "
     "'<group>.state == <state>'"),
    ("ca_groups: [{name: g, axes: [a]}, {name: g, axes: [b]}]\n",
     "bad.yaml:3: ca_groups[0].name: 'g' is used 2 times; it must be unique"),
])
def test_bad_ca_input_names_file_line_and_field(text: str, expected: str) -> None:
    found = problems(BASE + text)
    assert any(problem.startswith(expected) for problem in found), found
