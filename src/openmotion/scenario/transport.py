"""CA groups in scenario files: the ``ca_groups`` list and the timeline entries of TF5410.

A CA group (transport/group.py) owns the setpoints of its movers, so their motion commands
go through the group: ``move_absolute_ca``, ``move_relative_ca`` and ``halt_ca`` name the
mover in ``axis`` (the run finds its group), ``set_gap`` changes the gap of a running move
with ``continuous_update``, ``activate_track`` and ``register_compensation`` pick the frame
of a mover's later moves (the group's parts, tracks and templates: scenario/tracks.py), and
the group commands (``group_halt``, ``group_stop``, ``group_enable``, ``group_disable``,
``group_reset``) name the group in ``group`` instead of an axis. The membership blocks
(``add_axis_to_group`` ...), the group reads and MC_TransformPosition are called once as
blocks on either kind of group, MC_ReadTrackPositions on a mover (scenario/queries.py).

schema.py puts these models into its ``COMMANDS``, ``TimelineEntry`` and ``Scenario``; they
share its value types, conditions and name checks.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Literal, get_type_hints

from pydantic import (
    AfterValidator,
    Field,
    StrictBool,
    StrictInt,
    StrictStr,
    ValidationError,
    create_model,
    model_validator,
)
from pydantic_core import InitErrorDetails, PydanticCustomError

from openmotion.axis.commands import Command
from openmotion.core.enums import BufferMode
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE
from openmotion.scenario.queries import Called, Query, block_query
from openmotion.scenario.schema import (
    _NAMES,
    BufferModeName,
    ConditionText,
    Entry,
    Identifier,
    InputValue,
    Number,
    Seconds,
    _check_axis,
    _check_group,
    _check_id,
    _check_mover,
    _enum_by_name,
    _Model,
    _parameter_type,
    _unique,
    with_options,
)
from openmotion.scenario.stations import RouteSpec, StationSpec, station_problems
from openmotion.scenario.tracks import GeometrySpec, PartSpec, TemplateSpec, TrackSpec, problems
from openmotion.transport.blocks import (
    MC_AddAxisToGroup,
    MC_GroupReadError,
    MC_GroupReadStatus,
    MC_RemoveAxisFromGroup,
    MC_UngroupAllAxes,
    ST_HaltCAOptions,
    ST_MoveAbsoluteCAOptions,
    ST_MoveRelativeCAOptions,
)
from openmotion.transport.enums import (
    GapControlMode,
    MasterSignalCorrection,
    ModuloDirection,
    SyncMode,
    SyncStrategy,
)
from openmotion.transport.gear_blocks import ST_GearInPosCAOptions
from openmotion.transport.group import UDINT_TO_IDENTINGROUP, CaGroup
from openmotion.transport.parameters import CaGroupParameters
from openmotion.transport.track_blocks import MC_ReadTrackPositions, MC_TransformPosition

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime

GapControlModeName = _enum_by_name(GapControlMode)
ModuloDirectionName = _enum_by_name(ModuloDirection)
SyncStrategyName = _enum_by_name(SyncStrategy)
SyncModeName = _enum_by_name(SyncMode)
MasterSignalCorrectionName = _enum_by_name(MasterSignalCorrection)
CA_MOVES = ("move_absolute_ca", "move_relative_ca")  #: the entries ``set_gap`` can change
#: an OTCID input of a block: a UDINT; 0 = none (the absolute frame, the motor path)
OidInput = Annotated[StrictInt, Field(ge=0, le=0xFFFFFFFF)]

# -- ca_groups -----------------------------------------------------------------------------


class _CaParametersBase(_Model):
    @model_validator(mode="after")
    def _in_range(self) -> _CaParametersBase:
        self.build()  # CaGroupParameters.validate names the field: "rail_length: must be > 0"
        return self

    def build(self) -> CaGroupParameters:
        parameters = CaGroupParameters(**{name: getattr(self, name)
                                          for name in self.model_fields_set})
        parameters.validate()
        return parameters


_HINTS = get_type_hints(CaGroupParameters)
#: the group parameters a scenario sets: all of them (TF5410 §6)
_SCENARIO_PARAMETERS = dataclasses.fields(CaGroupParameters)
CaGroupParametersSpec = create_model(
    "CaGroupParametersSpec",
    __base__=_CaParametersBase,
    __doc__="Fields of CaGroupParameters (transport/parameters.py, TF5410 §6), same name and "
            "unit; unset fields keep their defaults. Enums by lower-case name "
            "(default_gap_control_mode: fast, gap_control_direction: positive, "
            "gear_in_pos_default_dynamics_after_sync: maximum_slave_dynamics).",
    **{f.name: (_parameter_type(_HINTS[f.name]), f.default) for f in _SCENARIO_PARAMETERS},
)


def _not_an_axis(name: str) -> str:
    names = _NAMES.get()
    if names is not None and name in names.axes:
        raise ValueError(f"{name!r} is an axis name; a CA group needs a name of its own")
    return name


def _in_one_group(name: str) -> str:
    _check_axis(name)
    names = _NAMES.get()
    groups = names.members.get(name, []) if names is not None else []
    if len(groups) > 1:
        raise ValueError(f"{name!r} is listed {len(groups)} times in ca_groups "
                         f"({', '.join(groups)}); an axis is in one CA group only")
    return name


class CaGroupSpec(_Model):
    """A CA group (TF5410): its movers in insertion order and its parameters.

    The run builds the group after the axes and adds the axes with IdentInGroup 1, 2, ...
    in the listed order (the CA order follows the positions, §8.1.1). With ``enable`` the run
    powers every member (a CA mover needs MC_Power) and enables the group at t = 0.
    """

    name: Annotated[Identifier, _unique("groups"), AfterValidator(_not_an_axis)]
    """Unique name, not an axis name; group entries and conditions refer to it."""
    axes: Annotated[list[Annotated[StrictStr, AfterValidator(_in_one_group)]],
                    Field(min_length=1)]
    """The member axes, added in this order (IdentInGroup 1..n)."""
    parameters: CaGroupParametersSpec = CaGroupParametersSpec()  # type: ignore[valid-type]
    """CaGroupParameters fields to set (the rest keep their defaults)."""
    enable: StrictBool = True
    """Power the members and enable the group at t = 0; false: the timeline does it
    (power entries, then group_enable)."""
    parts: list[PartSpec] = []
    """Parts of the rail (group.tracks.add_part), in this order."""
    tracks: list[TrackSpec] = []
    """Tracks of adjacent parts (group.tracks.add_track); activate_track names one."""
    geometry: GeometrySpec | None = None
    """The starter-kit geometry (group.tracks.geo.set_geometry); templates need it."""
    templates: list[TemplateSpec] = []
    """Mover templates (group.tracks.geo.add_template); register_compensation names one."""
    stations: list[StationSpec] = []
    """Stations on the rail (scenario/stations.py); routes send movers round them."""
    routes: list[RouteSpec] = []
    """The stations movers of the group visit, in order (scenario/stations.py)."""

    @model_validator(mode="after")
    def _tracks_build(self) -> CaGroupSpec:
        """Parts, tracks, geometry and templates go onto a scratch group as the run will put
        them onto the real one; each failure names its field. Stations and routes are checked
        as the run will build them."""
        parameters = self.parameters.build()
        found = problems(self) + station_problems(
            self.stations, self.routes, list(self.axes), parameters.rail_length,
            parameters.rail_is_ring)
        if found:
            raise ValidationError.from_exception_data(type(self).__name__, [
                InitErrorDetails(type=PydanticCustomError("value_error", message), loc=loc,
                                 input=None) for loc, message in found])
        return self


# -- timeline entries on a mover -----------------------------------------------------------


class CaEntry(Entry):
    """A CA command for one mover: the run calls the method of the mover's group (of
    ``group.tracks`` or ``group.tracks.geo`` when ``owner`` says so)."""

    owner: ClassVar[str] = ""  #: the attribute path from the group to ``method``'s object
    axis: Annotated[StrictStr, AfterValidator(_check_mover)]
    """Name of the mover (an axis of one of the ca_groups)."""


class _CaMove(CaEntry):
    velocity: InputValue
    """[mm/s]; MC_MAXIMUM = axis maximum."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    gap: InputValue = MC_DEFAULT
    """Minimum gap to the predecessor [mm]; MC_DEFAULT = the group's default_gap."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting or buffered (the CA blocks refuse the blending modes)."""
    gap_control_mode: GapControlModeName = GapControlMode.GROUP_DEFAULT
    """group_default, standard, fast or none."""
    continuous_update: StrictBool = False
    """A ``set_gap`` entry may change the gap while the command runs."""


