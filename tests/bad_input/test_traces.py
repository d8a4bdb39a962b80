"""Bad trace input at the command line: a trace suffix that is neither .csv nor .npz is
refused before the run; a CSV without its sidecar still plots (the scope, with a note); a
missing or corrupt trace is exit 2 with one line, never a traceback. After each, the CLI
does the next valid thing."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

import openmotion.scenario
from openmotion.cli import app
from openmotion.scenario import examples_dir

runner = CliRunner()
PNG = b"\x89PNG\r\n\x1a\n"
SINGLE = str(examples_dir() / "single_move.yaml")


@pytest.fixture(autouse=True)
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def clean_exit(result, code: int) -> None:
    """The exit code, and no exception but the exit itself (no traceback)."""
    assert result.exit_code == code, result.output
    assert isinstance(result.exception, SystemExit) or (code == 0 and result.exception is None)
    assert "Traceback" not in result.output


@pytest.mark.parametrize("name", ["x.parquet", "x.txt", "trace"])
def test_a_trace_suffix_other_than_csv_or_npz_is_refused_before_the_run(
        in_tmp: Path, monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    def no_run(*args, **kwargs):
        raise AssertionError("the scenario must not run")

    with monkeypatch.context() as patch:
        patch.setattr(openmotion.scenario, "run_scenario", no_run)
        result = runner.invoke(app, ["run", SINGLE, "--trace", name, "--plot", "f.png"])
    clean_exit(result, 2)
    assert result.stderr == (f"ConfigError: {name}: the trace format comes from the suffix: "
                             ".csv, .npz (a .csv gets its events and layout in a .events.json "
                             "beside it)\n")
    assert list(in_tmp.iterdir()) == []  # nothing written
    clean_exit(runner.invoke(app, ["run", SINGLE, "-q", "--trace", "x.npz"]), 0)
    assert (in_tmp / "x.npz").read_bytes()[:2] == b"PK"


def test_a_csv_without_its_sidecar_plots_the_scope_with_a_note(in_tmp: Path) -> None:
    clean_exit(runner.invoke(app, ["run", SINGLE, "-q", "--trace", "t.csv"]), 0)
    (in_tmp / "t.events.json").rename(in_tmp / "elsewhere.json")
    result = runner.invoke(app, ["plot", "t.csv"])
    clean_exit(result, 0)
    assert result.stderr.splitlines() == [
        "note: t.csv: no t.events.json beside it: the command events and the layout are "
        "missing, so only the scope can be drawn",
        "plot: written to t.png"]
    assert (in_tmp / "t.png").read_bytes()[:8] == PNG
    (in_tmp / "elsewhere.json").rename(in_tmp / "t.events.json")
    result = runner.invoke(app, ["plot", "t.csv", "-o", "again.png"])
    clean_exit(result, 0)
    assert "note:" not in result.stderr


def test_a_csv_with_a_broken_sidecar_plots_the_scope_with_a_note(in_tmp: Path) -> None:
    clean_exit(runner.invoke(app, ["run", SINGLE, "-q", "--trace", "t.csv"]), 0)
    (in_tmp / "t.events.json").write_text('{"format": 1, "events": [')
    result = runner.invoke(app, ["plot", "t.csv"])
    clean_exit(result, 0)
    assert result.stderr.startswith("note: t.csv: t.events.json is not a trace sidecar (")
    assert (in_tmp / "t.png").read_bytes()[:8] == PNG


@pytest.mark.parametrize(("name", "content", "message"), [
    ("nope.csv", None, "nope.csv: cannot read the trace: No such file or directory"),
    ("nope.npz", None, "nope.npz: cannot read the trace: No such file or directory"),
    ("binary.csv", b"\x89PNG\r\n\x1a\n\xff\x00\x10", "binary.csv: not a CSV trace: 'utf-8' codec"),
    ("header.csv", b"a,b\n1,2\n", "header.csv:1: the header must start with 'time'"),
    ("ragged.csv", b"time,x\n0,1\n0.1\n", "ragged.csv:3: 1 values for 2 columns"),
    ("half.npz", b"PK\x03\x04" + bytes(30), "half.npz: not an NPZ trace"),
    ("text.npz", b"time,x\n0,1\n", "text.npz: not an NPZ trace"),
    ("trace.txt", b"time,x\n0,1\n", "trace.txt: the trace format comes from the suffix: .csv, "
                                    ".npz"),
    ("folder.csv", "dir", "folder.csv: cannot read the trace: Is a directory"),
])
def test_plot_of_a_missing_or_corrupt_trace_exits_2_with_one_line(
        in_tmp: Path, name: str, content: bytes | str | None, message: str) -> None:
    if content == "dir":
        (in_tmp / name).mkdir()
    elif isinstance(content, bytes):
        (in_tmp / name).write_bytes(content)
    result = runner.invoke(app, ["plot", name, "-o", "out.png"])
    clean_exit(result, 2)
    assert result.stderr.startswith(f"ConfigError: {message}"), result.stderr
    assert len(result.stderr.splitlines()) == 1
    assert not (in_tmp / "out.png").exists()
    clean_exit(runner.invoke(app, ["run", SINGLE, "-q", "--trace", "good.csv"]), 0)
    clean_exit(runner.invoke(app, ["plot", "good.csv", "-o", "out.png"]), 0)
    assert (in_tmp / "out.png").read_bytes()[:8] == PNG
