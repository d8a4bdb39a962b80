"""Command feedback (TF5430 §6.7, §7.2.2.2-7.2.2.6; digest-planar-concepts §2.7).

``queue.send`` is the user's method call; ``queue.take()`` and ``queue.publish()`` frame the
object's update in which the command is processed. What a test reads after ``publish()`` is
what the user reads in the next cycle.
"""

from __future__ import annotations

import pytest

from openmotion.core.errors import ErrorId
from openmotion.planar.enums import PlanarObjectType
from openmotion.planar.feedback import (
    CommandPhase,
    CommandQueue,
    ExternalSetpointStream,
    MC_PlanarFeedback,
    MC_PlanarFeedbackBase,
    MC_PlanarFeedbackGearInPosOnTrack,
    MC_PlanarFeedbackGearInPosOnTrackWithMasterMover,
    MC_PlanarFeedbackInSync,
    PlanarCommand,
    PlanarObjectInfo,
)

ENVIRONMENT = PlanarObjectInfo(PlanarObjectType.ENVIRONMENT, 0x05120010)


def outputs(feedback: MC_PlanarFeedbackBase) -> str:
    """The feedback's flags as a word, e.g. 'busy active' or 'done'; checks the invariants."""
    flags = [flag for flag in ("busy", "active", "done", "aborted", "error", "in_sync")
             if getattr(feedback, flag, False)]
    ends = {"done", "aborted", "error"} & set(flags)
    assert len(ends) <= 1 and not (ends and feedback.busy), flags
    assert feedback.busy or not feedback.active, "active without busy"
    assert feedback.error or feedback.error_id is ErrorId.NO_ERROR, "error_id without error"
    return " ".join(flags) or "-"


def processed(queue: CommandQueue) -> PlanarCommand:
    """The one command sent since the last update."""
    (command,) = queue.take()
    return command


def test_a_new_feedback_shows_nothing():
    feedback = MC_PlanarFeedback()
    assert outputs(feedback) == "-"
    assert feedback.object_info == PlanarObjectInfo(PlanarObjectType.INVALID, 0)
    assert (feedback.error_id, feedback.message) == (ErrorId.NO_ERROR, "")
    feedback.update()  # nothing attached: nothing to show
    assert outputs(feedback) == "-"


def test_lifecycle_busy_active_done_each_one_update_after_the_change():
    queue, feedback = CommandQueue(), MC_PlanarFeedback()
    queue.send("MoveToPosition", feedback, (1000.0, 1000.0))
    assert outputs(feedback) == "busy"  # sent: being processed
    command = processed(queue)
    assert command.args == ((1000.0, 1000.0),)
    command.start()
    assert outputs(feedback) == "busy"  # the object's update has not published yet
    queue.publish()
    assert outputs(feedback) == "busy active"
    command.finish()
    assert outputs(feedback) == "busy active"
    queue.publish()
    assert outputs(feedback) == "done"  # §6.7.1: Done, not Active, not Busy


def test_an_accepted_command_that_waits_is_busy_but_not_active():
    queue, feedback = CommandQueue(), MC_PlanarFeedback()
    queue.send("MoveOnTrack", feedback)
    command = processed(queue)
    command.accept()
    queue.publish()
    assert command.phase is CommandPhase.ACCEPTED and outputs(feedback) == "busy"
    command.start()
    command.accept()  # no way back
    queue.publish()
    assert command.phase is CommandPhase.ACTIVE and outputs(feedback) == "busy active"


def test_collision_rejection_names_the_partner():
    """§6.7.2: 33158 (16#8186) with the environment 16#05120010 (85065744) as partner."""
    queue, feedback = CommandQueue(), MC_PlanarFeedback()
    queue.send("MoveToPosition", feedback)
    processed(queue).reject(ErrorId.PLANAR_COLLISION, "area reserved", ENVIRONMENT)
    queue.publish()
    assert outputs(feedback) == "error"
    assert feedback.error_id == 33158
    assert feedback.object_info.object_type is PlanarObjectType.ENVIRONMENT
    assert feedback.object_info.id == 85065744
    assert feedback.message == "area reserved"


