"""An ADS server for a served machine: stock ADS clients (pyads, TwinCAT's ADS blocks) read
its symbols, drive its commands and receive its notifications over AMS/TCP.

The server speaks AMS/TCP itself (Beckhoff ADS specification, "AMS/TCP packet", "ADS
commands" 1-9) rather than extending pyads' test server (D-265): that one takes one
``recv`` for one frame, keeps its variables in a table of its own, and delivers
notifications by calling the client's callbacks in its own process; here frames are read as
a stream with bounded sizes, the symbols are the machine model's (``ads_symbols``), and a
notification is a DeviceNotification frame sent to the client's socket.

Services (index groups as TwinCAT's PLC runtime answers them):

- ReadDeviceInfo, ReadState (always RUN: the machine is served);
- Read / Write / ReadWrite of a symbol by group and offset, by handle (SYM_HNDBYNAME,
  SYM_VALBYHND, SYM_RELEASEHND) and by name (SYM_VALBYNAME);
- symbol information and upload (SYM_INFOBYNAMEEX, SYM_UPLOADINFO(2), SYM_UPLOAD,
  SYM_DT_UPLOAD, SYM_VERSION);
- sum commands (SUMUP_READ, SUMUP_WRITE, SUMUP_READWRITE), all on one snapshot;
- Add/DelDeviceNotification, on change and cyclic, sampled from the host's snapshots.

Security (D-268): binds 127.0.0.1 unless told otherwise; read-only unless ``writable`` is
True or lists the AMS NetIds that may write, as a TwinCAT route does; a write from any
other client is answered ADSERR_DEVICE_ACCESSDENIED and changes nothing.
"""

from __future__ import annotations

import contextlib
import socket
import struct
import threading
import time
from collections.abc import Callable, Collection
from dataclasses import dataclass, field
from typing import Any

from openmotion.core.errors import ConfigError
from openmotion.endpoints.ads_symbols import (
    ADSERR_ACCESSDENIED,
    ADSERR_INVALIDACCESS,
    ADSERR_INVALIDDATA,
    ADSERR_INVALIDGRP,
    ADSERR_INVALIDSIZE,
    ADSERR_INVALIDWATCHSIZE,
    ADSERR_NOMOREHDLS,
    ADSERR_NOTIFYHNDINVALID,
    ADSERR_SRVNOTSUPP,
    ADSERR_SYMBOLNOTFOUND,
    INDEX_GROUP,
    AdsError,
    AdsSymbol,
    SymbolTable,
)
from openmotion.endpoints.host import HostError, MachineHost, Snapshot

__all__ = ["AdsServer"]

DEFAULT_PORT = 48898  #: AMS/TCP
MAX_FRAME = 1 << 20  #: longest AMS packet taken [bytes]; a longer claim closes the connection
MAX_CLIENTS = 32  #: connections served at once; more are closed at once
MAX_HANDLES = 10_000  #: symbol handles one connection may hold
MAX_NOTIFICATIONS = 1_000  #: notifications one connection may hold
MAX_SUM = 500  #: sub-requests of one sum command (TwinCAT's limit)
MAX_NOTE_SIZE = 1 << 16  #: bytes one notification may watch
NOTE_TICK = 0.01  #: longest sleep of the notification thread [s]
#: from adding a notification to its first sample [s]: a client maps the handle only after
#: it has read the reply, and drops a sample for a handle it does not know yet; 2 ms lost the
#: first sample on a loaded machine
FIRST_SAMPLE_DELAY = 0.05
MIN_NOTE_CYCLE = 0.001  #: shortest cycle of a notification (a cycle time of 0 means this) [s]
SEND_TIMEOUT = 2.0  #: a client that takes nothing for this long is dropped [s]
POLL = 0.2  #: how often blocked threads look whether the server stops [s]
DEVICE_NAME = "openmotion"
DEVICE_VERSION = (3, 1, 4024)  #: what ReadDeviceInfo says (a TwinCAT 3.1 runtime's shape)

# AMS commands
READ_DEVICE_INFO, READ, WRITE, READ_STATE, WRITE_CONTROL = 1, 2, 3, 4, 5
ADD_NOTIFICATION, DEL_NOTIFICATION, DEVICE_NOTIFICATION, READ_WRITE = 6, 7, 8, 9
FLAG_RESPONSE, FLAG_ADS = 0x0001, 0x0004
ADSSTATE_RUN = 5
TRANS_CYCLIC, TRANS_ON_CHANGE = (3, 5), (4, 6)  #: ADSTRANS_SERVERCYCLE(2), SERVERONCHA(2)

