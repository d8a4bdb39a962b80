"""The PLCopen Part 4 function blocks over the ``AxesGroup`` Python API (§5, §6).

The administration blocks (MC_AddAxisToGroup, MC_GroupEnable, MC_GroupReset, ...) are the
same classes as for the CA group (transport/blocks.py): one set of group blocks for both kinds
of group. MC_GroupStop and MC_GroupHalt extend the CA group's with Part 4's BufferMode input.
This module adds the rest. The group comes first, as there::

    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[100.0, 50.0, 0.0], velocity=200.0)

Positions are sequences: one value per member in ACS, one per kinematics coordinate in MCS
and PCS (``group.kinematics.coordinates``). Dynamics inputs take numbers > 0, MC_DEFAULT
(the group's defaults) or MC_MAXIMUM. Short names (§1.3.1) are aliases of the same classes.
"""

# ruff: noqa: N801 - the standard's block names

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.coordinated.cam import PathMode
from openmotion.coordinated.frames import CartesianTransform, Frame
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem, TransitionMode, enum_value
from openmotion.coordinated.path_table import (
    MC_PATH_DATA_REF,
    MC_BlockerPreparation,
    MC_DwellTimePreparation,
    MC_GroupReadBlockerStatus,
    MC_MoveCircularAbsolutePreparation,
    MC_MoveLinearAbsolutePreparation,
    MC_ReleaseBlocker,
    MC_SetCoordinateTransformPreparation,
)
from openmotion.coordinated.paths import PathData, select_path
from openmotion.coordinated.states import ExecutionMode
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.special_values import MC_DEFAULT
from openmotion.geometry.path import CircMode, PathChoice
from openmotion.kernel import group_blocks
from openmotion.kernel.group_blocks import (
    GroupCommand,
    GroupRead,
    MC_AddAxisToGroup,
    MC_GroupDisable,
    MC_GroupEnable,
    MC_GroupReadError,
    MC_GroupReadStatus,
    MC_GroupReset,
    MC_RemoveAxisFromGroup,
    MC_UngroupAllAxes,
)

__all__ = [
    "MC_AddAxisToGroup", "MC_GroupContinue", "MC_GroupDisable", "MC_GroupEnable",
    "MC_GroupHalt", "MC_GroupHome", "MC_GroupInterrupt", "MC_GroupReadActualAcceleration",
    "MC_GroupReadActualPosition", "MC_GroupReadActualVelocity", "MC_GroupReadConfiguration",
    "MC_GroupReadError", "MC_GroupReadStatus", "MC_GroupReset", "MC_GroupSetOverride",
    "MC_GroupSetPosition", "MC_GroupStop", "MC_MoveCircularAbsolute", "MC_MoveCircularRelative",
    "MC_MoveDirectAbsolute", "MC_MoveDirectRelative", "MC_MoveLinearAbsolute",
    "MC_MoveLinearRelative", "MC_MovePath", "MC_PathSelect", "MC_ReadCartesianTransform",
    "MC_ReadCoordinateTransform", "MC_ReadKinTransform", "MC_RemoveAxisFromGroup",
    "MC_SetCartesianTransform", "MC_SetCoordinateTransform", "MC_SetKinTransform",
    "MC_SetDynCoordTransform", "MC_SyncAxisToGroup", "MC_SyncGroupToAxis",
    "MC_TrackConveyorBelt",
    "MC_TrackRotaryTable", "MC_UngroupAllAxes",
    # TF5410 §9.3's path tables on the same group (path_table.py)
    "MC_BlockerPreparation", "MC_DwellTimePreparation", "MC_GroupReadBlockerStatus",
    "MC_MoveCircularAbsolutePreparation", "MC_MoveLinearAbsolutePreparation",
    "MC_ReleaseBlocker", "MC_SetCoordinateTransformPreparation",
]
#: the blocks of TF5410 §9.3 that Part 4 does not have (MC_MovePath is both)
TF5410_PATH_TABLE_BLOCKS = frozenset(__all__[-7:])

