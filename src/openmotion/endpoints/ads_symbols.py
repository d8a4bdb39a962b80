"""The ADS symbols of a served machine, generated from its machine model (docs/endpoints.md).

A TwinCAT user reads an axis as ``<axis>.NcToPlc.ActPos`` and drives it through function
block instances; the ADS server shows the machine model the same way (D-266):

- per object one struct of its signals, read-only: ``<axis>.NcToPlc.<Name>`` for an axis
  (with TwinCAT's NcToPlc names where one exists: ActPos, ActVelo, SetPos ...),
  ``<object>.Status.<Name>`` for every other kind; the other signals' names are their
  model names in CamelCase (``track_position`` -> ``TrackPosition``);
- per served command an FB-like struct ``<object>.<Command>``: its inputs (writable), a
  rising ``Execute`` that starts it, and the PLCopen outputs ``Done``, ``Busy``,
  ``Active``, ``CommandAborted``, ``Error``, ``ErrorID``; a level command (MC_Power) has its
  inputs, applied at every write, and ``Status``;
- ``Host.Cycle`` and ``Host.Time`` (read), ``Host.Step`` and ``Host.RunFor`` (write, a
  lockstep machine advances by that many cycles or seconds before the write returns).

Every symbol is a leaf with a plain IEC type (LREAL, BOOL, DINT, UDINT, STRING(80), ARRAY
OF LREAL) at its own offset in index group ``INDEX_GROUP``, so that a client can read it by
name, by handle, by group and offset and in a sum read alike.
"""

from __future__ import annotations

import bisect
import math
import re
import struct
import threading
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from typing import Any

from openmotion.core.errors import ConfigError
from openmotion.endpoints.host import HostError, MachineHost, Snapshot
from openmotion.endpoints.wire import (
    HandleState,
    WireCommand,
    WireError,
    WireInput,
    WireKind,
    default_of,
)

__all__ = ["INDEX_GROUP", "AdsError", "AdsSymbol", "AdsType", "SymbolTable", "camel"]

INDEX_GROUP = 0x4040  #: where TwinCAT's PLC keeps its data; every symbol's group here
STRING_LENGTH = 80  #: characters of a STRING input (an object's name)
VECTOR_LENGTH = 16  #: elements of an ARRAY input of any length (NaN ends it)
MAX_STEP = 1_000_000  #: most cycles one write of ``Host.Step`` advances

#: TwinCAT's NcToPlc names of an axis's signals (the others are their names in CamelCase)
NC_TO_PLC = {"set_position": "SetPos", "set_velocity": "SetVelo", "set_acceleration": "SetAcc",
             "set_jerk": "SetJerk", "position": "ActPos", "velocity": "ActVelo",
             "following_error": "PosDiff", "state": "AxisState", "axis_error_id": "ErrorCode"}

# ADS return codes (Beckhoff ADS return codes, device errors 0x700 ...)
ADSERR_NOERR = 0
ADSERR_SRVNOTSUPP = 0x701
ADSERR_INVALIDGRP = 0x702
ADSERR_INVALIDOFFSET = 0x703
ADSERR_INVALIDACCESS = 0x704
ADSERR_INVALIDSIZE = 0x705
ADSERR_INVALIDDATA = 0x706
ADSERR_NOTREADY = 0x707
ADSERR_SYMBOLNOTFOUND = 0x710
ADSERR_NOTIFYHNDINVALID = 0x714
ADSERR_NOMOREHDLS = 0x716
ADSERR_INVALIDWATCHSIZE = 0x717
ADSERR_TIMEOUT = 0x719
ADSERR_ACCESSDENIED = 0x723


class AdsError(Exception):
    """A request the server answers with an ADS return code instead of data."""

    def __init__(self, code: int, message: str = "") -> None:
        super().__init__(message or f"ADS error 0x{code:x}")
        self.code = code


