"""Group collision avoidance by area reservation (TF5430 §6.3, §6.4, §6.7.2).

Every member of a planar group holds a reserved area. A motion command asks the group for the
area its motion needs; the command is rejected at once, without waiting, when that area meets
an area another member holds, and otherwise the area becomes the member's reservation (§6.3).
The environment is a member too: it blocks every area that leaves the stator surface (§6.4,
§6.7.2). The rejection names the blocking object so that the caller can fill the feedback
with ``ErrorId.PLANAR_COLLISION`` (0x8186) and ``objectInfo`` (§6.7.2).

Footprint and swept area. A mover's footprint is its width x height rectangle (155 x 155 mm by
default, §6.1.1) centred on (x, y) and turned by c. The planner hands over its path sampled at a
fixed time step, an (k, 3) array of x, y, c. ``swept_area`` cuts the path into runs where the
travel passes each ``release_step`` and covers each run with one convex piece: the hull H of
the footprints of all its samples, grown by g on every side (each corner replaced by the square
of half-side g around it, which holds the disc of radius g), where

    g = r * (largest turn between two samples of the run, in rad)

and r is the half diagonal. A run that turns 30 degrees or more between two samples (coarse
input) is covered by the discs of radius r around its centres instead: a disc holds the
footprint at any angle. A straight move needs only the run's first and last footprints (and,
when it turns, the footprints at the run's extreme angles and their apexes, ``_line_pieces``);
without rotation its pieces are exact (g = 0). ``straight_swept_area`` builds those pieces
from the run ends alone, for a caller that knows its path is straight (a MoveToPosition).

Why a piece contains the true swept area: we assume that between two samples the centre moves
on the straight segment joining them and c moves monotonically (true to micrometres at the
planner's sample step, which includes every segment boundary). Every sample's footprint is in
H. Between samples a and a + 1, a point of the footprint is p_a + s (p_a+1 - p_a) + R(c) u for
some s in [0, 1]; it differs from the blend (1 - s) (p_a + R(c_a) u) + s (p_a+1 + R(c_a+1) u),
which lies in H (H is convex), by at most |u| times the turn. So every footprint of the run
lies within g of H, inside the piece. A bent path or a turning mover is covered by its hull,
which bridges the dent a trailing edge leaves; a safety ``margin`` widens the footprint on every
side.

Release while moving (our rule; the manual does not say when areas are freed, digest §8.21).
Each piece knows the last sample it covers (``until``). The group calls
``release(member, sample)`` with the index of the sample the member's setpoint has reached
(every cycle is cheap: nothing happens until a piece lies wholly behind); pieces with
``until < sample`` are dropped, and the last piece is never dropped. When the motion ends the
group calls ``settle(member, footprint)``. Safety: the pieces kept cover the samples from the
one reached to the end of the path, and the motion between them, so the reservation always
contains the current footprint and every future footprint of the path; releasing only removes
area, so it can never make two reservations meet. A follower is admitted once the pieces in its
way are released, at most one ``release_step`` (plus a footprint) behind the leader.

Determinism: requests are decided in call order (first caller wins, §6.3.2). When several
members block, the one added to the group first is named, whether mover, track or environment.
Touching is not meeting: areas that share only edges or corners do not block each other.

Speed: the boxes of all members' pieces sit in one numpy array, updated in place on every
change, so an admission check is one compiled bounding-box scan that also tests each piece
against the few slots near and orders the pairs, then the exact test (interiors meet: shapely's
``intersects`` and not ``touches``) on the candidates in member order, stopping at the first
meeting. An STRtree would need a rebuild after every accepted command and every release. A
piece's outline is computed when an exact test first needs it (``SweptArea.outline``): its
bounds come exactly from the numbers it is made of, and most pieces never meet another member's
box. Two convex outlines (footprints, the pieces of straight moves) are compared by compiled
separating edges (``area_kernels.interiors_meet``); other pieces by shapely. A surface that is
one rectangle covers a piece exactly when it covers the piece's bounds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from functools import cached_property
from operator import itemgetter
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from openmotion.core.errors import ConfigError
from openmotion.planar import area_kernels as kernels
from openmotion.planar.enums import PlanarObjectType
from openmotion.planar.frames import cos_sin
from openmotion.planar.tolerances import DISTANCE_NOISE, SURFACE_TOLERANCE

if TYPE_CHECKING:
    from openmotion.trajectory.segments import Profile

MOVER_WIDTH = 155.0  #: default footprint extent in x at c = 0 [mm] (§6.1.1 "Mover width")
MOVER_HEIGHT = 155.0  #: default footprint extent in y at c = 0 [mm] (§6.1.1 "Mover height")
RELEASE_STEP = 100.0  #: travel covered by one releasable piece of a swept area [mm]
_STRAIGHT_SPAN = 20.0  #: [deg] the largest turn of a run the straight-move cover takes
_DISC_TURN = 30.0  #: a run stepping this far [deg] between samples is covered by discs
_SQUARE = np.array([(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)])
_RING = np.stack([np.cos(np.arange(32) * math.pi / 16), np.sin(np.arange(32) * math.pi / 16)],
                 axis=1) / math.cos(math.pi / 32)  #: a 32-gon that encloses the unit disc
_RANK = itemgetter(0)
NEVER = int(np.iinfo(np.int64).max)  #: ``until`` of a piece that progress never releases
_NEVER = np.array([NEVER], dtype=np.int64)  #: the ``until`` of an area never released
_FLIP = np.array([1.0, 1.0, -1.0, -1.0])  #: bounds to the stored box, keys to query keys
_KEY_ORDER = np.array([2, 3, 0, 1])
_NO_RANKS = np.empty(0, dtype=np.int64)  #: no member's slots are left out
_CONVEX_VERTICES = 8  #: a polygon area of up to this many vertices is tested compiled if convex


class MemberId(NamedTuple):
    """A group member: its kind and object id (fills ``PlanarObjectInfo`` on a rejection)."""

    object_type: PlanarObjectType
    id: int


def footprint(x: float, y: float, c: float = 0.0, width: float = MOVER_WIDTH,
              height: float = MOVER_HEIGHT, margin: float = 0.0) -> Polygon:
    """The mover's rectangle at (x, y) [mm] turned by c [deg], grown by ``margin`` [mm]."""
    _check_size(width, height, margin)
    cos, sin = cos_sin(float(c))  # exact at quarter turns, so edges of neighbours meet
    hx, hy = width / 2 + margin, height / 2 + margin
    return shapely.polygons([(x + cos * u - sin * v, y + sin * u + cos * v)
                             for u, v in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))])