_DYNAMICS: dict[str, Any] = {"velocity": MC_DEFAULT, "acceleration": MC_DEFAULT,
                             "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}
_BLENDING: dict[str, Any] = {"buffer_mode": BufferMode.ABORTING,
                             "transition_mode": TransitionMode.TM_NONE,
                             "transition_parameter": None}


def _group(reference: Any) -> AxesGroup:
    if not isinstance(reference, AxesGroup):
        raise TypeError("this block needs a Part 4 AxesGroup: call it as fb(group, ...)")
    return reference


# -- motion (§5.20-§5.27) --------------------------------------------------------------------------


class _Move(GroupCommand):
    INPUTS: ClassVar[dict[str, Any]] = {**_DYNAMICS, "coord_system": CoordSystem.MCS,
                                        **_BLENDING}

    def _common(self) -> dict[str, Any]:
        return {name: getattr(self, name) for name in (*_DYNAMICS, "coord_system", *_BLENDING)}


class MC_MoveLinearAbsolute(_Move):
    """Straight line to ``position`` (§5.20). Outputs: done, busy, active, command_aborted,
    error, error_id. Error ids: INVALID_POSITION, INVALID_VELOCITY ... INVALID_JERK,
    INVALID_MODE (TransitionMode 5-9, Aborting with a corner mode), the group's refusals."""

    INPUTS: ClassVar[dict[str, Any]] = {"position": None}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).move_linear_absolute(self.position, **self._common())


class MC_MoveLinearRelative(_Move):
    """Straight line by ``distance`` from the start (§5.21)."""

    INPUTS: ClassVar[dict[str, Any]] = {"distance": None}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).move_linear_relative(self.distance, **self._common())


class MC_MoveCircularAbsolute(_Move):
    """Arc to ``end_point`` (§5.22): ``circ_mode`` BORDER (``aux_point`` on the arc), CENTER
    (the centre) or RADIUS (the plane normal, its length the radius); ``path_choice``
    picks the short (COUNTERCLOCKWISE) or the long (CLOCKWISE) arc."""

    INPUTS: ClassVar[dict[str, Any]] = {"circ_mode": CircMode.BORDER, "aux_point": None,
                                        "end_point": None,
                                        "path_choice": PathChoice.COUNTERCLOCKWISE}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).move_circular_absolute(self.aux_point, self.end_point,
                                                    self.circ_mode, self.path_choice,
                                                    **self._common())


class MC_MoveCircularRelative(MC_MoveCircularAbsolute):
    """As MC_MoveCircularAbsolute, with points relative to the start (§5.23)."""

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).move_circular_relative(self.aux_point, self.end_point,
                                                    self.circ_mode, self.path_choice,
                                                    **self._common())


class MC_MoveDirectAbsolute(_Move):
    """Point to point in joint space (§5.24); ``coord_system`` defaults to ACS."""

    INPUTS: ClassVar[dict[str, Any]] = {"position": None, "coord_system": CoordSystem.ACS}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).move_direct_absolute(self.position, **self._common())


class MC_MoveDirectRelative(_Move):
    """Point to point by ``distance`` (§5.25)."""

    INPUTS: ClassVar[dict[str, Any]] = {"distance": None, "coord_system": CoordSystem.ACS}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).move_direct_relative(self.distance, **self._common())


class MC_PathSelect(GroupCommand):
    """Prepare ``path_description`` (§5.26): a list of elements (see coordinated/paths.py)
    becomes ``path_data`` for MC_MovePath; Done at once. ``transition_mode`` and
    ``transition_parameter`` (ours) round the corners inside the path; an element may set
    its own. Error: INVALID_PATH_GEOMETRY, INVALID_POSITION, INVALID_MODE."""

    INPUTS: ClassVar[dict[str, Any]] = {"path_description": None,
                                        "coord_system": CoordSystem.MCS,
                                        "transition_mode": TransitionMode.TM_MAX_CORNER_DEVIATION,
                                        "transition_parameter": 0.1}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.path_data: PathData | None = None

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        command = Command("MC_PathSelect", _group(group).runtime.now)
        try:
            self.path_data = select_path(group, self.path_description, self.coord_system,
                                         self.transition_mode, self.transition_parameter)
        except CommandRejected as rejected:
            command.end(CommandStatus.ERROR, command.issued_at, rejected.error_id,
                         rejected.message)
            return command
        command.value = self.path_data
        command.end(CommandStatus.DONE, command.issued_at)
        return command