@dataclass(frozen=True)
class AdsType:
    """An IEC type as ADS describes it."""

    name: str  #: as a TwinCAT symbol shows it: "LREAL", "STRING(80)" ...
    ads: int  #: ADST_* number
    size: int  #: bytes
    code: str = ""  #: struct format of one element ("" for STRING)
    count: int = 1  #: elements of an ARRAY

    def encode(self, value: Any) -> bytes:
        if self.code == "":
            raw = str(value).encode("utf-8")[:self.size - 1]
            return raw + bytes(self.size - len(raw))
        if self.count > 1:
            items = list(value)[:self.count]
            items += [math.nan] * (self.count - len(items))
            return struct.pack(f"<{self.count}{self.code}", *items)
        return struct.pack("<" + self.code, value)

    def decode(self, data: bytes) -> Any:
        if self.code == "":
            if len(data) > self.size:
                raise AdsError(ADSERR_INVALIDSIZE, f"{self.name} takes at most {self.size} bytes")
            return data.split(b"\0", 1)[0].decode("utf-8", errors="replace")
        if len(data) != self.size:
            raise AdsError(ADSERR_INVALIDSIZE, f"{self.name} is {self.size} bytes, "
                                               f"not {len(data)}")
        values = struct.unpack(f"<{self.count}{self.code}", data)
        return list(values) if self.count > 1 else values[0]


LREAL = AdsType("LREAL", 5, 8, "d")
BOOL = AdsType("BOOL", 33, 1, "?")
DINT = AdsType("DINT", 3, 4, "i")
UDINT = AdsType("UDINT", 19, 4, "I")
STRING = AdsType(f"STRING({STRING_LENGTH})", 30, STRING_LENGTH + 1)


def _array(count: int) -> AdsType:
    return AdsType(f"ARRAY [0..{count - 1}] OF LREAL", 5, 8 * count, "d", count)


Reader = Callable[[Snapshot], bytes]
Writer = Callable[[bytes], None]


@dataclass(eq=False)
class AdsSymbol:
    """One leaf symbol: its name, type and place, how to read it from a snapshot and (where
    a client may) how to write it."""

    name: str
    type: AdsType
    offset: int
    read: Reader
    write: Writer | None = None
    comment: str = ""
    group: int = INDEX_GROUP

    size: int = 0  #: bytes (the type's), set when made

    def __post_init__(self) -> None:
        self.size = self.type.size

    def entry(self) -> bytes:
        """The symbol as SYM_UPLOAD and SYM_INFOBYNAMEEX describe it (AdsSymbolEntry)."""
        name, kind, comment = (text.encode("utf-8") for text in
                               (self.name, self.type.name, self.comment))
        body = struct.pack("<IIIIIHHH", self.group, self.offset, self.size, self.type.ads,
                           _FLAG_READONLY if self.write is None else 0,
                           len(name), len(kind), len(comment)) \
            + name + b"\0" + kind + b"\0" + comment + b"\0"
        return struct.pack("<I", 4 + len(body)) + body


_FLAG_READONLY = 0x10  #: ADSSYMBOLFLAG_READONLY (no symbol flag says "persistent" here)


def camel(name: str) -> str:
    """``move_absolute`` -> ``MoveAbsolute`` (a model name as an IEC identifier part)."""
    return "".join(part[:1].upper() + part[1:] for part in re.split(r"[_\s]+", name) if part)


def _number_type(dtype: type) -> AdsType:
    if dtype is bool:
        return BOOL
    if isinstance(dtype, type) and issubclass(dtype, Enum | int) and dtype is not float:
        return UDINT if "error" in dtype.__name__.lower() else DINT
    return LREAL


def _cast(kind: AdsType, value: float) -> Any:
    """A signal's float as the symbol's type: NaN (not shown now) is 0, or -1 for a DINT."""
    if kind is LREAL:
        return value
    if math.isnan(value):
        return -1 if kind is DINT else 0
    if kind is BOOL:
        return value != 0
    return int(value) & 0xFFFFFFFF if kind is UDINT else int(value)


