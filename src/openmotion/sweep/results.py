"""A sweep's results: one JSON file per finished point (what makes a sweep resumable), and
the table assembled from them (one row per point, ordered by point index).

A point's file is named by its id and written whole (a temporary file, then a rename), so an
interrupted sweep leaves finished points and nothing half-written. A file counts for a later
sweep when its key matches: the same metrics and the same openmotion version (D-253).
"""

from __future__ import annotations

import json
import os
import uuid
from pathlib import Path
from typing import TYPE_CHECKING, Any

import openmotion
from openmotion.sweep.metrics import Metric
from openmotion.sweep.points import Point, digest
from openmotion.sweep.spec import Parameter

if TYPE_CHECKING:
    import pandas

POINTS_DIR = "points"  #: one JSON file per finished point, in the output directory
TABLE_FILE = "results.parquet"
FIGURE_FILE = "summary.png"


def store_key(metrics: list[Metric]) -> str:
    """What a stored row must match to be reused: the metrics and the openmotion version."""
    return digest([[{metric.key: metric.model_dump()} for metric in metrics],
                   openmotion.__version__])


class ResultStore:
    """The finished points of a sweep in ``directory/points/``; nothing kept when None."""

    def __init__(self, directory: str | Path | None, metrics: list[Metric]) -> None:
        self.folder = None if directory is None else Path(directory) / POINTS_DIR
        self.key = store_key(metrics)
        if self.folder is not None:
            self.folder.mkdir(parents=True, exist_ok=True)

    def load(self, point: Point) -> dict[str, Any] | None:
        """The stored row of a point; None when absent, for other metrics or another
        version, unreadable, or lost to dying workers (tried again)."""
        if self.folder is None:
            return None
        try:
            data = json.loads((self.folder / f"{point.point_id}.json").read_text("utf-8"))
        except (OSError, ValueError):
            return None
        if not isinstance(data, dict) or data.get("key") != self.key or data.get("lost"):
            return None
        return data

    def save(self, point: Point, row: dict[str, Any]) -> None:
        if self.folder is None:
            return
        data = {"key": self.key, "point_id": point.point_id, **row}
        target = self.folder / f"{point.point_id}.json"
        temporary = target.with_name(f".{target.name}.{uuid.uuid4().hex}")
        temporary.write_text(json.dumps(data, allow_nan=True), encoding="utf-8")
        os.replace(temporary, target)


def build_table(points: list[Point], rows: dict[int, dict[str, Any]],
                parameters: list[Parameter], metrics: list[Metric]) -> pandas.DataFrame:
    """One row per point in index order: index, id, seed, sample, repeat, the parameters,
    status, error, the metrics, scenario hash, openmotion version; the timing metrics
    (``cycle_cost.*``) last."""
    import pandas

    ordered = sorted(points, key=lambda p: p.index)
    columns: dict[str, Any] = {
        "index": pandas.array([p.index for p in ordered], dtype="int64"),
        "point_id": [p.point_id for p in ordered],
        "seed": pandas.array([p.seed for p in ordered], dtype="int64"),
        "sample": pandas.array([p.sample for p in ordered], dtype="int64"),
        "repeat": pandas.array([p.repeat for p in ordered], dtype="int64"),
    }
    for parameter in parameters:
        columns[parameter.column] = _parameter_column([p.params[parameter.column]
                                                       for p in ordered])
    columns["status"] = [rows[p.index]["status"] for p in ordered]
    columns["error"] = [rows[p.index]["error"] for p in ordered]
    timing: dict[str, Any] = {}
    for metric in metrics:
        for name, dtype in metric.columns().items():
            values = [rows[p.index]["metrics"].get(name) for p in ordered]
            (timing if metric.timing else columns)[name] = pandas.array(values, dtype=dtype)
    columns["scenario_hash"] = [p.scenario_hash for p in ordered]
    columns["openmotion_version"] = [openmotion.__version__] * len(ordered)
    return pandas.DataFrame({**columns, **timing})


def timing_columns(metrics: list[Metric]) -> list[str]:
    """The columns that depend on the wall clock, left out of the determinism guarantee."""
    return [name for metric in metrics if metric.timing for name in metric.columns()]


def _parameter_column(values: list[Any]) -> Any:
    """A typed column: booleans, whole numbers, numbers or text as they are; anything else
    (lists, mappings, mixed kinds) as canonical JSON text."""
    import pandas

    kinds = {type(value) for value in values}
    if kinds == {bool}:
        return pandas.array(values, dtype="boolean")
    if kinds == {int}:
        return pandas.array(values, dtype="int64")
    if kinds <= {int, float}:
        return pandas.array([float(value) for value in values], dtype="float64")
    if kinds == {str}:
        return values
    return [json.dumps(value, sort_keys=True, separators=(",", ":"), default=str)
            for value in values]
