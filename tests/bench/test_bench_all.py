"""``openmotion bench all`` and the figures of docs/benchmarks.md rendered from its file."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from openmotion.bench import BENCHMARK_NAMES, report, suite
from openmotion.cli import app
from openmotion.core.errors import ConfigError

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "benchmarks.md"
PUBLISHED = ROOT / "docs" / "bench" / "all.json"
REGENERATE = "openmotion bench report docs/bench/all.json --write-docs docs/benchmarks.md"


def _goal(text: str, value: Any, passed: bool | None) -> dict[str, Any]:
    return {"goal": text, "value": value, "passed": passed}


def _fbcall(**extra: Any) -> dict[str, Any]:
    return {"fb_call_us": 1.25, "fb_call_bare_us": 0.5, "empty_call_us": 0.04,
            "step_1_axis_us": 5.5, **extra}


def _run(benchmarks: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """A run as suite.run_suite writes it, with made-up figures."""
    return {"format": suite.FORMAT, "command": "openmotion bench all", "quick": False,
            "date": "2026-12-07T20:00:00+00:00", "git": {"commit": "abcdef1234567", "dirty": True},
            "seconds": 12.5, "passed": False,
            "machine": {"cpu": "Test CPU", "cpu_count": 2, "os": "Linux-test", "python": "3.11.7",
                        "load_average": [0.5, 0.25, 1.5],
                        "versions": {"numpy": "2.4.6", "ray": None}},
            "benchmarks": benchmarks}


def _entry(results: dict[str, Any] | None, goals: dict[str, Any] | None = None,
           error: str | None = None) -> dict[str, Any]:
    goals = goals or {}
    status = "error" if error else ("passed" if all(g["passed"] for g in goals.values())
                                    else "failed")
    return {"status": status, "error": error, "goals": goals, "results": results,
            "seconds": 3.0}


# -- the run ---------------------------------------------------------------------------------


def test_select_keeps_the_catalogue_order_and_names_an_unknown_benchmark() -> None:
    assert suite.select() == list(BENCHMARK_NAMES)
    assert suite.select(["path", "axes"], ["axes"]) == ["path"]
    with pytest.raises(ValueError, match="unknown benchmark 'nope'.*axes, otg"):
        suite.select(["axes", "nope"])


def test_a_benchmark_that_raises_is_recorded_and_the_others_still_run() -> None:
    ran: list[str] = []

    def run_one(name: str, quick: bool, progress: Any) -> dict[str, Any]:
        ran.append(name)
        progress("working")
        if name == "ca":
            raise ImportError("the sweep extra is missing")
        return {"results": {"x": 1}, "passed": name != "path",
                "goals": {"g": _goal("x is 1", 1, name != "path")}}

    said: list[str] = []
    run = suite.run_suite(["axes", "ca", "path"], quick=True, echo=said.append, run_one=run_one)
    assert ran == ["axes", "ca", "path"]
    assert {n: b["status"] for n, b in run["benchmarks"].items()} == {
        "axes": "passed", "ca": "error", "path": "failed"}
    assert run["benchmarks"]["ca"]["error"] == "ImportError: the sweep extra is missing"
    assert run["benchmarks"]["ca"]["results"] is None and run["passed"] is False
    assert all(b["seconds"] >= 0 and "cpu_seconds" in b and "load_average" in b
               for b in run["benchmarks"].values())
    assert any("ca" in line and "working" in line for line in said)  # progress, with its name
    assert any("[2/3] ca: error" in line for line in said)
    json.loads(json.dumps(run, allow_nan=False))
    assert "FAIL x is 1" in suite.summary(run) and "passed: no" in suite.summary(run)


def test_a_process_that_dies_is_an_error_with_the_end_of_its_stderr() -> None:
    lines: list[str] = []
    die = [sys.executable, "-c", "import sys; print('first'); print('boom', file=sys.stderr); "
                                 "sys.exit(3)"]
    with pytest.raises(suite.BenchmarkError, match=r"(?s)code 3 and no result.*boom"):
        suite.run_in_process("fbcall", False, lines.append, command=die)
    assert lines == ["boom"]


def test_the_child_writes_the_error_of_its_benchmark(tmp_path: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    from openmotion.bench import runner

    def broken(quick: bool, progress: Any) -> dict[str, Any]:
        raise RuntimeError("no pyplcopen today")

    monkeypatch.setitem(runner.BENCHMARKS, "fbcall", broken)
    out = tmp_path / "result.json"
    assert suite._child(["fbcall", "--out", str(out), "--quick"]) == 1
    assert json.loads(out.read_text()) == {"error": "RuntimeError: no pyplcopen today"}
    monkeypatch.undo()
    assert suite._child(["fbcall", "--out", str(out), "--quick"]) == 0
    answer = json.loads(out.read_text())
    assert answer["benchmark"] == "fbcall" and "machine" not in answer
    assert answer["options"] == {}


def test_in_a_suite_startup_leaves_out_the_empty_cache_run_of_every_example(
        monkeypatch: pytest.MonkeyPatch) -> None:
    from openmotion.bench import runner

    seen: list[dict[str, Any]] = []

    def startup(quick: bool, progress: Any, **options: Any) -> dict[str, Any]:
        seen.append(options)
        raise KeyError("stop here")

    monkeypatch.setitem(runner.BENCHMARKS, "startup", startup)
    for in_suite in (False, True):
        with pytest.raises(KeyError, match="stop here"):
            runner.run_benchmark("startup", in_suite=in_suite)
    assert seen == [{}, {"cold_examples": False}]


def test_cli_bench_all_quick_writes_one_file_and_the_page(tmp_path: Path) -> None:
    page = tmp_path / "benchmarks.md"
    page.write_text("# Figures\n\nhand-written\n\n<!-- generated figures: summary -->\nold\n"
                    "<!-- end of generated figures -->\n\n## path\n\n<!-- generated figures: "
                    "path -->\n<!-- end of generated figures -->\n\nmore hand-written\n")
    out = tmp_path / "bench" / "all.json"
    result = CliRunner().invoke(app, ["bench", "all", "--quick", "--only", "path,otg", "-o",
                                      str(out), "--write-docs", str(page)])
    run = json.loads(out.read_text())
    assert result.exit_code == (0 if run["passed"] else 1), result.output
    assert list(run["benchmarks"]) == ["otg", "path"]  # the catalogue's order
    path = run["benchmarks"]["path"]
    assert path["status"] == "passed" and path["goals"]["limit_violations"]["passed"] is True
    assert run["quick"] is True and run["machine"]["versions"]["ruckig"]
    assert run["command"].startswith("openmotion bench all --quick --only path,otg -o ")
    assert "[2/2] path" in result.stderr and "path: passed" in result.stderr
    assert "path" in result.stdout and "passed:" in result.stdout
    text = page.read_text()
    assert "old" not in text and "hand-written" in text and "more hand-written" in text
    assert "| [path](#path) | passed |" in text and "### otg" in text  # otg has no block
    assert text == report.fill(text, run)  # the page is the file's rendering


def test_cli_bench_all_refuses_bad_options_then_runs(tmp_path: Path) -> None:
    runner = CliRunner()
    bad = runner.invoke(app, ["bench", "all", "--only", "path,nope"])
    assert bad.exit_code == 2 and "unknown benchmark 'nope'" in bad.stderr
    bad = runner.invoke(app, ["bench", "path", "--only", "path"])
    assert bad.exit_code == 2 and "--only does not go with 'bench path'" in bad.stderr
    bad = runner.invoke(app, ["bench", "all", "--only", "path", "--skip", "path"])
    assert bad.exit_code == 2 and "no benchmark to run" in bad.stderr
    page = tmp_path / "page.md"
    page.write_text("no markers\n")
    bad = runner.invoke(app, ["bench", "all", "--only", "path", "--write-docs", str(page)])
    assert bad.exit_code == 2 and "has no <!-- generated figures: summary --> block" in bad.stderr
    good = runner.invoke(app, ["bench", "all", "--quick", "--only", "path", "--json"])
    assert json.loads(good.stdout)["benchmarks"]["path"]["status"] == "passed"


# -- the renderer ------------------------------------------------------------------------------


def test_report_renders_machine_verdicts_new_keys_and_unknown_benchmarks() -> None:
    run = _run({
        "fbcall": _entry(_fbcall(bulk={"per_call_us": 0.25}),
                         {"fb_call_us": _goal("<= 2.0 us", 1.25, True),
                          "other": _goal("a goal not judged", None, None)}),
        "routing": _entry({"movers": 4, "by_n": {"10": {"p99_us": 12.5, "routes": 3},
                                                  "1000": {"p99_us": 80.0, "routes": 7}}},
                          {"p99": _goal("p99 < 50 us", 80.0, False)}),
        "serve": _entry(None, error="ImportError: asyncua is missing"),
        "sweep": _entry(None, error="RuntimeError: a client failed:\n  File \"/home/x.py\"\n"
                                    "ConnectionError: client is disconnected"),
    })
    text = report.markdown(run)
    assert "2026-12-07 20:00:00 UTC, commit abcdef1234 with local changes" in text
    assert "Test CPU, 2 cores, Linux-test, Python 3.11.7, load average 0.50 / 0.25 / 1.50" in text
    assert "numpy 2.4.6; not installed: ray." in text
    assert "| routing | failed | 0 / 1 | p99 < 50 us | 3.0 | - | - |" in text
    assert "| serve | error | 0 / 0 | ImportError: asyncua is missing | 3.0 |" in text
    assert "| MC_MoveAbsolute(axis, execute=True, ...) us/call | 1.250 |" in text  # its renderer
    assert "| bulk.per_call_us | 0.250 |" in text  # a key the renderer does not read
    assert "| <= 2.0 us | 1.250 | met |" in text
    assert "| a goal not judged | - | not judged |" in text
    assert "| movers | 4 |" in text and "| 1000 | 80 | 7 |" in text  # no renderer: generic
    assert "| p99 < 50 us | 80 | **missed** |" in text
    assert "```\nImportError: asyncua is missing\n```" in text
    assert ("```\nRuntimeError: a client failed:\n...\nConnectionError: client is disconnected"
            "\n```") in text and "/home/x.py" not in text  # a traceback's ends only


def test_a_renderer_that_cannot_read_an_older_file_gives_way_to_generic_tables() -> None:
    results = _fbcall()
    del results["fb_call_us"]
    lines = report.figures("fbcall", results)
    assert lines[0] == "All figures (generic tables):"
    assert "| fb_call_bare_us | 0.500 |" in lines


def test_fill_keeps_the_hand_written_text_and_is_stable() -> None:
    run = _run({"fbcall": _entry(_fbcall(), {"fb_call_us": _goal("<= 2.0 us", 1.25, True)})})
    page = ("# B\n\n<!-- generated figures: summary -->\n<!-- end of generated figures -->\n\n"
            "## fbcall\n\nwhat it does\n\n<!-- generated figures: fbcall -->\nstale\n"
            "<!-- end of generated figures -->\n\n## axes\n\n<!-- generated figures: axes -->\n"
            "<!-- end of generated figures -->\n\ntail\n")
    filled = report.fill(page, run)
    assert report.fill(filled, run) == filled
    assert "stale" not in filled and "what it does" in filled and filled.endswith("\ntail\n")
    assert "| [fbcall](#fbcall) | passed | 1 / 1 | - | 3.0 |" in filled
    assert "`axes` was not part of the run of 2026-12-07." in filled
    assert "### fbcall" not in filled  # its figures are in its own section


def test_fill_and_load_refuse_what_they_cannot_use(tmp_path: Path) -> None:
    run = _run({})
    with pytest.raises(ConfigError, match="no <!-- generated figures: summary --> block"):
        report.fill("# nothing\n", run)
    with pytest.raises(ConfigError, match="unknown benchmark: nope"):
        report.fill("<!-- generated figures: summary -->\n<!-- end of generated figures -->\n"
                    "<!-- generated figures: nope -->\n<!-- end of generated figures -->\n", run)
    bad = tmp_path / "run.json"
    bad.write_text(json.dumps({"format": 0, "benchmarks": {}}))
    with pytest.raises(ConfigError, match="not a file of `openmotion bench all`"):
        report.load_run(bad)
    bad.write_text(json.dumps(run))
    assert report.load_run(bad) == run


def test_cli_report_prints_markdown_and_refuses_a_bad_file(tmp_path: Path) -> None:
    runner = CliRunner()
    file = tmp_path / "all.json"
    file.write_text("{")
    bad = runner.invoke(app, ["bench", "report", str(file)])
    assert bad.exit_code == 2 and "cannot read a bench all file" in bad.stderr
    file.write_text(json.dumps(_run({"fbcall": _entry(_fbcall())})))
    good = runner.invoke(app, ["bench", "report", str(file)])
    assert good.exit_code == 0 and good.stdout.startswith("# Current figures\n")
    assert "### fbcall" in good.stdout


# -- the published figures ---------------------------------------------------------------------


def test_the_published_figures_are_those_of_the_committed_run() -> None:
    run = report.load_run(PUBLISHED)
    page = PAGE.read_text()
    assert report.fill(page, run) == page, f"docs/benchmarks.md is stale: run `{REGENERATE}`"
    assert set(run["benchmarks"]) <= set(BENCHMARK_NAMES)
