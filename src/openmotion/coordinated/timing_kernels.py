"""Compiled loops of the path time law (numba): zoning, the look-ahead pass and the zone legs.

The time law (timing.py) runs these on events, never per cycle. A dense contour of 10 000
pieces may put a thousand zones into one look-ahead window; as Python loops the pass alone
would cost milliseconds, compiled it costs microseconds (the style of rail/kernels.py).

Symbols follow the jerk-limited speed change from (v1, a = 0) to (v2, a = 0) with peak
acceleration a_max and jerk j (the "ramp"): it lasts
T = |v2 - v1| / a_max + a_max / j when |v2 - v1| >= a_max² / j, else T = 2·sqrt(|v2 - v1| / j),
and covers D = (v1 + v2) / 2 · T, because the velocity curve is point-symmetric about its
middle. D is symmetric in v1 and v2 and grows with the larger of them.
"""

from __future__ import annotations

import math

import numpy as np

from openmotion.coordinated.tolerances import RELATIVE_TOLERANCE
from openmotion.core.compiled import compiled, true_indices

#: a zone's velocity caps lie within this factor of each other; a zone runs at its smallest
#: cap, so a path whose caps change gradually keeps at least this share of them (D-134)
RATIO = 0.95
_BISECTIONS = 200  #: bound on bisection steps; they stop earlier when the interval is one ulp


@compiled
def ramp_time(dv: float, a_max: float, j: float) -> float:
    """Duration of a ramp changing the speed by ``dv`` >= 0."""
    if dv * j >= a_max * a_max:
        return dv / a_max + a_max / j
    return 2.0 * math.sqrt(dv / j)


@compiled
def ramp_distance(v1: float, v2: float, acc: float, dec: float, j: float) -> float:
    """D: the distance of the ramp from v1 to v2 (``acc`` speeding up, ``dec`` slowing)."""
    if v2 >= v1:
        return 0.5 * (v1 + v2) * ramp_time(v2 - v1, acc, j)
    return 0.5 * (v1 + v2) * ramp_time(v1 - v2, dec, j)


@compiled
def other_end(v: float, length: float, a_max: float, j: float) -> float:
    """The speed w >= v with D(v, w) = ``length``: how fast a ramp from ``v`` gets within
    ``length``, or (D being symmetric) how fast one may be and still slow to ``v`` in it.

    Triangular ramp: w - v = y² with y³ + 2v·y = length·sqrt(j), a cubic with one real root
    (the sinh form avoids Cardano's cancellation). Trapezoidal: the quadratic
    w² + (a²/j)·w - v² + (a²/j)·v - 2·a·length = 0.
    """
    if length <= 0.0:
        return v
    q = length * math.sqrt(j)
    p = 2.0 * v
    if p * p * p <= 1e-30 * q * q:
        y = q ** (1.0 / 3.0)
    else:
        r = math.sqrt(p / 3.0)
        y = 2.0 * r * math.sinh(math.asinh(0.5 * q / (r * r * r)) / 3.0)
    for _ in range(2):  # Newton polish of the cubic's root
        y -= (y * (y * y + p) - q) / (3.0 * y * y + p)
    c = a_max * a_max / j
    if y * y <= c:
        return v + y * y
    half = 0.5 * c
    return -half + math.sqrt((v - half) * (v - half) + 2.0 * a_max * length)


@compiled(inline=True)  # called with constants: one copy, not one per constant
def _ramp_phases(v1: float, v2: float, acc: float, dec: float, j: float,
                 jerks: np.ndarray, times: np.ndarray, n: int) -> int:
    """Append the (jerk, duration) phases of the ramp v1 -> v2 at index ``n``; new count."""
    if v2 == v1:
        return n
    up = v2 > v1
    a_max = acc if up else dec
    dv = v2 - v1 if up else v1 - v2
    sign = 1.0 if up else -1.0
    if dv * j >= a_max * a_max:
        t1 = a_max / j
        t2 = dv / a_max - t1
    else:
        t1 = math.sqrt(dv / j)
        t2 = 0.0
    jerks[n], times[n] = sign * j, t1
    jerks[n + 1], times[n + 1] = 0.0, t2
    jerks[n + 2], times[n + 2] = -sign * j, t1
    return n + 3


