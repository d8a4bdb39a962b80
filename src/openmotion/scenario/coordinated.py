"""Axes groups (PLCopen Part 4) in scenario files: the ``axes_groups`` list and its entries.

An axes group (coordinated/group.py) moves its member axes together on a path. The list
declares each group's members in IdentInGroup order, its kinematics, its path dynamics and
its first Cartesian transform; the run builds the groups after the axes and the CA groups
(coordinated_machine.py). Timeline entries name the group in ``group`` and call the
``AxesGroup`` method of the same name with its argument names: the moves
(``move_linear_absolute`` ...), ``move_path`` (MC_PathSelect then MC_MovePath), the stops
and the transforms. The five group commands both kinds of group share (``group_enable``,
``group_disable``, ``group_reset``, ``group_halt``, ``group_stop``: the same FBs,
transport/blocks.py) are scenario/transport.py's and take an axes group too.

Signals of a group (``<group>.x`` ...) are its kind's in the machine model
(coordinated/kind.py, scenario/signals.py); a condition on a group compares one of them, or
its state (``<group>.state == standby``).
schema.py puts the list into ``Scenario`` and the entries into ``TIMELINE_COMMANDS``; they
share its value types, conditions and name checks.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from typing import Annotated, Any, ClassVar, Literal, get_args

from pydantic import (
    AfterValidator,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    ValidationError,
    model_validator,
)
from pydantic_core import InitErrorDetails, PydanticCustomError

from openmotion.axis.commands import Command
from openmotion.coordinated.blocks import (
    MC_GroupReadActualAcceleration,
    MC_GroupReadActualPosition,
    MC_GroupReadActualVelocity,
    MC_GroupReadBlockerStatus,
    MC_GroupReadConfiguration,
    MC_ReadCartesianTransform,
    MC_ReadCoordinateTransform,
    MC_ReadKinTransform,
)
from openmotion.coordinated.cam import PathMode
from openmotion.coordinated.frames import CartesianTransform, Frame
from openmotion.coordinated.inputs import CoordSystem, PathDynamics, TransitionMode
from openmotion.coordinated.kinematics import (
    COORDINATES,
    CartesianGantry,
    DeltaRobot,
    Kinematics,
    Scara,
)
from openmotion.coordinated.path_table import (
    MAX_ROWS,
    McCircMode,
    McCircPathChoice,
    McTransitionMode,
)
from openmotion.coordinated.states import AxesGroupState, ExecutionMode
from openmotion.core.enums import BufferMode
from openmotion.core.errors import ConfigError
from openmotion.core.special_values import MC_DEFAULT
from openmotion.geometry.path import CircMode, PathChoice
from openmotion.scenario.queries import Query, block_query, query_command
from openmotion.scenario.schema import (
    _NAMES,
    BufferModeName,
    Condition,
    Identifier,
    InputValue,
    Number,
    Seconds,
    _check_axis,
    _enum_by_name,
    _Model,
    _signal_value,
    _unique,
)
from openmotion.scenario.signals import check_signal, spec_of, value_of_name
from openmotion.scenario.transport import _Timed

CoordSystemName = _enum_by_name(CoordSystem)
TransitionModeName = _enum_by_name(TransitionMode)
CircModeName = _enum_by_name(CircMode)
PathChoiceName = _enum_by_name(PathChoice)
ExecutionModeName = _enum_by_name(ExecutionMode)
PathModeName = _enum_by_name(PathMode)
Loc = tuple[str | int, ...]
#: a position: one value per member axis (ACS) or per kinematics coordinate (MCS, PCS)
Position = Annotated[list[Number], Field(min_length=1)]
Point = Annotated[list[Number], Field(min_length=1, max_length=3)]  #: x, y, z; missing 0
_STATES = ", ".join(state.name.lower() for state in AxesGroupState)
_TRANSFORM = "trans_x, trans_y, trans_z [mm], rot_angle1, rot_angle2, rot_angle3 [°]"

# -- names ---------------------------------------------------------------------------------


def _check_axes_group(name: str) -> str:
    names = _NAMES.get()
    if names is not None and name not in names.axes_groups:
        known = ", ".join(sorted(names.axes_groups)) or "none"
        raise ValueError(f"unknown axes group {name!r} (axes_groups: {known})")
    return name


def _own_name(name: str) -> str:
    names = _NAMES.get()
    if names is None:
        return name
    for kind, what in (("axes", "an axis"), ("groups", "a CA group"),
                       ("planar_movers", "a planar mover"), ("planar_groups", "a planar group")):
        if name in getattr(names, kind):
            raise ValueError(f"{name!r} is already the name of {what}")
    return name


def _in_one_group(name: str) -> str:
    _check_axis(name)
    names = _NAMES.get()
    if names is None:
        return name
    groups = names.group_axes.get(name, [])
    if len(groups) > 1:
        raise ValueError(f"{name!r} is listed {len(groups)} times in axes_groups "
                         f"({', '.join(groups)}); an axis is in one axes group only")
    if name in names.members:
        raise ValueError(f"{name!r} is in CA group {names.members[name][0]!r} already")
    return name


def axes_group_condition(text: str, subject: str, attribute: str, operator: str,
                         raw: str) -> Condition | None:
    """``<group>.<signal> <op> <number>`` or ``<group>.state == <state>``; None when
    ``subject`` is no axes group."""
    names = _NAMES.get()
    if names is None or subject not in names.axes_groups:
        return None
    signal = f"{subject}.{attribute}"
    check_signal(signal, names)
    if attribute == "state":
        value = value_of_name(spec_of(signal, names), raw, names)
        if operator != "==" or value is None:
            raise ValueError(f"{text!r}: an axes group's state condition is '<group>.state == "
                             f"<state>' (states: {_STATES})")
        return Condition(text.strip(), subject, attribute, operator, value)
    return Condition(text.strip(), subject, attribute, operator,
                     _signal_value(signal, raw, text))


def _raise(model: _Model, problems: Iterable[tuple[Loc, str]]) -> None:
    """Raise the problems as one ValidationError, each at its field path."""
    found = list(problems)
    if found:
        raise ValidationError.from_exception_data(type(model).__name__, [
            InitErrorDetails(type=PydanticCustomError("value_error", message), loc=loc,
                             input=None) for loc, message in found])


# -- axes_groups ---------------------------------------------------------------------------

AxisLimits = tuple[Number, Number] | None  #: (minimum, maximum) of one ACS axis, or none
_MODEL_FIELDS = {"cartesian": ("mapping", "sign", "offset"),
                 "scara": ("l1", "l2", "z_axis", "c_axis", "limits"),
                 "delta": ("base_radius", "effector_radius", "upper_arm", "forearm", "limits")}
_REQUIRED = {"cartesian": ("mapping",), "scara": ("l1", "l2"),
             "delta": ("base_radius", "effector_radius", "upper_arm", "forearm")}


class KinematicsSpec(_Model):
    """A kinematic model (coordinated/kinematics.py, §2.1.1): ``model`` picks it, the other
    fields are its constructor's arguments."""

    model: Literal["cartesian", "scara", "delta"]
    """cartesian (CartesianGantry), scara (Scara) or delta (DeltaRobot)."""
    mapping: list[Literal["x", "y", "z", "a", "b", "c"]] | None = None
    """cartesian: the MCS coordinate each member drives, in IdentInGroup order."""
    sign: list[Number] | None = None
    """cartesian: +1 or -1 per member (default all +1)."""
    offset: list[Number] | None = None
    """cartesian: MCS = sign * ACS + offset, per member [mm or °] (default 0)."""
    l1: Number | None = None
    """scara: base axis to elbow axis [mm]."""
    l2: Number | None = None
    """scara: elbow axis to TCP [mm]."""
    z_axis: StrictBool = False
    """scara: a third member drives z."""
    c_axis: StrictBool = False
    """scara: a last member turns the tool (c = theta1 + theta2 + theta4)."""
    base_radius: Number | None = None
    """delta: centre of the base to an arm's axis [mm]."""
    effector_radius: Number | None = None
    """delta: TCP to a forearm's platform joint [mm]."""
    upper_arm: Number | None = None
    """delta: arm axis to elbow [mm]."""
    forearm: Number | None = None
    """delta: elbow to platform joint [mm]."""
    limits: list[AxisLimits] | None = None
    """scara, delta: [minimum, maximum] per member axis, or null for none."""

    @model_validator(mode="after")
    def _builds(self) -> KinematicsSpec:
        own = _MODEL_FIELDS[self.model]
        problems: list[tuple[Loc, str]] = [
            ((name,), f"not a field of the {self.model} model (fields: {', '.join(own)})")
            for name in sorted(self.model_fields_set - {"model", *own})]
        problems += [((name,), f"required for the {self.model} model")
                     for name in _REQUIRED[self.model] if getattr(self, name) is None]
        _raise(self, problems)
        try:
            self.build()
        except ConfigError as exc:  # "l1: link length must be > 0 mm, got -1.0"
            name, _, message = str(exc).partition(": ")
            if name not in type(self).model_fields:
                raise ValueError(str(exc)) from None
            _raise(self, [((name,), message)])
        return self

    def build(self) -> Kinematics:
        """A new model (each run needs its own)."""
        if self.model == "cartesian":
            return CartesianGantry(tuple(self.mapping or ()), sign=self.sign, offset=self.offset)
        if self.model == "scara":
            return Scara(self.l1, self.l2, z_axis=self.z_axis,  # type: ignore[arg-type]
                         c_axis=self.c_axis, limits=self.limits)
        return DeltaRobot(self.base_radius, self.effector_radius,  # type: ignore[arg-type]
                          self.upper_arm, self.forearm, limits=self.limits)  # type: ignore


