"""The enumerations of the sync engine (gear.py), which CA rails and planar tracks share;
``openmotion.transport`` exports them as the TF5410 blocks name them."""

from __future__ import annotations

from enum import IntEnum


class SyncStrategy(IntEnum):
    """MC_SYNC_STRATEGY (§9.4.1.5)."""

    LATE = 1
    SLOW = 2
    EARLY = 3


class MasterSignalCorrection(IntEnum):
    """MC_MASTER_SIGNAL_CORRECTION (§9.1.2.6): whether MC_GearInPosCA corrects the master's
    signal (D-205)."""

    AUTO = 0
    NONE = 1
