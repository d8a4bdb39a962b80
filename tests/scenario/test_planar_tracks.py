"""Planar tracks in scenario files (TF5430 §6.2): the ``planar.tracks`` block, its build order,
the track entries join_track, leave_track, move_on_track (and mover_halt on a track), the
``track`` and ``s`` signals, the summary's tables, and the two track examples."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from openmotion.core.special_values import MC_DEFAULT
from openmotion.planar import DynamicConstraint_PathXY, ModuloDirection, PositionXYC
from openmotion.planar.options import (
    ST_JoinTrackOptions,
    ST_LeaveTrackOptions,
    ST_MoveOnTrackOptions,
)
from openmotion.scenario import (
    CommandRow,
    ScenarioError,
    ScenarioResult,
    examples_dir,
    parse_scenario,
    run_scenario,
)
from openmotion.scenario.planar_riding import JoinTrack, LeaveTrack, MoveOnTrack
from openmotion.scenario.planar_tracks import TrackRef, build_order

ROOT = Path(__file__).resolve().parents[2]

#: every key of a track and every track entry
VALID = """\
name: tracks
planar:
  movers:
    - {name: m1, x: 0, y: 0}
    - {name: m2, x: 240, y: 0}
  groups: [{name: g}]
  tracks:
    - name: back                                  # listed first, built after line
      starts_from: line
      geometry:
        - circle: {start: [960, 0], end: [960, 480], center: [960, 240], clockwise: false}
        - line: [[960, 480], [0, 480]]
      ends_at: line
      collision_ranges: [0, 0]
    - name: line
      geometry: [{position: [0, 0]}, {position: [960, 0]}]
      max_mover_width: 120
      max_mover_height: 130
    - name: ring
      geometry: [{line: [[0, 1200], [480, 1200]]}, {line: [[480, 1440], [0, 1440]]}]
      closed_loop: true
timeline:
  - {id: on, at: 0, mover: m1, command: join_track, track: line}
  - {at: 0, mover: m2, command: join_track, track: line, use_orientation: false, velocity: 500}
  - {at: 1, mover: m1, command: move_on_track, track: back, position: 100, gap: 250,
     direction: positive, additional_turns: 1, modulo_tolerance: 2}
  - {at: 2, mover: m1, command: move_on_track, position: 50}
  - {at: 3, mover: m1, command: leave_track, x: 120, y: 240, c: 90}
  - {at: 3, mover: m2, command: leave_track, x: 120, y: 240, reference_id: 0}
  - {when: m1.track == back, mover: m2, command: mover_halt}
  - {when: m1.track == none, mover: m2, command: mover_halt}
  - {when: m1.s > 30, mover: m2, command: mover_halt}
checks:
  - {signal: m1.track, expect: ring}
  - {signal: m1.track, expect: 2}
  - {signal: m1.s, min: 0}
