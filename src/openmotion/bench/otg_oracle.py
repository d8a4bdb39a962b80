"""The time-optimal duration of a move with acceleration != deceleration, by brute force.

For the ``otg`` benchmark and the tests only: slow (tens of thousands of ruckig calls per
move), and independent of the planner's own search in trajectory/plan.py (D-201).

The rule (PLCopen, TcMC §3.1): the acceleration is bounded by ``acceleration`` while |v|
rises and by ``deceleration`` while |v| falls. Motion in one direction maps exactly onto
ruckig's signed pair; a move that turns back is two such pieces joined where the velocity is
zero. So the optimum is the fastest of

* ruckig with the limits mapped for the direction of the move, where its profile keeps that
  direction;
* ruckig with both limits at min(acceleration, deceleration), which keeps every bound;
* a reversal: a first piece in the start's direction to a crossing state (position p_c,
  velocity 0, acceleration a_c pointing back), then a second piece to the target, each
  planned by ruckig with its own mapped limits and kept only where it does not turn back
  itself. |a_c| <= min(acceleration, deceleration), since the acceleration is continuous and
  bounds both sides. The search is a grid over (a_c, p_c), each cell refined by golden
  sections. Along p_c two grids are joined: an even one from the start, and a geometric one
  from where the hardest braking to that a_c stops (no crossing lies nearer; near it the
  first piece may be feasible only in a window narrower than the even grid's step). The
  planner's claim that this stop point is the best p_c is not assumed: both grids reach far
  beyond it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import ruckig

from openmotion.trajectory.plan import Limits, _segments, golden_minimum
from openmotion.trajectory.segments import KinematicState

ACCELERATION_CELLS = 24  #: grid lines over |a_c| in [0, min(acc, dec)]
POSITION_CELLS = 40  #: grid lines over p_c (each of the two grids)
ANCHOR_SPAN = 1e-8  #: relative to the reach: the finest step of the grid from the stop point
GOLDEN_STEPS = 40  #: golden-section steps in each refinement
REVERSAL_TOLERANCE = 1e-9  #: relative: a piece turning back by less is float residue
RETRY_FACTORS = (1.0, 1.0 - 1e-12, 1.0 - 1e-10, 1.0 - 1e-8)  #: as the otg benchmark's


@dataclass(frozen=True)
class Optimum:
    """The oracle's answer: the best duration [s] and which kind of profile gave it."""

    duration: float
    kind: str  #: "direct", "symmetric" or "reversal"
    crossing_acceleration: float | None = None  #: |a_c| of the best reversal [mm/s²]
    crossing_position: float | None = None  #: p_c of the best reversal [mm]
    #: the direction-mapped ruckig profile keeps its direction (no turn needed)
    direct_valid: bool = False


class _Pieces:
    """One ruckig instance and input, reused for every piece the search tries."""

    def __init__(self) -> None:
        self.otg = ruckig.Ruckig(1)
        self.inp = ruckig.InputParameter(1)
        self.trajectory = ruckig.Trajectory(1)
        self.velocity_input = ruckig.InputParameter(1)
        self.velocity_input.control_interface = ruckig.ControlInterface.Velocity

    def stop(self, start: KinematicState, c: float, limits: Limits, first: int) -> float:
        """Where braking as hard as the bounds allow, to zero velocity with acceleration
        -``first``·``c``, ends (ruckig's velocity interface): no crossing with that
        acceleration lies nearer, so a second grid over p_c starts there, fine near it (the
        first piece's feasible window can be narrow); the start position where ruckig
        fails."""
        inp = self.velocity_input
        inp.current_position = [start.position]
        inp.current_velocity = [start.velocity]
        inp.current_acceleration = [start.acceleration]
        inp.target_velocity = [0.0]
        inp.target_acceleration = [-first * c]
        up, down = limits.acceleration, limits.deceleration
        if first < 0:
            up, down = down, up
        inp.max_velocity = [limits.velocity]
        inp.max_acceleration, inp.min_acceleration = [up], [-down]
        inp.max_jerk = [limits.jerk]
        try:
            result = self.otg.calculate(inp, self.trajectory)
        except (ruckig.RuckigError, RuntimeError, ValueError):
            return start.position
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            return start.position
        return float(self.trajectory.profiles[0][0].p[-1])

    def duration(self, start: KinematicState, target: KinematicState, limits: Limits,
                 direction: int, up: float, down: float) -> float:
        """Duration of ruckig's move ``start`` -> ``target`` with the acceleration bounded
        by ``up`` towards ``direction`` and ``down`` against it; inf where ruckig fails or
        the profile turns against ``direction``."""
        inp = self.inp
        inp.current_position = [start.position]
        inp.current_velocity = [start.velocity]
        inp.current_acceleration = [start.acceleration]
        inp.target_position = [target.position]
        inp.target_velocity = [target.velocity]
        inp.target_acceleration = [target.acceleration]
        if direction < 0:
            up, down = down, up  # bounds of +a and -a
        for factor in RETRY_FACTORS:  # ruckig's step 1 fails on a few inputs that solve
            inp.max_velocity = [limits.velocity * factor]  # with every limit a hair lower
            inp.max_acceleration, inp.min_acceleration = [up * factor], [-down * factor]
            inp.max_jerk = [limits.jerk * factor]
            try:
                result = self.otg.calculate(inp, self.trajectory)
            except (ruckig.RuckigError, RuntimeError, ValueError):
                continue
            break
        else:
            return math.inf
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            return math.inf
        profile = _segments(self.trajectory.profiles[0][0])
        lo, hi = profile.velocity_extrema()
        tolerance = REVERSAL_TOLERANCE * max(abs(lo), abs(hi), limits.velocity * 1e-3, 1e-12)
        if (direction > 0 and lo < -tolerance) or (direction < 0 and hi > tolerance):
            return math.inf
        return float(self.trajectory.duration)


