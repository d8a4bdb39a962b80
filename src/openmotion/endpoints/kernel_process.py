"""A machine host whose kernel runs in a process of its own (D-320).

The servers of ``openmotion serve`` (asyncua's event loop, the ADS threads) are busy Python
code. In one interpreter they hold the interpreter lock while a 1 ms motion cycle is due,
and the cycle finishes late. ``ProcessHost`` moves the kernel out of their way: it forks a
kernel process that runs an ordinary ``MachineHost`` (its own interpreter, its own lock), and
keeps in the servers' process only the description of the machine (its model, names and
commands, which both processes built before the fork, so they agree).

Snapshots cross on a ``SnapshotBoard``: one shared memory block the kernel writes after every
batch of cycles and the servers read without asking, under a sequence lock (an odd version
while a write is under way; a reader that sees the version change retries), so a reader
always gets the values of one cycle. Requests (a call, a switch, a step, a pause, the status)
cross a pipe, one at a time, and their results and errors come back on it.

The servers' process talks to a ``ProcessHost`` exactly as to a ``MachineHost``: the
endpoints do not know which one they serve.
"""

from __future__ import annotations

import gc
import mmap
import multiprocessing
import os
import pickle
import threading
import time
from collections.abc import Callable
from contextlib import AbstractContextManager, suppress
from dataclasses import replace
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.endpoints.host import (
    REQUEST_TIMEOUT,
    Clients,
    HostError,
    HostStatus,
    MachineHost,
    Pace,
    Snapshot,
)
from openmotion.endpoints.wire import HandleState, WireCommand
from openmotion.kernel.model import MachineObject
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.live import Machine, scenario_machine
from openmotion.scenario.schema import Scenario

__all__ = ["ProcessHost", "SnapshotBoard", "kernel_process_available"]

HANDLE_BYTES = 1 << 20  #: room for the pickled command outputs of one snapshot
POLL = 0.0005  #: [s] how often a waiting reader looks at the board for a newer snapshot
READ_RETRIES = 10_000  #: tries of a reader before it calls the board stuck
START_TIMEOUT = 30.0  #: [s] for the kernel process to say it is ready
STOP_TIMEOUT = 5.0  #: [s] for the kernel process to end before it is killed
#: how much the kernel process lowers its nice value where it may (D-321)
KERNEL_NICE = -10
#: the real-time priority (SCHED_FIFO, the lowest) of the kernel thread where it may (D-321)
KERNEL_RT_PRIORITY = 1
#: what a kernel process may ask of the scheduler: real time (else nice), nice, or nothing
PRIORITIES = ("realtime", "nice", "normal")
_HEADER = 8  #: version, seq, cycle, time, handle bytes, failed, (2 spare)


def kernel_process_available() -> bool:
    """Whether this platform can fork a kernel process (POSIX: yes; Windows: no)."""
    return "fork" in multiprocessing.get_all_start_methods()


class SnapshotBoard:
    """One snapshot at a time in memory shared by a writer process and its readers."""

    def __init__(self, signals: int, handle_bytes: int = HANDLE_BYTES) -> None:
        self.signals = signals
        words = _HEADER + signals
        # an anonymous shared mapping: a forked process writes to the very same pages
        self._memory = mmap.mmap(-1, words * 8 + handle_bytes)
        self._words = np.frombuffer(self._memory, dtype=np.float64, count=words)
        self._header = self._words[:_HEADER]
        self._values = self._words[_HEADER:]
        self._blob = memoryview(self._memory)[words * 8:]
        self._last_handles: dict[int, HandleState] | None = None
        self._last_blob = b""
        self._cached: tuple[float, Snapshot] | None = None

    # -- the writer (the kernel process) --------------------------------------------------

    def write(self, snapshot: Snapshot) -> None:
        """Publish ``snapshot``; readers see it whole or not at all."""
        if snapshot.handles != self._last_handles:
            self._last_handles = dict(snapshot.handles)
            self._last_blob = self._fit(snapshot.handles)
        header = self._header
        header[0] += 1.0  # odd: a write is under way
        header[1:5] = (snapshot.seq, snapshot.cycle, snapshot.time, len(self._last_blob))
        self._values[:] = snapshot.values
        self._blob[:len(self._last_blob)] = self._last_blob
        header[0] += 1.0

    def fail(self) -> None:
        """Say that the kernel stopped on an error (readers' ``failed``)."""
        self._header[5] = 1.0

    def _fit(self, handles: dict[int, HandleState]) -> bytes:
        blob = pickle.dumps(handles, protocol=pickle.HIGHEST_PROTOCOL)
        if len(blob) > len(self._blob):  # only the running commands, then
            blob = pickle.dumps({t: h for t, h in handles.items() if h.busy})
        if len(blob) > len(self._blob):
            raise HostError(f"the outputs of {len(handles)} commands do not fit the "
                            f"snapshot board ({len(self._blob)} bytes)")
        return blob

    # -- readers (the servers' process) ---------------------------------------------------

    @property
    def failed(self) -> bool:
        return bool(self._header[5])

    @property
    def seq(self) -> int:
        return int(self._header[1])

    def read(self) -> Snapshot:
        """The newest snapshot, copied out whole."""
        header = self._header
        for _ in range(READ_RETRIES):
            version = float(header[0])
            if version % 2.0:
                time.sleep(0)
                continue
            cached = self._cached
            if cached is not None and cached[0] == version:
                return cached[1]
            seq, cycle, now, size = (float(v) for v in header[1:5])
            values = self._values.copy()
            blob = bytes(self._blob[:int(size)])
            if float(header[0]) != version:
                continue
            handles = pickle.loads(blob) if blob else {}  # noqa: S301 - our own kernel's
            snapshot = Snapshot(int(seq), int(cycle), now, values, handles)
            self._cached = (version, snapshot)
            return snapshot
        raise HostError("the snapshot board stays busy: the kernel process hangs")

    def close(self) -> None:
        self._cached = None
        self._last_handles = None
        del self._header, self._values, self._words
        self._blob.release()
        self._memory.close()