class PathDynamicsSpec(_Model):
    """The group's path dynamics (coordinated/inputs.py PathDynamics): the values MC_DEFAULT
    takes and the caps above which a command's values are clamped; unset fields keep their
    defaults."""

    velocity: Number | None = None
    """Default path velocity [mm/s] (100)."""
    acceleration: Number | None = None
    """[mm/s²] (1000)."""
    deceleration: Number | None = None
    """[mm/s²] (1000)."""
    jerk: Number | None = None
    """[mm/s³] (10000)."""
    max_velocity: Number | None = None
    """[mm/s] (1000)."""
    max_acceleration: Number | None = None
    """[mm/s²] (10000)."""
    max_deceleration: Number | None = None
    """[mm/s²] (10000)."""
    max_jerk: Number | None = None
    """[mm/s³] (1e6)."""

    @model_validator(mode="after")
    def _positive(self) -> PathDynamicsSpec:
        # the values as built, but not built: PathDynamics would refuse the first bad one
        # alone, where this names every bad field at its path
        built = {f.name: f.default for f in dataclasses.fields(PathDynamics)} | {
            name: getattr(self, name) for name in self.model_fields_set}
        _raise(self, [((name,), f"must be > 0, got {value!r}")
                      for name, value in built.items() if not value > 0.0])
        _raise(self, [((name,), f"{built[name]!r} is above max_{name} {built[f'max_{name}']!r}")
                      for name in ("velocity", "acceleration", "deceleration", "jerk")
                      if built[name] > built[f"max_{name}"]])
        return self

    def build(self) -> PathDynamics:
        return PathDynamics(**{name: getattr(self, name) for name in self.model_fields_set})