def _with_options(entry: type[_Model], options: type) -> Any:
    """``entry`` with the fields of a CA options struct (schema.with_options, D-235). A
    reference system is an OTCID: 0 = the motor path; the template the mover registered
    (register_compensation): a position or distance on its TCP path, dynamics the TCP keeps
    (in a move that meets a curve every limit is scaled by R / (R + y_shift), D-072)."""
    return with_options(entry, options, types={
        f.name: OidInput for f in dataclasses.fields(options)
        if f.name.endswith("_reference_system")})


class _MoveAbsoluteCa(_CaMove):
    """MC_MoveAbsoluteCA (TF5410 §9.1.1.1.1): Done only at the target."""

    method = "move_absolute"
    command: Literal["move_absolute_ca"]
    position: InputValue
    """Target [mm]; a modulo position (0 <= position < rail_length) with a modulo direction."""
    direction: ModuloDirectionName = ModuloDirection.NON_MODULO
    """non_modulo, positive, shortest_way or negative (modulo directions: ring rails only)."""


#: with the fields of ST_MoveAbsoluteCAOptions (additional_turns: whole extra laps of a modulo
#: move; the reference systems)
MoveAbsoluteCa = _with_options(_MoveAbsoluteCa, ST_MoveAbsoluteCAOptions)


