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
                                        "a": 0.0, "b": 0.0, "c": 0.0, "coordinate_system": 0}
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


# -- parts and coordinate systems (§5, §6.6) ---------------------------------------------------

CS_1, CS_2 = 0x01010060, 0x010100A0  #: the coordinate systems of §6.1.4 and §6.6.1
PART_1, PART_2, PART_3 = 0x01010020, 0x01010030, 0x01010080

#: §6.1.4: two static one-stator parts side by side in one coordinate system
TWO_PARTS = """\
name: two parts
planar:
  environment:
    coordinate_systems: [16#01010060]
    parts:
      - {oid: 16#01010020, stators: [[0, 0]], positions: [{coordinate_system: 16#01010060}]}
      - {oid: 16#01010030, stators: [[0, 0]],
         positions: [{coordinate_system: 16#01010060, x: 240}]}
  movers:
    - {name: m, part: 16#01010020, x: 120, y: 120}
record: {signals: [m.x, m.y, m.velocity, m.coordinate_system, m.state]}
timeline:
"""


def run_passing(text: str) -> ScenarioResult:
    result = run_scenario(parse_scenario(text))
    assert result.passed, [check for check in result.checks if not check.passed]
    return result


def test_manual_614_a_target_on_the_right_part_is_reported_in_the_coordinate_system() -> None:
    """§6.1.4: (100, 100) on part 16#01010030 is x = 340, y = 100 in the coordinate system,
    PhysicalAreaID 16842848; crossing to the adjacent part is allowed."""
    result = run_passing(TWO_PARTS + "  - {id: go, at: 0, mover: m, command: move_to_position, "
                                     "x: 100, y: 100, reference_id: 16#01010030}\n")
    movers = {row.mover: row for row in result.planar_movers}
    assert (movers["m"].x, movers["m"].y, movers["m"].coordinate_system) == (340.0, 100.0,
                                                                             16842848)
    assert rows(result)["go"].result == "DONE"
    assert set(result.trace["m.coordinate_system"]) == {float(CS_1)}


def test_a_target_off_its_part_or_with_an_unknown_reference_fails() -> None:
    result = run_passing(
        TWO_PARTS + "  - {id: off, at: 0, mover: m, command: move_to_position, x: 300, y: 100,"
        " reference_id: 16#01010020}\n"
        "  - {id: unknown, at: 0, mover: m, command: move_to_position, x: 1, y: 1,"
        " reference_id: 16#0BADF00D}\n"
        "  - {id: zero, at: 0, mover: m, command: move_to_position, x: 300, y: 100}\n"
        "checks:\n  - {command: off, result: error, error_id: INVALID_REFERENCE_ID}\n"
        "  - {command: unknown, result: error, error_id: INVALID_REFERENCE_ID}\n"
        "  - {command: zero, result: done}\n  - {signal: m.x, expect: 300}\n")
    assert rows(result)["off"].message == (
        "rejected (29699): target (300, 100) lies off part 16#01010020: give the part it lies "
        "on or the coordinate system (§6.1.7)")
    assert rows(result)["unknown"].message.startswith(
        "rejected (29699): ReferenceId 16#0BADF00D names no part and no coordinate system")


ELEVATOR = (Path(__file__).resolve().parents[2] / "examples" / "planar_parts.yaml").read_text()


def test_the_elevator_carries_the_mover_into_the_other_coordinate_system() -> None:
    """§6.6.1 (examples/planar_parts.yaml): the mover's numbers do not change when the
    elevator moves, its coordinate system does, in the cycle of ActivatePosition."""
    result = run_passing(ELEVATOR)
    trace, ride = result.trace, rows(result)["ride"]
    assert ride.issued_at == ride.ended_at
    at = int(np.searchsorted(trace.time, ride.ended_at - 1e-9))
    assert trace["mover.coordinate_system"][at - 1] == CS_1
    assert trace["mover.coordinate_system"][at] == CS_2
    assert trace["mover.y"][at - 1] == trace["mover.y"][at] == 360.0
    assert result.planar_movers[0].coordinate_system == CS_2


