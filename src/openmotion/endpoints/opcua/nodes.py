"""OPC UA nodes as the server adds them: items of an AddNodes request, units, data types.

Only the standard types of OPC 10000-3/-5/-8 are used: objects with HasComponent children,
``AnalogUnitType`` variables carrying ``EngineeringUnits`` (UNECE codes, OPC 10000-8
§5.6.3), enumerations as ``Enumeration`` subtypes with ``EnumValues``, methods with
``InputArguments``/``OutputArguments`` properties.
"""

from __future__ import annotations

from enum import IntEnum
from typing import Any

from asyncua import ua

__all__ = ["UNECE", "UNITS_URI", "argument", "data_type", "eu_information", "method", "obj",
           "object_type", "prop", "variable"]

UNITS_URI = "http://www.opcfoundation.org/UA/units/un/cefact"
#: the units signals and inputs carry, by their symbol: (UNECE common code, name); a unit
#: without a common code has none ("" : UnitId -1, OPC 10000-8 §5.6.3)
UNECE: dict[str, tuple[str, str]] = {
    "mm": ("MMT", "millimetre"), "mm/s": ("C16", "millimetre per second"),
    "mm/s²": ("M41", "millimetre per second squared"),
    "mm/s³": ("", "millimetre per second cubed"),
    "°": ("DD", "degree"), "°/s": ("E96", "degree per second"),
    "°/s²": ("M45", "degree per second squared"), "%": ("P1", "percent"),
    "s": ("SEC", "second"), "ms": ("C26", "millisecond"),
}
READ = ua.AccessLevel.CurrentRead.mask


def eu_information(unit: str) -> ua.EUInformation:
    """The EngineeringUnits of a unit symbol: its UNECE code as UnitId (three characters,
    one byte each) where it has one."""
    code, name = UNECE.get(unit, ("", unit))
    unit_id = -1
    if code:
        unit_id = 0
        for char in code:
            unit_id = (unit_id << 8) | ord(char)
    return ua.EUInformation(NamespaceUri=UNITS_URI, UnitId=unit_id,
                            DisplayName=ua.LocalizedText(unit), Description=ua.LocalizedText(name))


def _item(nodeid: ua.NodeId, name: ua.QualifiedName, parent: ua.NodeId, reference: int,
          node_class: ua.NodeClass, attributes: Any, typedef: ua.NodeId | None = None) \
        -> ua.AddNodesItem:
    item = ua.AddNodesItem()
    item.RequestedNewNodeId = nodeid
    item.BrowseName = name
    item.ParentNodeId = parent
    item.ReferenceTypeId = ua.NodeId(reference)
    item.NodeClass = node_class
    if typedef is not None:
        item.TypeDefinition = typedef
    item.NodeAttributes = attributes
    return item


def _named(attributes: Any, name: str, description: str) -> Any:
    attributes.DisplayName = ua.LocalizedText(name)
    attributes.Description = ua.LocalizedText(description or name)
    attributes.WriteMask = 0
    attributes.UserWriteMask = 0
    return attributes


def obj(nodeid: ua.NodeId, name: ua.QualifiedName, parent: ua.NodeId, typedef: ua.NodeId,
        description: str = "", reference: int = ua.ObjectIds.HasComponent) -> ua.AddNodesItem:
    attributes = _named(ua.ObjectAttributes(), name.Name, description)
    attributes.EventNotifier = 0
    return _item(nodeid, name, parent, reference, ua.NodeClass.Object, attributes, typedef)


def object_type(nodeid: ua.NodeId, name: ua.QualifiedName, description: str = "") \
        -> ua.AddNodesItem:
    attributes = _named(ua.ObjectTypeAttributes(), name.Name, description)
    attributes.IsAbstract = False
    return _item(nodeid, name, ua.NodeId(ua.ObjectIds.BaseObjectType), ua.ObjectIds.HasSubtype,
                 ua.NodeClass.ObjectType, attributes)


