"""Linear gear couplings: slave setpoint = ratio * master setpoint + offset (TcMC §3.17-3.21).

The couplings of all axes are applied in one vectorised pass right after the setpoints are
evaluated; when a master is itself a slave, one coupling at a time, masters before their
slaves whatever order they were made in (D-185; otherwise the slave would follow its master's
previous sample, and jump when the master is released). A dynamic ratio (MC_GearInDyn)
re-anchors the offset whenever it changes, so the slave position stays continuous:
p_s = p_s(previous) + ratio * (p_m - p_m(previous)).
"""

from __future__ import annotations

import numpy as np


class Couplings:
    """Coupled slave rows with their master rows, ratios and offsets, as arrays."""

    def __init__(self) -> None:
        self.slaves = np.zeros(0, dtype=np.int64)
        self.masters = np.zeros(0, dtype=np.int64)
        self.ratio = np.zeros(0)
        self.offset = np.zeros(0)
        self.ratio_rate = np.zeros(0)  #: d(ratio)/dt during a dynamic ratio change [1/s]
        #: a master is itself a slave: the couplings one at a time, masters first
        self._order: list[int] | None = None

    def __contains__(self, row: int) -> bool:
        return bool(np.any(self.slaves == row))

    def couple(self, slave: int, master: int, ratio: float, master_position: float,
               slave_position: float) -> None:
        self.decouple(slave)
        self.slaves = np.append(self.slaves, slave)
        self.masters = np.append(self.masters, master)
        self.ratio = np.append(self.ratio, ratio)
        self.offset = np.append(self.offset, slave_position - ratio * master_position)
        self.ratio_rate = np.append(self.ratio_rate, 0.0)
        self._order = self._masters_first()

    def decouple(self, slave: int) -> None:
        keep = self.slaves != slave
        if keep.all():
            return
        self.slaves, self.masters = self.slaves[keep], self.masters[keep]
        self.ratio, self.offset = self.ratio[keep], self.offset[keep]
        self.ratio_rate = self.ratio_rate[keep]
        self._order = self._masters_first()

    def masters_of(self, row: int) -> list[int]:
        """The rows ``row`` follows, its master first, then that master's master, ..."""
        coupling_of = {int(s): i for i, s in enumerate(self.slaves)}
        chain: list[int] = []
        while row in coupling_of and len(chain) <= len(coupling_of):
            row = int(self.masters[coupling_of[row]])
            chain.append(row)
        return chain

    def _masters_first(self) -> list[int] | None:
        """Coupling indices ordered by how deep their master is in a chain (None: no chain)."""
        if not np.isin(self.masters, self.slaves).any():
            return None
        return sorted(range(self.slaves.size),
                      key=lambda i: len(self.masters_of(int(self.slaves[i]))))

    def set_ratio(self, slave: int, ratio: float, master_position: float, rate: float) -> None:
        """Change the ratio of ``slave`` keeping its position: re-anchor the offset."""
        i = int(np.flatnonzero(self.slaves == slave)[0])
        self.offset[i] += (self.ratio[i] - ratio) * master_position
        self.ratio[i] = ratio
        self.ratio_rate[i] = rate

    def shift(self, slave: int, offset: float) -> None:
        """Move a slave's coupled position by ``offset`` (a finished superposition)."""
        self.offset[self.slaves == slave] += offset

    def ratio_of(self, slave: int) -> float:
        return float(self.ratio[np.flatnonzero(self.slaves == slave)[0]])

    @property
    def chained(self) -> bool:
        """A master is itself a slave: the couplings are applied one at a time."""
        return self._order is not None

    def apply(self, p: np.ndarray, v: np.ndarray, a: np.ndarray, j: np.ndarray,
              overlays: tuple[np.ndarray, ...] | None = None) -> None:
        """Overwrite the slave setpoints from their masters' (one pass per coupling level).

        ``overlays`` (position, velocity, acceleration, jerk and the superimposed mask), with
        a chain only: a slave's superimposed motion is added as soon as it is set, so that
        its own slaves follow its whole setpoint.
        """
        if not self.slaves.size:
            return
        for i in self._order if self._order is not None else (slice(None),):
            s, m, r = self.slaves[i], self.masters[i], self.ratio[i]
            p[s] = r * p[m] + self.offset[i]
            v[s] = r * v[m]
            a[s] = r * a[m] + self.ratio_rate[i] * v[m]
            j[s] = r * j[m]
            if overlays is not None and overlays[4][s]:
                p[s] += overlays[0][s]
                v[s] += overlays[1][s]
                a[s] += overlays[2][s]
                j[s] += overlays[3][s]
