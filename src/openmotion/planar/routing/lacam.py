"""A complete first plan for dense fields: LaCAM over PIBT steps on the routing grid.

The configuration of the movers is where each one stands at a step: a grid cell, or (for a
mover whose start or target pose is no cell centre) a vertex of its own for that pose, whose
cells are what the mover occupies there (``Agent.start_cells`` / ``Agent.final_cells``).

What a mover covers is the set of cells its footprint touches, as in the planner's
half-step table (planner.py). In a step of the search, a mover may enter cells that another
leaves in the same step only behind a mover that goes into free cells (trains of two, so no
swaps and no rotations), and a diagonal move needs the cells beside it empty before and
after. ``with_gaps`` then replays the plan so that no mover enters cells another leaves in
the same step (the half-step table's rule, D-340): each move waits until the movers the plan
let through its cells before have left them. A train of two costs one step of delay there;
longer trains cost more, which is why they are not planned.

- **PIBT step** (priority inheritance with backtracking, after Okumura et al., AIJ 2022):
  movers decide in order of priority (steps spent away from the target); each takes the
  neighbour nearest to its target that the cells allow; a mover standing there that has
  not decided yet is asked first, with the inherited priority, to move on, and when it
  cannot, the asking mover tries its next choice (waiting is one of them).
- **LaCAM** (Okumura 2023): a depth-first search over configurations whose successors come
  from PIBT steps under constraints ("mover i goes to v"); when PIBT alone cycles, the
  constraints enumerate the other successors one by one. The search is complete: it finds a
  plan whenever one exists on the grid (given the time), and otherwise exhausts the
  configurations it can reach.
"""

from __future__ import annotations

import math
import random
import time
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from openmotion.planar.routing.grid import RoutingGrid

TIE = 1e-3  #: random part of a priority, breaks ties between movers


class SearchExhausted(Exception):
    """No configuration reachable from the start has every mover on its target; ``closest``
    is the mover farthest from its target in the configuration nearest to the goal."""

    def __init__(self, closest: int, explored: int) -> None:
        super().__init__(f"no plan exists ({explored} configurations searched)")
        self.closest = closest
        self.explored = explored


class SearchTimeout(Exception):
    """The time limit or the work limit ended the search; ``closest`` is the mover farthest
    from its target in the configuration nearest to the goal."""

    def __init__(self, closest: int, explored: int) -> None:
        super().__init__(f"no plan within the limit ({explored} configurations)")
        self.closest = closest
        self.explored = explored


@dataclass
class _Low:
    """A low-level constraint: movers ``who`` go to ``where`` in the next step."""

    who: tuple[int, ...]
    where: tuple[int, ...]


class _High:
    __slots__ = ("config", "parent", "tree", "order", "priorities")

    def __init__(self, config: tuple[int, ...], parent: _High | None,
                 priorities: list[float]) -> None:
        self.config = config
        self.parent = parent
        self.priorities = priorities
        self.order = sorted(range(len(config)), key=lambda a: -priorities[a])
        self.tree: deque[_Low] = deque([_Low((), ())])


