"""Compiled loops of the traffic's cycle (numba): what every cycle asks of every rider.

Every cycle asks the same few questions of every rider on a track: what it proposes to do,
where it may stop given its neighbours' brakes, who is ahead of it and behind it, what a held
rider does next, whether the gap filter lets it, whether it holds or may enter a switch zone,
and where its setpoints lie. As numpy passes each question was a dozen array operations on a
hundred numbers, and their call overhead, not the arithmetic, set the cycle time
(docs/benchmarks.md, tracks). These loops do the arithmetic per rider in one pass, with the
same formulas in the same order as the numpy formulation each replaced in traffic.py (its
docstring names it), so the results are the same bit for bit: numpy's NaN rules of
``minimum``/``maximum``/``clip`` and Python's ``max``/``min`` are kept where the old code
had them (tests/planar/test_track_kernels.py compares them). Planning and the rider objects
stay in traffic.py (D-143). Each loop loads (or compiles) when a cycle first needs it;
``warm`` loads every loop with the cycle's argument types (D-157).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from openmotion.core.compiled import compiled, true_indices
from openmotion.planar.tolerances import (
    LIMIT_PRECISION,
    TRACK_END_PRECISION,
    TRACKING_REST_PRECISION,
)
from openmotion.planar.track_atlas import frames_on
from openmotion.rail.gap_control import TOLERANCE
from openmotion.rail.kernels import brake_states, candidates, envelope

_SLACK = 1 + LIMIT_PRECISION  #: relative float slack of the limit checks of a held rider

Floats = NDArray[np.float64]
Ints = NDArray[np.int64]
Bools = NDArray[np.bool_]


@compiled
def _minimum(a: float, b: float) -> float:
    """numpy.minimum of two floats (NaN wins)."""
    return a if (a <= b or math.isnan(a)) else b


@compiled
def _maximum(a: float, b: float) -> float:
    """numpy.maximum of two floats (NaN wins)."""
    return a if (a >= b or math.isnan(a)) else b


@compiled
def rooms(n: int, succ: Ints, pred: Ints, offset: Floats, gap: Floats, lo: Floats,
          hi: Floats, stopped: Ints, low: Floats, high: Floats) -> tuple[Floats, Floats]:
    """``RiderPairs.room``: where each of ``n`` riders may stop given its neighbours' brake
    envelopes (lo, hi): behind its predecessor's low end less the gap, ahead of its
    successor's high end plus the gap, and within the stop lines (low, high) of the riders
    ``stopped`` (kept out of a switch zone)."""
    room_lo, room_hi = np.full(n, -np.inf), np.full(n, np.inf)
    for m in range(succ.size):
        s, k = succ[m], pred[m]
        room_hi[s] = _minimum(room_hi[s], lo[k] + offset[m] - gap[m])
        room_lo[k] = _maximum(room_lo[k], hi[s] + gap[m] - offset[m])
    for i in range(stopped.size):  # Python's max and min: the first unless the second wins
        k = stopped[i]
        if low[i] > room_lo[k]:
            room_lo[k] = low[i]
        if high[i] < room_hi[k]:
            room_hi[k] = high[i]
    return room_lo, room_hi


@compiled
def extensions(queued: Ints, target: Floats, goal: Floats, room_lo: Floats, room_hi: Floats,
               ahead: Ints, v: Floats, a: Floats, mode: Ints, held: int, extend: float
               ) -> tuple[Floats, Bools]:
    """``Traffic._extend_queued`` for the riders ``queued`` (following a profile that ends
    short of their target): how far each may go now (``reach``: the target, or the end of its room)
    and whether it gets a profile to there: the way to the target is free, or the room grew
    by more than ``extend`` with the rider ahead standing. One whose room grew while the
    rider ahead drives on becomes ``held`` (its tracking step follows that rider)."""
    reach = np.empty(queued.size)
    grow = np.zeros(queued.size, dtype=np.bool_)
    for i in range(queued.size):
        k = queued[i]
        t, g = target[k], goal[k]
        forward = t >= g
        r = _minimum(t, room_hi[k]) if forward else _maximum(t, room_lo[k])
        further = (r - g) * (1.0 if forward else -1.0)
        free = further > 0.0 and r == t
        front = ahead[k]
        rests = front < 0 or (v[front] == 0.0 and a[front] == 0.0)
        grow[i] = free or (further > extend and rests)
        if not free and further > extend and not grow[i]:
            mode[k] = held
        reach[i] = r
    return reach, grow


@compiled
def neighbours(n: int, succ: Ints, pred: Ints) -> tuple[Ints, Ints]:
    """The rider ahead of and behind each rider on its path (-1: none); of several pairs
    the last one counts, as numpy's fancy assignment has it."""
    ahead, behind = np.full(n, -1, dtype=np.int64), np.full(n, -1, dtype=np.int64)
    for m in range(succ.size):
        ahead[succ[m]] = pred[m]
        behind[pred[m]] = succ[m]
    return ahead, behind


