"""Planar motion (TF5430): maglev movers on a stator surface, planar groups, parts, feedback."""

from openmotion.planar.enums import (
    CoordinateMode,
    ExternalSetPositionMode,
    ModuloDirection,
    MoverCommandMode,
    PlanarObjectType,
    PlanarState,
    SyncDirections,
    TrackOperationMode,
)
from openmotion.planar.environment import MC_PlanarEnvironment, MC_PlanarPart
from openmotion.planar.feedback import (
    CommandPhase,
    MC_PlanarFeedback,
    MC_PlanarFeedbackBase,
    PlanarCommand,
    PlanarObjectInfo,
)
from openmotion.planar.frames import Pose
from openmotion.planar.group import MC_PlanarGroup
from openmotion.planar.mover import MC_PlanarMover
from openmotion.planar.options import (
    DynamicConstraint_PathXY,
    IPlcDynamicConstraint,
    MoverVector,
    PlanarMoverParameters,
    ST_ExternalSetpointGenerationOptions,
    ST_MoveCOptions,
    ST_MoveToPositionOptions,
)
from openmotion.planar.parts import Part, PartLayout, PartPosition
from openmotion.planar.positions import PositionXYC
from openmotion.planar.stators import StatorField
from openmotion.planar.system import PlanarSystem

__all__ = [
    "CommandPhase",
    "CoordinateMode",
    "DynamicConstraint_PathXY",
    "ExternalSetPositionMode",
    "IPlcDynamicConstraint",
    "MC_PlanarEnvironment",
    "MC_PlanarFeedback",
    "MC_PlanarFeedbackBase",
    "MC_PlanarGroup",
    "MC_PlanarMover",
    "MC_PlanarPart",
    "ModuloDirection",
    "MoverCommandMode",
    "MoverVector",
    "Part",
    "PartLayout",
    "PartPosition",
    "PlanarCommand",
    "PlanarMoverParameters",
    "PlanarObjectInfo",
    "PlanarObjectType",
    "PlanarState",
    "PlanarSystem",
    "Pose",
    "PositionXYC",
    "ST_ExternalSetpointGenerationOptions",
    "ST_MoveCOptions",
    "ST_MoveToPositionOptions",
    "StatorField",
    "SyncDirections",
    "TrackOperationMode",
]
