"""Gear-in on planar tracks in scenario files (TF5430 §6.2.8, §6.2.9, §6.8): the entries
gear_in_pos_on_track and gear_in_pos_on_track_with_master_mover, their trail, options and
``<id>.in_sync``, the file:line errors of bad input, and the station example."""

from __future__ import annotations

import re
from pathlib import Path
from unittest import mock

import numpy as np
import pytest

from openmotion.axis.axis import Axis
from openmotion.core.special_values import MC_DEFAULT
from openmotion.planar import (
    DynamicConstraint_PathXY,
    MC_PlanarFeedbackGearInPosOnTrack,
    MC_PlanarMover,
    MC_PlanarTrack,
    MC_PlanarTrackTrail,
    ModuloDirection,
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    SyncDirections,
)
from openmotion.scenario import (
    CommandRow,
    ScenarioError,
    ScenarioResult,
    examples_dir,
    parse_scenario,
    run_scenario,
)
from openmotion.scenario.planar_gearing import (
    AxisRef,
    GearInPosOnTrack,
    GearInPosOnTrackWithMasterMover,
    MoverRef,
    TrailRef,
)
from openmotion.scenario.planar_tracks import TrackRef

ROOT = Path(__file__).resolve().parents[2]

#: a straight line of two tracks, a -> b, a mover on each end of a and a belt axis
LINE = """\
name: gear
axes: [{name: belt}]
planar:
  movers:
    - {name: m, x: 500, y: 0}
    - {name: k, x: 900, y: 0}
  tracks:
    - {name: a, geometry: [{line: [[0, 0], [1000, 0]]}]}
    - {name: b, starts_from: a, geometry: [{line: [[1000, 0], [2000, 0]]}]}
timeline:
  - {at: 0, axis: belt, command: power}
  - {id: j, at: 0, mover: m, command: join_track, track: a}
  - {id: jk, at: 0, mover: k, command: join_track, track: a}
"""

#: every field of both entries
VALID = LINE + """\
  - {id: g1, at: 1, mover: m, command: gear_in_pos_on_track, master: belt, trail: [a, b],
     master_sync_position: 100, slave_sync_position: 400, slave_sync_track: b, velocity: 500,
     gap: 250, in_sync_tolerance_distance: 0.5, direction_slave_sync_position: positive,
     modulo_tolerance_slave_sync_position: 2, allowed_slave_sync_directions: both}
  - {id: g2, at: 2, mover: m, command: gear_in_pos_on_track, master: belt,
     master_sync_position: 0, slave_sync_position: 10, slave_sync_track: a}
  - {id: g3, at: 3, mover: m, command: gear_in_pos_on_track_with_master_mover, master_mover: k,
     trail: [a, b], master_sync_position: 950, master_sync_track: a, slave_sync_position: 700,
     slave_sync_track: a, direction_master_sync_position: shortest_way,
     modulo_tolerance_master_sync_position: 3, follow_mover: true, gap: 220,
     allowed_slave_sync_directions: negative, jerk: 9000}
  - {when: g1.in_sync, mover: k, command: mover_halt}
checks:
  - {signal: m.s, min: 0, when: g3.in_sync}
"""


def test_the_entries_build_the_method_arguments() -> None:
    entries = parse_scenario(VALID).timeline[3:]
    assert [type(entry) for entry in entries[:3]] == [
        GearInPosOnTrack, GearInPosOnTrack, GearInPosOnTrackWithMasterMover]
    assert entries[0].arguments() == (
        AxisRef("belt"), TrailRef(("a", "b")), 100.0, 400.0, TrackRef("b"),
        DynamicConstraint_PathXY(500.0, MC_DEFAULT, MC_DEFAULT, MC_DEFAULT),
        ST_GearInPosOnTrackOptions(250.0, 0.5, ModuloDirection.POSITIVE, 2.0,
                                   SyncDirections.BOTH))
    assert entries[1].arguments() == (AxisRef("belt"), None, 0.0, 10.0, TrackRef("a"), None,
                                      ST_GearInPosOnTrackOptions())
    assert entries[2].arguments() == (
        MoverRef("k"), TrailRef(("a", "b")), 950.0, TrackRef("a"), 700.0, TrackRef("a"),
        DynamicConstraint_PathXY(MC_DEFAULT, MC_DEFAULT, MC_DEFAULT, 9000.0),
        ST_GearInPosOnTrackWithMasterMoverOptions(
            220.0, 0.0, ModuloDirection.NON_MODULO, 0.0, ModuloDirection.SHORTEST_WAY, 3.0,
            SyncDirections.NEGATIVE, True))


