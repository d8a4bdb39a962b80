"""Smoke test of ``openmotion bench tracks``: tiny sizes, structure and safety, never timings."""

from __future__ import annotations

import numpy as np
import pytest

from openmotion.bench import tracks
from openmotion.bench.planar import near_pairs
from openmotion.bench.runner import BENCHMARKS, goals_tracks, render, run_benchmark


@pytest.fixture(scope="module")
def result() -> dict:
    seen: list[str] = []
    out = run_benchmark("tracks", quick=True, progress=seen.append)
    assert seen and all(line.startswith("tracks: ") for line in seen)
    return out


def test_tracks_is_a_benchmark() -> None:
    assert "tracks" in BENCHMARKS


def test_the_network_has_four_switches() -> None:
    import openmotion as om

    rt = om.Runtime(tracks.CYCLE_TIME)
    network = tracks.build_network(rt)
    switches = {v for t in network for v in t.network.switches(t) if v is not None}
    assert len(network) == 10 and len(switches) == 4


def test_movers_keep_apart_and_the_report_renders(result: dict) -> None:
    row = result["results"]["by_n"]["12"]
    assert row["movers"] == 12 and row["commands"] >= 12
    assert row["overlaps"] == 0 and row["gap_violations"] == 0
    assert row["closest_centres_mm"] >= tracks.GAP - 1e-6
    assert result["goals"]["overlaps"]["passed"] and result["goals"]["gaps"]["passed"]
    assert "cycle_p99" not in result["goals"]  # judged at 100 movers only
    assert "4 switches" in render(result)


def test_more_movers_run_on_more_ovals_apart() -> None:
    import openmotion as om

    assert [tracks.ovals_for(n) for n in (1, 100, 101, 1000)] == [1, 1, 2, 10]
    rt = om.Runtime(tracks.CYCLE_TIME)
    first, second = tracks.build_network(rt), tracks.build_network(rt, 1)
    assert len({t.name for t in first + second}) == 20  # names apart too
    low = first[0].get_position_at(0.0)
    high = second[0].get_position_at(0.0)
    assert (high.x, high.y) == (low.x, low.y + tracks.OVAL_PITCH)
    switches = {v for t in first + second for v in t.network.switches(t) if v is not None}
    assert len(switches) == 8  # four on each oval


def test_near_pairs_are_all_pairs_within_reach() -> None:
    rng = np.random.default_rng(1)
    xy = rng.uniform(0.0, 2000.0, (300, 2))
    first, second, distance = near_pairs(xy, 150.0)
    found = {tuple(sorted(p)) for p in zip(first.tolist(), second.tolist(), strict=True)}
    full = np.hypot(*(xy[:, None] - xy[None]).transpose(2, 0, 1))
    expected = {(i, j) for i, j in zip(*np.nonzero(np.triu(full < 150.0, 1)), strict=True)}
    assert found == {(int(i), int(j)) for i, j in expected}
    assert np.allclose(distance, np.hypot(*(xy[first] - xy[second]).T))


def test_the_goals_judge_1000_movers_and_the_growth() -> None:
    row = {"overlaps": 0, "gap_violations": 0, "switches": 4, "cycle_us_mean": 100.0,
           "cycle_us_p99": 400.0}
    large = dict(row, switches=40, cycle_us_mean=1200.0, cycle_us_p99=900.0)
    goals = goals_tracks({"by_n": {"100": row, "1000": large}})
    assert goals["cycle_p99_large"]["passed"] and goals["cycle_p99"]["passed"]
    assert not goals["cycle_linear"]["passed"]  # 12x the cost for 10x the movers
    assert goals["cycle_linear"]["value"] == pytest.approx(1.2)
