"""The planar state machine (TF5430 §4.1), the mover's command modes (§4.2) and the rules for
which commands a mover and a track accept (§4.2, §4.3).

Timing of ``PlanarStateMachine``:

* The owner takes its sent commands in call order in ``update()`` and hands Enable, Disable
  and Reset to ``request()``.
* Enabling, Disabling, ErrorPending and Resetting last at least until the next update. After
  that they last until the owner's ``transition_done`` hook says the work is finished (the
  part enabled, the QuickStop braked, ...).
* ``update()`` publishes ``state``, ``error`` and ``error_id``. The owner calls it after its
  commands and its motion and before ``CommandQueue.publish()``, so the user sees each change
  one cycle after the call.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum, IntEnum, StrEnum

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.enums import (
    ExternalSetPositionMode,
    MoverCommandMode,
    PlanarState,
    TrackOperationMode,
)
from openmotion.planar.feedback import PlanarCommand
from openmotion.planar.rotation import (
    CWindows,
    mode_after_c_motion,
    mode_at_enable,
    mode_during_c_motion,
)
from openmotion.trajectory.segments import Profile

_S = PlanarState
_M = MoverCommandMode
_TRANSITIONAL = frozenset({_S.ENABLING, _S.DISABLING, _S.ERROR_PENDING, _S.RESETTING})
_ERROR_STATES = frozenset({_S.ERROR_PENDING, _S.ERROR, _S.RESETTING})


def title(member: Enum) -> str:
    """The manual's spelling of an enumerator: ``C_ROTATION_ON_TRACK`` -> CRotationOnTrack."""
    return "".join(word.capitalize() for word in member.name.split("_"))


class ErrorReaction(IntEnum):
    """How an object reacts to an error (§4.1). QuickStop brakes and stays powered; Abort
    switches off. The stricter reaction wins."""

    QUICK_STOP = 0
    ABORT = 1


class StateCommand(StrEnum):
    """The commands of the state machine, by the manual's method names."""

    ENABLE = "Enable"
    DISABLE = "Disable"
    RESET = "Reset"


def _at_once(state: PlanarState) -> bool:
    return True


def _nothing(state: PlanarState) -> None:
    return None


