"""MC_PlanarEnvironment and MC_PlanarPart (TF5430 §6.4, §6.6, §7.2.2.1, §7.2.2.9).

The environment describes where movers may go: stators added one by one (AddStator,
CreateBoundary) or, with the part feature, a ``PartLayout`` (the processing unit of §5.2). In a
group it holds the stator surface, so that no motion leaves it (§6.4). It also carries the
commands of MC_PlanarPart (§6.6.1) and resolves the reference ids of targets (§5.3).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.planar.enums import PlanarObjectType, PlanarState
from openmotion.planar.feedback import MC_PlanarFeedbackBase, PlanarCommand, PlanarObjectInfo
from openmotion.planar.frames import Pose
from openmotion.planar.options import CDT_MCTOPLC_PLANAR_ENVIRONMENT_STD
from openmotion.planar.parts import Part, PartLayout, PartPosition
from openmotion.planar.positions import PositionXYC, finite
from openmotion.planar.reservation import MemberId
from openmotion.planar.states import ErrorReaction
from openmotion.planar.stators import Boundary, StatorField
from openmotion.planar.system import PlanarObject, PlanarSystem

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from openmotion.planar.group import MC_PlanarGroup
    from openmotion.planar.mover import MC_PlanarMover
    from openmotion.runtime.runtime import Runtime

_ACTIVE = (PlanarState.ENABLING, PlanarState.ENABLED)
_FAILED = (PlanarState.ERROR_PENDING, PlanarState.ERROR, PlanarState.RESETTING)


class MC_PlanarEnvironment(PlanarObject):
    """The stator surface. ``layout`` switches the part feature on (§5.2): the stators are
    then the parts' in their active positions, and reference ids name parts and coordinate
    systems."""

    def __init__(self, runtime: Runtime, layout: PartLayout | None = None,
                 name: str | None = None) -> None:
        system = PlanarSystem.of(runtime)
        super().__init__(system, system.next_oid("object"))
        self.name = name or "environment"
        self.layout = layout
        self.field = StatorField()
        self.boundary: Boundary | None = None
        self._group: MC_PlanarGroup | None = None
        self.error = False  #: the environment has no state machine (§7.2.2.1)
        self.error_id = ErrorId.NO_ERROR
        system.environments.append(self)
        system.register(self)
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
        return self._send("AddToGroup", feedback, group)

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
            self._group._leave(self.member)
            self._group = None
        elif kind.startswith("Part."):
            self._part_command(command)
            return
        command.finished()

    def _create_boundary(self) -> None:
        try:
            self._build_boundary()
        except ConfigError as bad:  # parts off one stator grid: refuse, never raise (§6.4)
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, str(bad)) from None

    def _build_boundary(self) -> None:
        if self.layout is not None:
            field = StatorField()
            for part in self.layout.parts_in(self._system_oid()):
                for x, y in part.stators:
                    corner = part.active_position.pose.compose(Pose(x, y, 0.0))
                    placed = part.active_position.pose.compose(Pose(x + 240.0, y + 240.0, 0.0))
                    field.add_stator(min(corner.x, placed.x), min(corner.y, placed.y))
            self.field = field
        self.boundary = self.field.create_boundary()
        self._surface_changed()

    def _add_to_group(self, group: MC_PlanarGroup) -> None:
        if self._group is not None:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"the environment is in group 16#{self._group.oid:08X} already")
        group._admit(self, self.surface, self.member)
        self._group = group

    def _surface_changed(self) -> None:
        if self._group is not None:
            self._group.registry.set_surface(self.surface)

    def _system_oid(self) -> int:
        """The coordinate system a group checks in: the layout's first (§5.1)."""
        assert self.layout is not None
        return self.layout.coordinate_systems[0]

    def _publish(self) -> bool:
        """Parts follow the movers of their coordinate system, and a part that fails or is
        force-disabled takes the movers on it into error (§6.6): checked every cycle."""
        if self.layout is not None:
            active = {m.coordinate_system for m in self._system.movers
                      if m._states.current in _ACTIVE}
            self.layout.follow_movers(active)
            self.layout.update()
            for mover in self._system.movers:
                part = self._part_of(mover)
                if mover._states.current is PlanarState.ENABLED and part is not None and \
                        (part.disable_forced or part.state in _FAILED):
                    why = "is force-disabled" if part.disable_forced else "has an error"
                    mover._states.fail(ErrorId.PLANAR_PART_NOT_ENABLED, ErrorReaction.ABORT,
                                       f"part 16#{part.oid:08X} under the mover {why} (§6.6)")
                    mover._awake = True
        self._queue.publish()
        return self.layout is not None

    def _part_of(self, mover: MC_PlanarMover) -> Part | None:
        """The part under the mover's centre, in its coordinate system."""
        if self.layout is None:
            return None
        return self.layout._part_under(mover.coordinate_system, mover.pose)

    def _part_ready(self, mover: MC_PlanarMover) -> bool:
        """Enable and Reset of a mover wait for the part under it (§6.6 rule 2 and 8); a part
        that cannot be enabled fails the mover's command."""
        part = self._part_of(mover)
        if part is None:
            return True
        if part.disable_forced or part.state in _FAILED:
            mover._states.fail(ErrorId.PLANAR_PART_NOT_ENABLED, ErrorReaction.ABORT,
                               f"part 16#{part.oid:08X} under the mover cannot be enabled (§6.6)")
            return False
        return part.state is PlanarState.ENABLED

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
            mover._place(pose)
        elif layout.is_static or len(layout.coordinate_systems) == 1:
            mover.coordinate_system = layout.coordinate_systems[0]

    def _part_command(self, command: PlanarCommand) -> None:
        part_oid, *args = command.args
        if self.layout is None:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                  f"part 16#{part_oid:08X}: the environment has no parts (§5.2)")
        part = self.layout.part(part_oid) if part_oid in self.layout.parts else None
        if part is None:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                  f"16#{part_oid:08X} is no part of the processing unit")
        kind = command.kind.removeprefix("Part.")
        if kind == "ActivatePosition":
            (index,) = args
            before, area = part.active_position, part.surface()
            self.layout.activate_position(part_oid, index)
            self._carry(before, part.active_position, area)
        elif kind == "AllowEnable":
            part.allow_enable()
        elif kind == "ForceDisable":
            part.force_disable()
        elif kind == "Reset":
            part.reset()
        command.finished()

    def _carry(self, before: PartPosition, after: PartPosition, area: BaseGeometry) -> None:
        """Movers standing on a part that changes position ride along (§6.6.1)."""
        if before == after:
            return
        move = after.pose.compose(before.pose.inverse())
        for mover in self._system.movers:
            if mover.coordinate_system == before.coordinate_system and \
                    area.covers(mover.footprint().centroid):
                mover.coordinate_system = after.coordinate_system
                mover._place(move.compose(mover.pose))