def test_coordinate_systems_are_connected_only_by_a_part_that_moves() -> None:
    """Before the ride part 2 (CS 2) is out of reach; 0 is no reference with two coordinate
    systems; a position index the part does not have is an invalid input."""
    text = ELEVATOR.replace("  # states 8-9", """\
  - {id: too_early, when: board.done, mover: mover, command: move_to_position, x: 120, y: 120,
     reference_id: 16#01010030}
  - {id: zero, when: board.done, mover: mover, command: move_to_position, x: 120, y: 120}
  - {id: third, when: board.done, part: 16#01010080, command: activate_part_position,
     position_index: 3}
  # states 8-9""")
    result = run_passing(text)
    too_early, zero, third = (rows(result)[name] for name in ("too_early", "zero", "third"))
    assert (too_early.error, too_early.message) == (
        "PLANAR_PART_NOT_ENABLED", "rejected (29703): part 16#01010030 is in position 1, in "
        "coordinate system 16#010100A0, not in the mover's (16#01010060)")
    assert zero.error == "INVALID_REFERENCE_ID"
    assert zero.message.startswith("rejected (29699): ReferenceId 0 needs one static "
                                   "coordinate system (§5.3)")
    assert (third.error, third.message) == (
        "PLANAR_INVALID_INPUT", "rejected (29705): part 16#01010080: position index 3 is not "
        "in 1..2")
    assert rows(result)["leave"].result == "DONE"  # the later steps are unaffected


def test_a_static_layout_lets_the_environment_guard_the_parts_in_a_group() -> None:
    """One coordinate system, static parts: the environment joins the group by default and
    its boundary is the parts' outline."""
    text = TWO_PARTS.replace("record:", "  groups: [{name: g}]\nrecord:")
    result = run_passing(text + "  - {id: out, at: 0, mover: m, command: move_to_position,"
                                " x: 120, y: 200}\n"
                                "checks:\n  - {command: out, result: error,"
                                " error_id: PLANAR_COLLISION}\n")
    assert rows(result)["out"].message == "rejected (33158) by environment 16#05120010"


# -- external setpoints (§6.1.6, §6.1.7) -------------------------------------------------------


def max_brake(speed: float) -> float:
    """The time-optimal stopping distance from ``speed`` (no acceleration) with the default
    maximum XY dynamics, where StopExternalSetpointGeneration brakes (§6.1.6)."""
    limits = PlanarMoverParameters().maximum_dynamic_xy
    if speed >= limits.deceleration ** 2 / limits.jerk:
        return speed ** 2 / (2 * limits.deceleration) + speed * limits.deceleration / (
            2 * limits.jerk)
    return speed * (speed / limits.jerk) ** 0.5


def test_a_ramp_is_followed_exactly_and_stop_brakes_after_the_cycles_setpoint() -> None:
    """The first setpoint goes in the firing cycle (at 0: cycle 1), one per cycle after it;
    the stop entry comes after its cycle's setpoint, then the mover brakes with its maximum
    dynamics and is back in FreeMovement (a move is accepted)."""
    result = run("  - {id: ext, at: 0, mover: a, command: start_external_setpoint_generation,"
                 " feed: {x: {ramp: {velocity: 200}}}}\n"
                 "  - {id: stop, at: 0.5, mover: a, command: stop_external_setpoint_generation}\n"
                 "  - {id: free, at: 1, mover: a, command: move_to_position, x: 360,"
                 " y: 240}\n",
                 "checks:\n  - {command: ext, result: done}\n  - {command: stop, result: done}\n"
                 "  - {command: free, result: done}\n")
    trace = result.trace
    fed = trace["a.x"][1:501]  # cycles 1..500
    assert np.array_equal(fed, 120.0 + 200.0 * (np.arange(500) * 0.001))  # τ, then x
    assert np.all(trace["a.velocity"][1:501] == 200.0) and trace["a.y"][500] == 120.0
    ext = rows(result)["ext"]
    assert (ext.issued_at, ext.ended_at) == (0.0, pytest.approx(0.5))
    assert trace["a.velocity"][999] == 0.0
    assert trace["a.x"][999] == pytest.approx(fed[-1] + max_brake(200.0), abs=1e-9)


