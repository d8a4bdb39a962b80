"""The machine model: every object of a runtime with its signals and its commands.

One description, read by every edge that shows or drives the machine (trace, viewer, and the
endpoints to come), so that a new signal or command is declared once, next to its object
(docs/architecture.md "The machine model", D-226).

Each kind of object declares a ``Kind`` as the class attribute ``MACHINE``, in its own
package: its signals (``SignalSpec``: how to read one signal of any object of the kind) and
how to find its commands (public methods that return the kind's command handle; their inputs
come from the method signatures, ``derive_commands``). ``machine(runtime)`` walks the
runtime's systems and binds the declarations to the live objects: ``MachineObject`` with
``Signal`` and ``CommandSpec`` entries.

This module is the kernel's: it imports no system package (axis, plcopen, transport,
coordinated, planar); it finds the objects through the System contract (``runtime.systems``,
each system's ``objects()``) and their kinds through the objects themselves.
"""

from __future__ import annotations

import difflib
import inspect
import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.core.errors import ConfigError

if TYPE_CHECKING:
    from openmotion.kernel.runtime import CyclicRuntime

__all__ = ["REQUIRED", "UNITS", "CommandSpec", "Input", "Kind", "MachineModel",
           "MachineObject", "Signal", "SignalSpec", "compact_index", "derive_commands",
           "kind_of", "machine"]

Reader = Callable[[], float]
BulkReader = Callable[[], np.ndarray]

#: the unit of a command input by its name: one name per quantity across the package (style
#: guide), so the name says the unit; a kind overrides it where its quantity differs [° ...]
UNITS: Mapping[str, str] = {
    "position": "mm", "distance": "mm", "target_position": "mm", "actual_position": "mm",
    "velocity": "mm/s", "velocity_diff": "mm/s", "acceleration": "mm/s²",
    "deceleration": "mm/s²", "jerk": "mm/s³", "gap": "mm", "percent": "%",
}


class _Required:
    """The default of an input the caller must give."""

    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED: Any = _Required()  #: ``Input.default`` of an input without a default


@dataclass(frozen=True)
class SignalSpec:
    """One signal of every object of a kind, declared once next to the kind's class.

    The value is a float, as a trace records it: an enum is its number, a bool 0 or 1, NaN
    where the object cannot show it now. ``dtype`` says what the float encodes.
    """

    name: str
    unit: str  #: "" for a number without unit (a state, a count)
    dtype: type  #: float, bool, int or the IntEnum whose number the value is
    read: Callable[[Any], float]  #: the value of one object now
    doc: str = ""
    #: a live scope offers it (the viewer): what one watches while the machine runs
    scope: bool = False
    default: bool = False  #: recorded when a scenario names no signals
    actual: str = ""  #: the signal that measures what this setpoint asks for
    #: reads all given objects at once (one numpy gather), or None: one ``read`` per object
    bulk: Callable[[Sequence[Any]], BulkReader] | None = field(default=None, compare=False)

    def bind(self, obj: Any) -> Signal:
        read = self.read
        return Signal(self.name, self.unit, self.dtype, lambda: read(obj), self)


@dataclass(frozen=True)
class Signal:
    """One signal of one object: read it once per cycle (after the cycle, as a trace
    samples), and it gives the value the trace records."""

    name: str
    unit: str
    dtype: type
    read: Reader = field(compare=False)
    spec: SignalSpec = field(repr=False, compare=False)  #: its declaration (doc, bulk ...)

    @property
    def scope(self) -> bool:
        return self.spec.scope


@dataclass(frozen=True)
class Input:
    """One input of a command, from the signature of the method that starts it."""

    name: str
    dtype: str  #: the annotation as written ("InputValue", "BufferMode", "Axis" ...)
    unit: str = ""
    default: Any = REQUIRED
    choices: tuple[str, ...] = ()  #: the enum members' names, for an enum input
    range: tuple[float, float] | None = None  #: closed bounds where the kind knows them

    @property
    def required(self) -> bool:
        return self.default is REQUIRED


@dataclass(frozen=True)
class CommandSpec:
    """One command: its name (the method an FB calls), its inputs and how to start it.

    Unbound (``start`` is None) in a ``Kind``; bound to an object in a ``MachineObject``,
    where ``start(**inputs)`` issues it and returns the command handle (``Command``,
    ``PlanarCommand``) that follows the FB handshake.
    """

    name: str
    inputs: tuple[Input, ...]
    doc: str = ""
    start: Callable[..., Any] | None = field(default=None, compare=False, repr=False)
    #: a level, not an edge: the method sets a state and returns its status at once (MC_Power's
    #: Enable and Status); no command handle follows it
    level: bool = False

    def bind(self, obj: Any) -> CommandSpec:
        method = getattr(obj, self.name)
        names = [put.name for put in self.inputs]

        def start(**inputs: Any) -> Any:
            unknown = sorted(set(inputs).difference(names))
            if unknown:
                raise TypeError(_unknown(f"{self.name} has no input", unknown[0], names))
            return method(**inputs)

        return CommandSpec(self.name, self.inputs, self.doc, start, self.level)


