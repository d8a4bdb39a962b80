"""The OPC UA server of a served machine: asyncua on its own thread and event loop.

The host's kernel thread steps the machine; this thread serves clients. A writer task on the
server's loop copies the newest snapshot into the variables every ``update_interval``: all
values of one cycle are written without yielding to the loop, so a client's Read, and every
notification a subscription sends, shows one consistent cycle. Subscriptions sample at the
client's interval: each monitored item keeps the newest value per publishing interval (D-260).
"""

from __future__ import annotations

import asyncio
import contextlib
import gc
import ipaddress
import logging
import socket
import tempfile
import threading
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
from asyncua import Server, ua
from asyncua.server.address_space import AttributeValue, NodeData
from asyncua.server.internal_server import InternalServer

from openmotion.core.errors import ConfigError
from openmotion.endpoints.host import HostError, MachineHost
from openmotion.endpoints.opcua import nodes
from openmotion.endpoints.opcua.calls import command_method, host_methods
from openmotion.endpoints.opcua.security import Access
from openmotion.endpoints.opcua.space import (
    HANDLE_OUTPUTS,
    NAMESPACE_URI,
    AddressSpace,
    FreshValue,
    build,
    command_items,
    handle_values,
    variant,
)
from openmotion.endpoints.wire import HandleState
from openmotion.kernel.model import MachineObject

__all__ = ["APPLICATION_URI", "DEFAULT_PORT", "SECURITY_POLICIES", "OpcUaServer"]

_LOG = logging.getLogger("openmotion.endpoints.opcua")
DEFAULT_PORT = 4840
APPLICATION_URI = "urn:openmotion:server"
UPDATE_INTERVAL = 0.01  #: how often the writer copies the newest snapshot [s]
STARTUP_TIMEOUT = 120.0  #: longest wait for the server to listen [s]
STOP_TIMEOUT = 10.0
#: the security policies a server offers, by the name ``security`` takes
SECURITY_POLICIES: dict[str, tuple[ua.SecurityPolicyType, ...]] = {
    "none": (ua.SecurityPolicyType.NoSecurity,),
    "basic256sha256": (ua.SecurityPolicyType.Basic256Sha256_Sign,
                       ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt),
}
_STANDARD: dict[Any, NodeData] = {}
_STANDARD_LOCK = threading.Lock()


class _InternalServer(InternalServer):
    """asyncua's server with the standard address space built once per process: it takes
    about 2 s of CPU to build and each server needs its own copy (tests start dozens)."""

    async def load_standard_address_space(self, shelf_file: Path | None = None) -> None:
        with _STANDARD_LOCK:
            if not _STANDARD:
                template = InternalServer()
                await InternalServer.load_standard_address_space(template)
                _STANDARD.update(template.aspace._nodes)
            collecting = gc.isenabled()
            gc.disable()  # 80 000 small objects, no garbage: collections would walk them all
            try:
                self.aspace._nodes = {nodeid: _copy(node) for nodeid, node in _STANDARD.items()}
            finally:
                if collecting:
                    gc.enable()


    async def stop(self) -> None:
        """Stop at once: the server clock's task sleeps a second between its updates."""
        task, self.time_task = self.time_task, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
        await super().stop()


def _copy(node: NodeData) -> NodeData:
    copy = NodeData(node.nodeid)
    for attribute, value in node.attributes.items():
        fresh = AttributeValue(value.value)
        fresh.value_callback, fresh.value_setter = value.value_callback, value.value_setter
        copy.attributes[attribute] = fresh
    copy.references = list(node.references)
    copy.call = node.call
    return copy


def free_port(address: str) -> int:
    """A TCP port free on ``address`` now."""
    family = socket.AF_INET6 if ":" in address else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        probe.bind((address, 0))
        return int(probe.getsockname()[1])


