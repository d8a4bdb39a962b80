"""Streaming mode of TraceRecorder: NPZ chunks in a directory, read back as the same trace
(issue 19 point 10, D-188)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import openmotion as om
from openmotion.trace import (
    StreamedTrace,
    TraceRecorder,
    read_stream,
    read_trace,
    save_plot,
    write_trace,
)
from openmotion.trace.stream import MANIFEST, chunk_name, default_chunk

CYCLE = 0.001
SIGNALS = ["x.set_position", "x.set_velocity", "x.state", "y.set_position"]


def run(cycles: int = 400, every: int = 1, **options: object) -> TraceRecorder:
    rt = om.Runtime(CYCLE)
    x = rt.add_axis("x", max_velocity=500.0, acceleration=2000.0, jerk=20000.0)
    y = rt.add_axis("y")
    x.power()
    y.power()
    recorder = TraceRecorder(rt, SIGNALS, every, **options)  # type: ignore[arg-type]
    recorder.sample(rt)
    rt.add_observer(recorder)
    plan = {0: lambda: (x.move_absolute(50.0, velocity=200.0), "x", "out"),
            30: lambda: (y.move_absolute(20.0, velocity=100.0), "y", "slow"),
            90: lambda: (y.halt(), "y", "halt"),
            150: lambda: (x.move_absolute(0.0, velocity=-1.0), "x", "bad")}
    for cycle in range(cycles):
        if cycle in plan:
            command, target, label = plan[cycle]()
            recorder.follow(command, target, label)
        rt.step()
    return recorder


@pytest.mark.parametrize(("chunk", "every"), [(1, 1), (7, 1), (64, 3), (100_000, 1)])
def test_streamed_trace_reads_back_bit_for_bit_as_the_unbounded_one(
        tmp_path: Path, chunk: int, every: int) -> None:
    """D-188: chunks of any size (one row, a few, one that never fills) give back the
    columns bit for bit, the same events in the same order, the layout and the title."""
    full = run(every=every, title="t").trace
    recorder = run(every=every, title="t", stream=tmp_path / "s", chunk=chunk)
    assert recorder.allocated == chunk
    streamed = recorder.trace
    assert isinstance(streamed, StreamedTrace) and len(streamed) == len(full)
    assert streamed.equals(full) and streamed.data.tobytes() == full.data.tobytes()
    assert streamed.events == full.events and len(full.events) == 7  # "out" still runs
    assert streamed.layout == full.layout and streamed.title == "t"
    again = read_trace(tmp_path / "s")
    assert again.equals(full) and again.events == full.events


def test_a_stream_read_mid_run_goes_on_and_is_complete_at_the_end(tmp_path: Path) -> None:
    """Reading ``trace`` flushes what is buffered; recording continues after it."""
    rt = om.Runtime(CYCLE)
    rt.add_axis("x").power()
    recorder = TraceRecorder(rt, ["x.set_position"], stream=tmp_path / "s", chunk=10)
    rt.add_observer(recorder)
    rt.run(0.015)
    assert len(recorder.trace) == 15
    rt.run(0.020)
    trace = recorder.trace
    assert len(trace) == 35 and trace.time.tolist() == [(i + 1) * CYCLE for i in range(35)]


def test_the_stream_directory_is_a_trace_after_every_chunk(tmp_path: Path) -> None:
    """The manifest is rewritten with each chunk: without a flush the directory holds every
    full chunk's rows."""
    recorder = run(200, stream=tmp_path / "s", chunk=64)
    on_disk = read_stream(tmp_path / "s")
    assert len(on_disk) == 192 and on_disk.data.tobytes() == \
        run(200).trace.data[:192].tobytes()
    assert len(recorder.trace) == 201


def test_memory_of_a_streaming_recorder_stays_at_one_chunk(tmp_path: Path) -> None:
    """Issue 19 point 10: 20 000 samples allocate one chunk of rows, whatever the length;
    the events went to disk with their chunks."""
    rt = om.Runtime(CYCLE)
    x = rt.add_axis("x")
    x.power()
    recorder = TraceRecorder(rt, ["x.set_position"], stream=tmp_path / "s", chunk=256)
    rt.add_observer(recorder)
    for cycle in range(20_000):
        if cycle % 1000 == 0:
            recorder.follow(x.move_relative(1.0, velocity=100.0), "x")
        rt.step()
        assert recorder.allocated == 256
    assert len(recorder._events) <= 2
    assert len(recorder.trace) == 20_000 and len(recorder.trace.events) == 40


