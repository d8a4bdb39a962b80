"""The scenario file format: one pydantic model per YAML mapping, unknown keys rejected.

Names are the Python API's names (style §2): a timeline entry's keys are the arguments of the
axis method it calls, enum values are the members' names in lower case and the MC special
values are written ``MC_DEFAULT``, ``MC_MAXIMUM``, ``MC_INVALID``. Wrong types and unknown
keys are configuration errors; a wrong *value* for a command (a negative velocity) is not: the
command is issued and fails with its error id, as an FB would.

Cross references (the axis of an entry, the ids and signals in conditions and checks) are
checked in the same pass as the types, so that ``openmotion check`` lists every problem at
once: ``Scenario`` publishes the axis names and entry ids of its raw input in a context
variable that the nested validators read.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping
from contextvars import ContextVar
from enum import Enum
from typing import (
    TYPE_CHECKING,
    Annotated,
    Any,
    ClassVar,
    Literal,
    Union,
    get_args,
    get_type_hints,
)

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    PlainSerializer,
    PlainValidator,
    PrivateAttr,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    Tag,
    ValidationError,
    create_model,
    model_validator,
)
from pydantic_core import InitErrorDetails, PydanticCustomError

from openmotion.axis.drive import DriveModel
from openmotion.axis.kind import AXIS
from openmotion.axis.parameters import AxisParameters
from openmotion.axis.probe import InputRef, ProbeSignal, SignalEdge, TouchProbeSource
from openmotion.axis.probe import _intervals as _probe_intervals
from openmotion.coordinated.kind import AXES_GROUP
from openmotion.core.enums import (
    BufferMode,
    DecoupleMode,
    Direction,
    NewPosAndVeloMode,
    SuperpositionMode,
)
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.core.special_values import (
    DEFAULT_HOME_POSITION,
    MC_DEFAULT,
    MC_INVALID,
    SPECIAL_VALUES,
    SpecialValue,
)
from openmotion.planar.kind import PLANAR_MOVER
from openmotion.scenario.queries import Query
from openmotion.scenario.signals import (
    AXIS_CHOICES,
    SUBJECT,
    check_axis,
    check_mover,
    check_signal,
    declared,
    default_signals,
    expect_hint,
    spec_of,
    value_of_name,
)
from openmotion.transport.enums import GroupState

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

# -- names known while one Scenario validates ----------------------------------------------


@dataclasses.dataclass(frozen=True)
class _Names:
    axes: Counter[str]
    ids: Counter[str]
    commands: dict[str, object]  #: entry id -> its ``command`` value (raw)
    groups: Counter[str] = dataclasses.field(default_factory=Counter)  #: CA group names
    members: dict[str, list[str]] = dataclasses.field(default_factory=dict)  #: axis ->
    #: the CA groups that list it (once per listing)
    planar_movers: Counter[str] = dataclasses.field(default_factory=Counter)
    planar_groups: Counter[str] = dataclasses.field(default_factory=Counter)
    planar_parts: set[int] = dataclasses.field(default_factory=set)  #: part OIDs
    axes_groups: Counter[str] = dataclasses.field(default_factory=Counter)  #: Part 4 groups
    group_axes: dict[str, list[str]] = dataclasses.field(default_factory=dict)  #: axis ->
    #: the axes groups that list it (once per listing)
    planar_tracks: Counter[str] = dataclasses.field(default_factory=Counter)  #: in file order
    #: track -> its raw (starts_from, ends_at, closed_loop): the links a trail must follow
    track_links: dict[str, tuple[object, object, object]] = dataclasses.field(
        default_factory=dict)
    #: the axes that add_axis_to_group entries add to a CA group (movers from then on)
    added: set[str] = dataclasses.field(default_factory=set)
    stations: Counter[str] = dataclasses.field(default_factory=Counter)  #: of the CA groups

    @classmethod
    def of(cls, data: object) -> _Names:
        """The names in raw input, however malformed the rest of it is."""
        def items(key: str, within: object = data) -> list[dict]:
            found = within.get(key) if isinstance(within, dict) else None
            return [item for item in found if isinstance(item, dict)] \
                if isinstance(found, list) else []

        def names(key: str, field: str, within: object = data) -> Counter[str]:
            return Counter(item[field] for item in items(key, within)
                           if isinstance(item.get(field), str))

        commands = {item["id"]: item.get("command") for item in items("timeline")
                    if isinstance(item.get("id"), str)}
        members: dict[str, list[str]] = {}
        for group in items("ca_groups"):
            axes = group.get("axes")
            for axis in axes if isinstance(axes, list) else []:
                if isinstance(axis, str):
                    members.setdefault(axis, []).append(str(group.get("name")))
        group_axes: dict[str, list[str]] = {}
        for group in items("axes_groups"):
            axes = group.get("axes")
            for axis in axes if isinstance(axes, list) else []:
                if isinstance(axis, str):
                    group_axes.setdefault(axis, []).append(str(group.get("name")))
        planar = data.get("planar") if isinstance(data, dict) else None
        return cls(names("axes", "name"), names("timeline", "id"), commands,
                   names("ca_groups", "name"), members, names("movers", "name", planar),
                   names("groups", "name", planar), part_oids(planar),
                   names("axes_groups", "name"), group_axes, names("tracks", "name", planar),
                   {item["name"]: (item.get("starts_from"), item.get("ends_at"),
                                   item.get("closed_loop")) for item in items("tracks", planar)
                    if isinstance(item.get("name"), str)},
                   {item["axis"] for item in items("timeline")
                    if item.get("command") == "add_axis_to_group"
                    and isinstance(item.get("axis"), str)
                    and item.get("group") in names("ca_groups", "name")},
                   sum((names("stations", "name", group) for group in items("ca_groups")),
                       names("stations", "name", planar)))


_NAMES: ContextVar[_Names | None] = ContextVar("openmotion_scenario_names", default=None)


def names_in(data: object) -> _Names:
    """The names raw scenario data declares: what its references are checked against (and
    what signals.scenario_signals lists the signals of)."""
    return _Names.of(data)


def _check_axis(name: str) -> str:
    check_axis(name, _NAMES.get())
    return name


def _check_mover(name: str) -> str:
    """An axis that one of the ``ca_groups`` lists, or that an add_axis_to_group entry adds
    to one."""
    check_mover(name, _NAMES.get())
    return name


def _check_group(name: str) -> str:
    """A CA group or an axes group: the group commands both share (MC_GroupEnable ...)."""
    names = _NAMES.get()
    if names is not None and name not in names.groups and name not in names.axes_groups:
        known = ", ".join(sorted(names.groups)) or "none"
        if not names.axes_groups:
            raise ValueError(f"unknown CA group {name!r} (ca_groups: {known})")
        axes_groups = ", ".join(sorted(names.axes_groups))
        raise ValueError(f"unknown group {name!r} (ca_groups: {known}; axes_groups: "
                         f"{axes_groups})")
    return name


def _check_id(name: str) -> str:
    names = _NAMES.get()
    if names is not None and name not in names.ids:
        known = ", ".join(sorted(names.ids)) or "none"
        raise ValueError(f"{name!r} is not the id of a timeline entry (ids: {known})")
    return name


def _check_id_of(command: str, what: str) -> Any:
    """The id of a timeline entry whose ``command`` is ``command``."""
    def check(name: str) -> str:
        _check_id(name)
        names = _NAMES.get()
        if names is not None and names.commands.get(name) != command:
            raise ValueError(f"{name!r} is not the id of a {command} entry ({what})")
        return name

    return AfterValidator(check)


# -- value types ---------------------------------------------------------------------------

_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def _identifier(value: str) -> str:
    if not _IDENTIFIER.match(value):
        raise ValueError(f"{value!r} must be letters, digits and _, not starting with a digit")
    return value


def _input_value(value: object) -> float | SpecialValue:
    if isinstance(value, SpecialValue):
        return value
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, str) and value in SPECIAL_VALUES:
        return SPECIAL_VALUES[value]
    raise ValueError(f"must be a number or one of {', '.join(SPECIAL_VALUES)}, got {value!r}")


def _enum_by_name(enum: type[Enum]) -> Any:
    """An enum written as its member's name in lower case (``blending_low``)."""
    names = [member.name.lower() for member in enum]

    def parse(value: object) -> Enum:
        if isinstance(value, enum):
            return value
        if isinstance(value, str) and value in names:
            return enum[value.upper()]
        raise ValueError(f"must be one of {', '.join(names)}, got {value!r}")

    return Annotated[enum, PlainValidator(parse),
                     PlainSerializer(lambda member: member.name.lower(), when_used="json")]