def _load_certificate(path: str | Path) -> bytes:
    """The DER bytes of a certificate file (DER or PEM)."""
    from cryptography import x509
    from cryptography.hazmat.primitives.serialization import Encoding

    try:
        data = Path(path).read_bytes()
    except OSError as error:
        raise ConfigError(f"cannot read the certificate {path}: {error.strerror}") from None
    try:
        if b"-----BEGIN" in data:
            return x509.load_pem_x509_certificate(data).public_bytes(Encoding.DER)
        return x509.load_der_x509_certificate(data).public_bytes(Encoding.DER)
    except ValueError:
        raise ConfigError(f"{path} is no X.509 certificate (DER or PEM)") from None


class OpcUaServer:
    """A machine host served over OPC UA (docs/endpoints.md "OPC UA")."""

    def __init__(self, host: MachineHost, address: str = "127.0.0.1",
                 port: int = DEFAULT_PORT, *, writable: bool = False,
                 users: dict[str, str] | None = None, certificates: tuple[str | Path, ...] = (),
                 security: tuple[str, ...] = ("none",), certificate_dir: str | Path | None = None,
                 update_interval: float = UPDATE_INTERVAL) -> None:
        unknown = [name for name in security if name not in SECURITY_POLICIES]
        if unknown or not security:
            raise ConfigError(f"OPC UA security: {', '.join(unknown) or 'none given'}; choose "
                              f"from {', '.join(SECURITY_POLICIES)}")
        if not 0.001 <= update_interval <= 10.0:
            raise ConfigError(f"update_interval must be in [0.001, 10] s, not {update_interval}")
        self.host = host
        self.address = address
        self.port = free_port(address) if port == 0 else port
        self.access = Access(users, [_load_certificate(path) for path in certificates],
                             writable=writable)
        self.security = tuple(security)
        self.certificate_dir = Path(certificate_dir) if certificate_dir is not None else None
        self.update_interval = update_interval
        self.space: AddressSpace | None = None
        #: the started commands the address space shows, with their last written outputs
        self.commands: dict[int, HandleState] = {}
        self._thread: threading.Thread | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stopping: asyncio.Event | None = None
        self._ready = threading.Event()
        self._error: BaseException | None = None
        self._temporary: tempfile.TemporaryDirectory[str] | None = None
        self._writer: _Writer | None = None

    @property
    def url(self) -> str:
        try:
            literal = ipaddress.ip_address(self.address).version == 6
        except ValueError:
            literal = False
        where = f"[{self.address}]" if literal else self.address
        return f"opc.tcp://{where}:{self.port}/openmotion"

    @property
    def namespace(self) -> str:
        return NAMESPACE_URI

    # -- life -----------------------------------------------------------------------------

    def start(self) -> OpcUaServer:
        """Build the address space and listen; returns once clients can connect."""
        if self._thread is not None:
            raise HostError("the OPC UA server runs already")
        self._ready.clear()
        self._error = None
        self._thread = threading.Thread(target=lambda: asyncio.run(self._main()),
                                        name="openmotion-opcua", daemon=True)
        self._thread.start()
        if not self._ready.wait(STARTUP_TIMEOUT):
            self.stop()
            raise HostError(f"the OPC UA server did not start within {STARTUP_TIMEOUT} s")
        if self._error is not None:
            self._thread.join(STOP_TIMEOUT)
            self._thread = None
            error, self._error = self._error, None
            if isinstance(error, OSError):
                raise OSError(error.errno, f"cannot listen on {self.address}:{self.port}: "
                              f"{error.strerror or error}") from error
            raise error
        return self

    def stop(self) -> None:
        """Close every session and stop listening."""
        loop, stopping = self._loop, self._stopping
        if loop is not None and stopping is not None:
            with contextlib.suppress(RuntimeError):  # the loop ended already
                loop.call_soon_threadsafe(stopping.set)
        if self._thread is not None:
            self._thread.join(STOP_TIMEOUT)
            self._thread = None
        if self._temporary is not None:
            self._temporary.cleanup()
            self._temporary = None

    def __enter__(self) -> OpcUaServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- the server's thread ---------------------------------------------------------------

    async def _main(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._stopping = asyncio.Event()
        server: Server | None = None
        try:
            server = await self._setup()
            await server.start()
        except BaseException as error:  # noqa: BLE001 - start() raises it in the caller
            self._error = error
            if server is not None:
                with contextlib.suppress(Exception):
                    await server.iserver.stop()
            self._ready.set()
            return
        self._ready.set()
        writer = self._writer
        assert writer is not None
        last_status = 0.0
        try:
            while not self._stopping.is_set():
                try:
                    clock = time.monotonic()
                    full = clock - last_status >= STATUS_INTERVAL
                    last_status = clock if full else last_status
                    await writer.publish(status=full)
                except Exception:  # noqa: BLE001 - a client must never see a dead server
                    _LOG.exception("updating the OPC UA variables failed")
                with contextlib.suppress(TimeoutError):
                    await asyncio.wait_for(self._stopping.wait(), self.update_interval)
        finally:
            writer.close()
            await server.stop()
            self._loop = None

    async def _setup(self) -> Server:
        server = Server(iserver=_InternalServer(user_manager=self.access))
        await server.init()
        server.set_endpoint(self.url)
        server.set_server_name("openmotion")
        await server.set_application_uri(APPLICATION_URI)
        policies = [policy for name in self.security for policy in SECURITY_POLICIES[name]]
        server.set_security_policy(policies, permission_ruleset=self.access)
        server.set_identity_tokens(self.access.tokens)
        if any(name != "none" for name in self.security):
            key, certificate = await self._certificate()
            await server.load_certificate(str(certificate))
            await server.load_private_key(str(key))
        namespace = await server.register_namespace(NAMESPACE_URI)
        space = build(self.host, namespace, self.update_interval * 1e3)
        _host_object(space, self.update_interval * 1e3)
        session = server.iserver.isession
        for result in await session.add_nodes(space.items):
            result.StatusCode.check()
        for status in await session.add_references(space.references):
            status.check()
        for node, definition in space.definitions.items():
            await server.write_attribute_value(
                node, ua.DataValue(ua.Variant(definition, ua.VariantType.ExtensionObject)),
                ua.AttributeIds.DataTypeDefinition)
        self.space = space
        self._writer = writer = _Writer(self, server)
        for node, served in space.methods.items():
            session.add_method_callback(node, command_method(
                self.host, served, self._adder(server, space), writer.publish))
        for name, callback in host_methods(self.host, writer.publish).items():
            session.add_method_callback(space.id(f"Host:{name}"), callback)
        return server

    def _adder(self, server: Server, space: AddressSpace) -> Any:
        async def add(ticket: int, owner: MachineObject, name: str) -> ua.NodeId:
            state = self.host.snapshot.handles.get(ticket, HandleState())
            node, items = command_items(space, ticket, owner, name, state)
            for result in await server.iserver.isession.add_nodes(items):
                result.StatusCode.check()
            self.commands[ticket] = state
            return node
        return add

    async def _certificate(self) -> tuple[Path, Path]:
        """The server's key and certificate: from ``certificate_dir``, made there (a
        self-signed one) when missing; in a temporary directory without one."""
        from asyncua.crypto.cert_gen import setup_self_signed_certificate
        from cryptography.x509.oid import ExtendedKeyUsageOID

        folder = self.certificate_dir
        if folder is None:
            self._temporary = tempfile.TemporaryDirectory(prefix="openmotion-opcua-")
            folder = Path(self._temporary.name)
        folder.mkdir(parents=True, exist_ok=True)
        key, certificate = folder / "server_key.pem", folder / "server_cert.der"
        await setup_self_signed_certificate(
            key, certificate, APPLICATION_URI, socket.gethostname(),
            [ExtendedKeyUsageOID.SERVER_AUTH, ExtendedKeyUsageOID.CLIENT_AUTH],
            {"organizationName": "openmotion"})
        return key, certificate


#: the Host object's variables: (name, variant type, data type, unit, what it says)
_HOST_VARIABLES = (
    ("Pace", ua.VariantType.String, ua.ObjectIds.String, "", "wall or lockstep"),
    ("Speed", ua.VariantType.Double, ua.ObjectIds.Double, "", "virtual seconds per wall second"),
    ("Paused", ua.VariantType.Boolean, ua.ObjectIds.Boolean, "", "a wall-paced machine stands"),
    ("Cycle", ua.VariantType.UInt64, ua.ObjectIds.UInt64, "", "cycles stepped"),
    ("Time", ua.VariantType.Double, ua.ObjectIds.Double, "s", "virtual time"),
    ("CycleTime", ua.VariantType.Double, ua.ObjectIds.Double, "s", "one cycle"),
    ("LateP99", ua.VariantType.Double, ua.ObjectIds.Double, "ms",
     "p99 of how late cycles finished against the wall clock"),
    ("Slips", ua.VariantType.UInt32, ua.ObjectIds.UInt32, "",
     "times virtual time slipped behind the wall clock"),
    ("Clients", ua.VariantType.UInt32, ua.ObjectIds.UInt32, "", "connected clients (all kinds)"),
    ("Failure", ua.VariantType.String, ua.ObjectIds.String, "", "why the machine stopped"),
)
_HOST_KINDS = {name: kind for name, kind, *_ in _HOST_VARIABLES}
STATUS_INTERVAL = 0.2  #: how often the Host object's status variables are refreshed [s]
#: the Host object's methods: (name, input arguments, output arguments, what it does)
_HOST_METHODS = (
    ("Step", [("Cycles", ua.ObjectIds.UInt32)], True, "lockstep: step cycles now"),
    ("RunFor", [("Seconds", ua.ObjectIds.Double)], True,
     "lockstep: step the cycles of virtual seconds"),
    ("Pause", [], False, "wall pace: stand still"),
    ("Resume", [], False, "wall pace: go on from here"),
    ("SetSpeed", [("Speed", ua.ObjectIds.Double)], False, "wall pace: virtual s per wall s"),
)


def _host_object(space: AddressSpace, interval_ms: float) -> None:
    """The Host object: the pace as variables, lockstep and pace control as methods."""
    node = space.id("Host")
    space.items.append(nodes.obj(node, space.name("Host"), ua.NodeId(ua.ObjectIds.ObjectsFolder),
                                 ua.NodeId(ua.ObjectIds.BaseObjectType),
                                 "the served machine's pace", ua.ObjectIds.Organizes))
    for name, _kind, datatype, unit, doc in _HOST_VARIABLES:
        variable = space.id(f"Host.{name}")
        space.items.append(nodes.variable(
            variable, space.name(name), node, ua.Variant(None, ua.VariantType.Null),
            ua.NodeId(datatype), description=doc, interval_ms=interval_ms,
            typedef=ua.ObjectIds.AnalogUnitType if unit else ua.ObjectIds.BaseDataVariableType))
        if unit:
            space.items.append(nodes.prop(space.id(f"Host.{name}#EngineeringUnits"),
                                          "EngineeringUnits", variable,
                                          ua.Variant(nodes.eu_information(unit),
                                                     ua.VariantType.ExtensionObject),
                                          ua.ObjectIds.EUInformation))
    for name, inputs, paced, doc in _HOST_METHODS:
        method = space.id(f"Host:{name}")
        space.items.append(nodes.method(method, space.name(name), node, doc))
        arguments = [nodes.argument(arg, datatype) for arg, datatype in inputs]
        outputs = [nodes.argument("Cycle", ua.ObjectIds.UInt64),
                   nodes.argument("Time", ua.ObjectIds.Double, "virtual time [s]")] if paced else []
        for label, args in (("InputArguments", arguments), ("OutputArguments", outputs)):
            if args:
                space.items.append(nodes.prop(space.id(f"Host:{name}#{label}"), label, method,
                                              ua.Variant(args, ua.VariantType.ExtensionObject),
                                              ua.ObjectIds.Argument, array=True))


class _Writer:
    """Copies snapshots into the address space: changed values only, one cycle at a time."""

    def __init__(self, owner: OpcUaServer, server: Server) -> None:
        self.owner = owner
        self.host = owner.host
        self.server = server
        self.aspace = server.iserver.aspace
        self.space = owner.space
        self.seq = -1
        self.values = np.full(len(self.host.names), np.nan)
        self.written = np.zeros(len(self.host.names), dtype=bool)
        self.status: dict[str, Any] = {}
        self.clients: list[contextlib.ExitStack] = []
        self.lock = asyncio.Lock()

    async def publish(self, status: bool = True) -> None:
        """Copy the newest snapshot: every ``update_interval``, and at once after a method
        changed the machine (a client that stepped reads the cycle it stepped to); the
        host's status (lateness percentiles, clients) only with ``status``."""
        async with self.lock:  # one snapshot at a time, never two interleaved
            now = datetime.now(UTC)
            snapshot = self.host.snapshot
            if snapshot.seq != self.seq:
                self.seq = snapshot.seq
                await self._signals(snapshot.values, now)
                await self._commands(snapshot.handles, now)
                await self._clock(snapshot, now)
            if status:
                await self._status(now)
                self._count_clients()

    async def _write(self, node: ua.NodeId, value: ua.DataValue, now: datetime) -> None:
        value.SourceTimestamp = value.ServerTimestamp = now
        await self.aspace.write_attribute_value(node, ua.AttributeIds.Value, value)

    async def _signals(self, values: np.ndarray, now: datetime) -> None:
        same = (values == self.values) | (np.isnan(values) & np.isnan(self.values))
        changed = np.flatnonzero(~same | ~self.written)
        signals = self.space.signals  # type: ignore[union-attr]
        for index in changed.tolist():
            node, kind = signals[index]
            await self._write(node, variant(float(values[index]), kind), now)
        self.values = values.copy()
        self.written[:] = True

    async def _commands(self, handles: dict[int, HandleState], now: datetime) -> None:
        known = self.owner.commands
        for ticket, last in list(known.items()):
            state = handles.get(ticket)
            if state is None:  # the host forgot it: so does the address space
                del known[ticket]
                node = self.server.get_node(self.space.id(f"Commands/{ticket}"))  # type: ignore[union-attr]
                await self.server.delete_nodes([node], recursive=True)
                continue
            if state == last:
                continue
            known[ticket] = state
            for label, (value, _) in zip(HANDLE_OUTPUTS, _values(state), strict=True):
                await self._write(self.space.id(f"Commands/{ticket}.{label}"),  # type: ignore[union-attr]
                                  FreshValue(value), now)

    async def _clock(self, snapshot: Any, now: datetime) -> None:
        await self._host_values({"Cycle": snapshot.cycle, "Time": snapshot.time}, now)

    async def _status(self, now: datetime) -> None:
        status = self.host.status()
        await self._host_values({
            "Pace": status.pace.value, "Speed": status.speed, "Paused": status.paused,
            "CycleTime": self.host.cycle_time, "LateP99": status.late_p99_ms,
            "Slips": status.slips, "Clients": sum(status.clients.values()),
            "Failure": status.failure}, now)

    async def _host_values(self, values: dict[str, Any], now: datetime) -> None:
        for name, value in values.items():
            if self.status.get(name) != value:
                self.status[name] = value
                await self._write(self.space.id(f"Host.{name}"),  # type: ignore[union-attr]
                                  FreshValue(ua.Variant(value, _HOST_KINDS[name])), now)

    def _count_clients(self) -> None:
        """Count the connected OPC UA clients on the host (its status line shows them)."""
        connected = len(self.server.bserver.clients) if self.server.bserver else 0
        while len(self.clients) < connected:
            stack = contextlib.ExitStack()
            stack.enter_context(self.host.client("opcua"))
            self.clients.append(stack)
        while len(self.clients) > connected:
            self.clients.pop().close()

    def close(self) -> None:
        while self.clients:
            self.clients.pop().close()


def _values(state: HandleState) -> list[tuple[ua.Variant, int]]:
    return list(handle_values(state))
