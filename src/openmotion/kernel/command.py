"""The command handle every system gives its callers: one status, one way to finish.

Blocks and the Python layer read ``done``, ``busy``, ``active``, ``aborted``, ``error`` and
``error_id``; the system that runs the command starts it with ``start`` and finishes it with
``end``. Every system hands out this type: the planar objects a subclass with the TF5430
feedback's extra outputs (planar/feedback.py, D-238).
"""

from __future__ import annotations

from enum import IntEnum

from openmotion.core.errors import ErrorId


class CommandStatus(IntEnum):
    BUFFERED = 0  #: accepted, waits for the command before it
    ACTIVE = 1  #: controls the axis
    DONE = 2
    ABORTED = 3
    ERROR = 4


class Command:
    """What a user holds after issuing a command: ``done``, ``busy``, ``error_id``, ...

    ``hold`` keeps a finished stop in force (PLCopen: the axis stays in Stopping while
    MC_Stop.Execute is TRUE); the FB releases it on the falling edge.
    """

    __slots__ = ("kind", "status", "error_id", "message", "warnings", "in_velocity", "hold",
                 "issued_at", "ended_at", "value")

    def __init__(self, kind: str, issued_at: float) -> None:
        self.kind = kind
        self.status = CommandStatus.BUFFERED
        self.error_id = ErrorId.NO_ERROR
        self.message = ""
        self.warnings: list[str] = []
        self.in_velocity = False
        self.hold = False
        self.issued_at = issued_at
        self.ended_at: float | None = None
        self.value: object = None  #: a result, for commands that return one

    @property
    def done(self) -> bool:
        return self.status is CommandStatus.DONE

    @property
    def busy(self) -> bool:
        return self.status <= CommandStatus.ACTIVE

    @property
    def active(self) -> bool:
        return self.status is CommandStatus.ACTIVE

    @property
    def aborted(self) -> bool:
        return self.status is CommandStatus.ABORTED

    @property
    def error(self) -> bool:
        return self.status is CommandStatus.ERROR

    @property
    def finished(self) -> bool:
        """Done, aborted or failed: nothing more will happen."""
        return self.status > CommandStatus.ACTIVE

    def start(self) -> None:
        """The command controls its object now (Active); an active or ended one stays so."""
        if self.status is CommandStatus.BUFFERED:
            self.status = CommandStatus.ACTIVE

    def release(self) -> None:
        """End a held stop (the falling edge of MC_Stop.Execute)."""
        self.hold = False

    def end(self, status: CommandStatus, now: float, error_id: ErrorId = ErrorId.NO_ERROR,
            message: str = "") -> None:
        """Finish the command at ``now`` as DONE, ABORTED or ERROR (with its error id and
        a readable ``message``); a command that has finished already stays as it ended."""
        if self.status > CommandStatus.ACTIVE:
            return
        self.status = status
        self.error_id = error_id
        self.message = message
        self.in_velocity = False
        self.ended_at = now

    def __repr__(self) -> str:
        detail = f" {self.error_id.name}: {self.message}" if self.error else ""
        return f"<Command {self.kind} {self.status.name}{detail}>"