@dataclass(frozen=True)
class Kind:
    """What every object of one class shows: declared as the class attribute ``MACHINE``.

    Its commands are derived from the class: the public methods that return one of
    ``handles`` (``derive_commands``). ``identify`` gives the object's id (an OID where the
    manual has one), ``parent`` the name of the object it belongs to ("" for none),
    ``children`` the objects it holds that its system does not list itself (a CA group's
    movers, an environment's parts).
    """

    name: str  #: the kind: "axis", "ca_group", "planar_mover" ...
    signals: tuple[SignalSpec, ...] = ()
    handles: tuple[str, ...] = ()  #: the command handle types its command methods return
    #: methods that set a level and return its status (``CommandSpec.level``): MC_Power
    levels: tuple[str, ...] = ()
    #: units of command inputs where ``UNITS`` does not fit: by input or "<command>.<input>"
    units: Mapping[str, str] = field(default_factory=dict, compare=False)
    identify: Callable[[Any], int] = field(default=lambda obj: int(obj.oid), compare=False)
    parent: Callable[[Any], str] = field(default=lambda obj: "", compare=False)
    children: Callable[[Any], Iterable[Any]] = field(default=lambda obj: (), compare=False)
    label: Callable[[Any], str] = field(default=lambda obj: str(obj.name), compare=False)
    #: what its signals read: the object itself, or (a CA mover) the axis it is
    subject: Callable[[Any], Any] = field(default=lambda obj: obj, compare=False)

    def __post_init__(self) -> None:
        names = [spec.name for spec in self.signals]
        if len(set(names)) != len(names):
            raise ConfigError(f"kind {self.name!r}: a signal is declared twice in {names}")

    @property
    def signal_names(self) -> tuple[str, ...]:
        return tuple(spec.name for spec in self.signals)

    def signal(self, name: str) -> SignalSpec:
        """The declaration of one signal; ``ConfigError`` naming the choices otherwise."""
        for spec in self.signals:
            if spec.name == name:
                return spec
        raise ConfigError(_unknown(f"{self.name}: no signal", name, self.signal_names))

    def commands(self, cls: type) -> tuple[CommandSpec, ...]:
        """The commands of objects of ``cls`` (derived once per class)."""
        key = (cls, self.name)
        found = _COMMANDS.get(key)
        if found is None:
            found = _COMMANDS[key] = derive_commands(cls, self.handles, self.units, self.levels)
        return found

    def describe(self, obj: Any, parent: str = "") -> MachineObject:
        """``obj`` as the model shows it, its signals and commands bound to it; ``parent``
        names the object that holds it when its kind does not say."""
        subject = self.subject(obj)
        return MachineObject(
            self.name, self.label(obj), self.identify(obj), self.parent(obj) or parent,
            tuple(spec.bind(subject) for spec in self.signals),
            tuple(command.bind(obj) for command in self.commands(type(obj))), obj)


_COMMANDS: dict[tuple[type, str], tuple[CommandSpec, ...]] = {}


@dataclass(frozen=True)
class MachineObject:
    """One object of the machine: what an endpoint lists, reads and commands."""

    kind: str
    name: str
    id: int
    parent: str  #: the name of the object it belongs to; "" for none
    signals: tuple[Signal, ...]
    commands: tuple[CommandSpec, ...]
    target: Any = field(repr=False, compare=False)  #: the live object

    def signal(self, name: str) -> Signal:
        """One signal by name; ``ConfigError`` naming the choices otherwise."""
        for signal in self.signals:
            if signal.name == name:
                return signal
        raise ConfigError(_unknown(f"{self.kind} {self.name!r}: no signal", name,
                                   [signal.name for signal in self.signals]))

    def command(self, name: str) -> CommandSpec:
        """One command by name; ``ConfigError`` naming the choices otherwise."""
        for command in self.commands:
            if command.name == name:
                return command
        raise ConfigError(_unknown(f"{self.kind} {self.name!r}: no command", name,
                                   [command.name for command in self.commands]))


@dataclass(frozen=True)
class MachineModel:
    """Every object of a runtime, system by system in the order they were added, each
    system's objects in creation order (a parent before the children it holds)."""

    objects: tuple[MachineObject, ...]

    def __iter__(self) -> Iterator[MachineObject]:
        return iter(self.objects)

    def __len__(self) -> int:
        return len(self.objects)

    def signals(self) -> dict[str, Signal]:
        """Every signal by its qualified name ``<object>.<signal>``, in model order."""
        return {f"{obj.name}.{signal.name}": signal
                for obj in self.objects for signal in obj.signals}

    def signal(self, qualified: str) -> Signal:
        """A signal by ``<object>.<signal>``; ``ConfigError`` naming the choices otherwise."""
        owner, dot, name = qualified.partition(".")
        if not dot:
            raise ConfigError(f"{qualified!r} is not '<object>.<signal>'")
        found = [obj for obj in self.objects if obj.name == owner]
        if not found:
            raise ConfigError(_unknown("no object", owner,
                                       dict.fromkeys(obj.name for obj in self.objects)))
        for obj in found:
            for signal in obj.signals:
                if signal.name == name:
                    return signal
        names = [signal.name for obj in found for signal in obj.signals]
        raise ConfigError(_unknown(f"{owner!r}: no signal", name, names))

    def find(self, name: str, kind: str | None = None) -> MachineObject:
        """The first object named ``name`` (of ``kind``, if given)."""
        for obj in self.objects:
            if obj.name == name and (kind is None or obj.kind == kind):
                return obj
        raise ConfigError(_unknown("no object", name,
                                   dict.fromkeys(obj.name for obj in self.objects)))


