"""Planar motion (TF5430) in scenario files: the ``planar`` block and its timeline entries.

``planar`` declares a stator ``environment``, the ``movers``, the planar ``groups`` and the
``tracks``; the run builds and sets them up before t = 0 (planar_machine.py). The block
validates by doing the same setup on a scratch runtime, so a file that loads also sets up, and
each failure names its field: a mover standing on another, a mover off the stators, a track
whose geometry the engine refuses.

Timeline entries name the mover in ``mover`` (or the planar group in ``group``) and call the
MC_PlanarMover (MC_PlanarGroup) method of the same name; ``arguments()`` gives the method's
inputs after the feedback (the run passes none: PLC 0). Signals of a mover (``<mover>.x``
...) are its kind's in the machine model (planar/kind.py, scenario/signals.py). schema.py
puts the block into its
``Scenario`` and the entries into ``TIMELINE_COMMANDS``; they share its value types,
conditions and name checks. Parts and coordinate systems (the environment's ``parts``, the
``activate_part_position`` entry) are in planar_parts.py, the external setpoint entries in
planar_setpoints.py, tracks in planar_tracks.py, the track commands of movers in
planar_riding.py, the gear-ins on tracks in planar_gearing.py and the router with its
``route`` entry in planar_routing.py.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from dataclasses import fields
from typing import Annotated, Any, Literal, get_args, get_type_hints

from pydantic import (
    AfterValidator,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    ValidationError,
    create_model,
    model_validator,
)
from pydantic_core import InitErrorDetails, PydanticCustomError

from openmotion.core.errors import ConfigError
from openmotion.core.special_values import MC_DEFAULT
from openmotion.planar import (
    DynamicConstraint_PathXY,
    ModuloDirection,
    MoverVector,
    PartLayout,
    PlanarMoverParameters,
    PlanarState,
    PositionXYC,
    ST_MoveCOptions,
    ST_MoveToPositionOptions,
)
from openmotion.planar.options import ST_AdoptTrackOrientationOptions
from openmotion.planar.stators import STATOR_SIZE, StatorField
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.planar_parts import (
    ObjectId,
    PartSpec,
    ReferenceId,
    build_layout,
    is_static,
    layout_problems,
    oid_text,
)
from openmotion.scenario.planar_routing import RouterSpec, router_problems
from openmotion.scenario.planar_tracks import TrackName, TrackSpec, order_problems
from openmotion.scenario.schema import (
    _NAMES,
    Condition,
    Identifier,
    InputValue,
    Number,
    _enum_by_name,
    _Model,
    _signal_value,
    _unique,
)
from openmotion.scenario.signals import check_signal, spec_of, value_of_name
from openmotion.scenario.stations import (
    PlanarRouteSpec,
    PlanarStationSpec,
    planar_station_problems,
)
from openmotion.scenario.transport import _Timed
from openmotion.trajectory.plan import Limits

Loc = tuple[str | int, ...]
ModuloDirectionName = _enum_by_name(ModuloDirection)

# -- names ---------------------------------------------------------------------------------


def _check_planar_mover(name: str) -> str:
    names = _NAMES.get()
    if names is not None and name not in names.planar_movers:
        known = ", ".join(sorted(names.planar_movers)) or "none"
        raise ValueError(f"unknown planar mover {name!r} (planar.movers: {known})")
    return name


def _check_planar_group(name: str) -> str:
    names = _NAMES.get()
    if names is not None and name not in names.planar_groups:
        known = ", ".join(sorted(names.planar_groups)) or "none"
        raise ValueError(f"unknown planar group {name!r} (planar.groups: {known})")
    return name


def _own_name(*kinds: str) -> Any:
    """A name that is none of the other ``kinds`` of names (conditions find it by name)."""
    def check(name: str) -> str:
        names = _NAMES.get()
        for kind in kinds:
            if names is not None and name in getattr(names, kind):
                raise ValueError(f"{name!r} is already the name of {_KINDS[kind]}")
        return name

    return AfterValidator(check)


_KINDS = {"axes": "an axis", "groups": "a CA group", "planar_movers": "a planar mover"}


def planar_condition(text: str, subject: str, attribute: str, operator: str,
                     raw: str) -> Condition | None:
    """``<mover>.<signal> <op> <value>`` or ``<group>.state == <state>``; None when
    ``subject`` is not planar. A state is a PlanarState name (``enabled``)."""
    names = _NAMES.get()
    if names is not None and subject in names.planar_groups:
        if attribute != "state" or operator != "==" or raw.upper() not in PlanarState.__members__:
            raise ValueError(f"{text!r}: a planar group's condition is '<group>.state == "
                             f"<state>' (states: {_STATES})")
        return Condition(text.strip(), subject, attribute, operator,
                         float(PlanarState[raw.upper()]))
    if names is None or subject not in names.planar_movers:
        return None
    signal = f"{subject}.{attribute}"
    check_signal(signal, names)
    named = value_of_name(spec_of(signal, names), raw, names)
    if attribute == "state" and named is None:
        raise ValueError(f"{text!r}: {raw!r} is not a planar state ({_STATES})")
    if attribute == "track" and named is None and not _is_number(raw):
        raise ValueError(f"{text!r}: {raw!r} is not a planar track ({_tracks()})")
    value = named if named is not None else _signal_value(signal, raw, text)
    return Condition(text.strip(), subject, attribute, operator, value)


_STATES = ", ".join(state.name.lower() for state in PlanarState)


def _tracks() -> str:
    """The names a ``track`` signal compares with: the planar tracks and ``none``."""
    names = _NAMES.get()
    return ", ".join([*(names.planar_tracks if names is not None else []), "none"])


def _is_number(raw: str) -> bool:
    try:
        float(raw)
    except ValueError:
        return False
    return True

# -- planar.environment --------------------------------------------------------------------

Corner = tuple[Number, Number]


class EnvironmentSpec(_Model):
    """MC_PlanarEnvironment (§6.4): a block of ``columns`` x ``rows`` stators from ``origin``,
    the lower-left corners of the ``stators`` one by one (AddStator, §6.4.2), or the ``parts``
    of a processing unit in its ``coordinate_systems`` (§5.2, planar_parts.py)."""

    columns: Annotated[StrictInt, Field(ge=1)] | None = None
    """Stators along x (with ``rows``)."""
    rows: Annotated[StrictInt, Field(ge=1)] | None = None
    """Stators along y (with ``columns``)."""
    origin: Corner = (0.0, 0.0)
    """Lower-left corner of the block [mm]."""
    stators: Annotated[list[Corner], Field(min_length=1)] | None = None
    """Instead of columns and rows: the corners [mm] on one 240 mm grid, no two alike."""
    coordinate_systems: Annotated[list[ObjectId], Field(min_length=1)] | None = None
    """With ``parts``: the OIDs of the coordinate systems (a group checks in the first, D-088)."""
    blocks = ("MC_PlanarEnvironment.add_stator", "MC_PlanarEnvironment.create_boundary",
              "MC_PlanarEnvironment.update")  #: in the setup; Update every cycle

    parts: Annotated[list[PartSpec], Field(min_length=1)] | None = None
    """Instead of stators: the parts (§5.1), each with its stators in the part frame and its
    positions in the coordinate systems. Targets then take a ``reference_id`` (§5.3)."""

    @model_validator(mode="after")
    def _one_layout(self) -> EnvironmentSpec:
        block = self.columns is not None or self.rows is not None
        if (self.parts is None) != (self.coordinate_systems is None):
            raise ValueError("'parts' and 'coordinate_systems' go together")
        if block + (self.stators is not None) + (self.parts is not None) != 1:
            raise ValueError("give 'columns' and 'rows', or 'stators' (a list of [x, y]), or "
                             "'parts' with 'coordinate_systems'")
        if block and (self.columns is None or self.rows is None):
            raise ValueError("give both 'columns' and 'rows'")
        if not block and "origin" in self.model_fields_set:
            raise ValueError("'origin' goes with columns and rows; stators and parts give "
                             "their corners")
        if self.parts is not None and self.coordinate_systems is not None:
            _raise(self, layout_problems(self.coordinate_systems, self.parts))
            return self
        problems = []
        field = StatorField()
        for index, (x, y) in enumerate(self.corners()):
            try:
                field.add_stator(x, y)
            except ConfigError as exc:  # "stators[1] (240.0, 0.0): overlaps stators[0] ..."
                problems.append((("stators", index), str(exc).split(": ", 1)[-1]))
        _raise(self, problems)
        return self

    def corners(self) -> list[tuple[float, float]]:
        """The stators' lower-left corners [mm] in AddStator order (row by row); none with
        parts, whose stators the environment takes from the layout."""
        if self.stators is not None:
            return [(float(x), float(y)) for x, y in self.stators]
        x0, y0 = self.origin
        return [(x0 + i * STATOR_SIZE, y0 + j * STATOR_SIZE)
                for j in range(self.rows or 0) for i in range(self.columns or 0)]

    def layout(self) -> PartLayout | None:
        """A new PartLayout of the parts (each run needs its own); None without parts."""
        if self.parts is None or self.coordinate_systems is None:
            return None
        return build_layout(self.coordinate_systems, self.parts)

    @property
    def is_static(self) -> bool:
        """No parts, or one coordinate system and no part with several positions: the
        boundary holds for the whole run, so the environment can join a group."""
        return self.parts is None or is_static(self.coordinate_systems or [], self.parts)

    def part_oids(self) -> list[int]:
        return [part.oid for part in self.parts or []]


# -- planar.movers -------------------------------------------------------------------------


class _Partial(_Model):
    """Some fields of a parameter struct; ``over`` fills the rest from its default."""

    def over(self, default: Any) -> Any:
        return type(default)(**{f.name: getattr(default, f.name) if getattr(self, f.name) is None
                                else getattr(self, f.name) for f in fields(default)})


class LimitsSpec(_Partial):
    """Dynamics of one coordinate group; unset fields keep the parameter's default."""

    velocity: Number | None = None
    """[mm/s or °/s]."""
    acceleration: Number | None = None
    """[mm/s² or °/s²]."""
    deceleration: Number | None = None
    """[mm/s² or °/s²]."""
    jerk: Number | None = None
    """[mm/s³ or °/s³]."""


