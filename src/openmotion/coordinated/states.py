"""The axes-group state machine of PLCopen Part 4 (§3.1–§3.3, §5; digest §2, §3).

Fig. 7 is missing from the source, so the transition table below is rebuilt from the §3.1
prose and its Notes 1–6; every gap we had to fill is marked *decision* with its section.
Three tables, each written once:

* ``TRANSITIONS``: which event moves which group state to which;
* ``ACCEPTS``: in which states each group FB may start (``check_accepts`` turns a refusal
  into the FB's error id, as ``axis.state_machine.admit`` does for one axis);
* the coupling to the member axes (§3.2, Table 5), as pure functions over ``AxisState``.

Nothing here touches an axis or a clock: the group that owns this machine fires the events.
"""

from __future__ import annotations

import difflib
from enum import Enum, IntEnum

from openmotion.core.enums import AxisState, BufferMode
from openmotion.core.errors import CommandRejected, ErrorId


class AxesGroupState(IntEnum):
    """The six states of an AXES_GROUP_REF (§3.1).

    The numbers are those of TF5410's ``transport.enums.GroupState`` (§11.1), which names the
    same six states; Part 4 has no NotReady or Suspended, so 7 and 8 stay unused.
    """

    DISABLED = 1
    STANDBY = 2
    MOVING = 3
    STOPPING = 4
    ERROR_STOP = 5
    HOMING = 6

    @property
    def spec_name(self) -> str:
        """The manual's spelling, e.g. ``GroupErrorStop`` (the MC_GroupReadStatus flags)."""
        return _SPEC_NAMES[self]


_SPEC_NAMES = {
    AxesGroupState.DISABLED: "GroupDisabled",
    AxesGroupState.STANDBY: "GroupStandby",
    AxesGroupState.MOVING: "GroupMoving",
    AxesGroupState.STOPPING: "GroupStopping",
    AxesGroupState.ERROR_STOP: "GroupErrorStop",
    AxesGroupState.HOMING: "GroupHoming",
}


class GroupEvent(Enum):
    """What can happen to a group; the automatic ones are the dotted lines of Fig. 7."""

    ENABLE = "enable"  #: MC_GroupEnable
    DISABLE = "disable"  #: MC_GroupDisable
    UNGROUP = "ungroup"  #: MC_UngroupAllAxes
    ADD_AXIS = "add_axis"  #: MC_AddAxisToGroup
    REMOVE_AXIS = "remove_axis"  #: MC_RemoveAxisFromGroup, axes remain (Note 5)
    REMOVE_LAST_AXIS = "remove_last_axis"  #: MC_RemoveAxisFromGroup, none remain (Note 4)
    MOTION_START = "motion_start"  #: a moving FB takes control (Note 1)
    HALT = "halt"  #: MC_GroupHalt takes control (§5.14)
    HOME_START = "home_start"  #: MC_GroupHome takes control (§5.7)
    STOP = "stop"  #: MC_GroupStop, rising Execute (§5.13)
    RESET = "reset"  #: MC_GroupReset (§5.19)
    MOTION_END = "motion_end"  #: the last motion FB is Done, nothing buffered (§4.1)
    HOME_END = "home_end"  #: MC_GroupHome Done (§5.7)
    STOP_RELEASED = "stop_released"  #: MC_GroupStop Done and Execute low (Note 3)
    ERROR = "error"  #: a group error, or a member entered ErrorStop (§3.1, §3.2)
    MEMBER_POWER_OFF = "member_power_off"  #: a member's MC_Power went low (§3.2, §5.13)


#: events nobody commands: where the table has no entry for them they change nothing
AUTOMATIC = frozenset({GroupEvent.MOTION_END, GroupEvent.HOME_END, GroupEvent.STOP_RELEASED,
                       GroupEvent.ERROR, GroupEvent.MEMBER_POWER_OFF})

G = AxesGroupState
E = GroupEvent
ALL_STATES = frozenset(G)
_ACTIVE = frozenset({G.STANDBY, G.HOMING, G.MOVING, G.STOPPING})  #: supervised, not in error