def optimal_duration(start: KinematicState, target: float, limits: Limits,
                     target_velocity: float = 0.0) -> Optimum:
    """The fastest profile from ``start`` to ``target`` (arriving with ``target_velocity``)
    that keeps the direction-dependent bounds at every instant (module docstring)."""
    pieces = _Pieces()
    acc, dec = limits.acceleration, limits.deceleration
    low = min(acc, dec)
    end = KinematicState(target, target_velocity, 0.0)
    sign = _sign(target - start.position) or _sign(target_velocity) or _sign(start.velocity) \
        or 1
    best = Optimum(pieces.duration(start, end, limits, 0, low, low), "symmetric")
    direct = pieces.duration(start, end, limits, sign, acc, dec)
    if direct < best.duration:
        best = Optimum(direct, "direct")
    heading = _sign(start.velocity) or _sign(start.acceleration)
    for first in ((heading,) if heading else (1, -1)):
        reversal = _best_reversal(pieces, start, end, limits, first)
        if reversal.duration < best.duration:
            best = reversal
    return replace(best, direct_valid=math.isfinite(direct))


def _best_reversal(pieces: _Pieces, start: KinematicState, end: KinematicState,
                   limits: Limits, first: int) -> Optimum:
    """Grid over the crossing state (|a_c|, p_c), then golden sections around the best
    cell: first along p_c for each grid |a_c|, then along |a_c| with p_c refined inside."""
    low = min(limits.acceleration, limits.deceleration)
    reach = _reach(start, limits, first)
    if reach <= 0.0:
        return Optimum(math.inf, "reversal")

    def total(c: float, p: float) -> float:
        crossing = KinematicState(p, 0.0, -first * c)
        a = pieces.duration(start, crossing, limits, first, limits.acceleration,
                            limits.deceleration)
        if math.isinf(a):
            return math.inf
        return a + pieces.duration(crossing, end, limits, -first, limits.acceleration,
                                   limits.deceleration)

    def along_p(c: float) -> tuple[float, float]:
        anchor = pieces.stop(start, c, limits, first)
        grid = np.unique(np.concatenate((
            start.position + first * reach * np.linspace(0.0, 1.0, POSITION_CELLS + 1),
            anchor + first * reach * np.concatenate(
                ([0.0], np.geomspace(ANCHOR_SPAN, 1.0, POSITION_CELLS))),
        )))
        values = [total(c, float(p)) for p in grid]
        k = int(np.argmin(values))
        if math.isinf(values[k]):
            return math.inf, float(grid[k])
        lo, hi = float(grid[max(k - 1, 0)]), float(grid[min(k + 1, len(grid) - 1)])
        p, value = _golden(lambda x: total(c, x), lo, hi)
        return (value, p) if value < values[k] else (values[k], float(grid[k]))

    grid_c = np.linspace(0.0, low, ACCELERATION_CELLS + 1)
    rows = [along_p(float(c)) for c in grid_c]
    k = int(np.argmin([r[0] for r in rows]))
    if math.isinf(rows[k][0]):
        return Optimum(math.inf, "reversal")
    lo, hi = float(grid_c[max(k - 1, 0)]), float(grid_c[min(k + 1, ACCELERATION_CELLS)])
    c, value = _golden(lambda x: along_p(x)[0], lo, hi, steps=GOLDEN_STEPS // 2)
    if value < rows[k][0]:
        return Optimum(value, "reversal", c, along_p(c)[1])
    return Optimum(rows[k][0], "reversal", float(grid_c[k]), rows[k][1])


def _reach(start: KinematicState, limits: Limits, first: int) -> float:
    """How far past the start (towards ``first``) the crossing may lie, generously: the
    fastest speed the start can still reach, held for as long as the slowest braking (at
    the lower limit, after turning the acceleration round) could take to reach zero."""
    low = min(limits.acceleration, limits.deceleration)
    v = max(start.velocity * first, 0.0)
    a = start.acceleration * first
    top = v + max(a, 0.0) ** 2 / (2.0 * limits.jerk)
    braking = (abs(a) + low) / limits.jerk + top / low
    return 1.25 * top * braking


def _golden(function, lo: float, hi: float,  # noqa: ANN001 - a float -> float callable
            steps: int = GOLDEN_STEPS) -> tuple[float, float]:
    """Golden-section minimum of ``function`` on [lo, hi]: (argument, value)."""
    return golden_minimum(function, lo, hi, steps)


def _sign(value: float) -> int:
    return int(value > 0.0) - int(value < 0.0)
