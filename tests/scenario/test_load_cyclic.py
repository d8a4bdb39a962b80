"""Loading the block entries (jog, external setpoints, override filter, stepper, reference
flag) and the override, homed and axis_error_id signals, and their errors."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

import openmotion as om
import openmotion.plcopen as blocks
from openmotion.core.enums import TargetPositionType
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.plcopen.jog import JogMode
from openmotion.plcopen.stepper import DestallDetectMode, DestallMode, PowerStepperParams
from openmotion.scenario import ScenarioError, load_scenario, parse_scenario
from openmotion.scenario.cyclic import (
    BlockEntry,
    DisableExternalSetpoints,
    EnableExternalSetpoints,
    InjectStall,
    Jog,
    OverrideFilter,
    PowerStepper,
    ReadAxisComponents,
    ReleaseStall,
    SetReferenceFlag,
)
from openmotion.scenario.schema import COMMANDS

VALID = """\
name: block entries
axes: [{name: x}, {name: g}]
timeline:
  - {id: j, at: 0, axis: x, command: jog, mode: inching, direction: backwards, position: 2.5,
     velocity: 50, hold: 0.2}
  - {when: j.done, axis: x, command: jog, mode: continuous, velocity: 10,
     release_when: x.position <= -5}
  - {id: ext, at: 1, axis: x, command: enable_external_setpoints, position: 10,
     position_type: relative, feed: {axis: g}, feed_for: 0.5}
  - {at: 2, axis: x, command: enable_external_setpoints, feed: {sine: {amplitude: 5, period: 1}}}
  - {at: 3, axis: x, command: disable_external_setpoints}
  - {at: 0, axis: g, command: override_filter, raw: [[0, 16384], [0.5, 32767]],
     lower_override_threshold: 100, override_steps: 50, override_recovery_time: 0.2}
  - {at: 0, axis: x, command: power_stepper, override: 80, destall_enable: true,
     destall_detect_mode: encoderless, destall_mode: set_err_non_ref, status_mon_enable: true}
  - {at: 1, axis: x, command: inject_stall, duration: 0.25}
  - {at: 2, axis: x, command: inject_stall}
  - {at: 3, axis: x, command: release_stall}
  - {at: 0, axis: x, command: set_reference_flag, reference_flag: true}
  - {at: 0, axis: x, command: read_axis_components}
checks:
  - {signal: x.homed, expect: 1}
  - {signal: x.override, min: 0, max: 100, at: always}
  - {signal: x.axis_error_id, expect: STEPPER_STALL, when: x.axis_error_id == stepper_stall}
  - {signal: g.axis_error_id, expect: 0}
