"""Properties of a planar group over random stator fields, movers and command sequences
(TF5430 §6.3, §6.4, §6.7.2).

A scenario is a rectangle of 2-5 x 2-5 stators whose environment is in an enabled group, 2-8
movers standing apart on it, and a few rounds: wait some cycles, then command several movers
in one cycle (MoveToPosition with or without a C target, MoveC, Halt), often while others
still move. At every cycle:

* no two mover footprints (155 x 155 mm turned by c) overlap with positive area,
* no footprint leaves the stator surface,
* a mover that has finished and got no new accepted command stays where it finished.

Per command:

* a command is accepted or rejected in the cycle it is sent, and a rejection changes nothing;
* an accepted command ends Done or Aborted, never Error, and only a later accepted command of
  the same mover aborts it; Halt is never rejected for a collision (it may always brake);
* a MoveToPosition (MoveC) that ends Done ends exactly on its target (1e-9 mm, 1e-9 deg);
* a PLANAR_COLLISION rejection names a real blocker: another member mover whose reserved area
  at the moment of the decision meets the requested area, or the environment when the
  requested area leaves the surface;
* and, so that an implementation that refuses everything cannot pass, a command is not
  rejected for a collision when even a generous cover of its path meets no other reserved area
  and stays on the surface.

The requested area is not observable, so the test bounds it by geometry of its own:

* a straight move without a turn, from rest: exactly the hull of the start and end
  footprints (reservation.py), so blocker, touching and surface checks are exact;
* a move or a turn in place from rest with a turn: inside, the end footprints, the inscribed
  circle's sweep and (in place) the footprints at every angle; outside, the hull of all
  footprints grown by r * the largest turn between path samples (reservation.py's
  construction, ``TURN_GROWTH``);
* a command to a moving mover: the centre brakes along its present velocity (at most the
  time-optimal stopping distance with its default dynamics), then runs straight to the target
  (D-090), or, for a MoveC, stays on the path it has reserved; every footprint lies within the
  half diagonal of the hull of those points.

``COVER_SLACK`` adds float and polygon slack. GEOS overlay can lose an overlap of nearly
coincident edges, so decisive checks use DE-9IM predicates and a separating-axis test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Point, Polygon, box
from shapely.geometry.base import BaseGeometry

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    MoverVector,
    PlanarCommand,
    PlanarMoverParameters,
    PlanarObjectType,
    PlanarState,
    PositionXYC,
)
from openmotion.planar.feedback import CommandPhase

STATOR = 240.0
SIDE = 155.0
HALF = SIDE / 2
HALF_DIAGONAL = math.hypot(HALF, HALF)
COVER_SLACK = 2.0  #: [mm] float and polygon slack on top of the documented construction
#: [deg] the largest turn between two path samples: the default C velocity (360°/s) over the
#: 10-cycle sample step of mover.py. A turning run's hull grows by g = r * that turn
#: (reservation.py); each corner becomes a square of half-side g, so by at most g * sqrt(2).
SAMPLE_TURN = 360.0 * 0.010
TURN_GROWTH = HALF_DIAGONAL * math.radians(SAMPLE_TURN) * math.sqrt(2)
EXACT = 1e-9  #: [mm], [deg] a finished move is on its target
ANGLE_STEP = 1.0  #: [deg] turned footprints are sampled this finely
AREA = 1e-6  #: [mm²] a smaller overlap of a path with a reservation is rounding
GRID = 2.5  #: [mm] starts and targets on this grid: touching footprints happen often
SETTLE_CYCLES = 5000  #: a scenario's commands must all have ended within this many cycles

# -- scenarios ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class Move:
    mover: int
    x: float
    y: float
    c: float


@dataclass(frozen=True)
class MoveC:
    mover: int
    c: float


@dataclass(frozen=True)
class Halt:
    mover: int


Action = Move | MoveC | Halt


@dataclass(frozen=True)
class Scenario:
    columns: int
    rows: int
    starts: tuple[tuple[float, float], ...]
    rounds: tuple[tuple[int, tuple[Action, ...]], ...]  #: (cycles to wait, same-cycle calls)


def _on_grid(low: float, high: float) -> st.SearchStrategy[float]:
    return st.integers(math.ceil(low / GRID), math.floor(high / GRID)).map(lambda n: n * GRID)


def _apart(a: tuple[float, float], b: tuple[float, float]) -> bool:
    """Two footprints at c = 0 overlap with positive area unless one coordinate differs by a
    whole side (touching is allowed)."""
    return abs(a[0] - b[0]) >= SIDE or abs(a[1] - b[1]) >= SIDE


@st.composite
def scenarios(draw: st.DrawFn) -> Scenario:
    columns, rows = draw(st.integers(2, 5)), draw(st.integers(2, 5))
    width, height = columns * STATOR, rows * STATOR
    wanted = draw(st.integers(2, 8))
    starts: list[tuple[float, float]] = []
    for _ in range(wanted):
        for _attempt in range(12):
            start = (draw(_on_grid(HALF, width - HALF)), draw(_on_grid(HALF, height - HALF)))
            if all(_apart(start, other) for other in starts):
                starts.append(start)
                break
    count = len(starts)
    if count < 2:  # a crowded small field: put two movers side by side in a corner
        starts = [(HALF, HALF), (HALF + SIDE, HALF)]
        count = 2
    mover = st.integers(0, count - 1)
    c_target = st.one_of(st.just(0.0), _on_grid(-15.0, 15.0))
    # targets reach the whole rectangle: centres near an edge put the footprint off the surface
    move = st.builds(Move, mover, _on_grid(0.0, width), _on_grid(0.0, height), c_target)

    def near(i: int) -> st.SearchStrategy[Move]:  # short moves: more of them get through
        x, y = starts[i]
        return st.builds(Move, st.just(i), _on_grid(max(x - 250.0, 0.0), min(x + 250.0, width)),
                         _on_grid(max(y - 250.0, 0.0), min(y + 250.0, height)), c_target)

    turn = st.builds(MoveC, mover, st.sampled_from([0.0, 10.0, -15.0, 30.0, 45.0, 90.0]))
    action = st.one_of(move, mover.flatmap(near), mover.flatmap(near), turn,
                       st.builds(Halt, mover))
    same_cycle = st.lists(action, min_size=1, max_size=4, unique_by=lambda a: a.mover)
    rounds = draw(st.lists(st.tuples(st.integers(0, 250), same_cycle.map(tuple)),
                           min_size=1, max_size=6))
    return Scenario(columns, rows, tuple(starts), tuple(rounds))


# -- the geometric oracle ----------------------------------------------------------------------


def square(x: float, y: float, c: float) -> Polygon:
    """The test's own footprint: the 155 mm square centred on (x, y), turned by c [deg]."""
    cos, sin = math.cos(math.radians(c)), math.sin(math.radians(c))
    return Polygon([(x + cos * u - sin * v, y + sin * u + cos * v)
                    for u, v in ((-HALF, -HALF), (HALF, -HALF), (HALF, HALF), (-HALF, HALF))])