def _six(values: list[float]) -> list[float]:
    if len(values) != len(CartesianTransform._fields):
        raise ValueError(f"give six values: {_TRANSFORM}; got {len(values)}")
    return values


#: MC_SetCartesianTransform's six inputs as one list (the PLC's ARRAY[1..6] OF REAL)
Transform = Annotated[list[Number], AfterValidator(_six)]


def frame_of(values: list[float]) -> Frame:
    """The Frame of six values (frames.py reads them: Z, then Y', then X'')."""
    return Frame.from_cartesian(*values)


class AxesGroupSpec(_Model):
    """One axes group (Part 4 §4): its members, kinematics, dynamics and first transform.

    The run builds it after the axes and the CA groups, adds the members with IdentInGroup
    1, 2, ... in the listed order, sets the kinematics and the transform, and with
    ``enable`` powers the members and enables the group: it is GroupStandby at t = 0.
    """

    name: Annotated[Identifier, _unique("axes_groups"), AfterValidator(_own_name)]
    """Unique, not the name of an axis, a CA group or a planar mover or group."""
    axes: Annotated[list[Annotated[StrictStr, AfterValidator(_in_one_group)]],
                    Field(min_length=1)]
    """The member axes, added in this order (IdentInGroup 1..n: the ACS order)."""
    kinematics: KinematicsSpec | None = None
    """The ACS <-> MCS model; default: the neutral one (members are x, y, z, a, b, c)."""
    dynamics: PathDynamicsSpec = PathDynamicsSpec()
    """Path dynamics: MC_DEFAULT values and caps."""
    cartesian_transform: Transform | None = None
    """The PCS in the MCS (MC_SetCartesianTransform): six values, trans_x, trans_y, trans_z
    [mm], rot_angle1, rot_angle2, rot_angle3 [°]; default: the PCS is the MCS."""
    enable: StrictBool = True
    """Power the members and enable the group at t = 0; false: the timeline does it
    (power entries, then group_enable)."""

    @model_validator(mode="after")
    def _fits(self) -> AxesGroupSpec:
        if self.kinematics is not None:
            n_axes = self.kinematics.build().n_axes
            if n_axes != len(self.axes):
                _raise(self, [(("kinematics",), f"the {self.kinematics.model} model drives "
                                                f"{n_axes} axes, the group has {len(self.axes)}")])
        elif len(self.axes) > len(COORDINATES):
            _raise(self, [(("axes",), f"without kinematics at most {len(COORDINATES)} axes "
                                      f"(x, y, z, a, b, c); give a model")])
        return self


# -- timeline entries ----------------------------------------------------------------------


class AxesGroupEntry(_Timed):
    """A command for one axes group: the run calls the AxesGroup method ``method``."""

    group_fields: ClassVar[tuple[str, ...]] = ()  #: arguments that name an axes group
    group: Annotated[StrictStr, AfterValidator(_check_axes_group)]
    """Name of the axes group."""

    @property
    def axis(self) -> str:
        """The group's name, for the summary's axis column."""
        return self.group

    def arguments(self) -> dict[str, Any]:
        """Keyword arguments of the AxesGroup method, by its parameter names."""
        skip = {"id", "at", "when", "group", "command"}
        return {name: getattr(self, name) for name in type(self).model_fields
                if name not in skip}


class _Dynamics(AxesGroupEntry):
    velocity: InputValue = MC_DEFAULT
    """Path velocity [mm/s] (ACS units for move_direct_*); MC_DEFAULT: the group's default,
    MC_MAXIMUM: its maximum."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting, buffered, blending_low, blending_previous, blending_next, blending_high."""
    transition_mode: TransitionModeName = TransitionMode.TM_NONE  # type: ignore[valid-type]
    """The contour to the command before (blending only): tm_none, tm_start_velocity,
    tm_constant_velocity, tm_corner_distance, tm_max_corner_deviation."""
    transition_parameter: Number | None = None
    """The mode's value: a percentage for the velocity modes, [mm] for the corner modes."""


class _Cartesian(_Dynamics):
    coord_system: CoordSystemName = CoordSystem.MCS  # type: ignore[valid-type]
    """mcs or pcs (acs: a line in joint space)."""


class MoveLinearAbsolute(_Cartesian):
    """MC_MoveLinearAbsolute (§5.20): a straight line to ``position``."""

    method = "move_linear_absolute"
    command: Literal["move_linear_absolute"]
    position: Position
    """One value per coordinate of ``coord_system``."""


class MoveLinearRelative(_Cartesian):
    """MC_MoveLinearRelative (§5.21): a straight line by ``distance``."""

    method = "move_linear_relative"
    command: Literal["move_linear_relative"]
    distance: Position
    """From where the TCP is when the command starts (or the queue's end when buffered)."""


