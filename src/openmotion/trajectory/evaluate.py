"""Evaluate the stored profiles of all objects at one instant, in a few numpy operations.

Row i holds the segments of object i with absolute start times; unused columns start at
+inf. The coefficients of each row's *current* segment are cached in flat arrays, so a cycle
costs one cubic over N values plus a gather for the few rows that crossed a segment boundary.
Planning writes a row on an event; evaluation reads every row every cycle.
"""

from __future__ import annotations

import numpy as np

from openmotion.trajectory.segments import KinematicState, Profile


class SegmentTable:
    """Struct of arrays: segment starts and boundary states, one row per object."""

    def __init__(self, capacity: int = 16, columns: int = 24) -> None:
        self.columns = columns
        self.size = 0
        self.capacity = 0
        self._allocate(capacity)

    def _allocate(self, capacity: int) -> None:
        n = self.size
        shape = (capacity, self.columns)

        def grown(name: str, fill: float, dims: tuple[int, ...]) -> np.ndarray:
            new = np.full(dims, fill)
            if n:
                new[:n] = getattr(self, name)[:n]
            return new

        self.start = grown("start", np.inf, shape)
        for name in ("p", "v", "a", "j"):
            setattr(self, name, grown(name, 0.0, shape))
        self.end = grown("end", -np.inf, (capacity,))  # start of the open segment [s]
        self.next_start = grown("next_start", np.inf, (capacity,))
        self.index = grown("index", 0, (capacity,)).astype(np.int64)
        for name in ("t0", "p0", "v0", "a0", "j0"):
            setattr(self, name, grown(name, 0.0, (capacity,)))
        # scratch buffers reused every cycle
        self._dt = np.zeros(capacity)
        self._tmp = np.zeros(capacity)
        self.out_p, self.out_v, self.out_a = (np.zeros(capacity) for _ in range(3))
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
        n = len(profile.t)
        if n > self.columns:
            raise ValueError(f"profile has {n} segments, the table holds {self.columns}")
        start = profile.t + time
        self.start[row, :n] = start
        self.start[row, n:] = np.inf
        self.p[row, :n] = profile.p
        self.v[row, :n] = profile.v
        self.a[row, :n] = profile.a
        self.j[row, :n] = profile.j
        self.end[row] = start[-1]
        self._select(row, 0)

    def shift(self, row: int, offset: float) -> None:
        """Move every position of ``row`` by ``offset`` (a coordinate shift)."""
        self.p[row] += offset
        self.p0[row] += offset

    def _select(self, row: int, k: int) -> None:
        self.index[row] = k
        self.t0[row] = self.start[row, k]
        self.p0[row] = self.p[row, k]
        self.v0[row] = self.v[row, k]
        self.a0[row] = self.a[row, k]
        self.j0[row] = self.j[row, k]
        self.next_start[row] = self.start[row, k + 1] if k + 1 < self.columns else np.inf

    def _advance(self, rows: np.ndarray, now: float) -> None:
        """Move the cached segment of ``rows`` to the one that holds ``now``."""
        k = (self.start[rows, 1:] <= now).sum(axis=1)
        self.index[rows] = k
        self.t0[rows] = self.start[rows, k]
        self.p0[rows] = self.p[rows, k]
        self.v0[rows] = self.v[rows, k]
        self.a0[rows] = self.a[rows, k]
        self.j0[rows] = self.j[rows, k]
        nxt = np.minimum(k + 1, self.columns - 1)
        self.next_start[rows] = np.where(k + 1 < self.columns, self.start[rows, nxt], np.inf)

    def evaluate(self, now: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity, acceleration and jerk of every row at ``now`` (views)."""
        n = self.size
        crossed = np.flatnonzero(self.next_start[:n] <= now)
        if crossed.size:
            self._advance(crossed, now)
        dt, tmp = self._dt[:n], self._tmp[:n]
        a0, v0, j0 = self.a0[:n], self.v0[:n], self.j0[:n]
        p, v, a = self.out_p[:n], self.out_v[:n], self.out_a[:n]
        np.subtract(now, self.t0[:n], out=dt)
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
        np.add(p, self.p0[:n], out=p)
        return p, v, a, j0

    def state(self, row: int, time: float) -> KinematicState:
        """Exact kinematic state of one row at ``time`` (used when planning from it)."""
        k = int((self.start[row, 1:] <= time).sum())
        dt = time - self.start[row, k]
        p0, v0, a0, j = self.p[row, k], self.v[row, k], self.a[row, k], self.j[row, k]
        position = p0 + dt * (v0 + dt * (a0 * 0.5 + dt * j * (1.0 / 6.0)))
        velocity = v0 + dt * (a0 + dt * j * 0.5)
        if time >= self.end[row]:  # open segment: the exact end state
            return KinematicState(float(position), float(velocity), 0.0)
        return KinematicState(float(position), float(velocity), float(a0 + dt * j))
