"""Record axis signals once per cycle into growable numpy arrays.

A ``TraceRecorder`` is a runtime observer (architecture §cycle, phase 4): it samples after
drives and monitoring, so a row shows the state a PLC would read at the start of the next
cycle. Every value is a float64; an axis state is stored as its ``AxisState`` number, an axis
error as its ``ErrorId`` number.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.core.errors import CommandRejected, ConfigError

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.runtime.runtime import Runtime

#: Axis properties a trace can record, in the order ``default_signals`` lists them.
AXIS_SIGNALS = ("set_position", "set_velocity", "set_acceleration", "set_jerk", "position",
                "velocity", "following_error", "state", "override", "homed", "axis_error_id",
                "gap", "track_position", "tcp_position")
#: The signals only members of a CA group have (NaN for other axes).
MOVER_SIGNALS = ("gap", "track_position", "tcp_position")
#: What a scenario records when it names no signals: setpoint and actual position.
DEFAULT_AXIS_SIGNALS = ("set_position", "set_velocity", "set_acceleration", "position")
TIME = "time"
_WHOLE_SIGNALS = frozenset({"state", "homed", "axis_error_id"})
_SIGNAL = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\.([a-z_]+)$")


def split_signal(name: str) -> tuple[str, str]:
    """``"x.set_position"`` -> ``("x", "set_position")``; ValueError for anything else."""
    match = _SIGNAL.match(name)
    if match is None or match.group(2) not in AXIS_SIGNALS:
        raise ValueError(f"{name!r} is not '<axis>.<signal>' with a signal among "
                         f"{', '.join(AXIS_SIGNALS)}")
    return match.group(1), match.group(2)


def read_signal(axis: Axis, prop: str) -> float:
    """One signal of ``axis`` as a float: the state as its AxisState number, the override in
    percent (0-100), homed as 0 or 1, the axis error as its ErrorId number (0: none). The
    signals of a CA mover (transport/; NaN for an axis in no CA group):

    - ``gap``: the setpoint gap [mm] to the predecessor in the group (inf: no predecessor);
    - ``track_position``: the set position on the active track, as MC_ReadTrackPositions
      gives it; the absolute set position without one; NaN once off an (open) track;
    - ``tcp_position``: the TCP arc length [mm] of the set position on the path of the
      registered mover template (MC_TransformPosition from 0 to it); NaN without one.
    """
    if prop in MOVER_SIGNALS:
        group = axis.group
        return math.nan if group is None else _mover_signal(group, axis, prop)
    value = getattr(axis, prop)
    if prop == "override":
        return float(value) * 100.0
    return float(int(value)) if prop in _WHOLE_SIGNALS else float(value)


def _mover_signal(group: Any, axis: Axis, prop: str) -> float:
    if prop == "gap":
        return float(group.gaps()[group.mover_of(axis).slot])
    if prop == "track_position":
        try:
            return float(group.tracks.read_track_positions(axis).track_position)
        except CommandRejected:  # NOT_ON_TRACK: the mover left its open track
            return math.nan
    geo = group.tracks.geo
    template = geo.registered(axis)
    return math.nan if template is None else geo.to_tcp(template, axis.set_position)


def default_signals(axis_names: Iterable[str]) -> list[str]:
    return [f"{axis}.{prop}" for axis in axis_names for prop in DEFAULT_AXIS_SIGNALS]


class Trace:
    """Recorded columns: ``time`` first, then one column per signal, in recording order."""

    def __init__(self, columns: Sequence[str], data: np.ndarray) -> None:
        data = np.asarray(data, dtype=np.float64)
        if data.ndim != 2 or data.shape[1] != len(columns):
            raise ValueError(f"data of shape {data.shape} does not fit {len(columns)} columns")
        if not columns or columns[0] != TIME:
            raise ValueError(f"the first column must be {TIME!r}")
        self.columns = tuple(columns)
        self.data = data
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
        return f"<Trace {len(self)} rows: {', '.join(self.columns)}>"

    @property
    def time(self) -> np.ndarray:
        return self.data[:, 0]

    @property
    def signals(self) -> tuple[str, ...]:
        return self.columns[1:]

    @property
    def axes(self) -> list[str]:
        """Axis names in the order their first signal appears."""
        return list(dict.fromkeys(name.split(".", 1)[0] for name in self.signals))

    def peak(self, name: str) -> float:
        """Largest absolute value of one column (0 for an empty trace)."""
        column = self[name]
        return float(np.max(np.abs(column))) if column.size else 0.0

    def equals(self, other: Trace) -> bool:
        """Bit-identical: same columns and exactly the same numbers."""
        return self.columns == other.columns and np.array_equal(self.data, other.data)


class TraceRecorder:
    """Runtime observer that records ``signals`` every ``every`` cycles.

    Construct it, then ``runtime.add_observer(recorder)``; call ``sample(runtime)`` once more
    before the first cycle for a row at t = 0.
    """

    def __init__(self, runtime: Runtime, signals: Sequence[str], every: int = 1,
                 capacity: int = 1024) -> None:
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            raise ConfigError(f"every: must be an integer >= 1, got {every!r}")
        self._getters: list[tuple[Axis, str]] = []
        for name in signals:
            try:
                axis_name, prop = split_signal(name)
            except ValueError as exc:
                raise ConfigError(f"signals: {exc}") from None
            if axis_name not in runtime.axes:
                raise ConfigError(f"signals: {name!r} names no axis of the runtime")
            self._getters.append((runtime.axes[axis_name], prop))
        self.columns = (TIME, *signals)
        self.every = every
        self._data = np.empty((max(capacity, 1), len(self.columns)))
        self._rows = 0

    def __call__(self, runtime: Runtime) -> None:
        if runtime.cycle % self.every == 0:
            self.sample(runtime)

    def sample(self, runtime: Runtime) -> None:
        """Append one row with the values now."""
        if self._rows == self._data.shape[0]:
            grown = np.empty((2 * self._rows, len(self.columns)))
            grown[: self._rows] = self._data
            self._data = grown
        row = self._data[self._rows]
        row[0] = runtime.now
        for i, (axis, prop) in enumerate(self._getters, start=1):
            row[i] = read_signal(axis, prop)
        self._rows += 1

    @property
    def trace(self) -> Trace:
        """A copy of what has been recorded so far."""
        return Trace(self.columns, self._data[: self._rows].copy())
