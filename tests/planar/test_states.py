"""The planar state machine (TF5430 §4.1), the command modes (§4.2) and the acceptance rules
of movers and tracks (§4.2, §4.3; digest-planar-concepts §2.3).

Timing convention: ``Owner.call`` is the user's method call in a cycle; ``Owner.cycle`` is
the object's update that follows it (take the commands, apply them, ``update()``, publish).
What a test reads after ``cycle()`` is what the user reads in the next cycle.
"""

from __future__ import annotations

import pytest

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.enums import (
    ExternalSetPositionMode,
    MoverCommandMode,
    PlanarState,
    TrackOperationMode,
)
from openmotion.planar.feedback import CommandQueue, MC_PlanarFeedback
from openmotion.planar.options import PlanarMoverParameters
from openmotion.planar.states import (
    CommandModes,
    ErrorReaction,
    MoverCommand,
    PlanarStateMachine,
    StateCommand,
    check_accepts,
    check_track_accepts,
    title,
)
from openmotion.trajectory.plan import plan_position
from openmotion.trajectory.segments import KinematicState, Profile

S, M, C, X = PlanarState, MoverCommandMode, MoverCommand, ExternalSetPositionMode
ENABLE, DISABLE, RESET = StateCommand.ENABLE, StateCommand.DISABLE, StateCommand.RESET
PARAMETERS = PlanarMoverParameters()


class Owner:
    """A planar object reduced to its state machine; ``busy`` holds transitions open."""

    def __init__(self) -> None:
        self.busy: set[PlanarState] = set()
        self.entered: list[PlanarState] = []
        self.queue = CommandQueue()
        self.states = PlanarStateMachine(transition_done=lambda s: s not in self.busy,
                                         on_enter=self.entered.append)

    def call(self, kind: StateCommand) -> MC_PlanarFeedback:
        feedback = MC_PlanarFeedback()
        self.queue.send(kind, feedback)
        return feedback

    def cycle(self, n: int = 1) -> None:
        for _ in range(n):
            for command in self.queue.take():
                self.states.request(command)
            self.states.update()
            self.queue.publish()

    def enabled(self) -> Owner:
        self.call(ENABLE)
        self.cycle(2)
        assert self.states.state is S.ENABLED
        return self

    def failed(self, reaction: ErrorReaction = ErrorReaction.QUICK_STOP) -> Owner:
        self.states.fail(ErrorId.FOLLOWING_ERROR, reaction, "lag")
        self.cycle(2)
        assert self.states.state is S.ERROR
        return self


def outputs(feedback: MC_PlanarFeedback) -> str:
    """The feedback's flags as a word, e.g. 'busy active' or 'done'."""
    flags = ("busy", "active", "done", "aborted", "error")
    return " ".join(flag for flag in flags if getattr(feedback, flag)) or "-"


def held_in(state: PlanarState) -> Owner:
    """An owner that failed while Enabled (QuickStop), held in the error state ``state``."""
    owner = Owner().enabled()
    owner.busy.update({S.ERROR_PENDING, S.RESETTING})
    owner.states.fail(ErrorId.FOLLOWING_ERROR, ErrorReaction.QUICK_STOP)
    owner.cycle()
    if state is not S.ERROR_PENDING:
        owner.busy.discard(S.ERROR_PENDING)
        owner.cycle()
    if state is S.RESETTING:
        owner.call(RESET)
        owner.cycle()
    assert owner.states.state is state
    return owner


# -- state machine (§4.1) --------------------------------------------------------------------------


def test_boots_disabled_without_error():
    states = PlanarStateMachine()
    assert (states.state, states.current, states.error, states.error_id) == (
        S.DISABLED, S.DISABLED, False, ErrorId.NO_ERROR)


def test_enable_shows_one_cycle_after_the_call_and_enabling_lasts_one_update():
    owner = Owner()
    feedback = owner.call(ENABLE)
    assert owner.states.state is S.DISABLED and outputs(feedback) == "busy"  # sent
    owner.cycle()
    assert owner.states.state is S.ENABLING and outputs(feedback) == "busy active"
    owner.cycle()
    assert owner.states.state is S.ENABLED and outputs(feedback) == "done"  # §6.7.1
    assert owner.entered == [S.ENABLING, S.ENABLED]


