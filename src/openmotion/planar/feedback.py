"""Command feedback (TF5430 §6.7, §7.2.2.2-7.2.2.6) and the object side that fills it.

Lifecycle:

* Sending a command attaches its feedback. From then on the feedback shows Busy only, and the
  result of an earlier command is gone: a reused feedback must not show a stale Done.
* The object takes its commands in call order in its ``update()`` and ends that update with
  ``CommandQueue.publish()``. The user therefore reads the result in the next cycle (§6.7.1
  waits for ``feedback.Done`` in a later cycle): Busy while sent or waiting, Busy and Active
  while executing, then exactly one of Done, Aborted and Error.
* A command whose feedback has been attached to a newer command no longer writes to it.
* ``feedback=None`` is the PLC's 0: the command runs as usual and only its ``PlanarCommand``
  keeps the status.
* ``update()``, the manual's method, shows the status of the attached command. The object
  already calls it, so a user who calls it as well (PLC style) sees nothing new.

The feedback of SetExternalSetpointReferenceId follows its own rules (§6.1.7):
``ExternalSetpointStream``.
"""

# ruff: noqa: N801 - the manual's block names

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Any

from openmotion.core.errors import ErrorId
from openmotion.planar.enums import PlanarObjectType


@dataclass(frozen=True, slots=True)
class PlanarObjectInfo:
    """PlanarObjectInfo (§7.2.1.2.3): one planar object, e.g. the one a command would hit."""

    object_type: PlanarObjectType = PlanarObjectType.INVALID
    id: int = 0  #: the object's OID (UDINT)


class CommandPhase(IntEnum):
    """Where a command is. SENT and ACCEPTED look the same on a feedback: Busy only."""

    SENT = 0  #: called, not yet processed by the object
    ACCEPTED = 1  #: accepted, waits to execute
    ACTIVE = 2  #: executing
    DONE = 3
    ABORTED = 4  #: ended because another command started
    ERROR = 5  #: rejected, or failed while executing


_NO_INFO = PlanarObjectInfo()


class PlanarCommand:
    """One command as the object that runs it sees it: the MC side of a feedback.

    The object reports progress with ``accepted()``, ``started()``, ``finished()``,
    ``aborted()`` and ``rejected()``. The first report that ends the command wins and later
    ones are ignored, so aborting a command that has just finished is harmless.
    """

    __slots__ = ("kind", "args", "phase", "error_id", "message", "object_info", "in_sync",
                 "warnings", "_feedback")

    def __init__(self, kind: str, feedback: MC_PlanarFeedbackBase | None = None,
                 args: tuple[Any, ...] = ()) -> None:
        self.kind = kind  #: the manual's method name, e.g. "MoveToPosition"
        self.args = args  #: the call's arguments after the feedback, as given
        self.phase = CommandPhase.SENT
        self.error_id = ErrorId.NO_ERROR
        self.message = ""
        self.object_info = _NO_INFO
        self.in_sync = False  #: shown by MC_PlanarFeedbackInSync feedbacks
        self.warnings: list[str] = []  #: e.g. a clipped constraint (§6.1.9); no output shows it
        self._feedback = feedback
        if feedback is not None:
            feedback._command = self
            feedback._show(self)

    @property
    def busy(self) -> bool:
        """Sent, waiting or executing: the command has not ended."""
        return self.phase <= CommandPhase.ACTIVE

    active = property(lambda self: self.phase is CommandPhase.ACTIVE)
    done = property(lambda self: self.phase is CommandPhase.DONE)
    error = property(lambda self: self.phase is CommandPhase.ERROR)

    def __repr__(self) -> str:
        return f"<PlanarCommand {self.kind} {self.phase.name}>"

    def accepted(self) -> None:
        """The object took the command; it waits before it executes."""
        if self.phase is CommandPhase.SENT:
            self.phase = CommandPhase.ACCEPTED

    def started(self) -> None:
        """The command executes now (Active)."""
        if self.phase < CommandPhase.ACTIVE:
            self.phase = CommandPhase.ACTIVE

    def finished(self) -> None:
        """The command ended as it should (Done)."""
        self._end(CommandPhase.DONE)

    def aborted(self) -> None:
        """Another command took over (Aborted)."""
        self._end(CommandPhase.ABORTED)

    def rejected(self, error_id: ErrorId, message: str,
                 object_info: PlanarObjectInfo | None = None) -> None:
        """The command was refused, or could not go on (Error). ``object_info`` names the
        collision partner (§6.7.2); without one it keeps its reset value (Invalid, 0)."""
        self._end(CommandPhase.ERROR, error_id, message, object_info or _NO_INFO)

    def publish(self) -> None:
        """Show the status on the feedback, unless a newer command has taken it over."""
        if self._feedback is not None and self._feedback._command is self:
            self._feedback.update()

    def _end(self, phase: CommandPhase, error_id: ErrorId = ErrorId.NO_ERROR, message: str = "",
             object_info: PlanarObjectInfo = _NO_INFO) -> None:
        if not self.busy:
            return
        self.phase = phase
        self.error_id = error_id
        self.message = message
        self.object_info = object_info
        self.in_sync = False


