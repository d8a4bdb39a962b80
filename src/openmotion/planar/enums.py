"""Enumerations of the planar library (TF5430 §7.2.1.1; §4 for the ones without numbers).

Where §7 prints values they are kept exactly. The state, command-mode, track-mode and
set-position-mode enums appear only by name in the manual (watch windows, §4): their
numbers are ours (docs/decisions.md).
"""

from __future__ import annotations

from enum import IntEnum

from openmotion.core.enums import ModuloDirection as ModuloDirection  # MC_DIRECTION, §7.2.1.1.2


class PlanarObjectType(IntEnum):
    """EPlanarObjectType (§7.2.1.1.1): the kind of object a feedback names. No Group, no Part."""

    INVALID = 0  #: the information is not valid (no connection, component not ready)
    NONE = 301
    MOVER = 302
    TRACK = 303
    ENVIRONMENT = 304


class SyncDirections(IntEnum):
    """MC_SYNC_DIRECTIONS (§7.2.1.1.3): directions a slave may move in while it syncs."""

    POSITIVE = 1
    NEGATIVE = 2
    BOTH = 3


class PlanarState(IntEnum):
    """MC_PLANAR_STATE (§4.1), for movers, tracks, groups and the environment."""

    DISABLED = 0
    ENABLING = 1
    ENABLED = 2
    DISABLING = 3
    RESETTING = 4
    ERROR_PENDING = 5
    ERROR = 6


class MoverCommandMode(IntEnum):
    """MC_PLANAR_MOVER_COMMAND_MODE (§4.2): which commands a mover accepts now."""

    FREE_MOVEMENT = 0
    ON_TRACK = 1
    JOINING_TRACK = 2
    LEAVING_TRACK = 3
    C_ROTATION_FREE_MOVEMENT = 4
    C_ROTATION_ON_TRACK = 5
    EXTERNAL_SETPOINT_GENERATION = 6


class TrackOperationMode(IntEnum):
    """MC_PLANAR_TRACK_OPERATION_MODE (§4.3)."""

    UNINITIALIZED = 0
    CONFIGURING = 1
    STANDING = 2
    MOVING = 3


class ExternalSetPositionMode(IntEnum):
    """MC_EXTERNAL_SET_POSITION_MODE (§6.1.1, §7.2.1.2.6). NONE shows it is off."""

    NONE = 0
    ABSOLUTE = 1
    RELATIVE = 2


class CoordinateMode(IntEnum):
    """MC_PLANAR_COORDINATE_MODE (§6.2.7): C follows the track or is moved on its own."""

    DEPENDENT = 0
    INDEPENDENT = 1
