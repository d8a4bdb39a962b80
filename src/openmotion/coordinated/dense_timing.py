"""The time law of a dense path in one pass: the acceleration changes on the lines (D-335).

A dense path (coordinated/dense.py: many short lines, each corner rounded by a blend contour
of a tenth of a millimetre) is a string of tiny pieces whose velocity caps (limits.py) come
from the contours' curvature rate and change gradually along the path. Zones (timing.py)
run each stretch at its smallest cap and return to a = 0 between stretches; on such a path
that leaves about a tenth of what the axes allow (`bench path`). The axes need jerk only to
change the acceleration, and a line has the axes' whole jerk for it, while a contour at its
steady speed has almost none to spare. So the profile here holds the path acceleration
constant on each piece after a ramp of the acceleration at its start (with the piece's own
jerk cap, so a contour, with its small jerk cap, keeps nearly the acceleration it enters
with and the line before it sets it): on piece k, from (w, a) at its start,

    ramp:  jerk ±J_k for tau = |a1 - a| / J_k      then  hold:  a1 to the piece's end.

a1 is the highest acceleration whose end speed stays within the junction speeds W of a
backward and a forward pass (constant acceleration per piece, ``SHARE`` of each piece's
deceleration and acceleration caps and the next piece's, so the acceleration has room to
follow), looking one piece ahead (a1 is held over the next piece too, which the next
piece's jerk cap may not change), and from whose end state the hardest brake the pieces'
caps allow keeps W up to rest (``_safe``): the ramps that lag behind a falling W are
started early enough. Every segment is then checked against its piece's caps, the same
checks the zone legs keep (``check``); a profile that fails them is not used, and the zone
law runs instead. The last pieces before the end are a ruckig brake (timing.py) from the state the
profile has at a junction.
"""

from __future__ import annotations

import math

import numpy as np

from openmotion.coordinated.tolerances import ABSOLUTE_SLACK, RELATIVE_TOLERANCE
from openmotion.core.compiled import compiled

SHARE = 0.5  #: of each piece's acceleration and deceleration caps, what the passes plan with
_BISECTIONS = 30  #: steps of the searches on the held acceleration
_HORIZON = 400  #: pieces a brake that proves a state safe may look ahead
_CONTINUITY = 1e-9  #: relative: one segment's end meets the next one's start this well
_TIME_ROUNDING = 8.0 * np.finfo(np.float64).eps  #: relative round-off of a segment's time


@compiled
def _run(w: float, a: float, a1: float, length: float, jerk: float
         ) -> tuple[bool, float, float, float, float, float]:
    """Piece of ``length`` from speed ``w``, acceleration ``a``: ramp to ``a1`` with ``jerk``,
    hold it to the end. (ok, ramp time, ramp distance, speed after the ramp, end speed, hold
    time); ok is False where the ramp does not fit or the speed would reach zero. The peak
    speed inside is max(w, end speeds, the speed where the ramp crosses a = 0): ``_peak``."""
    tau = abs(a1 - a) / jerk
    js = jerk if a1 > a else -jerk
    d1 = tau * (w + tau * (0.5 * a + tau * js / 6.0))
    v1 = w + tau * (a + 0.5 * tau * js)
    if d1 > length or v1 < 0.0:
        return False, tau, d1, v1, 0.0, 0.0
    if tau > 0.0:
        t_star = -a / js
        if 0.0 < t_star < tau and w + t_star * (a + 0.5 * t_star * js) < 0.0:
            return False, tau, d1, v1, 0.0, 0.0
    d2 = length - d1
    square = v1 * v1 + 2.0 * a1 * d2
    if square < 0.0:
        return False, tau, d1, v1, 0.0, 0.0
    w_end = math.sqrt(square)
    if d2 > 0.0 and v1 + w_end <= 0.0:
        return False, tau, d1, v1, 0.0, 0.0
    t2 = 2.0 * d2 / (v1 + w_end) if d2 > 0.0 else 0.0
    return True, tau, d1, v1, w_end, t2


