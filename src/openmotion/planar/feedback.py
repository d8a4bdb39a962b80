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

from collections.abc import Callable
from dataclasses import dataclass
from enum import IntEnum
from typing import Any, ClassVar

from openmotion.core.errors import ErrorId
from openmotion.kernel.command import Command, CommandStatus
from openmotion.planar.enums import PlanarObjectType


@dataclass(frozen=True, slots=True)
class PlanarObjectInfo:
    """PlanarObjectInfo (§7.2.1.2.3): one planar object, e.g. the one a command would hit."""

    object_type: PlanarObjectType = PlanarObjectType.INVALID
    id: int = 0  #: the object's OID (UDINT)


class CommandPhase(IntEnum):
    """Where a command is, as TF5430 tells it. SENT and ACCEPTED look the same on a feedback
    (Busy only); both are the kernel's BUFFERED (``PlanarCommand.phase``)."""

    SENT = 0  #: called, not yet processed by the object
    ACCEPTED = 1  #: accepted, waits to execute
    ACTIVE = 2  #: executing
    DONE = 3
    ABORTED = 4  #: ended because another command started
    ERROR = 5  #: rejected, or failed while executing


_NO_INFO = PlanarObjectInfo()
_PHASES = {CommandStatus.ACTIVE: CommandPhase.ACTIVE, CommandStatus.DONE: CommandPhase.DONE,
           CommandStatus.ABORTED: CommandPhase.ABORTED, CommandStatus.ERROR: CommandPhase.ERROR}


class PlanarCommand(Command):
    """The kernel's command handle with what a planar feedback shows besides (D-238).

    ``done``, ``busy``, ``active``, ``aborted``, ``error``, ``error_id``, ``message``,
    ``issued_at`` and ``ended_at`` mean what they mean for every command; a planar command adds
    the colliding ``object_info`` (§6.7.2), ``in_sync`` (§7.2.2.6), the call's ``args``, the
    TF5430 ``phase`` and the feedback it shows its status on. The object reports progress with
    ``accept()``, ``start()``, ``finish()``, ``abort()`` and ``reject()``. The first report
    that ends the command wins and later ones are ignored, so aborting a command that has just
    finished is harmless.
    """

    __slots__ = ("args", "object_info", "in_sync", "_accepted", "_feedback", "_clock")

    def __init__(self, kind: str, feedback: MC_PlanarFeedbackBase | None = None,
                 args: tuple[Any, ...] = (), clock: Callable[[], float] | None = None) -> None:
        super().__init__(kind, clock() if clock is not None else 0.0)
        self.args = args  #: the call's arguments after the feedback, as given
        self.object_info = _NO_INFO
        self.in_sync = False  #: shown by MC_PlanarFeedbackInSync feedbacks
        self._accepted = False
        self._clock = clock  #: the runtime's time for ``ended_at``; None: ``issued_at``
        self._feedback = feedback
        if feedback is not None:  # from now on it shows this command (Busy), not an older one
            feedback.command = self
            show(feedback, self)

    @property
    def phase(self) -> CommandPhase:
        """The TF5430 view of ``status``: a buffered command is SENT or ACCEPTED."""
        if self.status is CommandStatus.BUFFERED:
            return CommandPhase.ACCEPTED if self._accepted else CommandPhase.SENT
        return _PHASES[self.status]

    def __repr__(self) -> str:
        return f"<PlanarCommand {self.kind} {self.phase.name}>"

    def accept(self) -> None:
        """The object took the command; it waits before it executes."""
        self._accepted = True

    def finish(self) -> None:
        """The command ended as it should (Done)."""
        self.end(CommandStatus.DONE, self._now())

    def abort(self) -> None:
        """Another command took over (Aborted)."""
        self.end(CommandStatus.ABORTED, self._now())

    def reject(self, error_id: ErrorId, message: str,
               object_info: PlanarObjectInfo | None = None) -> None:
        """The command was refused, or could not go on (Error). ``object_info`` names the
        collision partner (§6.7.2); without one it keeps its reset value (Invalid, 0)."""
        self.end(CommandStatus.ERROR, self._now(), error_id, message, object_info or _NO_INFO)

    def end(self, status: CommandStatus, now: float, error_id: ErrorId = ErrorId.NO_ERROR,
            message: str = "", object_info: PlanarObjectInfo = _NO_INFO) -> None:
        """``Command.end`` that also sets ``object_info`` and drops ``in_sync``."""
        if self.finished:
            return
        super().end(status, now, error_id, message)
        self.object_info = object_info
        self.in_sync = False

    def publish(self) -> None:
        """Show the status on the feedback, unless a newer command has taken it over."""
        if self._feedback is not None and self._feedback.command is self:
            self._feedback.update()

    def _now(self) -> float:
        return self._clock() if self._clock is not None else self.issued_at


