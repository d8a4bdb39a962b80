"""The ADS server with the real pyads client: reads by name, by handle and in sums, symbol
upload, a move driven by Execute, lockstep control and notifications over the wire."""

from __future__ import annotations

import itertools
import json
import re
import struct
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

pyads = pytest.importorskip("pyads")

from openmotion.core.errors import ConfigError  # noqa: E402
from openmotion.endpoints import MachineHost, ProcessHost  # noqa: E402
from openmotion.endpoints.ads import AdsServer  # noqa: E402
from openmotion.endpoints.ads_symbols import NC_TO_PLC, camel  # noqa: E402
from openmotion.runtime.runtime import Runtime  # noqa: E402

EXAMPLES = sorted((Path(__file__).parents[2] / "examples").glob("*.yaml"))
_NET_IDS = itertools.count(1)


def net_id() -> str:
    """A target AMS NetId no other connection of this process routes (AdsLib keeps one
    route table per process)."""
    n = next(_NET_IDS)
    return f"127.0.{n // 200}.{n % 200 + 1}.1.1"


def connect(server: AdsServer) -> pyads.Connection:
    conn = pyads.Connection(net_id(), 851, f"127.0.0.1:{server.port}")
    conn.open()
    conn.set_timeout(3000)
    return conn


def two_axes() -> Runtime:
    runtime = Runtime()
    runtime.add_axis("x", max_velocity=500.0, acceleration=2000.0, deceleration=2000.0,
                     jerk=20000.0)
    runtime.add_axis("y")
    return runtime


@pytest.fixture(params=[MachineHost, ProcessHost], ids=["kernel-thread", "kernel-process"])
def served(request) -> Iterator[tuple[MachineHost, AdsServer, pyads.Connection]]:
    """The same server on a kernel thread and on a kernel process (D-320)."""
    host = request.param(two_axes(), pace="lockstep").prepare()
    host.start()
    server = AdsServer(host, port=0, writable=True).start()
    conn = connect(server)
    try:
        yield host, server, conn
    finally:
        conn.close()
        server.stop()
        host.stop()


def test_a_stock_client_connects_on_the_default_port() -> None:
    """pyads as it is used against a PLC: no port in the address (AMS/TCP's 48898)."""
    host = MachineHost(two_axes(), pace="lockstep")
    server = AdsServer(host)
    assert server.port == 48898
    try:
        server.start()
    except ConfigError as error:  # another program serves ADS on this machine
        pytest.skip(str(error))
    try:
        conn = pyads.Connection(net_id(), 851, "127.0.0.1")
        conn.open()
        try:
            assert conn.read_by_name("x.NcToPlc.ActPos") == 0.0
        finally:
            conn.close()
    finally:
        server.stop()


def test_device_info_and_state(served) -> None:
    _, _, conn = served
    name, version = conn.read_device_info()
    assert name == "openmotion" and (version.version, version.revision) == (3, 1)
    assert conn.read_state() == (pyads.ADSSTATE_RUN, 0)


