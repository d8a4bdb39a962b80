"""Streamed traces: a directory of NPZ chunks that a long run writes as its buffer fills (D-188).

The directory holds ``trace.json`` (format number, columns, title, layout, the number of
chunks and of rows) and ``chunk-000000.npz``, ``chunk-000001.npz``, ... (numpy's zip of
arrays, uncompressed, no pickles): each chunk's rows as ``data`` (rows x columns, float64 as
recorded) and the command events recorded since the chunk before, one array per field plus
``events_sequence`` (the order the recorder took them in, which breaks ties of time). The
manifest is rewritten after every chunk, so the directory is a readable trace of every row up
to the last chunk written at any moment.

``read_stream`` gives the trace back: the events and the layout at once, the columns when
they are first used (a ``StreamedTrace`` knows its row count without reading them), one
allocation of the whole table, so a streamed trace reads back as any other and compares bit
for bit with the same run recorded in memory. pyarrow is not a dependency of openmotion,
hence NPZ rather than Parquet.
"""

from __future__ import annotations

import json
import zipfile
import zlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.trace.record import Event, Trace

STREAM_FORMAT = 1  #: the ``format`` number of the manifests written here
MANIFEST = "trace.json"  #: the manifest's name inside the directory
CHUNK_VALUES = 1 << 20  #: values (8 MiB of float64) per chunk unless ``chunk`` says otherwise


def chunk_name(number: int) -> str:
    return f"chunk-{number:06d}.npz"


def _is_chunk(name: str) -> bool:
    return name.startswith("chunk-") and name.endswith(".npz")