"""


def problems(tmp_path: Path, text: str) -> list[str]:
    path = tmp_path / "scenario.yaml"
    path.write_text(textwrap.dedent(text))
    with pytest.raises(ScenarioError) as caught:
        load_scenario(path)
    return [str(problem) for problem in caught.value.problems]


def test_the_block_entries_load_with_the_block_inputs() -> None:
    scenario = parse_scenario(VALID)
    (inch, continuous, ext, sine, disable, flt, stepper, stall, forever, release, flag,
     read) = scenario.timeline
    assert isinstance(inch, Jog) and inch.arguments() == {
        "mode": JogMode.INCHING, "position": 2.5, "velocity": 50.0,
        "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}
    assert (inch.key, inch.hold, inch.release_when) == ("jog_backwards", 0.2, None)
    assert isinstance(continuous, Jog) and continuous.key == "jog_forward"
    assert str(continuous.release_when) == "x.position <= -5" and continuous.hold == 0.0
    assert isinstance(ext, EnableExternalSetpoints) and ext.arguments() == {
        "position": 10.0, "position_type": TargetPositionType.RELATIVE}
    assert (ext.feed.axis, ext.feed.sine, ext.feed_for) == ("g", None, 0.5)
    assert isinstance(sine, EnableExternalSetpoints) and sine.feed.sine is not None
    assert (sine.feed.sine.amplitude, sine.feed.sine.period, sine.feed.sine.offset) == \
        (5.0, 1.0, None)
    assert sine.arguments() == {"position": MC_INVALID,
                                "position_type": TargetPositionType.ABSOLUTE}
    assert isinstance(disable, DisableExternalSetpoints) and disable.arguments() == {}
    assert isinstance(flt, OverrideFilter) and flt.raw == [(0.0, 16384.0), (0.5, 32767.0)]
    assert flt.arguments() == {"lower_override_threshold": 100.0,
                               "upper_override_threshold": 32767.0, "override_steps": 50.0,
                               "override_recovery_time": 0.2}
    assert isinstance(stepper, PowerStepper) and stepper.arguments() == {
        "enable": True, "enable_positive": True, "enable_negative": True, "override": 80.0,
        "destall_params": PowerStepperParams(DestallDetectMode.ENCODERLESS,
                                             DestallMode.SET_ERR_NON_REF, True, True)}
    assert isinstance(stall, InjectStall) and stall.duration == 0.25
    assert isinstance(forever, InjectStall) and forever.duration is None
    assert isinstance(release, ReleaseStall)
    assert isinstance(flag, SetReferenceFlag) and flag.arguments() == {"reference_flag": True}
    assert isinstance(read, ReadAxisComponents) and read.arguments() == {}
    stall_check = scenario.checks[2]
    assert stall_check.expected == float(om.ErrorId.STEPPER_STALL)
    assert stall_check.when is not None and stall_check.when.value == 0x4636


def test_defaults_are_the_block_defaults() -> None:
    scenario = parse_scenario("""\
name: t
axes: [{name: x}]
timeline:
  - {at: 0, axis: x, command: jog}
  - {at: 0, axis: x, command: override_filter, raw: [[0, 0]]}
  - {at: 0, axis: x, command: power_stepper}
