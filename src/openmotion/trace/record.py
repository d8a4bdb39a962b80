"""Record signals of any object into columnar numpy buffers, and the commands' events.

A ``TraceRecorder`` is a runtime observer (architecture §cycle, phase 4): it samples after
drives and monitoring, so a row shows the state a PLC would read at the start of the next
cycle. It samples every ``every``-th cycle (decimation; ``every=1``: every cycle). Each signal
has a column of its own (one row of a ``(columns, capacity)`` float64 buffer); the objects'
signal sources (signals.py) give the readers, and the axes' kinematic signals are read for
all axes in one numpy gather per signal kind.

Beside the columns a trace holds the command events, (time, object, command, result), of the
commands the recorder follows, and a ``layout``: what its figures need to know of the objects
(stators, footprints, CA rails and gaps; ``signals.describe``).

Where the rows go (D-188): by default into one buffer that doubles when full, every row kept
(a short run's trace, as it always was). ``keep=N``: a ring of N rows, the last N kept,
memory fixed once it is full. ``stream=directory``: chunks of ``chunk`` rows written to disk
as they fill (stream.py), memory fixed at one chunk. Each mode is a policy of ``_make_room``,
called only when the buffer is full, so sampling itself is the same code in all three.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.kernel.model import machine
from openmotion.trace.signals import (
    AXIS_SIGNALS,
    MOVER_SIGNALS,
    BulkReader,
    Reader,
    SignalSource,
    compact_index,
    default_signals,
    describe,
    read_signal,
    source_of,
    split_signal,
)

if TYPE_CHECKING:
    from openmotion.axis.commands import Command
    from openmotion.runtime.runtime import Runtime
    from openmotion.trace.stream import ChunkWriter

#: with the axis signals of signals.py, which scenario/schema.py and tests import from here
__all__ = ["AXIS_SIGNALS", "MOVER_SIGNALS", "RESULTS", "TIME", "Event", "Trace",
           "TraceRecorder", "default_signals", "read_signal", "split_signal"]

TIME = "time"
#: an event's result: the command was issued, or how it ended
RESULTS = ("ISSUED", "DONE", "ABORTED", "ERROR")


class Event(NamedTuple):
    """One command event."""

    time: float  #: [s]
    object: str  #: the axis, mover or group the command went to
    command: str  #: the command (``move_absolute``, ``move_to_position``, ...)
    result: str  #: one of RESULTS
    label: str = ""  #: the timeline entry's id (``#<number>`` without one); "" from Python
    detail: str = ""  #: error name and message, or why it was aborted


class Trace:
    """Recorded columns (``time`` first, then one per signal, in recording order), the command
    events in time order, the layout of the recorded objects (JSON-able), and a title (what
    was run: a scenario's name) for its figures."""

    def __init__(self, columns: Sequence[str], data: np.ndarray, events: Iterable[Event] = (),
                 layout: dict[str, Any] | None = None, title: str = "") -> None:
        data = np.asarray(data, dtype=np.float64)
        if data.ndim != 2 or data.shape[1] != len(columns):
            raise ValueError(f"data of shape {data.shape} does not fit {len(columns)} columns")
        if not columns or columns[0] != TIME:
            raise ValueError(f"the first column must be {TIME!r}")
        self.columns = tuple(columns)
        self.data = data
        self.events = tuple(Event(*event) for event in events)
        self.layout: dict[str, Any] = layout or {}
        self.title = title
        self._index = {name: i for i, name in enumerate(self.columns)}

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.data[:, self._index[name]]
        except KeyError:
            raise KeyError(f"{name!r} was not recorded; columns: {', '.join(self.columns)}")\
                from None

    def __contains__(self, name: object) -> bool:
        return name in self._index

    def __len__(self) -> int:
        return self.data.shape[0]

    def __repr__(self) -> str:
        return f"<Trace {len(self)} rows, {len(self.events)} events: {', '.join(self.columns)}>"

    @property
    def time(self) -> np.ndarray:
        return self.data[:, 0]

    @property
    def signals(self) -> tuple[str, ...]:
        return self.columns[1:]

    @property
    def objects(self) -> list[str]:
        """Object names in the order their first signal appears."""
        return list(dict.fromkeys(name.split(".", 1)[0] for name in self.signals))

    def peak(self, name: str) -> float:
        """Largest absolute value of one column (0 for an empty trace)."""
        column = self[name]
        return float(np.max(np.abs(column))) if column.size else 0.0

    def equals(self, other: Trace) -> bool:
        """Bit-identical columns: same names and the same float64 bits (NaN equals NaN, 0.0
        differs from -0.0). Events, layout and title are not compared (a CSV alone holds
        none of them)."""
        return self.columns == other.columns and self.data.shape == other.data.shape \
            and self.data.tobytes() == other.data.tobytes()


class TraceRecorder:
    """Runtime observer that records ``signals`` every ``every``-th cycle.

    ``signals`` are ``<object>.<signal>`` names of the runtime's axes and of ``objects``
    (planar movers, groups, the environment: anything with a ``name`` whose type has a
    signal source, signals.py). Construct it, then ``runtime.add_observer(recorder)``; call
    ``sample(runtime)`` once more before the first cycle for a row at t = 0. ``follow`` a
    command to record its events. ``title`` goes with the trace (its figures' title).

    Long runs (D-188): ``keep=N`` keeps only the last N rows (and the events from the first
    of them on); ``stream=directory`` writes every ``chunk`` rows to disk (default: about a
    million values per chunk) and keeps one chunk in memory; ``flush()`` or reading
    ``trace`` writes the rest. Without either, every row stays in memory.
    """

    def __init__(self, runtime: Runtime, signals: Sequence[str], every: int = 1,
                 capacity: int = 1024, objects: Iterable[Any] = (), title: str = "", *,
                 keep: int | None = None, stream: str | Path | None = None,
                 chunk: int | None = None) -> None:
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            raise ConfigError(f"every: must be an integer >= 1, got {every!r}")
        _check_rows("keep", keep)
        _check_rows("chunk", chunk)
        if keep is not None and stream is not None:
            raise ConfigError("keep and stream: give one of them (keep the last rows in "
                              "memory, or stream every row to disk)")
        if chunk is not None and stream is None:
            raise ConfigError("chunk: only with stream (the rows per chunk written to disk)")
        named: dict[str, Any] = dict(runtime.axes)
        named.update((obj.name, obj) for obj in objects)
        self._objects = list(named.values())  #: what the layout describes
        self._bulk, self._single = _readers(runtime, _with_model(runtime, named, signals),
                                            signals)
        self.columns = (TIME, *signals)
        self.every = every
        self.title = title
        self.keep = keep  #: rows a bounded recorder keeps; None: all of them
        self._writer: ChunkWriter | None = None
        if stream is not None:
            from openmotion.trace.stream import ChunkWriter, default_chunk

            capacity = chunk if chunk is not None else default_chunk(len(self.columns))
            self._writer = ChunkWriter(stream, self.columns)
        elif keep is not None:
            capacity = min(capacity, keep)
        self._buffer = np.empty((len(self.columns), max(capacity, 1)))
        self._rows = 0  #: where the next row goes (the oldest row, once a ring has wrapped)
        self._wrapped = False  #: a full ring: every slot holds a row
        self._events: list[tuple[int, Event]] = []  #: (sequence, event)
        self._open: list[tuple[int, Command, str, str]] = []  #: followed, not yet ended
        self._sequence = 0  #: counts follow and add_event calls

    def __call__(self, runtime: Runtime) -> None:
        if runtime.cycle % self.every == 0:
            self.sample(runtime)

    def sample(self, runtime: Runtime) -> None:
        """Append one row with the values now."""
        row = self._rows
        if row == self._buffer.shape[1]:
            row = self._make_room()
        buffer = self._buffer
        buffer[0, row] = runtime.now
        for columns, read_all in self._bulk:
            buffer[columns, row] = read_all()
        for column, read in self._single:
            buffer[column, row] = read()
        self._rows = row + 1
        if self._open:
            self._poll()

    def _make_room(self) -> int:
        """The buffer is full: where the next row goes. Grow it (unbounded, or a ring not yet
        at ``keep``), wrap the ring to its oldest row, or write the rows out as a chunk."""
        row = self._rows
        if self._writer is not None:
            self._write_chunk()
            return 0
        size = 2 * row if self.keep is None else min(2 * row, self.keep)
        if size == row:
            self._wrapped = True
            self._drop_events(self._buffer[0, 0])
            return 0
        grown = np.empty((len(self.columns), size))
        grown[:, :row] = self._buffer
        self._buffer = grown
        return row

    @property
    def allocated(self) -> int:
        """Rows the in-memory buffer has room for: at most ``keep`` or one chunk when bounded
        or streaming, whatever has been recorded otherwise."""
        return self._buffer.shape[1]

    def _drop_events(self, oldest: float) -> None:
        """A ring forgets the events before its oldest row (a NaN time is kept)."""
        self._events = [item for item in self._events if not item[1].time < oldest]

    def _write_chunk(self) -> None:
        assert self._writer is not None
        self._poll()
        self._writer.write_chunk(self._buffer[:, :self._rows].T, self._events)
        self._writer.write_manifest(describe(self._objects), self.title)
        self._events = []
        self._rows = 0

    def flush(self) -> None:
        """Streaming: write the rows and events not yet on disk, and the manifest, so that the
        directory holds the whole trace so far. Nothing to do in memory."""
        if self._writer is not None and (self._rows or self._events or not
                                         self._writer.chunks):
            self._write_chunk()

    # -- events --------------------------------------------------------------------------------

    def follow(self, command: Command, object: str, label: str = "") -> None:
        """Record ``command``'s events: ISSUED at its issue time, and its end (DONE, ABORTED,
        ERROR) at its end time once it has ended. ``object`` names what it went to."""
        self._sequence += 1
        self._events.append((self._sequence, Event(command.issued_at, object, command.kind,
                                                   "ISSUED", label)))
        self._open.append((self._sequence, command, object, label))
        if command.finished:
            self._poll()

    def add_event(self, event: Event) -> None:
        """Record an event of your own (a program's, say)."""
        self._sequence += 1
        self._events.append((self._sequence, Event(*event)))

    def _poll(self) -> None:
        still = []
        for sequence, command, obj, label in self._open:
            if not command.finished:
                still.append((sequence, command, obj, label))
                continue
            detail = f"{command.error_id.name}: {command.message}" if command.error \
                else command.message
            ended = command.ended_at if command.ended_at is not None else math.nan
            self._events.append((sequence, Event(ended, obj, command.kind, command.status.name,
                                                 label, detail)))
        self._open = still

    @property
    def trace(self) -> Trace:
        """A copy of what has been recorded so far (with ``keep``: the last rows and the
        events from the first of them on; with ``stream``: flushed, then read back from the
        directory, the columns when first used). Events are in time order, and at one time
        in the order the commands were followed (ISSUED before the end): the same whatever
        the decimation, since an end is looked for only now and then."""
        self._poll()
        if self._writer is not None:
            from openmotion.trace.stream import read_stream

            self.flush()
            return read_stream(self._writer.directory)
        data = self._rows_in_order()
        events = self._events
        if self._wrapped:
            oldest = data[0, 0]
            events = [item for item in events if not item[1].time < oldest]
        events = sorted(events, key=lambda item: (item[1].time, item[0]))
        return Trace(self.columns, data, [event for _, event in events],
                     describe(self._objects), self.title)

    def _rows_in_order(self) -> np.ndarray:
        """The rows held, oldest first (rows x columns): one copy, in two parts once a ring
        has wrapped."""
        buffer, row = self._buffer, self._rows
        if not self._wrapped:
            return buffer[:, :row].T.copy()
        data = np.empty((buffer.shape[1], len(self.columns)))
        older = buffer.shape[1] - row
        data[:older] = buffer[:, row:].T
        data[older:] = buffer[:, :row].T
        return data


def _check_rows(name: str, value: int | None) -> None:
    if value is not None and (isinstance(value, bool) or not isinstance(value, int)
                              or value < 1):
        raise ConfigError(f"{name}: must be an integer >= 1 (rows), got {value!r}")


def _readers(runtime: Runtime, named: dict[str, Any], signals: Sequence[str]) \
        -> tuple[list[tuple[slice | np.ndarray, BulkReader]], list[tuple[int, Reader]]]:
    """(columns, bulk reader) for each signal name whose source reads all its objects at
    once, and (column, reader) for every other signal."""
    wanted: dict[tuple[int, str], list[tuple[int, Any]]] = {}  # (source, prop) -> columns
    sources: dict[int, SignalSource] = {}
    for column, name in enumerate(signals, start=1):
        obj, source, prop = _resolve(named, name)
        sources[id(source)] = source
        wanted.setdefault((id(source), prop), []).append((column, obj))
    bulk: list[tuple[slice | np.ndarray, BulkReader]] = []
    single: list[tuple[int, Reader]] = []
    for (key, prop), targets in wanted.items():
        source = sources[key]
        read_all = source.bulk(runtime, [obj for _, obj in targets], prop)
        if read_all is not None:
            bulk.append((compact_index([column for column, _ in targets]), read_all))
        else:
            single += [(column, source.reader(obj, prop)) for column, obj in targets]
    return bulk, single


def _with_model(runtime: Runtime, named: dict[str, Any], signals: Sequence[str]) \
        -> dict[str, Any]:
    """``named``, and every other object of the machine model when a signal names one
    (a CA group, a planar track or part): a trace records any signal of the model."""
    if all(name.partition(".")[0] in named for name in signals):
        return named
    found = {obj.name: obj.target for obj in reversed(machine(runtime).objects)}
    return {**found, **named}


def _resolve(named: dict[str, Any], name: str) -> tuple[Any, SignalSource, str]:
    subject, _, prop = name.partition(".")
    if not prop:
        raise ConfigError(f"signals: {name!r} is not '<object>.<signal>'")
    obj = named.get(subject)
    if obj is None:
        raise ConfigError(f"signals: {name!r} names no object of the runtime "
                          f"(known: {', '.join(named) or 'none'})")
    source = source_of(obj)
    if source is None:
        raise ConfigError(f"signals: {name!r}: no signal source for {type(obj).__name__} "
                          "(signals.register_source)")
    if prop not in source.signals:
        raise ConfigError(f"signals: {name!r}: a signal of {source.kind} {subject!r} is one "
                          f"of {', '.join(source.signals) or 'none'}")
    return obj, source, prop

