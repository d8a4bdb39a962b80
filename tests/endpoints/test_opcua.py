"""The OPC UA server, driven by a real asyncua client over loopback (docs/endpoints.md).

Every server here listens on 127.0.0.1 on a free port and is stopped by its fixture; the
machine runs in lockstep, so what a client sees after a Step is the same every run.
"""

from __future__ import annotations

import asyncio
import math
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

asyncua = pytest.importorskip("asyncua")
from asyncua import Client, ua  # noqa: E402
from asyncua.ua.uaerrors import UaStatusCodeError  # noqa: E402

import openmotion as om  # noqa: E402
from openmotion.core.errors import ConfigError  # noqa: E402
from openmotion.endpoints import MachineHost, serve  # noqa: E402
from openmotion.endpoints.opcua import NAMESPACE_URI, OpcUaServer  # noqa: E402
from openmotion.scenario import examples_dir  # noqa: E402

USER, PASSWORD = "operator", "secret"
WAIT = 5.0  #: longest wait for the writer to publish a snapshot [s]


def axis_host() -> MachineHost:
    rt = om.Runtime(cycle_time=0.001)
    rt.add_axis("x", max_velocity=500.0, acceleration=2000.0, jerk=20000.0)
    return MachineHost(rt, pace="lockstep")


@pytest.fixture(scope="module")
def served() -> Iterator[OpcUaServer]:
    """One axis in lockstep; anonymous clients read, the user commands."""
    host = axis_host().start()
    server = OpcUaServer(host, port=0, users={USER: PASSWORD}).start()
    yield server
    server.stop()
    host.stop()


def run(coroutine: Any) -> Any:
    return asyncio.run(coroutine)


def client(server: OpcUaServer, user: str | None = USER, password: str = PASSWORD) -> Client:
    found = Client(server.url, timeout=10)
    if user is not None:
        found.set_user(user)
        found.set_password(password)
    return found


class Ids:
    """NodeIds and browse names in the server's namespace."""

    def __init__(self, namespace: int) -> None:
        self.namespace = namespace

    def __call__(self, text: str) -> ua.NodeId:
        return ua.NodeId(text, self.namespace)

    def method(self, name: str) -> str:
        """A method by its browse name, as a client calls it on an object."""
        return f"{self.namespace}:{name}"


async def ids(c: Client) -> Ids:
    return Ids(await c.get_namespace_index(NAMESPACE_URI))


async def wait_cycle(c: Client, node: Any, cycle: int) -> None:
    """Until the Host.Cycle variable shows ``cycle`` (the writer copies every 10 ms)."""
    for _ in range(int(WAIT / 0.01)):
        if await c.get_node(node("Host.Cycle")).read_value() >= cycle:
            return
        await asyncio.sleep(0.01)
    raise AssertionError(f"Host.Cycle never reached {cycle}")


async def step(c: Client, node: Any, cycles: int) -> int:
    cycle, _ = await c.get_node(node("Host")).call_method(
        node("Host:Step"), ua.Variant(cycles, ua.VariantType.UInt32))
    await wait_cycle(c, node, cycle)
    return int(cycle)


async def raw_call(c: Client, node: Any, owner: str, method: str, *args: ua.Variant) \
        -> ua.CallMethodResult:
    method_id = node(f"Host:{method}") if owner == "Host" else node(f"type:axis:{method}")
    request = ua.CallMethodRequest(ObjectId=node(owner), MethodId=method_id,
                                   InputArguments=list(args))
    (result,) = await c.uaclient.call([request])
    return result


# -- the address space of every shipped example ----------------------------------------------

EXAMPLES = sorted(examples_dir().glob("*.yaml"))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda path: path.stem)
def test_address_space_of_every_example_is_its_machine_model(path: Path) -> None:
    host = MachineHost.for_scenario(path, pace="lockstep")
    with OpcUaServer(host, port=0) as server:
        run(_check_address_space(server, host))