class CommandQueue:
    """The commands sent to one planar object, in call order.

    The object's ``update()`` takes them (``take()``), processes them and ends with
    ``publish()``. That shows every command taken so far and still running, or ended since
    the last publish, on its feedback. Ended commands are then dropped. ``clock`` gives the
    runtime's time for the commands' ``issued_at`` and ``ended_at``.
    """

    def __init__(self, clock: Callable[[], float] | None = None) -> None:
        self._sent: list[PlanarCommand] = []
        self._open: list[PlanarCommand] = []
        self._clock = clock

    def send(self, kind: str, feedback: MC_PlanarFeedbackBase | None = None,
             *args: Any) -> PlanarCommand:
        """Record a method call; the object processes it in its next ``update()``."""
        command = PlanarCommand(kind, feedback, args, self._clock)
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


def show(feedback: MC_PlanarFeedbackBase, command: PlanarCommand) -> None:
    """Set the outputs of ``feedback`` (its ``SHOWS``) from ``command``'s status."""
    for name in feedback.SHOWS:
        setattr(feedback, name, getattr(command, name))


class MC_PlanarFeedbackBase:
    """What every feedback shows (§7.2.2.3): Active, Busy, Aborted, Error, ErrorId and
    objectInfo. ``message`` is openmotion's readable reason for an error."""

    #: its outputs, each the command attribute of the same name (``show``)
    SHOWS: ClassVar[tuple[str, ...]] = ("busy", "active", "aborted", "error", "error_id",
                                        "object_info", "message")

    def __init__(self) -> None:
        #: the command it shows: the one it was last passed with (openmotion's link, no output)
        self.command: PlanarCommand | None = None
        self.active = False
        self.busy = False
        self.aborted = False
        self.error = False
        self.error_id = ErrorId.NO_ERROR
        self.object_info = _NO_INFO
        self.message = ""

    def update(self) -> None:
        """Show the status of the command this feedback follows (§7.2.2.2.1)."""
        if self.command is not None:
            show(self, self.command)


class MC_PlanarFeedback(MC_PlanarFeedbackBase):
    """The general feedback (§7.2.2.2), accepted by most commands; adds Done."""

    SHOWS = (*MC_PlanarFeedbackBase.SHOWS, "done")

    def __init__(self) -> None:
        super().__init__()
        self.done = False


class MC_PlanarFeedbackInSync(MC_PlanarFeedbackBase):
    """Base of the feedbacks with inSync (§7.2.2.6). They have no Done: a gear command runs
    until another command or an error ends it (§6.2.8)."""

    SHOWS = (*MC_PlanarFeedbackBase.SHOWS, "in_sync")

    def __init__(self) -> None:
        super().__init__()
        self.in_sync = False


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

    def __init__(self, clock: Callable[[], float] | None = None) -> None:
        self._clock = clock  #: the runtime's time, for the commands' ``issued_at``/``ended_at``
        self._command: PlanarCommand | None = None
        self._feedback: MC_PlanarFeedbackBase | None = None
        self._pending: tuple[ErrorId, str, PlanarObjectInfo | None] | None = None

    def call(self, feedback: MC_PlanarFeedbackBase | None) -> None:
        """One SetExternalSetpointReferenceId call: show what was reported before it."""
        command = self._command
        if command is None:
            self._feedback = feedback
            command = self._command = PlanarCommand(self.KIND, feedback, clock=self._clock)
            command.start()
        elif feedback is not None and feedback is not self._feedback:
            other = PlanarCommand(self.KIND, feedback, clock=self._clock)
            other.reject(ErrorId.PLANAR_EXT_SETPOINT,
                         "pass the same feedback with every call (§6.1.7)")
            other.publish()
            return
        if self._pending is not None:
            command.reject(*self._pending)
            self._pending = None
        command.publish()

    def report(self, error_id: ErrorId, message: str,
               object_info: PlanarObjectInfo | None = None) -> None:
        """An error of the setpoint stream; the first one shows after the next call."""
        if self._pending is None:
            self._pending = (error_id, message, object_info)