class VectorSpec(_Partial):
    """Six coordinates; unset ones keep the parameter's default (``.inf`` allowed)."""

    x: StrictFloat | None = None
    y: StrictFloat | None = None
    z: StrictFloat | None = None
    a: StrictFloat | None = None
    b: StrictFloat | None = None
    c: StrictFloat | None = None


class _MoverParametersBase(_Model):
    @model_validator(mode="after")
    def _in_range(self) -> _MoverParametersBase:
        try:
            self.build(MoverVector())
        except ConfigError as exc:  # "default_dynamic_xy.velocity: must be > 0 ..."
            match = re.match(r"^([a-z_]+)(?:\.([a-z_]+))?: (.*)$", str(exc), re.S)
            if match is None:
                raise ValueError(str(exc)) from None
            _raise(self, [(tuple(filter(None, match.groups()[:2])), match.group(3))])
        return self

    def build(self, initial_position: MoverVector, part_oid: int = 0) -> PlanarMoverParameters:
        values = {}
        for name in self.model_fields_set:
            value = getattr(self, name)
            values[name] = value.over(_DEFAULTS[name]) if isinstance(value, _Partial) else value
        return PlanarMoverParameters(**values, initial_position=initial_position,
                                     part_oid=part_oid)


_DEFAULTS = {f.name: f.default for f in fields(PlanarMoverParameters)}
_HINTS = get_type_hints(PlanarMoverParameters)
_SPEC_TYPES: dict[Any, Any] = {float: Number, bool: StrictBool, Limits: LimitsSpec | None,
                               MoverVector: VectorSpec | None}