def footprint_area(x: float, y: float, c: float = 0.0, width: float = MOVER_WIDTH,
                   height: float = MOVER_HEIGHT, margin: float = 0.0) -> SweptArea:
    """``footprint`` as one piece that progress never releases, its polygon built only when
    a check needs it (a standing mover's reservation)."""
    _check_size(width, height, margin)
    outline, bounds, keys, key = kernels.footprint_outline(
        float(x), float(y), float(c), width / 2 + margin, height / 2 + margin)
    return SweptArea.from_keys(bounds, keys, key, _NEVER, lambda _: outline)


@dataclass(eq=False)
class SweptArea:
    """An area as convex pieces in path order, each with the last sample it covers.

    ``keys`` hold each piece's max x, max y, -min x, -min y: a stored box (min x, min y,
    -max x, -max y) overlaps piece i with positive area exactly when it lies below
    ``keys[i]`` in all four; ``key`` is the same for all pieces together. They are computed
    here, with the area, so that the admission check only compares.

    A piece given by its bounds and a way to compute its vertices (``from_bounds``) gets them
    only when it is first needed (``outline``), and becomes a shapely polygon only when a view
    or a non-convex member asks (``piece``): the admission check compares boxes first, few
    pieces ever meet a box of another member, and two outlines are compared compiled
    (``area_kernels.interiors_meet``)."""

    until: np.ndarray  #: int64, the last path sample each piece covers
    bounds: np.ndarray  #: (n, 4) min x, min y, max x, max y of each piece [mm]
    keys: np.ndarray  #: (n, 4) query keys of the pieces
    key: np.ndarray  #: (4,) query key of the whole area
    polygons: np.ndarray | list  #: each piece's polygon, None until it is built
    outlines: list | None = None  #: each piece's vertices, None until they are made
    vertices: Callable[[int], np.ndarray] | None = None  #: piece i's convex outline, ccw

    @classmethod
    def from_pieces(cls, pieces: np.ndarray, until: np.ndarray | list[int]) -> SweptArea:
        bounds = shapely.bounds(pieces)
        keys = bounds[:, _KEY_ORDER] * _FLIP
        return cls(np.asarray(until, dtype=np.int64), bounds, keys, keys.max(axis=0), pieces)

    @classmethod
    def from_bounds(cls, bounds: np.ndarray, until: np.ndarray | list[int],
                    vertices: Callable[[int], np.ndarray]) -> SweptArea:
        """Piece i is the convex polygon ``vertices(i)`` ((k, 2), counter-clockwise), whose
        bounds are exactly ``bounds[i]``."""
        keys = bounds[:, _KEY_ORDER]
        keys *= _FLIP
        return cls.from_keys(bounds, keys, keys.max(axis=0) if len(bounds) > 1 else keys[0],
                             until, vertices)

    @classmethod
    def from_keys(cls, bounds: np.ndarray, keys: np.ndarray, key: np.ndarray,
                  until: np.ndarray | list[int], vertices: Callable[[int], np.ndarray]
                  ) -> SweptArea:
        """``from_bounds`` with the keys computed by the caller (a compiled loop)."""
        count = len(bounds)
        return cls(np.asarray(until, dtype=np.int64), bounds, keys, key, [None] * count,
                   [None] * count, vertices)

    @property
    def pieces(self) -> np.ndarray:
        """All pieces as shapely polygons (object array), in path order."""
        pieces = np.empty(len(self.polygons), dtype=object)
        pieces[:] = [self.piece(i) for i in range(len(self.polygons))]
        return pieces

    def piece(self, i: int) -> BaseGeometry:
        """Piece ``i`` as a shapely polygon (built when it is first needed)."""
        polygon = self.polygons[i]
        if polygon is None:
            polygon = self.polygons[i] = shapely.polygons(self.outline(i))
        return polygon

    def outline(self, i: int) -> np.ndarray | None:
        """Piece ``i``'s vertices, counter-clockwise, when it is known convex (a piece given by
        its bounds, a convex polygon); None for any other piece given as a polygon."""
        if self.outlines is None:
            return None
        vertices = self.outlines[i]
        if vertices is None:
            vertices = self.vertices(i)  # type: ignore[misc]
            if vertices is None:  # not convex: shapely compares it
                self.outlines = None
                return None
            self.outlines[i] = vertices
        return vertices

    def meets(self, i: int, other: np.ndarray) -> bool | None:
        """Whether piece ``i`` and the convex outline ``other`` (ccw) share interior points,
        compiled (``area_kernels.interiors_meet``); None when piece ``i`` is not known convex
        (shapely compares it). A piece of a straight move whose outline is still to be made
        gets it in the same compiled call."""
        outlines = self.outlines
        if outlines is not None and outlines[i] is None:
            both = getattr(self.vertices, "meets", None)
            if both is not None:
                outlines[i], meets = both(i, other)
                return meets
        mine = self.outline(i)
        return None if mine is None else kernels.interiors_meet(mine, other)

    @classmethod
    def from_geometry(cls, geometry: BaseGeometry) -> SweptArea:
        """One piece that progress never releases (a standing footprint, a track's band).
        A convex polygon of a few vertices (a footprint) also gets its outline, so that the
        exact test against a convex piece is compiled (``_convex_vertices``)."""
        area = cls.from_pieces(np.array([geometry], dtype=object), [NEVER])
        if isinstance(geometry, Polygon) and not geometry.interiors:
            area.outlines = [None]
            area.vertices = lambda _: _convex_vertices(geometry)
        return area

    @cached_property
    def geometry(self) -> BaseGeometry:
        """The union of the pieces (for views and tests; checks use the pieces)."""
        return shapely.union_all(self.pieces)


