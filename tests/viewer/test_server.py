"""The viewer's server: the page and its files (all shipped, nothing from elsewhere), the
websocket stream and its controls, same-origin only, and a page that never reads."""

from __future__ import annotations

import base64
import fnmatch
import json
import re
import socket
import time
import tomllib
import urllib.error
import urllib.request
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from websockets.exceptions import InvalidStatus
from websockets.sync.client import ClientConnection, connect

from openmotion import Runtime
from openmotion.scenario import examples_dir
from openmotion.viewer import Session, serving
from openmotion.viewer.server import STATIC

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def server() -> Iterator[tuple[str, Session]]:
    session = Session.for_scenario(examples_dir() / "single_move.yaml")
    with serving(session) as url:  # the app's lifespan starts the kernel
        yield url, session


def get(url: str) -> tuple[int, str, str]:
    """Status, content type and text of a GET."""
    try:
        with urllib.request.urlopen(url, timeout=5) as response:
            return response.status, response.headers["content-type"], response.read().decode()
    except urllib.error.HTTPError as error:
        return error.code, error.headers["content-type"], error.read().decode()


def post(url: str, data: object, origin: str | None = None) -> int:
    headers = {"Content-Type": "application/json"} | ({"Origin": origin} if origin else {})
    request = urllib.request.Request(url, json.dumps(data).encode(), headers, method="POST")
    try:
        with urllib.request.urlopen(request, timeout=5) as response:
            return response.status
    except urllib.error.HTTPError as error:
        return error.code


def socket_of(url: str, **options: Any) -> ClientConnection:
    return connect(url.replace("http://", "ws://") + "ws", open_timeout=5, **options)


def receive_until(ws: ClientConnection, predicate: Callable[[dict], bool],
                  limit: int = 200) -> dict:
    """The first message that ``predicate`` accepts."""
    for _ in range(limit):
        message = json.loads(ws.recv(timeout=5))
        if predicate(message):
            return message
    raise AssertionError("no such message")


def wait_for(condition: Callable[[], bool]) -> None:
    deadline = time.monotonic() + 5.0
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.01)


def test_the_page_and_its_files_come_from_the_package(server: tuple[str, Session]) -> None:
    url, _ = server
    status, _, page = get(url)
    assert status == 200 and '<canvas id="machine"' in page
    for name, kind in (("viewer.js", "javascript"), ("viewer.css", "text/css")):
        status, content_type, _ = get(f"{url}static/{name}")
        assert status == 200 and kind in content_type


def test_nothing_is_loaded_from_elsewhere() -> None:
    """No CDN, no web font, no remote image: the viewer works offline."""
    page = (STATIC / "index.html").read_text()
    for target in re.findall(r'(?:src|href)="([^"]*)"', page):
        assert target.startswith(("/static/", "data:")), target
    for path in STATIC.iterdir():
        assert not re.search(r"https?://|@import|url\(", path.read_text()), path.name


def test_the_static_files_are_package_data() -> None:
    setup = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    patterns = setup["package-data"]["openmotion.viewer"]
    for path in STATIC.iterdir():
        relative = path.relative_to(STATIC.parent).as_posix()
        assert any(fnmatch.fnmatch(relative, pattern) for pattern in patterns), relative


def test_the_websocket_streams_hello_scope_and_frames_and_takes_controls(
        server: tuple[str, Session]) -> None:
    url, session = server
    with socket_of(url) as ws:
        hello = json.loads(ws.recv(timeout=5))
        assert hello["type"] == "hello" and hello["name"] == "single move"
        assert hello["restart"] is True and "x.set_position" in hello["signals"]
        scope = json.loads(ws.recv(timeout=5))
        assert scope["type"] == "scope" and scope["reset"] and scope["samples"]
        assert json.loads(ws.recv(timeout=5))["type"] == "frame"
        ws.send(json.dumps({"op": "pause"}))
        paused = receive_until(ws, lambda m: m["type"] == "frame" and m["paused"])
        assert session.paused and paused["time"] == session.machine.runtime.now
        ws.send("{not json")
        assert "Expecting" in receive_until(ws, lambda m: m["type"] == "error")["message"]
        ws.send(json.dumps({"op": "speed", "value": -2}))
        assert "speed" in receive_until(ws, lambda m: m["type"] == "error")["message"]


