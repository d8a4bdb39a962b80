"""The viewer's web server: the page, its files, the frame stream and the controls.

One websocket per page. The first one to connect starts a session that waits for a page.
Its sending task looks at the session's latest frame every half frame period and sends it
when it is new, so a page that reads slowly skips frames and never holds anything up; its
receiving loop hands control messages to the session. Everything the page
needs ships in ``static/``: the server fetches nothing and the page loads nothing from
elsewhere, so the viewer works offline.

The server listens on 127.0.0.1 by default and accepts pages of its own origin only (a page
of another site could otherwise drive the session through the browser).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import socket
import sys
import threading
import time
import webbrowser
from collections.abc import AsyncIterator, Callable, Iterator
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import uvicorn
from starlette.applications import Starlette
from starlette.datastructures import Headers
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from openmotion.viewer.session import Session

STATIC = Path(__file__).parent / "static"
DEFAULT_PORT = 8765
START_TIMEOUT = 10.0  #: seconds ``serving`` waits for the server to listen


def create_app(session: Session) -> Starlette:
    """The ASGI app of one session; its lifespan starts and stops the session's kernel."""

    @contextlib.asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        session.start()
        try:
            yield
        finally:
            await asyncio.to_thread(session.stop)

    async def index(request: Request) -> Response:
        return FileResponse(STATIC / "index.html", headers={"Cache-Control": "no-cache"})

    async def frame(request: Request) -> Response:
        latest = session.frame
        if latest is None:
            return JSONResponse({"error": "no frame yet"}, status_code=503)
        return Response(latest.text, media_type="application/json")

    async def hello(request: Request) -> Response:
        return Response(session.hello(), media_type="application/json")

    async def control(request: Request) -> Response:
        if not _same_origin(request.headers):
            return JSONResponse({"error": "cross-origin request"}, status_code=403)
        try:
            session.control(json.loads(await request.body()))
        except ValueError as exc:  # bad JSON too
            return JSONResponse({"error": str(exc)}, status_code=400)
        return Response(status_code=204)

    async def stream(websocket: WebSocket) -> None:
        if not _same_origin(websocket.headers):
            await websocket.close(code=1008)
            return
        await websocket.accept()
        session.page_connected()
        sender = asyncio.create_task(_send_frames(websocket, session))
        try:
            await _receive_controls(websocket, session)
        finally:
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError, WebSocketDisconnect, OSError,
                                     RuntimeError):
                await sender

    return Starlette(routes=[
        Route("/", index),
        Route("/api/frame", frame),
        Route("/api/hello", hello),
        Route("/api/control", control, methods=["POST"]),
        WebSocketRoute("/ws", stream),
        Mount("/static", StaticFiles(directory=STATIC), name="static"),
    ], lifespan=lifespan)


async def _send_frames(websocket: WebSocket, session: Session) -> None:
    """Send the newest frame whenever there is one, after a hello for every new machine and
    the scope samples this page has not seen."""
    generation, seq, scope_id, count = 0, 0, 0, 0
    while True:
        latest = session.frame
        if latest is not None and latest.seq != seq:
            if latest.generation != generation:
                await websocket.send_text(session.hello())
                generation = latest.generation
            scope, scope_id, count = session.scope_since(scope_id, count)
            if scope is not None:
                await websocket.send_text(json.dumps(scope, separators=(",", ":")))
            await websocket.send_text(latest.text)
            seq = latest.seq
        await asyncio.sleep(0.5 / session.current_frame_rate)


async def _receive_controls(websocket: WebSocket, session: Session) -> None:
    while True:
        message = await websocket.receive()
        if message["type"] == "websocket.disconnect":
            return
        try:
            session.control(json.loads(message.get("text") or "null"))
        except ValueError as exc:
            await websocket.send_text(json.dumps({"type": "error", "message": str(exc)}))


def _same_origin(headers: Headers) -> bool:
    """No Origin (not a browser) or the page's own: the Host it was served from."""
    origin = headers.get("origin")
    return origin is None or urlsplit(origin).netloc == headers.get("host")


# -- serving -------------------------------------------------------------------------------


def serve(session: Session, host: str = "127.0.0.1", port: int = DEFAULT_PORT, *,
          open_browser: bool = False, announce: Callable[[str], Any] | None = None) -> None:
    """Serve the page until interrupted (Ctrl+C). Raises ``OSError`` when the port is taken;
    ``announce(url)`` is called once the port listens."""
    with _listen(host, port) as sock:
        url = _url(host, sock)
        if announce is not None:
            announce(url)
        if open_browser:
            open_page(url)
        _server(session).run(sockets=[sock])


@contextlib.contextmanager
def serving(session: Session, host: str = "127.0.0.1", port: int = 0) -> Iterator[str]:
    """Serve on a background thread while the block runs; yields the page's URL. Port 0
    takes a free port."""
    sock = _listen(host, port)
    server = _server(session)
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]},
                              name="openmotion-viewer-server", daemon=True)
    thread.start()
    try:
        deadline = time.monotonic() + START_TIMEOUT
        while not server.started:
            if not thread.is_alive() or time.monotonic() > deadline:
                raise RuntimeError("the viewer's server did not start")
            time.sleep(0.01)
        yield _url(host, sock)
    finally:
        server.should_exit = True
        thread.join(START_TIMEOUT)
        sock.close()


def open_page(url: str) -> bool:
    """Open ``url`` in the desktop's browser; False where there is no desktop (a text-mode
    browser would take over the terminal)."""
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY")
                                                 or os.environ.get("WAYLAND_DISPLAY")):
        return False
    return webbrowser.open(url)


def _server(session: Session) -> uvicorn.Server:
    # websockets-sansio: the websockets implementation that is not deprecated (websockets 14+
    # deprecates the legacy server uvicorn's "websockets" uses); no logging set-up of its own
    config = uvicorn.Config(create_app(session), http="h11", ws="websockets-sansio",
                            lifespan="on", log_config=None, log_level="warning",
                            access_log=False, timeout_graceful_shutdown=2)
    return uvicorn.Server(config)


def _listen(host: str, port: int) -> socket.socket:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    return socket.create_server((host, port), family=family)


def _url(host: str, sock: socket.socket) -> str:
    port = sock.getsockname()[1]
    shown = {"0.0.0.0": "127.0.0.1", "::": "[::1]"}.get(host, f"[{host}]" if ":" in host
                                                          else host)
    return f"http://{shown}:{port}/"
