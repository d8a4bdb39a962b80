"""Traces as CSV: one header line, one column per signal, floats written with ``repr``.

``repr`` gives the shortest text that parses back to the same float64, so a trace read back
from its file is bit-identical to the recorded one and two runs can be diffed as text.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.trace.record import TIME, Trace


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
