"""Re-routing: a new target mid-route, a halted or disabled mover and a part that moves
re-plan only the movers concerned; the others go on as planned (docs/planar-routing.md)."""

from __future__ import annotations

import random

import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.planar import (
    DynamicConstraint_PathXY,
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarPart,
    MoverVector,
    Part,
    PartLayout,
    PartPosition,
    PlanarMoverParameters,
    PlanarState,
    Pose,
)
from openmotion.planar.routing import RouteCommand, Router
from openmotion.planar.routing.grid import build_grid
from openmotion.planar.stators import STATOR_SIZE
from openmotion.testing import grouped_field

OVERLAP = 1e-6  #: [mm²] footprints may share rounding only
STATORS = STATOR_SIZE  #: the routing cells are the stators here [mm]
CS_1, PART_1, PART_2 = 0x01010060, 0x01010020, 0x01010030
SLOW = DynamicConstraint_PathXY(300.0, 3000.0, 3000.0, 30000.0)  #: [mm/s, mm/s², mm/s², mm/s³]


def centre(i: int, j: int) -> tuple[float, float]:
    return STATORS * (i + 0.5), STATORS * (j + 0.5)


field = grouped_field  #: nx x ny stators, movers at starts, all in one group


class Watch:
    """Steps the runtime until the router is idle; counts overlaps, footprints off the
    surface and cycles in which a mover stood still while its route was Busy."""

    def __init__(self, rt: om.Runtime, router: Router, environment: MC_PlanarEnvironment,
                 movers: list[MC_PlanarMover]) -> None:
        self.rt, self.router, self.environment, self.movers = rt, router, environment, movers
        self.overlaps = self.off = 0

    def step(self) -> None:
        self.rt.step()
        surface = shapely.buffer(self.environment.surface, 1e-6, join_style="mitre")
        prints = [m.footprint() for m in self.movers]
        self.off += int((~shapely.covers(surface, prints)).sum())
        for a in range(len(prints)):
            for b in range(a + 1, len(prints)):
                if shapely.area(shapely.intersection(prints[a], prints[b])) > OVERLAP:
                    self.overlaps += 1

    def run(self, seconds: float) -> None:
        end = self.rt.now + seconds
        while self.rt.now < end - 1e-9:
            self.step()

    def until_idle(self, timeout: float = 30.0) -> None:
        end = self.rt.now + timeout
        while self.router.busy and self.rt.now < end:
            self.step()
        assert not self.router.busy, "the routes did not end in time"
        assert (self.overlaps, self.off, self.router.stats.rejected) == (0, 0, 0)


def three_movers() -> tuple[om.Runtime, MC_PlanarEnvironment, list[MC_PlanarMover], Router,
                            dict[MC_PlanarMover, RouteCommand]]:
    """6 x 4 stators: m0 along row 1 to the right (one long leg), m1 from the top-left corner
    around an obstacle on the next stator (three legs: it stands at corners), m2 along the
    top row from the right; their ways do not meet."""
    rt, environment, group, movers = field(6, 4, [centre(0, 1), centre(0, 3), centre(5, 3)])
    wall = shapely.box(STATORS, 3 * STATORS, 2 * STATORS, 4 * STATORS)
    router = Router(group, pitch=STATORS, time_budget=0.0, obstacles=[wall],
                    obstacle_names=["wall"])
    handles = router.route({movers[0]: (*centre(5, 1), 0.0), movers[1]: (*centre(2, 3), 0.0),
                            movers[2]: (*centre(3, 3), 0.0)})
    return rt, environment, movers, router, handles


def test_a_new_target_mid_route_leaves_the_other_movers_untouched() -> None:
    rt, environment, movers, router, handles = three_movers()
    watch = Watch(rt, router, environment, movers)
    watch.until_idle()
    alone = {m.name: handles[m].ended_at for m in movers[1:]}

    rt, environment, movers, router, handles = three_movers()
    watch = Watch(rt, router, environment, movers)
    watch.run(0.1)
    assert movers[0].in_motion and movers[1].in_motion
    kept = {m: router.routes[m.name] for m in movers[1:]}
    new = router.route({movers[0]: (*centre(1, 0), 0.0)})[movers[0]]
    assert handles[movers[0]].command_aborted and "new route" in handles[movers[0]].message
    assert new.busy and handles[movers[1]].busy and handles[movers[2]].busy
    watch.until_idle()
    assert new.done and movers[0].pose[:2] == pytest.approx(centre(1, 0))
    # not slowed at all: m1 is not held at its corners while m0 ends its leg
    assert {m.name: handles[m].ended_at for m in movers[1:]} == alone
    assert all(handles[m].done and router.routes[m.name] == kept[m] for m in movers[1:])
    assert router.stats.replans == 1