class Space:
    """The movers' vertices, their neighbours, the cells they occupy and their distances.

    Vertices ``0 .. grid.size - 1`` are cells; ``grid.size + 2k`` is mover k's start pose and
    ``grid.size + 2k + 1`` its target pose (used only when they are not cell centres)."""

    def __init__(self, grid: RoutingGrid, agents: Sequence, dist: Sequence[dict[int, int]]
                 ) -> None:
        self.grid = grid
        self.agents = list(agents)
        self.size = grid.size
        self.dist = list(dist)
        self.starts = tuple(self.size + 2 * k if a.start_leg else a.start_cell
                            for k, a in enumerate(self.agents))
        self.goals = tuple(self.size + 2 * k + 1 if a.final_leg else a.goal_cell
                           for k, a in enumerate(self.agents))
        shapes: dict[tuple[float, float], int] = {}
        #: per mover: a key its grid moves share with the movers of its size (negative)
        self.shape = [-1 - shapes.setdefault((a.hx, a.hy), len(shapes)) for a in self.agents]
        self._near: dict[int, list[int]] = {}
        self._moves: dict[tuple[int, int, int], tuple[int, ...]] = {}
        self._near_goal: dict[tuple[int, int], float] = {}
        self._cells: dict[tuple[int, int], tuple[int, ...]] = {}
        self._ranked: dict[tuple[int, int], list[int]] = {}
        self._beside: dict[tuple[int, int, int], tuple[int, ...]] = {}

    def neighbours(self, k: int, v: int) -> list[int]:
        """Where mover k may be one step after standing on v (v itself first)."""
        agent = self.agents[k]
        if v >= self.size:
            return [v, agent.start_cell] if v == self.starts[k] else [v, agent.goal_cell]
        near = self._near.get(v)
        if near is None:
            near = [v, *(u for u in self.grid.neighbours(v))]
            self._near[v] = near
        if agent.final_leg and v == agent.goal_cell:
            return [*near, self.goals[k]]
        return near

    def _key(self, k: int, u: int, v: int) -> tuple[int, int, int]:
        return (self.shape[k] if u < self.size and v < self.size else k), u, v

    def cells(self, k: int, v: int) -> tuple[int, ...]:
        key = (self.shape[k] if v < self.size else k), v
        out = self._cells.get(key)
        if out is None:
            out = self._cells[key] = self.move(k, v, v)
        return out

    def beside(self, k: int, u: int, v: int) -> tuple[int, ...]:
        """The cells mover k's move u -> v sweeps that are under it neither before nor
        after (those beside a diagonal move)."""
        key = self._key(k, u, v)
        out = self._beside.get(key)
        if out is None:
            ends = set(self.cells(k, u)) | set(self.cells(k, v))
            out = tuple(c for c in self.move(k, u, v) if c not in ends)
            self._beside[key] = out
        return out

    def ranked(self, k: int, u: int) -> list[int]:
        """Where mover k may go from u, nearest to its target first (steps, then straight
        distance): PIBT's order of preference, fixed per vertex."""
        key = (k, u)
        out = self._ranked.get(key)
        if out is None:
            out = sorted(self.neighbours(k, u), key=lambda v: (self.h(k, v), self.near(k, v)))
            self._ranked[key] = out
        return out

    def move(self, k: int, u: int, v: int) -> tuple[int, ...]:
        """The cells mover k touches while it goes from u to v (or waits, u == v)."""
        key = self._key(k, u, v)
        out = self._moves.get(key)
        if out is None:
            agent = self.agents[k]
            if u >= self.size or v >= self.size:
                pose = u if u >= self.size else v
                cell = v if u >= self.size else u
                own = self.grid.touched_cells(cell, cell, agent.hx, agent.hy) \
                    if cell < self.size and u != v else ()
                extra = agent.start_cells if pose == self.starts[k] else agent.final_cells
                out = tuple(sorted(set(extra) | set(own)))
            else:
                out = self.grid.touched_cells(u, v, agent.hx, agent.hy)
            self._moves[key] = out
        return out

    def near(self, k: int, v: int) -> float:
        """The straight distance from v to mover k's target [mm] (breaks ties of ``h``)."""
        key = (k, v)
        out = self._near_goal.get(key)
        if out is None:
            agent = self.agents[k]
            x, y = self._point(k, v)
            out = math.hypot(agent.target[0] - x, agent.target[1] - y)
            self._near_goal[key] = out
        return out

    def _point(self, k: int, v: int) -> tuple[float, float]:
        if v < self.size:
            return self.grid.centre(v)
        agent = self.agents[k]
        return agent.start[:2] if v == self.starts[k] else agent.target[:2]

    def h(self, k: int, v: int) -> int:
        """Steps from v to mover k's target (large when cut off)."""
        agent = self.agents[k]
        if v >= self.size:
            if v == self.goals[k]:
                return 0
            v = agent.start_cell
            extra = 1
        else:
            extra = 0
        d = self.dist[k].get(v)
        if d is None:
            return 1 << 20
        return d + extra + (1 if agent.final_leg else 0)


