"""Smoke tests of ``openmotion bench planar``: tiny sizes, structure and safety, never timings."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

import openmotion as om
from openmotion.bench import planar
from openmotion.bench.runner import BENCHMARKS, goals_planar, render, run_benchmark
from openmotion.cli import app
from openmotion.planar import MC_PlanarMover, MoverVector, PlanarMoverParameters

MACHINE_KEYS = {"cpu_count", "python", "platform", "numpy", "ruckig", "pyplcopen"}


@pytest.fixture(scope="module")
def result() -> dict:
    seen: list[str] = []
    out = planar.run_planar(counts=(3, 8), cycles=300, commands=40, progress=seen.append)
    assert seen and all(line.startswith("planar: ") for line in seen)
    return out


def test_planar_is_a_benchmark() -> None:
    assert "planar" in BENCHMARKS


def test_the_field_has_room_for_the_movers() -> None:
    assert planar.side_for(100) == 12
    assert planar.side_for(10) == 4
    assert all(planar.side_for(n) ** 2 >= n for n in (1, 2, 3, 10, 50, 100, 1000))


def test_rows_count_commands_and_keep_movers_apart(result: dict) -> None:
    for runs in (result["by_n"], result["translation"]):
        assert set(runs) == {"3", "8"}
        for n, row in runs.items():
            assert row["movers"] == int(n)
            assert row["commands"] > 0
            assert row["accepted"] + row["rejected"] == row["commands"]
            assert row["done"] <= row["accepted"]
            assert row["overlaps"] == 0 and row["off_surface"] == 0
            assert 0.0 < row["cycle_us_p50"] <= row["cycle_us_p99"] <= row["cycle_us_max"]
    for row in result["by_n"].values():
        admission = row["admission"]
        assert admission["commands"] == 40 and admission["mismatches"] == 0
        assert admission["admission_us_p50"] > 0.0


def test_build_puts_enabled_movers_on_distinct_stators_in_one_group() -> None:
    fleet = planar.build(5, seed=2)
    assert len(set(fleet.cells)) == 5 and fleet.side == 3
    assert {m.state.name for m in fleet.movers} == {"ENABLED"}
    assert len(fleet.group.members) == 6  # five movers and the environment
    for mover, cell in zip(fleet.movers, fleet.cells, strict=True):
        assert (mover.position.x, mover.position.y) == planar._centre(cell, fleet.side)


def test_the_safety_check_sees_overlaps_and_footprints_off_the_surface() -> None:
    rt = om.Runtime()
    movers = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x, y)))
              for x, y in ((120.0, 120.0), (200.0, 150.0), (450.0, 120.0), (600.0, 600.0))]
    fleet = planar.Fleet(rt, None, None, movers, side=2, cells=[])  # type: ignore[arg-type]
    safety = {"overlaps": 0, "off_surface": 0, "closest": float("inf")}
    planar._check(fleet, [m.position for m in movers], safety)
    # the first two overlap; the last two reach beyond the 480 mm field
    assert safety["overlaps"] == 1 and safety["off_surface"] == 2
    assert safety["closest"] < 0.0


def test_run_benchmark_quick_is_json_and_renders() -> None:
    out = run_benchmark("planar", quick=True)
    assert out["benchmark"] == "planar" and set(out["machine"]) == MACHINE_KEYS
    json.loads(json.dumps(out, allow_nan=False))  # strict JSON: no NaN or inf
    assert out["goals"]["overlaps"]["passed"] is True
    assert out["goals"]["off_surface"]["passed"] is True
    assert "cycle_p99" not in out["goals"]  # judged at 100 movers only
    text = render(out)
    assert "bench planar" in text and "admission p50" in text and "passed:" in text


def test_cli_runs_the_planar_benchmark(monkeypatch: pytest.MonkeyPatch) -> None:
    from openmotion.bench import runner

    def tiny(quick: bool, progress: object) -> dict:
        return planar.run_planar(counts=(2,), cycles=50, commands=10)

    monkeypatch.setitem(runner.BENCHMARKS, "planar", tiny)
    result = CliRunner().invoke(app, ["bench", "planar", "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["benchmark"] == "planar" and list(data["results"]["by_n"]) == ["2"]


def test_the_goals_judge_1000_movers_and_the_growth() -> None:
    def row(cycle_mean: float, cycle_p99: float, admission_p50: float) -> dict:
        return {"overlaps": 0, "off_surface": 0, "cycle_us_mean": cycle_mean,
                "cycle_us_p99": cycle_p99,
                "admission": {"mismatches": 0, "overlaps": 0, "admission_us_p50": admission_p50}}

    results = {"by_n": {"100": row(40.0, 200.0, 30.0), "1000": row(300.0, 1100.0, 45.0)},
               "translation": {}}
    goals = goals_planar(results)
    assert goals["admission_us_large"]["passed"] and goals["admission_linear"]["passed"]
    assert goals["cycle_linear"]["passed"]  # 7.5x for 10x the movers
    assert goals["cycle_linear"]["value"] == pytest.approx(0.75)
    assert not goals["cycle_p99_large"]["passed"]  # 1.1 ms: over the 1 ms cycle
    del results["by_n"]["1000"]
    assert "cycle_p99_large" not in goals_planar(results)
