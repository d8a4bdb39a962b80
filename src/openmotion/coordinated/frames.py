"""Rigid 3-D frames between MCS and PCS (PLCopen Part 4 §2.1, §2.2, §5.8.2, §5.8.3).

A ``Frame`` places a child frame (a PCS) in its parent (the MCS): a point given in the child
has the parent coordinates ``p_parent = R @ p_child + t``, where ``t`` is the child's origin
seen from the parent and the columns of ``R`` are the child's axes seen from the parent.

The six values of MC_SetCartesianTransform (TransX, TransY, TransZ, RotAngle1..3) are read
as follows; §5.8.2 leaves the order to the vendor and says only that the rotation turns
about every coordinate direction in turn, starting with Z, and its planar example puts the
angle in the sixth slot:

* ``trans_x, trans_y, trans_z`` [mm]: the PCS origin in MCS coordinates;
* ``rot_angle3`` [°] about Z first, then ``rot_angle2`` [°] about the new Y, then
  ``rot_angle1`` [°] about the newest X (intrinsic Z-Y'-X''), so that
  ``R = Rz(rot_angle3) @ Ry(rot_angle2) @ Rx(rot_angle1)``; positive angles turn
  counter-clockwise looking down the axis (right-hand rule).

Angles are degrees in the public API and radians inside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from openmotion.coordinated.tolerances import GIMBAL_LOCK, ORTHONORMAL_TOLERANCE
from openmotion.core.angles import cos_sin
from openmotion.core.checks import finite_number
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId


class CartesianTransform(NamedTuple):
    """The six inputs of MC_SetCartesianTransform (§5.8.2), read as the module docstring says."""

    trans_x: float = 0.0  #: [mm]
    trans_y: float = 0.0  #: [mm]
    trans_z: float = 0.0  #: [mm]
    rot_angle1: float = 0.0  #: about X, applied last [°]
    rot_angle2: float = 0.0  #: about Y [°]
    rot_angle3: float = 0.0  #: about Z, applied first [°]


class Frame:
    """A child frame placed in its parent frame: a rotation and a translation.

    Immutable; the arrays it returns are read-only views.
    """

    __slots__ = ("_rotation", "_translation")

    def __init__(self, rotation: ArrayLike | None = None,
                 translation: ArrayLike = (0.0, 0.0, 0.0)) -> None:
        try:
            r = np.eye(3) if rotation is None else np.array(rotation, dtype=float)
            t = np.array(translation, dtype=float)
        except (TypeError, ValueError):  # text, None, ragged lists
            raise ConfigError(f"a frame needs a 3x3 rotation and 3 translation numbers, got "
                              f"{rotation!r}, {translation!r}") from None
        if r.shape != (3, 3) or not np.all(np.isfinite(r)):
            raise ConfigError(f"rotation: must be a finite 3x3 matrix, got {r.tolist()}")
        if (not np.allclose(r.T @ r, np.eye(3), rtol=0.0, atol=ORTHONORMAL_TOLERANCE)
                or np.linalg.det(r) < 0.0):
            raise ConfigError(f"rotation: must be orthonormal with det +1, got {r.tolist()}")
        if t.shape != (3,) or not np.all(np.isfinite(t)):
            raise ConfigError(f"translation: must be 3 finite values, got {t.tolist()}")
        self._set(r, t)

    def _set(self, rotation: NDArray[np.float64], translation: NDArray[np.float64]) -> None:
        rotation.flags.writeable = False
        translation.flags.writeable = False
        self._rotation = rotation
        self._translation = translation

    @classmethod
    def _trusted(cls, rotation: NDArray[np.float64], translation: NDArray[np.float64]) -> Frame:
        """Skip the checks for results of our own products, which are rotations already."""
        frame = cls.__new__(cls)
        cls._set(frame, rotation, translation)
        return frame

    @classmethod
    def from_cartesian(cls, trans_x: float = 0.0, trans_y: float = 0.0, trans_z: float = 0.0,
                       rot_angle1: float = 0.0, rot_angle2: float = 0.0,
                       rot_angle3: float = 0.0) -> Frame:
        """The frame MC_SetCartesianTransform sets (§5.8.2); all zeros give the identity.

        These are FB inputs, so a value that is not finite is a rejected command
        (INVALID_PARAMETER_VALUE), not a configuration error.
        """
        values = CartesianTransform(trans_x, trans_y, trans_z, rot_angle1, rot_angle2, rot_angle3)
        for name, value in zip(CartesianTransform._fields, values, strict=True):
            if not math.isfinite(value):
                raise CommandRejected(ErrorId.INVALID_PARAMETER_VALUE,
                                      f"Cartesian transform: {name} must be finite, got {value}")
        rotation = _rot_z(rot_angle3) @ _rot_y(rot_angle2) @ _rot_x(rot_angle1)
        return cls._trusted(rotation, np.array([trans_x, trans_y, trans_z], dtype=float))

    def cartesian(self) -> CartesianTransform:
        """The six values that give this frame back (MC_ReadCartesianTransform, §5.8.5).

        Angles come back in (-180, 180], rot_angle2 in [-90, 90]. At rot_angle2 = ±90° only
        the difference (or sum) of the other two angles is defined; rot_angle1 is then 0.
        """
        r = self._rotation
        cos2 = math.hypot(r[0, 0], r[1, 0])
        angle2 = math.atan2(-r[2, 0], cos2)
        if cos2 > GIMBAL_LOCK:
            angle1 = math.atan2(r[2, 1], r[2, 2])
            angle3 = math.atan2(r[1, 0], r[0, 0])
        else:
            angle1 = 0.0
            angle3 = math.atan2(-r[0, 1], r[1, 1])
        x, y, z = (float(v) for v in self._translation)
        return CartesianTransform(x, y, z, *(_degrees(a) for a in (angle1, angle2, angle3)))

    @property
    def rotation(self) -> NDArray[np.float64]:
        """R: the child's axes as columns, in parent coordinates."""
        return self._rotation

    @property
    def translation(self) -> NDArray[np.float64]:
        """t: the child's origin in parent coordinates [mm]."""
        return self._translation

    def matrix(self) -> NDArray[np.float64]:
        """The 4x4 homogeneous matrix [[R, t], [0, 1]]."""
        m = np.eye(4)
        m[:3, :3] = self._rotation
        m[:3, 3] = self._translation
        return m

    def compose(self, inner: Frame) -> Frame:
        """``inner``, given in this frame's child, placed in this frame's parent.

        Chaining transforms that are active together (§5.8.2: more than one may be) is
        ``first.compose(second)`` when ``second`` is given in the frame ``first`` sets up.
        """
        return Frame._trusted(self._rotation @ inner._rotation,
                              self._rotation @ inner._translation + self._translation)

    def shifted(self, shift: NDArray[np.float64]) -> Frame:
        """The same frame with its origin moved by ``shift`` in the parent [mm]."""
        return Frame._trusted(self._rotation, self._translation + shift)

    def inverse(self) -> Frame:
        """The parent placed in the child: turns MCS coordinates into PCS coordinates."""
        rotation = self._rotation.T.copy()
        return Frame._trusted(rotation, -(rotation @ self._translation))

    def apply(self, positions: ArrayLike) -> NDArray[np.float64]:
        """Positions given in the child, in parent coordinates [mm]; shape (3,) or (n, 3)."""
        p = _vectors(positions)
        return p @ self._rotation.T + self._translation

    def rotate(self, vectors: ArrayLike) -> NDArray[np.float64]:
        """Free vectors (velocities, accelerations) from the child into the parent.

        A static frame adds no motion of its own, so only the rotation acts; for a moving
        frame use ``FrameMotion.point_velocity``.
        """
        return _vectors(vectors) @ self._rotation.T

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Frame):
            return NotImplemented
        return (np.array_equal(self._rotation, other._rotation)
                and np.array_equal(self._translation, other._translation))

    def __hash__(self) -> int:
        return hash((self._rotation.tobytes(), self._translation.tobytes()))

    def __repr__(self) -> str:
        return f"Frame.from_cartesian{tuple(round(v, 9) for v in self.cartesian())}"


