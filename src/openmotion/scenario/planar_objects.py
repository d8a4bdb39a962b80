"""Planar entries on tracks and the environment, and the Get queries of every planar object.

The ``planar`` block builds the tracks and the environment and adds them to their groups
before t = 0 (planar_machine.py); these entries send the same objects their other methods
later: a track's Enable, Disable, Reset, Clear and group membership (TF5430 §7.2.2.10), the
environment's Clear and group membership (§7.2.2.1). The Get methods (GetLength,
GetPositionAt, GetArcLengthClosestTo, GetPositionOnCurrentPart, a part's GetPosition,
GetPlanarObjectInfo) are queries: the entry calls the method once and its row keeps what it
returned (scenario/queries.py; checks pick one with ``output``, D-218). planar.py puts these
entries into ``PLANAR_ENTRIES``.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Literal, NamedTuple

from pydantic import AfterValidator, StrictStr

from openmotion.axis.commands import Command
from openmotion.core.errors import ErrorId
from openmotion.planar import PlanarObjectInfo, PositionXYC
from openmotion.scenario.planar import PlanarEntry, _check_planar_group
from openmotion.scenario.planar_parts import PartEntry, ReferenceId
from openmotion.scenario.planar_tracks import TrackName
from openmotion.scenario.queries import Query, query_command
from openmotion.scenario.schema import Number
from openmotion.scenario.transport import _Timed

if TYPE_CHECKING:
    from openmotion.scenario.planar_machine import PlanarMachine

_INFO = ("object_type", "id")  #: PlanarObjectInfo: the type's number and the OID
_POSITION = ("x", "y", "c", "reference_id")  #: a PositionXYC's outputs


class GroupRef(NamedTuple):
    """A planar group argument, by name; the run passes the group of that name."""

    name: str


def _position(position: PositionXYC) -> dict[str, float]:
    return {"x": position.x, "y": position.y, "c": position.c,
            "reference_id": position.reference_id}


class PlanarQuery(Query):
    """A Get method called once on the entry's object; what it returns is the row's outputs
    (a PositionXYC: x, y, c, reference_id; a PlanarObjectInfo: object_type, id; a number:
    the one output)."""

    method: ClassVar[str]

    def call(self, target: Any, now: float) -> Command:
        machine: PlanarMachine = target
        owner = machine.target_of(self)
        if owner is None:
            return query_command(self.command, now, {}, ErrorId.PLANAR_INVALID_INPUT,
                                 "there is no planar.environment")
        returned = getattr(owner, self.method)(*self.arguments())  # type: ignore[attr-defined]
        if isinstance(returned, PositionXYC):
            return query_command(self.command, now, _position(returned))
        if isinstance(returned, PlanarObjectInfo):
            return query_command(self.command, now, dataclasses.asdict(returned))
        return query_command(self.command, now, {self.outputs[0]: returned})


# -- tracks ------------------------------------------------------------------------------------


class TrackEntry(_Timed):
    """A command for one planar track: the run calls the MC_PlanarTrack method ``method``."""

    track: TrackName
    """Name of the track (one of planar.tracks)."""

    @property
    def axis(self) -> str:
        """The track's name, for the summary's axis column."""
        return self.track

    def arguments(self) -> tuple[Any, ...]:
        return ()


class TrackEnable(TrackEntry):
    """MC_PlanarTrack.Enable (§7.2.2.10.10): a disabled track is Standing again."""

    method = "enable"
    command: Literal["track_enable"]


class TrackDisable(TrackEntry):
    """MC_PlanarTrack.Disable (§7.2.2.10.11): refused while movers ride on it."""

    method = "disable"
    command: Literal["track_disable"]


class TrackReset(TrackEntry):
    """MC_PlanarTrack.Reset (§7.2.2.10.12): clear an error of the track."""

    method = "reset"
    command: Literal["track_reset"]


class TrackClear(TrackEntry):
    """MC_PlanarTrack.Clear (§7.2.2.10.1): delete the geometry (and the blocking of its
    links); a track in use refuses it."""

    method = "clear"
    command: Literal["track_clear"]


class TrackAddToGroup(TrackEntry):
    """MC_PlanarTrack.AddToGroup (§7.2.2.10.18): the track joins ``group``."""

    method = "add_to_group"
    command: Literal["track_add_to_group"]
    group: Annotated[StrictStr, AfterValidator(_check_planar_group)]
    """Name of the planar group."""

    def arguments(self) -> tuple[Any, ...]:
        return (GroupRef(self.group),)


class TrackRemoveFromGroup(TrackEntry):
    """MC_PlanarTrack.RemoveFromGroup (§7.2.2.10.19): the track leaves its group."""

    method = "remove_from_group"
    command: Literal["track_remove_from_group"]


class TrackGetLength(TrackEntry, PlanarQuery):
    """MC_PlanarTrack.GetLength (§7.2.2.10.15): output ``length`` [mm]."""

    method = "get_length"
    command: Literal["track_get_length"]
    outputs = ("length",)


class TrackGetPositionAt(TrackEntry, PlanarQuery):
    """MC_PlanarTrack.GetPositionAt (§7.2.2.10.14): the point at ``arc_length`` (outputs x,
    y, c: the heading [°], reference_id)."""

    method = "get_position_at"
    command: Literal["track_get_position_at"]
    outputs = _POSITION
    arc_length: Number
    """[mm] along the track."""

    def arguments(self) -> tuple[Any, ...]:
        return (self.arc_length,)


class TrackGetArcLengthClosestTo(TrackEntry, PlanarQuery):
    """MC_PlanarTrack.GetArcLengthClosestTo (§7.2.2.10.13): output ``arc_length`` [mm] where
    the track comes closest to (x, y)."""

    method = "get_arc_length_closest_to"
    command: Literal["track_get_arc_length_closest_to"]
    outputs = ("arc_length",)
    x: Number
    """[mm]."""
    y: Number
    """[mm]."""
    reference_id: ReferenceId = 0
    """The frame of x and y, as move_to_position's."""

    def arguments(self) -> tuple[Any, ...]:
        return (PositionXYC(self.x, self.y, 0.0, self.reference_id),)