def test_reads_by_name_by_handle_and_by_sum_read_show_one_snapshot(served) -> None:
    host, _, conn = served
    conn.write_by_name("x.Power.Enable", True)
    conn.write_list_by_name({"x.MoveVelocity.Velocity": 100.0, "x.MoveVelocity.Execute": True})
    conn.write_by_name("Host.Step", 50)
    expected = host.value("x.position")
    assert 0 < expected < 5
    assert conn.read_by_name("x.NcToPlc.ActPos", pyads.PLCTYPE_LREAL) == expected
    assert conn.read_by_name("x.NcToPlc.ActPos") == expected  # typed from the symbol
    handle = conn.get_handle("x.NcToPlc.ActVelo")
    assert conn.read_by_name("", pyads.PLCTYPE_LREAL, handle=handle) == \
        host.value("x.velocity")
    conn.release_handle(handle)
    with pytest.raises(pyads.ADSError) as released:  # a released handle reads no more
        conn.read_by_name("", pyads.PLCTYPE_LREAL, handle=handle)
    assert released.value.err_code == 0x710
    values = conn.read_list_by_name(["x.NcToPlc.ActPos", "x.NcToPlc.AxisState", "Host.Cycle",
                                     "y.NcToPlc.ActPos", "x.MoveVelocity.Busy"])
    assert values == {"x.NcToPlc.ActPos": expected, "x.NcToPlc.AxisState": 4,
                      "Host.Cycle": 50, "y.NcToPlc.ActPos": 0.0, "x.MoveVelocity.Busy": True}
    with pytest.raises(pyads.ADSError) as unknown:
        conn.read_by_name("x.NcToPlc.NoSuchThing", pyads.PLCTYPE_LREAL)
    assert unknown.value.err_code == 0x710  # ADSERR_DEVICE_SYMBOLNOTFOUND
    assert conn.read_by_name("Host.Cycle") == 50  # and the server serves on


def test_sum_write_reports_each_item(served) -> None:
    host, _, conn = served
    result = conn.write_list_by_name({"x.MoveAbsolute.Position": 12.5,
                                      "x.NcToPlc.ActPos": 1.0})
    assert result == {"x.MoveAbsolute.Position": "no error",
                      "x.NcToPlc.ActPos": "reading/writing not permitted"}
    assert conn.read_by_name("x.MoveAbsolute.Position") == 12.5
    # inputs never written read their defaults: an enum's number, 0 for MC_DEFAULT
    buffer_mode = next(put for put in host.command("x", "move_absolute").inputs
                       if put.name == "buffer_mode")
    assert conn.read_list_by_name(["x.MoveAbsolute.BufferMode",
                                   "x.MoveAbsolute.Acceleration"]) == \
        {"x.MoveAbsolute.BufferMode": buffer_mode.input.default.value,
         "x.MoveAbsolute.Acceleration": 0.0}


def test_a_move_driven_by_execute_reports_done(served) -> None:
    host, _, conn = served
    conn.write_by_name("x.Power.Enable", True)
    assert conn.read_by_name("x.Power.Status") is True
    conn.write_list_by_name({"x.MoveAbsolute.Position": 100.0,
                             "x.MoveAbsolute.Velocity": 250.0,
                             "x.MoveAbsolute.BufferMode": 0})
    conn.write_by_name("x.MoveAbsolute.Execute", True)
    assert conn.read_list_by_name(["x.MoveAbsolute.Busy", "x.MoveAbsolute.Done"]) == \
        {"x.MoveAbsolute.Busy": True, "x.MoveAbsolute.Done": False}
    conn.write_by_name("Host.RunFor", 1.0)
    outputs = conn.read_list_by_name([f"x.MoveAbsolute.{name}" for name in
                                      ("Done", "Busy", "Error", "ErrorID")])
    assert outputs == {"x.MoveAbsolute.Done": True, "x.MoveAbsolute.Busy": False,
                       "x.MoveAbsolute.Error": False, "x.MoveAbsolute.ErrorID": 0}
    assert conn.read_by_name("x.NcToPlc.ActPos") == pytest.approx(100.0, abs=1e-6)
    conn.write_by_name("x.MoveAbsolute.Execute", False)  # outputs reset with Execute
    assert conn.read_by_name("x.MoveAbsolute.Done") is False
    # a value the command cannot take: Error and an ErrorID, the axis stays where it is
    conn.write_list_by_name({"x.MoveAbsolute.Position": 0.0, "x.MoveAbsolute.BufferMode": 99,
                             "x.MoveAbsolute.Execute": True})
    assert conn.read_list_by_name(["x.MoveAbsolute.Error", "x.MoveAbsolute.ErrorID"]) == \
        {"x.MoveAbsolute.Error": True, "x.MoveAbsolute.ErrorID": 0x706}
    conn.write_by_name("Host.Step", 100)
    assert host.value("x.position") == pytest.approx(100.0, abs=1e-6)
    # a new rising edge with good inputs moves again
    conn.write_by_name("x.MoveAbsolute.Execute", False)
    conn.write_list_by_name({"x.MoveAbsolute.BufferMode": 0, "x.MoveAbsolute.Execute": True})
    conn.write_by_name("Host.RunFor", 1.0)
    assert conn.read_by_name("x.MoveAbsolute.Done") is True
    assert host.value("x.position") == pytest.approx(0.0, abs=1e-6)