def test_a_standing_mover_routed_while_others_run_is_planned_around_them() -> None:
    rt, environment, group, movers = field(6, 4, [centre(0, 1), centre(5, 3), centre(3, 2)])
    router = Router(group, pitch=STATORS, time_budget=0.0)
    handles = router.route({movers[0]: (*centre(5, 1), 0.0), movers[1]: (*centre(1, 3), 0.0)})
    watch = Watch(rt, router, environment, movers)
    watch.run(0.1)
    late = router.route({movers[2]: (*centre(0, 0), 0.0)})[movers[2]]
    assert late.busy and handles[movers[0]].busy and handles[movers[1]].busy
    watch.until_idle()
    assert late.done and movers[2].pose[:2] == pytest.approx(centre(0, 0))
    assert all(handles[m].done for m in movers[:2]) and router.stats.replans >= 1


def test_a_new_target_on_a_kept_route_re_plans_that_mover_too() -> None:
    rt, environment, group, movers = field(6, 4, [centre(0, 1), centre(0, 3)])
    router = Router(group, pitch=STATORS, constraint=SLOW, time_budget=0.0)
    handles = router.route({movers[0]: (*centre(2, 1), 0.0), movers[1]: (*centre(5, 3), 0.0)})
    watch = Watch(rt, router, environment, movers)
    watch.run(0.1)
    new = router.route({movers[0]: (*centre(4, 3), 0.0)})[movers[0]]  # on m1's way
    watch.until_idle()
    assert new.done and movers[0].pose[:2] == pytest.approx(centre(4, 3))
    assert handles[movers[1]].done and movers[1].pose[:2] == pytest.approx(centre(5, 3))
    assert router.stats.replans >= 1


@pytest.mark.parametrize("stop", ["halt", "disable"])
def test_a_stopped_mover_stays_and_the_routes_through_it_are_re_planned(stop: str) -> None:
    """m0 crosses m1's column first (the longer way goes first); it stops on the crossing,
    and m1, which was to pass there after it, goes around it."""
    rt, environment, group, movers = field(6, 4, [centre(0, 1), centre(2, 3)])
    router = Router(group, pitch=STATORS, constraint=SLOW, time_budget=0.0)
    handles = router.route({movers[0]: (*centre(5, 1), 0.0), movers[1]: (*centre(2, 0), 0.0)})
    watch = Watch(rt, router, environment, movers)
    while movers[0].pose.x < centre(2, 1)[0] - 60.0:
        watch.step()
    getattr(movers[0], stop)()
    while movers[0].in_motion:
        watch.step()
    stood = movers[0].pose
    watch.until_idle()
    assert handles[movers[0]].command_aborted and not handles[movers[0]].error
    assert movers[0].pose == stood
    assert handles[movers[1]].done and movers[1].pose[:2] == pytest.approx(centre(2, 0))
    assert router.stats.replans == 1
    if stop == "halt":  # still routable: a new route from where it stands
        again = router.route({movers[0]: (*centre(5, 2), 0.0)})[movers[0]]
        watch.until_idle()
        assert again.done
    else:
        assert movers[0].state is PlanarState.DISABLED


def parted() -> tuple[om.Runtime, MC_PlanarEnvironment, MC_PlanarGroup, list[MC_PlanarMover],
                      MC_PlanarPart]:
    """A static part (stators marked #) and a one-stator shuttle at x (position 1, in the
    bottom row's gap) that can move to s (position 2):

        y=3  # # # # # #
        y=2  # # # # # s
        y=1  # . . . # .
        y=0  # # x # # .
    """
    cells = [(i, 3) for i in range(6)] + [(i, 2) for i in range(5)] + [(0, 1), (4, 1)] + \
        [(0, 0), (1, 0), (3, 0), (4, 0)]
    shuttle = Part(PART_2, [(0.0, 0.0)], [PartPosition(CS_1, Pose(2 * STATORS, 0.0)),
                                         PartPosition(CS_1, Pose(5 * STATORS, 2 * STATORS))])
    layout = PartLayout([CS_1], [Part(PART_1, [(i * STATORS, j * STATORS) for i, j in cells],
                                      [PartPosition(CS_1, Pose())]), shuttle])
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt, layout=layout)
    movers = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(*centre(
        *cell)), part_oid=PART_1), name=f"m{k}") for k, cell in enumerate([(0, 1), (0, 3)])]
    for mover in movers:
        mover.enable()
    group = MC_PlanarGroup(rt)
    environment.create_boundary()
    group.enable()
    rt.run(0.01)
    for mover in movers:
        mover.add_to_group(group)
    environment.add_to_group(group)
    part = MC_PlanarPart()
    part.initialize(PART_2, environment)
    rt.run(0.01)
    assert all(m.state is PlanarState.ENABLED and m.group is group for m in movers)
    return rt, environment, group, movers, part