#: (state, event) -> next state; a commanded event missing here is refused by ``ACCEPTS``
TRANSITIONS: dict[tuple[AxesGroupState, GroupEvent], AxesGroupState] = {
    **{(s, E.DISABLE): G.DISABLED for s in G},  # Note 6
    **{(s, E.ERROR): G.ERROR_STOP for s in _ACTIVE},  # §3.1, Note 2
    **{(s, E.UNGROUP): G.DISABLED for s in (G.DISABLED, G.STANDBY, G.ERROR_STOP)},  # §5.3
    **{(s, E.REMOVE_LAST_AXIS): G.DISABLED for s in (G.DISABLED, G.STANDBY, G.ERROR_STOP)},
    **{(s, E.MEMBER_POWER_OFF): G.DISABLED for s in (G.HOMING, G.MOVING, G.STOPPING)},
    (G.DISABLED, E.ENABLE): G.STANDBY,  # §5.5
    (G.DISABLED, E.ADD_AXIS): G.DISABLED,  # §4.1 steps 3-4
    (G.DISABLED, E.REMOVE_AXIS): G.DISABLED,
    (G.DISABLED, E.RESET): G.DISABLED,  # decision: resets the members only (§5.19)
    (G.STANDBY, E.ENABLE): G.STANDBY,  # decision: Done without effect (digest §8.1 q32)
    (G.STANDBY, E.ADD_AXIS): G.STANDBY,  # Note 5
    (G.STANDBY, E.REMOVE_AXIS): G.STANDBY,  # Note 5
    (G.STANDBY, E.MOTION_START): G.MOVING,  # Note 1, Table 5
    (G.STANDBY, E.HALT): G.MOVING,  # Table 5
    (G.STANDBY, E.HOME_START): G.HOMING,  # §3.1, Table 5
    (G.STANDBY, E.STOP): G.STOPPING,  # §5.13
    (G.STANDBY, E.RESET): G.STANDBY,  # decision: Done without effect (digest §8.1 q32)
    (G.HOMING, E.HOME_END): G.STANDBY,  # §5.7 "completes at GroupStandby"
    (G.HOMING, E.STOP): G.STOPPING,  # decision: a stop is never refused to a moving group
    (G.MOVING, E.MOTION_START): G.MOVING,  # Note 1: aborting or buffered
    (G.MOVING, E.HALT): G.MOVING,  # §5.14
    (G.MOVING, E.HOME_START): G.HOMING,  # a buffered MC_GroupHome takes over (§5.7)
    (G.MOVING, E.MOTION_END): G.STANDBY,  # §4.1, §5.14
    (G.MOVING, E.STOP): G.STOPPING,  # §5.13
    (G.STOPPING, E.STOP_RELEASED): G.STANDBY,  # Note 3
    (G.ERROR_STOP, E.REMOVE_AXIS): G.ERROR_STOP,  # §5.2
    (G.ERROR_STOP, E.RESET): G.STANDBY,  # §5.19, the only way out but Disable/Ungroup
}


def next_state(state: AxesGroupState, event: GroupEvent) -> AxesGroupState:
    """The state after ``event``; an automatic event that does not apply changes nothing."""
    target = TRANSITIONS.get((state, event))
    if target is not None:
        return target
    if event in AUTOMATIC:
        return state
    raise ValueError(f"{event.name} does not apply in {state.spec_name}: check_accepts first")


def stop_released(done: bool, execute: bool) -> bool:
    """Note 3: GroupStopping ends once MC_GroupStop is Done and its Execute is low, either order."""
    return done and not execute


# -- which group FB may start in which state -------------------------------------------------

READS = frozenset({
    "MC_GroupReadConfiguration", "MC_GroupReadActualPosition", "MC_GroupReadActualVelocity",
    "MC_GroupReadActualAcceleration", "MC_GroupReadStatus", "MC_GroupReadError",
    "MC_ReadKinTransform", "MC_ReadCartesianTransform", "MC_ReadCoordinateTransform",
})
MOVES = frozenset({
    "MC_MoveLinearAbsolute", "MC_MoveLinearRelative", "MC_MoveCircularAbsolute",
    "MC_MoveCircularRelative", "MC_MoveDirectAbsolute", "MC_MoveDirectRelative", "MC_MovePath",
    "MC_SyncGroupToAxis",
})
TRANSFORMS = frozenset({
    "MC_SetKinTransform", "MC_SetCartesianTransform", "MC_SetCoordinateTransform",
    "MC_SetDynCoordTransform",
})
#: the FBs with an ExecutionMode input (§5.8.1-§5.8.3); MC_SetDynCoordTransform has BufferMode
EXECUTION_MODE_BLOCKS = frozenset(TRANSFORMS - {"MC_SetDynCoordTransform"})
#: BufferMode Aborting needs GroupStandby; any other mode queues behind a motion (§5.7)
AT_REST_UNLESS_BUFFERED = frozenset({"MC_GroupHome", "MC_GroupSetPosition"})

_RUNNING = frozenset({G.STANDBY, G.MOVING})
_PREPARE = frozenset({G.DISABLED, G.STANDBY, G.HOMING, G.MOVING})  # Note 2 bars the other two
_REGROUP = frozenset({G.DISABLED, G.STANDBY, G.ERROR_STOP})  # §5.2, §5.3