class PlanarStateMachine:
    """The seven planar states of a mover, track or group (§4.1).

    ``transition_done(state)`` is asked once per update while the object is in a transitional
    state; by default every transition takes one update. ``on_enter(state)`` tells the owner
    that a state has begun, so that it can start the work (brake, power up, ...).
    """

    def __init__(self, *, transition_done: Callable[[PlanarState], bool] = _at_once,
                 on_enter: Callable[[PlanarState], None] = _nothing) -> None:
        self._transition_done = transition_done
        self._on_enter = on_enter
        self.current = _S.DISABLED  #: the object's own state, published by update()
        self.reaction = ErrorReaction.QUICK_STOP  #: the error reaction in force
        self._error_id = ErrorId.NO_ERROR
        self._message = ""
        self._command: PlanarCommand | None = None  #: the Enable/Disable/Reset in progress
        self._fresh = False  #: entered in this update
        self.state = _S.DISABLED
        self.error = False
        self.error_id = ErrorId.NO_ERROR
        self.message = ""

    @property
    def settled(self) -> bool:
        """Nothing to do in ``update()``: no transition runs and the state is published."""
        return (self.current is self.state and not self._fresh
                and self.current not in _TRANSITIONAL)

    def request(self, command: PlanarCommand) -> None:
        """Apply a sent Enable, Disable or Reset (``command.kind`` is a ``StateCommand``)."""
        {StateCommand.ENABLE: self._enable, StateCommand.DISABLE: self._disable,
         StateCommand.RESET: self._reset}[StateCommand(command.kind)](command)

    def fail(self, error_id: ErrorId, reaction: ErrorReaction = ErrorReaction.QUICK_STOP,
             message: str = "") -> None:
        """An error of the object. It goes to ErrorPending, except from Resetting: then the
        reset fails and it is back in Error (§4.1). A further error keeps the first error id
        and may only make the reaction stricter. Outside Enabled there is nothing to brake, so
        the reaction is Abort."""
        state = self.current
        if state in (_S.ERROR_PENDING, _S.ERROR):
            self.reaction = max(self.reaction, reaction)
            return
        if state is _S.ENABLED:
            self.reaction = reaction
        elif state is _S.RESETTING:
            self.reaction = max(self.reaction, reaction)
        else:
            self.reaction = ErrorReaction.ABORT
        self._error_id, self._message = error_id, message
        if self._command is not None:
            self._command.reject(error_id, message)
            self._command = None
        self._enter(_S.ERROR if state is _S.RESETTING else _S.ERROR_PENDING)

    def update(self) -> None:
        """End a transition the owner reports done, then publish the state and the error."""
        state = self.current
        if state in _TRANSITIONAL and not self._fresh and self._transition_done(state):
            self._complete(state)
        self._fresh = False
        self.state = self.current
        self.error = self.current in _ERROR_STATES
        self.error_id = self._error_id if self.error else ErrorId.NO_ERROR
        self.message = self._message if self.error else ""

    def _enable(self, command: PlanarCommand) -> None:
        if self.current in _ERROR_STATES:
            command.reject(ErrorId.PLANAR_WRONG_STATE, f"Enable is not accepted in "
                           f"{title(self.current)}: Reset the error first (§4.1)")
        elif self.current is _S.ENABLED:
            command.finish()
        else:
            self._begin(_S.ENABLING, command)

    def _disable(self, command: PlanarCommand) -> None:
        if self.current in _ERROR_STATES:
            self.reaction = ErrorReaction.ABORT  # §4.1: forces the Abort reaction
            command.finish()
        elif self.current is _S.DISABLED:
            command.finish()
        else:
            self._begin(_S.DISABLING, command)

    def _reset(self, command: PlanarCommand) -> None:
        if self.current in (_S.ERROR, _S.RESETTING):
            self._begin(_S.RESETTING, command)
        elif self.current is _S.ERROR_PENDING:
            command.reject(ErrorId.PLANAR_WRONG_STATE, "Reset is not accepted in "
                           "ErrorPending: wait until the state is Error (§4.1)")
        else:
            command.finish()

    def _begin(self, state: PlanarState, command: PlanarCommand) -> None:
        """Start (or take over) a transition: the command it replaces is Aborted."""
        if self._command is not None:
            self._command.abort()
        self._command = command
        command.start()
        if state is not self.current:
            self._enter(state)

    def _complete(self, state: PlanarState) -> None:
        if state is _S.ERROR_PENDING:
            self._enter(_S.ERROR)
            return
        if state is _S.RESETTING:
            after = _S.ENABLED if self.reaction is ErrorReaction.QUICK_STOP else _S.DISABLED
            self.reaction = ErrorReaction.QUICK_STOP
            self._error_id, self._message = ErrorId.NO_ERROR, ""
        else:
            after = _S.ENABLED if state is _S.ENABLING else _S.DISABLED
        if self._command is not None:
            self._command.finish()
            self._command = None
        self._enter(after)

    def _enter(self, state: PlanarState) -> None:
        self.current = state
        self._fresh = True
        self._on_enter(state)


# -- mover commands and their acceptance (§4.2, §4.3; digest-planar-concepts §2.3) --------------


class MoverCommand(StrEnum):
    """The mover's commands by the manual's method names (§7.2.2.8). The two ways to start
    external setpoints are two kinds because different modes accept them."""

    MOVE_TO_POSITION = "MoveToPosition"
    JOIN_TRACK = "JoinTrack"
    LEAVE_TRACK = "LeaveTrack"
    MOVE_ON_TRACK = "MoveOnTrack"
    GEAR_IN_POS_ON_TRACK = "GearInPosOnTrack"
    GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER = "GearInPosOnTrackWithMasterMover"
    MOVE_Z = "MoveZ"
    MOVE_A = "MoveA"
    MOVE_B = "MoveB"
    MOVE_C = "MoveC"
    ADOPT_TRACK_ORIENTATION = "AdoptTrackOrientation"
    HALT = "Halt"
    SET_POSITION = "SetPosition"
    START_EXTERNAL_SETPOINT_GENERATION = "StartExternalSetpointGeneration"  #: Absolute
    START_RELATIVE_EXTERNAL_SETPOINT_GENERATION = "StartExternalSetpointGeneration(Relative)"
    SET_EXTERNAL_SETPOINT = "SetExternalSetpoint"  #: also SetExternalSetpointReferenceId
    STOP_EXTERNAL_SETPOINT_GENERATION = "StopExternalSetpointGeneration"
    ADD_TO_GROUP = "AddToGroup"
    REMOVE_FROM_GROUP = "RemoveFromGroup"


_C = MoverCommand
_ROTATABLE = frozenset({_M.FREE_MOVEMENT, _M.C_ROTATION_FREE_MOVEMENT, _M.ON_TRACK,
                        _M.C_ROTATION_ON_TRACK})
_ANY = frozenset(_M)
_ON_TRACK = frozenset({_M.ON_TRACK})