def test_lockstep_control_symbols(served) -> None:
    _, _, conn = served
    conn.write_by_name("Host.Step", 10)
    conn.write_by_name("Host.RunFor", 0.05)
    assert conn.read_by_name("Host.Cycle") == 60
    assert conn.read_by_name("Host.Time") == pytest.approx(0.06)
    with pytest.raises(pyads.ADSError) as refused:
        conn.write_by_name("Host.RunFor", -1.0)
    assert refused.value.err_code == 0x706
    assert conn.read_by_name("Host.Cycle") == 60


def test_a_wall_paced_machine_refuses_steps() -> None:
    host = MachineHost(two_axes(), pace="wall").start()
    try:
        with AdsServer(host, port=0, writable=True) as server:
            conn = connect(server)
            try:
                with pytest.raises(pyads.ADSError) as refused:
                    conn.write_by_name("Host.Step", 5)
                assert refused.value.err_code == 0x707  # device not ready
                assert conn.read_by_name("Host.Cycle") >= 0
            finally:
                conn.close()
    finally:
        host.stop()


def test_notifications_arrive_and_stop_when_deleted(served) -> None:
    _, _, conn = served
    cycles: list[int] = []

    def on_cycle(notification, name) -> None:
        cycles.append(conn.parse_notification(notification, pyads.PLCTYPE_UDINT)[2])

    attrib = pyads.NotificationAttrib(4, trans_mode=pyads.ADSTRANS_SERVERONCHA)
    handles = conn.add_device_notification("Host.Cycle", attrib, on_cycle)
    try:
        _wait_for(lambda: cycles == [0])  # the value at once
        for _ in range(3):
            conn.write_by_name("Host.Step", 7)
            _wait_for(lambda: cycles and cycles[-1] == conn.read_by_name("Host.Cycle"))
    finally:
        conn.del_device_notification(*handles)
    assert cycles == [0, 7, 14, 21]
    conn.write_by_name("Host.Step", 7)
    with pytest.raises(TimeoutError):
        _wait_for(lambda: len(cycles) > 4, timeout=0.3)


def _wait_for(predicate, timeout: float = 3.0) -> None:
    import time
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > end:
            raise TimeoutError
        time.sleep(0.005)


CLIENT = textwrap.dedent("""
    import json, sys, time, pyads
    port, target = int(sys.argv[1]), sys.argv[2]
    conn = pyads.Connection(target, 851, f"127.0.0.1:{port}")
    conn.open()
    changes, cyclic = [], []
    def on_change(notification, name):
        changes.append(conn.parse_notification(notification, pyads.PLCTYPE_UDINT)[2])
    def on_cycle(notification, name):
        handle, stamp, value = conn.parse_notification(notification, pyads.PLCTYPE_LREAL)
        cyclic.append([stamp.timestamp(), value])
    a = conn.add_device_notification("Host.Cycle", pyads.NotificationAttrib(4), on_change)
    b = conn.add_device_notification(
        "x.NcToPlc.ActPos", pyads.NotificationAttrib(
            8, trans_mode=pyads.ADSTRANS_SERVERCYCLE, cycle_time=20), on_cycle)
    def wait_for(cycle):
        end = time.monotonic() + 5.0
        while not (changes and changes[-1] == cycle) and time.monotonic() < end:
            time.sleep(0.005)
    wait_for(0)
    for step in range(1, 6):
        conn.write_by_name("Host.Step", 3)
        wait_for(3 * step)
    time.sleep(0.2)
    conn.del_device_notification(*a)
    conn.del_device_notification(*b)
    conn.close()
    print(json.dumps({"changes": changes, "cyclic": cyclic}))
""")


