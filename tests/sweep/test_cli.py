"""``openmotion sweep``: the shipped example sweep, exit codes, errors, ``--ray`` and resume."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import pandas
import pytest
from typer.testing import CliRunner

import openmotion.sweep
from openmotion.cli import app
from openmotion.examples import examples_dir
from openmotion.sweep import TABLE_FILE

runner = CliRunner()
EXAMPLE = examples_dir() / "sweeps" / "ca_ring_movers_velocity.yaml"


@pytest.fixture(autouse=True)
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)  # the default output directory is in the working directory
    return tmp_path


def test_the_example_sweep_runs_and_queues_one_mover_fewer_than_it_has(in_tmp: Path) -> None:
    result = runner.invoke(app, ["sweep", str(EXAMPLE), "--json", "--workers", "2"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["output"] == "ca_ring_movers_velocity.sweep"
    assert (summary["points"], summary["done"], summary["failed"]) == (6, 6, 0)
    table = pandas.read_parquet(in_tmp / summary["table"])
    assert list(table["movers"]) == [2, 2, 4, 4, 8, 8]
    assert list(table["timeline[*].velocity"]) == [1000.0, 4000.0] * 3
    assert list(table["commands.busy"]) == [1, 1, 3, 3, 7, 7]  # all but the leader queue
    assert list(table["commands.done"]) == [1] * 6 and list(table["gap.min"]) == [100.0] * 6
    assert all(table["run.passed"])
    slow, fast = table["run.end_time"][::2].to_numpy(), table["run.end_time"][1::2].to_numpy()
    assert (fast < slow).all()
    assert (in_tmp / summary["figure"]).read_bytes()[:4] == b"\x89PNG"
    again = runner.invoke(app, ["sweep", str(EXAMPLE), "--json"])  # all six found: resumed
    assert again.exit_code == 0 and json.loads(again.stdout)["reused"] == 6


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


FAILING = """\
scenario: {base}
parameters:
  - path: axes[0].parameters.max_velocity
    values: [1000.0, -1.0]
metrics:
  - {{run: [cycles]}}
"""


def test_a_failed_point_is_listed_and_exits_1(in_tmp: Path) -> None:
    base = Path(__file__).with_name("short_move.yaml")
    sweep = _write(in_tmp / "failing.yaml", FAILING.format(base=base))
    result = runner.invoke(app, ["sweep", str(sweep), "--no-figure", "-o", "out"])
    assert result.exit_code == 1, result.output
    lines = result.stdout.splitlines()
    assert lines[0] == "2 points: 1 done, 1 failed, 0 reused from out"
    assert lines[1].startswith("  point 1 (") and "invalid scenario: axes[0].parameters." \
        "max_velocity: must be a finite number > 0" in lines[1]
    assert (in_tmp / "out" / TABLE_FILE).exists() and not (in_tmp / "out" / "summary.png").exists()


def test_a_bad_sweep_file_is_one_line_and_exit_2(in_tmp: Path) -> None:
    sweep = _write(in_tmp / "bad.yaml", "scenario: single_move\nmetrics: [{runs: [cycles]}]\n")
    result = runner.invoke(app, ["sweep", str(sweep)])
    assert result.exit_code == 2
    assert result.stderr == f"ConfigError: {sweep}:2: metrics[0]: give exactly one of signal, " \
                            "commands, run, station, cycle_cost\n"
    assert not (in_tmp / "bad.sweep").exists()


def test_a_missing_extra_is_named_and_exits_2(in_tmp: Path, monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "pandas", None)
    result = runner.invoke(app, ["sweep", str(EXAMPLE)])
    assert result.exit_code == 2
    assert result.stderr == "error: sweeps need pandas: install them with pip install " \
                            "'openmotion[sweep]'\n"


@pytest.mark.parametrize(("arguments", "expected"), [
    ([], False), (["--ray"], "local"), (["--ray", "--json"], "local"),
    (["--ray", "local"], "local"),
    (["--ray", "auto"], "auto"), (["--ray", "10.0.0.2:6379", "--json"], "10.0.0.2:6379"),
    (["--ray=ray://head:10001"], "ray://head:10001")])
def test_ray_alone_starts_a_local_cluster_and_an_address_joins_one(
        monkeypatch, arguments: list[str], expected: Any) -> None:
    seen: dict[str, Any] = {}

    def fake_run_sweep(sweep: Any, output: Any, **options: Any) -> pandas.DataFrame:
        seen.update(options)
        return pandas.DataFrame({"index": [0], "point_id": ["a"], "status": ["done"],
                                 "error": [""]})

    monkeypatch.setattr(openmotion.sweep, "run_sweep", fake_run_sweep)
    result = runner.invoke(app, ["sweep", str(EXAMPLE), *arguments])
    assert result.exit_code == 0, result.output
    assert seen["ray"] == expected


def test_an_interrupted_sweep_says_how_to_resume(monkeypatch) -> None:
    def interrupted(sweep: Any, output: Any, progress: Any, **options: Any) -> None:
        progress(openmotion.sweep.SweepProgress(done=2, failed=0, reused=0, total=6))
        raise KeyboardInterrupt

    monkeypatch.setattr(openmotion.sweep, "run_sweep", interrupted)
    result = runner.invoke(app, ["sweep", str(EXAMPLE), "-o", "out"])
    assert result.exit_code == 130
    assert result.stderr == "interrupted: 2 of 6 points are stored in out; the same command " \
                            "again resumes\n"


def test_the_sweep_benchmark_without_the_extra_exits_2(monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    result = runner.invoke(app, ["bench", "sweep", "--quick"])
    assert result.exit_code == 2
    assert result.stderr == "error: sweeps need pyarrow: install them with pip install " \
                            "'openmotion[sweep]'\n"
