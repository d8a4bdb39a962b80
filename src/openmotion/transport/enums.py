"""Enumerations of the CA group (TF5410 §9.1.2, §9.4; Tc3_McCoordinatedMotion §11.1)."""

from __future__ import annotations

from enum import IntEnum

from openmotion.core.enums import ModuloDirection as ModuloDirection  # the CA blocks take it

# the sync engine's, shared with planar tracks (rail/enums.py)
from openmotion.rail.enums import MasterSignalCorrection as MasterSignalCorrection
from openmotion.rail.enums import SyncStrategy as SyncStrategy


class GapControlMode(IntEnum):
    """MC_GAP_CONTROL_MODE (§9.1.2.5); the group default is STANDARD or FAST only."""

    GROUP_DEFAULT = 0
    STANDARD = 1
    FAST = 2
    NONE = 3


class GapControlDirection(IntEnum):
    """MC_GAP_CONTROL_DIRECTION (§6, §8.1.3). The manual gives no numbers (D8 Q6): ours."""

    POSITIVE = 1  #: only the successor keeps the gap to its predecessor
    BOTH = 2  #: a mover moving backwards also keeps the gap to its successor


class GroupState(IntEnum):
    """GroupStatus.State of the cyclic group interface (§11.1)."""

    DISABLED = 1
    STANDBY = 2
    MOVING = 3
    STOPPING = 4
    ERROR_STOP = 5
    HOMING = 6
    NOT_READY = 7
    SUSPENDED = 8


class GearInPosDefaultDynamicsAfterSync(IntEnum):
    """MC_GearInPosDefaultDynamicsAfterSync (§8.1.4)."""

    MAXIMUM_SLAVE_DYNAMICS = 0
    JOB_DYNAMICS = 1


class GroupType(IntEnum):
    """GroupType of the cyclic group interface (§11.1)."""

    INVALID = 0
    CA = 1
    DXD = 2


class SyncMode(IntEnum):
    """MC_SYNC_MODE (§9.4.1.4): how SlaveSyncPosition is read on a ring."""

    NON_MODULO = 0
    POSITIVE = 1
    NEGATIVE = 3


class CompensationType(IntEnum):
    """MC_COMPENSATION_TYPE of Tc3_McCompensations (§9.4.1.2)."""

    INVALID = 0  #: mcTypeInvalidCompensation
    GEO = 1  #: mcTypeGeoCompensation
