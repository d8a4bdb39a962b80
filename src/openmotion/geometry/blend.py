"""Contour curves that round the corner between two segments (PLCopen Part 4 §7.4.4, §7.4.5).

Shape. Part 4 leaves the contour's shape to the supplier (§2.4.1, §7.4). Ours is one quintic
Bézier curve that matches position, unit tangent and curvature vector of both trimmed segments
at its ends, so curvature is continuous along the whole path (G2). Why:

- The textbook circular fillet makes the curvature jump from 0 (or 1/R of an arc) to 1/r at both
  joins, so the normal acceleration v²κ jumps at full path speed. A jerk-limited interpolator or
  a servo follows such a step only with overshoot: the 2-8x acceleration peaks that users of
  other controllers report on small blends. Matching the curvature removes the step.
- One polynomial serves lines and arcs alike, in 3-D and in closed form; clothoids need an
  iterative fit and have none for arcs in different planes.
- The inner control points lie at h and 2h along the end tangents, plus the curvature term
  1.25·h²·κN that makes the ends G2. We take h = 0.375·|S2' - E1'|/(1+c), with c = cos(ψ/2)
  for a turn ψ between the end tangents. Between two lines the chord |S2' - E1'| is 2·d·c (d
  the corner distance), so h = 0.75·d·c/(1+c): a sweep over ψ chose it, the peak curvature
  stays within 1.27x that of the circular fillet with the same d (tan(ψ/2)/d) and the
  curvature rate (the jerk v³·dκ/ds) stays moderate. A shorter h brings the peak down towards
  1.03x but makes the rate grow steeply; a longer one does the reverse. Next to an arc the
  trimmed tangents turn by more than the corner while the chord stays wide: near a half turn
  h from d·c shrank to 1/200 of the chord and the curve bent on a radius of 1/2000 of its
  length (decisions D-138); h from the chord keeps the peak curvature within about 2.5x of
  the circle through both ends that turns as far (tests/geometry/test_blend.py).

``max_curvature`` bounds the contour speed: v <= sqrt(a_max / max_curvature) (§7.4.3-§7.4.5:
curvature and acceleration may keep the blending velocity from being reached).

Parameters. The corner distance d (§1.4, §7.1) is the straight distance from the corner to the
contour's start E1' and to its end S2' (TF5410's "tolerance ball"; along a line it is the path
distance). A segment gives up at most its half to a blend, so that the blend at its other end
fits too: d is clamped to the distance from the corner to the nearer segment midpoint and the
same d applies on both sides (§7.4.4 has one parameter). An arc gives up at most so much that
the path the contour replaces turns by less than half a turn: with θ the corner's turn, the
trimmed pieces of the arcs turn by at most ``_WINDING`` of π - θ together (each by
2·asin(d/2r)). A contour only knows its end tangents, which cannot tell a turn ψ from 2π - ψ,
so beyond half a turn it bends the other way or loops on a tiny radius (D-138). Either clamp
shortens the blend, as §7.4 lets the supplier; ``Blend.clamped`` reports it. The
corner deviation e (§1.4) is the shortest distance from the corner to the contour; for a
requested e we solve for d so that the deviation equals e, or take the largest d when even that
stays below e.

The other transition modes are velocity rules that reuse these segments (§7.4.1-§7.4.3): TMNone
inserts no contour (the path stops at the corner, as Buffered); for TMStartVelocity the planner
finds where the pre-block's deceleration reaches TPStartVelocity % of its velocity and passes
that point's distance to the corner to ``corner_distance_blend``; for TMConstantVelocity it picks
the d whose ``max_curvature`` lets the contour run at TPVelocity % of the transition velocity
(between lines max_curvature is proportional to 1/d).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.geometry.path import TOLERANCE, Arc, Segment, Vector, as_point

REVERSAL_ANGLE = 1e-6  #: [rad] a corner turning back by more than π minus this cannot blend
_HANDLE = 0.375  #: h = _HANDLE·|S2' - E1'|/(1+c), see the module docstring
_WINDING = 0.75  #: of π minus the corner's turn, the most the trimmed arcs may turn (module text)
_PIECES = 64  #: pieces of the curve parameter in the arc-length table
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(8)
_NEWTON = 3  #: Newton steps from arc length to curve parameter: two reach round-off already
_SAMPLES = 257  #: samples before refining an extremum
_ZOOMS = 6  #: zoom steps around a sampled extremum, 16x finer each
_REGULAR = 1e-6  #: smallest parametric speed, relative to the largest, before we call it a cusp
_PEAKS_SAMPLES = 513  #: samples of ``_peaks``
_CANDIDATES = 3  #: sampled peaks per column that ``_peaks`` refines
_MAX_ZOOMS = 12  #: zoom steps of ``_peaks`` at most, 4x finer each
_BEND = 2e-4  #: ``_peaks`` zooms until its curvature allowance is below this share of the peak
BOUND_MARGIN = 1e-9  #: relative, added to the refined peaks of ``Contour.derivative_bounds``


def _bernstein(degree: int, u: NDArray[np.float64]) -> NDArray[np.float64]:
    k = np.arange(degree + 1)
    binomial = np.array([math.comb(degree, i) for i in k], dtype=float)
    u = u[..., None]
    return binomial * u**k * (1.0 - u) ** (degree - k)


def _monomial(degree: int) -> NDArray[np.float64]:
    """Bernstein to power basis: row k holds the weights of the control points in u**k."""
    matrix = np.zeros((degree + 1, degree + 1))
    for k in range(degree + 1):
        for i in range(k + 1):
            matrix[k, i] = math.comb(degree, i) * math.comb(degree - i, k - i) * (-1) ** (k - i)
    return matrix


def _reject(message: str) -> CommandRejected:
    return CommandRejected(ErrorId.INVALID_PATH_GEOMETRY, message)


class Contour:
    """Quintic Bézier from ``start`` to ``end`` matching unit tangents and curvature vectors.

    ``handle`` [mm] is the distance of the second control point from the first (and of the
    fifth from the last). Control points are kept relative to ``start`` so that round-off
    scales with the contour, not with the coordinates: small blends keep exact curvature.
    """

    def __init__(self, start: ArrayLike, start_tangent: ArrayLike,
                 start_curvature_vector: ArrayLike, end: ArrayLike, end_tangent: ArrayLike,
                 end_curvature_vector: ArrayLike, handle: float) -> None:
        self.start, self.end = as_point(start, "start"), as_point(end, "end")
        t0, t1 = as_point(start_tangent, "tangent"), as_point(end_tangent, "tangent")
        k0 = as_point(start_curvature_vector, "curvature vector")
        k1 = as_point(end_curvature_vector, "curvature vector")
        if not (math.isfinite(handle) and handle > 0.0):
            raise _reject("contour: the handle length must be > 0")
        if min(np.linalg.norm(t0), np.linalg.norm(t1)) == 0.0:
            raise _reject("contour: zero tangent vector")
        t0, t1 = t0 / np.linalg.norm(t0), t1 / np.linalg.norm(t1)
        step = np.empty((5, 3))  # differences of consecutive control points
        bend0, bend1 = 1.25 * handle**2 * k0, 1.25 * handle**2 * k1  # B''(0) = (5·handle)²·k0
        step[0] = handle * t0
        step[1] = step[0] + bend0
        step[4] = handle * t1
        step[3] = step[4] - bend1
        step[2] = (self.end - self.start) - step[0] - step[1] - step[3] - step[4]
        #: the control points less the start [mm]
        self.control_offsets = np.vstack([np.zeros(3), np.cumsum(step, axis=0)])
        self._first = 5.0 * step
        self._second = 20.0 * np.diff(step, axis=0)
        # the ends exactly: on a contour much smaller than the radii next to it, bend is
        # rounding against handle·t, and the difference above loses the curvature's digits
        self._second[0], self._second[3] = 20.0 * bend0, 20.0 * bend1
        self._power = _monomial(4) @ self._first  # B' in powers of u, for fast arc lengths
        self.control_points = self.start + self.control_offsets  #: [mm], for plots
        speed = self._speed(np.linspace(0.0, 1.0, _SAMPLES))
        if not np.all(np.isfinite(speed)) or speed.min() <= _REGULAR * speed.max():
            raise _reject("contour: the curve would stop in a cusp (turn too close to 180°)")

    @classmethod
    def from_arrays(cls, start: Vector, end: Vector, control_offsets: Vector, first: Vector,
                    second: Vector, power: Vector, arc_length_table: NDArray[np.float64],
                    derivatives_in_powers: Vector) -> Contour:
        """A contour whose arrays a batch builder computed for many at once, as ``__init__``
        would to round-off, its checks passed (coordinated/dense.py): ``first`` = 5 x the
        control-point steps, ``second`` = 20 x their differences, ``power`` = B' in powers
        of u, ``derivatives_in_powers`` as the property. Skips the per-contour numpy calls
        that dominate a dense path's preparation."""
        self = cls.__new__(cls)
        self.start, self.end, self.control_offsets = start, end, control_offsets
        self._first, self._second, self._power = first, second, power
        self.control_points = start + control_offsets
        self.__dict__["arc_length_table"] = arc_length_table
        self.__dict__["derivatives_in_powers"] = derivatives_in_powers
        return self

    @property
    def power(self) -> Vector:
        """B' in powers of u: (5, 3), row k the coefficient of u**k."""
        return self._power

    def keep_derivative_bounds(self, bounds: Vector) -> None:
        """Take ``bounds`` (3, 3) as ``derivative_bounds``, computed by the same sampling for
        many contours at once (coordinated/dense_kernels.py)."""
        self.__dict__["_derivative_bounds"] = bounds

    def __repr__(self) -> str:
        return (f"Contour(start={self.start.tolist()}, end={self.end.tolist()}, "
                f"length={self.length:.6g})")

    def _derivative(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        return _bernstein(4, u) @ self._first

    def _speed(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """|B'(u)| by Horner's rule, one coordinate at a time: arc lengths evaluate it most."""
        total = np.zeros(np.shape(u))
        for power in self._power.T:
            value = power[4] * u + power[3]
            for coefficient in power[2::-1]:
                value = value * u + coefficient
            total += value * value
        return np.sqrt(total)

    def _integral(self, lo: NDArray[np.float64], hi: NDArray[np.float64]) -> NDArray[np.float64]:
        """Arc length between two curve parameters, 8-point Gauss-Legendre."""
        half = 0.5 * (hi - lo)
        u = (lo + half)[..., None] + half[..., None] * _NODES
        return half * (self._speed(u) @ _WEIGHTS)

    @cached_property
    def arc_length_table(self) -> NDArray[np.float64]:
        """Arc length [mm] at the curve parameters k/_PIECES, k = 0.._PIECES."""
        edges = np.linspace(0.0, 1.0, _PIECES + 1)
        return np.concatenate([[0.0], np.cumsum(self._integral(edges[:-1], edges[1:]))])

    @property
    def length(self) -> float:
        """[mm]"""
        return float(self.arc_length_table[-1])

    def _parameter(self, s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The curve parameter u at arc length s (Newton on the arc-length integral)."""
        table = self.arc_length_table
        s = np.clip(np.asarray(s, dtype=float), 0.0, table[-1])
        k = np.clip(np.searchsorted(table, s, side="right") - 1, 0, _PIECES - 1)
        lo, hi = k / _PIECES, (k + 1) / _PIECES
        u = lo + (s - table[k]) / (table[k + 1] - table[k]) * (hi - lo)
        for _ in range(_NEWTON):
            u = np.clip(u - (table[k] + self._integral(lo, u) - s) / self._speed(u), lo, hi)
        u = np.where(s <= 0.0, 0.0, np.where(s >= table[-1], 1.0, u))
        return s, u

    def position(self, s: ArrayLike) -> Vector:
        s, u = self._parameter(s)
        values = self.start + _bernstein(5, u) @ self.control_offsets
        values = np.where((s <= 0.0)[..., None], self.start, values)
        return np.where((s >= self.length)[..., None], self.end, values)

    def tangent(self, s: ArrayLike) -> Vector:
        _, u = self._parameter(s)
        first = self._derivative(u)
        return first / np.linalg.norm(first, axis=-1, keepdims=True)

    def _curvature_vector_at(self, u: NDArray[np.float64]) -> Vector:
        first, second = self._derivative(u), _bernstein(3, u) @ self._second
        speed2 = np.sum(first * first, axis=-1, keepdims=True)
        along = np.sum(first * second, axis=-1, keepdims=True) / speed2
        return (second - along * first) / speed2

    def curvature_vector(self, s: ArrayLike) -> Vector:
        """Curvature times the principal normal [1/mm]."""
        return self._curvature_vector_at(self._parameter(s)[1])

    def curvature(self, s: ArrayLike) -> NDArray[np.float64]:
        return np.linalg.norm(self.curvature_vector(s), axis=-1)

    @cached_property
    def max_curvature(self) -> float:
        """[1/mm], the peak over the whole contour (sampled, then refined)."""
        return _peak(lambda u: np.linalg.norm(self._curvature_vector_at(u), axis=-1))

    def _frame_at(self, u: NDArray[np.float64]) -> tuple[Vector, Vector, Vector]:
        """Unit tangent, curvature vector and its arc-length rate at curve parameters ``u``.

        With r1, r2, r3 the u-derivatives of the curve and σ = |r1| = ds/du:
        k = N/σ⁴ with N = σ²·r2 - (r1·r2)·r1, and dk/ds = (N'/σ⁴ - 4(r1·r2)·N/σ⁶)/σ with
        N' = (r1·r2)·r2 + σ²·r3 - (r2·r2 + r1·r3)·r1.
        """
        u = np.asarray(u, dtype=float)
        powers = np.empty(u.shape + (5,))
        powers[..., 0], powers[..., 1], powers[..., 2] = 1.0, u, u * u
        powers[..., 3], powers[..., 4] = powers[..., 2] * u, powers[..., 2] * powers[..., 2]
        r = powers @ self.derivatives_in_powers
        r1, r2, r3 = r[..., 0:3], r[..., 3:6], r[..., 6:9]
        speed2, d12 = _dot(r1, r1), _dot(r1, r2)
        n = speed2 * r2 - d12 * r1
        n_rate = d12 * r2 + speed2 * r3 - (_dot(r2, r2) + _dot(r1, r3)) * r1
        speed, speed4 = np.sqrt(speed2), speed2 * speed2
        return r1 / speed, n / speed4, (n_rate - 4.0 * d12 * n / speed2) / (speed4 * speed)

    @cached_property
    def derivatives_in_powers(self) -> NDArray[np.float64]:
        """B', B'', B''' side by side in powers of u: (5, 9), one product evaluates all three."""
        third = 3.0 * np.diff(self._second, axis=0)  # 60 x third differences of the points
        table = np.zeros((5, 9))
        table[:, 0:3] = self._power
        table[:4, 3:6] = _monomial(3) @ self._second
        table[:3, 6:9] = _monomial(2) @ third
        return table

    def curvature_rate(self, s: ArrayLike) -> Vector:
        """d(curvature_vector)/ds [1/mm²]: the axis jerk has a term v³·dk/ds."""
        return self._frame_at(self._parameter(s)[1])[2]

    @cached_property
    def max_curvature_rate(self) -> float:
        """[1/mm²], the peak of ``|curvature_rate|`` over the whole contour (sampled, refined)."""
        return _peak(lambda u: np.linalg.norm(self._frame_at(u)[2], axis=-1))

    def derivative_bounds(self) -> Vector:
        """Per coordinate, the largest |dx/ds|, |d²x/ds²|, |d³x/ds³| on the contour: (3, 3).

        Row 0 bounds the tangent, row 1 the curvature vector, row 2 its rate; the axis limits
        of a Cartesian group follow from them (coordinated/limits.py). Sampled, not proven:
        each of the nine functions is sampled at 513 curve parameters, and each sampled peak
        gets an allowance for the curve between samples (``_peaks``), which puts the bound at
        most ~2e-4 above the true peak; ``BOUND_MARGIN`` covers the round-off where a peak
        is sampled exactly (the ends). A peak could only be missed if it hid between two
        samples without lifting either; the coordinates are smooth rational functions of the
        curve parameter, which even near a cusp vary on a scale far above the spacing.
        """
        return self._derivative_bounds.copy()

    @cached_property
    def _derivative_bounds(self) -> Vector:
        def magnitudes(u: NDArray[np.float64]) -> NDArray[np.float64]:
            return np.abs(np.concatenate(self._frame_at(u), axis=-1))

        return (1.0 + BOUND_MARGIN) * _peaks(magnitudes).reshape(3, 3)

    def distance_to(self, target: ArrayLike) -> float:
        """Shortest distance [mm] from ``target`` to the contour."""
        offset = as_point(target, "point") - self.start
        local = self.control_offsets
        return -_peak(lambda u: -np.linalg.norm(_bernstein(5, u) @ local - offset, axis=-1))


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Dot products over the last axis, kept as a length-1 axis for broadcasting."""
    return np.einsum("...i,...i->...", a, b)[..., None]


def _peak(f: Callable[[NDArray[np.float64]], NDArray[np.float64]]) -> float:
    """Largest value of f on [0, 1]: sample, then zoom in around the best local peaks.

    Each zoom samples the neighbourhood of a candidate 16x finer; after ``_ZOOMS`` the
    parameter is known to ~1e-9, so a smooth peak's value to round-off.
    """
    u = np.linspace(0.0, 1.0, _SAMPLES)
    y = f(u)
    inner = np.flatnonzero((y[1:-1] >= y[:-2]) & (y[1:-1] >= y[2:])) + 1
    centre = u[inner[np.argsort(y[inner])[-8:]]]
    width = 1.0 / (_SAMPLES - 1)
    offsets = np.linspace(-1.0, 1.0, 33)
    best = float(y.max())
    for _ in range(_ZOOMS if centre.size else 0):
        grid = np.clip(centre[:, None] + width * offsets, 0.0, 1.0)
        values = f(grid)
        pick = np.argmax(values, axis=1)
        centre = grid[np.arange(grid.shape[0]), pick]
        best = max(best, float(values.max()))
        width /= 16.0
    return best


def _peaks(f: Callable[[NDArray[np.float64]], NDArray[np.float64]]) -> NDArray[np.float64]:
    """An upper bound of each column of f on [0, 1]: ``_peak`` for several functions at once.

    f maps parameters of any shape to values of that shape plus one axis of m columns.
    Between two samples δ apart a smooth function exceeds the larger by at most
    max|f''|·δ²/8. At each sampled peak the second difference estimates |f''|·δ², an average
    over two intervals, and we add a quarter of it (``_bent_peaks``): twice the worst case,
    for f'' that grows towards the peak. That holds while f'' changes little between
    samples, which a small allowance shows: up to ``_BEND`` of the column's peak we accept it
    (at most ~2e-4, mostly ~1e-5, on contours at 513 samples: one call of f). Otherwise, as
    near a cusp, we zoom in on the ``_CANDIDATES`` best peaks of each column, 4x finer each
    time, until the allowance is that small. Sampled, not proven: a peak narrower than the
    spacing that no sample notices is missed (contours have none, tests/coordinated).
    """
    u = np.linspace(0.0, 1.0, _PEAKS_SAMPLES)
    y = f(u).T
    bound, bend, totals = _bent_peaks(y)
    if np.all(bend <= _BEND * bound):
        return bound
    centre = u[np.argsort(totals, axis=1)[:, -_CANDIDATES:]]  # (m, candidates)
    width = 1.0 / (_PEAKS_SAMPLES - 1)
    columns = np.arange(len(bound))
    offsets = np.linspace(-1.0, 1.0, 9)
    for _ in range(_MAX_ZOOMS):
        centre = np.clip(centre, width, 1.0 - width)  # windows inside [0, 1]: no repeats
        grid = centre[..., None] + width * offsets  # (m, candidates, 9)
        values = f(grid)[columns, :, :, columns]  # each column at its own points
        zoomed, bends, _ = _bent_peaks(values)
        pick = np.argmax(values, axis=2)[..., None]
        centre, width = np.take_along_axis(grid, pick, axis=2)[..., 0], width / 4.0
        best = zoomed.max(axis=1)
        if np.all(bends <= _BEND * best[:, None]):
            break
    return np.maximum(y.max(axis=1), best)  # the samples, and the zoomed peaks with allowance


def _bent_peaks(values: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    """Along the last axis (equally spaced samples): the largest sample at a local peak plus
    a quarter of the second difference there, that allowance, and the sum at every sample
    (-inf off the peaks), see ``_peaks``."""
    edge = np.full(values.shape[:-1] + (1,), -np.inf)
    padded = np.concatenate([edge, values, edge], axis=-1)
    peak = (values >= padded[..., :-2]) & (values >= padded[..., 2:])
    k = np.clip(np.arange(values.shape[-1]), 1, values.shape[-1] - 2)
    bend = np.maximum(2.0 * values[..., k] - values[..., k - 1] - values[..., k + 1], 0.0) / 4.0
    total = np.where(peak, values + bend, -np.inf)
    best = np.argmax(total, axis=-1)[..., None]
    return (np.take_along_axis(total, best, -1)[..., 0],
            np.take_along_axis(bend, best, -1)[..., 0], total)


@dataclass(frozen=True, eq=False)
class Blend:
    """A rounded corner: trimmed pre-block, contour, trimmed post-block (Part 4 §7.1)."""

    before: Segment  #: the pre-block up to the contour's start E1'
    contour: Contour  #: from E1' to S2'
    after: Segment  #: the post-block from the contour's end S2'
    corner: Vector  #: the programmed corner E1 = S2 [mm]
    corner_distance: float  #: straight distance from the corner to E1' and to S2' [mm]
    corner_deviation: float  #: shortest distance from the corner to the contour [mm]
    clamped: bool  #: the request did not fit: half a segment, or an arc's turn (module text)


def corner_distance_blend(before: Segment, after: Segment, distance: float) -> Blend:
    """TMCornerDistance (§7.4.4): leave ``before`` and join ``after`` ``distance`` [mm] from
    the corner."""
    distance = _positive(distance, "TPCornerDistance")
    corner, limit = _corner(before, after)
    return _blend(before, after, corner, min(distance, limit), distance > limit)


def max_corner_deviation_blend(before: Segment, after: Segment, deviation: float) -> Blend:
    """TMMaxCornerDeviation (§7.4.5): the contour passes ``deviation`` [mm] from the corner,
    or nearer when even half a segment gives less (then ``clamped``)."""
    deviation = _positive(deviation, "TPCornerDeviation")
    corner, limit = _corner(before, after)
    widest = _blend(before, after, corner, limit, True)
    if widest.corner_deviation <= deviation:
        return widest

    def excess(d: float) -> float:
        return _blend(before, after, corner, d, False).corner_deviation - deviation

    d = _root(excess, limit, -deviation, widest.corner_deviation - deviation, deviation)
    return _blend(before, after, corner, d, False)


def _positive(value: float, name: str) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise _reject(f"{name} must be a finite length > 0 [mm]")
    return value


def _corner(before: Segment, after: Segment) -> tuple[Vector, float]:
    """The corner (the end of ``before``) and the largest corner distance both sides allow."""
    corner = before.end
    if float(np.linalg.norm(after.start - corner)) > TOLERANCE:
        raise _reject("blend: the second segment does not start where the first ends")
    t0, t1 = before.tangent(before.length), after.tangent(0.0)
    if float(t0 @ t1) <= -math.cos(REVERSAL_ANGLE):
        raise _reject("blend: the path turns back at the corner (180°): it must stop there")
    limit = min(float(np.linalg.norm(before.position(0.5 * before.length) - corner)),
                float(np.linalg.norm(after.position(0.5 * after.length) - after.start)))
    radii = [segment.radius for segment in (before, after) if isinstance(segment, Arc)]
    if radii:  # π minus the corner's turn, accurate near a reversal too
        left = 2.0 * math.atan2(float(np.linalg.norm(t0 + t1)), float(np.linalg.norm(t0 - t1)))
        limit = _winding_limit(radii, _WINDING * left, limit)
    return corner, limit


def _winding_limit(radii: list[float], budget: float, limit: float) -> float:
    """The largest corner distance up to ``limit`` at which the one or two arcs of these radii,
    trimmed by it, turn by at most ``budget`` [rad] together (module docstring).

    An arc of radius r trimmed by the straight distance d turns by 2·asin(d/2r). For two arcs
    the half-turns α and β add up to budget/2 with r1·sin α = r2·sin β = d/2, so
    tan α = r2·sin(budget/2) / (r1 + r2·cos(budget/2)).
    """
    half = 0.5 * budget
    alpha = half if len(radii) == 1 else math.atan2(
        radii[1] * math.sin(half), radii[0] + radii[1] * math.cos(half))
    return min(limit, 2.0 * radii[0] * math.sin(alpha))


def _along(segment: Segment, distance: float) -> float:
    """Arc length from a segment end to the point ``distance`` away from that end in a line."""
    if isinstance(segment, Arc):
        return 2.0 * segment.radius * math.asin(min(1.0, distance / (2.0 * segment.radius)))
    return distance


def _blend(before: Segment, after: Segment, corner: Vector, distance: float,
           clamped: bool) -> Blend:
    head = before.substring(0.0, before.length - _along(before, distance))
    tail = after.substring(_along(after, distance), after.length)
    t0, t1 = head.tangent(head.length), tail.tangent(0.0)
    c = math.sqrt(max(0.0, 0.5 * (1.0 + float(t0 @ t1))))
    chord = float(np.linalg.norm(tail.start - head.end))
    contour = Contour(head.end, t0, head.curvature_vector(head.length), tail.start, t1,
                      tail.curvature_vector(0.0), _HANDLE * chord / (1.0 + c))
    return Blend(head, contour, tail, corner, distance, contour.distance_to(corner), clamped)


def _root(f: Callable[[float], float], hi: float, f_lo: float, f_hi: float,
          scale: float) -> float:
    """A zero of f on (0, hi) with f(0) = f_lo < 0 < f_hi = f(hi): Illinois false position."""
    lo, side = 0.0, 0
    best, best_value = hi, abs(f_hi)
    for _ in range(100):
        x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        if not lo < x < hi:
            x = 0.5 * (lo + hi)
        value = f(x)
        if abs(value) < best_value:
            best, best_value = x, abs(value)
        if abs(value) <= 1e-13 * max(1.0, scale):
            break
        if value > 0.0:
            hi, f_hi = x, value
            if side == 1:
                f_lo *= 0.5
            side = 1
        else:
            lo, f_lo = x, value
            if side == -1:
                f_hi *= 0.5
            side = -1
    return best