def _convex_vertices(polygon: Polygon) -> np.ndarray | None:
    """The vertices of ``polygon`` counter-clockwise when it is strictly convex with at most
    ``_CONVEX_VERTICES`` of them (a footprint), else None."""
    ring = polygon.exterior.coords
    count = len(ring) - 1
    if not 3 <= count <= _CONVEX_VERTICES:
        return None
    points = np.array(ring[:-1], dtype=float)
    edges = np.roll(points, -1, axis=0) - points
    turns = edges[:, 0] * np.roll(edges[:, 1], -1) - edges[:, 1] * np.roll(edges[:, 0], -1)
    if (turns > 0.0).all():
        return points
    if (turns < 0.0).all():
        return points[::-1].copy()
    return None


def swept_area(path: np.ndarray, width: float = MOVER_WIDTH, height: float = MOVER_HEIGHT,
               margin: float = 0.0, release_step: float | None = RELEASE_STEP) -> SweptArea:
    """The area a mover needs to follow ``path``, (k, 3) samples of x, y [mm], c [deg].

    Contains every footprint along the path (see the module docstring). ``release_step`` [mm]
    bounds the travel per piece, so that ``ReservationRegistry.release`` can free the area
    behind the mover; None keeps whole runs.
    """
    _check_size(width, height, margin)
    if release_step is not None and not release_step > 0.0:
        raise ConfigError(f"swept area: release_step must be > 0, got {release_step}")
    path = _checked_path(path)
    half = (width / 2 + margin, height / 2 + margin)
    xy, c = path[:, :2], path[:, 2]
    if len(path) == 1:
        return SweptArea.from_pieces(
            np.array([footprint(*path[0], width, height, margin)], dtype=object), [0])
    starts, ends = travel_runs(_travel(xy), release_step)
    if _straight(xy):  # the usual free move: cheap, and exact without rotation
        area = _straight_area(xy, c, starts, ends, half)
        if area is not None:
            return area
    radius = math.hypot(*half)
    turn = np.maximum.reduceat(np.abs(np.diff(c)), starts)  # [deg] largest step of each run
    grow = radius * np.radians(turn)
    grow[grow <= DISTANCE_NOISE] = 0.0
    index = [np.arange(a, b + 1) for a, b in zip(starts.tolist(), ends.tolist(), strict=True)]
    disc = turn >= _DISC_TURN  # coarse turns: the disc around the centre holds any angle
    clouds = []
    if (~disc).any():
        keep = np.flatnonzero(~disc)
        samples = np.concatenate([index[k] for k in keep])
        runs = np.repeat(keep, [len(index[k]) for k in keep])
        corners = _corners(xy[samples], _cos_sin(c[samples]), half)  # (n, 4, 2)
        cloud = corners[:, :, None, :] + grow[runs][:, None, None, None] * _SQUARE
        clouds.append((cloud.reshape(-1, 2), np.repeat(runs, 16)))
    if disc.any():
        keep = np.flatnonzero(disc)
        samples = np.concatenate([index[k] for k in keep])
        runs = np.repeat(keep, [len(index[k]) for k in keep])
        cloud = xy[samples][:, None, :] + radius * _RING
        clouds.append((cloud.reshape(-1, 2), np.repeat(runs, len(_RING))))
    points = np.concatenate([cloud for cloud, _ in clouds])
    runs = np.concatenate([run for _, run in clouds])
    order = np.argsort(runs, kind="stable")  # shapely wants the pieces' points together
    lines = shapely.linestrings(points[order], indices=runs[order])
    return SweptArea.from_pieces(shapely.convex_hull(lines), ends)


