"""Stations on a CA rail (issue 23, D-257): movers visit stations in route order, stay their
process time, queue under collision avoidance, and the line's metrics match hand-computed
values."""

from __future__ import annotations

import math

import pytest

from openmotion import Runtime
from openmotion.axis.parameters import AxisParameters
from openmotion.core.errors import ConfigError
from openmotion.kernel.model import machine
from openmotion.rail.stations import FlowState, Route, Station, StationLine
from openmotion.transport import CaGroup, IdentInGroup
from openmotion.transport.stations import add_stations

DYNAMICS = dict(max_velocity=4000.0, acceleration=10000.0, deceleration=10000.0,
                max_acceleration=10000.0, max_deceleration=10000.0, jerk=100000.0,
                max_jerk=100000.0)
VELOCITY = 1000.0


def ring(positions: list[float], length: float = 3000.0) -> tuple[Runtime, CaGroup]:
    rt = Runtime(0.001)
    group = CaGroup(rt, "ring", rail_length=length, rail_is_ring=True, default_gap=100.0)
    for number, position in enumerate(positions, start=1):
        axis = rt.add_axis(f"m{number}", parameters=AxisParameters(**DYNAMICS),
                           position=position)
        axis.power()
        group.add_axis(axis, IdentInGroup(number))
    group.enable()
    rt.run(0.01)
    return rt, group


def travel_time(distance: float) -> float:
    """A plain single-axis move of ``distance`` with the movers' dynamics: the reference the
    line's hops are computed from, without any CA group."""
    rt = Runtime(0.001)
    axis = rt.add_axis("x", parameters=AxisParameters(**DYNAMICS))
    axis.power()
    start = rt.now
    rt.run_until(axis.move_relative(distance=distance, velocity=VELOCITY))
    return rt.now - start


def test_one_mover_and_two_stations_give_the_hand_computed_throughput():
    """A at 1000 mm (0.5 s), B at 2500 mm (0.25 s) on a 3 m ring, one mover starting at A. A
    lap is two hops of 1500 mm and both process times; each hop adds at most two cycles of
    reaction (Done seen, next move sent, as a PLC program). No mover waits."""
    rt, group = ring([1000.0])
    line = add_stations(rt, group, [Station("A", 1000.0, 0.5), Station("B", 2500.0, 0.25)],
                        Route(("A", "B")), VELOCITY)
    hop = travel_time(1500.0)
    lap = 2 * hop + 0.75
    rt.run(20.0)
    a, b = line.station_rows()
    elapsed = line.station("A").elapsed
    assert elapsed == pytest.approx(20.0, abs=1e-9)
    slack = 2 * 0.002  # two hops of at most two cycles each
    laps_low, laps_high = math.floor(elapsed / (lap + slack)), math.floor(elapsed / lap) + 1
    assert laps_low <= b.processed <= laps_high
    assert b.parts_per_minute == pytest.approx(60.0 * b.processed / elapsed)
    # utilisation: each finished visit of A is 0.5 s of its slot time (+ the visit under way)
    assert a.utilisation == pytest.approx(0.5 * a.processed / elapsed, abs=0.5 / elapsed)
    assert b.utilisation == pytest.approx(0.25 * b.processed / elapsed, abs=0.25 / elapsed)
    assert (a.mean_wait, b.mean_wait, a.max_queue, b.max_queue) == (0.0, 0.0, 0, 0)
    [mover] = line.mover_rows()
    assert mover.visits == a.processed + b.processed + (line.state_of("m1") is
                                                         FlowState.PROCESSING)
    assert mover.wait_time == 0.0


def test_a_mover_sent_to_a_busy_station_queues_at_the_gap_and_never_overtakes():
    rt, group = ring([500.0, 300.0])
    line = add_stations(rt, group, [Station("S", 1000.0, 2.0), Station("T", 2500.0, 0.0)],
                        Route(("S", "T")), VELOCITY)
    smallest, queued_at = math.inf, []
    for _ in range(6000):
        rt.step()
        smallest = min(smallest, float(min(group.gaps())))
        if line.station("S").queue_length:
            queued_at.append(rt.axes["m2"].set_position)
        assert [mover.axis.name for mover in group.movers] in (["m1", "m2"], ["m2", "m1"])
    assert smallest >= 100.0 - 1e-9  # the gap of the CA group, never less
    assert queued_at and max(queued_at) == pytest.approx(900.0, abs=1e-6)  # 100 mm behind S
    rows = {row.mover: row for row in line.mover_rows()}
    assert rows["m1"].wait_time == 0.0
    assert rows["m2"].wait_time > 1.5  # most of m1's 2 s at S
    assert line.station("S").max_queue == 1