def test_enabling_lasts_until_the_owner_reports_it_done():
    owner = Owner()
    owner.busy.add(S.ENABLING)
    feedback = owner.call(ENABLE)
    owner.cycle(5)
    assert owner.states.state is S.ENABLING and feedback.active
    owner.busy.clear()
    owner.cycle()
    assert owner.states.state is S.ENABLED and feedback.done


def test_disable_goes_through_disabling_to_disabled():
    owner = Owner().enabled()
    feedback = owner.call(DISABLE)
    owner.cycle()
    assert owner.states.state is S.DISABLING and outputs(feedback) == "busy active"
    owner.cycle()
    assert owner.states.state is S.DISABLED and outputs(feedback) == "done"


def test_disable_while_enabling_cancels_the_enable():
    owner = Owner()
    owner.busy.add(S.ENABLING)
    enable = owner.call(ENABLE)
    owner.cycle()
    disable = owner.call(DISABLE)
    owner.cycle()
    assert owner.states.state is S.DISABLING
    assert outputs(enable) == "aborted" and outputs(disable) == "busy active"
    owner.cycle()
    assert owner.states.state is S.DISABLED and disable.done


def test_enable_while_disabling_cancels_the_disable():
    owner = Owner().enabled()
    owner.busy.add(S.DISABLING)
    disable = owner.call(DISABLE)
    owner.cycle()
    enable = owner.call(ENABLE)
    owner.cycle()
    assert owner.states.state is S.ENABLING and outputs(disable) == "aborted"
    owner.cycle()
    assert owner.states.state is S.ENABLED and enable.done


def test_a_second_enable_takes_over_and_the_first_is_aborted():
    owner = Owner()
    owner.busy.add(S.ENABLING)
    first = owner.call(ENABLE)
    owner.cycle()
    second = owner.call(ENABLE)
    owner.busy.clear()
    owner.cycle(2)
    assert outputs(first) == "aborted" and outputs(second) == "done"


@pytest.mark.parametrize(("state", "kind"), [(S.ENABLED, ENABLE), (S.DISABLED, DISABLE),
                                             (S.ENABLED, RESET), (S.DISABLED, RESET)])
def test_a_request_with_nothing_to_do_is_done_at_once(state: PlanarState, kind: StateCommand):
    owner = Owner().enabled() if state is S.ENABLED else Owner()
    feedback = owner.call(kind)
    owner.cycle()
    assert owner.states.state is state and outputs(feedback) == "done"


def test_commands_of_one_cycle_apply_in_call_order():
    owner = Owner()
    enable, disable = owner.call(ENABLE), owner.call(DISABLE)
    owner.cycle()
    assert owner.states.state is S.DISABLING and enable.aborted and disable.active


def test_error_goes_through_error_pending_and_is_published_at_the_next_update():
    owner = Owner().enabled()
    owner.busy.add(S.ERROR_PENDING)  # the QuickStop still brakes
    owner.states.fail(ErrorId.FOLLOWING_ERROR, ErrorReaction.QUICK_STOP, "lag too big")
    assert owner.states.current is S.ERROR_PENDING
    assert owner.states.state is S.ENABLED and not owner.states.error  # not yet published
    owner.cycle(3)
    assert owner.states.state is S.ERROR_PENDING
    assert (owner.states.error, owner.states.error_id) == (True, ErrorId.FOLLOWING_ERROR)
    assert owner.states.message == "lag too big"
    owner.busy.clear()
    owner.cycle()
    assert owner.states.state is S.ERROR and owner.states.error


@pytest.mark.parametrize(("reaction", "after"), [(ErrorReaction.QUICK_STOP, S.ENABLED),
                                                 (ErrorReaction.ABORT, S.DISABLED)])
def test_reset_ends_enabled_after_quick_stop_and_disabled_after_abort(
        reaction: ErrorReaction, after: PlanarState):
    owner = Owner().enabled().failed(reaction)
    feedback = owner.call(RESET)
    owner.cycle()
    assert owner.states.state is S.RESETTING and owner.states.error and feedback.active
    owner.cycle()
    assert owner.states.state is after and outputs(feedback) == "done"
    assert (owner.states.error, owner.states.error_id, owner.states.message) == (
        False, ErrorId.NO_ERROR, "")
    assert owner.states.reaction is ErrorReaction.QUICK_STOP