def test_in_sync_is_a_condition_and_a_check_trigger() -> None:
    scenario = parse_scenario(VALID)
    assert (scenario.timeline[6].when.subject, scenario.timeline[6].when.attribute) == (
        "g1", "in_sync")
    assert scenario.checks[0].when.attribute == "in_sync"


# -- running ------------------------------------------------------------------------------------


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


def run(timeline: str, extra: str = "", text: str = LINE) -> ScenarioResult:
    return run_scenario(parse_scenario(text + timeline + extra))


def test_a_slave_follows_its_axis_one_to_one_onto_the_next_track_of_its_trail() -> None:
    """§6.2.8, §6.8: once in sync, s = slave sync + (belt - master sync); the trail takes the
    slave from a onto b, where the same coupling holds (its s counted on b)."""
    result = run("""\
  - {id: v, at: 0.1, axis: belt, command: move_velocity, velocity: 300}
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track, master: belt, trail: [a, b],
     master_sync_position: 200, slave_sync_position: 400, slave_sync_track: a}
  - {id: away, at: 0.1, mover: k, command: move_on_track, track: b, position: 900,
     velocity: 1000}
  - {id: seen, when: g.in_sync, mover: k, command: mover_halt}
""", "duration: 5\nrecord: {signals: [m.s, m.track, belt.set_position]}\n")
    commands = rows(result)
    assert commands["g"].result == "BUSY" and commands["g"].error == ""  # no Done (§6.2.8)
    assert commands["seen"].issued_at is not None  # the in_sync condition held
    since = float(re.fullmatch(r"in sync at (\S+) s", commands["g"].value_detail).group(1))
    trace = result.trace
    time, s = np.asarray(trace["time"]), np.asarray(trace["m.s"])
    track, belt = np.asarray(trace["m.track"]), np.asarray(trace["belt.set_position"])
    synced = time >= since
    offset = np.where(track == 2.0, 1000.0, 0.0)  # b starts where a ends, 1000 mm on
    assert np.abs(s + offset - (400.0 + belt - 200.0))[synced] == pytest.approx(0.0, abs=1e-9)
    assert {1.0, 2.0} <= set(track[synced])
    assert result.planar_movers[0].track == "b"


def test_a_slave_follows_a_master_mover_one_to_one() -> None:
    """§6.2.9: the master mover's arc length drives the slave: s_m = 300 + (s_k - 900)."""
    result = run("""\
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track_with_master_mover,
     master_mover: k, master_sync_position: 900, master_sync_track: a,
     slave_sync_position: 500, slave_sync_track: a}
  - {id: go, at: 0.05, mover: k, command: move_on_track, position: 980, velocity: 100}
  - {id: off, at: 1.5, mover: m, command: move_on_track, position: 100}
""", "record: {signals: [m.s, k.s]}\n")
    commands = rows(result)
    assert (commands["g"].result, commands["off"].result) == ("ABORTED", "DONE")
    assert commands["g"].value_detail.startswith("in sync at")
    trace = result.trace
    time = np.asarray(trace["time"])
    coupled = (time > 0.2) & (time < 1.5)
    s_m, s_k = np.asarray(trace["m.s"]), np.asarray(trace["k.s"])
    assert np.abs(s_m - (500.0 + s_k - 900.0))[coupled] == pytest.approx(0.0, abs=1e-9)
    assert s_k[-1] == pytest.approx(980.0) and s_m[-1] == pytest.approx(100.0)


def test_the_run_passes_the_objects_the_trail_and_the_options() -> None:
    """The entry's names become the Axis, the tracks, an MC_PlanarTrackTrail of them, and the
    options and feedback reach the mover's method as given."""
    original = MC_PlanarMover.gear_in_pos_on_track
    with mock.patch.object(MC_PlanarMover, "gear_in_pos_on_track", autospec=True,
                           side_effect=original) as spy:
        run_scenario(parse_scenario(VALID.replace("at: 2,", "at: 1.5,") + "duration: 2.5\n"))
    first, second = spy.call_args_list
    mover, belt, trail, msp, ssp, track, constraint, options = first.args
    assert isinstance(belt, Axis) and belt.name == "belt" and mover.name == "m"
    assert isinstance(trail, MC_PlanarTrackTrail) and [t.name for t in trail.tracks] == ["a", "b"]
    assert isinstance(track, MC_PlanarTrack) and track.name == "b"
    assert (msp, ssp, constraint.velocity) == (100.0, 400.0, 500.0)
    assert options == ST_GearInPosOnTrackOptions(250.0, 0.5, ModuloDirection.POSITIVE, 2.0,
                                                 SyncDirections.BOTH)
    assert isinstance(first.kwargs["feedback"], MC_PlanarFeedbackGearInPosOnTrack)
    assert second.args[2] is None  # no trail


