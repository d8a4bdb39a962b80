"""Geo-compensation of a CA group: the starter-kit geometry, mover templates and the TCP path
(TF5410 §4.1, §8.2, §9.2; docs/collision-avoidance.md, D-070 to D-073).

Setpoints always live on the motor path. A mover template shifts the tool centre point (TCP)
outward by ``y_shift``, perpendicular to the motor path, so that on the arc length ``x`` of
the motor path (the absolute position) the TCP path has the arc length

    tcp(x) = F(x + rail_offset) - F(rail_offset),   F(s) = s + y * turned(s)

where ``turned(s)`` is the angle the path has turned after the arc length ``s``: 0 along a
straight, ``1/R`` per mm in a curve. So ``ds_tcp = ds_motor`` on straights,
``ds_tcp = ds_motor * (R + y) / R`` in curves, and one TCP lap is ``rail_length + 2 pi y``.
Both maps are monotone bijections of the real line, exact up to float rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.checks import finite_number, non_negative_number
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.trajectory.plan import Limits, plan_stop
from openmotion.trajectory.segments import KinematicState
from openmotion.transport.enums import CompensationType

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.transport.group import CaGroup, CaJob

#: the curve radius we assume [mm]: a 180° arc of 500 mm (two 250 mm XTS motor modules), so
#: the 3000 mm starter kit has two 1000 mm straights. The manual gives no radius (D-070).
STARTER_KIT_CURVE_RADIUS = 500.0 / math.pi


@dataclass(frozen=True)
class StarterKitGeometry:
    """The XTS standard object: two 180° curves joined by two equal straights (§4.1).

    The arc length ``s`` of the motor path starts where the upper-left curve ends, before the
    first straight, and counts clockwise as seen in the manual's figure: the upper straight
    (left to right), the right curve, the lower straight (right to left), the left curve. The
    absolute position is ``x = s - rail_offset``: a positive offset moves the zero further
    along the path (D-070).
    """

    rail_length: float = 3000.0  #: motor path of both curves and both straights [mm]
    curve_radius: float = STARTER_KIT_CURVE_RADIUS  #: radius of the motor path in curves [mm]
    rail_offset: float = 0.0  #: zero shift of the absolute position along the path [mm]
    _s: np.ndarray = field(init=False, repr=False, compare=False)
    _turned: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("rail_length", "curve_radius", "rail_offset"):
            finite_number(getattr(self, name), f"StarterKitGeometry.{name}")
        if self.curve_radius <= 0.0 or 2.0 * math.pi * self.curve_radius >= self.rail_length:
            raise ConfigError(f"StarterKitGeometry: curve_radius {self.curve_radius:g} must be "
                              f"> 0 and leave straights: 2 pi R < rail_length "
                              f"{self.rail_length:g}")
        straight, arc = self.straight_length, math.pi * self.curve_radius
        # breakpoints of one lap and the angle turned there: straight, curve, straight, curve
        s = np.cumsum([0.0, straight, arc, straight, arc])
        s[-1] = self.rail_length
        object.__setattr__(self, "_s", s)
        object.__setattr__(self, "_turned", np.array([0.0, 0.0, math.pi, math.pi, 2 * math.pi]))

    @property
    def straight_length(self) -> float:
        """Length of each straight [mm]."""
        return (self.rail_length - 2.0 * math.pi * self.curve_radius) / 2.0

    def tcp_lap(self, y_shift: float) -> float:
        """Length of one lap of the TCP path [mm]."""
        return self.rail_length + 2.0 * math.pi * y_shift

    def curvature(self, position: float | np.ndarray) -> float | np.ndarray:
        """Curvature of the motor path at the absolute ``position`` [1/mm]: 1/R or 0."""
        s = np.mod(np.asarray(position, dtype=float) + self.rail_offset, self.rail_length)
        in_curve = ((s >= self._s[1]) & (s < self._s[2])) | (s >= self._s[3])
        out = np.where(in_curve, 1.0 / self.curve_radius, 0.0)
        return float(out) if out.ndim == 0 else out

    def touches_curve(self, a: float, b: float) -> bool:
        """Whether the motor path between the positions ``a`` and ``b`` meets a curve."""
        lo, hi = min(a, b), max(a, b)
        return bool(self._turned_at(hi) > self._turned_at(lo) or self.curvature(lo) or
                    self.curvature(hi))

    def motor_to_tcp(self, position: float | np.ndarray, y_shift: float
                     ) -> float | np.ndarray:
        """Arc length on the TCP path of the absolute motor ``position`` [mm]."""
        x = np.asarray(position, dtype=float)
        out = self._arc(x + self.rail_offset, y_shift) - self._arc(self.rail_offset, y_shift)
        return float(out) if out.ndim == 0 else out

    def tcp_to_motor(self, position: float | np.ndarray, y_shift: float
                     ) -> float | np.ndarray:
        """The absolute motor position whose TCP arc length is ``position`` [mm]."""
        u = np.asarray(position, dtype=float) + self._arc(self.rail_offset, y_shift)
        lap = self.tcp_lap(y_shift)
        k = np.floor(u / lap)
        s = np.interp(u - k * lap, self._s + y_shift * self._turned, self._s)
        out = k * self.rail_length + s - self.rail_offset
        return float(out) if out.ndim == 0 else out

    def _turned_at(self, position: float) -> np.ndarray:
        """The angle turned from the geometry's zero to the absolute ``position``."""
        s = np.asarray(position, dtype=float) + self.rail_offset
        k = np.floor(s / self.rail_length)
        return 2.0 * math.pi * k + np.interp(s - k * self.rail_length, self._s, self._turned)

    def _arc(self, s: float | np.ndarray, y_shift: float) -> np.ndarray:
        """F(s) = s + y * turned(s): TCP arc length from the geometry's own zero."""
        s = np.asarray(s, dtype=float)
        k = np.floor(s / self.rail_length)
        r = s - k * self.rail_length
        return k * self.tcp_lap(y_shift) + r + y_shift * np.interp(r, self._s, self._turned)


