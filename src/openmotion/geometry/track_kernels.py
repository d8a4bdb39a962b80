"""Compiled loops of track lookups (numba): frames at arc lengths and closest arc lengths.

Movers on tracks ask every cycle where their arc length puts them; hundreds of them per
track. As numpy passes per piece kind the cost is the passes, not the arithmetic, so these
loops do the arithmetic per point in one compiled pass over a flat table of the track
(``TrackTable``, built by ``geometry.track``).

Lines and arcs are evaluated in closed form. A transition's curve parameter u at arc length s
comes from its table: the cubic Hermite interpolant of u(s) between two table entries (slopes
1/|B'|), then Newton steps on s(u) = table + 8-point Gauss-Legendre until the residual they
leave is predicted below ``RESIDUAL``: one step in practice, since the interpolant is already
within about 1e-5 mm on the manual's tracks.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from openmotion.core.compiled import compiled
from openmotion.core.errors import ConfigError
from openmotion.geometry.track_elements import NODES, TABLE_PIECES, WEIGHTS

RESIDUAL = 1e-12  #: [mm] arc-length residual at which the Newton steps stop
_NEWTON = 6  #: Newton steps at most from the interpolated u
_SAMPLES = 32  #: intervals of u searched for a closest point on a transition
_ROOT_STEPS = 60  #: safeguarded Newton steps on one interval at most
LINE, ARC, TRANSITION = 0, 1, 2  #: ``PieceKind`` values, as plain ints for the kernels


class TrackTable(NamedTuple):
    """A track as flat arrays; row k of ``rows`` means, by ``kinds[k]``:
    LINE (x0, y0, cos, sin, heading, 0), ARC (cx, cy, radius, start angle, sense, 0),
    TRANSITION (index j into the transition arrays, 0, ...)."""

    starts: NDArray[np.float64]  #: (m + 1,) [mm] arc length at each piece's start, then total
    kinds: NDArray[np.int64]  #: (m,)
    rows: NDArray[np.float64]  #: (m, 6)
    origins: NDArray[np.float64]  #: (k, 2) [mm] transition starts
    coefficients: NDArray[np.float64]  #: (k, 6, 2) B(u) - origin in powers of u
    first: NDArray[np.float64]  #: (k, 5, 2) dB/du
    second: NDArray[np.float64]  #: (k, 4, 2) d²B/du²
    tables: NDArray[np.float64]  #: (k, TABLE_PIECES + 1) [mm] arc length at u = i/TABLE_PIECES
    speeds: NDArray[np.float64]  #: (k, TABLE_PIECES + 1) |dB/du| there
    boxes: NDArray[np.float64]  #: (k, 4) [mm] xmin, ymin, xmax, ymax of the control points
    closed: bool


@compiled
def _point(c: NDArray[np.float64], j: int, u: float) -> tuple[float, float]:
    """B(u) - origin of transition j by Horner's rule (c: coefficients)."""
    a = c[j]
    x = ((((a[5, 0] * u + a[4, 0]) * u + a[3, 0]) * u + a[2, 0]) * u + a[1, 0]) * u + a[0, 0]
    y = ((((a[5, 1] * u + a[4, 1]) * u + a[3, 1]) * u + a[2, 1]) * u + a[1, 1]) * u + a[0, 1]
    return x, y


@compiled
def _first(c: NDArray[np.float64], j: int, u: float) -> tuple[float, float]:
    """dB/du of transition j (c: first)."""
    a = c[j]
    x = (((a[4, 0] * u + a[3, 0]) * u + a[2, 0]) * u + a[1, 0]) * u + a[0, 0]
    y = (((a[4, 1] * u + a[3, 1]) * u + a[2, 1]) * u + a[1, 1]) * u + a[0, 1]
    return x, y


@compiled
def _second(c: NDArray[np.float64], j: int, u: float) -> tuple[float, float]:
    """d²B/du² of transition j (c: second)."""
    a = c[j]
    x = ((a[3, 0] * u + a[2, 0]) * u + a[1, 0]) * u + a[0, 0]
    y = ((a[3, 1] * u + a[2, 1]) * u + a[1, 1]) * u + a[0, 1]
    return x, y


@compiled
def _speed(first: NDArray[np.float64], j: int, u: float) -> float:
    x, y = _first(first, j, u)
    return math.sqrt(x * x + y * y)


@compiled
def _integral(first: NDArray[np.float64], j: int, lo: float, hi: float) -> float:
    """Arc length of transition j between curve parameters lo and hi (Gauss-Legendre)."""
    width = hi - lo
    total = 0.0
    for q in range(NODES.size):
        total += WEIGHTS[q] * _speed(first, j, lo + width * NODES[q])
    return width * total