def test_allowed_sync_directions_reach_the_engine() -> None:
    """The belt stands and the coupled position (300) lies behind the slave (500): with the
    default (positive) it waits where it is; with both it goes back and is in sync (D-146)."""
    gear = """\
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track, master: belt,
     master_sync_position: 0, slave_sync_position: 300, slave_sync_track: a%s}
"""
    waits = run(gear % "", "duration: 1\n")
    back = run(gear % ", allowed_slave_sync_directions: both", "duration: 1\n")
    assert waits.planar_movers[0].s == pytest.approx(500.0)
    assert rows(waits)["g"].value_detail == ""  # never in sync
    assert back.planar_movers[0].s == pytest.approx(300.0)
    assert rows(back)["g"].value_detail.startswith("in sync at")


def test_the_gap_reaches_the_engine() -> None:
    """The coupled position (900) is where k stands: the slave stops a gap behind it."""
    gear = """\
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track, master: belt,
     master_sync_position: 0, slave_sync_position: 900, slave_sync_track: a%s}
"""
    for gap, extra in ((200.0, ""), (300.0, ", gap: 300")):
        result = run(gear % extra, "duration: 1.5\n")
        s = result.planar_movers[0].s
        assert 900.0 - gap - 0.1 < s <= 900.0 - gap, (gap, s)


def test_a_value_the_engine_refuses_fails_the_row() -> None:
    result = run("""\
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track, master: belt,
     master_sync_position: 0, slave_sync_position: 600, slave_sync_track: a, gap: -1}
  - {id: h, when: g.error, mover: m, command: gear_in_pos_on_track, master: belt,
     master_sync_position: 0, slave_sync_position: 600, slave_sync_track: a,
     modulo_tolerance_slave_sync_position: 1}
""")
    commands = rows(result)
    assert (commands["g"].result, commands["g"].error) == ("ERROR", "PLANAR_INVALID_INPUT")
    assert "gap: must be a finite number >= 0" in commands["g"].message
    assert (commands["h"].result, commands["h"].error) == ("ERROR", "INVALID_MODULO_OPTIONS")


def test_a_trail_whose_links_do_not_hold_at_run_time_fails_the_row() -> None:
    """The load checks a trail by the file's links; where they do not hold when the entry
    fires (a link across parts), AddTrack refuses and the row says why (§6.8)."""
    scenario = parse_scenario(LINE + """\
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track, master: belt,
     trail: [a, b], master_sync_position: 0, slave_sync_position: 600, slave_sync_track: a}
""")
    entry = scenario.timeline[3].model_copy(update={"trail": ["b", "a"]})
    result = run_scenario(scenario.model_copy(update={"timeline": [*scenario.timeline[:3],
                                                                   entry]}))
    row = rows(result)["g"]
    assert (row.result, row.error) == ("ERROR", "PLANAR_INVALID_INPUT")
    assert row.message == "rejected (29705): trail: a does not start where b ends (§6.8)"


def test_a_standing_slave_does_not_keep_an_open_ended_run_going() -> None:
    """As a queued move_on_track: the slave waits for a master that stands."""
    result = run("""\
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track, master: belt,
     master_sync_position: 100, slave_sync_position: 300, slave_sync_track: a}
""")
    assert rows(result)["g"].result == "BUSY" and result.end_time < 1.0


def test_a_slave_waiting_for_its_product_on_a_running_belt_keeps_the_run_going() -> None:
    """The belt is at speed (it no longer keeps the run going) and the slave stands until its
    coupled position (100 + belt) comes by: the run goes on until the slave is in sync."""
    result = run("""\
  - {at: 0, axis: belt, command: move_velocity, velocity: 300}
  - {id: g, when: jk.done, mover: m, command: gear_in_pos_on_track, master: belt,
     master_sync_position: 500, slave_sync_position: 600, slave_sync_track: a}
  - {id: off, when: g.in_sync, mover: m, command: move_on_track, position: 650}
""")
    commands = rows(result)
    assert (commands["g"].result, commands["off"].result) == ("ABORTED", "DONE")
    assert commands["off"].issued_at > 1.2  # belt 400 at about 1.35 s


