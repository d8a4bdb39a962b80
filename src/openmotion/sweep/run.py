"""Run a sweep: expand its points, reuse the ones finished before, run the rest on an
executor, store each row as it arrives, then write the table and the summary figure.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from openmotion.sweep.executors import DEFAULT_RETRIES, ProcessPool, RayExecutor
from openmotion.sweep.points import Point, expand
from openmotion.sweep.results import (
    FIGURE_FILE,
    TABLE_FILE,
    ResultStore,
    build_table,
    timing_columns,
)
from openmotion.sweep.spec import Sweep, load_sweep
from openmotion.sweep.worker import FAILED, PointHook

if TYPE_CHECKING:
    import pandas

EXTRA = "sweep"  #: pyproject's optional dependencies for sweeps
TABLE_MODULES = ("pandas", "pyarrow")  #: what every sweep needs
RAY_MODULES = ("ray",)  #: what ``ray=`` needs
RAY_LOCAL = "local"  #: ``ray=`` for a new local cluster, as True (Ray's own word for it)


class MissingExtra(ImportError):
    """A module of the ``sweep`` extra is not installed; the message says what to install."""


@dataclass(frozen=True)
class SweepProgress:
    """Where a sweep stands, after each point (and once before the first)."""

    done: int  #: points with a row, reused ones included
    failed: int  #: of those, the failed ones
    reused: int  #: rows found in the output directory, not computed again
    total: int


def require_extra(ray: bool = False) -> None:
    """``MissingExtra`` naming the extra to install when pandas, pyarrow (or ray) are missing."""
    missing = []
    for name in TABLE_MODULES + (RAY_MODULES if ray else ()):
        try:
            importlib.import_module(name)
        except ImportError:
            missing.append(name)
    if missing:
        raise MissingExtra(f"sweeps need {', '.join(missing)}: install them with "
                           f"pip install 'openmotion[{EXTRA}]'")


def run_sweep(sweep: str | Path | Sweep, output: str | Path | None = None, *,
              workers: int | None = None, ray: bool | str = False,
              retries: int = DEFAULT_RETRIES,
              progress: Callable[[SweepProgress], Any] | None = None,
              on_point: PointHook | None = None, figure: bool = True) -> pandas.DataFrame:
    """Run every point of a sweep file (or loaded ``Sweep``) and return its table.

    ``output``: a directory for the finished points (a sweep run again with it resumes), the
    table (``results.parquet``) and, with ``figure``, the summary figure (``summary.png``);
    None keeps nothing. ``workers``: processes, or the CPUs of a local Ray cluster (default:
    the CPUs this process may use). ``ray``: False runs a local process pool; True or
    ``"local"`` starts a local Ray cluster; any other string is the address of one to join.
    ``retries``: new attempts for a point whose worker died. ``progress`` is called after
    each point; an exception from it (KeyboardInterrupt) stops the sweep with every finished
    point stored. ``on_point`` is called in the worker before each point runs.
    """
    require_extra(ray=ray is not False)
    if not isinstance(sweep, Sweep):
        sweep = load_sweep(sweep)
    points = expand(sweep)
    store = ResultStore(output, sweep.metrics)
    rows = {point.index: row for point in points if (row := store.load(point)) is not None}
    reused = len(rows)

    def report() -> None:
        if progress is not None:
            failed = sum(row["status"] == FAILED for row in rows.values())
            progress(SweepProgress(len(rows), failed, reused, len(points)))

    report()
    todo = [point for point in points if point.index not in rows]
    if todo:
        _compute(todo, rows, store, sweep, workers, ray, retries, on_point, report)
    table = build_table(points, rows, sweep.spec.parameters, sweep.metrics)
    if output is not None:
        table.to_parquet(Path(output) / TABLE_FILE, index=False)
        if figure:
            from openmotion.sweep.figure import save_sweep_figure

            metrics = [name for metric in sweep.metrics for name in metric.columns()]
            save_sweep_figure(table, [p.column for p in sweep.spec.parameters], metrics,
                              Path(output) / FIGURE_FILE, sweep.spec.name)
    return table


def _compute(todo: list[Point], rows: dict[int, dict[str, Any]], store: ResultStore,
             sweep: Sweep, workers: int | None, ray: bool | str, retries: int,
             on_point: PointHook | None, report: Callable[[], None]) -> None:
    executor: ProcessPool | RayExecutor
    if ray is False:
        executor = ProcessPool(sweep.metrics, workers, retries, on_point)
    else:
        address = None if ray is True or ray == RAY_LOCAL else str(ray)
        executor = RayExecutor(sweep.metrics, address, workers, retries, on_point)
    try:
        for point, row in executor.results(todo):
            store.save(point, row)
            rows[point.index] = row
            report()
    finally:
        executor.close()


def compared(table: pandas.DataFrame, sweep: Sweep) -> pandas.DataFrame:
    """The table without its timing columns: what two executors give bit for bit."""
    return table.drop(columns=timing_columns(sweep.metrics))
