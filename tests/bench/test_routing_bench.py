"""``openmotion bench routing``: one MagBotSim layout instance runs, is checked and judged."""

from __future__ import annotations

import pytest

import openmotion as om
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


def test_the_bound_takes_the_shortest_way_round_a_hole() -> None:
    """A 3 x 3 stator square without its middle stator: from the middle of the left column
    to the middle of the right one the straight line crosses the hole; the shortest way for
    a 155 mm mover's centre bends round two corners of the hole grown by half a mover."""
    import math

    import shapely

    from openmotion.bench.routing import free_space, lower_bound, shortest_way
    from openmotion.planar import MC_PlanarMover, MoverVector, PlanarMoverParameters

    s = STATOR_SIZE
    surface = shapely.difference(shapely.box(0, 0, 3 * s, 3 * s), shapely.box(s, s, 2 * s, 2 * s))
    mover = MC_PlanarMover(om.Runtime(0.001), PlanarMoverParameters(
        initial_position=MoverVector(s / 2, 1.5 * s)))
    free = free_space(surface, mover)
    start, goal = (s / 2, 1.5 * s), (2.5 * s, 1.5 * s)
    corner = s - 77.5  # the hole's corner, grown by half the mover
    leg = math.hypot(corner - s / 2, 1.5 * s - corner)
    want = 2 * leg + (2 * s + 77.5) - corner
    assert shortest_way(free, start, goal) == pytest.approx(want, abs=1e-3)
    assert shortest_way(free, start, (s / 2, 2.5 * s)) == pytest.approx(s)  # in sight
    assert lower_bound(mover, goal, free) > lower_bound(mover, goal)  # the straight line's
    closed = shapely.union(shapely.box(0, 0, s, s), shapely.box(2 * s, 0, 3 * s, s))
    assert shortest_way(free_space(closed, mover), (s / 2, s / 2), (2.5 * s, s / 2)) == math.inf