class _Step:
    """One PIBT step from ``config`` (priority inheritance with backtracking): a mover may
    enter cells another leaves in the same step if that one goes into free cells (trains of
    two, which rules out swaps and rotations); the cells a diagonal move sweeps beside it
    must be empty before and after."""

    def __init__(self, space: Space, config: tuple[int, ...]) -> None:
        self.space = space
        self.config = config
        self.occupant: dict[int, int] = {}
        for k, v in enumerate(config):
            for cell in space.cells(k, v):
                self.occupant[cell] = k
        self.claimed: dict[int, int] = {}  #: cell -> mover there after the step
        self.swept: dict[int, int] = {}  #: cell -> mover sweeping it beside a diagonal
        self.follows: dict[int, tuple[int, ...]] = {}  #: mover -> the movers it follows
        self.followed: dict[int, int] = {}  #: mover -> how many follow it
        self.next: list[int] = [-1] * len(config)
        self.journal: list[int] = []

    def _try(self, k: int, v: int) -> tuple[int, ...] | None:
        """Assign k -> v when the cells allow it; the movers k now follows, else None."""
        space = self.space
        u = self.config[k]
        nxt = space.cells(k, v)
        claimed, swept, occupant = self.claimed, self.swept, self.occupant
        for c in nxt:
            if c in claimed or c in swept:
                return None
        beside = space.beside(k, u, v)
        for c in beside:
            if c in claimed or c in swept or occupant.get(c, k) != k:
                return None
        others = tuple({occupant[c] for c in nxt if occupant.get(c, k) != k})
        if others:  # a train: only behind movers that go into free cells
            if k in self.followed or any(o in self.follows for o in others):
                return None
            for o in others:
                self.followed[o] = self.followed.get(o, 0) + 1
            self.follows[k] = others
        self.next[k] = v
        for c in nxt:
            claimed[c] = k
        for c in beside:
            swept[c] = k
        self.journal.append(k)
        return others

    def _rollback(self, mark: int) -> None:
        space = self.space
        while len(self.journal) > mark:
            k = self.journal.pop()
            v = self.next[k]
            u = self.config[k]
            for c in space.cells(k, v):
                del self.claimed[c]
            for c in space.beside(k, u, v):
                del self.swept[c]
            self.next[k] = -1
            for o in self.follows.pop(k, ()):
                left = self.followed[o] - 1
                if left:
                    self.followed[o] = left
                else:
                    del self.followed[o]

    def force(self, k: int, v: int) -> bool:
        if v not in self.space.neighbours(k, self.config[k]):
            return False
        return self._try(k, v) is not None

    def decide(self, k: int) -> bool:
        """Give mover k its next vertex, asking the movers on it to move on first."""
        space = self.space
        u = self.config[k]
        for v in space.ranked(k, u):
            mark = len(self.journal)
            others = self._try(k, v)
            if others is None:
                continue
            if all(self.next[o] >= 0 or self.decide(o) for o in others):
                return True
            self._rollback(mark)
        return False


def pibt_step(space: Space, config: tuple[int, ...], order: Sequence[int],
              who: Sequence[int] = (), where: Sequence[int] = ()) -> tuple[int, ...] | None:
    """The next configuration, or None when the constraints ``who`` -> ``where`` clash or
    leave a mover no place."""
    step = _Step(space, config)
    for k, v in zip(who, where, strict=True):
        if not step.force(k, v):
            return None
    for k in order:
        if step.next[k] < 0 and not step.decide(k):
            return None
    return tuple(step.next)