def test_notifications_cross_the_wire_to_a_client_process(served) -> None:
    host, server, _ = served
    result = subprocess.run([sys.executable, "-c", CLIENT, str(server.port), net_id()],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    received = json.loads(result.stdout.strip().splitlines()[-1])
    assert received["changes"] == [0, 3, 6, 9, 12, 15]  # on change: each new value once
    cyclic = received["cyclic"]
    assert len(cyclic) >= 3  # cyclic: the value again each cycle, changed or not
    assert all(value == 0.0 for _, value in cyclic)
    stamps = [stamp for stamp, _ in cyclic]
    assert stamps == sorted(stamps) and len(set(stamps)) == len(stamps)
    assert host.snapshot.cycle == 15


def _expected_symbols(host: MachineHost) -> dict[str, str]:
    """The symbols the machine model says there must be, with their types."""
    expected: dict[str, str] = {}
    types = {bool: "BOOL", float: "LREAL"}
    seen: set[str] = set()
    for obj in host.model:
        group = "NcToPlc" if obj.kind == "axis" else "Status"
        if f"{obj.name}.{group}" in seen:
            group = camel(obj.kind) + "Status"
        seen.add(f"{obj.name}.{group}")
        for signal in obj.signals:
            alias = NC_TO_PLC.get(signal.name) if obj.kind == "axis" else None
            kind = types.get(signal.dtype) or \
                ("UDINT" if "error" in signal.dtype.__name__.lower() else "DINT")
            expected[f"{obj.name}.{group}.{alias or camel(signal.name)}"] = kind
        for command in host.commands[obj.name]:
            if command.owner is obj:
                last = "Status" if command.spec.level else "Execute"
                expected[f"{obj.name}.{camel(command.name)}.{last}"] = "BOOL"
    return expected


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda path: path.stem)
def test_symbol_upload_lists_the_typed_symbols_of_every_example(example: Path) -> None:
    host = MachineHost.for_scenario(example, pace="lockstep")
    with AdsServer(host, port=0) as server:
        conn = connect(server)
        try:
            symbols = {symbol.name: symbol for symbol in conn.get_all_symbols()}
            for name, kind in _expected_symbols(host).items():
                assert symbols[name].symbol_type == kind, name
            assert {"Host.Cycle", "Host.Step", "Host.RunFor"} <= set(symbols)
            assert all(symbol.plc_type is not None for symbol in symbols.values())
            assert len(symbols) == len(server.symbols.symbols)
            cycle = symbols["Host.Cycle"]
            info = pyads.pyads_ex.adsGetSymbolInfo(conn._port, conn._adr, "Host.Cycle")
            assert (info.iGroup, info.iOffs, info.symbol_type) == \
                (cycle.index_group, cycle.index_offset, cycle.symbol_type)
            assert cycle.read() == host.snapshot.cycle  # by group and offset
        finally:
            conn.close()


def test_symbols_of_a_command_are_typed_from_its_inputs() -> None:
    host = MachineHost.for_scenario(EXAMPLES[0].parent / "gantry_contour.yaml",
                                    pace="lockstep")
    server = AdsServer(host, port=0)
    types = {symbol.name: symbol.type.name for symbol in server.symbols.symbols}
    assert types["x.MoveAbsolute.Position"] == "LREAL"
    assert types["x.MoveAbsolute.BufferMode"] == "DINT"
    assert types["x.GearIn.Master"] == "STRING(80)"
    assert types["x.Stop.Hold"] == "BOOL"
    assert types["x.MoveAbsolute.ErrorID"] == "UDINT"
    vectors = [name for name, kind in types.items() if kind.startswith("ARRAY [0..")]
    assert any(name.startswith("gantry.") for name in vectors)


