"""The command line, through click's CliRunner: exit codes, stdout, stderr and written files."""

from __future__ import annotations

import json
import sys
import types
from pathlib import Path

import pytest
from typer.testing import CliRunner

from openmotion.cli import app
from openmotion.scenario import examples_dir

runner = CliRunner()
PNG = b"\x89PNG\r\n\x1a\n"
BAD = """\
name: bad
axes:
  - name: x
    parameters: {max_velocity: -1}
timeline:
  - {at: 0, axis: y, command: power}
  - {at: 0, axis: x, command: fly}
"""
FAILING = """\
name: failing
axes: [{name: x}]
timeline:
  - {at: 0, axis: x, command: power}
checks:
  - {signal: x.set_position, expect: 1}
"""


@pytest.fixture(autouse=True)
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)  # `run` writes trace.csv into the current directory
    return tmp_path


def test_run_without_argument_runs_the_shipped_example_and_writes_the_trace(in_tmp) -> None:
    result = runner.invoke(app, ["run"])
    assert result.exit_code == 0, result.output
    assert result.stdout == (examples_dir() / "single_move.out").read_text()
    header = (in_tmp / "trace.csv").read_text().splitlines()[0]
    assert header.startswith("time,x.set_position,")
    assert "written to trace.csv" in result.stderr