@pytest.mark.parametrize("state", [S.ERROR_PENDING, S.ERROR, S.RESETTING])
def test_disable_in_an_error_state_forces_abort(state: PlanarState):
    owner = held_in(state)
    feedback = owner.call(DISABLE)
    owner.cycle()
    assert owner.states.state is state and outputs(feedback) == "done"
    assert owner.states.reaction is ErrorReaction.ABORT
    owner.busy.clear()
    owner.cycle()
    if state is not S.RESETTING:
        owner.call(RESET)
        owner.cycle(2)
    assert owner.states.state is S.DISABLED


@pytest.mark.parametrize("state", [S.DISABLED, S.ENABLING, S.DISABLING])
def test_an_error_outside_enabled_has_the_abort_reaction(state: PlanarState):
    owner = Owner().enabled() if state is S.DISABLING else Owner()
    owner.busy.update({S.ENABLING, S.DISABLING})
    running = None
    if state is not S.DISABLED:
        running = owner.call(ENABLE if state is S.ENABLING else DISABLE)
        owner.cycle()
    assert owner.states.state is state
    owner.states.fail(ErrorId.DRIVE_NOT_READY, ErrorReaction.QUICK_STOP, "part off")
    owner.cycle()
    assert owner.states.state is S.ERROR_PENDING
    assert owner.states.reaction is ErrorReaction.ABORT
    if running is not None:  # the Enable or Disable in progress fails
        assert outputs(running) == "error" and running.error_id is ErrorId.DRIVE_NOT_READY


@pytest.mark.parametrize("state", [S.ERROR_PENDING, S.ERROR, S.RESETTING])
def test_enable_is_rejected_in_every_error_state(state: PlanarState):
    owner = held_in(state)
    feedback = owner.call(ENABLE)
    owner.cycle()
    assert owner.states.state is state
    assert outputs(feedback) == "error" and feedback.error_id is ErrorId.PLANAR_WRONG_STATE
    assert "Reset the error first" in feedback.message


def test_reset_in_error_pending_is_rejected():
    owner = held_in(S.ERROR_PENDING)
    feedback = owner.call(RESET)
    owner.cycle()
    assert owner.states.state is S.ERROR_PENDING
    assert feedback.error and feedback.error_id is ErrorId.PLANAR_WRONG_STATE


def test_an_error_while_resetting_fails_the_reset_back_to_error():
    owner = Owner().enabled().failed(ErrorReaction.ABORT)
    owner.busy.add(S.RESETTING)
    reset = owner.call(RESET)
    owner.cycle()
    owner.states.fail(ErrorId.DRIVE_NOT_READY, ErrorReaction.QUICK_STOP, "part error")
    assert owner.states.current is S.ERROR  # §4.1: no ErrorPending from Resetting
    owner.cycle()
    assert owner.states.state is S.ERROR and owner.states.error_id is ErrorId.DRIVE_NOT_READY
    assert outputs(reset) == "error" and reset.error_id is ErrorId.DRIVE_NOT_READY
    assert owner.states.reaction is ErrorReaction.ABORT  # the stricter one stays


def test_a_further_error_keeps_the_first_id_and_only_tightens_the_reaction():
    owner = Owner().enabled().failed(ErrorReaction.QUICK_STOP)
    owner.states.fail(ErrorId.DRIVE_NOT_READY, ErrorReaction.ABORT)
    owner.states.fail(ErrorId.SOFT_LIMIT_REACHED, ErrorReaction.QUICK_STOP)
    owner.cycle()
    assert owner.states.state is S.ERROR and owner.states.error_id is ErrorId.FOLLOWING_ERROR
    assert owner.states.reaction is ErrorReaction.ABORT


def test_the_owner_hears_of_every_state_it_enters():
    owner = Owner().enabled().failed()
    owner.call(RESET)
    owner.cycle(2)
    assert owner.entered == [S.ENABLING, S.ENABLED, S.ERROR_PENDING, S.ERROR, S.RESETTING,
                             S.ENABLED]


def test_title_spells_enumerators_as_the_manual():
    assert [title(s) for s in S] == ["Disabled", "Enabling", "Enabled", "Disabling",
                                     "Resetting", "ErrorPending", "Error"]
    assert title(M.C_ROTATION_FREE_MOVEMENT) == "CRotationFreeMovement"


# -- the acceptance matrix (digest-planar-concepts §2.3, completed by our decisions) -------------

MODES = [M.FREE_MOVEMENT, M.C_ROTATION_FREE_MOVEMENT, M.JOINING_TRACK, M.ON_TRACK,
         M.C_ROTATION_ON_TRACK, M.LEAVING_TRACK, M.EXTERNAL_SETPOINT_GENERATION]