def variable(nodeid: ua.NodeId, name: ua.QualifiedName, parent: ua.NodeId, value: ua.Variant,
             datatype: ua.NodeId, *, typedef: int = ua.ObjectIds.BaseDataVariableType,
             description: str = "", interval_ms: float = 0.0,
             reference: int = ua.ObjectIds.HasComponent) -> ua.AddNodesItem:
    """A read-only variable (signals and command outputs: clients never write them)."""
    attributes = _named(ua.VariableAttributes(), name.Name, description)
    attributes.Value = value
    attributes.DataType = datatype
    attributes.ValueRank = ua.ValueRank.Scalar
    attributes.AccessLevel = READ
    attributes.UserAccessLevel = READ
    attributes.MinimumSamplingInterval = interval_ms
    attributes.Historizing = False
    return _item(nodeid, name, parent, reference, ua.NodeClass.Variable, attributes,
                 ua.NodeId(typedef))


def prop(nodeid: ua.NodeId, name: str, parent: ua.NodeId, value: ua.Variant,
         datatype: int | ua.NodeId, *, array: bool = False) -> ua.AddNodesItem:
    attributes = _named(ua.VariableAttributes(), name, "")
    attributes.Value = value
    attributes.DataType = datatype if isinstance(datatype, ua.NodeId) else ua.NodeId(datatype)
    attributes.ValueRank = ua.ValueRank.OneDimension if array else ua.ValueRank.Scalar
    if array:
        attributes.ArrayDimensions = [0]
    attributes.AccessLevel = READ
    attributes.UserAccessLevel = READ
    return _item(nodeid, ua.QualifiedName(name, 0), parent, ua.ObjectIds.HasProperty,
                 ua.NodeClass.Variable, attributes, ua.NodeId(ua.ObjectIds.PropertyType))


def method(nodeid: ua.NodeId, name: ua.QualifiedName, parent: ua.NodeId, description: str) \
        -> ua.AddNodesItem:
    attributes = _named(ua.MethodAttributes(), name.Name, description)
    attributes.Executable = True
    attributes.UserExecutable = True
    return _item(nodeid, name, parent, ua.ObjectIds.HasComponent, ua.NodeClass.Method,
                 attributes)


def argument(name: str, datatype: ua.NodeId | int, description: str = "",
             length: int | None = None, array: bool = False) -> ua.Argument:
    """One method argument; an array of ``length`` numbers (0: any) when ``array``."""
    arg = ua.Argument()
    arg.Name = name
    arg.DataType = datatype if isinstance(datatype, ua.NodeId) else ua.NodeId(datatype)
    arg.ValueRank = ua.ValueRank.OneDimension if array else ua.ValueRank.Scalar
    arg.ArrayDimensions = [length or 0] if array else []
    arg.Description = ua.LocalizedText(description)
    return arg


def data_type(nodeid: ua.NodeId, cls: type[IntEnum], namespace: int) \
        -> tuple[list[ua.AddNodesItem], ua.EnumDefinition]:
    """An ``Enumeration`` subtype for an IntEnum: the data type node, its ``EnumValues``
    property (for clients of OPC UA 1.03) and its definition (1.04 and later)."""
    qname = ua.QualifiedName(cls.__name__, namespace)
    attributes = _named(ua.DataTypeAttributes(), cls.__name__,
                        (cls.__doc__ or "").strip().split("\n")[0])
    attributes.IsAbstract = False
    node = _item(nodeid, qname, ua.NodeId(ua.ObjectIds.Enumeration), ua.ObjectIds.HasSubtype,
                 ua.NodeClass.DataType, attributes)
    values = [ua.EnumValueType(Value=int(member), DisplayName=ua.LocalizedText(member.name),
                               Description=ua.LocalizedText(member.name)) for member in cls]
    definition = ua.EnumDefinition(Fields=[
        ua.EnumField(Value=int(member), DisplayName=ua.LocalizedText(member.name),
                     Description=ua.LocalizedText(member.name), Name=member.name)
        for member in cls])
    enum_values = prop(ua.NodeId(f"{nodeid.Identifier}#EnumValues", namespace), "EnumValues",
                       nodeid, ua.Variant(values, ua.VariantType.ExtensionObject),
                       ua.ObjectIds.EnumValueType, array=True)
    return [node, enum_values], definition