def default_chunk(columns: int) -> int:
    """Rows per chunk for a trace of ``columns`` columns: about CHUNK_VALUES values."""
    return max(1, CHUNK_VALUES // columns)


class ChunkWriter:
    """Writes the chunks and the manifest of one streamed trace into ``directory``.

    The directory is created if missing; one that holds a streamed trace already is emptied
    of it (a run writes over the last run's trace, as it does a CSV); one that holds anything
    else is refused, so a typo never deletes a user's files. Unwritable: ConfigError at once,
    before the first cycle."""

    def __init__(self, directory: str | Path, columns: Sequence[str]) -> None:
        self.directory = Path(directory)
        self.columns = tuple(columns)
        self.chunks = 0
        self.rows = 0
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            self._clear()
            self.write_manifest({}, "")
        except OSError as exc:
            raise ConfigError(f"stream: {self.directory}: cannot write the trace there: "
                              f"{exc.strerror or exc}") from None

    def _clear(self) -> None:
        present = list(self.directory.iterdir())
        if not present:
            return
        names = {path.name for path in present}
        if MANIFEST not in names or any(name != MANIFEST and not _is_chunk(name)
                                         for name in names):
            raise ConfigError(f"stream: {self.directory}: the directory holds other files "
                              f"than a streamed trace; give an empty or new directory")
        for path in present:
            path.unlink()

    def write_chunk(self, data: np.ndarray, events: Sequence[tuple[int, Event]]) -> None:
        """Write ``data`` (rows x columns) and ``events`` ((sequence, event) pairs) as the
        next chunk."""
        arrays = {f"events_{field}": np.array([getattr(event, field) for _, event in events],
                                              dtype=np.float64 if field == "time" else np.str_)
                  for field in Event._fields}
        with (self.directory / chunk_name(self.chunks)).open("wb") as file:
            np.savez(file, data=data, events_sequence=np.array(
                [sequence for sequence, _ in events], dtype=np.int64), **arrays)
        self.chunks += 1
        self.rows += data.shape[0]

    def write_manifest(self, layout: dict[str, Any], title: str) -> None:
        content = {"format": STREAM_FORMAT, "columns": list(self.columns), "title": title,
                   "chunks": self.chunks, "rows": self.rows, "layout": layout}
        (self.directory / MANIFEST).write_text(json.dumps(content, ensure_ascii=False),
                                               encoding="utf-8")


class StreamedTrace(Trace):
    """A trace read from a stream directory: columns, events, layout and title at once, the
    data when it is first used (``len`` does not read it)."""

    def __init__(self, directory: Path, columns: Sequence[str], rows: int, chunks: int,
                 events: Sequence[Event], layout: dict[str, Any], title: str) -> None:
        if not columns or columns[0] != "time":
            raise ValueError("the first column must be 'time'")
        self.columns = tuple(columns)
        self.events = tuple(events)
        self.layout = layout
        self.title = title
        self._index = {name: i for i, name in enumerate(self.columns)}
        self.directory = directory  #: where the chunks are
        self._rows, self._chunks = rows, chunks
        self._data: np.ndarray | None = None

    @property  # type: ignore[override]
    def data(self) -> np.ndarray:
        if self._data is None:
            self._data = _read_data(self.directory, len(self.columns), self._rows,
                                    self._chunks)
        return self._data

    def __len__(self) -> int:
        return self._rows


def read_stream(directory: str | Path) -> StreamedTrace:
    """The trace in a stream directory written by a ``TraceRecorder(..., stream=...)``."""
    directory = Path(directory)
    manifest = directory / MANIFEST
    try:
        content = json.loads(manifest.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(f"{directory}: not a streamed trace: no {MANIFEST}") from None
    except OSError as exc:
        raise ConfigError(f"{manifest}: cannot read the trace: {exc.strerror or exc}") \
            from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise ConfigError(f"{manifest}: not a trace manifest: {exc}") from None
    if not isinstance(content, dict) or content.get("format") != STREAM_FORMAT:
        raise ConfigError(f"{manifest}: not a trace manifest of format {STREAM_FORMAT}")
    try:
        columns, rows, chunks = list(content["columns"]), int(content["rows"]), \
            int(content["chunks"])
        events = _read_events(directory, chunks)
        return StreamedTrace(directory, columns, rows, chunks, events, content["layout"],
                             str(content.get("title", "")))
    except (KeyError, TypeError, ValueError) as exc:
        raise ConfigError(f"{manifest}: not a trace manifest: {exc}") from None


def _load(path: Path, names: Sequence[str]) -> dict[str, np.ndarray]:
    try:
        with path.open("rb") as file, np.load(file, allow_pickle=False) as archive:
            return {name: archive[name] for name in names}
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the chunk: {exc.strerror or exc}") from None
    except (KeyError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        raise ConfigError(f"{path}: not a trace chunk: {exc}") from None


def _read_events(directory: Path, chunks: int) -> list[Event]:
    """Every chunk's events in time order, ties in the order they were recorded."""
    names = ["events_sequence", *(f"events_{field}" for field in Event._fields)]
    found: list[tuple[float, int, Event]] = []
    for number in range(chunks):
        arrays = _load(directory / chunk_name(number), names)
        fields = [arrays[f"events_{field}"].tolist() for field in Event._fields]
        rows = zip(*fields, strict=True)
        for sequence, values in zip(arrays["events_sequence"].tolist(), rows, strict=True):
            event = Event(*values)
            found.append((event.time, sequence, event))
    found.sort(key=lambda item: (item[0], item[1]))
    return [event for _, _, event in found]


def _read_data(directory: Path, columns: int, rows: int, chunks: int) -> np.ndarray:
    """All chunks' rows in one array, filled chunk by chunk (one copy of the table)."""
    data = np.empty((rows, columns))
    row = 0
    for number in range(chunks):
        path = directory / chunk_name(number)
        part = _load(path, ["data"])["data"]
        if part.ndim != 2 or part.shape[1] != columns or row + part.shape[0] > rows:
            raise ConfigError(f"{path}: a chunk of shape {part.shape} does not fit the "
                              f"manifest ({rows} rows x {columns} columns)")
        data[row:row + part.shape[0]] = part
        row += part.shape[0]
    if row != rows:
        raise ConfigError(f"{directory}: the chunks hold {row} rows, the manifest says {rows}")
    return data