def stop_distance(speed: float, acceleration: float, deceleration: float, jerk: float) -> float:
    """An upper bound of the time-optimal jerk-limited stopping distance [mm] from ``speed``
    with ``acceleration`` along the motion (a negative one only shortens the stop)."""
    if speed <= 0.0:
        return 0.0
    gain = max(acceleration, 0.0)
    distance = (speed + gain * gain / (2 * jerk)) * gain / jerk  # take the acceleration out
    speed += gain * gain / (2 * jerk)
    if speed >= deceleration * deceleration / jerk:
        return distance + speed * speed / (2 * deceleration) + speed * deceleration / (2 * jerk)
    return distance + speed * math.sqrt(speed / jerk)


@dataclass(frozen=True)
class Bounds:
    """What the test knows of a requested area A, as lists of pieces (no overlay union, which
    GEOS may get wrong for nearly coincident edges): A contains every piece of ``lower``
    (None: nothing certain), the pieces of ``upper`` together contain A; ``exact`` when A is
    the single piece of ``lower`` itself."""

    lower: tuple[BaseGeometry, ...] | None
    upper: tuple[BaseGeometry, ...]
    exact: bool = False


def sweep_from_rest(p0: tuple[float, float], c0: float, p1: tuple[float, float],
                    c1: float) -> Bounds:
    """A straight move (or a turn in place) from rest, C going monotonically from c0 to c1.

    Without a turn the area is exactly the hull of the two footprints (reservation.py). With
    one, each footprint on the way is turned by some angle in [c0, c1], so it lies in the hull
    of the end footprints at that angle (angles sampled every ``ANGLE_STEP`` miss at most
    R * step² / 8 = 0.004 mm): that union is inside A. A covers each run by the hull of its
    footprints grown by g (reservation.py: it bridges the dents a turning square leaves), so A
    lies in the hull of all of them grown by ``TURN_GROWTH``."""
    if c0 == c1:
        hull = shapely.convex_hull(shapely.MultiPolygon([square(*p0, c0), square(*p1, c0)]))
        return Bounds((hull,), (hull.buffer(COVER_SLACK),), exact=True)
    angles = np.linspace(c0, c1, max(2, math.ceil(abs(c1 - c0) / ANGLE_STEP) + 1))
    squares = [square(*p, a) for a in angles for p in (p0, p1)]
    upper = shapely.convex_hull(shapely.MultiPolygon(squares)).buffer(TURN_GROWTH + COVER_SLACK)
    if p0 == p1:  # a turn in place: the sampled footprints are in A
        return Bounds(tuple(squares[::2]), (upper,))
    disc = LineString([p0, p1]).buffer(HALF)  # the inscribed circle's sweep
    return Bounds((square(*p0, c0), square(*p1, c1), disc), (upper,))