@compiled
def held_plans(held: Ints, p: Floats, v: Floats, a: Floats, target: Floats, limits: Floats,
               room_lo: Floats, room_hi: Floats, mode: Ints, idle: int, ahead: Ints,
               behind: Ints, nxt_p: Floats, nxt_v: Floats, nxt_a: Floats, nxt_j: Floats,
               known: Bools, known_lo: Floats, known_hi: Floats
               ) -> tuple[Floats, Floats, Bools, Bools]:
    """First half of ``Traffic._track_held``: the direction of each held rider to its target
    (``sign``), the goal (the target, or the end of the room), the riders that wait (at
    rest in a queue, or head on: their step is standing, written into ``nxt`` and
    ``known``), those that ``fit`` a fresh profile (the command's dynamics take the state
    over without turning round and stop before the goal, and the way is free or the rider
    ahead stands) and the ``rest`` (a tracking step)."""
    count = held.size
    sign, goal = np.empty(count), np.empty(count)
    fits, rest = np.zeros(count, dtype=np.bool_), np.zeros(count, dtype=np.bool_)
    for i in range(count):
        k = held[i]
        pk, vk, ak, tk = p[k], v[k], a[k], target[k]
        vmax, acc, dec, jerk = limits[0, k], limits[1, k], limits[2, k], limits[3, k]
        s = 1.0 if tk >= pk else -1.0
        g = _minimum(tk, room_hi[k]) if s > 0 else _maximum(tk, room_lo[k])
        sign[i], goal[i] = s, g
        at_rest = (vk == 0.0) and (ak == 0.0)
        waiting = at_rest and ((g - pk) * s <= TOLERANCE)  # in a queue
        if at_rest and s < 0 and not waiting:  # head on: the rider behind wants forwards
            r = behind[k]
            waiting = r >= 0 and mode[r] != idle and target[r] > p[r] + TOLERANCE
        if waiting:
            nxt_p[k], nxt_v[k], nxt_a[k], nxt_j[k] = pk, 0.0, 0.0, 0.0
            known[k], known_lo[k], known_hi[k] = True, pk, pk
            continue
        u, b = s * vk, s * ak
        gentle = (b <= acc * _SLACK and b >= -dec * _SLACK and u >= 0.0
                  and u + b * abs(b) / (2.0 * jerk) >= -TRACKING_REST_PRECISION * vmax
                  and abs(vk) <= vmax * _SLACK)
        settled = g == tk
        if not settled:
            front = ahead[k]
            settled = front < 0 or (v[front] == 0.0 and a[front] == 0.0)
        fit = gentle and settled
        if fit:
            c_lo, c_hi = envelope(pk, vk, ak, dec, jerk)
            fit = c_hi <= g + TOLERANCE if s > 0 else c_lo >= g - TOLERANCE
        fits[i], rest[i] = fit, not fit
    return sign, goal, fits, rest


@compiled
def held_steps(held: Ints, sign: Floats, rest: Bools, cycle_time: float, p: Floats,
               v: Floats, a: Floats, target: Floats, limits: Floats,
               brake_deceleration: Floats, brake_jerk: Floats, room_lo: Floats,
               room_hi: Floats, lo: Floats, hi: Floats, nxt_p: Floats, nxt_v: Floats,
               nxt_a: Floats, nxt_j: Floats, known: Bools, known_lo: Floats, known_hi: Floats
               ) -> None:
    """Second half of ``Traffic._track_held``: the ``rest`` of the held riders take the most
    progressive constant-jerk step that keeps their brake in their room (``candidates``,
    the room widened to their own envelope), else a brake: the command's, or gap control's
    where that brakes harder than the command's takes back without turning round. Float
    residue of the steps (|v| ~ 1e-17) is rest: snapped, their envelope left to the filter."""
    n = p.size
    signs = np.ones(n)
    for i in range(held.size):
        signs[held[i]] = sign[i]
    rows = np.empty(held.size, dtype=np.int64)  # held[rest]
    count = 0
    for i in range(held.size):
        if rest[i]:
            rows[count] = held[i]
            count += 1
    rows = rows[:count]
    wide_lo, wide_hi = np.empty(n), np.empty(n)
    for k in range(n):
        wide_lo[k], wide_hi[k] = _minimum(room_lo[k], lo[k]), _maximum(room_hi[k], hi[k])
    out, env = np.empty((4, n)), np.empty((2, n))
    fitted = candidates(rows, cycle_time, p, v, a, signs, target, limits[0], limits[1],
                        limits[2], limits[3], brake_deceleration, brake_jerk, wide_lo,
                        wide_hi, out, env)
    lost = np.empty(rows.size, dtype=np.int64)  # rows[~fitted]
    count = 0
    for i in range(rows.size):
        k = rows[i]
        if fitted[i]:
            nxt_p[k], nxt_v[k], nxt_a[k], nxt_j[k] = out[0, k], out[1, k], out[2, k], out[3, k]
            known[k], known_lo[k], known_hi[k] = True, env[0, k], env[1, k]
        else:
            lost[count] = k
            count += 1
    lost = lost[:count]
    if lost.size:
        lp, lv, la = np.empty(lost.size), np.empty(lost.size), np.empty(lost.size)
        dec, jerk = np.empty(lost.size), np.empty(lost.size)
        for i in range(lost.size):
            k = lost[i]
            lp[i], lv[i], la[i] = p[k], v[k], a[k]
            u, b = signs[k] * v[k], signs[k] * a[k]
            d, j = limits[2, k], limits[3, k]
            hard = (b < -d) or (u + b * abs(b) / (2.0 * j) < 0.0)
            dec[i], jerk[i] = (brake_deceleration[k], brake_jerk[k]) if hard else (d, j)
        step = brake_states(lp, lv, la, dec, jerk, cycle_time)
        for i in range(lost.size):
            k = lost[i]
            nxt_p[k], nxt_v[k], nxt_a[k], nxt_j[k] = step[0][i], step[1][i], step[2][i], step[3][i]
    for k in rows:
        if abs(nxt_v[k]) <= TRACKING_REST_PRECISION * limits[0, k] and \
                abs(nxt_a[k]) <= TRACKING_REST_PRECISION * limits[1, k]:
            nxt_v[k], nxt_a[k], nxt_j[k] = 0.0, 0.0, 0.0
            known[k] = False


@compiled
def _bounds(x: Floats) -> tuple[float, float]:
    """``x.min(), x.max()`` of a non-empty array, NaN where x holds one (as numpy's)."""
    low = high = x[0]
    for k in range(1, x.size):
        if math.isnan(x[k]):
            return x[k], x[k]
        if x[k] < low:
            low = x[k]
        if x[k] > high:
            high = x[k]
    return low, high


