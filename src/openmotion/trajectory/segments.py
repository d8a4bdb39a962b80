"""A planned setpoint as stored pieces: constant jerk per segment, open-ended last segment.

Ruckig plans; we keep its segment boundaries (time offset, position, velocity, acceleration,
jerk) and evaluate the cubic ourselves, for all axes at once (evaluate.py). The last segment has
zero acceleration and jerk and lasts forever: standstill at the target, or cruising at the
target velocity.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from openmotion.core.compiled import compiled


@dataclass(frozen=True, slots=True)
class KinematicState:
    position: float  #: [mm]
    velocity: float = 0.0  #: [mm/s]
    acceleration: float = 0.0  #: [mm/s²]


class Profile:
    """Segments k = 0..n-1 start at offset ``t[k]`` [s] with state ``p, v, a`` and jerk ``j``.

    The five rows live in one (5, n) array ``data``: the table installs it in one copy.
    """

    __slots__ = ("data",)

    def __init__(self, t: ArrayLike, p: ArrayLike, v: ArrayLike, a: ArrayLike,
                 j: ArrayLike) -> None:
        self.data = np.array((t, p, v, a, j), dtype=float)

    @classmethod
    def from_data(cls, data: np.ndarray) -> Profile:
        profile = cls.__new__(cls)
        profile.data = data
        return profile

    t = property(lambda self: self.data[0])
    p = property(lambda self: self.data[1])
    v = property(lambda self: self.data[2])
    a = property(lambda self: self.data[3])
    j = property(lambda self: self.data[4])

    def __repr__(self) -> str:
        return f"<Profile {self.data.shape[1]} segments, {self.duration:.6g} s>"

    @property
    def duration(self) -> float:
        """Start of the open-ended last segment: when the motion has reached its end state."""
        return float(self.data[0, -1])

    @property
    def end(self) -> KinematicState:
        data = self.data
        return KinematicState(float(data[1, -1]), float(data[2, -1]), 0.0)

    def at(self, time: float) -> tuple[float, float, float, float]:
        """Position, velocity, acceleration and jerk at ``time`` after the start."""
        k = max(int(np.searchsorted(self.t, time, side="right")) - 1, 0)
        dt = time - self.t[k]
        p0, v0, a0, j = self.p[k], self.v[k], self.a[k], self.j[k]
        return (
            float(p0 + dt * (v0 + dt * (a0 / 2.0 + dt * j / 6.0))),
            float(v0 + dt * (a0 + dt * j / 2.0)),
            float(a0 + dt * j),
            float(j),
        )

    def velocity_extrema(self) -> tuple[float, float]:
        """Lowest and highest velocity over the whole profile (segment ends and interior)."""
        return _velocity_extrema(self.data)

    def position_extrema(self) -> tuple[float, float]:
        """Lowest and highest position over the whole profile (where velocity is zero)."""
        return _position_extrema(self.data)

    @staticmethod
    def hold(state: KinematicState) -> Profile:
        """Stay at ``state.position`` (or cruise at ``state.velocity``) forever."""
        return Profile(
            np.zeros(1), np.array([state.position]), np.array([state.velocity]),
            np.zeros(1), np.zeros(1),
        )

    @staticmethod
    def concatenate(first: Profile, second: Profile) -> Profile:
        """``second`` starts where ``first`` ends (its open segment is dropped)."""
        return Profile.from_data(_concatenate(first.data, second.data))


@compiled
def _concatenate(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """``Profile.concatenate`` in one pass: every turn and every brake-then-move makes one,
    and as numpy slices it cost four times the copy. ``second``'s times are shifted by the
    end time of ``first``, the addition numpy made."""
    n = first.shape[1] - 1
    m = second.shape[1]
    both = np.empty((5, n + m))
    offset = first[0, n]
    for field in range(5):
        for k in range(n):
            both[field, k] = first[field, k]
    for k in range(m):
        both[0, n + k] = second[0, k] + offset
    for field in range(1, 5):
        for k in range(m):
            both[field, n + k] = second[field, k]
    return both


@compiled
def _position_extrema(data: np.ndarray) -> tuple[float, float]:
    """``Profile.position_extrema`` compiled: segment ends and the instants where the
    velocity v0 + a0 t + j t²/2 is zero inside a segment (position limits of every plan)."""
    t, p, v, a, j = data[0], data[1], data[2], data[3], data[4]
    low = high = p[0]
    for k in range(t.shape[0] - 1):
        dt = t[k + 1] - t[k]
        p0, v0, a0, jk = p[k], v[k], a[k], j[k]
        low, high = min(low, p[k + 1]), max(high, p[k + 1])
        if jk == 0.0:
            if a0 == 0.0:
                continue
            first = second = -v0 / a0
        else:
            disc = a0 * a0 - 2.0 * jk * v0
            if disc < 0.0:
                continue
            root = disc ** 0.5
            first, second = (-a0 - root) / jk, (-a0 + root) / jk
        for tm in (first, second):
            if 0.0 < tm < dt:
                here = p0 + tm * (v0 + tm * (a0 / 2.0 + tm * jk / 6.0))
                low, high = min(low, here), max(high, here)
    return low, high


@compiled
def _velocity_extrema(data: np.ndarray) -> tuple[float, float]:
    """``Profile.velocity_extrema`` compiled: every plan asks it (does a motion turn back?)."""
    t, v, a, j = data[0], data[2], data[3], data[4]
    low = high = v[0]
    for k in range(t.shape[0] - 1):
        dt = t[k + 1] - t[k]
        v0, a0, jk = v[k], a[k], j[k]
        end = v0 + dt * (a0 + dt * jk / 2.0)
        # the integrated end and the next row's own value, which a pinned end state sets
        low, high = min(low, end, v[k + 1]), max(high, end, v[k + 1])
        if jk != 0.0:
            tm = -a0 / jk
            if 0.0 < tm < dt:
                peak = v0 + tm * (a0 + tm * jk / 2.0)
                low, high = min(low, peak), max(high, peak)
    return low, high