class MoveCircularAbsolute(_Cartesian):
    """MC_MoveCircularAbsolute (§5.22): an arc to ``end_point``."""

    method = "move_circular_absolute"
    command: Literal["move_circular_absolute"]
    aux_point: Position
    """border: a point on the arc; center: the centre; radius: the plane normal, its length
    the radius."""
    end_point: Position
    """The arc's end."""
    circ_mode: CircModeName = CircMode.BORDER  # type: ignore[valid-type]
    """border, center or radius."""
    path_choice: PathChoiceName = PathChoice.COUNTERCLOCKWISE  # type: ignore[valid-type]
    """counterclockwise (the short arc) or clockwise (the long one)."""


class MoveCircularRelative(MoveCircularAbsolute):
    """MC_MoveCircularRelative (§5.23): aux_point and end_point relative to the start."""

    method = "move_circular_relative"
    command: Literal["move_circular_relative"]  # type: ignore[assignment]


class _Direct(_Dynamics):
    coord_system: CoordSystemName = CoordSystem.ACS  # type: ignore[valid-type]
    """acs (one value per member), mcs or pcs."""


class MoveDirectAbsolute(_Direct):
    """MC_MoveDirectAbsolute (§5.24): point to point in joint space, all axes end together."""

    method = "move_direct_absolute"
    command: Literal["move_direct_absolute"]
    position: Position
    """Target in ``coord_system``."""


class MoveDirectRelative(_Direct):
    """MC_MoveDirectRelative (§5.25)."""

    method = "move_direct_relative"
    command: Literal["move_direct_relative"]
    distance: Position
    """In ``coord_system``, from the start."""


class PathElementSpec(_Model):
    """One element of a path description (coordinated/paths.py): a line or an arc to a
    point; its corner with the element before may get its own contour."""

    line: Point | None = None
    """A straight line to this point [mm] (x, y, z; missing ones 0)."""
    arc: Point | None = None
    """An arc to this point [mm]; needs ``aux``."""
    aux: Point | None = None
    """The arc's aux point, as ``circ_mode`` reads it."""
    circ_mode: CircModeName | None = None  # type: ignore[valid-type]
    """border (default), center or radius."""
    path_choice: PathChoiceName | None = None  # type: ignore[valid-type]
    """counterclockwise (default) or clockwise."""
    transition_mode: TransitionModeName | None = None  # type: ignore[valid-type]
    """The contour at this element's start; default: the select's."""
    transition_parameter: Number | None = None
    """Its value [mm]."""

    @model_validator(mode="after")
    def _one_kind(self) -> PathElementSpec:
        if (self.line is None) == (self.arc is None):
            raise ValueError("give 'line' or 'arc' (a point), not both")
        arc_only = {"aux", "circ_mode", "path_choice"} & self.model_fields_set
        if self.line is not None and arc_only:
            raise ValueError(f"{', '.join(sorted(arc_only))}: only with 'arc'")
        if self.arc is not None and self.aux is None:
            raise ValueError("aux: an arc needs its aux point")
        return self

    def description(self) -> dict[str, Any]:
        """The element as select_path reads it (enums as members)."""
        names = ("line", "arc", "aux", "circ_mode", "path_choice", "transition_mode",
                 "transition_parameter")
        return {name: getattr(self, name) for name in names if getattr(self, name) is not None}


class PathSelectSpec(_Model):
    """MC_PathSelect's inputs besides the description (coordinated/paths.py select_path)."""

    coord_system: CoordSystemName = CoordSystem.MCS  # type: ignore[valid-type]
    """mcs or pcs: the frame of the points (a PCS is taken as it is when the entry fires)."""
    transition_mode: TransitionModeName = (  # type: ignore[valid-type]
        TransitionMode.TM_MAX_CORNER_DEVIATION)
    """The contour at every corner inside the path (an element may set its own):
    tm_corner_distance, tm_max_corner_deviation, or tm_none (stop at each corner)."""
    transition_parameter: Number = 0.1
    """Its value [mm]."""


class MovePath(_Dynamics):
    """MC_PathSelect, then MC_MovePath (§5.26, §5.27) in the same cycle: the path runs from
    where the TCP is (or the queue's end). A path that MC_PathSelect refuses ends the entry
    with its error (the command column then says MC_PathSelect)."""

    method = "move_path"
    command: Literal["move_path"]
    path: Annotated[list[PathElementSpec], Field(min_length=1)]
    """The path description: ``{line: [x, y, z]}`` and ``{arc: [...], aux: [...]}``."""
    select: PathSelectSpec = PathSelectSpec()
    """MC_PathSelect's coord_system and corner contours."""

    def description(self) -> list[dict[str, Any]]:
        return [element.description() for element in self.path]

    def arguments(self) -> dict[str, Any]:
        arguments = super().arguments()
        del arguments["path"], arguments["select"]
        return arguments


class GroupInterrupt(AxesGroupEntry):
    """MC_GroupInterrupt (§5.15): brake along the path and keep the rest for group_continue."""

    method = "interrupt"
    command: Literal["group_interrupt"]
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""


class GroupContinue(AxesGroupEntry):
    """MC_GroupContinue (§5.16): resume what group_interrupt kept; Done once resumed."""

    method = "continue_"
    command: Literal["group_continue"]


