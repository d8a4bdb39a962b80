"""The planar router: movers reach their targets through TF5430 commands the group admits;
unreachable or occupied targets end with PLANAR_COLLISION naming the blocker."""

from __future__ import annotations

import math
import random

import pytest
import shapely
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
)
from openmotion.planar.layouts import MAGBOTSIM_LAYOUTS, magbotsim_layout
from openmotion.planar.routing import Router
from openmotion.planar.routing.grid import build_grid
from openmotion.planar.routing.planner import distances
from openmotion.planar.stators import STATOR_SIZE
from openmotion.testing import grouped_field

OVERLAP = 1e-6  #: [mm²] footprints may share rounding only


field = grouped_field  #: nx x ny stators, movers at starts, all in one group


def run_checked(rt: om.Runtime, router: Router, environment: MC_PlanarEnvironment,
                movers: list[MC_PlanarMover], timeout: float = 30.0) -> dict[str, int]:
    """Run until the router is idle; count overlaps and footprints off the surface."""
    surface = shapely.buffer(environment.surface, 1e-6, join_style="mitre")
    counts = {"overlaps": 0, "off": 0}
    end = rt.now + timeout
    while router.busy and rt.now < end:
        rt.step()
        prints = [m.footprint() for m in movers]
        counts["off"] += int((~shapely.covers(surface, prints)).sum())
        for a in range(len(prints)):
            for b in range(a + 1, len(prints)):
                if shapely.area(shapely.intersection(prints[a], prints[b])) > OVERLAP:
                    counts["overlaps"] += 1
    assert not router.busy, "the routes did not end in time"
    return counts


def centre(i: int, j: int) -> tuple[float, float]:
    return STATOR_SIZE * (i + 0.5), STATOR_SIZE * (j + 0.5)


def test_two_movers_swap_places_through_admitted_commands() -> None:
    a, b = centre(0, 1), centre(3, 1)
    rt, environment, group, movers = field(4, 3, [a, b])
    router = Router(group)
    handles = router.route({movers[0]: (*b, 0.0), movers[1]: (*a, 0.0)})
    assert all(h.busy and not h.done for h in handles.values())
    counts = run_checked(rt, router, environment, movers)
    assert counts == {"overlaps": 0, "off": 0}
    assert all(h.done and not h.error for h in handles.values())
    assert router.stats.rejected == 0 and router.stats.legs >= 2
    assert movers[0].pose.x == pytest.approx(b[0]) and movers[1].pose.y == pytest.approx(a[1])
    assert set(router.routes) == {"m0", "m1"} and router.routes["m0"][0] == pytest.approx(a)


def test_a_follower_on_the_line_starts_short_and_is_extended_without_a_stop() -> None:
    """D-373: the group refuses the follower's whole run while the leader's reservation
    covers it; a shorter leg starts once the first cell clears and is lengthened in motion."""
    rt, environment, group, movers = field(6, 1, [centre(1, 0), centre(0, 0)])
    leader, follower = movers
    router = Router(group, time_budget=0.0, pitch=STATOR_SIZE)
    handles = router.route({leader: (*centre(5, 0), 0.0), follower: (*centre(4, 0), 0.0)})
    started_at, stops = None, 0
    while router.busy and rt.now < 5.0:
        was_moving = follower.in_motion
        rt.step()
        if follower.in_motion and started_at is None:
            started_at = leader.pose.x
        if was_moving and not follower.in_motion and follower.pose.x < centre(4, 0)[0] - 1e-3:
            stops += 1
    assert all(h.done for h in handles.values())
    assert started_at is not None and started_at < centre(3, 0)[0]  # the leader far from done
    assert stops == 0 and router.stats.rejected == 0
    assert router.stats.shortened >= 1 and router.stats.extended >= 1


def test_a_target_with_c_turns_the_mover_there() -> None:
    rt, environment, group, movers = field(3, 3, [centre(0, 0)])
    router = Router(group)
    handle = router.route({movers[0]: (*centre(2, 2), 90.0)})[movers[0]]
    run_checked(rt, router, environment, movers)
    assert handle.done
    assert movers[0].pose.c == pytest.approx(90.0)
    assert movers[0].pose.x == pytest.approx(centre(2, 2)[0])


