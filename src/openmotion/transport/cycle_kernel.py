"""A CA group's cycle in one compiled call (numba): proposals, the gap filter, the events.

At the XTS task's 250 us cycle a rail of ten movers has about 20 us for gap control, and a
thousand movers must cost less than a plain ruckig loop over them (D-281). As a sequence of
numpy passes (transport/cycle.py) each of the few dozen questions gap control asks per cycle
is an array operation with its own fixed cost, a microsecond or more; at ten movers those
fixed costs were the whole cycle. ``group_step`` asks them per mover in one compiled pass and
hands back only what needs the Python objects: the movers whose profile ended, the held
movers that finish or replan.

Every expression keeps the operation order of the numpy formulation in transport/cycle.py,
so traces are the same bit for bit (tests/transport/test_cycle_kernel.py runs both on the
same scenarios). The numpy formulation stays the reference and runs the cases this loop
leaves out: gaps on a TCP path (D-073) and coupled movers (MC_GearInPosCA).
"""

from __future__ import annotations

import math

import numpy as np

from openmotion.core.compiled import compiled
from openmotion.rail.kernels import (
    _brake_state,
    _first_step,
    blame,
    brake_blamed,
    envelope,
    pair_safety,
)
from openmotion.rail.tolerances import TOLERANCE
from openmotion.transport.movers import FOLLOW, GEAR, HELD, IDLE
from openmotion.transport.tolerances import FIT_SLACK, REST_SHARE


@compiled
def all_at(mask: np.ndarray, rows: np.ndarray) -> bool:
    """``mask[rows].all()`` without the copy: numpy's reductions cost some microseconds a
    call on short arrays, more than the question."""
    for r in range(rows.shape[0]):  # noqa: SIM110 - numba compiles no generator into all()
        if not mask[rows[r]]:
            return False
    return True


@compiled
def no_command(mode: np.ndarray) -> bool:
    """Every mover IDLE (``not mode.any()``, see ``all_at``)."""
    for i in range(mode.shape[0]):  # noqa: SIM110 - as all_at
        if mode[i] != IDLE:
            return False
    return True


@compiled
def pair_arrays(pred: np.ndarray, gmode: np.ndarray, none: int, fast_mode: int,
                fast_grace: np.ndarray, offset: np.ndarray, gap: np.ndarray) -> tuple:
    """The pairs of a group (GroupCycle._pairs): the successors with a predecessor and gap
    control, their predecessors, offsets, gaps and whether each pair is checked as FAST."""
    succ = np.empty(pred.shape[0], dtype=np.int64)
    count = 0
    for i in range(pred.shape[0]):
        if pred[i] >= 0 and gmode[i] != none:
            succ[count] = i
            count += 1
    succ = succ[:count].copy()
    pred_s, offset_s, gap_s = np.empty(count, dtype=np.int64), np.empty(count), np.empty(count)
    fast = np.empty(count, dtype=np.bool_)
    for m in range(count):
        i = succ[m]
        pred_s[m], offset_s[m], gap_s[m] = pred[i], offset[i], gap[i]
        fast[m] = gmode[i] == fast_mode or fast_grace[i]
    return succ, pred_s, offset_s, gap_s, fast


@compiled
def _maximum(a: float, b: float) -> float:
    """numpy.maximum: nan if either is nan."""
    return a if (a >= b or a != a) else b


@compiled
def _minimum(a: float, b: float) -> float:
    """numpy.minimum: nan if either is nan."""
    return a if (a <= b or a != a) else b


@compiled
def rooms(lo: np.ndarray, hi: np.ndarray, psucc: np.ndarray, ppred: np.ndarray,
          poffset: np.ndarray, pgap: np.ndarray, both: bool) -> tuple[np.ndarray, np.ndarray]:
    """GroupCycle._room for every mover: (room_hi, room_lo), where it may stop given its
    neighbours' brake envelopes (lo, hi)."""
    n = lo.shape[0]
    room_hi, room_lo = np.full(n, np.inf), np.full(n, -np.inf)
    for m in range(psucc.shape[0]):
        room_hi[psucc[m]] = lo[ppred[m]] + poffset[m] - pgap[m]
    if both:
        for m in range(psucc.shape[0]):
            room_lo[ppred[m]] = hi[psucc[m]] + pgap[m] - poffset[m]
    return room_hi, room_lo


@compiled
def _resting(k: int, v: np.ndarray, a: np.ndarray, lim: np.ndarray) -> bool:
    """GroupCycle._resting for one mover."""
    return abs(v[k]) <= REST_SHARE * lim[0, k] and abs(a[k]) <= REST_SHARE * lim[1, k]


