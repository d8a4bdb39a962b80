"""MC_PlanarEnvironment and MC_PlanarPart (TF5430 §6.4, §6.6, §7.2.2.1, §7.2.2.9).

The environment describes where movers may go: stators added one by one (AddStator,
CreateBoundary) or, with the part feature, a ``PartLayout`` (the processing unit of §5.2). In a
group it holds the stator surface, so that no motion leaves it (§6.4). It also carries the
commands of MC_PlanarPart (§6.6.1) and resolves the reference ids of targets (§5.3).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
import shapely

from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.kernel.model import Kind
from openmotion.planar.enums import ExternalSetPositionMode, PlanarObjectType, PlanarState
from openmotion.planar.feedback import MC_PlanarFeedbackBase, PlanarCommand, PlanarObjectInfo
from openmotion.planar.frames import Pose
from openmotion.planar.group import planar_group
from openmotion.planar.kind import PLANAR_ENVIRONMENT
from openmotion.planar.motion import sample_path
from openmotion.planar.options import CDT_MCTOPLC_PLANAR_ENVIRONMENT_STD
from openmotion.planar.parts import Part, PartLayout, PartPosition
from openmotion.planar.positions import PositionXYC, finite
from openmotion.planar.reservation import MemberId, footprint, grown_surface, path_on_surface
from openmotion.planar.states import ErrorReaction
from openmotion.planar.stators import Boundary, StatorField
from openmotion.planar.system import ObjectPort, PlanarObject, PlanarSystem
from openmotion.planar.tolerances import PART_TOLERANCE

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from openmotion.planar.group import MC_PlanarGroup
    from openmotion.planar.mover import MC_PlanarMover
    from openmotion.runtime.runtime import Runtime

#: a mover in these states keeps the parts of its coordinate system on (§6.6): until it is off
_ACTIVE = (PlanarState.ENABLING, PlanarState.ENABLED, PlanarState.DISABLING)
_FAILED = (PlanarState.ERROR_PENDING, PlanarState.ERROR, PlanarState.RESETTING)
_PART_ERRORS = (PlanarState.ERROR_PENDING, PlanarState.ERROR)
_SAMPLE_CYCLES = 10  #: a running motion is sampled every this many cycles for the part check


def _keeps_parts_on(mover: MC_PlanarMover) -> bool:
    """§6.6: parts stay on while a mover of their system is on, is being switched off, or is
    in an error with the QuickStop reaction (through the error and its Reset). The Abort
    reaction, also one a Disable forces during the error, lets them go off."""
    states = mover.states
    if states.current in _ACTIVE:
        return True
    return states.current in _FAILED and states.reaction is ErrorReaction.QUICK_STOP


def _busy(mover: MC_PlanarMover) -> bool:
    """Not at standstill: a motion runs (a brake too), it rides a track, or external
    setpoints drive it."""
    if mover.in_motion or mover.modes.external is not ExternalSetPositionMode.NONE:
        return True
    traffic = mover.system.traffic
    return mover.rider is not None and traffic is not None and traffic.moving(mover.rider)


def _overlap(area: BaseGeometry, footprints: list[BaseGeometry]) -> bool:
    """Whether any footprint covers part of ``area``; touching edges do not count."""
    return bool((shapely.area(shapely.intersection(area, footprints)) > PART_TOLERANCE).any())


def _oid_text(oid: object) -> str:
    """An object id as the manual prints it (16#01010080); anything else as Python shows it."""
    if isinstance(oid, int) and not isinstance(oid, bool) and 0 <= oid <= 0xFFFF_FFFF:
        return f"16#{oid:08X}"
    return repr(oid)


@dataclass(frozen=True)
class EnvironmentPort(ObjectPort):
    """What the movers and the MC_PlanarPart handles call on the environment (D-239)."""

    place: Callable[[MC_PlanarMover], None]  #: a new mover into its initial part's system
    #: a PositionXYC target and the mover's coordinate system -> (system OID, pose in it)
    resolve: Callable[[PositionXYC, int], tuple[int, Pose]]
    part_ready: Callable[[MC_PlanarMover], bool]  #: its parts are on: Enable/Reset may end
    reset_parts: Callable[[int], None]  #: Reset of a mover: the parts of its system first
    #: an MC_PlanarPart's command: (kind, feedback, part OID, *args) -> its PlanarCommand
    send_part_command: Callable[..., PlanarCommand]


class MC_PlanarEnvironment(PlanarObject):
    """The stator surface. ``layout`` switches the part feature on (§5.2): the stators are
    then the parts' in their active positions, and reference ids name parts and coordinate
    systems."""

    MACHINE: ClassVar[Kind] = PLANAR_ENVIRONMENT  #: its signals and commands in the machine model

    def __init__(self, runtime: Runtime, layout: PartLayout | None = None,
                 name: str | None = None) -> None:
        if layout is not None and not isinstance(layout, PartLayout):
            raise ConfigError(f"layout: must be a PartLayout, got {type(layout).__name__}")
        system = PlanarSystem.of(runtime)
        super().__init__(system, system.next_oid("object"))
        self.name = name or "environment"
        self.layout = layout
        self.field = StatorField()
        self.boundary: Boundary | None = None
        #: the boundary's surface grown and prepared for ``carries``, made when first needed
        self._carrier: tuple[BaseGeometry | None, tuple[float, ...] | None] | None = None
        self._group: MC_PlanarGroup | None = None
        self.error = False  #: the environment has no state machine (§7.2.2.1)
        self.error_id = ErrorId.NO_ERROR
        #: what the movers and the part handles call on it besides the system's hooks
        self.port = EnvironmentPort(self._run, self._publish, place=self._place,
                                    resolve=self._resolve, part_ready=self._part_ready,
                                    reset_parts=self._reset_parts,
                                    send_part_command=self._send_part_command)
        system.environments.append(self)
        self._rank = system.register(self)
        for mover in system.movers:
            self._place(mover)

    def __repr__(self) -> str:
        return f"<MC_PlanarEnvironment 16#{self.oid:08X} {len(self.field)} stators>"

    # -- the manual's methods (§7.2.2.1) ---------------------------------------------------------

    def clear(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("Clear", feedback)

    def add_stator(self, lower_x: float, lower_y: float,
                   feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """One 240 mm stator by its lower-left corner [mm] (§6.4.2)."""
        return self._send("AddStator", feedback, lower_x, lower_y)

    def create_boundary(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Freeze the surface of the stators added so far; its outer sides are the boundary."""
        return self._send("CreateBoundary", feedback)

    def add_to_group(self, group: MC_PlanarGroup,
                     feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("AddToGroup", feedback, planar_group(group))

    def remove_from_group(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("RemoveFromGroup", feedback)

    def get_planar_object_info(self) -> PlanarObjectInfo:
        return PlanarObjectInfo(PlanarObjectType.ENVIRONMENT, self.oid)

    @property
    def member(self) -> MemberId:
        return MemberId(PlanarObjectType.ENVIRONMENT, self.oid)

    @property
    def surface(self) -> BaseGeometry | None:
        """The surface the boundary encloses (None before CreateBoundary)."""
        return None if self.boundary is None else self.boundary.surface

    # -- execution -------------------------------------------------------------------------------

    def _execute(self, command: PlanarCommand) -> None:
        kind = command.kind
        if kind == "AddStator":
            if self.layout is not None:
                raise CommandRejected(ErrorId.PLANAR_WRONG_STATE, "the stators come from the "
                                      "parts of the processing unit (§5.2)")
            try:
                self.field.add_stator(*(finite(v, n) for v, n in zip(
                    command.args, ("lower_x", "lower_y"), strict=True)))
            except ConfigError as bad:
                raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, str(bad)) from None
        elif kind == "Clear":
            self.field.clear()
            self.boundary = None
            self._surface_changed()
        elif kind == "CreateBoundary":
            self._create_boundary()
        elif kind == "AddToGroup":
            self._add_to_group(command.args[0])
        elif kind == "RemoveFromGroup":
            if self._group is None:
                raise CommandRejected(ErrorId.PLANAR_NOT_IN_GROUP, "the environment is in no "
                                      "group")
            self._group.port.leave(self.member)
            self._group = None
        elif kind.startswith("Part."):
            self._part_command(command)
            return
        command.finish()

    def _create_boundary(self) -> None:
        try:
            self._build_boundary()
        except ConfigError as bad:  # parts off one stator grid: refuse, never raise (§6.4)
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, str(bad)) from None

    def _build_boundary(self) -> None:
        if self.layout is not None:
            self.field = self._layout_field()
        self.boundary = self.field.create_boundary()
        self._surface_changed()

    def _layout_field(self) -> StatorField:
        """The stators of the parts in their active positions in the group's coordinate
        system; ``ConfigError`` if they are not on one grid."""
        field = StatorField()
        for part in self.layout.parts_in(self._system_oid()):
            for x, y in part.stators:
                corner = part.active_position.pose.compose(Pose(x, y, 0.0))
                placed = part.active_position.pose.compose(Pose(x + 240.0, y + 240.0, 0.0))
                field.add_stator(min(corner.x, placed.x), min(corner.y, placed.y))
        return field

    def _add_to_group(self, group: MC_PlanarGroup) -> None:
        if self._group is not None:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"the environment is in group 16#{self._group.oid:08X} already")
        group.port.admit(self, self.surface, self.member)
        self._group = group

    def _surface_changed(self) -> None:
        self._carrier = None
        if self._group is not None:
            self._group.registry.set_surface(self.surface)

    def carries(self, coordinate_system: int, points: np.ndarray) -> bool:
        """Whether stators carry a mover whose centre follows the polyline ``points`` (n, 2)
        [mm] in ``coordinate_system``: the centre stays on the surface (edges count). True
        where the surface is unknown: before CreateBoundary, or in a coordinate system
        other than the boundary's (D-088); nothing can be checked there (D-163)."""
        if self.boundary is None or (self.layout is not None
                                     and coordinate_system != self._system_oid()):
            return True
        if self._carrier is None:
            self._carrier = grown_surface(self.surface)
        surface, rectangle = self._carrier
        return surface is None or path_on_surface(surface, rectangle, points)

    def _system_oid(self) -> int:
        """The coordinate system a group checks in: the layout's first (§5.1)."""
        assert self.layout is not None
        return self.layout.coordinate_systems[0]

    def _publish(self) -> bool:
        """Parts follow the movers of their coordinate system, and a part that fails or is
        force-disabled takes the movers on it into error (§6.6): checked every cycle."""
        if self.layout is not None:
            active = {m.coordinate_system for m in self.system.movers if _keeps_parts_on(m)}
            self.layout.follow_movers(active)
            self.layout.update()
            for mover in self.system.movers:
                part = self._part_of(mover)
                if mover.states.current is PlanarState.ENABLED and part is not None and \
                        (part.disable_forced or part.state in _FAILED):
                    why = "is force-disabled" if part.disable_forced else "has an error"
                    mover.states.fail(ErrorId.PLANAR_PART_NOT_ENABLED, ErrorReaction.ABORT,
                                       f"part 16#{part.oid:08X} under the mover {why} (§6.6)")
                    mover.awake = True
        self.commands.publish()
        return self.layout is not None

    def _part_of(self, mover: MC_PlanarMover) -> Part | None:
        """The part under the mover's centre, in its coordinate system."""
        if self.layout is None:
            return None
        return self.layout.part_under(mover.coordinate_system, mover.pose)

    def _part_ready(self, mover: MC_PlanarMover) -> bool:
        """Enable and Reset of a mover wait for the part under it (§6.6): Enable, and a Reset
        that ends Enabled (QuickStop), need the part Enabled; a Reset that ends Disabled
        (Abort) needs it only free of errors. A part that cannot get there fails the mover's
        command."""
        part = self._part_of(mover)
        if part is None:
            return True
        if part.state is PlanarState.RESETTING:  # the mover's Reset is resetting it (§6.6)
            return False
        if part.state in _PART_ERRORS:
            return self._part_refuses(mover, part, "has an error")
        if mover.states.current is PlanarState.RESETTING and \
                mover.states.reaction is ErrorReaction.ABORT:
            return True
        if part.disable_forced:
            return self._part_refuses(mover, part, "is force-disabled")
        return part.state is PlanarState.ENABLED

    @staticmethod
    def _part_refuses(mover: MC_PlanarMover, part: Part, why: str) -> bool:
        mover.states.fail(ErrorId.PLANAR_PART_NOT_ENABLED, ErrorReaction.ABORT,
                           f"part 16#{part.oid:08X} under the mover {why} (§6.6)")
        return False

    def _reset_parts(self, coordinate_system: int) -> None:
        """A mover's Reset first resets the failed parts of its coordinate system (§6.6)."""
        if self.layout is None:
            return
        for part in self.layout.parts_in(coordinate_system):
            if part.state is PlanarState.ERROR:
                part.reset()

    @property
    def mc_to_plc_std(self) -> CDT_MCTOPLC_PLANAR_ENVIRONMENT_STD:
        """EnvironmentOID, GroupOID, StatorCount, BoundaryElementCount (§6.4.2)."""
        return CDT_MCTOPLC_PLANAR_ENVIRONMENT_STD(
            environment_oid=self.oid, group_oid=self._group.oid if self._group else 0,
            stator_count=len(self.field),
            boundary_element_count=self.boundary.element_count if self.boundary else 0)

    # -- reference ids and parts (§5.3, §6.6) ----------------------------------------------------

    def _resolve(self, target: PositionXYC, coordinate_system: int) -> tuple[int, Pose]:
        """A target in the frame its reference id names, as (coordinate system, pose)."""
        if self.layout is None:
            if target.reference_id != 0:
                raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                      f"reference id 16#{target.reference_id:08X} names no part "
                                      "or coordinate system: the environment has no parts "
                                      "(§5.3)")
            return 0, target.pose
        return self.layout.resolve_target(target.reference_id, target.pose,
                                          coordinate_system or None)

    def _place(self, mover: MC_PlanarMover) -> None:
        """Put a new mover into the coordinate system of its initial part (§6.1.1)."""
        layout = self.layout
        if layout is None:
            return
        part_oid = mover.parameters.part_oid
        if part_oid:
            position = layout.part(part_oid).active_position
            mover.coordinate_system = position.coordinate_system
            start = mover.parameters.initial_position
            pose = position.pose.compose(Pose(start.x, start.y, start.c))
            mover.port.place(pose)
        elif layout.is_static or len(layout.coordinate_systems) == 1:
            mover.coordinate_system = layout.coordinate_systems[0]

    def _send_part_command(self, kind: str, feedback: MC_PlanarFeedbackBase | None,
                          *args: object) -> PlanarCommand:
        """An MC_PlanarPart's command: it travels through the environment (§6.6.1)."""
        return self._send(kind, feedback, *args)

    def _part_command(self, command: PlanarCommand) -> None:
        part_oid, *args = command.args
        if self.layout is None:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID, f"part {_oid_text(part_oid)}: "
                                  "the environment has no parts (§5.2)")
        known = isinstance(part_oid, int) and part_oid in self.layout.parts
        if not known:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                  f"{_oid_text(part_oid)} is no part of the processing unit")
        part = self.layout.part(part_oid)
        kind = command.kind.removeprefix("Part.")
        if kind == "Initialize":
            (handle,) = args
            (confirm,) = args  # the handle's own confirmation, as it sent it
            confirm(self, part_oid)
        elif kind == "ActivatePosition":
            self._activate_position(part, *args)
        elif kind == "AllowEnable":
            part.allow_enable()
        elif kind == "ForceDisable":
            part.force_disable()
        elif kind == "Reset":
            part.reset()
        command.finish()

    def _activate_position(self, part: Part, index: int) -> None:
        """ActivatePosition (§7.2.2.9.2): the part moves with the movers standing on it
        (§6.6.1). It moves only under movers at standstill and hits no mover where it leaves
        or arrives (D-141). A boundary made by CreateBoundary follows the parts, so that a
        group checks against the parts where they are (§6.4)."""
        layout = self.layout
        assert layout is not None
        layout.check_activation(part.oid, index)
        before, area = part.active_position, part.surface()
        if part.positions[index - 1] == before:
            part.position_index = index
            return
        old_index = part.position_index
        self._check_movers(part, index)
        layout.activate_position(part.oid, index)
        field = None
        if self.boundary is not None:
            try:
                field = self._layout_field()
            except ConfigError as bad:  # the parts would leave the stator grid
                part.position_index = old_index
                raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, str(bad)) from None
        self._carry(before, part.active_position, area)
        if field is not None:
            self.field = field
            self.boundary = field.create_boundary()
            self._surface_changed()

    def _check_movers(self, part: Part, index: int) -> None:
        """Refuse the part's move to ``index`` while a mover is not at standstill on it, or
        its motion reaches the part where it is or where it goes (PLANAR_WRONG_STATE), and
        while a standing mover it does not carry (its centre is off the part) reaches into
        either place (PLANAR_COLLISION, naming the mover)."""
        before, after = part.active_position, part.positions[index - 1]
        places = ((before.coordinate_system, part.surface()),
                  (after.coordinate_system, part.surface(index)))
        for mover in self.system.movers:
            busy = _busy(mover)
            if not busy and mover.coordinate_system == before.coordinate_system and \
                    places[0][1].covers(mover.footprint().centroid):
                continue  # it rides along
            footprints = self._footprints_ahead(mover) if busy else [mover.footprint()]
            for system, area in places:
                if mover.coordinate_system != system or not _overlap(area, footprints):
                    continue
                name = f"mover {mover.name} (16#{mover.oid:08X})"
                if busy:
                    raise CommandRejected(ErrorId.PLANAR_WRONG_STATE, f"part 16#{part.oid:08X}"
                                          f" cannot change position while {name}, on it or "
                                          "moving onto it, is not at standstill (§6.6)")
                rejection = CommandRejected(ErrorId.PLANAR_COLLISION, f"part 16#{part.oid:08X}"
                                            f" would hit {name}, which reaches over its edge")
                rejection.object_info = mover.get_planar_object_info()
                raise rejection

    def _footprints_ahead(self, mover: MC_PlanarMover) -> list[BaseGeometry]:
        """The footprints of a moving mover now and along the rest of its free motion (on a
        track the traffic drives it: only where it is now counts)."""
        if mover.rider is not None:
            return [mover.footprint()]
        previous = self.system.previous
        _, path = sample_path(mover.port.future_plans({}, previous), previous,
                              self.system.cycle_time * _SAMPLE_CYCLES)
        width, height = mover.parameters.mover_width, mover.parameters.mover_height
        return [mover.footprint(), *(footprint(x, y, c, width, height)
                                     for x, y, c in path.tolist())]

    def _carry(self, before: PartPosition, after: PartPosition, area: BaseGeometry) -> None:
        """Movers standing on a part that changes position ride along (§6.6.1); in a group
        their footprint goes with them."""
        move = after.pose.compose(before.pose.inverse())
        for mover in self.system.movers:
            if mover.coordinate_system == before.coordinate_system and \
                    area.covers(mover.footprint().centroid):
                pose = move.compose(mover.pose)
                mover.coordinate_system = after.coordinate_system
                mover.port.place(pose)
                if mover.group is not None:
                    mover.group.registry.settle(mover.member, mover.port.standing_area(pose))