@compiled
def _peak(w: float, a: float, a1: float, jerk: float, tau: float, v1: float,
          w_end: float) -> float:
    """The highest speed of ``_run``'s piece."""
    peak = max(w, v1, w_end)
    if tau > 0.0:
        js = jerk if a1 > a else -jerk
        t_star = -a / js
        if 0.0 < t_star < tau:
            peak = max(peak, w + t_star * (a + 0.5 * t_star * js))
    return peak


@compiled
def _excess(k: int, w: float, a: float, a1: float, lengths: np.ndarray, vel: np.ndarray,
            jerk: np.ndarray, targets: np.ndarray) -> tuple[bool, float]:
    """(ok, how far piece k run with ``a1`` overshoots): its end speed over W[k + 1], its
    peak over its cap, and, holding ``a1`` over piece k + 1, that end speed over W[k + 2]
    (largest of the three, relative to the junction speed; <= 0: nothing overshoots)."""
    ok, tau, _, v1, w_end, _ = _run(w, a, a1, lengths[k], jerk[k])
    if not ok:
        return False, 0.0
    peak = _peak(w, a, a1, jerk[k], tau, v1, w_end)
    excess = max(w_end - targets[k + 1], peak - vel[k])
    n = lengths.shape[0]
    if k + 1 < n:
        square = w_end * w_end + 2.0 * a1 * lengths[k + 1]
        ahead = math.sqrt(square) if square > 0.0 else 0.0
        excess = max(excess, ahead - targets[k + 2], ahead - vel[k + 1])
    return True, excess


@compiled
def _safe(j: int, w: float, a: float, lengths: np.ndarray, vel: np.ndarray, dec: np.ndarray,
          jerk: np.ndarray, targets: np.ndarray) -> bool:
    """Whether the motion at junction ``j`` with speed ``w`` and acceleration ``a`` can still
    keep the junction speeds ahead: braking as hard as the pieces' jerk and deceleration
    caps let it (the acceleration ramped down on each piece as far as the piece allows,
    then held), it never passes a junction above W or a piece above its cap, up to rest or
    ``_HORIZON`` pieces."""
    n = lengths.shape[0]
    for k in range(j, min(n, j + _HORIZON)):
        if w > targets[k] * (1.0 + RELATIVE_TOLERANCE) + ABSOLUTE_SLACK:
            return False
        lo = -dec[k] if k + 1 == n else -min(dec[k], dec[k + 1])
        tau = lengths[k] / w if w > 0.0 else 0.0
        a1 = max(lo, a - jerk[k] * tau)
        for _ in range(12):
            ok, tau, _, v1, w_end, _ = _run(w, a, a1, lengths[k], jerk[k])
            if ok:
                break
            if v1 < 0.0 or (tau > 0.0 and a1 >= a):  # it comes to rest here: safe
                return True
            a1 = a + 0.7 * (a1 - a)
        else:
            return True  # no ramp that fits keeps moving: it comes to rest within the piece
        if _peak(w, a, a1, jerk[k], tau, v1, w_end) > vel[k] * (1.0 + RELATIVE_TOLERANCE):
            return False
        w, a = w_end, a1
    return j + _HORIZON < n or w <= targets[n] + ABSOLUTE_SLACK


