"""Evaluate the stored profiles of all objects at one instant, in a few numpy operations.

Row i holds the segments of object i as records (start, p, v, a, j) with absolute start
times; unused records start at +inf. The record of each row's *current* segment is cached
column-wise, so a cycle costs one cubic over N values plus one gather for the rows that
crossed a segment boundary. Planning writes a row on an event; evaluation reads every row
every cycle.
"""

from __future__ import annotations

import numpy as np

from openmotion.trajectory.segments import KinematicState, Profile

_T, _P, _V, _A, _J = range(5)


class SegmentTable:
    """Struct of arrays: segment records per row, and the current record of every row."""

    def __init__(self, capacity: int = 16, columns: int = 24) -> None:
        self.columns = columns
        self.size = 0
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
        self._dt, self._tmp = np.zeros(capacity), np.zeros(capacity)
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
        records = self.seg[row]
        records[:n] = data.T
        records[:n, _T] += time
        records[n:, _T] = np.inf
        self.cur[:, row] = records[0]
        self.next_start[row] = records[1, _T] if n > 1 else np.inf
        self.end[row] = records[n - 1, _T]

    def end_position(self, row: int) -> float:
        """Position of the open segment of ``row`` (where its profile comes to rest)."""
        records = self.seg[row]
        n = int(np.isfinite(records[:, _T]).sum())
        return float(records[n - 1, _P])

    def shift(self, row: int, offset: float) -> None:
        """Move every position of ``row`` by ``offset`` (a coordinate shift)."""
        self.seg[row, :, _P] += offset
        self.cur[_P, row] += offset

    def _advance(self, rows: np.ndarray, now: float) -> None:
        """Move the cached record of ``rows`` to the segment that holds ``now``."""
        seg = self.seg
        k = (seg[rows, 1:, _T] <= now).sum(axis=1)
        self.cur[:, rows] = seg[rows, k].T
        following = np.minimum(k + 1, self.columns - 1)
        self.next_start[rows] = np.where(k + 1 < self.columns, seg[rows, following, _T],
                                         np.inf)

    def evaluate(self, now: float, p: np.ndarray, v: np.ndarray, a: np.ndarray,
                 j: np.ndarray) -> None:
        """Write position, velocity, acceleration and jerk of every row at ``now`` into the
        first ``size`` elements of ``p``, ``v``, ``a`` and ``j``."""
        n = self.size
        crossed = np.flatnonzero(self.next_start[:n] <= now)
        if crossed.size:
            self._advance(crossed, now)
        cur = self.cur
        t0, p0, v0, a0, j0 = cur[_T, :n], cur[_P, :n], cur[_V, :n], cur[_A, :n], cur[_J, :n]
        dt, tmp = self._dt[:n], self._tmp[:n]
        p, v, a = p[:n], v[:n], a[:n]
        j[:n] = j0
        np.subtract(now, t0, out=dt)
        # acceleration: a0 + dt*j
        np.multiply(dt, j0, out=a)
        np.add(a, a0, out=a)
        # velocity: v0 + dt*(a0 + dt*j/2)
        np.multiply(j0, 0.5, out=tmp)
        np.multiply(tmp, dt, out=tmp)
        np.add(tmp, a0, out=tmp)
        np.multiply(tmp, dt, out=v)
        np.add(v, v0, out=v)
        # position: p0 + dt*(v0 + dt*(a0/2 + dt*j/6))
        np.multiply(j0, 1.0 / 6.0, out=tmp)
        np.multiply(tmp, dt, out=tmp)
        np.multiply(a0, 0.5, out=p)
        np.add(tmp, p, out=tmp)
        np.multiply(tmp, dt, out=tmp)
        np.add(tmp, v0, out=tmp)
        np.multiply(tmp, dt, out=p)
        np.add(p, p0, out=p)

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