#: the init parameters a scenario sets (§6.1.1); the start is the mover's part, x, y, c
_SCENARIO_PARAMETERS = [f.name for f in fields(PlanarMoverParameters)
                        if f.name not in ("initial_position", "part_oid", "simulation_mode")]
PlanarMoverParametersSpec = create_model(
    "PlanarMoverParametersSpec",
    __base__=_MoverParametersBase,
    __doc__="Fields of PlanarMoverParameters (planar/options.py, TF5430 §6.1.1), same names and "
            "units: mover_width, mover_height [mm], default_dynamic_xy / maximum_dynamic_xy "
            "(and _c, _z, _a, _b) as {velocity, acceleration, deceleration, jerk}, ...",
    **{name: (_SPEC_TYPES[_HINTS[name]], None if _HINTS[name] in (Limits, MoverVector)
              else _DEFAULTS[name]) for name in _SCENARIO_PARAMETERS},
)


class PlanarMoverSpec(_Model):
    """One MC_PlanarMover (§6.1): where it stands at the start and its init parameters."""

    name: Annotated[Identifier, _unique("planar_movers"), _own_name("axes", "groups")]
    """Unique, not an axis or CA group name; entries, signals and conditions refer to it."""
    part: ObjectId | None = None
    """The part it starts on (PlanarMoverParameters.part_oid, §6.1.1); x, y and c are then
    in the part frame. Needed when planar.environment has several coordinate systems."""
    x: Number = 0.0
    """Start position [mm]."""
    y: Number = 0.0
    """Start position [mm]."""
    c: Number = 0.0
    """Start orientation [°]."""
    parameters: PlanarMoverParametersSpec = PlanarMoverParametersSpec()  # type: ignore[valid-type]
    """PlanarMoverParameters fields to set (the rest keep their defaults)."""
    enable: StrictBool = True
    """Enable the mover in the setup; false: a ``mover_enable`` entry does it."""

    blocks = ("MC_PlanarMover.enable", "MC_PlanarMover.update")  #: setup; every cycle

    def build(self) -> PlanarMoverParameters:
        return self.parameters.build(MoverVector(self.x, self.y, c=self.c), self.part or 0)


