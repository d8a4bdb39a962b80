"""``openmotion bench startup``: whole processes, warm, first and cold; structure, never
timings."""

from __future__ import annotations

import json

import pytest

from openmotion.bench.runner import goals_startup, render, run_benchmark


@pytest.fixture(scope="module")
def result() -> dict:
    seen: list[str] = []
    out = run_benchmark("startup", quick=True, progress=seen.append)
    assert any("cold" in line for line in seen), seen
    return out


def test_every_figure_is_a_positive_wall_time(result: dict) -> None:
    r = result["results"]
    assert set(r["warm"]) == {"import", "import_runtime", "check", "check_1mb", "run"}
    assert set(r["floors"]) == {"python", "numpy_numba"}
    for row in [*r["warm"].values(), *r["floors"].values(), r["cold"]["run"]]:
        assert 0.0 < row["min_s"] <= row["median_s"] <= row["max_s"] and row["runs"] >= 1
    assert r["cold"]["examples"] == {}  # quick: the default example only
    assert list(r["first"]) == ["single_move"] and r["first"]["single_move"] > 0.0
    json.loads(json.dumps(result, allow_nan=False))
    text = render(result)
    assert "openmotion check" in text and "cold: openmotion run" in text


def test_a_cold_run_compiles_so_it_is_slower_than_a_warm_one(result: dict) -> None:
    """The cold run really starts from an empty kernel cache (else the figure is a lie)."""
    r = result["results"]
    assert r["cold"]["run"]["min_s"] > r["warm"]["run"]["min_s"]


def test_goals_judge_the_medians_and_the_slowest_first_run() -> None:
    def stats(median: float) -> dict:
        return {"min_s": median, "median_s": median, "max_s": median, "runs": 1}

    results = {"warm": {"check": stats(0.9), "run": stats(1.6), "check_1mb": stats(1.9)},
               "first": {"a": 3.0, "b": 11.0},
               "cold": {"run": stats(4.0), "examples": {"a": 30.0, "b": 12.0}}}
    goals = goals_startup(results)
    assert goals["check"]["passed"] is True and goals["run"]["passed"] is False
    assert goals["check_1mb"]["passed"] is True
    assert goals["first"]["passed"] is False and "slowest: b" in goals["first"]["goal"]
