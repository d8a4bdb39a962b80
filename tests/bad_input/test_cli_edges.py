"""Issue 18, the command line's edges: bad ports, hosts, names and flags answer with exit 2 and
one plain line on stderr, never a traceback, and the next valid command works."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from openmotion.bench import BENCHMARK_NAMES
from openmotion.cli import app
from openmotion.examples import list_examples

runner = CliRunner()


@pytest.fixture(autouse=True)
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture
def served(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, int]]:
    """``view`` up to the point where it would listen: the addresses it would serve."""
    import openmotion.viewer

    calls: list[tuple[str, int]] = []
    monkeypatch.setattr(openmotion.viewer, "serve",
                        lambda session, host, port, **_: calls.append((host, port)))
    return calls


def _plain_error(result) -> str:
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and result.exception is None or \
        isinstance(result.exception, SystemExit)
    return result.stderr


@pytest.mark.parametrize("port", ["99999", "65536", "-1", "http"])
def test_view_refuses_a_port_outside_0_to_65535(port: str, served) -> None:
    err = _plain_error(runner.invoke(app, ["view", "--no-open", "--port", port]))
    assert "--port" in err
    assert served == []
    ok = runner.invoke(app, ["view", "--no-open", "--port", "0"])
    assert ok.exit_code == 0, ok.output
    assert served == [("127.0.0.1", 0)]


@pytest.mark.parametrize("host", ["bad host!", "-leading.dash", "a..b", "x" * 254, ""])
def test_view_refuses_a_host_that_is_no_address_or_name(host: str, served) -> None:
    err = _plain_error(runner.invoke(app, ["view", "--no-open", "--host", host]))
    assert "neither an IP address nor a host name" in err
    assert served == []


@pytest.mark.parametrize("host", ["127.0.0.1", "::1", "localhost", "127.0.0.2"])
def test_loopback_hosts_are_served_without_a_warning(host: str, served) -> None:
    result = runner.invoke(app, ["view", "--no-open", "--host", host])
    assert result.exit_code == 0, result.output
    assert "warning" not in result.stderr and served == [(host, 8765)]


@pytest.mark.parametrize("host", ["0.0.0.0", "192.0.2.7", "machine.example"])
def test_any_other_host_is_served_with_a_plain_warning(host: str, served) -> None:
    result = runner.invoke(app, ["view", "--no-open", "--host", host])
    assert result.exit_code == 0, result.output
    assert f"warning: listening on {host}" in result.stderr
    assert served == [(host, 8765)]


def test_an_unknown_scenario_name_says_where_to_look(served) -> None:
    for command in (["run"], ["check"], ["view", "--no-open"]):
        err = _plain_error(runner.invoke(app, [*command, "no_such_example"]))
        assert err == ("error: no_such_example: no such file, and no shipped example of that "
                       "name ('openmotion examples' lists them)\n")
    assert runner.invoke(app, ["check", "single_move"]).exit_code == 0


def test_bench_help_and_errors_name_every_benchmark_and_nothing_outside_the_repo() -> None:
    help_text = " ".join(runner.invoke(app, ["bench", "--help"]).stdout.split())
    for name in BENCHMARK_NAMES:
        assert re.search(rf"\b{name}\b", help_text), name
    assert "performance.md" not in help_text
    err = _plain_error(runner.invoke(app, ["bench", "nope"]))
    assert err == (f"error: unknown benchmark 'nope'; choose one of: "
                   f"{', '.join(BENCHMARK_NAMES)}, all, report\n")


@pytest.mark.parametrize("command", ["run", "view", "bench", "examples"])
def test_boolean_flags_show_as_flags(command: str) -> None:
    text = runner.invoke(app, [command, "--help"]).stdout
    assert "<bool>" not in text and "BOOLEAN" not in text
    flags = {"run": ["--json", "--quiet"], "view": ["--no-open"], "bench": ["--json", "--quick"],
             "examples": ["--json"]}[command]
    for flag in [*flags, "--help"]:
        line = next(line for line in text.splitlines()
                    if re.match(rf"\s*(-\w, )?{flag}\b", line))
        after = line.split(flag, 1)[1]
        assert not after.startswith((" <", " TEXT", " INTEGER")), line


def test_examples_lists_every_shipped_scenario_and_run_finds_one_by_name(in_tmp) -> None:
    result = runner.invoke(app, ["examples"])
    assert result.exit_code == 0
    names = [line.split()[0] for line in result.stdout.splitlines()]
    assert names == [example.name for example in list_examples()] and len(names) >= 19
    assert "single_move" in names and "run one with 'openmotion run NAME'" in result.stderr
    run = runner.invoke(app, ["run", "touch_probe", "--quiet", "--trace", "t.csv"])
    assert run.exit_code == 0 and (in_tmp / "t.csv").exists()
    assert runner.invoke(app, ["run", "touch_probe.yaml", "--quiet"]).exit_code == 0


def test_a_file_in_the_working_directory_wins_over_an_example_of_the_same_name(in_tmp) -> None:
    (in_tmp / "single_move").write_text("name: mine\naxes: [{name: q}]\n")
    result = runner.invoke(app, ["check", "single_move"])
    assert result.exit_code == 0 and result.stdout.startswith("single_move: ok (1 axes")