@compiled
def touching(ax: Floats, ay: Floats, ca: Floats, sa: Floats, ahx: float, ahy: float,
             bx: Floats, by: Floats, cb: Floats, sb: Floats, bhx: float, bhy: float,
             reach: float) -> Bools:
    """For each footprint of a (centre x, y, cos and sin of its turn, half sides): whether it
    overlaps any footprint of b (separating axes; touching is apart). ``reach``: the sum of
    the two half diagonals, within which centres are near enough to check."""
    out = np.zeros(ax.size, dtype=np.bool_)
    if not bx.size:
        return out
    # a centre farther than ``reach`` plus 1 mm outside b's box is far from all of b (the
    # margin dwarfs the rounding of the differences); a difference of at least ``reach``
    # along x or y has a hypot of at least ``reach``: both skip only pairs that are far
    margin = reach + 1.0
    x_lo, x_hi = _bounds(bx)
    y_lo, y_hi = _bounds(by)
    x_lo, x_hi, y_lo, y_hi = x_lo - margin, x_hi + margin, y_lo - margin, y_hi + margin
    for i in range(ax.size):
        if ax[i] < x_lo or ax[i] > x_hi or ay[i] < y_lo or ay[i] > y_hi:
            continue
        for j in range(bx.size):
            dx, dy = bx[j] - ax[i], by[j] - ay[i]
            if abs(dx) >= reach or abs(dy) >= reach or not math.hypot(dx, dy) < reach:
                continue
            cai, sai, cbj, sbj = ca[i], sa[i], cb[j], sb[j]
            overlap = True
            for axis in range(4):
                if axis == 0:
                    nx, ny = cai, sai
                elif axis == 1:
                    nx, ny = -sai, cai
                elif axis == 2:
                    nx, ny = cbj, sbj
                else:
                    nx, ny = -sbj, cbj
                span = (ahx * abs(cai * nx + sai * ny) + ahy * abs(-sai * nx + cai * ny)
                        + bhx * abs(cbj * nx + sbj * ny) + bhy * abs(-sbj * nx + cbj * ny))
                if not abs(dx * nx + dy * ny) < span:
                    overlap = False
                    break
            if overlap:
                out[i] = True
                break
    return out


@compiled
def write_setpoints(mode: Ints, idle: int, p: Floats, v: Floats, a: Floats, base: Floats,
                    rested: Bools, track: Ints, x_rows: Ints, y_rows: Ints, c_rows: Ints,
                    oriented: Bools, c_deg: Floats, p_all: Floats, v_all: Floats,
                    a_all: Floats, j_all: Floats, tables: tuple) -> Ints:
    """``Traffic._write``: x, y (and c where it follows the track) of every rider that moves,
    or came to rest this cycle, from its track's curve (``track_atlas.frames_on``) into the
    setpoint rows, with the velocities and accelerations along the curve (the normal one
    v²κ included). A rider that stays at rest holds its rows in the table (``rested``).
    Returns the riders that came to rest (their rows are held from now on)."""
    n = p.size
    count, fresh_count = 0, 0
    write, fresh = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    for k in range(n):
        if mode[k] == idle:
            continue
        still = v[k] == 0.0 and a[k] == 0.0
        if still and not rested[k]:  # came to rest: write once, then hold in the table
            fresh[fresh_count] = k
            fresh_count += 1
        if not still:
            rested[k] = False
        if not (still and rested[k]):
            write[count] = k
            count += 1
    k_all = write[:count]
    s = np.empty(count)
    ids = np.empty(count, dtype=np.int64)
    for i in range(count):
        k = k_all[i]
        s[i], ids[i] = p[k] - base[k], track[k]
    frame = frames_on(ids, s, True, tables)
    for i in range(count):
        k = k_all[i]
        vk, ak, heading, curvature = v[k], a[k], frame[2, i], frame[3, i]
        cos, sin = math.cos(heading), math.sin(heading)
        normal = curvature * vk * vk
        rx, ry = x_rows[k], y_rows[k]
        p_all[rx], p_all[ry] = frame[0, i], frame[1, i]
        v_all[rx], v_all[ry] = cos * vk, sin * vk
        a_all[rx] = cos * ak - sin * normal
        a_all[ry] = sin * ak + cos * normal
        j_all[rx] = j_all[ry] = 0.0
        if oriented[k]:
            c = c_deg[k]
            c = c + ((math.degrees(heading) - c + 180.0) % 360.0 - 180.0)
            c_deg[k] = c
            rc = c_rows[k]
            p_all[rc] = c
            v_all[rc] = math.degrees(curvature * vk)
            a_all[rc] = math.degrees(curvature * ak)
            j_all[rc] = 0.0
    return fresh[:fresh_count]


