"""``openmotion serve`` and ``endpoints.serve``: options, errors, and that it serves."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from openmotion.cli import app
from openmotion.core.errors import ConfigError
from openmotion.endpoints import ENDPOINTS, EndpointUnavailable, serve
from openmotion.endpoints.serve import endpoint_class, is_loopback

runner = CliRunner()


def test_serve_help_lists_its_options() -> None:
    result = runner.invoke(app, ["serve", "--help"])
    assert result.exit_code == 0
    for option in ("--pace", "--speed", "--kernel", "--opcua", "--opcua-port", "--ads",
                   "--ads-port", "--bind", "--user", "--users-file", "--writable", "--duration"):
        assert option in result.output


@pytest.mark.parametrize(("arguments", "message"), [
    (["--pace", "fast", "--opcua"], "--pace must be wall or lockstep"),
    (["--kernel", "fibre", "--opcua"], "--kernel must be process or thread"),
    (["--kernel-priority", "urgent", "--opcua"], "--kernel-priority must be realtime"),
    ([], "choose at least one endpoint"),
    (["--opcua", "--bind", "not a host!"], "--bind 'not a host!' is neither"),
    (["--opcua", "--user", "nopassword"], "NAME:PASSWORD"),
    (["--opcua", "--writable", "--user", "a:b"], "choose one"),
    (["--opcua", "--speed", "0"], "speed must be a number"),
    (["--opcua", "--opcua-security", "rot13"], "rot13"),
    (["--opcua", "--users-file", "/no/such/users"], "cannot read the users file"),
    (["no_such_scenario", "--opcua"], "no such file"),
])
def test_bad_flags_exit_2_with_a_message(arguments: list[str], message: str) -> None:
    result = runner.invoke(app, ["serve", *arguments, "--opcua-port", "0", "--duration", "0"])
    assert result.exit_code == 2, result.output
    assert message in result.output
    # the command is usable right after: a valid call serves and stops
    assert runner.invoke(app, ["serve", "--help"]).exit_code == 0


@pytest.mark.parametrize("kernel", ["process", "thread"])
def test_serve_serves_and_stops_after_its_duration(tmp_path: Path, kernel: str) -> None:
    users = tmp_path / "users"
    users.write_text("# who may command\noperator:secret\n", encoding="utf-8")
    result = runner.invoke(app, ["serve", "single_move", "--opcua", "--opcua-port", "0",
                                 "--pace", "lockstep", "--users-file", str(users),
                                 "--kernel", kernel, "--duration", "0.2"])
    assert result.exit_code == 0, result.output
    assert "opcua opc.tcp://127.0.0.1:" in result.output
    assert "stopped: t = 0.000 s (cycle 0) · lockstep" in result.output
    assert "warning" not in result.output


def test_a_non_loopback_bind_warns() -> None:
    result = runner.invoke(app, ["serve", "single_move", "--opcua", "--opcua-port", "0",
                                 "--bind", "0.0.0.0", "--pace", "lockstep",
                                 "--duration", "0"])
    assert result.exit_code == 0, result.output
    assert "warning: listening on 0.0.0.0" in result.output


def test_a_missing_endpoint_library_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(ENDPOINTS, "ads", ("openmotion.no_such_module", "AdsServer",
                                           "endpoints"))
    with pytest.raises(EndpointUnavailable, match=r"pip install 'openmotion\[endpoints\]'"):
        endpoint_class("ads")
    result = runner.invoke(app, ["serve", "single_move", "--ads", "--duration", "0"])
    assert result.exit_code == 2
    assert "openmotion[endpoints]" in result.output
    with pytest.raises(ConfigError, match="no endpoint 'modbus'"):
        endpoint_class("modbus")


def test_serve_in_python_starts_and_stops_a_host_with_its_endpoints() -> None:
    served = serve("single_move", pace="lockstep", opcua={"port": 0})
    assert not served.host.running
    with served:
        assert served.host.running
        assert served.urls()["opcua"].startswith("opc.tcp://127.0.0.1:")
        assert "lockstep" in served.line()
    assert serve(served.host, opcua=True).host is served.host  # a host of one's own
    assert not served.host.running and not served.endpoints
    with pytest.raises(ConfigError, match="at least one endpoint"):
        serve("single_move")


@pytest.mark.parametrize(("address", "loopback"), [
    ("127.0.0.1", True), ("::1", True), ("localhost", True), ("0.0.0.0", False),
    ("192.168.0.10", False), ("plc.example", False)])
def test_loopback_addresses(address: str, loopback: bool) -> None:
    assert is_loopback(address) is loopback


def test_the_endpoints_package_loads_no_endpoint_library() -> None:
    """asyncua stays optional: importing the endpoints (and the CLI) does not load it."""
    import subprocess
    import sys

    code = ("import sys, openmotion.endpoints, openmotion.cli; "
            "print('asyncua' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            timeout=120, check=True)
    assert result.stdout.strip() == "False"
