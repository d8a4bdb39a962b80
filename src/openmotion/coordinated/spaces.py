"""Where a group's TCP is in ACS, MCS and PCS, and the maps between them (Part 4 §2.1, §2.2).

A group holds one kinematics (ACS <-> MCS), an MCS offset (MC_GroupSetPosition in MCS, §5.9),
and the PCS: a static Cartesian transform (MC_SetCartesianTransform / MC_SetCoordinateTransform)
composed with an optional moving frame (MC_TrackConveyorBelt, MC_TrackRotaryTable,
MC_SetDynCoordTransform). Paths run in 3-D: ``xyz`` fills x, y, z from the kinematics'
coordinates (0 where a model has none); orientations (a, b, c) are kept aside.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from openmotion.coordinated.frames import DynamicFrame, Frame, FrameMotion
from openmotion.coordinated.kinematics import COORDINATES, CartesianGantry, Kinematics

Array = NDArray[np.float64]
_XYZ = ("x", "y", "z")


def default_kinematics(n_axes: int) -> CartesianGantry:
    """The neutral transformation for ``n_axes`` members: x, y, z, a, b, c in ident order."""
    return CartesianGantry(COORDINATES[:max(1, min(n_axes, len(COORDINATES)))])


class Spaces:
    """The coordinate systems of one group; pure maps, no state of the motion."""

    def __init__(self, kinematics: Kinematics) -> None:
        self.kinematics = kinematics
        self.explicit = False  #: set by MC_SetKinTransform (else rebuilt on regrouping)
        self.mcs_offset = np.zeros(len(kinematics.coordinates))  #: §5.9 SetPosition in MCS
        self.cartesian = Frame()  #: static PCS placement in the MCS
        self.dynamic: DynamicFrame | None = None  #: moving PCS (tracking, §2.2)
        self.configuration = kinematics.default_configuration
        self._refresh()

    def set_kinematics(self, kinematics: Kinematics, explicit: bool = True) -> None:
        self.kinematics = kinematics
        self.explicit = explicit
        self.mcs_offset = np.zeros(len(kinematics.coordinates))
        self.configuration = kinematics.default_configuration
        self._refresh()

    def _refresh(self) -> None:
        coordinates = self.kinematics.coordinates
        self.slots = np.array([coordinates.index(c) for c in _XYZ if c in coordinates],
                              dtype=np.int64)  #: MCS slots holding x, y, z
        self.axes3 = np.array([_XYZ.index(c) for c in _XYZ if c in coordinates],
                              dtype=np.int64)  #: which of x, y, z those are
        self.linear = isinstance(self.kinematics, CartesianGantry)
        self.size = len(coordinates)
        if self.linear:  # acs[k] = sign[k] * (mcs[slot[k]] - offset[k]): no Jacobian needed
            model = self.kinematics
            self._slot, self._sign, self._offset = model.slots, model.signs, model.offsets

    # -- MCS <-> 3-D points ---------------------------------------------------------------------

    def xyz(self, mcs: Array) -> Array:
        """The TCP point of an MCS vector (missing coordinates are 0)."""
        point = np.zeros(3)
        point[self.axes3] = mcs[self.slots]
        return point

    def with_xyz(self, mcs: Array, point: Array) -> Array:
        """``mcs`` with its x, y, z replaced by ``point`` (orientations kept)."""
        out = np.array(mcs, dtype=float)
        out[self.slots] = point[self.axes3]
        return out

    # -- ACS <-> MCS <-> PCS ----------------------------------------------------------------------

    def frame(self, now: float) -> Frame:
        """The PCS placement in the MCS at ``now``: the moving frame replaces the static one
        (a tracking FB and MC_SetCartesianTransform abort each other, §6.6)."""
        if self.dynamic is None:
            return self.cartesian
        return self.dynamic(now).frame

    def frame_motion(self, now: float) -> FrameMotion | None:
        return None if self.dynamic is None else self.dynamic(now)

    def to_mcs(self, acs: Array) -> Array:
        return self.kinematics.forward(acs) + self.mcs_offset

    def to_acs(self, mcs: Array, near: Array | None = None) -> Array:
        """ACS of an MCS vector; ``near``: the axes' positions to stay nearest to, where an
        axis may take whole turns (``Kinematics.inverse``)."""
        if self.linear:
            return (mcs[self._slot] - self.mcs_offset[self._slot] - self._offset) * self._sign
        return self.kinematics.inverse(mcs - self.mcs_offset, self.configuration, near)

    def acs_rates(self, acs: Array, mcs_rates: Array) -> Array:
        """Axis velocities (or, for linear kinematics, accelerations) of MCS rates."""
        if self.linear:
            return mcs_rates[self._slot] * self._sign
        return self.kinematics.inverse_velocity(acs, mcs_rates)

    def pcs_of(self, mcs: Array, now: float) -> Array:
        """PCS coordinates of an MCS vector: the point moves, orientations stay (§2.1)."""
        point = self.frame(now).inverse().apply(self.xyz(mcs))
        return self.with_xyz(mcs, point)

    def mcs_of(self, pcs: Array, now: float) -> Array:
        point = self.frame(now).apply(self.xyz(pcs))
        return self.with_xyz(pcs, point)