def _signal(name: str) -> str:
    """A signal of the machine model (signals.py)."""
    return check_signal(name, _NAMES.get())


def _unique(kind: str) -> Any:
    def check(name: str) -> str:
        names = _NAMES.get()
        count = getattr(names, kind)[name] if names is not None else 0
        if count > 1:
            raise ValueError(f"{name!r} is used {count} times; it must be unique")
        return name

    return AfterValidator(check)


def _error_id(value: object) -> ErrorId:
    if isinstance(value, ErrorId):
        return value
    if isinstance(value, str) and value in ErrorId.__members__:
        return ErrorId[value]
    raise ValueError(f"{value!r} is not an ErrorId name such as INVALID_VELOCITY")


def _expect_value(value: object) -> float | str:
    if isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value):
        return float(value)
    if isinstance(value, str):
        return value
    raise ValueError(f"must be a finite number (or a state or ErrorId name), got {value!r}")


Identifier = Annotated[StrictStr, AfterValidator(_identifier)]
Number = Annotated[StrictFloat, Field(allow_inf_nan=False)]
Seconds = Annotated[StrictFloat, Field(ge=0.0, allow_inf_nan=False)]
PositiveSeconds = Annotated[StrictFloat, Field(gt=0.0, allow_inf_nan=False)]
InputValue = Annotated[float | SpecialValue, PlainValidator(_input_value),
                       PlainSerializer(lambda v: v.name if isinstance(v, SpecialValue) else v,
                                       when_used="json")]
SignalName = Annotated[StrictStr, AfterValidator(_signal)]
DirectionName = _enum_by_name(Direction)
BufferModeName = _enum_by_name(BufferMode)
ErrorIdName = Annotated[ErrorId, PlainValidator(_error_id),
                        PlainSerializer(lambda member: member.name, when_used="json")]


# -- conditions ----------------------------------------------------------------------------

#: the outputs of an entry's command handle a condition may name (``<id>.done``): not
#: signals of the machine model, which ``<object>.<signal> <op> <value>`` compares (signals.py)
COMMAND_FLAGS = ("done", "error", "aborted", "busy", "active", "in_velocity", "finished",
                 "in_gear", "in_sync")
#: the entries whose rows have ``in_sync``: the gear-ins on planar tracks (planar_gearing.py)
_IN_SYNC_COMMANDS = ("gear_in_pos_on_track", "gear_in_pos_on_track_with_master_mover")
OPERATORS = ("<=", ">=", "==", "<", ">")
_CONDITION = re.compile(rf"^\s*({SUBJECT.pattern[4:-2]})\.([a-z_]+)\s*"
                        r"(?:(<=|>=|==|<|>)\s*(\S+))?\s*$")


@dataclasses.dataclass(frozen=True)
class Condition:
    """``<id>.<flag>`` (a command's output, COMMAND_FLAGS) or ``<object>.<signal> <op>
    <number>`` (a signal of the machine model, signals.py)."""

    text: str
    subject: str  #: entry id or object name
    attribute: str  #: command flag or signal
    operator: str | None = None  #: None: a command flag
    value: float | None = None

    def __str__(self) -> str:
        return self.text

    @property
    def signal(self) -> str:
        """``<object>.<signal>`` of a signal condition."""
        return f"{self.subject}.{self.attribute}"