class CommandQueue:
    """The commands sent to one planar object, in call order.

    The object's ``update()`` takes them (``take()``), processes them and ends with
    ``publish()``. That shows every command taken so far and still running, or ended since
    the last publish, on its feedback. Ended commands are then dropped.
    """

    def __init__(self) -> None:
        self._sent: list[PlanarCommand] = []
        self._open: list[PlanarCommand] = []

    def send(self, kind: str, feedback: MC_PlanarFeedbackBase | None = None,
             *args: Any) -> PlanarCommand:
        """Record a method call; the object processes it in its next ``update()``."""
        command = PlanarCommand(kind, feedback, args)
        self._sent.append(command)
        return command

    def take(self) -> list[PlanarCommand]:
        """The commands sent since the last call, oldest first."""
        sent, self._sent = self._sent, []
        self._open += sent
        return sent

    def publish(self) -> None:
        for command in self._open:
            command.publish()
        self._open = [command for command in self._open if command.busy]


class MC_PlanarFeedbackBase:
    """What every feedback shows (§7.2.2.3): Active, Busy, Aborted, Error, ErrorId and
    objectInfo. ``message`` is openmotion's readable reason for an error."""

    def __init__(self) -> None:
        self._command: PlanarCommand | None = None
        self.active = False
        self.busy = False
        self.aborted = False
        self.error = False
        self.error_id = ErrorId.NO_ERROR
        self.object_info = _NO_INFO
        self.message = ""

    def update(self) -> None:
        """Show the status of the command this feedback follows (§7.2.2.2.1)."""
        if self._command is not None:
            self._show(self._command)

    def _show(self, command: PlanarCommand) -> None:
        phase = command.phase
        self.busy = command.busy
        self.active = phase is CommandPhase.ACTIVE
        self.aborted = phase is CommandPhase.ABORTED
        self.error = phase is CommandPhase.ERROR
        self.error_id = command.error_id
        self.object_info = command.object_info
        self.message = command.message


class MC_PlanarFeedback(MC_PlanarFeedbackBase):
    """The general feedback (§7.2.2.2), accepted by most commands; adds Done."""

    def __init__(self) -> None:
        super().__init__()
        self.done = False

    def _show(self, command: PlanarCommand) -> None:
        super()._show(command)
        self.done = command.phase is CommandPhase.DONE


class MC_PlanarFeedbackInSync(MC_PlanarFeedbackBase):
    """Base of the feedbacks with inSync (§7.2.2.6). They have no Done: a gear command runs
    until another command or an error ends it (§6.2.8)."""

    def __init__(self) -> None:
        super().__init__()
        self.in_sync = False

    def _show(self, command: PlanarCommand) -> None:
        super()._show(command)
        self.in_sync = command.in_sync


class MC_PlanarFeedbackGearInPosOnTrack(MC_PlanarFeedbackInSync):
    """Feedback of GearInPosOnTrack (§7.2.2.4): inSync with the master axis."""


class MC_PlanarFeedbackGearInPosOnTrackWithMasterMover(MC_PlanarFeedbackInSync):
    """Feedback of GearInPosOnTrackWithMasterMover (§7.2.2.5): inSync with the master mover."""


class ExternalSetpointStream:
    """The feedback given to SetExternalSetpointReferenceId, object side (§6.1.7).

    The same feedback comes with every call, and each call updates it: no ``update()`` is
    needed and the object does not publish it. It is Busy and Active from the first call. An
    error the object reports shows after the next call, so it may stem from an earlier cycle.
    Stopping the generation does not make it Done, and Halt does not abort it: it keeps its
    last outputs. The object makes a new stream for each StartExternalSetpointGeneration.
    """

    KIND = "SetExternalSetpointReferenceId"

    def __init__(self) -> None:
        self._command: PlanarCommand | None = None
        self._feedback: MC_PlanarFeedbackBase | None = None
        self._pending: tuple[ErrorId, str, PlanarObjectInfo | None] | None = None

    def call(self, feedback: MC_PlanarFeedbackBase | None) -> None:
        """One SetExternalSetpointReferenceId call: show what was reported before it."""
        command = self._command
        if command is None:
            self._feedback = feedback
            command = self._command = PlanarCommand(self.KIND, feedback)
            command.started()
        elif feedback is not None and feedback is not self._feedback:
            other = PlanarCommand(self.KIND, feedback)
            other.rejected(ErrorId.PLANAR_EXT_SETPOINT,
                           "pass the same feedback with every call (§6.1.7)")
            other.publish()
            return
        if self._pending is not None:
            command.rejected(*self._pending)
            self._pending = None
        command.publish()

    def report(self, error_id: ErrorId, message: str,
               object_info: PlanarObjectInfo | None = None) -> None:
        """An error of the setpoint stream; the first one shows after the next call."""
        if self._pending is None:
            self._pending = (error_id, message, object_info)
