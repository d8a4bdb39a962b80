"""Multi-mover path planning on the routing grid: LaCAM first, then space-time A*.

Every mover is an agent with a start pose and a target pose. Time runs in steps; in a step
an agent waits or moves to one of the eight neighbouring cells. Half-steps index what an
agent occupies: ``2t`` the cells under it at step ``t``, ``2t + 1`` the cells its move from
step ``t`` to ``t + 1`` touches; in a valid plan no two agents hold a cell at the same
half-step, and an agent parks on its target for good (``conflicts`` checks this). An
agent's start pose and target pose need not be cell centres: it first moves from its pose
to the centre of its start cell and ends with a move from its goal cell's centre to the
target (turning there, if the target's c differs), both reserved like moves.

The first plan comes from LaCAM over PIBT steps (lacam.py, complete, D-339), replayed with
gaps so that it obeys the half-step rule (D-340). While the time budget lasts it is improved
(D-341, D-369): groups of agents are re-planned one after the other with space-time A*
around the others' routes, held in the reservation table ``_Table``; the A*'s cost counts
moves, waits and a stop per run of moves (D-368). The plan whose last agent would arrive
earliest when run in its order of passage (``executed_times``) is kept (anytime). What
cannot be planned is reported with the agent farthest from its target.
"""

from __future__ import annotations

import heapq
import math
import random
import time
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field

from openmotion.planar.routing.grid import MOVES, RoutingGrid
from openmotion.planar.routing.lacam import (
    SearchExhausted,
    SearchTimeout,
    Space,
    lacam,
    with_gaps,
)

MAX_EXPANSIONS = 20_000  #: A* gives up on one agent after this many expansions
CLOCK_EVERY = 64  #: an improvement round's A* looks at the clock every this many expansions
HORIZON_SLACK = 40  #: steps an agent may wait beyond its distance and the others' last use
FOREVER = 1 << 30  #: a half-step after every plan
#: the first plan's search gives up after this many PIBT steps of one mover (about a second
#: of one core here; the densest test fields need an eighth of it), or when a longer time
#: budget ends: a count, not a clock, so a failed search fails alike everywhere (D-374)
FIRST_PLAN_WORK = 500_000
LNS_EXPANSIONS = 20_000  #: A* gives up on one agent of an improvement round after this many
LNS_SIZE = 4  #: agents re-planned together in one improvement round
#: the estimated time a mover loses to a stop and a start (a turn, a wait on its way), in
#: moves of one cell: at the default dynamics a one-cell leg takes about three times as long
#: as one more cell of a longer leg (160-240 mm cells, D-368)
STOP_COST = 2.0
FLOOR_AGENTS = 8  #: up to this many agents, the anytime rounds stop at each one's best alone
#: one step's wait: about a one-cell leg of the mover waited for, in moves of one cell
WAIT_COST = 3.0


@dataclass
class Agent:
    """One mover to route: where it is, where it goes and what it occupies on the way."""

    name: str
    start: tuple[float, float, float]  #: x, y [mm], c [°]
    target: tuple[float, float, float]
    hx: float  #: half extents of its footprint while it travels [mm]
    hy: float
    start_cell: int
    goal_cell: int
    start_cells: tuple[int, ...]  #: occupied by the move from the start pose to its cell
    final_cells: tuple[int, ...]  #: occupied from the move to the target on, for good
    start_leg: bool  #: the start pose is no cell centre: one step to reach it
    final_leg: bool  #: the target is no cell centre (or turns): one step to reach it


@dataclass
class Route:
    """One agent's planned motion: positions per step and what it occupies per half-step."""

    agent: Agent
    points: list[tuple[float, float]]  #: centre per step (step 0: the start pose)
    occupied: list[tuple[int, ...]]  #: cells per half-step, 2 * len(points) - 1 of them
    cells: list[int]  #: the grid cell per step (-1: the start or target pose)

    @property
    def arrival(self) -> int:
        """The step at which it reaches its target."""
        return len(self.points) - 1


