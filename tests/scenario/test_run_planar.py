"""Running planar movers from scenario files: the setup before t = 0, rejections with their
blocking object, positions reached, C/Z/A/B moves, halt, signals, summary and JSON."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import openmotion as om
from openmotion.planar import (
    MC_PlanarGroup,
    MC_PlanarMover,
    MoverVector,
    PlanarMoverParameters,
    PositionXYC,
)
from openmotion.scenario import CommandRow, ScenarioResult, parse_scenario, run_scenario

#: TF5430 §6.3.2 with the setup done by the run: one (0, 0), two (240, 0), one group
MANUAL_632 = """\
name: two movers
planar:
  movers:
    - {name: one, x: 0, y: 0}
    - {name: two, x: 240, y: 0}
  groups: [{name: group}]
timeline:
  - {id: pos1, at: 0, mover: one, command: move_to_position, x: 0, y: 240}
  - {id: pos2, at: 0, mover: two, command: move_to_position, x: 0, y: 0}
checks:
  - {signal: one.state, expect: enabled, at: 0}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def manual() -> ScenarioResult:
    return run_scenario(parse_scenario(MANUAL_632))


def test_manual_632_the_second_mover_is_rejected_by_the_first(manual: ScenarioResult) -> None:
    """§6.3.2: commanded in the same cycle, mover two's way to the origin meets the area of
    mover one, which still stands there: rejected with PLANAR_COLLISION and mover one's OID."""
    assert manual.passed, manual.checks  # enabled and grouped at t = 0
    first, second = rows(manual)["pos1"], rows(manual)["pos2"]
    assert (first.result, second.result) == ("DONE", "ERROR")
    assert (second.error, second.message) == ("PLANAR_COLLISION",
                                              "rejected (33158) by mover 16#05110010")
    assert second.issued_at == 0.0 and second.ended_at == pytest.approx(0.001)
    movers = {row.mover: row for row in manual.planar_movers}
    assert (movers["one"].x, movers["one"].y) == (0.0, 240.0)
    assert (movers["two"].x, movers["two"].y) == (240.0, 0.0)  # never moved
    assert (movers["one"].oid, movers["two"].oid) == (0x05110010, 0x05110020)
    assert movers["one"].group == "group" and movers["one"].state == "enabled"


def test_the_setup_happens_before_t0(manual: ScenarioResult) -> None:
    """The move takes as long as in a Python script that sets the machine up and then moves:
    the setup's cycles are not on the scenario's clock."""
    rt = om.Runtime()
    group = MC_PlanarGroup(rt)
    one = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(0.0, 0.0)))
    group.enable()
    one.enable()
    rt.run(0.002)
    one.add_to_group(group)
    rt.step()
    start = rt.now
    move = one.move_to_position(PositionXYC(0.0, 240.0))
    rt.run_until(lambda: move.done, timeout=5.0)
    assert rows(manual)["pos1"].ended_at == pytest.approx(rt.now - start, abs=1e-12)
    assert manual.trace.time[0] == 0.0 and manual.trace["one.y"][0] == 0.0


def test_an_open_ended_run_stops_settle_time_after_the_movers(manual: ScenarioResult) -> None:
    assert manual.end_time == pytest.approx(rows(manual)["pos1"].ended_at + 0.1)


def test_the_summary_and_json_show_the_planar_movers(manual: ScenarioResult) -> None:
    text = manual.summary()
    assert text.startswith("two movers: 2 planar movers, ")
    assert text.index("Commands") < text.index("Planar movers") < text.index("Checks")
    assert "PLANAR_COLLISION: rejected (33158) by mover 16#05110010" in " ".join(text.split())
    assert "  one     16#05110010   group   enabled        0      240" in text
    data = json.loads(json.dumps(manual.to_dict()))
    assert data["planar_movers"][1] == {"mover": "two", "oid": 0x05110020, "group": "group",
                                        "state": "enabled", "x": 240.0, "y": 0.0, "z": 0.0,
                                        "a": 0.0, "b": 0.0, "c": 0.0}
    assert data["commands"][1]["error"] == "PLANAR_COLLISION"


def test_a_scenario_without_planar_movers_has_no_planar_output() -> None:
    result = run_scenario(parse_scenario("name: t\naxes: [{name: x}]\n"))
    assert result.planar_movers == [] and "planar_movers" not in result.to_dict()
    assert "Planar movers" not in result.summary() and result.summary().startswith("t: 1 axis")