class GroupSetOverride(AxesGroupEntry):
    """MC_GroupSetOverride (§5.28): factors on the commanded path dynamics."""

    method = "set_override"
    command: Literal["group_set_override"]
    velocity: Number = 1.0
    """VelFactor, 0 to 1 (0: the path pauses)."""
    acceleration: Number = 1.0
    """AccFactor, > 0 to 1."""
    jerk: Number = 1.0
    """JerkFactor, > 0 to 1."""


class GroupHome(AxesGroupEntry):
    """MC_GroupHome (§5.7): every member homes; Done when all are."""

    method = "home"
    command: Literal["group_home"]
    position: Position | None = None
    """Where the group is after homing, in ``coord_system``; default: each axis' configured
    home position."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting (at rest only) or buffered (the blending modes act as buffered): after the
    motion issued before."""
    coord_system: CoordSystemName = CoordSystem.ACS  # type: ignore[valid-type]
    """acs (one value per member), mcs or pcs (one per coordinate)."""


class GroupSetPosition(AxesGroupEntry):
    """MC_GroupSetPosition (§5.9): new coordinates without motion."""

    method = "set_position"
    command: Literal["group_set_position"]
    position: Position
    """In ``coord_system``."""
    relative: StrictBool = False
    """Add ``position`` to the present coordinates."""
    coord_system: CoordSystemName = CoordSystem.ACS  # type: ignore[valid-type]
    """acs, mcs or pcs."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting (at rest only) or buffered (the blending modes act as buffered): after the
    motion issued before (D-130)."""


class SetKinematics(AxesGroupEntry):
    """MC_SetKinTransform (§5.8.1): a new kinematic model for the group."""

    method = "set_kinematics"
    command: Literal["set_kinematics"]
    kinematics: KinematicsSpec
    """The model, as in axes_groups."""
    mode: ExecutionModeName = ExecutionMode.IMMEDIATELY  # type: ignore[valid-type]
    """immediately, delayed (when the running motion ends) or queued (when all issued
    motions ended)."""

    def arguments(self) -> dict[str, Any]:
        return {"kinematics": self.kinematics.build(), "mode": self.mode}


class SetCartesianTransform(AxesGroupEntry):
    """MC_SetCartesianTransform (§5.8.2): place the PCS in the MCS; ends a tracking entry."""

    method = "set_cartesian_transform"
    command: Literal["set_cartesian_transform"]
    frame: Transform
    """Six values: trans_x, trans_y, trans_z [mm], rot_angle1, rot_angle2, rot_angle3 [°]."""
    mode: ExecutionModeName = ExecutionMode.IMMEDIATELY  # type: ignore[valid-type]
    """immediately, delayed or queued."""

    def arguments(self) -> dict[str, Any]:
        return {"frame": frame_of(self.frame), "mode": self.mode}


class _TrackingInputs(AxesGroupEntry):
    coord_system: CoordSystemName = CoordSystem.PCS  # type: ignore[valid-type]
    """The system that moves: pcs, the only one that can."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting (set now) or buffered (the blending modes act as buffered): once the motion
    issued before is over."""


class _Tracking(_TrackingInputs):
    origin: Transform
    """Six values: the moving frame's origin in the MCS."""
    initial_object: Transform = [0.0] * 6
    """Six values: the object in the moving frame when it is set."""

    def arguments(self) -> dict[str, Any]:
        arguments = super().arguments()
        arguments.update(origin=frame_of(self.origin),
                         initial_object=frame_of(self.initial_object))
        return arguments


class TrackConveyorBelt(_Tracking):
    """MC_TrackConveyorBelt (§6.6): the PCS rides on the belt axis' travel along the x axis of
    ``origin``; Busy (Active) while it tracks, aborted when a transform entry replaces it.
    Starts no motion, and does not keep an open-ended run going."""

    method = "track_conveyor_belt"
    command: Literal["track_conveyor_belt"]
    axis_fields: ClassVar[tuple[str, ...]] = ("belt",)
    belt: Annotated[StrictStr, AfterValidator(_check_axis)]
    """The belt axis (its set position is the travel)."""


class TrackRotaryTable(_Tracking):
    """MC_TrackRotaryTable (§6.7): the PCS turns with the table axis about the z axis of
    ``origin``; as track_conveyor_belt otherwise."""

    method = "track_rotary_table"
    command: Literal["track_rotary_table"]
    axis_fields: ClassVar[tuple[str, ...]] = ("table",)
    table: Annotated[StrictStr, AfterValidator(_check_axis)]
    """The table axis [°]."""


class SetDynCoordTransform(_TrackingInputs):
    """MC_SetDynCoordTransform (§6.5): this group's PCS rides on ``master``'s TCP."""

    method = "set_dyn_coord_transform"
    command: Literal["set_dyn_coord_transform"]
    group_fields: ClassVar[tuple[str, ...]] = ("master",)
    master: Annotated[StrictStr, AfterValidator(_check_axes_group)]
    """The master axes group."""
    offset: Transform = [0.0] * 6
    """Six values: the PCS on the master's TCP."""
    mode: PathModeName = PathMode.NON_PERIODIC  # type: ignore[valid-type]
    """non_periodic or periodic (MC_PathMode): checked, changes nothing."""

    def arguments(self) -> dict[str, Any]:
        arguments = super().arguments()
        arguments["offset"] = frame_of(self.offset)
        return arguments