def _straight(xy: np.ndarray) -> bool:
    """The centre runs forward on one straight line (a free move from rest)."""
    (x0, y0), (x1, y1) = xy[0].tolist(), xy[-1].tolist()
    cx, cy = x1 - x0, y1 - y0
    length = math.hypot(cx, cy)
    if length == 0.0:
        return bool((xy == xy[0]).all())
    offset = (xy - xy[0]) / length
    across = cx * offset[:, 1] - cy * offset[:, 0]
    if not np.abs(across).max() <= DISTANCE_NOISE:
        return False
    along = offset[:, 0] * cx + offset[:, 1] * cy  # no BLAS call for a handful of numbers
    return bool((along[1:] - along[:-1]).min() >= -DISTANCE_NOISE)


def straight_swept_area(poses: np.ndarray | list[list[float]], until: np.ndarray | list[int],
                        width: float = MOVER_WIDTH, height: float = MOVER_HEIGHT,
                        margin: float = 0.0) -> SweptArea | None:
    """The area of a centre running forward on one straight line through ``poses`` (m + 1
    rows of x, y [mm], c [deg]): run j from pose j to pose j + 1, covering the path samples up
    to ``until[j]``, while c moves monotonically between the two poses' c. The same pieces as
    ``swept_area`` gives for the samples of such a path, built from the run ends alone; None
    when a run turns more than ``_STRAIGHT_SPAN`` (then ``swept_area`` on samples)."""
    _check_size(width, height, margin)
    poses = np.ascontiguousarray(poses, dtype=float)
    hx, hy = width / 2 + margin, height / 2 + margin
    fits, low, high, bounds, keys, key = kernels.straight_pieces(poses, _STRAIGHT_SPAN, hx, hy,
                                                                 DISTANCE_NOISE)
    if not fits:
        return None
    return SweptArea.from_keys(bounds, keys, key, until, _LineHulls(poses, low, high, hx, hy))


def straight_run_area(s: Profile, plans: Sequence[tuple[Profile, float]],
                      moving: Sequence[bool], c_in_grid: bool, start: float, step: float,
                      width: float = MOVER_WIDTH, height: float = MOVER_HEIGHT
                      ) -> tuple[np.ndarray, SweptArea] | None:
    """The sample times [s after ``start``] and swept area of a centre running forward on a
    straight line with arc length ``s`` from ``start``: the runs of ``RELEASE_STEP`` of
    ``area_kernels.straight_runs`` and the pieces of ``straight_swept_area`` at their ends,
    from one compiled call. ``plans``: (profile, t0) of x, y and c, each resting at its end
    unless ``moving``. None when a run turns more than ``_STRAIGHT_SPAN``."""
    _check_size(width, height, 0.0)
    (x, tx), (y, ty), (c, tc) = plans
    hx, hy = width / 2, height / 2
    return straight_run_pieces(kernels.straight_area_numbers(
        s.data, x.data, tx, moving[0], y.data, ty, moving[1], c.data, tc, moving[2],
        c_in_grid, start, step, RELEASE_STEP, _STRAIGHT_SPAN, hx, hy, DISTANCE_NOISE), hx, hy)


def straight_sweep(start: float, step: float, width: float = MOVER_WIDTH,
                   height: float = MOVER_HEIGHT) -> tuple[float, ...]:
    """The arguments of ``straight_run_area``'s kernel after the plans, for a planner that
    computes the area's numbers in its own compiled pass (``motion.plan_move_to_position``'s
    ``sweep``); ``straight_run_pieces`` makes the area of them."""
    _check_size(width, height, 0.0)
    return (start, step, RELEASE_STEP, _STRAIGHT_SPAN, width / 2, height / 2, DISTANCE_NOISE)


def straight_run_pieces(numbers: tuple, hx: float, hy: float
                        ) -> tuple[np.ndarray, SweptArea] | None:
    """The sample times and swept area of ``straight_run_area`` from the numbers of its kernel
    (``area_kernels.straight_area_numbers``) and the footprint's half sizes [mm]; None when a
    run turns more than ``_STRAIGHT_SPAN``."""
    samples, ends, poses, fits, low, high, bounds, keys, key = numbers
    if not fits:
        return None
    return samples, SweptArea.from_keys(bounds, keys, key, ends,
                                        _LineHulls(poses, low, high, hx, hy))


