"""Smoke tests of ``openmotion bench``: tiny sizes, structure and correctness, never timings."""

from __future__ import annotations

import json
import math

import pytest

from openmotion.bench import axes, ca, otg
from openmotion.bench.peers import StreamCommand
from openmotion.bench.runner import BENCHMARKS, render, run_benchmark
from openmotion.transport import GapControlMode

MACHINE_KEYS = {"cpu_count", "python", "platform", "numpy", "ruckig", "pyplcopen"}


@pytest.fixture(scope="module")
def results() -> dict[str, dict]:
    """Each benchmark once (quick), shared by the tests below."""
    seen: list[str] = []
    out = {name: run_benchmark(name, quick=True, progress=seen.append) for name in BENCHMARKS
           if name != "startup"}  # processes of its own: tests/bench/test_startup_bench.py
    assert seen, "progress was never called"
    return out


@pytest.mark.parametrize("name", ["axes", "otg", "fbcall", "ca"])
def test_result_shape_is_json_and_renders(results: dict[str, dict], name: str) -> None:
    result = results[name]
    assert result["benchmark"] == name
    assert set(result["machine"]) == MACHINE_KEYS
    assert isinstance(result["passed"], bool)
    assert result["goals"] and all({"goal", "value", "passed"} <= set(g)
                                   for g in result["goals"].values())
    json.loads(json.dumps(result, allow_nan=False))  # strict JSON: no NaN or inf
    text = render(result)
    assert f"bench {name}" in text and "passed:" in text


def test_reports_carry_no_notes_to_ourselves(results: dict[str, dict]) -> None:
    """Issue 18: user-facing output names nothing outside the repo and no internal plans."""
    for result in results.values():
        text = render(result).lower()
        for phrase in ("not yet", "issue", "todo", "performance.md", "shared/"):
            assert phrase not in text, (result["benchmark"], phrase)


def test_the_cli_names_every_benchmark_the_runner_has() -> None:
    """The CLI lists the names without importing the runner; both lists must agree."""
    from openmotion.bench import BENCHMARK_NAMES

    assert tuple(BENCHMARKS) == BENCHMARK_NAMES


def test_unknown_benchmark_names_the_choices() -> None:
    with pytest.raises(KeyError, match="axes.*ca.*fbcall.*otg"):
        run_benchmark("nope", quick=True)


def test_axes_keyed_by_n_without_violations(results: dict[str, dict]) -> None:
    by_n = results["axes"]["results"]["by_n"]
    assert list(by_n) == ["1", "10", "100"]
    for n, row in by_n.items():
        assert row["axes"] == int(n)
        assert row["violations"] == 0, row["check"]["first_violations"]
        assert row["check"]["rejected"] == 0, row["check"]["rejections"]
        for key in ("ours_us", "ours_trace_us", "ruckig_us"):
            assert row[key] > 0.0
        assert row["pyplcopen_us"] is None or row["pyplcopen_us"] > 0.0
    assert results["axes"]["goals"]["violations"]["passed"] is True


def test_axes_cycles_stay_in_bounds() -> None:
    assert axes.cycles_for(1) >= 2000
    assert axes.cycles_for(10_000) >= 200
    assert axes.cycles_for(10_000) * 10_000 <= axes.WORK


def test_forced_speed_is_the_overshoot_of_a_full_jerk_ramp() -> None:
    assert axes.forced_speed(100.0, 0.0, 1e4) == 100.0
    assert axes.forced_speed(100.0, 1000.0, 1e4) == pytest.approx(150.0)
    assert axes.forced_speed(100.0, -1000.0, 1e4) == 100.0  # slows down first
    assert axes.forced_speed(10.0, -1000.0, 1e4) == pytest.approx(40.0)  # through zero


def test_command_limits_follow_d020() -> None:
    c = StreamCommand(cycle=0, axis=0, kind="absolute", value=0.0, velocity=100.0,
                      acceleration=1000.0, deceleration=2000.0, jerk=5000.0)
    assert axes.command_limits(c, 0.0, 0.0) == (100.0, 2000.0, 5000.0)
    # 450 mm/s, +1000 mm/s^2: jerk 5000 would reach 550 mm/s > max_velocity 500, so the
    # smallest jerk that keeps 500 is allowed: 1000^2 / (2 * 50) = 10000.
    assert axes.command_limits(c, 450.0, 1000.0) == pytest.approx((500.0, 2000.0, 10000.01))
    # +3000 mm/s^2 needs 90000 > max_jerk 50000: max_jerk, and 450 + 3000^2/1e5 is forced.
    assert axes.command_limits(c, 450.0, 3000.0) == pytest.approx((540.0, 3000.0, 50000.0))


def test_otg_reaches_in_time_within_limits(results: dict[str, dict]) -> None:
    r = results["otg"]["results"]
    assert r["samples"] > 0
    assert r["reached"] == r["samples"], r["failures"]
    assert r["time_ok"] == r["time_judged"] > 0, r["failures"]
    assert r["violations"] == 0, r["failures"]
    assert r["command_errors"] == 0
    assert results["otg"]["passed"] is True


def test_otg_samples_are_deterministic_and_produce_moving_starts() -> None:
    first = otg.draw_samples(20, seed=3)
    assert first == otg.draw_samples(20, seed=3)
    runs = [otg.run_sample(s) for s in first]
    assert any(r["start"]["velocity"] != 0.0 for r in runs)
    assert any(r["start"]["acceleration"] != 0.0 for r in runs)
    for r in runs:
        assert r["reached"], r
        assert r["bound_cycles"] is None or math.isfinite(r["ruckig_duration"])


