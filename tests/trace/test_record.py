"""TraceRecorder: any object's signals through the source registry, decimation, events."""

from __future__ import annotations

import math

import numpy as np
import pytest

import openmotion as om
from openmotion.planar import MC_PlanarEnvironment, MC_PlanarGroup, MC_PlanarMover
from openmotion.trace import Event, SignalSource, Trace, TraceRecorder, register_source
from openmotion.trace.signals import AXIS_SIGNALS, read_planar_signal, read_signal
from openmotion.transport import CaGroup
from openmotion.transport.group import UDINT_TO_IDENTINGROUP

CYCLE = 0.001


def moving_runtime() -> tuple[om.Runtime, om.Axis, om.Command]:
    rt = om.Runtime(CYCLE)
    x = rt.add_axis("x", max_velocity=500.0, acceleration=2000.0, jerk=20000.0)
    rt.add_axis("y")
    x.power()
    return rt, x, x.move_absolute(50.0, velocity=200.0)


def record(rt: om.Runtime, signals: list[str], cycles: int, every: int = 1,
           **options: object) -> TraceRecorder:
    recorder = TraceRecorder(rt, signals, every, **options)  # type: ignore[arg-type]
    recorder.sample(rt)
    rt.add_observer(recorder)
    for _ in range(cycles):
        rt.step()
    return recorder


def test_every_axis_signal_reads_what_read_signal_reads_bit_for_bit() -> None:
    """The kinematic signals come from one numpy gather; they must equal the per-axis reads."""
    rt, x, _ = moving_runtime()
    signals = [f"{axis}.{prop}" for axis in ("y", "x") for prop in AXIS_SIGNALS]
    seen: list[list[float]] = []
    rt.add_observer(lambda runtime: seen.append(
        [runtime.now] + [read_signal(runtime.axes[name.split(".")[0]], name.split(".")[1])
                         for name in signals]))
    trace = record(rt, signals, 120).trace
    assert trace.columns == ("time", *signals)
    expected = np.array(seen)
    assert trace.data[1:].tobytes() == expected.tobytes()  # NaN gaps of non-CA axes included
    assert math.isnan(trace["x.gap"][-1]) and trace["x.set_velocity"][-1] > 0.0


def test_decimation_keeps_every_nth_cycle_of_the_full_trace() -> None:
    full = record(moving_runtime()[0], ["x.set_position", "x.state"], 200).trace
    decimated = record(moving_runtime()[0], ["x.set_position", "x.state"], 200, every=7).trace
    assert len(decimated) == 200 // 7 + 1  # t = 0 and cycles 7, 14, ...
    assert decimated.data.tobytes() == full.data[::7].tobytes()
    assert np.allclose(np.diff(decimated.time), 7 * CYCLE)


@pytest.mark.parametrize("every", [0, -1, 1.5, True])
def test_decimation_must_be_a_whole_number_of_cycles(every: object) -> None:
    with pytest.raises(om.ConfigError, match="every: must be an integer >= 1"):
        TraceRecorder(om.Runtime(), [], every)  # type: ignore[arg-type]


def test_the_buffer_grows_past_its_capacity() -> None:
    trace = record(moving_runtime()[0], ["x.set_position"], 50, capacity=4).trace
    assert len(trace) == 51 and trace.time[-1] == pytest.approx(50 * CYCLE)


def test_planar_movers_groups_and_ca_movers_are_recorded_through_their_sources() -> None:
    rt = om.Runtime(CYCLE)
    a, b = rt.add_axis("a"), rt.add_axis("b", position=300.0)
    group = CaGroup(rt, "xts", rail_length=3000.0)
    for ident, axis in enumerate((a, b), start=1):
        axis.power()
        assert group.add_axis(axis, UDINT_TO_IDENTINGROUP(ident)).done
    group.enable()
    mover, planar = MC_PlanarMover(rt, name="m"), MC_PlanarGroup(rt, "field")
    mover.enable()
    signals = ["m.x", "m.y", "m.c", "m.velocity", "m.state", "field.state", "a.gap", "b.gap"]
    recorder = record(rt, signals, 5, objects=[mover, planar])
    trace = recorder.trace
    assert trace["m.x"][-1] == read_planar_signal(mover, "x")
    assert trace["m.state"][-1] == float(mover.state) == float(om_planar_enabled())
    assert trace["field.state"][-1] == float(planar.state)
    assert trace["a.gap"][-1] == read_signal(a, "gap") == 300.0  # b is a's predecessor
    assert trace["b.gap"][-1] == read_signal(b, "gap") == 2700.0  # the ring's wrap pair
    assert trace.layout["objects"] == {"a": "axis", "b": "axis", "m": "planar_mover",
                                       "field": "planar_group"}
    assert trace.layout["ca_groups"]["xts"] == {"rail_length": 3000.0, "rail_is_ring": True,
                                                "default_gap": 100.0, "movers": ["b", "a"]}
    assert trace.layout["planar"]["movers"] == {"m": {"width": 155.0, "height": 155.0}}