def test_default_chunk_is_about_a_million_values() -> None:
    assert default_chunk(1) == 1 << 20 and default_chunk(301) == (1 << 20) // 301
    assert default_chunk(10**7) == 1


def test_an_unwritable_directory_is_a_config_error_before_the_run(tmp_path: Path) -> None:
    """D-188: a path that cannot become a directory (here: below a file) fails at once,
    naming it; a valid directory on the same runtime works next."""
    (tmp_path / "file").write_text("x")
    rt = om.Runtime(CYCLE)
    rt.add_axis("x")
    with pytest.raises(om.ConfigError, match=r"stream: .*file/s: cannot write the trace "
                                             "there: Not a directory"):
        TraceRecorder(rt, ["x.set_position"], stream=tmp_path / "file" / "s")
    assert len(TraceRecorder(rt, ["x.set_position"], stream=tmp_path / "s").trace) == 0


def test_a_directory_of_other_files_is_refused_and_left_alone(tmp_path: Path) -> None:
    """D-188: streaming never deletes what it did not write."""
    (tmp_path / "notes.txt").write_text("mine")
    rt = om.Runtime(CYCLE)
    rt.add_axis("x")
    with pytest.raises(om.ConfigError, match="holds other files than a streamed trace"):
        TraceRecorder(rt, ["x.set_position"], stream=tmp_path)
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_a_new_stream_replaces_the_last_one_in_the_same_directory(tmp_path: Path) -> None:
    run(300, stream=tmp_path / "s", chunk=7).flush()
    assert (tmp_path / "s" / chunk_name(42)).exists()
    recorder = run(20, stream=tmp_path / "s", chunk=100)
    assert len(recorder.trace) == 21
    assert sorted(p.name for p in (tmp_path / "s").iterdir()) == [chunk_name(0), MANIFEST]


def test_a_damaged_stream_is_a_config_error(tmp_path: Path) -> None:
    with pytest.raises(om.ConfigError, match="not a streamed trace: no trace.json"):
        read_stream(tmp_path)
    run(50, stream=tmp_path / "s", chunk=10).flush()
    (tmp_path / "s" / chunk_name(2)).unlink()
    with pytest.raises(om.ConfigError, match=r"chunk-000002.npz: cannot read the chunk"):
        read_stream(tmp_path / "s")
    manifest = json.loads((tmp_path / "s" / MANIFEST).read_text())
    (tmp_path / "s" / MANIFEST).write_text(json.dumps({**manifest, "format": 99}))
    with pytest.raises(om.ConfigError, match="not a trace manifest of format 1"):
        read_stream(tmp_path / "s")


def test_a_streamed_trace_exports_and_plots_as_any_trace(tmp_path: Path) -> None:
    """The rest of the code takes a streamed trace as it is: CSV with its sidecar, NPZ and
    the scope read back equal to the unbounded trace."""
    full = run(200).trace
    streamed = run(200, stream=tmp_path / "s", chunk=16).trace
    for name in ("t.csv", "t.npz"):
        write_trace(streamed, tmp_path / name)
        again = read_trace(tmp_path / name)
        assert again.equals(full) and again.events == full.events
    save_plot(read_trace(tmp_path / "s"), tmp_path / "t.png")
    assert (tmp_path / "t.png").read_bytes().startswith(b"\x89PNG")


def test_read_trace_takes_a_directory_for_a_stream(tmp_path: Path) -> None:
    """A directory without a manifest says what is missing; one named like a trace file
    keeps the file's message."""
    (tmp_path / "empty").mkdir()
    with pytest.raises(om.ConfigError, match="empty: not a streamed trace: no trace.json"):
        read_trace(tmp_path / "empty")
    (tmp_path / "folder.csv").mkdir()
    with pytest.raises(om.ConfigError, match="folder.csv: cannot read the trace"):
        read_trace(tmp_path / "folder.csv")
    run(20, stream=tmp_path / "s.csv", chunk=8).flush()
    assert len(read_trace(tmp_path / "s.csv")) == 21