def move_while_moving(mover: MC_PlanarMover, target: tuple[float, float]) -> Bounds:
    """A MoveToPosition sent while the mover moves: it brakes along its present velocity, then
    runs straight to the target, so every footprint lies within the half diagonal of the hull
    of (start, farthest stop, target)."""
    setpoints = mover.mc_to_plc.set
    p = np.array([setpoints.set_pos.x, setpoints.set_pos.y])
    v = np.array([setpoints.set_velo.x, setpoints.set_velo.y])
    a = np.array([setpoints.set_acc.x, setpoints.set_acc.y])
    speed = float(np.hypot(*v))
    points = [tuple(p), target]
    if speed > 0.0:
        direction = v / speed
        limits = mover.parameters.default_dynamic_xy
        reach = stop_distance(speed, float(a @ direction), limits.deceleration, limits.jerk)
        points.append(tuple(p + (1.05 * reach + 2.0 + speed * 2e-3) * direction))
    hull = shapely.MultiPoint(points).convex_hull
    return Bounds(None, (hull.buffer(HALF_DIAGONAL + TURN_GROWTH + COVER_SLACK),))


def turn_while_moving(mover: MC_PlanarMover, reserved: BaseGeometry) -> Bounds:
    """A MoveC sent while the mover moves: the centre stays on the path it has reserved (the
    reservation holds its centre now and later), so every run's hull of footprints lies in
    the hull of that reservation grown by the half diagonal, at any angle."""
    centre = Point(mover.position.x, mover.position.y)
    hull = shapely.convex_hull(shapely.GeometryCollection([reserved, centre]))
    return Bounds(None, (hull.buffer(HALF_DIAGONAL + TURN_GROWTH + COVER_SLACK),))


def overlap(a: BaseGeometry, b: BaseGeometry) -> float:
    """The overlap area. GEOS overlay may lose it for nearly coincident edges (two squares
    1e-14 mm apart gave 0 instead of 24025 mm²), so use it only where a wrong 0 makes the test
    miss, never where it would make it fail."""
    return a.intersection(b).area