def test_a_target_off_the_surface_is_refused_and_the_others_still_go() -> None:
    rt, environment, group, movers = field(4, 3, [centre(0, 0), centre(3, 2)])
    router = Router(group)
    handles = router.route({movers[0]: (2000.0, 120.0, 0.0), movers[1]: (*centre(0, 2), 0.0)})
    bad, good = handles[movers[0]], handles[movers[1]]
    assert bad.error and bad.error_id is ErrorId.PLANAR_COLLISION
    assert "leaves the stator surface" in bad.message and bad.blocker == "the stator surface"
    run_checked(rt, router, environment, movers)
    assert good.done and movers[0].pose.x == pytest.approx(centre(0, 0)[0])
    again = router.route({movers[0]: (*centre(3, 0), 0.0)})[movers[0]]  # still usable
    run_checked(rt, router, environment, movers)
    assert again.done


def test_a_target_on_a_mover_that_is_not_routed_names_that_mover() -> None:
    rt, environment, group, movers = field(4, 3, [centre(0, 0), centre(2, 1)])
    router = Router(group)
    handle = router.route({movers[0]: (*centre(2, 1), 0.0)})[movers[0]]
    assert handle.error and handle.error_id is ErrorId.PLANAR_COLLISION
    assert "m1" in handle.message and "16#05110020" in handle.blocker
    assert not router.busy


def test_an_obstacle_on_the_target_and_a_wall_that_cuts_it_off_are_named() -> None:
    rt, environment, group, movers = field(5, 3, [centre(0, 1)])
    wall = shapely.box(2 * STATOR_SIZE + 40, 0.0, 2 * STATOR_SIZE + 200, 3 * STATOR_SIZE)
    router = Router(group, obstacles=[wall], obstacle_names=["the fence"])
    handle = router.route({movers[0]: (*centre(2, 1), 0.0)})[movers[0]]
    assert handle.error and "occupied by the fence" in handle.message
    handle = router.route({movers[0]: (*centre(4, 1), 0.0)})[movers[0]]
    assert handle.error and "cannot be reached" in handle.message
    assert handle.blocker == "the fence"
    handle = router.route({movers[0]: (*centre(1, 2), 0.0)})[movers[0]]  # this side: fine
    run_checked(rt, router, environment, movers)
    assert handle.done


def test_movers_go_around_a_hole_in_the_field() -> None:
    holes = {(1, 1), (2, 1)}
    rt, environment, group, movers = field(4, 3, [centre(0, 1), centre(3, 1)], holes)
    router = Router(group, pitch=STATOR_SIZE)
    handles = router.route({movers[0]: (*centre(3, 1), 0.0), movers[1]: (*centre(0, 1), 0.0)})
    counts = run_checked(rt, router, environment, movers)
    assert counts == {"overlaps": 0, "off": 0}
    assert all(h.done for h in handles.values()) and router.stats.rejected == 0


def test_a_halted_mover_ends_its_route_as_command_aborted() -> None:
    rt, environment, group, movers = field(5, 2, [centre(0, 0)])
    router = Router(group)
    handle = router.route({movers[0]: (*centre(4, 1), 0.0)})[movers[0]]
    rt.run_until(lambda: movers[0].in_motion, timeout=1.0)
    movers[0].halt()
    rt.run_until(lambda: not handle.busy, timeout=2.0)
    assert handle.command_aborted and not handle.error
    moving = router.route({movers[0]: (*centre(0, 1), 0.0)})[movers[0]]
    if movers[0].in_motion:  # still braking: a route starts from standstill
        assert moving.error and "standstill" in moving.message
    rt.run_until(lambda: not movers[0].in_motion, timeout=2.0)
    again = router.route({movers[0]: (*centre(0, 1), 0.0)})[movers[0]]
    run_checked(rt, router, environment, movers)
    assert again.done


def test_a_router_needs_an_environment_and_a_sane_pitch() -> None:
    rt = om.Runtime()
    group = MC_PlanarGroup(rt)
    with pytest.raises(ConfigError, match="MC_PlanarEnvironment"):
        Router(group)
    surface = shapely.box(0, 0, 960, 720)
    with pytest.raises(ConfigError, match="pitch"):
        build_grid(surface, 155.0, pitch=100.0)
    assert build_grid(surface, 155.0, pitch=240.0).nx == 4


