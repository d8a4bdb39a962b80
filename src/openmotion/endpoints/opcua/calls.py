"""Method calls: a client's arguments become a command's inputs, or a Bad status code.

OPC 10000-4 §5.11.2 (Call): a call whose arguments do not fit answers Bad_InvalidArgument
with, per argument, Bad_TypeMismatch (not of the argument's data type) or Bad_OutOfRange (of
its type, but no value the input takes: outside its range, not finite, no such enum member
or object; the wire layer's message goes into the argument's DiagnosticInfo). Too few
required arguments answer Bad_ArgumentsMissing, too many Bad_TooManyArguments. The machine is
touched only when every argument fits (D-261).

Optional inputs may be left out at the end, or sent as a Null variant; a NaN Double means the
input's default as well (MC_DEFAULT where the input takes it). An input that takes the
special values (MC_DEFAULT, MC_MAXIMUM ...) takes their names as a String too.
"""

from __future__ import annotations

import asyncio
import logging
import math
from collections.abc import Awaitable, Callable, Mapping, Sequence
from typing import Any

from asyncua import ua

from openmotion.core.errors import ConfigError
from openmotion.core.special_values import SPECIAL_VALUES
from openmotion.endpoints.host import HostError, MachineHost
from openmotion.endpoints.opcua.space import Served
from openmotion.endpoints.wire import WireCommand, WireError, WireInput, WireKind, coerce
from openmotion.kernel.model import MachineObject

__all__ = ["CallRefused", "arguments", "command_method", "host_methods"]

_LOG = logging.getLogger("openmotion.endpoints.opcua")
_V = ua.VariantType
INTEGERS = frozenset({_V.SByte, _V.Byte, _V.Int16, _V.UInt16, _V.Int32, _V.UInt32, _V.Int64,
                      _V.UInt64})
NUMBERS = INTEGERS | {_V.Float, _V.Double}
MAX_STEP = 10_000_000  #: most cycles one Step call advances
_OMITTED = object()

AddCommand = Callable[[int, MachineObject, str], Awaitable[ua.NodeId]]
Publish = Callable[[], Awaitable[None]]  #: copies the newest snapshot into the variables


class CallRefused(Exception):
    """A call the server answers with a Bad status code, the machine untouched."""

    def __init__(self, status: int, message: str, argument: int | None = None,
                 argument_status: int = ua.StatusCodes.Good) -> None:
        super().__init__(message)
        self.status = status
        self.argument = argument
        self.argument_status = argument_status

    def result(self, count: int) -> ua.CallMethodResult:
        result = ua.CallMethodResult()
        result.StatusCode = ua.StatusCode(self.status)
        if self.argument is not None:
            result.InputArgumentResults = [
                ua.StatusCode(self.argument_status if i == self.argument else ua.StatusCodes.Good)
                for i in range(count)]
            result.InputArgumentDiagnosticInfos = [
                ua.DiagnosticInfo(AdditionalInfo=str(self)) if i == self.argument
                else ua.DiagnosticInfo() for i in range(count)]
        return result


def _mismatch(index: int, put: WireInput, wanted: str) -> CallRefused:
    return CallRefused(ua.StatusCodes.BadInvalidArgument,
                       f"input {put.name!r} takes {wanted}", index,
                       ua.StatusCodes.BadTypeMismatch)


def _value(index: int, put: WireInput, given: ua.Variant) -> Any:
    """The Python value of one argument, ``_OMITTED`` for a default; ``CallRefused`` with
    Bad_TypeMismatch when its variant type does not fit the input."""
    kind, value = given.VariantType, given.Value
    if kind is _V.Null or value is None:
        return _OMITTED
    array = isinstance(value, list | tuple)
    if put.kind is WireKind.VECTOR:
        if not array or kind not in NUMBERS:
            raise _mismatch(index, put, "an array of numbers")
        return [float(item) for item in value]
    if array:
        raise _mismatch(index, put, "one value, not an array")
    if put.kind is WireKind.NUMBER:
        if kind in NUMBERS:
            number = float(value)
            return _OMITTED if math.isnan(number) else number
        if kind is _V.String and put.input.dtype.startswith("InputValue") \
                and value.upper() in SPECIAL_VALUES:
            return value  # MC_DEFAULT, MC_MAXIMUM ...: whether this input takes it, the wire says
        raise _mismatch(index, put, "a Double")
    if put.kind is WireKind.INTEGER and kind in INTEGERS:
        return int(value)
    if put.kind is WireKind.BOOL and kind is _V.Boolean:
        return bool(value)
    if put.kind is WireKind.ENUM and (kind in INTEGERS or kind is _V.String):
        return value if kind is _V.String else int(value)
    if put.kind is WireKind.OBJECT and kind is _V.String:
        return value
    wanted = {WireKind.INTEGER: "a whole number", WireKind.BOOL: "a Boolean",
              WireKind.ENUM: "an enumeration value or name",
              WireKind.OBJECT: "an object's name (String)"}
    raise _mismatch(index, put, wanted.get(put.kind, "another type"))


def arguments(command: WireCommand, given: Sequence[ua.Variant], host: MachineHost) \
        -> dict[str, Any]:
    """The inputs of ``command`` from a call's arguments; ``CallRefused`` otherwise."""
    if len(given) > len(command.inputs):
        raise CallRefused(ua.StatusCodes.BadTooManyArguments,
                          f"{command.name} takes {len(command.inputs)} arguments, "
                          f"not {len(given)}")
    inputs: dict[str, Any] = {}
    for index, put in enumerate(command.inputs):
        value = _value(index, put, given[index]) if index < len(given) else _OMITTED
        if value is _OMITTED:
            if put.required:
                raise CallRefused(ua.StatusCodes.BadArgumentsMissing,
                                  f"{command.name}: input {put.name!r} is required")
            continue
        try:
            coerce(put, value, host.model)
        except WireError as error:
            raise CallRefused(ua.StatusCodes.BadInvalidArgument, str(error), index,
                              ua.StatusCodes.BadOutOfRange) from None
        inputs[put.name] = value
    return inputs