class _Fb:
    """What a command struct remembers between writes: its inputs, Execute, its ticket."""

    def __init__(self, command: WireCommand) -> None:
        self.command = command
        self.values: dict[str, Any] = {}  #: the inputs a client wrote
        self.execute = False
        self.ticket: int | None = None
        self.failed: HandleState | None = None  #: a start the host refused
        self.status = False  #: a level command's status
        self.lock = threading.Lock()


class SymbolTable:
    """Every ADS symbol of a served machine, by name (case-insensitive, as TwinCAT's)."""

    def __init__(self, host: MachineHost) -> None:
        self.host = host
        self.symbols: list[AdsSymbol] = []
        self._by_name: dict[str, AdsSymbol] = {}
        self._offsets: list[int] = []
        self.by_offset: dict[int, AdsSymbol] = {}  #: in ``INDEX_GROUP``
        self._next = 0
        used: set[str] = set()
        index = 0  # host.names lists every object's signals in model order
        for obj in host.model:
            group = "NcToPlc" if obj.kind == "axis" else "Status"
            if f"{obj.name}.{group}".lower() in used:  # two objects of one name (a CA mover)
                group = camel(obj.kind) + "Status"
            used.add(f"{obj.name}.{group}".lower())
            for signal in obj.signals:
                alias = NC_TO_PLC.get(signal.name, "") if obj.kind == "axis" else ""
                kind = _number_type(signal.dtype)
                unit = f" [{signal.unit}]" if signal.unit else ""
                self._add(f"{obj.name}.{group}.{alias or camel(signal.name)}", kind,
                          _signal_reader(kind, index), comment=f"{signal.name}{unit}")
                index += 1
            for command in _commands(host, obj):
                self._add_command(obj.name, command)
        self._add_host()

    # -- building --------------------------------------------------------------------------

    def _add(self, name: str, kind: AdsType, read: Reader, write: Writer | None = None,
             comment: str = "") -> None:
        key = name.lower()
        if key in self._by_name:
            raise ConfigError(f"two ADS symbols would be named {name!r}")
        symbol = AdsSymbol(name, kind, self._next, read, write, comment)
        self._next += kind.size
        self.symbols.append(symbol)
        self._offsets.append(symbol.offset)
        self.by_offset[symbol.offset] = symbol
        self._by_name[key] = symbol

    def _add_command(self, owner: str, command: WireCommand) -> None:
        fb = _Fb(command)
        prefix = f"{owner}.{camel(command.name)}"
        level = command.spec.level
        for number, put in enumerate(command.inputs):
            kind = _input_type(put)
            start = default_of(put)
            if level and number == 0 and put.kind is WireKind.BOOL:
                start = False  # the level (MC_Power's Enable) is off until a client sets it
            self._add(f"{prefix}.{camel(put.name)}", kind,
                      _input_reader(fb, put, kind, start), self._input_writer(fb, put, kind),
                      comment=_input_comment(put))
        if level:
            self._add(f"{prefix}.Status", BOOL, lambda _s: BOOL.encode(fb.status),
                      comment=f"what {command.name} returned at the last write")
            return
        self._add(f"{prefix}.Execute", BOOL, lambda _s: BOOL.encode(fb.execute),
                  self._execute_writer(fb), comment=f"a rising edge starts {command.name}")
        for output, kind in (("Done", BOOL), ("Busy", BOOL), ("Active", BOOL),
                             ("CommandAborted", BOOL), ("Error", BOOL), ("ErrorID", UDINT)):
            attribute = {"CommandAborted": "command_aborted", "ErrorID": "error_id"}.get(
                output, output.lower())
            self._add(f"{prefix}.{output}", kind, _output_reader(fb, attribute, kind))

    def _add_host(self) -> None:
        host = self.host
        self._add("Host.Cycle", UDINT, lambda s: UDINT.encode(s.cycle & 0xFFFFFFFF),
                  comment="cycles stepped")
        self._add("Host.Time", LREAL, lambda s: LREAL.encode(s.time),
                  comment="virtual time [s]")

        def step(data: bytes) -> None:
            cycles = UDINT.decode(data)
            if cycles > MAX_STEP:
                raise AdsError(ADSERR_INVALIDDATA, f"Host.Step takes at most {MAX_STEP}")
            _advance(lambda: host.advance(cycles))

        def run_for(data: bytes) -> None:
            seconds = LREAL.decode(data)
            if not math.isfinite(seconds) or not 0 <= seconds <= \
                    MAX_STEP * host.cycle_time:
                raise AdsError(ADSERR_INVALIDDATA, f"Host.RunFor: {seconds} s is out of range")
            _advance(lambda: host.run_for(seconds))

        self._add("Host.Step", UDINT, lambda _s: UDINT.encode(0), step,
                  comment="write n: a lockstep machine steps n cycles")
        self._add("Host.RunFor", LREAL, lambda _s: LREAL.encode(0.0), run_for,
                  comment="write t: a lockstep machine steps t seconds [s]")

    def _input_writer(self, fb: _Fb, put: WireInput, kind: AdsType) -> Writer:
        host = self.host

        def write(data: bytes) -> None:
            value = kind.decode(data)
            if put.kind is WireKind.VECTOR and kind.count > 1:
                value = _until_nan(value)
            with fb.lock:
                if not fb.command.spec.level:
                    fb.values[put.name] = value
                    return
                before = dict(fb.values)
                fb.values[put.name] = value
                inputs = {p.name: _level_value(fb, p) for p in fb.command.inputs}
                try:
                    fb.status = bool(host.switch(fb.command.owner.name, fb.command.name,
                                                 inputs))
                except (WireError, HostError) as error:
                    fb.values = before  # a level the machine did not take is not kept
                    code = ADSERR_INVALIDDATA if isinstance(error, WireError) else \
                        ADSERR_NOTREADY
                    raise AdsError(code, str(error)) from None
        return write

    def _execute_writer(self, fb: _Fb) -> Writer:
        host = self.host

        def write(data: bytes) -> None:
            execute = bool(BOOL.decode(data))
            with fb.lock:
                rising = execute and not fb.execute
                fb.execute = execute
                if rising:
                    fb.failed = None
                    try:
                        fb.ticket = host.call(fb.command.owner.name, fb.command.name,
                                              dict(fb.values))
                    except HostError as error:
                        fb.execute = False  # nothing started: the next write is an edge
                        raise AdsError(ADSERR_NOTREADY, str(error)) from None
                    except ConfigError as error:  # WireError: the machine is untouched
                        fb.ticket = None
                        fb.failed = HandleState(error=True, error_id=ADSERR_INVALIDDATA,
                                                message=str(error))
                elif not execute and fb.ticket is not None:
                    state = host.snapshot.handles.get(fb.ticket)
                    if state is None or not state.busy:
                        fb.ticket = None  # outputs reset with Execute, as an FB's do
                elif not execute:
                    fb.failed = None
        return write

    # -- looking up ------------------------------------------------------------------------

    def find(self, name: str) -> AdsSymbol:
        symbol = self._by_name.get(name.strip().lower())
        if symbol is None:
            raise AdsError(ADSERR_SYMBOLNOTFOUND, f"no symbol {name!r}")
        return symbol

    def at(self, group: int, offset: int) -> AdsSymbol:
        """The symbol that begins at ``offset`` of ``group``."""
        if group != INDEX_GROUP:
            raise AdsError(ADSERR_INVALIDGRP)
        symbol = self.by_offset.get(offset)
        if symbol is None:
            raise AdsError(ADSERR_INVALIDOFFSET)
        return symbol

    def read(self, symbol: AdsSymbol, length: int, snapshot: Snapshot) -> bytes:
        """``length`` bytes from where ``symbol`` begins: a read may span the symbols that
        follow it, as a read of a PLC's memory does."""
        chunks, have = [], 0
        position = bisect.bisect_left(self._offsets, symbol.offset) \
            if length > symbol.size else 0
        current = symbol
        while True:
            chunks.append(current.read(snapshot))
            have += current.size
            if have >= length or length <= symbol.size:
                break
            position += 1
            if position >= len(self.symbols):
                break
            current = self.symbols[position]
        return b"".join(chunks)[:length]

    def upload(self) -> bytes:
        return b"".join(symbol.entry() for symbol in self.symbols)