def test_magbotsim_layouts_have_their_shapes_and_mover_counts() -> None:
    assert [layout.movers for layout in MAGBOTSIM_LAYOUTS] == [3, 3, 4, 4, 4, 3, 4, 4, 5, 5]
    assert [layout.shape for layout in MAGBOTSIM_LAYOUTS] == [
        (4, 3), (4, 3), (8, 5), (7, 7), (8, 6), (11, 6), (8, 6), (7, 7), (8, 6), (8, 8)]
    assert len(magbotsim_layout("B0").stators()) == 12
    assert len(magbotsim_layout("B1").stators()) == 11


@st.composite
def routing_problems(draw: st.DrawFn) -> tuple[int, int, list, list, list]:
    """A rectangular field, up to two obstacles on stators, movers with distinct starts and
    distinct targets on free cells of the router's default grid."""
    n = draw(st.integers(2, 30))
    side = max(3, math.ceil(math.sqrt(n * 2.5)))
    nx = draw(st.integers(side, side + 1))
    ny = side
    surface = shapely.box(0, 0, nx * STATOR_SIZE, ny * STATOR_SIZE)
    blocks = draw(st.lists(st.tuples(st.integers(0, nx - 1), st.integers(0, ny - 1)),
                           max_size=2, unique=True))
    obstacles = [shapely.box(STATOR_SIZE * i + 60, STATOR_SIZE * j + 60,
                             STATOR_SIZE * i + 180, STATOR_SIZE * j + 180) for i, j in blocks]
    grid = build_grid(surface, 155.0, obstacles)
    # starts and targets on every other cell in x and y, so that each has free cells
    # around it: prioritized planning is incomplete in dense clusters (docs/planar-routing.md)
    spaced = [c for c in range(grid.size)
              if grid.free[c] and (c % grid.nx) % 2 == 0 and (c // grid.nx) % 2 == 0]
    reachable = max((distances(grid, c) for c in spaced), key=len)  # the largest region
    cells = [c for c in spaced if c in reachable]
    n = min(n, len(cells))
    rng = random.Random(draw(st.integers(0, 2**32 - 1)))
    starts = rng.sample(cells, n)
    targets = rng.sample(cells, n)
    return nx, ny, obstacles, [grid.centre(c) for c in starts], [grid.centre(c) for c in targets]


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow],
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(routing_problems())
def test_every_mover_arrives_without_overlap_or_rejection(problem) -> None:  # noqa: ANN001
    nx, ny, obstacles, starts, targets = problem
    rt, environment, group, movers = field(nx, ny, starts)
    router = Router(group, obstacles=obstacles, time_budget=0.0)
    handles = router.route({m: (*t, 0.0) for m, t in zip(movers, targets, strict=True)})
    counts = run_checked(rt, router, environment, movers, timeout=60.0)
    assert counts == {"overlaps": 0, "off": 0}
    assert router.stats.rejected == 0
    failed = [h.message for h in handles.values() if not h.done]
    assert not failed
    for mover, target in zip(movers, targets, strict=True):
        assert mover.pose.x == pytest.approx(target[0]) and mover.pose.y == pytest.approx(
            target[1])


@settings(max_examples=5, deadline=None)
@given(st.integers(0, 2), st.integers(3, 5))
def test_a_target_behind_a_closed_wall_gives_the_documented_error(row: int, nx: int) -> None:
    rt, environment, group, movers = field(nx, 3, [centre(0, 0), centre(0, 2)])
    wall = shapely.box(STATOR_SIZE * 1 + 40, 0.0, STATOR_SIZE * 1 + 200, 3 * STATOR_SIZE)
    router = Router(group, obstacles=[wall], obstacle_names=["wall"], pitch=STATOR_SIZE)
    handles = router.route({movers[0]: (*centre(nx - 1, row), 0.0),
                            movers[1]: (*centre(0, 1), 0.0)})
    bad = handles[movers[0]]
    assert bad.error and bad.error_id is ErrorId.PLANAR_COLLISION
    assert bad.blocker == "wall" and "cannot be reached" in bad.message
    run_checked(rt, router, environment, movers)
    assert handles[movers[1]].done
