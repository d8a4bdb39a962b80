"""MC_PlanarGroup (TF5430 §6.3, §7.2.2.7): collision avoidance by area reservation.

Members (movers, the environment; tracks later) hold areas in the group's
``ReservationRegistry``. A member's motion command asks for the area it sweeps and is refused
at once when another member holds any of it (§6.3); the environment holds the stator surface,
so nothing may leave it (§6.4). Members join and leave with their own AddToGroup and
RemoveFromGroup. Commands of members are refused while the group is not Enabled: collision
avoidance is then not in force (docs/decisions.md).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.kernel.model import Kind
from openmotion.planar.enums import PlanarState
from openmotion.planar.feedback import PlanarCommand
from openmotion.planar.kind import PLANAR_GROUP
from openmotion.planar.options import CDT_MCTOPLC_PLANAR_GROUP_STD
from openmotion.planar.reservation import MemberId, ReservationRegistry, SweptArea
from openmotion.planar.states import PlanarStateMachine, title
from openmotion.planar.system import ObjectPort, PlanarObject, PlanarSystem, StatefulObject

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from openmotion.runtime.runtime import Runtime


@dataclass(frozen=True)
class GroupPort(ObjectPort):
    """What a group's members (movers, tracks, the environment) call on it (D-239)."""

    #: AddToGroup: an object joins with its area, or is refused naming the blocker (§6.3)
    admit: Callable[[PlanarObject, SweptArea | BaseGeometry | None, MemberId], None]
    leave: Callable[[MemberId], None]  #: RemoveFromGroup: the member gives back its area
    check_enabled: Callable[[str], None]  #: refuse ``what`` unless the group is Enabled


class MC_PlanarGroup(StatefulObject):
    """A planar group: Enable, Disable, Reset and the members' reserved areas."""

    MACHINE: ClassVar[Kind] = PLANAR_GROUP  #: its signals and commands in the machine model

    def __init__(self, runtime: Runtime, name: str | None = None) -> None:
        system = PlanarSystem.of(runtime)
        super().__init__(system, system.next_oid("object"))
        self.name = name or f"group{self.oid & 0xFFF:x}"
        self.registry = ReservationRegistry()
        self.states = PlanarStateMachine()
        #: what its members call on it besides the system's hooks
        self.port = GroupPort(self._run, self._publish, self._admit, self._leave,
                              self._check_enabled)
        self._rank = system.register(self)

    def __repr__(self) -> str:
        return f"<MC_PlanarGroup 16#{self.oid:08X} {self.state.name}>"

    @property
    def mc_to_plc_std(self) -> CDT_MCTOPLC_PLANAR_GROUP_STD:
        """GroupOID, State and the member count, as the last motion phase left them."""
        return CDT_MCTOPLC_PLANAR_GROUP_STD(group_oid=self.oid, state=self.states.state,
                                            group_object_count=len(self.registry.members))

    @property
    def state(self) -> PlanarState:
        return self.states.state

    @property
    def members(self) -> tuple[MemberId, ...]:
        return self.registry.members

    def reserved(self, member: MemberId) -> BaseGeometry:
        """The area ``member`` holds now (the environment: the stator surface)."""
        return self.registry.reserved(member)

    # -- for the members (motion phase) ----------------------------------------------------------

    def _check_enabled(self, what: str) -> None:
        if self.states.current is not PlanarState.ENABLED:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{what}: group 16#{self.oid:08X} is "
                                  f"{title(self.states.current)}, not Enabled (§6.3)")

    def _admit(self, obj: PlanarObject, area: SweptArea | BaseGeometry | None,
               member: MemberId) -> None:
        """AddToGroup: ``obj`` joins with ``area`` or is refused with the blocker (§6.3)."""
        from openmotion.planar.mover import Collision

        self._check_enabled("AddToGroup")
        blocker = self.registry.add_member(member, area)
        if blocker is not None:
            raise Collision(blocker, "its footprint")

    def _leave(self, member: MemberId) -> None:
        """RemoveFromGroup: ``member`` gives back its area."""
        self.registry.remove_member(member)

    # -- cycle -----------------------------------------------------------------------------------

    def _execute(self, command: PlanarCommand) -> None:
        self.states.request(command)

    def _publish(self) -> bool:
        self.states.update()
        self.commands.publish()
        return not self.states.settled


def planar_group(group: object) -> MC_PlanarGroup:
    """The group an AddToGroup names: anything else is a Python error at the call, as a
    wrong input type is (never an exception out of a cycle)."""
    if not isinstance(group, MC_PlanarGroup):
        raise TypeError(f"AddToGroup needs an MC_PlanarGroup, got {type(group).__name__}")
    return group
