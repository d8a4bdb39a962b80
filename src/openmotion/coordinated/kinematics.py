"""Kinematic transformations ACS <-> MCS (PLCopen Part 4 §2.1.1, §5.8.1: MC_KIN_REF).

The spec leaves the model to the vendor; this module gives one interface and three models: a
Cartesian gantry, a 2-link SCARA and a 3-axis delta robot. Every map is vectorised: pass one
point, shape (n,), or many, shape (m, n).

Units in the public API: linear axes and coordinates in mm, rotary axes and orientations in
degrees, velocities per second. Radians are used inside only.

MCS vectors hold only the coordinates a model drives, in the fixed order of ``COORDINATES``
(x, y, z, a, b, c); ``Kinematics.coordinates`` names them.

Rejections raise ``CommandRejected`` so that the group FB can report them. Targets out of
reach and singular poses are TARGET_UNREACHABLE and KINEMATICS_SINGULAR.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from enum import Enum

import numpy as np
from numpy.typing import ArrayLike, NDArray

from openmotion.coordinated.tolerances import AXIS_LIMIT_TOLERANCE, REACH_TOLERANCE
from openmotion.core.checks import (
    finite_number,
    finite_pair,
    flag,
    non_negative_number,
    positive_number,
)
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId

Array = NDArray[np.float64]
Limits = Sequence[tuple[float, float] | None]  #: per ACS axis: (minimum, maximum) or None

COORDINATES = ("x", "y", "z", "a", "b", "c")  #: MCS slots in their fixed order (§4)
_UNREACHABLE = ErrorId.TARGET_UNREACHABLE
_SINGULAR = ErrorId.KINEMATICS_SINGULAR
_SINGULAR_CONDITION = 1e12  #: a Jacobian worse conditioned than this is not inverted
_DEG = math.pi / 180.0  #: [rad/°] scales the Jacobian's angle columns to the public units


class Configuration(Enum):
    """Which inverse solution to take where a model has several (§2.1.1, Fig. 4).

    For a SCARA, seen from above with the base-to-TCP line pointing away from the viewer,
    ELBOW_DOWN has the elbow on the right (elbow angle in [0, 180]°), ELBOW_UP on the left
    (elbow angle in [-180, 0]°). Drawn in a vertical plane, as Fig. 4 does, these are the
    elbow below and above that line.
    """

    ELBOW_DOWN = "elbow_down"
    ELBOW_UP = "elbow_up"


class Kinematics(ABC):
    """Forward and inverse maps of one machine, with their Jacobian for velocities."""

    configurations: tuple[Configuration, ...] = ()  #: the inverse solutions offered
    default_configuration: Configuration | None = None  #: taken when ``inverse`` gets None

    def __init__(self, n_axes: int, coordinates: tuple[str, ...],
                 limits: Limits | None = None) -> None:
        self.n_axes = n_axes  #: number of ACS axes
        self.coordinates = coordinates  #: names of the MCS coordinates, from COORDINATES
        self.limits = _limit_array(limits, n_axes)  #: (n_axes, 2), ±inf where free [mm or °]

    def forward(self, acs: ArrayLike) -> Array:
        """MCS coordinates of ACS axis positions: where the TCP is."""
        q, single = self._points(acs, self.n_axes, "ACS position")
        x = self._forward(q)
        return x[0] if single else x

    def inverse(self, mcs: ArrayLike, configuration: Configuration | None = None,
                near: ArrayLike | None = None) -> Array:
        """ACS axis positions that put the TCP at ``mcs``, in the chosen configuration.

        ``near`` (ACS positions, one for all points or one per point): where the model has
        axes that may turn by whole turns without moving the TCP (a SCARA's base), take the
        turn nearest to ``near`` rather than the principal angle. A path passes its axes'
        last setpoints here, so that an axis runs on past ±180° instead of jumping a turn.

        Raises CommandRejected for a configuration the model does not offer, a target
        outside the workspace or beyond an axis limit.
        """
        x, single = self._points(mcs, len(self.coordinates), "MCS position")
        q = self._inverse(x, self._chosen(configuration))
        if near is not None:
            reference, _ = self._points(near, self.n_axes, "ACS position")
            q = self._nearest_turn(q, np.broadcast_to(reference, q.shape))
        low, high = self.limits[:, 0], self.limits[:, 1]  # a target on a limit, rounded
        q = np.where((q < low) & (q >= low - AXIS_LIMIT_TOLERANCE), low, q)  # past it, is on it
        q = np.where((q > high) & (q <= high + AXIS_LIMIT_TOLERANCE), high, q)
        bad = np.any((q < self.limits[:, 0]) | (q > self.limits[:, 1]), axis=1)
        self._reject(bad, lambda i: self._limit_message(x[i], q[i]))
        return q[0] if single else q

    def jacobian(self, acs: ArrayLike) -> Array:
        """d mcs / d acs at ``acs`` in public units (mm/°, mm/mm, °/°): (n_coords, n_axes)."""
        q, single = self._points(acs, self.n_axes, "ACS position")
        j = self._jacobian(q)
        return j[0] if single else j

    def forward_velocity(self, acs: ArrayLike, acs_velocity: ArrayLike) -> Array:
        """MCS velocity of the TCP from axis velocities at ``acs`` [mm/s, °/s].

        One velocity per position, or one for all of them.
        """
        q, single = self._points(acs, self.n_axes, "ACS position")
        qd, _ = self._points(acs_velocity, self.n_axes, "ACS velocity")
        v = np.einsum("mij,mj->mi", self._jacobian(q), np.broadcast_to(qd, q.shape))
        return v[0] if single else v

    def inverse_velocity(self, acs: ArrayLike, mcs_velocity: ArrayLike) -> Array:
        """Axis velocities that move the TCP at ``mcs_velocity`` from ``acs``.

        Rejected at a singular pose, where no finite axis velocity gives some TCP velocities.
        """
        q, single = self._points(acs, self.n_axes, "ACS position")
        v, _ = self._points(mcs_velocity, len(self.coordinates), "MCS velocity")
        v = np.broadcast_to(v, (len(q), len(self.coordinates)))
        j = self._jacobian(q)
        bad = np.linalg.cond(j) > _SINGULAR_CONDITION
        self._reject(bad, lambda i: f"ACS position {_fmt(q[i])} is singular: the TCP cannot "
                     "move in every direction there", _SINGULAR)
        qd = np.linalg.solve(j, v[..., None])[..., 0]
        return qd[0] if single else qd

    def configuration(self, acs: ArrayLike) -> Configuration | None:
        """The configuration an ACS position is in; None where the model has one solution."""
        return None

    @abstractmethod
    def _forward(self, q: Array) -> Array:
        """(m, n_axes) -> (m, n_coords)."""

    @abstractmethod
    def _inverse(self, x: Array, configuration: Configuration | None) -> Array:
        """(m, n_coords) -> (m, n_axes); rejects targets out of reach, ignores axis limits."""

    @abstractmethod
    def _jacobian(self, q: Array) -> Array:
        """(m, n_axes) -> (m, n_coords, n_axes) in public units."""

    def _nearest_turn(self, q: Array, near: Array) -> Array:
        """``q`` with its turning axes the whole turns nearest to ``near``; none by default."""
        return q

    def _points(self, values: ArrayLike, n: int, space: str) -> tuple[Array, bool]:
        """Values as (m, n) and whether one point came in; bad input is an FB input error."""
        error_id = ErrorId.INVALID_VELOCITY if "velocity" in space else ErrorId.INVALID_POSITION
        a = np.asarray(values, dtype=float)
        if a.ndim not in (1, 2) or a.shape[-1] != n:
            raise CommandRejected(error_id, f"{type(self).__name__}: an {space} needs {n} "
                                  f"values, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise CommandRejected(error_id, f"{type(self).__name__}: {space} values must be "
                                  f"finite, got {a.tolist()}")
        return np.atleast_2d(a), a.ndim == 1

    def _chosen(self, configuration: Configuration | None) -> Configuration | None:
        if configuration is None:
            return self.default_configuration
        if configuration not in self.configurations:
            offered = ", ".join(c.name for c in self.configurations) or "none"
            raise CommandRejected(ErrorId.INVALID_CONFIGURATION,
                                  f"{type(self).__name__}: no configuration {configuration!r}; "
                                  f"it offers: {offered}")
        return configuration

    def _reject(self, bad: NDArray[np.bool_], describe: Callable[[int], str],
                error_id: ErrorId = _UNREACHABLE) -> None:
        """Raise for the first bad point, naming it when there are several."""
        if not np.any(bad):
            return
        i = int(np.argmax(bad))
        where = f" (point {i} of {len(bad)})" if len(bad) > 1 else ""
        raise CommandRejected(error_id, f"{type(self).__name__}: {describe(i)}{where}")

    def _limit_message(self, x: Array, q: Array) -> str:
        k = int(np.argmax((q < self.limits[:, 0]) | (q > self.limits[:, 1])))
        low, high = self.limits[k]
        return (f"MCS position {_fmt(x)} needs axis {k + 1} at {q[k]:.6g}, outside its "
                f"limits [{low:g}, {high:g}]")


class CartesianGantry(Kinematics):
    """Axes that move along (or turn about) MCS directions: a gantry or handling (§2.1.1).

    ``mapping[k]`` names the MCS coordinate ACS axis k drives, so that
    ``mcs[mapping[k]] = sign[k] * acs[k] + offset[k]``. With mapping ("x", "y", "z"), no
    signs and no offsets it is the neutral transformation of §5.8.1 (MCS = ACS).
    """

    def __init__(self, mapping: Sequence[str] = ("x", "y", "z"), *,
                 sign: Sequence[float] | None = None,
                 offset: Sequence[float] | None = None) -> None:
        mapping = tuple(mapping)  # keeps the caller's list from changing the model later
        if not mapping or len(set(mapping)) != len(mapping) or not set(mapping) <= {*COORDINATES}:
            raise ConfigError(f"mapping: must name distinct coordinates of {COORDINATES}, "
                              f"got {mapping}")
        n = len(mapping)
        signs = np.ones(n) if sign is None else _numbers(sign, n, "sign")
        offsets = np.zeros(n) if offset is None else _numbers(offset, n, "offset")
        if not np.all(np.abs(signs) == 1.0):
            raise ConfigError(f"sign: must be {n} values of +1 or -1, got {signs.tolist()}")
        super().__init__(n, tuple(c for c in COORDINATES if c in mapping))
        self.mapping = mapping  #: the MCS coordinate of each ACS axis
        #: the MCS slot of each ACS axis: acs[k] = signs[k] * (mcs[slots[k]] - offsets[k])
        self.slots = np.array([self.coordinates.index(c) for c in mapping])
        self.signs = signs  #: +1 or -1 per ACS axis
        self.offsets = offsets  #: [mm] per ACS axis

    def _forward(self, q: Array) -> Array:
        x = np.empty_like(q)
        x[:, self.slots] = self.signs * q + self.offsets
        return x

    def _inverse(self, x: Array, configuration: Configuration | None) -> Array:
        return (x[:, self.slots] - self.offsets) * self.signs

    def _jacobian(self, q: Array) -> Array:
        j = np.zeros((self.n_axes, self.n_axes))
        j[self.slots, np.arange(self.n_axes)] = self.signs
        return np.broadcast_to(j, (len(q), self.n_axes, self.n_axes)).copy()


class Scara(Kinematics):
    """A 2-link SCARA arm in the x-y plane, optionally with a z axis and a tool axis (§2.1.1).

    ACS: (theta1 [°], theta2 [°], [z [mm]], [theta4 [°]]); MCS: (x, y, [z], [c]). theta1
    turns link 1 from the x axis, theta2 turns link 2 against link 1, both counter-clockwise
    seen from above. z passes through; the tool axis theta4 sits on link 2, so the tool's
    orientation is c = theta1 + theta2 + theta4.

    The workspace is the ring |l1 - l2| <= r <= l1 + l2 around the base, cut by the axis
    ``limits``. On its borders (arm stretched or folded) both configurations meet and the
    Jacobian is singular.
    """

    configurations = (Configuration.ELBOW_DOWN, Configuration.ELBOW_UP)
    default_configuration = Configuration.ELBOW_DOWN

    def __init__(self, l1: float, l2: float, *, z_axis: bool = False, c_axis: bool = False,
                 limits: Limits | None = None) -> None:
        l1, l2 = positive_number(l1, "l1"), positive_number(l2, "l2")  # link lengths [mm]
        flag(z_axis, "z_axis"), flag(c_axis, "c_axis")
        coordinates = ("x", "y") + ("z",) * z_axis + ("c",) * c_axis
        super().__init__(len(coordinates), coordinates, limits)
        self.l1 = l1  #: length of link 1, base axis to elbow axis [mm]
        self.l2 = l2  #: length of link 2, elbow axis to TCP [mm]
        self.z_axis = z_axis
        self.c_axis = c_axis

    def _forward(self, q: Array) -> Array:
        t1, t12 = np.radians(q[:, 0]), np.radians(q[:, 0] + q[:, 1])
        x = self.l1 * np.cos(t1) + self.l2 * np.cos(t12)
        y = self.l1 * np.sin(t1) + self.l2 * np.sin(t12)
        columns = [x, y]
        if self.z_axis:
            columns.append(q[:, 2])
        if self.c_axis:
            columns.append(q[:, 0] + q[:, 1] + q[:, -1])
        return np.stack(columns, axis=1)

    def _inverse(self, x: Array, configuration: Configuration | None) -> Array:
        l1, l2 = self.l1, self.l2
        r = np.hypot(x[:, 0], x[:, 1])
        outer, inner = r - (l1 + l2), abs(l1 - l2) - r
        self._reject((outer > REACH_TOLERANCE) | (inner > REACH_TOLERANCE), lambda i: (
            f"MCS position {_fmt(x[i, :2])} is out of reach: {r[i]:.6g} mm from the base, "
            f"the arm reaches {abs(l1 - l2):g} to {l1 + l2:g} mm"))
        # sin(theta2) from the two distances to the borders: accurate where 1 - cos^2 is not
        s2 = np.sqrt(np.maximum(-outer, 0.0) * (l1 + l2 + r)
                     * np.maximum(-inner, 0.0) * (r + abs(l1 - l2))) / (2.0 * l1 * l2)
        if configuration is Configuration.ELBOW_UP:
            s2 = -s2
        c2 = (r * r - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
        t2 = np.arctan2(s2, c2)
        t1 = np.arctan2(x[:, 1], x[:, 0]) - np.arctan2(l2 * s2, l1 + l2 * c2)
        q = np.stack([_fit_turn(_principal(np.degrees(t1)), self.limits[0]),
                      _fit_turn(np.degrees(t2), self.limits[1])], axis=1)
        if self.z_axis:
            q = np.column_stack([q, x[:, 2]])
        if self.c_axis:
            q = np.column_stack([q, x[:, -1] - q[:, 0] - q[:, 1]])
        return q

    def _jacobian(self, q: Array) -> Array:
        t1, t12 = np.radians(q[:, 0]), np.radians(q[:, 0] + q[:, 1])
        j = np.zeros((len(q), self.n_axes, self.n_axes))
        j[:, 0, 1] = -self.l2 * np.sin(t12) * _DEG
        j[:, 0, 0] = -self.l1 * np.sin(t1) * _DEG + j[:, 0, 1]
        j[:, 1, 1] = self.l2 * np.cos(t12) * _DEG
        j[:, 1, 0] = self.l1 * np.cos(t1) * _DEG + j[:, 1, 1]
        if self.z_axis:
            j[:, 2, 2] = 1.0
        if self.c_axis:
            j[:, -1, [0, 1, -1]] = 1.0
        return j

    def _nearest_turn(self, q: Array, near: Array) -> Array:
        """The base axis a whole number of turns nearer to ``near``; the tool axis turns back
        as many, so that c = theta1 + theta2 + theta4 stays. The elbow stays in its
        configuration's half turn."""
        turns = 360.0 * np.round((near[:, 0] - q[:, 0]) / 360.0)
        q = q.copy()
        q[:, 0] += turns
        if self.c_axis:
            q[:, -1] -= turns
        return q

    def configuration(self, acs: ArrayLike) -> Configuration | None:
        """ELBOW_DOWN for an elbow angle in [0, 180]° (modulo 360°), else ELBOW_UP."""
        q, _ = self._points(acs, self.n_axes, "ACS position")
        if len(q) != 1:
            raise ValueError("configuration: one ACS position at a time")
        elbow = math.remainder(float(q[0, 1]), 360.0)
        return Configuration.ELBOW_DOWN if elbow >= 0.0 or elbow == -180.0 \
            else Configuration.ELBOW_UP


class DeltaRobot(Kinematics):
    """A 3-axis delta robot: three rotary arms carry a platform that keeps its orientation.

    MCS origin at the centre of the base, z up, the platform below. Arm k (k = 1, 2, 3) turns
    about an axis at ``base_radius`` from the centre, at azimuth 120°·(k - 1) from the x
    axis; its angle is 0 with the upper arm horizontal and pointing outwards, positive
    turning it down. Its forearm (a parallelogram) of length ``forearm`` joins the elbow to
    the platform at ``effector_radius`` from the TCP, at the same azimuth.
    ACS: (theta1, theta2, theta3) [°]; MCS: (x, y, z) [mm].

    Both maps are exact (closed form). Forward takes the platform below the elbows; inverse
    keeps every elbow outside the line from its shoulder to its wrist (knees out). That is
    how delta robots are built, so there is no configuration to choose.
    """

    def __init__(self, base_radius: float, effector_radius: float, upper_arm: float,
                 forearm: float, *, limits: Limits | None = None) -> None:
        base_radius = non_negative_number(base_radius, "base_radius")
        effector_radius = non_negative_number(effector_radius, "effector_radius")
        upper_arm, forearm = positive_number(upper_arm, "upper_arm"), positive_number(
            forearm, "forearm")
        super().__init__(3, ("x", "y", "z"), limits)
        self.base_radius = base_radius  #: centre of the base to an arm's axis [mm]
        self.effector_radius = effector_radius  #: TCP to a forearm's platform joint [mm]
        self.upper_arm = upper_arm  #: arm axis to elbow [mm]
        self.forearm = forearm  #: elbow to platform joint [mm]
        azimuth = np.radians([0.0, 120.0, 240.0])
        self._u = np.stack([np.cos(azimuth), np.sin(azimuth), np.zeros(3)], axis=1)
        self._scale = base_radius + effector_radius + upper_arm + forearm

    def _centres(self, q: Array) -> Array:
        """(m, 3 arms, 3): the elbows moved in by the effector radius, one sphere each."""
        t = np.radians(q)
        radial = self.base_radius - self.effector_radius + self.upper_arm * np.cos(t)
        centres = radial[..., None] * self._u
        centres[..., 2] = -self.upper_arm * np.sin(t)
        return centres

    def _forward(self, q: Array) -> Array:
        c = self._centres(q)
        a, b = c[:, 0] - c[:, 2], c[:, 1] - c[:, 2]
        n = np.cross(a, b)
        nn = np.einsum("mi,mi->m", n, n)
        self._reject(nn <= (1e-12 * self._scale**2) ** 2, lambda i: (
            f"ACS position {_fmt(q[i])} puts the three elbows in line"), _SINGULAR)
        aa, bb = np.einsum("mi,mi->m", a, a), np.einsum("mi,mi->m", b, b)
        centre = c[:, 2] + np.cross(aa[:, None] * b - bb[:, None] * a, n) / (2.0 * nn[:, None])
        h2 = self.forearm**2 - np.einsum("mi,mi->m", centre - c[:, 0], centre - c[:, 0])
        self._reject(h2 < -REACH_TOLERANCE * self.forearm, lambda i: (
            f"ACS position {_fmt(q[i])} cannot be assembled: the elbows are more than two "
            "forearms apart"))
        down = np.where(n[:, 2:] >= 0.0, 1.0, -1.0) * n / np.sqrt(nn)[:, None]
        return centre - np.sqrt(np.maximum(h2, 0.0))[:, None] * down

    def _inverse(self, x: Array, configuration: Configuration | None) -> Array:
        w = x[:, None, :] + (self.effector_radius - self.base_radius) * self._u
        along, height = np.einsum("mki,ki->mk", w, self._u), w[..., 2]
        cos_term, sin_term = 2.0 * self.upper_arm * along, -2.0 * self.upper_arm * height
        rest = np.einsum("mki,mki->mk", w, w) + self.upper_arm**2 - self.forearm**2
        reach = np.hypot(cos_term, sin_term)
        ratio = rest / np.maximum(reach, 1e-300)
        bad = np.abs(ratio) > 1.0 + 1e-12
        self._reject(np.any(bad, axis=1), lambda i: (
            f"MCS position {_fmt(x[i])} is out of reach of arm {int(np.argmax(bad[i])) + 1}"))
        theta = np.arctan2(sin_term, cos_term) - np.arccos(np.clip(ratio, -1.0, 1.0))
        return _principal(np.degrees(theta))

    def _jacobian(self, q: Array) -> Array:
        p, t = self._forward(q), np.radians(q)
        arms = p[:, None, :] - self._centres(q)
        turn = -self.upper_arm * (np.sin(t)[..., None] * self._u)
        turn[..., 2] = -self.upper_arm * np.cos(t)
        drive = np.einsum("mki,mki->mk", arms, turn)
        self._reject(np.linalg.cond(arms) > _SINGULAR_CONDITION, lambda i: (
            f"ACS position {_fmt(q[i])} is singular: the forearms cannot hold the platform"),
            _SINGULAR)
        return np.linalg.solve(arms, drive[..., None] * np.eye(3)) * _DEG


def _fit_turn(angle: Array, limits: Array) -> Array:
    """Shift angles by a full turn where that brings them inside the axis limits (or a
    rounding beyond one, which ``Kinematics.inverse`` puts on it)."""
    low, high = limits[0] - AXIS_LIMIT_TOLERANCE, limits[1] + AXIS_LIMIT_TOLERANCE
    for shift in (360.0, -360.0):
        outside = (angle < low) | (angle > high)
        moved = angle + shift
        angle = np.where(outside & (moved >= low) & (moved <= high), moved, angle)
    return angle


def _principal(angle: Array) -> Array:
    """Angles in (-180, 180] [°]."""
    return 180.0 - np.remainder(180.0 - angle, 360.0)


def _limit_array(limits: Limits | None, n_axes: int) -> Array:
    array = np.tile([-np.inf, np.inf], (n_axes, 1))
    if limits is None:
        return array
    if isinstance(limits, str | bytes) or not hasattr(limits, "__len__") or \
            len(limits) != n_axes:
        raise ConfigError(f"limits: need {n_axes} entries (one per axis), got {limits!r}")
    for k, pair in enumerate(limits):
        if pair is None:
            continue
        low, high = finite_pair(pair, f"limits[{k}]")
        if not low < high:
            raise ConfigError(f"limits[{k}]: need finite minimum < maximum, got {pair}")
        array[k] = low, high
    return array


def _numbers(values: object, n: int, field: str) -> Array:
    """``n`` finite numbers, one per axis."""
    if isinstance(values, str | bytes) or not hasattr(values, "__len__") or len(values) != n:
        raise ConfigError(f"{field}: must be {n} values, got {values!r}")
    return np.array([finite_number(v, f"{field}[{k}]") for k, v in enumerate(values)])


def _fmt(values: Array) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in values) + ")"
