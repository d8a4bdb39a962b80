"""Caps on the path parameter that keep every axis of a group within its own limits.

PLCopen Part 4 gives a path move (MC_MoveLinear*, MC_MoveCircular*, §5.20-§5.23) a Velocity,
Acceleration, Deceleration and Jerk for the path, maxima that are "not necessarily reached";
MC_MoveDirect* (§5.24, §5.25) has none, and its axes move within their own limits. Either way
no axis may exceed its own. The time law along an element (coordinated/timing.py) takes four
caps V, A, D, J on the path parameter s and keeps 0 <= s' <= V, -D <= s'' <= A, |s'''| <= J.
This module chooses the caps so that *every* such s(t) keeps every axis within its limits,
with the FB's dynamics (already scaled by the override, §5.28) as upper bounds.

Chain rule. An axis at q(s) moves with

    q' = q_s·s'      q'' = q_s·s'' + q_ss·s'²      q''' = q_s·s''' + 3·q_ss·s'·s'' + q_sss·s'³

where q_s, q_ss, q_sss are its derivatives by arc length. For a Cartesian gantry they are the
element's unit tangent t, curvature vector k and its rate k', coordinate by coordinate. Let
T, K, R bound |q_s|, |q_ss|, |q_sss| over the element, per axis (``derivative_bounds``).

Budget. With v, a, j an axis' velocity, acceleration and jerk limits (a the smaller of its
acceleration and deceleration: on a curve an axis may speed up or slow down whichever way the
path goes) and M = max(A, D), over all axes:

    V = min(Velocity,     v/T,  sqrt(a / 2K),  cbrt(3j / 4R))
    A = min(Acceleration, (a - K·V²)/T,  j / (24·K·V))        D the same with Deceleration
    J = min(Jerk,         (j - R·V³ - 3·K·V·M)/T)

Proof, per axis: |q'| <= T·V <= v; |q''| <= T·M + K·V² <= a; |q'''| <= T·J + 3·K·V·M + R·V³ <= j.
All caps are positive: K·V² <= a/2 leaves at least half the acceleration to the path, and
R·V³ <= 3j/4, 3·K·V·M <= j/8 leave at least an eighth of the jerk. The split (half of a to the
centripetal term; three quarters of j to the curvature rate, an eighth to the turning term,
the rest to the path: ``CENTRIPETAL_SHARE``, ``CURVATURE_RATE_SHARE``, ``TURNING_SHARE``) is
fixed: a few operations per element and no policy for trading speed against acceleration.
It is not loose: on random arcs and blends some axis reaches its limit in the worst case.

The shares favour speed on curves. At a steady speed (s'' = s''' = 0) only K·V² and R·V³ load
the axes, so the highest steady speed an element allows is min(v/T, sqrt(a/K), cbrt(j/R))
(``steady_speed``); the caps reach sqrt(1/2) of it where the curvature binds and cbrt(3/4)
(0.91) where its rate does. The rate binds on short contours: a dense path of chords rounded
by tiny blends runs at the contours' V throughout, so their V sets its speed, while the
path's own A, D and J only shape its few speed changes (decisions D-134, `bench path`).
A dense path's contours (``many_limits``) may give the rate up to 0.97 of the jerk: its
profile changes the acceleration on the lines between them (D-335, D-336).

Straight elements (K = R = 0 on every axis: a gantry's lines, MoveDirect's lines in ACS) are
exact: each axis keeps the sign of its velocity, so speeding the path up speeds every axis up,
and V = min(Velocity, v/T), A = min(Acceleration, acceleration/T), D = min(Deceleration,
deceleration/T), J = min(Jerk, j/T). The binding axis reaches its limit exactly when the path
reaches the cap: the time law is time-optimal for the axes too.

Where T, K, R come from:

- Cartesian gantry (``cartesian_limits``): the element's own bounds, exact for Line and Arc;
  for a blend Contour sampled with an allowance for the curve between samples, at most ~2e-4
  above the true peak (geometry/blend.py, ``_peaks``).
- Other kinematics (``sampled_limits``): sampled, not proven. q_s = J⁻¹·t from the Jacobian at
  n points along the element, q_ss and q_sss from second-order differences of q_s. n doubles
  until the samples resolve the map (no axis' q_s/v changes between neighbours by more than
  5 % of the largest q_s/v: a singular pose near the path shows as a steep rise) and the caps
  from every sample and from every other sample agree within 1 %; past 32768 samples the
  element is rejected as too close to a singular pose. The sampled peaks are multiplied by
  ``SAMPLED_MARGIN``: the axes then peak near 1/1.1 of their limits, and the 10 % covers
  what the samples miss.

Units: s is in mm on a path; on a ``DirectLine`` it is the Euclidean length in the axes'
own units (mm and ° mixed). Axis limits are in each axis' units.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

from openmotion.coordinated.kinematics import CartesianGantry, Configuration, Kinematics
from openmotion.coordinated.tolerances import UNDRIVEN
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.geometry.blend import Contour
from openmotion.geometry.path import TOLERANCE, Arc, Line
from openmotion.trajectory.plan import Limits

Array = NDArray[np.float64]
PathElement: TypeAlias = Line | Arc | Contour  #: an element of a Cartesian path, in MCS [mm]

PATH_COORDINATES = ("x", "y", "z")  #: the MCS coordinates of a path element, in its order
SAMPLED_MARGIN = 1.1  #: factor on the sampled derivative peaks of non-Cartesian kinematics
SAMPLE_RESOLUTION = 1.0  #: [mm] first sample spacing of ``sampled_limits``
_CONVERGED = 0.01  #: caps from n and n/2 samples that agree this well are taken
_RESOLVED = 0.05  #: largest change of any axis' q_s/v between samples, of the largest q_s/v
_MIN_SAMPLES, _MAX_SAMPLES = 32, 2**15  #: sample intervals along one element
_SINGULAR_CONDITION = 1e8  #: a Jacobian worse than this on the path: the axes cannot follow
CENTRIPETAL_SHARE = 0.5  #: of an axis' acceleration, the most K·V² takes on a curve
CURVATURE_RATE_SHARE = 0.75  #: of an axis' jerk, the most R·V³ takes
TURNING_SHARE = 0.125  #: of an axis' jerk, the most 3·K·V·M takes; the path keeps the rest
#: the (curvature rate, turning) shares a dense path's contours may take (``many_limits``):
#: its profile changes the acceleration on the lines between them and needs little path
#: jerk on them, so the path keeps a hundredth; the one that plans fastest is taken (D-336)
DENSE_SHARES = ((0.97, 0.02), (0.94, 0.05), (0.89, 0.10), (0.79, 0.20))


class DirectLine:
    """The straight line in ACS from ``start`` to ``end`` that MC_MoveDirect* moves along.

    §5.24 prescribes no path: the axes move the shortest way, reach the target together
    (synchronised PTP, §2.3) and at least one of them is at its limit. A straight line in ACS
    with the caps of ``direct_limits`` does all three. ``s`` is the Euclidean length in the
    axes' own units (mm and °), clamped to ``[0, length]``.
    """

    def __init__(self, start: ArrayLike, end: ArrayLike) -> None:
        self.start, self.end = _acs_point(start, "start"), _acs_point(end, "end")
        if self.start.shape != self.end.shape:
            raise CommandRejected(ErrorId.INVALID_POSITION, "direct move: start and end need "
                                  f"the same number of axes, got {self.start.size} and "
                                  f"{self.end.size}")
        chord = self.end - self.start
        self.length = float(np.linalg.norm(chord))  #: [mm or °, mixed]
        if self.length <= TOLERANCE:
            raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY,
                                  "direct move: start and end coincide")
        self.direction = chord / self.length  #: unit vector, one entry per axis

    def __repr__(self) -> str:
        return f"DirectLine(start={self.start.tolist()}, end={self.end.tolist()})"

    def position(self, s: ArrayLike) -> Array:
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.length)
        values = self.start + s[..., None] * self.direction
        return np.where((s >= self.length)[..., None], self.end, values)

    def tangent(self, s: ArrayLike) -> Array:
        return np.broadcast_to(self.direction, np.shape(s) + self.direction.shape).copy()

    def derivative_bounds(self) -> Array:
        """Per axis, the largest |dq/ds|, |d²q/ds²|, |d³q/ds³|: (3, n_axes), exact."""
        bounds = np.zeros((3, self.direction.size))
        bounds[0] = np.abs(self.direction)
        return bounds


def path_limits(element: PathElement, kinematics: Kinematics, axis_limits: Sequence[Limits],
                commanded: Limits, *, configuration: Configuration | None = None,
                orientation: Mapping[str, float] | None = None,
                resolution: float = SAMPLE_RESOLUTION) -> Limits:
    """Caps on s for one path element: exact for a Cartesian gantry, else sampled.

    ``axis_limits`` holds one ``Limits`` per ACS axis (its maximum velocity, acceleration,
    deceleration and jerk, in mm or ° per s, s², s³); ``commanded`` the FB's Velocity,
    Acceleration, Deceleration and Jerk after override (inf where none). The keywords
    matter only for non-Cartesian kinematics, see ``sampled_limits``.
    """
    if isinstance(kinematics, CartesianGantry):
        return cartesian_limits(element, kinematics, axis_limits, commanded)
    return sampled_limits(element, kinematics, axis_limits, commanded,
                          configuration=configuration, orientation=orientation,
                          resolution=resolution)


def cartesian_limits(element: PathElement, gantry: CartesianGantry,
                     axis_limits: Sequence[Limits], commanded: Limits) -> Limits:
    """Caps on s for a gantry: axis k moves along the MCS coordinate ``gantry.mapping[k]``.

    Proven (module text), from the element's ``derivative_bounds``. Axes that drive an
    orientation (a, b, c) stand still on a path. Rejects an element that moves along a
    coordinate no axis drives (TARGET_UNREACHABLE).
    """
    bounds = element.derivative_bounds()
    _check_driven(bounds[0], gantry.coordinates, element)
    return limits_from_bounds(_gantry_bounds(bounds, gantry), axis_limits, commanded)


def line_limits(directions: ArrayLike, gantry: CartesianGantry, axis_limits: Sequence[Limits],
                commanded: Limits) -> Array:
    """Caps for many lines of a gantry at once: (m, 4) of velocity, acceleration,
    deceleration and jerk, from (m, 3) directions (any length > 0: each row is normalised).

    Equal to ``cartesian_limits`` line by line, for dense paths of many short lines.
    """
    d = np.asarray(directions, dtype=float)
    if d.ndim != 2 or d.shape[1] != 3:
        raise CommandRejected(ErrorId.INVALID_POSITION, "line directions: need shape (m, 3), "
                              f"got {d.shape}")
    # each row's length as Line measures its chord (a 1-D norm is a BLAS dot product, which
    # can round differently from a reduction over rows): equal caps bit for bit
    size = np.array([[np.linalg.norm(row)] for row in d]).reshape(len(d), 1)
    if not np.all(np.isfinite(size) & (size > 0.0)):
        raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY,
                              "line directions: every row must be finite and not zero")
    d = np.abs(d / size)
    undriven = [i for i, c in enumerate(PATH_COORDINATES) if c not in gantry.coordinates]
    if undriven and np.any(d[:, undriven] > UNDRIVEN):
        row = int(np.argmax(np.any(d[:, undriven] > UNDRIVEN, axis=1)))
        _check_driven(d[row], gantry.coordinates, f"line {row}")
    columns = _gantry_columns(gantry)
    tangent = np.where(columns >= 0, d[:, columns], 0.0)  # (m, n_axes)
    limit = _axis_arrays(axis_limits, gantry.n_axes)
    caps = np.empty((len(d), 4))
    for c, (cap, lim) in enumerate(zip(_commanded(commanded), limit, strict=True)):
        caps[:, c] = _capped_many(cap, np.max(tangent / lim, axis=1))
    return caps


def many_limits(bounds: ArrayLike, gantry: CartesianGantry, axis_limits: Sequence[Limits],
                commanded: Limits, *, rate_share: float = CURVATURE_RATE_SHARE,
                turning_share: float = TURNING_SHARE) -> Array:
    """``cartesian_limits`` of many elements at once from their derivative bounds (n, 3, 3):
    (n, 4) of velocity, acceleration, deceleration and jerk, equal to it element by element
    to round-off with the default shares. A dense path's contours (coordinated/dense.py)
    take one of ``DENSE_SHARES`` (D-336): the proof of the module text holds for any shares
    that leave the path a part of the jerk."""
    if not (rate_share > 0.0 and turning_share > 0.0 and rate_share + turning_share < 1.0):
        raise ConfigError("many_limits: the curvature-rate and turning shares must be > 0 and "
                          f"leave the path a part of the jerk, got {rate_share} and "
                          f"{turning_share}")
    b = np.asarray(bounds, dtype=float)
    for i, name in enumerate(PATH_COORDINATES):
        if name not in gantry.coordinates and np.any(b[:, 0, i] > UNDRIVEN):
            row = int(np.argmax(b[:, 0, i] > UNDRIVEN))
            _check_driven(b[row, 0], gantry.coordinates, f"element {row}")
    columns = _gantry_columns(gantry)
    g = np.where(columns >= 0, b[:, :, columns], 0.0)  # (n, 3, n_axes): T, K, R
    t, k, r = g[:, 0], g[:, 1], g[:, 2]
    v, acc, dec, jerk = _axis_arrays(axis_limits, gantry.n_axes)
    c_vel, c_acc, c_dec, c_jerk = _commanded(commanded)
    a = np.minimum(acc, dec)
    caps = np.empty((len(b), 4))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        velocity = _capped_many(c_vel, np.maximum.reduce([
            np.max(t / v, axis=1), np.sqrt(np.max(k / (CENTRIPETAL_SHARE * a), axis=1)),
            np.cbrt(np.max(r / (rate_share * jerk), axis=1))]))
        square = velocity[:, None] ** 2
        rate = np.maximum(np.max(t / (a - k * square), axis=1),
                          np.max(3.0 * k * velocity[:, None] / (turning_share * jerk), axis=1))
        acceleration, deceleration = _capped_many(c_acc, rate), _capped_many(c_dec, rate)
        rest = jerk - r * velocity[:, None] ** 3 \
            - 3.0 * k * velocity[:, None] * np.maximum(acceleration, deceleration)[:, None]
        caps[:] = np.column_stack([velocity, acceleration, deceleration,
                                   _capped_many(c_jerk, np.max(t / rest, axis=1))])
        straight = ~(k.any(axis=1) | r.any(axis=1))
        if straight.any():
            for c, (cap, lim) in enumerate(zip((c_vel, c_acc, c_dec, c_jerk),
                                               (v, acc, dec, jerk), strict=True)):
                caps[straight, c] = _capped_many(cap, np.max(t[straight] / lim, axis=1))
    unbounded = ~np.isfinite(velocity) & ~straight
    caps[unbounded] = (c_vel, c_acc, c_dec, c_jerk)  # no axis limit and no command
    return caps


def sampled_limits(element: PathElement, kinematics: Kinematics, axis_limits: Sequence[Limits],
                   commanded: Limits, *, configuration: Configuration | None = None,
                   orientation: Mapping[str, float] | None = None,
                   resolution: float = SAMPLE_RESOLUTION) -> Limits:
    """Caps on s for any kinematics, from the axis positions sampled along the element.

    Sampled, not proven (module text): the first spacing is ``resolution`` [mm] (32 to 32768
    intervals), halved until the samples resolve the map and the caps settle within 1 %.
    ``orientation`` gives the MCS orientation coordinates (a, b, c [°]) that the model has
    and the path holds, default 0; ``configuration`` the inverse solution. Raises
    TARGET_UNREACHABLE where the element leaves the workspace or an axis range,
    KINEMATICS_SINGULAR where it meets or passes too close to a singular pose, naming the
    MCS position.
    """
    if not (math.isfinite(resolution) and resolution > 0.0):
        raise ConfigError(f"resolution: must be a length > 0 mm, got {resolution}")
    velocity = _axis_arrays(axis_limits, kinematics.n_axes)[0]
    n = 2 * math.ceil(min(max(element.length / resolution, _MIN_SAMPLES), _MAX_SAMPLES) / 2)
    while True:
        s = np.linspace(0.0, element.length, n + 1)
        first = _axis_rates(element, kinematics, s, configuration, orientation)
        # resolved: the axes' speed per path speed changes by little from sample to sample
        step = np.abs(np.diff(first / velocity, axis=0)).max(axis=1)
        resolved = step.max() <= _RESOLVED * np.abs(first / velocity).max()
        fine = _difference_bounds(first, element.length / n)
        coarse = _difference_bounds(first[::2], 2.0 * element.length / n)
        caps = limits_from_bounds(SAMPLED_MARGIN * fine, axis_limits, commanded)
        check = limits_from_bounds(SAMPLED_MARGIN * coarse, axis_limits, commanded)
        if resolved and np.allclose(_commanded(caps), _commanded(check), rtol=_CONVERGED,
                                    atol=0.0):
            return caps
        if 2 * n > _MAX_SAMPLES:
            worst = s[int(np.argmax(step))]
            raise CommandRejected(ErrorId.KINEMATICS_SINGULAR, (
                f"{type(kinematics).__name__}: near MCS position "
                f"{_fmt(element.position(worst))} (s = {worst:.6g} mm of {element!r}) the "
                "axes' speeds change too fast to follow: too close to a singular pose"))
        n *= 2


def direct_limits(line: DirectLine, axis_limits: Sequence[Limits],
                  commanded: Limits | None = None) -> Limits:
    """Caps on s for MC_MoveDirect* (§5.24, §5.25): exact, each at the binding axis' limit.

    §5.24 has no dynamics inputs; ``commanded`` is for a caller that caps them anyway, such
    as the override (§5.28).
    """
    if commanded is None:
        commanded = Limits(math.inf, math.inf, math.inf, math.inf)
    return limits_from_bounds(line.derivative_bounds(), axis_limits, commanded)


def limits_from_bounds(bounds: ArrayLike, axis_limits: Sequence[Limits],
                       commanded: Limits) -> Limits:
    """The budget of the module text: caps on s from the per-axis bounds T, K, R (3, n_axes).

    Exact for straight elements (K = R = 0 everywhere), where acceleration and deceleration
    are capped separately.
    """
    t, k, r = np.asarray(bounds, dtype=float)  # T, K, R of the module text
    v, acc, dec, jerk = _axis_arrays(axis_limits, len(t))
    c_vel, c_acc, c_dec, c_jerk = _commanded(commanded)
    if not (k.any() or r.any()):
        return Limits(_capped(c_vel, np.max(t / v)), _capped(c_acc, np.max(t / acc)),
                      _capped(c_dec, np.max(t / dec)), _capped(c_jerk, np.max(t / jerk)))
    a = np.minimum(acc, dec)
    velocity = _capped(c_vel, max(np.max(t / v),
                                  math.sqrt(np.max(k / (CENTRIPETAL_SHARE * a))),
                                  math.cbrt(np.max(r / (CURVATURE_RATE_SHARE * jerk)))))
    if not math.isfinite(velocity):  # no axis limit and no command: nothing to divide
        return commanded
    rate = max(np.max(t / (a - k * velocity**2)),
               np.max(3.0 * k * velocity / (TURNING_SHARE * jerk)))
    acceleration, deceleration = _capped(c_acc, rate), _capped(c_dec, rate)
    rest = jerk - r * velocity**3 - 3.0 * k * velocity * max(acceleration, deceleration)
    return Limits(velocity, acceleration, deceleration, _capped(c_jerk, np.max(t / rest)))


def steady_speed(element: PathElement, gantry: CartesianGantry,
                 axis_limits: Sequence[Limits]) -> float:
    """The highest constant path speed [mm/s] along ``element`` at which every axis of the
    gantry keeps its limits: min(v/T, sqrt(a/K), cbrt(j/R)) over the axes (module text).

    Not a cap: speeding up or slowing down needs more than it leaves. It measures what the
    shares of the budget give up, and bounds any motion that holds its speed over the
    element (``openmotion bench path``).
    """
    bounds = element.derivative_bounds()
    _check_driven(bounds[0], gantry.coordinates, element)
    t, k, r = _gantry_bounds(bounds, gantry)
    v, acc, dec, jerk = _axis_arrays(axis_limits, len(t))
    with np.errstate(divide="ignore"):
        speeds = np.minimum.reduce([v / t, np.sqrt(np.minimum(acc, dec) / k),
                                    np.cbrt(jerk / r)])
    return float(speeds.min())


def _capped(commanded: float, rate: float) -> float:
    """min(commanded, 1/rate): an axis that needs ``rate`` per unit of the cap allows 1/rate."""
    return float(commanded) if rate <= 0.0 else min(float(commanded), 1.0 / float(rate))


def _capped_many(commanded: float, rate: Array) -> Array:
    """``_capped`` for an array of rates."""
    with np.errstate(divide="ignore"):
        return np.minimum(commanded, 1.0 / rate)


def _commanded(limits: Limits) -> tuple[float, float, float, float]:
    return limits.velocity, limits.acceleration, limits.deceleration, limits.jerk


def _axis_arrays(axis_limits: Sequence[Limits], n_axes: int) -> Array:
    """(4, n_axes): velocity, acceleration, deceleration and jerk of every axis."""
    if len(axis_limits) != n_axes:
        raise ConfigError(f"axis_limits: need {n_axes} entries (one per axis), "
                          f"got {len(axis_limits)}")
    return np.array([_commanded(limits) for limits in axis_limits], dtype=float).T


def _gantry_columns(gantry: CartesianGantry) -> NDArray[np.intp]:
    """Per axis, the path coordinate it drives (0, 1, 2), or -1 for an orientation axis."""
    return np.array([PATH_COORDINATES.index(c) if c in PATH_COORDINATES else -1
                     for c in gantry.mapping])


def _gantry_bounds(bounds: Array, gantry: CartesianGantry) -> Array:
    columns = _gantry_columns(gantry)
    return np.where(columns >= 0, bounds[:, columns], 0.0)


def _check_driven(tangent_bounds: Array, coordinates: tuple[str, ...],
                  what: object) -> None:
    """Reject a path that moves along x, y or z where the model has no such coordinate."""
    for i, name in enumerate(PATH_COORDINATES):
        if name not in coordinates and tangent_bounds[i] > UNDRIVEN:
            raise CommandRejected(ErrorId.TARGET_UNREACHABLE, (
                f"{what!s}: the path moves along {name}, which no axis of the group drives "
                f"(the kinematics has {', '.join(coordinates)})"))


def _mcs(values: Array, coordinates: tuple[str, ...], held: Mapping[str, float]) -> Array:
    """Path coordinates (m, 3) as MCS vectors of the model: orientations held at ``held``."""
    columns = [values[:, PATH_COORDINATES.index(c)] if c in PATH_COORDINATES
               else np.full(len(values), float(held.get(c, 0.0))) for c in coordinates]
    return np.stack(columns, axis=1)


def _axis_rates(element: PathElement, kinematics: Kinematics, s: Array,
                configuration: Configuration | None,
                orientation: Mapping[str, float] | None) -> Array:
    """dq/ds at every s: the Jacobian solved for the element's tangent. (len(s), n_axes)."""
    tangent = element.tangent(s)
    _check_driven(np.abs(tangent).max(axis=0), kinematics.coordinates, element)
    points = _mcs(element.position(s), kinematics.coordinates, orientation or {})
    try:
        q = kinematics.inverse(points, configuration)
        jacobian = kinematics.jacobian(q)
    except CommandRejected as error:
        raise CommandRejected(error.error_id, f"{element!r}: {error.message}") from error
    try:
        inverse = np.linalg.inv(jacobian)
        size = np.linalg.norm(jacobian, axis=(1, 2)) * np.linalg.norm(inverse, axis=(1, 2))
    except np.linalg.LinAlgError:  # exactly singular somewhere
        inverse, size = None, np.linalg.cond(jacobian)
    bad = ~(size <= _SINGULAR_CONDITION)  # Frobenius: between cond and n_axes·cond
    if inverse is None or np.any(bad):
        i = int(np.argmax(bad))
        raise CommandRejected(ErrorId.KINEMATICS_SINGULAR, (
            f"{type(kinematics).__name__}: the path meets a singular pose at MCS position "
            f"{_fmt(points[i])} (s = {s[i]:.6g} mm of {element!r}), where the axes cannot "
            "follow it"))
    return np.einsum("mij,mj->mi", inverse, _mcs(tangent, kinematics.coordinates, {}))


