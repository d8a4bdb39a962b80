"""``openmotion view``: its options, its errors, and that it serves the scenario it is given."""

from __future__ import annotations

import socket
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

import openmotion.viewer
from openmotion.cli import app
from openmotion.scenario import examples_dir

runner = CliRunner()


def test_view_help_lists_its_options() -> None:
    result = runner.invoke(app, ["view", "--help"])
    assert result.exit_code == 0
    for option in ("--speed", "--port", "--host", "--no-open", "--start-now"):
        assert option in result.output


def test_view_serves_the_scenario(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[dict[str, Any]] = []

    def serve(session: Any, host: str, port: int, **options: Any) -> None:
        calls.append({"session": session, "host": host, "port": port, **options})
        options["announce"]("http://127.0.0.1:9999/")

    monkeypatch.setattr(openmotion.viewer, "serve", serve)
    path = examples_dir() / "ca_tracks.yaml"
    result = runner.invoke(app, ["view", str(path), "--speed", "0.5", "--port", "9999",
                                 "--no-open"])
    assert result.exit_code == 0, result.output
    (call,) = calls
    assert call["session"].machine.name == "CA tracks and geo-compensation"
    assert call["session"].speed == 0.5 and call["session"].restartable
    assert call["session"].waiting  # the scenario starts when the first page connects
    assert (call["host"], call["port"], call["open_browser"]) == ("127.0.0.1", 9999, False)
    assert result.stderr == ("openmotion view: http://127.0.0.1:9999/ (Ctrl+C stops; the "
                             "scenario starts when the page connects)\n")


def test_view_without_a_scenario_shows_the_default_one(monkeypatch: pytest.MonkeyPatch) -> None:
    names: list[str] = []
    monkeypatch.setattr(openmotion.viewer, "serve",
                        lambda session, *args, **options: names.append(session.machine.name))
    assert runner.invoke(app, ["view"]).exit_code == 0
    assert names == ["single move"]


def test_view_start_now_starts_the_scenario_without_a_page(
        monkeypatch: pytest.MonkeyPatch) -> None:
    sessions: list[Any] = []
    monkeypatch.setattr(openmotion.viewer, "serve",
                        lambda session, *args, **options: sessions.append(session))
    assert runner.invoke(app, ["view", "--start-now", "--no-open"]).exit_code == 0
    (session,) = sessions
    assert not session.waiting and not session.paused


def test_view_config_error_is_one_line_and_exit_2(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: bad\naxes:\n  - name: x\n    parameters: {max_velocity: -1}\n")
    result = runner.invoke(app, ["view", str(bad), "--no-open"])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"ConfigError: {bad}:4: ")


def test_view_refuses_a_bad_speed() -> None:
    result = runner.invoke(app, ["view", "--speed", "0", "--no-open"])
    assert result.exit_code == 2
    assert result.stderr == "error: speed: must be a number from 0.01 to 1000, got 0.0\n"


def test_view_on_a_port_in_use_is_an_error() -> None:
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        result = runner.invoke(app, ["view", "--port", str(port), "--no-open"])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"error: cannot listen on 127.0.0.1:{port}: ")
