"""Stations and routes in scenario files (scenario/stations.py, D-257): what loads, what is
refused with a message naming the field, and what a run reports."""

from __future__ import annotations

import pytest

from openmotion.scenario import ScenarioError, parse_scenario, run_scenario

BASE = """
name: stations
cycle_time: 0.002
duration: 4.0
axes:
  - {name: m1, position: 0.0, parameters: {max_velocity: 4000.0, acceleration: 10000.0,
     deceleration: 10000.0, max_acceleration: 10000.0, max_deceleration: 10000.0,
     jerk: 100000.0, max_jerk: 100000.0}}
  - {name: m2, position: 2500.0}
ca_groups:
  - name: ring
    axes: [m1, m2]
    parameters: {rail_length: 3000.0, rail_is_ring: true, default_gap: 100.0}
    stations:
      - {name: load, position: 500.0, process_time: 0.5}
      - {name: drill, position: 2000.0, process_time: 0.25}
    routes:
      - {stations: [load, drill], velocity: 1000.0, movers: [m1]}
record:
  signals: [load.processed, drill.queue_length, m1.set_position]
checks:
  - {signal: load.processed, min: 1.0}
  - {signal: drill.utilisation, min: 0.01}
"""


def test_a_route_runs_and_the_summary_shows_the_stations():
    result = run_scenario(parse_scenario(BASE))
    assert result.passed, result.checks
    assert [row.name for _, row in result.stations] == ["load", "drill"]
    summary = result.summary()
    assert "Stations" in summary and "per minute" in summary
    assert result.trace["load.processed"][-1] >= 1.0
    data = result.to_dict()
    assert [row["name"] for row in data["stations"]] == ["load", "drill"]


def test_a_route_without_movers_takes_every_mover_no_route_names():
    result = run_scenario(parse_scenario(BASE.replace(", movers: [m1]", "")))
    assert result.passed
    assert result.trace["m1.set_position"][-1] != 0.0


@pytest.mark.parametrize(("old", "new", "message"), [
    ("{name: drill, position: 2000.0", "{name: load, position: 2000.0",
     "'load' is used 2 times"),
    ("{name: drill, position: 2000.0", "{name: m2, position: 2000.0",
     "names an axis or a CA group"),
    ("stations: [load, drill]", "stations: [load, paint]", "no station 'paint'; one of load"),
    ("movers: [m1]", "movers: [m7]", "'m7' is not a mover of the group"),
    ("position: 2000.0, process_time", "position: 3000.0, process_time", "off the ring"),
    ("process_time: 0.25}", "process_time: 0.25, capacity: 2}", "2 slots need a pitch"),
    ("process_time: 0.5}", "process_time: -0.5}", "greater than or equal to 0"),
    ("velocity: 1000.0, movers", "velocity: 1000.0, laps: 0, movers", "greater than or equal"),
    ("signals: [load.processed", "signals: [load.speed", "a station's signal is one of"),
])
def test_bad_stations_and_routes_name_the_field(old, new, message):
    assert old in BASE
    with pytest.raises(ScenarioError, match=message):
        parse_scenario(BASE.replace(old, new))
    assert parse_scenario(BASE).ca_groups[0].stations  # the loader goes on working


def test_a_sweep_collects_a_stations_figures_by_name():
    """The sweep's ``station`` metric (sweep/metrics.py) reads the summary's row."""
    from openmotion.sweep import StationMetric

    result = run_scenario(parse_scenario(BASE))
    metric = StationMetric(station="load", stats=["processed", "parts_per_minute", "max_queue"])
    assert metric.columns() == {"load.processed": "Int64", "load.parts_per_minute": "float64",
                                "load.max_queue": "Int64"}
    row = next(row for _, row in result.stations if row.name == "load")
    assert metric.collect(result, 0.0) == {"load.processed": row.processed,
                                           "load.parts_per_minute": row.parts_per_minute,
                                           "load.max_queue": row.max_queue}
    with pytest.raises(ValueError, match="no such station \\(stations: load, drill\\)"):
        StationMetric(station="paint").collect(result, 0.0)
