"""What a command input looks like on a wire, and how a wire value becomes the input.

Every endpoint (OPC UA, ADS, FMI) offers the machine model's commands to clients that know
numbers, booleans, strings and arrays, not Python objects. ``wire_input`` classifies one
``Input`` of a command once, from the annotation of the method that starts it; ``coerce``
turns what a client sent into the value the method takes, or raises ``WireError`` with a
message that names the input, so that each endpoint answers a bad value with its own
status code (OPC UA Bad_*, an ADS error code) and the machine is never touched.

Kinds of inputs (D-255):

- NUMBER: a float or an ``InputValue`` (a float or MC_DEFAULT, MC_INVALID ...): a finite
  number; where the input has a default, a client may leave it out.
- INTEGER, BOOL: as they say.
- ENUM: the member's name, or its number.
- OBJECT: another object of the machine (the master axis, a track), by its name in the model.
- VECTOR: a dataclass of numbers only (``PositionXYC``) or a position of an axes group: an
  array of numbers.
- Everything else (option structs, frames, kinematics, constraints, feedbacks) has no wire
  form: an optional one keeps its default, and a command that needs one is not served.
"""

from __future__ import annotations

import dataclasses
import enum
import inspect
import math
import typing
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any

from openmotion.core.errors import ConfigError
from openmotion.core.special_values import SPECIAL_VALUES, SpecialValue
from openmotion.kernel.model import REQUIRED, CommandSpec, Input, MachineModel, MachineObject

__all__ = ["HandleState", "WireCommand", "WireError", "WireInput", "WireKind", "coerce",
           "default_of", "handle_state", "wire_commands"]

#: a position of an axes group (an ``Any`` input of these names) is an array of numbers
_VECTOR_NAMES = frozenset({"position", "distance", "aux_point", "end_point"})
_MAX_VECTOR = 16  #: the longest array a vector input takes (an axes group's axes)


class WireError(ConfigError):
    """A value a client sent cannot be the input it was sent for."""


class WireKind(Enum):
    NUMBER = "number"
    INTEGER = "integer"
    BOOL = "bool"
    ENUM = "enum"
    OBJECT = "object"
    VECTOR = "vector"
    NONE = "none"  #: no wire form


@dataclass(frozen=True)
class WireInput:
    """One input of a command as a client sends it."""

    input: Input
    kind: WireKind
    #: the enum class (ENUM), the object's class name (OBJECT) or the dataclass (VECTOR)
    type: Any = None

    @property
    def name(self) -> str:
        return self.input.name

    @property
    def required(self) -> bool:
        return self.input.required

    @property
    def length(self) -> int | None:
        """The number of elements of a VECTOR of fixed size; None for any size."""
        if self.kind is WireKind.VECTOR and self.type is not None:
            return len(dataclasses.fields(self.type))
        return None


@dataclass(frozen=True)
class WireCommand:
    """One command of one object as endpoints offer it: its wire inputs, in order."""

    owner: MachineObject
    spec: CommandSpec
    inputs: tuple[WireInput, ...]

    @property
    def name(self) -> str:
        return self.spec.name

    def arguments(self, values: Mapping[str, Any], model: MachineModel) -> dict[str, Any]:
        """The keyword arguments of the command from what a client sent: unknown names,
        missing required inputs and bad values raise ``WireError``."""
        known = {put.name: put for put in self.inputs}
        unknown = sorted(set(values).difference(known))
        if unknown:
            raise WireError(f"{self.name} has no input {unknown[0]!r}; "
                            f"one of {', '.join(known) or 'none'}")
        arguments: dict[str, Any] = {}
        for put in self.inputs:
            if put.name in values:
                arguments[put.name] = coerce(put, values[put.name], model)
            elif put.required:
                raise WireError(f"{self.name}: input {put.name!r} is required")
        return arguments