@compiled
def gap_filter(p: Floats, v: Floats, a: Floats, lo_cur: Floats, hi_cur: Floats,
               nxt_p: Floats, nxt_v: Floats, nxt_a: Floats, nxt_j: Floats, cycle_time: float,
               dec: Floats, jerk: Floats, succ: Ints, pred: Ints, offset: Floats, gap: Floats,
               known: Bools, known_lo: Floats, known_hi: Floats
               ) -> tuple[Bools, Floats, Floats]:
    """``transport.gap_control.filter_steps`` for the traffic's pairs (STANDARD, both
    neighbours blamable, no TCP path): replaces unsafe proposals in ``nxt`` by the brake
    step from the state of the last cycle (p, v, a with its envelope lo_cur, hi_cur), round
    by round as the filter does, until no pair that got worse is left. ``known``: the
    proposals whose envelope (known_lo, known_hi) the caller computed. Returns the riders
    that brake and the envelopes of ``nxt``."""
    n = p.size
    braking = np.zeros(n, dtype=np.bool_)
    lo, hi = known_lo.copy(), known_hi.copy()
    for k in range(n):
        if not known[k]:
            lo[k], hi[k] = envelope(nxt_p[k], nxt_v[k], nxt_a[k], dec[k], jerk[k])
    if succ.size == 0:
        return braking, lo, hi
    check = np.ones(succ.size, dtype=np.bool_)
    while True:
        bad = False
        flag = np.zeros(n, dtype=np.bool_)
        for m in range(succ.size):
            s, k = succ[m], pred[m]
            if not check[m] or hi[s] + gap[m] <= lo[k] + offset[m] + TOLERANCE:
                continue
            bad = True
            if hi[s] > hi_cur[s] + TOLERANCE and not braking[s]:  # the follower claims room
                flag[s] = True
            if lo[k] < lo_cur[k] - TOLERANCE and not braking[k]:  # the leader comes back
                flag[k] = True
        if not bad:
            return braking, lo, hi
        blamed = true_indices(flag)
        count = blamed.size
        if count == 0:
            return braking, lo, hi  # only pairs that were unsafe before and do not get worse
        bp, bv, ba = np.empty(count), np.empty(count), np.empty(count)
        blamed_deceleration, blamed_jerk = np.empty(count), np.empty(count)
        for i in range(count):
            k = blamed[i]
            bp[i], bv[i], ba[i] = p[k], v[k], a[k]
            blamed_deceleration[i], blamed_jerk[i] = dec[k], jerk[k]
        step = brake_states(bp, bv, ba, blamed_deceleration, blamed_jerk, cycle_time)
        for i in range(blamed.size):
            k = blamed[i]
            braking[k] = True
            nxt_p[k], nxt_v[k], nxt_a[k], nxt_j[k] = step[0][i], step[1][i], step[2][i], step[3][i]
            lo[k], hi[k] = envelope(nxt_p[k], nxt_v[k], nxt_a[k], dec[k], jerk[k])
        for m in range(succ.size):
            check[m] = flag[succ[m]] or flag[pred[m]]


@compiled
def zone_holders(base: Floats, length: Floats, start_range: Floats, end_range: Floats,
                 zone_gap: Floats, start_switch: Ints, end_switch: Ints, lo: Floats, hi: Floats
                 ) -> tuple[Floats, Floats, Bools, Bools, Ints, Bools, Ints]:
    """``SwitchZones.holding`` before the conflicts: each rider's zone boundaries (the odometer
    of the end zone's start and of the start zone's end: max(collision range, zone gap) from
    the switch), whether its envelope (lo, hi) reaches into the zone at its track's end and
    at its start (or the zone covers the track), and the holders: rider, at the end (else
    the start), switch id; the end zones first."""
    n = base.size
    end_line, start_line = np.empty(n), np.empty(n)
    in_end, in_start = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
    for k in range(n):
        end_line[k] = base[k] + length[k] - _maximum(end_range[k], zone_gap[k])
        start_line[k] = base[k] + _maximum(start_range[k], zone_gap[k])
        in_end[k] = end_switch[k] >= 0 and (hi[k] > end_line[k] + TOLERANCE
                                            or end_line[k] <= base[k] + TOLERANCE)
        in_start[k] = start_switch[k] >= 0 and (
            lo[k] < start_line[k] - TOLERANCE
            or start_line[k] >= base[k] + length[k] - TOLERANCE)
    k_out, end, switch = _sides(in_end, in_start, start_switch, end_switch)
    return end_line, start_line, in_end, in_start, k_out, end, switch


@compiled
def _sides(at_end: Bools, at_start: Bools, start_switch: Ints, end_switch: Ints
           ) -> tuple[Ints, Bools, Ints]:
    """The riders of ``at_end`` then those of ``at_start`` (each in rider order), whether
    each is at its track's end, and the switch id there."""
    ends, starts = 0, 0
    for k in range(at_end.size):
        ends += 1 if at_end[k] else 0
        starts += 1 if at_start[k] else 0
    k_out = np.empty(ends + starts, dtype=np.int64)
    end = np.zeros(ends + starts, dtype=np.bool_)
    switch = np.empty(ends + starts, dtype=np.int64)
    i, j = 0, ends
    for k in range(at_end.size):
        if at_end[k]:
            k_out[i], end[i], switch[i] = k, True, end_switch[k]
            i += 1
        if at_start[k]:
            k_out[j], switch[j] = k, start_switch[k]
            j += 1
    return k_out, end, switch


@compiled
def zone_entries(start_switch: Ints, end_switch: Ints, in_end: Bools, in_start: Bools,
                 end_line: Floats, start_line: Floats, lo: Floats, hi: Floats, lookahead: float
                 ) -> tuple[Ints, Bools, Ints, Floats, Floats, Bools]:
    """``SwitchZones.keep_out``: the riders near a zone they are not in (their envelope (lo,
    hi) within ``lookahead`` of it), as ``_sides`` lists them, with the odometer bounds that
    keep them out (low, high) and whether their envelope passes them (``wanting`` in)."""
    n = start_switch.size
    near_end, near_start = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
    for k in range(n):
        near_end[k] = end_switch[k] >= 0 and not in_end[k] and hi[k] > end_line[k] - lookahead
        near_start[k] = start_switch[k] >= 0 and not in_start[k] and \
            lo[k] < start_line[k] + lookahead
    k_out, end, switch = _sides(near_end, near_start, start_switch, end_switch)
    low, high = np.empty(k_out.size), np.empty(k_out.size)
    wanting = np.empty(k_out.size, dtype=np.bool_)
    for i in range(k_out.size):
        k = k_out[i]
        low[i] = -np.inf if end[i] else start_line[k]
        high[i] = end_line[k] if end[i] else np.inf
        wanting[i] = hi[k] > high[i] + TOLERANCE or lo[k] < low[i] - TOLERANCE
    return k_out, end, switch, low, high, wanting


