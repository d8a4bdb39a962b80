"""Loading the gearing, oriented-stop, on-the-fly and touch-probe entries and their errors."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

import openmotion as om
from openmotion.axis.probe import SignalEdge
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.scenario import ScenarioError, load_scenario, parse_scenario
from openmotion.scenario.schema import (
    AbortTrigger,
    GearIn,
    GearOutExt,
    OrientedStop,
    SetActualPositionOnTheFly,
    SetGearRatio,
    TouchProbe,
)

VALID = """\
name: gearing and probe
axes:
  - name: belt
  - name: saw
    probe: {positions: [[10.5, 20.0], [30.0, .inf]]}
  - name: r
    probe: {times: [[0.25, 0.5]]}
timeline:
  - {id: couple, at: 0, axis: saw, command: gear_in, master: belt, ratio: 2}
  - {id: dyn, at: 0, axis: r, command: gear_in, master: belt, ratio: -0.5,
     acceleration: MC_DEFAULT}
  - {when: couple.in_gear, axis: r, command: set_gear_ratio, ratio: 1.5}
  - {at: 1, axis: r, command: gear_out}
  - {at: 1, axis: saw, command: gear_out_ext, mode: new_position_and_velocity,
     position: 5, velocity: 100, deceleration: 3000}
  - {at: 2, axis: r, command: oriented_stop, position: 90}
  - {at: 2, axis: saw, command: set_actual_position_on_the_fly, actual_position: 1000,
     previous_position: 10}
  - {id: p, at: 0, axis: saw, command: touch_probe, edge: falling, window_only: true,
     first_position: 1, last_position: 2.5, modulo_positions: true}
  - {at: 3, axis: saw, command: abort_trigger, probe: p}
checks:
  - {command: p, result: done, value: 12.5, tolerance: 1e-6}
  - {command: p, result: done}