"""


def test_the_tracks_load_with_their_links_geometry_and_parameters() -> None:
    scenario = parse_scenario(VALID)
    back, line, ring = scenario.planar.tracks
    assert (back.starts_from, back.ends_at, back.collision_ranges) == ("line", "line", (0, 0))
    assert [element.kind for element in back.geometry] == ["circle", "line"]
    assert back.geometry[0].circle.clockwise is False
    assert (line.max_mover_width, line.max_mover_height, line.collision_ranges) == (
        120.0, 130.0, None)
    assert (ring.closed_loop, ring.starts_from, ring.ends_at) == (True, None, None)
    assert scenario.planar.groups[0].tracks is None  # every track joins g


def test_the_track_entries_build_the_method_arguments() -> None:
    entries = parse_scenario(VALID).timeline
    assert entries[0].arguments() == (TrackRef("line"), None, ST_JoinTrackOptions(True))
    assert entries[1].arguments() == (
        TrackRef("line"), DynamicConstraint_PathXY(500.0, MC_DEFAULT, MC_DEFAULT, MC_DEFAULT),
        ST_JoinTrackOptions(False))
    assert entries[2].arguments() == (TrackRef("back"), 100.0, None, ST_MoveOnTrackOptions(
        250.0, ModuloDirection.POSITIVE, 1, 2.0))
    assert entries[3].arguments() == (None, 50.0, None, ST_MoveOnTrackOptions())
    assert entries[4].arguments() == (PositionXYC(120.0, 240.0, 90.0), None,
                                      ST_LeaveTrackOptions(True))
    assert entries[5].arguments() == (PositionXYC(120.0, 240.0, 0.0), None,
                                      ST_LeaveTrackOptions(False))
    assert [type(entry) for entry in entries[:6]] == [JoinTrack, JoinTrack, MoveOnTrack,
                                                     MoveOnTrack, LeaveTrack, LeaveTrack]


def test_track_conditions_and_checks_take_the_track_name() -> None:
    scenario = parse_scenario(VALID)
    conditions = [entry.when for entry in scenario.timeline[6:]]
    assert [(c.attribute, c.value) for c in conditions] == [("track", 1.0), ("track", 0.0),
                                                          ("s", 30.0)]
    assert [check.expected for check in scenario.checks[:2]] == [3.0, 2.0]


# -- the build order ----------------------------------------------------------------------------


def tracks(text: str) -> list:
    return parse_scenario("name: t\nplanar:\n  movers: [{name: m}]\n  tracks:\n" + text
                          ).planar.tracks


def test_a_track_is_built_after_the_track_it_starts_from_and_may_end_at_a_later_one() -> None:
    """StartFromTrack needs the other track finished; EndAtTrack only its geometry, so a
    track may end at one that starts from it (a loop of two)."""
    order, stuck = build_order(parse_scenario(VALID).planar.tracks)
    assert stuck == []
    assert order == [(1, "geometry"), (1, "end"), (0, "geometry"), (0, "end"), (2, "geometry"),
                     (2, "end")]  # line, then back, which starts from it and ends at it


def test_a_track_made_only_of_its_links_waits_for_the_track_it_ends_at() -> None:
    specs = tracks("    - {name: link, starts_from: a, ends_at: b}\n"
                   "    - {name: a, geometry: [{line: [[0, 0], [500, 0]]}]}\n"
                   "    - {name: b, geometry: [{line: [[1500, 400], [2000, 400]]}]}\n")
    order, stuck = build_order(specs)
    assert stuck == [] and order.index((0, "end")) > order.index((2, "geometry"))


# -- validation ---------------------------------------------------------------------------------


def problems(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        parse_scenario("name: t\nplanar:\n  movers: [{name: m}]\n" + text, "bad.yaml")
    return [str(problem) for problem in info.value.problems]


LINE = "{line: [[0, 0], [400, 0]]}"


@pytest.mark.parametrize(("text", "expected"), [
    (f"  tracks:\n    - {{name: a, starts_from: q, geometry: [{LINE}]}}\n",
     "bad.yaml:5: planar.tracks[0].starts_from: unknown planar track 'q' (planar.tracks: a)"),
    (f"  tracks:\n    - {{name: a, ends_at: a, geometry: [{LINE}]}}\n",
     "bad.yaml:5: planar.tracks[0].ends_at: a track cannot link to itself; a loop is "
     "closed_loop: true"),
    (f"  tracks:\n    - {{name: a, starts_from: a, geometry: [{LINE}]}}\n",
     "bad.yaml:5: planar.tracks[0].starts_from: a track cannot link to itself"),
    ("  tracks:\n    - {name: a}\n",
     "bad.yaml:5: planar.tracks[0]: geometry: give at least one line, circle or position (a "
     "track with none must have both starts_from and ends_at"),
    ("  tracks:\n    - {name: a, geometry: []}\n",
     "bad.yaml:5: planar.tracks[0].geometry: give at least one line, circle or position"),
    (f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n"
     "    - {name: b, starts_from: a, geometry: []}\n",
     "bad.yaml:6: planar.tracks[1].geometry: give at least one line"),
    ("  tracks:\n    - {name: a, geometry: [{line: [[0, 0], [1, 0]], position: [3, 4]}]}\n",
     "bad.yaml:5: planar.tracks[0].geometry[0]: give exactly one of 'line', 'circle' or "
     "'position'"),
    ("  tracks:\n    - {name: a, geometry: [{lin: [[0, 0], [1, 0]]}]}\n",
     "bad.yaml:5: planar.tracks[0].geometry[0].lin: unknown field 'lin' (did you mean "
     "'line'?)"),
    ("  tracks:\n    - {name: a, geometry: [{line: [[0, 0]]}]}\n",
     "bad.yaml:5: planar.tracks[0].geometry[0].line"),
    ("  tracks:\n    - {name: a, geometry: [{circle: {start: [0, 0], end: [9, 0], "
     "center: [4.5, 0]}}]}\n",
     "bad.yaml:5: planar.tracks[0].geometry[0].circle.clockwise: required field is missing"),
    (f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n"
     f"    - {{name: b, starts_from: a, closed_loop: true, geometry: [{LINE}]}}\n",
     "bad.yaml:6: planar.tracks[1].closed_loop: a closed loop neither starts from nor ends "
     "at another track"),
    (f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n    - {{name: a, geometry: [{LINE}]}}\n",
     "bad.yaml:5: planar.tracks[0].name: 'a' is used 2 times; it must be unique"),
    (f"  tracks:\n    - {{name: m, geometry: [{LINE}]}}\n",
     "bad.yaml:5: planar.tracks[0].name: 'm' is already the name of a planar mover"),
    (f"  groups: [{{name: g}}]\n  tracks:\n    - {{name: g, geometry: [{LINE}]}}\n",
     "bad.yaml:6: planar.tracks[0].name: 'g' is already the name of a planar group"),
    (f"  tracks:\n    - {{name: a, collision_ranges: [-1, 3], geometry: [{LINE}]}}\n",
     "bad.yaml:5: planar.tracks[0].collision_ranges[0]: must be greater than or equal to 0"),
    (f"  tracks:\n    - {{name: a, max_mover_width: 0, geometry: [{LINE}]}}\n",
     "bad.yaml:5: planar.tracks[0].max_mover_width: must be greater than 0, got 0"),
    # a ring of StartFromTrack links: no order builds it
    ("  tracks:\n    - {name: a, starts_from: b, geometry: [{line: [[0, 0], [100, 0]]}]}\n"
     "    - {name: b, starts_from: a, geometry: [{line: [[200, 0], [300, 0]]}]}\n",
     "bad.yaml:5: planar.tracks[0].starts_from: tracks a, b wait for each other: "
     "StartFromTrack needs the other track finished, EndAtTrack its geometry"),
    (f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n"
     "    - {name: x, starts_from: a, ends_at: y}\n    - {name: y, starts_from: a, ends_at: x}\n",
     "bad.yaml:7: planar.tracks[2].ends_at: tracks x, y wait for each other"),
    # refused by the engine during the scratch setup, at the element's field
    ("  tracks:\n    - {name: a, geometry: [{line: [[0, 0], [100, 0]]}, "
     "{line: [[100, 0], [0, 0]]}]}\n",
     "bad.yaml:5: planar.tracks[0].geometry[1]: PLANAR_INVALID_INPUT (29705): AppendLine: "
     "the track turns back on itself at (100, 0)"),
    ("  tracks:\n    - {name: a, geometry: [{circle: {start: [0, 0], end: [100, 0], "
     "center: [0, 100], clockwise: true}}]}\n",
     "bad.yaml:5: planar.tracks[0].geometry[0]: PLANAR_INVALID_INPUT (29705): AppendCircle"),
    ("  tracks:\n    - {name: a, closed_loop: true, geometry: [{position: [0, 0]}]}\n",
     "bad.yaml:5: planar.tracks[0].closed_loop: PLANAR_INVALID_INPUT (29705): CloseLoop: a "
     "loop needs at least one line or circle"),
    # groups and tracks
    (f"  groups: [{{name: g, tracks: [q]}}]\n  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n",
     "bad.yaml:4: planar.groups[0].tracks[0]: unknown planar track 'q' (planar.tracks: a)"),
    (f"  groups: [{{name: g, movers: [m]}}, {{name: h, movers: []}}]\n"
     f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n",
     "bad.yaml:4: planar.groups[1]: track 'a' is in group 'g' already: a track joins one "
     "group (list each group's tracks)"),
    (f"  groups: [{{name: g, movers: [m]}}, {{name: h, movers: [], tracks: [a]}}]\n"
     f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n",
     "bad.yaml:4: planar.groups[1].tracks[0]: track 'a' is in group 'g' already"),
    (f"  groups: [{{name: g, enable: false, tracks: [a]}}]\n"
     f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n",
     "bad.yaml:4: planar.groups[0].tracks: tracks join in the setup, which needs enable: true"),
    # entries, conditions, checks
    (f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n"
     "timeline:\n  - {at: 0, mover: m, command: join_track, track: q}\n",
     "bad.yaml:7: timeline[0].track: unknown planar track 'q' (planar.tracks: a)"),
    ("timeline:\n  - {at: 0, mover: m, command: join_track}\n",
     "bad.yaml:5: timeline[0].track: required field is missing"),
    ("timeline:\n  - {at: 0, mover: m, command: move_on_track}\n",
     "bad.yaml:5: timeline[0].position: required field is missing"),
    ("timeline:\n  - {at: 0, mover: m, command: move_on_track, position: 3, direction: up}\n",
     "bad.yaml:5: timeline[0].direction: must be one of non_modulo, positive, shortest_way, "
     "negative, got 'up'"),
    ("timeline:\n  - {at: 0, mover: m, command: move_on_track, position: 3, gpa: 100}\n",
     "bad.yaml:5: timeline[0].gpa: unknown field 'gpa' (did you mean 'gap'?)"),
    ("timeline:\n  - {at: 0, mover: m, command: leave_track, x: 1, y: 2, use_orientation: "
     "true}\n",
     "bad.yaml:5: timeline[0].use_orientation: true needs c"),
    (f"  tracks:\n    - {{name: a, geometry: [{LINE}]}}\n"
     "timeline:\n  - {when: m.track == q, mover: m, command: mover_halt}\n",
     "bad.yaml:7: timeline[0].when: 'm.track == q': 'q' is not a planar track (a, none)"),
    ("checks:\n  - {signal: m.track, expect: zz}\n",
     "bad.yaml:5: checks[0].expect: 'zz' is not a number or a planar track name"),
    ("record: {signals: [m.arc]}\n",
     "bad.yaml:4: record.signals[0]: 'm.arc': a planar mover's signal is one of x, y, z, a, b, "
     "c, velocity, state, coordinate_system, track, s"),
])
def test_bad_track_input_names_file_line_and_field(text: str, expected: str) -> None:
    found = problems(text)
    assert any(problem.startswith(expected) for problem in found), found


def test_only_the_first_refusal_of_a_track_is_listed() -> None:
    found = problems("  tracks:\n    - name: a\n      geometry:\n"
                     "        - {line: [[0, 0], [100, 0]]}\n"
                     "        - {line: [[100, 0], [0, 0]]}\n"
                     "        - {line: [[0, 0], [-100, 0]]}\n")
    assert len(found) == 1 and found[0].startswith("bad.yaml:8: planar.tracks[0].geometry[1]")


# -- running ------------------------------------------------------------------------------------


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def join() -> ScenarioResult:
    return run_scenario(examples_dir() / "planar_track_join.yaml")


def test_6_2_4_two_movers_join_the_track_where_they_stand_and_reach_150_and_350(
        join: ScenarioResult) -> None:
    """§6.2.4: the 400 mm track is Enabled at t = 0; the movers at x = 0 and 240 join in one
    cycle and move to 150 and 350 in one cycle, 200 mm (the default gap) apart."""
    assert join.passed, join.checks
    commands = rows(join)
    assert [commands[k].result for k in ("join1", "join2", "move1", "move2")] == ["DONE"] * 4
    assert commands["join1"].issued_at == commands["join2"].issued_at == 0.0
    assert commands["move1"].issued_at == commands["move2"].issued_at
    trace = join.trace
    done = int(np.argmax(np.asarray(trace["time"]) >= commands["move1"].ended_at))
    assert (trace["one.x"][done], trace["one.s"][done]) == pytest.approx((150.0, 150.0))
    (track,) = join.planar_tracks
    assert (track.track, track.oid, track.length, track.state, track.operation_mode) == (
        "track", 0x05120010, pytest.approx(400.0), "enabled", "standing")
    assert track.movers == ("one", "two")  # by arc length


def test_a_halt_on_a_track_brakes_along_it(join: ScenarioResult) -> None:
    commands = rows(join)
    assert (commands["back"].result, commands["stop"].result) == ("ABORTED", "DONE")
    one = next(row for row in join.planar_movers if row.mover == "one")
    assert one.track == "track" and 0.0 < one.s < 150.0
    assert (one.x, one.y) == pytest.approx((one.s, 0.0))


def test_the_track_signals_are_recorded(join: ScenarioResult) -> None:
    trace = join.trace
    assert math.isnan(trace["one.s"][0]) and trace["one.track"][0] == 0.0  # before the join
    assert set(np.asarray(trace["one.track"][1:])) == {1.0}
    assert np.asarray(trace["two.s"])[-1] == pytest.approx(350.0)


def test_the_summary_shows_the_tracks_and_the_movers_on_them(join: ScenarioResult) -> None:
    text = join.summary()
    assert text.splitlines()[0].startswith("planar track join: 2 planar movers, 1 planar track,")
    assert re.search(r"\n  track +16#05120010 +- +400 +0\.0 / 0\.0 +enabled +standing +2\n",
                     text), text
    assert re.search(r"Movers on tracks\n\n  mover +track +s \[mm\]\n.*\n  one +track +\d",
                     text), text
    data = json.loads(json.dumps(join.to_dict()))
    assert data["planar_tracks"][0]["movers"] == ["one", "two"]
    assert data["planar_movers"][1]["track"] == "track"
    assert data["planar_movers"][1]["s"] == pytest.approx(350.0)


@pytest.fixture(scope="module")
def network() -> ScenarioResult:
    return run_scenario(examples_dir() / "planar_track_network.yaml")


def test_twelve_movers_circulate_through_both_switches(network: ScenarioResult) -> None:
    assert network.passed, [check for check in network.checks if not check.passed]
    moves = [row for row in network.commands if row.command == "move_on_track"]
    assert len(moves) == 24 and all(row.result == "DONE" for row in moves)
    assert network.end_time < 6.0  # two rounds, well within max_duration
    by_name = {row.track: row for row in network.planar_tracks}
    assert by_name["b"].collision_ranges == pytest.approx((401.054451, 401.054451), abs=1e-6)
    assert by_name["s"].collision_ranges == pytest.approx((387.378019, 387.378019), abs=1e-6)
    assert by_name["a"].collision_ranges == by_name["c"].collision_ranges == (0.0, 0.0)
    assert [len(by_name[name].movers) for name in "abcs"] == [0, 4, 6, 2]


def test_the_siding_mover_stops_at_the_start_of_its_collision_range(
        network: ScenarioResult) -> None:
    """§6.2.2: m07 holds the merging switch; m12 on the siding stops where its collision
    range begins, then merges one gap or more behind m07."""
    trace = network.trace
    s, velocity = np.asarray(trace["m12.s"]), np.asarray(trace["m12.velocity"])
    on_siding = np.asarray(trace["m12.track"]) == 4.0
    start = by_track(network, "s").length - by_track(network, "s").collision_ranges[1]
    waiting = on_siding & (velocity == 0.0) & (s > 900.0)
    assert waiting.any() and s[waiting].max() <= start + 1e-6


def by_track(result: ScenarioResult, name: str):  # noqa: ANN201 - a PlanarTrackRow
    return next(row for row in result.planar_tracks if row.track == name)


def test_a_group_refuses_a_move_on_a_track_whose_surface_another_mover_stands_on() -> None:
    """§6.5 as a scenario: the track is in the group (by default); mover two stands on its
    surface, so mover one's MoveOnTrack is refused naming mover two, until two has moved."""
    result = run_scenario(parse_scenario("""\
name: "6.5"
planar:
  movers:
    - {name: one, x: 0, y: 0}
    - {name: two, x: 240, y: 0}
  groups: [{name: g}]
  tracks: [{name: t, geometry: [{line: [[0, 0], [400, 0]]}]}]
timeline:
  - {id: on, at: 0, mover: one, command: join_track, track: t}
  - {id: first, when: on.done, mover: one, command: move_on_track, position: 150}
  - {id: away, when: on.done, mover: two, command: move_to_position, x: 240, y: 320}
  - {id: second, when: away.done, mover: one, command: move_on_track, position: 150}
checks:
  - {signal: one.x, expect: 150}
"""))
    commands = rows(result)
    assert (commands["first"].error, commands["first"].message) == (
        "PLANAR_COLLISION", "rejected (33158) by mover 16#05110020")
    assert commands["second"].result == "DONE" and result.passed
    assert result.planar_tracks[0].group == "g"


def test_a_queued_mover_does_not_keep_the_run_going() -> None:
    """docs/scenarios.md#tracks: m1 waits one gap behind m2 for good; its row stays busy and
    the run ends once everything stands."""
    text = (ROOT / "docs" / "scenarios.md").read_text()
    block = re.search(r"### Tracks\n\n```yaml\n(.*?)```", text, re.S)
    assert block is not None
    result = run_scenario(parse_scenario("name: docs\n" + block.group(1)))
    assert result.passed, result.checks
    assert result.end_time < 5.0


def test_track_oids_follow_the_environment_and_the_groups() -> None:
    result = run_scenario(parse_scenario("""\
name: oids
planar:
  environment: {columns: 2, rows: 1}
  movers: [{name: m, x: 120, y: 120}]
  groups: [{name: g}, {name: h, movers: [], tracks: [], environment: false}]
  tracks:
    - {name: a, geometry: [{line: [[120, 120], [360, 120]]}]}
    - {name: b, starts_from: a, geometry: [{line: [[360, 120], [400, 120]]}]}
"""))
    assert [(row.oid, row.group) for row in result.planar_tracks] == [
        (0x05120040, "g"), (0x05120050, "g")]