@compiled
def going_back(v: Floats, a: Floats, jerk: Floats) -> Bools:
    """Per rider: moving back, or in a state that even the rider's own brake
    (``jerk``) turns round (a forward motion braked harder than it needs to stop)."""
    out = np.empty(v.size, dtype=np.bool_)
    for k in range(v.size):
        release = v[k] + a[k] * abs(a[k]) / (2.0 * jerk[k])
        out[k] = v[k] < 0.0 or release < -TOLERANCE
    return out


@compiled
def pair_gaps(succ: Ints, pred: Ints, mode: Ints, idle: int, target: Floats, p: Floats,
              going: Bools, gap: Floats) -> Floats:
    """``Traffic._pair_gaps``: the gap of each pair, the follower's, or the larger of the
    two where the leader goes back (a target behind it, or ``going``)."""
    out = np.empty(succ.size)
    for m in range(succ.size):
        k = pred[m]
        back = mode[k] != idle and (target[k] < p[k] or going[k])
        out[m] = _maximum(gap[succ[m]], gap[k]) if back else gap[succ[m]]
    return out


@compiled
def proposals(mode: Ints, follow: int, idle: int, rows: Ints, p: Floats, v: Floats,
              a: Floats, jerk: Floats, goal: Floats, target: Floats, p_all: Floats,
              v_all: Floats, a_all: Floats, j_all: Floats
              ) -> tuple[Floats, Floats, Floats, Floats, Bools, Floats, Floats, Bools, Ints]:
    """The start of ``Traffic.advance``: the next state of each rider as far as it is known
    now (a following rider's from the setpoint table, an idle one stays, the others are
    filled in later), the envelopes known already (idle riders': where they stand),
    ``going_back`` of the current states and the following riders whose profile ends
    elsewhere than their target (``queued``: they may extend it)."""
    n = p.size
    nxt_p, nxt_v, nxt_a, nxt_j = p.copy(), np.zeros(n), np.zeros(n), np.zeros(n)
    known, known_lo, known_hi = np.zeros(n, dtype=np.bool_), np.empty(n), np.empty(n)
    queued = np.empty(n, dtype=np.int64)
    count = 0
    for k in range(n):
        if mode[k] == follow:
            r = rows[k]
            nxt_p[k], nxt_v[k], nxt_a[k], nxt_j[k] = p_all[r], v_all[r], a_all[r], j_all[r]
            if goal[k] != target[k]:
                queued[count] = k
                count += 1
        elif mode[k] == idle:
            known[k], known_lo[k], known_hi[k] = True, p[k], p[k]
    return (nxt_p, nxt_v, nxt_a, nxt_j, known, known_lo, known_hi, going_back(v, a, jerk),
            queued[:count])


@compiled
def _linspace(out: Floats, start: float, stop: float) -> None:
    """numpy.linspace(start, stop, out.size) into ``out``, with numpy's arithmetic."""
    num = out.size
    div = num - 1
    delta = stop - start
    if div > 0:
        step = delta / div
        for i in range(num):
            out[i] = ((i / div) * delta if step == 0 else i * step) + start
        out[num - 1] = stop
    else:
        for i in range(num):
            out[i] = i * delta + start


@compiled
def stretch_samples(low: float, high: float, start: float, end: float, step: float,
                    count: int, own: int, lows: Floats, highs: Floats, sizes: Ints
                    ) -> tuple[Floats, Ints]:
    """The odometer positions ``SwitchZones.clear_stretch`` samples: a rider's envelope [low,
    high] in ``own`` samples, ``count`` steps ahead of it (up to ``end``) and behind it (down
    to ``start``), then each other rider's envelope [lows, highs] in its ``sizes`` samples
    (numpy.linspace each). Returns them and where each rider's begin (and the last end)."""
    at = np.empty(lows.size + 2, dtype=np.int64)
    at[0], at[1] = 0, own + 2 * count
    for j in range(lows.size):
        at[j + 2] = at[j + 1] + sizes[j]
    q = np.empty(at[-1])
    _linspace(q[:own], low, high)
    for i in range(count):
        q[own + i] = _minimum(high + step * (i + 1), end)
        q[own + count + i] = _maximum(low - step * (i + 1), start)
    for j in range(lows.size):
        _linspace(q[at[j + 1]:at[j + 2]], lows[j], highs[j])
    return q, at


@compiled
def stretch_hits(x: Floats, y: Floats, cos: Floats, sin: Floats, at: Ints, hx: Floats,
                 hy: Floats, radius: Floats, own: int, count: int) -> tuple[bool, int, int]:
    """Of ``SwitchZones.clear_stretch``'s samples (x, y, cos and sin of the turn; rider r's
    from ``at[r]`` to ``at[r + 1]``, half sides hx, hy, half diagonal ``radius``): whether a
    footprint on the envelope (the first ``own``) meets another rider's anywhere, and the
    first step ahead and behind (of ``count``) that does (``count``: none)."""
    a = at[1]
    hit = np.zeros(a, dtype=np.bool_)
    for j in range(1, at.size - 1):
        b0, b1 = at[j], at[j + 1]
        found = touching(x[:a], y[:a], cos[:a], sin[:a], hx[0], hy[0], x[b0:b1], y[b0:b1],
                         cos[b0:b1], sin[b0:b1], hx[j], hy[j], radius[0] + radius[j])
        for i in range(a):
            hit[i] = hit[i] or found[i]
    on_envelope = False
    for i in range(own):
        on_envelope = on_envelope or hit[i]
    first_ahead, first_behind = count, count
    for i in range(count - 1, -1, -1):
        if hit[own + i]:
            first_ahead = i
        if hit[own + count + i]:
            first_behind = i
    return on_envelope, first_ahead, first_behind


