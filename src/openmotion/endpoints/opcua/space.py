"""The address space of a served machine, generated from its machine model (D-260).

::

    Objects/
      Machine/                       folder; one object per object of the model
        x          (AxisType)        signals as variables, commands as methods
          position (AnalogUnitType, EngineeringUnits mm) ...
          move_absolute(position, velocity, ...) -> Ticket, Command
        xts        (CaGroupType)
          m1       (CaMoverType)     a child object: the model's parent/child hierarchy
      Host/                          the pace: Cycle, Time, Pace, Speed ...; Step, RunFor,
                                     Pause, Resume, SetSpeed
      Commands/                      one MotionCommandType object per started command:
        17                           Busy, Active, Done, CommandAborted, Error, ErrorID ...

NodeIds are strings in the server's namespace (``NAMESPACE_URI``): an object by its path
(``xts/m1``), a signal by its qualified name as the trace names it (``m1.gap``), a method by
``type:<kind>:<command>`` (one node per kind, called on any object of the kind: call it by its
browse name), a command by ``Commands/<ticket>``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any

from asyncua import ua

from openmotion.endpoints.host import MachineHost
from openmotion.endpoints.opcua import nodes
from openmotion.endpoints.wire import HandleState, WireCommand, WireInput, WireKind, default_of
from openmotion.kernel.model import MachineObject

__all__ = ["NAMESPACE_URI", "AddressSpace", "Served", "command_items"]

NAMESPACE_URI = "urn:openmotion:machine"
HANDLE_OUTPUTS = ("Busy", "Active", "Done", "CommandAborted", "Error", "ErrorID", "Message")


@dataclass(frozen=True)
class Served:
    """One method of the address space: the command it starts on its object."""

    owner: MachineObject
    command: WireCommand


@dataclass
class AddressSpace:
    """The nodes of one machine, before they are added: items in the order a server adds
    them, and what the server needs to keep them current."""

    namespace: int
    items: list[ua.AddNodesItem] = field(default_factory=list)
    definitions: dict[ua.NodeId, ua.EnumDefinition] = field(default_factory=dict)
    #: per signal, in the order of ``MachineHost.names``: its NodeId and variant type
    signals: list[tuple[ua.NodeId, ua.VariantType]] = field(default_factory=list)
    #: per method node (one per kind and command, on the kind's type): what it starts on
    #: each object that has it, by the object's NodeId
    methods: dict[ua.NodeId, dict[ua.NodeId, Served]] = field(default_factory=dict)
    #: the HasComponent references from each object to the methods of its kind
    references: list[ua.AddReferencesItem] = field(default_factory=list)
    #: the method node of each (kind, command, inputs): one per kind, shared by its objects
    shared: dict[tuple[object, ...], ua.NodeId] = field(default_factory=dict)
    paths: set[str] = field(default_factory=set)  #: the object paths given
    _enums: dict[type, ua.NodeId] = field(default_factory=dict)

    def id(self, text: str) -> ua.NodeId:
        return ua.NodeId(text, self.namespace)

    def name(self, text: str) -> ua.QualifiedName:
        return ua.QualifiedName(text, self.namespace)

    def enum(self, cls: type[IntEnum]) -> ua.NodeId:
        """The data type of an enumeration, added on first use."""
        found = self._enums.get(cls)
        if found is None:
            found = self._enums[cls] = self.id(f"type:{cls.__name__}")
            items, definition = nodes.data_type(found, cls, self.namespace)
            self.items.extend(items)
            self.definitions[found] = definition
        return found


def build(host: MachineHost, namespace: int, interval_ms: float) -> AddressSpace:
    """Every node of ``host``'s machine: types, the Machine folder, the Host and Commands."""
    space = AddressSpace(namespace)
    objects = ua.NodeId(ua.ObjectIds.ObjectsFolder)
    folder = ua.NodeId(ua.ObjectIds.FolderType)
    space.items.append(nodes.obj(space.id("Machine"), space.name("Machine"), objects, folder,
                                 "the served machine, one object per object of its model",
                                 ua.ObjectIds.Organizes))
    space.items.append(nodes.obj(space.id("Commands"), space.name("Commands"), objects, folder,
                                 "one object per started command (PLCopen handshake)",
                                 ua.ObjectIds.Organizes))
    space.items.append(nodes.object_type(space.id("type:MotionCommandType"),
                                         space.name("MotionCommandType"),
                                         "the outputs of one started command"))
    kinds: set[str] = set()
    paths: dict[str, str] = {}  #: object name -> path of the last object of that name
    values = host.snapshot.values
    index = 0
    for obj in host.model:
        if obj.kind not in kinds:
            kinds.add(obj.kind)
            space.items.append(nodes.object_type(space.id(f"type:{obj.kind}"),
                                                 space.name(_type_name(obj.kind))))
        path = _unique(f"{paths[obj.parent]}/{obj.name}" if obj.parent in paths else obj.name,
                       space)
        paths[obj.name] = path
        parent = space.id(paths.get(obj.parent, "Machine") if obj.parent else "Machine")
        _object(space, obj, path, parent)
        for signal in obj.signals:
            _signal(space, obj, signal.name, signal.unit, signal.dtype, space.id(path),
                    float(values[index]), interval_ms, signal.spec.doc)
            index += 1
        for command in host.commands_of(obj):
            _method(space, obj, command, path)
    return space


