"""What a sweep collects from each run, as table columns: one model per metric kind.

A metric kind is a pydantic model whose one distinguishing key names it (``signal``,
``commands``, ``run``, ``station``, ``cycle_cost``) and that knows its columns and how to read
them from a ``ScenarioResult``. A new kind is one more class in ``METRIC_KINDS``.
Timing kinds (``timing = True``) give wall-clock-dependent columns, which the determinism
guarantee leaves out (docs/sweeps.md, "Determinism").
"""

from __future__ import annotations

import fnmatch
import math
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

if TYPE_CHECKING:
    from openmotion.scenario.run import ScenarioResult

SignalStat = Literal["min", "max", "mean", "final"]
Outcome = Literal["done", "aborted", "error", "busy", "not_issued"]
RunField = Literal["end_time", "cycles", "passed"]
FLOAT, INT, BOOL = "float64", "Int64", "boolean"  #: column dtypes (pandas; Int64 takes nulls)


class Metric(BaseModel):
    """One entry of a sweep file's ``metrics`` list."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    key: ClassVar[str]  #: the field that names the kind
    timing: ClassVar[bool] = False  #: columns depend on the wall clock

    def columns(self) -> dict[str, str]:
        """Column name -> dtype, in table order."""
        raise NotImplementedError

    def collect(self, result: ScenarioResult, cpu: float) -> dict[str, Any]:
        """The columns' values for one finished run (``cpu``: process seconds of the run);
        raises ``ValueError`` when the run cannot give them."""
        raise NotImplementedError


class SignalMetric(Metric):
    """Statistics of recorded signals; a pattern (``*.gap``) pools every matching signal
    (``final`` is then the mean of their last samples)."""

    key: ClassVar[str] = "signal"
    signal: str = Field(min_length=1)
    stats: list[SignalStat] = Field(default=["min", "max", "mean", "final"], min_length=1)
    name: str | None = None  #: column prefix; default the signal

    def columns(self) -> dict[str, str]:
        return {f"{self.name or self.signal}.{stat}": FLOAT for stat in self.stats}

    def collect(self, result: ScenarioResult, cpu: float) -> dict[str, Any]:
        trace = result.trace
        names = [s for s in trace.signals if fnmatch.fnmatchcase(s, self.signal)]
        if not names:
            raise ValueError(f"metric signal {self.signal!r}: no recorded signal matches "
                             f"(recorded: {', '.join(trace.signals) or 'none'})")
        data = np.stack([np.asarray(trace[name], dtype=np.float64) for name in names])
        empty = data.shape[1] == 0
        values = {"min": lambda: data.min(), "max": lambda: data.max(),
                  "mean": lambda: data.mean(),
                  "final": lambda: data[:, -1].mean()}
        return {column: math.nan if empty else float(values[stat]())
                for column, stat in zip(self.columns(), self.stats, strict=True)}


class CommandsMetric(Metric):
    """How many timeline commands ended with each outcome."""

    key: ClassVar[str] = "commands"
    commands: list[Outcome] = Field(min_length=1)

    def columns(self) -> dict[str, str]:
        return {f"commands.{outcome}": INT for outcome in self.commands}

    def collect(self, result: ScenarioResult, cpu: float) -> dict[str, Any]:
        seen = [row.result.lower().replace(" ", "_") for row in result.commands]
        return {f"commands.{outcome}": seen.count(outcome) for outcome in self.commands}


class RunMetric(Metric):
    """Figures of the whole run: simulated end time [s], cycles, whether every check passed."""

    key: ClassVar[str] = "run"
    run: list[RunField] = Field(min_length=1)

    def columns(self) -> dict[str, str]:
        types = {"end_time": FLOAT, "cycles": INT, "passed": BOOL}
        return {f"run.{name}": types[name] for name in self.run}

    def collect(self, result: ScenarioResult, cpu: float) -> dict[str, Any]:
        values = {"end_time": float(result.end_time), "cycles": int(result.cycles),
                  "passed": bool(result.passed)}
        return {f"run.{name}": values[name] for name in self.run}


StationField = Literal["processed", "parts_per_minute", "utilisation", "mean_wait",
                       "mean_queue", "max_queue"]
_STATION_TYPES = {"processed": INT, "max_queue": INT}


class StationMetric(Metric):
    """A station's figures at the end of the run (rail/stations.py): parts processed and per
    minute, utilisation, mean wait [s], mean and largest queue."""

    key: ClassVar[str] = "station"
    station: str = Field(min_length=1)
    stats: list[StationField] = Field(default=["processed", "parts_per_minute",
                                               "utilisation"], min_length=1)

    def columns(self) -> dict[str, str]:
        return {f"{self.station}.{stat}": _STATION_TYPES.get(stat, FLOAT)
                for stat in self.stats}

    def collect(self, result: ScenarioResult, cpu: float) -> dict[str, Any]:
        rows = {row.name: row for _, row in result.stations}
        row = rows.get(self.station)
        if row is None:
            raise ValueError(f"metric station {self.station!r}: no such station (stations: "
                             f"{', '.join(rows) or 'none'})")
        return {column: getattr(row, stat)
                for column, stat in zip(self.columns(), self.stats, strict=True)}


class CycleCostMetric(Metric):
    """Process CPU time of the run, in all and per cycle [s]: timing, never compared."""

    key: ClassVar[str] = "cycle_cost"
    timing: ClassVar[bool] = True
    cycle_cost: Literal[True]

    def columns(self) -> dict[str, str]:
        return {"cycle_cost.cpu": FLOAT, "cycle_cost.cpu_per_cycle": FLOAT}

    def collect(self, result: ScenarioResult, cpu: float) -> dict[str, Any]:
        return {"cycle_cost.cpu": cpu,
                "cycle_cost.cpu_per_cycle": cpu / result.cycles if result.cycles else math.nan}


#: the metric kinds, by the key that names each
METRIC_KINDS: dict[str, type[Metric]] = {kind.key: kind for kind in (
    SignalMetric, CommandsMetric, RunMetric, StationMetric, CycleCostMetric)}


def metric_kind(data: Any) -> str | None:
    """The kind a ``metrics`` entry names: its one key among ``METRIC_KINDS`` (pydantic's
    discriminator); None when it names none or several."""
    if isinstance(data, Metric):
        return data.key
    if not isinstance(data, dict):
        return None
    kinds = [key for key in data if key in METRIC_KINDS]
    return kinds[0] if len(kinds) == 1 else None
