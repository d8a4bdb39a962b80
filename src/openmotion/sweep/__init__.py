"""Sweeps: many runs of one scenario with parameters varied, on a process pool or a Ray
cluster, collected into one table (docs/sweeps.md).

Loading a sweep needs only the core dependencies; running one needs the ``sweep`` extra
(pandas and pyarrow for the table, ray for ``ray=``).
"""

from __future__ import annotations

from openmotion.sweep.metrics import (
    METRIC_KINDS,
    CommandsMetric,
    CycleCostMetric,
    Metric,
    RunMetric,
    SignalMetric,
    StationMetric,
)
from openmotion.sweep.points import Point, expand
from openmotion.sweep.results import TABLE_FILE, timing_columns
from openmotion.sweep.run import MissingExtra, SweepProgress, compared, require_extra, run_sweep
from openmotion.sweep.spec import Sweep, SweepError, SweepSpec, load_sweep

__all__ = ["METRIC_KINDS", "TABLE_FILE", "CommandsMetric", "CycleCostMetric", "Metric",
           "MissingExtra", "Point", "RunMetric", "SignalMetric", "StationMetric", "Sweep",
           "SweepError", "SweepProgress", "SweepSpec", "compared", "expand", "load_sweep",
           "require_extra", "run_sweep", "timing_columns"]
