"""Running tracks and geo-compensation from scenario files: moves in track coordinates,
activate_track and register_compensation with their error ids, the reference systems of CA
moves, and the signals track_position and tcp_position."""

from __future__ import annotations

import math

import numpy as np
import pytest

from openmotion.core.errors import ConfigError
from openmotion.runtime.runtime import Runtime
from openmotion.scenario import (
    CommandRow,
    ScenarioResult,
    examples_dir,
    parse_scenario,
    run_scenario,
)
from openmotion.scenario.groups import CaGroups
from openmotion.scenario.tracks import PartSpec
from openmotion.trace.record import read_signal

PARAMETERS = """\
    parameters: &p {max_velocity: 4000, acceleration: 10000, deceleration: 10000,
                    max_acceleration: 10000, max_deceleration: 10000, jerk: 100000,
                    max_jerk: 100000}
"""
R = 500.0 / math.pi  #: the starter kit's curve radius [mm]

TRACKS = """\
name: tracks
axes:
  - name: a
    position: 1200
""" + PARAMETERS + """\
  - {name: b, position: 500, parameters: *p}
  - {name: x}
ca_groups:
  - name: xts
    axes: [a, b]
    parts:
      - {id: 11, start: 0, end: 1000}
      - {id: 12, start: 1000, end: 2000}
      - {id: 13, start: 2000, end: 0}
    tracks:
      - {id: 21, parts: [12, 13, 11]}     # closed, track position 0 at x = 1000
      - {id: 22, parts: [11]}             # open, [0, 1000)
timeline:
  - {id: off_22, at: 0, axis: a, command: activate_track, track: 22}
  - {id: unknown, at: 0, axis: a, command: activate_track, track: 99}
  - {id: on_21, at: 0, axis: a, command: activate_track, track: 21}
  - {id: a_700, at: 0, axis: a, command: move_absolute_ca, position: 700, velocity: 1000}
  - {id: seen, when: a.track_position >= 400, axis: x, command: power}
  - {id: again, when: a_700.done, axis: a, command: move_absolute_ca, position: 1800,
     velocity: 1000, direction: positive}
  - {id: absolute, when: again.done, axis: a, command: activate_track, track: 0}
  - {id: on_22, at: 0, axis: b, command: activate_track, track: 22}
  - {id: b_900, at: 0, axis: b, command: move_absolute_ca, position: 900, velocity: 1000}
  - {id: off_track, when: b_900.done, axis: b, command: move_absolute_ca, position: 1200,
     velocity: 1000}
  - {id: modulo, when: b_900.done, axis: b, command: move_absolute_ca, position: 10,
     velocity: 1000, direction: positive}
  - {id: leave, when: modulo.error, axis: b, command: move_relative_ca, distance: 200,
     velocity: 1000}
  - {id: back, at: 1.5, axis: b, command: activate_track, track: 0}
record: {signals: [a.set_position, a.track_position, b.set_position, b.track_position],
         every: 10}
checks:
  - {command: off_22, result: error, error_id: NOT_ON_TRACK}
  - {command: unknown, result: error, error_id: UNKNOWN_TRACK}
  - {command: off_track, result: error, error_id: TARGET_OFF_TRACK}
  - {command: modulo, result: error, error_id: INVALID_DIRECTION}
  - {signal: a.track_position, expect: 700, when: a_700.done}
  - {signal: a.set_position, expect: 1700, when: a_700.done}
  - {signal: b.track_position, expect: 900, when: b_900.done}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def tracks() -> ScenarioResult:
    return run_scenario(parse_scenario(TRACKS))


def test_a_track_is_the_frame_of_later_moves(tracks: ScenarioResult) -> None:
    assert tracks.passed, tracks.checks
    by_id = rows(tracks)
    assert [by_id[name].result for name in ("on_21", "a_700", "seen", "again", "absolute")] \
        == ["DONE"] * 5
    trace = tracks.trace
    # track 21 starts at x = 1000: track position = (x - 1000) mod 3000, from 200 at t = 0
    assert trace["a.track_position"][0] == 200.0
    on_track = trace.time < by_id["absolute"].issued_at
    np.testing.assert_allclose(trace["a.track_position"][on_track],
                               np.mod(trace["a.set_position"][on_track] - 1000.0, 3000.0),
                               atol=1e-9)
    # track position 400 = x 1400, reached at t = 0.3: the condition holds in the next cycle
    assert by_id["seen"].issued_at == pytest.approx(0.301, abs=1e-9)
    # positive modulo direction on the closed track: track position 1800 = x 2800
    movers = {row.mover: row for row in tracks.ca_movers}
    assert movers["a"].position == pytest.approx(2800.0, abs=1e-9)
    # back in the absolute frame the signal is the absolute set position
    assert trace["a.track_position"][-1] == trace["a.set_position"][-1] == \
        pytest.approx(2800.0, abs=1e-9)


def test_track_errors_are_the_blocks_error_ids(tracks: ScenarioResult) -> None:
    by_id = rows(tracks)
    assert (by_id["off_22"].error, by_id["unknown"].error) == ("NOT_ON_TRACK", "UNKNOWN_TRACK")
    assert by_id["off_22"].ended_at == by_id["off_22"].issued_at == 0.0  # at once
    assert "TrackId 99" in by_id["unknown"].message
    assert by_id["off_track"].error == "TARGET_OFF_TRACK"  # the open track is [0, 1000]
    assert by_id["modulo"].error == "INVALID_DIRECTION"  # open tracks: NonModulo only
    assert by_id["leave"].result == "DONE"  # conditions see .error as on any entry


def test_track_position_is_nan_once_off_an_open_track(tracks: ScenarioResult) -> None:
    trace, by_id = tracks.trace, rows(tracks)
    b, position = trace["b.track_position"], trace["b.set_position"]
    off = (position >= 1000.0) & (trace.time < by_id["back"].issued_at)
    assert off.sum() == 70 and np.all(np.isnan(b[off]))  # x >= 1000 is on no part of 22
    on = trace.time < by_id["back"].issued_at
    np.testing.assert_array_equal(b[on & ~off], position[on & ~off])  # track 22 starts at 0
    assert b[-1] == position[-1] == pytest.approx(1100.0, abs=1e-9)  # track 0 again


GEO = """\
name: geo
axes:
  - name: c
    position: 900