def _commands(host: MachineHost, obj: Any) -> tuple[WireCommand, ...]:
    return tuple(command for command in host.commands.get(obj.name, ())
                 if command.owner is obj)


def _advance(step: Callable[[], Any]) -> None:
    try:
        step()
    except HostError as error:
        raise AdsError(ADSERR_NOTREADY, str(error)) from None
    except TimeoutError:
        raise AdsError(ADSERR_TIMEOUT) from None


def _signal_reader(kind: AdsType, index: int) -> Reader:
    pack = struct.Struct("<" + kind.code).pack
    if kind is LREAL:
        return lambda s: pack(s.values[index])
    return lambda s: pack(_cast(kind, float(s.values[index])))


def _input_type(put: WireInput) -> AdsType:
    if put.kind is WireKind.BOOL:
        return BOOL
    if put.kind in (WireKind.INTEGER, WireKind.ENUM):
        return DINT if put.type is not None or put.kind is WireKind.INTEGER else STRING
    if put.kind is WireKind.OBJECT:
        return STRING
    if put.kind is WireKind.VECTOR:
        return _array(put.length or VECTOR_LENGTH)
    return LREAL


def _input_comment(put: WireInput) -> str:
    unit = f" [{put.input.unit}]" if put.input.unit else ""
    if put.kind is WireKind.ENUM and put.type is not None:
        return f"{put.name}{unit}: " + ", ".join(f"{m.value}={m.name}" for m in put.type)
    if put.kind is WireKind.VECTOR and put.length is None:
        return f"{put.name}{unit}: NaN ends the array"
    return f"{put.name}{unit}" + ("" if put.required else " (optional)")