def parse_condition(text: object) -> Condition:
    """Parse and check one condition; ValueError says what is wrong with it."""
    if isinstance(text, Condition):
        return text
    if not isinstance(text, str):
        raise ValueError(f"a condition is a string, got {text!r}")
    match = _CONDITION.match(text)
    if match is None:
        raise ValueError(f"{text!r} is neither '<id>.<flag>' nor '<axis>.<signal> <op> "
                         f"<number>' (op: {' '.join(OPERATORS)})")
    subject, attribute, operator, raw = match.groups()
    if operator is None:
        if attribute not in COMMAND_FLAGS:
            hint = (" needs a comparison, e.g. 'x.position >= 50'" if attribute in AXIS_CHOICES
                    else f": the flag must be one of {', '.join(COMMAND_FLAGS)}")
            raise ValueError(f"{text!r}{hint}")
        _check_id(subject)
        names = _NAMES.get()
        if attribute == "in_gear" and names is not None \
                and names.commands.get(subject) not in ("gear_in", "gear_in_pos_ca"):
            raise ValueError(f"{text!r}: in_gear is a flag of gear_in and gear_in_pos_ca "
                             "entries only")
        if attribute == "in_sync" and names is not None \
                and names.commands.get(subject) not in _IN_SYNC_COMMANDS:
            raise ValueError(f"{text!r}: in_sync is a flag of {' and '.join(_IN_SYNC_COMMANDS)} "
                             "entries only")
        return Condition(text.strip(), subject, attribute)
    names = _NAMES.get()
    if names is not None and subject in names.groups and subject not in names.axes:
        if attribute != "state" or operator != "==" or raw.upper() not in GroupState.__members__:
            states = ", ".join(state.name.lower() for state in GroupState)
            raise ValueError(f"{text!r}: a CA group's condition is '<group>.state == <state>' "
                             f"(states: {states})")
        return Condition(text.strip(), subject, attribute, operator,
                         float(GroupState[raw.upper()]))
    planar = planar_condition(text, subject, attribute, operator, raw)
    if planar is not None:
        return planar
    group = axes_group_condition(text, subject, attribute, operator, raw)
    if group is not None:
        return group
    if declared(subject, names) is not None:  # a planar track or part: any of its signals
        check_signal(f"{subject}.{attribute}", names)
    elif attribute not in AXIS_CHOICES:
        raise ValueError(f"{text!r}: the signal must be one of {', '.join(AXIS_CHOICES)}")
    else:
        check_signal(f"{subject}.{attribute}", names)
    return Condition(text.strip(), subject, attribute, operator,
                     _signal_value(f"{subject}.{attribute}", raw, text))


def _signal_value(signal: str, raw: str, text: str) -> float:
    """What a condition on ``signal`` (``<object>.<signal>``) compares with: a number, or a
    name its type takes (a state, an ErrorId ...: signals.value_of_name)."""
    names = _NAMES.get()
    named = value_of_name(spec_of(signal, names), raw, names)
    if named is not None:
        return named
    try:
        value = float(raw)
    except ValueError:
        raise ValueError(f"{text!r}: {raw!r} is not a number") from None
    if not math.isfinite(value):
        raise ValueError(f"{text!r}: {raw!r} is not finite")
    return value


ConditionText = Annotated[Condition, PlainValidator(parse_condition),
                          PlainSerializer(str, when_used="json")]


# -- axes ----------------------------------------------------------------------------------


class _Model(BaseModel):
    """Unknown keys are errors. Attribute docstrings document the fields for readers of
    this file; they are not extracted at import (D-173)."""

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True,
                              arbitrary_types_allowed=True)
    blocks: ClassVar[tuple[str, ...]] = ()  #: the blocks (``MC_Power``) and methods
    #: (``MC_PlanarTrack.append_line``) this part of a file reaches (scenario/coverage.py)
    outputs: ClassVar[tuple[str, ...]] = ()  #: a query entry's outputs (queries.py)


class _ParametersBase(_Model):
    @model_validator(mode="after")
    def _in_range(self) -> _ParametersBase:
        self.build()  # AxisParameters.validate names the field: "max_velocity: must be > 0"
        return self

    def build(self) -> AxisParameters:
        return AxisParameters(**{name: getattr(self, name) for name in self.model_fields_set})


_PARAMETER_TYPES: dict[Any, Any] = {float: Number, bool: StrictBool, int: StrictInt,
                                    tuple[float, float] | None: tuple[Number, Number] | None}


def _parameter_type(annotation: Any) -> Any:
    if isinstance(annotation, type) and issubclass(annotation, Enum):
        return _enum_by_name(annotation)
    return _PARAMETER_TYPES.get(annotation, annotation)


#: an option that also takes MC_DEFAULT, MC_IGNORE ... (core.special_values.InputValue)
_OPTION_TYPES: dict[Any, Any] = {float | SpecialValue: InputValue}