# -- planar.groups -------------------------------------------------------------------------


class PlanarGroupSpec(_Model):
    """One MC_PlanarGroup (§6.3): its members avoid each other (and the surface's edge)."""

    name: Annotated[Identifier, _unique("planar_groups"),
                    _own_name("axes", "groups", "planar_movers")]
    """Unique, not the name of an axis, a CA group or a planar mover."""
    movers: list[Annotated[StrictStr, AfterValidator(_check_planar_mover)]] | None = None
    """Members, added in this order; default: every mover."""
    environment: StrictBool | None = None
    """The environment is a member (no mover leaves the stators); default: true when
    planar.environment is given and the group has ``enable``."""
    tracks: list[TrackName] | None = None
    """Track members, added after the movers; default: every track when the group has
    ``enable`` (a mover in a group moves only on tracks of its group, §4.3)."""
    blocks = ("MC_PlanarGroup.enable", "MC_PlanarGroup.update", "MC_PlanarMover.add_to_group",
              "MC_PlanarEnvironment.add_to_group", "MC_PlanarTrack.add_to_group")  #: setup
    enable: StrictBool = True
    """Enable the group and add its members in the setup; false: the timeline does it
    (planar_group_enable, then add_to_group for each mover; the environment and tracks cannot
    join)."""


