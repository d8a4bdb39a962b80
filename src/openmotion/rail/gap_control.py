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
Braking can make further pairs unsafe, so the check repeats until nothing changes; each
round brakes at least one more mover. The pair check and each round's bookkeeping are
compiled loops over the pairs (kernels.py, D-186); the TCP pairs' positions one gap behind
stay numpy. docs/collision-avoidance.md has the safety argument.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from openmotion.rail.braking import brake_envelope
from openmotion.rail.kernels import blame, brake_blamed, min_brake_gaps, pair_safety
from openmotion.rail.tolerances import TOLERANCE as TOLERANCE  # the gap checks (planar, CA)


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
    # FAST pairs safe in the current state, asked only of pairs that are unsafe next
    fast_held = np.zeros(pairs.succ.size, dtype=bool)
    asked = ~pairs.fast
    check = np.ones(pairs.succ.size, dtype=bool)
    while True:
        ok = _safe(nxt, pairs, lo, hi, dec, jerk, check)
        bad = check & ~ok
        if not bad.any():
            return braking, lo, hi
        ask = bad & ~asked
        if ask.any():
            fast_held[ask] = _safe(cur, pairs, lo_cur, hi_cur, dec, jerk, ask)[ask]
            asked |= ask
        blamed, check = blame(bad, pairs.succ, pairs.pred, pairs.fast, pairs.both, fast_held,
                              braking, lo, hi, lo_cur, hi_cur)
        if blamed.size == 0:
            return braking, lo, hi  # only pairs that were unsafe before and do not get worse
        brake_blamed(blamed, cur[0], cur[1], cur[2], dec, jerk, cycle_time, *nxt, lo, hi,
                     braking)


def _safe(state: tuple[np.ndarray, ...] | list[np.ndarray], pairs: Pairs, lo: np.ndarray,
          hi: np.ndarray, dec: np.ndarray, jerk: np.ndarray, check: np.ndarray) -> np.ndarray:
    """Pair safety of the ``check``-ed pairs (unchecked ones report True): one compiled loop
    (kernels.pair_safety, D-186) after the TCP pairs' positions one gap behind."""
    tcp = np.zeros(pairs.succ.size, dtype=bool)
    behind = np.zeros(pairs.succ.size)
    if pairs.y is not None:  # gaps on a TCP path: the monotone map keeps the argument (D-073)
        m = np.flatnonzero(check)
        t = m[pairs.on_tcp(m)]
        if t.size:
            tcp[t] = True
            behind[t] = pairs.behind(t, lo[pairs.pred[t]] + pairs.offset[t])
    return pair_safety(check, pairs.succ, pairs.pred, pairs.offset, pairs.gap, pairs.fast,
                       tcp, behind, state[0], state[1], state[2], lo, hi, dec, jerk)


def min_brake_gap(pk: np.ndarray, vk: np.ndarray, ak: np.ndarray, dk: np.ndarray,
                  jk: np.ndarray, pi: np.ndarray, vi: np.ndarray, ai: np.ndarray,
                  di: np.ndarray, ji: np.ndarray) -> np.ndarray:
    """min over t >= 0 of brake_k(t) - brake_i(t): the closest the two get braking together.

    Both brakes are piecewise cubic; between the merged phase boundaries the difference is
    one cubic whose minimum lies at an end or where its derivative (a quadratic) vanishes.
    One compiled loop over the pairs (kernels.min_brake_gaps, D-186).
    """
    return min_brake_gaps(*(np.ascontiguousarray(x, dtype=float)
                            for x in (pk, vk, ak, dk, jk, pi, vi, ai, di, ji)))
