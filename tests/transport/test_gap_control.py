"""The FAST pair check of gap control, compiled (kernels.min_brake_gaps, kernels.pair_safety,
D-186), against the numpy formulation it replaced: the same closest approach bit for bit and
the same verdict for every pair, turning brakes, equal brakes and TCP pairs included.

The numpy code below is the formulation of gap_control.py before D-186 (kept here as the
reference, not as a second implementation in the package).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from openmotion.rail.braking import brake_phases
from openmotion.rail.gap_control import TOLERANCE, Pairs, _safe, min_brake_gap
from openmotion.rail.kernels import brake_gap_holds


def _boundaries(p: np.ndarray, v: np.ndarray, a: np.ndarray, durations: np.ndarray,
                jerks: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = p.shape[0]
    P, V, A = np.empty((n, 4)), np.empty((n, 4)), np.empty((n, 4))  # noqa: N806 - maths
    P[:, 0], V[:, 0], A[:, 0] = p, v, a
    for k in range(3):
        t, j = durations[:, k], jerks[:, k]
        p0, v0, a0 = P[:, k], V[:, k], A[:, k]
        P[:, k + 1] = p0 + t * (v0 + t * (0.5 * a0 + t * j / 6.0))
        V[:, k + 1] = v0 + t * (a0 + 0.5 * t * j)
        A[:, k + 1] = a0 + t * j
    V[:, 3] = 0.0
    A[:, 3] = 0.0
    return P, V, A


def _at(P, V, A, ends, jerks, t):  # noqa: N803 - maths
    rows = np.arange(P.shape[0])
    phase = (t[:, None] >= ends - 1e-15).sum(axis=1)
    start = np.where(phase == 0, 0.0, ends[rows, np.maximum(phase - 1, 0)])
    tau = np.maximum(t - start, 0.0)
    j = np.where(phase < 3, jerks[rows, np.minimum(phase, 2)], 0.0)
    p0, v0, a0 = P[rows, phase], V[rows, phase], A[rows, phase]
    return (p0 + tau * (v0 + tau * (0.5 * a0 + tau * j / 6.0)),
            v0 + tau * (a0 + 0.5 * tau * j), a0 + tau * j, j)


def reference_min_brake_gap(pk, vk, ak, dk, jk, pi, vi, ai, di, ji) -> np.ndarray:
    n = pk.shape[0]
    dur_k, jer_k = brake_phases(vk, ak, dk, jk)
    dur_i, jer_i = brake_phases(vi, ai, di, ji)
    Pk, Vk, Ak = _boundaries(pk, vk, ak, dur_k, jer_k)  # noqa: N806 - maths
    Pi, Vi, Ai = _boundaries(pi, vi, ai, dur_i, jer_i)  # noqa: N806
    end_k, end_i = np.cumsum(dur_k, axis=1), np.cumsum(dur_i, axis=1)
    times = np.sort(np.concatenate((np.zeros((n, 1)), end_k, end_i), axis=1), axis=1)
    best = np.full(n, np.inf)
    for c in range(times.shape[1]):
        t0 = times[:, c]
        xk, uk, bk, gk = _at(Pk, Vk, Ak, end_k, jer_k, t0)
        xi, ui, bi, gi = _at(Pi, Vi, Ai, end_i, jer_i, t0)
        best = np.minimum(best, xk - xi)
        if c == times.shape[1] - 1:
            break
        length = times[:, c + 1] - t0
        dv, da, dj = uk - ui, bk - bi, gk - gi
        with np.errstate(divide="ignore", invalid="ignore"):
            disc = np.sqrt(np.maximum(da * da - 2.0 * dj * dv, 0.0))
            roots = (np.where(dj != 0.0, (-da - disc) / dj, -dv / da),
                     np.where(dj != 0.0, (-da + disc) / dj, np.nan))
        for s in roots:
            inside = np.isfinite(s) & (s > 0.0) & (s < length)
            if not inside.any():
                continue
            s = np.where(inside, s, 0.0)
            diff = (xk - xi) + s * (dv + s * (0.5 * da + s * dj / 6.0))
            best = np.minimum(best, np.where(inside, diff, np.inf))
    return best


def reference_safe(state, pairs: Pairs, lo, hi, dec, jerk, check) -> np.ndarray:
    ok = np.ones(pairs.succ.size, dtype=bool)
    m = np.flatnonzero(check)
    s, k = pairs.succ[m], pairs.pred[m]
    standard = hi[s] + pairs.gap[m] <= lo[k] + pairs.offset[m] + TOLERANCE
    tcp = pairs.on_tcp(m)
    if tcp.any():
        t = m[tcp]
        standard[tcp] = hi[pairs.succ[t]] <= pairs.behind(
            t, lo[pairs.pred[t]] + pairs.offset[t]) + TOLERANCE
    ok[m] = standard
    fast = m[pairs.fast[m] & ~standard]
    if fast.size:
        s, k = pairs.succ[fast], pairs.pred[fast]
        p, v, a = state[0], state[1], state[2]
        gap = reference_min_brake_gap(p[k] + pairs.offset[fast], v[k], a[k], dec[k], jerk[k],
                                      p[s], v[s], a[s], dec[s], jerk[s])
        ok[fast] = gap >= pairs.gap[fast] - TOLERANCE
    return ok


def random_states(rng: np.random.Generator, n: int) -> list[np.ndarray]:
    """(p, v, a, dec, jerk) of n movers: cruising, braking, accelerating, beyond their own
    deceleration (turning brakes), at rest, and the brake phase boundaries' round values."""
    p = rng.uniform(-500.0, 500.0, n)
    v = rng.uniform(-3000.0, 3000.0, n)
    a = rng.uniform(-25000.0, 25000.0, n)
    dec = rng.uniform(1000.0, 20000.0, n)
    jerk = 10.0 ** rng.uniform(4.0, 6.0, n)
    rest = rng.random(n) < 0.1
    v[rest], a[rest] = 0.0, 0.0
    cruise = rng.random(n) < 0.2
    a[cruise] = 0.0
    at_dec = rng.random(n) < 0.1  # holding the peak deceleration exactly
    a[at_dec] = -np.sign(v[at_dec]) * dec[at_dec]
    return [p, v, a, dec, jerk]