class MC_MovePath(_Move):
    """Run ``path_data`` from MC_PathSelect (§5.27): Done at the end of the path. With an
    ``MC_PATH_DATA_REF`` it is TF5410's MC_MovePath (§9.3.1.2.5): the table's rows carry
    their own dynamics and modes, so the other inputs are not read (path_table.py)."""

    INPUTS: ClassVar[dict[str, Any]] = {"path_data": None}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        if isinstance(self.path_data, MC_PATH_DATA_REF):
            return _group(group).move_path_table(self.path_data)
        common = self._common()
        return _group(group).move_path(self.path_data, **common)


# -- administration and stopping (§5.4, §5.7, §5.9, §5.15, §5.16, §5.28) ----------------------


class MC_GroupHome(GroupCommand):
    """Home every member (§5.7); ``position``: where the group is after homing, in
    ``coord_system`` (ACS: one value per axis; MCS, PCS: per coordinate, taken back to the
    axes through the transforms in force), or None for the configured ones.
    ``buffer_mode`` Aborting needs GroupStandby; Buffered (the Blending modes act as
    Buffered) waits, Busy and not Active, until the motion before it is over."""

    INPUTS: ClassVar[dict[str, Any]] = {"position": None, "buffer_mode": BufferMode.ABORTING,
                                        "coord_system": CoordSystem.ACS}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).home(self.position, self.buffer_mode, self.coord_system)


class _BufferedBrake:
    """Part 4's BufferMode on the CA group's stop blocks (§5.13, §5.14): a CA group
    (TF5410) has none, so there only Aborting, the default, is accepted."""

    INPUTS: ClassVar[dict[str, Any]] = {"buffer_mode": BufferMode.ABORTING}
    deceleration: Any
    jerk: Any
    buffer_mode: Any
    method: ClassVar[str]

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        if isinstance(group, AxesGroup):
            return getattr(group, self.method)(self.deceleration, self.jerk, self.buffer_mode)
        if self.buffer_mode is not BufferMode.ABORTING and self.buffer_mode != 0:
            raise CommandRejected(ErrorId.INVALID_MODE, "a CA group's stop blocks have no "
                                  "BufferMode (Tc3_McCoordinatedMotion §9.3.1.2)")
        return super()._issue(group)  # type: ignore[misc]


class MC_GroupStop(_BufferedBrake, group_blocks.MC_GroupStop):
    """MC_GroupStop (§5.13) with ``buffer_mode``: Aborting stops at once; Buffered (the
    Blending modes act as Buffered) waits, Busy and not Active, until the motion before
    it is over, then stops the group at rest (decisions D-194). As the CA group's
    otherwise (transport/blocks.py)."""

    method = "stop"


class MC_GroupHalt(_BufferedBrake, group_blocks.MC_GroupHalt):
    """MC_GroupHalt (§5.14) with ``buffer_mode``: Buffered (the Blending modes act as
    Buffered) waits until the motion before it is over and is Done then (D-194)."""

    method = "halt"


class MC_GroupSetPosition(GroupCommand):
    """New coordinates without motion (§5.9); ``relative`` adds them. ``buffer_mode`` as
    MC_GroupHome: Aborting needs GroupStandby, the others wait for the motion before."""

    INPUTS: ClassVar[dict[str, Any]] = {"position": None, "relative": False,
                                        "coord_system": CoordSystem.ACS,
                                        "buffer_mode": BufferMode.ABORTING}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).set_position(self.position, bool(self.relative), self.coord_system,
                                          self.buffer_mode)


class MC_GroupInterrupt(GroupCommand):
    """Brake along the path and keep the rest (§5.15); Done at standstill."""

    INPUTS: ClassVar[dict[str, Any]] = {"deceleration": MC_DEFAULT, "jerk": MC_DEFAULT}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).interrupt(self.deceleration, self.jerk)


class MC_GroupContinue(GroupCommand):
    """Resume an interrupted path (§5.16). Error: NOTHING_TO_DO without an interrupt."""

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).continue_()


