"""The routing planner on its own: LaCAM over PIBT steps gives complete, conflict-free plans
on dense grids (the half-step table's rule: no mover enters cells another leaves in the same
step); what cannot be planned names the mover."""

from __future__ import annotations

import random

import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from openmotion.planar.routing import Router
from openmotion.planar.routing.grid import build_grid
from openmotion.planar.routing.lacam import SearchTimeout, Space, lacam, pibt_step, with_gaps
from openmotion.planar.routing.planner import (
    FIRST_PLAN_WORK,
    Agent,
    Planner,
    PlanningFailed,
    conflicts,
    distances,
    executed_times,
    plan_around,
    straight_runs,
)
from openmotion.planar.stators import STATOR_SIZE
from openmotion.testing import grouped_field

SIDE = 155.0  #: [mm] the default mover


def agents_on(grid, starts: list[int], goals: list[int]) -> list[Agent]:  # noqa: ANN001
    """Agents standing on cell centres with targets on cell centres."""
    out = []
    for k, (s, g) in enumerate(zip(starts, goals, strict=True)):
        out.append(Agent(f"m{k}", (*grid.centre(s), 0.0), (*grid.centre(g), 0.0),
                         SIDE / 2, SIDE / 2, s, g, (s,), (g,), False, False))
    return out


def square_grid(stators: int):  # noqa: ANN201
    surface = shapely.box(0.0, 0.0, stators * STATOR_SIZE, stators * STATOR_SIZE)
    return build_grid(surface, SIDE)


def test_a_dense_field_is_planned_completely_and_without_conflicts() -> None:
    grid = square_grid(6)  # 9 x 9 cells of 160 mm
    cells = [c for c in range(grid.size) if grid.free[c]]
    rng = random.Random(3)
    starts = rng.sample(cells, 30)
    goals = rng.sample(cells, 30)
    planner = Planner(grid, agents_on(grid, starts, goals))
    plan = planner.plan(0.0, seed=1)
    assert len(plan.routes) == 30 and conflicts(plan.routes) == []
    for route, start, goal in zip(plan.routes, starts, goals, strict=True):
        assert route.cells[0] == start and route.cells[-1] == goal
        assert route.points[-1] == grid.centre(goal)
        for a, b in zip(route.cells, route.cells[1:], strict=False):  # one move per step
            assert a == b or b in grid.neighbours(a)
    assert plan.makespan_steps == max(r.arrival for r in plan.routes)
    assert plan.first_time > 0.0 and plan.held and plan.parked
    assert all(straight_runs(r) or r.arrival == 0 for r in plan.routes)


def test_a_full_row_of_movers_swaps_ends_through_the_free_row() -> None:
    grid = square_grid(2)  # 3 x 3 cells: two rows of movers' worth, one free row
    starts = [0, 1, 2]
    goals = [2, 1, 0]
    planner = Planner(grid, agents_on(grid, starts, goals))
    plan = planner.plan(0.05, seed=0)
    assert conflicts(plan.routes) == []
    assert [r.cells[-1] for r in plan.routes] == goals


def test_no_mover_enters_a_cell_another_leaves_in_the_same_step() -> None:
    grid = square_grid(4)
    cells = [c for c in range(grid.size) if grid.free[c]]
    rng = random.Random(7)
    starts, goals = rng.sample(cells, 18), rng.sample(cells, 18)
    agents = agents_on(grid, starts, goals)
    space = Space(grid, agents, [distances(grid, a.goal_cell) for a in agents])
    configs = lacam(space, FIRST_PLAN_WORK, seed=0)
    assert configs[0] == space.starts and configs[-1] == space.goals
    timeline = with_gaps(space, configs)
    for t in range(len(timeline[0]) - 1):
        taken: dict[int, int] = {}
        for k, path in enumerate(timeline):
            for cell in space.move(k, path[t], path[t + 1]):
                assert taken.setdefault(cell, k) == k, (t, cell)


def test_the_first_search_gives_up_after_a_count_of_work_not_a_time() -> None:
    grid = square_grid(5)
    cells = [c for c in range(grid.size) if grid.free[c]]
    rng = random.Random(6)
    starts, goals = rng.sample(cells, 25), rng.sample(cells, 25)  # about 2500 steps to plan
    agents = agents_on(grid, starts, goals)
    space = Space(grid, agents, [distances(grid, a.goal_cell) for a in agents])
    ends = []
    for _ in range(2):  # the same configurations searched each time: no clock decides
        with pytest.raises(SearchTimeout) as ended:
            lacam(space, 25 * 40, seed=0)
        ends.append((ended.value.explored, ended.value.closest))
    assert ends[0] == ends[1] and ends[0][0] <= 42
    configs = lacam(space, FIRST_PLAN_WORK, seed=0)  # the same space, enough work: a plan
    assert configs[-1] == space.goals


