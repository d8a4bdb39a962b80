"""``bench path``'s goals (issue 24 point 4): judged from the figures, never timed here."""

from __future__ import annotations

import pytest

from openmotion.bench.runner import (
    PATH_GOAL_PREPARE_S,
    PATH_GOAL_SEGMENTS,
    PATH_GOAL_SPEED_SHARE,
    goals_path,
)

FIGURES = {"segments": PATH_GOAL_SEGMENTS, "done": True, "end_error_mm": 0.0,
           "limit_violations": 0, "planner_us_p99": 90.0, "select_ms": 400.0,
           "start_us": 300_000.0, "mean_path_velocity": 81.0, "steady_bound_velocity": 84.5}


def test_path_goals_pass_on_figures_within_them() -> None:
    goals = goals_path(FIGURES)
    assert {k: g["passed"] for k, g in goals.items()} == {
        "limit_violations": True, "end": True, "planner_p99": True, "prepare": True,
        "speed": True}
    assert goals["prepare"]["value"] == pytest.approx(0.7)  # seconds, select + start
    assert goals["speed"]["value"] == pytest.approx(81.0 / 84.5)


def test_path_goals_fail_on_slow_preparation_planner_and_speed() -> None:
    slow = dict(FIGURES, select_ms=1e3 * PATH_GOAL_PREPARE_S, start_us=1.0,
                mean_path_velocity=0.9 * 84.5, planner_us_p99=178.0)
    goals = goals_path(slow)
    assert not goals["prepare"]["passed"]
    assert not goals["planner_p99"]["passed"]
    assert not goals["speed"]["passed"]
    assert goals["speed"]["value"] == pytest.approx(0.9)
    assert goals["speed"]["value"] < PATH_GOAL_SPEED_SHARE


def test_a_quick_run_is_judged_on_limits_and_end_only() -> None:
    assert set(goals_path(dict(FIGURES, segments=200))) == {"limit_violations", "end"}