class _MoveRelativeCa(_CaMove):
    """MC_MoveRelativeCA (TF5410 §9.1.1.1.2): Done once the distance is travelled."""

    method = "move_relative"
    command: Literal["move_relative_ca"]
    distance: InputValue
    """From the set position where the move starts [mm]."""


#: with the fields of ST_MoveRelativeCAOptions (the reference systems)
MoveRelativeCa = _with_options(_MoveRelativeCa, ST_MoveRelativeCAOptions)


class _GearInPosCa(_CaMove):
    """MC_GearInPosCA (TF5410 §9.1.1.1.4): couple the mover to ``master``'s set values.

    Never Done (another command decouples); a ``<id>.in_gear`` condition holds while in sync.
    """

    method = "gear_in_pos"
    command: Literal["gear_in_pos_ca"]
    master: Annotated[StrictStr, AfterValidator(_check_axis)]
    """The master axis (any axis)."""
    ratio_numerator: Number = 1.0
    """Gear factor numerator (any real, also negative)."""
    ratio_denominator: Annotated[StrictInt, Field(ge=1, le=0xFFFF)] = 1
    """Gear factor denominator (UINT > 0)."""
    master_sync_position: InputValue
    """Master position at which the slave is in sync [mm]."""
    slave_sync_position: InputValue
    """Slave position at that moment [mm]."""
    sync_strategy: SyncStrategyName = SyncStrategy.LATE  # type: ignore[valid-type]
    """late, slow or early."""
    sync_mode: SyncModeName = SyncMode.NON_MODULO  # type: ignore[valid-type]
    """non_modulo; positive or negative: slave_sync_position is a ring position, the next one
    from the mover in that direction."""
    master_start_distance: InputValue = MC_IGNORE
    """MC_IGNORE: sync at once; > 0: once master >= MSP - d; < 0: once master <= MSP - d."""

    def arguments(self) -> dict[str, Any]:
        arguments = super().arguments()
        del arguments["master"]
        return arguments


#: with the fields of ST_GearInPosCAOptions (§9.1.2.1; gap_control_mode is _CaMove's):
#: after_sync_velocity ... jerk (MC_DEFAULT: the group's
#: gear_in_pos_default_dynamics_after_sync), the restrictions of the profile driven while it
#: syncs (D-204), override_slave_dynamic_restrictions (D-206), master_signal_correction
#: (D-205), the reference systems (0 only, D-207)
GearInPosCa = _with_options(_GearInPosCa, ST_GearInPosCAOptions)