def _third_differences(first: Array, h: float) -> Array:
    """d²(dq/ds)/ds² by second differences, one-sided (second order) at both ends."""
    third = np.empty_like(first)
    third[1:-1] = first[2:] - 2.0 * first[1:-1] + first[:-2]
    third[0] = 2.0 * first[0] - 5.0 * first[1] + 4.0 * first[2] - first[3]
    third[-1] = 2.0 * first[-1] - 5.0 * first[-2] + 4.0 * first[-3] - first[-4]
    return third / (h * h)


def _difference_bounds(first: Array, h: float) -> Array:
    """Sampled peaks of |q_s|, |q_ss|, |q_sss| per axis (3, n_axes), from q_s at spacing h."""
    second = np.gradient(first, h, axis=0, edge_order=2)
    return np.stack([np.abs(first).max(axis=0), np.abs(second).max(axis=0),
                     np.abs(_third_differences(first, h)).max(axis=0)])


def _acs_point(value: ArrayLike, name: str) -> Array:
    array = np.asarray(value, dtype=float)
    if array.ndim != 1 or array.size == 0 or not np.all(np.isfinite(array)):
        raise CommandRejected(ErrorId.INVALID_POSITION,
                              f"{name} must be finite axis positions, one per axis")
    return array


def _fmt(values: Array) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in values) + ")"
