"""``openmotion bench envs``: its figures, its peer column without MagBotSim, its extra."""

from __future__ import annotations

import json
import sys

import pytest

from openmotion.bench import envs
from openmotion.bench.runner import goals_envs, render, run_benchmark


def test_without_the_peer_the_benchmark_runs_and_says_why() -> None:
    results = envs.run_envs(counts=(3,), seconds=0.01, peer=False)
    row = results["by_n"]["3"]
    assert row["magbotsim"] is None and row["ours"]["steps"] >= envs.MIN_STEPS
    assert row["ours"]["commanded"] > 0  # a random policy sends moves the group decides
    assert results["magbotsim"] == {"version": None, "unavailable": "not asked for (peer=False)"}
    goals = goals_envs(results)
    assert goals["measured"]["passed"] is True and goals["magbotsim"]["passed"] is None
    json.loads(json.dumps(results, allow_nan=False))


def test_a_missing_peer_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco now fails
    version, why = envs.magbotsim_version()
    assert version is None and "openmotion[envs-peer]" in why


def test_a_missing_environments_extra_is_an_import_error_naming_it(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pettingzoo", None)
    with pytest.raises(ImportError, match=r"pip install 'openmotion\[envs\]'"):
        envs.run_envs(counts=(3,), seconds=0.01)
    monkeypatch.undo()
    assert envs.run_envs(counts=(2,), seconds=0.01, peer=False)["by_n"]["2"]["ours"]["steps"]


def test_the_quick_run_renders_both_sides_when_magbotsim_is_there() -> None:
    pytest.importorskip("magbotsim")
    result = run_benchmark("envs", quick=True)
    text = render(result)
    assert "MagBotSim steps/s" in text and "published mj_step" in text
    for row in result["results"]["by_n"].values():
        assert row["magbotsim"]["mj_step_ms"] > 0 and row["ratio_steps_per_s"] > 0
