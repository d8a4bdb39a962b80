"""One point, run where the executor puts it (a pool process, a Ray worker, or here).

``run_point`` never raises for a point: an invalid scenario or a run that raises gives a row
with status ``failed`` and the error, so that the sweep goes on. Only the death of the
process itself loses the point, and the executor retries it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import yaml
from pydantic import ValidationError

from openmotion.scenario import ScenarioError, parse_scenario, run_scenario
from openmotion.scenario.schema import Scenario
from openmotion.sweep.metrics import Metric
from openmotion.sweep.points import Point

DONE, FAILED = "done", "failed"  #: a row's status
#: called in the worker before each point runs (fault injection in tests: faults.py)
PointHook = Callable[[Point], Any]


def run_point(point: Point, metrics: list[Metric], on_point: PointHook | None = None) \
        -> dict[str, Any]:
    """The point's row: status, error, and the metrics' values (none when it failed)."""
    try:
        if on_point is not None:
            on_point(point)
        scenario = _scenario(point.document)
        started = time.process_time()
        result = run_scenario(scenario)
        cpu = time.process_time() - started
        values: dict[str, Any] = {}
        for metric in metrics:
            values.update(metric.collect(result, cpu))
    except Exception as exc:  # noqa: BLE001 - any failure of one point is that point's row
        return failed_row(_message(exc))
    return {"status": DONE, "error": "", "metrics": values}


def failed_row(error: str) -> dict[str, Any]:
    return {"status": FAILED, "error": error, "metrics": {}}


class InvalidScenario(Exception):
    """A point's document is not a valid scenario; the message lists the problems."""


def _scenario(document: dict[str, Any]) -> Scenario:
    """The document as a model; when it is invalid, the loader's problems (field paths and
    messages, without the line numbers of a file that does not exist)."""
    try:
        return Scenario.model_validate(document)
    except ValidationError:
        try:
            parse_scenario(yaml.safe_dump(document, sort_keys=False), "point")
        except ScenarioError as exc:
            raise InvalidScenario("; ".join(f"{p.path}: {p.message}" if p.path else p.message
                                            for p in exc.problems)) from None
        raise


def _message(exc: BaseException) -> str:
    if isinstance(exc, InvalidScenario):
        return f"invalid scenario: {exc}"
    return f"{type(exc).__name__}: {exc}"
