"""A machine served to clients: one kernel thread steps it, clients read snapshots.

The host is what every endpoint (OPC UA, ADS, FMI) stands on. Its kernel thread owns the
runtime: it alone steps it, reads it and starts commands on it, so a client's request never
lands in the middle of a cycle. Requests (``submit``, ``call``) wait in a queue and run
between two cycles, as the statements of a PLC program before the motion task's cycle.

After each batch of cycles the thread reads every signal of the machine model into one
array, a ``Snapshot`` of one cycle, and publishes it by replacing one reference: clients
sample at their own intervals and always see the values of one and the same cycle, with the
outputs of the commands they started (``HandleState``, the PLCopen handshake).

Two paces (D-256):

- ``wall``: virtual time follows the wall clock times ``speed`` (``PacedRuntime``'s rule,
  re-anchored at every resume and speed change so a pause never makes the machine catch up
  in a burst). How late each cycle finished against its slot is measured (``status``). A
  machine more than ``MAX_LAG`` behind lets virtual time slip, and says so.
- ``lockstep``: the machine stands until a client advances it (``advance``), for test
  harnesses that need the same cycles every run.

A served scenario plays its timeline and checks as ``openmotion run`` does, but it does not
end: once its timeline is over the machine goes on, driven by its clients.
"""

from __future__ import annotations

import math
import queue
import sys
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from contextlib import AbstractContextManager, contextmanager
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path
from typing import Any

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.endpoints.wire import HandleState, WireCommand, handle_state, wire_commands
from openmotion.kernel.model import MachineModel, MachineObject, Signal, kind_of, machine
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.live import Machine, scenario_machine
from openmotion.scenario.schema import Scenario

__all__ = ["HostError", "HostStatus", "MachineHost", "Pace", "Snapshot"]

MAX_LAG = 0.25  #: wall seconds a wall-paced machine may fall behind before its time slips
MAX_BATCH = 200  #: most cycles stepped between two looks at the request queue
LATENESS_WINDOW = 10_000  #: cycles whose lateness ``status`` summarises
MAX_TICKETS = 4096  #: command handles kept; the oldest finished ones are dropped first
IDLE_WAIT = 0.05  #: longest wait of an idle kernel thread for a request [s]
REQUEST_TIMEOUT = 10.0  #: how long a client waits for the kernel thread to take a request [s]
MIN_SPEED, MAX_SPEED = 0.01, 1000.0
#: [s] how long another thread may hold the interpreter before the kernel thread gets it
#: back, while a wall-paced host runs (Python's default, 5 ms, would make 1 ms cycles late
#: whenever a server thread is busy); the process's own value comes back at ``stop``
SWITCH_INTERVAL = 0.0002


class Pace(StrEnum):
    WALL = "wall"  #: virtual time follows the wall clock (times ``speed``)
    LOCKSTEP = "lockstep"  #: virtual time moves only when a client advances it


class HostError(RuntimeError):
    """The host cannot do what was asked (stopped, failed, or in the wrong pace)."""


@dataclass(frozen=True)
class Snapshot:
    """Every signal of the machine after one cycle, and the outputs of the started commands."""

    seq: int  #: counts published snapshots
    cycle: int
    time: float  #: virtual time [s]
    values: np.ndarray  #: in the order of ``MachineHost.names``
    handles: dict[int, HandleState] = field(default_factory=dict)


@dataclass(frozen=True)
class HostStatus:
    pace: Pace
    speed: float
    paused: bool
    cycle: int
    time: float
    clients: dict[str, int]
    late_p99_ms: float  #: p99 of how late cycles finished against their wall slots [ms]
    late_max_ms: float
    slips: int  #: times virtual time slipped because the machine could not keep up
    failure: str = ""

    def line(self) -> str:
        """One status line for a terminal."""
        who = ", ".join(f"{count} {kind}" for kind, count in sorted(self.clients.items()))
        pace = "lockstep" if self.pace is Pace.LOCKSTEP else \
            f"{'paused' if self.paused else 'running'} ×{self.speed:g}"
        late = "" if self.pace is Pace.LOCKSTEP else \
            f" · late p99 {self.late_p99_ms:.3f} ms (max {self.late_max_ms:.3f})"
        slipped = f" · slipped {self.slips}×" if self.slips else ""
        failed = f" · FAILED: {self.failure}" if self.failure else ""
        return (f"t = {self.time:.3f} s (cycle {self.cycle}) · {pace}{late}{slipped}"
                f" · clients: {who or 'none'}{failed}")


