"""Compiled loops of gap control (numba): the brake envelope, the held movers' steps, and
the gap filter's pair checks and rounds.

Gap control asks the same few dozen arithmetic questions of every mover in every cycle.
As numpy passes each question is an array operation with its own overhead; at 1000 movers
that overhead, not the arithmetic, set the cycle time (docs/collision-avoidance.md,
Performance). These loops do the same arithmetic per mover in one compiled pass. Every
expression keeps the operation order of the numpy formulation they replaced, so the results
were the same bit for bit (D-105, D-186); tests/transport/test_braking.py checks the brake
against the planner's own stop (trajectory.plan.plan_stop), tests/transport/test_gap_control.py
the Fast pair check against its numpy formulation.
"""

from __future__ import annotations

import math

import numpy as np

from openmotion.core.compiled import compiled, sort_in_place, true_indices
from openmotion.rail.tolerances import (
    BOUND_MARGIN,
    LIMIT_SLACK,
    PHASE_END_TOLERANCE,
    TOLERANCE,
)


@compiled
def _sign(x: float) -> float:
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return x  # 0.0, -0.0 or nan, as numpy.sign


@compiled
def _phases(v: float, a: float, dec: float, jerk: float) -> tuple[float, ...]:
    """The brake from (v, a) for one mover: durations t1, t2, t3, jerks j1, j3 (j2 = 0) and the
    velocity once the acceleration is taken away at once (its sign decides the brake)."""
    inv = 0.5 / jerk
    release = v + a * abs(a) * inv
    d = -_sign(release)
    peak_sq = 0.5 * a * a - jerk * d * v
    triangular = (peak_sq <= dec * dec) or (d == 0.0)
    peak = d * math.sqrt(max(peak_sq, 0.0)) if triangular else d * dec
    first = _sign(peak - a)
    gained = (peak * peak - a * a) * inv * first
    hold = 0.0 if triangular else (-v - gained - peak * abs(peak) * inv) / peak
    return (abs(peak - a) / jerk, max(hold, 0.0), abs(peak) / jerk, first * jerk, -d * jerk,
            release)


@compiled
def envelope(p: float, v: float, a: float, dec: float, jerk: float) -> tuple[float, float]:
    """braking.brake_envelope for one mover: the lowest and highest position of its brake."""
    t1, t2, t3, j1, j3, release = _phases(v, a, dec, jerk)
    p1 = p + t1 * (v + t1 * (0.5 * a + t1 * j1 / 6.0))
    v1 = v + t1 * (a + 0.5 * t1 * j1)
    a1 = a + t1 * j1
    p2 = p1 + t2 * (v1 + 0.5 * t2 * a1)
    v2 = v1 + t2 * a1
    p3 = p2 + t3 * (v2 + t3 * (0.5 * a1 + t3 * j3 / 6.0))
    lo, hi = min(p, p3), max(p, p3)
    if v * release < 0.0:  # it turns: add the phase boundaries and the turning points
        durations = (t1, t2, t3)
        jerks = (j1, 0.0, j3)
        pk, vk, ak = p, v, a
        for k in range(3):
            t, j = durations[k], jerks[k]
            for root in _roots(vk, ak, j, t):
                position = pk
                if not math.isnan(root):
                    position = pk + root * (vk + root * (0.5 * ak + root * j / 6.0))
                lo, hi = min(lo, position), max(hi, position)
            pk, vk, ak = (pk + t * (vk + t * (0.5 * ak + t * j / 6.0)),
                          vk + t * (ak + 0.5 * t * j), ak + t * j)
    return lo, hi


@compiled
def _roots(v0: float, a0: float, j: float, duration: float) -> tuple[float, float]:
    """Times in [0, duration] where v0 + a0 t + j t²/2 = 0 (nan: none)."""
    disc = math.sqrt(max(a0 * a0 - 2.0 * j * v0, 0.0))
    if j != 0.0:
        r1, r2 = (-a0 - disc) / j, (-a0 + disc) / j
    else:
        r1 = -v0 / a0 if a0 != 0.0 else (math.nan if v0 == 0.0 else math.inf)
        r2 = math.nan
    out1 = r1 if math.isfinite(r1) and 0.0 <= r1 <= duration else math.nan
    out2 = r2 if math.isfinite(r2) and 0.0 <= r2 <= duration else math.nan
    return out1, out2