def lacam(space: Space, work_limit: int, seed: int = 0,
          time_limit: float = 0.0) -> list[tuple[int, ...]]:
    """Configurations from the starts to the goals (each a step), by LaCAM over PIBT.

    The search gives up after ``work_limit`` PIBT steps of one mover (configurations tried x
    movers), or later, once ``time_limit`` [s] of wall clock has also passed. Without a time
    limit no clock is read, so the outcome is the same on any machine under any load
    (D-374)."""
    rng = random.Random(seed)
    started = time.perf_counter()
    n = len(space.agents)
    max_count = max(1, work_limit // max(1, n))
    start, goal = space.starts, space.goals
    priorities = [rng.random() * TIE for _ in range(n)]
    root = _High(start, None, priorities)
    explored: dict[tuple[int, ...], _High] = {start: root}
    open_: list[_High] = [root]
    best, best_h = root, sum(space.h(k, v) for k, v in enumerate(start))
    count = 0
    while open_:
        node = open_[-1]
        if node.config == goal:
            return _backtrack(node)
        count += 1
        if count > max_count and (time_limit <= 0.0 or (
                count % 8 == 0 and time.perf_counter() - started > time_limit)):
            worst = max(range(n), key=lambda k: space.h(k, best.config[k]))
            raise SearchTimeout(worst, len(explored))
        if not node.tree:
            open_.pop()
            continue
        low = node.tree.popleft()
        depth = len(low.who)
        if depth < n:
            k = node.order[depth]
            options = list(space.neighbours(k, node.config[k]))
            rng.shuffle(options)
            for v in options:
                node.tree.append(_Low((*low.who, k), (*low.where, v)))
        config = pibt_step(space, node.config, node.order, low.who, low.where)
        if config is None:
            continue
        known = explored.get(config)
        if known is not None:
            open_.append(known)  # revisit: its remaining successors are still to try
            continue
        child_priorities = [
            p + 1.0 if config[k] != goal[k] else p - int(p)
            for k, p in enumerate(node.priorities)]
        child = _High(config, node, child_priorities)
        explored[config] = child
        open_.append(child)
        h = sum(space.h(k, v) for k, v in enumerate(config))
        if h < best_h:
            best, best_h = child, h
    raise SearchExhausted(max(range(n), key=lambda k: space.h(k, best.config[k])),
                          len(explored))


def _backtrack(node: _High) -> list[tuple[int, ...]]:
    out = []
    current: _High | None = node
    while current is not None:
        out.append(current.config)
        current = current.parent
    out.reverse()
    return out


class ExecutionStuck(Exception):
    """The conversion to one-step gaps found no mover free to go on (a rotation slipped
    through): not expected for a plan of ``lacam``."""


def with_gaps(space: Space, configs: Sequence[tuple[int, ...]]) -> list[list[int]]:
    """Per mover its vertex per step, replayed so that no mover enters cells another leaves
    in the same step: each move waits until every mover that the plan lets through its
    cells before it has left them (the plan's order of passage per cell, as the router
    executes it, D-302). Acyclic for a plan without rotations, so every step some mover
    goes on."""
    n = len(space.agents)
    paths: list[list[int]] = []
    for k in range(n):
        path = [configs[0][k]]
        for config in configs[1:]:
            if config[k] != path[-1]:
                path.append(config[k])
        paths.append(path)
    # the order of passage per cell: (first half-step, agent, move index that enters it)
    visits: dict[int, list[tuple[int, int, int]]] = {}
    for k in range(n):
        index = 0
        for t, config in enumerate(configs):
            v = config[k]
            if t == 0:
                for c in space.cells(k, v):
                    visits.setdefault(c, []).append((0, k, 0))
                continue
            u = configs[t - 1][k]
            if u == v:
                continue
            index += 1
            held = space.cells(k, u)
            for c in space.move(k, u, v):
                if c not in held:
                    visits.setdefault(c, []).append((2 * t - 1, k, index))
    turn: dict[int, list[tuple[int, int]]] = {}
    for c, cell_visits in visits.items():
        cell_visits.sort()
        turn[c] = [(k, index) for _, k, index in cell_visits]
    position = [0] * n  # index into the path
    head = dict.fromkeys(turn, 0)  # per cell: whose visit is on
    timeline = [[p[0]] for p in paths]
    done = sum(len(p) == 1 for p in paths)
    while done < n:
        moving = set()
        for k in range(n):
            i = position[k]
            if i + 1 >= len(paths[k]):
                continue
            u, v = paths[k][i], paths[k][i + 1]
            if all(_turn_of(turn, head, c) == (k, i + 1) or _inside(turn, head, c, k, i)
                   for c in space.move(k, u, v)):
                moving.add(k)
        if not moving:
            raise ExecutionStuck()
        for k in range(n):
            i = position[k]
            if k in moving:
                u, v = paths[k][i], paths[k][i + 1]
                kept = space.cells(k, v)
                for c in space.move(k, u, v):  # cells it leaves: the next visitor's turn
                    if c not in kept:
                        head[c] += 1
                position[k] = i + 1
                timeline[k].append(v)
                done += position[k] + 1 == len(paths[k])
            else:
                timeline[k].append(paths[k][i])
    return timeline


def _turn_of(turn: dict[int, list[tuple[int, int]]], head: dict[int, int], c: int
             ) -> tuple[int, int] | None:
    order = turn.get(c)
    h = head.get(c, 0)
    return order[h] if order is not None and h < len(order) else None


def _inside(turn: dict[int, list[tuple[int, int]]], head: dict[int, int], c: int, k: int,
            i: int) -> bool:
    """Mover k (at path index i) holds cell c already: its visit is the current one."""
    now = _turn_of(turn, head, c)
    return now is not None and now[0] == k and now[1] <= i
