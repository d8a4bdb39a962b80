"""The gap filter: which movers must brake this cycle so that no gap is ever undershot.

Every mover proposes a next setpoint (its profile, or the tracking step of a held mover).
Its *envelope* is the interval it would sweep if it braked from there with its maximum
deceleration and jerk (braking.py). For a successor ``i`` with predecessor ``k`` the pair is
safe when

* STANDARD: ``hi_i + gap <= lo_k`` (the successor can stop behind any point the predecessor
  can still be at, even if the predecessor stopped at once: gaps grow with speed);
* FAST: ``brake_k(t) - brake_i(t) >= gap`` for every t (both brake together: with equal
  dynamics the gap can stay at its minimum at any speed).

A mover that *claims* room towards a neighbour (moves its envelope end towards it) in a pair
that is not safe brakes instead: it follows its own brake for one cycle, which never claims.
Braking can make further pairs unsafe, so the check repeats until nothing changes; every
round is vectorised and each round brakes at least one more mover. docs/collision-avoidance.md
has the safety argument.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from openmotion.transport.braking import (
    _boundaries,
    brake_envelope,
    brake_phases,
    brake_state,
)

TOLERANCE = 1e-9  #: [mm] float slack of the pair checks


class TcpPath(Protocol):
    """The monotone maps between the motor path and a TCP path (geo.StarterKitGeometry)."""

    def motor_to_tcp(self, position: np.ndarray, y_shift: float) -> np.ndarray: ...

    def tcp_to_motor(self, position: np.ndarray, y_shift: float) -> np.ndarray: ...


@dataclass
class Pairs:
    """Adjacent pairs of a group: successor ``succ[m]`` keeps ``gap[m]`` to ``pred[m]``.

    ``offset[m]`` is added to the predecessor's positions (a lap on a ring), ``fast[m]``
    selects the FAST check, ``both`` lets a predecessor moving backwards be blamed.
    ``y[m] > 0`` measures the pair's gap on the TCP path of the successor's mover template
    (geo-compensation, D-073) through ``path``; 0 on the motor path.
    """

    succ: np.ndarray
    pred: np.ndarray
    offset: np.ndarray
    gap: np.ndarray
    fast: np.ndarray
    both: bool
    y: np.ndarray | None = None
    path: TcpPath | None = None

    def on_tcp(self, m: np.ndarray) -> np.ndarray:
        """Which of the pairs ``m`` measure their gap on a TCP path."""
        return np.zeros(m.size, dtype=bool) if self.y is None else self.y[m] > 0.0

    def behind(self, m: np.ndarray, ahead: np.ndarray) -> np.ndarray:
        """Motor position one gap behind ``ahead`` (motor positions, in the successor's lap),
        measured on the TCP path, for the TCP pairs ``m``."""
        return self._shifted(m, ahead, -self.gap[m])

    def ahead(self, m: np.ndarray, behind: np.ndarray) -> np.ndarray:
        """Motor position one gap (on the TCP path) ahead of ``behind``, for the pairs ``m``."""
        return self._shifted(m, behind, self.gap[m])

    def _shifted(self, m: np.ndarray, position: np.ndarray, by: np.ndarray) -> np.ndarray:
        assert self.y is not None and self.path is not None
        out = np.empty(m.size)
        y = self.y[m]
        for shift in np.unique(y).tolist():
            k = y == shift
            out[k] = self.path.tcp_to_motor(self.path.motor_to_tcp(position[k], shift) + by[k],
                                            shift)
        return out


def filter_steps(cur: tuple[np.ndarray, np.ndarray, np.ndarray],
                 envelope: tuple[np.ndarray, np.ndarray], nxt: list[np.ndarray],
                 cycle_time: float, dec: np.ndarray, jerk: np.ndarray,
                 pairs: Pairs, known: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Replace unsafe proposals in ``nxt`` ([p, v, a, j], modified) by the brake step.

    ``cur`` is the state of the last cycle with its ``envelope`` (lo, hi); the brake step
    (one cycle of each mover's brake from there) is computed only for the movers that brake.
    Returns the mask of movers that brake and the envelope of ``nxt``. ``known`` = (mask,
    lo, hi) gives the envelopes of proposals the caller computed already.
    """
    n = cur[0].shape[0]
    braking = np.zeros(n, dtype=bool)
    if known is None:
        lo, hi = brake_envelope(nxt[0], nxt[1], nxt[2], dec, jerk)
    else:
        mask, lo, hi = known
        lo, hi = lo.copy(), hi.copy()
        todo = np.flatnonzero(~mask)
        if todo.size:
            lo[todo], hi[todo] = brake_envelope(nxt[0][todo], nxt[1][todo], nxt[2][todo],
                                                dec[todo], jerk[todo])
    if pairs.succ.size == 0:
        return braking, lo, hi
    lo_cur, hi_cur = envelope
    fast_held = np.zeros(pairs.succ.size, dtype=bool)
    if pairs.fast.any():
        fast_held = _safe(cur, pairs, lo_cur, hi_cur, dec, jerk, pairs.fast)
    check = np.ones(pairs.succ.size, dtype=bool)
    while True:
        ok = _safe(nxt, pairs, lo, hi, dec, jerk, check)
        bad = check & ~ok
        if not bad.any():
            return braking, lo, hi
        s, k = pairs.succ[bad], pairs.pred[bad]
        claims = hi[s] > hi_cur[s] + TOLERANCE
        claims |= pairs.fast[bad] & fast_held[bad]
        blamed = s[claims & ~braking[s]]
        if pairs.both:
            backwards = lo[k] < lo_cur[k] - TOLERANCE
            blamed = np.concatenate((blamed, k[backwards & ~braking[k]]))
        # FAST: with the successor braking, only a predecessor that brakes too is sure to
        # keep the pair (its brake then moves on exactly as before)
        fast_pred = pairs.fast[bad] & braking[s] & ~braking[k]
        blamed = np.concatenate((blamed, k[fast_pred]))
        flag = np.zeros(n, dtype=bool)
        flag[blamed] = True
        blamed = np.flatnonzero(flag)  # sorted, once each
        if blamed.size == 0:
            return braking, lo, hi  # only pairs that were unsafe before and do not get worse
        braking[blamed] = True
        step = brake_state(cur[0][blamed], cur[1][blamed], cur[2][blamed], dec[blamed],
                           jerk[blamed], cycle_time)
        for field, source in zip(nxt, step, strict=True):
            field[blamed] = source
        lo[blamed], hi[blamed] = brake_envelope(
            nxt[0][blamed], nxt[1][blamed], nxt[2][blamed], dec[blamed], jerk[blamed])
        check = flag[pairs.succ] | flag[pairs.pred]


def _safe(state: tuple[np.ndarray, ...] | list[np.ndarray], pairs: Pairs, lo: np.ndarray,
          hi: np.ndarray, dec: np.ndarray, jerk: np.ndarray, check: np.ndarray) -> np.ndarray:
    """Pair safety of the ``check``-ed pairs (unchecked ones report True)."""
    ok = np.ones(pairs.succ.size, dtype=bool)
    m = np.flatnonzero(check)
    s, k = pairs.succ[m], pairs.pred[m]
    standard = hi[s] + pairs.gap[m] <= lo[k] + pairs.offset[m] + TOLERANCE
    tcp = pairs.on_tcp(m)
    if tcp.any():  # the gap on the TCP path: the monotone map keeps the argument (D-073)
        t = m[tcp]
        standard[tcp] = hi[pairs.succ[t]] <= pairs.behind(
            t, lo[pairs.pred[t]] + pairs.offset[t]) + TOLERANCE
    ok[m] = standard
    fast = m[pairs.fast[m] & ~standard]
    if fast.size:
        s, k = pairs.succ[fast], pairs.pred[fast]
        p, v, a = state[0], state[1], state[2]
        gap = min_brake_gap(p[k] + pairs.offset[fast], v[k], a[k], dec[k], jerk[k],
                            p[s], v[s], a[s], dec[s], jerk[s])
        ok[fast] = gap >= pairs.gap[fast] - TOLERANCE
    return ok


def min_brake_gap(pk: np.ndarray, vk: np.ndarray, ak: np.ndarray, dk: np.ndarray,
                  jk: np.ndarray, pi: np.ndarray, vi: np.ndarray, ai: np.ndarray,
                  di: np.ndarray, ji: np.ndarray) -> np.ndarray:
    """min over t >= 0 of brake_k(t) - brake_i(t): the closest the two get braking together.

    Both brakes are piecewise cubic; between the merged phase boundaries the difference is
    one cubic whose minimum lies at an end or where its derivative (a quadratic) vanishes.
    """
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
        # derivative of the difference on [t0, t1]: dv + da s + dj s²/2
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


def _at(P: np.ndarray, V: np.ndarray, A: np.ndarray, ends: np.ndarray, jerks: np.ndarray,  # noqa: N803
        t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(p, v, a, jerk of the phase that starts here) of a brake at times ``t`` (N,)."""
    rows = np.arange(P.shape[0])
    phase = (t[:, None] >= ends - 1e-15).sum(axis=1)
    start = np.where(phase == 0, 0.0, ends[rows, np.maximum(phase - 1, 0)])
    tau = np.maximum(t - start, 0.0)
    j = np.where(phase < 3, jerks[rows, np.minimum(phase, 2)], 0.0)
    p0, v0, a0 = P[rows, phase], V[rows, phase], A[rows, phase]
    return (p0 + tau * (v0 + tau * (0.5 * a0 + tau * j / 6.0)),
            v0 + tau * (a0 + 0.5 * tau * j), a0 + tau * j, j)