@compiled
def leg(v0: float, length: float, u: float, v_max: float, acc: float, dec: float,
        j: float) -> tuple[np.ndarray, float, bool]:
    """Time-optimal leg from (0, v0, a = 0) to (``length``, w, a = 0), w <= ``u`` as high as
    reachable, never faster than ``v_max`` (>= v0): ramp to a peak, cruise, ramp to w.

    With zero acceleration at both ends and speeds >= 0 this three-part shape is ruckig's
    time-optimal profile; the peak solves D(v0, peak) + D(peak, w) = length by bisection
    (the sum grows with the peak). Returns the segments as a (5, n) array (t, p, v, a, j; the
    last one open, pinned to the end state), w, and False where w < v0 cannot be reached
    within ``length`` (the caller brakes instead).
    """
    w = u
    if w > v0:
        w = min(w, other_end(v0, length, acc, j))
    elif ramp_distance(v0, w, acc, dec, j) > length * (1.0 + RELATIVE_TOLERANCE):  # round-off
        return np.zeros((5, 1)), w, False
    lo = max(v0, w)
    hi = v_max
    if ramp_distance(v0, hi, acc, dec, j) + ramp_distance(hi, w, acc, dec, j) <= length:
        peak = hi
    else:
        for _ in range(_BISECTIONS):
            mid = 0.5 * (lo + hi)
            if mid <= lo or mid >= hi:
                break
            if ramp_distance(v0, mid, acc, dec, j) + ramp_distance(mid, w, acc, dec, j) <= length:
                lo = mid
            else:
                hi = mid
        peak = lo
    jerks = np.zeros(7)
    times = np.zeros(7)
    n = _ramp_phases(v0, peak, acc, dec, j, jerks, times, 0)
    rest = length - ramp_distance(v0, peak, acc, dec, j) - ramp_distance(peak, w, acc, dec, j)
    if peak > 0.0 and rest > 0.0:
        jerks[n], times[n] = 0.0, rest / peak
        n += 1
    ramp_end = n
    n = _ramp_phases(peak, w, acc, dec, j, jerks, times, n)
    return _integrate(v0, jerks, times, n, 3 if peak != v0 else 0, ramp_end, peak, length, w), \
        w, True


@compiled
def _integrate(v0: float, jerks: np.ndarray, times: np.ndarray, n: int, first_ramp_end: int,
               second_ramp_start: int, peak: float, length: float, w: float) -> np.ndarray:
    """Segments of the phases; where the acceleration is known to be zero (the end of a ramp)
    the state is set exactly, so a cruise runs at the peak to the last bit."""
    data = np.zeros((5, n + 1))
    t = p = a = 0.0
    v = v0
    m = 0
    for k in range(n):
        dt = times[k]
        if dt > 0.0:
            jk = jerks[k]
            data[0, m], data[1, m], data[2, m], data[3, m], data[4, m] = t, p, v, a, jk
            m += 1
            t += dt
            p += dt * (v + dt * (0.5 * a + dt * jk / 6.0))
            v += dt * (a + 0.5 * dt * jk)
            a += dt * jk
        if k + 1 == first_ramp_end or k + 1 == second_ramp_start:
            v, a = peak, 0.0
    data[0, m], data[1, m], data[2, m], data[3, m], data[4, m] = t, length, w, 0.0, 0.0
    return data[:, :m + 1].copy()