class TrackGetPlanarObjectInfo(TrackEntry, PlanarQuery):
    """MC_PlanarTrack.GetPlanarObjectInfo (§7.2.2.10.16): outputs object_type, id (OID)."""

    method = "get_planar_object_info"
    command: Literal["track_get_planar_object_info"]
    outputs = _INFO


# -- the environment ---------------------------------------------------------------------------


class EnvironmentEntry(_Timed):
    """A command for the planar environment: the MC_PlanarEnvironment method ``method``.
    Without planar.environment it ends with an error."""

    @property
    def axis(self) -> str:
        """For the summary's axis column."""
        return "environment"

    def arguments(self) -> tuple[Any, ...]:
        return ()


class EnvironmentAddToGroup(EnvironmentEntry):
    """MC_PlanarEnvironment.AddToGroup (§7.2.2.1.5): the movers of ``group`` stay on the
    stators."""

    method = "add_to_group"
    command: Literal["environment_add_to_group"]
    group: Annotated[StrictStr, AfterValidator(_check_planar_group)]
    """Name of the planar group."""

    def arguments(self) -> tuple[Any, ...]:
        return (GroupRef(self.group),)


class EnvironmentRemoveFromGroup(EnvironmentEntry):
    """MC_PlanarEnvironment.RemoveFromGroup (§7.2.2.1.6): no boundary checks any more."""

    method = "remove_from_group"
    command: Literal["environment_remove_from_group"]


class EnvironmentClear(EnvironmentEntry):
    """MC_PlanarEnvironment.Clear (§7.2.2.1.1): remove every stator and the boundary."""

    method = "clear"
    command: Literal["environment_clear"]


class EnvironmentGetPlanarObjectInfo(EnvironmentEntry, PlanarQuery):
    """MC_PlanarEnvironment.GetPlanarObjectInfo (§7.2.2.1.7): outputs object_type, id."""

    method = "get_planar_object_info"
    command: Literal["environment_get_planar_object_info"]
    outputs = _INFO


# -- movers and parts --------------------------------------------------------------------------


class MoverGetPlanarObjectInfo(PlanarEntry, PlanarQuery):
    """MC_PlanarMover.GetPlanarObjectInfo (§7.2.2.8.25): outputs object_type, id (OID)."""

    method = "get_planar_object_info"
    command: Literal["mover_get_planar_object_info"]
    outputs = _INFO


class GetPositionOnCurrentPart(PlanarEntry, PlanarQuery):
    """MC_PlanarMover.GetPositionOnCurrentPart (§7.2.2.8.24): the set position in the frame
    of the part under the mover (outputs x, y, c, reference_id: the part's OID)."""

    method = "get_position_on_current_part"
    command: Literal["get_position_on_current_part"]
    outputs = _POSITION


class PartGetPosition(PartEntry, PlanarQuery):
    """MC_PlanarPart.GetPosition (§7.2.2.9.6): where the part's frame lies in its coordinate
    system (outputs x, y, c, reference_id)."""

    method = "get_position"
    command: Literal["part_get_position"]
    outputs = _POSITION


#: planar.py adds them to PLANAR_ENTRIES
OBJECT_ENTRIES: tuple[type, ...] = (
    TrackEnable, TrackDisable, TrackReset, TrackClear, TrackAddToGroup, TrackRemoveFromGroup,
    TrackGetLength, TrackGetPositionAt, TrackGetArcLengthClosestTo, TrackGetPlanarObjectInfo,
    EnvironmentAddToGroup, EnvironmentRemoveFromGroup, EnvironmentClear,
    EnvironmentGetPlanarObjectInfo, MoverGetPlanarObjectInfo, GetPositionOnCurrentPart,
    PartGetPosition)