def meets(a: BaseGeometry, b: BaseGeometry) -> bool:
    """Interiors intersect (positive-area overlap): a robust DE-9IM predicate."""
    return bool(a.relate_pattern(b, "T********"))


def corners(polygon: Polygon) -> np.ndarray:
    return np.asarray(polygon.exterior.coords)[:-1]


def penetration(a: np.ndarray, b: np.ndarray) -> float:
    """How deep two convex polygons (corner arrays) overlap [mm]; <= 0 when they are apart or
    only touch (separating axis theorem, no overlay)."""
    depth = math.inf
    for polygon in (a, b):
        edges = np.roll(polygon, -1, axis=0) - polygon
        for nx, ny in np.column_stack([-edges[:, 1], edges[:, 0]]):
            normal = np.array([nx, ny]) / math.hypot(nx, ny)
            pa, pb = a @ normal, b @ normal
            depth = min(depth, min(pa.max(), pb.max()) - max(pa.min(), pb.min()))
    return depth


# -- running a scenario ------------------------------------------------------------------------


@dataclass
class Sent:
    """One call the scenario made and what the test knows about it."""

    action: Action
    mover: MC_PlanarMover
    command: PlanarCommand
    cycle: int
    accepted: bool = False


@dataclass
class World:
    rt: om.Runtime
    environment: MC_PlanarEnvironment
    group: MC_PlanarGroup
    movers: list[MC_PlanarMover]
    width: float
    height: float
    cycle: int = 0
    open: list[Sent] = field(default_factory=list)  #: accepted, not yet ended
    resting: dict[int, tuple[float, float, float]] = field(default_factory=dict)

    def step(self) -> None:
        self.rt.step()
        self.cycle += 1
        self.check_cycle()

    def check_cycle(self) -> None:
        """The per-cycle invariants: apart, on the surface, enabled, resting movers rest."""
        prints = [corners(mover.footprint()) for mover in self.movers]
        centres = np.array([[m.position.x, m.position.y] for m in self.movers])
        for mover, footprint in zip(self.movers, prints, strict=True):
            assert mover.state is PlanarState.ENABLED and not mover.error, (mover, mover.message)
            p = mover.position
            mine = corners(square(p.x, p.y, p.c))
            miss = np.hypot(*(footprint[:, None] - mine[None]).transpose(2, 0, 1)).min(axis=1)
            assert len(footprint) == 4 and miss.max() < 1e-9, \
                f"{mover.name}.footprint() is not the 155 mm square at {p}"
            low_x, low_y = footprint.min(axis=0)
            high_x, high_y = footprint.max(axis=0)
            assert low_x >= -1e-9 and low_y >= -1e-9 and high_x <= self.width + 1e-9 \
                and high_y <= self.height + 1e-9, \
                f"cycle {self.cycle}: {mover.name} at {mover.position} leaves the surface"
            if mover.mc_to_plc.std.busy.busy_mover or any(s.mover is mover for s in self.open):
                continue
            x, y, c = self.resting.setdefault(mover.oid, (p.x, p.y, p.c))
            assert max(abs(p.x - x), abs(p.y - y), abs(p.c - c)) <= EXACT, \
                f"cycle {self.cycle}: {mover.name} at rest drifts from {(x, y, c)} to {p}"
        near = np.argwhere(np.hypot(*(centres[:, None] - centres[None]).transpose(2, 0, 1))
                           < 2 * HALF_DIAGONAL)
        for i, j in near[near[:, 0] < near[:, 1]]:
            depth = penetration(prints[i], prints[j])
            assert depth <= EXACT, (f"cycle {self.cycle}: {self.movers[i].name} at "
                                    f"{self.movers[i].position} and {self.movers[j].name} at "
                                    f"{self.movers[j].position} overlap {depth:g} mm deep")

    def reserved(self) -> dict[int, BaseGeometry]:
        return {m.oid: self.group.reserved(m.member) for m in self.movers}

    def send(self, actions: tuple[Action, ...]) -> list[Sent]:
        """Call ``actions`` in one cycle and check how each was decided."""
        before = self.reserved()
        sent = [self._call(action) for action in actions]
        bounds = [self._bounds(s, before) for s in sent]
        running = list(self.open)
        self.step()
        after = self.reserved()
        at_decision = dict(before)  # the areas each decision saw: earlier calls count
        for s, bound in zip(sent, bounds, strict=True):
            self._decided(s, bound, at_decision)
            if s.accepted:
                at_decision[s.mover.oid] = after[s.mover.oid]
        restarted = {s.mover.oid for s in sent if s.accepted}
        for s in running:
            if s.command.phase is CommandPhase.ABORTED:
                assert s.mover.oid in restarted, f"{s.action} aborted without a new command"
        self.open += [s for s in sent if s.accepted]
        self._ended()
        return sent

    def _call(self, action: Action) -> Sent:
        mover = self.movers[action.mover]
        if isinstance(action, Move):
            command = mover.move_to_position(PositionXYC(action.x, action.y, action.c))
        elif isinstance(action, MoveC):
            command = mover.move_c(action.c)
        else:
            command = mover.halt()
        return Sent(action, mover, command, self.cycle)

    def _bounds(self, sent: Sent, reserved: dict[int, BaseGeometry]) -> Bounds | None:
        mover, action, p = sent.mover, sent.action, sent.mover.position
        at_rest = not mover.mc_to_plc.std.busy.busy_mover
        if isinstance(action, Move):
            if at_rest:
                return sweep_from_rest((p.x, p.y), p.c, (action.x, action.y), action.c)
            return move_while_moving(mover, (action.x, action.y))
        if isinstance(action, MoveC):
            if at_rest:
                return sweep_from_rest((p.x, p.y), p.c, (p.x, p.y), action.c)
            return turn_while_moving(mover, reserved[mover.oid])
        return None  # Halt: stays on the path already reserved

    def _decided(self, s: Sent, bounds: Bounds | None,
                 reserved: dict[int, BaseGeometry]) -> None:
        command = s.command
        assert command.phase is not CommandPhase.SENT, f"{s.action} undecided after its cycle"
        others = {oid: area for oid, area in reserved.items() if oid != s.mover.oid}
        surface = box(0.0, 0.0, self.width, self.height)
        where = f"{s.action} of {s.mover.name} at {s.mover.position}"
        if command.phase is not CommandPhase.ERROR:
            s.accepted = True
            self.resting.pop(s.mover.oid, None)
            if bounds is not None and bounds.lower is not None:  # it must have been refused
                for oid, area in others.items():
                    deepest = max(overlap(piece, area) for piece in bounds.lower)
                    assert deepest <= AREA, (f"{where} accepted, though its path crosses "
                                             f"{deepest:g} mm² of what 16#{oid:08X} holds")
                grown = surface.buffer(1e-6, join_style="mitre")
                assert all(grown.covers(piece) for piece in bounds.lower), \
                    f"{where} accepted, though its path leaves the surface"
            return
        assert bounds is not None, f"Halt rejected: {command.message}"
        if command.error_id != ErrorId.PLANAR_COLLISION:
            return  # e.g. PLANAR_WRONG_MODE while turned out of the C windows
        # not refused for nothing: something must be in the way
        for pieces in (bounds.lower, bounds.upper) if bounds.exact else (bounds.upper,):
            free = not any(meets(piece, other) for piece in pieces for other in others.values())
            on_surface = all(surface.covers(piece) for piece in pieces)
            assert not (free and on_surface), \
                f"{where} refused though nothing is in its way: {command.message}"
        # and the blocker named is one
        info = command.object_info
        if info.object_type is PlanarObjectType.ENVIRONMENT:
            assert info.id == self.environment.oid, info
            assert not all(surface.covers(piece) for piece in bounds.upper), \
                f"{where} blamed on the environment, but stays on the surface"
            return
        assert info.object_type is PlanarObjectType.MOVER, info
        assert info.id in others, f"{where}: blocker 16#{info.id:08X} is no other member"
        nearest = [p.buffer(1e-6) for p in bounds.lower] if bounds.exact else bounds.upper
        assert any(meets(others[info.id], piece) for piece in nearest), (
            f"{where}: blocker 16#{info.id:08X} holds {others[info.id].wkt[:160]}..., "
            "nowhere on the path")

    def _ended(self) -> None:
        """Commands that ended in this cycle: Done on target, or Aborted; never Error."""
        still = []
        for s in self.open:
            phase = s.command.phase
            if phase in (CommandPhase.ACTIVE, CommandPhase.ACCEPTED):
                still.append(s)
                continue
            assert phase is not CommandPhase.ERROR, f"{s.action} failed: {s.command.message}"
            if phase is CommandPhase.DONE:
                p = s.mover.position
                if isinstance(s.action, Move):
                    miss = max(abs(p.x - s.action.x), abs(p.y - s.action.y),
                               abs(p.c - s.action.c))
                    assert miss <= EXACT, f"{s.action} done at {p}: {miss:g} off"
                elif isinstance(s.action, MoveC):
                    assert abs(p.c - s.action.c) <= EXACT, f"{s.action} done at c = {p.c!r}"
        self.open = still