#                                               Free CRotF Join OnTr CRotOn Leav ExtAbs
MATRIX_TEXT = """
MoveToPosition                                   Y    N     N    N    N      N    N
JoinTrack                                        Y    N     N    N    N      N    N
LeaveTrack                                       N    N     N    Y    N      N    N
MoveOnTrack                                      N    N     N    Y    N      N    N
GearInPosOnTrack                                 N    N     N    Y    N      N    N
GearInPosOnTrackWithMasterMover                  N    N     N    Y    N      N    N
MoveC                                            Y    Y     N    Y    Y      N    N
AdoptTrackOrientation                            N    N     N    Y    Y      N    N
MoveZ                                            Y    Y     N    Y    Y      N    N
MoveA                                            Y    Y     N    Y    Y      N    N
MoveB                                            Y    Y     N    Y    Y      N    N
Halt                                             Y    Y     N    Y    Y      N    Y
StartExternalSetpointGeneration                  Y    N     N    N    N      N    N
StartExternalSetpointGeneration(Relative)        Y    Y     N    Y    Y      N    N
SetExternalSetpoint                              Y    Y     Y    Y    Y      Y    Y
StopExternalSetpointGeneration                   Y    Y     Y    Y    Y      Y    Y
AddToGroup                                       Y    Y     N    Y    Y      N    Y
RemoveFromGroup                                  Y    Y     N    Y    Y      N    Y
"""
MATRIX = {C(row.split()[0]): dict(zip(MODES, (cell == "Y" for cell in row.split()[1:]),
                                      strict=True))
          for row in MATRIX_TEXT.strip().splitlines()}
STREAM = {C.SET_EXTERNAL_SETPOINT, C.STOP_EXTERNAL_SETPOINT_GENERATION}
CELLS = [(command, mode) for command in MATRIX for mode in MODES]


def test_the_matrix_names_every_command_but_set_position():
    assert set(MATRIX) == set(C) - {C.SET_POSITION}


@pytest.mark.parametrize(("command", "mode"), CELLS, ids=[f"{c}-{title(m)}" for c, m in CELLS])
def test_acceptance_matrix_cell(command: MoverCommand, mode: MoverCommandMode):
    running = X.ABSOLUTE if mode is M.EXTERNAL_SETPOINT_GENERATION else X.NONE
    if command in STREAM and running is X.NONE:
        running = X.RELATIVE  # the stream commands need a generation that runs
    if MATRIX[command][mode]:
        check_accepts(S.ENABLED, mode, command, external=running)
        return
    with pytest.raises(CommandRejected) as rejected:
        check_accepts(S.ENABLED, mode, command, external=running)
    assert rejected.value.error_id is ErrorId.PLANAR_WRONG_MODE
    assert f"{command} is not accepted in command mode {title(mode)}" in rejected.value.message


@pytest.mark.parametrize(("command", "mode", "reason"), [
    (C.MOVE_ON_TRACK, M.FREE_MOVEMENT, "on no track: JoinTrack first"),
    (C.ADOPT_TRACK_ORIENTATION, M.C_ROTATION_FREE_MOVEMENT, "on no track: JoinTrack first"),
    (C.MOVE_TO_POSITION, M.ON_TRACK, "on a track: LeaveTrack first"),
    (C.MOVE_TO_POSITION, M.C_ROTATION_FREE_MOVEMENT, "X and Y stay locked"),
    (C.LEAVE_TRACK, M.C_ROTATION_ON_TRACK, "X and Y stay locked"),
    (C.HALT, M.JOINING_TRACK, "until it has joined the track"),
    (C.MOVE_C, M.LEAVING_TRACK, "until it has left the track"),
    (C.MOVE_Z, M.EXTERNAL_SETPOINT_GENERATION, "StopExternalSetpointGeneration first"),
])
def test_a_rejection_says_why(command: MoverCommand, mode: MoverCommandMode, reason: str):
    with pytest.raises(CommandRejected, match=reason):
        check_accepts(S.ENABLED, mode, command)


#: command -> the states that accept it; every other command needs Enabled
STATES_OF = {C.SET_POSITION: {S.DISABLED}, C.ADD_TO_GROUP: {S.DISABLED, S.ENABLED},
             C.REMOVE_FROM_GROUP: {S.DISABLED, S.ENABLED}}