def option_fields(options: type, skip: Iterable[str] = (),
                  types: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The fields of an options struct (a dataclass such as ST_GearInPosCAOptions) as fields
    of a scenario entry (``create_model``): the same names and defaults, the type from the
    annotation (an enum by its lower-case name, a float a finite number, an input that takes
    MC_DEFAULT an InputValue); ``types`` by name where the annotation says too little,
    ``skip`` the fields the entry has already. A field added to the struct is a field of the
    entry (D-235)."""
    hints = get_type_hints(options)
    given = types or {}
    return {f.name: (given.get(f.name) or _OPTION_TYPES.get(hints[f.name])
                     or _parameter_type(hints[f.name]), f.default)
            for f in dataclasses.fields(options) if f.name not in set(skip)}


def with_options(base: type[BaseModel], options: type,
                 types: Mapping[str, Any] | None = None) -> Any:
    """The entry ``base`` (an entry with the block's other inputs, named ``_<Entry>``) with
    the fields of the struct ``options`` it lacks (``option_fields``), named ``<Entry>``, with
    ``base``'s docstring and its own ``blocks`` (scenario/coverage.py reads a model's own)."""
    own = {"blocks": (ClassVar[tuple[str, ...]], vars(base)["blocks"])} \
        if "blocks" in vars(base) else {}
    return create_model(base.__name__.lstrip("_"), __base__=base, __doc__=base.__doc__,
                        __module__=base.__module__, **own,
                        **option_fields(options, skip=base.model_fields, types=types))


_HINTS = get_type_hints(AxisParameters)
AxisParametersSpec = create_model(
    "AxisParametersSpec",
    __base__=_ParametersBase,
    __doc__="Any field of AxisParameters (axis/parameters.py, TcMC §6.1), same name and unit; "
            "unset fields keep the AxisParameters default.",
    **{f.name: (_parameter_type(_HINTS[f.name]), f.default)
       for f in dataclasses.fields(AxisParameters)},
)


class DriveSpec(_Model):
    """The drive and encoder model (axis/drive.py): ideal, or a lag behind a dead time."""

    model: Literal["ideal", "lag"] = "ideal"
    """ideal: actual = set position; lag: first-order lag behind a dead time."""
    time_constant: Seconds = 0.0
    """Lag of the closed position loop [s]."""
    dead_time: Seconds = 0.0
    """Transport delay [s], rounded to whole cycles."""

    def build(self) -> DriveModel:
        return DriveModel(self.model, self.time_constant, self.dead_time)


ProbeBound = Annotated[StrictFloat, Field(allow_inf_nan=True)]
ProbeInterval = tuple[ProbeBound, ProbeBound]


class ProbeSpec(_Model):
    """A ProbeSignal (axis/probe.py): the input is TRUE inside ``positions`` or ``times``."""

    positions: list[ProbeInterval] = []
    """[from, to] of the machine position, from <= p < to; ``.inf`` for an open end."""
    times: list[ProbeInterval] = []
    """[from, to] of the simulated time [s], from <= t < to."""

    @model_validator(mode="after")
    def _intervals(self) -> ProbeSpec:
        if bool(self.positions) == bool(self.times):
            raise ValueError("give 'positions' or 'times' (a non-empty list of [from, to])")
        for name in ("positions", "times"):
            try:
                _probe_intervals(name, getattr(self, name))
            except ConfigError as exc:
                raise ValueError(str(exc)) from None
        return self

    def build(self, axis: Axis) -> ProbeSignal:
        return ProbeSignal(axis, positions=self.positions, times=self.times)


class AxisSpec(_Model):
    """One axis of the runtime."""

    name: Annotated[Identifier, _unique("axes")]
    """Unique name; signals and timeline entries refer to it."""
    parameters: AxisParametersSpec = AxisParametersSpec()  # type: ignore[valid-type]
    """AxisParameters fields to set (the rest keep their defaults)."""
    drive: DriveSpec = DriveSpec()
    """Drive and encoder model."""
    position: Number = 0.0
    """Initial position [mm or °]."""
    probe: ProbeSpec | None = None
    """The touch-probe input (TouchProbe1) of the axis; default: none wired."""


# -- timeline ------------------------------------------------------------------------------


class Entry(_Model):
    """One timeline entry: a command for one axis, issued once at a time or on a condition.

    Entries are looked at in file order at the start of every cycle (before motion), so a
    condition sees the state after the previous cycle; ``at`` fires in the first cycle whose
    time is >= ``at`` (``at: 0`` before the first cycle).
    """

    method: ClassVar[str]  #: the Axis method the entry calls
    axis_fields: ClassVar[tuple[str, ...]] = ()  #: arguments that name an axis (the run
    #: passes the Axis object)
    id: Annotated[Identifier, _unique("ids")] | None = None
    """Name for conditions and checks; unique."""
    at: Seconds | None = None
    """Issue time [s]; give ``at`` or ``when``."""
    when: ConditionText | None = None
    """Issue once, in the first cycle this condition holds."""
    axis: Annotated[StrictStr, AfterValidator(_check_axis)]
    """Name of the axis the command is for."""

    @model_validator(mode="after")
    def _trigger(self) -> Entry:
        if (self.at is None) == (self.when is None):
            raise ValueError("give exactly one of 'at' (seconds) or 'when' (a condition)")
        return self

    def arguments(self) -> dict[str, Any]:
        """Keyword arguments of the Axis method, by the method's parameter names."""
        skip = {"id", "at", "when", "axis", "command"}
        return {name: getattr(self, name) for name in type(self).model_fields
                if name not in skip}


class _Move(Entry):
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]; 0 or MC_DEFAULT = axis default, MC_MAXIMUM = axis maximum."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]; 0 or MC_DEFAULT = axis default, MC_MAXIMUM = axis maximum."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]; 0 or MC_DEFAULT = axis default, MC_MAXIMUM = axis maximum."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """aborting, buffered, blending_low, blending_previous, blending_next, blending_high."""


class Power(Entry):
    """MC_Power with Enable TRUE: the axis goes from Disabled to Standstill."""

    method = "power"
    command: Literal["power"]
    enable_positive: StrictBool = True
    """Feed enable in positive direction."""
    enable_negative: StrictBool = True
    """Feed enable in negative direction."""
    override: Number | None = None
    """MC_Power's Override [%], 0-100, written as MC_SetOverride does; default: left as it
    is (100 at the start). A value outside 0-100 ends the entry with INVALID_OVERRIDE."""

    def arguments(self) -> dict[str, Any]:
        return {"enable_positive": self.enable_positive, "enable_negative": self.enable_negative}


class PowerOff(Entry):
    """MC_Power with Enable FALSE: running commands are aborted, the axis is Disabled."""

    method = "power"
    command: Literal["power_off"]

    def arguments(self) -> dict[str, Any]:
        return {"enable": False}


class Reset(Entry):
    """MC_Reset: leave ErrorStop once the error reaction has stopped the axis."""

    method = "reset"
    command: Literal["reset"]


class SetOverride(Entry):
    """MC_SetOverride: velocity override in percent."""

    method = "set_override"
    command: Literal["set_override"]
    override: Number
    """Velocity override [%], 0-100."""

    def arguments(self) -> dict[str, Any]:
        return {"percent": self.override}


class MoveAbsolute(_Move):
    """MC_MoveAbsolute (TcMC §3.1)."""

    method = "move_absolute"
    command: Literal["move_absolute"]
    position: InputValue
    """Target position [mm or °]."""
    velocity: InputValue
    """[mm/s]; MC_MAXIMUM = axis maximum."""


class MoveRelative(_Move):
    """MC_MoveRelative (TcMC §3.2)."""

    method = "move_relative"
    command: Literal["move_relative"]
    distance: InputValue
    """Distance from the set position where the move starts [mm or °]."""
    velocity: InputValue
    """[mm/s]; MC_MAXIMUM = axis maximum."""


class MoveModulo(_Move):
    """MC_MoveModulo (TcMC §3.4, §3.5)."""

    method = "move_modulo"
    command: Literal["move_modulo"]
    position: InputValue
    """Modulo target; a target >= the period adds whole turns."""
    velocity: InputValue
    """[mm/s]; MC_MAXIMUM = axis maximum."""
    direction: DirectionName = Direction.POSITIVE
    """positive, negative or shortest_way."""


class MoveVelocity(_Move):
    """MC_MoveVelocity (TcMC §3.3)."""

    method = "move_velocity"
    command: Literal["move_velocity"]
    velocity: InputValue
    """Speed [mm/s], > 0."""
    direction: DirectionName = Direction.POSITIVE
    """positive, negative or current."""


class Halt(Entry):
    """MC_Halt: a stop that other commands may abort."""

    method = "halt"
    command: Literal["halt"]
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]; 0 or MC_DEFAULT = axis default."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]; 0 or MC_DEFAULT = axis default."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """As for moves."""


class Stop(Entry):
    """MC_Stop (TcMC §3.15): brake to rest; the axis refuses motion commands meanwhile."""

    method = "stop"
    command: Literal["stop"]
    deceleration: InputValue = 0.0
    """[mm/s²]; 0 keeps the running move's deceleration."""
    jerk: InputValue = 0.0
    """[mm/s³]; 0 keeps the running move's jerk."""