# index groups
SYM_HNDBYNAME, SYM_VALBYNAME, SYM_VALBYHND, SYM_RELEASEHND = 0xF003, 0xF004, 0xF005, 0xF006
SYM_VERSION, SYM_INFOBYNAMEEX, SYM_UPLOAD, SYM_UPLOADINFO = 0xF008, 0xF009, 0xF00B, 0xF00C
SYM_DT_UPLOAD, SYM_UPLOADINFO2 = 0xF00E, 0xF00F
SUMUP_READ, SUMUP_WRITE, SUMUP_READWRITE = 0xF080, 0xF081, 0xF082

_TCP = struct.Struct("<HI")
_AMS = struct.Struct("<6sH6sHHHIII")
#: bytes after the result code in a reply of each command, zero when it fails
_ERROR_TAIL = {READ_DEVICE_INFO: 20, READ: 4, READ_STATE: 4, ADD_NOTIFICATION: 4,
               READ_WRITE: 4}
_FILETIME_EPOCH = 116_444_736_000_000_000  #: 1601-01-01 to 1970-01-01 in 100 ns


@dataclass(frozen=True)
class _Address:
    net_id: bytes
    port: int


@dataclass(eq=False)
class _Notification:
    handle: int
    symbol: AdsSymbol
    length: int
    on_change: bool
    cycle: float  #: [s]
    client: _Address
    server: _Address
    due: float = 0.0
    last: bytes | None = None
    seq: int = -1  #: the snapshot last sampled: an older one is never sent after it


@dataclass(eq=False)
class _Connection:
    sock: socket.socket
    peer: str
    send_lock: threading.Lock = field(default_factory=threading.Lock)
    handles: dict[int, AdsSymbol] = field(default_factory=dict)
    notifications: dict[int, _Notification] = field(default_factory=dict)
    next_handle: int = 1
    open: bool = True


