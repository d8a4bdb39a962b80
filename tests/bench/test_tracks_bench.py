"""Smoke test of ``openmotion bench tracks``: tiny sizes, structure and safety, never timings."""

from __future__ import annotations

import pytest

from openmotion.bench import tracks
from openmotion.bench.runner import BENCHMARKS, render, run_benchmark


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