FIELD = """\
name: field
planar:
  environment: {columns: 3, rows: 2}
  movers:
    - {name: a, x: 120, y: 120}
    - name: b
      x: 600
      y: 360
      parameters: {maximum_dynamic_xy: {velocity: 1500}, default_dynamic_xy: {velocity: 1000}}
  groups: [{name: g}]
record: {signals: [a.x, a.y, a.c, a.z, a.a, a.b, a.velocity, b.x, b.velocity, b.state]}
"""


def run(timeline: str, checks: str = "") -> ScenarioResult:
    result = run_scenario(parse_scenario(FIELD + "timeline:\n" + timeline + checks))
    assert result.passed, [check for check in result.checks if not check.passed]
    return result


def test_the_environment_blocks_a_move_off_the_stators() -> None:
    result = run("  - {id: out, at: 0, mover: a, command: move_to_position, x: 50, y: 120}\n"
                 "  - {id: fine, when: out.error, mover: a, command: move_to_position, x: 200,"
                 " y: 200}\n",
                 "checks:\n  - {command: out, result: error, error_id: PLANAR_COLLISION}\n"
                 "  - {signal: a.x, expect: 200}\n  - {signal: a.y, expect: 200}\n")
    assert rows(result)["out"].message == "rejected (33158) by environment 16#05120010"
    assert rows(result)["out"].ended_at == pytest.approx(0.001)  # decided in the first cycle
    assert rows(result)["fine"].issued_at == pytest.approx(0.002)  # seen in the next one


def test_positions_c_z_a_b_are_reached_and_recorded() -> None:
    result = run("  - {id: xy, at: 0, mover: a, command: move_to_position, x: 360, y: 240, c: 5}\n"
                 "  - {id: z, at: 0, mover: a, command: move_z, position: 3}\n"
                 "  - {id: tilt_a, at: 0, mover: a, command: move_a, position: 1.5}\n"
                 "  - {id: tilt_b, at: 0, mover: a, command: move_b, position: -2}\n",
                 "checks:\n  - {signal: a.c, expect: 5}\n  - {signal: a.z, expect: 3}\n"
                 "  - {signal: a.a, expect: 1.5}\n  - {signal: a.b, expect: -2}\n")
    assert all(row.result == "DONE" for row in result.commands)  # side by side, §6.1.5
    trace = result.trace
    assert (trace["a.x"][-1], trace["a.y"][-1], trace["a.z"][-1]) == (360.0, 240.0, 3.0)
    assert trace["a.x"][0] == 120.0 and np.all(np.diff(trace["a.x"]) >= 0.0)
    assert trace["b.state"][0] == float(om.planar.PlanarState.ENABLED)


def test_a_constraint_limits_the_path_velocity_and_is_clipped_to_the_maximum() -> None:
    result = run("  - {id: slow, at: 0, mover: a, command: move_to_position, x: 360, y: 120,"
                 " velocity: 500}\n"
                 "  - {id: fast, at: 0, mover: b, command: move_to_position, x: 600, y: 120,"
                 " velocity: 9000, acceleration: MC_IGNORE}\n")
    assert result.trace.peak("a.velocity") == pytest.approx(500.0, abs=1e-9)
    assert result.trace.peak("b.velocity") <= 1500.0 * (1 + 1e-12)
    assert "constraint velocity 9000 clipped to the mover maximum 1500" in \
        rows(result)["fast"].message


def test_move_c_out_of_the_windows_locks_xy_until_back_in_a_window() -> None:
    result = run("  - {id: turn, at: 0, mover: a, command: move_c, position: 45}\n"
                 "  - {id: locked, when: turn.done, mover: a, command: move_to_position,"
                 " x: 360, y: 120}\n"
                 "  - {id: back, when: locked.error, mover: a, command: move_c, position: 180,"
                 " direction: positive, additional_turns: 1}\n"
                 "  - {id: free, when: back.done, mover: a, command: move_to_position, x: 360,"
                 " y: 120}\n",
                 "checks:\n  - {command: locked, result: error, error_id: PLANAR_WRONG_MODE}\n"
                 "  - {command: free, result: done}\n  - {signal: a.c, expect: 540}\n")
    assert rows(result)["locked"].message.startswith(
        "rejected (29698): MoveToPosition is not accepted in command mode "
        "CRotationFreeMovement")