class MC_GroupSetOverride(GroupRead):
    """Factors on the path dynamics while ``enable`` (§5.28); ``enabled`` once applied. The
    last factors stay in force after ``enable`` falls (rule 94)."""

    INPUTS: ClassVar[dict[str, Any]] = {"vel_factor": 1.0, "acc_factor": 1.0,
                                        "jerk_factor": 1.0}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.enabled = False

    def _read(self, group: Any) -> None:
        command = _group(group).set_override(self.vel_factor, self.acc_factor, self.jerk_factor)
        if command.error:
            self.enabled = False
            raise CommandRejected(command.error_id, command.message)
        self.enabled = True


class MC_GroupReadActualPosition(GroupRead):
    """``position`` in ``coord_system`` (§5.10): per member (ACS) or per coordinate."""

    INPUTS: ClassVar[dict[str, Any]] = {"coord_system": CoordSystem.ACS}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.position: np.ndarray | None = None

    def _read(self, group: Any) -> None:
        coord = enum_value(CoordSystem, self.coord_system, "CoordSystem")
        self.position = _group(group).position(coord)


class MC_GroupReadActualVelocity(GroupRead):
    """``velocity`` in ``coord_system`` and ``path_velocity``, the TCP speed (§5.11)."""

    INPUTS: ClassVar[dict[str, Any]] = {"coord_system": CoordSystem.ACS}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.velocity: np.ndarray | None = None
        self.path_velocity = 0.0

    def _read(self, group: Any) -> None:
        coord = enum_value(CoordSystem, self.coord_system, "CoordSystem")
        self.velocity, self.path_velocity = _group(group).velocity(coord)


class MC_GroupReadActualAcceleration(GroupRead):
    """``acceleration`` and ``path_acceleration`` (§5.12; positive while speeding up)."""

    INPUTS: ClassVar[dict[str, Any]] = {"coord_system": CoordSystem.ACS}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.acceleration: np.ndarray | None = None
        self.path_acceleration = 0.0

    def _read(self, group: Any) -> None:
        coord = enum_value(CoordSystem, self.coord_system, "CoordSystem")
        self.acceleration, self.path_acceleration = _group(group).acceleration(coord)


class MC_GroupReadConfiguration(GroupRead):
    """The member with ``ident_in_group`` (ACS), or a view of MCS/PCS coordinate
    ``ident_in_group`` (1-based) whose ``position`` is the TCP's (§5.4, rule 35)."""

    INPUTS: ClassVar[dict[str, Any]] = {"coord_system": CoordSystem.ACS, "ident_in_group": None}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.axis_ref: Any = None

    def _read(self, group: Any) -> None:
        group = _group(group)
        coord = enum_value(CoordSystem, self.coord_system, "CoordSystem")
        ident = getattr(self.ident_in_group, "value", self.ident_in_group)
        if coord is CoordSystem.ACS:
            if ident not in group.members:
                raise CommandRejected(ErrorId.AXIS_NOT_IN_GROUP,
                                      f"no member has IdentInGroup {ident!r}")
            self.axis_ref = group.members[ident]
            return
        size = len(group.kinematics.coordinates)
        if not isinstance(ident, int) or not 1 <= ident <= size:
            raise CommandRejected(ErrorId.INVALID_IDENT,
                                  f"coordinate {ident!r}: 1..{size} in {coord.name}")
        self.axis_ref = CoordinateView(group, coord, ident - 1)


class CoordinateView:
    """One MCS or PCS coordinate of a group, read like an axis (§5.4: a virtual axis)."""

    def __init__(self, group: AxesGroup, coord: CoordSystem, index: int) -> None:
        self.group, self.coord, self.index = group, coord, index
        self.name = f"{group.name}.{coord.name}.{group.kinematics.coordinates[index]}"

    @property
    def position(self) -> float:
        return float(self.group.position(self.coord)[self.index])


# -- coordinate systems (§5.8) ------------------------------------------------------------------


class MC_SetKinTransform(GroupCommand):
    """Set the ACS <-> MCS model (§5.8.1): ``kin_transform`` is a ``Kinematics``."""

    INPUTS: ClassVar[dict[str, Any]] = {"kin_transform": None,
                                        "execution_mode": ExecutionMode.IMMEDIATELY}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).set_kinematics(self.kin_transform, self.execution_mode)


