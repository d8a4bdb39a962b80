"""Traces in files: CSV with a JSON sidecar, or NPZ; the format comes from the suffix.

CSV (``.csv``): one header line, one column per signal, floats written with ``repr``, which
gives the shortest text that parses back to the same float64, so a trace read back from its
file is bit-identical to the recorded one and two runs can be diffed as text. The CSV stays
plain (spreadsheets and pandas read it as it is); what it cannot hold, the command events, the
layout and the title, goes into a sidecar beside it, ``<name>.events.json`` (``sidecar_path``),
so that ``openmotion plot`` draws the run's own figure again (D-170).

NPZ (``.npz``, numpy's zip of arrays, no pickles): ``columns`` and ``data`` as recorded, the
events as one array per field (``events_time``, ``events_object``, ...), the layout as JSON
text, the title and a ``format`` number. Everything reads back bit-identical.

Any other suffix is a ConfigError naming these two (``trace_format``), before anything is
written or read. A directory is read as a streamed trace (stream.py, D-188).
"""

from __future__ import annotations

import csv
import json
import math
import warnings
import zipfile
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.trace.record import TIME, Event, Trace
from openmotion.trace.stream import MANIFEST, read_stream

TRACE_FORMATS = ("csv", "npz")  #: by the file's suffix
NPZ_FORMAT = 1  #: the ``format`` number of the NPZ files written here
SIDECAR_SUFFIX = ".events.json"  #: ``trace.csv`` -> ``trace.events.json``
SIDECAR_FORMAT = 1  #: the ``format`` number of the sidecars written here


class TraceWarning(UserWarning):
    """A trace read back without part of what was recorded (a CSV without its sidecar)."""


def trace_format(path: str | Path) -> str:
    """The trace format of ``path`` by its suffix; ConfigError for any other suffix."""
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in TRACE_FORMATS:
        raise ConfigError(f"{path}: the trace format comes from the suffix: "
                          f"{', '.join('.' + name for name in TRACE_FORMATS)} "
                          f"(a .csv gets its events and layout in a {SIDECAR_SUFFIX} beside it)")
    return suffix


def sidecar_path(path: str | Path) -> Path:
    """Where the events, layout and title of the CSV trace ``path`` go."""
    path = Path(path)
    return path.with_name(path.stem + SIDECAR_SUFFIX)


def write_csv(trace: Trace, path: str | Path) -> Path:
    """Write ``trace``'s columns to ``path``; axis states as integers, every other value via
    ``repr``. Only the columns: ``write_trace`` adds the sidecar."""
    path = Path(path)
    integer = [name.endswith(".state") for name in trace.columns]
    with path.open("w", newline="", encoding="utf-8") as file:
        file.write(",".join(trace.columns) + "\n")
        for row in trace.data.tolist():
            file.write(",".join(str(int(value)) if is_int else repr(value)
                                for value, is_int in zip(row, integer, strict=True)) + "\n")
    return path


