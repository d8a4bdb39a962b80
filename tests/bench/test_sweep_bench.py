"""``openmotion bench sweep``: structure and arithmetic of the figures, never timings."""

from __future__ import annotations

import json

import pytest

from openmotion.bench.runner import goals_sweep, render, run_benchmark
from openmotion.bench.sweep import _figures


@pytest.fixture(scope="module")
def result() -> dict:
    seen: list[str] = []
    out = run_benchmark("sweep", quick=True, progress=seen.append)
    assert any("process pool" in line for line in seen), seen
    return out


def test_quick_runs_serial_and_pool_on_twenty_points(result: dict) -> None:
    r = result["results"]
    assert (r["points"], r["workers"], r["ray"]) == (20, 2, None)
    for name in ("serial", "pool"):
        assert r[name]["wall_s"] > 0 and r[name]["points_per_s"] > 0
    assert r["serial"]["efficiency_per_worker"] == 1.0 and r["pool"]["failed"] == 0
    assert r["serial"]["cpu_s_per_point"] > 0 and r["pool"]["cpu_s_per_point"] > 0
    assert set(result["goals"]) == {"pool"}
    json.loads(json.dumps(result, allow_nan=False))
    text = render(result)
    assert "points/s" in text and "efficiency/worker" in text and "load average" in text
    assert "cpu ms/point" in text


def test_the_figures_follow_from_the_wall_times() -> None:
    figures = _figures(points=100, wall=2.0, workers=2, serial=3.0)
    assert figures["points_per_s"] == 50.0 and figures["s_per_point"] == 0.02
    assert figures["overhead_s_per_point"] == pytest.approx(0.01)  # 2 * 2 / 100 - 3 / 100
    assert figures["efficiency_per_worker"] == pytest.approx(0.75)  # 50 / (2 * 100 / 3)


def test_goals_judge_the_efficiency_and_the_same_table() -> None:
    def row(efficiency: float) -> dict:
        return {"efficiency_per_worker": efficiency}

    goals = goals_sweep({"workers": 2, "pool": row(0.6),
                         "ray": {**row(0.9), "next": row(0.2), "same_table": True}})
    assert goals["pool"]["passed"] is True and goals["ray"]["passed"] is False
    assert goals["ray"]["value"] == 0.2  # judged on the next sweep, the first one shown
    goals = goals_sweep({"workers": 2, "pool": row(0.6),
                         "ray": {**row(0.1), "next": row(0.3), "same_table": True}})
    assert goals["ray"]["passed"] is True
    assert goals["same_table"]["passed"] is True
    assert goals_sweep({"workers": 2, "pool": row(0.4), "ray": None})["pool"]["passed"] is False
