"""Straight and circular path segments in 3-D, parameterised by arc length.

PLCopen Part 4 §5.20-§5.23 (MC_MoveLinear*, MC_MoveCircular*). Every segment answers, for many
arc lengths ``s`` [mm] at once, the position [mm], the unit tangent and the curvature [1/mm], so
that one cycle of many groups costs a few numpy operations. ``s`` outside ``[0, length]`` is
clamped. Degenerate input raises ``CommandRejected``: the FB layer turns it into ``error_id``.

Circle modes (§5.22, §5.23; ``Arc.from_circ_mode``). The relative FB adds its start point to
AuxPoint and EndPoint first, except in RADIUS mode: there AuxPoint *is* the normal vector in
both FBs (from the origin in the absolute FB, from the start in the relative one).

PathChoice (§5.22 types it CLOCKWISE/COUNTERCLOCKWISE, its prose speaks of short and long
sectors). COUNTERCLOCKWISE takes the short sector and CLOCKWISE the long one:

- CENTER: the plane normal is (start - centre) x (end - centre), so the short arc turns counter-
  clockwise about it and the long arc clockwise: the names hold literally.
- RADIUS: the sense always follows the right-hand rule about the given vector (§5.22); the choice
  picks the circle with the short or the long sector. TF5410's CLOCKWISE turns the other way
  (TF5410 §9.3.2); we follow PLCopen here.
- BORDER: ignored; the border point fixes the arc.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

from openmotion.core.errors import CommandRejected, ErrorId

Vector: TypeAlias = NDArray[np.float64]

TOLERANCE = 1e-6  #: [mm] points closer than this coincide, lie on one line or on the circle


class CircMode(IntEnum):
    """MC_CIRC_MODE: the meaning of AuxPoint (Part 4 §5.22; values of TF5410 §9.3.2)."""

    BORDER = 0x2000  #: AuxPoint lies on the arc between start and end
    CENTER = 0x2001  #: AuxPoint is the centre of the circle
    RADIUS = 0x2002  #: AuxPoint is the plane's normal vector; its length is the radius


class PathChoice(IntEnum):
    """MC_CIRC_PATHCHOICE (Part 4 §5.22): which of the two possible arcs, see the module text."""

    CLOCKWISE = 0x3000  #: the long sector (sweep above 180°)
    COUNTERCLOCKWISE = 0x3001  #: the short sector (sweep below 180°); the default


def as_point(value: ArrayLike, name: str) -> Vector:
    """A finite 3-D point or vector as a float array, or ``CommandRejected`` naming the input."""
    array = np.asarray(value, dtype=float)
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise CommandRejected(ErrorId.INVALID_POSITION, f"{name} must be 3 finite numbers [mm]")
    return array


def _reject(message: str) -> CommandRejected:
    return CommandRejected(ErrorId.INVALID_PATH_GEOMETRY, message)


def _clamped(s: ArrayLike, length: float) -> NDArray[np.float64]:
    return np.clip(np.asarray(s, dtype=float), 0.0, length)


def _with_ends(values: Vector, s: NDArray[np.float64], length: float, start: Vector,
               end: Vector) -> Vector:
    """Return the stored end points bit-exactly at ``s = 0`` and ``s = length``."""
    values = np.where((s <= 0.0)[..., None], start, values)
    return np.where((s >= length)[..., None], end, values)


class Line:
    """Straight segment from ``start`` to ``end`` (MC_MoveLinear*, Part 4 §5.20, §5.21)."""

    def __init__(self, start: ArrayLike, end: ArrayLike) -> None:
        self.start = as_point(start, "start")
        self.end = as_point(end, "end")
        chord = self.end - self.start
        self.length = float(np.linalg.norm(chord))  #: [mm]
        if self.length <= TOLERANCE:
            raise _reject("line: start and end coincide")
        self.direction = chord / self.length
        self.max_curvature = 0.0

    def __repr__(self) -> str:
        return f"Line(start={self.start.tolist()}, end={self.end.tolist()})"

    def position(self, s: ArrayLike) -> Vector:
        s = _clamped(s, self.length)
        values = self.start + s[..., None] * self.direction
        return _with_ends(values, s, self.length, self.start, self.end)

    def tangent(self, s: ArrayLike) -> Vector:
        return np.broadcast_to(self.direction, np.shape(s) + (3,)).copy()

    def curvature(self, s: ArrayLike) -> NDArray[np.float64]:
        return np.zeros(np.shape(s))

    def curvature_vector(self, s: ArrayLike) -> Vector:
        """Curvature times the principal normal [1/mm]: zero on a line."""
        return np.zeros(np.shape(s) + (3,))

    def curvature_rate(self, s: ArrayLike) -> Vector:
        """d(curvature_vector)/ds [1/mm²]: zero on a line."""
        return np.zeros(np.shape(s) + (3,))

    @property
    def max_curvature_rate(self) -> float:
        """[1/mm²], the peak of ``|curvature_rate|``: zero."""
        return 0.0

    def derivative_bounds(self) -> Vector:
        """Per coordinate, the largest |dx/ds|, |d²x/ds²|, |d³x/ds³| on the segment: (3, 3).

        Row 0 bounds the tangent, row 1 the curvature vector, row 2 its rate; the axis limits
        of a Cartesian group follow from them (coordinated/limits.py). Exact on a line.
        """
        bounds = np.zeros((3, 3))
        bounds[0] = np.abs(self.direction)
        return bounds

    def substring(self, s_start: float, s_end: float) -> Line:
        """The part between two arc lengths (shapely's name), for trimming at blends."""
        return Line(self.position(s_start), self.position(s_end))


class Arc:
    """Circular arc, sweep in (0, 2π), turning right-handed about ``normal`` (Part 4 §5.22).

    The constructor takes the centre and the turning sense directly; ``from_border``,
    ``from_center`` and ``from_radius`` implement the three CircModes.
    """

    def __init__(self, start: ArrayLike, end: ArrayLike, center: ArrayLike,
                 normal: ArrayLike) -> None:
        start, end = as_point(start, "start"), as_point(end, "end")
        center, normal = as_point(center, "center"), as_point(normal, "normal")
        radius = float(np.linalg.norm(start - center))
        if radius <= TOLERANCE:
            raise _reject("arc: zero radius (the centre is the start point)")
        if abs(float(np.linalg.norm(end - center)) - radius) > TOLERANCE:
            raise _reject("arc: start and end are not equally far from the centre")
        if float(np.linalg.norm(end - start)) <= TOLERANCE:
            raise _reject("arc: start and end coincide (a full circle is not one command)")
        size = float(np.linalg.norm(normal))
        if size == 0.0:
            raise _reject("arc: zero normal vector")
        unit_normal = normal / size
        if max(abs(float((start - center) @ unit_normal)),
               abs(float((end - center) @ unit_normal))) > TOLERANCE:
            raise _reject("arc: start or end lies off the plane through the centre")
        u = start - center
        u = u - (u @ unit_normal) * unit_normal
        u /= np.linalg.norm(u)
        v = np.cross(unit_normal, u)
        to_end = end - center
        sweep = math.atan2(float(to_end @ v), float(to_end @ u)) % (2.0 * math.pi)
        self._set(start, end, center, radius, u, v, sweep)

    def _set(self, start: Vector, end: Vector, center: Vector, radius: float, u: Vector,
             v: Vector, sweep: float) -> None:
        self.start, self.end, self.center = start, end, center
        self.radius = radius  #: [mm]
        self.normal = np.cross(u, v)  #: unit vector; the arc turns right-handed about it
        self.sweep = sweep  #: [rad], in (0, 2π)
        self.length = radius * sweep  #: [mm]
        self.max_curvature = 1.0 / radius  #: [1/mm]
        #: the arc's plane: point(φ) = center + radius·(cos φ·u + sin φ·v); u points from the
        #: center to the start, v is the unit tangent at the start
        self.u, self.v = u, v

    def __repr__(self) -> str:
        return (f"Arc(start={self.start.tolist()}, end={self.end.tolist()}, "
                f"center={self.center.tolist()}, sweep={math.degrees(self.sweep):.6g} deg)")

    @classmethod
    def from_border(cls, start: ArrayLike, border: ArrayLike, end: ArrayLike) -> Arc:
        """CircMode BORDER: the arc from ``start`` through ``border`` to ``end`` (§5.22)."""
        a, b, c = as_point(start, "start"), as_point(border, "aux point"), as_point(end, "end")
        ab, bc, ac = b - a, c - b, c - a
        cross = np.cross(ab, ac)
        longest = max(float(np.linalg.norm(x)) for x in (ab, bc, ac))
        if longest <= TOLERANCE or float(np.linalg.norm(cross)) / longest <= TOLERANCE:
            raise _reject("BORDER: start, aux point and end coincide or lie on one line")
        # circumcentre of the triangle, written from the start point
        center = a + np.cross(ab @ ab * ac - ac @ ac * ab, cross) / (2.0 * (cross @ cross))
        return cls(a, c, center, np.cross(ab, bc))

    @classmethod
    def from_center(cls, start: ArrayLike, center: ArrayLike, end: ArrayLike,
                    path_choice: PathChoice = PathChoice.COUNTERCLOCKWISE) -> Arc:
        """CircMode CENTER (§5.22): a centre off by at most ``TOLERANCE`` is moved onto the
        perpendicular bisector of start and end, so that both lie on the circle exactly."""
        a, m, c = as_point(start, "start"), as_point(center, "center"), as_point(end, "end")
        radius = float(np.linalg.norm(a - m))
        if radius <= TOLERANCE or float(np.linalg.norm(c - m)) <= TOLERANCE:
            raise _reject("CENTER: zero radius (the centre is the start or end point)")
        if abs(float(np.linalg.norm(c - m)) - radius) > TOLERANCE:
            raise _reject("CENTER: start and end are not equally far from the centre")
        chord = c - a
        if float(np.linalg.norm(chord)) <= TOLERANCE:
            raise _reject("CENTER: start and end coincide (a full circle is not one command)")
        normal = np.cross(a - m, c - m)
        if float(np.linalg.norm(normal)) / radius <= TOLERANCE:
            raise _reject("CENTER: start, centre and end on one line (180°: plane unknown)")
        normal /= np.linalg.norm(normal)
        across = np.cross(normal, chord / np.linalg.norm(chord))
        middle = 0.5 * (a + c)
        center_fixed = middle + ((m - middle) @ across) * across
        sense = 1.0 if path_choice == PathChoice.COUNTERCLOCKWISE else -1.0
        return cls(a, c, center_fixed, sense * normal)

    @classmethod
    def from_radius(cls, start: ArrayLike, end: ArrayLike, normal: ArrayLike,
                    path_choice: PathChoice = PathChoice.COUNTERCLOCKWISE) -> Arc:
        """CircMode RADIUS (§5.22, §5.23): ``normal`` is the plane's normal vector, its length
        the radius; the arc turns right-handed about it. A radius short of half the chord by
        at most ``TOLERANCE`` gives the half circle."""
        a, c, n = as_point(start, "start"), as_point(end, "end"), as_point(normal, "aux point")
        radius = float(np.linalg.norm(n))
        if radius <= TOLERANCE:
            raise _reject("RADIUS: zero radius (zero normal vector)")
        chord = c - a
        length = float(np.linalg.norm(chord))
        if length <= TOLERANCE:
            raise _reject("RADIUS: start and end coincide (a full circle is not one command)")
        along = chord / length
        if abs(float(n @ along)) * length / radius > TOLERANCE:
            raise _reject("RADIUS: the end lies off the plane given by the normal vector")
        n = n - (n @ along) * along  # removes an offset within tolerance
        n /= np.linalg.norm(n)
        half = 0.5 * length
        if radius < half - TOLERANCE:
            raise _reject(f"RADIUS: radius {radius:g} mm is less than half the chord {half:g} mm")
        offset = math.sqrt(max(radius * radius - half * half, 0.0))
        if path_choice == PathChoice.CLOCKWISE:
            offset = -offset
        center = 0.5 * (a + c) + offset * np.cross(n, along)
        return cls(a, c, center, n)

    @classmethod
    def from_circ_mode(cls, circ_mode: CircMode, start: ArrayLike, aux_point: ArrayLike,
                       end_point: ArrayLike,
                       path_choice: PathChoice = PathChoice.COUNTERCLOCKWISE) -> Arc:
        """MC_MoveCircularAbsolute's inputs (§5.22), all in one coordinate system."""
        if circ_mode == CircMode.BORDER:
            return cls.from_border(start, aux_point, end_point)
        if circ_mode == CircMode.CENTER:
            return cls.from_center(start, aux_point, end_point, path_choice)
        if circ_mode == CircMode.RADIUS:
            return cls.from_radius(start, end_point, aux_point, path_choice)
        raise CommandRejected(ErrorId.INVALID_MODE, f"unknown CircMode {circ_mode!r}")

    def _angle(self, s: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        s = _clamped(s, self.length)
        return s, s / self.radius

    def position(self, s: ArrayLike) -> Vector:
        s, phi = self._angle(s)
        radial = np.cos(phi)[..., None] * self.u + np.sin(phi)[..., None] * self.v
        values = self.center + self.radius * radial
        return _with_ends(values, s, self.length, self.start, self.end)

    def tangent(self, s: ArrayLike) -> Vector:
        _, phi = self._angle(s)
        return -np.sin(phi)[..., None] * self.u + np.cos(phi)[..., None] * self.v

    def curvature(self, s: ArrayLike) -> NDArray[np.float64]:
        return np.full(np.shape(s), 1.0 / self.radius)

    def curvature_vector(self, s: ArrayLike) -> Vector:
        """Curvature times the principal normal [1/mm]: towards the centre, length 1/radius."""
        _, phi = self._angle(s)
        radial = np.cos(phi)[..., None] * self.u + np.sin(phi)[..., None] * self.v
        return -radial / self.radius

    def curvature_rate(self, s: ArrayLike) -> Vector:
        """d(curvature_vector)/ds [1/mm²]: -tangent/radius², length 1/radius²."""
        return -self.tangent(s) / self.radius**2

    @property
    def max_curvature_rate(self) -> float:
        """[1/mm²], the peak of ``|curvature_rate|``: 1/radius² everywhere."""
        return 1.0 / self.radius**2

    def derivative_bounds(self) -> Vector:
        """Per coordinate, the largest |dx/ds|, |d²x/ds²|, |d³x/ds³| on the arc: (3, 3).

        Exact: each coordinate of the tangent and of the curvature vector is a sinusoid
        ``ρ·cos(φ - α)`` of the angle φ in [0, sweep]; its largest magnitude is ρ when a crest
        (φ = α + mπ) lies in the sweep, else the larger end value. The rate is -tangent/R².
        """
        bounds = np.empty((3, 3))
        bounds[0] = _sinusoid_peak(self.v, -self.u, self.sweep)
        bounds[1] = _sinusoid_peak(-self.u, -self.v, self.sweep) / self.radius
        bounds[2] = bounds[0] / self.radius**2
        return bounds

    def substring(self, s_start: float, s_end: float) -> Arc:
        """The part between two arc lengths on the same circle, for trimming at blends."""
        s0, s1 = float(_clamped(s_start, self.length)), float(_clamped(s_end, self.length))
        if s1 - s0 <= TOLERANCE:
            raise _reject("arc: the part to keep is shorter than the tolerance")
        phi = s0 / self.radius
        u = math.cos(phi) * self.u + math.sin(phi) * self.v
        v = np.cross(self.normal, u)
        part = object.__new__(Arc)
        part._set(self.position(s0), self.position(s1), self.center, self.radius, u, v,
                  (s1 - s0) / self.radius)
        return part


def _sinusoid_peak(a: Vector, b: Vector, sweep: float) -> Vector:
    """Largest |a·cos φ + b·sin φ| over φ in [0, sweep], per coordinate."""
    crest = np.remainder(np.arctan2(b, a), math.pi)  # first φ >= 0 where |value| = amplitude
    ends = np.maximum(np.abs(a), np.abs(a * math.cos(sweep) + b * math.sin(sweep)))
    return np.where(crest <= sweep, np.hypot(a, b), ends)


Segment: TypeAlias = Line | Arc