STATE_CELLS = [(command, state) for command in C for state in S]


@pytest.mark.parametrize(("command", "state"), STATE_CELLS,
                         ids=[f"{c}-{title(s)}" for c, s in STATE_CELLS])
def test_acceptance_by_state(command: MoverCommand, state: PlanarState):
    mode = next(m for m in MODES if MATRIX.get(command, {}).get(m, True))  # one that accepts
    running = X.RELATIVE if command in STREAM else X.NONE
    if state in STATES_OF.get(command, {S.ENABLED}):
        check_accepts(state, mode, command, external=running)
        return
    with pytest.raises(CommandRejected) as rejected:
        check_accepts(state, mode, command, external=running)
    expected = ErrorId.PLANAR_NOT_DISABLED if command is C.SET_POSITION else (
        ErrorId.PLANAR_WRONG_STATE)
    assert rejected.value.error_id is expected
    assert f"the mover is {title(state)}" in rejected.value.message


def test_the_mode_does_not_count_while_disabled():
    check_accepts(S.DISABLED, M.JOINING_TRACK, C.SET_POSITION)
    check_accepts(S.DISABLED, M.LEAVING_TRACK, C.ADD_TO_GROUP)


@pytest.mark.parametrize("command", sorted(STREAM))
def test_stream_commands_need_a_running_generation(command: MoverCommand):
    with pytest.raises(CommandRejected, match="no external setpoint generation runs") as e:
        check_accepts(S.ENABLED, M.ON_TRACK, command)
    assert e.value.error_id is ErrorId.PLANAR_WRONG_MODE


@pytest.mark.parametrize("command", [C.START_EXTERNAL_SETPOINT_GENERATION,
                                     C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION])
def test_a_second_generation_is_rejected(command: MoverCommand):
    with pytest.raises(CommandRejected, match="a Relative external setpoint generation runs"):
        check_accepts(S.ENABLED, M.FREE_MOVEMENT, command, external=X.RELATIVE)


#                       Uninitialized Configuring Standing Moving   (§4.3)
TRACK_TEXT = """
JoinTrack                       N          Y          Y       N
LeaveTrack                      N          Y          Y       N
MoveOnTrack                     N          N          Y       Y
GearInPosOnTrack                N          N          Y       Y
GearInPosOnTrackWithMasterMover N          N          Y       Y
"""
TRACK_MODES = [TrackOperationMode.UNINITIALIZED, TrackOperationMode.CONFIGURING,
               TrackOperationMode.STANDING, TrackOperationMode.MOVING]
TRACK_CELLS = [(C(row.split()[0]), mode, cell == "Y")
               for row in TRACK_TEXT.strip().splitlines()
               for mode, cell in zip(TRACK_MODES, row.split()[1:], strict=True)]


@pytest.mark.parametrize(("command", "mode", "accepted"), TRACK_CELLS,
                         ids=[f"{c}-{title(m)}" for c, m, _ in TRACK_CELLS])
def test_track_acceptance(command: MoverCommand, mode: TrackOperationMode, accepted: bool):
    if accepted:
        check_track_accepts(S.ENABLED, mode, command)
        return
    with pytest.raises(CommandRejected, match=f"while the track is {title(mode)}") as e:
        check_track_accepts(S.ENABLED, mode, command)
    assert e.value.error_id is ErrorId.PLANAR_WRONG_MODE


def test_a_track_that_is_not_enabled_takes_no_mover():
    with pytest.raises(CommandRejected, match="the track is Disabled") as e:
        check_track_accepts(S.DISABLED, TrackOperationMode.STANDING, C.JOIN_TRACK)
    assert e.value.error_id is ErrorId.PLANAR_WRONG_STATE


def test_commands_without_a_track_rule_pass():
    check_track_accepts(S.DISABLED, TrackOperationMode.UNINITIALIZED, C.MOVE_C)


# -- command modes (§4.2) --------------------------------------------------------------------------


def c_move(start: float, end: float) -> Profile:
    return plan_position(KinematicState(start), end, PARAMETERS.default_dynamic_c)


def modes(c: float = 0.0) -> CommandModes:
    tracker = CommandModes(PARAMETERS.c_windows)
    tracker.enabled(c)
    return tracker


@pytest.mark.parametrize(("c", "mode"), [(0.0, M.FREE_MOVEMENT), (90.0, M.FREE_MOVEMENT),
                                         (20.0, M.C_ROTATION_FREE_MOVEMENT)])