def test_a_part_that_moves_away_re_plans_the_route_over_it() -> None:
    rt, environment, group, movers, part = parted()
    router = Router(group, pitch=STATORS, constraint=SLOW, time_budget=0.0)
    handles = router.route({movers[0]: (*centre(3, 0), 0.0), movers[1]: (*centre(3, 3), 0.0)})
    assert centre(2, 0) in router.routes["m0"]  # over the shuttle
    watch = Watch(rt, router, environment, movers)
    watch.run(0.2)
    moved = part.activate_position(2)
    watch.step()
    assert moved.done and not environment.surface.covers(shapely.Point(centre(2, 0)))
    watch.until_idle()
    assert handles[movers[0]].done and movers[0].pose[:2] == pytest.approx(centre(3, 0))
    assert centre(4, 1) in router.routes["m0"]  # around by the right-hand column
    assert handles[movers[1]].done and router.stats.replans == 1


def test_bad_input_mid_route_is_refused_and_the_router_stays_usable() -> None:
    rt, environment, movers, router, handles = three_movers()
    watch = Watch(rt, router, environment, movers)
    watch.run(0.2)
    with pytest.raises(ConfigError, match="finite"):
        router.route({movers[0]: (float("nan"), 100.0, 0.0)})
    assert handles[movers[0]].busy  # nothing changed
    off = router.route({movers[1]: (5000.0, 120.0, 0.0)})[movers[1]]
    watch.until_idle()
    assert off.error and off.error_id is ErrorId.PLANAR_COLLISION
    assert "leaves the stator surface" in off.message and off.blocker == "the stator surface"
    assert handles[movers[1]].command_aborted
    assert handles[movers[0]].done and handles[movers[2]].done
    again = router.route({movers[1]: (*centre(2, 2), 0.0)})[movers[1]]
    watch.until_idle()
    assert again.done and movers[1].pose[:2] == pytest.approx(centre(2, 2))


def test_a_mover_outside_the_group_is_refused_mid_route() -> None:
    rt, environment, movers, router, handles = three_movers()
    stranger = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(
        *centre(2, 2))), name="stranger")
    watch = Watch(rt, router, environment, movers)
    watch.run(0.1)
    refused = router.route({stranger: (*centre(1, 2), 0.0)})[stranger]
    assert refused.error and refused.error_id is ErrorId.PLANAR_WRONG_STATE
    assert "not in the router's group" in refused.message
    watch.until_idle()
    assert all(handles[m].done for m in movers)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(2, 8), st.integers(3, 5), st.sampled_from(["target", "halt", "disable"]),
       st.floats(0.02, 0.5), st.integers(0, 2**32 - 1))
def test_re_routing_never_jams_overlaps_or_gets_refused(n: int, side: int, event: str,
                                                        when: float, seed: int) -> None:
    """Random fields and targets on every other cell of the default grid; after ``when``
    seconds one mover gets a new target, is halted or disabled. Every route ends, no
    footprints overlap, the group refuses nothing; errors only name what blocks."""
    rng = random.Random(seed)
    grid = build_grid(shapely.box(0, 0, (side + 1) * STATORS, side * STATORS), 155.0)
    cells = [grid.centre(c) for c in range(grid.size)
             if (c % grid.nx) % 2 == 0 and (c // grid.nx) % 2 == 0]
    n = min(n, len(cells) - 1)
    starts, targets = rng.sample(cells, n), rng.sample(cells, n)
    rt, environment, group, movers = field(side + 1, side, starts)
    router = Router(group, time_budget=0.0)
    handles = list(router.route({m: (*t, 0.0) for m, t in zip(movers, targets,
                                                               strict=True)}).values())
    watch = Watch(rt, router, environment, movers)
    watch.run(when)
    chosen = rng.choice(movers)
    if event == "target":
        free = [c for c in cells if c not in targets]
        handles.append(router.route({chosen: (*rng.choice(free), 0.0)})[chosen])
    else:
        getattr(chosen, event)()
    watch.until_idle(60.0)
    assert not any(h.busy for h in handles)
    for handle in handles:
        if handle.error:
            assert handle.error_id is ErrorId.PLANAR_COLLISION and handle.blocker


# --- execution: fewer stops -------------------------------------------------------------------

@pytest.mark.parametrize(("c", "legs"), [(10.0, 1), (-12.0, 1), (90.0, 2)])
def test_a_small_final_turn_is_made_on_the_way(c: float, legs: int) -> None:
    """A turn inside the C window (±15° by default, §4.2) goes with the last move; a quarter
    turn needs a MoveC at standstill after it."""
    rt, environment, group, movers = field(4, 3, [centre(0, 0)])
    router = Router(group)
    handle = router.route({movers[0]: (*centre(3, 1), c)})[movers[0]]
    Watch(rt, router, environment, movers).until_idle()
    assert handle.done and movers[0].pose == pytest.approx((*centre(3, 1), c))
    assert router.stats.legs == legs


def test_a_staircase_of_cells_is_one_straight_leg_when_nothing_is_in_the_way() -> None:
    rt, environment, group, movers = field(5, 3, [centre(0, 0)])
    router = Router(group, pitch=STATORS)
    handle = router.route({movers[0]: (*centre(4, 2), 0.0)})[movers[0]]
    assert len(router.routes["m0"]) > 2  # the plan has a corner
    Watch(rt, router, environment, movers).until_idle()
    assert handle.done and router.stats.legs == 1
