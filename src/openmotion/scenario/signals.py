"""The signals a scenario records, checks and waits on: the machine model's, and no others.

A scenario names a signal ``<object>.<signal>``, as the trace and the model do. Which signals
an object has is what its kind declares (``MACHINE``, kernel/model.py, D-226); this module
keeps no list of its own (D-234). While a file validates, each name is an object the file
declares, and the section that declares it gives its kind (``SECTIONS``): an axis, a CA group,
an axes group, a planar mover, group or track, a station; a planar part by the model's name of it,
``part 16#00010001``. While it runs, ``RunSignals`` finds the same names in the model of the
runtime. A CA mover's signals (``gap`` ...) are named on its axis, as the trace names them
(D-227).

What a scenario may compare a signal with follows from the signal's type: a number, or for
an enumeration the name of a member (``standstill``, ``error_stop``, ``STEPPER_STALL``). Two
planar mover signals number objects, and take their names too: ``track`` (a track of the
file, or ``none``) and ``coordinate_system`` (an OID, ``16#...``).

Not signals, and kept apart: a timeline entry's command outputs in conditions
(``<id>.done`` ..., schema.COMMAND_FLAGS: the command handle's), and the outputs of query
entries (queries.py).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING, Any

from openmotion.axis.kind import AXIS
from openmotion.coordinated.kind import AXES_GROUP
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.kernel.model import Kind, MachineObject, Signal, SignalSpec, machine
from openmotion.planar.kind import PLANAR_GROUP, PLANAR_MOVER, PLANAR_PART, PLANAR_TRACK
from openmotion.rail.stations import StationState
from openmotion.transport.kind import CA_GROUP, CA_MOVER

if TYPE_CHECKING:
    from openmotion.kernel.runtime import CyclicRuntime

__all__ = ["AXIS_CHOICES", "SECTIONS", "SUBJECT", "RunSignals", "Section", "check_axis",
           "check_mover", "check_signal", "declared",
           "default_signals", "expect_hint", "part_name", "scenario_signals", "signal_text",
           "spec_of", "value_of_name"]

#: what a scenario may name on an axis: its own signals, then a CA mover's (D-227), which
#: only an axis in a CA group has
AXIS_CHOICES = AXIS.signal_names + CA_MOVER.signal_names
_SUBJECT = r"[A-Za-z_][A-Za-z0-9_]*|part 16#[0-9A-F]{8}"
SUBJECT = re.compile(rf"^(?:{_SUBJECT})$")  #: an object name a signal name may start with
_SIGNAL = re.compile(rf"^({_SUBJECT})\.([a-z_]+)$")
_PART = re.compile(r"^part 16#([0-9A-F]{8})$")
#: the planar mover signals that number objects: a track, a coordinate system (an OID)
_TRACK, _COORDINATES = PLANAR_MOVER.signal("track"), PLANAR_MOVER.signal("coordinate_system")


@dataclass(frozen=True)
class Section:
    """Objects of one kind a scenario declares: the validation names that list them (a
    field of schema's ``_Names``) and what messages call one."""

    names: str
    what: str
    kind: Kind


#: every kind of object a scenario declares besides axes and planar parts, in the order a
#: name is looked up after the axes
SECTIONS = (
    Section("groups", "a CA group", CA_GROUP),
    Section("axes_groups", "an axes group", AXES_GROUP),
    Section("planar_movers", "a planar mover", PLANAR_MOVER),
    Section("planar_groups", "a planar group", PLANAR_GROUP),
    Section("planar_tracks", "a planar track", PLANAR_TRACK),
    Section("stations", "a station", StationState.MACHINE),  # type: ignore[attr-defined]
)
_PARTS = Section("planar_parts", "a planar part", PLANAR_PART)
#: which object a name means where objects of several kinds share it: the one validation
#: takes it for (an axis first, with the CA mover it is; then SECTIONS' order)
_PRECEDENCE = (AXIS.name, CA_MOVER.name, *(section.kind.name for section in SECTIONS),
               PLANAR_PART.name)


def part_name(oid: int) -> str:
    """A planar part's name in the model (and in signal names): ``part 16#00010001``."""
    return f"part {_oid_text(oid)}"


def _oid_text(oid: int) -> str:
    from openmotion.scenario.planar_parts import oid_text  # it imports the schema

    return oid_text(oid)


def _is_axis(subject: str, names: Any) -> bool:
    return names is None or subject in names.axes


def _is_mover(subject: str, names: Any) -> bool:
    """An axis that one of the ca_groups lists, or that an add_axis_to_group entry adds."""
    return names is None or subject in names.members or subject in names.added


def declared(subject: str, names: Any) -> Section | None:
    """The section of the file being validated (``names``) that declares ``subject``; None
    for an axis (or a name the file does not declare: it is taken for an axis, whose checks
    name the axes)."""
    if names is None or subject in names.axes:
        return None
    for section in SECTIONS:
        if subject in getattr(names, section.names):
            return section
    match = _PART.match(subject)
    if match is not None and int(match.group(1), 16) in names.planar_parts:
        return _PARTS
    return None


def _kinds(subject: str, names: Any) -> tuple[Kind, ...]:
    """The kinds whose signals ``subject`` shows: an axis's and, for a CA mover, a mover's."""
    section = declared(subject, names)
    if section is not None:
        return (section.kind,)
    return (AXIS, CA_MOVER) if _is_mover(subject, names) else (AXIS,)


def scenario_signals(names: Any) -> dict[str, tuple[str, ...]]:
    """Every object the file declares, with the signals a scenario may name of it: what
    ``check_signal`` accepts, object by object."""
    objects = [*names.axes, *(name for section in SECTIONS
                              for name in getattr(names, section.names)),
               *(part_name(oid) for oid in sorted(names.planar_parts))]
    return {name: tuple(prop for kind in _kinds(name, names) for prop in kind.signal_names)
            for name in dict.fromkeys(objects)}


def check_signal(name: str, names: Any) -> str:
    """``<object>.<signal>`` with a signal the object's kind declares; ValueError naming the
    choices otherwise (or the axes, or the CA groups, for an axis that has none of them)."""
    match = _SIGNAL.match(name)
    subject, prop = match.groups() if match is not None else (name.partition(".")[0], "")
    section = declared(subject, names)
    if section is not None:
        if prop not in section.kind.signal_names:
            raise ValueError(f"{name!r}: {section.what}'s signal is one of "
                             f"{', '.join(section.kind.signal_names)}")
        return name
    if names is not None and _PART.match(subject):
        known = ", ".join(part_name(oid) for oid in sorted(names.planar_parts)) or "none"
        raise ValueError(f"unknown planar part {subject!r} (planar.environment.parts: {known})")
    if match is None or prop not in AXIS_CHOICES:
        raise ValueError(f"{name!r} is not '<axis>.<signal>' with a signal among "
                         f"{', '.join(AXIS_CHOICES)}")
    if prop in CA_MOVER.signal_names:
        check_mover(subject, names)
    else:
        check_axis(subject, names)
    return name


def check_axis(name: str, names: Any) -> None:
    """ValueError naming the axes when ``name`` is none of them."""
    if not _is_axis(name, names):
        known = ", ".join(sorted(names.axes)) or "none"
        raise ValueError(f"unknown axis {name!r} (axes: {known})")


def check_mover(name: str, names: Any) -> None:
    """ValueError unless ``name`` is an axis that is or becomes a CA mover (``_is_mover``)."""
    check_axis(name, names)
    if not _is_mover(name, names):
        raise ValueError(f"{name!r} is in no CA group (ca_groups[].axes)")


def spec_of(name: str, names: Any) -> SignalSpec:
    """The declaration of a signal ``check_signal`` accepted."""
    subject, _, prop = name.partition(".")
    for kind in _kinds(subject, names):
        if prop in kind.signal_names:
            return kind.signal(prop)
    raise ValueError(f"{name!r}: no such signal")  # check_signal refused it already


def _enum(spec: SignalSpec) -> type[Enum] | None:
    dtype = spec.dtype
    return dtype if isinstance(dtype, type) and issubclass(dtype, Enum) else None


def _track(name: str, names: Any) -> float | None:
    """The ``track`` signal's value for the track ``name`` (its 1-based place in
    planar.tracks, as the runtime numbers tracks in the order they are made); ``none``: 0."""
    if name == "none":
        return 0.0
    if names is None or name not in names.planar_tracks:
        return None
    return float(list(names.planar_tracks).index(name) + 1)


def _oid(name: str, names: Any) -> float | None:
    """The OID of ``16#...`` text."""
    from openmotion.scenario.planar_parts import parse_oid  # it imports the schema

    oid = parse_oid(name) if name.startswith("16#") else None
    return None if oid is None else float(oid)


#: names a signal that numbers objects takes: its declaration -> the number of a name
_OBJECT_NUMBERS: dict[int, Callable[[str, Any], float | None]] = {
    id(_TRACK): _track, id(_COORDINATES): _oid}


def value_of_name(spec: SignalSpec, name: str, names: Any) -> float | None:
    """The number behind ``name`` for one signal: a member of its enumeration (any case),
    or the object a numbering signal names; None when ``name`` is none of them."""
    enum = _enum(spec)
    if enum is not None and name.upper() in enum.__members__:
        return float(enum[name.upper()].value)
    numbered = _OBJECT_NUMBERS.get(id(spec))
    return None if numbered is None else numbered(name, names)


#: what a check's message calls a name of each enumeration's members
_ENUM_NAMES = {"AxisState": "a state name", "PlanarState": "a planar state name",
               "AxesGroupState": "an axes group state name", "ErrorId": "an ErrorId name",
               "GroupState": "a CA group state name"}


def expect_hint(spec: SignalSpec) -> str:
    """What else than a number a check may expect of the signal (`` or a state name``)."""
    if spec is _TRACK:
        return " or a planar track name"
    enum = _enum(spec)
    if enum is None:
        return ""
    return " or " + _ENUM_NAMES.get(enum.__name__, f"a {enum.__name__} name")


def default_signals(kind: Kind, objects: Iterable[str]) -> list[str]:
    """What a scenario records of ``objects`` of ``kind`` when it names no signals: the
    signals the kind marks ``default``."""
    props = [spec.name for spec in kind.signals if spec.default]
    return [f"{name}.{prop}" for name in objects for prop in props]


# -- while a scenario runs ---------------------------------------------------------------------


class RunSignals:
    """The signals of a running scenario by name: the model's ``Signal`` of the object of that
    name, looked up once (the model is taken again when a name is not in it yet)."""

    def __init__(self, runtime: CyclicRuntime, track_names: Callable[[], list[str]]) -> None:
        self.runtime = runtime
        self._track_names = track_names  #: the planar tracks, numbered as ``track`` numbers
        self._objects: dict[str, list[MachineObject]] | None = None
        self._signals: dict[str, Signal] = {}

    def signal(self, name: str) -> Signal:
        found = self._signals.get(name)
        if found is None:
            found = self._signals[name] = self._find(name)
        return found

    def read(self, name: str) -> float:
        return self.signal(name).read()

    def _find(self, name: str) -> Signal:
        subject, _, prop = name.partition(".")
        for fresh in (False, True):
            objects = self._named(fresh).get(subject, [])
            for obj in objects:
                for signal in obj.signals:
                    if signal.name == prop:
                        return signal
            axis = next((obj.target for obj in objects if obj.kind == AXIS.name), None)
            if axis is not None and prop in CA_MOVER.signal_names:
                # an axis that joins its CA group later: its mover's signals read NaN till
                # then, named on the axis (D-227)
                return CA_MOVER.signal(prop).bind(axis)
        raise ConfigError(f"{name!r}: no such signal in the machine model")

    def _named(self, fresh: bool) -> dict[str, list[MachineObject]]:
        if self._objects is None or fresh:
            self._objects = {}
            for obj in machine(self.runtime):
                self._objects.setdefault(obj.name, []).append(obj)
            for objects in self._objects.values():
                objects.sort(key=lambda obj: _PRECEDENCE.index(obj.kind)
                             if obj.kind in _PRECEDENCE else len(_PRECEDENCE))
        return self._objects

    def reading(self, name: str) -> tuple[float, str, bool]:
        """(value, its text, whether the text is a name) of one signal now."""
        signal = self.signal(name)
        value = signal.read()
        return (value, *signal_text(signal, value, self._track_names))


def signal_text(signal: Signal, value: float, track_names: Callable[[], list[str]]) \
        -> tuple[str, bool]:
    """How a check shows a value: a member's name for an enumeration (a state in lower case,
    an ErrorId as written), a track or an OID for the signals that number them; else ""."""
    enum = _enum(signal.spec)
    if enum is not None and math.isfinite(value):
        try:
            member = enum(int(value))
        except ValueError:
            return "", False
        return (member.name if enum is ErrorId else member.name.lower()), True
    if signal.spec is _TRACK:
        names = track_names()
        number = int(value) if math.isfinite(value) else 0
        return (names[number - 1] if 1 <= number <= len(names) else "none"), True
    if signal.spec is _COORDINATES and math.isfinite(value):
        return _oid_text(int(value)), True
    return "", False
