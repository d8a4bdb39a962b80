"""Compiled loops over many blend contours at once (numba), for dense paths (D-290).

A 10 000-chord path has about as many contours. Each one's arc-length table, cusp test,
corner deviation and derivative bounds are numpy calls on a few hundred samples in
geometry/blend.py: tens of microseconds of interpreter work per contour and call, seconds for
the path. These loops do the same sampling, refinement and allowances, contour after contour,
from the contours' polynomial coefficients; they agree with blend.py to round-off (the sums
run in another order), not bit for bit, so only dense paths use them (coordinated/dense.py).

Inputs per contour: ``power`` (5, 3), B' in powers of u (``Contour`` keeps it); ``offsets``
(6, 3), the control points less the start; ``derivatives`` (5, 9), B', B'', B''' in powers
of u (``Contour.derivatives_in_powers``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from openmotion.core.compiled import compiled

_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(8)


@compiled(inline=True)
def _speed(power: NDArray[np.float64], u: float) -> float:
    """|B'(u)|, Horner's rule per coordinate (blend.Contour._speed)."""
    total = 0.0
    for c in range(3):
        value = power[4, c] * u + power[3, c]
        value = value * u + power[2, c]
        value = value * u + power[1, c]
        value = value * u + power[0, c]
        total += value * value
    return math.sqrt(total)


@compiled
def arc_tables(power: NDArray[np.float64], pieces: int, nodes: NDArray[np.float64],
               weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """(n, pieces + 1): arc length at u = k/pieces, 8-point Gauss-Legendre per piece."""
    n = power.shape[0]
    table = np.zeros((n, pieces + 1))
    for i in range(n):
        total = 0.0
        for k in range(pieces):
            lo, hi = k / pieces, (k + 1) / pieces
            half = 0.5 * (hi - lo)
            part = 0.0
            for g in range(nodes.size):
                part += _speed(power[i], (lo + half) + half * nodes[g]) * weights[g]
            total += half * part
            table[i, k + 1] = total
    return table


@compiled
def cusps(power: NDArray[np.float64], samples: int, regular: float) -> NDArray[np.bool_]:
    """Per contour: its parametric speed falls to ``regular`` of its largest, or is not
    finite, at one of ``samples`` equally spaced parameters (blend.Contour's cusp test)."""
    n = power.shape[0]
    out = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        low, high, finite = math.inf, 0.0, True
        for k in range(samples):
            s = _speed(power[i], k / (samples - 1))
            if not math.isfinite(s):
                finite = False
            low, high = min(low, s), max(high, s)
        out[i] = (not finite) or low <= regular * high
    return out


@compiled(inline=True)
def _negative_distance(offsets: NDArray[np.float64], target: NDArray[np.float64],
                       u: float) -> float:
    """-|B(u) - start - target| with B from its control offsets (quintic Bernstein)."""
    w = 1.0 - u
    u2, w2 = u * u, w * w
    b0, b1, b2 = w2 * w2 * w, 5.0 * u * w2 * w2, 10.0 * u2 * w2 * w
    b3, b4, b5 = 10.0 * u2 * u * w2, 5.0 * u2 * u2 * w, u2 * u2 * u
    total = 0.0
    for c in range(3):
        value = (b0 * offsets[0, c] + b1 * offsets[1, c] + b2 * offsets[2, c]
                 + b3 * offsets[3, c] + b4 * offsets[4, c] + b5 * offsets[5, c]) - target[c]
        total += value * value
    return -math.sqrt(total)


@compiled
def corner_distances(offsets: NDArray[np.float64], targets: NDArray[np.float64],
                     samples: int, zooms: int) -> NDArray[np.float64]:
    """Per contour, the shortest distance from ``targets[i]`` (relative to its start) to it:
    blend.Contour.distance_to, the sampled peak refined around up to 8 local peaks."""
    n = offsets.shape[0]
    out = np.empty(n)
    y = np.empty(samples)
    order = np.empty(8, dtype=np.int64)
    for i in range(n):
        best = -math.inf
        for k in range(samples):
            y[k] = _negative_distance(offsets[i], targets[i], k / (samples - 1))
            best = max(best, y[k])
        count = 0  # the (up to) 8 highest inner local peaks
        for k in range(1, samples - 1):
            if y[k] >= y[k - 1] and y[k] >= y[k + 1]:
                if count < 8:
                    order[count] = k
                    count += 1
                else:
                    low = 0
                    for m in range(1, 8):
                        if y[order[m]] < y[order[low]]:
                            low = m
                    if y[k] > y[order[low]]:
                        order[low] = k
        width = 1.0 / (samples - 1)
        for m in range(count):
            centre = order[m] / (samples - 1)
            zoom_width = width
            for _ in range(zooms):
                top, pick = -math.inf, centre
                for q in range(33):
                    u = min(max(centre + zoom_width * (-1.0 + q / 16.0), 0.0), 1.0)
                    value = _negative_distance(offsets[i], targets[i], u)
                    if value > top:
                        top, pick = value, u
                best = max(best, top)
                centre = pick
                zoom_width /= 16.0
        out[i] = -best
    return out


@compiled(inline=True)
def _magnitudes(d: NDArray[np.float64], u: float, out: NDArray[np.float64],
                r: NDArray[np.float64]) -> None:
    """|unit tangent|, |curvature vector|, |its rate| per coordinate at u (blend._frame_at);
    ``r`` is scratch space for the three derivatives (9)."""
    u2 = u * u
    p0, p1, p2, p3, p4 = 1.0, u, u2, u2 * u, u2 * u2
    for c in range(9):
        r[c] = p0 * d[0, c] + p1 * d[1, c] + p2 * d[2, c] + p3 * d[3, c] + p4 * d[4, c]
    speed2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    d12 = r[0] * r[3] + r[1] * r[4] + r[2] * r[5]
    d22 = r[3] * r[3] + r[4] * r[4] + r[5] * r[5]
    d13 = r[0] * r[6] + r[1] * r[7] + r[2] * r[8]
    inverse = 1.0 / math.sqrt(speed2)
    inverse2 = inverse * inverse
    inverse4 = inverse2 * inverse2
    for c in range(3):
        n = speed2 * r[3 + c] - d12 * r[c]
        n_rate = d12 * r[3 + c] + speed2 * r[6 + c] - (d22 + d13) * r[c]
        out[c] = abs(r[c]) * inverse
        out[3 + c] = abs(n) * inverse4
        out[6 + c] = abs(n_rate - 4.0 * d12 * n * inverse2) * (inverse4 * inverse)


@compiled(inline=True)
def _bent_peak(values: NDArray[np.float64]) -> tuple[float, float]:
    """The largest sample at a local peak (ends included) plus a quarter of the second
    difference there, and that allowance (blend._bent_peaks, one row)."""
    m = values.size
    best_total, best_bend = -math.inf, 0.0
    for k in range(m):
        left = values[k - 1] if k > 0 else -math.inf
        right = values[k + 1] if k < m - 1 else -math.inf
        if values[k] >= left and values[k] >= right:
            c = min(max(k, 1), m - 2)
            bend = max(2.0 * values[c] - values[c - 1] - values[c + 1], 0.0) / 4.0
            if values[k] + bend > best_total:
                best_total, best_bend = values[k] + bend, bend
    return best_total, best_bend


@compiled
def derivative_peaks(derivatives: NDArray[np.float64], samples: int, candidates: int,
                     max_zooms: int, bend_share: float) -> NDArray[np.float64]:
    """(n, 9): per contour the upper bounds of blend.Contour.derivative_bounds (without its
    margin): each of the nine magnitudes sampled at ``samples`` parameters, plus the
    allowance at its best peak; where an allowance exceeds ``bend_share`` of its peak, the
    ``candidates`` best peaks of every column are zoomed into, 4x finer each time."""
    n = derivatives.shape[0]
    out = np.empty((n, 9))
    y = np.empty((9, samples))
    row = np.empty(9)
    scratch = np.empty(9)
    totals = np.empty(samples)
    zoomed = np.empty((9, 9))
    for i in range(n):
        d = derivatives[i]
        for k in range(samples):
            _magnitudes(d, k / (samples - 1), row, scratch)
            for c in range(9):
                y[c, k] = row[c]
        settled = True
        for c in range(9):
            bound, bend = _bent_peak(y[c])
            out[i, c] = bound
            if bend > bend_share * bound:
                settled = False
        if settled:
            continue
        centres = np.empty((9, candidates))
        for c in range(9):  # the best totals of each column
            values = y[c]
            for k in range(samples):
                left = values[k - 1] if k > 0 else -math.inf
                right = values[k + 1] if k < samples - 1 else -math.inf
                q = min(max(k, 1), samples - 2)
                bend = max(2.0 * values[q] - values[q - 1] - values[q + 1], 0.0) / 4.0
                peak = values[k] >= left and values[k] >= right
                totals[k] = values[k] + bend if peak else -math.inf
            order = np.argsort(totals, kind="mergesort")
            for m in range(candidates):
                centres[c, m] = order[samples - candidates + m] / (samples - 1)
        width = 1.0 / (samples - 1)
        best = np.full(9, -math.inf)
        bends = np.empty((9, candidates))
        for _ in range(max_zooms):
            best[:] = -math.inf
            for m in range(candidates):
                for c in range(9):
                    centre = min(max(centres[c, m], width), 1.0 - width)
                    for q in range(9):
                        _magnitudes(d, centre + width * (-1.0 + q / 4.0), row, scratch)
                        zoomed[c, q] = row[c]
                    total, bends[c, m] = _bent_peak(zoomed[c])
                    best[c] = max(best[c], total)
                    pick = 0
                    for q in range(1, 9):
                        if zoomed[c, q] > zoomed[c, pick]:
                            pick = q
                    centres[c, m] = centre + width * (-1.0 + pick / 4.0)
            width /= 4.0
            settled = True
            for c in range(9):
                for m in range(candidates):
                    if bends[c, m] > bend_share * best[c]:
                        settled = False
            if settled:
                break
        for c in range(9):
            top = -math.inf
            for k in range(samples):
                top = max(top, y[c, k])
            out[i, c] = max(top, best[c])
    return out