def test_enable_starts_free_unless_c_lies_outside_every_window(c: float, mode: MoverCommandMode):
    assert modes(c).mode is mode and modes(c).external is X.NONE


def test_move_c_to_20_stays_in_c_rotation_and_on_to_90_returns():
    """§6.1.8: MoveC to 20° leaves FreeMovement; a further move to 90° ends it."""
    tracker = modes()
    tracker.c_motion_started(c_move(0.0, 20.0))
    assert tracker.mode is M.C_ROTATION_FREE_MOVEMENT
    tracker.c_at_rest(20.0)
    assert tracker.mode is M.C_ROTATION_FREE_MOVEMENT
    tracker.c_motion_started(c_move(20.0, 90.0))
    tracker.c_at_rest(90.0)
    assert tracker.mode is M.FREE_MOVEMENT


def test_a_small_c_move_never_leaves_free_movement():
    """§6.1.5: MoveC to 3° stays inside [-15, 15]."""
    tracker = modes()
    tracker.c_motion_started(c_move(0.0, 3.0))
    assert tracker.mode is M.FREE_MOVEMENT


def test_join_move_c_and_adopt_on_a_track():
    """§6.2.6, §6.2.7: joined, MoveC 190° rotates in CRotationOnTrack and ends OnTrack."""
    tracker = modes()
    tracker.started(C.JOIN_TRACK)
    assert tracker.mode is M.JOINING_TRACK
    tracker.ended(C.JOIN_TRACK, done=True, c=0.0)
    assert tracker.mode is M.ON_TRACK
    tracker.c_motion_started(c_move(0.0, 190.0))
    assert tracker.mode is M.C_ROTATION_ON_TRACK
    tracker.c_at_rest(120.0)  # halted outside every window
    assert tracker.mode is M.C_ROTATION_ON_TRACK
    tracker.c_motion_started(c_move(120.0, 180.0))  # AdoptTrackOrientation
    tracker.c_at_rest(180.0)
    assert tracker.mode is M.ON_TRACK


@pytest.mark.parametrize(("command", "done", "c", "mode"), [
    (C.JOIN_TRACK, False, 0.0, M.FREE_MOVEMENT),
    (C.JOIN_TRACK, False, 40.0, M.C_ROTATION_FREE_MOVEMENT),
    (C.LEAVE_TRACK, True, 0.0, M.FREE_MOVEMENT),
    (C.LEAVE_TRACK, False, 0.0, M.FREE_MOVEMENT),
])
def test_join_or_leave_that_ends_leaves_the_mover_free(command: MoverCommand, done: bool,
                                                      c: float, mode: MoverCommandMode):
    tracker = modes()
    tracker.started(command)
    assert tracker.mode is (M.JOINING_TRACK if command is C.JOIN_TRACK else M.LEAVING_TRACK)
    tracker.ended(command, done=done, c=c)
    assert tracker.mode is mode


def test_absolute_external_setpoints_own_the_mode_and_end_free():
    """§4.2, §6.1.6: ExternalSetpointGeneration, then FreeMovement after the stop."""
    tracker = modes()
    tracker.started(C.START_EXTERNAL_SETPOINT_GENERATION)
    assert (tracker.mode, tracker.external) == (M.EXTERNAL_SETPOINT_GENERATION, X.ABSOLUTE)
    tracker.ended(C.START_EXTERNAL_SETPOINT_GENERATION, done=True, c=0.0)
    assert (tracker.mode, tracker.external) == (M.FREE_MOVEMENT, X.NONE)


def test_relative_external_setpoints_leave_the_mode_alone():
    """§4.2: relative setpoints add to the mode's own; the mode is not ExternalSetpoint..."""
    tracker = modes()
    tracker.started(C.JOIN_TRACK)
    tracker.ended(C.JOIN_TRACK, done=True, c=0.0)
    tracker.started(C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION)
    assert (tracker.mode, tracker.external) == (M.ON_TRACK, X.RELATIVE)
    tracker.ended(C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION, done=True, c=0.0)
    assert (tracker.mode, tracker.external) == (M.ON_TRACK, X.NONE)


def test_other_commands_keep_the_mode():
    tracker = modes()
    for command in (C.MOVE_TO_POSITION, C.MOVE_Z, C.HALT, C.MOVE_C):
        tracker.started(command)
    assert tracker.mode is M.FREE_MOVEMENT