async def _check_address_space(server: OpcUaServer, host: MachineHost) -> None:
    async with client(server, user=None) as c:
        node = await ids(c)
        found: dict[str, Any] = {}

        async def walk(parent: Any) -> None:
            for ref in await c.get_node(parent).get_children_descriptions():
                if ref.NodeClass == ua.NodeClass.Object:
                    found[ref.NodeId.Identifier] = ref
                    await walk(ref.NodeId)

        await walk(node("Machine"))
        assert len(found) == len(host.model)
        paths = iter(found)
        units: list[tuple[Any, str]] = []
        for obj in host.model:
            path = next(paths)
            assert path.rsplit("/", 1)[-1].split("~")[0] == obj.name
            children = await c.get_node(node(path)).get_children_descriptions()
            variables = [r.BrowseName.Name for r in children
                         if r.NodeClass == ua.NodeClass.Variable
                         and r.ReferenceTypeId == ua.NodeId(ua.ObjectIds.HasComponent)]
            methods = {r.BrowseName.Name: r.NodeId for r in children
                       if r.NodeClass == ua.NodeClass.Method}
            assert variables == [signal.name for signal in obj.signals]
            assert list(methods) == [command.name for command in host.commands_of(obj)]
            taking = [command for command in host.commands_of(obj) if command.inputs]
            arguments = await c.read_values([
                c.get_node(node(f"{methods[command.name].Identifier}#InputArguments"))
                for command in taking])
            assert [[arg.Name for arg in args] for args in arguments] == \
                [[put.name for put in command.inputs] for command in taking]
            units += [(node(f"{obj.name}.{s.name}#EngineeringUnits"), s.unit)
                      for s in obj.signals if s.unit and s.dtype is float]
        if units:
            values = await c.read_values([c.get_node(nid) for nid, _ in units])
            assert [value.DisplayName.Text for value in values] == [unit for _, unit in units]


def test_a_signal_has_its_data_type_and_unit_code(served: OpcUaServer) -> None:
    async def check() -> None:
        async with client(served, user=None) as c:
            node = await ids(c)
            position = c.get_node(node("x.position"))
            assert await position.read_data_type() == ua.NodeId(ua.ObjectIds.Double)
            assert await position.read_type_definition() == \
                ua.NodeId(ua.ObjectIds.AnalogUnitType)
            units = await (await position.get_child("0:EngineeringUnits")).read_value()
            assert units.UnitId == int.from_bytes(b"MMT", "big")  # UNECE millimetre
            state = c.get_node(node("x.state"))
            assert await state.read_data_type() == node("type:AxisState")
            enum = await c.get_node(node("type:AxisState")).get_child("0:EnumValues")
            names = {v.DisplayName.Text: v.Value for v in await enum.read_value()}
            assert names[om.AxisState.STANDSTILL.name] == int(om.AxisState.STANDSTILL)
            assert await c.get_node(node("x.homed")).read_data_type() == \
                ua.NodeId(ua.ObjectIds.Boolean)
    run(check())


# -- read, subscribe, command ----------------------------------------------------------------

def test_read_returns_the_values_of_one_published_cycle(served: OpcUaServer) -> None:
    host = served.host

    async def check() -> None:
        async with client(served) as c:
            node = await ids(c)
            cycle = await step(c, node, 7)
            names = ["Host.Cycle", *host.names]
            values = await c.read_values([c.get_node(node(name)) for name in names])
            snapshot = host.snapshot
            assert values[0] == snapshot.cycle == cycle
            for name, value in zip(host.names, values[1:], strict=True):
                expected = host.value(name, snapshot)
                assert value == pytest.approx(expected) or (
                    math.isnan(expected) and value is None), name
    run(check())