"""


def problems(tmp_path: Path, text: str) -> list[str]:
    path = tmp_path / "scenario.yaml"
    path.write_text(textwrap.dedent(text))
    with pytest.raises(ScenarioError) as caught:
        load_scenario(path)
    return [str(problem) for problem in caught.value.problems]


def test_the_new_entries_load_with_api_names_and_values() -> None:
    scenario = parse_scenario(VALID)
    (couple, dyn, ratio, out, ext, oriented, fly, probe, abort) = scenario.timeline
    assert isinstance(couple, GearIn) and couple.arguments() == {
        "master": "belt", "ratio": 2.0, "acceleration": None}
    assert couple.axis_fields == ("master",)
    assert isinstance(dyn, GearIn) and dyn.acceleration is MC_DEFAULT and dyn.ratio == -0.5
    assert isinstance(ratio, SetGearRatio) and ratio.arguments() == {"ratio": 1.5}
    assert str(ratio.when) == "couple.in_gear"
    assert out.arguments() == {}
    assert isinstance(ext, GearOutExt) and ext.arguments() == {
        "mode": om.DecoupleMode.NEW_POSITION_AND_VELOCITY, "position": 5.0, "velocity": 100.0,
        "acceleration": MC_DEFAULT, "deceleration": 3000.0, "jerk": MC_DEFAULT}
    assert isinstance(oriented, OrientedStop) and oriented.arguments() == {"position": 90.0}
    assert isinstance(fly, SetActualPositionOnTheFly) and fly.arguments() == {
        "actual_position": 1000.0, "previous_position": 10.0}
    assert isinstance(probe, TouchProbe) and probe.arguments() == {
        "window_only": True, "first_position": 1.0, "last_position": 2.5}
    ref = probe.trigger_input()
    assert ref.edge is SignalEdge.FALLING and ref.modulo_positions
    assert ref is not probe.trigger_input()  # a fresh InputRef each time
    assert isinstance(abort, AbortTrigger) and abort.probe == "p" and abort.arguments() == {}
    saw, r = scenario.axes[1:]
    assert saw.probe is not None and saw.probe.positions == [(10.5, 20.0), (30.0, float("inf"))]
    assert r.probe is not None and r.probe.times == [(0.25, 0.5)]
    assert scenario.axes[0].probe is None
    assert scenario.checks[0].value == 12.5 and scenario.checks[0].tolerance == 1e-6
    assert scenario.checks[1].value is None


def test_gear_out_ext_defaults_are_the_fb_defaults() -> None:
    scenario = parse_scenario("name: t\naxes: [{name: x}]\ntimeline:\n"
                              "  - {at: 0, axis: x, command: gear_out_ext, mode: stop}\n")
    assert scenario.timeline[0].arguments() == {
        "mode": om.DecoupleMode.STOP, "position": MC_INVALID, "velocity": MC_INVALID,
        "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}


@pytest.mark.parametrize(("text", "line", "path", "message"), [
    pytest.param("""\
        name: t
        axes: [{name: saw}, {name: belt}]
        timeline:
          - at: 0
            axis: saw
            command: gear_in
            master: conveyor
            ratio: 1
        """, 7, "timeline[0].master", "unknown axis 'conveyor' (axes: belt, saw)",
        id="unknown-master"),
    pytest.param("""\
        name: t
        axes: [{name: saw}, {name: belt}]
        timeline:
          - {at: 0, axis: saw, command: gear_in, ratio: 1}
        """, 4, "timeline[0].master", "required field is missing", id="missing-master"),
    pytest.param("""\
        name: t
        axes: [{name: saw}, {name: belt}]
        timeline:
          - at: 0
            axis: saw
            command: gear_in
            master: belt
            ratio: one
        """, 8, "timeline[0].ratio", "must be a valid number", id="ratio-not-a-number"),
    pytest.param("""\
        name: t
        axes: [{name: saw}]
        timeline:
          - at: 0
            axis: saw
            command: gear_out_ext
            mode: coast
        """, 7, "timeline[0].mode", "must be one of stop, oriented_stop, endless, "
        "endless_new_velocity, new_position, new_position_and_velocity, instantaneous_stop",
        id="bad-decouple-mode"),
    pytest.param("""\
        name: t
        axes: [{name: saw}]
        timeline:
          - {at: 0, axis: saw, command: set_actual_position_on_the_fly, actual_position: 3}
        """, 4, "timeline[0].previous_position", "required field is missing",
        id="on-the-fly-missing-previous"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {id: m, at: 0, axis: x, command: move_velocity, velocity: 5}
          - {when: m.in_gear, axis: x, command: halt}
        """, 5, "timeline[1].when", "in_gear is a flag of gear_in and gear_in_pos_ca entries only",
        id="in-gear-of-a-move"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: touch_probe
            edge: both
        """, 7, "timeline[0].edge", "must be one of rising, falling", id="bad-edge"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {id: m, at: 0, axis: x, command: halt}
          - at: 0
            axis: x
            command: abort_trigger
            probe: m
        """, 8, "timeline[1].probe", "'m' is not the id of a touch_probe entry",
        id="abort-trigger-of-a-halt"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: abort_trigger, probe: p}
        """, 4, "timeline[0].probe", "'p' is not the id of a timeline entry",
        id="abort-trigger-unknown-id"),
    pytest.param("""\
        name: t
        axes:
          - name: x
            probe:
              positions: [[10, 20], [15, 30]]
        """, 5, "axes[0].probe.positions", "intervals overlap or touch at 15.0",
        id="probe-overlap"),
    pytest.param("""\
        name: t
        axes:
          - name: x
            probe:
              times: [[0.5, 0.2]]
        """, 5, "axes[0].probe.times", "need from < to", id="probe-empty-interval"),
    pytest.param("""\
        name: t
        axes:
          - name: x
            probe: {positions: [[1, 2]], times: [[1, 2]]}
        """, 4, "axes[0].probe", "give 'positions' or 'times'", id="probe-both"),
    pytest.param("""\
        name: t
        axes:
          - name: x
            probe: {}
        """, 4, "axes[0].probe", "give 'positions' or 'times'", id="probe-none"),
    pytest.param("""\
        name: t
        axes:
          - name: x
            probe: {positions: [[1, 2, 3]]}
        """, 4, "axes[0].probe.positions[0]", "at most 2 items", id="probe-triple"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {id: p, at: 0, axis: x, command: touch_probe}
        checks:
          - {command: p, result: done, tolerance: 0.1}
        """, 6, "checks[0]", "'tolerance' needs 'value'", id="tolerance-without-value"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {id: p, at: 0, axis: x, command: touch_probe}
        checks:
          - {command: p, result: done, value: near}
        """, 6, "checks[0].value", "must be a valid number", id="value-not-a-number"),
])
def test_invalid_files_name_file_line_and_field(tmp_path: Path, text: str, line: int, path: str,
                                                message: str) -> None:
    found = problems(tmp_path, text)
    where = f"{tmp_path / 'scenario.yaml'}:{line}: " + (f"{path}: " if path else "")
    assert any(p.startswith(where) and message in p for p in found), found
