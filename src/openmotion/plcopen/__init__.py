"""PLCopen single-axis function blocks of the TcMC library, with their manual names."""

from openmotion.kernel.handshake import EnableBlock, ExecuteBlock, FunctionBlock
from openmotion.plcopen.admin import (
    MC_ChangeDynParam,
    MC_Reset,
    MC_SetActualPosition,
    MC_SetOverride,
)
from openmotion.plcopen.external import (
    MC_ExtSetPointGenDisable,
    MC_ExtSetPointGenEnable,
    MC_ExtSetPointGenFeed,
)
from openmotion.plcopen.gear import (
    MC_GearIn,
    MC_GearInDyn,
    MC_GearInFloat,
    MC_GearOut,
    MC_GearOutExt,
)
from openmotion.plcopen.home import MC_Home
from openmotion.plcopen.jog import JogMode, MC_Jog
from openmotion.plcopen.move import (
    MC_MoveAbsolute,
    MC_MoveAbsoluteOrRestart,
    MC_MoveModulo,
    MC_MoveRelative,
    MC_MoveVelocity,
)
from openmotion.plcopen.newpos import MC_NewPos, MC_NewPosAndVelo
from openmotion.plcopen.override_filter import MC_OverrideFilter
from openmotion.plcopen.parameters import (
    MC_ReadBoolParameter,
    MC_ReadParameter,
    MC_ReadParameterSet,
    MC_WriteBoolParameter,
    MC_WriteParameter,
)
from openmotion.plcopen.power import MC_Power
from openmotion.plcopen.read import MC_ReadActualPosition, MC_ReadAxisError, MC_ReadStatus
from openmotion.plcopen.reference import MC_ReadAxisComponents, MC_SetReferenceFlag
from openmotion.plcopen.stepper import (
    DestallDetectMode,
    DestallMode,
    MC_PowerStepper,
    PowerStepperParams,
)
from openmotion.plcopen.stop import MC_Halt, MC_Stop
from openmotion.plcopen.stop_ext import MC_OrientedStop, MC_SetActualPositionOnTheFly
from openmotion.plcopen.superposition import (
    MC_AbortSuperposition,
    MC_MoveSuperImposed,
    MC_MoveSuperImposedExt,
)
from openmotion.plcopen.touch_probe import (
    InputRef,
    MC_AbortTrigger,
    MC_TouchProbe,
    SignalEdge,
    TouchProbeSource,
    TouchProbeState,
)
from openmotion.plcopen.version import F_GetVersionTcMC

__all__ = [
    "DestallDetectMode",
    "DestallMode",
    "EnableBlock",
    "F_GetVersionTcMC",
    "ExecuteBlock",
    "FunctionBlock",
    "InputRef",
    "JogMode",
    "MC_AbortSuperposition",
    "MC_AbortTrigger",
    "MC_ChangeDynParam",
    "MC_ExtSetPointGenDisable",
    "MC_ExtSetPointGenEnable",
    "MC_ExtSetPointGenFeed",
    "MC_GearIn",
    "MC_GearInDyn",
    "MC_GearInFloat",
    "MC_GearOut",
    "MC_GearOutExt",
    "MC_Halt",
    "MC_Home",
    "MC_Jog",
    "MC_MoveAbsolute",
    "MC_MoveAbsoluteOrRestart",
    "MC_MoveModulo",
    "MC_MoveRelative",
    "MC_MoveSuperImposed",
    "MC_MoveSuperImposedExt",
    "MC_MoveVelocity",
    "MC_NewPos",
    "MC_NewPosAndVelo",
    "MC_OrientedStop",
    "MC_OverrideFilter",
    "MC_Power",
    "MC_PowerStepper",
    "MC_ReadActualPosition",
    "MC_ReadAxisComponents",
    "MC_ReadAxisError",
    "MC_ReadBoolParameter",
    "MC_ReadParameter",
    "MC_ReadParameterSet",
    "MC_ReadStatus",
    "MC_Reset",
    "MC_SetActualPosition",
    "MC_SetActualPositionOnTheFly",
    "MC_SetOverride",
    "MC_SetReferenceFlag",
    "MC_Stop",
    "MC_TouchProbe",
    "MC_WriteBoolParameter",
    "MC_WriteParameter",
    "PowerStepperParams",
    "SignalEdge",
    "TouchProbeSource",
    "TouchProbeState",
]