async def _off_loop(function: Callable[..., Any], *args: Any) -> Any:
    """Run a blocking host request on a worker thread: the server's loop goes on serving."""
    return await asyncio.get_running_loop().run_in_executor(None, function, *args)


def _refusal(error: Exception) -> CallRefused:
    if isinstance(error, HostError):
        return CallRefused(ua.StatusCodes.BadInvalidState, str(error))
    return CallRefused(ua.StatusCodes.BadInvalidArgument, str(error))


def command_method(host: MachineHost, served: Mapping[ua.NodeId, Served],
                   add_command: AddCommand, publish: Publish) -> Callable[..., Awaitable[Any]]:
    """The callback of one command's method, shared by the objects of a kind (``served``:
    by the object's NodeId): start it, answer its ticket and object (or the level's
    status)."""

    async def call(parent: ua.NodeId, *given: ua.Variant) -> Any:
        found = served.get(parent)
        if found is None:
            return CallRefused(ua.StatusCodes.BadMethodInvalid,
                               f"{parent.Identifier} has no such method").result(len(given))
        command, owner = found.command, found.owner
        try:
            inputs = arguments(command, given, host)
            if command.spec.level:
                status = await _off_loop(host.switch, owner, command.name, inputs)
                await publish()
                return [ua.Variant(bool(status), _V.Boolean)]
            ticket = await _off_loop(host.call, owner, command.name, inputs)
        except CallRefused as refused:
            _LOG.info("%s.%s refused: %s", owner.name, command.name, refused)
            return refused.result(len(given))
        except (ConfigError, HostError) as error:
            return _refusal(error).result(len(given))
        except Exception as error:  # noqa: BLE001 - a client must never see a dead server
            _LOG.exception("%s.%s failed", owner.name, command.name)
            return CallRefused(ua.StatusCodes.BadInternalError,
                               f"{type(error).__name__}: {error}").result(len(given))
        node = await add_command(ticket, owner, command.name)
        await publish()
        return [ua.Variant(ticket, _V.UInt32), ua.Variant(node, _V.NodeId)]

    return call


def _number(given: Sequence[ua.Variant], name: str, kinds: frozenset[ua.VariantType]) -> float:
    if len(given) != 1:
        raise CallRefused(ua.StatusCodes.BadArgumentsMissing if not given
                          else ua.StatusCodes.BadTooManyArguments, f"{name} takes one argument")
    if given[0].VariantType not in kinds or isinstance(given[0].Value, list | tuple):
        raise CallRefused(ua.StatusCodes.BadInvalidArgument, f"{name} takes a number", 0,
                          ua.StatusCodes.BadTypeMismatch)
    return given[0].Value


def host_methods(host: MachineHost, publish: Publish) \
        -> dict[str, Callable[..., Awaitable[Any]]]:
    """The callbacks of the Host object's methods: Step, RunFor, Pause, Resume, SetSpeed;
    each publishes the machine as it left it before it answers."""

    def pace_result(snapshot: Any) -> list[ua.Variant]:
        return [ua.Variant(snapshot.cycle, _V.UInt64), ua.Variant(snapshot.time, _V.Double)]

    def checked(value: float, name: str, low: float, high: float) -> float:
        if not (math.isfinite(value) and low <= value <= high):
            raise CallRefused(ua.StatusCodes.BadInvalidArgument,
                              f"{name} must be in [{low:g}, {high:g}], not {value}", 0,
                              ua.StatusCodes.BadOutOfRange)
        return value

    async def step(parent: ua.NodeId, *given: ua.Variant) -> Any:
        cycles = int(checked(_number(given, "Step", INTEGERS), "Cycles", 0, MAX_STEP))
        return pace_result(await _off_loop(host.advance, cycles))

    async def run_for(parent: ua.NodeId, *given: ua.Variant) -> Any:
        seconds = checked(float(_number(given, "RunFor", NUMBERS)), "Seconds", 0.0,
                          MAX_STEP * host.cycle_time)
        return pace_result(await _off_loop(host.run_for, seconds))

    async def set_speed(parent: ua.NodeId, *given: ua.Variant) -> Any:
        await _off_loop(host.set_speed, float(_number(given, "SetSpeed", NUMBERS)))
        return []

    async def pause(parent: ua.NodeId, *given: ua.Variant) -> Any:
        await _off_loop(host.pause)
        return []

    async def resume(parent: ua.NodeId, *given: ua.Variant) -> Any:
        await _off_loop(host.resume)
        return []

    def guarded(method: Callable[..., Awaitable[Any]]) -> Callable[..., Awaitable[Any]]:
        async def call(parent: ua.NodeId, *given: ua.Variant) -> Any:
            try:
                result = await method(parent, *given)
                await publish()
                return result
            except CallRefused as refused:
                return refused.result(len(given))
            except (ConfigError, HostError) as error:
                refused = _refusal(error)
                if isinstance(error, ConfigError):  # a value the host refuses: out of range
                    refused = CallRefused(ua.StatusCodes.BadInvalidArgument, str(error), 0,
                                          ua.StatusCodes.BadOutOfRange)
                return refused.result(len(given))
        return call

    return {name: guarded(method) for name, method in (
        ("Step", step), ("RunFor", run_for), ("Pause", pause), ("Resume", resume),
        ("SetSpeed", set_speed))}