@dataclass
class Plan:
    routes: list[Route]
    order: list[int]  #: the agents by arrival step
    first_time: float = 0.0  #: wall time to the first plan [s]
    first_cpu: float = 0.0  #: the planning thread's CPU time to the first plan [s]
    time: float = 0.0  #: wall time spent planning in all [s]
    tried: int = 0  #: plans tried: the first and every improvement round
    cost: tuple[int, int] = (0, 0)  #: (last arrival, sum of arrivals) [steps]
    held: dict[tuple[int, int], int] = field(default_factory=dict)  #: (cell, half) -> agent
    parked: dict[int, int] = field(default_factory=dict)  #: cell -> half-step parked from

    @property
    def makespan_steps(self) -> int:
        return self.cost[0]


class PlanningFailed(Exception):
    """No order of the agents found a plan: ``agent`` could not be routed."""

    def __init__(self, agent: Agent, reason: str) -> None:
        super().__init__(f"{agent.name}: {reason}")
        self.agent = agent
        self.reason = reason


@dataclass
class _Table:
    """The half-steps at which cells are held: by whom, and until when."""

    held: dict[tuple[int, int], int] = field(default_factory=dict)  #: (cell, half) -> agent
    standing: dict[int, int] = field(default_factory=dict)  #: cell -> agent not yet planned
    parked: dict[int, int] = field(default_factory=dict)  #: cell -> first half-step held
    last: dict[int, int] = field(default_factory=dict)  #: cell -> last half-step held

    def free(self, cells: tuple[int, ...], half: int, agent: int,
             goal: frozenset[int] = frozenset()) -> bool:
        """No other agent holds a cell at ``half``; one not planned yet stands on none,
        except on the agent's ``goal`` cells (it must leave them before the agent comes)."""
        held, parked, standing = self.held, self.parked, self.standing
        for cell in cells:
            owner = held.get((cell, half))
            if owner is not None and owner != agent:
                return False
            owner = standing.get(cell)
            if owner is not None and owner != agent and cell not in goal:
                return False
            if parked.get(cell, FOREVER) <= half:
                return False
        return True

    def free_after(self, cells: tuple[int, ...], half: int) -> bool:
        """No cell held at ``half`` or later (to park there for good)."""
        return all(self.last.get(cell, -1) < half and cell not in self.parked
                   for cell in cells)

    def hold(self, route: Route, agent: int) -> None:
        for cell in route.agent.start_cells:
            if self.standing.get(cell) == agent:
                del self.standing[cell]
        for half, cells in enumerate(route.occupied):
            for cell in cells:
                self.held[(cell, half)] = agent
                if self.last.get(cell, -1) < half:
                    self.last[cell] = half
        for cell in route.occupied[-1]:
            self.parked[cell] = len(route.occupied) - 1


def distances(grid: RoutingGrid, goal: int) -> dict[int, int]:
    """Steps from every free cell to ``goal`` on the static grid (breadth first)."""
    dist = {goal: 0}
    queue = deque([goal])
    while queue:
        cell = queue.popleft()
        d = dist[cell] + 1
        for other in grid.neighbours(cell):
            if other not in dist:
                dist[other] = d
                queue.append(other)
    return dist