def om_planar_enabled() -> int:
    from openmotion.planar import PlanarState

    return PlanarState.ENABLED


def test_the_environment_describes_its_stators() -> None:
    rt = om.Runtime(CYCLE)
    environment = MC_PlanarEnvironment(rt)
    for corner in ((0.0, 0.0), (240.0, 0.0)):
        environment.add_stator(*corner)
    environment.create_boundary()
    trace = record(rt, [], 2, objects=[environment]).trace
    assert trace.layout["planar"] == {"stator_size": 240.0,
                                      "stators": [[0.0, 0.0], [240.0, 0.0]]}


@pytest.mark.parametrize(("signal", "message"), [
    ("q.set_position", "'q.set_position' names no object of the runtime"),
    ("x.speed", "'x.speed': a signal of axis 'x' is one of set_position, "),
    ("m.set_position", "a signal of planar_mover 'm' is one of x, y, "),
    ("x", "'x' is not '<object>.<signal>'"),
])
def test_unknown_objects_and_signals_are_config_errors(signal: str, message: str) -> None:
    rt = om.Runtime()
    rt.add_axis("x")
    with pytest.raises(om.ConfigError, match=message):
        TraceRecorder(rt, [signal], objects=[MC_PlanarMover(rt, name="m")])


def test_a_registered_source_records_a_new_kind_of_object() -> None:
    class Conveyor:
        name = "belt"
        speed = 12.5

    class ConveyorSignals(SignalSource):
        kind = "conveyor"
        signals = ("speed",)

        def read(self, obj: Conveyor, prop: str) -> float:
            return float(getattr(obj, prop))

    register_source(Conveyor, ConveyorSignals())
    trace = record(om.Runtime(), ["belt.speed"], 3, objects=[Conveyor()]).trace
    assert trace["belt.speed"].tolist() == [12.5] * 4
    assert trace.layout["objects"] == {"belt": "conveyor"}


def test_followed_commands_give_issued_and_end_events_in_time_order() -> None:
    rt, x, move = moving_runtime()
    recorder = TraceRecorder(rt, ["x.set_position"], every=10)
    recorder.follow(move, "x", "out")
    rt.add_observer(recorder)
    rt.run_until(lambda: move.done, timeout=5.0)
    late = x.move_absolute(0.0, velocity=-1.0)  # refused at once: INVALID_VELOCITY
    recorder.follow(late, "x", "bad")
    recorder.add_event(Event(0.0, "x", "note", "DONE", detail="by hand"))
    events = recorder.trace.events
    assert [(e.label, e.result) for e in events] == [
        ("out", "ISSUED"), ("", "DONE"), ("out", "DONE"), ("bad", "ISSUED"), ("bad", "ERROR")]
    done = events[2]
    assert done.time == move.ended_at and done.object == "x" and done.command == move.kind
    assert events[-1].detail.startswith(f"{late.error_id.name}: ")
    assert [e.time for e in events] == sorted(e.time for e in events)


def test_trace_equals_compares_bits() -> None:
    data = np.array([[0.0, math.nan], [0.001, 1.0]])
    same = Trace(("time", "x.gap"), data.copy())
    assert Trace(("time", "x.gap"), data).equals(same)  # NaN is NaN
    signed = data.copy()
    signed[1, 1] = 1.0
    signed[0, 0] = -0.0
    assert not Trace(("time", "x.gap"), signed).equals(same)


# -- bounded mode: a ring of the last ``keep`` rows (issue 19 point 10, D-188) ---------------