def _type_name(kind: str) -> str:
    return "".join(part.capitalize() for part in kind.split("_")) + "Type"


def _unique(path: str, space: AddressSpace) -> str:
    """``path``, or ``path~2`` ... when two objects of one parent share a name."""
    candidate, count = path, 1
    while candidate in space.paths:
        count += 1
        candidate = f"{path}~{count}"
    space.paths.add(candidate)
    return candidate


def _object(space: AddressSpace, obj: MachineObject, path: str, parent: ua.NodeId) -> None:
    reference = ua.ObjectIds.Organizes if parent == space.id("Machine") \
        else ua.ObjectIds.HasComponent
    node = space.id(path)
    space.items.append(nodes.obj(node, space.name(obj.name), parent, space.id(f"type:{obj.kind}"),
                                 f"{obj.kind} {obj.name}", reference))
    space.items.append(nodes.prop(space.id(f"{path}#Kind"), "Kind", node,
                                  ua.Variant(obj.kind, ua.VariantType.String),
                                  ua.ObjectIds.String))
    space.items.append(nodes.prop(space.id(f"{path}#Id"), "Id", node,
                                  ua.Variant(obj.id, ua.VariantType.Int64), ua.ObjectIds.Int64))


def signal_type(dtype: type) -> tuple[ua.VariantType, int | None]:
    """How a signal's float travels: its variant type, and the standard data type (None for
    an enumeration, whose data type the address space adds)."""
    if isinstance(dtype, type) and issubclass(dtype, IntEnum):
        return ua.VariantType.Int32, None
    if dtype is bool:
        return ua.VariantType.Boolean, ua.ObjectIds.Boolean
    if dtype is int:
        return ua.VariantType.Int32, ua.ObjectIds.Int32
    return ua.VariantType.Double, ua.ObjectIds.Double


class FreshValue(ua.DataValue):
    """A value the server writes once and never changes afterwards (D-322).

    asyncua deep-copies every value it hands to a monitored item, in case the writer changes
    it later; for a float in a Variant that copy costs about 25 times as much as making the
    value. The server makes a new value for every write, so the copy may be the value itself.
    """

    def __deepcopy__(self, memo: dict[int, Any]) -> FreshValue:
        return self


def variant(value: float, kind: ua.VariantType) -> ua.DataValue:
    """One signal's value as the server holds it; NaN (the object cannot show it now) is
    NaN for a Double and Bad_NoData for the others (D-260)."""
    if kind is ua.VariantType.Double:
        return FreshValue(ua.Variant(value, kind))
    if math.isnan(value):
        return FreshValue(ua.Variant(None, ua.VariantType.Null),
                          StatusCode=ua.StatusCode(ua.StatusCodes.BadNoData))
    number = bool(value) if kind is ua.VariantType.Boolean else int(value)
    return FreshValue(ua.Variant(number, kind))


def _signal(space: AddressSpace, obj: MachineObject, name: str, unit: str, dtype: type,
            parent: ua.NodeId, value: float, interval_ms: float, doc: str) -> None:
    kind, standard = signal_type(dtype)
    datatype = space.enum(dtype) if standard is None else ua.NodeId(standard)  # type: ignore[arg-type]
    node = space.id(f"{obj.name}.{name}")
    analog = unit and kind is ua.VariantType.Double
    space.items.append(nodes.variable(
        node, space.name(name), parent, variant(value, kind).Value, datatype,
        interval_ms=interval_ms, description=f"{doc} [{unit}]" if unit else doc,
        typedef=ua.ObjectIds.AnalogUnitType if analog else ua.ObjectIds.BaseDataVariableType))
    if analog:
        space.items.append(nodes.prop(space.id(f"{node.Identifier}#EngineeringUnits"),
                                      "EngineeringUnits", node,
                                      ua.Variant(nodes.eu_information(unit),
                                                 ua.VariantType.ExtensionObject),
                                      ua.ObjectIds.EUInformation))
    space.signals.append((node, kind))


# -- methods ------------------------------------------------------------------------------------

def input_type(space: AddressSpace, put: WireInput) -> tuple[ua.NodeId, bool]:
    """The data type of an input's argument, and whether it is an array."""
    if put.kind is WireKind.VECTOR:
        return ua.NodeId(ua.ObjectIds.Double), True
    if put.kind is WireKind.ENUM:
        cls = put.type
        if isinstance(cls, type) and issubclass(cls, IntEnum):
            return space.enum(cls), False
        return ua.NodeId(ua.ObjectIds.String), False  # an Enum of names: by its name
    standard = {WireKind.NUMBER: ua.ObjectIds.Double, WireKind.INTEGER: ua.ObjectIds.Int32,
                WireKind.BOOL: ua.ObjectIds.Boolean, WireKind.OBJECT: ua.ObjectIds.String}
    return ua.NodeId(standard[put.kind]), False