class SyncAxisToGroup(AxesGroupEntry):
    """MC_SyncAxisToGroup (§6.3): ``slave`` runs at ratio x the path velocity. Busy while it
    follows (``<id>.in_velocity``: InSync); does not keep an open-ended run going."""

    method = "sync_axis_to_group"
    command: Literal["sync_axis_to_group"]
    axis_fields: ClassVar[tuple[str, ...]] = ("slave",)
    slave: Annotated[StrictStr, AfterValidator(_check_axis)]
    """The slave axis (in no group)."""
    ratio_numerator: Number = 1.0
    """Ratio numerator."""
    ratio_denominator: Number = 1.0
    """Ratio denominator, != 0."""
    acceleration: InputValue = MC_DEFAULT
    """Of the slave while it ramps in and speeds up [mm/s²]; MC_DEFAULT: its default."""
    deceleration: InputValue = MC_DEFAULT
    """While it ramps in and slows down [mm/s²]; MC_DEFAULT: its default."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]; MC_DEFAULT: its default."""
    coord_system: CoordSystemName = CoordSystem.MCS  # type: ignore[valid-type]
    """Where the path length is measured: acs, mcs or pcs."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting (takes the slave over) or buffered (the blending modes act as buffered):
    after the slave's own command."""


class SyncGroupToAxis(AxesGroupEntry):
    """MC_PathSelect, then MC_SyncGroupToAxis (§5.26, §6.4) in the same cycle: the arc length
    along ``path`` follows ``master``, s = tuc_numerator / tuc_denominator x (master - master
    when it couples). Busy while it follows (``<id>.in_velocity``: InSync); a
    non-periodic path stops at its end and waits. Does not keep an open-ended run going."""

    method = "sync_group_to_axis"
    command: Literal["sync_group_to_axis"]
    axis_fields: ClassVar[tuple[str, ...]] = ("master",)
    master: Annotated[StrictStr, AfterValidator(_check_axis)]
    """The master axis."""
    path: Annotated[list[PathElementSpec], Field(min_length=1)]
    """The path description, as in move_path."""
    select: PathSelectSpec = PathSelectSpec()
    """MC_PathSelect's coord_system and corner contours."""
    mode: PathModeName = PathMode.NON_PERIODIC  # type: ignore[valid-type]
    """non_periodic (stop at the path's end) or periodic (the path must be closed)."""
    tuc_numerator: Number = 1.0
    """Path millimetres per ``tuc_denominator`` master units."""
    tuc_denominator: Number = 1.0
    """!= 0."""
    acceleration: InputValue = MC_DEFAULT
    """While it engages [mm/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting (a moving group brakes along its path and couples at rest) or buffered (the
    blending modes act as buffered): after the motion issued before."""

    def description(self) -> list[dict[str, Any]]:
        return [element.description() for element in self.path]

    def arguments(self) -> dict[str, Any]:
        arguments = super().arguments()
        del arguments["path"], arguments["select"]
        arguments["coord_system"] = self.select.coord_system
        return arguments


# -- TF5410 §9.3 path tables (coordinated/path_table.py) -----------------------------------

McTransitionModeName = _enum_by_name(McTransitionMode)
McCircModeName = _enum_by_name(McCircMode)
McCircPathChoiceName = _enum_by_name(McCircPathChoice)


class _RowDynamics(_Model):
    velocity: Annotated[StrictFloat, Field(gt=0.0, allow_inf_nan=False)]
    """[mm/s], > 0 (no default, §9.3.1.2.3)."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²], >= 1, or MC_DEFAULT / MC_MAXIMUM."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³], >= 100, or MC_DEFAULT / MC_MAXIMUM (100 x the default)."""
    buffer_mode: BufferModeName = BufferMode.BUFFERED
    """buffered (with transition_mode none), blending_previous (with a corner mode), or
    aborting (the first row only)."""
    transition_mode: McTransitionModeName = McTransitionMode.NONE  # type: ignore[valid-type]
    """none, corner_distance (one parameter) or corner_distance_advanced (r_in, r_out)."""
    transition_parameter: list[Number] | None = None
    """[mm]."""
    invoke_id: Annotated[StrictInt, Field(ge=0)] = 0
    """Segment id, for analysis."""


class LinearRowSpec(_RowDynamics):
    """MC_MoveLinearAbsolutePreparation's inputs (§9.3.1.2.3)."""

    blocks = ("MC_MoveLinearAbsolutePreparation",)  #: called for the row by the entry

    position: Position
    """One value per MCS coordinate, in the frame in force at this row."""


class CircularRowSpec(_RowDynamics):
    """MC_MoveCircularAbsolutePreparation's inputs (§9.3.1.2.4)."""

    blocks = ("MC_MoveCircularAbsolutePreparation",)

    circ_mode: McCircModeName  # type: ignore[valid-type]
    """border, center or radius."""
    aux_point: Annotated[list[Number], Field(min_length=3, max_length=3)]
    """x, y, z: a point on the arc, the centre, or the plane normal (its length the radius)."""
    end_point: Position
    """The arc's end."""
    path_choice: McCircPathChoiceName = (  # type: ignore[valid-type]
        McCircPathChoice.COUNTERCLOCKWISE)
    """clockwise, counterclockwise, short_segment, long_segment."""