class _HaltCa(CaEntry):
    """MC_HaltCA (TF5410 §9.1.1.1.3): brake to rest, keeping the gap."""

    method = "halt_axis"
    command: Literal["halt_ca"]
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    gap: InputValue = MC_DEFAULT
    """Minimum gap to the predecessor [mm]."""
    gap_control_mode: GapControlModeName = GapControlMode.GROUP_DEFAULT
    """group_default, standard, fast or none."""


#: with the fields of ST_HaltCAOptions (dynamics_reference_system: the registered template: a
#: stop that meets a curve brakes at R / (R + y_shift) of deceleration and jerk)
HaltCa = _with_options(_HaltCa, ST_HaltCAOptions)


class ActivateTrack(CaEntry):
    """MC_ActivateTrack (TF5410 §9.1.1.1.6): ``track`` becomes the frame of the mover's later
    move_absolute_ca positions. Done at once; UNKNOWN_TRACK, NOT_ON_TRACK as the block."""

    owner = "tracks"
    method = "activate_track"
    command: Literal["activate_track"]
    track: OidInput
    """The id of a track of the mover's group; 0 = the absolute frame again."""

    def arguments(self) -> dict[str, Any]:
        return {"track_id": self.track}


class RegisterCompensation(CaEntry):
    """MC_RegisterCompensation (TF5410 §9.2.1.1): link the mover to a mover template, so that
    its later moves may name it as position or dynamics reference system. Done at once;
    UNKNOWN_TEMPLATE as the block."""

    owner = "tracks.geo"
    method = "register_compensation"
    command: Literal["register_compensation"]
    template: OidInput
    """The id of a template of the mover's group."""

    def arguments(self) -> dict[str, Any]:
        return {"template_id": self.template}


# -- entries without an axis ---------------------------------------------------------------


class _Timed(_Model):
    """Id and trigger of an entry that names no axis (as in Entry)."""

    method: ClassVar[str]  #: the CaGroup method the entry calls
    axis_fields: ClassVar[tuple[str, ...]] = ()
    id: Annotated[Identifier, _unique("ids")] | None = None
    """Name for conditions and checks; unique."""
    at: Seconds | None = None
    """Issue time [s]; give ``at`` or ``when``."""
    when: ConditionText | None = None
    """Issue once, in the first cycle this condition holds."""

    @model_validator(mode="after")
    def _trigger(self) -> _Timed:
        if (self.at is None) == (self.when is None):
            raise ValueError("give exactly one of 'at' (seconds) or 'when' (a condition)")
        return self


def _ca_move(name: str) -> str:
    _check_id(name)
    names = _NAMES.get()
    if names is not None and names.commands.get(name) not in CA_MOVES:
        raise ValueError(f"{name!r} is not the id of a {' or '.join(CA_MOVES)} entry")
    return name


class SetGap(_Timed):
    """ContinuousUpdate of a running CA move: its gap becomes ``gap`` at once (§1.4).

    Done at once; the row says when the group ignored it (the move is not running or has
    continuous_update false).
    """

    method = "set_gap"
    command: Literal["set_gap"]
    move: Annotated[StrictStr, AfterValidator(_ca_move)]
    """The id of the move_absolute_ca or move_relative_ca entry."""
    gap: InputValue
    """New minimum gap to the predecessor [mm]; MC_DEFAULT = the group's default_gap."""

    @property
    def axis(self) -> str:
        """No axis of its own: the summary shows the move's (the run fills it in)."""
        return ""

    def arguments(self) -> dict[str, Any]:
        return {"gap": self.gap}


class GroupEntry(_Timed):
    """A command for a whole CA group (Tc3_McCoordinatedMotion §9.3)."""

    group: Annotated[StrictStr, AfterValidator(_check_group)]
    """Name of the CA group."""

    @property
    def axis(self) -> str:
        """The group's name, for the summary's axis column."""
        return self.group

    def arguments(self) -> dict[str, Any]:
        skip = {"id", "at", "when", "group", "command", "hold", "release_at"}
        return {name: getattr(self, name) for name in type(self).model_fields
                if name not in skip}