def test_a_subscription_gets_data_change_notifications(served: OpcUaServer) -> None:
    class Handler:
        def __init__(self) -> None:
            self.values: list[float] = []

        def datachange_notification(self, node: Any, value: Any, data: Any) -> None:
            self.values.append(value)

    async def check() -> None:
        async with client(served) as c:
            node = await ids(c)
            x = c.get_node(node("x"))
            await x.call_method(node.method("power"), True)
            handler = Handler()
            subscription = await c.create_subscription(10, handler)
            await subscription.subscribe_data_change(c.get_node(node("x.set_position")))
            start = len(handler.values)
            await x.call_method(node.method("move_relative"), 5.0, 100.0)
            for _ in range(10):
                await step(c, node, 20)
                await asyncio.sleep(0.03)
            await subscription.delete()
            assert len(set(handler.values[start:])) >= 3, handler.values
    run(check())


def test_a_move_started_by_a_method_reports_done_after_steps(served: OpcUaServer) -> None:
    async def check() -> None:
        async with client(served) as c:
            node = await ids(c)
            x = c.get_node(node("x"))
            assert await x.call_method(node.method("power"), True) is True
            await step(c, node, 1)
            start = await c.get_node(node("x.position")).read_value()
            ticket, command = await x.call_method(node.method("move_absolute"), start + 100.0,
                                                  250.0)
            assert command == node(f"Commands/{ticket}")
            outputs = {name: c.get_node(node(f"Commands/{ticket}.{name}"))
                       for name in ("Busy", "Done", "Error", "ErrorID", "CommandAborted")}
            assert await outputs["Busy"].read_value() is True
            assert await outputs["Done"].read_value() is False
            await step(c, node, 1500)
            for _ in range(int(WAIT / 0.01)):
                if await outputs["Done"].read_value():
                    break
                await asyncio.sleep(0.01)
            assert await outputs["Done"].read_value() is True
            assert await outputs["Busy"].read_value() is False
            assert await outputs["Error"].read_value() is False
            assert await outputs["ErrorID"].read_value() == 0
            position = await c.get_node(node("x.set_position")).read_value()
            assert position == pytest.approx(start + 100.0)
            owner = await c.get_node(command).get_child("0:Owner")
            assert await owner.read_value() == "x"
    run(check())


# -- Bad status codes, and the server serves on ----------------------------------------------

def test_unknown_nodes_and_bad_arguments_get_bad_status_codes(served: OpcUaServer) -> None:
    async def check() -> None:
        async with client(served) as c:
            node = await ids(c)
            with pytest.raises(UaStatusCodeError) as unknown:
                await c.get_node(node("x.no_such_signal")).read_value()
            assert unknown.value.code == ua.StatusCodes.BadNodeIdUnknown
            text = await raw_call(c, node, "x", "move_absolute",
                                  ua.Variant("far", ua.VariantType.String),
                                  ua.Variant(10.0, ua.VariantType.Double))
            assert text.StatusCode.value == ua.StatusCodes.BadInvalidArgument
            assert text.InputArgumentResults[0].value == ua.StatusCodes.BadTypeMismatch
            infinite = await raw_call(c, node, "x", "move_absolute",
                                      ua.Variant(math.inf, ua.VariantType.Double),
                                      ua.Variant(10.0, ua.VariantType.Double))
            assert infinite.StatusCode.value == ua.StatusCodes.BadInvalidArgument
            assert infinite.InputArgumentResults[0].value == ua.StatusCodes.BadOutOfRange
            assert "finite" in infinite.InputArgumentDiagnosticInfos[0].AdditionalInfo
            mode = await raw_call(c, node, "x", "move_absolute",
                                  ua.Variant(1.0, ua.VariantType.Double),
                                  ua.Variant(10.0, ua.VariantType.Double),
                                  *[ua.Variant(None)] * 3,
                                  ua.Variant(99, ua.VariantType.Int32))
            assert mode.InputArgumentResults[5].value == ua.StatusCodes.BadOutOfRange
            missing = await raw_call(c, node, "x", "move_absolute",
                                     ua.Variant(1.0, ua.VariantType.Double))
            assert missing.StatusCode.value == ua.StatusCodes.BadArgumentsMissing
            many = await raw_call(c, node, "x", "halt", *[ua.Variant(1.0)] * 9)
            assert many.StatusCode.value == ua.StatusCodes.BadTooManyArguments
            nowhere = await raw_call(c, node, "x", "no_such_command")
            assert nowhere.StatusCode.is_bad()
            elsewhere = await raw_call(c, node, "Host.Cycle", "halt")  # not an axis
            assert elsewhere.StatusCode.value in (ua.StatusCodes.BadMethodInvalid,
                                                  ua.StatusCodes.BadNodeIdInvalid)
            steps = await raw_call(c, node, "Host", "RunFor",
                                   ua.Variant(-1.0, ua.VariantType.Double))
            assert steps.InputArgumentResults[0].value == ua.StatusCodes.BadOutOfRange
            # nothing was started, and the server still serves: a valid call succeeds
            ticket, _ = await c.get_node(node("x")).call_method(
                node.method("halt"), ua.Variant(None), ua.Variant(None), "BUFFERED")
            assert ticket >= 1
            await step(c, node, 1)
            assert await c.get_node(node("x.state")).read_value() >= 0
    run(check())


