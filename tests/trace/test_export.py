"""Trace files: CSV as before (bit for bit), NPZ with events and layout, read back exactly."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import openmotion as om
from openmotion.scenario import examples_dir, run_scenario
from openmotion.trace import (
    Event,
    Trace,
    read_csv,
    read_npz,
    read_trace,
    write_csv,
    write_npz,
    write_trace,
)

ODD = Trace(("time", "x.set_position", "x.state", "m2.gap"),
            np.array([[0.0, -0.0, 0.0, math.inf], [0.001, 0.1 + 0.2, 4.0, math.nan],
                      [0.002, 1e-300, 2.0, -5e-324]]),
            [Event(0.0, "x", "move_absolute", "ISSUED", "out"),
             Event(0.002, "x", "move_absolute", "ERROR", "out", "INVALID_VELOCITY: ü -> ✓")],
            {"objects": {"x": "axis"}, "ca_groups": {"g": {"rail_length": 3000.0,
                                                          "movers": ["m2"]}}})


@pytest.fixture(scope="module")
def planar() -> Trace:
    return run_scenario(examples_dir() / "planar_two_movers.yaml", figure=True).trace


def test_csv_is_the_same_text_as_before(tmp_path: Path) -> None:
    """One header, repr floats, states as integers: the format the golden traces use."""
    text = write_csv(ODD, tmp_path / "t.csv").read_text()
    assert text == ("time,x.set_position,x.state,m2.gap\n"
                    "0.0,-0.0,0,inf\n"
                    "0.001,0.30000000000000004,4,nan\n"
                    "0.002,1e-300,2,-5e-324\n")
    assert read_csv(tmp_path / "t.csv").equals(ODD)


def test_npz_round_trip_is_bit_identical_with_events_and_layout(tmp_path: Path) -> None:
    path = write_npz(ODD, tmp_path / "odd.bin")  # any name: no ".npz" is added
    assert path == tmp_path / "odd.bin" and path.exists()
    again = read_npz(path)
    assert again.equals(ODD) and again.data.tobytes() == ODD.data.tobytes()
    assert again.events == ODD.events and again.layout == ODD.layout


def test_npz_of_a_run_keeps_everything(tmp_path: Path, planar: Trace) -> None:
    again = read_trace(write_trace(planar, tmp_path / "run.npz"))
    assert again.equals(planar)
    assert again.events == planar.events and len(again.events) > 0
    assert again.layout == planar.layout and "planar" in again.layout
    assert all(isinstance(event.time, float) for event in again.events)


def test_a_trace_without_events_round_trips(tmp_path: Path) -> None:
    empty = Trace(("time",), np.zeros((0, 1)))
    again = read_npz(write_npz(empty, tmp_path / "e.npz"))
    assert again.equals(empty) and again.events == () and again.layout == {}


def test_write_and_read_trace_pick_the_format_by_suffix(tmp_path: Path) -> None:
    write_trace(ODD, tmp_path / "t.npz")
    write_trace(ODD, tmp_path / "t.csv")
    assert (tmp_path / "t.npz").read_bytes()[:2] == b"PK"  # a zip
    assert read_trace(tmp_path / "t.npz").events == ODD.events
    assert read_trace(tmp_path / "t.csv").events == ()


@pytest.mark.parametrize(("content", "message"), [
    (b"time,x\n0,1\n", "not an NPZ trace"),
    (None, "cannot read the trace"),
])
def test_a_file_that_is_no_npz_trace_is_a_config_error(tmp_path: Path, content: bytes | None,
                                                       message: str) -> None:
    path = tmp_path / "bad.npz"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(om.ConfigError, match=message):
        read_npz(path)


def test_an_npz_without_the_trace_arrays_is_a_config_error(tmp_path: Path) -> None:
    path = tmp_path / "other.npz"
    np.savez(path, data=np.zeros(3))
    with pytest.raises(om.ConfigError, match="not an NPZ trace: no columns, events_command"):
        read_npz(path)
