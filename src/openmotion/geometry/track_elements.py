"""The pieces of a planar track and the rule that joins them (TF5430 §6.2.2, §6.2.10, §7.2.2.10).

A track is a chain of pieces, each parameterised by its own arc length ``s`` [mm] from 0:

- ``TrackLine`` and ``TrackArc``: what AppendLine, AppendPosition and AppendCircle describe;
- ``Transition``: a G2 quintic Bézier that ``join`` inserts where two of them do not meet
  continuously in position, heading and curvature (§6.2.10 requires C² tracks).

Headings are angles of the unit tangent from +x [rad]; curvature is signed [1/mm], positive
where the track turns counter-clockwise (to the left of the direction of travel).

``join`` is the whole rule; the module docstring of ``geometry.track`` explains why it is so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum
from typing import NamedTuple, TypeAlias

import numpy as np
import shapely
from numpy.typing import NDArray

from openmotion.core.errors import CommandRejected, ConfigError
from openmotion.geometry.blend import Contour
from openmotion.geometry.path import TOLERANCE

ANGLE_TOLERANCE = 1e-9  #: [rad] headings closer than this are equal
CURVATURE_TOLERANCE = 1e-9  #: [1/mm] curvatures closer than this are equal
REVERSAL_ANGLE = 1e-6  #: [rad] a corner turning by more than π minus this turns back
CORNER_SHARE = 0.25  #: share of the shorter neighbour that a rounded corner takes from each
HANDLE = 0.375  #: transition handle h = HANDLE·chord/(1 + cos(turn/2)), as blend.py's corners
TABLE_PIECES = 64  #: pieces of the curve parameter in a transition's arc-length table
CUSP_RATIO = 0.2  #: a transition whose |dB/du| drops below this share of its peak is refused
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(8)
NODES, WEIGHTS = 0.5 * (_NODES + 1.0), 0.5 * _WEIGHTS  #: Gauss-Legendre on [0, 1]
_SHAPE_SAMPLES = 257  #: samples of a transition for the cusp and crossing checks


class PieceKind(IntEnum):
    """What a piece of the track is."""

    LINE = 0  #: a straight line (AppendLine, AppendPosition, or a straight connector)
    ARC = 1  #: a circular arc (AppendCircle)
    TRANSITION = 2  #: a quintic inserted so that the track stays G2 (§6.2.10)


class TrackPose(NamedTuple):
    """A point of a track with its direction and bend: what a connection must match."""

    x: float  #: [mm]
    y: float  #: [mm]
    heading: float  #: [rad] angle of the direction of travel from +x
    curvature: float  #: [1/mm], > 0 turning counter-clockwise


def wrap(angle: float) -> float:
    """The angle in (-π, π]."""
    return math.pi - (math.pi - angle) % (2.0 * math.pi)


def joins_smoothly(before: TrackPose, after: TrackPose) -> bool:
    """True when a track ending in ``before`` continues G2 into one starting in ``after``:
    same point (``TOLERANCE``), heading and curvature (§6.2.2: continuous including direction
    and curvature)."""
    return (math.hypot(after.x - before.x, after.y - before.y) <= TOLERANCE
            and abs(wrap(after.heading - before.heading)) <= ANGLE_TOLERANCE
            and abs(after.curvature - before.curvature) <= CURVATURE_TOLERANCE)


def _shown(x: float, y: float) -> str:
    """A point for messages."""
    return f"({x:.6g}, {y:.6g})"


class TrackLine:
    """A straight piece from ``start`` to ``end`` [mm]."""

    kind = PieceKind.LINE
    max_curvature = 0.0  #: [1/mm]

    def __init__(self, start: tuple[float, float], end: tuple[float, float]) -> None:
        self.start, self.end = start, end
        self.length = math.hypot(end[0] - start[0], end[1] - start[1])  #: [mm]
        if self.length <= TOLERANCE:
            raise ConfigError(f"the line from {_shown(*start)} to {_shown(*end)} has zero "
                              "length")
        self.heading = math.atan2(end[1] - start[1], end[0] - start[0])  #: [rad]

    def __repr__(self) -> str:
        return f"TrackLine({_shown(*self.start)} -> {_shown(*self.end)})"

    def pose_at(self, s: float) -> TrackPose:
        if s >= self.length:
            return TrackPose(*self.end, self.heading, 0.0)
        c, n = math.cos(self.heading), math.sin(self.heading)
        return TrackPose(self.start[0] + s * c, self.start[1] + s * n, self.heading, 0.0)

    def trimmed(self, head: float, tail: float) -> TrackLine:
        """The piece without ``head`` [mm] at its start and ``tail`` at its end."""
        if head == 0.0 and tail == 0.0:
            return self
        start, end = self.pose_at(head), self.pose_at(self.length - tail)
        return TrackLine((start.x, start.y), (end.x, end.y))

    def row(self) -> list[float]:
        """Its line of the evaluation table (track_kernels)."""
        return [self.start[0], self.start[1], math.cos(self.heading), math.sin(self.heading),
                self.heading, 0.0]


class TrackArc:
    """A circular arc about ``center`` [mm] from the polar angle ``start_angle`` [rad],
    turning by ``sweep`` [rad] (> 0 counter-clockwise, up to a full turn)."""

    kind = PieceKind.ARC

    def __init__(self, center: tuple[float, float], radius: float, start_angle: float,
                 sweep: float) -> None:
        self.center, self.radius = center, radius  #: [mm]
        self.start_angle, self.sweep = start_angle, sweep
        self.sense = 1.0 if sweep > 0.0 else -1.0  #: +1 counter-clockwise, -1 clockwise
        self.length = radius * abs(sweep)  #: [mm]
        self.max_curvature = 1.0 / radius  #: [1/mm]
        self.end: tuple[float, float] = self._position(abs(sweep))

    def __repr__(self) -> str:
        turn = "clockwise" if self.sense < 0 else "counter-clockwise"
        return (f"TrackArc(center={_shown(*self.center)}, radius={self.radius:.6g}, "
                f"{math.degrees(abs(self.sweep)):.6g} deg {turn})")

    @classmethod
    def through(cls, start: tuple[float, float], end: tuple[float, float],
                center: tuple[float, float], clockwise: bool) -> TrackArc:
        """AppendCircle's arc (§7.2.2.10.4): from ``start`` about ``center`` to ``end``,
        clockwise or not; ``end`` = ``start`` is the full circle. A centre off the
        perpendicular bisector of start and end by at most ``TOLERANCE`` is moved onto it, so
        that both ends lie on the circle exactly."""
        radius = math.hypot(start[0] - center[0], start[1] - center[1])
        if radius <= TOLERANCE:
            raise ConfigError(f"the circle about {_shown(*center)} has radius 0 (the centre is "
                              "the start point)")
        other = math.hypot(end[0] - center[0], end[1] - center[1])
        if abs(other - radius) > TOLERANCE:
            raise ConfigError(f"the circle's end {_shown(*end)} is {other:.6g} mm from the "
                              f"centre {_shown(*center)}, its start {radius:.6g} mm")
        chord = (end[0] - start[0], end[1] - start[1])
        size = math.hypot(*chord)
        sense = -1.0 if clockwise else 1.0
        if size <= TOLERANCE:
            sweep = 2.0 * math.pi
        else:
            if other != radius:
                across = (-chord[1] / size, chord[0] / size)
                middle = (0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1]))
                offset = ((center[0] - middle[0]) * across[0]
                          + (center[1] - middle[1]) * across[1])
                center = (middle[0] + offset * across[0], middle[1] + offset * across[1])
                radius = math.hypot(start[0] - center[0], start[1] - center[1])
            a0 = math.atan2(start[1] - center[1], start[0] - center[0])
            a1 = math.atan2(end[1] - center[1], end[0] - center[0])
            sweep = (sense * (a1 - a0)) % (2.0 * math.pi)
        arc = cls(center, radius, math.atan2(start[1] - center[1], start[0] - center[0]),
                  sense * sweep)
        arc.end = end
        return arc

    def _position(self, s: float) -> tuple[float, float]:
        phi = self.start_angle + self.sense * s / self.radius
        return (self.center[0] + self.radius * math.cos(phi),
                self.center[1] + self.radius * math.sin(phi))

    def pose_at(self, s: float) -> TrackPose:
        x, y = self.end if s >= self.length else self._position(s)
        phi = self.start_angle + self.sense * s / self.radius
        return TrackPose(x, y, wrap(phi + self.sense * 0.5 * math.pi),
                         self.sense / self.radius)

    def trimmed(self, head: float, tail: float) -> TrackArc:
        if head == 0.0 and tail == 0.0:
            return self
        arc = TrackArc(self.center, self.radius,
                       self.start_angle + self.sense * head / self.radius,
                       self.sense * (self.length - head - tail) / self.radius)
        if tail == 0.0:
            arc.end = self.end
        return arc

    def row(self) -> list[float]:
        return [self.center[0], self.center[1], self.radius, self.start_angle, self.sense, 0.0]


class Transition:
    """The quintic Bézier from pose ``start`` to pose ``end`` that matches both in position,
    heading and curvature: blend.py's ``Contour`` with the handle rule of ``HANDLE``.

    ``table`` holds the arc length at the curve parameters u = k/``TABLE_PIECES`` and
    ``speeds`` |dB/du| there; track_kernels inverts s(u) with them.
    """

    kind = PieceKind.TRANSITION

    def __init__(self, start: TrackPose, end: TrackPose) -> None:
        self.start, self.end = start, end
        chord = math.hypot(end.x - start.x, end.y - start.y)
        turn = abs(wrap(end.heading - start.heading))
        handle = HANDLE * chord / (1.0 + math.cos(0.5 * turn))
        try:
            self.contour = Contour(_point3(start), _tangent3(start), _bend3(start),
                                   _point3(end), _tangent3(end), _bend3(end), handle)
        except CommandRejected as rejected:
            raise ConfigError(f"no smooth transition from {_shown(start.x, start.y)} to "
                              f"{_shown(end.x, end.y)}: {rejected.message}") from None
        points = self.contour.control_points[:, :2]
        self.origin = points[0].copy()  #: [mm] the start; the coefficients are relative to it
        power = _POWER @ (points - points[0])  # B(u) - origin in powers of u: (6, 2)
        self.coefficients = power
        self.first = power[1:] * np.arange(1, 6)[:, None]  #: dB/du in powers of u: (5, 2)
        self.second = self.first[1:] * np.arange(1, 5)[:, None]  #: d²B/du²: (4, 2)
        self.box = np.concatenate([points.min(axis=0), points.max(axis=0)])  #: hull bounds
        self.table, self.speeds = self._arc_lengths()
        self.length = float(self.table[-1])  #: [mm]
        self._check_shape()

    def __repr__(self) -> str:
        return (f"Transition({_shown(self.start.x, self.start.y)} -> "
                f"{_shown(self.end.x, self.end.y)}, length={self.length:.6g})")

    @property
    def max_curvature(self) -> float:
        """[1/mm] the peak of |curvature| (blend.py's sampled and refined peak)."""
        return self.contour.max_curvature

    def _speed(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        derivative = np.polynomial.polynomial.polyval(u, self.first)
        return np.hypot(derivative[0], derivative[1])

    def _arc_lengths(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        edges = np.linspace(0.0, 1.0, TABLE_PIECES + 1)
        width = 1.0 / TABLE_PIECES
        pieces = self._speed(edges[:-1, None] + width * NODES) @ WEIGHTS * width
        return np.concatenate([[0.0], np.cumsum(pieces)]), self._speed(edges)

    def _check_shape(self) -> None:
        """Refuse a curve that nearly stops in a cusp or crosses itself, and one whose table
        would not give the arc length to 1e-10 mm (no curve that passed the first two checks
        has failed this one in our tests)."""
        where = f"from {_shown(self.start.x, self.start.y)} to {_shown(self.end.x, self.end.y)}"
        u = np.linspace(0.0, 1.0, _SHAPE_SAMPLES)
        speed = self._speed(u)
        if speed.min() < CUSP_RATIO * speed.max():
            raise ConfigError(f"no smooth transition {where}: the curve would turn back in a "
                              "near-cusp (the next element starts behind or too far aside)")
        points = self.origin + np.polynomial.polynomial.polyval(u, self.coefficients).T
        if not shapely.LineString(points).is_simple:
            raise ConfigError(f"no smooth transition {where}: the curve would cross itself")
        width = 0.5 / TABLE_PIECES
        edges = np.linspace(0.0, 1.0, 2 * TABLE_PIECES + 1)[:-1, None]
        finer = np.sum(self._speed(edges + width * NODES) @ WEIGHTS) * width
        if abs(finer - self.length) > 1e-10:
            raise ConfigError(f"no smooth transition {where}: too sharp to measure its length")

    def pose_at(self, s: float) -> TrackPose:
        """Only the ends are asked for when pieces are joined."""
        return self.end if s >= self.length else self.start


Piece: TypeAlias = TrackLine | TrackArc | Transition
Element: TypeAlias = TrackLine | TrackArc


def _power_matrix() -> NDArray[np.float64]:
    """Bernstein (degree 5) to powers of u: row k holds the weights of the points in u**k."""
    matrix = np.zeros((6, 6))
    for k in range(6):
        for i in range(k + 1):
            matrix[k, i] = math.comb(5, i) * math.comb(5 - i, k - i) * (-1) ** (k - i)
    return matrix


_POWER = _power_matrix()


def _point3(pose: TrackPose) -> NDArray[np.float64]:
    return np.array([pose.x, pose.y, 0.0])


def _tangent3(pose: TrackPose) -> NDArray[np.float64]:
    return np.array([math.cos(pose.heading), math.sin(pose.heading), 0.0])


def _bend3(pose: TrackPose) -> NDArray[np.float64]:
    """The curvature vector: curvature times the left normal."""
    return pose.curvature * np.array([-math.sin(pose.heading), math.cos(pose.heading), 0.0])


@dataclass(frozen=True)
class Join:
    """How two neighbours meet: what each gives up [mm] and the piece put between them."""

    trim_before: float  #: taken from the end of the piece before
    trim_after: float  #: taken from the start of the piece after
    piece: TrackLine | Transition | None  #: None where they meet G2 already


def join(before: Element | TrackPose, after: Element | TrackPose) -> Join:
    """The join from ``before`` to ``after``. A ``TrackPose`` is the end (start) of another
    track, which keeps its geometry; elements may give up a share of their length.

    - They meet G2 already: nothing.
    - A gap: a connector from the end pose to the start pose (``connector``).
    - A corner or a curvature step at a shared point: each element gives up ``CORNER_SHARE``
      of the shorter element's length and a connector joins what is left. At another track's
      end only a curvature step can be rounded (the other track cannot give anything up).
    """
    end = before if isinstance(before, TrackPose) else before.pose_at(before.length)
    start = after if isinstance(after, TrackPose) else after.pose_at(0.0)
    if math.hypot(start.x - end.x, start.y - end.y) > TOLERANCE:
        return Join(0.0, 0.0, connector(end, start))
    if joins_smoothly(end, start):
        return Join(0.0, 0.0, None)
    turn = wrap(start.heading - end.heading)
    where = _shown(end.x, end.y)
    if abs(turn) > math.pi - REVERSAL_ANGLE:
        raise ConfigError(f"the track turns back on itself at {where}")
    elements = [e for e in (before, after) if not isinstance(e, TrackPose)]
    if len(elements) < 2 and abs(turn) > ANGLE_TOLERANCE:
        raise ConfigError(f"a corner of {math.degrees(turn):.6g} deg at {where}, the end of "
                          "the other track, which cannot be rounded off; leave a gap for the "
                          "transition")
    if not elements:
        raise ConfigError(f"the two track ends meet at {where} with different curvatures "
                          "and there is no element between them to make the transition")
    share = CORNER_SHARE * min(e.length for e in elements)
    trim_before = 0.0 if isinstance(before, TrackPose) else share
    trim_after = 0.0 if isinstance(after, TrackPose) else share
    end = before if isinstance(before, TrackPose) else before.pose_at(before.length - share)
    start = after if isinstance(after, TrackPose) else after.pose_at(share)
    return Join(trim_before, trim_after, connector(end, start))


def connector(end: TrackPose, start: TrackPose) -> TrackLine | Transition:
    """The piece from pose ``end`` to pose ``start`` (at different points): a straight line
    where both are straight and ``start`` lies straight ahead, else a ``Transition``."""
    dx, dy = start.x - end.x, start.y - end.y
    c, n = math.cos(end.heading), math.sin(end.heading)
    if (abs(end.curvature) <= CURVATURE_TOLERANCE and abs(start.curvature) <= CURVATURE_TOLERANCE
            and abs(wrap(start.heading - end.heading)) <= ANGLE_TOLERANCE
            and abs(c * dy - n * dx) <= TOLERANCE and c * dx + n * dy > 0.0):
        return TrackLine((end.x, end.y), (start.x, start.y))
    return Transition(end, start)
