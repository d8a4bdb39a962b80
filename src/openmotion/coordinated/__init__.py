"""PLCopen Part 4 coordinated motion: axes groups, their blocks, frames and kinematics.

The public names load their modules on first use (PEP 562, as the top-level package does,
D-173): the scenario schema and the CLI read ``coordinated.inputs`` without the path
planner. Short block names (``MC_MoveLinAbs``, §1.3.1) stay in ``coordinated.blocks`` (D-224).
"""

# ruff: noqa: N801 - the standard's block names

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_BLOCKS = "openmotion.coordinated.blocks"

_WHERE = {
    # the blocks (§5, §6); the administration ones are the CA group's classes (D-113)
    "MC_AddAxisToGroup": _BLOCKS,
    "MC_GroupContinue": _BLOCKS,
    "MC_GroupDisable": _BLOCKS,
    "MC_GroupEnable": _BLOCKS,
    "MC_GroupHalt": _BLOCKS,
    "MC_GroupHome": _BLOCKS,
    "MC_GroupInterrupt": _BLOCKS,
    "MC_GroupReadActualAcceleration": _BLOCKS,
    "MC_GroupReadActualPosition": _BLOCKS,
    "MC_GroupReadActualVelocity": _BLOCKS,
    "MC_GroupReadConfiguration": _BLOCKS,
    "MC_GroupReadError": _BLOCKS,
    "MC_GroupReadStatus": _BLOCKS,
    "MC_GroupReset": _BLOCKS,
    "MC_GroupSetOverride": _BLOCKS,
    "MC_GroupSetPosition": _BLOCKS,
    "MC_GroupStop": _BLOCKS,
    "MC_MoveCircularAbsolute": _BLOCKS,
    "MC_MoveCircularRelative": _BLOCKS,
    "MC_MoveDirectAbsolute": _BLOCKS,
    "MC_MoveDirectRelative": _BLOCKS,
    "MC_MoveLinearAbsolute": _BLOCKS,
    "MC_MoveLinearRelative": _BLOCKS,
    "MC_MovePath": _BLOCKS,
    "MC_PathSelect": _BLOCKS,
    "MC_ReadCartesianTransform": _BLOCKS,
    "MC_ReadCoordinateTransform": _BLOCKS,
    "MC_ReadKinTransform": _BLOCKS,
    "MC_RemoveAxisFromGroup": _BLOCKS,
    "MC_SetCartesianTransform": _BLOCKS,
    "MC_SetCoordinateTransform": _BLOCKS,
    "MC_SetDynCoordTransform": _BLOCKS,
    "MC_SetKinTransform": _BLOCKS,
    "MC_SyncAxisToGroup": _BLOCKS,
    "MC_SyncGroupToAxis": _BLOCKS,
    "MC_TrackConveyorBelt": _BLOCKS,
    "MC_TrackRotaryTable": _BLOCKS,
    "MC_UngroupAllAxes": _BLOCKS,
    # the objects
    "AxesGroup": "openmotion.coordinated.group",
    "CoordinateView": _BLOCKS,
    "CartesianTransform": "openmotion.coordinated.frames",
    "DynamicFrame": "openmotion.coordinated.frames",
    "Frame": "openmotion.coordinated.frames",
    "FrameMotion": "openmotion.coordinated.frames",
    "LinearFrame": "openmotion.coordinated.frames",
    "CartesianGantry": "openmotion.coordinated.kinematics",
    "DeltaRobot": "openmotion.coordinated.kinematics",
    "Kinematics": "openmotion.coordinated.kinematics",
    "Scara": "openmotion.coordinated.kinematics",
    "PathData": "openmotion.coordinated.paths",
    # enums and option types
    "AxesGroupState": "openmotion.coordinated.states",
    "ExecutionMode": "openmotion.coordinated.states",
    "CircMode": "openmotion.geometry.path",
    "PathChoice": "openmotion.geometry.path",
    "Configuration": "openmotion.coordinated.kinematics",
    "CoordSystem": "openmotion.coordinated.inputs",
    "PathDynamics": "openmotion.coordinated.inputs",
    "TransitionMode": "openmotion.coordinated.inputs",
    "PathMode": "openmotion.coordinated.cam",
    # TF5410 §9.3 path tables (path_table.py)
    "McTransitionMode": "openmotion.coordinated.path_table",
    "McCircMode": "openmotion.coordinated.path_table",
    "McCircPathChoice": "openmotion.coordinated.path_table",
    "MC_COORD_REF": "openmotion.coordinated.path_table",
    "MC_PATH_DATA_REF": "openmotion.coordinated.path_table",
    "MC_MoveLinearAbsolutePreparation": "openmotion.coordinated.path_table",
    "MC_MoveCircularAbsolutePreparation": "openmotion.coordinated.path_table",
    "MC_BlockerPreparation": "openmotion.coordinated.path_table",
    "MC_DwellTimePreparation": "openmotion.coordinated.path_table",
    "MC_SetCoordinateTransformPreparation": "openmotion.coordinated.path_table",
    "MC_ReleaseBlocker": "openmotion.coordinated.path_table",
    "MC_GroupReadBlockerStatus": "openmotion.coordinated.path_table",
}