class ProcessHost:
    """A machine host whose kernel steps in a forked process (see the module's text).

    Same interface as ``MachineHost`` for the endpoints; ``submit`` of arbitrary code is the
    one thing it cannot do (code does not cross processes), so clients use ``call``,
    ``switch`` and the pace methods.
    """

    def __init__(self, machine_: Machine | Runtime, *, pace: Pace | str = Pace.WALL,
                 speed: float = 1.0, priority: str = "realtime") -> None:
        if not kernel_process_available():
            raise HostError("a kernel process needs fork (POSIX); use MachineHost")
        if priority not in PRIORITIES:
            raise ConfigError(f"priority must be one of {', '.join(PRIORITIES)}, "
                              f"not {priority!r}")
        self.priority = priority
        #: the machine as built; the kernel process steps its copy, this one stays at rest
        #: and describes the machine (model, names, commands) to the servers
        self._kernel = MachineHost(machine_, pace=pace, speed=speed)
        self.machine = self._kernel.machine
        self.pace = self._kernel.pace
        self.speed = self._kernel.speed
        self.model = self._kernel.model
        self.names = self._kernel.names
        self.index = self._kernel.index
        self.signals = self._kernel.signals
        self.commands = self._kernel.commands
        self._objects = {id(obj): number for number, obj in enumerate(self.model)}
        self._board = SnapshotBoard(len(self.names))
        self._board.write(self._kernel.snapshot)
        self._process: multiprocessing.process.BaseProcess | None = None
        self._pipe: Connection | None = None
        self._lock = threading.Lock()
        self._clients = Clients()
        self._started = False
        self._closed = False
        #: what the scheduler gave the kernel ("realtime", "nice -10" or "normal"), once it
        #: runs: the ``priority`` asked for, or less where the system refused it
        self.kernel_priority: str | None = None
        self.kernel_thread_id: int | None = None  #: the kernel thread's id in the system

    @classmethod
    def for_scenario(cls, source: str | Path | Scenario, **options: Any) -> ProcessHost:
        return cls(scenario_machine(source), **options)

    # -- life -----------------------------------------------------------------------------

    def prepare(self) -> ProcessHost:
        """Fork the kernel process now, its machine standing: before the servers start
        threads (a fork copies only the thread that forks)."""
        if self._closed:
            raise HostError("the host was stopped; make a new one")
        if self._process is None:
            ours, theirs = multiprocessing.Pipe()
            process = multiprocessing.get_context("fork").Process(
                target=_kernel_main,
                args=(self._kernel, self._board, theirs, ours, self.priority),
                name="openmotion-kernel", daemon=True)
            process.start()
            theirs.close()
            self._process, self._pipe = process, ours
            self._ask("ready", timeout=START_TIMEOUT)
        return self

    def start(self) -> ProcessHost:
        if self._started:
            raise HostError("the host runs already")
        self.prepare()
        self.kernel_thread_id, self.kernel_priority = self._ask("start")
        self._started = True
        return self

    def stop(self) -> None:
        process, pipe = self._process, self._pipe
        self._started, self._closed = False, True
        if process is None or pipe is None:
            return
        with suppress(HostError):
            self._ask("stop", timeout=STOP_TIMEOUT)
        process.join(STOP_TIMEOUT)
        if process.is_alive():
            process.kill()
            process.join(STOP_TIMEOUT)
        pipe.close()
        self._process = self._pipe = None

    def __enter__(self) -> ProcessHost:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    @property
    def running(self) -> bool:
        process = self._process
        return (self._started and process is not None and process.is_alive()
                and not self._board.failed)

    @property
    def cycle_time(self) -> float:
        return self._kernel.cycle_time

    @property
    def kernel_pid(self) -> int | None:
        """The kernel process's id (None before ``prepare``/``start``)."""
        return self._process.pid if self._process is not None else None

    # -- reading ---------------------------------------------------------------------------

    @property
    def snapshot(self) -> Snapshot:
        return self._board.read()

    def wait_snapshot(self, after: int, timeout: float = REQUEST_TIMEOUT) -> Snapshot:
        """The first snapshot newer than ``after``; ``HostError`` on timeout."""
        deadline = time.monotonic() + timeout
        while self._board.seq <= after and self.running:
            if time.monotonic() >= deadline:
                raise HostError(f"no new snapshot within {timeout} s")
            time.sleep(POLL)
        return self._board.read()

    # the description is the resting copy's: it answers with the board's snapshot

    def value(self, name: str, snapshot: Snapshot | None = None) -> float:
        return self._kernel.value(name, snapshot or self.snapshot)

    def handle(self, ticket: int, snapshot: Snapshot | None = None) -> HandleState:
        return self._kernel.handle(ticket, snapshot or self.snapshot)

    def command(self, owner: str | MachineObject, name: str) -> WireCommand:
        return self._kernel.command(owner, name)

    def commands_of(self, owner: MachineObject) -> tuple[WireCommand, ...]:
        return self._kernel.commands_of(owner)

    # -- commanding ------------------------------------------------------------------------

    def submit(self, request: Callable[[], Any], timeout: float = REQUEST_TIMEOUT) -> Any:
        raise HostError("the kernel runs in its own process: code cannot be sent to it; "
                        "use call, switch, advance or the pace methods")

    def call(self, owner: str | MachineObject, name: str,
             inputs: dict[str, Any] | None = None) -> int:
        self._check(owner, name, inputs, level=False)
        return int(self._ask("call", self._ref(owner), name, dict(inputs or {})))

    def switch(self, owner: str | MachineObject, name: str,
               inputs: dict[str, Any] | None = None) -> Any:
        self._check(owner, name, inputs, level=True)
        return self._ask("switch", self._ref(owner), name, dict(inputs or {}))

    def _check(self, owner: str | MachineObject, name: str, inputs: dict[str, Any] | None,
               *, level: bool) -> None:
        """The wire's checks here, so a bad request never travels (the kernel checks too)."""
        command = self.command(owner, name)
        if command.spec.level and not level:
            raise ConfigError(f"{name} sets a level and returns no command: use switch()")
        if level and not command.spec.level:
            raise ConfigError(f"{name} starts a command: use call()")
        command.arguments(inputs or {}, self.model)

    def _ref(self, owner: str | MachineObject) -> str | int:
        """How the kernel process finds ``owner``: its name, or its place in the model."""
        if isinstance(owner, MachineObject):
            return self._objects[id(owner)]
        return owner

    # -- pace ------------------------------------------------------------------------------

    def advance(self, cycles: int = 1) -> Snapshot:
        if self.pace is not Pace.LOCKSTEP:
            raise HostError("advance needs pace 'lockstep'; this host follows the wall clock")
        if isinstance(cycles, bool) or not isinstance(cycles, int) or cycles < 0:
            raise ConfigError(f"cycles must be a whole number >= 0, not {cycles!r}")
        self._ask("advance", cycles, timeout=REQUEST_TIMEOUT + cycles * 0.01)
        return self._board.read()

    def run_for(self, seconds: float) -> Snapshot:
        if not isinstance(seconds, int | float) or seconds != seconds or seconds < 0 \
                or seconds == float("inf"):
            raise ConfigError(f"seconds must be a finite number >= 0, not {seconds!r}")
        return self.advance(round(seconds / self.cycle_time))

    def pause(self) -> None:
        self._ask("pause")

    def resume(self) -> None:
        self._ask("resume")

    def set_speed(self, speed: float) -> None:
        self.speed = self._ask("set_speed", speed)

    # -- clients ---------------------------------------------------------------------------

    def client(self, kind: str) -> AbstractContextManager[None]:
        return self._clients.connected(kind)

    def status(self) -> HostStatus:
        clients = self._clients.connected_now()
        if self._process is None:
            snapshot = self.snapshot
            return HostStatus(self.pace, self.speed, False, snapshot.cycle, snapshot.time,
                              clients, 0.0, 0.0, 0)
        try:
            status: HostStatus = self._ask("status")
        except HostError as error:
            snapshot = self.snapshot
            return HostStatus(self.pace, self.speed, False, snapshot.cycle, snapshot.time,
                              clients, 0.0, 0.0, 0, str(error))
        return replace(status, clients=clients)

    # -- the pipe --------------------------------------------------------------------------

    def _ask(self, what: str, *args: Any, timeout: float = REQUEST_TIMEOUT) -> Any:
        """Send one request to the kernel process; its result, or its error raised here."""
        pipe, process = self._pipe, self._process
        if pipe is None or process is None:
            raise HostError("the host is not running")
        with self._lock:
            try:
                pipe.send((what, args))
                if not pipe.poll(timeout):
                    raise HostError(f"the kernel process did not answer {what!r} within "
                                    f"{timeout:g} s")
                ok, result = pipe.recv()
            except (EOFError, OSError, BrokenPipeError):
                raise HostError(f"the kernel process ended (exit code "
                                f"{process.exitcode})") from None
        if not ok:
            raise result
        return result


