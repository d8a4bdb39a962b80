"""The TF5430 methods that scenario files reach since issue 20 ("Scenario files reach every
block"): a track's Enable, Disable, Reset, Clear and group membership (§7.2.2.10), the
environment's Clear and group membership (§7.2.2.1), and the Get queries of movers, tracks,
parts and the environment (§7.2.2.1.7, §7.2.2.8.24-25, §7.2.2.9.6, §7.2.2.10.13-16), whose
outputs a check reads with ``output`` (D-218)."""

from __future__ import annotations

import pytest

from openmotion.planar import PlanarObjectType
from openmotion.scenario import CommandRow, ScenarioResult, parse_scenario, run_scenario

OBJECTS = f"""\
name: objects
planar:
  environment: {{columns: 4, rows: 2}}
  movers: [{{name: m, x: 120, y: 120}}]
  groups: [{{name: g}}]
  tracks:
    - {{name: t, geometry: [{{line: [[120, 360], [840, 360]]}}]}}
timeline:
  - {{id: len, at: 0, track: t, command: track_get_length}}
  - {{id: at, at: 0, track: t, command: track_get_position_at, arc_length: 100}}
  - {{id: near, at: 0, track: t, command: track_get_arc_length_closest_to, x: 500, y: 300}}
  - {{id: info, at: 0, track: t, command: track_get_planar_object_info}}
  - {{id: minfo, at: 0, mover: m, command: mover_get_planar_object_info}}
  - {{id: einfo, at: 0, command: environment_get_planar_object_info}}
  - {{id: out, at: 0, track: t, command: track_remove_from_group}}
  - {{id: out_again, when: out.done, track: t, command: track_remove_from_group}}
  - {{id: back, when: out.done, track: t, command: track_add_to_group, group: g}}
  - {{id: off, when: back.done, track: t, command: track_disable}}
  - {{id: on, when: off.done, track: t, command: track_enable}}
  - {{id: reset, when: on.done, track: t, command: track_reset}}
  - {{id: env_out, at: 0.02, command: environment_remove_from_group}}
  - {{id: env_out_again, when: env_out.done, command: environment_remove_from_group}}
  - {{id: env_in, when: env_out.done, command: environment_add_to_group, group: g}}
  - {{id: disable, at: 0.03, track: t, command: track_disable}}
  - {{id: clear, when: disable.done, track: t, command: track_clear}}
  - {{id: len0, when: clear.done, track: t, command: track_get_length}}
  - {{id: wipe, at: 0.05, command: environment_clear}}
checks:
  - {{command: len, result: done, output: length, value: 720}}
  - {{command: at, result: done, output: x, value: 220}}
  - {{command: at, result: done, output: y, value: 360}}
  - {{command: near, result: done, output: arc_length, value: 380}}
  - {{command: info, result: done, output: object_type, value: {int(PlanarObjectType.TRACK)}}}
  - {{command: info, result: done, output: id, value: 85065776}}
  - {{command: minfo, result: done, output: object_type, value: {int(PlanarObjectType.MOVER)}}}
  - {{command: minfo, result: done, output: id, value: 85000208}}
  - {{command: einfo, result: done, output: object_type,
     value: {int(PlanarObjectType.ENVIRONMENT)}}}
  - {{command: out, result: done}}
  - {{command: out_again, result: error, error_id: PLANAR_NOT_IN_GROUP}}
  - {{command: back, result: done}}
  - {{command: off, result: done}}
  - {{command: on, result: done}}
  - {{command: reset, result: done}}
  - {{command: env_out, result: done}}
  - {{command: env_out_again, result: error, error_id: PLANAR_NOT_IN_GROUP}}
  - {{command: env_in, result: done}}
  - {{command: clear, result: done}}
  - {{command: len0, result: done, output: length, value: 0}}
  - {{command: wipe, result: done}}
"""

#: §6.1.4: two one-stator parts side by side in one coordinate system
PARTS = """\
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
timeline:
  - {id: go, at: 0, mover: m, command: move_to_position, x: 100, y: 100,
     reference_id: 16#01010030}
  - {id: here, when: go.done, mover: m, command: get_position_on_current_part}
  - {id: part, when: go.done, part: 16#01010030, command: part_get_position}
checks:
  - {command: here, result: done, output: x, value: 100, tolerance: 1e-9}
  - {command: here, result: done, output: y, value: 100, tolerance: 1e-9}
  - {command: here, result: done, output: reference_id, value: 16842800}
  - {command: part, result: done, output: x, value: 240}
  - {command: part, result: done, output: reference_id, value: 16842848}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


def test_track_and_environment_methods_and_queries_pass_their_checks() -> None:
    """§7.2.2.10: GetLength, GetPositionAt, GetArcLengthClosestTo, GetPlanarObjectInfo,
    AddToGroup/RemoveFromGroup (twice: PLANAR_NOT_IN_GROUP), Disable, Enable, Reset, Clear
    (the length is 0 after it); §7.2.2.1: the environment's membership, Clear and info."""
    result = run_scenario(parse_scenario(OBJECTS))
    assert result.passed, [check for check in result.checks if not check.passed]
    assert rows(result)["at"].value_detail == "x 220, y 360, c 0, reference_id 0"


def test_positions_on_parts_are_read_in_the_part_frame_and_the_coordinate_system() -> None:
    """§7.2.2.8.24: the mover at (340, 100) of the coordinate system is (100, 100) on part
    16#01010030; §7.2.2.9.6: that part lies at x = 240 in coordinate system 16#01010060."""
    result = run_scenario(parse_scenario(PARTS))
    assert result.passed, [check for check in result.checks if not check.passed]


def test_an_environment_entry_without_an_environment_fails_and_the_run_goes_on() -> None:
    """An environment entry needs planar.environment; the row says so, later entries run."""
    result = run_scenario(parse_scenario("""\
name: t
planar: {movers: [{name: m}]}
timeline:
  - {id: info, at: 0, command: environment_get_planar_object_info}
  - {id: wipe, at: 0, command: environment_clear}
  - {id: me, at: 0, mover: m, command: mover_get_planar_object_info}
"""))
    by_id = rows(result)
    for name in ("info", "wipe"):
        assert (by_id[name].result, by_id[name].error) == ("ERROR", "PLANAR_INVALID_INPUT")
        assert by_id[name].message == "there is no planar.environment"
    assert by_id["me"].result == "DONE"


@pytest.mark.parametrize("entry", [
    "{at: 0, track: q, command: track_get_length}",
    "{at: 0, track: t, command: track_add_to_group, group: h}",
])
def test_unknown_tracks_and_groups_are_load_errors(entry: str) -> None:
    with pytest.raises(Exception, match="unknown planar (track 'q'|group 'h')"):
        parse_scenario(OBJECTS.split("timeline:")[0] + "timeline:\n  - " + entry + "\n")
