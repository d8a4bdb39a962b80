"""Smoke test of ``openmotion bench trace``: tiny sizes, structure and the goal's shape, never
timings."""

from __future__ import annotations

import json

import pytest

from openmotion.bench import runner, trace
from openmotion.bench.runner import BENCHMARKS, render, run_benchmark


@pytest.fixture(scope="module")
def result() -> dict:
    seen: list[str] = []
    out = run_benchmark("trace", quick=True, progress=seen.append)
    assert seen and all(line.startswith("trace: ") for line in seen)
    return out


def test_trace_is_a_benchmark() -> None:
    assert "trace" in BENCHMARKS


def test_the_goal_records_100_signals_of_60_axes() -> None:
    names = [f"a{i}" for i in range(100)]
    signals = trace.goal_signals(names)
    assert len(signals) == trace.GOAL_SIGNALS == len(set(signals))
    assert {name.split(".")[0] for name in signals} == set(names[:60])


def test_result_shape_is_json_and_renders(result: dict) -> None:
    figures = result["results"]
    assert [(r["kind"], r["signals"]) for r in figures["sampling"]] == [
        ("kernel", 10), ("kernel", 100), ("axis state", 100), ("planar", 30)]
    for row in figures["sampling"]:
        assert row["sample_us"] > 0.0
        assert row["signal_sample_us"] == pytest.approx(row["sample_us"] / row["signals"])
    goal = figures["goal"]
    assert set(goal["cycle_us"]) == {"off", "every_cycle", "every_10"}
    assert goal["signal_sample_us"] > 0.0 and isinstance(goal["faster_than_real_time"], bool)
    assert set(result["goals"]) == {"real_time", "memory_bounded", "memory_streaming"}
    json.loads(json.dumps(result, allow_nan=False))
    text = render(result)
    assert "bench trace" in text and "per signal-sample" in text and "passed:" in text
    assert "memory of a long run" in text


def test_memory_part_holds_keep_rows_and_one_chunk_while_unbounded_grows(result: dict) -> None:
    """Issue 19 point 10 (D-188): the bounded and streaming runs end with the rows they are
    allowed (counted in allocated rows, not time); the unbounded one with all of them."""
    memory = {row["mode"]: row for row in result["results"]["memory"]}
    assert list(memory) == ["bounded", "streaming", "unbounded"]
    samples = runner.QUICK_MEMORY_CYCLES
    bounded, streaming, unbounded = memory["bounded"], memory["streaming"], memory["unbounded"]
    assert bounded["samples"] == streaming["samples"] == unbounded["samples"] == samples
    assert bounded["allocated_rows"] == bounded["keep"] == samples // 10
    assert streaming["allocated_rows"] == streaming["chunk"] == samples // 10
    assert unbounded["allocated_rows"] >= samples and bounded["disk_mb"] == 0.0
    assert streaming["disk_mb"] * trace.MIB >= samples * (trace.MEMORY_SIGNALS + 1) * 8
    assert len(bounded["checkpoints"]) == trace.CHECKPOINTS
    assert [point["samples"] for point in bounded["checkpoints"]][-1] == samples


def test_cycles_is_for_the_long_runs_only() -> None:
    """A cycle count the benchmark would ignore is an error, not a silent default."""
    with pytest.raises(ValueError, match="cycles: only for trace, not 'otg'"):
        run_benchmark("otg", quick=True, cycles=10)
    short = trace.run_memory(cycles=200)
    assert [row["samples"] for row in short] == [200, 200, 200]
    assert all(row["checkpoints"][-1]["allocated_rows"] <= 20 for row in short[:2])


def test_wide_traces_take_fewer_samples() -> None:
    assert trace.samples_for(10, 20_000) == 20_000
    assert trace.samples_for(1000, 20_000) == trace.SAMPLE_VALUES // 1000
    assert trace.samples_for(10**7, 20_000) == 100