class MC_ReadKinTransform(GroupRead):
    """``kin_transform``: the model in force (§5.8.4)."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.kin_transform: Any = None

    def _read(self, group: Any) -> None:
        self.kin_transform = _group(group).kinematics


class MC_SetCartesianTransform(GroupCommand):
    """One more Cartesian transform of the PCS (§5.8.2): translation [mm], then rotations
    [°] about z, y, x (frames.py), composed with those active (given in the frame they set
    up); all zeros de-select the PCS. Ends a tracking FB on the PCS."""

    INPUTS: ClassVar[dict[str, Any]] = {"trans_x": 0.0, "trans_y": 0.0, "trans_z": 0.0,
                                        "rot_x": 0.0, "rot_y": 0.0, "rot_z": 0.0,
                                        "execution_mode": ExecutionMode.IMMEDIATELY}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        try:
            frame = Frame.from_cartesian(self.trans_x, self.trans_y, self.trans_z,
                                         self.rot_x, self.rot_y, self.rot_z)
        except (ValueError, TypeError) as bad:
            raise CommandRejected(ErrorId.INVALID_POSITION, str(bad)) from None
        return _group(group).set_cartesian_transform(frame, self.execution_mode)


class MC_ReadCartesianTransform(GroupRead):
    """The PCS placement in force as trans_x ... rot_z (§5.8.5)."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.trans_x = self.trans_y = self.trans_z = 0.0
        self.rot_x = self.rot_y = self.rot_z = 0.0

    def _read(self, group: Any) -> None:
        group = _group(group)
        values = group.spaces.frame(group.runtime.now).cartesian()
        (self.trans_x, self.trans_y, self.trans_z,
         self.rot_x, self.rot_y, self.rot_z) = values


class MC_SetCoordinateTransform(GroupCommand):
    """Place the PCS in the MCS (§5.8.3), replacing the transforms active before:
    ``coord_transform`` is a ``Frame`` or six values (trans_x, trans_y, trans_z, rot_x,
    rot_y, rot_z)."""

    INPUTS: ClassVar[dict[str, Any]] = {"coord_transform": None,
                                        "execution_mode": ExecutionMode.IMMEDIATELY}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).set_coordinate_transform(_frame(self.coord_transform),
                                                      self.execution_mode)