class PlanarSpec(_Model):
    """The planar machine of a scenario: stators, movers and groups (TF5430)."""

    environment: EnvironmentSpec | None = None
    """The stator surface; without it movers go anywhere."""
    movers: Annotated[list[PlanarMoverSpec], Field(min_length=1)]
    """The movers, created in this order (OIDs 16#05110010, 16#05110020, ...)."""
    groups: list[PlanarGroupSpec] = []
    """Planar groups, created in this order."""
    tracks: list[TrackSpec] = []
    """Planar tracks (§6.2), created in this order after the groups (planar_tracks.py)."""
    stations: list[PlanarStationSpec] = []
    """Stations on the tracks (scenario/stations.py); routes send movers round them."""
    routes: list[PlanarRouteSpec] = []
    """The stations movers visit, in order, by MoveOnTrack (scenario/stations.py)."""
    router: RouterSpec | None = None
    """The options of the router that ``route`` entries use (planar_routing.py); default:
    its defaults on the only planar group."""

    #: the run hands each planar command an MC_PlanarFeedback, which the object updates
    blocks = ("MC_PlanarFeedback.update", "MC_PlanarFeedbackBase.update")

    @model_validator(mode="after")
    def _sets_up(self) -> PlanarSpec:
        """Memberships first; then the setup on a scratch runtime, each failure at its field."""
        from openmotion.scenario.planar_machine import PlanarMachine  # it builds on the specs

        problems = [*self._membership_problems(), *self._track_membership_problems(),
                    *self._part_problems(), *order_problems(self.tracks),
                    *planar_station_problems(self.stations, self.routes,
                                             [mover.name for mover in self.movers],
                                             [track.name for track in self.tracks]),
                    *router_problems(self)]
        if not problems:
            problems = PlanarMachine(Runtime(), self).set_up()
        _raise(self, problems)
        return self

    def members(self, index: int) -> list[tuple[Loc, str]]:
        """(field path, mover) of each mover group ``index`` lists, in order."""
        group = self.groups[index]
        if group.movers is None:
            return [(("movers", k), mover.name) for k, mover in enumerate(self.movers)]
        return [(("groups", index, "movers", k), name) for k, name in enumerate(group.movers)]

    def track_members(self, index: int) -> list[tuple[Loc, str]]:
        """(field path, track) of each track group ``index`` takes in the setup, in order."""
        group = self.groups[index]
        if group.tracks is None:
            return [(("tracks", k), track.name) for k, track in enumerate(self.tracks)] \
                if group.enable else []
        return [(("groups", index, "tracks", k), name) for k, name in enumerate(group.tracks)]

    def has_environment(self, index: int) -> bool:
        group = self.groups[index]
        default = self.environment is not None and self.environment.is_static and group.enable
        return default if group.environment is None else group.environment

    def _membership_problems(self) -> Iterator[tuple[Loc, str]]:
        seen: dict[str, str] = {}  # mover -> its group
        environment = ""
        for index, group in enumerate(self.groups):
            for loc, name in self.members(index):
                if name in seen:
                    yield ("groups", index) if group.movers is None else loc, \
                        f"{name!r} is in group {seen[name]!r} already: a mover joins one " \
                        "group (list each group's movers)"
                    break
                seen[name] = group.name
            if not self.has_environment(index):
                continue
            loc = ("groups", index, "environment")
            if self.environment is None:
                yield loc, "there is no planar.environment"
            elif not group.enable:
                yield loc, "the environment joins in the setup, which needs enable: true"
            elif not self.environment.is_static:
                yield loc, "its boundary would not follow the parts: with movable parts or " \
                           "several coordinate systems the environment joins no group (D-088)"
            elif environment:
                yield loc, f"the environment is in group {environment!r} already: set " \
                           "environment: false"
            environment = environment or group.name

    def _track_membership_problems(self) -> Iterator[tuple[Loc, str]]:
        seen: dict[str, str] = {}  # track -> its group
        for index, group in enumerate(self.groups):
            if group.tracks and not group.enable:
                yield ("groups", index, "tracks"), "tracks join in the setup, which needs " \
                                                   "enable: true"
                continue
            for loc, name in self.track_members(index):
                if name in seen:
                    yield ("groups", index) if group.tracks is None else loc, \
                        f"track {name!r} is in group {seen[name]!r} already: a track joins " \
                        "one group (list each group's tracks)"
                    break
                seen[name] = group.name

    def _part_problems(self) -> Iterator[tuple[Loc, str]]:
        """A mover's ``part`` names a part; with several coordinate systems each has one."""
        environment = self.environment
        parts = environment.part_oids() if environment is not None else []
        systems = len(environment.coordinate_systems or []) if environment is not None else 0
        for index, mover in enumerate(self.movers):
            if mover.part is not None and mover.part not in parts:
                known = ", ".join(map(oid_text, parts))
                yield ("movers", index, "part"), \
                    f"{oid_text(mover.part)} is no part of planar.environment.parts " \
                    f"(parts: {known})" if parts else "planar.environment has no parts"
            elif mover.part is None and systems > 1:
                yield ("movers", index), f"give the 'part' it starts on: with {systems} " \
                                         "coordinate systems x and y alone are no place (§5.1)"


def _raise(model: _Model, problems: Iterable[tuple[Loc, str]]) -> None:
    """Raise the problems as one ValidationError, each at its field path."""
    found = list(problems)
    if found:
        raise ValidationError.from_exception_data(type(model).__name__, [
            InitErrorDetails(type=PydanticCustomError("value_error", message), loc=loc,
                             input=None) for loc, message in found])


# -- timeline entries ----------------------------------------------------------------------


class PlanarEntry(_Timed):
    """A command for one planar mover: the run calls the MC_PlanarMover method ``method``."""

    mover: Annotated[StrictStr, AfterValidator(_check_planar_mover)]
    """Name of the mover (one of planar.movers)."""

    @property
    def axis(self) -> str:
        """The mover's name, for the summary's axis column."""
        return self.mover

    def arguments(self) -> tuple[Any, ...]:
        """The method's arguments after the feedback (the run passes none: PLC 0)."""
        return ()


