"""Jerk-limited braking to rest for many movers at once: the maths of gap control.

Collision avoidance rests on one question per mover and cycle: if it started braking now,
with its maximum deceleration ``dec`` and maximum jerk ``jerk``, where could it be until it
stands? The brake is the time-optimal change to velocity 0 (the closed form of
``trajectory.plan._velocity_profile``, here vectorised): at most three constant-jerk phases,
jerk towards the peak deceleration, hold it, jerk back to zero.

* :func:`brake_phases`: durations and jerks of the three phases, shape (N, 3).
* :func:`brake_state`: the state a time ``t`` into the brake (rest after its end).
* :func:`brake_envelope`: the interval ``[lo, hi]`` of positions the brake passes through.

Braking is *time-consistent*: braking from a state on a brake follows the rest of that same
brake, so its envelope is a sub-interval. docs/collision-avoidance.md builds the safety
argument on that.
"""

from __future__ import annotations

import numpy as np

Arrays = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def brake_phases(v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                 jerk: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(durations, jerks), each (N, 3): the time-optimal brake from (v, a) to rest."""
    t1, t2, t3, j1, j3, _ = _phases(v, a, dec, jerk)
    zero = np.zeros_like(v)
    return np.stack((t1, t2, t3), axis=1), np.stack((j1, zero, j3), axis=1)


def _phases(v: np.ndarray, a: np.ndarray, dec: np.ndarray,
            jerk: np.ndarray) -> tuple[np.ndarray, ...]:
    """Durations t1, t2, t3 and jerks j1, j3 of the three phases (j2 = 0), and the
    velocity once the acceleration is taken away at once (its sign decides the brake)."""
    inv = 0.5 / jerk
    release = v + a * np.abs(a) * inv
    d = -np.sign(release)  # direction of the velocity change
    peak_sq = 0.5 * a * a - jerk * d * v
    triangular = (peak_sq <= dec * dec) | (d == 0.0)
    peak = np.where(triangular, d * np.sqrt(np.maximum(peak_sq, 0.0)), d * dec)
    first = np.sign(peak - a)
    # velocity gained while the acceleration goes from a to the peak, then held
    gained = (peak * peak - a * a) * inv * first
    safe_peak = np.where(triangular, 1.0, peak)
    hold = np.where(triangular, 0.0, (-v - gained - peak * np.abs(peak) * inv) / safe_peak)
    return (np.abs(peak - a) / jerk, np.maximum(hold, 0.0), np.abs(peak) / jerk,
            first * jerk, -d * jerk, release)


def _boundaries(p: np.ndarray, v: np.ndarray, a: np.ndarray, durations: np.ndarray,
                jerks: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions, velocities, accelerations at the four phase boundaries, each (N, 4)."""
    n = p.shape[0]
    P, V, A = np.empty((n, 4)), np.empty((n, 4)), np.empty((n, 4))  # noqa: N806 - maths
    P[:, 0], V[:, 0], A[:, 0] = p, v, a
    for k in range(3):
        t, j = durations[:, k], jerks[:, k]
        p0, v0, a0 = P[:, k], V[:, k], A[:, k]
        P[:, k + 1] = p0 + t * (v0 + t * (0.5 * a0 + t * j / 6.0))
        V[:, k + 1] = v0 + t * (a0 + 0.5 * t * j)
        A[:, k + 1] = a0 + t * j
    V[:, 3] = 0.0  # the brake ends at rest: drop the float residue
    A[:, 3] = 0.0
    return P, V, A


def brake_state(p: np.ndarray, v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                jerk: np.ndarray, t: float) -> Arrays:
    """(p, v, a, j) a time ``t`` [s] into the brake of each mover; at rest after its end."""
    durations, jerks = brake_phases(v, a, dec, jerk)
    P, V, A = _boundaries(p, v, a, durations, jerks)  # noqa: N806
    ends = np.cumsum(durations, axis=1)
    phase = (t >= ends).sum(axis=1)  # 0..3; 3 = at rest
    rows = np.arange(p.shape[0])
    start = np.where(phase == 0, 0.0, ends[rows, np.maximum(phase - 1, 0)])
    tau = t - start
    j = np.where(phase < 3, jerks[rows, np.minimum(phase, 2)], 0.0)
    p0, v0, a0 = P[rows, phase], V[rows, phase], A[rows, phase]
    return (p0 + tau * (v0 + tau * (0.5 * a0 + tau * j / 6.0)),
            v0 + tau * (a0 + 0.5 * tau * j), a0 + tau * j, j)


def brake_envelope(p: np.ndarray, v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                   jerk: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi): lowest and highest position each mover passes while braking to rest.

    Usually the velocity keeps its sign while braking and the envelope is spanned by the
    start and the stop point. The velocity can change sign only in a state that brakes harder
    than it needs to: taking its acceleration away at once would already reverse it
    (``release`` and ``v`` of opposite signs). There the turning points are added.
    """
    t1, t2, t3, j1, j3, release = _phases(v, a, dec, jerk)
    # phase 1 (jerk j1), phase 2 (constant acceleration a1), phase 3 (jerk j3)
    p1 = p + t1 * (v + t1 * (0.5 * a + t1 * j1 / 6.0))
    v1 = v + t1 * (a + 0.5 * t1 * j1)
    a1 = a + t1 * j1
    p2 = p1 + t2 * (v1 + 0.5 * t2 * a1)
    v2 = v1 + t2 * a1
    p3 = p2 + t3 * (v2 + t3 * (0.5 * a1 + t3 * j3 / 6.0))
    lo, hi = np.minimum(p, p3), np.maximum(p, p3)
    turns = v * release < 0.0
    if turns.any():
        rows = np.flatnonzero(turns)
        durations, jerks = brake_phases(v[rows], a[rows], dec[rows], jerk[rows])
        P, V, A = _boundaries(p[rows], v[rows], a[rows], durations, jerks)  # noqa: N806
        for k in range(3):
            for tau in _velocity_roots(V[:, k], A[:, k], jerks[:, k], durations[:, k]):
                inside = np.isfinite(tau)
                tau = np.where(inside, tau, 0.0)
                pos = P[:, k] + tau * (V[:, k] + tau * (0.5 * A[:, k] + tau * jerks[:, k] / 6.0))
                pos = np.where(inside, pos, P[:, k])
                lo[rows] = np.minimum(lo[rows], pos)
                hi[rows] = np.maximum(hi[rows], pos)
    return lo, hi


def _velocity_roots(v0: np.ndarray, a0: np.ndarray, j: np.ndarray,
                    duration: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Times in [0, duration] where v0 + a0 t + j t²/2 = 0 (nan where there is none)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(np.maximum(a0 * a0 - 2.0 * j * v0, 0.0))
        quadratic = j != 0.0
        r1 = np.where(quadratic, (-a0 - disc) / j, -v0 / a0)
        r2 = np.where(quadratic, (-a0 + disc) / j, np.nan)
    roots = []
    for r in (r1, r2):
        ok = np.isfinite(r) & (r >= 0.0) & (r <= duration)
        roots.append(np.where(ok, r, np.nan))
    return roots[0], roots[1]