def _input_reader(fb: _Fb, put: WireInput, kind: AdsType, start: Any) -> Reader:
    """The input as last written, or its default."""
    if isinstance(start, str) and put.kind is WireKind.ENUM and put.type is not None:
        start = put.type[start].value  # an enum default reads as its number
    elif isinstance(start, str) and kind is not STRING:
        start = 0  # MC_DEFAULT reads 0, which the blocks take as "the default" too
    if start is None:
        start = [] if kind.count > 1 else "" if kind is STRING else 0

    def read(_snapshot: Snapshot) -> bytes:
        value = fb.values.get(put.name, start)
        if put.kind is WireKind.ENUM and isinstance(value, Enum):
            value = value.value
        return kind.encode(value)
    return read


def _level_value(fb: _Fb, put: WireInput) -> Any:
    if put.name in fb.values:
        return fb.values[put.name]
    return False if put is fb.command.inputs[0] and put.kind is WireKind.BOOL else \
        default_of(put)


def _until_nan(values: list[float]) -> list[float]:
    for position, value in enumerate(values):
        if math.isnan(value):
            return values[:position]
    return values


def _output_reader(fb: _Fb, attribute: str, kind: AdsType) -> Reader:
    def read(snapshot: Snapshot) -> bytes:
        state = fb.failed
        if state is None and fb.ticket is not None:
            state = snapshot.handles.get(fb.ticket)
        value = getattr(state, attribute) if state is not None else 0
        return kind.encode(value & 0xFFFFFFFF if kind is UDINT else bool(value))
    return read