@compiled
def _head_on(k: int, p: np.ndarray, mode: np.ndarray, target: np.ndarray,
             gsucc: np.ndarray) -> bool:
    """GroupCycle._head_on for one mover."""
    s = gsucc[k]
    return s >= 0 and mode[s] != IDLE and target[s] > p[s] + TOLERANCE


@compiled
def _can_stop(k: int, forward: bool, goal: float, p: np.ndarray, v: np.ndarray,
              a: np.ndarray, vmax: float, acc: float, dec: float, jerk: float) -> bool:
    """GroupCycle._can_stop for one mover."""
    step = 1.0 if forward else -1.0
    b = step * a[k]
    c_lo, c_hi = envelope(p[k], v[k], a[k], dec, jerk)
    fits = c_hi <= goal + TOLERANCE if forward else c_lo >= goal - TOLERANCE
    fits = fits and (b <= acc * FIT_SLACK) and (b >= -dec * FIT_SLACK)
    u = step * v[k]
    fits = fits and (u >= 0.0) and (u + b * abs(b) / (2.0 * jerk) >= -REST_SHARE * vmax)
    return fits and abs(v[k]) <= vmax * FIT_SLACK


@compiled
def resume(p: np.ndarray, v: np.ndarray, a: np.ndarray, mode: np.ndarray,
           target: np.ndarray, lim: np.ndarray, halting: np.ndarray, bdec: np.ndarray,
           bjerk: np.ndarray, gpred: np.ndarray, gsucc: np.ndarray, lo: np.ndarray,
           hi: np.ndarray, room_hi: np.ndarray, room_lo: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """GroupCycle._resume's decision for the held movers: (finish, replan, goals, limits).

    ``finish``: halting movers now at rest, whose job ends; ``replan``: movers that get a
    profile to ``goals[r]`` again, with the command's limits or, where ``limits[r, 0]`` is not
    nan, with (velocity, acceleration, deceleration, jerk) = ``limits[r]`` (D-210)."""
    n = p.shape[0]
    finish = np.empty(n, dtype=np.int64)
    replan = np.empty(n, dtype=np.int64)
    goals = np.empty(n)
    limits = np.full((n, 4), np.nan)
    nf = nr = 0
    for k in range(n):
        if mode[k] != HELD:
            continue
        tk, pk = target[k], p[k]
        halt = halting[k]
        forward = tk >= pk
        free = (not halt) and room_lo[k] <= tk and tk <= room_hi[k]
        other = gpred[k] if forward else gsucc[k]
        other_rests = other < 0 or _resting(other, v, a, lim)
        if not (halt or free or other_rests):
            continue
        rest = _resting(k, v, a, lim)
        goal = _minimum(_maximum(tk, room_lo[k]), room_hi[k])
        queue = (not halt) and (not free) and other_rests
        queue = queue and not (rest and ((goal - pk) * (tk - pk) <= 0.0
                                         or abs(goal - pk) <= TOLERANCE))
        queue = queue and (hi[k] <= goal + TOLERANCE if forward else lo[k] >= goal - TOLERANCE)
        queue = queue and (forward or not _head_on(k, p, mode, target, gsucc))
        if halt and rest:
            finish[nf] = k
            nf += 1
        if not (free or queue):
            continue
        there = tk if free else goal
        vmax, acc, dec, jerk = lim[0, k], lim[1, k], lim[2, k], lim[3, k]
        if _can_stop(k, forward, there, p, v, a, vmax, acc, dec, jerk):
            replan[nr], goals[nr] = k, there
            nr += 1
            continue
        u, b = (v[k], a[k]) if forward else (-v[k], -a[k])
        hard = queue and ((b < -dec) or (u + b * abs(b) / (2.0 * jerk) < 0.0))
        if hard and _can_stop(k, forward, there, p, v, a, vmax, acc, bdec[k], bjerk[k]):
            replan[nr], goals[nr] = k, there
            limits[nr, 0], limits[nr, 1], limits[nr, 2], limits[nr, 3] = (vmax, acc, bdec[k],
                                                                          bjerk[k])
            nr += 1
    return finish[:nf], replan[:nr], goals[:nr], limits[:nr]


@compiled
def group_step(dt: float, now: float, rows: np.ndarray, set_p: np.ndarray,
               set_v: np.ndarray, set_a: np.ndarray, set_j: np.ndarray, seg_end: np.ndarray,
               p: np.ndarray, v: np.ndarray, a: np.ndarray, mode: np.ndarray,
               goal: np.ndarray, target: np.ndarray, lim: np.ndarray, halting: np.ndarray,
               bdec: np.ndarray, bjerk: np.ndarray, gpred: np.ndarray, gsucc: np.ndarray,
               env_lo: np.ndarray, env_hi: np.ndarray, psucc: np.ndarray,
               ppred: np.ndarray, poffset: np.ndarray, pgap: np.ndarray, pfast: np.ndarray,
               both: bool, fast_grace: np.ndarray, lo: np.ndarray, hi: np.ndarray,
               slots: np.ndarray, goals: np.ndarray) -> tuple[int, int, int, int, bool]:
    """GroupCycle.advance up to its events, for a group without TCP pairs or coupled movers.

    Reads the profiles' setpoints of this cycle from the kernel arrays (``rows``), writes the
    gap-controlled ones back and into (p, v, a), their brake envelope into (lo, hi), and
    changes ``mode`` (held movers) and ``fast_grace`` in place; (env_lo, env_hi) is the
    envelope of the last cycle's (p, v, a). Returns (grace_changed, ended, finish, replan,
    idle): whether a pair left its FAST grace (-1: a coupled mover, nothing done: the numpy
    formulation runs this cycle), counts, and whether no mover has a command. With ``ended``
    > 0, ``slots[:ended]`` are the movers whose profile ended and the held movers are left to
    ``resume`` after them; else ``slots`` holds ``resume``'s ``finish`` and then ``replan``
    movers, ``goals[r]`` the goal and limits of the r-th replan (columns 1-4, nan: the
    command's)."""
    n = rows.shape[0]
    for i in range(n):
        if mode[i] == GEAR:
            return -1, 0, 0, 0, False
    nxt_p, nxt_v, nxt_a, nxt_j = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        r = rows[i]
        nxt_p[i], nxt_v[i], nxt_a[i], nxt_j[i] = set_p[r], set_v[r], set_a[r], set_j[r]
    known = np.zeros(n, dtype=np.bool_)
    room_hi, room_lo = rooms(env_lo, env_hi, psucc, ppred, poffset, pgap, both)
    for i in range(n):  # _leave_stale_queues (D-210)
        g = goal[i]
        if mode[i] == FOLLOW and not halting[i] and math.isfinite(g) and g != target[i]:
            grown = room_hi[i] > g + TOLERANCE if target[i] >= g else room_lo[i] < g - TOLERANCE
            if grown:
                mode[i] = HELD
    pair_of = np.full(n, -1, dtype=np.int64)
    for m in range(psucc.shape[0]):
        pair_of[psucc[m]] = m
    out, env = np.empty((4, n)), np.empty((2, n))
    ahead, times = np.empty(6), np.empty(7)
    for i in range(n):
        if mode[i] == IDLE:  # no command: the mover rests where it is
            nxt_p[i], nxt_v[i], nxt_a[i], nxt_j[i] = p[i], 0.0, 0.0, 0.0
            known[i], lo[i], hi[i] = True, p[i], p[i]
            continue
        if mode[i] != HELD:
            continue
        pk, tk = p[i], target[i]
        forward = tk >= pk
        if v[i] == 0.0 and a[i] == 0.0 and not halting[i]:  # _waiting
            room = room_hi[i] - pk if forward else pk - room_lo[i]
            if room <= TOLERANCE or (not forward and _head_on(i, p, mode, target, gsucc)):
                nxt_p[i], nxt_v[i], nxt_a[i], nxt_j[i] = pk, 0.0, 0.0, 0.0
                known[i], lo[i], hi[i] = True, pk, pk
                continue
        # _track: the first fitting constant-jerk step, else a brake
        vmax, acc, dec, jm = lim[0, i], lim[1, i], lim[2, i], lim[3, i]
        s = 1.0 if forward else -1.0
        r_hi = _maximum(room_hi[i], env_hi[i])
        r_lo = _minimum(room_lo[i], env_lo[i])
        fitted = False
        if not halting[i]:
            ahead[:] = np.nan
            m = pair_of[i]
            if m >= 0 and s > 0.0 and pfast[m]:  # _ahead (D-211)
                k = ppred[m]
                bp, bv, ba, _ = _brake_state(p[k] + poffset[m], v[k], a[k], bdec[k], bjerk[k],
                                             dt)
                ahead[0], ahead[1], ahead[2] = bp, bv, ba
                ahead[3], ahead[4], ahead[5] = bdec[k], bjerk[k], pgap[m]
            fitted = _first_step(i, dt, p, v, a, s, tk, vmax, acc, dec, jm, bdec[i], bjerk[i],
                                 r_lo, r_hi, ahead, times, out, env)
            if not fitted:
                u, b = s * v[i], s * a[i]
                if b < -dec or u + b * abs(b) / (2.0 * jm) < 0.0:
                    fitted = _first_step(i, dt, p, v, a, s, tk, vmax, acc, bdec[i], bjerk[i],
                                         bdec[i], bjerk[i], r_lo, r_hi, ahead, times, out,
                                         env)
        if fitted:
            known[i], lo[i], hi[i] = True, env[0, i], env[1, i]
        else:  # the command's brake, or the hardest one where that cannot take it back
            u, b = s * v[i], s * a[i]
            hard = (b < -dec) or (u + b * abs(b) / (2.0 * jm) < 0.0)
            out[0, i], out[1, i], out[2, i], out[3, i] = _brake_state(
                p[i], v[i], a[i], bdec[i] if hard else dec, bjerk[i] if hard else jm, dt)
        if abs(out[1, i]) <= REST_SHARE * vmax and abs(out[2, i]) <= REST_SHARE * acc:
            out[1, i], out[2, i], out[3, i] = 0.0, 0.0, 0.0  # float residue: rest
            known[i] = False
        nxt_p[i], nxt_v[i], nxt_a[i], nxt_j[i] = out[0, i], out[1, i], out[2, i], out[3, i]
    # the gap filter (gap_control.filter_steps)
    for i in range(n):
        if not known[i]:
            lo[i], hi[i] = envelope(nxt_p[i], nxt_v[i], nxt_a[i], bdec[i], bjerk[i])
    braking = np.zeros(n, dtype=np.bool_)
    npairs = psucc.shape[0]
    if npairs:
        tcp, behind = np.zeros(npairs, dtype=np.bool_), np.zeros(npairs)
        fast_held = np.zeros(npairs, dtype=np.bool_)
        asked = ~pfast
        check = np.ones(npairs, dtype=np.bool_)
        while True:
            ok = pair_safety(check, psucc, ppred, poffset, pgap, pfast, tcp, behind, nxt_p,
                             nxt_v, nxt_a, lo, hi, bdec, bjerk)
            bad = check & ~ok
            if not bad.any():
                break
            ask = bad & ~asked
            if ask.any():
                held_ok = pair_safety(ask, psucc, ppred, poffset, pgap, pfast, tcp, behind, p,
                                      v, a, env_lo, env_hi, bdec, bjerk)
                for m in range(npairs):
                    if ask[m]:
                        fast_held[m] = held_ok[m]
                        asked[m] = True
            blamed, check = blame(bad, psucc, ppred, pfast, both, fast_held, braking, lo, hi,
                                  env_lo, env_hi)
            if blamed.shape[0] == 0:
                break
            brake_blamed(blamed, p, v, a, bdec, bjerk, dt, nxt_p, nxt_v, nxt_a, nxt_j, lo, hi,
                         braking)
    for i in range(n):
        r = rows[i]
        set_p[r], set_v[r], set_a[r], set_j[r] = nxt_p[i], nxt_v[i], nxt_a[i], nxt_j[i]
    grace_changed = 0
    if fast_grace.any():  # _end_fast_grace (D-106)
        for m in range(npairs):
            s_, k_ = psucc[m], ppred[m]
            if fast_grace[s_] and hi[s_] + pgap[m] <= lo[k_] + poffset[m] + TOLERANCE:
                fast_grace[s_] = False
                grace_changed = 1
        for i in range(n):
            if gpred[i] < 0:
                fast_grace[i] = False
    ended = 0
    for i in range(n):
        p[i], v[i], a[i] = nxt_p[i], nxt_v[i], nxt_a[i]
        if braking[i] and mode[i] == FOLLOW:
            mode[i] = HELD
        elif mode[i] == FOLLOW and seg_end[rows[i]] <= now:
            slots[ended] = i
            ended += 1
    if ended:
        return grace_changed, ended, 0, 0, False
    # the events need no Python object: decide for the held movers now
    r_hi, r_lo = rooms(lo, hi, psucc, ppred, poffset, pgap, both)
    finish, replan, there, limits = resume(p, v, a, mode, target, lim, halting, bdec, bjerk,
                                           gpred, gsucc, lo, hi, r_hi, r_lo)
    nf, nr = finish.shape[0], replan.shape[0]
    slots[:nf] = finish
    slots[nf:nf + nr] = replan
    goals[:nr, 0] = there
    goals[:nr, 1:] = limits
    return grace_changed, 0, nf, nr, no_command(mode)