def test_a_wall_paced_host_refuses_step_with_bad_invalid_state() -> None:
    host = MachineHost(axis_host().runtime, pace="wall")
    with host, OpcUaServer(host, port=0, writable=True) as server:
        async def check() -> None:
            async with client(server, user=None) as c:
                node = await ids(c)
                result = await raw_call(c, node, "Host", "Step",
                                        ua.Variant(1, ua.VariantType.UInt32))
                assert result.StatusCode.value == ua.StatusCodes.BadInvalidState
                await c.get_node(node("Host")).call_method(node("Host:SetSpeed"), 2.0)
                for _ in range(int(WAIT / 0.01)):
                    if await c.get_node(node("Host.Speed")).read_value() == 2.0:
                        break
                    await asyncio.sleep(0.01)
                assert host.speed == 2.0
                # anonymous clients command a writable server
                assert await c.get_node(node("x")).call_method(node.method("power"), True) is True
        run(check())


# -- security ---------------------------------------------------------------------------------

def test_anonymous_clients_read_but_neither_call_nor_write(served: OpcUaServer) -> None:
    async def check() -> None:
        async with client(served, user=None) as c:
            node = await ids(c)
            assert await c.get_node(node("x.position")).read_value() is not None
            with pytest.raises(UaStatusCodeError) as call:
                await c.get_node(node("x")).call_method(node.method("power"), True)
            assert call.value.code == ua.StatusCodes.BadUserAccessDenied
            with pytest.raises(UaStatusCodeError) as write:
                await c.get_node(node("x.position")).write_value(1.0)
            assert write.value.code == ua.StatusCodes.BadUserAccessDenied
            # the session is still served
            assert await c.get_node(node("Host.Pace")).read_value() == "lockstep"
        async with client(served) as c:  # a user may call, but signals are never written
            node = await ids(c)
            with pytest.raises(UaStatusCodeError) as write:
                await c.get_node(node("x.position")).write_value(1.0)
            assert write.value.code in (ua.StatusCodes.BadNotWritable,
                                        ua.StatusCodes.BadUserAccessDenied)
    run(check())


def test_a_wrong_password_is_refused(served: OpcUaServer) -> None:
    async def check() -> None:
        with pytest.raises(UaStatusCodeError) as refused:
            async with client(served, password="guess"):
                pass
        assert refused.value.code in (ua.StatusCodes.BadUserAccessDenied,
                                      ua.StatusCodes.BadIdentityTokenRejected)
    run(check())


def test_writable_and_users_together_are_refused() -> None:
    with pytest.raises(ConfigError, match="choose one"):
        OpcUaServer(axis_host(), port=0, writable=True, users={USER: PASSWORD})
    with pytest.raises(ConfigError, match="basic128"):
        OpcUaServer(axis_host(), port=0, security=("basic128",))


