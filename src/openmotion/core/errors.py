"""Error ids and exceptions.

FBs never raise during a cycle: they report ``error_id`` from ``ErrorId``. Vendor numbers are
used where a manual names one (TcMC §3.9, §4.20, §6.7). Every other id is openmotion's own and
lives in 0x7000-0x7FFF so that it cannot be mistaken for a TwinCAT NC code (docs/decisions.md,
D-004).
"""

from __future__ import annotations

from enum import IntEnum


class ErrorId(IntEnum):
    NO_ERROR = 0
    # vendor numbers named by TcMC
    SUPERPOSITION_INCOMPLETE = 0x4243  #: TcMC §3.9: compensated only partly
    DYN_VELOCITY_EXCEEDED = 0x423A  #: TcMC §4.20: would exceed the travel velocity
    DYN_STRICTER_STOP_ACTIVE = 0x425D  #: TcMC §4.20: a stricter stop is in progress
    DYN_OPTIMISATION_FAILED = 0x427E  #: TcMC §4.20: internal optimisation not possible
    DYN_TARGET_OVERSHOT = 0x427F  #: TcMC §4.20: the target would be overshot
    DYN_DIRECTION_REVERSAL = 0x4289  #: TcMC §4.20: braking would reverse the direction
    STEPPER_STALL = 0x4636  #: TcMC §6.7: stepper stall
    # openmotion: bad input values (0x70xx)
    INVALID_POSITION = 0x7001  #: a position or distance input is missing or not finite
    INVALID_VELOCITY = 0x7002  #: velocity missing, not > 0, or MC_DEFAULT (has no default)
    INVALID_ACCELERATION = 0x7003  #: acceleration not > 0 (0 means default)
    INVALID_DECELERATION = 0x7004  #: deceleration not > 0 (0 means default)
    INVALID_JERK = 0x7005  #: jerk not > 0, or above the axis max_jerk
    INVALID_DIRECTION = 0x7006  #: not an MC_Direction, or not allowed for this block
    INVALID_BUFFER_MODE = 0x7007  #: not an MC_BUFFER_MODE
    INVALID_OVERRIDE = 0x7008  #: override outside 0..100 %
    INVALID_MODULO_TARGET = 0x7009  #: shortest way with a target outside [0, period)
    INVALID_MODULO_PERIOD = 0x700A  #: modulo period not > 0
    INVALID_PARAMETER_NUMBER = 0x7010  #: no such MC_AxisPara number (TcMC §6.1)
    PARAMETER_TYPE_MISMATCH = 0x7011  #: a bool parameter read or written as a number, or back
    PARAMETER_READ_ONLY = 0x7012  #: a status parameter (1, 10, 11, 1000, 2000-2002)
    INVALID_PARAMETER_VALUE = 0x7013  #: the value would make the parameter set invalid
    INVALID_STOP_DYNAMICS = 0x7014  #: reserved for stop inputs
    INVALID_MODE = 0x7015  #: an unknown mode enum value
    INVALID_GEAR_RATIO = 0x7016  #: a gear ratio that is not finite, or a zero denominator
    INVALID_GAP = 0x7017  #: a CA gap that is not a finite number >= 0 (TF5410 §9.1.1.1)
    INVALID_TARGET_POSITION = 0x7018  #: TF5410 §11.3: modulo target outside [0, rail length]
    INVALID_ADDITIONAL_TURNS = 0x7019  #: TF5410 §11.3: turns > 0 with NonModulo/ShortestWay
    INVALID_IDENT = 0x701A  #: IdentInGroup is not a UDINT_TO_IDENTINGROUP value
    INVALID_SYNC_OPTIONS = 0x701B  #: MC_GearInPosCA: under- and overshoot both forbidden
    # openmotion: state and command rejections (0x71xx)
    AXIS_DISABLED = 0x7101  #: the axis is not powered (MC_Power.Status FALSE)
    AXIS_IN_ERROR_STOP = 0x7102  #: the axis is in ErrorStop: MC_Reset first
    AXIS_STOPPING = 0x7103  #: MC_Stop holds the axis (PLCopen Stopping state)
    AXIS_HOMING = 0x7104  #: homing in progress
    AXIS_NOT_MOVING = 0x7105  #: the command needs a moving axis (MC_NewPos)
    AXIS_NOT_STANDSTILL = 0x7106  #: the command needs a standing axis
    TARGET_BEYOND_SOFT_LIMIT = 0x7107  #: the target lies beyond an enabled software limit
    PATH_BEYOND_SOFT_LIMIT = 0x7108  #: the profile would pass a software limit on the way
    NO_PROFILE = 0x7109  #: no trajectory exists for these inputs
    BUFFER_FULL = 0x710A  #: 16 commands wait already (D-008)
    AXIS_NOT_HOMED = 0x710B  #: reserved: the command needs a homed axis
    NOTHING_TO_DO = 0x710C  #: a modifying command without a running job to modify
    PROBE_ALREADY_ARMED = 0x710D  #: the touch-probe input is armed by another cycle
    NOT_COUPLED = 0x710E  #: MC_GearOut on an axis that is not a geared slave
    SUPERPOSITION_ACTIVE = 0x710F  #: a superposition runs (or brakes) already
    AXIS_IN_GROUP = 0x7110  #: a CA group member only moves through the CA blocks
    COUPLING_LOOP = 0x7111  #: the master follows this axis through its own couplings
    # openmotion: group rejections (0x73xx)
    GROUP_EMPTY = 0x7301  #: MC_GroupEnable on a group without axes (TF5410 §7 note 9)
    GROUP_NOT_ENABLED = 0x7302  #: a motion command while the group is Disabled or NotReady
    GROUP_STOPPING = 0x7303  #: MC_GroupStop holds the group (TF5410 §7 note 2)
    GROUP_IN_ERROR = 0x7304  #: the group is in GroupErrorStop: MC_GroupReset first
    AXIS_NOT_IN_GROUP = 0x7305  #: a CA command for an axis that is not a member
    AXIS_MOVING = 0x7306  #: adding or removing a moving axis (TF5410 §7, V3.1.10)
    AXIS_IN_OTHER_GROUP = 0x7307  #: the axis belongs to another group already
    IDENT_IN_USE = 0x7308  #: another axis of the group has this IdentInGroup
    MODULO_ON_OPEN_RAIL = 0x7309  #: a modulo direction on a rail that is not a ring
    SYNC_FAILED = 0x730A  #: MC_GearInPosCA: synchronisation impossible (Late: master accelerated)
    GROUP_ERROR = 0x7310  #: a member axis went to ErrorStop: the group stopped (GroupErrorStop)
    UNKNOWN_TRACK = 0x7311  #: MC_ActivateTrack: no track of the group has this TrackId
    NOT_ON_TRACK = 0x7312  #: the mover's set position is on no part of the (active) track
    TARGET_OFF_TRACK = 0x7313  #: a track position outside [0, length] of an open track
    UNKNOWN_TEMPLATE = 0x7314  #: an OTCID that names no mover template of the group (§9.2)
    COMPENSATION_NOT_REGISTERED = 0x7315  #: a reference system the axis did not register
    INVALID_COMPENSATION_TYPE = 0x7316  #: MC_RegisterCompensation: CompensationType is not GEO
    # planar (TF5430); 0x8186 is the manual's own number (§6.7.2), the rest are ours (0x74xx)
    PLANAR_COLLISION = 0x8186  #: the command's area meets an area reserved in the group (§6.7.2)
    PLANAR_WRONG_STATE = 0x7401  #: the object's state does not accept the command (§4.1)
    PLANAR_WRONG_MODE = 0x7402  #: the mover's command mode does not accept the command (§4.2)
    INVALID_REFERENCE_ID = 0x7403  #: names no part or coordinate system, or 0 is ambiguous (§5.3)
    INVALID_MODULO_OPTIONS = 0x7404  #: turns without direction, tolerance with NonModulo (§6.1.1)
    PLANAR_NOT_DISABLED = 0x7405  #: SetPosition on a mover that is not Disabled (§7.2.2.8)
    PLANAR_POSITION_LIMIT = 0x7406  #: a target outside the mover's position limits
    PLANAR_PART_NOT_ENABLED = 0x7407  #: the target's part position is not active (§6.6)
    PLANAR_EXT_SETPOINT = 0x7408  #: an external setpoint is missing or beyond the limits (§6.1.6)
    PLANAR_INVALID_INPUT = 0x7409  #: a dynamics or option value out of range (NaN, negative)
    PLANAR_NOT_IN_GROUP = 0x740A  #: a group command for an object that is not a member (§6.3)
    PLANAR_PATH_END = 0x740B  #: a geared mover reached the end of its path and stopped (§6.2.8)
    # coordinated motion (PLCopen Part 4; ours)
    GROUP_MOVING = 0x7317  #: the block needs the axes group at rest (GroupStandby)
    GROUP_HOMING = 0x7318  #: the axes group is homing
    TARGET_UNREACHABLE = 0x7501  #: no axis solution: outside the workspace or an axis limit
    KINEMATICS_SINGULAR = 0x7502  #: a velocity asked for at a singular pose
    INVALID_CONFIGURATION = 0x7503  #: a kinematic configuration the model does not offer
    INVALID_PATH_GEOMETRY = 0x7504  #: no unique circle, a zero-length segment, no blend possible
    # TF5410 §9.3 path tables (MC_PATH_DATA_REF and its blocks; ours)
    PATH_TABLE_FULL = 0x7510  #: the table holds 30 rows, or its buffer is full (§9.3.2.4)
    PATH_TABLE_EMPTY = 0x7511  #: MC_MovePath over a table without rows
    INVALID_BLOCKER_ID = 0x7512  #: BlockerId is not a UDINT > 0 (§9.3.1.2.6)
    UNKNOWN_BLOCKER = 0x7513  #: MC_ReleaseBlocker: no such blocker ahead on the running path
    INVALID_DWELL_TIME = 0x7514  #: DwellTime is not a time >= 0 (§9.3.1.2.9)
    INVALID_TRANSITION_PARAMETER = 0x7515  #: too few TransitionParameter values, or not > 0
    # openmotion: axis errors raised by monitoring (0x72xx), these take the axis to ErrorStop
    FOLLOWING_ERROR = 0x7201  #: following error above 1020 for longer than 1021
    SOFT_LIMIT_REACHED = 0x7202  #: a move stopped at an enabled software limit (D-016, D-179)
    IN_TARGET_TIMEOUT = 0x7203  #: not in the target window within 1028 after the profile
    DRIVE_NOT_READY = 0x7204  #: MC_Power enabled while the drive reports not ready
    HOMING_FAILED = 0x7205  #: no reference cam to search
    GEAR_LIMIT_EXCEEDED = 0x7206  #: a geared slave would exceed its velocity or acceleration
    EXT_SETPOINT_MISSING = 0x7207  #: external setpoints enabled, but none fed this cycle
    EXT_SETPOINT_LIMIT = 0x7208  #: a fed setpoint beyond the axis' velocity or acceleration
    MASTER_DISABLED = 0x7209  #: the master of a geared slave was powered off (D-199)


class ConfigError(ValueError):
    """A configuration (scenario file, object construction) is invalid; names the field."""


class CommandRejected(Exception):
    """Raised inside the kernel when a command cannot start; carries the FB error id.

    Caught at the command boundary and turned into ``error``/``error_id``: it never leaves a
    cycle.
    """

    def __init__(self, error_id: ErrorId, message: str) -> None:
        super().__init__(message)
        self.error_id = error_id
        self.message = message