__all__ = [
    "AxesGroup",
    "AxesGroupState",
    "CartesianGantry",
    "CartesianTransform",
    "CircMode",
    "Configuration",
    "CoordSystem",
    "CoordinateView",
    "DeltaRobot",
    "DynamicFrame",
    "ExecutionMode",
    "Frame",
    "FrameMotion",
    "Kinematics",
    "LinearFrame",
    "MC_AddAxisToGroup",
    "MC_BlockerPreparation",
    "MC_COORD_REF",
    "MC_DwellTimePreparation",
    "MC_GroupContinue",
    "MC_GroupDisable",
    "MC_GroupEnable",
    "MC_GroupHalt",
    "MC_GroupHome",
    "MC_GroupInterrupt",
    "MC_GroupReadActualAcceleration",
    "MC_GroupReadActualPosition",
    "MC_GroupReadActualVelocity",
    "MC_GroupReadBlockerStatus",
    "MC_GroupReadConfiguration",
    "MC_GroupReadError",
    "MC_GroupReadStatus",
    "MC_GroupReset",
    "MC_GroupSetOverride",
    "MC_GroupSetPosition",
    "MC_GroupStop",
    "MC_MoveCircularAbsolute",
    "MC_MoveCircularAbsolutePreparation",
    "MC_MoveCircularRelative",
    "MC_MoveDirectAbsolute",
    "MC_MoveDirectRelative",
    "MC_MoveLinearAbsolute",
    "MC_MoveLinearAbsolutePreparation",
    "MC_MoveLinearRelative",
    "MC_MovePath",
    "MC_PATH_DATA_REF",
    "MC_PathSelect",
    "MC_ReadCartesianTransform",
    "MC_ReadCoordinateTransform",
    "MC_ReadKinTransform",
    "MC_ReleaseBlocker",
    "MC_RemoveAxisFromGroup",
    "MC_SetCartesianTransform",
    "MC_SetCoordinateTransform",
    "MC_SetCoordinateTransformPreparation",
    "MC_SetDynCoordTransform",
    "MC_SetKinTransform",
    "MC_SyncAxisToGroup",
    "MC_SyncGroupToAxis",
    "MC_TrackConveyorBelt",
    "MC_TrackRotaryTable",
    "MC_UngroupAllAxes",
    "McCircMode",
    "McCircPathChoice",
    "McTransitionMode",
    "PathChoice",
    "PathData",
    "PathDynamics",
    "PathMode",
    "Scara",
    "TransitionMode",
]


def __getattr__(name: str) -> Any:
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module 'openmotion.coordinated' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:
    from openmotion.coordinated.blocks import (
        CoordinateView,
        MC_AddAxisToGroup,
        MC_GroupContinue,
        MC_GroupDisable,
        MC_GroupEnable,
        MC_GroupHalt,
        MC_GroupHome,
        MC_GroupInterrupt,
        MC_GroupReadActualAcceleration,
        MC_GroupReadActualPosition,
        MC_GroupReadActualVelocity,
        MC_GroupReadConfiguration,
        MC_GroupReadError,
        MC_GroupReadStatus,
        MC_GroupReset,
        MC_GroupSetOverride,
        MC_GroupSetPosition,
        MC_GroupStop,
        MC_MoveCircularAbsolute,
        MC_MoveCircularRelative,
        MC_MoveDirectAbsolute,
        MC_MoveDirectRelative,
        MC_MoveLinearAbsolute,
        MC_MoveLinearRelative,
        MC_MovePath,
        MC_PathSelect,
        MC_ReadCartesianTransform,
        MC_ReadCoordinateTransform,
        MC_ReadKinTransform,
        MC_RemoveAxisFromGroup,
        MC_SetCartesianTransform,
        MC_SetCoordinateTransform,
        MC_SetDynCoordTransform,
        MC_SetKinTransform,
        MC_SyncAxisToGroup,
        MC_SyncGroupToAxis,
        MC_TrackConveyorBelt,
        MC_TrackRotaryTable,
        MC_UngroupAllAxes,
    )
    from openmotion.coordinated.cam import PathMode
    from openmotion.coordinated.frames import (
        CartesianTransform,
        DynamicFrame,
        Frame,
        FrameMotion,
        LinearFrame,
    )
    from openmotion.coordinated.group import AxesGroup
    from openmotion.coordinated.inputs import CoordSystem, PathDynamics, TransitionMode
    from openmotion.coordinated.kinematics import (
        CartesianGantry,
        Configuration,
        DeltaRobot,
        Kinematics,
        Scara,
    )
    from openmotion.coordinated.path_table import (
        MC_COORD_REF,
        MC_PATH_DATA_REF,
        MC_BlockerPreparation,
        MC_DwellTimePreparation,
        MC_GroupReadBlockerStatus,
        MC_MoveCircularAbsolutePreparation,
        MC_MoveLinearAbsolutePreparation,
        MC_ReleaseBlocker,
        MC_SetCoordinateTransformPreparation,
        McCircMode,
        McCircPathChoice,
        McTransitionMode,
    )
    from openmotion.coordinated.paths import PathData
    from openmotion.coordinated.states import AxesGroupState, ExecutionMode
    from openmotion.geometry.path import CircMode, PathChoice
