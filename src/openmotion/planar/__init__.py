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
    MC_PlanarFeedbackGearInPosOnTrack,
    MC_PlanarFeedbackGearInPosOnTrackWithMasterMover,
    PlanarCommand,
    PlanarObjectInfo,
)
from openmotion.planar.frames import Pose
from openmotion.planar.gearing import MC_PlanarTrackTrail
from openmotion.planar.group import MC_PlanarGroup
from openmotion.planar.mover import MC_PlanarMover
from openmotion.planar.options import (
    DynamicConstraint_PathXY,
    IPlcDynamicConstraint,
    MoverVector,
    PlanarMoverParameters,
    ST_EndAtTrackAdvancedOptions,
    ST_ExternalSetpointGenerationOptions,
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    ST_JoinTrackOptions,
    ST_LeaveTrackOptions,
    ST_MoveCOptions,
    ST_MoveOnTrackOptions,
    ST_MoveToPositionOptions,
    ST_StartFromTrackAdvancedOptions,
)
from openmotion.planar.parts import Part, PartLayout, PartPosition
from openmotion.planar.positions import PositionXYC
from openmotion.planar.stators import StatorField
from openmotion.planar.system import PlanarSystem
from openmotion.planar.track import MC_PlanarTrack

__all__ = [
    "CommandPhase",
    "CoordinateMode",
    "DynamicConstraint_PathXY",
    "ExternalSetPositionMode",
    "IPlcDynamicConstraint",
    "MC_PlanarEnvironment",
    "MC_PlanarFeedback",
    "MC_PlanarFeedbackBase",
    "MC_PlanarFeedbackGearInPosOnTrack",
    "MC_PlanarFeedbackGearInPosOnTrackWithMasterMover",
    "MC_PlanarGroup",
    "MC_PlanarMover",
    "MC_PlanarPart",
    "MC_PlanarTrack",
    "MC_PlanarTrackTrail",
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
    "ST_EndAtTrackAdvancedOptions",
    "ST_ExternalSetpointGenerationOptions",
    "ST_GearInPosOnTrackOptions",
    "ST_GearInPosOnTrackWithMasterMoverOptions",
    "ST_JoinTrackOptions",
    "ST_LeaveTrackOptions",
    "ST_MoveCOptions",
    "ST_MoveOnTrackOptions",
    "ST_MoveToPositionOptions",
    "ST_StartFromTrackAdvancedOptions",
    "StatorField",
    "SyncDirections",
    "TrackOperationMode",
]
