"""openmotion: a deterministic PLCopen motion-control runtime and simulator."""

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.axis.drive import DriveModel
from openmotion.axis.parameters import AxisPara, AxisParameters
from openmotion.core.enums import (
    AxisState,
    BufferMode,
    DecoupleMode,
    Direction,
    NewPosAndVeloMode,
    ReadMode,
    ReferenceMode,
    SuperpositionMode,
    TargetPositionType,
)
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.core.special_values import (
    DEFAULT_HOME_POSITION,
    MC_DEFAULT,
    MC_IGNORE,
    MC_INVALID,
    MC_MAXIMUM,
)
from openmotion.runtime.paced import FallingBehindError, PacedRuntime
from openmotion.runtime.runtime import Runtime

__version__ = "0.1.0"

__all__ = [
    "DEFAULT_HOME_POSITION",
    "MC_DEFAULT",
    "MC_IGNORE",
    "MC_INVALID",
    "MC_MAXIMUM",
    "Axis",
    "AxisPara",
    "AxisParameters",
    "AxisState",
    "BufferMode",
    "Command",
    "CommandStatus",
    "ConfigError",
    "DecoupleMode",
    "Direction",
    "DriveModel",
    "ErrorId",
    "FallingBehindError",
    "NewPosAndVeloMode",
    "PacedRuntime",
    "ReadMode",
    "ReferenceMode",
    "Runtime",
    "SuperpositionMode",
    "TargetPositionType",
    "__version__",
]