def test_a_rejection_without_partner_keeps_the_reset_object_info():
    queue, feedback = CommandQueue(), MC_PlanarFeedback()
    queue.send("JoinTrack", feedback)
    processed(queue).reject(ErrorId.PLANAR_WRONG_MODE, "on a track")
    queue.publish()
    assert feedback.error and feedback.object_info == PlanarObjectInfo()


def test_a_newer_command_aborts_the_running_one():
    queue, first, second = CommandQueue(), MC_PlanarFeedback(), MC_PlanarFeedback()
    queue.send("MoveToPosition", first)
    running = processed(queue)
    running.start()
    queue.publish()
    queue.send("MoveToPosition", second)
    newer = processed(queue)
    running.abort()
    newer.start()
    queue.publish()
    assert outputs(first) == "aborted" and outputs(second) == "busy active"


def test_a_reused_feedback_resets_at_once_and_follows_only_the_new_command():
    """§6.7.1 reuses one feedback for Enable and then MoveToPosition."""
    queue, feedback = CommandQueue(), MC_PlanarFeedback()
    queue.send("Enable", feedback)
    enable = processed(queue)
    enable.finish()
    queue.publish()
    assert outputs(feedback) == "done"
    queue.send("MoveToPosition", feedback)
    assert outputs(feedback) == "busy"  # the old Done is gone with the call
    move = processed(queue)
    move.start()
    queue.publish()
    enable.abort()  # ignored: it ended already
    enable.publish()  # ignored: the feedback follows the move now
    assert outputs(feedback) == "busy active"


def test_the_old_command_no_longer_writes_to_a_reused_feedback():
    queue, feedback = CommandQueue(), MC_PlanarFeedback()
    queue.send("MoveToPosition", feedback)
    old = processed(queue)
    old.start()
    queue.publish()
    queue.send("MoveToPosition", feedback)
    new = processed(queue)
    old.abort()
    new.reject(ErrorId.PLANAR_COLLISION, "reserved", ENVIRONMENT)
    queue.publish()
    assert outputs(feedback) == "error" and feedback.error_id is ErrorId.PLANAR_COLLISION
    assert old.phase is CommandPhase.ABORTED


def test_the_first_end_wins():
    command = PlanarCommand("Halt")
    command.finish()
    command.abort()
    command.reject(ErrorId.PLANAR_WRONG_STATE, "late")
    command.start()
    assert (command.phase, command.error_id, command.busy) == (
        CommandPhase.DONE, ErrorId.NO_ERROR, False)


def test_no_feedback_is_plc_zero_and_the_command_still_keeps_its_status():
    queue = CommandQueue()
    queue.send("MoveZ", None, 5.0)
    command = processed(queue)
    command.start()
    queue.publish()
    command.reject(ErrorId.PLANAR_POSITION_LIMIT, "z above 6 mm")
    queue.publish()
    assert command.phase is CommandPhase.ERROR and command.message == "z above 6 mm"


def test_the_user_update_shows_what_the_object_published():
    queue, feedback = CommandQueue(), MC_PlanarFeedback()
    queue.send("MoveC", feedback)
    processed(queue).finish()
    queue.publish()
    feedback.update()
    feedback.update()
    assert outputs(feedback) == "done"


class CountingFeedback(MC_PlanarFeedback):
    def __init__(self) -> None:
        super().__init__()
        self.updates = 0

    def update(self) -> None:
        self.updates += 1
        super().update()


def test_publish_shows_taken_commands_until_they_end_then_drops_them():
    queue, feedback = CommandQueue(), CountingFeedback()
    queue.send("MoveToPosition", feedback)
    queue.publish()
    assert feedback.updates == 0  # sent, not taken: the object has not seen it
    command = processed(queue)
    command.start()
    queue.publish()
    queue.publish()
    command.finish()
    queue.publish()
    queue.publish()
    assert feedback.updates == 3