@compiled
def zones(vel: np.ndarray, acc: np.ndarray, dec: np.ndarray, jerk: np.ndarray,
          exit_: np.ndarray, space: np.ndarray, lengths: np.ndarray,
          previous: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Zone the new pieces: whether each begins a zone, and the velocity caps zoning used.

    A piece joins the zone before when the junction does not bind: the exit cap is at least
    the smaller velocity cap, the space is the same, and the zone's velocity caps stay within
    ``RATIO`` of each other. Then bumps are flattened until none is left: a zone shorter than
    its own ramp by that ratio, faster than both neighbours, and too short to climb from the
    neighbour's speed by that ratio, takes the velocity cap of its slower neighbour across a
    soft junction (one that binds by the ratio only) and so joins it. It could not use its
    higher cap anyway, and without this a dense contour whose caps alternate (chords and
    blends) would return to a = 0 at every junction and crawl.

    ``previous`` describes the path so far, (has_pieces, zoning velocity, exit, space of its
    last piece, zone v_min, v_max, acc, dec, jerk): the new pieces join its last zone only
    where that leaves the zone's caps unchanged, because the motion may already be planned
    into that zone with them.
    """
    effective = vel.copy()
    while True:
        starts = _ratio_starts(effective, acc, dec, jerk, exit_, space, previous)
        if not _flatten_bumps(effective, starts, acc, dec, jerk, exit_, space, lengths,
                              previous):
            return starts, effective


@compiled
def _ratio_starts(vel: np.ndarray, acc: np.ndarray, dec: np.ndarray, jerk: np.ndarray,
                  exit_: np.ndarray, space: np.ndarray, previous: np.ndarray) -> np.ndarray:
    n = vel.shape[0]
    starts = np.ones(n, dtype=np.bool_)
    v_min = v_max = vel[0]
    if previous[0] != 0.0 and _keeps_caps(vel[0], acc[0], dec[0], jerk[0], previous) \
            and _joins(previous[1], previous[2], previous[3], vel[0], space[0], previous[4],
                       previous[5]):
        starts[0] = False
        v_min, v_max = previous[4], max(previous[5], vel[0])
    joining_old = not starts[0]  # pieces that join the path's last zone must keep its caps
    for k in range(1, n):
        if _joins(vel[k - 1], exit_[k - 1], space[k - 1], vel[k], space[k], v_min, v_max) and (
                not joining_old or _keeps_caps(vel[k], acc[k], dec[k], jerk[k], previous)):
            starts[k] = False
            v_min, v_max = min(v_min, vel[k]), max(v_max, vel[k])
        else:
            v_min = v_max = vel[k]
            joining_old = False
    return starts


@compiled
def _keeps_caps(vel: float, acc: float, dec: float, jerk: float, previous: np.ndarray) -> bool:
    return (vel >= previous[4] and acc >= previous[6] and dec >= previous[7]
            and jerk >= previous[8])


@compiled
def _joins(v_before: float, exit_before: float, space_before: float, v: float, space: float,
           v_min: float, v_max: float) -> bool:
    return (exit_before >= min(v_before, v) and space_before == space
            and min(v_min, v) >= RATIO * max(v_max, v))


@compiled
def _flatten_bumps(vel: np.ndarray, starts: np.ndarray, acc: np.ndarray, dec: np.ndarray,
                   jerk: np.ndarray, exit_: np.ndarray, space: np.ndarray, lengths: np.ndarray,
                   previous: np.ndarray) -> bool:
    """Lower the velocity caps of the bump zones in place; True if any changed."""
    n = vel.shape[0]
    first = true_indices(starts)
    m = first.size
    if m == 0:
        return False
    v_min = np.empty(m)
    length = np.zeros(m)
    for z in range(m):
        lo, hi = first[z], first[z + 1] if z + 1 < m else n
        v_min[z] = _lowest(vel, lo, hi)
        total = 0.0  # lengths[lo:hi].sum(), in its order
        for k in range(lo, hi):
            total += lengths[k]
        length[z] = total
    changed = False
    for z in range(m):
        lo, hi = first[z], first[z + 1] if z + 1 < m else n
        a_z, d_z, j_z = _lowest(acc, lo, hi), _lowest(dec, lo, hi), _lowest(jerk, lo, hi)
        if length[z] >= ramp_distance(RATIO * v_min[z], v_min[z], a_z, d_z, j_z):
            continue
        # the neighbours' speeds (a binding junction caps them; rest beyond the path)
        left, left_soft = 0.0, False
        if z > 0 or previous[0] != 0.0:
            if lo > 0:
                v_left, ex, same = vel[lo - 1], exit_[lo - 1], space[lo - 1] == space[lo]
            else:
                v_left, ex, same = previous[1], previous[2], previous[3] == space[lo]
            left = v_min[z - 1] if z > 0 else previous[4]
            soft = ex >= min(v_left, vel[lo]) and same
            left_soft = soft and (z > 0 or _keeps_caps(left, a_z, d_z, j_z, previous))
            if not soft:
                left = min(left, ex) if same else 0.0
        right, right_soft = 0.0, False
        if z + 1 < m:
            right = v_min[z + 1]
            same = space[hi - 1] == space[hi]
            right_soft = exit_[hi - 1] >= min(vel[hi - 1], vel[hi]) and same
            if not right_soft:
                right = min(right, exit_[hi - 1]) if same else 0.0
        if left >= v_min[z] or right >= v_min[z]:
            continue
        target = -1.0
        if left_soft:
            target = left
        if right_soft:
            target = max(target, right)
        if target < 0.0:
            continue
        # only where the zone is too short to climb from the target by the ratio (or to its
        # caps): else the target may be far below what it reaches, and a contour crawling at
        # 0.02 mm/s would drag a 20 mm line after it down to that speed
        if length[z] >= ramp_distance(target, min(v_min[z], target / RATIO), a_z, d_z, j_z):
            continue
        for k in range(lo, hi):
            vel[k] = min(vel[k], target)
        changed = True
    return changed


@compiled
def _lowest(x: np.ndarray, lo: int, hi: int) -> float:
    """``x[lo:hi].min()`` (lo < hi) as numba computes it: the first NaN, else the first of
    the smallest values."""
    low = x[lo]
    for k in range(lo, hi):
        if math.isnan(x[k]):
            return x[k]
        if x[k] < low:
            low = x[k]
    return low


@compiled
def _need(v: float, acc: float, dec: float, j: float) -> float:
    """Look-ahead one zone asks for: speed up from rest, then twice its stopping distance."""
    return ramp_distance(0.0, v, acc, dec, j) + 2.0 * ramp_distance(v, 0.0, acc, dec, j)


@compiled
def look_ahead(start: np.ndarray, end: np.ndarray, vel: np.ndarray, acc: np.ndarray,
               dec: np.ndarray, jerk: np.ndarray, exit_: np.ndarray, z0: int, s0: float,
               fv: float, fa: float, fj: float,
               span: float) -> tuple[np.ndarray, int, int, float, int]:
    """The backward pass over a window of zones from zone ``z0`` (position ``s0``).

    ``B[k]`` is the highest speed (with a = 0) at the end of zone z0 + k from which every
    later zone can still keep its caps, assuming rest at the end of the window. The window
    takes whole zones: a horizon inside a zone would save no work, since a zone is one entry
    here. B[k] is exact (the same as over the whole path) from the last junction where the
    caps, not the assumed rest, set it (``k_exact``) backwards; the window grows (doubling)
    until that exact part covers half of it or the window reaches the path's end, and covers
    at least what each zone needs to speed up from rest and twice to stop.
    Returns (B, n, k_exact, span, zones scanned).
    """
    nz = start.shape[0]
    reach = s0 + max(span, _need(vel[z0] * fv, acc[z0] * fa, dec[z0] * fa, jerk[z0] * fj))
    scanned = 0
    while True:
        i, h = z0, reach
        while i < nz and start[i] < h:
            h = max(h, start[i] + _need(vel[i] * fv, acc[i] * fa, dec[i] * fa, jerk[i] * fj))
            i += 1
        n = i - z0
        h_end = end[i - 1]
        exact_end = i == nz
        values = np.empty(n)
        values[n - 1] = 0.0
        k_exact = n - 1 if exact_end else -1
        for k in range(n - 2, -1, -1):
            z = z0 + k
            cap = min(exit_[z], vel[z], vel[z + 1]) * fv
            back = other_end(values[k + 1], end[z + 1] - start[z + 1], dec[z + 1] * fa,
                             jerk[z + 1] * fj)
            if cap <= back:
                values[k] = cap
                if k_exact < 0:
                    k_exact = k
            else:
                values[k] = back
        scanned += n
        covered = end[z0 + k_exact] - s0 if k_exact >= 0 else 0.0
        if exact_end or covered >= 0.5 * (h_end - s0):
            break
        reach = s0 + 2.0 * (h_end - s0)
    return values, n, k_exact, h_end - s0, scanned
