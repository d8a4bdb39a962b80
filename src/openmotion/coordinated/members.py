"""The member axes of an axes group (Part 4 §4, §3.2): who they are, by IdentInGroup, and what
the group does to their kernel rows - the path output, holding, braking and settling.

A read-only mapping IdentInGroup -> axis, so ``group.members[1]`` and ``len(group.members)``
read as before; the group adds and removes members through ``add``, ``pop`` and ``clear``.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from typing import TYPE_CHECKING

import numpy as np

from openmotion.core.enums import AxisState
from openmotion.trajectory.plan import plan_stop
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.coordinated.group import AxesGroup

#: a setpoint the group wrote counts as the last one for this many cycles (a reaction in the
#: cycle after the path output still starts from it)
WRITTEN_CYCLES = 1.5


class GroupMembers(Mapping[int, "Axis"]):
    """IdentInGroup -> axis, and the members' setpoints as the group drives them."""

    def __init__(self, group: AxesGroup) -> None:
        self.group = group
        self.kernel, self.runtime = group.kernel, group.runtime
        self._by_ident: dict[int, Axis] = {}  #: in insertion order
        self._axes: list[Axis] = []  #: in IdentInGroup order
        self._rows = np.zeros(0, dtype=np.int64)
        self.solo: dict[int, Axis] = {}  #: members running their own MC_Stop / MC_Home, by row
        self.last_states: dict[int, AxisState] = {}  #: member states the group has seen, by row
        self._written: tuple[float, np.ndarray, np.ndarray, np.ndarray] | None = None

    # -- the mapping ---------------------------------------------------------------------------

    def __getitem__(self, ident: int) -> Axis:
        return self._by_ident[ident]

    def __iter__(self) -> Iterator[int]:
        return iter(self._by_ident)

    def __len__(self) -> int:
        return len(self._by_ident)

    def __repr__(self) -> str:
        return repr(self._by_ident)

    def add(self, ident: int, axis: Axis) -> None:
        self._by_ident[ident] = axis
        self._reorder()

    def pop(self, ident: int) -> Axis:
        axis = self._by_ident.pop(ident)
        self._reorder()
        return axis

    def clear(self) -> None:
        self._by_ident.clear()
        self._reorder()

    def _reorder(self) -> None:
        self._axes = [self._by_ident[i] for i in sorted(self._by_ident)]
        self._rows = np.array([a.row for a in self._axes], dtype=np.int64)
        self._rows.flags.writeable = False

    @property
    def axes(self) -> list[Axis]:
        """Members in IdentInGroup order (the ACS order, §5.10)."""
        return list(self._axes)

    @property
    def rows(self) -> np.ndarray:
        """Their kernel rows, in the same order (read-only)."""
        return self._rows

    @property
    def standing(self) -> bool:
        """No member's setpoint moves or accelerates."""
        k, rows = self.kernel, self._rows
        return bool(np.all(k.set_v[rows] == 0.0) and np.all(k.set_a[rows] == 0.0))

    # -- leaving the group -------------------------------------------------------------------

    def release(self, axis: Axis) -> None:
        """``axis`` leaves the group: it stands on its own again."""
        axis.group = None
        self.solo.pop(axis.row, None)
        if axis.state is AxisState.SYNCHRONIZED_MOTION:
            axis.state = AxisState.STANDSTILL
        self.last_states.pop(axis.row, None)

    @contextmanager
    def ungrouped(self, axis: Axis) -> Iterator[None]:
        """Let the group issue a single-axis command to its member (home, set position)."""
        axis.group = None
        try:
            yield
        finally:
            axis.group = self.group

    def solo_running(self) -> bool:
        """A member's own MC_Stop or MC_Home runs or is held, or the members still brake
        after it; once all is over the members follow the group again."""
        if not self.solo:
            return False
        own = (AxisState.STOPPING, AxisState.HOMING)
        if self.standing and not any(a.state in own or a.has_job for a in self.solo.values()):
            self.solo = {}
            return False
        return True

    # -- setpoints -----------------------------------------------------------------------------

    def write_setpoints(self, p: np.ndarray, v: np.ndarray, a: np.ndarray,
                        j: np.ndarray | None = None) -> None:
        """The path cycle's output: the member rows' setpoints, after the kernel evaluated."""
        k, rows = self.kernel, self._rows
        k.set_p[rows], k.set_v[rows], k.set_a[rows] = p, v, a
        k.set_j[rows] = 0.0 if j is None else j
        self._written = (self.runtime.now, np.array(p, dtype=float), np.array(v, dtype=float),
                         np.array(a, dtype=float))

    def last_setpoints(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The members' setpoints as the group last wrote them: in a cycle where the group
        reacts before its path output (a fault, a power loss), the kernel has already
        evaluated the rows' own resting profiles, which lag behind the path."""
        k, rows = self.kernel, self._rows
        written = self._written
        if written is not None and written[1].shape == rows.shape \
                and written[0] >= self.runtime.now - WRITTEN_CYCLES * self.runtime.cycle_time:
            return written[1], written[2], written[3]
        return k.set_p[rows].copy(), k.set_v[rows].copy(), k.set_a[rows].copy()

    def settle(self, p: np.ndarray) -> None:
        """The path ended at ``p``: the rows hold there on their own profiles."""
        k = self.kernel
        self._written = None
        for row, value in zip(self._rows.tolist(), p.tolist(), strict=True):
            k.set_p[row] = value
            k.set_v[row] = k.set_a[row] = k.set_j[row] = 0.0
            k.segments.install(row, Profile.hold(KinematicState(value)), k.sample_time)

    def hold(self) -> None:
        """Stop at once where the setpoints are (GroupDisable, power loss)."""
        k = self.kernel
        p, _, _ = self.last_setpoints()
        for axis, value in zip(self._axes, p.tolist(), strict=True):
            row = axis.row
            k.set_p[row] = value
            k.set_v[row] = k.set_a[row] = k.set_j[row] = 0.0
            k.segments.install(row, Profile.hold(KinematicState(value)), k.sample_time)
        self._written = None

    def brake(self) -> None:
        """Each healthy member brakes on its own profile (the group error reaction)."""
        k = self.kernel
        p, v, a = self.last_setpoints()
        for index, axis in enumerate(self._axes):
            if axis.state is AxisState.ERROR_STOP:
                continue
            row = axis.row
            start = KinematicState(float(p[index]), float(v[index]), float(a[index]))
            profile = plan_stop(start, axis.parameters.max_deceleration, axis.parameters.max_jerk)
            k.segments.install(row, profile, k.sample_time)
            k.set_p[row], k.set_v[row], k.set_a[row] = start.position, start.velocity, \
                start.acceleration
        self._written = None
