"""A viewer session: one machine on a kernel thread, paced against the wall clock.

The kernel thread owns the runtime: it alone steps it and reads it. Each pass of its loop
(``tick``) it applies the controls the pages sent (play, pause, step, speed, restart, scope
signals), steps the cycles the wall clock asks for, samples the selected scope signals every
``scope_every`` seconds of virtual time into a history and, up to ``frame_rate`` times a
second of wall time, builds a frame: the state of every layer as one JSON text. Publishing a
frame replaces one reference, so the server's tasks read frames without locks and the kernel
never waits for them: a slow page only gets fewer frames. Scope samples are not part of the
frames: each page asks for the samples it has not seen yet (``scope_since``), so a skipped
frame loses none; the history's lock is held only to append or copy a few samples.

A session made with ``wait_for_page`` holds its machine at its start until the first page
connects (``page_connected``) or a ``play``, so that a page opened late still sees the run
from t = 0.

Pacing is ``PacedRuntime``'s rule, virtual time = anchor + wall time since the anchor x speed,
with the anchor set again at every play and speed change, so that a pause or a new speed never
makes the kernel catch up in a burst. Cycles run in batches of at most half a frame period of
wall time. When the machine is more than a frame late, the frames give way first: the frame
period doubles at every frame down to ``MIN_FRAME_RATE``, and halves again once twice the
frames would still leave the kernel idle a fifth of the time (``RAISE_BELOW``). Only when
the machine is still more than ``MAX_LAG`` late at the fewest frames does the anchor move:
the machine then runs as fast as it can, and the frame says ``behind`` with a ``notice`` in
plain words. Virtual time is unaffected by all this: a scenario runs through exactly the
cycles ``openmotion run`` gives it, whatever the pace.
"""

from __future__ import annotations

import json
import math
import queue
import threading
import time
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from openmotion.core.errors import ConfigError
from openmotion.kernel.model import machine as machine_model
from openmotion.runtime.paced import PacedRuntime
from openmotion.runtime.runtime import Runtime
from openmotion.scenario import Scenario
from openmotion.scenario.live import Machine, scenario_machine
from openmotion.viewer.layers import (
    Layer,
    LayerFactory,
    Reader,
    finite,
    first_scope,
    model_rows,
    registered_layers,
    scope_signals,
)

FRAME_RATE = 25.0  #: frames per second of wall time, the most a session sends
MIN_FRAME_RATE = 5.0  #: the fewest frames per second a session that cannot keep up sends
RAISE_BELOW = 0.8  #: the kernel gets twice the frames if it would then work less of the time
SCOPE_EVERY = 0.01  #: virtual seconds between two scope samples
SCOPE_HISTORY = 2000  #: scope samples kept (a page that connects gets them all)
SCOPE_SIGNALS = 6  #: most signals the scope shows at once
MAX_ROWS = 200  #: table rows in one frame
MAX_LAG = 0.25  #: wall seconds the kernel may be late at the fewest frames before time slips
SLOW_HOLD = 2.0  #: wall seconds ``behind`` stays after the clock last slipped
RATE_WINDOW = 1.0  #: wall seconds over which the reached speed is measured
MIN_SPEED, MAX_SPEED = 0.01, 1000.0
MIN_WAIT = 0.002  #: shortest sleep of the kernel loop [s]
_CLOCK_EVERY = 8  #: cycles between two looks at the wall clock inside a batch


@dataclass(frozen=True)
class Frame:
    """One published state: ``data`` and the same as JSON ``text``."""

    seq: int
    generation: int  #: counts machines: a restart makes a new one
    data: dict[str, Any]
    text: str