class BlockerRowSpec(_Model):
    """MC_BlockerPreparation's inputs (§9.3.1.2.6)."""

    blocks = ("MC_BlockerPreparation",)

    blocker_id: Annotated[StrictInt, Field(gt=0)]
    """> 0; release_blocker with this id lets the path go on."""
    buffer_mode: BufferModeName = BufferMode.BUFFERED
    """buffered, or aborting (the first row only)."""
    invoke_id: Annotated[StrictInt, Field(ge=0)] = 0


class DwellRowSpec(_Model):
    """MC_DwellTimePreparation's inputs (§9.3.1.2.9)."""

    blocks = ("MC_DwellTimePreparation",)

    dwell_time: Seconds
    """[s] >= 0; 0 still stops the path exactly."""
    buffer_mode: BufferModeName = BufferMode.BUFFERED
    """buffered, or aborting (the first row only)."""
    invoke_id: Annotated[StrictInt, Field(ge=0)] = 0


class PathRowSpec(_Model):
    """One row of a path table: exactly one of its kinds."""

    blocks = ("MC_SetCoordinateTransformPreparation",)  #: for ``coord_transform``

    linear: LinearRowSpec | None = None
    circular: CircularRowSpec | None = None
    blocker: BlockerRowSpec | None = None
    dwell: DwellRowSpec | None = None
    coord_transform: Annotated[list[Number], Field(min_length=6, max_length=6)] | None = None
    """MC_SetCoordinateTransformPreparation (§9.3.1.1.10): the frame of the rows after it,
    six values (trans_x, trans_y, trans_z [mm], rot_x, rot_y, rot_z [°]); zeros: the MCS."""

    @model_validator(mode="after")
    def _one_kind(self) -> PathRowSpec:
        given = [name for name in ROW_KINDS if getattr(self, name) is not None]
        if len(given) != 1:
            raise ValueError(f"give exactly one of {', '.join(ROW_KINDS)}")
        return self

    @property
    def kind(self) -> str:
        return next(name for name in ROW_KINDS if getattr(self, name) is not None)

    def inputs(self) -> dict[str, Any]:
        """The preparation block's inputs (enums as members)."""
        value = getattr(self, self.kind)
        if self.kind == "coord_transform":
            return {"coord_transform": list(value)}
        return {name: getattr(value, name) for name in type(value).model_fields}


ROW_KINDS = ("linear", "circular", "blocker", "dwell", "coord_transform")


class MovePathTable(AxesGroupEntry):
    """TF5410 §9.3: the *Preparation blocks append ``rows`` to a fresh MC_PATH_DATA_REF (as
    after ClearPath), then MC_MovePath runs it, all in one cycle. A row a block refuses
    fails the entry with its error (the command column names the block)."""

    method = "move_path_table"
    command: Literal["move_path_table"]
    rows: Annotated[list[PathRowSpec], Field(min_length=1, max_length=MAX_ROWS)]
    """The table: ``{linear: {...}}``, ``{circular: {...}}``, ``{blocker: {blocker_id}}``,
    ``{dwell: {dwell_time}}``, ``{coord_transform: [six values]}``."""

    def arguments(self) -> dict[str, Any]:
        return {}


class ReleaseBlocker(AxesGroupEntry):
    """MC_ReleaseBlocker (TF5410 §9.3.1.2.7): the blocker the path stands at, or the next
    one ahead with this id; Done at once, UNKNOWN_BLOCKER if there is none."""

    method = "release_blocker"
    command: Literal["release_blocker"]
    blocker_id: Annotated[StrictInt, Field(gt=0)]
    """The blocker's id."""
class SetCoordinateTransform(AxesGroupEntry):
    """MC_SetCoordinateTransform (§5.8.3): place the PCS in the MCS, replacing the transforms
    active before (set_cartesian_transform composes with them)."""

    method = "set_coordinate_transform"
    command: Literal["set_coordinate_transform"]
    frame: Transform
    """Six values: trans_x, trans_y, trans_z [mm], rot_angle1, rot_angle2, rot_angle3 [°]."""
    mode: ExecutionModeName = ExecutionMode.IMMEDIATELY  # type: ignore[valid-type]
    """immediately, delayed or queued."""

    def arguments(self) -> dict[str, Any]:
        return {"frame": frame_of(self.frame), "mode": self.mode}


# -- reads: the Part 4 read blocks called once (scenario/queries.py) ----------------------------


class _GroupRead(AxesGroupEntry, Query):
    """A Part 4 read block called once with Enable TRUE on the group."""

    method = ""
    block_type: ClassVar[Any]  #: the block class

    def inputs(self) -> dict[str, Any]:
        return {}

    def call(self, target: Any, now: float) -> Command:
        group, _ = target
        block = self.block_type(group)
        block(enable=True, **self.inputs())
        return block_query(self.command, now, block, self.names())

    def names(self) -> tuple[str, ...]:
        """The block outputs the row keeps."""
        return tuple(name.rstrip("_") for name in self.outputs)


class _ReadIn(_GroupRead):
    coord_system: CoordSystemName = CoordSystem.ACS  # type: ignore[valid-type]
    """acs (one value per member, IdentInGroup order), mcs or pcs (x, y, z, a, b, c as the
    kinematics has them)."""

    def inputs(self) -> dict[str, Any]:
        return {"coord_system": self.coord_system}