class MC_PlanarPart:
    """MC_PlanarPart (§7.2.2.9, V3.2.60): the PLC handle of a part. Its commands travel
    through the environment, which the runtime updates every cycle (§6.6.1)."""

    def __init__(self) -> None:
        self.part_oid = 0
        self._environment: MC_PlanarEnvironment | None = None

    @property
    def is_initialized(self) -> bool:
        return self._environment is not None

    def initialize(self, part_oid: int, environment: MC_PlanarEnvironment) -> None:
        """Connect to the part ``part_oid`` of ``environment``'s processing unit."""
        if environment.layout is None or part_oid not in environment.layout.parts:
            raise ConfigError(f"part 16#{part_oid:08X}: no such part in the environment's "
                              "layout (§5.2)")
        self.part_oid = part_oid
        self._environment = environment

    @property
    def position_index(self) -> int:
        return self._part().position_index

    @property
    def state(self) -> PlanarState:
        return self._part().state

    def get_position(self) -> PositionXYC:
        """The active position: the part frame in its coordinate system."""
        position = self._part().active_position
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

    def _part(self):  # noqa: ANN202 - parts.Part
        if self._environment is None or self._environment.layout is None:
            raise ConfigError("MC_PlanarPart: call initialize(part_oid, environment) first")
        return self._environment.layout.part(self.part_oid)

    def _command(self, kind: str, feedback: MC_PlanarFeedbackBase | None,
                 *args: object) -> PlanarCommand:
        if self._environment is None:
            raise ConfigError("MC_PlanarPart: call initialize(part_oid, environment) first")
        return self._environment._send(f"Part.{kind}", feedback, self.part_oid, *args)