def test_the_default_bind_is_loopback() -> None:
    server = OpcUaServer(axis_host(), port=0)
    assert server.address == "127.0.0.1"
    assert server.url.startswith("opc.tcp://127.0.0.1:")
    serving = serve(axis_host(), opcua=True)
    assert serving.bind == "127.0.0.1"


def test_basic256sha256_with_a_trusted_client_certificate(tmp_path: Path) -> None:
    from asyncua.crypto.cert_gen import setup_self_signed_certificate
    from asyncua.crypto.security_policies import SecurityPolicyBasic256Sha256
    from cryptography.x509.oid import ExtendedKeyUsageOID

    key, certificate = tmp_path / "client_key.pem", tmp_path / "client_cert.der"
    uri = "urn:openmotion:test-client"
    run(setup_self_signed_certificate(key, certificate, uri, "localhost",
                                      [ExtendedKeyUsageOID.CLIENT_AUTH], {}))
    host = axis_host()
    with host, OpcUaServer(host, port=0, security=("basic256sha256",),
                           certificate_dir=tmp_path / "server",
                           certificates=(certificate,)) as server:
        assert (tmp_path / "server" / "server_cert.der").is_file()

        async def check() -> None:
            c = Client(server.url, timeout=10)
            c.application_uri = uri
            await c.set_security(SecurityPolicyBasic256Sha256, str(certificate), str(key),
                                 mode=ua.MessageSecurityMode.SignAndEncrypt)
            async with c:
                node = await ids(c)
                # the trusted certificate is the user: it commands without a password
                assert await c.get_node(node("x")).call_method(node.method("power"), True) is True
            plain = Client(server.url, timeout=10)
            with pytest.raises(Exception):  # noqa: B017 - no None policy offered
                async with plain:
                    pass
        run(check())


def test_stopped_servers_leave_no_thread_behind() -> None:
    before = set(threading.enumerate())
    host = axis_host()
    with host, OpcUaServer(host, port=0):
        started = set(threading.enumerate()) - before
        assert {thread.name for thread in started} >= {"openmotion-opcua", "openmotion-kernel"}
    assert not [thread for thread in started if thread.is_alive()]


def test_the_asyncua_recipe_of_the_docs_drives_the_example(capsys: pytest.CaptureFixture) \
        -> None:
    """docs/endpoints.md's client runs against the served example and prints what its
    comments say."""
    import re

    page = (Path(__file__).resolve().parents[2] / "docs" / "endpoints.md").read_text()
    section = page.split("### Connect and drive with asyncua", 1)[1]
    (block,) = re.findall(r"```python\n(.*?)```", section.split("\n### ", 1)[0], flags=re.S)
    expected = re.findall(r"print\(.*\)\s+# (.*)$", block, flags=re.M)
    with serve("virtual_commissioning", pace="lockstep",
               opcua={"port": 0, "users": {USER: PASSWORD}}) as served:
        code = block.replace("opc.tcp://127.0.0.1:4840/openmotion", served.urls()["opcua"])
        exec(compile(code, "docs/endpoints.md", "exec"), {})  # noqa: S102 - docs must run
    assert capsys.readouterr().out.splitlines() == expected


def test_a_served_value_is_never_deep_copied_and_encodes_as_a_plain_data_value() -> None:
    """D-322: asyncua deep-copies what it hands to monitored items; ours are made fresh for
    each write, so the copy is the value itself, and a client cannot tell the difference."""
    import copy

    from asyncua.ua.ua_binary import to_binary

    from openmotion.endpoints.opcua.space import variant

    for value, kind in ((1.5, ua.VariantType.Double), (3.0, ua.VariantType.Int32),
                        (1.0, ua.VariantType.Boolean), (float("nan"), ua.VariantType.Int32)):
        served = variant(value, kind)
        assert copy.deepcopy(served) is served
        plain = ua.DataValue(served.Value, StatusCode=served.StatusCode)
        assert to_binary(ua.DataValue, served) == to_binary(ua.DataValue, plain)