@compiled
def _choose(k: int, w: float, a: float, lengths: np.ndarray, vel: np.ndarray,
            acc: np.ndarray, dec: np.ndarray, jerk: np.ndarray, targets: np.ndarray
            ) -> tuple[bool, float]:
    """The acceleration to hold on piece k: the highest that fits and overshoots nothing,
    else the lowest that fits (the check decides)."""
    n = lengths.shape[0]
    lo, hi = -dec[k], acc[k]
    if k + 1 < n:
        lo, hi = max(lo, -dec[k + 1]), min(hi, acc[k + 1])
    a0 = min(max(a, lo), hi)
    ok0, _ = _excess(k, w, a, a0, lengths, vel, jerk, targets)
    if not ok0:  # holding on would stop the motion: find a higher acceleration that fits
        found = False
        for m in range(40, -1, -1):
            trial = a0 + (hi - a0) * 0.5**m
            if _excess(k, w, a, trial, lengths, vel, jerk, targets)[0]:
                a0, found = trial, True
                break
        if not found:
            return False, a0
    # the accelerations that fit: [down, up] around a0 (a longer ramp fits less)
    up = a0 + _ramp_reach(w, a0, lengths[k], jerk[k], 1.0, hi - a0)
    down = a0 - _ramp_reach(w, a0, lengths[k], jerk[k], -1.0, a0 - lo)
    if a0 != a:  # the ramp starts at a, not a0: make sure the ends fit
        while up > a0 and not _excess(k, w, a, up, lengths, vel, jerk, targets)[0]:
            up = a0 + 0.5 * (up - a0)
    if not _excess(k, w, a, down, lengths, vel, jerk, targets)[0]:
        good, bad = a0, down  # the hold would bring the motion to rest
        for _ in range(_BISECTIONS):
            middle = 0.5 * (good + bad)
            if middle >= good or middle <= bad:
                break
            if _excess(k, w, a, middle, lengths, vel, jerk, targets)[0]:
                good = middle
            else:
                bad = middle
        down = good
    high = _excess(k, w, a, up, lengths, vel, jerk, targets)[1]
    if high <= 0.0:
        best = up
    else:
        low = _excess(k, w, a, down, lengths, vel, jerk, targets)[1]
        if low > 0.0:
            return True, down
        best = _root(k, w, a, down, low, up, high, lengths, vel, jerk, targets)
    if _safe_after(k, w, a, best, lengths, vel, dec, jerk, targets) \
            or not _safe_after(k, w, a, down, lengths, vel, dec, jerk, targets):
        return True, best
    good, bad = down, best
    for _ in range(_BISECTIONS):
        middle = 0.5 * (good + bad)
        if middle <= good or middle >= bad:
            break
        if _safe_after(k, w, a, middle, lengths, vel, dec, jerk, targets):
            good = middle
        else:
            bad = middle
    return True, good


@compiled
def _ramp_reach(w: float, a: float, length: float, jerk: float, sign: float,
                limit: float) -> float:
    """The largest change (<= ``limit``) of the acceleration, up (``sign`` 1) or down (-1),
    whose ramp from speed ``w`` and acceleration ``a`` fits in ``length`` with the speed
    staying >= 0: bisection on the ramp time."""
    js = sign * jerk

    def fits(tau: float) -> bool:
        d = tau * (w + tau * (0.5 * a + tau * js / 6.0))
        v = w + tau * (a + 0.5 * tau * js)
        t_star = -a / js
        if 0.0 < t_star < tau and w + t_star * (a + 0.5 * t_star * js) < 0.0:
            return False
        return d <= length and v >= 0.0

    if limit <= 0.0:
        return 0.0
    top = limit / jerk
    if fits(top):
        return limit
    good, bad = 0.0, top
    for _ in range(_BISECTIONS):
        middle = 0.5 * (good + bad)
        if middle <= good or middle >= bad:
            break
        if fits(middle):
            good = middle
        else:
            bad = middle
    return good * jerk


@compiled
def _root(k: int, w: float, a: float, lo: float, f_lo: float, hi: float, f_hi: float,
          lengths: np.ndarray, vel: np.ndarray, jerk: np.ndarray, targets: np.ndarray) -> float:
    """The highest acceleration in [lo, hi] whose ``_excess`` is <= 0 (f_lo <= 0 < f_hi):
    false position with the Illinois step, ending on the side that overshoots nothing."""
    side = 0
    for _ in range(2 * _BISECTIONS):
        if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1.0):
            break
        middle = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        if not lo < middle < hi:
            middle = 0.5 * (lo + hi)
        f = _excess(k, w, a, middle, lengths, vel, jerk, targets)[1]
        if f <= 0.0:
            lo, f_lo = middle, f
            if side == -1:
                f_hi *= 0.5
            side = -1
        else:
            hi, f_hi = middle, f
            if side == 1:
                f_lo *= 0.5
            side = 1
        if f_lo == 0.0:
            break
    return lo