def test_a_station_with_two_slots_fills_from_the_front_and_moves_movers_up():
    rt, group = ring([700.0, 550.0, 400.0])
    line = add_stations(rt, group, [Station("S", 1500.0, 1.0, capacity=2, pitch=200.0),
                                    Station("T", 2800.0, 0.0, capacity=3, pitch=200.0)],
                        Route(("S", "T"), laps=1), VELOCITY)
    processed_at: dict[str, set[float]] = {"m1": set(), "m2": set(), "m3": set()}
    both = False
    for _ in range(8000):
        rt.step()
        station = line.station("S")
        both = both or station.occupied == 2
        for mover in station.slots:
            if mover is not None:
                processed_at[mover].add(round(rt.axes[mover].set_position, 6))
    assert both  # two movers processed at once
    assert processed_at["m1"] == {1500.0} and processed_at["m2"] == {1300.0}
    assert processed_at["m3"] == {1500.0}  # moved up to the front slot once it was free
    # a mover whose laps are done stays in its slot at the last station and holds it
    assert [row.state for row in line.mover_rows()] == ["FINISHED"] * 3
    assert sorted(round(rt.axes[m].set_position, 6) for m in ("m1", "m2", "m3")) == [
        2400.0, 2600.0, 2800.0]
    assert line.station("T").occupied == 3 and line.station("T").processed == 3
    assert not line.busy


def test_stations_are_objects_of_the_machine_model():
    rt, group = ring([0.0])
    add_stations(rt, group, [Station("load", 100.0, 0.1)], Route(("load",)), VELOCITY)
    model = machine(rt)
    load = model.find("load", "station")
    assert [signal.name for signal in load.signals] == [
        "queue_length", "occupied", "processed", "utilisation"]
    rt.run(1.0)
    assert model.signal("load.processed").read() >= 1.0


@pytest.mark.parametrize(("make", "message"), [
    (lambda: Station("", 1.0, 1.0), "a station needs a name"),
    (lambda: Station("s", math.nan, 1.0), "position must be finite"),
    (lambda: Station("s", 1.0, -1.0), "process_time must be >= 0"),
    (lambda: Station("s", 1.0, 1.0, capacity=0), "capacity must be a whole number >= 1"),
    (lambda: Station("s", 1.0, 1.0, capacity=2), "2 slots need a pitch > 0"),
    (lambda: Route(()), "at least one station"),
    (lambda: Route(("a",), laps=0), "laps must be a whole number >= 1"),
    (lambda: StationLine([Station("a", 1.0, 1.0), Station("a", 2.0, 1.0)], [], 0.001),
     "station 'a' is defined twice"),
])
def test_bad_stations_and_routes_are_config_errors(make, message):
    with pytest.raises(ConfigError, match=message):
        make()


def test_a_line_that_cannot_be_built_leaves_the_runtime_as_it_was():
    rt, group = ring([0.0, 500.0])
    empty = CaGroup(rt, "empty")
    systems = rt.systems
    with pytest.raises(ConfigError, match="no station 'B'; one of A"):
        add_stations(rt, group, [Station("A", 100.0, 0.1)], Route(("A", "B")), VELOCITY)
    with pytest.raises(ConfigError, match="off the ring"):
        add_stations(rt, group, [Station("A", 3000.0, 0.1)], Route(("A",)), VELOCITY)
    with pytest.raises(ConfigError, match="'m9' is not a mover of the group"):
        add_stations(rt, group, [Station("A", 100.0, 0.1)], {"m9": Route(("A",))}, VELOCITY)
    with pytest.raises(ConfigError, match="the group has no movers"):
        add_stations(rt, empty, [Station("A", 100.0, 0.1)], Route(("A",)), VELOCITY)
    assert rt.systems == systems
    line = add_stations(rt, group, [Station("A", 100.0, 0.1)], Route(("A",)), VELOCITY)
    rt.run(0.5)
    assert line.station("A").processed >= 1  # the group works on