def test_halt_brakes_a_move_which_shows_aborted() -> None:
    result = run("  - {id: go, at: 0, mover: a, command: move_to_position, x: 600, y: 120}\n"
                 "  - {id: stop, when: a.x > 200, mover: a, command: mover_halt}\n",
                 "checks:\n  - {command: go, result: aborted}\n"
                 "  - {command: stop, result: done}\n  - {signal: a.velocity, expect: 0}\n"
                 "  - {signal: a.x, min: 200, max: 599}\n")
    assert rows(result)["go"].ended_at == rows(result)["stop"].issued_at


def test_a_mover_without_enable_is_refused_until_the_timeline_enables_it() -> None:
    text = FIELD.replace("- {name: a, x: 120, y: 120}", "- {name: a, x: 120, y: 120, "
                                                        "enable: false}")
    result = run_scenario(parse_scenario(
        text + "timeline:\n"
        "  - {id: early, at: 0, mover: a, command: move_to_position, x: 360, y: 120}\n"
        "  - {id: on, when: early.error, mover: a, command: mover_enable}\n"
        "  - {id: go, when: a.state == enabled, mover: a, command: move_to_position, x: 360,"
        " y: 120}\n"
        "checks:\n  - {command: early, result: error, error_id: PLANAR_WRONG_STATE}\n"
        "  - {command: go, result: done}\n  - {signal: a.x, expect: 360}\n"))
    assert result.passed, result.checks
    on = rows(result)["on"]  # Enabling shows for one cycle, Enabled in the next (§4.1)
    assert (on.issued_at, on.ended_at) == (pytest.approx(0.002), pytest.approx(0.003))


def test_group_commands_and_membership_from_the_timeline() -> None:
    """Leaving the group switches collision avoidance off: the same move is accepted."""
    result = run("  - {id: blocked, at: 0, mover: a, command: move_to_position, x: 600,"
                 " y: 360}\n"
                 "  - {id: leave, at: 0, mover: a, command: remove_from_group}\n"
                 "  - {id: free, when: leave.done, mover: a, command: move_to_position,"
                 " x: 600, y: 360}\n"
                 "  - {id: off, when: free.done, group: g, command: planar_group_disable}\n"
                 "  - {id: join, when: off.done, mover: a, command: add_to_group, group: g}\n",
                 "checks:\n  - {command: blocked, result: error, error_id: PLANAR_COLLISION}\n"
                 "  - {command: free, result: done}\n"
                 "  - {command: join, result: error, error_id: PLANAR_WRONG_STATE}\n")
    assert rows(result)["free"].result == "DONE"


def test_axes_and_planar_movers_in_one_scenario_leave_the_axis_trace_alone() -> None:
    axis = ("name: mixed\naxes: [{name: x}]\ntimeline:\n"
            "  - {at: 0, axis: x, command: power}\n"
            "  - {at: 0.01, axis: x, command: move_absolute, position: 50, velocity: 200}\n")
    alone = run_scenario(parse_scenario(axis + "record: {signals: [x.set_position]}\n"))
    mixed = run_scenario(parse_scenario(
        axis + "  - {at: 0.01, mover: m, command: move_to_position, x: 100, y: 0}\n"
        "planar:\n  movers: [{name: m}]\n  groups: [{name: g}]\n"
        "record: {signals: [m.x, x.set_position]}\n"))
    assert mixed.trace.columns == ("time", "m.x", "x.set_position")
    assert np.array_equal(mixed.trace["x.set_position"][:len(alone.trace)],
                          alone.trace["x.set_position"])
    assert mixed.trace["m.x"][-1] == 100.0
    assert mixed.summary().startswith("mixed: 1 axis, 1 planar mover, ")


def test_two_runs_give_bit_identical_traces() -> None:
    first, second = (run_scenario(parse_scenario(MANUAL_632)) for _ in range(2))
    assert first.trace.equals(second.trace) and first.summary() == second.summary()


def test_the_docs_planar_example_runs_as_described() -> None:
    """docs/scenarios.md#planar-movers: m1 goes first, m2 is rejected by it."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "scenarios.md").read_text()
    block = re.search(r"## Planar movers\n\n```yaml\n(.*?)```", text, re.S)
    assert block is not None
    result = run_scenario(parse_scenario("name: docs\n" + block.group(1)))
    assert (rows(result)["go"].result, rows(result)["too"].message) == (
        "DONE", "rejected (33158) by mover 16#05110010")