#: command -> the command modes that accept it while the mover is Enabled
ACCEPTING_MODES: dict[MoverCommand, frozenset[MoverCommandMode]] = {
    _C.MOVE_TO_POSITION: frozenset({_M.FREE_MOVEMENT}),
    _C.JOIN_TRACK: frozenset({_M.FREE_MOVEMENT}),
    _C.LEAVE_TRACK: _ON_TRACK,
    _C.MOVE_ON_TRACK: _ON_TRACK,
    _C.GEAR_IN_POS_ON_TRACK: _ON_TRACK,
    _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER: _ON_TRACK,
    _C.MOVE_Z: _ROTATABLE,
    _C.MOVE_A: _ROTATABLE,
    _C.MOVE_B: _ROTATABLE,
    _C.MOVE_C: _ROTATABLE,
    _C.ADOPT_TRACK_ORIENTATION: frozenset({_M.ON_TRACK, _M.C_ROTATION_ON_TRACK}),
    _C.HALT: _ROTATABLE | {_M.EXTERNAL_SETPOINT_GENERATION},
    _C.SET_POSITION: _ANY,
    _C.START_EXTERNAL_SETPOINT_GENERATION: frozenset({_M.FREE_MOVEMENT}),
    _C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION: _ROTATABLE,
    _C.SET_EXTERNAL_SETPOINT: _ANY,
    _C.STOP_EXTERNAL_SETPOINT_GENERATION: _ANY,
    _C.ADD_TO_GROUP: _ROTATABLE | {_M.EXTERNAL_SETPOINT_GENERATION},
    _C.REMOVE_FROM_GROUP: _ROTATABLE | {_M.EXTERNAL_SETPOINT_GENERATION},
}

#: command -> the states that accept it (all others: Enabled only)
ACCEPTING_STATES: dict[MoverCommand, frozenset[PlanarState]] = {
    _C.SET_POSITION: frozenset({_S.DISABLED}),
    _C.ADD_TO_GROUP: frozenset({_S.DISABLED, _S.ENABLED}),
    _C.REMOVE_FROM_GROUP: frozenset({_S.DISABLED, _S.ENABLED}),
}
_ENABLED = frozenset({_S.ENABLED})
_TRACK_COMMANDS = frozenset({_C.LEAVE_TRACK, _C.MOVE_ON_TRACK, _C.GEAR_IN_POS_ON_TRACK,
                             _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER,
                             _C.ADOPT_TRACK_ORIENTATION})
_STREAM = frozenset({_C.SET_EXTERNAL_SETPOINT, _C.STOP_EXTERNAL_SETPOINT_GENERATION})
_STARTS = frozenset({_C.START_EXTERNAL_SETPOINT_GENERATION,
                     _C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION})


def check_accepts(state: PlanarState, mode: MoverCommandMode, command: MoverCommand, *,
                  external: ExternalSetPositionMode = ExternalSetPositionMode.NONE) -> None:
    """Raise ``CommandRejected`` unless a mover in ``state`` and ``mode`` accepts ``command``.

    ``external`` is the external setpoint generation that runs (Relative leaves the mode as
    it is, §4.2). The command mode counts only while the mover is Enabled.
    """
    states = ACCEPTING_STATES.get(command, _ENABLED)
    if state not in states:
        error_id = (ErrorId.PLANAR_NOT_DISABLED if command is _C.SET_POSITION
                    else ErrorId.PLANAR_WRONG_STATE)
        needed = " or ".join(title(s) for s in sorted(states))
        raise CommandRejected(error_id, f"{command} needs state {needed}; the mover is "
                                        f"{title(state)} (§4.1)")
    if state is not _S.ENABLED:
        return
    if mode not in ACCEPTING_MODES[command]:
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE, f"{command} is not accepted in "
                              f"command mode {title(mode)} (§4.2); {_why(command, mode)}")
    running = external is not ExternalSetPositionMode.NONE
    if command in _STREAM and not running:
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE,
                              f"{command}: no external setpoint generation runs (§6.1.6)")
    if command in _STARTS and running:
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE, f"{command}: a {title(external)} "
                              "external setpoint generation runs already (§6.1.6)")