class _GroupBrake(GroupEntry):
    """group_halt and group_stop: an axes group's take Part 4's BufferMode too."""

    buffer_mode: BufferModeName = BufferMode.ABORTING
    """Axes groups only (Part 4 §5.13, §5.14): aborting, or buffered (the blending modes act
    as buffered), which waits for the motion issued before. A CA group has none."""

    @model_validator(mode="after")
    def _buffer_mode_of_axes_groups(self) -> _GroupBrake:
        names = _NAMES.get()
        if self.buffer_mode is not BufferMode.ABORTING and names is not None \
                and self.group not in names.axes_groups:
            raise ValueError("buffer_mode: a CA group's stop and halt have none "
                             "(Tc3_McCoordinatedMotion §9.3.1.2); only axes groups")
        return self

    def arguments(self) -> dict[str, Any]:
        arguments = super().arguments()
        if self.buffer_mode is BufferMode.ABORTING:  # the CA group's methods have none
            del arguments["buffer_mode"]
        return arguments


class GroupHalt(_GroupBrake):
    """MC_GroupHalt (§9.3.1.2.1): every mover brakes to rest; the group is not locked."""

    method = "halt"
    command: Literal["group_halt"]
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""


class GroupStop(_GroupBrake):
    """MC_GroupStop (§9.3.1.2.2): brake every mover and lock the group while Execute is TRUE.

    Execute falls after ``hold`` seconds or at ``release_at``; the run goes on until then.
    """

    method = "stop"
    command: Literal["group_stop"]
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    hold: Seconds = 0.0
    """How long Execute stays TRUE [s]: released in the first cycle at or after the firing
    time + hold; 0 = one cycle."""
    release_at: Seconds | None = None
    """Instead of ``hold``: the run time [s] at which Execute falls."""

    @model_validator(mode="after")
    def _one_release(self) -> GroupStop:
        if self.release_at is not None and "hold" in self.model_fields_set:
            raise ValueError("give 'hold' or 'release_at', not both")
        return self


class GroupEnable(GroupEntry):
    """MC_GroupEnable (§9.3.1.1.3): Standby once every member is powered, else NotReady."""

    method = "enable"
    command: Literal["group_enable"]


class GroupDisable(GroupEntry):
    """MC_GroupDisable (§9.3.1.1.2): a moving group stands still at once."""

    method = "disable"
    command: Literal["group_disable"]


class GroupReset(GroupEntry):
    """MC_GroupReset (§9.3.1.1.6): clear group and member errors."""

    method = "reset"
    command: Literal["group_reset"]


# -- blocks called once: membership, reads, TransformPosition ------------------------------


class _GroupCall(GroupEntry, Called):
    """A group block (transport/blocks.py, the same for CA and axes groups) called once as
    ``fb(group, ...)``: the row follows its command, or records its outputs (queries.py)."""

    block_type: ClassVar[Any]  #: the block class
    trigger: ClassVar[str] = "execute"

    def inputs(self, group: Any, rt: Runtime) -> dict[str, Any]:
        """The block's inputs besides the trigger."""
        return {}

    def call(self, target: Any, now: float) -> Command:
        group, rt = target
        block = self.block_type(group)
        block(**{self.trigger: True}, **self.inputs(group, rt))
        if isinstance(self, Query):
            return block_query(self.command, now, block, self.outputs)
        return block.command  # type: ignore[no-any-return] - an edge always leaves one


def _ident(group: Any, number: int) -> Any:
    """IdentInGroup ``number``: a CA group takes it as UDINT_TO_IDENTINGROUP(number)."""
    return UDINT_TO_IDENTINGROUP(number) if isinstance(group, CaGroup) else number