class AdsServer:
    """The machine of ``host`` over ADS, on ``address``:``port`` (0: a free port)."""

    def __init__(self, host: MachineHost, address: str = "127.0.0.1",
                 port: int = DEFAULT_PORT, *, writable: bool | Collection[str] = False,
                 max_clients: int = MAX_CLIENTS) -> None:
        self.host = host
        self.address = address
        self._port = port
        if isinstance(writable, str):
            raise ConfigError("writable takes True/False or a list of AMS NetIds, not a "
                              f"string {writable!r}")
        self._writers: frozenset[bytes] | None = None if isinstance(writable, bool) else \
            frozenset(_net_id(text) for text in writable)
        self._writable_all = writable is True
        self.max_clients = max_clients
        self.symbols = SymbolTable(host)
        self._upload = self.symbols.upload()
        self._types = _datatype_upload(self.symbols.symbols)
        self._listener: socket.socket | None = None
        self._connections: set[_Connection] = set()
        self._lock = threading.Lock()
        self._running = threading.Event()
        self._stopping = threading.Event()
        self._threads: list[threading.Thread] = []
        self._next_notification = 1

    # -- life -----------------------------------------------------------------------------

    @property
    def port(self) -> int:
        """The bound port (the one the system chose for ``port=0``)."""
        return self._listener.getsockname()[1] if self._listener is not None else self._port

    def start(self) -> AdsServer:
        if self._listener is not None:
            raise HostError("the ADS server runs already")
        listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            listener.bind((self.address, self._port))
        except OSError as error:
            listener.close()
            raise ConfigError(f"ADS: cannot bind {self.address}:{self._port}: "
                              f"{error.strerror}") from None
        listener.listen(16)
        listener.settimeout(POLL)
        self._listener = listener
        self._running.set()
        self._stopping.clear()
        for target, name in ((self._accept, "ads-accept"), (self._notify, "ads-notify")):
            thread = threading.Thread(target=target, name=name, daemon=True)
            thread.start()
            self._threads.append(thread)
        return self

    def stop(self) -> None:
        self._running.clear()
        self._stopping.set()
        with self._lock:
            connections = list(self._connections)
        for connection in connections:
            self._close(connection)
        for thread in self._threads:
            thread.join(timeout=2.0)
        self._threads.clear()
        if self._listener is not None:
            self._listener.close()
            self._listener = None

    def __enter__(self) -> AdsServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    @property
    def clients(self) -> int:
        with self._lock:
            return len(self._connections)

    # -- connections ----------------------------------------------------------------------

    def _accept(self) -> None:
        assert self._listener is not None
        while self._running.is_set():
            try:
                sock, peer = self._listener.accept()
            except TimeoutError:
                continue
            except OSError:
                return
            with self._lock:
                full = len(self._connections) >= self.max_clients
                connection = _Connection(sock, f"{peer[0]}:{peer[1]}")
                if not full:
                    self._connections.add(connection)
            if full:
                sock.close()
                continue
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            sock.settimeout(POLL)
            thread = threading.Thread(target=self._serve, args=(connection,),
                                      name=f"ads-{connection.peer}", daemon=True)
            thread.start()

    def _serve(self, connection: _Connection) -> None:
        with self.host.client("ads"):
            try:
                while self._running.is_set() and connection.open:
                    head = self._receive(connection, _TCP.size)
                    if head is None:
                        return
                    reserved, length = _TCP.unpack(head)
                    if reserved != 0 or not _AMS.size <= length <= MAX_FRAME:
                        return  # not AMS/TCP, or a size we do not take: close
                    body = self._receive(connection, length)
                    if body is None:
                        return
                    reply = self._answer(connection, body)
                    if reply is not None:
                        self._send(connection, reply)
            except OSError:
                return
            finally:
                self._close(connection)

    def _receive(self, connection: _Connection, size: int) -> bytes | None:
        """Exactly ``size`` bytes, or None when the peer closed or the server stops."""
        chunks, have = [], 0
        while have < size:
            if not self._running.is_set() or not connection.open:
                return None
            try:
                chunk = connection.sock.recv(min(size - have, 65536))
            except TimeoutError:
                continue
            if not chunk:
                return None
            chunks.append(chunk)
            have += len(chunk)
        return b"".join(chunks)

    def _send(self, connection: _Connection, frame: bytes) -> None:
        with connection.send_lock:
            if not connection.open:
                return
            try:
                connection.sock.settimeout(SEND_TIMEOUT)
                connection.sock.sendall(frame)
                connection.sock.settimeout(POLL)
            except OSError:
                connection.open = False

    def _close(self, connection: _Connection) -> None:
        connection.open = False
        with self._lock:
            self._connections.discard(connection)
        with contextlib.suppress(OSError):
            connection.sock.shutdown(socket.SHUT_RDWR)
        connection.sock.close()

    # -- requests -------------------------------------------------------------------------

    def _answer(self, connection: _Connection, body: bytes) -> bytes | None:
        """The reply frame to one AMS packet; None for a packet that wants none."""
        target_id, target_port, source_id, source_port, command, flags, length, _, invoke = \
            _AMS.unpack_from(body)
        if flags & FLAG_RESPONSE:
            return None  # a reply to nothing we asked
        target, source = _Address(target_id, target_port), _Address(source_id, source_port)
        data = body[_AMS.size:]
        handler = self._COMMANDS.get(command)
        if length != len(data):
            payload, error = b"", ADSERR_INVALIDSIZE
        elif handler is None:
            payload, error = b"", ADSERR_SRVNOTSUPP
        else:
            error = 0
            try:
                payload = struct.pack("<I", 0) + handler(self, connection, data, source, target)
            except AdsError as failure:
                payload = struct.pack("<I", failure.code) + bytes(_ERROR_TAIL.get(command, 0))
            except struct.error:
                payload = struct.pack("<I", ADSERR_INVALIDSIZE) + \
                    bytes(_ERROR_TAIL.get(command, 0))
        header = _AMS.pack(source_id, source_port, target_id, target_port, command,
                           FLAG_RESPONSE | FLAG_ADS, len(payload), error, invoke)
        return _TCP.pack(0, len(header) + len(payload)) + header + payload

    def _device_info(self, connection: _Connection, data: bytes, *_: Any) -> bytes:
        major, minor, build = DEVICE_VERSION
        return struct.pack("<BBH16s", major, minor, build, DEVICE_NAME.encode())

    def _state(self, connection: _Connection, data: bytes, *_: Any) -> bytes:
        return struct.pack("<HH", ADSSTATE_RUN, 0)

    def _read_command(self, connection: _Connection, data: bytes, *_: Any) -> bytes:
        group, offset, length = struct.unpack("<III", _exact(data, 12))
        value = self._read(connection, group, offset, length, self.host.snapshot)
        return struct.pack("<I", len(value)) + value

    def _write_command(self, connection: _Connection, data: bytes, source: _Address,
                       _target: _Address) -> bytes:
        group, offset, length = struct.unpack_from("<III", data)
        self._write(connection, group, offset, _exact(data[12:], length), source)
        return b""

    def _read_write_command(self, connection: _Connection, data: bytes, source: _Address,
                            _target: _Address) -> bytes:
        group, offset, read_length, write_length = struct.unpack_from("<IIII", data)
        value = self._read_write(connection, group, offset, read_length,
                                 _exact(data[16:], write_length), source, self.host.snapshot)
        return struct.pack("<I", len(value)) + value

    def _add_notification(self, connection: _Connection, data: bytes, source: _Address,
                          target: _Address) -> bytes:
        if len(data) < 40:
            raise AdsError(ADSERR_INVALIDSIZE)
        group, offset, length, mode, _, cycle = struct.unpack_from("<IIIIII", data)
        symbol = self._symbol(connection, group, offset)
        if not 0 < length <= MAX_NOTE_SIZE:
            raise AdsError(ADSERR_INVALIDWATCHSIZE)
        if mode not in TRANS_CYCLIC + TRANS_ON_CHANGE:
            raise AdsError(ADSERR_INVALIDDATA, f"transmission mode {mode} is not served")
        if len(connection.notifications) >= MAX_NOTIFICATIONS:
            raise AdsError(ADSERR_NOMOREHDLS)
        with self._lock:
            handle = self._next_notification
            self._next_notification += 1
        # the first sample goes out after the reply that names its handle has reached the
        # client, which only then knows where to deliver it (as TwinCAT's next task cycle)
        connection.notifications[handle] = _Notification(
            handle, symbol, length, mode in TRANS_ON_CHANGE, max(cycle * 1e-7, MIN_NOTE_CYCLE),
            source, target, due=time.monotonic() + FIRST_SAMPLE_DELAY)
        return struct.pack("<I", handle)

    def _del_notification(self, connection: _Connection, data: bytes, *_: Any) -> bytes:
        (handle,) = struct.unpack("<I", _exact(data, 4))
        if connection.notifications.pop(handle, None) is None:
            raise AdsError(ADSERR_NOTIFYHNDINVALID)
        return b""

    def _write_control(self, *_: Any) -> bytes:
        raise AdsError(ADSERR_SRVNOTSUPP, "the served machine's ADS state is always RUN")

    _COMMANDS: dict[int, Callable[..., bytes]] = {
        READ_DEVICE_INFO: _device_info, READ: _read_command, WRITE: _write_command,
        READ_STATE: _state, WRITE_CONTROL: _write_control,
        ADD_NOTIFICATION: _add_notification, DEL_NOTIFICATION: _del_notification,
        READ_WRITE: _read_write_command}

    # -- index groups ---------------------------------------------------------------------

    def _symbol(self, connection: _Connection, group: int, offset: int) -> AdsSymbol:
        if group == SYM_VALBYHND:
            symbol = connection.handles.get(offset)
            if symbol is None:
                raise AdsError(ADSERR_SYMBOLNOTFOUND, f"no handle {offset}")
            return symbol
        return self.symbols.at(group, offset)

    def _read(self, connection: _Connection, group: int, offset: int, length: int,
              snapshot: Snapshot) -> bytes:
        if group == SYM_UPLOADINFO2:
            info = struct.pack("<IIIIII", len(self.symbols.symbols), len(self._upload),
                               self._types[0], len(self._types[1]), 0, 0)
            return info[:length]
        if group == SYM_UPLOADINFO:
            return struct.pack("<II", len(self.symbols.symbols), len(self._upload))[:length]
        if group == SYM_UPLOAD:
            return self._upload[:length]
        if group == SYM_DT_UPLOAD:
            return self._types[1][:length]
        if group == SYM_VERSION:
            return b"\x01"[:length]
        return self.symbols.read(self._symbol(connection, group, offset), length, snapshot)

    def _write(self, connection: _Connection, group: int, offset: int, data: bytes,
               source: _Address) -> None:
        if group == SYM_RELEASEHND:
            (handle,) = struct.unpack("<I", _exact(data, 4))
            if connection.handles.pop(handle, None) is None:
                raise AdsError(ADSERR_SYMBOLNOTFOUND, f"no handle {handle}")
            return
        self._write_symbol(self._symbol(connection, group, offset), data, source)

    def _write_symbol(self, symbol: AdsSymbol, data: bytes, source: _Address) -> None:
        if symbol.write is None:
            raise AdsError(ADSERR_INVALIDACCESS, f"{symbol.name} is read-only")
        if not self._may_write(source):
            raise AdsError(ADSERR_ACCESSDENIED, "this client may not write")
        symbol.write(data)

    def _may_write(self, source: _Address) -> bool:
        return self._writable_all or (self._writers is not None
                                      and source.net_id in self._writers)

    def _read_write(self, connection: _Connection, group: int, offset: int, read_length: int,
                    data: bytes, source: _Address, snapshot: Snapshot) -> bytes:
        if group in (SYM_HNDBYNAME, SYM_INFOBYNAMEEX, SYM_VALBYNAME):
            symbol = self.symbols.find(_name(data))
            if group == SYM_INFOBYNAMEEX:
                return symbol.entry()[:read_length]
            if group == SYM_VALBYNAME:
                return self.symbols.read(symbol, read_length, snapshot)
            if len(connection.handles) >= MAX_HANDLES:
                raise AdsError(ADSERR_NOMOREHDLS)
            handle = connection.next_handle
            connection.next_handle = handle % 0xFFFF_FFFE + 1
            connection.handles[handle] = symbol
            return struct.pack("<I", handle)[:read_length]
        if group == SUMUP_READ:
            return self._sum_read(connection, offset, data, snapshot)
        if group == SUMUP_WRITE:
            return self._sum_write(connection, offset, data, source)
        if group == SUMUP_READWRITE:
            return self._sum_read_write(connection, offset, data, source, snapshot)
        if data:
            self._write(connection, group, offset, data, source)
        return self._read(connection, group, offset, read_length, snapshot) \
            if read_length else b""

    def _sum_read(self, connection: _Connection, count: int, data: bytes,
                  snapshot: Snapshot) -> bytes:
        requests = _sum_requests(count, data, 12)
        heads = struct.unpack_from(f"<{3 * requests}I", data)
        by_offset = self.symbols.by_offset
        codes, values = [], []
        for item in range(0, 3 * requests, 3):
            group, offset, length = heads[item:item + 3]
            symbol = by_offset.get(offset) if group == INDEX_GROUP else None
            if symbol is not None and length == symbol.size:  # the common case, quickly
                codes.append(0)
                values.append(symbol.read(snapshot))
                continue
            code, value = _attempt(self._read, connection, group, offset, length, snapshot)
            codes.append(code)
            values.append(value.ljust(length, b"\0")[:length])  # offsets stay those asked
        return struct.pack(f"<{requests}I", *codes) + b"".join(values)

    def _sum_write(self, connection: _Connection, count: int, data: bytes,
                   source: _Address) -> bytes:
        requests = _sum_requests(count, data, 12)
        heads = [struct.unpack_from("<III", data, 12 * i) for i in range(requests)]
        position = 12 * requests
        if position + sum(length for *_, length in heads) != len(data):
            raise AdsError(ADSERR_INVALIDSIZE)
        codes = []
        for group, offset, length in heads:
            chunk = data[position:position + length]
            position += length
            codes.append(_attempt(self._write, connection, group, offset, chunk, source)[0])
        return struct.pack(f"<{requests}I", *codes)

    def _sum_read_write(self, connection: _Connection, count: int, data: bytes,
                        source: _Address, snapshot: Snapshot) -> bytes:
        requests = _sum_requests(count, data, 16)
        heads = [struct.unpack_from("<IIII", data, 16 * i) for i in range(requests)]
        position = 16 * requests
        if position + sum(head[3] for head in heads) != len(data):
            raise AdsError(ADSERR_INVALIDSIZE)
        results, values = [], []
        for group, offset, read_length, write_length in heads:
            chunk = data[position:position + write_length]
            position += write_length
            if group in (SUMUP_READ, SUMUP_WRITE, SUMUP_READWRITE):
                code, value = ADSERR_INVALIDGRP, b""
            else:
                code, value = _attempt(self._read_write, connection, group, offset,
                                       read_length, chunk, source, snapshot)
            results.append(struct.pack("<II", code, len(value)))
            values.append(value)
        return b"".join(results) + b"".join(values)

    # -- notifications --------------------------------------------------------------------

    def _notify(self) -> None:
        """Samples every notification from the host's snapshots: cyclic ones when their
        cycle is due, on-change ones when a new snapshot comes (or ``NOTE_TICK`` passed,
        for a command input a client wrote)."""
        seq = self.host.snapshot.seq
        while self._running.is_set():
            now = time.monotonic()
            with self._lock:
                connections = [c for c in self._connections if c.notifications]
            due = min((n.due for c in connections for n in list(c.notifications.values())
                       if not n.on_change or n.last is None), default=now + NOTE_TICK)
            wait = min(NOTE_TICK, max(MIN_NOTE_CYCLE, due - now))
            if self.host.running:
                try:
                    snapshot = self.host.wait_snapshot(seq, timeout=wait)
                except HostError:
                    snapshot = self.host.snapshot
            else:  # a stopped host publishes nothing: its last snapshot, at the pace asked
                self._stopping.wait(wait)
                snapshot = self.host.snapshot
            seq = snapshot.seq
            now = time.monotonic()
            for connection in connections:
                for frame in self._notifications(connection, snapshot, now):
                    self._send(connection, frame)

    def _notifications(self, connection: _Connection, snapshot: Snapshot,
                       now: float) -> list[bytes]:
        return self._frames(list(connection.notifications.values()), snapshot, now)

    def _frames(self, notes: list[_Notification], snapshot: Snapshot,
                now: float) -> list[bytes]:
        """The DeviceNotification frames due on ``connection``: one per pair of addresses,
        one stamp (the wall time of sampling) with every sample due."""
        samples: dict[tuple[_Address, _Address], list[bytes]] = {}
        for note in notes:
            if now < note.due or snapshot.seq < note.seq:
                continue
            note.due, note.seq = now + note.cycle, snapshot.seq
            try:
                value = self.symbols.read(note.symbol, note.length, snapshot)
            except AdsError:
                continue
            if note.on_change and value == note.last:
                continue
            note.last = value
            samples.setdefault((note.client, note.server), []).append(
                struct.pack("<II", note.handle, len(value)) + value)
        stamp = time.time_ns() // 100 + _FILETIME_EPOCH
        frames = []
        for (client, server), items in samples.items():
            stream = struct.pack("<IQI", 1, stamp, len(items)) + b"".join(items)
            payload = struct.pack("<I", len(stream)) + stream
            header = _AMS.pack(client.net_id, client.port, server.net_id, server.port,
                               DEVICE_NOTIFICATION, FLAG_ADS, len(payload), 0, 0)
            frames.append(_TCP.pack(0, len(header) + len(payload)) + header + payload)
        return frames