@pytest.mark.parametrize("keep", [1, 3, 4, 50, 199, 201, 202, 5000])
def test_keep_holds_exactly_the_last_rows_in_time_order_across_wrap_around(keep: int) -> None:
    """D-188: a ring keeps the last ``keep`` rows, oldest first, bit for bit what an unbounded
    recorder holds at its end, read at any time (here before the first wrap, after one and
    after several; 201 rows recorded: keep 201 is exactly full, 202 never full)."""
    signals = ["x.set_position", "x.set_velocity", "x.state"]
    full = record(moving_runtime()[0], signals, 200).trace
    rt = moving_runtime()[0]
    ring = TraceRecorder(rt, signals, capacity=2, keep=keep)
    ring.sample(rt)
    rt.add_observer(ring)
    for cycles in (3, 60, 137):
        for _ in range(cycles):
            rt.step()
        rows = 1 + rt.cycle
        trace = ring.trace
        assert len(trace) == min(keep, rows)
        assert trace.data.tobytes() == full.data[max(0, rows - keep):rows].tobytes()
    assert ring.allocated <= keep


def test_keep_forgets_the_events_before_its_oldest_row() -> None:
    """D-188: the trace of a ring holds the events from its first row on, in time order."""
    rt, x, move = moving_runtime()
    recorder = TraceRecorder(rt, ["x.set_position"], keep=100)
    recorder.follow(move, "x", "out")
    rt.add_observer(recorder)
    rt.run_until(lambda: move.done, timeout=5.0)
    rt.run(0.2)
    back = x.move_absolute(0.0, velocity=200.0)
    recorder.follow(back, "x", "back")
    rt.run(0.05)  # the window of 100 cycles starts after the first move ended
    trace = recorder.trace
    assert move.ended_at < trace.time[0] < back.issued_at and len(trace) == 100
    assert [(e.label, e.result) for e in trace.events] == [("back", "ISSUED")]
    rt.run_until(lambda: back.done, timeout=5.0)
    assert [(e.label, e.result) for e in recorder.trace.events][-1] == ("back", "DONE")


def test_memory_of_a_bounded_recorder_stops_growing_at_keep_rows() -> None:
    """Issue 19 point 10: memory flat over a long run. Measured in allocated rows (the
    buffer's samples), not in time: 20 000 samples into keep=500 allocate 500 rows; the
    unbounded recorder allocates at least every row; the events stay within the window."""
    rt, x, _ = moving_runtime()
    bounded = TraceRecorder(rt, ["x.set_position", "y.set_position"], capacity=16, keep=500)
    unbounded = TraceRecorder(rt, ["x.set_position", "y.set_position"], capacity=16)
    for cycle in range(20_000):
        if cycle % 100 == 0:
            bounded.add_event(Event(rt.now, "x", "note", "DONE"))
        bounded.sample(rt)
        unbounded.sample(rt)
        rt.step()
        assert bounded.allocated <= 500
    assert bounded.allocated == 500 and unbounded.allocated >= 20_000
    assert len(bounded._events) <= 2 * 500 // 100 + 1  # the window and the one before it
    assert len(bounded.trace.events) == 5


@pytest.mark.parametrize(("options", "message"), [
    ({"keep": 0}, "keep: must be an integer >= 1 (rows), got 0"),
    ({"keep": -5}, "keep: must be an integer >= 1 (rows), got -5"),
    ({"keep": 2.5}, "keep: must be an integer >= 1 (rows), got 2.5"),
    ({"keep": True}, "keep: must be an integer >= 1 (rows), got True"),
    ({"stream": "s", "chunk": 0}, "chunk: must be an integer >= 1 (rows), got 0"),
    ({"keep": 10, "stream": "s"}, "keep and stream: give one of them"),
    ({"chunk": 10}, "chunk: only with stream"),
])
def test_bad_keep_stream_and_chunk_are_config_errors(tmp_path, options: dict[str, object],
                                                     message: str) -> None:
    """D-188: a bound that keeps nothing, both modes at once, or a chunk size without
    streaming: a ConfigError before anything is recorded or written; a valid recorder on
    the same runtime works next."""
    rt, _, _ = moving_runtime()
    options = {name: tmp_path / value if name == "stream" else value
               for name, value in options.items()}
    with pytest.raises(om.ConfigError) as caught:
        TraceRecorder(rt, ["x.set_position"], **options)  # type: ignore[arg-type]
    assert str(caught.value).startswith(message)
    assert not (tmp_path / "s").exists()
    assert len(record(rt, ["x.set_position"], 5, keep=3).trace) == 3