""" + PARAMETERS + """\
  - {name: d, position: 2000, parameters: *p}
ca_groups:
  - name: xts
    axes: [c, d]
    geometry: {}
    templates: [{id: 31, y_shift: 100}, {id: 32, y_shift: 50}]
timeline:
  - {id: not_registered, at: 0, axis: d, command: move_relative_ca, distance: 10,
     velocity: 100, position_reference_system: 31}
  - {id: unknown, at: 0, axis: d, command: register_compensation, template: 99}
  - {id: no_dynamics, at: 0, axis: d, command: move_absolute_ca, position: 2100,
     velocity: 100, dynamics_reference_system: 32}
  - {id: reg_c, at: 0, axis: c, command: register_compensation, template: 31}
  - {id: reg_d, at: 0, axis: d, command: register_compensation, template: 31}
  - {id: tcp_1000, at: 0, axis: c, command: move_relative_ca, distance: 1000, velocity: 2000,
     position_reference_system: 31, dynamics_reference_system: 31}
  - {id: straight, at: 0, axis: d, command: move_absolute_ca, position: 2400, velocity: 500,
     dynamics_reference_system: 31}
  - {id: replace, when: tcp_1000.done, axis: c, command: register_compensation, template: 32}
  - {id: halt_other, at: 0.01, axis: d, command: halt_ca, dynamics_reference_system: 32}
record: {signals: [c.set_position, c.set_velocity, c.tcp_position, d.set_velocity,
                   d.tcp_position]}