class Clients:
    """The clients connected to a served machine, by kind ("opcua", "ads" ...): both hosts
    count them for their status."""

    def __init__(self) -> None:
        self._count: Counter[str] = Counter()

    @contextmanager
    def connected(self, kind: str) -> Iterator[None]:
        """Count a client of ``kind`` while inside."""
        self._count[kind] += 1
        try:
            yield
        finally:
            self._count[kind] -= 1

    def connected_now(self) -> dict[str, int]:
        return {kind: n for kind, n in self._count.items() if n > 0}


class MachineHost:
    """A machine on a kernel thread, for endpoints to read and command."""

    def __init__(self, machine_: Machine | Runtime, *, pace: Pace | str = Pace.WALL,
                 speed: float = 1.0, clock: Callable[[], float] = time.monotonic) -> None:
        self.machine = machine_ if isinstance(machine_, Machine) else Machine(machine_)
        self.runtime: Runtime = self.machine.runtime
        try:
            self.pace = Pace(pace)
        except ValueError:
            raise ConfigError(f"pace must be one of {', '.join(p.value for p in Pace)}, "
                              f"not {pace!r}") from None
        self.speed = _speed(speed)
        self._clock = clock
        #: the machine as its clients see it; fixed when the host is made
        self.model: MachineModel = machine(self.runtime)
        signals = self.model.signals()
        self.names: tuple[str, ...] = tuple(signals)
        self.index: dict[str, int] = {name: i for i, name in enumerate(self.names)}
        self.signals: tuple[Signal, ...] = tuple(signals.values())
        #: by object name; objects of one name (an axis and its CA mover) share an entry
        self.commands: dict[str, tuple[WireCommand, ...]] = {}
        for obj in self.model:
            self.commands[obj.name] = self.commands.get(obj.name, ()) + wire_commands(obj)
        #: the served commands of each object of the model, by the object's identity: two
        #: objects may share a name (an axis and the CA mover it is)
        self._object_commands: dict[int, tuple[WireCommand, ...]] = {
            id(obj): wire_commands(obj) for obj in self.model}
        self._readers = _bulk_readers(self.model, len(self.names))
        self._requests: queue.SimpleQueue[tuple[Callable[[], Any], Future[Any]]] = \
            queue.SimpleQueue()
        self._tickets: dict[int, Any] = {}
        self._next_ticket = 1
        self._snapshot = self._read(0)
        self._published = threading.Condition()
        self._clients = Clients()
        self._lateness = np.zeros(LATENESS_WINDOW)
        self._late_count = 0
        self._slips = 0
        self._paused = False
        self._anchor: tuple[float, float] | None = None  #: (wall, virtual) at the last anchor
        self._thread: threading.Thread | None = None
        self._running = threading.Event()
        self._failure = ""
        self._switch_interval: float | None = None  #: the process's, while we run wall-paced
        self._observers: list[Callable[[Snapshot], Any]] = []

    @classmethod
    def for_scenario(cls, source: str | Path | Scenario, **options: Any) -> MachineHost:
        """A host of a scenario set up as ``openmotion run`` sets it up."""
        return cls(scenario_machine(source), **options)

    # -- life -----------------------------------------------------------------------------

    def start(self) -> MachineHost:
        if self._thread is not None:
            raise HostError("the host runs already")
        self._running.set()
        if self.pace is Pace.WALL:
            self._switch_interval = sys.getswitchinterval()
            sys.setswitchinterval(min(SWITCH_INTERVAL, self._switch_interval))
        self._thread = threading.Thread(target=self._loop, name="openmotion-kernel",
                                        daemon=True)
        self._thread.start()
        return self

    def stop(self) -> None:
        self._running.clear()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
            self._thread = None
        if self._switch_interval is not None:
            sys.setswitchinterval(self._switch_interval)
            self._switch_interval = None

    def __enter__(self) -> MachineHost:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    @property
    def running(self) -> bool:
        return self._thread is not None and self._running.is_set()

    @property
    def kernel_thread_id(self) -> int | None:
        """The operating system's id of the kernel thread (None before ``start``)."""
        return self._thread.native_id if self._thread is not None else None

    @property
    def failed(self) -> bool:
        """Whether the kernel thread stopped on an error (``status().failure`` says which)."""
        return bool(self._failure)

    def prepare(self) -> MachineHost:
        """Nothing to prepare for a kernel thread (a kernel process forks here)."""
        return self

    @property
    def cycle_time(self) -> float:
        """The machine's cycle [s]."""
        return self.runtime.cycle_time

    def observe(self, callback: Callable[[Snapshot], Any]) -> None:
        """Call ``callback`` with every snapshot as it is published, on the kernel thread
        (a kernel process hands its snapshots to the servers' process this way)."""
        self._observers.append(callback)

    # -- reading ---------------------------------------------------------------------------

    @property
    def snapshot(self) -> Snapshot:
        """The newest published snapshot (one cycle's values)."""
        return self._snapshot

    def wait_snapshot(self, after: int, timeout: float = REQUEST_TIMEOUT) -> Snapshot:
        """The first snapshot newer than ``after`` (its ``seq``); ``HostError`` on timeout."""
        with self._published:
            if not self._published.wait_for(lambda: self._snapshot.seq > after or
                                             not self.running, timeout):
                raise HostError(f"no new snapshot within {timeout} s")
        return self._snapshot

    def value(self, name: str, snapshot: Snapshot | None = None) -> float:
        """One signal ``<object>.<signal>`` in ``snapshot`` (the newest by default)."""
        index = self.index.get(name)
        if index is None:
            self.model.signal(name)  # raises ConfigError naming the choices
            raise ConfigError(f"no signal {name!r}")
        return float((snapshot or self._snapshot).values[index])

    def handle(self, ticket: int, snapshot: Snapshot | None = None) -> HandleState:
        """The outputs of the command ``ticket`` in ``snapshot`` (the newest by default)."""
        state = (snapshot or self._snapshot).handles.get(ticket)
        if state is None:
            raise ConfigError(f"no command {ticket}")
        return state

    def command(self, owner: str | MachineObject, name: str) -> WireCommand:
        """The served command ``name`` of the object ``owner`` (its name, or the object of
        ``model`` itself where two objects share a name)."""
        if isinstance(owner, MachineObject):
            commands = self.commands_of(owner)
            owner = owner.name
        else:
            commands = self.commands.get(owner)
        if commands is None:
            self.model.find(owner)  # raises ConfigError naming the objects
            raise ConfigError(f"no object {owner!r}")
        for command in commands:
            if command.name == name:
                return command
        raise ConfigError(f"{owner!r} has no command {name!r} served; one of "
                          f"{', '.join(c.name for c in commands) or 'none'}")

    def commands_of(self, owner: MachineObject) -> tuple[WireCommand, ...]:
        """The served commands of one object of ``model``."""
        commands = self._object_commands.get(id(owner))
        if commands is None:
            raise ConfigError(f"{owner.kind} {owner.name!r} is not an object of this host")
        return commands

    # -- commanding ------------------------------------------------------------------------

    def submit(self, request: Callable[[], Any], timeout: float = REQUEST_TIMEOUT) -> Any:
        """Run ``request`` on the kernel thread between two cycles; its result or error."""
        if not self.running:
            raise HostError("the host is not running")
        future: Future[Any] = Future()
        self._requests.put((request, future))
        return future.result(timeout)

    def call(self, owner: str | MachineObject, name: str,
             inputs: dict[str, Any] | None = None) -> int:
        """Start the command ``name`` of ``owner`` with ``inputs`` as a client sent them
        (``WireError`` for bad ones, the machine untouched); its ticket, for ``handle``."""
        command = self.command(owner, name)
        if command.spec.level:
            raise ConfigError(f"{name} sets a level and returns no command: use switch()")
        arguments = command.arguments(inputs or {}, self.model)
        return int(self.submit(lambda: self._start(command, arguments)))

    def switch(self, owner: str | MachineObject, name: str,
               inputs: dict[str, Any] | None = None) -> Any:
        """Set the level command ``name`` of ``owner`` (MC_Power's Enable): its status."""
        command = self.command(owner, name)
        if not command.spec.level:
            raise ConfigError(f"{name} starts a command: use call()")
        arguments = command.arguments(inputs or {}, self.model)

        def apply() -> Any:
            status = command.spec.start(**arguments)  # type: ignore[misc]
            self._publish()
            return status
        return self.submit(apply)

    def _start(self, command: WireCommand, arguments: dict[str, Any]) -> int:
        handle = command.spec.start(**arguments)  # type: ignore[misc]
        ticket = self._next_ticket
        self._next_ticket += 1
        self._tickets[ticket] = handle
        if len(self._tickets) > MAX_TICKETS:
            self._forget()
        self._publish()  # the handle's outputs at once (Busy), not after the next cycle
        return ticket

    def _forget(self) -> None:
        finished = [t for t, handle in self._tickets.items() if not handle.busy]
        for ticket in (finished or list(self._tickets))[:len(self._tickets) - MAX_TICKETS]:
            del self._tickets[ticket]

    # -- pace ------------------------------------------------------------------------------

    def advance(self, cycles: int = 1) -> Snapshot:
        """Lockstep: step ``cycles`` cycles now; the snapshot after them."""
        if self.pace is not Pace.LOCKSTEP:
            raise HostError("advance needs pace 'lockstep'; this host follows the wall clock")
        if isinstance(cycles, bool) or not isinstance(cycles, int) or cycles < 0:
            raise ConfigError(f"cycles must be a whole number >= 0, not {cycles!r}")
        return self.submit(lambda: self._step(cycles), timeout=REQUEST_TIMEOUT + cycles * 0.01)

    def run_for(self, seconds: float) -> Snapshot:
        """Lockstep: step the cycles of ``seconds`` of virtual time."""
        if not isinstance(seconds, int | float) or not math.isfinite(seconds) or seconds < 0:
            raise ConfigError(f"seconds must be a finite number >= 0, not {seconds!r}")
        return self.advance(round(seconds / self.runtime.cycle_time))

    def pause(self) -> None:
        self.submit(lambda: setattr(self, "_paused", True))

    def resume(self) -> None:
        def go() -> None:
            self._paused = False
            self._anchor = None
        self.submit(go)

    def set_speed(self, speed: float) -> None:
        speed = _speed(speed)

        def change() -> None:
            self.speed = speed
            self._anchor = None
        self.submit(change)

    # -- clients ---------------------------------------------------------------------------

    def client(self, kind: str) -> AbstractContextManager[None]:
        """Count a connected client of ``kind`` ("opcua", "ads" ...) while inside."""
        return self._clients.connected(kind)

    def status(self) -> HostStatus:
        count = min(self._late_count, LATENESS_WINDOW)
        late = self._lateness[:count]
        snapshot = self._snapshot
        return HostStatus(
            self.pace, self.speed, self._paused, snapshot.cycle, snapshot.time,
            self._clients.connected_now(),
            float(np.percentile(late, 99)) * 1e3 if count else 0.0,
            float(late.max()) * 1e3 if count else 0.0, self._slips, self._failure)

    # -- the kernel thread -----------------------------------------------------------------

    def _loop(self) -> None:
        try:
            while self._running.is_set():
                self._serve_requests(self._wait())
                if self.pace is Pace.WALL and not self._paused:
                    self._keep_pace()
        except Exception as error:  # noqa: BLE001 - shown in the status, clients refused
            self._failure = f"{type(error).__name__}: {error}"
            self._running.clear()
        finally:
            with self._published:
                self._published.notify_all()
            self._refuse_waiting()

    def _wait(self) -> float:
        """How long to wait for a request before the next cycle is due."""
        if self.pace is Pace.LOCKSTEP or self._paused or self._anchor is None:
            return IDLE_WAIT if self.pace is Pace.LOCKSTEP or self._paused else 0.0
        due = self._due_wall(self.runtime.now + self.runtime.cycle_time)
        return max(0.0, min(IDLE_WAIT, due - self._clock()))

    def _serve_requests(self, wait: float) -> None:
        try:
            request, future = self._requests.get(timeout=wait) if wait > 0 else \
                self._requests.get_nowait()
        except queue.Empty:
            return
        while True:
            if future.set_running_or_notify_cancel():
                try:
                    future.set_result(request())
                except Exception as error:  # noqa: BLE001 - the client gets it
                    future.set_exception(error)
            try:
                request, future = self._requests.get_nowait()
            except queue.Empty:
                return

    def _refuse_waiting(self) -> None:
        while True:
            try:
                _, future = self._requests.get_nowait()
            except queue.Empty:
                return
            if future.set_running_or_notify_cancel():
                future.set_exception(HostError(self._failure or "the host stopped"))

    def _due_wall(self, virtual: float) -> float:
        wall, start = self._anchor  # type: ignore[misc]
        return wall + (virtual - start) / self.speed

    def _keep_pace(self) -> None:
        rt = self.runtime
        now = self._clock()
        if self._anchor is None:
            self._anchor = (now, rt.now)
        due = math.floor((now - self._anchor[0]) * self.speed / rt.cycle_time + 1e-9) \
            - round((rt.now - self._anchor[1]) / rt.cycle_time)
        if due <= 0:
            return
        for _ in range(min(due, MAX_BATCH)):
            rt.step()
            end = self._clock()
            self._lateness[self._late_count % LATENESS_WINDOW] = \
                max(0.0, end - self._due_wall(rt.now))
            self._late_count += 1
        if self._clock() - self._due_wall(rt.now) > MAX_LAG:
            self._slips += 1
            self._anchor = None  # time slips: the machine runs on from where it is
        self._publish()

    def _step(self, cycles: int) -> Snapshot:
        for _ in range(cycles):
            self.runtime.step()
        self._publish()
        return self._snapshot

    def _publish(self) -> None:
        snapshot = self._read(self._snapshot.seq + 1)
        for observer in self._observers:
            observer(snapshot)
        with self._published:
            self._snapshot = snapshot
            self._published.notify_all()

    def _read(self, seq: int) -> Snapshot:
        values = np.empty(len(self.names))
        for read, where in self._readers:
            values[where] = read()
        handles = {ticket: handle_state(handle) for ticket, handle in self._tickets.items()}
        return Snapshot(seq, self.runtime.cycle, self.runtime.now, values, handles)