def _why(command: MoverCommand, mode: MoverCommandMode) -> str:
    if mode is _M.JOINING_TRACK:
        return "the mover accepts no command until it has joined the track"
    if mode is _M.LEAVING_TRACK:
        return "the mover accepts no command until it has left the track"
    if mode is _M.EXTERNAL_SETPOINT_GENERATION:
        return "external setpoints drive the mover: StopExternalSetpointGeneration first"
    if command in _TRACK_COMMANDS and mode in (_M.FREE_MOVEMENT, _M.C_ROTATION_FREE_MOVEMENT):
        return "the mover is on no track: JoinTrack first"
    if mode in (_M.C_ROTATION_FREE_MOVEMENT, _M.C_ROTATION_ON_TRACK):
        return "X and Y stay locked until a C move ends inside a C window"
    return "the mover is on a track: LeaveTrack first"


#: command -> the track operation modes in which the track takes it (§4.3)
TRACK_ACCEPTING_MODES: dict[MoverCommand, frozenset[TrackOperationMode]] = {
    _C.JOIN_TRACK: frozenset({TrackOperationMode.STANDING, TrackOperationMode.CONFIGURING}),
    _C.LEAVE_TRACK: frozenset({TrackOperationMode.STANDING, TrackOperationMode.CONFIGURING}),
    _C.MOVE_ON_TRACK: frozenset({TrackOperationMode.STANDING, TrackOperationMode.MOVING}),
    _C.GEAR_IN_POS_ON_TRACK: frozenset({TrackOperationMode.STANDING, TrackOperationMode.MOVING}),
    _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER: frozenset({TrackOperationMode.STANDING,
                                                         TrackOperationMode.MOVING}),
}


def check_track_accepts(state: PlanarState, mode: TrackOperationMode,
                        command: MoverCommand) -> None:
    """Raise ``CommandRejected`` unless the track takes a mover's ``command`` now (§4.3):
    no join or leave while it is Moving, no motion while it is Configuring, nothing while it
    is Uninitialized or not Enabled. Commands without a track rule pass."""
    modes = TRACK_ACCEPTING_MODES.get(command)
    if modes is None:
        return
    if state is not _S.ENABLED:
        raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                              f"{command}: the track is {title(state)}, not Enabled (§4.1)")
    if mode not in modes:
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE,
                              f"{command} is not accepted while the track is {title(mode)} "
                              "(§4.3)")


# -- command modes (§4.2) ------------------------------------------------------------------------


class CommandModes:
    """The command mode of one mover (§4.2). The mover reports what happens; ``mode`` and
    ``external`` are what its status publishes. The C windows and the CRotation rules are
    rotation.py's."""

    def __init__(self, windows: CWindows) -> None:
        self.windows = windows
        self.mode = _M.FREE_MOVEMENT
        self.external = ExternalSetPositionMode.NONE

    def enabled(self, c: float) -> None:
        """After Enable: FreeMovement, or CRotationFreeMovement if C [°] is in no window."""
        self.external = ExternalSetPositionMode.NONE
        self.mode = mode_at_enable(c, self.windows)

    def started(self, command: MoverCommand) -> None:
        """The mover accepted ``command``: a join, a leave or an external setpoint generation
        switches the mode (Relative keeps it, §4.2)."""
        if command is _C.JOIN_TRACK:
            self.mode = _M.JOINING_TRACK
        elif command is _C.LEAVE_TRACK:
            self.mode = _M.LEAVING_TRACK
        elif command is _C.START_EXTERNAL_SETPOINT_GENERATION:
            self.mode = _M.EXTERNAL_SETPOINT_GENERATION
            self.external = ExternalSetPositionMode.ABSOLUTE
        elif command is _C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION:
            self.external = ExternalSetPositionMode.RELATIVE

    def ended(self, command: MoverCommand, *, done: bool, c: float) -> None:
        """A join, a leave or an external setpoint generation (its start command) is over;
        ``done`` is False when it failed or was aborted. ``c`` is the C position [°]."""
        if command is _C.JOIN_TRACK and done:
            self.mode = _M.ON_TRACK
        elif command in (_C.JOIN_TRACK, _C.LEAVE_TRACK):
            self.mode = mode_at_enable(c, self.windows)
        elif command in _STARTS:
            self.external = ExternalSetPositionMode.NONE
            if command is _C.START_EXTERNAL_SETPOINT_GENERATION:
                self.mode = mode_at_enable(c, self.windows)

    def c_motion_started(self, c: Profile) -> None:
        """A planned C motion (MoveC, AdoptTrackOrientation) that leaves its window starts
        a CRotation mode."""
        self.mode = mode_during_c_motion(self.mode, c, self.windows)

    def c_at_rest(self, c: float) -> None:
        """C has come to rest: its move finished, was halted, or was aborted without a
        successor. A CRotation mode ends if ``c`` [°] lies inside a window."""
        self.mode = mode_after_c_motion(self.mode, c, self.windows)