"""


@pytest.fixture(scope="module")
def geo() -> ScenarioResult:
    return run_scenario(parse_scenario(GEO))


def test_compensation_errors_are_the_blocks_error_ids(geo: ScenarioResult) -> None:
    by_id = rows(geo)
    assert by_id["not_registered"].error == by_id["no_dynamics"].error == \
        by_id["halt_other"].error == "COMPENSATION_NOT_REGISTERED"
    assert by_id["unknown"].error == "UNKNOWN_TEMPLATE"
    assert [by_id[name].result for name in ("reg_c", "reg_d", "tcp_1000", "straight",
                                            "replace")] == ["DONE"] * 5


def test_a_relative_distance_on_the_tcp_path(geo: ScenarioResult) -> None:
    trace, by_id = geo.trace, rows(geo)
    done = np.flatnonzero(np.isclose(trace.time, by_id["tcp_1000"].ended_at))[0]
    # from x = 900 (straight, TCP = motor) through the right curve [1000, 1500): the curve
    # adds pi * y to the TCP path, so the motor travels 1000 - 100 pi
    assert trace["c.set_position"][done] == pytest.approx(1900.0 - 100.0 * math.pi, abs=1e-9)
    assert trace["c.tcp_position"][0] == pytest.approx(900.0, abs=1e-9)
    assert trace["c.tcp_position"][done] == pytest.approx(1900.0, abs=1e-9)


def test_the_tcp_stays_within_the_commanded_velocity_in_a_curve(geo: ScenarioResult) -> None:
    trace = geo.trace
    factor = R / (R + 100.0)
    assert trace.peak("c.set_velocity") == pytest.approx(2000.0 * factor, rel=1e-12)
    tcp_velocity = np.diff(trace["c.tcp_position"]) / np.diff(trace.time)
    assert tcp_velocity.max() <= 2000.0 * (1.0 + 1e-9)
    assert tcp_velocity.max() == pytest.approx(2000.0, rel=1e-6)  # in the curve: exactly
    # a move on a straight keeps its full limits, even with a dynamics reference system
    assert trace.peak("d.set_velocity") == pytest.approx(500.0, rel=1e-12)
    assert "0.61413 of the limits" in rows(geo)["tcp_1000"].message


def test_tcp_position_follows_the_registered_template(geo: ScenarioResult) -> None:
    trace, by_id = geo.trace, rows(geo)
    after = trace.time > by_id["replace"].issued_at
    x = trace["c.set_position"][after][-1]  # 1900 - 100 pi, after the right curve
    assert trace["c.tcp_position"][after][-1] == pytest.approx(x + 50.0 * math.pi, abs=1e-9)
    # d registered at t = 0 (the first row is sampled before the entries' cycle)
    assert trace["d.tcp_position"][0] == pytest.approx(2000.0 + 100.0 * math.pi, abs=1e-9)


def test_tcp_position_is_nan_without_a_registered_template() -> None:
    line = "  - {id: reg_d, at: 0, axis: d, command: register_compensation, template: 31}\n"
    assert line in GEO
    result = run_scenario(parse_scenario(GEO.replace(line, "")))
    assert np.all(np.isnan(result.trace["d.tcp_position"]))
    assert not np.isnan(result.trace["c.tcp_position"]).any()
    assert rows(result)["straight"].error == "COMPENSATION_NOT_REGISTERED"


def test_mover_signals_are_nan_for_an_axis_in_no_group() -> None:
    rt = Runtime()
    axis = rt.add_axis("x")
    assert math.isnan(read_signal(axis, "track_position"))
    assert math.isnan(read_signal(axis, "tcp_position"))


def test_the_example_keeps_the_tcp_within_the_commanded_velocity() -> None:
    result = run_scenario(examples_dir() / "ca_tracks.yaml")
    assert result.passed, result.checks
    trace = result.trace
    tcp_velocity = np.diff(trace["m2.tcp_position"]) / np.diff(trace.time)
    assert tcp_velocity.min() >= 0.0 and tcp_velocity.max() <= 2000.0 * (1.0 + 1e-9)
    assert trace["m2.tcp_position"][-1] == pytest.approx(2000.0, abs=1e-9)
    assert trace["m1.track_position"][0] == 100.0  # x 1600 on track 21 (from x 1500)


def test_the_run_refuses_a_group_whose_tracks_do_not_build() -> None:
    """The loader validates the same way; a spec built around it still cannot slip by."""
    (spec,) = parse_scenario("name: t\naxes: [{name: a}]\nca_groups: [{name: g, axes: [a]}]"
                             "\n").ca_groups
    bad = spec.model_copy(update={"parts": [PartSpec(id=1, start=0.0, end=100.0),
                                            PartSpec(id=2, start=50.0, end=150.0)]})
    rt = Runtime()
    rt.add_axis("a")
    with pytest.raises(ConfigError, match=r"ca_groups g: parts\.1: part 2 overlaps part 1"):
        CaGroups(rt, [bad])