class Session:
    """Runs ``machine`` (a ``Machine``, a ``Runtime``, or a function that builds a Machine,
    which makes the session restartable) paced at ``speed`` virtual seconds per wall second.

    With ``wait_for_page`` the machine stays at its start until the first page connects
    (``openmotion view`` does this unless told ``--start-now``); ``paused`` keeps it paused
    after that too. The controls (``play`` ... ``select``, ``control``) may be called from
    any thread; they take effect at the kernel's next pass. ``start`` runs the kernel thread;
    tests may call ``tick`` themselves instead, with a fake ``clock``.
    """

    def __init__(self, machine: Machine | Runtime | Callable[[], Machine], *,
                 speed: float = 1.0, frame_rate: float = FRAME_RATE,
                 scope_every: float = SCOPE_EVERY, paused: bool = False,
                 wait_for_page: bool = False,
                 layers: Sequence[LayerFactory] | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        if isinstance(machine, Runtime):
            machine = Machine(machine)
        self._build = None if isinstance(machine, Machine) else machine
        self.speed = _speed(speed)
        if not (isinstance(frame_rate, int | float) and 0 < frame_rate <= 1000):
            raise ValueError(f"frame_rate: must be in (0, 1000] Hz, got {frame_rate!r}")
        if not (isinstance(scope_every, int | float) and scope_every > 0):
            raise ValueError(f"scope_every: must be > 0 s, got {scope_every!r}")
        self.frame_rate = float(frame_rate)
        self.paused = paused
        self.waiting = wait_for_page  #: held at the start until the first page connects
        self.finished = False  #: the machine has ended; only a restart goes on
        self.behind = False  #: the asked speed could not be kept lately, even at fewest frames
        self.failure = ""  #: why the kernel stopped or a restart failed
        self._base_period = self._period = 1.0 / self.frame_rate  #: asked, current [s]
        self._max_period = max(self._base_period, 1.0 / MIN_FRAME_RATE)
        self._scope_every = float(scope_every)
        self._factories = tuple(layers) if layers is not None else registered_layers()
        self._clock = clock
        self._controls: queue.SimpleQueue[Callable[[float], None]] = queue.SimpleQueue()
        self._wake = threading.Event()
        self._thread: threading.Thread | None = None
        self._stopping = False
        self._lock = threading.Lock()  #: guards the scope selection and history
        self._history: deque[list[float | None]] = deque(maxlen=SCOPE_HISTORY)
        self._scope_id = 0  #: counts selections
        self._sampled = 0  #: samples taken since the selection
        self._seq = 0
        self._generation = 0
        self._frame: Frame | None = None
        self._next_frame = self._last_frame = clock()
        self._busy = 0.0  #: wall seconds the kernel worked since the last frame
        self._frame_cost = 0.0  #: wall seconds the last frame took to build
        self._lag = 0.0  #: wall seconds the machine is late after the last batch
        self._slipped = -math.inf  #: wall time the clock last slipped
        self._dirty = True
        self._load(machine if isinstance(machine, Machine) else machine())

    @classmethod
    def for_scenario(cls, source: str | Path | Scenario, **options: Any) -> Session:
        """A restartable session of a scenario file: a restart reads the file again."""
        return cls(lambda: scenario_machine(source), **options)

    # -- reading (any thread) --------------------------------------------------------------

    @property
    def frame(self) -> Frame | None:
        """The latest frame; None before the kernel's first pass."""
        return self._frame

    @property
    def restartable(self) -> bool:
        return self._build is not None

    @property
    def current_frame_rate(self) -> float:
        """Frames per second now: ``frame_rate``, or fewer while the machine is late."""
        return 1.0 / self._period

    def hello(self) -> str:
        """What a page needs once per machine: its name and the signal list, as JSON."""
        return self._hello

    def scope_since(self, scope_id: int, count: int) -> tuple[dict[str, Any] | None, int, int]:
        """The scope samples a page has not seen: it saw ``count`` samples of selection
        ``scope_id``. Returns (message or None, the selection, its sample count); the message
        has ``reset`` when the page must drop what it has (a new selection, or it fell more
        than the history behind)."""
        with self._lock:
            current, total, history = self._scope_id, self._sampled, self._history
            new = total - count
            reset = scope_id != current or new > len(history)
            if not reset and new <= 0:
                return None, current, total
            samples = list(history) if reset else list(history)[len(history) - new:]
            names = self._scope_names
        return {"type": "scope", "id": current, "names": names, "reset": reset,
                "samples": samples}, current, total

    # -- controls (any thread) -------------------------------------------------------------

    def play(self) -> None:
        """Let virtual time go on (a session waiting for a page starts too)."""
        self._send(self._play)

    def page_connected(self) -> None:
        """A page is watching: a session waiting for its first page starts."""
        self._send(self._page_connected)

    def pause(self) -> None:
        self._send(self._pause)

    def step(self) -> None:
        """Pause and advance by one frame's worth of virtual time (at least one cycle)."""
        self._send(self._step)

    def set_speed(self, speed: float) -> None:
        value = _speed(speed)
        self._send(lambda now: self._set_speed(now, value))

    def restart(self) -> None:
        """Build the machine again (a scenario file is read again); keeps play or pause."""
        if self._build is None:
            raise ValueError("restart: this session runs a runtime it cannot build again")
        self._send(self._restart)

    def select(self, signals: Sequence[str]) -> None:
        """Show these scope signals (unknown names are left out); the scope starts anew."""
        if isinstance(signals, str) or not all(isinstance(name, str) for name in signals):
            raise ValueError(f"signals: a list of names is needed, got {signals!r}")
        names = list(signals)
        self._send(lambda now: self._select(names))

    def control(self, message: Mapping[str, Any]) -> None:
        """A page's control message: ``{"op": "play" | "pause" | "step" | "restart"}``,
        ``{"op": "speed", "value": 2.0}`` or ``{"op": "scope", "signals": [...]}``."""
        op = message.get("op") if isinstance(message, Mapping) else None
        if op in ("play", "pause", "step", "restart"):
            getattr(self, op)()
        elif op == "speed":
            self.set_speed(message.get("value"))  # type: ignore[arg-type]
        elif op == "scope":
            self.select(message.get("signals"))  # type: ignore[arg-type]
        else:
            raise ValueError(f"unknown control {message!r}: op must be play, pause, step, "
                             "speed, restart or scope")

    def _send(self, apply: Callable[[float], None]) -> None:
        self._controls.put(apply)
        self._wake.set()

    # -- the kernel thread -----------------------------------------------------------------

    def start(self) -> None:
        """Run the kernel loop on a daemon thread (once)."""
        if self._thread is None:
            self._stopping = False
            self._go(self._clock())  # the wall clock counts from here, not from __init__
            self._thread = threading.Thread(target=self._loop, name="openmotion-viewer",
                                            daemon=True)
            self._thread.start()

    def stop(self) -> None:
        """End the kernel loop and wait for it."""
        thread, self._thread = self._thread, None
        if thread is not None:
            self._stopping = True
            self._wake.set()
            thread.join()

    def _loop(self) -> None:
        while not self._stopping:
            try:
                self.tick()
            except Exception as exc:  # the page must say why the kernel stopped
                self.failure, self.finished = f"{type(exc).__name__}: {exc}", True
                self._frame = self._failure_frame()
            timeout = self._wait()
            if timeout > 0:
                self._wake.wait(timeout)
                self._wake.clear()

    def tick(self) -> None:
        """One pass: the controls, the cycles that are due, then a frame when one is due."""
        start = self._clock()
        while True:
            try:
                apply = self._controls.get_nowait()
            except queue.Empty:
                break
            apply(start)
            self._dirty = True
        self._advance(start)
        now = self._clock()
        self._busy += now - start
        if self._dirty or now >= self._next_frame:
            if now >= self._next_frame:
                self._adapt(now)
            self._publish(now)
            later = self._next_frame + self._period
            self._next_frame = later if later > now else now + self._period
            self._dirty = False
            self._frame_cost = self._clock() - now
            self._busy += self._frame_cost

    def _running(self) -> bool:
        return not (self.paused or self.waiting or self.finished)

    def _wait(self) -> float:
        """Seconds until the next cycle or frame is due; 0 when a cycle is due already: a late
        machine goes on at once (a sleep costs it a turn of the OS scheduler, on a loaded
        machine many milliseconds)."""
        now, until = self._clock(), self._next_frame
        if self._running():
            rt = self.machine.runtime
            until = min(until, self._wall_of(rt.now + rt.cycle_time))
            if until <= now:
                return 0.0
        return min(max(until - now, MIN_WAIT), self._period)

    # -- pacing ----------------------------------------------------------------------------

    def _anchor(self, now: float) -> None:
        self._anchor_wall, self._anchor_virtual = now, self.machine.runtime.now

    def _wall_of(self, virtual: float) -> float:
        return self._anchor_wall + (virtual - self._anchor_virtual) / self.speed

    def _go(self, now: float) -> None:
        """Virtual time runs (again) from ``now``: a new anchor, the pace measured anew."""
        self._anchor(now)
        self._rates.clear()
        self._slipped, self._lag = -math.inf, 0.0

    def _due(self, now: float) -> int:
        """Cycles to run now: the pending steps when paused, none while waiting for a page,
        else what the clock asks for."""
        if self.paused:
            return self._pending
        if self.waiting:
            return 0
        rt = self.machine.runtime
        target = self._anchor_virtual + (now - self._anchor_wall) * self.speed
        return math.floor((target - rt.now) / rt.cycle_time + 1e-9)

    def _advance(self, now: float) -> None:
        due = 0 if self.finished else self._due(now)
        self._lag = 0.0
        if due <= 0:
            return
        rt, deadline, done = self.machine.runtime, now + self._period / 2, 0
        while done < due:
            if self.machine.finished():
                self.finished = self._dirty = True
                break
            rt.step()
            done += 1
            if rt.cycle % self._scope_cycles == 0:
                self._sample()
            if done % _CLOCK_EVERY == 0 and self._clock() > deadline:
                break
        if self.paused:
            self._pending = 0 if self.finished else self._pending - done
            return
        if self.finished:
            return
        self._lag = (due - done) * rt.cycle_time / self.speed  # [s] of wall time
        if self._lag > MAX_LAG and self._period >= self._max_period:
            self._slipped = self._clock()  # frames cannot give more: the pace falls
            self._anchor(self._slipped)

    def _adapt(self, now: float) -> None:
        """At a frame that is due: half the frames while the machine is more than a frame
        late; twice as many again when the kernel, with one frame more in the last frame
        period, would still have worked less than ``RAISE_BELOW`` of it; all of them while
        time stands still."""
        span, busy = now - self._last_frame, self._busy
        self._last_frame, self._busy = now, 0.0
        if not self._running():
            self._period = self._base_period
        elif self._lag > self._base_period:
            self._period = min(2.0 * self._period, self._max_period)
        elif busy + self._frame_cost < RAISE_BELOW * span:
            self._period = max(self._period / 2.0, self._base_period)

    def _play(self, now: float) -> None:
        self.paused, self.waiting, self._pending = False, False, 0
        self._go(now)

    def _page_connected(self, now: float) -> None:
        if self.waiting:
            self.waiting = False
            self._go(now)

    def _pause(self, now: float) -> None:
        self.paused, self._pending = True, 0

    def _step(self, now: float) -> None:
        rt = self.machine.runtime
        self.paused, self.waiting = True, False
        self._pending += max(1, round(self.speed / self.frame_rate / rt.cycle_time))

    def _set_speed(self, now: float, speed: float) -> None:
        self._go(now)
        self.speed = speed

    def _restart(self, now: float) -> None:
        assert self._build is not None
        try:
            machine = self._build()
        except ConfigError as exc:
            self.failure = f"restart failed: {exc}"
            return
        self._load(machine)

    # -- machine, layers, scope ------------------------------------------------------------

    def _load(self, machine: Machine) -> None:
        rt = machine.runtime
        if isinstance(rt, PacedRuntime):
            raise ValueError("the session paces its runtime itself: give it a Runtime, not a "
                             "PacedRuntime")
        self.machine = machine
        self._layers: list[Layer] = [layer for factory in self._factories
                                     for layer in factory(rt)]
        self._model = machine_model(rt)  #: the objects the table lists, as they were at the start
        scope = scope_signals(self._model)
        self._signals: dict[str, Reader] = {name: signal.read for name, signal in scope.items()}
        for layer in self._layers:
            self._signals.update(layer.signals())
        self.finished, self.behind, self.failure = False, False, ""
        self._pending = 0
        self._generation += 1
        self._scope_cycles = max(1, round(self._scope_every / rt.cycle_time))
        self._rates: deque[tuple[float, float]] = deque()  #: (wall, virtual) at frames
        self._go(self._clock())
        self._hello = json.dumps({
            "type": "hello", "generation": self._generation, "name": machine.name,
            "cycle_time": rt.cycle_time, "frame_rate": self.frame_rate,
            "restart": self.restartable, "signals": list(self._signals)})
        chosen = [name for name in machine.signals if name in self._signals]
        self._select(chosen or first_scope(scope) or list(self._signals)[:2])

    def _select(self, names: list[str]) -> None:
        names = [name for name in dict.fromkeys(names) if name in self._signals]
        with self._lock:
            self._scope_names = names[:SCOPE_SIGNALS]
            self._readers = [self._signals[name] for name in self._scope_names]
            self._history.clear()
            self._scope_id += 1
            self._sampled = 0
        self._sample()

    def _sample(self) -> None:
        sample = [self.machine.runtime.now, *(_read(reader) for reader in self._readers)]
        with self._lock:
            self._history.append(sample)
            self._sampled += 1

    # -- frames ----------------------------------------------------------------------------

    def _publish(self, now: float) -> None:
        rate = self._reached(now)
        self.behind = self._running() and now - self._slipped < SLOW_HOLD
        shown = [row for layer in self._layers for row in layer.rows()]
        shown += model_rows(self._model, (row.name for row in shown))
        rows = [asdict(row) for row in shown]
        data = {**self._status(rate),
                "panels": [{"kind": layer.kind, "name": layer.name, **layer.panel()}
                           for layer in self._layers],
                "rows": rows[:MAX_ROWS], "hidden_rows": max(0, len(rows) - MAX_ROWS)}
        self._set_frame(data)

    def _reached(self, now: float) -> float | None:
        """Virtual seconds per wall second over the last ``RATE_WINDOW``; None right after
        a play, a speed change or a start."""
        rates = self._rates
        rates.append((now, self.machine.runtime.now))
        while len(rates) > 2 and now - rates[1][0] >= RATE_WINDOW:
            rates.popleft()
        (wall0, virtual0), (wall1, virtual1) = rates[0], rates[-1]
        return finite((virtual1 - virtual0) / (wall1 - wall0)) if wall1 > wall0 else None

    def _status(self, rate: float | None = None) -> dict[str, Any]:
        rt = self.machine.runtime
        self._seq += 1
        return {"type": "frame", "seq": self._seq, "generation": self._generation,
                "name": self.machine.name, "time": rt.now, "cycle": rt.cycle,
                "speed": self.speed, "rate": rate, "frame_rate": self.current_frame_rate,
                "paused": self.paused, "waiting": self.waiting, "finished": self.finished,
                "behind": self.behind, "notice": self._notice(rate), "failure": self.failure,
                "scope": self._scope_names}

    def _notice(self, rate: float | None) -> str:
        """What the page says of the pace, in plain words; "" while the asked speed holds
        with every frame."""
        if not self._running():
            return ""
        shown, asked = self.current_frame_rate, self.frame_rate
        cycle = f"{self.machine.runtime.cycle_time * 1e3:g} ms"
        if self.behind and rate is not None:
            return (f"This computer runs the simulation at {rate:.2f}× real time, slower than "
                    f"the {self.speed:g}× asked, even with {shown:g} frames a second instead "
                    f"of {asked:g}. Every {cycle} cycle is still computed: the motion is the "
                    "same, only slower.")
        if shown < asked:
            return (f"{shown:g} frames a second instead of {asked:g}: frames are dropped so "
                    f"that this computer keeps the {self.speed:g}× asked. Every {cycle} cycle "
                    "is still computed.")
        return ""

    def _failure_frame(self) -> Frame:
        data = {**self._status(), "panels": [], "rows": [], "hidden_rows": 0}
        return Frame(self._seq, self._generation, data, json.dumps(data, default=str))

    def _set_frame(self, data: dict[str, Any]) -> None:
        text = json.dumps(data, separators=(",", ":"), allow_nan=False)
        self._frame = Frame(data["seq"], data["generation"], data, text)


def _read(reader: Reader) -> float | None:
    """A scope value; None when the signal cannot be read now (an object left its group)."""
    try:
        return finite(reader())
    except (LookupError, ArithmeticError, ValueError):
        return None


def _speed(value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or \
            not MIN_SPEED <= value <= MAX_SPEED:
        raise ValueError(f"speed: must be a number from {MIN_SPEED:g} to {MAX_SPEED:g}, "
                         f"got {value!r}")
    return float(value)