def wire_commands(owner: MachineObject) -> tuple[WireCommand, ...]:
    """The commands of ``owner`` that a client can send: those whose required inputs all
    have a wire form; inputs without one are left out (they keep their defaults)."""
    served = []
    for spec in owner.commands:
        hints = _hints(owner.target, spec.name)
        inputs = tuple(_classify(put, hints.get(put.name)) for put in spec.inputs)
        if any(put.kind is WireKind.NONE and put.required for put in inputs):
            continue
        served.append(WireCommand(owner, spec, tuple(
            put for put in inputs if put.kind is not WireKind.NONE)))
    return tuple(served)


def _hints(target: Any, name: str) -> dict[str, Any]:
    method = getattr(type(target), name)
    try:
        return typing.get_type_hints(method)
    except Exception:  # noqa: BLE001 - a forward reference we cannot resolve: by its text
        return {}


def _classify(put: Input, hint: Any) -> WireInput:
    options = [arg for arg in typing.get_args(hint) if arg is not type(None)] \
        if _is_union(hint) else [hint]
    for option in options:
        if isinstance(option, type) and issubclass(option, Enum):
            return WireInput(put, WireKind.ENUM, option)
    if put.choices:
        return WireInput(put, WireKind.ENUM)
    for option in options:
        if option is bool:
            return WireInput(put, WireKind.BOOL)
    if any(option is float for option in options) or put.dtype.startswith("InputValue"):
        return WireInput(put, WireKind.NUMBER)
    for option in options:
        if option is int:
            return WireInput(put, WireKind.INTEGER)
        if dataclasses.is_dataclass(option) and isinstance(option, type) and _numbers_only(option):
            return WireInput(put, WireKind.VECTOR, option)
        if isinstance(option, type) and getattr(option, "MACHINE", None) is not None:
            return WireInput(put, WireKind.OBJECT, option.__name__)
    if put.dtype == "Any" and put.name in _VECTOR_NAMES:
        return WireInput(put, WireKind.VECTOR)
    return WireInput(put, WireKind.NONE)


def _is_union(hint: Any) -> bool:
    return typing.get_origin(hint) in (typing.Union, __import__("types").UnionType)


def _numbers_only(cls: type) -> bool:
    hints = typing.get_type_hints(cls)
    return all(hints.get(field.name) in (float, int) for field in dataclasses.fields(cls))


def coerce(put: WireInput, value: Any, model: MachineModel) -> Any:
    """``value`` as the input ``put`` takes it; ``WireError`` naming the input otherwise."""
    try:
        return _COERCE[put.kind](put, value, model)
    except WireError:
        raise
    except (TypeError, ValueError, KeyError) as error:
        raise WireError(f"input {put.name!r}: {error}") from None


def _number(put: WireInput, value: Any, model: MachineModel) -> float | SpecialValue:
    if isinstance(value, str) and put.input.dtype.startswith("InputValue"):
        special = SPECIAL_VALUES.get(value.upper())
        if special is None:
            raise WireError(f"input {put.name!r} takes a number or one of "
                            f"{', '.join(SPECIAL_VALUES)}, not {value!r}")
        return special
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise WireError(f"input {put.name!r} takes a number, not {type(value).__name__}")
    number = float(value)
    if not math.isfinite(number):
        raise WireError(f"input {put.name!r} must be finite, not {number}")
    bounds = put.input.range
    if bounds is not None and not bounds[0] <= number <= bounds[1]:
        raise WireError(f"input {put.name!r} = {number} is outside [{bounds[0]}, {bounds[1]}]")
    return number


def _finite(put: WireInput, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) \
            or not math.isfinite(value):
        raise WireError(f"input {put.name!r} takes finite numbers, not {value!r}")
    return float(value)


def _integer(put: WireInput, value: Any, model: MachineModel) -> int:
    if isinstance(value, bool) or not isinstance(value, int | float) or value != int(value):
        raise WireError(f"input {put.name!r} takes a whole number, not {value!r}")
    return int(value)


def _bool(put: WireInput, value: Any, model: MachineModel) -> bool:
    if not isinstance(value, bool | int) or value not in (0, 1):
        raise WireError(f"input {put.name!r} takes TRUE or FALSE, not {value!r}")
    return bool(value)