def _speed(value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) \
            or not MIN_SPEED <= value <= MAX_SPEED:
        raise ConfigError(f"speed must be a number in [{MIN_SPEED}, {MAX_SPEED}], "
                          f"not {value!r}")
    return float(value)


def _bulk_readers(model: MachineModel, size: int) \
        -> list[tuple[Callable[[], Any], slice | np.ndarray | int]]:
    """Readers that fill a snapshot: one numpy gather per signal of a kind where the kind
    declares one (``SignalSpec.bulk``), one call per signal otherwise."""
    positions: dict[tuple[int, str], list[tuple[int, Any]]] = {}
    plain: list[tuple[Callable[[], Any], int]] = []
    index = 0
    for obj in model:
        kind = kind_of(obj.target)
        subject = kind.subject(obj.target) if kind is not None else obj.target
        for signal in obj.signals:
            if signal.spec.bulk is not None:
                positions.setdefault((id(signal.spec), signal.name), []).append(
                    (index, subject))
            else:
                plain.append((signal.read, index))
            index += 1
    assert index == size
    readers: list[tuple[Callable[[], Any], slice | np.ndarray | int]] = list(plain)
    specs = {(id(s.spec), s.name): s.spec for obj in model for s in obj.signals}
    for key, entries in positions.items():
        spec = specs[key]
        where = np.array([i for i, _ in entries], dtype=np.intp)
        readers.append((spec.bulk([subject for _, subject in entries]), where))  # type: ignore[misc]
    return readers