def read_csv(path: str | Path) -> Trace:
    """Read a file written by ``write_csv`` (or any CSV with a ``time`` column first); the
    columns only."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as file:
            rows = list(csv.reader(file))
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the trace: {exc.strerror or exc}") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise ConfigError(f"{path}: not a CSV trace: {exc}") from None
    if not rows or not rows[0] or rows[0][0] != TIME:
        raise ConfigError(f"{path}:1: the header must start with {TIME!r}")
    columns = rows[0]
    data = np.empty((len(rows) - 1, len(columns)))
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(columns):
            raise ConfigError(f"{path}:{number}: {len(row)} values for {len(columns)} columns")
        try:
            data[number - 2] = [float(value) for value in row]
        except ValueError as exc:
            raise ConfigError(f"{path}:{number}: {exc}") from None
    return Trace(columns, data)


def write_sidecar(trace: Trace, path: str | Path) -> Path:
    """Write the events, layout and title of ``trace``, whose columns are in the CSV ``path``,
    to ``sidecar_path(path)`` as JSON. It names the CSV and its columns and row count, so that
    a sidecar left beside another CSV is not taken for its own."""
    target = sidecar_path(path)
    head = {"format": SIDECAR_FORMAT, "trace": Path(path).name, "title": trace.title,
            "rows": len(trace), "columns": list(trace.columns)}
    events = [json.dumps({field: _finite_or_none(value) if field == "time" else value
                          for field, value in zip(Event._fields, event, strict=True)},
                         ensure_ascii=False) for event in trace.events]
    lines = [f" {json.dumps(key)}: {json.dumps(value, ensure_ascii=False)}," for key, value
             in head.items()]  # one line per entry and per event: a diff reads as a diff
    lines += [' "events": [', ",\n".join(f"  {event}" for event in events), " ],",
              f' "layout": {json.dumps(trace.layout, ensure_ascii=False)}']
    target.write_text("{\n" + "\n".join(line for line in lines if line) + "\n}\n",
                      encoding="utf-8")
    return target


def read_sidecar(trace: Trace, path: str | Path) -> Trace:
    """``trace`` (read from the CSV ``path``) with the events, layout and title of its
    sidecar. Without a sidecar that fits, the columns alone and a ``TraceWarning`` saying why
    the events and layout are missing."""
    target = sidecar_path(path)
    try:
        content = _sidecar(target, trace)
    except _NoSidecar as exc:
        warnings.warn(f"{path}: {exc}: the command events and the layout are missing, so only "
                      "the scope can be drawn", TraceWarning, stacklevel=3)
        return trace
    return Trace(trace.columns, trace.data, content["events"], content["layout"],
                 content["title"])


class _NoSidecar(Exception):
    """Why a CSV trace has no sidecar to go with it."""


def _sidecar(target: Path, trace: Trace) -> dict[str, Any]:
    """The sidecar's events, layout and title, checked against the CSV's ``trace``."""
    try:
        text = target.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise _NoSidecar(f"no {target.name} beside it") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise _NoSidecar(f"cannot read {target.name}: {getattr(exc, 'strerror', None) or exc}")\
            from None
    try:
        content = json.loads(text)
        if not isinstance(content, dict) or content.get("format") != SIDECAR_FORMAT:
            raise ValueError(f"no \"format\": {SIDECAR_FORMAT}")
        if content.get("columns") != list(trace.columns) or content.get("rows") != len(trace):
            raise _NoSidecar(f"{target.name} was written for another trace (its columns or "
                             "row count differ)")
        events = [Event(math.nan if item["time"] is None else float(item["time"]),
                        *(str(item.get(field, "")) for field in Event._fields[1:]))
                  for item in content["events"]]
        layout, title = content["layout"], content.get("title", "")
        if not isinstance(layout, dict) or not isinstance(title, str):
            raise ValueError("layout must be an object and title a string")
    except (ValueError, TypeError, KeyError) as exc:
        raise _NoSidecar(f"{target.name} is not a trace sidecar ({exc})") from None
    return {"events": events, "layout": layout, "title": title}


def _finite_or_none(value: float) -> float | None:
    """JSON has no NaN: an event that never ended has a null time."""
    return value if math.isfinite(value) else None


def write_npz(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` with its events, layout and title to ``path`` (compressed NPZ)."""
    path = Path(path)
    events = {f"events_{field}": np.array([getattr(event, field) for event in trace.events],
                                          dtype=np.float64 if field == "time" else np.str_)
              for field in Event._fields}
    with path.open("wb") as file:  # a file object: numpy adds no ".npz" to the name
        np.savez_compressed(file, format=np.array(NPZ_FORMAT), columns=np.array(trace.columns),
                            data=trace.data, layout=np.array(json.dumps(trace.layout)),
                            title=np.array(trace.title), **events)
    return path


def read_npz(path: str | Path) -> Trace:
    """Read a file written by ``write_npz`` (one without a title: the title is "")."""
    path = Path(path)
    try:
        with path.open("rb") as file, np.load(file, allow_pickle=False) as archive:
            arrays = {name: archive[name] for name in archive.files}
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the trace: {exc.strerror or exc}") from None
    except (ValueError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        raise ConfigError(f"{path}: not an NPZ trace: {exc}") from None
    missing = {"format", "columns", "data", "layout"} - set(arrays)
    missing |= {f"events_{field}" for field in Event._fields} - set(arrays)
    if missing:
        raise ConfigError(f"{path}: not an NPZ trace: no {', '.join(sorted(missing))}")
    try:
        number = int(arrays["format"])
    except (ValueError, TypeError) as exc:
        raise ConfigError(f"{path}: not an NPZ trace: format: {exc}") from None
    if number != NPZ_FORMAT:
        raise ConfigError(f"{path}: NPZ trace format {number}, this version reads {NPZ_FORMAT}")
    try:
        fields = [arrays[f"events_{field}"].tolist() for field in Event._fields]
        events = [Event(*values) for values in zip(*fields, strict=True)]
        title = str(arrays["title"]) if "title" in arrays else ""
        return Trace(arrays["columns"].tolist(), arrays["data"], events,
                     json.loads(str(arrays["layout"])), title)
    except (ValueError, TypeError) as exc:
        raise ConfigError(f"{path}: not an NPZ trace: {exc}") from None


def write_trace(trace: Trace, path: str | Path) -> Path:
    """``write_npz`` for a ``.npz`` path; ``write_csv`` and ``write_sidecar`` for a ``.csv``
    path; ConfigError for any other (``trace_format``)."""
    if trace_format(path) == "npz":
        return write_npz(trace, path)
    write_csv(trace, path)
    write_sidecar(trace, path)
    return Path(path)


def read_trace(path: str | Path) -> Trace:
    """``read_stream`` for a directory (a streamed trace; unless it is named like a trace
    file and holds no manifest); ``read_npz`` for a ``.npz`` path; ``read_csv`` and
    ``read_sidecar`` for a ``.csv`` path (a ``TraceWarning`` when the sidecar is missing);
    ConfigError for any other."""
    path = Path(path)
    if path.is_dir() and ((path / MANIFEST).exists()
                          or path.suffix.lower().lstrip(".") not in TRACE_FORMATS):
        return read_stream(path)
    if trace_format(path) == "npz":
        return read_npz(path)
    return read_sidecar(read_csv(path), path)