class ChangeDynamics(Entry):
    """MC_ChangeDynParam (TcMC §4.20): new dynamics for the running move."""

    method = "change_dynamics"
    command: Literal["change_dynamics"]
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""


class NewPosition(Entry):
    """MC_NewPos (TcMC §3.7): a new target for the running move."""

    method = "new_position"
    command: Literal["new_position"]
    position: InputValue
    """New target position [mm or °]."""


class NewPositionAndVelocity(Entry):
    """MC_NewPosAndVelo (TcMC §3.8): new target and/or velocity, now or at a position."""

    method = "new_position_and_velocity"
    command: Literal["new_position_and_velocity"]
    mode: _enum_by_name(NewPosAndVeloMode)  # type: ignore[valid-type]
    """change_pos, change_velo, change_pos_and_velo, ..._at_switchpos, reach_velo_at_pos."""
    position: InputValue = MC_INVALID
    """New target position [mm or °], for the modes that change it."""
    velocity: InputValue = MC_INVALID
    """New velocity [mm/s], for the modes that change it."""
    activation_position: Number = 0.0
    """Switch position [mm or °] of the *_at_switchpos and reach_velo_at_pos modes."""


class SetActualPosition(Entry):
    """MC_SetActualPosition (TcMC §4.12): shift the coordinates so actual = position."""

    method = "set_actual_position"
    command: Literal["set_actual_position"]
    position: InputValue
    """New actual position [mm or °]."""


class Home(Entry):
    """MC_Home (TcMC §3.14) with the axis' configured reference mode."""

    method = "home"
    command: Literal["home"]
    position: InputValue = DEFAULT_HOME_POSITION
    """Reference position; default: the axis' calibration_value."""
    calibration_cam: ProbeSpec | None = None
    """MC_Home's bCalibrationCam as the PLC wires it: TRUE inside ``positions`` (of the
    machine position) or ``times``, every cycle while the homing runs; default: the axis'
    simulated cam (its reference_cam parameter)."""

    def arguments(self) -> dict[str, Any]:
        return {"position": self.position}


class GearIn(Entry):
    """MC_GearIn / MC_GearInFloat, or MC_GearInDyn with ``acceleration`` (TcMC §3.17-3.19).

    Couples at standstill only: slave in Standstill, master at rest.
    """

    method = "gear_in"
    command: Literal["gear_in"]
    axis_fields: ClassVar[tuple[str, ...]] = ("master",)
    master: Annotated[StrictStr, AfterValidator(_check_axis)]
    """Name of the master axis."""
    ratio: Number
    """Gear ratio slave : master (may be negative or fractional)."""
    acceleration: InputValue | None = None
    """[mm/s²]: a dynamic coupling (MC_GearInDyn) whose ratio changes slew at most at
    acceleration / master max_velocity per second; omitted: a fixed coupling."""


class SetGearRatio(Entry):
    """A new target ratio for a coupling (MC_GearInDyn's GearRatio input, TcMC §3.19)."""

    method = "set_gear_ratio"
    command: Literal["set_gear_ratio"]
    ratio: Number
    """New gear ratio slave : master."""


class GearOut(Entry):
    """MC_GearOut (TcMC §3.20): decouple; a moving slave keeps its velocity."""

    method = "gear_out"
    command: Literal["gear_out"]