def test_the_http_api_reads_frames_and_takes_controls(server: tuple[str, Session]) -> None:
    url, session = server
    wait_for(lambda: get(f"{url}api/frame")[0] == 200)
    assert json.loads(get(f"{url}api/frame")[2])["type"] == "frame"
    assert json.loads(get(f"{url}api/hello")[2])["type"] == "hello"
    assert post(f"{url}api/control", {"op": "fly"}) == 400
    assert post(f"{url}api/control", {"op": "pause"}) == 204
    wait_for(lambda: session.paused)


def test_pages_of_other_origins_are_refused(server: tuple[str, Session]) -> None:
    url, session = server
    with pytest.raises(InvalidStatus):
        socket_of(url, origin="http://elsewhere.example")  # type: ignore[arg-type]
    assert post(f"{url}api/control", {"op": "pause"}, origin="http://elsewhere.example") == 403
    assert not session.paused
    own = url.rstrip("/")
    with socket_of(url, origin=own) as ws:  # type: ignore[arg-type]
        assert json.loads(ws.recv(timeout=5))["type"] == "hello"
    assert post(f"{url}api/control", {"op": "pause"}, origin=own) == 204


def _stuck_page(url: str) -> socket.socket:
    """A websocket client that shakes hands and then never reads: its buffers fill up."""
    host, port = url.removeprefix("http://").rstrip("/").split(":")
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.connect((host, int(port)))
    key = base64.b64encode(b"openmotion-stuck").decode()
    sock.sendall(f"GET /ws HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                 f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                 "Sec-WebSocket-Version: 13\r\n\r\n".encode())
    return sock


def test_a_page_that_never_reads_slows_neither_the_kernel_nor_other_pages() -> None:
    rt = Runtime()
    for number in range(500):  # big frames (~130 kB): the stuck page's buffers fill in 1 s
        axis = rt.add_axis(f"axis{number}")
        axis.power()
        axis.move_velocity(10.0 + number)
    session = Session(rt)
    with serving(session) as url:
        stuck = _stuck_page(url)
        try:
            with socket_of(url) as page:
                start_wall, start_virtual = time.monotonic(), rt.now
                time.sleep(2.0)
                frame = None
                while frame is None or frame["seq"] < session.frame.seq - 2:  # type: ignore
                    message = json.loads(page.recv(timeout=5))
                    frame = message if message["type"] == "frame" else frame
                wall = time.monotonic() - start_wall
                assert rt.now - start_virtual > 0.8 * wall  # the kernel kept the wall clock
                assert abs(frame["time"] - rt.now) < 0.5  # the reading page is up to date
        finally:
            stuck.close()


def test_the_first_page_starts_a_session_that_waits_for_one() -> None:
    session = Session.for_scenario(examples_dir() / "single_move.yaml", wait_for_page=True)
    with serving(session) as url:
        wait_for(lambda: get(f"{url}api/frame")[0] == 200)
        time.sleep(0.3)  # the kernel runs its passes, the machine waits at its start
        waiting = json.loads(get(f"{url}api/frame")[2])
        assert waiting["waiting"] and (waiting["time"], waiting["cycle"]) == (0.0, 0)
        assert session.machine.runtime.cycle == 0  # reading frames over HTTP starts nothing
        with socket_of(url) as ws:
            running = receive_until(ws, lambda m: m["type"] == "frame" and m["cycle"] > 0)
            assert not running["waiting"] and not running["finished"]
        assert not session.waiting


def test_a_page_opened_after_the_end_sees_it_finished_and_can_restart() -> None:
    session = Session.for_scenario(examples_dir() / "single_move.yaml", speed=20.0)
    with serving(session) as url:  # started at once: nobody watches
        wait_for(lambda: session.finished)
        with socket_of(url) as ws:
            ended = receive_until(ws, lambda m: m["type"] == "frame")
            assert ended["finished"] and ended["time"] > 0.5 and ended["generation"] == 1
            ws.send(json.dumps({"op": "pause"}))  # a restart keeps the pause: the new run
            ws.send(json.dumps({"op": "restart"}))  # waits at its start, for the test to see
            again = receive_until(ws, lambda m: m["type"] == "frame" and m["generation"] == 2)
            assert (again["time"], again["finished"], again["paused"]) == (0.0, False, True)
            ws.send(json.dumps({"op": "play"}))
            receive_until(ws, lambda m: m["type"] == "frame" and m["cycle"] > 0)