class MC_ReadCoordinateTransform(GroupRead):
    """``coord_transform``: the PCS placement in force, a ``Frame`` (§5.8.6)."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.coord_transform: Frame | None = None

    def _read(self, group: Any) -> None:
        group = _group(group)
        self.coord_transform = group.spaces.frame(group.runtime.now)


def _frame(value: Any) -> Frame:
    if isinstance(value, Frame):
        return value
    try:
        return Frame.from_cartesian(*CartesianTransform(*value))
    except (TypeError, ValueError):
        raise CommandRejected(ErrorId.INVALID_POSITION,
                              "CoordTransform: a Frame or six numbers (trans_x, trans_y, "
                              "trans_z, rot_x, rot_y, rot_z)") from None


# -- synchronisation and tracking (§6) -----------------------------------------------------------


class _Tracking(GroupCommand):
    """A block that sets a moving PCS (§6.5-§6.7): Done once the transformation is set (at
    once), with Busy FALSE (§3.3: Busy falls with Done); Active while the frame is computed
    every cycle, whatever Execute does; CommandAborted when another transform replaces it
    (decisions D-131). Done follows Execute as any result does: shown at least one cycle."""

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self._set_shown = False

    def _clear(self) -> None:
        super()._clear()
        self._set_shown = False

    def _show_progress(self, command: Command) -> None:
        if command.status is CommandStatus.BUFFERED:  # a buffered one waits: Busy only
            return
        self.busy = False
        self.done = bool(self.execute) or not self._set_shown
        self._set_shown = True

    def _show_result(self, command: Command | None) -> None:
        if command is None:  # Execute fell after the end: outputs reset
            self._set_shown = False


class MC_TrackConveyorBelt(_Tracking):
    """The PCS rides on ``conveyor_belt`` (an axis) (§6.6): ``conveyor_belt_origin`` places the
    belt frame in the MCS (its x axis is the belt's direction), ``initial_object_position``
    the object on the belt. Done once set, Active while tracking; CommandAborted when another
    transform FB replaces the PCS. Moves in PCS then follow the object. ``coord_system``:
    PCS, the one system that can move (others: INVALID_MODE); ``buffer_mode``: Aborting
    sets it now, Buffered (the Blending modes act as Buffered) when the motion before it is
    over, Busy and not Active until then (decisions D-194)."""

    INPUTS: ClassVar[dict[str, Any]] = {"conveyor_belt": None, "conveyor_belt_origin": None,
                                        "initial_object_position": None,
                                        "coord_system": CoordSystem.PCS,
                                        "buffer_mode": BufferMode.ABORTING}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).track_conveyor_belt(
            _axis_input(self.conveyor_belt, "ConveyorBelt"),
            _frame_or_identity(self.conveyor_belt_origin),
            _frame_or_identity(self.initial_object_position), self.coord_system,
            self.buffer_mode)


class MC_TrackRotaryTable(_Tracking):
    """The PCS turns with ``rotary_table`` (an axis, degrees) about the z axis of
    ``rotary_table_origin`` (§6.7); ``coord_system`` and ``buffer_mode`` as
    MC_TrackConveyorBelt."""

    INPUTS: ClassVar[dict[str, Any]] = {"rotary_table": None, "rotary_table_origin": None,
                                        "initial_object_position": None,
                                        "coord_system": CoordSystem.PCS,
                                        "buffer_mode": BufferMode.ABORTING}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).track_rotary_table(
            _axis_input(self.rotary_table, "RotaryTable"),
            _frame_or_identity(self.rotary_table_origin),
            _frame_or_identity(self.initial_object_position), self.coord_system,
            self.buffer_mode)


class MC_SetDynCoordTransform(_Tracking):
    """This group's PCS rides on the TCP of ``master`` (another AxesGroup), offset by
    ``coord_transform`` (§6.5). ``mode`` (MC_PathMode) is checked and changes nothing (the
    PCS follows the master's TCP whatever its path); ``coord_system`` and ``buffer_mode``
    as MC_TrackConveyorBelt (decisions D-194)."""

    INPUTS: ClassVar[dict[str, Any]] = {"master": None, "coord_transform": None,
                                        "mode": PathMode.NON_PERIODIC,
                                        "coord_system": CoordSystem.PCS,
                                        "buffer_mode": BufferMode.ABORTING}

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        if not isinstance(self.master, AxesGroup):
            raise CommandRejected(ErrorId.INVALID_MODE, "Master: an AxesGroup")
        return _group(group).set_dyn_coord_transform(
            self.master, _frame_or_identity(self.coord_transform), self.mode,
            self.coord_system, self.buffer_mode)


class MC_SyncAxisToGroup(GroupCommand):
    """``slave`` (an axis outside the group) counts the group's path length (§6.3): it ramps
    in to ratio_numerator / ratio_denominator x the path speed in ``coord_system`` with
    ``acceleration``, ``deceleration`` and ``jerk`` (MC_DEFAULT: the slave's defaults), then
    locks in position. ``in_sync`` once locked; a single-axis command to the slave ends it
    (CommandAborted). Retriggering with a new ratio replaces it (rule 116). ``buffer_mode``
    Buffered (the Blending modes act as Buffered) waits until the slave's own command is
    over (decisions D-193)."""

    INPUTS: ClassVar[dict[str, Any]] = {"slave": None, "ratio_numerator": 1.0,
                                        "ratio_denominator": 1.0, "acceleration": MC_DEFAULT,
                                        "deceleration": MC_DEFAULT, "jerk": MC_DEFAULT,
                                        "coord_system": CoordSystem.MCS,
                                        "buffer_mode": BufferMode.ABORTING}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.in_sync = False

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).sync_axis_to_group(
            _axis_input(self.slave, "Slave"), self.ratio_numerator, self.ratio_denominator,
            self.acceleration, self.deceleration, self.jerk, self.coord_system,
            self.buffer_mode)

    def _show_progress(self, command: Command) -> None:
        self.in_sync = command.in_velocity

    def _show_result(self, command: Command | None) -> None:
        self.in_sync = False


class MC_SyncGroupToAxis(GroupCommand):
    """The group's arc length along ``path_data`` (MC_PathSelect) follows ``master`` like a
    cam (§6.4): s = tuc_numerator / tuc_denominator x (master - master when it couples).
    ``buffer_mode`` Aborting takes over a moving group (it brakes along its path, then
    couples there); Buffered (the Blending modes act as Buffered) waits, Busy and not
    Active, until the motion before it is over (decisions D-193). ``in_sync`` once
    synchronised; MC_GroupStop or any other motion command ends it (CommandAborted); never
    Done."""

    INPUTS: ClassVar[dict[str, Any]] = {
        "master": None, "path_data": None, "mode": PathMode.NON_PERIODIC, "tuc_numerator": 1,
        "tuc_denominator": 1, "acceleration": MC_DEFAULT, "deceleration": MC_DEFAULT,
        "jerk": MC_DEFAULT, "coord_system": CoordSystem.MCS, "buffer_mode": BufferMode.ABORTING}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.in_sync = False

    def _issue(self, group: Any) -> Command:  # type: ignore[override]
        return _group(group).sync_group_to_axis(
            _axis_input(self.master, "Master"), self.path_data, self.mode, self.tuc_numerator,
            self.tuc_denominator, self.acceleration, self.deceleration, self.jerk,
            self.coord_system, self.buffer_mode)

    def _show_progress(self, command: Command) -> None:
        self.in_sync = command.in_velocity

    def _show_result(self, command: Command | None) -> None:
        self.in_sync = False


def _frame_or_identity(value: Any) -> Frame:
    """A frame input; None (not given) is the identity."""
    return Frame() if value is None else _frame(value)


def _axis_input(value: Any, name: str) -> Any:
    from openmotion.axis.axis import Axis
    if not isinstance(value, Axis):
        raise CommandRejected(ErrorId.INVALID_MODE, f"{name}: an axis is needed")
    return value


# -- short names (§1.3.1) --------------------------------------------------------------------------

MC_AddAxisToGrp = MC_AddAxisToGroup
MC_RemAxisFromGrp = MC_RemoveAxisFromGroup
MC_GrpReadCfg = MC_GroupReadConfiguration
MC_GrpEnable = MC_GroupEnable
MC_GrpDisable = MC_GroupDisable
MC_GrpHome = MC_GroupHome
MC_SetKinTrans = MC_SetKinTransform
MC_SetCartTrans = MC_SetCartesianTransform
MC_SetCoordTrans = MC_SetCoordinateTransform
MC_ReadKinTrans = MC_ReadKinTransform
MC_ReadCartTrans = MC_ReadCartesianTransform
MC_ReadCoordTrans = MC_ReadCoordinateTransform
MC_GrpReadActPos = MC_GroupReadActualPosition
MC_GrpReadActVel = MC_GroupReadActualVelocity
MC_GrpReadActAcc = MC_GroupReadActualAcceleration
MC_GrpStop = MC_GroupStop
MC_GrpHalt = MC_GroupHalt
MC_GrpInterrupt = MC_GroupInterrupt
MC_GrpContinue = MC_GroupContinue
MC_GrpReadStatus = MC_GroupReadStatus
MC_GrpReadError = MC_GroupReadError
MC_GrpReset = MC_GroupReset
MC_GrpSetOverride = MC_GroupSetOverride
MC_SyncGrpToAxis = MC_SyncGroupToAxis
MC_SyncAxisToGrp = MC_SyncAxisToGroup
MC_SetDynCoordTrans = MC_SetDynCoordTransform
MC_TrackConvBelt = MC_TrackConveyorBelt
MC_MoveLinAbs = MC_MoveLinearAbsolute
MC_MoveLinRel = MC_MoveLinearRelative
MC_MoveCircAbs = MC_MoveCircularAbsolute
MC_MoveCircRel = MC_MoveCircularRelative
MC_MoveDirAbs = MC_MoveDirectAbsolute
MC_MoveDirRel = MC_MoveDirectRelative
