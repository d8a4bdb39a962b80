"""Malformed AMS/TCP frames get an error reply or a closed connection, and the ADS server
keeps serving its other clients (raw sockets beside a real pyads client)."""

from __future__ import annotations

import itertools
import random
import socket
import struct
import threading
import time
from collections.abc import Iterator

import pytest

pyads = pytest.importorskip("pyads")

from openmotion.endpoints import MachineHost  # noqa: E402
from openmotion.endpoints.ads import AdsServer  # noqa: E402
from openmotion.runtime.runtime import Runtime  # noqa: E402

CLIENT_ID = bytes([127, 0, 0, 1, 9, 9])
SERVER_ID = bytes([127, 0, 0, 1, 1, 1])
FUZZ_FRAMES = 10_000
_NET_IDS = itertools.count(1)


@pytest.fixture
def served() -> Iterator[tuple[MachineHost, AdsServer]]:
    runtime = Runtime()
    runtime.add_axis("x")
    host = MachineHost(runtime, pace="lockstep").start()
    server = AdsServer(host, port=0).start()  # read-only: fuzzed writes cannot move it
    try:
        yield host, server
    finally:
        server.stop()
        host.stop()


def frame(command: int, data: bytes, *, length: int | None = None, invoke: int = 7,
          flags: int = 0x0004, reserved: int = 0) -> bytes:
    header = struct.pack("<6sH6sHHHIII", SERVER_ID, 851, CLIENT_ID, 30000, command, flags,
                         len(data) if length is None else length, 0, invoke)
    return struct.pack("<HI", reserved, len(header) + len(data)) + header + data


def exchange(port: int, payload: bytes) -> bytes:
    """What the server answers to ``payload``: its reply frame, or b"" when it closed."""
    with socket.create_connection(("127.0.0.1", port), timeout=3.0) as sock:
        try:
            sock.sendall(payload)
            return _reply(sock)
        except (ConnectionResetError, BrokenPipeError):  # closed while we still sent
            return b""


def _reply(sock: socket.socket) -> bytes:
    """One reply frame, read to its end and no further; b"" when the server closed."""
    head = _exactly(sock, 6)
    return head + _exactly(sock, struct.unpack_from("<I", head, 2)[0]) if head else b""


def _exactly(sock: socket.socket, size: int) -> bytes:
    data = b""
    while len(data) < size:
        chunk = sock.recv(size - len(data))
        if not chunk:
            return b""
        data += chunk
    return data


def _drain(sock: socket.socket) -> None:
    """Read until the server closes (it may answer first); a socket timeout fails."""
    while sock.recv(65536):
        pass


def ams_error(reply: bytes) -> int:
    return struct.unpack_from("<I", reply, 6 + 24)[0]


def ads_result(reply: bytes) -> int:
    return struct.unpack_from("<I", reply, 6 + 32)[0]


def test_a_good_frame_is_answered(served) -> None:
    _, server = served
    reply = exchange(server.port, frame(4, b""))  # ReadState
    assert ams_error(reply) == 0 and ads_result(reply) == 0
    assert struct.unpack_from("<HH", reply, 6 + 36) == (5, 0)
    assert struct.unpack_from("<I", reply, 6 + 20)[0] == 8  # its own data length


def test_unknown_command_gets_service_not_supported(served) -> None:
    _, server = served
    assert ams_error(exchange(server.port, frame(0x55, b"abc"))) == 0x701


def test_wrong_data_length_gets_an_error_reply(served) -> None:
    _, server = served
    assert ams_error(exchange(server.port, frame(2, bytes(12), length=40))) == 0x705
    # a Read whose data is too short for its three fields
    assert ads_result(exchange(server.port, frame(2, bytes(5)))) == 0x705


@pytest.mark.parametrize("payload", [
    struct.pack("<HI", 0, 0xFFFF_FFFF),  # claims 4 GB: never read, never allocated
    struct.pack("<HI", 0, 10),  # shorter than an AMS header
    struct.pack("<HI", 1, 32) + bytes(32),  # the reserved field is not 0
], ids=["4GB", "short", "reserved"])
def test_frames_the_server_cannot_take_close_the_connection(served, payload: bytes) -> None:
    _, server = served
    assert exchange(server.port, payload) == b""
    assert ads_result(exchange(server.port, frame(4, b""))) == 0  # and it serves on