@compiled
def _safe_after(k: int, w: float, a: float, a1: float, lengths: np.ndarray, vel: np.ndarray,
                dec: np.ndarray, jerk: np.ndarray, targets: np.ndarray) -> bool:
    """``_safe`` at the end of piece k run with ``a1``."""
    ok, _, _, _, w_end, _ = _run(w, a, a1, lengths[k], jerk[k])
    return ok and _safe(k + 1, w_end, a1, lengths, vel, dec, jerk, targets)


@compiled
def junction_speeds(lengths: np.ndarray, vel: np.ndarray, acc: np.ndarray, dec: np.ndarray,
                    exit_: np.ndarray, space: np.ndarray) -> np.ndarray:
    """W: the speeds at the n + 1 junctions (rest at both ends) of the fastest motion with a
    constant acceleration on each piece, within ``SHARE`` of its caps and the next piece's
    (the acceleration held on a piece carries into the next); all zero where a junction
    inside binds to rest (a stop the profile does not make)."""
    n = lengths.shape[0]
    w = np.zeros(n + 1)
    for k in range(1, n):
        w[k] = min(vel[k - 1], vel[k], exit_[k - 1])
        if space[k - 1] != space[k] or not w[k] > 0.0:
            return np.zeros(n + 1)
    for k in range(n - 1, -1, -1):
        d = dec[k] if k + 1 == n else min(dec[k], dec[k + 1])
        w[k] = min(w[k], math.sqrt(w[k + 1] * w[k + 1] + 2.0 * SHARE * d * lengths[k]))
    for k in range(1, n + 1):
        u = acc[k - 1] if k == n else min(acc[k - 1], acc[k])
        w[k] = min(w[k], math.sqrt(w[k - 1] * w[k - 1] + 2.0 * SHARE * u * lengths[k - 1]))
    return w


@compiled
def planned_time(lengths: np.ndarray, vel: np.ndarray, acc: np.ndarray,
                 dec: np.ndarray) -> float:
    """Duration [s] of the motion through the junction speeds (``junction_speeds``, no exit
    caps) with a constant acceleration on each piece: what the profile plans to, and how
    the shares of a dense path's caps are chosen (limits_bridge.py)."""
    n = lengths.shape[0]
    w = junction_speeds(lengths, vel, acc, dec, np.full(n, np.inf), np.zeros(n))
    total = 0.0
    for k in range(n):
        total += 2.0 * lengths[k] / (w[k] + w[k + 1])
    return total