def test_a_pibt_step_refuses_a_constraint_that_swaps_two_movers() -> None:
    grid = square_grid(2)
    agents = agents_on(grid, [0, 1], [1, 0])
    space = Space(grid, agents, [distances(grid, a.goal_cell) for a in agents])
    assert pibt_step(space, (0, 1), [0, 1], who=(0, 1), where=(1, 0)) is None
    step = pibt_step(space, (0, 1), [0, 1])  # still usable: a valid step follows
    assert step is not None and step != (1, 0)


def test_no_plan_exists_names_a_mover() -> None:
    surface = shapely.box(0.0, 0.0, 2 * 160.0, 160.0)  # two cells side by side
    grid = build_grid(surface, SIDE)
    agents = agents_on(grid, [0, 1], [1, 0])  # a swap with no room to pass
    planner = Planner(grid, agents)
    with pytest.raises(PlanningFailed) as failed:
        planner.plan(0.0)
    assert failed.value.agent.name in {"m0", "m1"} and "no plan exists" in failed.value.reason
    ok = Planner(grid, agents_on(grid, [0], [1])).plan(0.0)  # the planner type stays usable
    assert ok.routes[0].cells == [0, 1]


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(2, 30), st.integers(0, 2**32 - 1))
def test_random_dense_fields_give_conflict_free_complete_plans(n: int, seed: int) -> None:
    grid = square_grid(6)  # 9 x 9 cells: up to 30 of 81 taken, as dense as 78 on 10 x 10
    cells = [c for c in range(grid.size) if grid.free[c]]
    rng = random.Random(seed)
    starts, goals = rng.sample(cells, n), rng.sample(cells, n)
    plan = Planner(grid, agents_on(grid, starts, goals)).plan(0.0, seed=seed)
    assert conflicts(plan.routes) == []
    assert [r.cells[-1] for r in plan.routes] == goals


def test_a_route_around_a_crossing_mover_keeps_its_line_rather_than_zigzag() -> None:
    # an agent along row 2 of 10 x 6 cells; a kept route crosses its line going down column 4
    grid = build_grid(shapely.box(0.0, 0.0, 1600.0, 960.0), SIDE)
    nx = grid.nx
    crossing = agents_on(grid, [4], [5 * nx + 4])[0]
    kept = Planner(grid, [crossing])._route(crossing, [j * nx + 4 for j in range(6)])  # noqa: SLF001
    agent = agents_on(grid, [2 * nx], [2 * nx + 7])[0]
    route = plan_around(Planner(grid, [agent]), [kept], [0], 0)[0]
    assert conflicts([kept, route]) == []
    assert route.cells[-1] == 2 * nx + 7 and route.arrival == 7  # as early as the zigzag
    assert len(straight_runs(route)) == 1  # one leg: no stop on the way (D-368)


def test_executed_times_drop_the_waits_no_order_asks_for() -> None:
    grid = build_grid(shapely.box(0.0, 0.0, 1600.0, 960.0), SIDE)
    nx = grid.nx
    planner = Planner(grid, agents_on(grid, [0, 2 * nx], [3, 2 * nx + 3]))
    straight = planner._route(planner.agents[0], [0, 1, 2, 3])  # noqa: SLF001
    waiting = planner._route(planner.agents[1], [2 * nx, 2 * nx, 2 * nx + 1, 2 * nx + 1,  # noqa: SLF001
                                                 2 * nx + 2, 2 * nx + 3])
    pitch = min(grid.pitch)
    # three moves and one start each: the waits of the second are nobody's order
    assert executed_times([straight, waiting], pitch) == [5.0, 5.0]
    # a mover that enters a cell after the first one passed it waits until it has gone on
    # to the cell after (4 = one start and a move), then starts and moves (3)
    follower = Planner(grid, agents_on(grid, [nx + 1], [1]))
    after = follower._route(follower.agents[0], [nx + 1, nx + 1, nx + 1, 1])  # noqa: SLF001
    assert executed_times([straight, after], pitch) == [5.0, 7.0]