class _Constrained(PlanarEntry):
    velocity: InputValue = MC_DEFAULT
    """DynamicConstraint_PathXY V [mm/s or °/s]; MC_DEFAULT = the mover's default dynamics,
    MC_IGNORE = its maximum; above the maximum: clipped, with a warning."""
    acceleration: InputValue = MC_DEFAULT
    """A [mm/s² or °/s²]."""
    deceleration: InputValue = MC_DEFAULT
    """D [mm/s² or °/s²]."""
    jerk: InputValue = MC_DEFAULT
    """J [mm/s³ or °/s³]."""

    def constraint(self) -> DynamicConstraint_PathXY | None:
        """None (PLC 0: the default dynamics) unless a limit is given."""
        given = {"velocity", "acceleration", "deceleration", "jerk"} & self.model_fields_set
        return DynamicConstraint_PathXY(self.velocity, self.acceleration, self.deceleration,
                                        self.jerk) if given else None


class _Target(_Constrained):
    """An entry with a target position x, y, c in the frame of ``reference_id``."""

    x: Number
    """Target [mm]."""
    y: Number
    """Target [mm]."""
    c: Number | None = None
    """Target orientation [°]."""
    use_orientation: StrictBool | None = None
    """The options' UseOrientation: also reach ``c``; default: true when c is given."""
    reference_id: ReferenceId = 0
    """The frame of x, y, c (§5.3): a part (the target must lie on it), a coordinate system,
    or 0 (no parts, or one static coordinate system). A wrong one fails the command."""

    @model_validator(mode="after")
    def _orientation_needs_c(self) -> _Target:
        if self.use_orientation and self.c is None:
            raise ValueError("use_orientation: true needs c")
        return self

    def target(self) -> PositionXYC:
        return PositionXYC(self.x, self.y, self.c or 0.0, self.reference_id)

    @property
    def orientation(self) -> bool:
        """``use_orientation`` as given; default: whether c is given."""
        return self.c is not None if self.use_orientation is None else self.use_orientation


class MoveToPosition(_Target):
    """MoveToPosition (§7.2.2.8.1): a straight move to (x, y), and to c with orientation."""

    method = "move_to_position"
    command: Literal["move_to_position"]

    def arguments(self) -> tuple[Any, ...]:
        return (self.target(), self.constraint(),
                ST_MoveToPositionOptions(use_orientation=self.orientation))


class MoveC(_Constrained):
    """MoveC (§7.2.2.8.10): rotate to ``position``; X and Y lock while C is outside the
    C windows (CRotationFreeMovement, §4.2)."""

    method = "move_c"
    command: Literal["move_c"]
    position: Number
    """Target orientation [°]."""
    direction: ModuloDirectionName = ModuloDirection.NON_MODULO  # type: ignore[valid-type]
    """ST_MoveCOptions: non_modulo, positive, shortest_way or negative."""
    additional_turns: StrictInt = 0
    """Whole extra turns of a positive or negative modulo move."""

    def arguments(self) -> tuple[Any, ...]:
        return (self.position, self.constraint(),
                ST_MoveCOptions(self.additional_turns, self.direction))


class _MoveAxis(_Constrained):
    position: Number
    """Target [mm for z, ° for a and b]."""

    def arguments(self) -> tuple[Any, ...]:
        return (self.position, self.constraint())


class MoveZ(_MoveAxis):
    """MoveZ (§7.2.2.8.7): lift or lower the mover."""

    method = "move_z"
    command: Literal["move_z"]


class MoveA(_MoveAxis):
    """MoveA (§7.2.2.8.8): tilt about x."""

    method = "move_a"
    command: Literal["move_a"]


class MoveB(_MoveAxis):
    """MoveB (§7.2.2.8.9): tilt about y."""

    method = "move_b"
    command: Literal["move_b"]


class MoverHalt(_Constrained):
    """Halt (§7.2.2.8.12): brake every coordinate to rest; the limits apply to x and y."""

    method = "halt"
    command: Literal["mover_halt"]

    def arguments(self) -> tuple[Any, ...]:
        return (self.constraint(),)


class AdoptTrackOrientation(_Constrained):
    """AdoptTrackOrientation (§6.2.7, §7.2.1.2.4): a standing mover on a track turns to the
    track's heading; C then follows the track again."""

    method = "adopt_track_orientation"
    command: Literal["adopt_track_orientation"]
    direction: ModuloDirectionName = ModuloDirection.SHORTEST_WAY  # type: ignore[valid-type]
    """ST_AdoptTrackOrientationOptions: shortest_way (its default), positive or negative."""
    additional_turns: StrictInt = 0
    """Whole extra turns of a positive or negative turn."""

    def arguments(self) -> tuple[Any, ...]:
        return (self.constraint(),
                ST_AdoptTrackOrientationOptions(self.additional_turns, self.direction))