def test_a_sine_per_coordinate_and_held_coordinates() -> None:
    """y: the raised cosine from the start position; c: one with an offset; x holds."""
    result = run("  - {id: ext, at: 0.01, mover: a, command: start_external_setpoint_generation,"
                 " feed: {y: {sine: {amplitude: 100, period: 0.4}},"
                 " c: {sine: {amplitude: -10, period: 0.2, offset: 5}}}}\n"
                 "  - {id: stop, at: 0.41, mover: a, command: stop_external_setpoint_generation}\n",
                 "checks:\n  - {command: ext, result: done}\n  - {signal: a.y, expect: 120}\n"
                 "  - {signal: a.x, expect: 120, at: always}\n")
    trace = result.trace
    tau = np.arange(401) * 0.001  # cycles 10..410
    assert trace["a.y"][10:411] == pytest.approx(120.0 + 50.0 * (1 - np.cos(tau * np.pi / 0.2)),
                                                 abs=1e-12)
    assert trace["a.c"][10:411] == pytest.approx(5.0 - 5.0 * (1 - np.cos(tau * np.pi / 0.1)),
                                                 abs=1e-12)
    peak = 50.0 * 2 * np.pi / 0.4  # amplitude / 2 * ω
    assert trace.peak("a.velocity") == pytest.approx(peak, rel=1e-4)


def test_a_missing_setpoint_is_the_movers_error() -> None:
    """feed_for 0.1 s: setpoints in cycles 1..100; cycle 101 has none: PLANAR_EXT_SETPOINT,
    the mover brakes (QuickStop) and ends in Error; the row shows the mover's error."""
    result = run("  - {id: ext, at: 0, mover: a, command: start_external_setpoint_generation,"
                 " feed_for: 0.1, feed: {x: {ramp: {velocity: 100}}}}\n",
                 "checks:\n  - {command: ext, result: error, error_id: PLANAR_EXT_SETPOINT}\n"
                 "  - {signal: a.state, expect: error}\n")
    ext = rows(result)["ext"]
    assert (ext.ended_at, ext.message) == (pytest.approx(0.101),
                                           "no external setpoint in this cycle (§6.1.6)")
    assert result.trace["a.x"][100] == pytest.approx(129.9, abs=1e-9)
    assert {row.mover: row.state for row in result.planar_movers}["a"] == "error"


def test_a_setpoint_above_the_maximum_velocity_is_the_movers_error() -> None:
    """The refused setpoint ends StartExternalSetpointGeneration with the mover's error."""
    result = run("  - {id: ext, at: 0, mover: a, command: start_external_setpoint_generation,"
                 " feed: {x: {ramp: {velocity: 5000}}}}\n",
                 "checks:\n  - {command: ext, result: error, error_id: PLANAR_EXT_SETPOINT}\n")
    ext = rows(result)["ext"]
    assert (ext.ended_at, ext.message) == (pytest.approx(0.001), "external setpoint velocity "
                                           "x 5000 above the maximum 4000 (§6.1.6)")


def test_a_start_the_mover_refuses_is_the_rows_error() -> None:
    text = FIELD.replace("- {name: a, x: 120, y: 120}", "- {name: a, x: 120, y: 120, "
                                                        "enable: false}")
    result = run_passing(text + "timeline:\n  - {id: ext, at: 0, mover: a, command: "
                                "start_external_setpoint_generation}\n"
                                "checks:\n  - {command: ext, result: error,"
                                " error_id: PLANAR_WRONG_STATE}\n")
    ext = rows(result)["ext"]
    assert ext.message.startswith("rejected (29697)") and ext.ended_at == pytest.approx(0.001)


def test_relative_setpoints_add_to_a_move_and_the_offset_stays() -> None:
    """Relative: the ramp's offset is added to the move; Stop keeps the offset reached."""
    result = run("  - {id: go, at: 0, mover: a, command: move_to_position, x: 360, y: 120}\n"
                 "  - {id: ext, at: 0, mover: a, command: start_external_setpoint_generation,"
                 " mode: relative, feed: {y: {ramp: {velocity: 50}}}}\n"
                 "  - {id: stop, at: 0.2, mover: a, command: stop_external_setpoint_generation}\n",
                 "checks:\n  - {command: go, result: done}\n  - {command: ext, result: done}\n"
                 "  - {signal: a.x, expect: 360}\n")
    trace = result.trace
    assert np.array_equal(trace["a.y"][1:201], 120.0 + 50.0 * (np.arange(200) * 0.001))
    assert trace["a.y"][-1] == pytest.approx(120.0 + 50.0 * 0.199, abs=1e-9)
    assert trace["a.x"][100] > 120.0  # the move ran meanwhile