@compiled
def profile(lengths: np.ndarray, vel: np.ndarray, acc: np.ndarray, dec: np.ndarray,
            jerk: np.ndarray, targets: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """Run the pieces from rest: per piece, the acceleration ramp and hold of the module text.

    Returns the segments (5, m): t, p, v, a, j from the path's start, the state at each
    junction reached (3, n + 1): time, speed, acceleration, and the last junction reached
    (the motion stops being plannable this way near the end, where the speeds fall to rest).
    """
    n = lengths.shape[0]
    data = np.zeros((5, 2 * n + 1))
    states = np.zeros((3, n + 1))
    t = s = w = a = 0.0
    m = 0
    for k in range(n):
        if k + 1 == n or targets[k + 1] <= 0.0:
            return data[:, :m].copy(), states, k
        ok, a1 = _choose(k, w, a, lengths, vel, acc, dec, jerk, targets)
        if not ok:
            return data[:, :m].copy(), states, k
        ok, tau, d1, v1, w_end, t2 = _run(w, a, a1, lengths[k], jerk[k])
        if not ok:
            return data[:, :m].copy(), states, k
        if tau > 0.0:
            data[0, m], data[1, m], data[2, m], data[3, m] = t, s, w, a
            data[4, m] = jerk[k] if a1 > a else -jerk[k]
            m += 1
        if t2 > 0.0:
            data[0, m], data[1, m], data[2, m], data[3, m], data[4, m] = t + tau, s + d1, v1, \
                a1, 0.0
            m += 1
        t += tau + t2
        s += lengths[k]
        w, a = w_end, a1
        states[0, k + 1], states[1, k + 1], states[2, k + 1] = t, w, a
    return data[:, :m].copy(), states, n


@compiled
def _cubic(p: float, v: float, a: float, j: float, d: float) -> tuple[float, float, float]:
    """(s, v, a) after ``d`` [s] of a constant-jerk segment."""
    return p + d * (v + d * (0.5 * a + d * j / 6.0)), v + d * (a + 0.5 * d * j), a + d * j


@compiled
def _landing_gap(v: float, a: float, deceleration: float, land_jerk: float) -> float:
    """a minus the acceleration from which a ramp to a = 0 with ``land_jerk`` ends at rest
    (not below -``deceleration``): > 0 brakes too softly to land yet, < 0 too hard."""
    return a + min(deceleration, math.sqrt(2.0 * land_jerk * max(v, 0.0)))


@compiled
def release(s: float, v: float, a: float, ends: np.ndarray, jerk: np.ndarray,
            deceleration: float, land_jerk: float) -> tuple[np.ndarray, bool]:
    """The start of a stop's brake on a dense path (D-362): from (s, v, a) the acceleration
    moves at once, with each piece's own jerk cap (``jerk``, already within the request),
    piece after piece, to the brake that ruckig's stop with ``deceleration`` and
    ``land_jerk`` continues to rest: down to -``deceleration``, or to where a ramp back to
    a = 0 with ``land_jerk`` ends at rest (v = a² / (2 land_jerk)); up to that brake where
    the motion brakes harder than it can land (the profile held a on the contours while it
    slowed for a slower stretch). Returns the segments (5, m) from t = 0, the last one the
    state reached (jerk 0), and False where the path ends or the motion rests first."""
    n = ends.shape[0]
    data = np.zeros((5, n + 4))
    m = 0
    t = 0.0
    k = int(np.searchsorted(ends, s, side="right"))
    tiny = 1e-12 * max(deceleration, abs(a), 1.0)
    for _ in range(n + 4):
        gap = _landing_gap(v, a, deceleration, land_jerk)
        if abs(gap) <= tiny or v <= 0.0:
            break
        if k >= n:
            return data[:, :0].copy(), False
        j = -jerk[k] if gap > 0.0 else jerk[k]
        if j < 0.0:  # down: a(t) - target(v(t)) falls once a <= 0 and crosses by a = -dec
            lo, hi = max(0.0, a / -j), (a + deceleration) / -j
        else:  # up: by a = 0 at the latest, if the motion is still moving then
            lo, hi = 0.0, -a / j
            if _cubic(s, v, a, j, hi)[1] <= 0.0:
                return data[:, :0].copy(), False
        for _ in range(60):
            middle = 0.5 * (lo + hi)
            _, vm, am = _cubic(s, v, a, j, middle)
            if (_landing_gap(vm, am, deceleration, land_jerk) > 0.0) == (j < 0.0):
                lo = middle
            else:
                hi = middle
        horizon = lo if j < 0.0 else hi  # the side from which ruckig's stop lands exactly
        crossed = _cubic(s, v, a, j, horizon)[0] > ends[k]
        if crossed:  # the piece ends first: its end, by bisection (s rises while v > 0)
            lo, hi = 0.0, horizon
            for _ in range(80):
                middle = 0.5 * (lo + hi)
                if _cubic(s, v, a, j, middle)[0] > ends[k]:
                    hi = middle
                else:
                    lo = middle
            horizon = lo
        if horizon > 0.0:
            data[0, m], data[1, m], data[2, m], data[3, m], data[4, m] = t, s, v, a, j
            m += 1
            s, v, a = _cubic(s, v, a, j, horizon)
            t += horizon
        if crossed:
            s = max(s, ends[k])
            k += 1
        elif horizon <= 0.0 or not crossed:
            break
    data[0, m], data[1, m], data[2, m], data[3, m], data[4, m] = t, s, max(v, 0.0), a, 0.0
    return data[:, :m + 1].copy(), v > 0.0


@compiled
def split(data: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """``data`` (its last segment open) with each segment cut where it passes a piece's end,
    so that ``check`` sees every stretch against the caps of its own piece."""
    m = data.shape[1]
    first = int(np.searchsorted(ends, data[1, 0], side="right"))
    last = int(np.searchsorted(ends, data[1, m - 1], side="left"))
    out = np.zeros((5, m + max(last - first, 0) + 2))
    q = 0
    k = first
    for i in range(m):
        t0, p0, v0, a0, j = data[0, i], data[1, i], data[2, i], data[3, i], data[4, i]
        out[0, q], out[1, q], out[2, q], out[3, q], out[4, q] = t0, p0, v0, a0, j
        q += 1
        if i + 1 == m:
            break
        dt = data[0, i + 1] - t0
        p1 = data[1, i + 1]
        while k < ends.shape[0] and ends[k] <= p0:
            k += 1
        while k < ends.shape[0] and ends[k] < p1 and q < out.shape[1] - 1:
            lo, hi = 0.0, dt
            for _ in range(80):
                middle = 0.5 * (lo + hi)
                if _cubic(p0, v0, a0, j, middle)[0] >= ends[k]:
                    hi = middle
                else:
                    lo = middle
            if 0.0 < hi < dt:
                ps, vs, as_ = _cubic(p0, v0, a0, j, hi)
                out[0, q], out[1, q], out[2, q], out[3, q], out[4, q] = t0 + hi, ps, vs, as_, j
                q += 1
            k += 1
    return out[:, :q].copy()


@compiled
def check(data: np.ndarray, ends: np.ndarray, vel: np.ndarray, acc: np.ndarray,
          dec: np.ndarray, jerk: np.ndarray) -> int:
    """-1 if every segment of ``data`` (its last one open) keeps the caps of the piece it
    runs on, never moves backwards and meets the next segment's state; else the first
    segment that does not."""
    m = data.shape[1]
    k = 0
    for i in range(m - 1):
        t0, p0, v0, a0, j = data[0, i], data[1, i], data[2, i], data[3, i], data[4, i]
        dt = data[0, i + 1] - t0
        p1 = p0 + dt * (v0 + dt * (0.5 * a0 + dt * j / 6.0))
        v1 = v0 + dt * (a0 + 0.5 * dt * j)
        a1 = a0 + dt * j
        # the times are absolute: a segment of a microsecond carries their round-off
        late = _TIME_ROUNDING * max(abs(data[0, i + 1]), 1.0)
        if abs(p1 - data[1, i + 1]) > _CONTINUITY * max(abs(p1), 1.0) + late * abs(v1) \
                or abs(v1 - data[2, i + 1]) > _CONTINUITY * max(abs(v0), abs(v1), 1.0) \
                + late * (abs(a0) + abs(j) * dt) \
                or abs(a1 - data[3, i + 1]) > _CONTINUITY * max(abs(a0), abs(a1), 1.0) \
                + late * abs(j):
            return i
        middle = 0.5 * (p0 + p1)  # the piece this segment runs on
        while k + 1 < ends.shape[0] and ends[k] <= middle:
            k += 1
        peak, low = max(v0, v1), min(v0, v1)
        if j != 0.0:
            t_star = -a0 / j
            if 0.0 < t_star < dt:
                v_star = v0 + t_star * (a0 + 0.5 * t_star * j)
                peak, low = max(peak, v_star), min(low, v_star)
        slack = 1.0 + RELATIVE_TOLERANCE
        if peak > vel[k] * slack + ABSOLUTE_SLACK or low < -ABSOLUTE_SLACK \
                or max(a0, a1) > acc[k] * slack or min(a0, a1) < -dec[k] * slack \
                or abs(j) > jerk[k] * slack:
            return i
    return -1


__all__ = ["SHARE", "check", "junction_speeds", "planned_time", "profile", "release",
           "split"]