def _enum(put: WireInput, value: Any, model: MachineModel) -> Any:
    cls = put.type
    if cls is None:
        if value not in put.input.choices:
            raise WireError(f"input {put.name!r}: {value!r} is not one of "
                            f"{', '.join(put.input.choices)}")
        return value
    if isinstance(value, str):
        member = cls.__members__.get(value.upper())
        if member is None:
            raise WireError(f"input {put.name!r}: no {cls.__name__} {value!r}; one of "
                            f"{', '.join(cls.__members__)}")
        return member
    if isinstance(value, bool) or not isinstance(value, int):
        raise WireError(f"input {put.name!r} takes a {cls.__name__} name or number")
    try:
        return cls(value)
    except ValueError:
        raise WireError(f"input {put.name!r}: {value} is no {cls.__name__}; one of "
                        + ", ".join(f"{m.name}={m.value}" for m in cls)) from None


def _object(put: WireInput, value: Any, model: MachineModel) -> Any:
    if not isinstance(value, str):
        raise WireError(f"input {put.name!r} takes the name of a {put.type}")
    matches = [obj for obj in model if obj.name == value
               and type(obj.target).__name__ == put.type]
    if not matches:
        names = [obj.name for obj in model if type(obj.target).__name__ == put.type]
        raise WireError(f"input {put.name!r}: no {put.type} {value!r}; one of "
                        f"{', '.join(names) or 'none'}")
    return matches[0].target


def _vector(put: WireInput, value: Any, model: MachineModel) -> Any:
    if isinstance(value, str | bytes) or not isinstance(value, Sequence):
        raise WireError(f"input {put.name!r} takes an array of numbers")
    numbers = [_finite(put, item) for item in value]
    length = put.length
    if length is not None and len(numbers) != length:
        raise WireError(f"input {put.name!r} takes {length} numbers, not {len(numbers)}")
    if not 0 < len(numbers) <= _MAX_VECTOR:
        raise WireError(f"input {put.name!r} takes 1 to {_MAX_VECTOR} numbers")
    if put.type is None:
        return numbers
    hints = typing.get_type_hints(put.type)
    fields = dataclasses.fields(put.type)
    for index, (item, number) in enumerate(zip(fields, numbers, strict=True)):
        if hints.get(item.name) is int:  # PositionXYC.reference_id: an object id
            if number != int(number):
                raise WireError(f"input {put.name!r}: {item.name} takes a whole number, "
                                f"not {number}")
            numbers[index] = int(number)  # type: ignore[call-overload]
    return put.type(*numbers)


_COERCE: dict[WireKind, Callable[[WireInput, Any, MachineModel], Any]] = {
    WireKind.NUMBER: _number, WireKind.INTEGER: _integer, WireKind.BOOL: _bool,
    WireKind.ENUM: _enum, WireKind.OBJECT: _object, WireKind.VECTOR: _vector}


# -- what a command handle shows ----------------------------------------------------------------

@dataclass(frozen=True)
class HandleState:
    """The FB outputs of one command as a client reads them (PLCopen handshake)."""

    busy: bool = False
    active: bool = False
    done: bool = False
    command_aborted: bool = False
    error: bool = False
    error_id: int = 0
    message: str = ""


def handle_state(handle: Any) -> HandleState:
    """The outputs of a command handle (``Command`` or a planar command)."""
    status = getattr(handle, "status", None) or getattr(handle, "phase", None)
    aborted = status is not None and getattr(status, "name", "") == "ABORTED"
    return HandleState(bool(handle.busy), bool(handle.active), bool(handle.done), aborted,
                       bool(handle.error), int(handle.error_id), str(handle.message))


def default_of(put: WireInput) -> Any:
    """The input's default as a client sees it (None when required)."""
    default = put.input.default
    if default is REQUIRED:
        return None
    if isinstance(default, enum.Enum | SpecialValue):
        return default.name
    return default if not inspect.isclass(default) else None