def test_setpoints_in_a_part_frame_must_switch_parts_those_in_the_system_need_not() -> None:
    """§6.1.7: with part 1's id the ramp fails past x = 240 (INVALID_REFERENCE_ID, the
    mover's error); with the coordinate system's id it crosses onto part 2."""
    ramp = ("  - {id: ext, at: 0, mover: m, command: start_external_setpoint_generation,"
            " reference_id: REF, feed: {x: {ramp: {velocity: 200}}}}\n"
            "  - {id: stop, at: 0.8, mover: m, command: stop_external_setpoint_generation}\n")
    on_part = run_scenario(parse_scenario(TWO_PARTS + ramp.replace("REF", "16#01010020")))
    ext = rows(on_part)["ext"]
    assert (ext.result, ext.error) == ("ERROR", "INVALID_REFERENCE_ID")
    assert ext.message.startswith("target (240.2, 120) lies off part 16#01010020")
    assert ext.ended_at == pytest.approx(0.602)  # τ = 0.601 s: x = 240.2
    in_system = run_scenario(parse_scenario(TWO_PARTS + ramp.replace("REF", "16#01010060")))
    assert rows(in_system)["ext"].result == "DONE"
    end = in_system.planar_movers[0].x
    assert end == pytest.approx(120.0 + 200.0 * 0.799 + max_brake(200.0), abs=1e-9)


def test_held_coordinates_and_default_offsets_are_in_the_frame_of_the_reference() -> None:
    """A mover at (120, 120) on part 2 is at x = 360 in the system; fed in part 2's frame,
    its held x is 120 there, which is 360 again."""
    text = TWO_PARTS.replace("{name: m, part: 16#01010020", "{name: m, part: 16#01010030")
    result = run_passing(text + "  - {id: ext, at: 0, mover: m, command: "
                                "start_external_setpoint_generation, reference_id: 16#01010030,"
                                " feed: {y: {ramp: {velocity: -100}}}}\n"
                                "  - {id: stop, at: 0.5, mover: m, command: "
                                "stop_external_setpoint_generation}\n"
                                "checks:\n  - {command: ext, result: done}\n"
                                "  - {signal: m.x, expect: 360, at: always}\n")
    assert result.trace["m.y"][500] == pytest.approx(120.0 - 100.0 * 0.499, abs=1e-9)


def test_an_axis_feeds_a_coordinate_one_cycle_late() -> None:
    """feed: {x: {axis: gen}}: the mover's x is the virtual axis' set position of the cycle
    before, a jerk-limited profile the mover follows exactly."""
    text = FIELD.replace("name: field\n", "name: field\naxes: [{name: gen, position: 120}]\n")
    text = text.replace("record: {signals: [", "record: {signals: [gen.set_position, ")
    result = run_passing(text + "timeline:\n  - {at: 0, axis: gen, command: power}\n"
                                "  - {id: ext, at: 0, mover: a, command: "
                                "start_external_setpoint_generation, feed: {x: {axis: gen}}}\n"
                                "  - {id: go, at: 0.01, axis: gen, command: move_absolute,"
                                " position: 400, velocity: 500}\n"
                                "  - {id: stop, when: go.done, mover: a, command: "
                                "stop_external_setpoint_generation}\n"
                                "checks:\n  - {command: ext, result: done}\n"
                                "  - {signal: a.x, expect: 400}\n")
    trace = result.trace
    assert np.array_equal(trace["a.x"][2:], trace["gen.set_position"][1:-1])


def test_the_docs_part_and_setpoint_examples_run_as_described() -> None:
    """docs/scenarios.md#parts-and-coordinate-systems and #external-setpoints."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "scenarios.md").read_text()
    for title in ("Parts and coordinate systems", "External setpoints"):
        block = re.search(rf"### {title}\n\n.*?```yaml\n(.*?)```", text, re.S)
        assert block is not None, title
        result = run_scenario(parse_scenario("name: docs\n" + block.group(1)))
        assert result.passed, (title, result.checks)