#: group FB -> states in which it may start (with BufferMode Aborting)
ACCEPTS: dict[str, frozenset[AxesGroupState]] = {
    **dict.fromkeys(READS | {"MC_GroupSetOverride", "MC_GroupDisable"}, ALL_STATES),
    **dict.fromkeys(MOVES | {"MC_GroupHalt", "MC_TrackConveyorBelt", "MC_TrackRotaryTable",
                             "MC_SyncAxisToGroup", "MC_GroupContinue"}, _RUNNING),
    **dict.fromkeys(TRANSFORMS | {"MC_PathSelect"}, _PREPARE),
    **dict.fromkeys(AT_REST_UNLESS_BUFFERED, frozenset({G.STANDBY})),
    "MC_AddAxisToGroup": frozenset({G.DISABLED, G.STANDBY}),  # §4.1
    "MC_RemoveAxisFromGroup": _REGROUP,
    "MC_UngroupAllAxes": _REGROUP,  # §5.3 over Note 6 (digest §8.1 q2)
    "MC_GroupEnable": frozenset({G.DISABLED, G.STANDBY}),
    "MC_GroupReset": _REGROUP,
    "MC_GroupStop": frozenset({G.STANDBY, G.HOMING, G.MOVING}),
    "MC_GroupInterrupt": frozenset({G.MOVING}),
}

#: group FB -> the event it fires when it takes control; FBs not listed leave the state alone
START_EVENT: dict[str, GroupEvent] = {
    **dict.fromkeys(MOVES | {"MC_GroupContinue"}, E.MOTION_START),
    "MC_GroupHalt": E.HALT,
    "MC_GroupHome": E.HOME_START,
    "MC_GroupStop": E.STOP,
    "MC_GroupEnable": E.ENABLE,
    "MC_GroupDisable": E.DISABLE,
    "MC_UngroupAllAxes": E.UNGROUP,
    "MC_AddAxisToGroup": E.ADD_AXIS,
    "MC_RemoveAxisFromGroup": E.REMOVE_AXIS,
    "MC_GroupReset": E.RESET,
}

# the refusals of a group that is busy (Part 4 §3.1)
_MOVING_ID = ErrorId.GROUP_MOVING
_HOMING_ID = ErrorId.GROUP_HOMING

_REFUSAL: dict[AxesGroupState, tuple[ErrorId, str]] = {
    G.DISABLED: (ErrorId.GROUP_NOT_ENABLED, "enable the group first (MC_GroupEnable)"),
    G.STANDBY: (ErrorId.NOTHING_TO_DO, "no motion runs that it could act on"),
    G.HOMING: (_HOMING_ID, "the group is homing"),
    G.MOVING: (_MOVING_ID, "the group must be at rest (GroupStandby)"),
    G.STOPPING: (ErrorId.GROUP_STOPPING, "MC_GroupStop holds the group (Note 2)"),
    G.ERROR_STOP: (ErrorId.GROUP_IN_ERROR, "MC_GroupReset first (Note 2)"),
}