class Planner:
    """Plans all agents on one grid; reuses the grid's distance tables between orders."""

    def __init__(self, grid: RoutingGrid, agents: Sequence[Agent]) -> None:
        self.grid = grid
        self.agents = list(agents)
        self._dist: dict[int, dict[int, int]] = {}
        self._neighbours: dict[tuple[float, float], dict[int, list]] = {}

    def distance(self, agent: Agent) -> dict[int, int]:
        table = self._dist.get(agent.goal_cell)
        if table is None:
            table = distances(self.grid, agent.goal_cell)
            self._dist[agent.goal_cell] = table
        return table

    def plan(self, time_budget: float, seed: int = 0) -> Plan:
        """A first plan (LaCAM, complete), improved while ``time_budget`` [s] lasts by
        re-planning groups of agents with space-time A* around the others (D-339, D-369);
        with a budget of 0 the first plan, and no clock read."""
        started = time.perf_counter()
        cpu = time.thread_time()
        rng = random.Random(seed)
        routes = self._first_routes(time_budget, seed)
        first_time = time.perf_counter() - started
        first_cpu = time.thread_time() - cpu
        score = self._score(routes)
        tried = 1
        if time_budget > 0:
            floor = self._floor()
            while score[0] > floor and time.perf_counter() - started < time_budget:
                tried += 1
                deadline = started + time_budget  # a round ends with the budget (D-375)
                if tried == 2 and len(routes) <= FLOOR_AGENTS:  # all, the longest way first
                    better = self._prioritized(deadline)
                else:
                    better = self._neighbourhood(routes, rng, deadline)
                if better is not None and self._score(better) < score:
                    routes, score = better, self._score(better)
        cost = _cost(routes)
        table = _Table()
        for index, route in enumerate(routes):
            table.hold(route, index)
        plan = Plan(routes, sorted(range(len(routes)), key=lambda a: routes[a].arrival),
                    first_time=first_time, first_cpu=first_cpu, cost=cost, held=table.held,
                    parked=table.parked)
        plan.time = time.perf_counter() - started
        plan.tried = tried
        return plan

    def _first_routes(self, time_budget: float, seed: int) -> list[Route]:
        """Routes from LaCAM over PIBT steps (lacam.py); PlanningFailed naming the agent
        farthest from its target when the search ends without a plan."""
        for index, agent in enumerate(self.agents):
            if agent.start_cell not in self.distance(agent):
                raise PlanningFailed(agent, "no way on the grid from its start to its target")
            del index
        space = Space(self.grid, self.agents, [self.distance(a) for a in self.agents])
        try:
            configs = lacam(space, FIRST_PLAN_WORK, seed, time_limit=time_budget)
        except SearchTimeout as failed:
            raise PlanningFailed(self.agents[failed.closest],
                                 f"no plan found within the search's limit "
                                 f"({failed.explored} configurations searched)") from None
        except SearchExhausted as failed:
            raise PlanningFailed(self.agents[failed.closest],
                                 f"every way to its target is taken by other movers "
                                 f"(no plan exists: {failed.explored} configurations "
                                 f"searched)") from None
        timeline = with_gaps(space, configs)
        return [self._route_of(space, k, timeline[k]) for k in range(len(self.agents))]

    def _route_of(self, space: Space, k: int, vertices: list[int]) -> Route:
        """Agent k's route from its vertex per step, cut after its last arrival."""
        agent = self.agents[k]
        goal = space.goals[k]
        end = len(vertices) - 1
        while end > 0 and vertices[end - 1] == goal:
            end -= 1
        vertices = vertices[:end + 1]
        points: list[tuple[float, float]] = []
        cells: list[int] = []
        occupied: list[tuple[int, ...]] = []
        for t, v in enumerate(vertices):
            if t:
                occupied.append(space.move(k, vertices[t - 1], v))
            if v < space.size:
                points.append(self.grid.centre(v))
                cells.append(v)
            else:
                points.append(agent.start[:2] if v == space.starts[k] else agent.target[:2])
                cells.append(-1)
            occupied.append(space.cells(k, v))
        occupied[-1] = tuple(sorted(set(occupied[-1]) | set(agent.final_cells)))
        return Route(agent, points, occupied, cells)

    def _neighbourhood(self, routes: list[Route], rng: random.Random,
                       deadline: float | None = None) -> list[Route] | None:
        """Re-plan the latest agent and up to LNS_SIZE - 1 agents whose routes meet its
        cells, one by one in a random order, around the others' routes (large neighbourhood
        search); None when an agent finds no slot or the ``deadline`` passes."""
        n = len(routes)
        times = executed_times(routes, min(self.grid.pitch))
        latest = max(times)
        critical = rng.choice([a for a in range(n) if times[a] == latest])
        last_step = max(r.arrival for r in routes)
        if n <= LNS_SIZE:
            group = list(range(n))
        else:
            mine = {c for cells in routes[critical].occupied for c in cells}
            near = [a for a in range(n) if a != critical and
                    any(c in mine for cells in routes[a].occupied for c in cells)]
            rng.shuffle(near)
            others = [a for a in range(n) if a != critical and a not in near]
            rng.shuffle(others)
            group = [critical, *(near + others)[:LNS_SIZE - 1]]
        chosen = set(group)
        table = _Table()
        for index, route in enumerate(routes):
            if index not in chosen:
                table.hold(route, index)
        for index in group:  # who is re-planned later holds its start at step 0 only
            for cell in self.agents[index].start_cells:
                table.held[(cell, 0)] = index
        rng.shuffle(group)
        new = list(routes)
        try:
            for index in group:
                route = self._plan_agent(index, table, LNS_EXPANSIONS, last_step, deadline)
                table.hold(route, index)
                new[index] = route
        except _OrderFailed:
            return None
        return new

    def _score(self, routes: list[Route]) -> tuple[float, float]:
        """(the latest estimated arrival, their sum) when the plan runs in its order of
        passage (``executed_times``): what the anytime rounds lower (D-368)."""
        times = executed_times(routes, min(self.grid.pitch))
        return max(times, default=0.0), round(sum(times), 6)

    def route_time(self, route: Route) -> float:
        """A route's estimated time in moves of one cell, as ``_plan_agent`` counts it: the
        length of every move, a wait per step standing, and a stop per run of moves in one
        direction (D-368)."""
        pitch = min(self.grid.pitch)
        total, last = 0.0, None
        points = route.points
        for a, b in zip(points, points[1:], strict=False):
            if a == b:
                total += WAIT_COST
                last = None
                continue
            direction = _direction(a, b)
            total += math.dist(a, b) / pitch + (0.0 if direction == last else STOP_COST)
            last = direction
        return round(total, 6)

    def _floor(self) -> float:
        """No round can end the latest arrival earlier than this: with few agents each one's
        best estimated time alone on the grid, with many (where that would take a good part
        of the budget) A*'s lower bound of it."""
        if len(self.agents) > FLOOR_AGENTS:
            return max((self._rest(a, self.distance(a))(a.start_cell, -1) + a.start_leg
                        + a.final_leg for a in self.agents), default=0.0)
        table = _Table()
        try:
            return max((self.route_time(self._plan_agent(k, table))
                        for k in range(len(self.agents))), default=0.0)
        except _OrderFailed:
            return 0.0

    def _prioritized(self, deadline: float | None = None) -> list[Route] | None:
        """Every agent by space-time A*, the longest way first, each standing on its start
        only until the first step (prioritized planning); None when one finds no slot or
        the ``deadline`` passes."""
        order = sorted(range(len(self.agents)), key=lambda a: -self.distance(
            self.agents[a]).get(self.agents[a].start_cell, 0))
        try:
            return self._plan_order(order, standing=False, deadline=deadline)[0]
        except _OrderFailed:
            return None

    def _plan_order(self, order: list[int], standing: bool = True,
                    deadline: float | None = None) -> tuple[list[Route], _Table]:
        """Plan the agents in ``order``. ``standing``: who is not planned yet stands on its
        start for good (the others go around it); else it holds its start only at step 0
        and must get out of the way of those planned before it (swaps need this)."""
        table = _Table()
        for index, agent in enumerate(self.agents):
            for cell in agent.start_cells:
                if standing:
                    table.standing[cell] = index
                else:
                    table.held[(cell, 0)] = index
        routes: list[Route | None] = [None] * len(self.agents)
        for index in order:
            route = self._plan_agent(index, table, deadline=deadline)
            table.hold(route, index)
            routes[index] = route
        return [r for r in routes if r is not None], table

    def _rest(self, agent: Agent, dist: dict[int, int]):  # noqa: ANN202 - a closure
        """A lower bound of the cost from (cell, direction of the last move) to the agent's
        goal cell: the longer of its steps on the grid and its octile length, plus a stop
        unless the goal lies straight ahead (consistent, so A* stays optimal)."""
        nx = self.grid.nx
        gi, gj = agent.goal_cell % nx, agent.goal_cell // nx
        cache: dict[tuple[int, int], float] = {}

        def rest(cell: int, direction: int) -> float:
            out = cache.get((cell, direction))
            if out is None:
                di, dj = gi - cell % nx, gj - cell // nx
                if di == 0 and dj == 0:
                    out = 0.0
                else:
                    ai, aj = abs(di), abs(dj)
                    octile = max(ai, aj) + (math.sqrt(2.0) - 1.0) * min(ai, aj)
                    out = max(float(dist[cell]), octile)
                    if direction < 0 or not _ahead(MOVES[direction], di, dj):
                        out += STOP_COST
                cache[(cell, direction)] = out
            return out
        return rest

    def _moves_from(self, cell: int, hx: float, hy: float
                    ) -> list[tuple[int, int, float, tuple[int, ...], tuple[int, ...]]]:
        """(cell, direction, length in pitches, cells swept, cells under it after) of a wait
        (direction -1) and of each move from ``cell``, for a footprint of half extents
        (hx, hy)."""
        table = self._neighbours.setdefault((hx, hy), {})
        out = table.get(cell)
        if out is None:
            grid = self.grid
            nx = grid.nx
            under = grid.touched_cells(cell, cell, hx, hy)
            out = [(cell, -1, 0.0, under, under)]
            for other in grid.neighbours(cell):
                di, dj = other % nx - cell % nx, other // nx - cell // nx
                out.append((other, MOVES.index((di, dj)), math.hypot(di, dj),
                            grid.touched_cells(cell, other, hx, hy),
                            grid.touched_cells(other, other, hx, hy)))
            table[cell] = out
        return out

    def _plan_agent(self, index: int, table: _Table, limit: int = MAX_EXPANSIONS,
                    latest: int | None = None, deadline: float | None = None) -> Route:
        """Agent ``index``'s cheapest route around what ``table`` holds: space-time A* over
        (cell, step, direction of the last move) whose cost is the estimated time of
        ``route_time`` (moves, waits and a stop per run), so that of two routes arriving
        alike the one with fewer turns and stops wins (D-368). ``latest``: the step by which
        it must arrive (an improvement round wants no later arrival). ``deadline``: the
        ``time.perf_counter()`` at which an improvement round's budget ends; the search
        gives up then, as after ``limit`` expansions."""
        agent = self.agents[index]
        grid = self.grid
        dist = self.distance(agent)
        if agent.start_cell not in dist:
            raise _OrderFailed(index, "no way on the grid from its start to its target")
        hx, hy = agent.hx, agent.hy
        t0 = 1 if agent.start_leg else 0
        own = grid.touched_cells(agent.start_cell, agent.start_cell, hx, hy)
        if agent.start_leg and not (table.free(agent.start_cells, 1, index)
                                    and table.free(own, 2, index)):
            raise _OrderFailed(index, "its start cell is taken at once")
        horizon = t0 + dist[agent.start_cell] + HORIZON_SLACK + max(table.last.values(),
                                                                    default=0) // 2
        if latest is not None:
            horizon = min(horizon, latest - (1 if agent.final_leg else 0))
        # state: (cell, step, direction of the move into it; -1 after a wait or at the start)
        start = (agent.start_cell, t0, -1)
        parent: dict[tuple[int, int, int], tuple[int, int, int] | None] = {start: None}
        best: dict[tuple[int, int, int], float] = {start: 0.0}
        rest = self._rest(agent, dist)
        heap = [(rest(agent.start_cell, -1), -t0, 0.0, agent.start_cell, t0, -1)]
        expansions = 0
        goal_state = None
        final = agent.final_cells
        goal = frozenset(final) | frozenset(grid.touched_cells(agent.goal_cell,
                                                               agent.goal_cell, hx, hy))
        passable: dict[tuple[int, int, int], bool] = {}  #: (u, v, step) -> the move is free
        while heap:
            _, _, g, u, t, d = heapq.heappop(heap)
            if g > best.get((u, t, d), math.inf):
                continue
            expansions += 1
            if expansions > limit or (deadline is not None and expansions % CLOCK_EVERY == 0
                                      and time.perf_counter() > deadline):
                break
            if u == agent.goal_cell:
                after = 2 * t + 1 if agent.final_leg else 2 * t
                if table.free_after(final, after):
                    goal_state = (u, t, d)
                    break
            if t >= horizon:
                continue
            for v, direction, length, swept, under in self._moves_from(u, hx, hy):
                if dist.get(v, FOREVER) + t + 1 > horizon:
                    continue
                if direction < 0:
                    cost = WAIT_COST
                else:
                    cost = length if direction == d else length + STOP_COST
                state = (v, t + 1, direction)
                further = g + cost
                if further >= best.get(state, math.inf):
                    continue
                key = (u, v, t)
                ok = passable.get(key)
                if ok is None:
                    ok = passable[key] = table.free(swept, 2 * t + 1, index, goal) and \
                        table.free(under, 2 * t + 2, index, goal)
                if not ok:
                    continue
                best[state] = further
                parent[state] = (u, t, d)
                heapq.heappush(heap, (further + rest(v, direction), -(t + 1), further, v,
                                      t + 1, direction))
        if goal_state is None:
            raise _OrderFailed(index, "every way to its target is taken by other movers "
                                      "(prioritized planning found no slot)")
        cells = []
        state: tuple[int, int, int] | None = goal_state
        while state is not None:
            cells.append(state[0])
            state = parent[state]
        cells.reverse()
        return self._route(agent, cells)

    def _route(self, agent: Agent, cells: list[int]) -> Route:
        grid = self.grid
        hx, hy = agent.hx, agent.hy
        points: list[tuple[float, float]] = []
        occupied: list[tuple[int, ...]] = []
        route_cells: list[int] = []
        if agent.start_leg:
            points.append(agent.start[:2])
            route_cells.append(-1)
            occupied += [agent.start_cells, agent.start_cells]
        for k, cell in enumerate(cells):
            if k:
                occupied.append(grid.touched_cells(cells[k - 1], cell, hx, hy))
            points.append(grid.centre(cell))
            route_cells.append(cell)
            occupied.append(grid.touched_cells(cell, cell, hx, hy))
        if agent.final_leg:
            points.append(agent.target[:2])
            route_cells.append(-1)
            occupied += [agent.final_cells, agent.final_cells]
        else:
            occupied[-1] = tuple(sorted(set(occupied[-1]) | set(agent.final_cells)))
        return Route(agent, points, occupied, route_cells)


