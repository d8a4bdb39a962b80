"""Trace files: CSV as before (bit for bit) with a sidecar for the events, layout and title;
NPZ with all of them; both read back exactly; other suffixes refused."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import openmotion as om
from openmotion.scenario import examples_dir, run_scenario
from openmotion.trace import (
    Event,
    Trace,
    TraceWarning,
    read_csv,
    read_npz,
    read_trace,
    sidecar_path,
    trace_format,
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
    write_trace(ODD, tmp_path / "t.CSV")
    assert (tmp_path / "t.npz").read_bytes()[:2] == b"PK"  # a zip
    assert sorted(path.name for path in tmp_path.iterdir()) == ["t.CSV", "t.events.json",
                                                                "t.npz"]
    assert read_trace(tmp_path / "t.npz").events == ODD.events
    assert read_trace(tmp_path / "t.CSV").events == ODD.events


@pytest.mark.parametrize("name", ["x.parquet", "x.txt", "x", "x.csv.gz", "x.events.json"])
def test_other_suffixes_are_refused_naming_the_two_formats(tmp_path: Path, name: str) -> None:
    with pytest.raises(om.ConfigError, match=r"the trace format comes from the suffix: "
                                             r"\.csv, \.npz"):
        trace_format(tmp_path / name)
    with pytest.raises(om.ConfigError, match=name.replace(".", r"\.")):
        write_trace(ODD, tmp_path / name)
    assert list(tmp_path.iterdir()) == []  # nothing written
    assert write_trace(ODD, tmp_path / "ok.csv").exists()  # and the next call works


def test_the_csv_stays_plain_and_the_sidecar_keeps_events_layout_and_title(
        tmp_path: Path) -> None:
    titled = Trace(ODD.columns, ODD.data, ODD.events, ODD.layout, "odd ü")
    path = write_trace(titled, tmp_path / "odd.csv")
    assert path.read_text() == write_csv(ODD, tmp_path / "plain.csv").read_text()
    assert sidecar_path(path) == tmp_path / "odd.events.json"
    content = json.loads(sidecar_path(path).read_text(encoding="utf-8"))
    assert content["trace"] == "odd.csv" and content["rows"] == 3
    assert content["columns"] == list(ODD.columns) and content["format"] == 1
    again = read_trace(path)
    assert again.equals(ODD) and again.data.tobytes() == ODD.data.tobytes()
    assert again.events == ODD.events and again.layout == ODD.layout
    assert again.title == "odd ü"


def test_a_csv_of_a_run_re_reads_with_everything(tmp_path: Path, planar: Trace) -> None:
    again = read_trace(write_trace(planar, tmp_path / "run.csv"))
    assert again.equals(planar) and again.title == "planar two movers"
    assert again.events == planar.events and len(again.events) > 0
    assert again.layout == planar.layout and "planar" in again.layout


def test_an_event_that_never_ended_keeps_its_nan_time_as_json_null(tmp_path: Path) -> None:
    trace = Trace(("time",), np.zeros((1, 1)), [Event(math.nan, "x", "halt", "ABORTED")])
    path = write_trace(trace, tmp_path / "t.csv")
    assert '"time": null' in sidecar_path(path).read_text()
    json.loads(sidecar_path(path).read_text())  # standard JSON: no NaN literal
    (event,) = read_trace(path).events
    assert math.isnan(event.time) and event[1:] == ("x", "halt", "ABORTED", "", "")


def test_a_csv_without_its_sidecar_reads_as_columns_with_a_warning(tmp_path: Path) -> None:
    path = write_csv(ODD, tmp_path / "alone.csv")
    with pytest.warns(TraceWarning, match=r"alone\.csv: no alone\.events\.json beside it: the "
                                          r"command events and the layout are missing"):
        again = read_trace(path)
    assert again.equals(ODD) and again.events == () and again.layout == {}
    assert again.title == ""


@pytest.mark.parametrize(("sidecar", "why"), [
    ("{not json", r"odd\.events\.json is not a trace sidecar"),
    ('{"format": 2}', r"odd\.events\.json is not a trace sidecar \(no \"format\": 1\)"),
    ('[1, 2]', r"odd\.events\.json is not a trace sidecar"),
    ('{"format": 1, "columns": ["time"], "rows": 3}', r"written for another trace"),
    (None, r"written for another trace"),  # the right columns, one row fewer
    (b"\xff\xfe", r"cannot read odd\.events\.json"),
])
def test_a_sidecar_that_does_not_fit_is_ignored_with_a_warning(
        tmp_path: Path, sidecar: str | bytes | None, why: str) -> None:
    path = write_trace(ODD, tmp_path / "odd.csv")
    if sidecar is None:  # the CSV rewritten by hand, shorter
        write_csv(Trace(ODD.columns, ODD.data[:2]), path)
    elif isinstance(sidecar, bytes):
        sidecar_path(path).write_bytes(sidecar)
    else:
        sidecar_path(path).write_text(sidecar)
    with pytest.warns(TraceWarning, match=why):
        again = read_trace(path)
    assert again.events == () and again.layout == {}
    write_trace(ODD, path)
    assert read_trace(path).events == ODD.events  # written again, it fits again


def test_npz_keeps_the_title_and_reads_one_without_it(tmp_path: Path) -> None:
    titled = Trace(ODD.columns, ODD.data, ODD.events, ODD.layout, "odd")
    assert read_npz(write_npz(titled, tmp_path / "t.npz")).title == "odd"
    with np.load(tmp_path / "t.npz") as archive:
        arrays = {name: archive[name] for name in archive.files if name != "title"}
    np.savez(tmp_path / "old.npz", **arrays)  # as written before there were titles
    old = read_npz(tmp_path / "old.npz")
    assert old.title == "" and old.events == ODD.events


@pytest.mark.parametrize(("content", "message"), [
    (b"time,x\n0,1\n", "not an NPZ trace"),
    (None, "cannot read the trace"),
    (b"PK\x03\x04" + bytes(40), "not an NPZ trace"),
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


def test_a_corrupt_npz_trace_is_a_config_error(tmp_path: Path) -> None:
    good = write_npz(ODD, tmp_path / "good.npz").read_bytes()
    (tmp_path / "half.npz").write_bytes(good[:len(good) // 2])
    with pytest.raises(om.ConfigError, match=r"half\.npz: not an NPZ trace"):
        read_npz(tmp_path / "half.npz")
    np.savez(tmp_path / "format.npz", **{**{name: np.array("") for name in
                                             ("columns", "data", "layout")},
                                          **{f"events_{field}": np.array([])
                                             for field in Event._fields},
                                          "format": np.array("one")})
    with pytest.raises(om.ConfigError, match=r"format\.npz: not an NPZ trace: format"):
        read_npz(tmp_path / "format.npz")


@pytest.mark.parametrize("content", [b"\xff\xfe\x00time", b"time,x\n0,1\x00\n"])
def test_a_csv_that_is_no_text_or_no_csv_is_a_config_error(tmp_path: Path,
                                                           content: bytes) -> None:
    (tmp_path / "bad.csv").write_bytes(content)
    with pytest.raises(om.ConfigError, match=r"bad\.csv"):
        read_csv(tmp_path / "bad.csv")
