"""ADS security: loopback by default, read-only unless told, writers by AMS NetId; a
refused write is ADSERR_DEVICE_ACCESSDENIED and leaves the machine as it was."""

from __future__ import annotations

import itertools
import socket
from collections.abc import Iterator

import pytest

pyads = pytest.importorskip("pyads")

from openmotion.core.errors import ConfigError  # noqa: E402
from openmotion.endpoints import MachineHost  # noqa: E402
from openmotion.endpoints.ads import AdsServer  # noqa: E402
from openmotion.runtime.runtime import Runtime  # noqa: E402

ACCESS_DENIED = 0x723  # ADSERR_DEVICE_ACCESSDENIED
NOT_PERMITTED = 0x704  # ADSERR_DEVICE_INVALIDACCESS: a read-only symbol
_NET_IDS = itertools.count(1)


@pytest.fixture
def host() -> Iterator[MachineHost]:
    runtime = Runtime()
    runtime.add_axis("x")
    served = MachineHost(runtime, pace="lockstep").start()
    served.switch("x", "power", {"enable": True})
    try:
        yield served
    finally:
        served.stop()


def connect(server: AdsServer) -> pyads.Connection:
    n = next(_NET_IDS)
    conn = pyads.Connection(f"127.0.2.{n}.1.1", 851, f"127.0.0.1:{server.port}")
    conn.open()
    conn.set_timeout(3000)
    return conn


def test_the_default_bind_is_loopback(host: MachineHost) -> None:
    server = AdsServer(host, port=0)
    assert server.address == "127.0.0.1"
    with server:
        assert server._listener.getsockname()[0] == "127.0.0.1"
        with socket.create_connection(("127.0.0.1", server.port), timeout=2.0):
            pass


def test_a_read_only_server_refuses_every_write_and_the_machine_stays(host) -> None:
    with AdsServer(host, port=0) as server:
        conn = connect(server)
        try:
            for name, value in (("x.MoveAbsolute.Position", 50.0),
                                ("x.MoveAbsolute.Velocity", 100.0),
                                ("x.MoveAbsolute.Execute", True), ("x.Power.Enable", False),
                                ("Host.Step", 100)):
                with pytest.raises(pyads.ADSError) as refused:
                    conn.write_by_name(name, value)
                assert refused.value.err_code == ACCESS_DENIED, name
            errors = conn.write_list_by_name({"x.MoveAbsolute.Execute": True,
                                              "Host.RunFor": 1.0})
            assert set(errors.values()) == {"access denied"}
            assert host.snapshot.cycle == 0 and not host.snapshot.handles
            assert conn.read_list_by_name(["x.MoveAbsolute.Position",
                                           "x.MoveAbsolute.Execute"]) == \
                {"x.MoveAbsolute.Position": 0.0, "x.MoveAbsolute.Execute": False}
            host.advance(100)
            assert host.value("x.position") == 0.0
            assert conn.read_by_name("Host.Cycle") == 100  # reads go on
        finally:
            conn.close()


def test_writers_are_named_by_their_ams_net_id(host: MachineHost) -> None:
    probe = AdsServer(host, port=0).start()
    conn = connect(probe)
    local = conn.get_local_address().netid
    conn.close()
    probe.stop()
    with AdsServer(host, port=0, writable=[local]) as server:
        conn = connect(server)
        try:
            conn.write_by_name("x.MoveAbsolute.Position", 5.0)
            assert conn.read_by_name("x.MoveAbsolute.Position") == 5.0
            with pytest.raises(pyads.ADSError) as read_only:  # a signal is never written
                conn.write_by_name("x.NcToPlc.ActPos", 1.0)
            assert read_only.value.err_code == NOT_PERMITTED
        finally:
            conn.close()
    with AdsServer(host, port=0, writable=["10.1.2.3.1.1"]) as server:
        conn = connect(server)
        try:
            with pytest.raises(pyads.ADSError) as refused:
                conn.write_by_name("x.MoveAbsolute.Position", 7.0)
            assert refused.value.err_code == ACCESS_DENIED
            assert conn.read_by_name("x.MoveAbsolute.Position") == 0.0
        finally:
            conn.close()


@pytest.mark.parametrize("writable", ["127.0.0.1.1.1", ["1.2.3"], ["1.2.3.4.5.300"]])
def test_bad_writer_lists_are_config_errors(host: MachineHost, writable) -> None:
    with pytest.raises(ConfigError, match="AMS NetId|string"):
        AdsServer(host, port=0, writable=writable)
    assert AdsServer(host, port=0, writable=["1.2.3.4.5.6"]).port == 0
