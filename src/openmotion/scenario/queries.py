"""Query entries: a read block or a Get method called once, its outputs kept on the entry's row.

A PLC program reads a value by calling a read block with Enable (MC_ReadStatus,
MC_GroupReadActualPosition, MC_ReadTrackPositions) or a Get method (GetLength) in one cycle.
A query entry does the same at its ``at`` or ``when``: it ends Done with the outputs as its
command's value, or Error with the block's error id. The value is a mapping from output name to
a number (flags read 1 or 0, enumerations and error ids their number) or to a text (a name, a
model); a list output such as an ACS position gives one output per element,
``position_1``, ``position_2`` ... (IdentInGroup or coordinate order). The summary lists them;
a command check compares one with ``output`` and ``value`` (D-218)::

    checks:
      - {command: status, result: done, output: standstill, value: 1}

The query entries live with the entries of their family (cyclic.py for the TcMC reads,
coordinated.py, transport.py, planar.py ...); this module holds what they share.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from enum import Enum
from typing import Any, ClassVar

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.errors import ErrorId

OutputValue = float | str
Outputs = dict[str, OutputValue]
#: an output name ending in this suffix stands for a list output (``position_`` for
#: position_1, position_2 ...)
LIST_SUFFIX = "_"
_HANDSHAKE = frozenset({"axis", "axes_group", "enable", "execute", "error", "error_id",
                        "message", "done", "busy", "active", "command_aborted", "valid"})


class Called:
    """Mixin of an entry that calls its block (or method) itself: ``call(target, now)``
    gives the row's command. The run passes the entry's axis, group, mover or track."""

    def call(self, target: Any, now: float) -> Command:
        raise NotImplementedError


class Query(Called):
    """Mixin of an entry whose command ends with outputs (a read block or a Get method)."""

    outputs: ClassVar[tuple[str, ...]] = ()  #: the output names a check may pick; a name
    #: ending in ``_`` is a list output (``position_`` for position_1, position_2 ...)

    @classmethod
    def has_output(cls, name: str) -> bool:
        """Whether ``output`` may name ``name`` (a list output by any 1-based index)."""
        for output in cls.outputs:
            if output == name:
                return True
            if output.endswith(LIST_SUFFIX) and name.startswith(output) \
                    and name[len(output):].isdigit() and int(name[len(output):]) >= 1:
                return True
        return False


def output_value(value: object) -> OutputValue | list[OutputValue]:
    """An output as the row keeps it: numbers as floats, flags 1/0, enums their number,
    arrays a list, other objects their text."""
    if isinstance(value, bool | np.bool_):
        return 1.0 if value else 0.0
    if isinstance(value, Enum):
        return float(value.value) if isinstance(value.value, int | float) else value.name
    if isinstance(value, int | float | np.integer | np.floating):
        return float(value)
    if isinstance(value, np.ndarray | list | tuple):
        return [output_value(item) for item in value]  # type: ignore[misc]
    return "-" if value is None else str(value)


def flatten(outputs: Mapping[str, object]) -> Outputs:
    """Outputs by name; a list output becomes ``name_1``, ``name_2`` ..."""
    flat: Outputs = {}
    for name, raw in outputs.items():
        value = output_value(raw)
        if isinstance(value, list):
            for index, item in enumerate(value, start=1):
                flat[f"{name}_{index}"] = item if not isinstance(item, list) else str(item)
        else:
            flat[name] = value
    return flat


def block_outputs(block: object, names: Iterable[str] | None = None) -> Outputs:
    """The outputs of a called block: ``names``, or every public attribute that is no input
    and no handshake output (done, error ...)."""
    inputs = getattr(block, "INPUTS", {})
    if names is None:
        names = [name for name in vars(block) if not name.startswith("_")
                 and name not in inputs and name not in _HANDSHAKE]
    return flatten({name: getattr(block, name) for name in names})


def query_command(kind: str, now: float, outputs: Mapping[str, object],
                  error_id: ErrorId = ErrorId.NO_ERROR, message: str = "") -> Command:
    """A query's record: Done with ``outputs`` as its value, or Error with ``error_id``."""
    command = Command(kind, now)
    if error_id != ErrorId.NO_ERROR:
        command.end(CommandStatus.ERROR, now, error_id, message)
        return command
    command.value = flatten(outputs)
    command.end(CommandStatus.DONE, now)
    return command


def block_query(kind: str, now: float, block: Any, names: Iterable[str] | None = None) \
        -> Command:
    """The record of a block that was just called: its error, or its outputs."""
    if block.error:
        return query_command(kind, now, {}, block.error_id, block.message)
    return query_command(kind, now, block_outputs(block, names))


def outputs_text(outputs: Outputs, number: Any) -> str:
    """The summary's text: ``name value, name value ...``."""
    return ", ".join(f"{name} {number(value) if isinstance(value, float) else value}"
                     for name, value in outputs.items())


def pick(outputs: object, name: str) -> float | None:
    """The number of output ``name``; None when there is none (or it is a text)."""
    if not isinstance(outputs, dict):
        return None
    value = outputs.get(name)
    return value if isinstance(value, float) and math.isfinite(value) else None
