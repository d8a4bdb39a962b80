"""Evaluate the stored profiles of all objects at one instant, in a few numpy operations.

Row i holds the segments of object i as records (start, p, v, a, j) with absolute start
times; unused records start at +inf. The record of each row's *current* segment is cached
column-wise, so a cycle costs one cubic per row plus a look-up for the rows that crossed a
segment boundary, in one compiled pass. Planning writes a row on an event; evaluation reads
every row every cycle.
"""

from __future__ import annotations

import numpy as np

from openmotion.core.compiled import compiled
from openmotion.trajectory.segments import KinematicState, Profile

_T, _P, _V, _A, _J = range(5)


class SegmentTable:
    """Struct of arrays: segment records per row, and the current record of every row."""

    def __init__(self, capacity: int = 16, columns: int = 24) -> None:
        self.columns = columns
        self.size = 0
        #: profiles installed so far: a reader that caches something derived from the end
        #: times (the axes' next event) knows it is stale when this count moved
        self.installs = 0
        self.capacity = 0
        self._allocate(capacity)

    def _allocate(self, capacity: int) -> None:
        n = self.size
        seg = np.zeros((capacity, self.columns, 5))
        seg[:, :, _T] = np.inf
        cur = np.zeros((5, capacity))
        next_start = np.full(capacity, np.inf)
        end = np.full(capacity, -np.inf)  # start of the open segment [s]
        if n:
            seg[:n], cur[:, :n] = self.seg[:n], self.cur[:, :n]
            next_start[:n], end[:n] = self.next_start[:n], self.end[:n]
        self.seg, self.cur, self.next_start, self.end = seg, cur, next_start, end
        self.capacity = capacity

    def add(self, state: KinematicState, time: float) -> int:
        """A new row holding ``state``; returns its index."""
        if self.size == self.capacity:
            self._allocate(2 * self.capacity)
        row = self.size
        self.size += 1
        self.install(row, Profile.hold(state), time)
        return row

    def install(self, row: int, profile: Profile, time: float) -> None:
        """Let row ``row`` follow ``profile`` from absolute ``time`` on."""
        data = profile.data
        n = data.shape[1]
        if n > self.columns:
            raise ValueError(f"profile has {n} segments, the table holds {self.columns}")
        self.installs += 1
        _install(self.seg, self.cur, self.next_start, self.end, row, data, time)

    def end_position(self, row: int) -> float:
        """Position of the open segment of ``row`` (where its profile comes to rest)."""
        records = self.seg[row]
        n = int(np.isfinite(records[:, _T]).sum())
        return float(records[n - 1, _P])

    def shift(self, row: int, offset: float) -> None:
        """Move every position of ``row`` by ``offset`` (a coordinate shift)."""
        self.seg[row, :, _P] += offset
        self.cur[_P, row] += offset

    def evaluate(self, now: float, p: np.ndarray, v: np.ndarray, a: np.ndarray,
                 j: np.ndarray) -> None:
        """Write position, velocity, acceleration and jerk of every row at ``now`` into the
        first ``size`` elements of ``p``, ``v``, ``a`` and ``j``."""
        evaluate_rows(self.seg, self.cur, self.next_start, self.size, p, v, a, j, now)

    def bound(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
        """The arguments ``evaluate_rows`` takes before its outputs, as they are now (stale
        once a row is added): for a compiled caller that evaluates as part of its own pass."""
        return self.seg, self.cur, self.next_start, self.size

    def evaluate_many(self, times: np.ndarray, p: np.ndarray, v: np.ndarray, a: np.ndarray,
                      j: np.ndarray) -> None:
        """``evaluate`` at every time of ``times`` (increasing) in one compiled call: row ``k``
        of the (len(times), size) arrays ``p``, ``v``, ``a``, ``j`` gets what ``evaluate`` at
        ``times[k]`` gives, bit for bit (it is the same loop), so a quiet stretch of cycles
        can be sampled at once."""
        _evaluate_many(self.seg, self.cur, self.next_start, self.size, times, p, v, a, j)

    def states(self, rows: list[int], time: float) -> list[KinematicState]:
        """``state`` of several rows (a plan of x, y and c starts from all three)."""
        values = _states(self.seg, self.cur, self.next_start, self.end,
                         np.array(rows, dtype=np.int64), time).tolist()
        return [KinematicState(p, v, a) for p, v, a in values]

    def remaining(self, row: int, time: float) -> Profile:
        """The rest of row ``row``'s profile from ``time`` on, starting with its state there
        (where a running motion will still go: software limits written during it, D-179; the
        room a superposition leaves, D-180)."""
        start = self.state(row, time)
        records = self.seg[row]
        finite = records[np.isfinite(records[:, _T])]
        k = max(int((finite[1:, _T] <= time).sum()), 0)
        later = finite[k + 1:]
        jerk = 0.0 if time >= self.end[row] else float(finite[k, _J])
        data = np.empty((5, later.shape[0] + 1))
        data[:, 0] = (0.0, start.position, start.velocity, start.acceleration, jerk)
        data[:, 1:] = later.T
        data[0, 1:] -= time
        return Profile.from_data(data)

    def state(self, row: int, time: float) -> KinematicState:
        """Exact kinematic state of one row at ``time`` (used when planning from it)."""
        t0 = float(self.cur[_T, row])
        if t0 <= time < self.next_start[row]:  # the cached current segment holds ``time``
            _, p0, v0, a0, j = self.cur[:, row].tolist()
        else:
            records = self.seg[row]
            k = int((records[1:, _T] <= time).sum())
            t0, p0, v0, a0, j = records[k].tolist()
        dt = time - t0
        # the operation order of evaluate(), so a plan starts from the sampled values exactly
        position = p0 + ((a0 * 0.5 + (j * (1.0 / 6.0)) * dt) * dt + v0) * dt
        velocity = v0 + ((j * 0.5) * dt + a0) * dt
        if time >= self.end[row]:  # open segment: the exact end state
            return KinematicState(position, velocity, 0.0)
        return KinematicState(position, velocity, a0 + dt * j)


@compiled
def _states(seg: np.ndarray, cur: np.ndarray, next_start: np.ndarray, end: np.ndarray,
            rows: np.ndarray, time: float) -> np.ndarray:
    """``SegmentTable.state`` of several rows at once: (rows, 3) position, velocity,
    acceleration, with its formulas in its order (bit for bit)."""
    out = np.empty((rows.shape[0], 3))
    columns = seg.shape[1]
    for i in range(rows.shape[0]):
        row = rows[i]
        if cur[_T, row] <= time < next_start[row]:
            t0, p0, v0, a0, j = cur[_T, row], cur[_P, row], cur[_V, row], cur[_A, row], \
                cur[_J, row]
        else:
            k = 0
            for column in range(1, columns):
                if seg[row, column, _T] <= time:
                    k += 1
            t0, p0, v0, a0, j = seg[row, k, _T], seg[row, k, _P], seg[row, k, _V], \
                seg[row, k, _A], seg[row, k, _J]
        dt = time - t0
        out[i, 0] = p0 + ((a0 * 0.5 + (j * (1.0 / 6.0)) * dt) * dt + v0) * dt
        out[i, 1] = v0 + ((j * 0.5) * dt + a0) * dt
        out[i, 2] = 0.0 if time >= end[row] else a0 + dt * j
    return out


@compiled
def evaluate_rows(seg: np.ndarray, cur: np.ndarray, next_start: np.ndarray, n: int,
                  p: np.ndarray, v: np.ndarray, a: np.ndarray, j: np.ndarray,
                  now: float) -> None:
    """``SegmentTable.evaluate`` in one compiled pass (a hundred planar movers are 600 rows;
    as numpy passes the cost was the seventeen passes, not the arithmetic). A row whose next
    segment has started moves its cached record to the segment that holds ``now``. The
    operation order is ``state``'s, so a plan starts from the evaluated values exactly."""
    columns = seg.shape[1]
    for row in range(n):
        if next_start[row] <= now:
            k = 0
            for column in range(1, columns):
                if seg[row, column, _T] <= now:
                    k += 1
            for field in range(5):
                cur[field, row] = seg[row, k, field]
            next_start[row] = seg[row, k + 1, _T] if k + 1 < columns else np.inf
        dt = now - cur[_T, row]
        p0, v0, a0, j0 = cur[_P, row], cur[_V, row], cur[_A, row], cur[_J, row]
        j[row] = j0
        a[row] = dt * j0 + a0
        v[row] = ((j0 * 0.5) * dt + a0) * dt + v0
        p[row] = ((a0 * 0.5 + (j0 * (1.0 / 6.0)) * dt) * dt + v0) * dt + p0


@compiled
def _evaluate_many(seg: np.ndarray, cur: np.ndarray, next_start: np.ndarray, n: int,
                   times: np.ndarray, p: np.ndarray, v: np.ndarray, a: np.ndarray,
                   j: np.ndarray) -> None:
    """``SegmentTable.evaluate_many``: ``evaluate_rows`` once per time, into one row each."""
    for k in range(times.shape[0]):
        evaluate_rows(seg, cur, next_start, n, p[k], v[k], a[k], j[k], times[k])


@compiled
def _install(seg: np.ndarray, cur: np.ndarray, next_start: np.ndarray, end: np.ndarray,
             row: int, data: np.ndarray, time: float) -> None:
    """``SegmentTable.install``: the records of ``data`` from absolute ``time`` on (a planar
    command installs three rows, a cycle of a hundred movers many)."""
    n = data.shape[1]
    for k in range(n):
        seg[row, k, _T] = data[0, k] + time
        for field in range(1, 5):
            seg[row, k, field] = data[field, k]
    for k in range(n, seg.shape[1]):
        seg[row, k, _T] = np.inf
    for field in range(5):
        cur[field, row] = seg[row, 0, field]
    next_start[row] = seg[row, 1, _T] if n > 1 else np.inf
    end[row] = seg[row, n - 1, _T]