class FrameMotion(NamedTuple):
    """Where a moving frame is at one instant and how fast it moves (§2.2)."""

    frame: Frame  #: the child placed in the parent at that instant
    velocity: NDArray[np.float64]  #: velocity of the child's origin, in the parent [mm/s]
    angular_velocity: NDArray[np.float64]  #: angular velocity, in the parent [°/s]

    def point_velocity(self, positions: ArrayLike,
                       velocities: ArrayLike = (0.0, 0.0, 0.0)) -> NDArray[np.float64]:
        """Parent velocities of points moving at ``velocities`` in the child [mm/s].

        The rigid-body rule v = v_origin + w x (R p) + R v_child: a point that holds its
        place in a dynamic PCS moves in MCS with the frame (§2.2).
        """
        arm = _vectors(positions) @ self.frame.rotation.T
        spin = np.cross(np.radians(self.angular_velocity), arm)
        return self.velocity + spin + self.frame.rotate(velocities)


class DynamicFrame(Protocol):
    """A PCS that moves relative to the MCS (§2.2): conveyor belts, rotary tables (§6.6, §6.7)."""

    def __call__(self, now: float) -> FrameMotion:
        """The frame and its velocity at time ``now`` [s]."""
        ...


@dataclass(frozen=True, slots=True)
class LinearFrame:
    """A frame sliding without turning at a constant velocity: a product on a belt (§6.6)."""

    start: Frame  #: the placement at ``start_time``
    velocity: tuple[float, float, float]  #: velocity of the frame, in the parent [mm/s]
    start_time: float = 0.0  #: [s]

    def __post_init__(self) -> None:
        if not isinstance(self.start, Frame):
            raise ConfigError(f"start: must be a Frame, got {type(self.start).__name__}")
        velocity = self.velocity
        if isinstance(velocity, str | bytes) or not hasattr(velocity, "__len__") or \
                len(velocity) != 3:
            raise ConfigError(f"velocity: must be 3 finite values, got {velocity!r}")
        for k, value in enumerate(velocity):
            finite_number(value, f"velocity[{k}]")
        finite_number(self.start_time, "start_time")

    def __call__(self, now: float) -> FrameMotion:
        velocity = np.array(self.velocity, dtype=float)
        shift = velocity * (now - self.start_time)
        return FrameMotion(self.start.shifted(shift), velocity, np.zeros(3))


def _vectors(values: ArrayLike) -> NDArray[np.float64]:
    v = np.asarray(values, dtype=float)
    if v.shape[-1:] != (3,) or v.ndim > 2:
        raise ValueError(f"expected shape (3,) or (n, 3), got {v.shape}")
    return v


def _degrees(radians: float) -> float:
    """Degrees in (-180, 180], so that a turn read back is the one set."""
    angle = math.degrees(radians) + 0.0  # + 0.0 turns -0.0 into 0.0
    return 180.0 if angle == -180.0 else angle


def _rot_x(angle: float) -> NDArray[np.float64]:
    c, s = cos_sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rot_y(angle: float) -> NDArray[np.float64]:
    c, s = cos_sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rot_z(angle: float) -> NDArray[np.float64]:
    c, s = cos_sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
