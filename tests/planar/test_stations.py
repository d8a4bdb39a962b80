"""Stations on a planar track (issue 23, D-257): movers on a closed loop visit stations by
MoveOnTrack, forwards round the loop, queue on the track at its gap, and never fail."""

from __future__ import annotations

import math

import pytest

from openmotion.core.errors import ConfigError
from openmotion.kernel.model import machine
from openmotion.planar.stations import add_planar_stations
from openmotion.rail.stations import Route, Station
from openmotion.scenario import examples_dir, parse_scenario
from openmotion.scenario.live import scenario_machine

LOOP = (examples_dir() / "planar_stations.yaml").read_text(encoding="utf-8")
#: the example without its own line: the tests add one from Python
BARE = LOOP[:LOOP.index("  stations:")] + LOOP[LOOP.index("timeline:"):LOOP.index("record:")] \
    + "checks:\n  - {signal: m1.x, min: -10000.0}\n"


def loop_machine():
    rt = scenario_machine(parse_scenario(BARE)).runtime
    model = machine(rt)
    movers = [obj.target for obj in model if obj.kind == "planar_mover"]
    tracks = {obj.name: obj.target for obj in model if obj.kind == "planar_track"}
    return rt, movers, tracks


def test_movers_circle_forwards_queue_at_the_gap_and_the_slowest_station_sets_the_pace():
    rt, movers, tracks = loop_machine()
    line = add_planar_stations(rt, movers, tracks, [
        Station("A", 1200.0, 1.5, path="loop"),
        Station("B", 3000.0, 0.3, capacity=2, pitch=250.0, path="loop")], Route(("A", "B")))
    length = tracks["loop"].length
    spacing = math.inf
    for _ in range(20000):
        rt.step()
        s = sorted(mover.mc_to_plc.set_on_track.set_pos for mover in movers)
        if rt.now > 1.0:  # after the joins and the first moves off the start positions
            spacing = min(spacing, *(b - a for a, b in zip(s, s[1:], strict=False)),
                          s[0] + length - s[-1])
    assert spacing >= 200.0 - 1e-6  # ST_MoveOnTrackOptions' gap, centre to centre
    a, b = line.station_rows()
    assert a.utilisation > 0.7  # A, 1.5 s a visit, is the bottleneck
    assert 25.0 <= a.parts_per_minute <= 60.0 / 1.5  # at most one part per process time
    assert a.processed - 2 <= b.processed <= a.processed
    assert a.max_queue >= 1 and a.mean_wait > 0.0  # movers queue before A
    assert all(row.state in ("HEADING", "PROCESSING") for row in line.mover_rows())


def test_a_station_on_an_unknown_track_or_an_unknown_mover_is_a_config_error():
    rt, movers, tracks = loop_machine()
    systems = rt.systems
    with pytest.raises(ConfigError, match="no track 'ring'; one of loop"):
        add_planar_stations(rt, movers, tracks, [Station("A", 1.0, 1.0, path="ring")],
                            Route(("A",)))
    with pytest.raises(ConfigError, match="'m9' is not one of the movers"):
        add_planar_stations(rt, movers, tracks, [Station("A", 1.0, 1.0, path="loop")],
                            {"m9": Route(("A",))})
    assert rt.systems == systems


def test_planar_stations_in_a_scenario_name_their_track():
    bad = LOOP.replace("{name: fill, track: loop", "{name: fill, track: ring")
    with pytest.raises(ConfigError, match="no track 'ring'; one of loop"):
        parse_scenario(bad)
    bad = LOOP.replace("- {stations: [fill, cap]}", "- {stations: [fill, cap], movers: [m7]}")
    with pytest.raises(ConfigError, match="'m7' is not a planar mover"):
        parse_scenario(bad)