@compiled
def group_by_track(index: Ints) -> tuple[Ints, Ints, Ints]:
    """Riders grouped by their tracks (``index``: each rider's track index): each rider's
    place (its track's, in the order first met), the riders by place (in rider order within
    a place) and where each place's riders end in that."""
    n = index.size
    top = index[0] if n else -1  # index.max()
    for k in range(1, n):
        if index[k] > top:
            top = index[k]
    place_of = np.full(top + 1, -1, dtype=np.int64)
    place = np.empty(n, dtype=np.int64)
    count = 0
    for k in range(n):
        if place_of[index[k]] < 0:
            place_of[index[k]] = count
            count += 1
        place[k] = place_of[index[k]]
    sizes = np.zeros(count, dtype=np.int64)
    for k in range(n):
        sizes[place[k]] += 1
    tails, fill = np.empty(count, dtype=np.int64), np.empty(count, dtype=np.int64)
    total = 0
    for g in range(count):  # tails: the running sum of the sizes; fill: where each begins
        fill[g] = total
        total += sizes[g]
        tails[g] = total
    ranked = np.empty(n, dtype=np.int64)
    for k in range(n):
        ranked[fill[place[k]]] = k
        fill[place[k]] += 1
    return place, ranked, tails


@compiled
def in_order(s: Floats, grouped: Ints, tails: Ints) -> Ints:
    """The riders of each group (``grouped``, a group ending at each of ``tails``) by arc
    length ``s``, stable: numpy.lexsort((s, place)) of the riders. A group is sorted by
    insertion, numpy's float order (NaN last); a stable sort has one result."""
    ranked = np.empty(grouped.size, dtype=np.int64)
    head = 0
    for g in range(tails.size):
        for i in range(head, tails[g]):
            k = grouped[i]
            key = s[k]
            j = i
            while j > head:
                other = s[ranked[j - 1]]
                if not (key < other or (math.isnan(other) and not math.isnan(key))):
                    break
                ranked[j] = ranked[j - 1]
                j -= 1
            ranked[j] = k
        head = tails[g]
    return ranked


@compiled
def track_pairs(s: Floats, grouped: Ints, tails: Ints, place: Ints, base: Floats
                ) -> tuple[Ints, Ints, Ints, Floats, Ints, Ints]:
    """``RiderPairs.pair_list`` on each track: the riders by track and arc length ``s``
    (``in_order``), each with the next one on its track (succ behind, pred ahead, and the
    odometer offset base[succ] - base[pred]), and where each track's riders begin and end
    in that order (heads, tails)."""
    ranked = in_order(s, grouped, tails)
    n = ranked.size
    succ, pred = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    offset = np.empty(n)
    heads, ends = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    count, groups = 0, 0
    for i in range(n):
        if i == 0 or place[ranked[i - 1]] != place[ranked[i]]:
            if groups:
                ends[groups - 1] = i
            heads[groups] = i
            groups += 1
        else:
            succ[count], pred[count] = ranked[i - 1], ranked[i]
            offset[count] = base[ranked[i - 1]] - base[ranked[i]]
            count += 1
    if groups:
        ends[groups - 1] = n
    return ranked, succ[:count], pred[:count], offset[:count], heads[:groups], ends[:groups]


@compiled
def riders_ahead(ranked: Ints, heads: Ints, ends: Ints, track_of: Ints, track_count: int,
                 base: Floats, look_tracks: Ints, look_bases: Floats, look_count: Ints
                 ) -> tuple[Ints, Ints, Floats]:
    """``RiderPairs.pair_list``'s pairs across tracks: for each track's front rider (the
    last of ``ranked[heads[g]:ends[g]]``), the first rider other than itself on the tracks
    it looks along (``look_tracks[m, :look_count[m]]``, each based at ``look_bases`` on its
    odometer; of each track its first rider, else its second), and the shift of that
    rider's odometer into the front rider's. Returns the front riders that have one, their
    leaders and shifts."""
    first = np.full((2, track_count), -1, dtype=np.int64)
    for g in range(heads.size):
        h = heads[g]
        index = track_of[ranked[h]]
        first[0, index] = ranked[h]
        if h + 1 < ends[g]:
            first[1, index] = ranked[h + 1]
    fronts = np.empty(heads.size, dtype=np.int64)
    leaders = np.empty(heads.size, dtype=np.int64)
    shifts = np.empty(heads.size)
    count = 0
    for g in range(heads.size):
        m = ranked[ends[g] - 1]
        for j in range(look_count[m]):
            index = look_tracks[m, j]
            k = first[0, index]
            if k == m:
                k = first[1, index]
            if k >= 0:
                fronts[count], leaders[count] = m, k
                shifts[count] = look_bases[m, j] - base[k]
                count += 1
                break
    return fronts[:count], leaders[:count], shifts[:count]


@compiled
def zone_stops(n: int, k: Ints, low: Floats, high: Floats, wanting: Bools, blocked: Bools
               ) -> tuple[Ints, Floats, Floats, Ints]:
    """Of ``zone_entries``' riders ``k``: those ``blocked`` (a conflicting rider holds the
    switch), once each in the order first met, each with the bounds of all its entries
    (the largest low, the smallest high: Python's max and min, as ``_narrow``), and the
    entries whose rider wants in and is not blocked (``entering``)."""
    at = np.full(n, -1, dtype=np.int64)
    riders, lows, highs = np.empty(k.size, dtype=np.int64), np.empty(k.size), np.empty(k.size)
    entering = np.empty(k.size, dtype=np.int64)
    count, entries = 0, 0
    for i in range(k.size):
        if not blocked[i]:
            if wanting[i]:
                entering[entries] = i
                entries += 1
            continue
        r = k[i]
        if at[r] < 0:
            at[r] = count
            riders[count], lows[count], highs[count] = r, -np.inf, np.inf
            count += 1
        j = at[r]
        if low[i] > lows[j]:
            lows[j] = low[i]
        if high[i] < highs[j]:
            highs[j] = high[i]
    return riders[:count], lows[:count], highs[:count], entering[:entries]


