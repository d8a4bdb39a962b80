"""Kinematic state of all axes as arrays; one cycle is a handful of numpy operations.

``Axis`` objects hold a row index and read through it. The kernel evaluates every setpoint,
simulates every drive and runs the vectorised monitors; the axes only see the rows with an
event (a profile that ended, a following-error alarm).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
from numba import typeof

from openmotion.axis.gearing import Couplings
from openmotion.axis.tolerances import LAG_FILTER_TOLERANCE, LIMIT_TOLERANCE
from openmotion.core.compiled import compiled
from openmotion.trajectory.evaluate import SegmentTable, evaluate_rows
from openmotion.trajectory.segments import KinematicState, Profile

#: rows of ``AxisKernel.fields``: the setpoint (rows 0-3), then the actual values (4-5)
_FLOAT_FIELDS = ("set_p", "set_v", "set_a", "set_j", "act_p", "act_v", "alpha", "lag_max",
                 "lag_filter", "lag_timer", "ext_p", "ext_v", "ext_a", "v_max", "a_max", "j_max")
_BOOL_FIELDS = ("has_job", "lag_on", "monitored", "blocked", "external", "fed", "superimposed")
_EMPTY = np.zeros(0, dtype=np.int64)


class AxisKernel:
    def __init__(self, cycle_time: float, capacity: int = 16) -> None:
        self.cycle_time = cycle_time
        self.segments = SegmentTable(capacity)
        self.overlay = SegmentTable(capacity)  #: superimposed motion, added to the setpoint
        self._overlays = 0
        self._op, self._ov, self._oa, self._oj = (np.zeros(capacity) for _ in range(4))
        self.size = 0
        self.sample_time = 0.0  #: instant of the last evaluated sample [s]
        self._capacity = 0
        self.dead = np.zeros(0, dtype=np.int64)
        self.history = np.zeros((0, 1))
        self._head = 0
        self._any_lag = False
        self._externals = 0  #: axes following external setpoints
        self._blocked = 0  #: axes whose drive is mechanically blocked (stall simulation)
        self.couplings = Couplings()
        #: time, rows and (p, v, a) of the geared slaves' previous sample
        self.previous = (0.0, _EMPTY, np.zeros((0, 3)))
        #: the earliest end of a job profile or superimposed motion (``next_event``), and the
        #: install counts of the two tables it was computed at (-1: compute it again)
        self._next_event = -math.inf
        self._seen_jobs = self._seen_overlays = -1
        self._grow(capacity)
        self._bind()

    def _grow(self, capacity: int) -> None:
        def grown(old: np.ndarray, dtype: type) -> np.ndarray:
            new = np.zeros(capacity, dtype=dtype)
            new[: self.size] = old[: self.size]
            return new

        fields = np.zeros((len(_FLOAT_FIELDS), capacity))  #: one array: one copy per phase
        for i, name in enumerate(_FLOAT_FIELDS):
            old = getattr(self, name, None)
            if old is not None:
                fields[i, : self.size] = old[: self.size]
            setattr(self, name, fields[i])
        self.fields = fields
        for name in _BOOL_FIELDS:
            setattr(self, name, grown(getattr(self, name, np.zeros(0, bool)), bool))
        self.dead = grown(self.dead, np.int64)
        history = np.zeros((capacity, self.history.shape[1]))
        history[: self.size] = self.history[: self.size]
        self.history = history
        self._capacity = capacity

    def _bind(self) -> None:
        """``sample(now, follow)``: the setpoints at ``now`` (and with ``follow``, ideal drives
        following them) in one compiled call bound to the arrays as they are now; taken again
        when a row comes. A cycle of one axis costs a few µs, and looking the arrays up was a
        good part of it. The events' passes (``next_event``, ``ended``) are bound alike, and
        each to its compiled entry point for these argument types, without the dispatcher's
        look at every argument's type in every call (the arrays keep their types and
        layouts; a new row binds again)."""
        table = (*self.segments.bound(), self.fields)
        self.sample = partial(_entry(_sample, *table, 0.0, False), *table)
        jobs = (self.has_job, self.segments.end, self.superimposed, self.overlay.end, self.size)
        self._earliest_end = partial(_entry(_earliest_end, *jobs), *jobs)
        self._ended = (self.has_job, self.segments.end, self.size,
                       np.empty(max(self._capacity, 1), dtype=np.int64))
        self._ended_rows = _entry(_ended_rows, *self._ended[:3], 0.0, self._ended[3])

    def add(self, position: float, alpha: float, dead_cycles: int) -> int:
        if self.size == self._capacity:
            self._grow(2 * self._capacity)
        row = self.segments.add(KinematicState(position), self.sample_time)
        self.overlay.add(KinematicState(0.0), self.sample_time)
        assert row == self.size
        self.size += 1
        self._bind()
        self.set_p[row] = self.act_p[row] = position
        self.alpha[row] = alpha
        self.dead[row] = dead_cycles
        if dead_cycles + 1 > self.history.shape[1]:
            history = np.zeros((self._capacity, dead_cycles + 1))
            history[:, : self.history.shape[1]] = self.history
            self.history = history
        self.history[row, :] = position
        self._any_lag = bool(np.any(self.alpha[: self.size] < 1.0) or np.any(self.dead > 0))
        return row

    # -- the cycle -------------------------------------------------------------------------

    def next_event(self) -> float:
        """The earliest instant at which a job profile or a superimposed motion ends: the
        first cycle whose ``now`` reaches it has rows in ``ended`` or ``overlay_ended``; none
        before it has (+inf: no event ahead). A lower bound, cached: every install of a
        profile makes it computed again, and ``forget_events`` after the events of a cycle
        were handled (a job that ends without a new install clears ``has_job``); a
        ``has_job`` cleared elsewhere only makes it early, and an early bound costs one
        look that finds nothing."""
        segments, overlay = self.segments, self.overlay
        if segments.installs != self._seen_jobs or overlay.installs != self._seen_overlays:
            self._seen_jobs, self._seen_overlays = segments.installs, overlay.installs
            self._next_event = self._earliest_end()
        return self._next_event

    def forget_events(self) -> None:
        """The events of this cycle were handled: ``next_event`` computes again."""
        self._seen_jobs = -1

    @property
    def quiet(self) -> bool:
        """Nothing in the kernel needs cycle-by-cycle work between events: ideal drives
        (no lag filter, dead time or stall to integrate), no geared slave (its limit check),
        no fed setpoint (the program feeds it every cycle)."""
        return not (self._any_lag or self._blocked or self._externals
                    or self.couplings.slaves.size)

    def evaluate_and_follow(self, now: float) -> bool:
        """``evaluate`` and, with ideal drives, ``simulate_drives`` in one pass, for the
        axes alone in a runtime (nothing corrects their setpoints in between); False (and
        nothing done) where either is more than that."""
        if self._overlays or self.couplings.slaves.size or self._externals or self._any_lag \
                or self._blocked:
            return False
        self.sample(now, True)
        self.sample_time = now
        return True

    @property
    def has_overlays(self) -> bool:
        """Some axis runs a superimposed motion (MC_MoveSuperImposed)."""
        return bool(self._overlays)

    def ended(self, now: float) -> np.ndarray:
        """Rows whose job profile reaches its end state at or before ``now`` (events)."""
        has_job, end, n, rows = self._ended
        return rows[: self._ended_rows(has_job, end, n, now, rows)]

    def evaluate(self, now: float, again: bool = False) -> None:
        """Sample every setpoint at ``now``; ``again``: the same instant after a fault
        re-planned some rows (the slaves' previous samples stay)."""
        slaves = self.couplings.slaves
        if slaves.size and not again:  # where a slave brakes from if its next sample is refused
            self.previous = (self.sample_time, slaves.copy(), np.stack(
                (self.set_p[slaves], self.set_v[slaves], self.set_a[slaves]), axis=1))
        self.sample(now, False)
        if not (self._overlays or slaves.size or self._externals):  # free axes only
            self.sample_time = now
            return
        if self._overlays:  # MC_MoveSuperImposed, free axes first: their slaves follow them
            self._add_overlays(now, slaves=False)
        # then geared slaves (flying saw); in a chain each as it is set, for its own slaves
        chained = bool(self._overlays) and self.couplings.chained
        overlays = (self._op, self._ov, self._oa, self._oj, self.superimposed) if chained \
            else None
        self.couplings.apply(self.set_p, self.set_v, self.set_a, self.set_j, overlays)
        if self._overlays and self.couplings.slaves.size and not chained:
            self._add_overlays(now, slaves=True)
        if self._externals:  # MC_ExtSetPointGen: the fed values are the setpoint
            rows = np.flatnonzero(self.external[: self.size])
            self.set_p[rows], self.set_v[rows] = self.ext_p[rows], self.ext_v[rows]
            self.set_a[rows], self.set_j[rows] = self.ext_a[rows], 0.0
        self.sample_time = now

    def slave_violations(self) -> np.ndarray:
        """Geared slave rows whose new sample breaks their maximum velocity, acceleration or
        jerk, or from which braking with the maximum jerk would pass the maximum velocity
        (D-182): they must fault and brake from their previous sample instead."""
        s = self.couplings.slaves
        if not s.size:
            return _EMPTY
        v, a, j = self.set_v[s], self.set_a[s], self.set_j[s]
        slack = 1.0 + LIMIT_TOLERANCE
        v_max, a_max, j_max = self.v_max[s] * slack, self.a_max[s] * slack, self.j_max[s] * slack
        reach = np.abs(v) + np.where(a * v > 0.0, a * a / (2.0 * self.j_max[s]), 0.0)
        bad = (reach > v_max) | (np.abs(a) > a_max) | (np.abs(j) > j_max)
        bad &= ~self.external[s]
        return s[bad]

    def previous_sample(self, row: int) -> tuple[float, KinematicState]:
        """Time and state of a geared slave's previous sample (its last admissible one)."""
        time, rows, values = self.previous
        found = np.flatnonzero(rows == row)
        if not found.size:  # coupled in this cycle: at rest where it stands
            return self.sample_time, KinematicState(float(self.set_p[row]))
        p, v, a = values[int(found[0])].tolist()
        return time, KinematicState(p, v, a)

    def simulate_drives(self) -> None:
        n = self.size
        if not self._any_lag and not self._blocked:  # ideal drives follow exactly
            self.fields[4:6, :n] = self.fields[0:2, :n]  # act_p, act_v = set_p, set_v
            return
        previous = self.act_p[:n].copy()
        if not self._any_lag:
            self.act_p[:n] = self.set_p[:n]
            self._hold_blocked(previous)
            self.act_v[:n] = (self.act_p[:n] - previous) / self.cycle_time
            return
        width = self.history.shape[1]
        self._head = (self._head + 1) % width
        self.history[:n, self._head] = self.set_p[:n]
        delayed = self.history[np.arange(n), (self._head - self.dead[:n]) % width]
        self.act_p[:n] += self.alpha[:n] * (delayed - self.act_p[:n])
        self._hold_blocked(previous)
        self.act_v[:n] = (self.act_p[:n] - previous) / self.cycle_time

    def _hold_blocked(self, previous: np.ndarray) -> None:
        if self._blocked:
            rows = np.flatnonzero(self.blocked[: self.size])
            self.act_p[rows] = previous[rows]

    def set_blocked(self, row: int, blocked: bool) -> None:
        """Block the mechanics of an axis: its actual position stops following (a stall)."""
        if bool(self.blocked[row]) != blocked:
            self.blocked[row] = blocked
            self._blocked += 1 if blocked else -1

    def set_external(self, row: int, on: bool) -> None:
        """Let an axis take its setpoint from ``ext_p/ext_v/ext_a`` (MC_ExtSetPointGen)."""
        if bool(self.external[row]) != on:
            self.external[row] = on
            self._externals += 1 if on else -1
            self.fed[row] = False
            self.ext_p[row], self.ext_v[row], self.ext_a[row] = (
                self.set_p[row], self.set_v[row], self.set_a[row])

    def lag_alarms(self) -> np.ndarray:
        """Rows whose following error stayed above the limit longer than the filter time."""
        n = self.size
        if not self._any_lag and not self._blocked:  # ideal drives: actual == set
            return _EMPTY
        over = self.monitored[:n] & self.lag_on[:n] & (
            np.abs(self.set_p[:n] - self.act_p[:n]) > self.lag_max[:n]
        )
        self.lag_timer[:n] = np.where(over, self.lag_timer[:n] + self.cycle_time, 0.0)
        late = self.lag_timer[:n] > self.lag_filter[:n] + LAG_FILTER_TOLERANCE
        return np.flatnonzero(over & late)

    # -- per-row operations on events ------------------------------------------------------

    def state(self, row: int) -> KinematicState:
        """The setpoint state at the last sample: where any new plan starts."""
        if not (self._externals or self._overlays or self.couplings.slaves.size):
            return self.segments.state(row, self.sample_time)  # a free axis' own profile
        coupled = bool(self.couplings.slaves.size) and row in self.couplings
        if coupled or self.external[row]:  # follows a master or a feed
            return KinematicState(float(self.set_p[row]), float(self.set_v[row]),
                                  float(self.set_a[row]))
        base = self.segments.state(row, self.sample_time)
        if not self.superimposed[row]:
            return base
        extra = self.overlay.state(row, self.sample_time)
        return KinematicState(base.position + extra.position, base.velocity + extra.velocity,
                              base.acceleration + extra.acceleration)

    def base_state(self, row: int) -> KinematicState:
        """The setpoint state at the last sample without the superimposed part: where a
        re-plan of the base motion starts while the superposition goes on (D-180)."""
        whole = self.state(row)
        if not self.superimposed[row]:
            return whole
        if row not in self.couplings and not self.external[row]:
            return self.segments.state(row, self.sample_time)
        extra = self.overlay.state(row, self.sample_time)
        return KinematicState(whole.position - extra.position, whole.velocity - extra.velocity,
                              whole.acceleration - extra.acceleration)

    def _add_overlays(self, now: float, slaves: bool) -> None:
        n = self.size
        if self._op.size < self._capacity:
            self._op, self._ov, self._oa, self._oj = (np.zeros(self._capacity) for _ in range(4))
        if not slaves:
            self.overlay.evaluate(now, self._op, self._ov, self._oa, self._oj)
        coupled = np.isin(np.arange(n), self.couplings.slaves)
        rows = np.flatnonzero(self.superimposed[:n] & (coupled if slaves else ~coupled))
        self.set_p[rows] += self._op[rows]
        self.set_v[rows] += self._ov[rows]
        self.set_a[rows] += self._oa[rows]
        self.set_j[rows] += self._oj[rows]

    def overlay_ended(self, now: float) -> np.ndarray:
        """Rows whose superimposed motion has reached its end at or before ``now``."""
        if not self._overlays:
            return _EMPTY
        n = self.size
        return np.flatnonzero(self.superimposed[:n] & (self.overlay.end[:n] <= now))

    def set_superimposed(self, row: int, on: bool) -> None:
        if bool(self.superimposed[row]) != on:
            self.superimposed[row] = on
            self._overlays += 1 if on else -1
            self._seen_overlays = -1  # its overlay's end is an event from now on, or no more
        if not on:
            self.overlay.install(row, Profile.hold(KinematicState(0.0)), self.sample_time)

    def shift(self, row: int, offset: float) -> None:
        """Move the coordinate system of one axis (MC_SetActualPosition, homing)."""
        self.segments.shift(row, offset)
        self.set_p[row] += offset
        self.act_p[row] += offset
        self.history[row] += offset

    def reset_setpoint_to_actual(self, row: int) -> None:
        """TcMC §3.5: enabling and MC_Reset take the actual position as set position."""
        self.history[row] = self.act_p[row]
        self.set_p[row] = self.act_p[row]
        self.set_v[row] = self.set_a[row] = self.set_j[row] = 0.0
        self.lag_timer[row] = 0.0


@compiled
def _earliest_end(has_job: np.ndarray, end: np.ndarray, superimposed: np.ndarray,
                  overlay_end: np.ndarray, n: int) -> float:
    """``AxisKernel.next_event``: the least ``end`` of the rows with a job and the least
    ``overlay_end`` of the superimposed rows (+inf for none)."""
    earliest = np.inf
    for row in range(n):
        if has_job[row] and end[row] < earliest:
            earliest = end[row]
        if superimposed[row] and overlay_end[row] < earliest:
            earliest = overlay_end[row]
    return earliest


def _entry(dispatcher: Any, *example: Any) -> Callable[..., Any]:
    """The compiled entry point of ``dispatcher`` for the types of ``example`` (compiled or
    loaded from the cache now): called with arguments of exactly these types, it skips the
    dispatcher's resolution of every argument's type, a good part of a call's cost when
    the work is a few rows."""
    return dispatcher.compile(tuple(typeof(value) for value in example))


@compiled
def _ended_rows(has_job: np.ndarray, end: np.ndarray, n: int, now: float,
                rows: np.ndarray) -> int:
    """``AxisKernel.ended`` in one pass: the rows with a job whose ``end`` <= ``now`` into
    the first elements of ``rows``; returns how many."""
    count = 0
    for row in range(n):
        if has_job[row] and end[row] <= now:
            rows[count] = row
            count += 1
    return count


@compiled
def _sample(seg: np.ndarray, cur: np.ndarray, next_start: np.ndarray, n: int,
            fields: np.ndarray, now: float, follow: bool) -> None:
    """``AxisKernel.sample``: the setpoints into rows 0-3 of ``fields`` (``evaluate_rows``,
    so bit for bit ``SegmentTable.evaluate``), and with ``follow`` rows 0-1 copied into the
    actual values (rows 4-5), as ideal drives do."""
    evaluate_rows(seg, cur, next_start, n, fields[0], fields[1], fields[2], fields[3], now)
    if follow:
        for row in range(n):
            fields[4, row] = fields[0, row]
            fields[5, row] = fields[1, row]