@dataclass(frozen=True)
class MoverTemplate:
    """A mover template object (§4.1): the TCP lies ``y_shift`` outward of the motor path."""

    template_id: int  #: its OTCID (> 0)
    y_shift: float = 100.0  #: TCP y-displacement [mm], >= 0 (outward)

    def __post_init__(self) -> None:
        if isinstance(self.template_id, bool) or not isinstance(self.template_id, int) or \
                self.template_id <= 0:
            raise ConfigError(f"MoverTemplate.template_id: an OTCID > 0, got {self.template_id!r}")
        non_negative_number(self.y_shift, "MoverTemplate.y_shift")


class GeoCompensation:
    """The geometry, the mover templates and the registrations of one CA group's rail.

    Reached as ``group.tracks.geo``: ``set_geometry``, ``add_template``,
    ``register_compensation`` (MC_RegisterCompensation) and ``transform_position``
    (MC_TransformPosition).
    """

    def __init__(self, group: CaGroup) -> None:
        self._group = group
        self.geometry: StarterKitGeometry | None = None
        self.templates: dict[int, MoverTemplate] = {}
        self._registered: dict[int, int] = {}  #: axis row -> template id

    def set_geometry(self, geometry: StarterKitGeometry) -> StarterKitGeometry:
        """The rail's geometry; its rail length is the group's and the rail is a ring."""
        parameters = self._group.parameters
        if not parameters.rail_is_ring:
            raise ConfigError("geo-compensation needs a ring rail (the starter-kit geometry)")
        if geometry.rail_length != parameters.rail_length:
            raise ConfigError(f"StarterKitGeometry.rail_length {geometry.rail_length:g} is not "
                              f"the group's rail_length {parameters.rail_length:g}")
        self.geometry = geometry
        return geometry

    def add_template(self, template: MoverTemplate) -> MoverTemplate:
        if self.geometry is None:
            raise ConfigError("add the geometry first: group.tracks.geo.set_geometry(...)")
        if template.template_id in self.templates:
            raise ConfigError(f"mover template {template.template_id} exists already")
        self.templates[template.template_id] = template
        return template

    def register_compensation(self, axis: Axis, template_id: int,
                              compensation_type: CompensationType = CompensationType.GEO
                              ) -> Command:
        """MC_RegisterCompensation (§9.2.1.1): later CA moves of ``axis`` may refer to this
        template (PositionReferenceSystem, DynamicsReferenceSystem). A new registration
        replaces the old one; there is no unregister (D-075)."""
        command = Command("register_compensation", self._group.runtime.now)
        try:
            if isinstance(compensation_type, bool) or compensation_type != CompensationType.GEO:
                raise CommandRejected(ErrorId.INVALID_COMPENSATION_TYPE,
                                      f"compensation_type: only GEO (1), got {compensation_type!r}")
            if axis.group is not self._group:
                raise CommandRejected(ErrorId.AXIS_NOT_IN_GROUP,
                                      f"{axis.name} is not in CA group {self._group.name!r}")
            self._registered[axis.row] = self.template(template_id).template_id
            self._group.pairs_changed()  # its gaps are now on the TCP path (D-073)
        except CommandRejected as rejected:
            command.end(CommandStatus.ERROR, command.issued_at, rejected.error_id,
                         rejected.message)
            return command
        command.end(CommandStatus.DONE, command.issued_at)
        return command

    @property
    def any_registered(self) -> bool:
        """At least one mover registered a template (MC_RegisterCompensation)."""
        return bool(self._registered)

    def registered(self, axis: Axis) -> MoverTemplate | None:
        """The template ``axis`` registered, if any."""
        template_id = self._registered.get(axis.row)
        return None if template_id is None else self.templates[template_id]

    def template(self, oid: int) -> MoverTemplate:
        """The template with this OTCID, or CommandRejected(UNKNOWN_TEMPLATE)."""
        if isinstance(oid, bool) or not isinstance(oid, int) or oid not in self.templates:
            raise CommandRejected(ErrorId.UNKNOWN_TEMPLATE,
                                  f"{oid!r} is no mover template of group {self._group.name!r}")
        return self.templates[oid]

    def reference(self, axis: Axis, oid: int) -> MoverTemplate | None:
        """The template a reference-system input of ``axis`` names: None for 0 (the motor
        path); else it must be the template the axis registered."""
        if not isinstance(oid, bool) and oid == 0:
            return None
        template = self.template(oid)
        if self._registered.get(axis.row) != template.template_id:
            raise CommandRejected(ErrorId.COMPENSATION_NOT_REGISTERED,
                                  f"{axis.name} did not register mover template {oid} "
                                  "(MC_RegisterCompensation)")
        return template

    def transform_position(self, origin_oid: int, destination_oid: int,
                           position: float) -> float:
        """MC_TransformPosition (§9.2.1.2): ``position`` in the frame ``origin_oid`` (0: the
        absolute motor path, else a template's TCP path) in the frame ``destination_oid``.
        Information only: no setpoint changes."""
        if isinstance(position, bool) or not isinstance(position, int | float) or \
                not math.isfinite(position):
            raise CommandRejected(ErrorId.INVALID_POSITION,
                                  f"origin_position: a finite number, got {position!r}")
        x = float(position)
        if not (not isinstance(origin_oid, bool) and origin_oid == 0):
            x = self.to_motor(self.template(origin_oid), x)
        if not (not isinstance(destination_oid, bool) and destination_oid == 0):
            x = self.to_tcp(self.template(destination_oid), x)
        return x

    def to_tcp(self, template: MoverTemplate, position: float) -> float:
        assert self.geometry is not None  # a template exists only with a geometry
        return float(self.geometry.motor_to_tcp(position, template.y_shift))

    def to_motor(self, template: MoverTemplate, position: float) -> float:
        assert self.geometry is not None
        return float(self.geometry.tcp_to_motor(position, template.y_shift))

    def compensate(self, axis: Axis, job: CaJob, dynamics_reference_system: int) -> None:
        """DynamicsReferenceSystem = a template: once the job starts, if its motor path meets
        a curve, every limit is scaled by R / (R + y), so that the TCP stays within the
        commanded velocity, acceleration, deceleration and jerk (D-072)."""
        template = self.reference(axis, dynamics_reference_system)
        if template is None or template.y_shift == 0.0:
            return
        assert self.geometry is not None and job.target_of is not None
        geometry, limits, target_of = self.geometry, job.limits, job.target_of
        factor = geometry.curve_radius / (geometry.curve_radius + template.y_shift)

        def compensated(start: float) -> float:
            target = target_of(start)
            job.limits = scaled(limits, factor) if geometry.touches_curve(start, target) \
                else limits
            return target

        job.target_of = compensated
        job.command.warnings.append(
            f"dynamics refer to the TCP of mover template {template.template_id}: in curves "
            f"the motor path runs at {factor:.6g} of the limits")

    def compensate_halt(self, axis: Axis, limits: Limits, start: KinematicState,
                        dynamics_reference_system: int, warnings: list[str]) -> Limits:
        """MC_HaltCA with a template as DynamicsReferenceSystem: if the stop meets a curve,
        deceleration and jerk are scaled by R / (R + y) as for moves (D-072); the longer
        stop this gives is then on the safe side for the TCP."""
        template = self.reference(axis, dynamics_reference_system)
        if template is None or template.y_shift == 0.0:
            return limits
        assert self.geometry is not None
        geometry = self.geometry
        stop = plan_stop(start, limits.deceleration, limits.jerk).end.position
        if not geometry.touches_curve(start.position, stop):
            return limits
        factor = geometry.curve_radius / (geometry.curve_radius + template.y_shift)
        warnings.append(f"dynamics refer to the TCP of mover template {template.template_id}: "
                        f"the stop meets a curve and brakes at {factor:.6g} of the limits")
        return scaled(limits, factor)


def scaled(limits: Limits, factor: float) -> Limits:
    """Every limit times ``factor``."""
    return Limits(limits.velocity * factor, limits.acceleration * factor,
                  limits.deceleration * factor, limits.jerk * factor)

