"""The track and geo-compensation blocks: MC_ReadTrackPositions, MC_ActivateTrack
(Tc3_McCollisionAvoidance §9.1.1.1.5-6) and MC_RegisterCompensation, MC_TransformPosition
(Tc3_McCompensations §9.2.1), over ``group.tracks`` (transport/tracks.py, transport/geo.py).

The axis blocks take the axis first and find its group through ``axis.group``.
MC_TransformPosition has no axis in the manual: it takes the CA group whose rail holds the
mover templates first, as the group blocks do.
"""

# ruff: noqa: N801 - the manual's block names

from __future__ import annotations

from typing import Any, ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.kernel.group_blocks import GroupCommand
from openmotion.kernel.handshake import EnableBlock, ExecuteBlock
from openmotion.transport.blocks import _group_of
from openmotion.transport.enums import CompensationType
from openmotion.transport.group import CaGroup


class MC_ActivateTrack(ExecuteBlock):
    """Make a track the frame of the axis' later MC_MoveAbsoluteCA positions (§9.1.1.1.6).

    Inputs: execute, track_id (OTCID of a track of the group; 0 = the absolute frame again).
    Outputs: done, busy, error, error_id. Done in the call of the rising edge.
    Error ids: AXIS_NOT_IN_GROUP, UNKNOWN_TRACK, NOT_ON_TRACK (the set position is on no part
    of that track).
    """

    INPUTS: ClassVar[dict[str, Any]] = {"track_id": 0}

    def _issue(self, axis: Axis) -> Command:
        return _group_of(axis).tracks.activate_track(axis, self.track_id)


class MC_ReadTrackPositions(EnableBlock):
    """The set position on the active track and on the current part, with their ids
    (§9.1.1.1.5); without an active track the absolute set position and ids 0.

    Outputs while ``enable``: valid, busy, track_position [mm], track_id, part_position [mm],
    part_id, error, error_id. Error ids: AXIS_NOT_IN_GROUP (the values are invalid outside a
    CA group), NOT_ON_TRACK (the mover left its open track).
    """

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self._clear()

    def _clear(self) -> None:
        self.valid = self.busy = False
        self.track_position = self.part_position = 0.0
        self.track_id = self.part_id = 0

    def _enabled(self, axis: Axis, rising: bool) -> None:
        self._clear()  # an error leaves the values invalid
        positions = _group_of(axis).tracks.read_track_positions(axis)
        self.track_position, self.track_id, self.part_position, self.part_id = positions
        self.valid = self.busy = True

    def _disabled(self) -> None:
        super()._disabled()
        self._clear()


class MC_RegisterCompensation(ExecuteBlock):
    """Link the axis to a mover template: its later CA moves may refer to the template's TCP
    path (§9.2.1.1).

    Inputs: execute, compensation_type (``CompensationType``; only GEO is valid, the PLC
    default INVALID is an error), compensation_id (OTCID of a mover template of the group).
    Outputs: done, busy, error, error_id. Error ids: AXIS_NOT_IN_GROUP,
    INVALID_COMPENSATION_TYPE, UNKNOWN_TEMPLATE.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"compensation_type": CompensationType.INVALID,
                                        "compensation_id": 0}

    def _issue(self, axis: Axis) -> Command:
        return _group_of(axis).tracks.geo.register_compensation(
            axis, self.compensation_id, self.compensation_type)


class MC_TransformPosition(GroupCommand):
    """A position from one frame to another, for information only (§9.2.1.2): 0 is the
    absolute motor path, a template's OTCID its TCP path. Called as ``fb(group, ...)``.

    Inputs: execute, origin_oid, destination_oid, origin_position [mm]. Outputs: done, busy,
    error, error_id, destination_position [mm] (set with done). Error ids: UNKNOWN_TEMPLATE,
    INVALID_POSITION.
    """

    INPUTS: ClassVar[dict[str, Any]] = {"origin_oid": 0, "destination_oid": 0,
                                        "origin_position": 0.0}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.destination_position = 0.0

    def _issue(self, group: CaGroup) -> Command:  # type: ignore[override]
        value = group.tracks.geo.transform_position(self.origin_oid, self.destination_oid,
                                                    self.origin_position)
        command = Command("transform_position", group.runtime.now)
        command.value = value
        command.end(CommandStatus.DONE, command.issued_at)
        return command

    def _show_result(self, command: Command | None) -> None:
        if command is not None and command.done:
            assert isinstance(command.value, float)
            self.destination_position = command.value
