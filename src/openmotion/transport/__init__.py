"""Linear transport with collision avoidance: the CA group and its blocks (TF5410)."""

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
