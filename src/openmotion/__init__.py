"""openmotion: a deterministic PLCopen motion-control runtime and simulator.

The public names load their modules on first use (PEP 562): ``openmotion --help``, ``check``
and the scenario tools start without the trajectory kernels.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from openmotion.core.lazy import lazy_exports

__version__ = "0.1.0"

_WHERE = {
    "Axis": "openmotion.axis.axis",
    "Command": "openmotion.axis.commands",
    "CommandStatus": "openmotion.axis.commands",
    "DriveModel": "openmotion.axis.drive",
    "AxisPara": "openmotion.axis.parameters",
    "AxisParameters": "openmotion.axis.parameters",
    "AxisState": "openmotion.core.enums",
    "BufferMode": "openmotion.core.enums",
    "DecoupleMode": "openmotion.core.enums",
    "Direction": "openmotion.core.enums",
    "NewPosAndVeloMode": "openmotion.core.enums",
    "ReadMode": "openmotion.core.enums",
    "ReferenceMode": "openmotion.core.enums",
    "SuperpositionMode": "openmotion.core.enums",
    "TargetPositionType": "openmotion.core.enums",
    "ConfigError": "openmotion.core.errors",
    "ErrorId": "openmotion.core.errors",
    "DEFAULT_HOME_POSITION": "openmotion.core.special_values",
    "MC_DEFAULT": "openmotion.core.special_values",
    "MC_IGNORE": "openmotion.core.special_values",
    "MC_INVALID": "openmotion.core.special_values",
    "MC_MAXIMUM": "openmotion.core.special_values",
    "FallingBehindError": "openmotion.runtime.paced",
    "PacedRuntime": "openmotion.runtime.paced",
    "Runtime": "openmotion.runtime.runtime",
}

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


__getattr__, __dir__ = lazy_exports(__name__, _WHERE, __all__)


if TYPE_CHECKING:
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