@compiled
def _parameter(first: NDArray[np.float64], second: NDArray[np.float64],
               tables: NDArray[np.float64], speeds: NDArray[np.float64], j: int,
               s: float) -> float:
    """The curve parameter of transition j at its arc length s.

    After a Newton step δu the arc-length residual is σ'·δu²/2 up to higher orders
    (σ = |B'|, σ' = B'·B''/σ): the loop stops when that is below ``RESIDUAL``.
    """
    lo, hi = 0, TABLE_PIECES
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if tables[j, mid] <= s:
            lo = mid
        else:
            hi = mid
    s0, h = tables[j, lo], tables[j, lo + 1] - tables[j, lo]
    t = min(max((s - s0) / h, 0.0), 1.0)
    u0, du = lo / TABLE_PIECES, 1.0 / TABLE_PIECES
    t2, t3 = t * t, t * t * t
    u = (u0 * (2.0 * t3 - 3.0 * t2 + 1.0) + (u0 + du) * (3.0 * t2 - 2.0 * t3)
         + h / speeds[j, lo] * (t3 - 2.0 * t2 + t) + h / speeds[j, lo + 1] * (t3 - t2))
    for _ in range(_NEWTON):
        step = (s - s0 - _integral(first, j, u0, u)) / _speed(first, j, u)
        u += step
        dx, dy = _first(first, j, u)
        ddx, ddy = _second(second, j, u)
        speed = math.sqrt(dx * dx + dy * dy)
        if 0.5 * abs(dx * ddx + dy * ddy) / speed * step * step <= RESIDUAL:
            break
    return min(max(u, 0.0), 1.0)


@compiled
def _piece(starts: NDArray[np.float64], s: float) -> int:
    """Index of the piece holding arc length s (the last one for s = length)."""
    lo, hi = 0, starts.size - 2
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if starts[mid] <= s:
            lo = mid
        else:
            hi = mid - 1
    return lo


@compiled
def _wrapped(s: float, length: float, closed: bool) -> float:
    if closed:
        s = s - length * math.floor(s / length)
        return 0.0 if s >= length else s
    return min(max(s, 0.0), length)


@compiled
def frames(s: NDArray[np.float64], starts: NDArray[np.float64], kinds: NDArray[np.int64],
           rows: NDArray[np.float64], origins: NDArray[np.float64],
           coefficients: NDArray[np.float64], first: NDArray[np.float64],
           second: NDArray[np.float64], tables: NDArray[np.float64],
           speeds: NDArray[np.float64], closed: bool) -> NDArray[np.float64]:
    """x, y [mm], heading [rad, in (-π, π]] and curvature [1/mm] at each arc length: (n, 4).

    Arc lengths are taken modulo the length on a closed track, clamped to it on an open one.
    """
    length = starts[-1]
    out = np.empty((s.size, 4))
    for i in range(s.size):
        if not math.isfinite(s[i]):
            raise ConfigError("arc lengths must be finite numbers [mm]")
        si = _wrapped(s[i], length, closed)
        k = _piece(starts, si)
        local = min(si - starts[k], starts[k + 1] - starts[k])
        row = rows[k]
        if kinds[k] == LINE:
            out[i, 0] = row[0] + local * row[2]
            out[i, 1] = row[1] + local * row[3]
            out[i, 2] = row[4]
            out[i, 3] = 0.0
        elif kinds[k] == ARC:
            radius, sense = row[2], row[4]
            phi = row[3] + sense * local / radius
            out[i, 0] = row[0] + radius * math.cos(phi)
            out[i, 1] = row[1] + radius * math.sin(phi)
            heading = phi + sense * 0.5 * math.pi
            out[i, 2] = math.atan2(math.sin(heading), math.cos(heading))
            out[i, 3] = sense / radius
        else:
            j = int(row[0])
            u = _parameter(first, second, tables, speeds, j, local)
            x, y = _point(coefficients, j, u)
            dx, dy = _first(first, j, u)
            ddx, ddy = _second(second, j, u)
            speed2 = dx * dx + dy * dy
            out[i, 0] = origins[j, 0] + x
            out[i, 1] = origins[j, 1] + y
            out[i, 2] = math.atan2(dy, dx)
            out[i, 3] = (dx * ddy - dy * ddx) / (speed2 * math.sqrt(speed2))
    return out