class GearOutExt(Entry):
    """MC_GearOutExt (TcMC §3.21): decouple, then a follow-up ``mode`` if the slave moves.

    The entry's outcome is the follow-up command's (Done at its target or velocity).
    """

    method = "gear_out_ext"
    command: Literal["gear_out_ext"]
    mode: _enum_by_name(DecoupleMode)  # type: ignore[valid-type]
    """stop, oriented_stop, endless, endless_new_velocity, new_position,
    new_position_and_velocity, instantaneous_stop."""
    position: InputValue = MC_INVALID
    """Target [mm or °] of new_position*, modulo position of oriented_stop."""
    velocity: InputValue = MC_INVALID
    """[mm/s] of endless_new_velocity and new_position_and_velocity."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""


class OrientedStop(Entry):
    """MC_OrientedStop (TcMC §3.16): stop at the next reachable modulo position."""

    method = "oriented_stop"
    command: Literal["oriented_stop"]
    position: InputValue
    """Modulo stop position, 0 <= position < modulo_period."""


class SetActualPositionOnTheFly(Entry):
    """MC_SetActualPositionOnTheFly (TcMC §4.13): shift the coordinates of a moving axis."""

    method = "set_actual_position_on_the_fly"
    command: Literal["set_actual_position_on_the_fly"]
    actual_position: InputValue
    """New value of ``previous_position`` [mm or °]."""
    previous_position: InputValue
    """The old coordinate that becomes ``actual_position`` [mm or °]."""


class TouchProbe(Entry):
    """MC_TouchProbe (TcMC §4.21) on the axis' ``probe`` input: latch the position at an edge.

    The command ends Done with the recorded position as its value (checks: ``value``).
    """

    method = "arm_probe"
    command: Literal["touch_probe"]
    touch_probe: _enum_by_name(TouchProbeSource) = (  # type: ignore[valid-type]
        TouchProbeSource.TOUCH_PROBE_1)
    """The trigger: touch_probe_1 (the axis' ``probe`` input) or plc_event (a plc_event
    entry's rising edge); touch_probe_2 to 4 fail (unsupported, §6.3)."""
    edge: _enum_by_name(SignalEdge) = SignalEdge.RISING  # type: ignore[valid-type]
    """rising or falling."""
    window_only: StrictBool = False
    """Accept only edges at positions in [first_position, last_position]."""
    first_position: Number = 0.0
    """Window start [mm or °]."""
    last_position: Number = 0.0
    """Window end [mm or °]; with modulo_positions a window first > last wraps through 0."""
    modulo_positions: StrictBool = False
    """Window and recorded position as modulo values of the axis' modulo_period."""

    def arguments(self) -> dict[str, Any]:
        return {"window_only": self.window_only, "first_position": self.first_position,
                "last_position": self.last_position}

    def trigger_input(self) -> InputRef:
        """A fresh MC_InputRef for this entry (TouchProbe1, the entry's edge)."""
        return InputRef(touch_probe=self.touch_probe, edge=self.edge,
                        modulo_positions=self.modulo_positions)


class PlcEvent(Entry):
    """MC_TouchProbe's TriggerInput.PlcEvent (TcMC §4.21, §6.3): the PLC program sets it to
    ``value``. A touch_probe entry with touch_probe: plc_event records the position of the
    cycle in which it rises. Done at once."""

    method = "plc_event"
    blocks = ("MC_TouchProbe",)
    command: Literal["plc_event"]
    probe: Annotated[StrictStr, _check_id_of("touch_probe", "probe")]
    """The id of the touch_probe entry whose TriggerInput it sets."""
    value: StrictBool = True
    """The new level of PlcEvent."""

    def arguments(self) -> dict[str, Any]:
        return {}  # the run sets the touch_probe entry's InputRef


class AbortTrigger(Entry):
    """MC_AbortTrigger (TcMC §4.22): disarm the probe cycle of a touch_probe entry."""

    method = "abort_probe"
    command: Literal["abort_trigger"]
    probe: Annotated[StrictStr, _check_id_of("touch_probe", "probe")]
    """The id of the touch_probe entry to disarm."""

    def arguments(self) -> dict[str, Any]:
        return {}  # the run passes the touch_probe entry's InputRef


class MoveSuperimposed(Entry):
    """MC_MoveSuperImposed(Ext) (TcMC §3.9): add ``distance`` on top of the running motion.

    The command's value is (ActualVelocityDiff, ActualDistance, ActualLength); a ``value``
    check compares the actual distance. A distance done only partly ends the command with
    SUPERPOSITION_INCOMPLETE.
    """

    method = "move_superimposed"
    blocks = ("MC_MoveSuperImposed", "MC_MoveSuperImposedExt")  #: Ext: the mode input
    command: Literal["move_superimposed"]
    distance: InputValue
    """Additional distance [mm or °], != 0; its sign gives the direction."""
    velocity_diff: InputValue
    """Maximum velocity difference to the base motion [mm/s]."""
    velocity_process: InputValue
    """Velocity of the base motion [mm/s] the length is planned for."""
    length: InputValue
    """Base-motion distance [mm or °] within which the superposition is done, != 0."""
    mode: _enum_by_name(SuperpositionMode) = (  # type: ignore[valid-type]
        SuperpositionMode.LENGTHREDUCTION_LIMITEDMOTION)
    """veloreduction_additivemotion, veloreduction_limitedmotion,
    lengthreduction_additivemotion, lengthreduction_limitedmotion."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""


class AbortSuperposition(Entry):
    """MC_AbortSuperposition (TcMC §3.12): end the superimposed part; the base continues."""

    method = "abort_superposition"
    command: Literal["abort_superposition"]


# Axes groups (PLCopen Part 4): the axes_groups list and the entries on axes groups.
from openmotion.scenario.coordinated import (  # noqa: E402 - needs Entry and the types above
    COORDINATED_COMMANDS,
    AxesGroupSpec,
    axes_group_condition,
)

# The entries that a function block carries out (jog, external setpoints, override filter,
# stepper, reference flag) build on Entry above; they live in their own module.
from openmotion.scenario.cyclic import (  # noqa: E402 - needs Entry and the types above
    CALL_ENTRIES,
    DisableExternalSetpoints,
    EnableExternalSetpoints,
    InjectStall,
    Jog,
    OverrideFilter,
    PowerStepper,
    ReadAxisComponents,
    ReleaseStall,
    SetReferenceFlag,
)

# Planar movers and groups (TF5430): the planar block and the entries on movers and groups.
from openmotion.scenario.planar import (  # noqa: E402 - needs Entry and the types above
    PLANAR_COMMANDS,
    PlanarSpec,
    planar_condition,
)
from openmotion.scenario.planar_parts import part_oids  # noqa: E402 - as planar above

# CA groups (TF5410): the ca_groups list and the entries on movers and groups.
from openmotion.scenario.transport import (  # noqa: E402 - needs Entry and the types above
    GROUP_CALL_ENTRIES,
    ActivateTrack,
    CaGroupSpec,
    GearInPosCa,
    GroupDisable,
    GroupEnable,
    GroupHalt,
    GroupReset,
    GroupStop,
    HaltCa,
    MoveAbsoluteCa,
    MoveRelativeCa,
    RegisterCompensation,
    SetGap,
)

COMMANDS: dict[str, type[Entry]] = {
    get_args(model.model_fields["command"].annotation)[0]: model
    for model in (Power, PowerOff, Reset, SetOverride, MoveAbsolute, MoveRelative, MoveModulo,
                  MoveVelocity, Halt, Stop, ChangeDynamics, NewPosition, NewPositionAndVelocity,
                  SetActualPosition, Home, GearIn, SetGearRatio, GearOut, GearOutExt,
                  OrientedStop, SetActualPositionOnTheFly, TouchProbe, AbortTrigger, PlcEvent,
                  MoveSuperimposed, AbortSuperposition, Jog, EnableExternalSetpoints,
                  DisableExternalSetpoints, OverrideFilter, PowerStepper, InjectStall,
                  ReleaseStall, SetReferenceFlag, ReadAxisComponents, MoveAbsoluteCa,
                  MoveRelativeCa, GearInPosCa, HaltCa, ActivateTrack, RegisterCompensation,
                  SetGap, GroupHalt, GroupStop, GroupEnable, GroupDisable,
                  GroupReset, *CALL_ENTRIES, *GROUP_CALL_ENTRIES)  # type: ignore[misc]
}
#: every timeline entry's model by its ``command``: COMMANDS (on axes, CA movers and groups),
#: the planar ones (on planar movers and groups), the axes-group ones and the router's
from openmotion.scenario.planar_routing import Route  # noqa: E402 - needs the planar names

#: the router's entry (planar_routing.py): it calls no TF5430 method, so it is no planar entry
ROUTING_COMMANDS: dict[str, type] = {"route": Route}
TIMELINE_COMMANDS: dict[str, type] = {**COMMANDS, **PLANAR_COMMANDS, **COORDINATED_COMMANDS,
                                      **ROUTING_COMMANDS}
TimelineEntry = Annotated[
    Union[tuple(Annotated[model, Tag(name)]  # noqa: UP007 - a union built from the dict
                for name, model in TIMELINE_COMMANDS.items())],
    Discriminator("command"),
]


# -- recording and checks ------------------------------------------------------------------


class RecordSpec(_Model):
    """What the trace holds."""

    signals: list[SignalName] | None = None
    """``<axis>.<signal>`` names; default: set_position, set_velocity, set_acceleration and
    position of every axis."""
    every: Annotated[StrictInt, Field(ge=1)] = 1
    """Record every N-th cycle."""
    keep: Annotated[StrictInt, Field(ge=1)] | None = None
    """Keep only the last N rows in memory (a ring; D-188). Default: every row."""
    stream: Annotated[StrictStr, Field(min_length=1)] | None = None
    """Write the trace to this directory in chunks as the run goes (relative to the working
    directory; D-188). Default: in memory."""
    chunk: Annotated[StrictInt, Field(ge=1)] | None = None
    """Rows per chunk with ``stream``. Default: about a million values per chunk."""

    @model_validator(mode="after")
    def _one_mode(self) -> RecordSpec:
        if self.keep is not None and self.stream is not None:
            raise ValueError("give 'keep' or 'stream', not both")
        if self.chunk is not None and self.stream is None:
            raise ValueError("'chunk' needs 'stream'")
        return self


def _check_time(value: object) -> float | str:
    if value in ("end", "always"):
        return value  # type: ignore[return-value]
    if isinstance(value, int | float) and not isinstance(value, bool) \
            and math.isfinite(value) and value >= 0:
        return float(value)
    raise ValueError(f"must be 'end', 'always' or a time in seconds >= 0, got {value!r}")


CheckTime = Annotated[float | str, PlainValidator(_check_time)]


class _Check(_Model):
    name: StrictStr | None = None
    """Label in the summary (default: generated from the check)."""
    at: CheckTime = "end"
    """end (default), a time [s] (the first cycle at or after it), or always (every cycle)."""
    when: ConditionText | None = None
    """Instead of ``at``: check once, in the first cycle this condition holds."""

    @model_validator(mode="after")
    def _one_trigger(self) -> _Check:
        if self.when is not None and "at" in self.model_fields_set:
            raise ValueError("give 'at' or 'when', not both")
        return self


class SignalCheck(_Check):
    """A signal must equal ``expect`` (± ``tolerance``) and/or lie in [min, max]."""

    signal: SignalName
    """``<object>.<signal>``: a signal of the machine model (signals.py)."""
    expect: Annotated[float | str, PlainValidator(_expect_value)] | None = None
    """Expected value; for ``.state`` also a state name such as standstill (a planar mover's:
    enabled), for ``.axis_error_id`` an ErrorId name such as STEPPER_STALL."""
    tolerance: Annotated[StrictFloat, Field(ge=0.0)] = 1e-9
    """Allowed |actual - expect|."""
    min: Number | None = None
    """Lower bound."""
    max: Number | None = None
    """Upper bound."""
    _expected: float | None = PrivateAttr(default=None)  #: ``expect`` as a number

    @model_validator(mode="after")
    def _something_to_check(self) -> SignalCheck:
        if self.expect is None and self.min is None and self.max is None:
            raise ValueError("give 'expect', 'min' or 'max'")
        names = _NAMES.get()
        spec = spec_of(self.signal, names)
        self._expected = self.expect if not isinstance(self.expect, str) else \
            value_of_name(spec, self.expect, names)
        if isinstance(self.expect, str) and self._expected is None:
            raise ValueError(f"expect: {self.expect!r} is not a number{expect_hint(spec)}")
        return self

    @property
    def expected(self) -> float | None:
        return self._expected


class CommandCheck(_Check):
    """A timeline entry's command must have ended with ``result`` (and ``value``)."""

    command: Annotated[StrictStr, AfterValidator(_check_id)]
    """The id of a timeline entry."""
    result: Literal["done", "aborted", "error", "busy"]
    """Expected outcome."""
    error_id: ErrorIdName | None = None
    """Expected ErrorId name, e.g. AXIS_STOPPING (with result: error)."""
    value: Number | None = None
    """Expected result value of the command, e.g. a touch_probe's recorded position or a
    move_superimposed's actual distance."""
    tolerance: Annotated[StrictFloat, Field(ge=0.0)] = 1e-9
    """Allowed |value - expected value|."""
    output: StrictStr | None = None
    """With ``value``: the output of a query entry to compare (read_status: standstill,
    group_read_actual_position: position_1 ...; scenario/queries.py, D-218)."""

    @model_validator(mode="after")
    def _tolerance_with_value(self) -> CommandCheck:
        if self.value is None and "tolerance" in self.model_fields_set:
            raise ValueError("'tolerance' needs 'value'")
        if self.output is not None and self.value is None:
            raise ValueError("'output' needs 'value'")
        names = _NAMES.get()
        model = TIMELINE_COMMANDS.get(names.commands.get(self.command)) \
            if names is not None and isinstance(names.commands.get(self.command), str) else None
        if model is not None and self.output is not None:
            if not issubclass(model, Query):
                raise ValueError(f"output: {self.command!r} is no query entry (read_status, "
                                 "get_length ...), it has no outputs")
            if not model.has_output(self.output):
                raise ValueError(f"output: {self.command!r} has no output {self.output!r} "
                                 f"(outputs: {', '.join(model.outputs) or 'none'})")
        elif model is not None and issubclass(model, Query) and self.value is not None:
            raise ValueError(f"value: {self.command!r} is a query; name the output to "
                             f"compare in 'output' (outputs: {', '.join(model.outputs)})")
        return self


CHECKS: dict[str, type[_Check]] = {"signal": SignalCheck, "command": CommandCheck}


def _check_kind(value: object) -> str | None:
    """The key that tells a check's kind: ``signal`` or ``command``."""
    for kind, model in CHECKS.items():
        if isinstance(value, model) or isinstance(value, dict) and kind in value:
            return kind
    return None

Check = Annotated[
    Annotated[SignalCheck, Tag("signal")] | Annotated[CommandCheck, Tag("command")],
    Discriminator(_check_kind, custom_error_type="check_kind",
                  custom_error_message="a check needs 'signal' or 'command'"),
]


# -- the scenario --------------------------------------------------------------------------


class Scenario(_Model):
    """A scenario file: axes, a timeline of commands, what to record and what to check."""

    name: StrictStr
    """Title shown in the summary."""
    description: StrictStr = ""
    """Free text."""
    cycle_time: PositiveSeconds = 0.001
    """Runtime cycle [s]."""
    duration: PositiveSeconds | None = None
    """Simulated time [s]. Default: until no ``at`` of an entry or check lies ahead, every
    issued command has ended (a MoveVelocity counts once at speed) and no axis moves, then
    ``settle_time`` more. An entry whose ``when`` never holds does not keep the run going."""
    settle_time: Seconds = 0.1
    """Extra time [s] after everything came to rest, when ``duration`` is not given."""
    max_duration: PositiveSeconds = 60.0
    """Hard cap [s] on simulated time when ``duration`` is not given."""
    axes: list[AxisSpec] = []
    """The axes, created in this order; at least one unless there are planar movers."""
    ca_groups: list[CaGroupSpec] = []
    """CA groups (TF5410), built after the axes in this order."""
    planar: PlanarSpec | None = None
    """Planar movers on a stator surface (TF5430): scenario/planar.py."""
    axes_groups: list[AxesGroupSpec] = []
    """Axes groups (PLCopen Part 4), built after the CA groups: scenario/coordinated.py."""
    timeline: list[TimelineEntry] = []
    """Commands, looked at in this order every cycle."""
    record: RecordSpec = RecordSpec()
    """Trace signals."""
    checks: list[Check] = []
    """Assertions; the run fails when one fails."""

    @model_validator(mode="wrap")
    @classmethod
    def _publish_names(cls, data: Any, handler: Any) -> Scenario:
        token = _NAMES.set(_Names.of(data))
        try:
            return handler(data)
        finally:
            _NAMES.reset(token)

    @model_validator(mode="after")
    def _something_to_run(self) -> Scenario:
        if not self.axes and self.planar is None:
            raise ValidationError.from_exception_data(type(self).__name__, [InitErrorDetails(
                type=PydanticCustomError("value_error", "give at least one axis (or planar "
                                                        "movers)"), loc=("axes",), input=None)])
        from openmotion.scenario.planar_routing import route_problems

        problems = route_problems(self.planar, self.timeline)
        if problems:
            raise ValidationError.from_exception_data(type(self).__name__, [InitErrorDetails(
                type=PydanticCustomError("value_error", message), loc=loc, input=None)
                for loc, message in problems])
        return self

    @property
    def signals(self) -> list[str]:
        """The recorded signals (the default set when ``record.signals`` is not given)."""
        if self.record.signals is not None:
            return list(self.record.signals)
        movers = [mover.name for mover in self.planar.movers] if self.planar else []
        return default_signals(AXIS, (axis.name for axis in self.axes)) + \
            default_signals(PLANAR_MOVER, movers) + \
            default_signals(AXES_GROUP, (group.name for group in self.axes_groups))

    def entries(self) -> Iterator[tuple[str, Entry]]:
        """(label, entry) in timeline order; the label is the id or ``#<number>``."""
        for number, entry in enumerate(self.timeline, start=1):
            yield entry.id or f"#{number}", entry