def _straight_area(xy: np.ndarray, c: np.ndarray, starts: np.ndarray, ends: np.ndarray,
                   half: tuple[float, float]) -> SweptArea | None:
    """Pieces for sampled centres on a straight line (``_line_pieces``), with each run's
    lowest and highest c."""
    if (c == c[0]).all():
        low = high = np.full(len(starts), c[0])
    else:
        low = np.minimum(np.minimum.reduceat(c, starts), c[ends])
        high = np.maximum(np.maximum.reduceat(c, starts), c[ends])
    return _line_pieces(xy[np.concatenate(([0], ends))], low, high, ends, half)


def _line_pieces(points: np.ndarray, low: np.ndarray, high: np.ndarray,
                 until: np.ndarray | list[int], half: tuple[float, float]) -> SweptArea | None:
    """Pieces for a centre on a straight line: run j runs from ``points[j]`` to
    ``points[j + 1]`` turning within [``low[j]``, ``high[j]``]; its piece is K + segment,
    where K holds the footprint at every angle the run takes. A corner turning from the
    run's lowest c to its highest travels an arc that lies in the triangle of the arc's chord
    and its two tangents, whose apex is the corner at the middle angle pushed out by
    1 / cos(span / 2): K is the hull of the corners at the lowest, the highest and (pushed
    out) the middle angle. Without rotation K is the footprint and the piece is exact. None
    when a run turns more than ``_STRAIGHT_SPAN`` (the apex then stands out by more than
    1.5 %; the general cover, which hulls every sample, is tighter for big turns).

    A piece's bounds are those of the two ends grown by K's reach in x and y, which are
    exactly the bounds of its hull; the hull itself is built when it is first needed. Both
    are compiled (``area_kernels``): a MoveToPosition computes them in the cycle it starts."""
    if float((high - low).max()) > _STRAIGHT_SPAN:
        return None
    return _pieces_on_line(np.ascontiguousarray(points, dtype=float),
                           np.ascontiguousarray(low, dtype=float),
                           np.ascontiguousarray(high, dtype=float), until, half)


def _pieces_on_line(points: np.ndarray, low: np.ndarray, high: np.ndarray,
                    until: np.ndarray | list[int], half: tuple[float, float]) -> SweptArea:
    """``_line_pieces`` of runs known to turn at most ``_STRAIGHT_SPAN`` (float arrays)."""
    hx, hy = half
    bounds, keys, key = kernels.line_piece_bounds(points, low, high, hx, hy, DISTANCE_NOISE)
    return SweptArea.from_keys(bounds, keys, key, until, _LineHulls(points, low, high, hx, hy))


class _LineHulls:
    """The vertices of piece i of ``_line_pieces``: the hull of K at both ends of run i
    (called as ``SweptArea.vertices``); ``meets`` also tests it against a convex outline in
    the same compiled call."""

    __slots__ = ("high", "hx", "hy", "low", "points")

    def __init__(self, points: np.ndarray, low: np.ndarray, high: np.ndarray, hx: float,
                 hy: float) -> None:
        self.points, self.low, self.high, self.hx, self.hy = points, low, high, hx, hy

    def __call__(self, i: int) -> np.ndarray:
        points, low, high = self.points, self.low, self.high
        return kernels.line_piece_hull(points[i, 0], points[i, 1], points[i + 1, 0],
                                       points[i + 1, 1], low[i], high[i], self.hx, self.hy,
                                       DISTANCE_NOISE)

    def meets(self, i: int, other: np.ndarray) -> tuple[np.ndarray, bool]:
        """Piece i's vertices and whether it meets the convex ``other`` (ccw)."""
        return kernels.line_piece_meets(self.points, self.low, self.high, i, self.hx, self.hy,
                                        DISTANCE_NOISE, other)


def _check_size(width: float, height: float, margin: float) -> None:
    if not (width > 0.0 and height > 0.0 and math.isfinite(width) and math.isfinite(height)):
        raise ConfigError(f"footprint: width and height must be finite and > 0, got "
                          f"{width} x {height}")
    if not (margin >= 0.0 and math.isfinite(margin)):
        raise ConfigError(f"footprint: margin must be finite and >= 0, got {margin}")


def _checked_path(path: np.ndarray) -> np.ndarray:
    path = np.asarray(path, dtype=float)
    if path.ndim != 2 or path.shape[1] != 3 or len(path) == 0:
        raise ValueError(f"path must be a (k, 3) array of x, y, c with k >= 1, got {path.shape}")
    if not np.isfinite(path).all():
        raise ValueError("path holds a value that is not finite")
    return path


def _cos_sin(c: np.ndarray) -> np.ndarray:
    """(n, 2) cosine and sine of c [deg], exact at multiples of 90 deg (edges then meet)."""
    if np.all(c == c[0]):  # no turn: one evaluation
        return np.broadcast_to(_cos_sin(c[:1]) if len(c) > 1 else _exact_cos_sin(c), (len(c), 2))
    return _exact_cos_sin(c)


def _exact_cos_sin(c: np.ndarray) -> np.ndarray:
    quarter = np.mod(c, 90.0) == 0.0
    turns = np.mod(np.round(c / 90.0), 4).astype(int)
    cos = np.where(quarter, np.array([1.0, 0.0, -1.0, 0.0])[turns], np.cos(np.radians(c)))
    sin = np.where(quarter, np.array([0.0, 1.0, 0.0, -1.0])[turns], np.sin(np.radians(c)))
    return np.stack([cos, sin], axis=1)