@compiled
def envelopes(p: np.ndarray, v: np.ndarray, a: np.ndarray, dec: np.ndarray,
              jerk: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``envelope`` for every mover."""
    n = p.shape[0]
    lo, hi = np.empty(n), np.empty(n)
    for i in range(n):
        lo[i], hi[i] = envelope(p[i], v[i], a[i], dec[i], jerk[i])
    return lo, hi


@compiled
def _first_step(k: int, dt: float, p: np.ndarray, v: np.ndarray, a: np.ndarray, s: float,
                target: float, vmax: float, acc: float, dk: float, jk: float, bdk: float,
                bjk: float, room_lo: float, room_hi: float, ahead: np.ndarray,
                times: np.ndarray, out: np.ndarray, env: np.ndarray) -> bool:
    """The first of the steps +J, 0, -J (jerk ``jk``) of mover ``k`` that keeps the limits
    (acc, dk, vmax), does not pass the target and whose brake with the hardest dynamics
    (bdk, bjk) stays in its room; written into ``out`` and ``env``. False: none fits.

    ``ahead`` = (p, v, a, dec, jerk, gap) of the predecessor's brake a cycle on, for a mover
    in a FAST pair moving forwards (gap nan: none): a step past the room is still taken when
    both brakes together keep that gap, the FAST pair check (D-211)."""
    for step in (1.0, 0.0, -1.0):
        j = step * s * jk
        p1 = p[k] + dt * (v[k] + dt * (0.5 * a[k] + dt * j / 6.0))
        v1 = v[k] + dt * (a[k] + 0.5 * dt * j)
        a1 = a[k] + dt * j
        u, b = s * v1, s * a1
        release = u + b * abs(b) / (2.0 * jk)
        if not (b <= acc * LIMIT_SLACK and b >= -dk * LIMIT_SLACK
                and release <= vmax * LIMIT_SLACK and u >= 0.0 and release >= 0.0):
            continue
        top = max(u, release)
        t_stop = (max(b, 0.0) + 2.0 * dk) / jk + top / dk
        if top * t_stop >= s * (target - p1):  # near the target: stop before it
            c_lo, c_hi = envelope(p1, v1, a1, dk, jk)
            if not (c_hi <= target + TOLERANCE if s > 0.0 else c_lo >= target - TOLERANCE):
                continue
        b_lo, b_hi = envelope(p1, v1, a1, bdk, bjk)
        fits = b_hi <= room_hi and b_lo >= room_lo
        if not fits and b_lo >= room_lo and not math.isnan(ahead[5]):
            fits = brake_gap_holds(ahead[0], ahead[1], ahead[2], ahead[3], ahead[4], p1, v1,
                                   a1, bdk, bjk, ahead[5] - TOLERANCE, times)
        if fits:
            out[0, k], out[1, k], out[2, k], out[3, k] = p1, v1, a1, j
            env[0, k], env[1, k] = b_lo, b_hi
            return True
    return False


@compiled
def candidates(rows: np.ndarray, dt: float, p: np.ndarray, v: np.ndarray, a: np.ndarray,
               sign: np.ndarray, target: np.ndarray, vmax: np.ndarray, acc: np.ndarray,
               dec: np.ndarray, jm: np.ndarray, bdec: np.ndarray, bjerk: np.ndarray,
               room_lo: np.ndarray, room_hi: np.ndarray, out: np.ndarray,
               env: np.ndarray) -> np.ndarray:
    """``fast_candidates`` with no FAST pairs (planar traffic: STANDARD only)."""
    ahead = np.full((rows.shape[0], 6), np.nan)
    return fast_candidates(rows, dt, p, v, a, sign, target, vmax, acc, dec, jm, bdec, bjerk,
                           room_lo, room_hi, ahead, out, env)


@compiled
def fast_candidates(rows: np.ndarray, dt: float, p: np.ndarray, v: np.ndarray, a: np.ndarray,
                    sign: np.ndarray, target: np.ndarray, vmax: np.ndarray, acc: np.ndarray,
                    dec: np.ndarray, jm: np.ndarray, bdec: np.ndarray, bjerk: np.ndarray,
                    room_lo: np.ndarray, room_hi: np.ndarray, ahead: np.ndarray,
                    out: np.ndarray, env: np.ndarray) -> np.ndarray:
    """GroupCycle._candidates for the held movers ``rows`` (indices into the other arrays):
    the first of the steps +J, 0, -J that keeps the command's limits, does not pass the
    target and whose brake (with the mover's hardest dynamics) stays in its room, or for a
    FAST pair keeps the gap braking together with the predecessor (``ahead[r]``, D-211).
    Writes the step into ``out`` (4, m) and its envelope into ``env`` (2, m); returns the
    mask of the rows that got one.

    A mover that gap control braked beyond its command's dynamics (its deceleration is
    beyond the command's, or the command's jerk cannot bring it to rest without turning)
    fits no such step. It then takes the steps of its hardest dynamics, so that it leaves
    that brake as soon as its room allows instead of riding it to rest short of its place
    (D-210)."""
    fitted = np.zeros(rows.shape[0], dtype=np.bool_)
    times = np.empty(7)
    for r in range(rows.shape[0]):
        k = rows[r]
        s = sign[k]
        fitted[r] = _first_step(k, dt, p, v, a, s, target[k], vmax[k], acc[k], dec[k], jm[k],
                                bdec[k], bjerk[k], room_lo[k], room_hi[k], ahead[r], times,
                                out, env)
        if fitted[r]:
            continue
        u, b = s * v[k], s * a[k]
        if b < -dec[k] or u + b * abs(b) / (2.0 * jm[k]) < 0.0:  # beyond the command's brake
            fitted[r] = _first_step(k, dt, p, v, a, s, target[k], vmax[k], acc[k], bdec[k],
                                    bjerk[k], bdec[k], bjerk[k], room_lo[k], room_hi[k],
                                    ahead[r], times, out, env)
    return fitted


@compiled
def _brake_state(p: float, v: float, a: float, dec: float, jerk: float,
                 t: float) -> tuple[float, float, float, float]:
    """(p, v, a, j) a time ``t`` into one mover's brake; at rest after its end."""
    t1, t2, t3, j1, j3, _ = _phases(v, a, dec, jerk)
    durations = (t1, t2, t3)
    jerks = (j1, 0.0, j3)
    pk, vk, ak = p, v, a
    start = 0.0
    end = 0.0
    j = 0.0
    rest = True
    for k in range(3):
        end = end + durations[k] if k else durations[k]
        if t < end:  # inside phase k
            j = jerks[k]
            rest = False
            break
        tk, jk = durations[k], jerks[k]
        pk, vk, ak = (pk + tk * (vk + tk * (0.5 * ak + tk * jk / 6.0)),
                      vk + tk * (ak + 0.5 * tk * jk), ak + tk * jk)
        start = end
    if rest:  # the brake has ended: at rest where it stopped
        vk, ak, j = 0.0, 0.0, 0.0
    tau = t - start
    return (pk + tau * (vk + tau * (0.5 * ak + tau * j / 6.0)),
            vk + tau * (ak + 0.5 * tau * j), ak + tau * j, j)


@compiled
def brake_states(p: np.ndarray, v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                 jerk: np.ndarray, t: float) -> tuple[np.ndarray, ...]:
    """braking.brake_state: (p, v, a, j) a time ``t`` into each mover's brake."""
    n = p.shape[0]
    po, vo, ao, jo = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        po[i], vo[i], ao[i], jo[i] = _brake_state(p[i], v[i], a[i], dec[i], jerk[i], t)
    return po, vo, ao, jo


@compiled
def phase_table(v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                jerk: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """braking.brake_phases: durations and jerks of the three phases, each (N, 3)."""
    n = v.shape[0]
    durations, jerks = np.empty((n, 3)), np.zeros((n, 3))
    for i in range(n):
        t1, t2, t3, j1, j3, _ = _phases(v[i], a[i], dec[i], jerk[i])
        durations[i, 0], durations[i, 1], durations[i, 2] = t1, t2, t3
        jerks[i, 0], jerks[i, 2] = j1, j3
    return durations, jerks


@compiled
def _advance(p: float, v: float, a: float, t: float, j: float) -> tuple[float, float, float]:
    """(p, v, a) after ``t`` of constant jerk ``j``."""
    return (p + t * (v + t * (0.5 * a + t * j / 6.0)), v + t * (a + 0.5 * t * j), a + t * j)


@compiled(inline=True)
def _brake_at(t: float, e1: float, e2: float, e3: float, j1: float, j3: float, p0: float,
              v0: float, a0: float, p1: float, v1: float, a1: float, p2: float, v2: float,
              a2: float, p3: float) -> tuple[float, float, float, float]:
    """(p, v, a, jerk of the phase that starts here) at time t of a brake given by the ends
    of its three phases (cumulated), their jerks (j2 = 0) and (p, v, a) at the phase
    boundaries; it ends at rest (the float residue of v and a dropped). Scalars, not a table
    of tuples: numba indexed those at run time, five times the cost of the arithmetic."""
    phase = 0
    if t >= e1 - PHASE_END_TOLERANCE:
        phase += 1
    if t >= e2 - PHASE_END_TOLERANCE:
        phase += 1
    if t >= e3 - PHASE_END_TOLERANCE:
        phase += 1
    if phase == 0:
        start, j, p, v, a = 0.0, j1, p0, v0, a0
    elif phase == 1:
        start, j, p, v, a = e1, 0.0, p1, v1, a1
    elif phase == 2:
        start, j, p, v, a = e2, j3, p2, v2, a2
    else:
        start, j, p, v, a = e3, 0.0, p3, 0.0, 0.0
    tau = t - start
    if tau < 0.0:  # numpy.maximum(tau, 0.0): nan stays nan
        tau = 0.0
    x, u, b = _advance(p, v, a, tau, j)
    return x, u, b, j


@compiled
def _minimum(a: float, b: float) -> float:
    """numpy.minimum: nan if either is nan."""
    return a if (a <= b or a != a) else b


@compiled(inline=True)
def _brake_ends(p: float, v: float, a: float, dec: float, jerk: float) -> tuple[float, ...]:
    """One brake by the ends of its phases (cumulated), their jerks and (p, v, a) at the phase
    boundaries, as ``_brake_at`` takes them (15 values)."""
    t1, t2, t3, j1, j3, _ = _phases(v, a, dec, jerk)
    p1, v1, a1 = _advance(p, v, a, t1, j1)
    p2, v2, a2 = _advance(p1, v1, a1, t2, 0.0)
    p3, _, _ = _advance(p2, v2, a2, t3, j3)
    e2 = t1 + t2
    return t1, e2, e2 + t3, j1, j3, p, v, a, p1, v1, a1, p2, v2, a2, p3


@compiled(inline=True)
def _merged_ends(times: np.ndarray, ke1: float, ke2: float, ke3: float, ie1: float,
                 ie2: float, ie3: float) -> None:
    """``times`` = 0 and the six phase ends of a pair's brakes, sorted."""
    times[0] = 0.0
    times[1], times[2], times[3] = ke1, ke2, ke3
    times[4], times[5], times[6] = ie1, ie2, ie3
    sort_in_place(times)


@compiled(inline=True)
def _gap_roots(da: float, dv: float, dj: float) -> tuple[float, float]:
    """Where the derivative dv + da s + dj s²/2 of a pair's gap vanishes (nan: no root)."""
    square = da * da - 2.0 * dj * dv
    if square < 0.0:  # numpy.maximum(square, 0.0): nan stays nan
        square = 0.0
    disc = math.sqrt(square)
    if dj != 0.0:
        return (-da - disc) / dj, (-da + disc) / dj
    return -dv / da, math.nan


@compiled
def _min_brake_gap(pk: float, vk: float, ak: float, dk: float, jk: float, pi: float,
                   vi: float, ai: float, di: float, ji: float, times: np.ndarray) -> float:
    """min over t >= 0 of brake_k(t) - brake_i(t) for one pair (``times``: scratch of 7).

    Between the merged phase boundaries of the two brakes the difference is one cubic; its
    minimum lies at an end or where its derivative (a quadratic) vanishes."""
    ke1, ke2, ke3, kj1, kj3, kp0, kv0, ka0, kp1, kv1, ka1, kp2, kv2, ka2, kp3 = _brake_ends(
        pk, vk, ak, dk, jk)
    ie1, ie2, ie3, ij1, ij3, ip0, iv0, ia0, ip1, iv1, ia1, ip2, iv2, ia2, ip3 = _brake_ends(
        pi, vi, ai, di, ji)
    _merged_ends(times, ke1, ke2, ke3, ie1, ie2, ie3)
    best = math.inf
    for c in range(7):
        t0 = times[c]
        xk, uk, bk, gk = _brake_at(t0, ke1, ke2, ke3, kj1, kj3, kp0, kv0, ka0, kp1, kv1, ka1,
                                   kp2, kv2, ka2, kp3)
        xi, ui, bi, gi = _brake_at(t0, ie1, ie2, ie3, ij1, ij3, ip0, iv0, ia0, ip1, iv1, ia1,
                                   ip2, iv2, ia2, ip3)
        best = _minimum(best, xk - xi)
        if c == 6:
            break
        length = times[c + 1] - t0
        # derivative of the difference on [t0, t1]: dv + da s + dj s²/2
        dv, da, dj = uk - ui, bk - bi, gk - gi
        r1, r2 = _gap_roots(da, dv, dj)
        if math.isfinite(r1) and r1 > 0.0 and r1 < length:
            best = _minimum(best, (xk - xi) + r1 * (dv + r1 * (0.5 * da + r1 * dj / 6.0)))
        if math.isfinite(r2) and r2 > 0.0 and r2 < length:
            best = _minimum(best, (xk - xi) + r2 * (dv + r2 * (0.5 * da + r2 * dj / 6.0)))
    return best


@compiled
def brake_gap_holds(pk: float, vk: float, ak: float, dk: float, jk: float, pi: float,
                    vi: float, ai: float, di: float, ji: float, need: float,
                    times: np.ndarray) -> bool:
    """``_min_brake_gap(...) >= need``, the FAST pair check, for less: it looks first where
    both brakes end (where a follower that cannot keep the gap nearly always fails), stops at
    the first value below ``need``, and skips the roots of a piece whose cubic a bound keeps
    ``BOUND_MARGIN`` above ``need``. The same answer for every pair
    (tests/transport/test_gap_control.py)."""
    ke1, ke2, ke3, kj1, kj3, kp0, kv0, ka0, kp1, kv1, ka1, kp2, kv2, ka2, kp3 = _brake_ends(
        pk, vk, ak, dk, jk)
    ie1, ie2, ie3, ij1, ij3, ip0, iv0, ia0, ip1, iv1, ia1, ip2, iv2, ia2, ip3 = _brake_ends(
        pi, vi, ai, di, ji)
    if not kp3 - ip3 >= need:  # where both rest: the last value the loop would see
        return False
    _merged_ends(times, ke1, ke2, ke3, ie1, ie2, ie3)
    for c in range(7):
        t0 = times[c]
        xk, uk, bk, gk = _brake_at(t0, ke1, ke2, ke3, kj1, kj3, kp0, kv0, ka0, kp1, kv1, ka1,
                                   kp2, kv2, ka2, kp3)
        xi, ui, bi, gi = _brake_at(t0, ie1, ie2, ie3, ij1, ij3, ip0, iv0, ia0, ip1, iv1, ia1,
                                   ip2, iv2, ia2, ip3)
        d0 = xk - xi
        if not d0 >= need:  # nan as well: the minimum would be nan
            return False
        if c == 6:
            break
        length = times[c + 1] - t0
        dv, da, dj = uk - ui, bk - bi, gk - gi
        low = d0 + length * (min(dv, 0.0) + length * (0.5 * min(da, 0.0)
                                                      + length * min(dj, 0.0) / 6.0))
        if low >= need + BOUND_MARGIN:  # no value of this piece can be below need
            continue
        r1, r2 = _gap_roots(da, dv, dj)
        if math.isfinite(r1) and r1 > 0.0 and r1 < length and not (
                d0 + r1 * (dv + r1 * (0.5 * da + r1 * dj / 6.0)) >= need):
            return False
        if math.isfinite(r2) and r2 > 0.0 and r2 < length and not (
                d0 + r2 * (dv + r2 * (0.5 * da + r2 * dj / 6.0)) >= need):
            return False
    return True


@compiled
def min_brake_gaps(pk: np.ndarray, vk: np.ndarray, ak: np.ndarray, dk: np.ndarray,
                   jk: np.ndarray, pi: np.ndarray, vi: np.ndarray, ai: np.ndarray,
                   di: np.ndarray, ji: np.ndarray) -> np.ndarray:
    """gap_control.min_brake_gap: ``_min_brake_gap`` for every pair."""
    n = pk.shape[0]
    best = np.empty(n)
    times = np.empty(7)
    for m in range(n):
        best[m] = _min_brake_gap(pk[m], vk[m], ak[m], dk[m], jk[m], pi[m], vi[m], ai[m], di[m],
                                 ji[m], times)
    return best


@compiled
def pair_safety(check: np.ndarray, succ: np.ndarray, pred: np.ndarray, offset: np.ndarray,
                gap: np.ndarray, fast: np.ndarray, tcp: np.ndarray, behind: np.ndarray,
                p: np.ndarray, v: np.ndarray, a: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                dec: np.ndarray, jerk: np.ndarray) -> np.ndarray:
    """gap_control._safe: the safety of the ``check``-ed pairs (the others report True).

    STANDARD: the successor's envelope ends one gap behind the predecessor's, on the motor
    path, or for a pair that measures its gap on a TCP path (``tcp``, D-073) below
    ``behind``. FAST pairs that fail it are safe when both brakes together keep the gap."""
    ok = np.ones(succ.shape[0], dtype=np.bool_)
    times = np.empty(7)
    for m in range(succ.shape[0]):
        if not check[m]:
            continue
        s, k = succ[m], pred[m]
        if tcp[m]:
            standard = hi[s] <= behind[m] + TOLERANCE
        else:
            standard = hi[s] + gap[m] <= lo[k] + offset[m] + TOLERANCE
        if not standard and fast[m]:
            standard = brake_gap_holds(p[k] + offset[m], v[k], a[k], dec[k], jerk[k], p[s],
                                       v[s], a[s], dec[s], jerk[s], gap[m] - TOLERANCE, times)
        ok[m] = standard
    return ok


@compiled
def blame(bad: np.ndarray, succ: np.ndarray, pred: np.ndarray, fast: np.ndarray, both: bool,
          fast_held: np.ndarray, braking: np.ndarray, lo: np.ndarray, hi: np.ndarray,
          lo_cur: np.ndarray, hi_cur: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One round of gap_control.filter_steps: which movers of the ``bad`` pairs brake now
    (ascending, once each) and which pairs to check again (those with a mover among them).

    A successor that claims room (its envelope end moves on, or a FAST pair was safe before)
    is blamed, with Both a predecessor that moves backwards too, and in a FAST pair whose
    successor already brakes the predecessor as well (then its brake moves on as before)."""
    flag = np.zeros(braking.shape[0], dtype=np.bool_)
    for m in range(succ.shape[0]):
        if not bad[m]:
            continue
        s, k = succ[m], pred[m]
        claims = hi[s] > hi_cur[s] + TOLERANCE or (fast[m] and fast_held[m])
        if claims and not braking[s]:
            flag[s] = True
        if both and lo[k] < lo_cur[k] - TOLERANCE and not braking[k]:
            flag[k] = True
        if fast[m] and braking[s] and not braking[k]:
            flag[k] = True
    check = np.empty(succ.shape[0], dtype=np.bool_)
    for m in range(succ.shape[0]):
        check[m] = flag[succ[m]] or flag[pred[m]]
    return true_indices(flag), check


@compiled
def brake_blamed(blamed: np.ndarray, p: np.ndarray, v: np.ndarray, a: np.ndarray,
                 dec: np.ndarray, jerk: np.ndarray, t: float, nxt_p: np.ndarray,
                 nxt_v: np.ndarray, nxt_a: np.ndarray, nxt_j: np.ndarray, lo: np.ndarray,
                 hi: np.ndarray, braking: np.ndarray) -> None:
    """The ``blamed`` movers follow their brake from (p, v, a) for a time ``t`` instead of
    their proposal in ``nxt_*``: their step, its envelope (lo, hi) and ``braking``, in place."""
    for r in range(blamed.shape[0]):
        k = blamed[r]
        braking[k] = True
        nxt_p[k], nxt_v[k], nxt_a[k], nxt_j[k] = _brake_state(p[k], v[k], a[k], dec[k],
                                                              jerk[k], t)
        lo[k], hi[k] = envelope(nxt_p[k], nxt_v[k], nxt_a[k], dec[k], jerk[k])