def executed_times(routes: list[Route], pitch: float) -> list[float]:
    """Each route's estimated arrival, in moves of one cell, when the routes run in the
    plan's order of passage through every cell rather than in its steps (as the router
    drives them, D-347): a move starts once the movers the plan lets through its cells
    before have left them, costs its length, and a stop when it does not continue the move
    before it without waiting (D-368). Waits of the plan that no order asks for vanish."""
    n = len(routes)
    # per cell: (first, last half-step, agent) of every visit, in order
    visits: dict[int, list[tuple[int, int, int]]] = {}
    for a, route in enumerate(routes):
        open_: dict[int, int] = {}
        for half, cells in enumerate(route.occupied):
            for cell in [c for c in open_ if c not in cells]:
                visits.setdefault(cell, []).append((open_.pop(cell), half - 1, a))
            for cell in cells:
                open_.setdefault(cell, half)
        for cell, first in open_.items():
            visits.setdefault(cell, []).append((first, FOREVER, a))
    after: list[dict[int, list[tuple[int, int]]]] = [{} for _ in range(n)]
    for cell_visits in visits.values():
        cell_visits.sort()
        for (_, last, a), (first, _, b) in zip(cell_visits, cell_visits[1:], strict=False):
            if a != b:  # b's step taking the cell waits until a reached the point after
                after[b].setdefault(max(0, (first - 1) // 2), []).append((a, last // 2 + 1))
    reach = [[0.0] + [math.inf] * (len(r.points) - 1) for r in routes]
    last: list[tuple[float, float] | None] = [None] * n
    steps = max((len(r.points) for r in routes), default=1)
    for step in range(steps - 1):
        for a, route in enumerate(routes):
            if step + 1 >= len(route.points):
                continue
            ready = reach[a][step]
            for other, point in after[a].get(step, ()):
                ready = max(ready, reach[other][min(point, len(routes[other].points) - 1)])
            u, v = route.points[step], route.points[step + 1]
            if u == v:
                if ready > reach[a][step]:
                    last[a] = None  # it stands still for another: the next move starts
                reach[a][step + 1] = ready
                continue
            direction = _direction(u, v)
            stop = direction != last[a] or ready > reach[a][step]
            reach[a][step + 1] = ready + math.dist(u, v) / pitch + (STOP_COST if stop else 0.0)
            last[a] = direction
    return [round(r[-1], 6) for r in reach]


def _ahead(move: tuple[int, int], di: int, dj: int) -> bool:
    """(di, dj) is a whole number of ``move``s."""
    k = max(abs(di), abs(dj))
    return move[0] * k == di and move[1] * k == dj


def _cost(routes: list[Route]) -> tuple[int, int]:
    arrivals = [r.arrival for r in routes]
    return max(arrivals, default=0), sum(arrivals)


def conflicts(routes: list[Route]) -> list[tuple[int, int, int, int]]:
    """(cell, half-step, agent, agent) where two routes hold a cell at once, or one holds a
    cell another has parked on: empty for a valid plan (the half-step table's rule)."""
    held: dict[tuple[int, int], int] = {}
    out = []
    for a, route in enumerate(routes):
        for half, cells in enumerate(route.occupied):
            for cell in cells:
                other = held.setdefault((cell, half), a)
                if other != a:
                    out.append((cell, half, other, a))
    horizon = max((len(r.occupied) for r in routes), default=0)
    for a, route in enumerate(routes):
        for half in range(len(route.occupied), horizon):
            for cell in route.occupied[-1]:
                other = held.get((cell, half))
                if other is not None and other != a:
                    out.append((cell, half, a, other))
    return out


class _OrderFailed(Exception):
    def __init__(self, index: int, reason: str) -> None:
        super().__init__(reason)
        self.index = index
        self.reason = reason


def straight_runs(route: Route) -> list[tuple[int, int]]:
    """(first, last) step of each run of moves in one direction, waits dropped."""
    runs: list[tuple[int, int]] = []
    points = route.points
    k = 0
    n = len(points)
    while k < n - 1:
        if points[k + 1] == points[k]:
            k += 1
            continue
        d = _direction(points[k], points[k + 1])
        end = k + 1
        while end < n - 1 and points[end + 1] != points[end] and \
                _direction(points[end], points[end + 1]) == d:
            end += 1
        runs.append((k, end))
        k = end
    return runs


def _direction(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    return round(dx / length, 6), round(dy / length, 6)


def plan_around(planner: Planner, kept: Sequence[Route], since: Sequence[int], start: int
                ) -> list[Route]:
    """Routes of ``planner``'s agents around the routes other movers go on driving (the
    router's re-routing): ``kept[k]`` still holds what it occupies from step ``since[k]`` on,
    and its last cells for good. The agents start at step ``start`` of the kept routes and
    stand on their starts until then: the routes returned begin with those waits, so that
    their steps count as the kept routes' do. Orders tried: the longest way first, then each
    agent first; PlanningFailed names an agent when no order finds a slot for all."""
    n = len(planner.agents)
    longest = sorted(range(n), key=lambda a: -planner.distance(planner.agents[a]).get(
        planner.agents[a].start_cell, 0))
    failure: PlanningFailed | None = None
    for order in [longest] + [[a] + [b for b in longest if b != a] for a in longest[1:]]:
        table = _kept_table(kept, since, 2 * start)
        for index, agent in enumerate(planner.agents):
            for cell in agent.start_cells:
                table.standing[cell] = index
        routes: list[Route] = []
        try:
            for index in order:
                routes.append(planner._plan_agent(index, table))  # noqa: SLF001 - this module's A*
                table.hold(routes[-1], index)
        except _OrderFailed as failed:
            failure = PlanningFailed(planner.agents[failed.index], failed.reason)
            continue
        by_agent = dict(zip(order, routes, strict=True))
        return [_delayed(by_agent[index], start) for index in range(n)]
    assert failure is not None
    raise failure


def _kept_table(kept: Sequence[Route], since: Sequence[int], base: int) -> _Table:
    """What the kept routes hold from half-step ``base`` on, counted from there; their
    owners are negative numbers, never an agent's."""
    table = _Table()
    for k, (route, first) in enumerate(zip(kept, since, strict=True)):
        end = len(route.occupied) - 1
        for half in range(max(2 * first, base), end + 1):
            for cell in route.occupied[half]:
                table.held[(cell, half - base)] = -1 - k
                table.last[cell] = max(table.last.get(cell, -1), half - base)
        for cell in route.occupied[-1]:
            table.parked[cell] = min(table.parked.get(cell, FOREVER), max(0, end - base))
    return table


def _delayed(route: Route, steps: int) -> Route:
    """``route`` standing on its start for ``steps`` steps first."""
    return Route(route.agent, [route.points[0]] * steps + route.points,
                 [route.occupied[0]] * (2 * steps) + route.occupied,
                 [route.cells[0]] * steps + route.cells)
