"""``openmotion bench routing``: one MagBotSim layout instance runs, is checked and judged."""

from __future__ import annotations

from openmotion.bench.routing import magbotsim_instances, run_instance
from openmotion.bench.runner import goals_routing
from openmotion.planar.stators import STATOR_SIZE


def test_a_magbotsim_instance_arrives_without_refusal_or_overlap() -> None:
    layout, starts, targets = magbotsim_instances(1)[0]
    row = run_instance(layout, starts, targets, pitch=STATOR_SIZE, time_budget=0.0)
    assert row["layout"] == "B0" and row["movers"] == 3
    assert row["success"] and row["arrived"] == 3
    assert row["rejected"] == 0 and row["overlaps"] == 0 and row["off_surface"] == 0
    assert row["ratio"] >= 1.0 and row["first_plan_ms"] is not None
    summary = {"magbotsim": {"instances": 1, "success_rate": 1.0, "first_plan_ms_max": 1.0,
                             "plan_ms_max": 1.0, "ratio_max": row["ratio"],
                             "ratio_mean": row["ratio"], "rejected": 0, "overlaps": 0,
                             "off_surface": 0}, "big": {}}
    goals = goals_routing({"summary": summary})
    assert goals["success"]["passed"] and goals["rejected"]["passed"]
    assert goals["ratio_layouts"]["passed"] is (row["ratio"] <= 1.3)