def test_run_json_is_one_json_object_without_colour(in_tmp) -> None:
    result = runner.invoke(app, ["run", str(examples_dir() / "single_move.yaml"), "--json",
                                 "--trace", "out.csv", "--plot", "scope.png"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["passed"] is True and data["scenario"] == "single move"
    assert data["trace"]["path"] == "out.csv" and data["plot"] == "scope.png"
    assert [row["result"] for row in data["commands"]] == ["DONE", "DONE", "DONE"]
    assert "\x1b[" not in result.output and result.stderr == ""
    assert (in_tmp / "out.csv").exists() and (in_tmp / "scope.png").read_bytes()[:8] == PNG


def test_run_exit_1_when_a_check_fails(in_tmp) -> None:
    (in_tmp / "failing.yaml").write_text(FAILING)
    result = runner.invoke(app, ["run", "failing.yaml"])
    assert result.exit_code == 1
    assert "FAIL" in result.stdout and "0 of 1 checks passed, 1 FAILED" in result.stdout


def test_run_quiet_prints_nothing(in_tmp) -> None:
    (in_tmp / "failing.yaml").write_text(FAILING)
    result = runner.invoke(app, ["run", "failing.yaml", "--quiet"])
    assert (result.exit_code, result.output) == (1, "")
    assert (in_tmp / "trace.csv").exists()


def test_run_config_error_is_one_line_on_stderr_and_exit_2(in_tmp) -> None:
    (in_tmp / "bad.yaml").write_text(BAD)
    result = runner.invoke(app, ["run", "bad.yaml"])
    assert result.exit_code == 2 and result.stdout == ""
    assert result.stderr.splitlines() == [
        "ConfigError: bad.yaml:4: axes[0].parameters.max_velocity: must be a finite number > 0,"
        " got -1.0 (and 2 more)"]
    assert not (in_tmp / "trace.csv").exists()


def test_check_lists_every_error_with_file_line_and_field(in_tmp) -> None:
    (in_tmp / "bad.yaml").write_text(BAD)
    result = runner.invoke(app, ["check", "bad.yaml"])
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 3 and all(line.startswith("ConfigError: bad.yaml:") for line in lines)
    assert lines[1].startswith("ConfigError: bad.yaml:6: timeline[0].axis: unknown axis 'y'")
    assert lines[2].startswith("ConfigError: bad.yaml:7: timeline[1].command: unknown command")


def test_check_accepts_every_example() -> None:
    for path in sorted(examples_dir().glob("*.yaml")):
        result = runner.invoke(app, ["check", str(path)])
        assert result.exit_code == 0, result.output
        assert result.stdout.startswith(f"{path}: ok (")


def test_plot_writes_a_png_from_a_trace(in_tmp) -> None:
    assert runner.invoke(app, ["run", "--quiet", "--trace", "t.csv"]).exit_code == 0
    result = runner.invoke(app, ["plot", "t.csv"])
    assert result.exit_code == 0, result.output
    assert (in_tmp / "t.png").read_bytes()[:8] == PNG
    result = runner.invoke(app, ["plot", "t.csv", "--output", "scope.png"])
    assert result.exit_code == 0 and (in_tmp / "scope.png").read_bytes()[:8] == PNG


def test_plot_of_a_file_that_is_no_trace_exits_2(in_tmp) -> None:
    (in_tmp / "nope.csv").write_text("a,b\n1,2\n")
    result = runner.invoke(app, ["plot", "nope.csv"])
    assert result.exit_code == 2 and result.stderr.startswith("ConfigError: nope.csv:1:")


def test_bench_unknown_name_exits_2() -> None:
    result = runner.invoke(app, ["bench", "no-such-benchmark", "--quick"])
    assert result.exit_code == 2
    assert "no-such-benchmark" in result.stderr or "not available" in result.stderr


@pytest.fixture
def fake_runner(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, bool]]:
    """A stand-in for openmotion.bench.runner: the CLI must only call its public functions."""
    calls: list[tuple[str, bool]] = []

    def run_benchmark(name: str, quick: bool = False, progress=None, cycles=None) -> dict:
        calls.append((name, quick) if cycles is None else (name, quick, cycles))
        progress(f"{name}: step 1")
        return {"benchmark": name, "passed": True}

    module = types.ModuleType("openmotion.bench.runner")
    module.run_benchmark = run_benchmark  # type: ignore[attr-defined]
    module.LONG_RUNS = ("trace",)  # type: ignore[attr-defined]
    module.render = lambda result: f"bench {result['benchmark']}: passed"  # type: ignore
    monkeypatch.setitem(sys.modules, "openmotion.bench.runner", module)
    import openmotion.bench

    monkeypatch.setattr(openmotion.bench, "runner", module, raising=False)
    return calls


def test_bench_calls_the_runner_and_prints_its_table_or_json(fake_runner) -> None:
    result = runner.invoke(app, ["bench", "otg", "--quick"])
    assert (result.exit_code, result.stdout) == (0, "bench otg: passed\n")
    result = runner.invoke(app, ["bench", "axes", "--json"])
    assert json.loads(result.stdout) == {"benchmark": "axes", "passed": True}
    assert fake_runner == [("otg", True), ("axes", False)]
    result = runner.invoke(app, ["bench", "nope"])
    assert result.exit_code == 2 and "choose one of: axes, otg" in result.stderr
    assert len(fake_runner) == 2


def test_bench_cycles_goes_to_the_long_runs_only(fake_runner) -> None:
    """D-188: ``--cycles`` sets the length of the trace memory run; any other benchmark
    would ignore it, so it is a usage error there (exit 2, nothing run)."""
    result = runner.invoke(app, ["bench", "otg", "--cycles", "5"])
    assert result.exit_code == 2 and "--cycles: only for trace, not otg" in result.stderr
    assert runner.invoke(app, ["bench", "trace", "--cycles", "0"]).exit_code == 2
    assert runner.invoke(app, ["bench", "trace", "--quick", "--cycles", "300"]).exit_code == 0
    assert fake_runner == [("trace", True, 300)]


def test_help_comes_from_the_declarations() -> None:
    result = runner.invoke(app, ["--help"])
    assert result.exit_code == 0
    for command in ("run", "check", "plot", "bench"):
        assert command in result.stdout
    result = runner.invoke(app, ["run", "--help"])
    assert "--trace" in result.stdout and "--json" in result.stdout


def test_usage_error_exits_2() -> None:
    assert runner.invoke(app, ["run", "--no-such-option"]).exit_code == 2
    assert runner.invoke(app, ["check"]).exit_code == 2


def test_run_trace_stream_writes_chunks_and_plot_reads_them(in_tmp) -> None:
    """D-188: --trace-stream puts the trace into a directory of chunks (no trace.csv unless
    --trace asks for one); 'openmotion plot' reads the directory."""
    result = runner.invoke(app, ["run", "--trace-stream", "st", "--trace-chunk", "500"])
    assert result.exit_code == 0, result.stderr
    assert "columns streamed to st" in result.stderr and not (in_tmp / "trace.csv").exists()
    assert sorted(p.name for p in (in_tmp / "st").iterdir())[:2] == ["chunk-000000.npz",
                                                                     "chunk-000001.npz"]
    shown = runner.invoke(app, ["plot", "st", "-o", "st.png"])
    assert shown.exit_code == 0 and (in_tmp / "st.png").read_bytes().startswith(PNG)
    both = runner.invoke(app, ["run", "--trace-stream", "st", "--trace", "t.csv", "--json"])
    assert both.exit_code == 0 and json.loads(both.stdout)["trace"]["path"] == "t.csv"
    assert runner.invoke(app, ["run", "--trace", "plain.csv"]).exit_code == 0
    assert (in_tmp / "t.csv").read_text() == (in_tmp / "plain.csv").read_text()


def test_run_trace_keep_writes_the_last_rows(in_tmp) -> None:
    result = runner.invoke(app, ["run", "--trace-keep", "50", "--json"])
    assert result.exit_code == 0 and json.loads(result.stdout)["trace"]["rows"] == 50
    assert len((in_tmp / "trace.csv").read_text().splitlines()) == 51


@pytest.mark.parametrize(("arguments", "message"), [
    (["--trace-keep", "0"], "Invalid value for '--trace-keep'"),
    (["--trace-chunk", "0", "--trace-stream", "s"], "Invalid value for '--trace-chunk'"),
    (["--trace-keep", "5", "--trace-stream", "s"], "ConfigError: keep and stream: give one"),
    (["--trace-chunk", "5"], "ConfigError: chunk: only with stream"),
    (["--trace-stream", "file/s"], "ConfigError: stream: file/s: cannot write the trace "
                                   "there: Not a directory"),
])
def test_run_bad_trace_options_exit_2_and_write_nothing(in_tmp, arguments: list[str],
                                                        message: str) -> None:
    """D-188: a bound that keeps nothing, both modes, or an unwritable directory: exit 2
    with the reason on stderr, nothing written; the same command without them runs."""
    (in_tmp / "file").write_text("x")
    result = runner.invoke(app, ["run", *arguments])
    assert result.exit_code == 2 and message in result.stderr
    assert not (in_tmp / "trace.csv").exists() and not (in_tmp / "s").exists()
    assert runner.invoke(app, ["run", "-q"]).exit_code == 0