class MC_PlanarPart:
    """MC_PlanarPart (§7.2.2.9, V3.2.60): the PLC handle of a part. Its commands, Initialize
    too, travel through the environment, which runs them in the motion phase (§6.6.1)."""

    def __init__(self) -> None:
        self.part_oid = 0
        self._environment: MC_PlanarEnvironment | None = None
        self._initialized = False  #: set by the environment when it knows the part

    def _initialized_by(self, environment: MC_PlanarEnvironment, part_oid: int) -> None:
        """Told by ``environment`` that it ran Initialize for ``part_oid``: the handle is
        initialized, unless it has been aimed at another part or environment since."""
        if self.part_oid == part_oid and self._environment is environment:
            self._initialized = True

    @property
    def is_initialized(self) -> bool:
        """True once the environment has accepted Initialize: read it from the next cycle on,
        as §6.6.1 does."""
        return self._initialized

    def initialize(self, part_oid: int, environment: MC_PlanarEnvironment,
                   feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Initialize (§7.2.2.9.1): connect to the part ``part_oid`` of ``environment``'s
        processing unit. An OID that names no part ends the command with
        INVALID_REFERENCE_ID and leaves the handle uninitialized."""
        if not isinstance(environment, MC_PlanarEnvironment):
            raise TypeError("MC_PlanarPart.initialize: environment must be an "
                            f"MC_PlanarEnvironment, got {type(environment).__name__}")
        self.part_oid = part_oid
        self._environment = environment
        self._initialized = False
        return environment.port.send_part_command("Part.Initialize", feedback, part_oid,
                                                  self._initialized_by)

    @property
    def position_index(self) -> int:
        """The active position (1-based); 0 while the handle is not initialized."""
        part = self._part()
        return 0 if part is None else part.position_index

    @property
    def state(self) -> PlanarState:
        """The part's PlanarState; Disabled while the handle is not initialized."""
        part = self._part()
        return PlanarState.DISABLED if part is None else part.state

    def get_position(self) -> PositionXYC:
        """The active position: the part frame in its coordinate system (zeros while the
        handle is not initialized)."""
        part = self._part()
        if part is None:
            return PositionXYC()
        position = part.active_position
        return PositionXYC(*position.pose, position.coordinate_system)

    def activate_position(self, position_index: int,
                          feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._command("ActivatePosition", feedback, position_index)

    def allow_enable(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._command("AllowEnable", feedback)

    def force_disable(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._command("ForceDisable", feedback)

    def reset(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._command("Reset", feedback)

    def _part(self) -> Part | None:
        environment = self._environment
        if not self._initialized or environment is None or environment.layout is None:
            return None
        return environment.layout.part(self.part_oid)

    def _command(self, kind: str, feedback: MC_PlanarFeedbackBase | None,
                 *args: object) -> PlanarCommand:
        """Send through the environment. Without an Initialize call there is no environment
        to send to: the command ends at once with INVALID_REFERENCE_ID (part OID 0)."""
        if self._environment is None:
            command = PlanarCommand(f"Part.{kind}", feedback, args)
            command.reject(ErrorId.INVALID_REFERENCE_ID, "MC_PlanarPart is not initialized "
                           "(part OID 0): call initialize(part_oid, environment) first "
                           "(§7.2.2.9.1)")
            command.publish()
            return command
        return self._environment.port.send_part_command(f"Part.{kind}", feedback,
                                                        self.part_oid, *args)