def test_fbcall_measures_a_busy_block(results: dict[str, dict]) -> None:
    r = results["fbcall"]["results"]
    assert r["still_busy"] and r["step_axis_moving"]
    assert r["fb_call_us"] > 0.0 and r["step_1_axis_us"] > 0.0


def test_ca_keeps_every_gap_and_limit(results: dict[str, dict]) -> None:
    ca = results["ca"]["results"]
    assert set(ca["by_n"]) == set(ca["by_n_250us"]) == {"10", "50"}
    assert ca["modes"] == ["standard", "fast", "mixed"]
    for by_mode in [*ca["by_n"].values(), *ca["by_n_250us"].values()]:
        for mode in ca["modes"]:
            row = by_mode[mode]
            assert row["commands"] >= row["movers"]  # every mover was commanded at least once
            assert row["gap_violations"] == 0 and row["min_gap"] >= 100.0 - 1e-9
            assert row["limit_violations"] == 0
            assert 0.0 < row["cycle_us_p50"] <= row["cycle_us_p99"]
            assert 0.0 <= row["cpu_us_p50"] <= row["cpu_us_p99"]
    assert results["ca"]["goals"]["gap_violations"]["passed"] is True


def test_ca_measures_fast_and_mixed_beside_standard(results: dict[str, dict]) -> None:
    """Issue 19, point 9: Fast and mixed gap control (TF5410 §8.1.2) in the same run as
    Standard, with the ratios of their cycle times to Standard's and Fast's own goal."""
    ca = results["ca"]["results"]["by_n"]["50"]
    for mode in ("fast", "mixed"):
        ratio = ca[f"{mode}_over_standard"]
        for key in ("p50", "p99"):
            assert ratio[key] == ca[mode][f"cycle_us_{key}"] / ca["standard"][f"cycle_us_{key}"]
    goal = results["ca"]["goals"]["cycle_p99_fast_small"]
    assert goal["value"] == ca["fast"]["cycle_us_p99"] and "N=50, fast" in goal["goal"]
    text = render(results["ca"])
    assert "fast" in text and "mixed" in text and "p99 / std" in text


def test_ca_runs_at_250_us_beside_the_ruckig_loop(results: dict[str, dict]) -> None:
    """Issue 24, point 2: the XTS cycle, and a plain ruckig loop over the same movers (no
    collision avoidance) in the same run as the reference of the cycle times."""
    ca = results["ca"]["results"]
    assert ca["cycle_times"] == {"1ms": 0.001, "250us": 0.00025}
    for table in (ca["by_n"], ca["by_n_250us"]):
        for n, by_mode in table.items():
            reference = by_mode["ruckig"]
            assert reference["movers"] == int(n) and reference["commands"] >= int(n)
            assert 0.0 < reference["cycle_us_p50"] <= reference["cycle_us_p99"]
            for mode in ca["modes"]:
                ratio = by_mode[f"{mode}_over_ruckig"]
                for key in ("p50", "p99"):
                    assert ratio[key] == (by_mode[mode][f"cycle_us_{key}"]
                                          / reference[f"cycle_us_{key}"])
    goal = results["ca"]["goals"]["cycle_p50_250us_small_standard"]
    assert goal["value"] == ca["by_n_250us"]["10"]["standard"]["cycle_us_p50"]
    assert "N=10, 250 us" in goal["goal"]
    text = render(results["ca"])
    assert "250 us cycle" in text and "p50 / ruckig" in text


def test_ca_judges_the_250_us_goals_against_the_reference() -> None:
    """The N=1000 goals are ratios to the ruckig loop of the same run."""
    from openmotion.bench.runner import goals_ca

    def row(p50: float, p99: float) -> dict[str, float | int]:
        return {"cycle_us_p50": p50, "cycle_us_p99": p99, "gap_violations": 0,
                "limit_violations": 0}

    by_mode: dict[str, object] = {"ruckig": row(300.0, 400.0)}
    for mode, (p50, p99) in {"standard": (150.0, 300.0), "fast": (240.0, 380.0),
                             "mixed": (180.0, 420.0)}.items():
        by_mode[mode] = row(p50, p99)
        by_mode[f"{mode}_over_ruckig"] = {"p50": p50 / 300.0, "p99": p99 / 400.0}
    goals = goals_ca({"by_n": {}, "by_n_250us": {"1000": by_mode},
                      "modes": ["standard", "fast", "mixed"]})
    assert goals["cycle_p50_250us_standard_over_ruckig"]["passed"] is True
    assert goals["cycle_p50_250us_fast_over_ruckig"]["passed"] is False  # 0.8 > 0.7
    assert goals["cycle_p99_250us_mixed_over_ruckig"]["passed"] is False  # 1.05 > 1.0
    assert goals["cycle_p99_250us_fast_over_ruckig"]["value"] == 380.0 / 400.0


def test_ca_modes_are_what_their_names_say() -> None:
    """Mixed: the mode is per command (§9.1.2.5), so every second mover runs Fast."""
    assert {ca.mode_of("standard", i) for i in range(4)} == {GapControlMode.STANDARD}
    assert {ca.mode_of("fast", i) for i in range(4)} == {GapControlMode.FAST}
    assert [ca.mode_of("mixed", i) for i in range(4)] == [
        GapControlMode.STANDARD, GapControlMode.FAST] * 2


def test_ca_fast_keeps_gaps_closer_than_standard() -> None:
    """Fast lets a successor follow at the gap at any speed where Standard's gaps grow with
    speed (§8.1.2): the modes really differ in the benchmark's runs."""
    run = ca.run_one(10, 400, seed=1)
    assert run["fast"]["min_gap"] < run["standard"]["min_gap"]
    assert run["fast"]["gap_violations"] == run["mixed"]["gap_violations"] == 0
