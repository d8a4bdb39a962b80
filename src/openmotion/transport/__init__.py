"""Linear transport with collision avoidance: the CA group and its blocks (TF5410)."""

from openmotion.transport.blocks import (
    MC_AddAxisToGroup,
    MC_GroupDisable,
    MC_GroupEnable,
    MC_GroupHalt,
    MC_GroupReadError,
    MC_GroupReadStatus,
    MC_GroupReset,
    MC_GroupStop,
    MC_HaltCA,
    MC_MoveAbsoluteCA,
    MC_MoveRelativeCA,
    MC_RemoveAxisFromGroup,
    MC_UngroupAllAxes,
    ST_HaltCAOptions,
    ST_MoveAbsoluteCAOptions,
    ST_MoveRelativeCAOptions,
)
from openmotion.transport.enums import (
    GapControlDirection,
    GapControlMode,
    GearInPosDefaultDynamicsAfterSync,
    GroupState,
    GroupType,
    ModuloDirection,
)
from openmotion.transport.group import UDINT_TO_IDENTINGROUP, CaGroup, IdentInGroup
from openmotion.transport.parameters import CaGroupParameters

__all__ = [
    "MC_AddAxisToGroup",
    "MC_GroupDisable",
    "MC_GroupEnable",
    "MC_GroupHalt",
    "MC_GroupReadError",
    "MC_GroupReadStatus",
    "MC_GroupReset",
    "MC_GroupStop",
    "MC_HaltCA",
    "MC_MoveAbsoluteCA",
    "MC_MoveRelativeCA",
    "MC_RemoveAxisFromGroup",
    "MC_UngroupAllAxes",
    "ST_HaltCAOptions",
    "ST_MoveAbsoluteCAOptions",
    "ST_MoveRelativeCAOptions",
    "UDINT_TO_IDENTINGROUP",
    "CaGroup",
    "CaGroupParameters",
    "GapControlDirection",
    "GapControlMode",
    "GearInPosDefaultDynamicsAfterSync",
    "GroupState",
    "GroupType",
    "IdentInGroup",
    "ModuloDirection",
]