def kind_of(obj: object) -> Kind | None:
    """The ``Kind`` the object's class declares (``MACHINE``), or None."""
    kind = getattr(type(obj), "MACHINE", None)
    return kind if isinstance(kind, Kind) else None


def machine(runtime: CyclicRuntime) -> MachineModel:
    """The model of ``runtime`` as it stands now: every object of every system, the systems
    in the order they run (``runtime.systems``: the axes first)."""
    found: list[MachineObject] = []
    seen: set[int] = set()
    for system in runtime.systems:
        for obj in system.objects():
            _walk(obj, found, seen)
    return MachineModel(tuple(found))


def _walk(obj: Any, found: list[MachineObject], seen: set[int], parent: str = "") -> None:
    kind = kind_of(obj)
    if kind is None or id(obj) in seen:
        return  # a system's helper the model does not show, or one listed already
    seen.add(id(obj))
    described = kind.describe(obj, parent)
    found.append(described)
    for child in kind.children(obj):
        _walk(child, found, seen, described.name)


# -- commands from signatures -------------------------------------------------------------------

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def derive_commands(cls: type, handles: Iterable[str],
                    units: Mapping[str, str] | None = None,
                    levels: Iterable[str] = ()) -> tuple[CommandSpec, ...]:
    """The commands of ``cls``: its public methods (its own and inherited, in definition
    order) whose return annotation is one of ``handles`` (the kind's command handle type),
    and after them the methods named in ``levels``, with their inputs from the signatures. ``units``
    overrides ``UNITS`` by input name or by ``"<command>.<input>"``."""
    levels = frozenset(levels)
    wanted = set(handles)
    methods: dict[str, Callable[..., Any]] = {}
    for klass in reversed(cls.__mro__):
        for name, value in vars(klass).items():
            if not name.startswith("_") and inspect.isfunction(value):
                methods[name] = value
    edges = [_command(name, method, units or {}) for name, method in methods.items()
             if _returns(method) in wanted and name not in levels]
    return (*edges, *(_command(name, method, units or {}, True)
                      for name, method in methods.items() if name in levels))


def _returns(method: Callable[..., Any]) -> str:
    annotation = inspect.signature(method).return_annotation
    return getattr(annotation, "__name__", str(annotation))


def _command(name: str, method: Callable[..., Any], units: Mapping[str, str],
             level: bool = False) -> CommandSpec:
    inputs = []
    for parameter in list(inspect.signature(method).parameters.values())[1:]:
        if parameter.kind in (parameter.VAR_POSITIONAL, parameter.VAR_KEYWORD):
            continue
        annotation = parameter.annotation
        dtype = "" if annotation is parameter.empty else \
            getattr(annotation, "__name__", str(annotation))
        default = REQUIRED if parameter.default is parameter.empty else parameter.default
        unit = units.get(f"{name}.{parameter.name}",
                         units.get(parameter.name, UNITS.get(parameter.name, "")))
        inputs.append(Input(parameter.name, dtype, unit, default,
                            _choices(method, dtype, default)))
    doc = (inspect.getdoc(method) or "").split("\n\n")[0].replace("\n", " ")
    return CommandSpec(name, tuple(inputs), doc, level=level)


def _choices(method: Callable[..., Any], dtype: str, default: Any) -> tuple[str, ...]:
    """The member names of the enum an input takes (from its annotation or default)."""
    names = getattr(method, "__globals__", {})
    for candidate in [type(default), *(names.get(token) for token in _TOKEN.findall(dtype))]:
        if isinstance(candidate, type) and issubclass(candidate, Enum):
            return tuple(member.name for member in candidate)
    return ()


def compact_index(positions: list[int]) -> slice | np.ndarray:
    """A slice for consecutive positions (a view, no gather), else an index array."""
    if positions and positions == list(range(positions[0], positions[0] + len(positions))):
        return slice(positions[0], positions[0] + len(positions))
    return np.array(positions, dtype=np.intp)


def _unknown(what: str, name: str, choices: Iterable[str]) -> str:
    choices = list(choices)
    close = difflib.get_close_matches(name, choices, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return f"{what} {name!r}{hint}; one of {', '.join(choices) or 'none'}"