class MoverEnable(PlanarEntry):
    """Enable (§7.2.2.8.13): Disabled -> Enabling -> Enabled."""

    method = "enable"
    command: Literal["mover_enable"]


class MoverDisable(PlanarEntry):
    """Disable (§7.2.2.8.14): a moving mover brakes with its maximum dynamics."""

    method = "disable"
    command: Literal["mover_disable"]


class MoverReset(PlanarEntry):
    """Reset (§7.2.2.8.15): clear an error."""

    method = "reset"
    command: Literal["mover_reset"]


class SetPosition(PlanarEntry):
    """SetPosition (§7.2.2.8.17): overwrite x, y and c; only while Disabled."""

    method = "set_position"
    command: Literal["set_position"]
    x: Number
    """[mm]."""
    y: Number
    """[mm]."""
    c: Number = 0.0
    """[°]."""
    reference_id: ReferenceId = 0
    """The frame of x, y, c, as move_to_position's."""

    def arguments(self) -> tuple[Any, ...]:
        return (PositionXYC(self.x, self.y, self.c, self.reference_id),)


class AddToGroup(PlanarEntry):
    """AddToGroup (§7.2.2.8.22): join ``group``; refused when the footprint meets an area
    the group holds."""

    method = "add_to_group"
    command: Literal["add_to_group"]
    group: Annotated[StrictStr, AfterValidator(_check_planar_group)]
    """Name of the planar group."""

    def arguments(self) -> tuple[Any, ...]:
        return (self.group,)  # the run passes the group of that name


class RemoveFromGroup(PlanarEntry):
    """RemoveFromGroup (§7.2.2.8.23): leave the group; collision avoidance is off."""

    method = "remove_from_group"
    command: Literal["remove_from_group"]


class PlanarGroupEntry(_Timed):
    """A command for a planar group (§7.2.2.7)."""

    group: Annotated[StrictStr, AfterValidator(_check_planar_group)]
    """Name of the planar group."""

    @property
    def axis(self) -> str:
        """The group's name, for the summary's axis column."""
        return self.group

    def arguments(self) -> tuple[Any, ...]:
        return ()


class PlanarGroupEnable(PlanarGroupEntry):
    """Enable (§7.2.2.7.1): members may join once the group is Enabled."""

    method = "enable"
    command: Literal["planar_group_enable"]


class PlanarGroupDisable(PlanarGroupEntry):
    """Disable (§7.2.2.7.2): the members' motion commands are refused meanwhile."""

    method = "disable"
    command: Literal["planar_group_disable"]


class PlanarGroupReset(PlanarGroupEntry):
    """Reset (§7.2.2.7.3)."""

    method = "reset"
    command: Literal["planar_group_reset"]


# Parts (§6.6) and external setpoints (§6.1.6): the latter build on PlanarEntry above.
from openmotion.scenario.planar_gearing import (  # noqa: E402
    GearInPosOnTrack,
    GearInPosOnTrackWithMasterMover,
)
from openmotion.scenario.planar_objects import OBJECT_ENTRIES  # noqa: E402
from openmotion.scenario.planar_parts import PART_ENTRIES  # noqa: E402
from openmotion.scenario.planar_riding import JoinTrack, LeaveTrack, MoveOnTrack  # noqa: E402
from openmotion.scenario.planar_setpoints import (  # noqa: E402
    StartExternalSetpointGeneration,
    StopExternalSetpointGeneration,
)

PLANAR_ENTRIES: tuple[type, ...] = (
    MoveToPosition, MoveC, MoveZ, MoveA, MoveB, MoverHalt, MoverEnable, MoverDisable,
    MoverReset, SetPosition, AddToGroup, RemoveFromGroup, StartExternalSetpointGeneration,
    StopExternalSetpointGeneration, PlanarGroupEnable, PlanarGroupDisable, PlanarGroupReset,
    *PART_ENTRIES, JoinTrack, LeaveTrack, MoveOnTrack, GearInPosOnTrack,
    GearInPosOnTrackWithMasterMover, AdoptTrackOrientation, *OBJECT_ENTRIES)
#: the planar entries by their ``command`` (schema.TIMELINE_COMMANDS holds them all)
PLANAR_COMMANDS: dict[str, type] = {
    get_args(model.model_fields["command"].annotation)[0]: model for model in PLANAR_ENTRIES}