def build(scenario: Scenario) -> World:
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    for i in range(scenario.columns):
        for j in range(scenario.rows):
            environment.add_stator(STATOR * i, STATOR * j)
    environment.create_boundary()
    group = MC_PlanarGroup(rt)
    group.enable()
    movers = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x, y)))
              for x, y in scenario.starts]
    for mover in movers:
        mover.enable()
    rt.run_until(lambda: all(m.state is PlanarState.ENABLED for m in movers)
                 and group.state is PlanarState.ENABLED, timeout=0.1)
    joins = [mover.add_to_group(group) for mover in movers]
    joins.append(environment.add_to_group(group))
    rt.step()
    assert all(join.done for join in joins), [(j.kind, j.message) for j in joins]
    world = World(rt, environment, group, movers, scenario.columns * STATOR,
                  scenario.rows * STATOR)
    world.check_cycle()
    return world


def run(scenario: Scenario) -> None:
    world = build(scenario)
    for wait, actions in scenario.rounds:
        for _ in range(wait):
            world.step()
            world._ended()
        world.send(actions)
    run_to_rest(world)


def run_to_rest(world: World) -> None:
    for _ in range(SETTLE_CYCLES):
        if not world.open and not any(m.mc_to_plc.std.busy.busy_mover for m in world.movers):
            return
        world.step()
        world._ended()
    raise AssertionError(f"still running after {SETTLE_CYCLES} cycles: {world.open}")