class AddAxisToGroup(_GroupCall):
    """MC_AddAxisToGroup (TF5410 §9.3.1.1.1, Part 4 §5.1): ``axis`` joins the group as
    ``ident_in_group``. A CA group takes a standing axis even while it moves; an axes group
    only in GroupDisabled or GroupStandby. CA entries may then name the axis."""

    block_type = MC_AddAxisToGroup
    command: Literal["add_axis_to_group"]
    axis_name: Annotated[StrictStr, AfterValidator(_check_axis)] = Field(alias="axis")
    """The axis that joins."""
    ident_in_group: Annotated[StrictInt, Field(ge=0)]
    """Its IdentInGroup (an axes group's ACS order; a CA group's UDINT_TO_IDENTINGROUP)."""

    def inputs(self, group: Any, rt: Runtime) -> dict[str, Any]:
        return {"axis": rt.axes[self.axis_name],
                "ident_in_group": _ident(group, self.ident_in_group)}


class RemoveAxisFromGroup(_GroupCall):
    """MC_RemoveAxisFromGroup (TF5410 §9.3.1.1.8, Part 4 §5.2): the member with
    ``ident_in_group`` leaves; refused while it moves."""

    block_type = MC_RemoveAxisFromGroup
    command: Literal["remove_axis_from_group"]
    ident_in_group: Annotated[StrictInt, Field(ge=0)]
    """The member's IdentInGroup."""

    def inputs(self, group: Any, rt: Runtime) -> dict[str, Any]:
        return {"ident_in_group": _ident(group, self.ident_in_group)}


class UngroupAllAxes(_GroupCall):
    """MC_UngroupAllAxes (TF5410 §9.3.1.1.12, Part 4 §5.3): every member leaves."""

    block_type = MC_UngroupAllAxes
    command: Literal["ungroup_all_axes"]


class GroupReadStatus(_GroupCall, Query):
    """MC_GroupReadStatus (TF5410 §9.3.1.1.5, Part 4 §5.17): the state flags, 1 or 0."""

    block_type = MC_GroupReadStatus
    trigger = "enable"
    command: Literal["group_read_status"]
    outputs = (*MC_GroupReadStatus.STATE_FLAGS.values(), "all_axes_standing",
               "constant_velocity", "accelerating", "decelerating", "in_position")


class GroupReadError(_GroupCall, Query):
    """MC_GroupReadError (TF5410 §9.3.1.1.4, Part 4 §5.18): ``group_error_id`` (a number)."""

    block_type = MC_GroupReadError
    trigger = "enable"
    command: Literal["group_read_error"]
    outputs = ("group_error_id",)


class TransformPosition(_GroupCall, Query):
    """MC_TransformPosition (TF5410 §9.2.1.2): ``origin_position`` from one frame to another
    (0: the motor path; a template id: its TCP path); output ``destination_position``."""

    block_type = MC_TransformPosition
    command: Literal["transform_position"]
    outputs = ("destination_position",)
    origin_oid: OidInput = 0
    """The frame of origin_position."""
    destination_oid: OidInput = 0
    """The frame of the result."""
    origin_position: Number
    """[mm]."""

    def inputs(self, group: Any, rt: Runtime) -> dict[str, Any]:
        return {"origin_oid": self.origin_oid, "destination_oid": self.destination_oid,
                "origin_position": self.origin_position}


class ReadTrackPositions(CaEntry, Query):
    """MC_ReadTrackPositions (TF5410 §9.1.1.1.5): the mover's set position on its active
    track and on its part, with their ids (outputs track_position, track_id, part_position,
    part_id)."""

    method = ""
    command: Literal["read_track_positions"]
    outputs = ("track_position", "track_id", "part_position", "part_id")

    def call(self, target: Any, now: float) -> Command:
        block = MC_ReadTrackPositions(target)
        block(enable=True)
        return block_query(self.command, now, block, self.outputs)


#: the entries that call a block once (schema.COMMANDS holds them)
GROUP_CALL_ENTRIES: tuple[type, ...] = (AddAxisToGroup, RemoveAxisFromGroup, UngroupAllAxes,
                                        GroupReadStatus, GroupReadError, TransformPosition,
                                        ReadTrackPositions)

CA_ENTRIES: tuple[type, ...] = (MoveAbsoluteCa, MoveRelativeCa, GearInPosCa, HaltCa,
                                ActivateTrack, RegisterCompensation, SetGap, GroupHalt,
                                GroupStop, GroupEnable, GroupDisable, GroupReset,
                                *GROUP_CALL_ENTRIES)