def test_the_recipe_of_the_docs_runs() -> None:
    """docs/endpoints.md's ADS recipe, the server on a free port instead of 48898."""
    text = (Path(__file__).parents[2] / "docs" / "endpoints.md").read_text()
    section = text.split("## ADS", 1)[1].split("\n## ", 1)[0]
    serve, drive = re.findall(r"```python\n(.*?)```", section, flags=re.S)[:2]
    namespace: dict = {}
    exec(serve.replace("writable=True)", "writable=True, port=0)"), namespace)  # noqa: S102
    try:
        drive = drive.replace("127.0.0.1:48898", f"127.0.0.1:{namespace['server'].port}")
        drive = drive.replace('"127.0.0.1.1.1"', repr(net_id()))
        exec(drive, namespace)  # noqa: S102 - the docs must run
        assert namespace["host"].value("x.position") == pytest.approx(100.0, abs=1e-6)
    finally:
        namespace["server"].stop()
        namespace["host"].stop()


def test_the_data_type_upload_lists_the_types_the_symbols_use(served) -> None:
    _, server, conn = served
    info = bytes(conn.read(0xF00F, 0, pyads.PLCTYPE_BYTE * 24, return_ctypes=True))
    symbols, symbol_bytes, types, type_bytes = struct.unpack_from("<IIII", info)
    assert symbols == len(server.symbols.symbols) == len(conn.get_all_symbols())
    upload = bytes(conn.read(0xF00E, 0, pyads.PLCTYPE_BYTE * type_bytes, return_ctypes=True))
    names, position = [], 0
    for _ in range(types):
        # AdsDatatypeEntry: length, version, 2 hashes, size, offset, type, flags, 5 counts
        length, size, ads_type, name_length = struct.unpack_from("<I12xI4xI4xH", upload,
                                                                 position)
        names.append(upload[position + 42:position + 42 + name_length].decode())
        assert size > 0 and ads_type in (3, 5, 19, 30, 33)
        position += length
    assert position == type_bytes
    assert sorted(names) == sorted({symbol.type.name for symbol in server.symbols.symbols})


def test_an_axis_and_its_ca_mover_of_one_name_keep_both_structs() -> None:
    """ca_gear_in_pos: axis m1 is also CA mover m1; its commands and both signal structs."""
    host = MachineHost.for_scenario(EXAMPLES[0].parent / "ca_gear_in_pos.yaml",
                                    pace="lockstep")
    assert "move_absolute" in [command.name for command in host.commands["m1"]]
    names = {symbol.name for symbol in AdsServer(host, port=0).symbols.symbols}
    assert {"m1.NcToPlc.ActPos", "m1.Status.Gap", "m1.MoveAbsolute.Execute",
            "m1.Power.Enable"} <= names


def test_a_stopped_host_answers_not_ready_and_keeps_nothing() -> None:
    host = MachineHost(two_axes(), pace="lockstep")  # never started
    with AdsServer(host, port=0, writable=True) as server:
        conn = connect(server)
        try:
            conn.write_list_by_name({"x.MoveAbsolute.Position": 1.0,
                                     "x.MoveAbsolute.Velocity": 1.0})  # remembered only
            for name, value in (("x.Power.Enable", True), ("x.MoveAbsolute.Execute", True),
                                ("Host.Step", 1)):
                with pytest.raises(pyads.ADSError) as refused:
                    conn.write_by_name(name, value)
                assert refused.value.err_code == 0x707, name
            assert conn.read_list_by_name(["x.Power.Enable", "x.MoveAbsolute.Execute"]) == \
                {"x.Power.Enable": False, "x.MoveAbsolute.Execute": False}
        finally:
            conn.close()