@compiled
def out_of_bounds(riders: Ints, lows: Floats, highs: Floats, skip: Bools, braking: Bools,
                  lo: Floats, hi: Floats) -> Ints:
    """The ``riders`` (not ``skip``-ped, not ``braking``) whose envelope (lo, hi) passes their
    bounds (lows, highs): they brake instead (``SwitchZones.keep_out``)."""
    out = np.empty(riders.size, dtype=np.int64)
    count = 0
    for i in range(riders.size):
        k = riders[i]
        if not skip[k] and not braking[k] and (hi[k] > highs[i] + TOLERANCE
                                               or lo[k] < lows[i] - TOLERANCE):
            out[count] = k
            count += 1
    return out[:count]


@compiled
def turning_gaps(nxt_v: Floats, nxt_a: Floats, jerk: Floats, going: Bools, succ: Ints,
                 pred: Ints, mode: Ints, idle: int, target: Floats, p: Floats, gap: Floats
                 ) -> tuple[Bools, Floats]:
    """After the proposals: the riders that turn back with them (``going_back`` of the
    proposals, not of the states before), and the pairs' gaps (``pair_gaps``) with them."""
    turning = going_back(nxt_v, nxt_a, jerk)
    either = np.empty(going.size, dtype=np.bool_)
    for k in range(going.size):
        turning[k] = turning[k] and not going[k]
        either[k] = going[k] or turning[k]
    return turning, pair_gaps(succ, pred, mode, idle, target, p, either, gap)


@compiled
def past_ends(p: Floats, base: Floats, length: Floats) -> Ints:
    """Riders whose arc length reached the end of their track (to ``TRACK_END_PRECISION``) or
    fell below its start (a route back over a loop's seam goes on there, D-147)."""
    out = np.empty(p.size, dtype=np.int64)
    count = 0
    for k in range(p.size):
        s = p[k] - base[k]
        if s >= length[k] - TRACK_END_PRECISION or s < 0.0:
            out[count] = k
            count += 1
    return out[:count]


@compiled
def resting(mode: Ints, held: int, v: Floats, a: Floats) -> Ints:
    """Riders in mode ``held`` at rest."""
    out = np.empty(mode.size, dtype=np.int64)
    count = 0
    for k in range(mode.size):
        if mode[k] == held and v[k] == 0.0 and a[k] == 0.0:
            out[count] = k
            count += 1
    return out[:count]


@compiled
def ended(mode: Ints, follow: int, end: Floats, rows: Ints, now: float) -> Ints:
    """Riders in mode ``follow`` whose profile (table row) ended by ``now``."""
    out = np.empty(mode.size, dtype=np.int64)
    count = 0
    for k in range(mode.size):
        if mode[k] == follow and end[rows[k]] <= now:
            out[count] = k
            count += 1
    return out[:count]


@compiled
def _conflict(r: int, at_end: bool, h: int, their_end: bool, track_of: Ints, next_of: Ints,
              seam: Bools, back: Bools) -> bool:
    """``SwitchZones.conflicts`` of rider ``r`` (at the end of its track, else its start) and
    holder ``h`` at their switch. ``back``: the rider's route goes back over its loop's
    seam (nobody passes onto its track behind it there)."""
    mine, theirs = track_of[r], track_of[h]
    my_next, their_next = next_of[r], next_of[h]
    onto = (at_end and my_next == theirs and not their_end and not back[h]) or \
        (their_end and their_next == mine and not at_end and not back[r])
    other = mine != theirs and not onto
    leaving = (at_end and my_next >= 0 and my_next != mine) or \
        (their_end and their_next >= 0 and their_next != theirs)
    same = mine == theirs and seam[r] and leaving
    return (other or same) and r != h


@compiled
def conflicts(slots: Ints, ends: Bools, holders: Ints, holder_ends: Bools, track_of: Ints,
              next_of: Ints, seam: Bools, back: Bools) -> NDArray[np.bool_]:
    """``SwitchZones.conflicts``: whether each of ``slots`` may meet each of ``holders`` at
    their switch, a matrix (``_conflict``)."""
    out = np.zeros((slots.size, holders.size), dtype=np.bool_)
    for i in range(slots.size):
        for j in range(holders.size):
            out[i, j] = _conflict(slots[i], ends[i], holders[j], holder_ends[j], track_of,
                                  next_of, seam, back)
    return out


@compiled
def zone_lines(start_switch: Ints, end_switch: Ints, in_end: Bools, in_start: Bools,
               end_line: Floats, start_line: Floats, lo: Floats, hi: Floats, lookahead: float,
               holders: Ints, holder_ends: Bools, holder_switches: Ints, track_of: Ints,
               next_of: Ints, seam: Bools, back: Bools
               ) -> tuple[Ints, Floats, Floats, Ints]:
    """The stop lines of ``SwitchZones.keep_out`` in one pass: ``zone_entries``, each entry
    blocked where a holder (``holders[j]``, at the end of its track where ``holder_ends[j]``,
    of switch ``holder_switches[j]``) at its switch conflicts with it, then ``zone_stops``."""
    k, end, switch, low, high, wanting = zone_entries(start_switch, end_switch, in_end,
                                                      in_start, end_line, start_line, lo, hi,
                                                      lookahead)
    blocked = np.zeros(k.size, dtype=np.bool_)
    by_switch, at = _by_switch(holder_switches)
    for i in range(k.size):
        s = switch[i]
        if s < 0 or s >= at.size - 1:
            continue
        for m in range(at[s], at[s + 1]):
            j = by_switch[m]
            if _conflict(k[i], end[i], holders[j], holder_ends[j], track_of, next_of, seam,
                         back):
                blocked[i] = True
                break
    return zone_stops(start_switch.size, k, low, high, wanting, blocked)