def _kernel_main(host: MachineHost, board: SnapshotBoard, pipe: Connection,
                 other_end: Connection, priority: str) -> None:
    """The kernel process: the host steps the machine; requests come on ``pipe``."""
    other_end.close()
    # everything the fork copied stays: the collector need not walk it again and again
    # (a full collection over the servers' whole heap is a pause of milliseconds)
    gc.freeze()
    host.observe(board.write)
    objects = list(host.model)

    def owner(ref: str | int) -> str | MachineObject:
        return objects[ref] if isinstance(ref, int) else ref

    def set_speed(speed: float) -> float:
        host.set_speed(speed)
        return host.speed

    def start() -> tuple[int | None, str]:
        host.start()
        return host.kernel_thread_id, _raise_priority(host.kernel_thread_id, priority)

    requests: dict[str, Callable[..., Any]] = {
        "ready": lambda: None,
        "start": start,
        "call": lambda ref, name, inputs: host.call(owner(ref), name, inputs),
        "switch": lambda ref, name, inputs: host.switch(owner(ref), name, inputs),
        "advance": lambda cycles: host.advance(cycles).seq,
        "pause": host.pause,
        "resume": host.resume,
        "set_speed": set_speed,
        "status": host.status,
    }
    try:
        while True:
            if not pipe.poll(0.1):
                if host.failed:
                    board.fail()
                continue
            what, args = pipe.recv()
            if what == "stop":
                host.stop()
                pipe.send((True, None))
                return
            try:
                reply: tuple[bool, Any] = (True, requests[what](*args))
            except Exception as error:  # noqa: BLE001 - the servers' process raises it
                reply = (False, _portable(error))
            if host.failed:
                board.fail()
            pipe.send(reply)
    except (EOFError, OSError, KeyboardInterrupt):  # the servers' process went away
        host.stop()


def _raise_priority(thread: int | None, priority: str) -> str:
    """Ask the scheduler for the kernel thread's ``priority``; what it got (D-321)."""
    if thread is None or priority == "normal":
        return "normal"
    if priority == "realtime":
        with suppress(OSError, AttributeError):  # no right to, or no such scheduler here
            os.sched_setscheduler(thread, os.SCHED_FIFO, os.sched_param(KERNEL_RT_PRIORITY))
            return "realtime"
    try:
        now = os.getpriority(os.PRIO_PROCESS, thread)  # Linux: of one thread
        os.setpriority(os.PRIO_PROCESS, thread, max(-20, now + KERNEL_NICE))
    except (OSError, AttributeError):
        return "normal"
    return f"nice {KERNEL_NICE}"


def _portable(error: Exception) -> Exception:
    """``error`` as it can cross the pipe (an exception whose class cannot be rebuilt from
    its arguments becomes a ``HostError`` with its text)."""
    try:
        pickle.loads(pickle.dumps(error))  # noqa: S301 - our own bytes
    except Exception:  # noqa: BLE001 - any failure to cross means: send the text
        return HostError(f"{type(error).__name__}: {error}")
    return error