""")
    jog, flt, stepper = scenario.timeline
    assert jog.arguments() == {name: value for name, value in blocks.MC_Jog.INPUTS.items()
                               if not name.startswith("jog_")}
    assert jog.key == "jog_forward" and jog.hold == 0.0
    assert flt.arguments() == {name: value for name, value in
                               blocks.MC_OverrideFilter.INPUTS.items()
                               if name != "override_value_raw"}
    inputs = stepper.arguments()
    assert inputs.pop("destall_params") == PowerStepperParams()
    assert inputs == {name: value for name, value in blocks.MC_PowerStepper.INPUTS.items()
                      if name not in ("destall_params", "kl_status", "kl_status2")} | {
        "enable": True}


@pytest.mark.parametrize("command", sorted(name for name, model in COMMANDS.items()
                                           if issubclass(model, BlockEntry)))
def test_block_entry_arguments_are_inputs_of_their_block(command: str) -> None:
    model = COMMANDS[command]
    required = {"feed": {"axis": "g"}, "raw": [[0.0, 1.0]], "reference_flag": True,
                "position": 1.0, "velocity": 1.0, "parameter_number": 1004,
                "value": command != "write_parameter" or 1.0, "version_element": 1}
    entry = model(at=0.0, command=command, **({"axis": "x"} if command != "get_version" else {}),
                  **{name: value for name, value in required.items()
                     if name in model.model_fields})
    block = getattr(blocks, model.block, None)
    if block is None:  # the stepper terminal's faults: no block inputs
        assert model.block.startswith("StepperTerminal.") and entry.arguments() == {}
        return
    assert set(entry.arguments()) <= set(getattr(block, "INPUTS", {}))  # F_GetVersionTcMC: {}


@pytest.mark.parametrize(("text", "line", "path", "message"), [
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: jog
            mode: continous_fast
        """, 7, "timeline[0].mode",
        "must be one of standard_slow, standard_fast, continuous, inching", id="jog-mode"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: jog
            direction: positive
        """, 7, "timeline[0].direction", "'forward' or 'backwards'", id="jog-direction"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: jog, hold: 1, release_when: x.position > 5}
        """, 4, "timeline[0]", "give 'hold' or 'release_when', not both", id="jog-two-releases"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: jog
            hold: -1
        """, 7, "timeline[0].hold", "greater than or equal to 0", id="jog-negative-hold"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: jog
            release_when: nope.done
        """, 7, "timeline[0].release_when", "'nope' is not the id of a timeline entry",
        id="jog-release-unknown-id"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: jog
            presed: 1
        """, 7, "timeline[0].presed", "unknown field 'presed'", id="jog-unknown-field"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: enable_external_setpoints}
        """, 4, "timeline[0].feed", "required field is missing", id="feed-missing"),
    pytest.param("""\
        name: t
        axes: [{name: x}, {name: g}]
        timeline:
          - at: 0
            axis: x
            command: enable_external_setpoints
            feed: {axis: g, sine: {amplitude: 1, period: 1}}
        """, 7, "timeline[0].feed", "give exactly one of 'axis'", id="feed-two-sources"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: enable_external_setpoints
            feed: {axis: gen}
        """, 7, "timeline[0].feed.axis", "unknown axis 'gen' (axes: x)", id="feed-unknown-axis"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: enable_external_setpoints, feed: {axis: x}}
        """, 4, "timeline[0].feed", "the axis cannot feed itself", id="feed-itself"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: enable_external_setpoints
            feed: {sine: {amplitude: 1, period: 0}}
        """, 7, "timeline[0].feed.sine.period", "greater than 0", id="feed-zero-period"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: enable_external_setpoints
            feed: {axis: x}
            position_type: circular
        """, 8, "timeline[0].position_type", "must be one of absolute, relative, modulo",
        id="feed-position-type"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: override_filter
            raw: []
        """, 7, "timeline[0].raw", "must hold at least 1 item", id="filter-no-raw"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: override_filter, raw: [[1, 10], [0.5, 20]]}
        """, 4, "timeline[0].raw", "the times must be ascending", id="filter-raw-order"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: override_filter
            raw: [[0, 10]]
            override_steps: many
        """, 8, "timeline[0].override_steps", "must be a valid number", id="filter-steps-text"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: power_stepper
            destall_mode: stop
        """, 7, "timeline[0].destall_mode",
        "must be one of none, set_error, set_err_non_ref, use_override", id="destall-mode"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: power_stepper
            destall_detect_mode: lag
        """, 7, "timeline[0].destall_detect_mode", "must be one of none, encoderless, lagging",
        id="destall-detect-mode"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - at: 0
            axis: x
            command: inject_stall
            duration: -0.1
        """, 7, "timeline[0].duration", "greater than or equal to 0", id="stall-duration"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {at: 0, axis: x, command: set_reference_flag}
        """, 4, "timeline[0].reference_flag", "required field is missing", id="flag-missing"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        checks:
          - {signal: x.axis_error_id, expect: STALL}
        """, 4, "checks[0].expect", "'STALL' is not a number or an ErrorId name",
        id="check-error-name"),
    pytest.param("""\
        name: t
        axes: [{name: x}]
        timeline:
          - {when: x.homed == yes, axis: x, command: halt}
        """, 4, "timeline[0].when", "'yes' is not a number", id="homed-not-a-number"),
])
def test_invalid_files_name_file_line_and_field(tmp_path: Path, text: str, line: int, path: str,
                                                message: str) -> None:
    found = problems(tmp_path, text)
    where = f"{tmp_path / 'scenario.yaml'}:{line}: " + (f"{path}: " if path else "")
    assert any(p.startswith(where) and message in p for p in found), found


def test_an_unknown_jog_mode_is_a_config_error_naming_file_line_and_field(
        tmp_path: Path) -> None:
    path = tmp_path / "jog.yaml"
    path.write_text("name: t\naxes: [{name: x}]\ntimeline:\n"
                    "  - {at: 0, axis: x, command: jog, mode: fast}\n")
    with pytest.raises(om.ConfigError) as caught:
        load_scenario(path)
    assert str(caught.value) == (f"{path}:4: timeline[0].mode: must be one of standard_slow, "
                                 "standard_fast, continuous, inching, got 'fast'")