def test_take_returns_the_calls_in_order_once():
    queue = CommandQueue()
    for kind in ("MoveA", "MoveB", "MoveC", "MoveZ"):  # §6.1.5: four calls in one cycle
        queue.send(kind)
    assert [command.kind for command in queue.take()] == ["MoveA", "MoveB", "MoveC", "MoveZ"]
    assert queue.take() == []


@pytest.mark.parametrize("kind", [MC_PlanarFeedbackGearInPosOnTrack,
                                  MC_PlanarFeedbackGearInPosOnTrackWithMasterMover])
def test_gear_feedbacks_show_in_sync_and_have_no_done(kind: type[MC_PlanarFeedbackInSync]):
    """§7.2.2.4-7.2.2.5: Active, Busy, Aborted, Error, ErrorId, objectInfo, inSync."""
    queue, feedback = CommandQueue(), kind()
    assert isinstance(feedback, MC_PlanarFeedbackInSync) and not hasattr(feedback, "done")
    queue.send("GearInPosOnTrack", feedback)
    command = processed(queue)
    command.start()
    command.in_sync = True
    queue.publish()
    assert outputs(feedback) == "busy active in_sync"
    command.in_sync = False  # sync lost while braking for the gap (§6.2.8)
    queue.publish()
    assert outputs(feedback) == "busy active"
    command.in_sync = True
    command.abort()
    queue.publish()
    assert outputs(feedback) == "aborted"  # out of sync once it ended


def test_a_finished_gear_command_only_stops_being_busy():
    queue, feedback = CommandQueue(), MC_PlanarFeedbackGearInPosOnTrack()
    queue.send("GearInPosOnTrack", feedback)
    processed(queue).finish()
    queue.publish()
    assert outputs(feedback) == "-"


# -- the feedback of SetExternalSetpointReferenceId (§6.1.7) --------------------------------------


def test_stream_feedback_is_busy_from_the_first_call_without_update():
    stream, feedback = ExternalSetpointStream(), MC_PlanarFeedback()
    stream.call(feedback)
    assert outputs(feedback) == "busy active"
    stream.call(feedback)
    assert outputs(feedback) == "busy active"


def test_stream_error_shows_after_the_next_call():
    stream, feedback = ExternalSetpointStream(), MC_PlanarFeedback()
    stream.call(feedback)
    stream.report(ErrorId.INVALID_REFERENCE_ID, "no such coordinate system")
    stream.report(ErrorId.PLANAR_EXT_SETPOINT, "a later error")
    feedback.update()
    assert outputs(feedback) == "busy active"  # not before the next call
    stream.call(feedback)
    assert outputs(feedback) == "error"
    assert feedback.error_id is ErrorId.INVALID_REFERENCE_ID  # the first, from an earlier cycle
    stream.report(ErrorId.PLANAR_EXT_SETPOINT, "after the end")
    stream.call(feedback)
    assert feedback.error_id is ErrorId.INVALID_REFERENCE_ID


def test_stream_feedback_is_neither_done_on_stop_nor_aborted_by_halt():
    """The object drops the stream on Stop; a Halt goes to its own feedback."""
    stream, feedback, halt = ExternalSetpointStream(), MC_PlanarFeedback(), MC_PlanarFeedback()
    queue = CommandQueue()
    stream.call(feedback)
    queue.send("Halt", halt)
    processed(queue).finish()
    queue.publish()
    feedback.update()
    assert outputs(feedback) == "busy active" and outputs(halt) == "done"


def test_stream_wants_the_same_feedback_every_call():
    stream, feedback, other = ExternalSetpointStream(), MC_PlanarFeedback(), MC_PlanarFeedback()
    stream.call(feedback)
    stream.call(other)
    assert outputs(other) == "error" and other.error_id is ErrorId.PLANAR_EXT_SETPOINT
    assert outputs(feedback) == "busy active"
    stream.call(None)  # PLC 0: nothing to show
    assert outputs(feedback) == "busy active"