def _describe(put: WireInput) -> str:
    unit = f" [{put.input.unit}]" if put.input.unit else ""
    if put.required:
        return f"{put.name}{unit}, required"
    default = default_of(put)
    omitted = "omitted or NaN" if put.kind is WireKind.NUMBER else "omitted"
    return f"{put.name}{unit}, optional: {omitted} means {default!r}"


def _method(space: AddressSpace, obj: MachineObject, command: WireCommand, path: str) -> None:
    """A command's method: one node per kind and command, a component of the kind's type
    and of every object that has the command (OPC 10000-4 §5.11.2 lets a client call the
    type's method on an instance); a hundred axes add a hundred references, not a hundred
    copies of 27 methods with their arguments."""
    key = (obj.kind, type(obj.target), command.name,
           tuple((put.name, put.kind, put.type) for put in command.inputs), command.spec.level)
    node = space.shared.get(key)
    if node is None:
        node = space.shared[key] = space.id(_unique(f"type:{obj.kind}:{command.name}", space))
        _method_node(space, node, command, space.id(f"type:{obj.kind}"))
        space.methods[node] = {}
    space.methods[node][space.id(path)] = Served(obj, command)
    reference = ua.AddReferencesItem()
    reference.SourceNodeId = space.id(path)
    reference.ReferenceTypeId = ua.NodeId(ua.ObjectIds.HasComponent)
    reference.IsForward = True
    reference.TargetNodeId = node
    reference.TargetNodeClass = ua.NodeClass.Method
    space.references.append(reference)


def _method_node(space: AddressSpace, node: ua.NodeId, command: WireCommand,
                 parent: ua.NodeId) -> None:
    space.items.append(nodes.method(node, space.name(command.name), parent,
                                    command.spec.doc or command.name))
    arguments = []
    for put in command.inputs:
        datatype, array = input_type(space, put)
        arguments.append(nodes.argument(put.name, datatype, _describe(put), put.length, array))
    if command.spec.level:
        outputs = [nodes.argument("Status", ua.ObjectIds.Boolean, "the level's status now")]
    else:
        outputs = [nodes.argument("Ticket", ua.ObjectIds.UInt32, "the command's number"),
                   nodes.argument("Command", ua.ObjectIds.NodeId,
                                  "its object under Commands: Busy, Done, Error ...")]
    for name, args in (("InputArguments", arguments), ("OutputArguments", outputs)):
        if args:
            space.items.append(nodes.prop(space.id(f"{node.Identifier}#{name}"), name, node,
                                          ua.Variant(args, ua.VariantType.ExtensionObject),
                                          ua.ObjectIds.Argument, array=True))


# -- started commands ---------------------------------------------------------------------------

def command_items(space: AddressSpace, ticket: int, owner: MachineObject, name: str,
                  state: HandleState) -> tuple[ua.NodeId, list[ua.AddNodesItem]]:
    """The object of one started command with its handshake outputs (PLCopen: Busy,
    Active, Done, CommandAborted, Error, ErrorID), named by its ticket."""
    node = space.id(f"Commands/{ticket}")
    items = [nodes.obj(node, space.name(str(ticket)), space.id("Commands"),
                       space.id("type:MotionCommandType"), f"{owner.name}.{name}",
                       ua.ObjectIds.Organizes)]
    fixed = (("Ticket", ua.Variant(ticket, ua.VariantType.UInt32), ua.ObjectIds.UInt32),
             ("Owner", ua.Variant(owner.name, ua.VariantType.String), ua.ObjectIds.String),
             ("Name", ua.Variant(name, ua.VariantType.String), ua.ObjectIds.String))
    for label, value, datatype in fixed:
        items.append(nodes.prop(space.id(f"Commands/{ticket}#{label}"), label, node, value,
                                datatype))
    for label, (value, datatype) in zip(HANDLE_OUTPUTS, handle_values(state), strict=True):
        items.append(nodes.variable(space.id(f"Commands/{ticket}.{label}"), space.name(label),
                                    node, value, ua.NodeId(datatype)))
    return node, items


def handle_values(state: HandleState) -> Iterator[tuple[ua.Variant, int]]:
    """The command object's outputs, in the order of ``HANDLE_OUTPUTS``."""
    for flag in (state.busy, state.active, state.done, state.command_aborted, state.error):
        yield ua.Variant(flag, ua.VariantType.Boolean), ua.ObjectIds.Boolean
    yield ua.Variant(state.error_id, ua.VariantType.UInt32), ua.ObjectIds.UInt32
    yield ua.Variant(state.message, ua.VariantType.String), ua.ObjectIds.String
