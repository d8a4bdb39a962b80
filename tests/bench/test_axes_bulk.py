"""``bench axes`` in both modes (issue 24): the bulk runs, ours and pyplcopen's, end where the
stepped runs end, and the goals judge both modes. Structure and correctness, never timings."""

from __future__ import annotations

import pytest

from openmotion.bench import axes, peers
from openmotion.bench.runner import goals_axes, machine, render


def test_our_bulk_run_ends_on_the_stepped_runs_setpoints_bit_for_bit() -> None:
    stream = peers.random_command_stream(4, 1500, seed=3, rate=6.0)
    seconds, final = axes.bulk_run(4, stream, 1500, trace=True)
    assert seconds > 0.0
    assert final.tobytes() == axes._final_positions(4, stream, 1500).tobytes()
    assert axes.bulk_run(4, stream, 1500)[1].tobytes() == final.tobytes()


def test_pyplcopen_bulk_ends_where_its_stepped_run_ends() -> None:
    pytest.importorskip("pyplcopen")
    stream = peers.random_command_stream(3, 400, seed=0, rate=20.0)
    stepped = peers._drive_pyplcopen(3, stream, 400)
    bulk = peers._drive_pyplcopen(3, stream, 400, bulk=True)
    assert stepped is not None and bulk is not None
    assert bulk.final_positions == stepped.final_positions
    assert peers.run_pyplcopen(3, stream, 400, bulk=True) > 0.0


def test_both_modes_are_reported_judged_and_rendered() -> None:
    results = axes.run_axes(counts=(1, 100), cycles=200, trace=True, repeats=1)
    assert results["step_one_axis"]["ours_us"] > 0.0
    for row in results["by_n"].values():
        assert row["bulk_equal"] is True
        assert row["ours_bulk_us"] > 0.0 and row["ours_bulk_trace_us"] > 0.0
        if row["pyplcopen_bulk_us"] is not None:
            assert row["ratio_bulk_pyplcopen"] == pytest.approx(
                row["ours_bulk_us"] / row["pyplcopen_bulk_us"])
    goals = goals_axes(results)
    assert goals["bulk_equal"]["passed"] is True
    assert set(goals["bulk_ratio_pyplcopen"]["value"]) == {"1", "100"}
    assert set(goals["stepped_ratio_pyplcopen"]["value"]) == {"100"}
    assert isinstance(goals["step_one_axis"]["passed"], bool)
    text = render({"benchmark": "axes", "results": results, "goals": goals, "passed": False,
                   "machine": machine()})
    assert "step() of 1 moving axis" in text and "bulk:" in text and "= stepped" in text
