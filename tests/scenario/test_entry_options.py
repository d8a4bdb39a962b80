"""Block inputs that scenario files reach since issue 20 ("make every block, method and option
reachable"): MC_Power's Override (TcMC §4.1), MC_Home's bCalibrationCam (§3.14), MC_TouchProbe's
TriggerInput (TouchProbe source and PlcEvent, §4.21, §6.3) and MC_GroupSetPosition's BufferMode
(Part 4 §5.9, D-130)."""

from __future__ import annotations

import pytest

from openmotion.scenario import CommandRow, ScenarioResult, parse_scenario, run_scenario

OPTIONS = """\
name: options
axes:
  - name: h
    position: 55
    parameters: {reference_mode: cam_and_sync_pulse, calibration_value: 7}
  - name: v
    probe: {positions: [[1000, 2000]]}
timeline:
  - {at: 0, axis: h, command: power, override: 50}
  - {id: home, at: 0, axis: h, command: home, calibration_cam: {positions: [[10, 20]]}}
  - {id: ref, when: home.done, axis: h, command: read_status}
  - {at: 0, axis: v, command: power}
  - {id: run, at: 0, axis: v, command: move_velocity, velocity: 100}
  - {id: latch, at: 0, axis: v, command: touch_probe, touch_probe: plc_event}
  - {id: bad, at: 0, axis: v, command: touch_probe, touch_probe: touch_probe_2}
  - {id: event, at: 0.5, axis: v, command: plc_event, probe: latch}
  - {id: halt, at: 0.6, axis: v, command: halt}
  - {id: too_much, at: 0.7, axis: v, command: power, override: 150}
checks:
  - {command: home, result: done}
  - {command: ref, result: done, output: homing, value: 1}
  - {command: latch, result: done}
  - {command: bad, result: error, error_id: INVALID_MODE}
  - {command: too_much, result: error, error_id: INVALID_OVERRIDE}
"""

BUFFERED = """\
name: buffered set position
axes: [{name: a1}, {name: a2}]
axes_groups: [{name: xy, axes: [a1, a2]}]
timeline:
  - {id: go, at: 0, group: xy, command: move_linear_absolute, position: [100, 0]}
  - {id: now, at: 0.01, group: xy, command: group_set_position, position: [0, 0]}
  - {id: after, at: 0.01, group: xy, command: group_set_position, position: [0, 0],
     buffer_mode: buffered}
checks:
  - {command: now, result: error}
  - {command: after, result: done}
  - {signal: xy.x, expect: 0}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def options() -> ScenarioResult:
    return run_scenario(parse_scenario(OPTIONS))


def test_the_options_pass_their_checks(options: ScenarioResult) -> None:
    assert options.passed, [check for check in options.checks if not check.passed]


def test_the_calibration_cam_of_the_plc_references_the_axis() -> None:
    """§3.14, rule 66: without reference_cam the cam must come from the PLC; the same home
    without calibration_cam fails with HOMING_FAILED."""
    result = run_scenario(parse_scenario(OPTIONS.replace(
        ", calibration_cam: {positions: [[10, 20]]}", "")))
    assert (rows(result)["home"].result, rows(result)["home"].error) == ("ERROR",
                                                                          "HOMING_FAILED")


def test_plc_event_latches_the_position_of_its_cycle(options: ScenarioResult) -> None:
    """§6.3: TouchProbe = PlcEvent records the position of the cycle PlcEvent rose in (the
    plc_event entry at 0.5 s); the axis' own probe input (from 1000 mm) is not the trigger."""
    latch = rows(options)["latch"]
    assert latch.ended_at == pytest.approx(0.5)
    trace = options.trace
    cycle = round(0.5 / options.scenario.cycle_time)
    assert latch.value == pytest.approx(trace["v.set_position"][cycle], abs=1e-6)


def test_power_override_halves_the_velocity() -> None:
    """§4.1: Override 50 % on MC_Power: a move at 100 mm/s runs at 50 mm/s."""
    result = run_scenario(parse_scenario("""\
name: override
axes: [{name: x}]
duration: 1
timeline:
  - {at: 0, axis: x, command: power, override: 50}
  - {at: 0, axis: x, command: move_velocity, velocity: 100}
"""))
    assert result.trace["x.set_velocity"][-1] == pytest.approx(50.0, abs=1e-9)


def test_group_set_position_buffered_waits_for_the_move() -> None:
    """Part 4 §5.9, D-130: aborting is refused while the group moves; buffered is Done when
    the move before ends, and the group then reads the new position."""
    result = run_scenario(parse_scenario(BUFFERED))
    assert result.passed, [check for check in result.checks if not check.passed]
    assert rows(result)["after"].ended_at == rows(result)["go"].ended_at