class GroupReadActualPosition(_ReadIn):
    """MC_GroupReadActualPosition (§5.10): outputs position_1, position_2 ..."""

    block_type = MC_GroupReadActualPosition
    command: Literal["group_read_actual_position"]
    outputs = ("position_",)


class GroupReadActualVelocity(_ReadIn):
    """MC_GroupReadActualVelocity (§5.11): velocity_1 ... and path_velocity [mm/s]."""

    block_type = MC_GroupReadActualVelocity
    command: Literal["group_read_actual_velocity"]
    outputs = ("velocity_", "path_velocity")


class GroupReadActualAcceleration(_ReadIn):
    """MC_GroupReadActualAcceleration (§5.12): acceleration_1 ... and path_acceleration."""

    block_type = MC_GroupReadActualAcceleration
    command: Literal["group_read_actual_acceleration"]
    outputs = ("acceleration_", "path_acceleration")


class GroupReadBlockerStatus(_GroupRead):
    """MC_GroupReadBlockerStatus (TF5410 §9.3.1.2.8): ``blocked`` (the path stands at a
    blocker) and its ``blocker_id`` (0: none)."""

    block_type = MC_GroupReadBlockerStatus
    command: Literal["group_read_blocker_status"]
    outputs = ("blocked", "blocker_id")


class GroupReadConfiguration(_ReadIn):
    """MC_GroupReadConfiguration (§5.4): output ``axis`` (the member's name, or the MCS/PCS
    coordinate as ``<group>.MCS.x``) and its ``position`` now."""

    block_type = MC_GroupReadConfiguration
    command: Literal["group_read_configuration"]
    outputs = ("axis", "position")
    ident_in_group: Annotated[StrictInt, Field(ge=0)]
    """acs: the member's IdentInGroup; mcs, pcs: the coordinate, 1-based (x = 1)."""

    def inputs(self) -> dict[str, Any]:
        return {"coord_system": self.coord_system, "ident_in_group": self.ident_in_group}

    def call(self, target: Any, now: float) -> Command:
        group, _ = target
        block = self.block_type(group)
        block(enable=True, **self.inputs())
        if block.error:
            return block_query(self.command, now, block)
        ref = block.axis_ref  # an Axis, or a CoordinateView named <group>.MCS.x
        return query_command(self.command, now, {"axis": ref.name, "position": ref.position})


class ReadKinTransform(_GroupRead):
    """MC_ReadKinTransform (§5.8.4): output ``kin_transform``, the model in force (a text)."""

    block_type = MC_ReadKinTransform
    command: Literal["read_kin_transform"]
    outputs = ("kin_transform",)

    def call(self, target: Any, now: float) -> Command:
        group, _ = target
        block = self.block_type(group)
        block(enable=True)
        if block.error:
            return block_query(self.command, now, block)
        return query_command(self.command, now,
                             {"kin_transform": type(block.kin_transform).__name__})


class ReadCartesianTransform(_GroupRead):
    """MC_ReadCartesianTransform (§5.8.5): trans_x, trans_y, trans_z [mm], rot_x, rot_y,
    rot_z [°] of the PCS in force."""

    block_type = MC_ReadCartesianTransform
    command: Literal["read_cartesian_transform"]
    outputs = ("trans_x", "trans_y", "trans_z", "rot_x", "rot_y", "rot_z")


class ReadCoordinateTransform(_GroupRead):
    """MC_ReadCoordinateTransform (§5.8.6): the Frame in force (the moving one while
    tracking) as its six values trans_x ... rot_z."""

    block_type = MC_ReadCoordinateTransform
    command: Literal["read_coordinate_transform"]
    outputs = ("trans_x", "trans_y", "trans_z", "rot_x", "rot_y", "rot_z")

    def call(self, target: Any, now: float) -> Command:
        group, _ = target
        block = self.block_type(group)
        block(enable=True)
        if block.error:
            return block_query(self.command, now, block)
        return query_command(self.command, now,
                             dict(zip(self.outputs, block.coord_transform.cartesian(),
                                      strict=True)))


COORDINATED_ENTRIES: tuple[type, ...] = (
    MoveLinearAbsolute, MoveLinearRelative, MoveCircularAbsolute, MoveCircularRelative,
    MoveDirectAbsolute, MoveDirectRelative, MovePath, GroupInterrupt, GroupContinue,
    GroupSetOverride, GroupHome, GroupSetPosition, SetKinematics, SetCartesianTransform,
    TrackConveyorBelt, TrackRotaryTable, SetDynCoordTransform, SyncAxisToGroup,
    SyncGroupToAxis, MovePathTable, ReleaseBlocker, SetCoordinateTransform,
    GroupReadActualPosition, GroupReadActualVelocity, GroupReadActualAcceleration,
    GroupReadConfiguration, ReadKinTransform, ReadCartesianTransform, ReadCoordinateTransform,
    GroupReadBlockerStatus)
#: the axes-group entries by their ``command`` (schema.TIMELINE_COMMANDS holds them all)
COORDINATED_COMMANDS: dict[str, type] = {
    get_args(model.model_fields["command"].annotation)[0]: model
    for model in COORDINATED_ENTRIES}
#: entries whose command stays Busy while it runs in the background: it does not keep an
#: open-ended run going
BACKGROUND = (TrackConveyorBelt, TrackRotaryTable, SetDynCoordTransform, SyncAxisToGroup,
              SyncGroupToAxis)
