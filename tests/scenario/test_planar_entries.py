"""TF5430 methods that scenario files reach since issue 20: the mover's AdoptTrackOrientation
(§6.2.7, §7.2.1.2.4) and the part's AllowEnable, ForceDisable and Reset (§7.2.2.9.3-5,
§6.6)."""

from __future__ import annotations

from pathlib import Path

import pytest

from openmotion.core.special_values import MC_DEFAULT
from openmotion.planar import DynamicConstraint_PathXY, ModuloDirection
from openmotion.planar.options import ST_AdoptTrackOrientationOptions
from openmotion.scenario import (
    CommandRow,
    ScenarioError,
    ScenarioResult,
    parse_scenario,
    run_scenario,
)
from openmotion.scenario.planar import PLANAR_COMMANDS
from openmotion.scenario.planar_parts import PartAllowEnable, PartForceDisable, PartReset

ADOPT = """\
name: adopt
planar:
  movers:
    - {name: m, x: 120, y: 120}
  tracks: [{name: t, geometry: [{line: [[120, 120], [600, 120]]}]}]
timeline:
  - {id: on, at: 0, mover: m, command: join_track, track: t}
  - {id: turn, when: on.done, mover: m, command: move_c, position: 90}
  - {id: ride, when: turn.done, mover: m, command: move_on_track, position: 300}
  - {id: adopt, when: ride.done, mover: m, command: adopt_track_orientation%s}
checks:
  - {signal: m.c, expect: 0}
  - {signal: m.x, expect: 420}
"""

