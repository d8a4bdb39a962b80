"""Traces in files: CSV (the columns) and NPZ (the columns, the events and the layout).

CSV: one header line, one column per signal, floats written with ``repr``, which gives the
shortest text that parses back to the same float64, so a trace read back from its file is
bit-identical to the recorded one and two runs can be diffed as text.

NPZ (numpy's zip of arrays, no pickles): ``columns`` and ``data`` as recorded, the events as
one array per field (``events_time``, ``events_object``, ...), the layout as JSON text and a
``format`` number. Everything reads back bit-identical. ``write_trace`` and ``read_trace``
pick the format by the suffix: ``.npz``, else CSV.
"""

from __future__ import annotations

import csv
import json
import zipfile
from pathlib import Path

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.trace.record import TIME, Event, Trace

NPZ_FORMAT = 1  #: the ``format`` number of the NPZ files written here


def write_csv(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` to ``path``; axis states as integers, every other value via ``repr``."""
    path = Path(path)
    integer = [name.endswith(".state") for name in trace.columns]
    with path.open("w", newline="", encoding="utf-8") as file:
        file.write(",".join(trace.columns) + "\n")
        for row in trace.data.tolist():
            file.write(",".join(str(int(value)) if is_int else repr(value)
                                for value, is_int in zip(row, integer, strict=True)) + "\n")
    return path


def read_csv(path: str | Path) -> Trace:
    """Read a file written by ``write_csv`` (or any CSV with a ``time`` column first)."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as file:
            rows = list(csv.reader(file))
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the trace: {exc.strerror}") from None
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


def write_npz(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` with its events and layout to ``path`` (compressed NPZ)."""
    path = Path(path)
    events = {f"events_{field}": np.array([getattr(event, field) for event in trace.events],
                                          dtype=np.float64 if field == "time" else np.str_)
              for field in Event._fields}
    with path.open("wb") as file:  # a file object: numpy adds no ".npz" to the name
        np.savez_compressed(file, format=np.array(NPZ_FORMAT), columns=np.array(trace.columns),
                            data=trace.data, layout=np.array(json.dumps(trace.layout)),
                            **events)
    return path


def read_npz(path: str | Path) -> Trace:
    """Read a file written by ``write_npz``."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as archive:
            arrays = {name: archive[name] for name in archive.files}
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the trace: {exc.strerror or exc}") from None
    except (ValueError, zipfile.BadZipFile) as exc:
        raise ConfigError(f"{path}: not an NPZ trace: {exc}") from None
    missing = {"format", "columns", "data", "layout"} - set(arrays)
    missing |= {f"events_{field}" for field in Event._fields} - set(arrays)
    if missing:
        raise ConfigError(f"{path}: not an NPZ trace: no {', '.join(sorted(missing))}")
    if int(arrays["format"]) != NPZ_FORMAT:
        raise ConfigError(f"{path}: NPZ trace format {int(arrays['format'])}, this version "
                          f"reads {NPZ_FORMAT}")
    fields = [arrays[f"events_{field}"].tolist() for field in Event._fields]
    events = [Event(*values) for values in zip(*fields, strict=True)]
    try:
        return Trace(arrays["columns"].tolist(), arrays["data"], events,
                     json.loads(str(arrays["layout"])))
    except ValueError as exc:
        raise ConfigError(f"{path}: {exc}") from None


def write_trace(trace: Trace, path: str | Path) -> Path:
    """``write_npz`` for a ``.npz`` path, else ``write_csv``."""
    return write_npz(trace, path) if Path(path).suffix.lower() == ".npz" \
        else write_csv(trace, path)


def read_trace(path: str | Path) -> Trace:
    """``read_npz`` for a ``.npz`` path, else ``read_csv``."""
    return read_npz(path) if Path(path).suffix.lower() == ".npz" else read_csv(path)