def test_a_truncated_frame_leaves_the_server_serving(served) -> None:
    _, server = served
    whole = frame(2, struct.pack("<III", 0x4040, 0, 8))
    with socket.create_connection(("127.0.0.1", server.port), timeout=3.0) as sock:
        sock.sendall(whole[:len(whole) // 2])  # and hangs up in the middle
    assert ads_result(exchange(server.port, frame(4, b""))) == 0
    # the rest of a frame sent in pieces is awaited
    with socket.create_connection(("127.0.0.1", server.port), timeout=3.0) as sock:
        for piece in (whole[:3], whole[3:20], whole[20:]):
            sock.sendall(piece)
        assert ads_result(_reply(sock)) == 0


def test_two_frames_in_one_segment_get_two_replies(served) -> None:
    _, server = served
    with socket.create_connection(("127.0.0.1", server.port), timeout=3.0) as sock:
        sock.sendall(frame(4, b"", invoke=1) + frame(1, b"", invoke=2))
        first, second = _reply(sock), _reply(sock)
    assert [struct.unpack_from("<HI", reply, 6 + 16)[0] for reply in (first, second)] == [4, 1]
    assert second[6 + 32 + 8:6 + 32 + 18] == b"openmotion"


def test_connections_beyond_the_limit_are_closed(served) -> None:
    host, _ = served
    with AdsServer(host, port=0, max_clients=2) as server:
        with socket.create_connection(("127.0.0.1", server.port), timeout=3.0), \
                socket.create_connection(("127.0.0.1", server.port), timeout=3.0) as second:
            assert ads_result(exchange_on(second, frame(4, b""))) == 0
            assert exchange(server.port, frame(4, b"")) == b""  # a third: closed at once
        _wait_until(lambda: server.clients == 0)
        assert ads_result(exchange(server.port, frame(4, b""))) == 0


def exchange_on(sock: socket.socket, payload: bytes) -> bytes:
    sock.sendall(payload)
    return _reply(sock)


def _wait_until(predicate, timeout: float = 3.0) -> None:
    end = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < end, "timed out"
        time.sleep(0.01)


def test_bounded_sum_commands(served) -> None:
    _, server = served
    huge = struct.pack("<IIII", 0xF080, 1_000_000, 4, 12) + bytes(12)  # a million requests
    assert ads_result(exchange(server.port, frame(9, huge))) == 0x705
    read = struct.pack("<IIII", 0x4040, 0, 0xFFFF_FFF0, 0)  # asks for 4 GB back
    reply = exchange(server.port, frame(9, read))
    assert ads_result(reply) == 0 and len(reply) < 1 << 20


def test_random_bytes_never_stop_the_server(served) -> None:
    """10 000 random byte strings, half of them raw, half inside a well-formed header with
    a random command, while a pyads client reads on; the machine stays as it was."""
    host, server = served
    rng = random.Random(20261207)
    before = host.snapshot.values.copy()
    failures: list[BaseException] = []
    reads = [0]
    stop = threading.Event()

    def read_on() -> None:
        n = next(_NET_IDS)
        conn = pyads.Connection(f"127.0.1.{n}.1.1", 851, f"127.0.0.1:{server.port}")
        conn.open()
        conn.set_timeout(3000)
        try:
            while not stop.is_set():
                assert conn.read_by_name("x.NcToPlc.ActPos", pyads.PLCTYPE_LREAL) == 0.0
                reads[0] += 1
        except BaseException as error:  # noqa: BLE001 - reported by the test
            failures.append(error)
        finally:
            conn.close()

    reader = threading.Thread(target=read_on)
    reader.start()
    try:
        sock = socket.create_connection(("127.0.0.1", server.port), timeout=3.0)
        replies = closes = 0
        for number in range(FUZZ_FRAMES):
            garbage = rng.randbytes(rng.randrange(0, 80))
            if number % 2:  # raw bytes on a connection of their own, which then ends
                with socket.create_connection(("127.0.0.1", server.port), timeout=3.0) as raw:
                    try:
                        raw.sendall(garbage)
                        raw.shutdown(socket.SHUT_WR)
                        _drain(raw)
                    except TimeoutError:
                        raise  # the server neither answered nor closed
                    except OSError:  # closed (or reset) by the server already
                        pass
                    closes += 1
                continue
            command = rng.choice([1, 2, 3, 4, 5, 6, 7, 8, 9, 0, 0xFFFF])
            group = rng.choice([0x4040, 0xF003, 0xF004, 0xF005, 0xF006, 0xF009, 0xF00B,
                                0xF00F, 0xF080, 0xF081, 0xF082, rng.randrange(1 << 32)])
            data = struct.pack("<II", group, rng.randrange(4096)) + garbage
            sock.sendall(frame(command, data, invoke=number))
            reply = _reply(sock)  # a well-formed header is answered
            assert struct.unpack_from("<I", reply, 6 + 28)[0] == number
            replies += 1
        sock.close()
    finally:
        stop.set()
        reader.join(timeout=10)
    assert not failures, failures
    assert replies == closes == FUZZ_FRAMES // 2 and reads[0] > 0
    _wait_until(lambda: server.clients == 0)  # its thread sees the last close a moment later
    assert (host.snapshot.values == before).all()
    assert ads_result(exchange(server.port, frame(4, b""))) == 0