PARTS = """\
name: part commands
planar:
  environment:
    coordinate_systems: [16#01010060]
    parts:
      - oid: 16#01010020
        stators: [[0, 0], [240, 0]]
        positions: [{coordinate_system: 16#01010060}]
  movers:
    - {name: m, x: 120, y: 120}
timeline:
  - {id: wrong, at: 0, part: 16#01010020, command: part_reset}
  - {id: off, at: 0.1, part: 16#01010020, command: part_force_disable}
  - {id: cleared, when: m.state == error, mover: m, command: mover_reset}
  - {id: early, at: 0.3, mover: m, command: mover_enable}
  - {id: again, at: 0.5, part: 16#01010020, command: part_allow_enable}
  - {id: cleared2, at: 0.5, mover: m, command: mover_reset}
  - {id: on, at: 0.7, mover: m, command: mover_enable}
  - {id: move, when: on.done, mover: m, command: move_to_position, x: 360, y: 120}
checks:
  - {signal: m.x, expect: 360}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


def test_the_new_planar_commands_are_timeline_commands() -> None:
    """The four methods the scenario files did not reach (issue 20)."""
    assert {"adopt_track_orientation", "part_allow_enable", "part_force_disable",
            "part_reset"} <= set(PLANAR_COMMANDS)


def test_6_2_7_adopt_track_orientation_turns_c_back_to_the_track() -> None:
    """§6.2.7: a mover joined with its orientation coupled, turned away by MoveC (C
    independent), moved along the track, then AdoptTrackOrientation: C is the track's
    heading again (0) and the mover stays where it stands."""
    result = run_scenario(parse_scenario(ADOPT % ""))
    assert rows(result)["adopt"].result == "DONE" and result.passed, result.checks


def test_adopt_track_orientation_takes_its_options_and_dynamics() -> None:
    """§7.2.1.2.4: the options default to ShortestWay (not MoveC's NonModulo); direction and
    additional turns and the dynamics reach the method."""
    plain = parse_scenario(ADOPT % "").timeline[3]
    assert plain.arguments() == (None, ST_AdoptTrackOrientationOptions(
        0, ModuloDirection.SHORTEST_WAY))
    entry = parse_scenario(ADOPT % ", direction: negative, additional_turns: 1, "
                                   "velocity: 90").timeline[3]
    assert entry.arguments() == (
        DynamicConstraint_PathXY(90.0, MC_DEFAULT, MC_DEFAULT, MC_DEFAULT),
        ST_AdoptTrackOrientationOptions(1, ModuloDirection.NEGATIVE))
    took = {}
    for direction in ("shortest_way", "positive"):
        result = run_scenario(parse_scenario(ADOPT % f", direction: {direction}, velocity: 90"))
        adopt = rows(result)["adopt"]
        assert adopt.result == "DONE", direction
        assert result.planar_movers[0].c % 360.0 == pytest.approx(0.0, abs=1e-9)  # 0 or 360
        took[direction] = adopt.ended_at - adopt.issued_at
    # from 90°: 90° back the shortest way, 270° on the positive way, at 90°/s
    assert took["positive"] > took["shortest_way"] + 1.5


def test_adopt_track_orientation_off_a_track_fails_and_the_mover_goes_on() -> None:
    """A mover that is not on a track refuses AdoptTrackOrientation; its next command runs."""
    result = run_scenario(parse_scenario("""\
name: adopt off track
planar:
  movers: [{name: m, x: 120, y: 120}]
timeline:
  - {id: adopt, at: 0, mover: m, command: adopt_track_orientation}
  - {id: move, at: 0.1, mover: m, command: move_to_position, x: 360, y: 120}
checks:
  - {signal: m.x, expect: 360}
"""))
    commands = rows(result)
    assert commands["adopt"].result == "ERROR" and commands["adopt"].error
    assert commands["move"].result == "DONE" and result.passed


def test_7_2_2_9_force_disable_allow_enable_and_reset_of_a_part() -> None:
    """§7.2.2.9.3-5, §6.6: Reset outside Error is refused; ForceDisable switches the part
    off (the mover on it drops to Error) and keeps it off: an Enable of the mover fails with
    PLANAR_PART_NOT_ENABLED until AllowEnable; then the mover enables and moves."""
    result = run_scenario(parse_scenario(PARTS))
    commands = rows(result)
    assert (commands["wrong"].result, commands["wrong"].error) == ("ERROR",
                                                                   "PLANAR_WRONG_STATE")
    assert commands["off"].result == "DONE" and commands["cleared"].result == "DONE"
    assert (commands["early"].result, commands["early"].error) == ("ERROR",
                                                                   "PLANAR_PART_NOT_ENABLED")
    assert "force-disabled" in commands["early"].message
    assert [commands[k].result for k in ("again", "on", "move")] == ["DONE"] * 3
    assert result.passed, result.checks
    assert commands["off"].axis == "16#01010020"


@pytest.mark.parametrize("command,model", [("part_allow_enable", PartAllowEnable),
                                           ("part_force_disable", PartForceDisable),
                                           ("part_reset", PartReset)])
def test_the_part_entries_name_a_known_part(command: str, model: type) -> None:
    scenario = parse_scenario(PARTS)
    assert any(type(entry) is model for entry in scenario.timeline)
    bad = PARTS.replace(f"part: 16#01010020, command: {command}",
                        f"part: 16#01010099, command: {command}")
    with pytest.raises(ScenarioError, match="16#01010099 is no part of"):
        parse_scenario(bad)


#: §6.2.11: part 1 (8 stators), part 2 (2 stators) beside it, lower (1) or upper (2); track
#: three makes a U-turn on part 2, tracks two and one on part 1 start from and end at it with
#: the Advanced links (tests/planar/test_tracks.py builds the same in Python)
ADVANCED = Path(__file__).with_name("planar_6_2_11.yaml")


def _advanced(position: int) -> ScenarioResult:
    return run_scenario(parse_scenario(ADVANCED.read_text().replace(
        "\n        position_index: 1\n", f"\n        position_index: {position}\n")))


def test_6_2_11_tracks_on_parts_with_advanced_links_from_a_scenario() -> None:
    """§6.2.3, §6.2.11, §6.2.13: with part 2 lower the links run two -> three -> one, so the
    mover joined on two reaches one over three; with part 2 upper they run one -> three ->
    two and the same move is refused (no way from two to one)."""
    lower = _advanced(1)
    commands = rows(lower)
    assert commands["go"].result == "DONE", commands["go"].message
    assert (lower.planar_movers[0].track, lower.planar_movers[0].s) == ("one", 100.0)
    two, three = lower.planar_tracks[1], lower.planar_tracks[0]
    assert two.length == pytest.approx(three.length, abs=1e-9)  # as §6.2.11 says
    upper = _advanced(2)
    go = rows(upper)["go"]
    assert (go.result, go.error) == ("ERROR", "PLANAR_INVALID_INPUT")
    assert "one cannot be reached from two" in go.message
    assert upper.planar_movers[0].track == "two"


def test_the_advanced_link_options_are_passed_and_need_their_link() -> None:
    scenario = parse_scenario(ADVANCED.read_text())
    three, two, _ = scenario.planar.tracks
    assert three.part == 0x01010030 and two.part == 0x01010020
    assert two.starts_from_options.values() == (1, 2, False)
    assert two.ends_at_options.values() == (1, 1, False)
    bad = ADVANCED.read_text().replace("      starts_from: three\n", "", 1)
    with pytest.raises(ScenarioError, match="starts_from_options: options of a link that is "
                                            "not there"):
        parse_scenario(bad)
    with pytest.raises(ScenarioError, match="16#01010099 is no part of"):
        parse_scenario(ADVANCED.read_text().replace("part: 16#01010030\n",
                                                    "part: 16#01010099\n"))