def _exact(data: bytes, size: int) -> bytes:
    if len(data) != size:
        raise AdsError(ADSERR_INVALIDSIZE, f"{size} bytes expected, {len(data)} sent")
    return data


def _name(data: bytes) -> str:
    return data.split(b"\0", 1)[0].decode("utf-8", errors="replace")


def _sum_requests(count: int, data: bytes, head: int) -> int:
    if not 0 < count <= MAX_SUM or len(data) < head * count:
        raise AdsError(ADSERR_INVALIDSIZE, f"a sum command takes 1 to {MAX_SUM} requests")
    return count


def _attempt(action: Callable[..., Any], *arguments: Any) -> tuple[int, Any]:
    """The ADS code and result of one sub-request of a sum command."""
    try:
        result = action(*arguments)
    except AdsError as error:
        return error.code, b""
    except struct.error:
        return ADSERR_INVALIDSIZE, b""
    return 0, result if result is not None else b""


def _net_id(text: str) -> bytes:
    parts = text.split(".")
    try:
        numbers = [int(part) for part in parts]
    except ValueError:
        numbers = []
    if len(numbers) != 6 or not all(0 <= n <= 255 for n in numbers):
        raise ConfigError(f"{text!r} is not an AMS NetId (six numbers 0-255: 192.168.0.1.1.1)")
    return bytes(numbers)


def _datatype_upload(symbols: list[AdsSymbol]) -> tuple[int, bytes]:
    """The data types the symbols use, as SYM_DT_UPLOAD lists them (AdsDatatypeEntry):
    each a plain IEC type without members."""
    seen: dict[str, bytes] = {}
    for symbol in symbols:
        kind = symbol.type
        if kind.name in seen:
            continue
        name = kind.name.encode()
        dims = 1 if kind.count > 1 else 0
        body = struct.pack("<IIIIIIIHHHHH", 1, 0, 0, kind.size, 0, kind.ads, 0,
                           len(name), 0, 0, dims, 0) + name + b"\0" + b"\0" + b"\0"
        if dims:
            body += struct.pack("<II", 0, kind.count)
        seen[kind.name] = struct.pack("<I", 4 + len(body)) + body
    return len(seen), b"".join(seen.values())
