"""Loading scenario files: valid files load, every invalid one names its file, line and field."""

from __future__ import annotations

import inspect
import textwrap
from pathlib import Path

import pytest
from pydantic import ValidationError

import openmotion as om
from openmotion.axis import probe
from openmotion.core.special_values import MC_DEFAULT, MC_MAXIMUM
from openmotion.scenario import Scenario, ScenarioError, load_scenario, parse_scenario
from openmotion.scenario.cyclic import BlockEntry
from openmotion.scenario.schema import COMMANDS, MoveAbsolute, parse_condition
from openmotion.scenario.transport import CA_ENTRIES

VALID = """\
name: valid
cycle_time: 0.002
axes:
  - name: x
    parameters: {max_velocity: 500, homing_direction: positive}
    drive: {model: lag, time_constant: 0.004}
    position: 10
  - name: r
    parameters: {modulo_period: 360, modulo_tolerance_window: 1.5}
timeline:
  - {id: on, at: 0, axis: x, command: power}
  - {id: m1, at: 0.01, axis: x, command: move_absolute, position: 100, velocity: MC_MAXIMUM,
     buffer_mode: blending_low}
  - {when: m1.done, axis: x, command: move_velocity, velocity: 50, direction: negative}
  - {when: x.set_position >= 50.5, axis: r, command: move_modulo, position: 450,
     velocity: 90, direction: positive}
record:
  signals: [x.set_position, r.state]
  every: 2
checks:
  - {signal: x.set_position, expect: 100, tolerance: 1e-6, when: m1.done}
  - {signal: r.state, expect: standstill, at: 0.5}
  - {command: m1, result: done}
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scenario.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def problems(tmp_path: Path, text: str) -> list[str]:
    with pytest.raises(ScenarioError) as caught:
        load_scenario(write(tmp_path, text))
    return [str(problem) for problem in caught.value.problems]


def test_valid_file_loads_with_api_names_and_values(tmp_path: Path) -> None:
    scenario = load_scenario(write(tmp_path, VALID))
    assert scenario.name == "valid" and scenario.cycle_time == 0.002
    x, r = scenario.axes
    assert x.parameters.build().max_velocity == 500.0
    assert x.parameters.build().homing_direction is om.Direction.POSITIVE
    assert x.drive.build() == om.DriveModel("lag", 0.004, 0.0) and x.position == 10.0
    assert r.parameters.build().modulo_tolerance_window == 1.5
    power, move, velocity, modulo = scenario.timeline
    assert power.id == "on"  # YAML 1.2: "on" is a string, not True
    assert isinstance(move, MoveAbsolute) and move.velocity is MC_MAXIMUM
    assert move.arguments() == {"position": 100.0, "velocity": MC_MAXIMUM,
                                "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT,
                                "jerk": MC_DEFAULT, "buffer_mode": om.BufferMode.BLENDING_LOW}
    assert velocity.arguments()["direction"] is om.Direction.NEGATIVE
    assert str(modulo.when) == "x.set_position >= 50.5"
    assert scenario.signals == ["x.set_position", "r.state"] and scenario.record.every == 2
    assert scenario.checks[0].tolerance == 1e-6  # 1e-6 is a float, not the string "1e-6"
    assert scenario.checks[1].expected == float(om.AxisState.STANDSTILL)


def test_default_signals_are_set_position_velocity_acceleration_and_position() -> None:
    scenario = parse_scenario("name: d\naxes: [{name: a}, {name: b}]\n")
    assert scenario.signals == [f"{axis}.{signal}" for axis in "ab" for signal in
                                ("set_position", "set_velocity", "set_acceleration", "position")]


@pytest.mark.parametrize(("text", "line", "path", "message"), [
    pytest.param("""\
        name: t
        axes:
          - name: x
            parameters:
              max_velocty: 5
        """, 5, "axes[0].parameters.max_velocty",
        "unknown field 'max_velocty' (did you mean 'max_velocity'?)", id="unknown-field"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: move_absolute
            position: 10
            velocity: fast
        """, 8, "timeline[0].velocity", "must be a number or one of MC_DEFAULT",
        id="wrong-type"),
    pytest.param("""\
        name: t
        cycle_time: -0.001
        axes: [{name: x}]
        """, 2, "cycle_time", "greater than 0", id="negative-cycle-time"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: power}
          - {at: 1, axis: y, command: halt}
        """, 5, "timeline[1].axis", "unknown axis 'y' (axes: x)", id="unknown-axis"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: move_absolut
        """, 6, "timeline[0].command", "unknown command 'move_absolut' (did you mean "
        "'move_absolute'?)", id="unknown-command"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {id: m, at: 0, axis: x, command: power}
          - when: m.don
            axis: x
            command: halt
        """, 5, "timeline[1].when", "the flag must be one of done", id="bad-condition-flag"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {when: x.position >> 3, axis: x, command: halt}
        """, 4, "timeline[0].when", "is neither '<id>.<flag>'", id="bad-condition-syntax"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {when: q.done, axis: x, command: halt}
        """, 4, "timeline[0].when", "'q' is not the id of a timeline entry",
        id="condition-unknown-id"),
    pytest.param("""\
        name: t
        axes:
          - name: x
            parameters:
              jerk: 100
              max_velocity: -1
        """, 6, "axes[0].parameters.max_velocity", "must be a finite number > 0",
        id="parameter-out-of-range"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: move_absolute, velocity: 5}
        """, 4, "timeline[0].position", "required field is missing", id="missing-field"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {axis: x, command: power}
        """, 4, "timeline[0]", "give exactly one of 'at'", id="no-trigger"),
    pytest.param("""\
        name: t
        axes: [{name: x}, {name: x}]
        """, 2, "axes[0].name", "'x' is used 2 times", id="duplicate-axis"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        record: {signals: [x.speed]}
        """, 3, "record.signals[0]", "'x.speed' is not '<axis>.<signal>'", id="bad-signal"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        record: {keep: 0}
        """, 3, "record.keep", "greater than or equal to 1", id="keep-zero"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        record: {keep: 10, stream: out}
        """, 3, "record", "give 'keep' or 'stream', not both", id="keep-and-stream"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        record: {chunk: 100}
        """, 3, "record", "'chunk' needs 'stream'", id="chunk-without-stream"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        checks:
          - {command: m9, result: done}
        """, 4, "checks[0].command", "'m9' is not the id", id="check-unknown-id"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        checks:
          - {value: 3}
        """, 4, "checks[0]", "a check needs 'signal' or 'command'", id="check-kind"),
    pytest.param("""\
        name: t
        name: u
        axes: [{name: x}]
        """, 2, "name", "duplicate key", id="duplicate-key"),
    pytest.param("""\
        name: t
        axes: [{name: x}
        """, 3, "", "invalid YAML", id="yaml-syntax"),
])
def test_invalid_files_name_file_line_and_field(tmp_path: Path, text: str, line: int, path: str,
                                                message: str) -> None:
    found = problems(tmp_path, text)
    where = f"{tmp_path / 'scenario.yaml'}:{line}: " + (f"{path}: " if path else "")
    assert any(p.startswith(where) and message in p for p in found), found


def test_error_message_is_one_line_config_error(tmp_path: Path) -> None:
    path = write(tmp_path, "name: t\ncycle_time: 0\naxes: [{name: 3}]\n")
    with pytest.raises(om.ConfigError) as caught:
        load_scenario(path)
    text = str(caught.value)
    assert "\n" not in text
    assert text.startswith(f"{path}:2: cycle_time: ") and text.endswith("(and 1 more)")


def test_every_problem_is_listed_in_line_order(tmp_path: Path) -> None:
    found = problems(tmp_path, """\
        name: t
        cycle_time: fast
        axes:
          - name: x
            drive: {model: servo}
        timeline:
          - {at: -1, axis: y, command: halt, velocity: 3}
        checks:
          - {signal: x.position}
        """)
    assert [p.split(": ", 1)[0].rsplit(":", 1)[1] for p in found] == \
        ["2", "5", "7", "7", "7", "9"]


def test_missing_file_and_non_mapping_are_config_errors(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match="cannot read"):
        load_scenario(tmp_path / "nope.yaml")
    with pytest.raises(ScenarioError, match="must hold a mapping"):
        parse_scenario("- 1\n- 2\n", "list.yaml")


def test_python_construction_checks_cross_references_too() -> None:
    with pytest.raises(ValidationError, match="unknown axis 'y'"):
        Scenario(name="t", axes=[{"name": "x"}],
                 timeline=[{"at": 0.0, "axis": "y", "command": "power"}])


@pytest.mark.parametrize("command", sorted(name for name, model in COMMANDS.items()
                                     if not issubclass(model, (BlockEntry, *CA_ENTRIES))))
def test_entry_arguments_are_the_axis_method_parameters(command: str) -> None:
    """Block entries pass block inputs instead (test_load_cyclic.py), CA entries call their
    group (test_load_ca.py)."""
    model = COMMANDS[command]
    fields = {name: field for name, field in model.model_fields.items()
              if name not in ("id", "at", "when", "axis", "command")}
    required: dict[str, object] = {name: 1.0 for name, field in fields.items()
                                   if field.is_required()}
    required.update({"mode": {"new_position_and_velocity": "change_pos",
                              "gear_out_ext": "stop",
                              "move_superimposed": "veloreduction_additivemotion"}.get(command),
                     "master": "y",
                     "probe": "p"})
    entry = model(at=0.0, axis="x", command=command,
                  **{name: value for name, value in required.items() if name in fields})
    function = getattr(om.Axis, model.method, None) or getattr(probe, model.method, None)
    if function is None:  # plc_event writes the touch probe's InputRef field (D-219)
        assert entry.arguments() == {} and hasattr(probe.InputRef(), model.method)
        return
    parameters = inspect.signature(function).parameters
    assert set(entry.arguments()) <= set(parameters) - {"self", "axis", "ref", "now"}


@pytest.mark.parametrize(("text", "subject", "attribute", "operator", "value"), [
    ("m1.done", "m1", "done", None, None),
    ("x.in_velocity", "x", "in_velocity", None, None),
    ("x.set_position >= 50", "x", "set_position", ">=", 50.0),
    ("x.velocity<-1e3", "x", "velocity", "<", -1000.0),
    ("x.state == standstill", "x", "state", "==", float(om.AxisState.STANDSTILL)),
])
def test_conditions_parse(text: str, subject: str, attribute: str, operator: str | None,
                          value: float | None) -> None:
    condition = parse_condition(text)
    assert (condition.subject, condition.attribute, condition.operator, condition.value) == \
        (subject, attribute, operator, value)


@pytest.mark.parametrize("text", ["x.position", "x.done > 3", "x.position > fast", "done",
                                  "x.position != 3", "x.position > nan"])
def test_bad_conditions_are_rejected(text: str) -> None:
    with pytest.raises(ValueError):
        parse_condition(text)