def test_the_time_budget_only_ever_improves_the_first_plan() -> None:
    grid = square_grid(5)
    cells = [c for c in range(grid.size) if grid.free[c]]
    rng = random.Random(11)
    starts, goals = rng.sample(cells, 12), rng.sample(cells, 12)
    pitch = min(grid.pitch)
    first = Planner(grid, agents_on(grid, starts, goals)).plan(0.0, seed=2)
    again = Planner(grid, agents_on(grid, starts, goals)).plan(0.0, seed=2)
    assert [r.cells for r in first.routes] == [r.cells for r in again.routes]  # no clock
    better = Planner(grid, agents_on(grid, starts, goals)).plan(0.2, seed=2)
    assert conflicts(better.routes) == [] and [r.cells[-1] for r in better.routes] == goals
    assert max(executed_times(better.routes, pitch)) <= max(executed_times(first.routes,
                                                                           pitch))


def route_and_run(nx: int, ny: int, starts: list[tuple[float, float]],
                  targets: list[tuple[float, float, float]]) -> tuple[Router, list, dict]:
    """Route movers standing at ``starts`` to ``targets`` on an nx x ny stator field; run
    until the router is idle, counting overlapping footprints."""
    rt, _, group, movers = grouped_field(nx, ny, starts)
    router = Router(group, time_budget=0.0)
    handles = router.route(dict(zip(movers, targets, strict=True)))
    assert all(h.busy for h in handles.values())
    overlaps = 0
    end = rt.now + 60.0
    while router.busy and rt.now < end:
        rt.step()
        prints = [m.footprint() for m in movers]
        overlaps += sum(shapely.area(shapely.intersection(prints[a], prints[b])) > 1e-6
                        for a in range(len(prints)) for b in range(a + 1, len(prints)))
    assert not router.busy and overlaps == 0 and router.stats.rejected == 0
    return router, movers, handles


def test_a_packed_block_of_movers_is_routed_by_the_group() -> None:
    grid = build_grid(shapely.box(0.0, 0.0, 4 * STATOR_SIZE, 3 * STATOR_SIZE), SIDE)
    block = [j * grid.nx + i for j in range(2) for i in range(4)]  # 8 movers side by side
    starts = [grid.centre(c) for c in block]
    targets = [(*p, 0.0) for p in reversed(starts)]
    _, movers, handles = route_and_run(4, 3, starts, targets)
    assert all(h.done for h in handles.values())
    for mover, target in zip(movers, targets, strict=True):
        assert mover.pose.x == pytest.approx(target[0])


def test_poses_between_cell_centres_and_turns_are_planned_as_legs_of_their_own() -> None:
    # cells of 160 x 180 mm: poses off their centres cover two cells, a turn nine
    starts = [(85.0, 95.0), (570.0, 100.0), (250.0, 620.0)]
    targets = [(560.0, 450.0, 90.0), (100.0, 600.0, 0.0), (880.0, 630.0, 0.0)]
    router, movers, handles = route_and_run(4, 3, starts, targets)
    assert [h.message for h in handles.values() if not h.done] == []
    for mover, target in zip(movers, targets, strict=True):
        assert tuple(mover.pose) == pytest.approx(target, abs=1e-6)
    plan = router.stats.plans[-1]
    assert conflicts(plan.routes) == []
    assert any(-1 in r.cells[1:-1] or r.cells[0] == -1 for r in plan.routes)


def test_an_improvement_round_gives_up_when_its_deadline_has_passed() -> None:
    """A round that starts just before the budget ends may not run on past it: its A*
    looks at the clock and gives up (D-375). A deadline of 0 has always passed."""
    grid = square_grid(6)
    cells = [c for c in range(grid.size) if grid.free[c]]
    rng = random.Random(0)
    starts, goals = rng.sample(cells, 8), rng.sample(cells, 8)
    planner = Planner(grid, agents_on(grid, starts, goals))
    first = planner.plan(0.0, seed=0)
    assert planner._prioritized(deadline=0.0) is None  # noqa: SLF001
    assert planner._neighbourhood(first.routes, random.Random(0), deadline=0.0) is None  # noqa: SLF001
    # without a deadline the same rounds plan: the planner is still usable
    assert conflicts(planner._prioritized()) == []  # noqa: SLF001
    assert conflicts(planner._neighbourhood(first.routes, random.Random(0))) == []  # noqa: SLF001