def test_min_brake_gap_is_the_numpy_formulation_bit_for_bit() -> None:
    """D-186: the compiled closest approach equals the numpy one exactly (200 000 pairs)."""
    rng = np.random.default_rng(19)
    n = 200_000
    k, i = random_states(rng, n), random_states(rng, n)
    same = rng.random(n) < 0.1  # equal dynamics and state one gap apart: the FAST case
    for x, y in zip(k[1:], i[1:], strict=True):
        y[same] = x[same]
    k[0][same] = i[0][same] + 100.0
    got = min_brake_gap(*k, *i)
    want = reference_min_brake_gap(*k, *i)
    assert np.isfinite(want).all()
    assert np.array_equal(got.view(np.int64), want.view(np.int64))  # every bit


pair_counts = st.integers(2, 8)


@settings(deadline=None, max_examples=200)
@given(n=pair_counts, seed=st.integers(0, 2**32 - 1), tcp=st.booleans())
def test_pair_safety_is_the_numpy_formulation(n: int, seed: int, tcp: bool) -> None:
    """D-186: the same verdict for every checked pair of a ring, STANDARD and FAST, with
    gaps on a TCP path (D-073) or on the motor path."""
    rng = np.random.default_rng(seed)
    p, v, a, dec, jerk = random_states(rng, n)
    p = np.sort(rng.uniform(0.0, 300.0 * n, n))
    lo, hi = np.minimum(p, p + rng.normal(0.0, 80.0, n)), np.maximum(p, p + rng.normal(0, 80, n))
    succ = np.arange(n)
    pred = (succ + 1) % n
    offset = np.where(pred == 0, 300.0 * n, 0.0)
    gap = rng.uniform(0.0, 150.0, n)

    class Shift:  # a monotone TCP map: the TCP path runs 10 % longer, shifted by y
        def motor_to_tcp(self, x: np.ndarray, y: float) -> np.ndarray:
            return 1.1 * x + y

        def tcp_to_motor(self, x: np.ndarray, y: float) -> np.ndarray:
            return (x - y) / 1.1

    y = rng.choice([0.0, 30.0, 100.0], n) if tcp else None
    pairs = Pairs(succ, pred, offset, gap, rng.random(n) < 0.6, True, y,
                  Shift() if tcp else None)
    check = rng.random(n) < 0.8
    state = (p, v, a)
    got = _safe(state, pairs, lo, hi, dec, jerk, check)
    assert got.dtype == np.bool_
    assert np.array_equal(got, reference_safe(state, pairs, lo, hi, dec, jerk, check))


def test_the_fast_pair_check_answers_as_the_closest_approach_does() -> None:
    """kernels.brake_gap_holds, which looks where both brakes end first and skips roots a
    bound settles, says ``min_brake_gap >= need`` for every pair: needs at the closest
    approach itself, a float step either side of it, near it and far from it."""
    rng = np.random.default_rng(23)
    n = 20_000
    k, i = random_states(rng, n), random_states(rng, n)
    same = rng.random(n) < 0.3  # equal dynamics: a FAST follower one gap behind
    for x, y in zip(k[1:], i[1:], strict=True):
        y[same] = x[same]
    k[0][same] = i[0][same] + rng.uniform(50.0, 150.0, int(same.sum()))
    closest = min_brake_gap(*k, *i)
    needs = [closest, np.nextafter(closest, np.inf), np.nextafter(closest, -np.inf),
             closest + rng.normal(0.0, 1e-6, n), closest + rng.normal(0.0, 10.0, n),
             np.full(n, 100.0 - TOLERANCE)]
    times = np.empty(7)
    answers = {True: 0, False: 0}
    for need in needs:
        for m in range(n):
            want = bool(closest[m] >= need[m])
            got = brake_gap_holds(k[0][m], k[1][m], k[2][m], k[3][m], k[4][m], i[0][m],
                                  i[1][m], i[2][m], i[3][m], i[4][m], need[m], times)
            assert got == want, (m, need[m], closest[m])
            answers[want] += 1
    assert min(answers.values()) > n  # both answers, many times each