@compiled
def _closest_on_transition(coefficients: NDArray[np.float64], first: NDArray[np.float64],
                           second: NDArray[np.float64], j: int, px: float,
                           py: float) -> tuple[float, float]:
    """Curve parameter and squared distance of transition j's point closest to (px, py).

    Minima of the squared distance are the ends and the roots of g(u) = (B - p)·B' where g
    goes from - to +; g is sampled on ``_SAMPLES`` intervals and each sign change is solved by
    Newton kept inside its interval (bisection where a step would leave it).
    """
    best_u, best = 0.0, px * px + py * py
    x, y = _point(coefficients, j, 1.0)
    if (x - px) ** 2 + (y - py) ** 2 < best:
        best_u, best = 1.0, (x - px) ** 2 + (y - py) ** 2
    u_prev, g_prev = 0.0, 0.0
    for k in range(_SAMPLES + 1):
        u = k / _SAMPLES
        x, y = _point(coefficients, j, u)
        dx, dy = _first(first, j, u)
        g = (x - px) * dx + (y - py) * dy
        if k > 0 and g_prev < 0.0 <= g:
            lo, hi = u_prev, u
            r = 0.5 * (lo + hi)
            for _ in range(_ROOT_STEPS):
                x, y = _point(coefficients, j, r)
                dx, dy = _first(first, j, r)
                ddx, ddy = _second(second, j, r)
                gr = (x - px) * dx + (y - py) * dy
                if gr < 0.0:
                    lo = r
                else:
                    hi = r
                slope = dx * dx + dy * dy + (x - px) * ddx + (y - py) * ddy
                step = r - gr / slope if slope > 0.0 else -1.0
                r_next = step if lo < step < hi else 0.5 * (lo + hi)
                if abs(r_next - r) <= 1e-16 or hi - lo <= 1e-16:
                    r = r_next
                    break
                r = r_next
            x, y = _point(coefficients, j, r)
            d2 = (x - px) ** 2 + (y - py) ** 2
            if d2 < best:
                best_u, best = r, d2
        u_prev, g_prev = u, g
    return best_u, best


@compiled
def closest(points: NDArray[np.float64], starts: NDArray[np.float64],
            kinds: NDArray[np.int64], rows: NDArray[np.float64], origins: NDArray[np.float64],
            coefficients: NDArray[np.float64], first: NDArray[np.float64],
            second: NDArray[np.float64], tables: NDArray[np.float64],
            boxes: NDArray[np.float64], closed: bool) -> NDArray[np.float64]:
    """For each point (n, 2): the arc length of the closest track point and the distance [mm],
    (n, 2). Ties go to the smaller arc length; on a closed track the result is in [0, length).
    """
    length = starts[-1]
    out = np.empty((points.shape[0], 2))
    for i in range(points.shape[0]):
        px, py = points[i, 0], points[i, 1]
        if not (math.isfinite(px) and math.isfinite(py)):
            raise ConfigError("points must be finite numbers [mm]")
        best, best_s = np.inf, 0.0
        for k in range(kinds.size):
            row = rows[k]
            piece_length = starts[k + 1] - starts[k]
            if kinds[k] == LINE:
                along = (px - row[0]) * row[2] + (py - row[1]) * row[3]
                local = min(max(along, 0.0), piece_length)
                distance = math.hypot(px - row[0] - local * row[2], py - row[1] - local * row[3])
            elif kinds[k] == ARC:
                local, distance = _closest_on_arc(row, piece_length, px, py)
            else:
                j = int(row[0])
                box = boxes[j]
                outside = math.hypot(max(box[0] - px, 0.0, px - box[2]),
                                     max(box[1] - py, 0.0, py - box[3]))
                if outside >= best:
                    continue
                u, d2 = _closest_on_transition(coefficients, first, second, j,
                                               px - origins[j, 0], py - origins[j, 1])
                piece = min(int(u * TABLE_PIECES), TABLE_PIECES - 1)
                local = tables[j, piece] + _integral(first, j, piece / TABLE_PIECES, u)
                local = min(max(local, 0.0), piece_length)
                distance = math.sqrt(d2)
            if distance < best:
                best, best_s = distance, starts[k] + local
        if closed and best_s >= length:
            best_s = 0.0
        out[i, 0], out[i, 1] = best_s, best
    return out


@compiled
def _closest_on_arc(row: NDArray[np.float64], piece_length: float, px: float,
                    py: float) -> tuple[float, float]:
    cx, cy, radius, start, sense = row[0], row[1], row[2], row[3], row[4]
    r = math.hypot(px - cx, py - cy)
    if r == 0.0:
        return 0.0, radius
    turned = (sense * (math.atan2(py - cy, px - cx) - start)) % (2.0 * math.pi)
    if turned * radius <= piece_length:
        return turned * radius, abs(r - radius)
    end = start + sense * piece_length / radius
    to_start = math.hypot(px - cx - radius * math.cos(start), py - cy - radius * math.sin(start))
    to_end = math.hypot(px - cx - radius * math.cos(end), py - cy - radius * math.sin(end))
    if to_end < to_start:
        return piece_length, to_end
    return 0.0, to_start