# -- bad input ----------------------------------------------------------------------------------


def problems(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        parse_scenario(LINE + text, "bad.yaml")
    return [str(problem) for problem in info.value.problems]


GEAR = ("  - {id: g, at: 1, mover: m, command: gear_in_pos_on_track, master: belt, "
        "master_sync_position: 0, slave_sync_position: 10, slave_sync_track: a%s}\n")
MASTER = ("  - {at: 1, mover: m, command: gear_in_pos_on_track_with_master_mover, master_mover: k, "
          "master_sync_position: 0, master_sync_track: a, slave_sync_position: 10, "
          "slave_sync_track: a%s}\n")


@pytest.mark.parametrize(("text", "expected"), [
    (GEAR.replace("belt", "conveyor") % "",
     "bad.yaml:14: timeline[3].master: unknown axis 'conveyor' (axes: belt)"),
    (GEAR.replace("track: a", "track: q") % "",
     "bad.yaml:14: timeline[3].slave_sync_track: unknown planar track 'q' (planar.tracks: a, b)"),
    (GEAR % ", trail: [a, q]",
     "bad.yaml:14: timeline[3].trail[1]: unknown planar track 'q' (planar.tracks: a, b)"),
    (GEAR % ", trail: [b, a]",
     "bad.yaml:14: timeline[3].trail: 'a' does not start where 'b' ends: a trail follows the "
     "track links in order (§6.8)"),
    (GEAR % ", trail: [a, a]",
     "bad.yaml:14: timeline[3].trail: 'a' is in the trail twice (§6.8)"),
    (GEAR % ", trail: []",
     "bad.yaml:14: timeline[3].trail: must hold at least 1 item(s)"),
    (GEAR.replace("track: a", "track: b") % ", trail: [a]",
     "bad.yaml:14: timeline[3].slave_sync_track: 'b' is not in the trail ['a']: the slave's "
     "path is its track and the trail after it (§6.8)"),
    (GEAR % ", gpa: 3",
     "bad.yaml:14: timeline[3].gpa: unknown field 'gpa' (did you mean 'gap'?)"),
    (GEAR % ", gap: fast", "bad.yaml:14: timeline[3].gap"),
    (GEAR % ", direction_slave_sync_position: up",
     "bad.yaml:14: timeline[3].direction_slave_sync_position: must be one of non_modulo, "
     "positive, shortest_way, negative, got 'up'"),
    (GEAR % ", allowed_slave_sync_directions: forward",
     "bad.yaml:14: timeline[3].allowed_slave_sync_directions: must be one of positive, "
     "negative, both, got 'forward'"),
    (GEAR.replace("slave_sync_position: 10, ", "") % "",
     "bad.yaml:14: timeline[3].slave_sync_position: required field is missing"),
    (MASTER.replace("master_mover: k", "master_mover: q") % "",
     "bad.yaml:14: timeline[3].master_mover: unknown planar mover 'q' (planar.movers: k, m)"),
    (MASTER.replace("master_mover: k", "master_mover: m") % "",
     "bad.yaml:14: timeline[3].master_mover: 'm' cannot be its own master (§6.2.9)"),
    (MASTER.replace("master_sync_track: a", "master_sync_track: z") % "",
     "bad.yaml:14: timeline[3].master_sync_track: unknown planar track 'z'"),
    (MASTER % ", follow_mover: yes", "bad.yaml:14: timeline[3].follow_mover"),
    (MASTER.replace("slave_sync_track: a", "slave_sync_track: b") % ", trail: [a]",
     "bad.yaml:14: timeline[3].slave_sync_track: 'b' is not in the trail"),
    (MASTER % ", direction_master_sync_position: around",
     "bad.yaml:14: timeline[3].direction_master_sync_position: must be one of non_modulo"),
    # in_sync is a flag of the gear-ins on tracks only
    ("  - {when: j.in_sync, mover: k, command: mover_halt}\n",
     "bad.yaml:14: timeline[3].when: 'j.in_sync': in_sync is a flag of gear_in_pos_on_track "
     "and gear_in_pos_on_track_with_master_mover entries only"),
    (GEAR % "" + "checks:\n  - {signal: m.s, min: 0, when: j.in_sync}\n",
     "bad.yaml:16: checks[0].when: 'j.in_sync': in_sync is a flag of gear_in_pos_on_track"),
])
def test_bad_gear_input_names_file_line_and_field(text: str, expected: str) -> None:
    found = problems(text)
    assert any(problem.startswith(expected) for problem in found), found


def test_a_follower_s_sync_track_need_not_be_on_its_trail() -> None:
    """With follow_mover the trail only leads to the master's sync track (§6.2.12)."""
    scenario = parse_scenario(LINE + MASTER.replace("slave_sync_track: a", "slave_sync_track: b")
                              % ", trail: [a], follow_mover: true")
    assert scenario.timeline[3].follow_mover


def test_a_trail_may_run_round_a_loop_of_linked_tracks() -> None:
    """The links, not the file order, decide: c ends at a, so [b, c, a] is a trail."""
    text = LINE.replace("  tracks:\n", """\
  tracks:
    - name: c
      starts_from: b
      geometry:
        - circle: {start: [2000, 0], end: [2000, 500], center: [2000, 250], clockwise: false}
        - circle: {start: [0, 500], end: [0, 0], center: [0, 250], clockwise: false}
      ends_at: a
""")
    scenario = parse_scenario(text + GEAR.replace("track: a", "track: c")
                              % ", trail: [b, c, a]")
    assert scenario.timeline[3].trail == ["b", "c", "a"]


# -- the example and the docs -------------------------------------------------------------------


@pytest.fixture(scope="module")
def station() -> ScenarioResult:
    return run_scenario(examples_dir() / "planar_track_station.yaml")


def test_the_station_slaves_ride_with_the_belt_and_leave_it(station: ScenarioResult) -> None:
    """Each geared mover is exactly on its product from the cycle it is in sync until its
    MoveOnTrack aborts the gear-in (§6.2.8); m06 is carried from a onto the siding."""
    assert station.passed, [check for check in station.checks if not check.passed]
    commands = rows(station)
    trace = station.trace
    time, belt = np.asarray(trace["time"]), np.asarray(trace["belt.set_position"])
    for mover, master_sync, slave_sync in (("m12", 300.0, 1100.0), ("m11", 300.0, 850.0),
                                           ("m06", 1000.0, 850.0), ("m05", 1250.0, 850.0)):
        gear = commands[f"g{mover[1:]}"]
        since = float(gear.value_detail.split()[3])
        coupled = (time >= since) & (time < gear.ended_at)
        track, s = np.asarray(trace[f"{mover}.track"]), np.asarray(trace[f"{mover}.s"])
        on_s = coupled & (track == 4.0)
        assert on_s.sum() > 100, mover
        assert np.abs(s - (slave_sync + belt - master_sync))[on_s] == pytest.approx(0.0,
                                                                                 abs=1e-9)
        assert gear.result == "ABORTED"
    gear = commands["g06"]
    since = float(gear.value_detail.split()[3])
    m06 = np.asarray(trace["m06.track"])[(time >= since) & (time < gear.ended_at)]
    assert m06[0] == 1.0 and set(m06) == {1.0, 4.0}  # from a onto s, in sync on a already


def test_the_station_movers_keep_their_gap(station: ScenarioResult) -> None:
    """No two movers on one track come closer than the gap of 200 mm (arc length)."""
    trace = station.trace
    names = [f"m{k:02d}" for k in range(1, 13)]
    track = np.array([trace[f"{name}.track"] for name in names])
    s = np.array([trace[f"{name}.s"] for name in names])
    closest = np.inf
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            same = (track[i] == track[j]) & (track[i] > 0.0)
            if same.any():
                closest = min(closest, float(np.abs(s[i] - s[j])[same].min()))
    assert closest >= 200.0 - 1e-9
    assert station.end_time < 8.0
    assert all(row.result == "DONE" for row in station.commands
               if row.command == "move_on_track")


def test_the_docs_gear_in_example_runs() -> None:
    """docs/scenarios.md#gear-in-on-tracks: the block runs and its checks pass."""
    text = (ROOT / "docs" / "scenarios.md").read_text()
    block = re.search(r"### Gear-in on tracks\n\n```yaml\n(.*?)```", text, re.S)
    assert block is not None
    result = run_scenario(parse_scenario("name: docs\n" + block.group(1)))
    assert result.passed, result.checks