# -- the tests ---------------------------------------------------------------------------------

_QUICK = settings(max_examples=25, deadline=None,
                  suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
_LONG = settings(max_examples=1000, deadline=None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@_QUICK
@given(scenario=scenarios())
def test_group_keeps_movers_apart_on_the_surface_and_names_real_blockers(scenario: Scenario):
    run(scenario)


@pytest.mark.slow
@_LONG
@given(scenario=scenarios())
def test_group_keeps_movers_apart_on_the_surface_and_names_real_blockers_long(
        scenario: Scenario):
    run(scenario)


def test_the_oracle_blames_a_mover_that_stands_in_the_way():
    """§6.3.2's situation on a surface: mover two to where mover one stands is refused, with
    mover one named; the oracle's checks run on the decision."""
    world = build(Scenario(3, 2, ((120.0, 120.0), (360.0, 120.0)), ()))
    mover_one, mover_two = world.movers
    (sent,) = world.send((Move(1, 120.0, 120.0, 0.0),))
    assert sent.command.error and sent.command.error_id == ErrorId.PLANAR_COLLISION
    assert sent.command.object_info.id == mover_one.oid
    run_to_rest(world)
    assert (mover_two.position.x, mover_one.position.x) == (360.0, 120.0)


def test_touching_footprints_do_not_collide():
    """Mover two stops with its edge on mover one's (x = 197.5): touching is not meeting."""
    world = build(Scenario(3, 2, ((120.0, 120.0), (360.0, 120.0)), ()))
    world.send((Move(1, 275.0, 120.0, 0.0),))
    assert world.open, "the move was refused"
    run_to_rest(world)
    assert world.movers[1].position.x == 275.0


@pytest.mark.parametrize("c_target", [0.0, 5.0], ids=["c-stays", "c-turns"])
def test_move_c_aborts_a_move_to_position_that_drives_c(c_target: float):
    """D-082: MoveToPosition with useOrientation drives x, y and c, so a MoveC aborts it and
    x, y go on to the target without a command, whether or not the move's C has to turn
    (D-091 only skips planning a C that stays). A move that is not aborted must end Done on
    its whole target, c included."""
    rt = om.Runtime()
    mover = MC_PlanarMover(rt)
    mover.enable()
    rt.run(0.003)
    move = mover.move_to_position(PositionXYC(100.0, 0.0, c_target))
    rt.run(0.02)
    turn = mover.move_c(10.0)
    rt.run_until(lambda: not move.busy and not turn.busy
                 and not mover.mc_to_plc.std.busy.busy_mover, timeout=5.0)
    assert turn.done
    assert move.phase is CommandPhase.ABORTED, (move.phase, mover.position)
    assert (mover.position.x, mover.position.y, mover.position.c) == (100.0, 0.0, 10.0)


@pytest.mark.parametrize("c_start", [0.0, 10.0, -15.0])
def test_a_turn_in_place_is_not_refused_by_a_mover_out_of_reach(c_start: float):
    """A square turning in place stays in the disc of its half diagonal r = 109.6 mm; the
    documented cover adds g * sqrt(2) <= 9.7 mm (``TURN_GROWTH``). A mover standing 125 mm
    from the centre cannot be in the way of a turn to 90°, whatever C it starts from."""
    world = build(Scenario(4, 4, ((360.0, 360.0), (360.0 - 125.0 - HALF, 360.0)), ()))
    if c_start:
        world.send((MoveC(0, c_start),))
        run_to_rest(world)
    assert HALF_DIAGONAL + TURN_GROWTH + COVER_SLACK < 125.0
    (sent,) = world.send((MoveC(0, 90.0),))
    assert sent.accepted, (sent.command.message, sent.command.object_info)
    run_to_rest(world)
    assert world.movers[0].position.c == 90.0


def test_the_stop_distance_bound_matches_the_closed_forms():
    # from 2000 mm/s with 10000 mm/s², 200000 mm/s³: 200 mm of braking plus 50 mm of ramps
    assert stop_distance(2000.0, 0.0, 10000.0, 200000.0) == pytest.approx(250.0)
    # below D²/J = 500 mm/s the brake never reaches full deceleration: v * sqrt(v / J)
    assert stop_distance(100.0, 0.0, 10000.0, 200000.0) == pytest.approx(100.0 * math.sqrt(
        100.0 / 200000.0))
    assert stop_distance(0.0, 5000.0, 10000.0, 200000.0) == 0.0
    assert stop_distance(1000.0, 5000.0, 10000.0, 200000.0) > stop_distance(
        1000.0, 0.0, 10000.0, 200000.0)


def test_penetration_tells_overlap_from_touching():
    a = corners(square(0.0, 0.0, 0.0))
    assert penetration(a, corners(square(155.0, 0.0, 0.0))) == pytest.approx(0.0, abs=1e-12)
    assert penetration(a, corners(square(154.0, 10.0, 0.0))) == pytest.approx(1.0)
    assert penetration(a, corners(square(0.0, 200.0, 45.0))) < 0.0
    # the GEOS case: two copies 1e-14 mm apart overlap completely
    b = corners(square(282.5, 132.5, 55.79999999999998))
    assert penetration(b, b + 1e-14) == pytest.approx(155.0)