@compiled
def _by_switch(switch: Ints) -> tuple[Ints, Ints]:
    """The positions of ``switch`` (ids >= 0) grouped by id, ascending within an id, and
    where each id's begin (id s: ``at[s]`` to ``at[s + 1]``): a counting sort, so that a
    question about one switch visits only its holders (there are dozens of switches at
    1000 riders)."""
    top = -1
    for i in range(switch.size):
        if switch[i] > top:
            top = switch[i]
    at = np.zeros(top + 2, dtype=np.int64)
    for i in range(switch.size):
        at[switch[i] + 1] += 1
    for s in range(top + 1):
        at[s + 1] += at[s]
    fill = at[:-1].copy()
    out = np.empty(switch.size, dtype=np.int64)
    for i in range(switch.size):
        out[fill[switch[i]]] = i
        fill[switch[i]] += 1
    return out, at


@compiled
def contested_pairs(holders: Ints, at_end: Bools, switch: Ints, track_of: Ints,
                    next_of: Ints, seam: Bools, back: Bools) -> tuple[Ints, Ints]:
    """``SwitchZones.holding``'s clash of the holders with each other: the pairs (i, j) of
    positions in ``holders`` that hold one switch and conflict there (``_conflict``), in
    the order of numpy.nonzero of their matrix (by i, then j)."""
    by_switch, at = _by_switch(switch)
    first, second = np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    count = 0
    for i in range(holders.size):
        s = switch[i]
        for m in range(at[s], at[s + 1]):
            j = by_switch[m]
            if _conflict(holders[i], at_end[i], holders[j], at_end[j], track_of, next_of,
                         seam, back):
                if count == first.size:
                    first = np.concatenate((first, np.empty(max(8, count), dtype=np.int64)))
                    second = np.concatenate((second, np.empty(max(8, count),
                                                              dtype=np.int64)))
                first[count], second[count] = i, j
                count += 1
    return first[:count], second[:count]


def warm() -> None:
    """Load every loop of the traffic's cycle now (from numba's cache, or compile it), each
    with the argument types of the cycle. A run loads each loop in the first cycle that
    needs it (the first switch conflict, say: milliseconds from the cache, about a second
    to compile), and compiles none it does not need; a benchmark that times cycles calls
    this first."""
    from openmotion.planar.track_atlas import Atlas
    from openmotion.rail.kernels import brake_states as states
    from openmotion.rail.kernels import envelopes

    f, i, b = np.zeros(1), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.bool_)
    lim = np.ones((4, 1))
    none, nothing = np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.bool_)
    atlas = Atlas([])
    tables = atlas.tables()
    atlas.along_routes(none, np.zeros(0), i, np.zeros(0), i, tables)
    q, at = stretch_samples(0.0, 1.0, 0.0, 1.0, 2.0, 1, 1, np.zeros(0), np.zeros(0), none)
    stretch_hits(q, q, q, q, at, f, f, f, 1, 1)
    rooms(1, none, none, np.zeros(0), np.zeros(0), f, f, none, np.zeros(0), np.zeros(0))
    extensions(none, f, f, f, f, i, f, f, i, 2, 5.0)
    neighbours(1, none, none)
    held_plans(none, f, f, f, f, lim, f, f, i, 0, i, i, f.copy(), f.copy(), f.copy(), f.copy(),
               b.copy(), f.copy(), f.copy())
    held_steps(none, np.zeros(0), nothing, 0.001, f, f, f, f, lim, f, f, f, f, f, f, f.copy(),
               f.copy(), f.copy(), f.copy(), b.copy(), f.copy(), f.copy())
    touching(f, f, f, f, 1.0, 1.0, f, f, f, f, 1.0, 1.0, 1.0)
    write_setpoints(i, 0, f, f, f, f, b.copy(), i, i, i, i, b, f.copy(), f.copy(), f.copy(),
                    f.copy(), f.copy(), tables)
    gap_filter(f, f, f, f, f, f.copy(), f.copy(), f.copy(), f.copy(), 0.001, f + 1.0,
               f + 1.0, none, none, np.zeros(0), np.zeros(0), b, f, f)
    zone_holders(f, f, f, f, f, i, i, f, f)
    zone_entries(i, i, b, b, f, f, f, f, 1.0)
    pair_gaps(none, none, i, 0, f, f, b, f)
    going_back(f, f, f + 1.0)
    place, grouped, tails = group_by_track(i)
    zone_stops(1, i, f, f, b, b)
    out_of_bounds(i, f, f, b, b, f, f)
    turning_gaps(f, f, f + 1.0, b, none, none, i, 0, f, f, f)
    past_ends(f, f, f)
    resting(i, 2, f, f)
    ended(i, 1, f, i, 0.0)
    conflicts(i, b, i, b, i, i, b, b)
    contested_pairs(i, b, i, i, i, b, b)
    zone_lines(i, i, b, b, f, f, f, f, 1.0, i, b, i, i, i, b, b)
    in_order(f, grouped, tails)
    track_pairs(f, grouped, tails, place, f)
    riders_ahead(i, i, i + 1, i, 1, f, np.zeros((1, 1), dtype=np.int64), np.zeros((1, 1)), i)
    proposals(i, 1, 0, i, f, f, f, f + 1.0, f, f, f, f, f, f)
    envelopes(f, f, f, f + 1.0, f + 1.0)
    states(f, f, f, f + 1.0, f + 1.0, 0.001)