def accepting_states(block: str, buffer_mode: BufferMode = BufferMode.ABORTING
                     ) -> frozenset[AxesGroupState]:
    """The states in which ``block`` may start; an unknown name is a caller's bug."""
    if block not in ACCEPTS:
        close = difflib.get_close_matches(block, ACCEPTS, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise ValueError(f"{block!r} is not a Part 4 group FB{hint}")
    if block in AT_REST_UNLESS_BUFFERED and buffer_mode is not BufferMode.ABORTING:
        return _RUNNING
    return ACCEPTS[block]


def check_accepts(state: AxesGroupState, block: str,
                  buffer_mode: BufferMode = BufferMode.ABORTING) -> None:
    """Raise ``CommandRejected`` unless ``block`` may start in ``state`` (an FB error only)."""
    if state in accepting_states(block, buffer_mode):
        return
    error_id, reason = _REFUSAL[state]
    raise CommandRejected(error_id, f"{block} refused in {state.spec_name}: {reason}")


# -- coupling to the member axes (§3.2, Table 5) ---------------------------------------------

_OWN_STATES = frozenset({AxisState.DISABLED, AxisState.ERROR_STOP})


def member_state(group_state: AxesGroupState, axis_state: AxisState) -> AxisState:
    """The single-axis state a member shows after a group FB took the group to ``group_state``.

    Group commands drive every member in SynchronizedMotion, stopping included; reaching
    GroupStandby (or GroupDisabled, §4.1) releases them to StandStill; GroupErrorStop leaves
    them alone (Table 5, §3.2). A member that is unpowered or in ErrorStop keeps that state.
    """
    if axis_state in _OWN_STATES or group_state is G.ERROR_STOP:
        return axis_state
    if group_state in (G.HOMING, G.MOVING, G.STOPPING):
        return AxisState.SYNCHRONIZED_MOTION
    if axis_state is AxisState.SYNCHRONIZED_MOTION:
        return AxisState.STANDSTILL
    return axis_state


def member_event(axis_state: AxisState) -> GroupEvent | None:
    """What a member entering ``axis_state`` means to its group (§3.2, §5.13).

    Call it for every member on each change of its state and right after MC_GroupEnable.
    """
    if axis_state is AxisState.ERROR_STOP:
        return E.ERROR
    if axis_state is AxisState.DISABLED:
        return E.MEMBER_POWER_OFF
    return None


#: single-axis command families (as in ``axis.state_machine``) that a grouped axis refuses
_GROUP_ONLY = frozenset({"move", "modify", "set_position"})
MEMBER_FAMILIES = _GROUP_ONLY | {"stop", "home", "power", "reset", "read"}


def check_member_accepts(group_state: AxesGroupState, family: str) -> None:
    """§3.2 option 1: a member moves only through its group; MC_Stop is never refused.

    MC_Home is allowed in GroupStandby (§3.2 names it); power, reset and reads always pass,
    and the axis' own state machine decides the rest.
    """
    if family not in MEMBER_FAMILIES:
        raise ValueError(f"unknown single-axis command family {family!r}")
    if family in _GROUP_ONLY or (family == "home" and group_state is not G.STANDBY):
        if group_state in (G.STOPPING, G.ERROR_STOP):
            error_id, reason = _REFUSAL[group_state]
        else:
            error_id, reason = ErrorId.AXIS_IN_GROUP, "use the group FBs or remove the axis"
        raise CommandRejected(error_id, f"the axis is grouped ({group_state.spec_name}): {reason}")


def member_command_event(group_state: AxesGroupState, family: str) -> GroupEvent | None:
    """§3.2: a single-axis MC_Stop or MC_Home on a member makes a resting group GroupMoving."""
    if family in ("stop", "home") and group_state is G.STANDBY:
        return E.MOTION_START
    return None


# -- ExecutionMode (§3.3) ----------------------------------------------------------------------


class ExecutionMode(IntEnum):
    """MC_EXECUTION_MODE (§3.3) of the Set*Transform FBs; Part 4 gives no numbers: ours."""

    IMMEDIATELY = 0  #: valid at once; may change the running motion, never the state
    DELAYED = 1  #: valid when the running motion command ends (Done, Aborted or Error)
    QUEUED = 2  #: valid when every motion command issued before it has ended


def commands_to_wait(mode: ExecutionMode, running: bool, buffered: int = 0) -> int:
    """How many motion commands must end before an FB with ``mode`` takes effect.

    ``running``: a motion command is active; ``buffered``: commands queued behind it.
    """
    if buffered < 0 or (buffered and not running):
        raise ValueError(f"{buffered} buffered commands with running={running}")
    if mode is ExecutionMode.IMMEDIATELY:
        return 0
    if mode is ExecutionMode.DELAYED:
        return int(running)
    return int(running) + buffered


# -- the machine -------------------------------------------------------------------------------


class GroupStateMachine:
    """The state of one axes group and its member count, moved only by the tables above."""

    def __init__(self) -> None:
        self.state = G.DISABLED  #: §4.1: a new group is empty and GroupDisabled
        self.members = 0

    def accept(self, block: str, buffer_mode: BufferMode = BufferMode.ABORTING) -> None:
        """Raise ``CommandRejected`` unless ``block`` may start now; the state is unchanged."""
        check_accepts(self.state, block, buffer_mode)
        if block == "MC_GroupEnable" and not self.members:
            raise CommandRejected(ErrorId.GROUP_EMPTY, "MC_GroupEnable on a group without axes")
        if block == "MC_RemoveAxisFromGroup" and not self.members:
            raise CommandRejected(ErrorId.AXIS_NOT_IN_GROUP, "the group has no axes")

    def start(self, block: str) -> AxesGroupState:
        """``block`` takes control (now, or when its buffered turn comes): fire its event."""
        event = START_EVENT.get(block)
        return self.state if event is None else self.fire(event)

    def fire(self, event: GroupEvent) -> AxesGroupState:
        """Apply one event and return the new state."""
        removing = event in (E.REMOVE_AXIS, E.REMOVE_LAST_AXIS)
        if removing and not self.members:
            raise ValueError("no axis left to remove")
        if removing:  # Notes 4 and 5: the count, not the caller, says which one it is
            event = E.REMOVE_LAST_AXIS if self.members == 1 else E.REMOVE_AXIS
        self.state = next_state(self.state, event)
        if event is E.ADD_AXIS:
            self.members += 1
        elif removing:
            self.members -= 1
        elif event is E.UNGROUP:
            self.members = 0
        return self.state