def _corners(xy: np.ndarray, turning: np.ndarray, half: tuple[float, float]) -> np.ndarray:
    """(n, 4, 2) corners of the footprints centred on ``xy``, turned by (cos, sin), ccw."""
    local = np.array([(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]) * half
    cos, sin = turning[:, 0, None], turning[:, 1, None]
    x = cos * local[:, 0] - sin * local[:, 1]
    y = sin * local[:, 0] + cos * local[:, 1]
    return xy[:, None, :] + np.stack([x, y], axis=-1)


def travel_runs(travel: np.ndarray, release_step: float | None
                ) -> tuple[np.ndarray, np.ndarray]:
    """Runs (first, last sample) that each cover about ``release_step`` [mm] of travel: a run
    ends at the first sample whose ``travel`` (distance covered since sample 0, from 0) reaches
    the next multiple of the step, and at the last sample. None: one run."""
    last = len(travel) - 1
    if release_step is None:
        return np.array([0]), np.array([last])
    piece = np.floor(travel / release_step)
    marks = (np.flatnonzero(piece[1:] != piece[:-1]) + 1).tolist()
    if not marks or marks[-1] != last:
        marks.append(last)
    return np.array([0, *marks[:-1]]), np.array(marks)


def _travel(xy: np.ndarray) -> np.ndarray:
    """Centre travel [mm] from sample 0 to each sample along the polyline."""
    step = xy[1:] - xy[:-1]
    travel = np.empty(len(xy))
    travel[0] = 0.0
    np.cumsum(np.hypot(step[:, 0], step[:, 1]), out=travel[1:])
    return travel


def grown_surface(surface: BaseGeometry | None
                  ) -> tuple[BaseGeometry | None, tuple[float, float, float, float] | None]:
    """A stator surface grown by ``SURFACE_TOLERANCE`` and prepared, and its bounds when it
    is one rectangle (a convex piece is then on it when its bounds are); (None, None) for
    no surface (nothing to check against)."""
    if surface is None or surface.is_empty:
        return None, None
    grown = shapely.buffer(surface, SURFACE_TOLERANCE, join_style="mitre")
    shapely.prepare(grown)
    if shapely.equals(grown, shapely.box(*grown.bounds)):
        return grown, tuple(grown.bounds)
    return grown, None


def path_on_surface(surface: BaseGeometry,
                    rectangle: tuple[float, float, float, float] | None,
                    points: np.ndarray) -> bool:
    """Whether the polyline through ``points`` (n, 2) [mm] lies on the grown ``surface``
    (``grown_surface``): where a mover's centre may go, since a stator must carry it."""
    if rectangle is not None:  # convex: the polyline is inside when its points are
        low_x, low_y, high_x, high_y = rectangle
        x, y = points[:, 0], points[:, 1]
        return bool(np.all((x >= low_x) & (x <= high_x) & (y >= low_y) & (y <= high_y)))
    line = shapely.points(points[0]) if len(points) == 1 else shapely.linestrings(points)
    return bool(shapely.covers(surface, line))


def _as_swept(area: SweptArea | BaseGeometry) -> SweptArea:
    return area if isinstance(area, SweptArea) else SweptArea.from_geometry(area)


class ReservationRegistry:
    """The reserved areas of one planar group's members, decided in call order (§6.3)."""

    def __init__(self, capacity: int = 64) -> None:
        self._order: dict[MemberId, int] = {}  # member -> rank in member order
        self._members: dict[int, MemberId] = {}
        self._next_rank = 0
        self._slots: dict[MemberId, list[int]] = {}  # member -> its pieces' slots, path order
        self._extra: dict[MemberId, list[int]] = {}  # the slots of a member's ``cover``
        self._environment: MemberId | None = None
        self._surface: BaseGeometry | None = None
        self._rectangle: tuple[float, float, float, float] | None = None  # a box surface
        self._box = np.empty((0, 4))  # min x, min y, -max x, -max y of each slot's piece
        # per slot: the piece (its area and its index there), the rank of its member (-1 when
        # free), the last sample it covers; the arrays are written by compiled loops
        self._piece_of: list[tuple[SweptArea, int] | None] = []
        self._ranks = np.empty(0, dtype=np.int64)
        self._until = np.empty(0, dtype=np.int64)
        self._free: list[int] = []
        self._alone_ranks: dict[int, np.ndarray] = {}  # rank -> [rank] (``_alone``)
        self._grow(max(1, capacity))

    @property
    def members(self) -> tuple[MemberId, ...]:
        """The members in member order (the order they were added)."""
        return tuple(self._order)

    def __contains__(self, member: object) -> bool:
        return member in self._order

    @property
    def piece_count(self) -> int:
        """Pieces reserved by all members together."""
        return len(self._piece_of) - len(self._free)

    def add_member(self, member: MemberId,
                   area: SweptArea | BaseGeometry | None = None) -> MemberId | None:
        """Add a member holding ``area`` (a mover: its standing footprint; the environment:
        its stator surface, or None before a boundary exists). A mover whose area is blocked
        is not added, and the blocker is returned, as for ``request``."""
        if member in self._order:
            raise ConfigError(f"{_name(member)}: is a member of this group already")
        if member.object_type == PlanarObjectType.ENVIRONMENT:
            if self._environment is not None:
                raise ConfigError(f"{_name(member)}: the group holds "
                                  f"{_name(self._environment)} already")
            self._environment = member
            self.set_surface(area)
        elif area is not None:
            swept = _as_swept(area)
            block = self._blocker(swept, _NO_RANKS)
            if block is not None:
                return block
            self._slots[member] = self._store(swept, self._next_rank)
        self._order[member] = self._next_rank
        self._members[self._next_rank] = member
        self._next_rank += 1
        return None

    def remove_member(self, member: MemberId) -> None:
        """Drop a member and free its area (``RemoveFromGroup``, §7.2.2)."""
        rank = self._order.pop(member)
        del self._members[rank]
        self._extra.pop(member, None)
        self._free_slots(self._slots.pop(member, []))
        if member == self._environment:
            self._environment, self._surface, self._rectangle = None, None, None

    def set_surface(self, surface: BaseGeometry | None) -> None:
        """The environment's stator surface (after ``CreateBoundary``); None: no boundary yet,
        so nothing is checked against it (no boundary element to meet, §6.4)."""
        if self._environment is None:
            raise ConfigError("set_surface: the group holds no environment")
        self._surface, self._rectangle = grown_surface(surface)

    @property
    def checks_surface(self) -> bool:
        """Whether areas are checked against a stator surface (an environment with a
        boundary is a member)."""
        return self._surface is not None

    def blocker(self, owner: MemberId, area: SweptArea | BaseGeometry,
                ignore: Collection[MemberId] = ()) -> MemberId | None:
        """The first member (in member order) that blocks ``area`` for ``owner``, or None.

        ``owner``'s own reservation never blocks; nor do the members in ``ignore`` (e.g. the
        movers on a track that reserves its band; the environment too, when it is there)."""
        self._mover_rank(owner)
        skip = np.array([self._order[m] for m in (owner, *ignore)
                         if m in self._slots or (m == self._environment and m is not None)],
                        dtype=np.int64)
        return self._blocker(_as_swept(area), skip)

    def request(self, owner: MemberId, area: SweptArea | BaseGeometry,
                ignore: Collection[MemberId] = ()) -> MemberId | None:
        """Admit ``area`` for ``owner``: None and it replaces the owner's reservation, or the
        blocking member and nothing changes (the caller reports ``PLANAR_COLLISION``)."""
        swept = _as_swept(area)
        rank = self._mover_rank(owner)
        if ignore:
            block = self.blocker(owner, swept, ignore)
        else:  # ``blocker`` of the owner alone, without building its list
            slots = self._slots
            block = self._blocker(swept, self._alone(rank) if owner in slots else _NO_RANKS)
        if block is None:  # ``settle``
            self._extra.pop(owner, None)
            self._slots[owner] = self._store(swept, rank, self._slots.pop(owner, []))
        return block

    def release(self, owner: MemberId, sample: int) -> None:
        """Free the pieces wholly behind ``sample``, the index of the path sample the owner's
        setpoint has reached (release while moving; the last piece always stays)."""
        slots = self._slots.get(owner)
        if slots is None or len(slots) < 2 or self._until[slots[0]] >= sample:
            return
        until, freed, kept = self._until, [], []
        for slot in slots[:-1]:  # a few pieces: item by item beats a gather
            (freed if until.item(slot) < sample else kept).append(slot)
        self._free_slots(freed)
        self._slots[owner] = kept + slots[-1:]

    def cover(self, owner: MemberId, area: SweptArea | BaseGeometry) -> MemberId | None:
        """Hold ``area`` for ``owner`` besides its reservation, in place of what its last
        cover held (the footprint a relative external setpoint moves, §4.2): None, or the
        blocking member and the last cover stays. The next ``settle`` or ``request`` replaces
        reservation and cover together."""
        swept = _as_swept(area)
        block = self.blocker(owner, swept)
        if block is not None:
            return block
        rank = self._mover_rank(owner)
        old = self._extra.pop(owner, [])
        kept = [slot for slot in self._slots.get(owner, []) if slot not in old]
        self._extra[owner] = self._store(swept, rank, old)
        self._slots[owner] = kept + self._extra[owner]  # last: ``release`` never frees it
        return None

    def settle(self, owner: MemberId, area: SweptArea | BaseGeometry) -> None:
        """Replace ``owner``'s reservation without a check: only for an area inside it, such
        as the standing footprint at the end of the path (which the last piece contains)."""
        rank = self._mover_rank(owner)
        self._extra.pop(owner, None)
        self._slots[owner] = self._store(_as_swept(area), rank, self._slots.pop(owner, []))

    def vacate(self, owner: MemberId) -> None:
        """Give up ``owner``'s whole reservation (a track that stops Moving, §4.3)."""
        self._mover_rank(owner)
        self._extra.pop(owner, None)
        self._free_slots(self._slots.pop(owner, []))

    def reserved(self, member: MemberId) -> BaseGeometry:
        """The member's reserved area (the environment: its surface); empty if none."""
        if member == self._environment:
            return self._surface if self._surface is not None else Polygon()
        slots = self._slots.get(member)
        if slots is None:
            return Polygon()
        return shapely.union_all([self._piece(slot) for slot in slots])

    def _alone(self, rank: int) -> np.ndarray:
        """The ranks ``blocker`` leaves out for a member alone: its own (one array per
        member, made once; the compiled check only reads it)."""
        alone = self._alone_ranks.get(rank)
        if alone is None:
            alone = self._alone_ranks[rank] = np.array([rank], dtype=np.int64)
        return alone

    def _mover_rank(self, owner: MemberId) -> int:
        """The rank of a member that may hold an area (any member but the environment)."""
        if owner == self._environment:
            raise ConfigError(f"{_name(owner)}: the environment holds its surface, not an area")
        return self._order[owner]

    def _blocker(self, swept: SweptArea, excluded: np.ndarray) -> MemberId | None:
        rank = self._first_meeting(swept, excluded)
        environment = self._environment
        if environment is not None and (rank is None or self._order[environment] < rank) \
                and self._order[environment] not in excluded.tolist() \
                and not self._on_surface(swept):
            return environment
        return None if rank is None else self._members[rank]

    def _first_meeting(self, swept: SweptArea, excluded: np.ndarray) -> int | None:
        """Lowest rank among the members whose pieces meet (not only touch) ``swept``; the
        pieces of the members ranked ``excluded`` do not count.

        The whole area's box against every slot, then each piece's box against the few slots
        near, in one compiled pass (``area_kernels.meeting_pairs``); then the exact test pair
        by pair in rank order, stopping at the first meeting: compiled for two convex
        outlines, else shapely's scalar calls (they beat its ufuncs for a handful of pairs)."""
        pairs = kernels.meeting_pairs(self._box, swept.key, swept.keys, self._ranks, excluded)
        if not pairs.shape[1]:
            return None
        for rank, i, j in zip(*pairs.tolist(), strict=True):
            area, index = self._piece_of[j]  # type: ignore[misc]
            theirs = area.outline(index)
            meets = None if theirs is None else swept.meets(i, theirs)
            if meets is not None:  # two convex outlines: compiled
                if meets:
                    return rank
                continue
            mine, theirs = swept.piece(i), area.piece(index)
            if mine.intersects(theirs) and not mine.touches(theirs):
                return rank
        return None

    def _piece(self, slot: int) -> BaseGeometry:
        area, index = self._piece_of[slot]  # type: ignore[misc]
        return area.piece(index)

    def _on_surface(self, swept: SweptArea) -> bool:
        if self._surface is None:
            return True
        if self._rectangle is not None:  # a convex piece is in a box when its bounds are
            low_x, low_y, high_x, high_y = self._rectangle
            max_x, max_y, min_x, min_y = swept.key.tolist()  # min x and min y negated
            return max_x <= high_x and max_y <= high_y and -min_x >= low_x and -min_y >= low_y
        return bool(shapely.covers(self._surface, swept.pieces).all())

    def _store(self, swept: SweptArea, rank: int, reuse: list[int] | None = None) -> list[int]:
        """Slots holding ``swept``'s pieces for ``rank``: the slots ``reuse`` first (those
        left over are freed), then free ones."""
        reuse = reuse or []
        count = len(swept.until)
        if len(reuse) >= count:
            slots = reuse[:count]
            self._free_slots(reuse[count:])
        else:
            count -= len(reuse)
            if len(self._free) < count:
                self._grow(max(len(self._piece_of), count))
            slots = reuse + self._free[:-count - 1:-1]
            del self._free[-count:]
        if slots:
            kernels.write_slots(self._box, self._ranks, self._until,
                                np.array(slots, dtype=np.int64), swept.bounds, swept.until, rank)
            piece_of = self._piece_of
            for index, slot in enumerate(slots):
                piece_of[slot] = (swept, index)
        return slots

    def _free_slots(self, slots: list[int]) -> None:
        if not slots:
            return
        kernels.clear_slots(self._box, self._ranks, np.array(slots, dtype=np.int64))
        piece_of = self._piece_of
        for slot in slots:
            piece_of[slot] = None
        self._free.extend(reversed(slots))

    def _grow(self, extra: int) -> None:
        size = len(self._piece_of)
        self._box = np.concatenate([self._box, np.full((extra, 4), np.inf)])  # free: meets none
        self._piece_of.extend([None] * extra)
        self._ranks = np.concatenate([self._ranks, np.full(extra, -1, dtype=np.int64)])
        self._until = np.concatenate([self._until, np.zeros(extra, dtype=np.int64)])
        self._free.extend(range(size + extra - 1, size - 1, -1))


def _name(member: MemberId) -> str:
    return f"{member.object_type.name.lower()} {member.id:#x}"
