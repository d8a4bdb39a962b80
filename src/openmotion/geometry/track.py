"""The curve of a planar track: elements, automatic transitions, arc-length lookups.

TF5430 §6.2 and the geometry methods of MC_PlanarTrack (§7.2.2.10). ``TrackPath`` is built
the way those methods build a track and answers, for many arc lengths ``s`` [mm] at once, the
position, heading and curvature; and, for a point, the arc length of the nearest track point
(GetArcLengthClosestTo). The planar layer wraps it (planar/track.py).

Elements (§7.2.2.10.2-§7.2.2.10.5):

- AppendLine(start, end) a straight line; AppendCircle(start, end, center, clockwise) the arc
  about ``center`` from ``start`` to ``end``, clockwise or counter-clockwise; an ``end`` equal
  to ``start`` is the full circle. A centre off the perpendicular bisector of start and end
  by at most ``TOLERANCE`` is moved onto it.
- AppendPosition(p) makes p a polyline vertex: the first one is the start point; later ones
  append the line from the track's end to p. An element that starts away from a lone start
  point is reached by the line from that point.
- CloseLoop joins the end back to the start; StartFromTrack (EndAtTrack) starts (ends) the
  track at the end (start) pose of another one, which keeps its geometry (§6.2.10).

Continuity. §6.2.10 requires tracks to be C² at every point (position, direction and
curvature continuous), with automatic "blendings" between the straight sections the user gives,
and says that they are not circle arcs; §6.2.2 and §7.2.2.10.6/.7 call track connections
smooth. So wherever two neighbours do not meet G2, ``track_elements.join`` inserts a piece:

- a gap (the next element starts elsewhere, §6.2.10's own usage): a straight connector when both
  ends are straight and the next start lies straight ahead (§6.2.5: 20 mm; §6.2.11: 40 mm),
  else a transition from the end pose to the start pose;
- a shared point with a corner or a curvature step (a line meeting an arc tangentially):
  each element gives up a quarter of the shorter one's length and a transition joins what is
  left. A quarter leaves every element at least half of itself whatever its neighbours do,
  so the result does not depend on the order of the joins. At another track's end only a
  curvature step is rounded off: that track cannot give anything up, and a corner there would
  need an S-shaped hook, so it is refused (leave a gap);
- a U-turn at a shared point is refused, and so is a transition that would cross itself or
  come near a cusp (its parametric speed below ``CUSP_RATIO`` of its peak: the next element
  starts behind the end or far aside of it).

The transition is blend.py's ``Contour``: one quintic Bézier matching position, unit tangent
and curvature vector at both ends (D-103). We chose it over clothoids because it exists in
closed form for any pair of poses (lines or arcs at either end, gaps, corners, S-bends),
where a G2 clothoid fit between two poses is an iterative solve that for some pairs has no
solution; and its curvature is continuous, so the centripetal acceleration v²κ of a mover
never steps. The price is an arc length that must be computed (below). Its single handle is
h = 0.375·chord/(1 + cos(θ/2)) for a turn θ between the end headings: for a corner between
two lines trimmed equally this is blend.py's corner rule h = 0.75·d·c/(1 + c) exactly; written
with the chord the same rule serves every gap. In a sweep of the factor from 0.3 to 0.55,
0.375 gave the lowest peak curvature for the S-bend of §6.2.12 and the uneven corner of
§6.2.10, and within 16 % of the lowest (found at 0.45) for a U-turn and for a line meeting an
arc of radius R tangentially, whose transition peaks at 1.17/R.

Arc length. Lines and arcs are exact to round-off. A transition's arc length is tabulated at
64 equal steps of its curve parameter (8-point Gauss-Legendre per step; the build refuses a
transition where doubling the steps would move its length by more than 1e-10 mm). A lookup
interpolates the parameter (cubic Hermite in s), then takes Newton steps until the predicted
arc-length residual is below 1e-12 mm, one step in practice (track_kernels); positions agree
with an independent integration to about 1e-12 mm. Lookups are compiled (numba) and take
arrays: one call serves all movers of a track. On a closed loop, s is taken modulo the
length; on an open track it is clamped to [0, length]. Where the closing join rounds a corner
at the first element's start, s = 0 is where that transition ends.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from openmotion.core.errors import ConfigError
from openmotion.geometry.path import TOLERANCE
from openmotion.geometry.track_elements import (
    Element,
    Join,
    Piece,
    PieceKind,
    TrackArc,
    TrackLine,
    TrackPose,
    Transition,
    join,
    joins_smoothly,
)
from openmotion.geometry.track_kernels import TrackTable, closest, frames

__all__ = ["PieceKind", "TrackPath", "TrackPiece", "TrackPose", "joins_smoothly"]

_HOSE_SAMPLES = 32  #: samples per hose radius when ``hose_reach`` walks along a track


class TrackPiece(NamedTuple):
    """One piece of a built track, for speed limits and plots."""

    kind: PieceKind
    start: float  #: [mm] arc length where it starts
    end: float  #: [mm] arc length where it ends
    max_curvature: float  #: [1/mm] largest |curvature| on it


def _finite_point(value: ArrayLike, name: str) -> tuple[float, float]:
    array = np.asarray(value, dtype=float)
    if array.shape != (2,) or not np.all(np.isfinite(array)):
        raise ConfigError(f"{name} must be two finite numbers (x, y) [mm], got {value!r}")
    return float(array[0]), float(array[1])


class TrackPath:
    """The curve of one track: built by the append methods, then looked up by arc length."""

    def __init__(self) -> None:
        self._point: tuple[float, float] | None = None  #: a lone start point (AppendPosition)
        self._nodes: list[Element | TrackPose] = []  #: elements; poses of other tracks' ends
        self._joins: list[Join] = []  #: _joins[i] joins _nodes[i] to _nodes[i + 1]
        self._closing: Join | None = None
        self._ended = False  #: EndAtTrack: nothing may follow
        self._built: tuple[list[Piece], TrackTable] | None = None

    def __repr__(self) -> str:
        if self.empty:
            return "TrackPath(empty)"
        shape = "closed" if self.closed else "open"
        return f"TrackPath({len(self.table.kinds)} pieces, length={self.length:.6g}, {shape})"

    # -- building (§7.2.2.10.2-§7.2.2.10.7) -------------------------------------------------

    def append_position(self, position: ArrayLike) -> None:
        """AppendPosition: the start point, or the line from the track's end to ``position``."""
        point = _finite_point(position, "the position")
        self._check_open()
        if self._point is None and not self._nodes:
            self._point = point
        else:
            self._append(TrackLine(self._end_point(), point))

    def append_line(self, start: ArrayLike, end: ArrayLike) -> None:
        """AppendLine: the line from ``start`` to ``end`` [mm]."""
        start, end = _finite_point(start, "the line's start"), _finite_point(end, "the line's end")
        self._check_open()
        self._append(TrackLine(self._snapped(start), end))

    def append_circle(self, start: ArrayLike, end: ArrayLike, center: ArrayLike,
                      clockwise: bool) -> None:
        """AppendCircle: the arc about ``center`` from ``start`` to ``end`` [mm]; ``end`` =
        ``start`` is the full circle."""
        start = _finite_point(start, "the circle's start")
        end = _finite_point(end, "the circle's end")
        center = _finite_point(center, "the circle's center")
        self._check_open()
        self._append(TrackArc.through(self._snapped(start), end, center, bool(clockwise)))

    def close_loop(self) -> None:
        """CloseLoop: join the end back to the start; nothing may be appended afterwards."""
        self._check_open()
        if self._nodes and isinstance(self._nodes[0], TrackPose):
            raise ConfigError("a track that starts from another track cannot close a loop")
        if not self._nodes:
            raise ConfigError("a loop needs at least one line or circle")
        self._closing = join(self._nodes[-1], self._nodes[0])
        self._built = None

    def start_from(self, other: TrackPath | TrackPose) -> None:
        """StartFromTrack: start where ``other`` ends, with its heading and curvature."""
        pose = other.end_pose if isinstance(other, TrackPath) else _checked_pose(other)
        self._check_open()
        if self._point is not None or self._nodes:
            raise ConfigError("the start can be taken from another track only before the "
                              "first position, line or circle")
        self._nodes.append(pose)
        self._built = None

    def end_at(self, other: TrackPath | TrackPose) -> None:
        """EndAtTrack: end where ``other`` starts, with its heading and curvature; nothing may
        be appended afterwards."""
        pose = other.start_pose if isinstance(other, TrackPath) else _checked_pose(other)
        self._check_open()
        if self._point is None and not self._nodes:
            raise ConfigError("the track has no start to lead to the other track from")
        nodes = self._lead_in((pose.x, pose.y)) + [pose]
        self._extend(nodes)
        self._ended = True

    def _check_open(self) -> None:
        if self._closing is not None:
            raise ConfigError("the track is a closed loop: nothing can be appended")
        if self._ended:
            raise ConfigError("the track ends at another track: nothing can be appended")

    def _end_point(self) -> tuple[float, float]:
        if not self._nodes:
            assert self._point is not None
            return self._point
        last = self._nodes[-1]
        if isinstance(last, TrackPose):
            return last.x, last.y
        end = last.pose_at(last.length)
        return end.x, end.y

    def _snapped(self, start: tuple[float, float]) -> tuple[float, float]:
        """``start``, or the track's end when they are within ``TOLERANCE``: they coincide."""
        if self._point is None and not self._nodes:
            return start
        end = self._end_point()
        return end if math.hypot(start[0] - end[0], start[1] - end[1]) <= TOLERANCE else start

    def _lead_in(self, start: tuple[float, float]) -> list[Element | TrackPose]:
        """The line from a lone start point to the first element's start, if they differ."""
        if self._nodes or self._point is None:
            return []
        if math.hypot(start[0] - self._point[0], start[1] - self._point[1]) <= TOLERANCE:
            return []
        return [TrackLine(self._point, start)]

    def _append(self, element: Element) -> None:
        start = element.pose_at(0.0)
        self._extend(self._lead_in((start.x, start.y)) + [element])

    def _extend(self, nodes: list[Element | TrackPose]) -> None:
        """Append ``nodes`` with their joins; nothing changes if one of them is refused."""
        joins, before = [], self._nodes[-1] if self._nodes else None
        for node in nodes:
            if before is not None:
                joins.append(join(before, node))
            before = node
        self._nodes += nodes
        self._joins += joins
        self._point = None if self._nodes else self._point
        self._built = None

    # -- the built curve -------------------------------------------------------------------

    @property
    def empty(self) -> bool:
        """True while the track has no length (nothing, a start point or a start pose)."""
        return not self._assembled()[0]

    @property
    def closed(self) -> bool:
        """CloseLoop was called (§6.2.1 "Closed loop online information")."""
        return self._closing is not None

    @property
    def length(self) -> float:
        """[mm] including every transition (GetLength, §7.2.2.10.15)."""
        return float(self.table.starts[-1])

    @property
    def pieces(self) -> tuple[TrackPiece, ...]:
        pieces, table = self._assembled()
        return tuple(TrackPiece(p.kind, float(a), float(b), p.max_curvature)
                     for p, a, b in zip(pieces, table.starts[:-1], table.starts[1:],
                                        strict=True))

    @property
    def max_curvature(self) -> float:
        """[1/mm] the largest |curvature| anywhere on the track (asked by every route
        planned over it: taken from the assembled pieces once)."""
        pieces, _ = self._assembled()
        return max(piece.max_curvature for piece in pieces)

    @property
    def start_pose(self) -> TrackPose:
        """Position, heading and curvature at s = 0 (what EndAtTrack of another track meets)."""
        pieces = self._pieces()
        return pieces[0].pose_at(0.0)

    @property
    def end_pose(self) -> TrackPose:
        """At s = length (what StartFromTrack of another track starts from); on a closed loop
        the start pose."""
        pieces = self._pieces()
        if self.closed:
            return pieces[0].pose_at(0.0)
        return pieces[-1].pose_at(pieces[-1].length)

    def _pieces(self) -> list[Piece]:
        return self._nonempty()[0]

    @property
    def table(self) -> TrackTable:
        """The pieces as arrays for the compiled kernels; a new object when the path changes."""
        return self._nonempty()[1]

    def _nonempty(self) -> tuple[list[Piece], TrackTable]:
        built = self._built or self._assembled()
        if not built[0]:
            raise ConfigError("the track has no geometry yet")
        return built

    def _assembled(self) -> tuple[list[Piece], TrackTable]:
        if self._built is None:
            pieces = self._trimmed_pieces()
            self._built = pieces, _table(pieces, self.closed)
        return self._built

    def _trimmed_pieces(self) -> list[Piece]:
        count = len(self._nodes)
        head, tail = [0.0] * count, [0.0] * count
        for i, link in enumerate(self._joins):
            tail[i], head[i + 1] = link.trim_before, link.trim_after
        if self._closing is not None:
            tail[-1], head[0] = self._closing.trim_before, self._closing.trim_after
        pieces: list[Piece] = []
        for i, node in enumerate(self._nodes):
            if not isinstance(node, TrackPose):
                pieces.append(node.trimmed(head[i], tail[i]))
            link = self._joins[i] if i < len(self._joins) else None
            if link is not None and link.piece is not None:
                pieces.append(link.piece)
        if self._closing is not None and self._closing.piece is not None:
            pieces.append(self._closing.piece)
        return pieces

    # -- lookups -----------------------------------------------------------------------------

    def frame_at(self, s: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """x, y [mm], heading [rad, in (-π, π]] and curvature [1/mm] at the arc lengths ``s``
        [mm] (any shape; modulo the length on a closed loop, clamped on an open track)."""
        values = np.asarray(s, dtype=float)
        flat, t = np.ascontiguousarray(values.reshape(-1)), self.table
        out = frames(flat, t.starts, t.kinds, t.rows, t.origins, t.coefficients, t.first,
                     t.second, t.tables, t.speeds, t.closed)
        return tuple(out[:, k].reshape(values.shape) for k in range(4))

    def positions_at(self, s: ArrayLike) -> NDArray[np.float64]:
        """[mm] the points at the arc lengths ``s``: shape of ``s`` plus (2,)."""
        x, y, _, _ = self.frame_at(s)
        return np.stack([x, y], axis=-1)

    def headings_at(self, s: ArrayLike) -> NDArray[np.float64]:
        """[rad] the direction of travel at the arc lengths ``s``, in (-π, π]."""
        return self.frame_at(s)[2]

    def curvatures_at(self, s: ArrayLike) -> NDArray[np.float64]:
        """[1/mm] signed curvature at the arc lengths ``s`` (> 0 turning counter-clockwise)."""
        return self.frame_at(s)[3]

    def position_at(self, s: float) -> tuple[float, float]:
        """GetPositionAt (§7.2.2.10.14): the point [mm] at arc length ``s``."""
        x, y, _, _ = self.frame_at(np.array([s]))
        return float(x[0]), float(y[0])

    def arc_lengths_closest_to(self, points: ArrayLike) -> NDArray[np.float64]:
        """GetArcLengthClosestTo for many points (n, 2): the arc lengths [mm] of the nearest
        track points. Of equally near points the one with the smaller arc length wins; on a
        closed loop the result is in [0, length)."""
        return self._closest(points)[:, 0]

    def arc_length_closest_to(self, point: ArrayLike) -> float:
        """GetArcLengthClosestTo (§7.2.2.10.13) for one point (x, y) [mm]."""
        return float(self._closest(np.array([_finite_point(point, "the point")]))[0, 0])

    def _closest(self, points: ArrayLike) -> NDArray[np.float64]:
        array = np.ascontiguousarray(np.asarray(points, dtype=float).reshape(-1, 2))
        t = self.table
        return closest(array, t.starts, t.kinds, t.rows, t.origins, t.coefficients, t.first,
                       t.second, t.tables, t.boxes, t.closed)

    def hose_reach(self, other: TrackPath, distance: float, from_end: bool = False,
                   placement: tuple[float, float, float] | None = None) -> float:
        """Arc length [mm], counted from this track's start (end if ``from_end``), at which
        its centre line first leaves the hose of radius ``distance`` [mm] around ``other``'s:
        the §6.2.2 hose rule for automatic collision ranges; the whole length if it never
        does. ``placement`` (x, y [mm], c [deg]) places this track's frame in ``other``'s
        (tracks on two parts); None: one frame.

        The distance to ``other`` changes by at most 1 mm per mm of arc length, so walking in
        steps of ``distance``/32 misses only excursions that leave the hose by less than
        ``distance``/64 and come back within one step; the exit found is bisected to 1e-9 mm.
        """
        if not (math.isfinite(distance) and distance > 0.0):
            raise ConfigError(f"the hose radius must be a positive number [mm], got {distance!r}")
        length = self.length
        count = max(2, math.ceil(_HOSE_SAMPLES * length / distance) + 1)
        walked = np.linspace(0.0, length, count)

        if placement is None:
            turn, shift = np.eye(2), np.zeros(2)
        else:
            angle = math.radians(placement[2])
            turn = np.array([[math.cos(angle), math.sin(angle)],
                             [-math.sin(angle), math.cos(angle)]])  # row vectors: p @ turn
            shift = np.array(placement[:2], dtype=float)

        def outside(along: NDArray[np.float64]) -> NDArray[np.float64]:
            s = length - along if from_end else along
            points = self.positions_at(s) if placement is None else \
                self.positions_at(s) @ turn + shift
            return other._closest(points)[:, 1] > distance

        beyond = np.flatnonzero(outside(walked))
        if beyond.size == 0:
            return length
        if beyond[0] == 0:
            return 0.0
        lo, hi = float(walked[beyond[0] - 1]), float(walked[beyond[0]])
        while hi - lo > 1e-9:
            mid = 0.5 * (lo + hi)
            if outside(np.array([mid]))[0]:
                hi = mid
            else:
                lo = mid
        return lo


def _checked_pose(pose: TrackPose) -> TrackPose:
    if not isinstance(pose, TrackPose) or not all(math.isfinite(v) for v in pose):
        raise ConfigError(f"a track pose must be a TrackPose of finite numbers, got {pose!r}")
    return pose


def _table(pieces: list[Piece], closed: bool) -> TrackTable:
    """The flat arrays of track_kernels for ``pieces``."""
    transitions = [p for p in pieces if isinstance(p, Transition)]
    rows = []
    for piece in pieces:
        if isinstance(piece, Transition):
            rows.append([float(transitions.index(piece))] + [0.0] * 5)
        else:
            rows.append(piece.row())
    lengths = [p.length for p in pieces]

    def stacked(name: str, shape: tuple[int, ...]) -> NDArray[np.float64]:
        if not transitions:
            return np.zeros((0, *shape))
        return np.ascontiguousarray(np.stack([getattr(p, name) for p in transitions]))

    width = (len(transitions[0].table),) if transitions else (0,)
    return TrackTable(
        starts=np.concatenate([[0.0], np.cumsum(lengths)]),
        kinds=np.array([int(p.kind) for p in pieces], dtype=np.int64),
        rows=np.array(rows, dtype=float).reshape(len(pieces), 6),
        origins=stacked("origin", (2,)),
        coefficients=stacked("coefficients", (6, 2)),
        first=stacked("first", (5, 2)),
        second=stacked("second", (4, 2)),
        tables=stacked("table", width),
        speeds=stacked("speeds", width),
        boxes=stacked("box", (4,)),
        closed=closed,
    )
