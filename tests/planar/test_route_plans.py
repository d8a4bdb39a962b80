"""Planned routes reach the edges: ``RoutePlans`` notes every way a router planned, the trace's
layout keeps them with the obstacles, the planar plot draws them and the viewer's planar panel
shows the ways of movers still on them (docs/planar-routing.md "In plots and the viewer")."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely

import openmotion as om
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    MoverVector,
    PlanarMoverParameters,
    PlanarState,
)
from openmotion.planar.routing import Router
from openmotion.planar.routing.plans import RoutePlans
from openmotion.planar.stators import STATOR_SIZE
from openmotion.planar.system import PlanarSystem
from openmotion.trace import TraceRecorder
from openmotion.trace.planar import planar_figure
from openmotion.viewer.planar import PlanarLayer

STARTS = [(120.0, 120.0), (840.0, 120.0)]


def field() -> tuple[om.Runtime, MC_PlanarEnvironment, MC_PlanarGroup, list[MC_PlanarMover]]:
    """Two movers on 4 x 2 stators, in one group with the environment."""
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    for i in range(4):
        for j in range(2):
            environment.add_stator(STATOR_SIZE * i, STATOR_SIZE * j)
    environment.create_boundary()
    group = MC_PlanarGroup(rt)
    group.enable()
    movers = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(*start)),
                             name=name) for name, start in zip("ab", STARTS, strict=True)]
    for mover in movers:
        mover.enable()
    rt.run(0.002)
    for mover in movers:
        mover.add_to_group(group)
    environment.add_to_group(group)
    rt.run(0.002)
    assert all(m.state is PlanarState.ENABLED and m.group is group for m in movers)
    return rt, environment, group, movers


POST = shapely.box(550.0, 310.0, 650.0, 410.0)


def routed() -> tuple[om.Runtime, Router, RoutePlans, list[MC_PlanarMover]]:
    rt, environment, group, movers = field()
    router = Router(group, environment, obstacles=[POST], obstacle_names=["post"], pitch=240.0,
                    time_budget=0.0)
    plans = RoutePlans.of(rt)
    assert plans is not None
    plans.watch(router)
    return rt, router, plans, movers


def test_a_runtime_has_no_log_until_asked_and_then_one() -> None:
    rt = om.Runtime()
    assert RoutePlans.of(rt, create=False) is None
    plans = RoutePlans.of(rt)
    assert RoutePlans.of(rt) is plans and RoutePlans.of(rt, create=False) is plans
    assert RoutePlans.of(om.Runtime(), create=False) is None  # one per runtime


def test_every_plan_is_noted_once_with_its_time() -> None:
    rt, router, plans, (a, b) = routed()
    router.route({a: (840.0, 120.0, 0.0), b: (120.0, 120.0, 0.0)})
    plans.note()
    first = [(p["mover"], p["time"]) for p in plans.history]
    assert first == [("a", pytest.approx(0.004)), ("b", pytest.approx(0.004))]
    assert plans.history[0]["points"][0] == [120.0, 120.0]
    assert plans.history[0]["points"][-1] == [840.0, 120.0]
    rt.run_until(lambda: not router.busy, timeout=30.0)
    assert len(plans.history) == 2  # looked at every cycle, noted only when it changed
    router.route({a: (360.0, 360.0, 0.0)})
    rt.step()
    assert [p["mover"] for p in plans.history] == ["a", "b", "a"]
    assert plans.history[-1]["time"] == pytest.approx(rt.now)
    assert plans.history[-1]["points"][-1] == [360.0, 360.0]
    rt.run_until(lambda: not router.busy, timeout=30.0)
    assert plans.obstacles() == [{"name": "post", "rings": [
        [[650.0, 310.0], [650.0, 410.0], [550.0, 410.0], [550.0, 310.0], [650.0, 310.0]]]}]


def test_the_viewer_shows_the_ways_of_movers_still_on_them() -> None:
    rt, router, plans, (a, b) = routed()
    layer = PlanarLayer(PlanarSystem.of(rt))
    empty = layer.panel()
    assert empty["routes"] == [] and empty["obstacles"] == plans.obstacles()
    router.route({a: (840.0, 120.0, 0.0), b: (120.0, 120.0, 0.0)})
    rt.step()
    shown = layer.panel()
    assert [route["mover"] for route in shown["routes"]] == ["a", "b"]
    assert shown["routes"][0]["points"] == plans.history[0]["points"]
    json.dumps(shown)  # the frame is JSON
    rt.run_until(lambda: not router.busy, timeout=30.0)
    assert layer.panel()["routes"] == []  # both arrived


def test_a_runtime_without_a_router_shows_no_routes() -> None:
    rt, *_ = field()
    panel = PlanarLayer(PlanarSystem.of(rt)).panel()
    assert panel["routes"] == [] and panel["obstacles"] == []
    assert RoutePlans.of(rt, create=False) is None  # the viewer made no log


def test_the_trace_keeps_the_plans_and_the_plot_draws_them() -> None:
    rt, router, plans, movers = routed()
    recorder = TraceRecorder(rt, [f"{m.name}.{s}" for m in movers for s in "xyc"],
                             objects=[*movers, plans])
    rt.add_observer(recorder)
    handles = router.route({movers[0]: (840.0, 120.0, 0.0), movers[1]: (120.0, 120.0, 0.0),
                            })
    rt.run_until(lambda: not router.busy, timeout=30.0)
    assert all(handle.done for handle in handles.values())
    trace = recorder.trace
    layout = trace.layout["planar"]
    assert layout["planned_routes"] == plans.history
    assert layout["obstacles"] == plans.obstacles()
    assert trace.layout["objects"]["route plans"] == "route_plans"
    figure = planar_figure(trace)
    panel = figure.axes[0]
    routes = {line.get_gid(): line for line in panel.get_lines()
              if str(line.get_gid()).startswith("route:")}
    assert set(routes) == {"route:a:0", "route:b:1"}
    drawn = np.column_stack(routes["route:a:0"].get_data())
    assert drawn.tolist() == plans.history[0]["points"]
    assert routes["route:a:0"].get_linestyle() == "--"
    assert routes["route:a:0"].get_color() == next(
        line.get_color() for line in panel.get_lines() if line.get_gid() == "a")
    obstacles = [p for p in panel.patches if p.get_gid() == "obstacle:post"]
    assert len(obstacles) == 1
    labels = [text.get_text() for legend in figure.legends for text in legend.get_texts()]
    assert "planned route" in labels and "obstacle" in labels
