"""The PLCopen FB protocol, written once (TcMC §7.1; digest §1.3-1.6).

* Execute blocks start on the rising edge of ``execute``. Busy (and Active where the command
  controls the axis) follow the command. Done, CommandAborted and Error stay TRUE while
  ``execute`` stays TRUE, and show for exactly one call when ``execute`` was already FALSE.
  At most one of them is TRUE; ``error_id`` is 0 unless ``error``.
* Enable blocks act on every call while ``enable`` is TRUE.

Calling a block with keyword inputs evaluates it for this cycle:
``move(axis, execute=True, position=100.0, velocity=50.0)``. A misspelt input is a Python
``TypeError`` at once; a bad value is an FB error, never an exception.
"""

from __future__ import annotations

import difflib
from typing import Any, ClassVar

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.kernel.command import Command, CommandStatus

#: what a block acts on: an axis, an axes group, a CA group; the kernel names none of them
Target = Any

_NO_ERROR = ErrorId.NO_ERROR


class FunctionBlock:
    """Base of every FB: keyword inputs with defaults, an axis reference, strict checks."""

    INPUTS: ClassVar[dict[str, Any]] = {}
    strict: ClassVar[bool] = False  #: check the output invariants on every call (tests)
    _names: ClassVar[frozenset[str]] = frozenset()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        merged: dict[str, Any] = {}
        for base in reversed(cls.__mro__):
            merged.update(base.__dict__.get("INPUTS", {}))
        cls.INPUTS = merged
        cls._names = frozenset(merged) | {"axis"}

    def __init__(self, axis: Target | None = None, **inputs: Any) -> None:
        self.axis = axis
        self.__dict__.update(self.INPUTS)
        self._reset_outputs()
        if inputs:
            self._set_inputs(inputs)

    def _set_inputs(self, inputs: dict[str, Any]) -> None:
        if not self._names.issuperset(inputs):
            unknown = sorted(set(inputs) - self._names)[0]
            close = difflib.get_close_matches(unknown, sorted(self._names), n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise TypeError(f"{type(self).__name__} has no input {unknown!r}{hint}")
        self.__dict__.update(inputs)

    def _reset_outputs(self) -> None:
        self.error = False
        self.error_id = _NO_ERROR
        self.message = ""

    def _axis(self) -> Target:
        if self.axis is None:
            raise TypeError(f"{type(self).__name__} needs an axis: call it as fb(axis, ...)")
        return self.axis


class ExecuteBlock(FunctionBlock):
    """Rising edge of ``execute`` starts a command; outputs follow the command handle."""

    INPUTS: ClassVar[dict[str, Any]] = {"execute": False}
    retriggerable: ClassVar[bool] = False  #: a new edge while busy modifies the command

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.done = False
        self.busy = False
        self.active = False
        self.command_aborted = False
        self._command: Command | None = None
        self._shown = False
        self._last_execute = False

    def __call__(self, axis: Target | None = None, /, **inputs: Any) -> None:
        if inputs:
            self._set_inputs(inputs)
        if axis is not None:
            self.axis = axis
        execute = self.execute
        if execute and not self._last_execute:
            self._rising_edge()
        elif not execute and self._last_execute:
            self._falling_edge()
        self._last_execute = execute
        self._refresh(execute)
        if self.strict:
            self._check_invariants()

    @property
    def command(self) -> Command | None:
        """The command behind the outputs (the Python layer's handle)."""
        return self._command

    def _rising_edge(self) -> None:
        command = self._command
        if (self.retriggerable and command is not None and command.busy
                and self._retrigger(command)):
            return
        self._clear()
        try:
            self._command = self._issue(self._axis())
        except CommandRejected as rejected:  # a block-level check before any axis call
            self._command = Command(type(self).__name__, 0.0)
            self._command.end(CommandStatus.ERROR, 0.0, rejected.error_id, rejected.message)

    def _clear(self) -> None:
        self.done = self.busy = self.active = self.command_aborted = self.error = False
        self.error_id = _NO_ERROR
        self.message = ""
        self._shown = False

    def _falling_edge(self) -> None:
        """Hook for blocks whose command depends on the level (MC_Stop's hold)."""

    def _refresh(self, execute: bool) -> None:
        command = self._command
        if command is None:
            return
        status = command.status
        if status <= CommandStatus.ACTIVE:
            self.busy = True
            self.active = status is CommandStatus.ACTIVE
            self._show_progress(command)
            return
        if not self._shown:
            self._shown = True
            self.busy = self.active = False
            self.done = status is CommandStatus.DONE
            self.command_aborted = status is CommandStatus.ABORTED
            self.error = status is CommandStatus.ERROR
            self.error_id = command.error_id if self.error else _NO_ERROR
            self.message = command.message
            self._show_result(command)
        elif not execute:
            self._clear()
            self._show_result(None)
            self._command = None

    def _show_progress(self, command: Command) -> None:
        """Hook: outputs that change while the command runs (InVelocity)."""

    def _show_result(self, command: Command | None) -> None:
        """Hook: block-specific outputs at the end (None when they are cleared)."""

    def _issue(self, axis: Target) -> Command:
        raise NotImplementedError

    def _retrigger(self, command: Command) -> bool:
        return False

    def _check_invariants(self) -> None:
        terminal = self.done + self.command_aborted + self.error
        assert terminal <= 1, f"{type(self).__name__}: more than one of done/aborted/error"
        assert not (self.busy and terminal), f"{type(self).__name__}: busy with a result"
        assert self.error or self.error_id == _NO_ERROR, "error_id without error"
        command = self._command
        assert not (self._shown and command is not None and command.finished
                    and terminal == 0), f"{type(self).__name__}: ended without a result"


class EnableBlock(FunctionBlock):
    """Level-triggered: acts on every call while ``enable`` is TRUE."""

    INPUTS: ClassVar[dict[str, Any]] = {"enable": False}

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.done = False
        self._last_enable = False

    def __call__(self, axis: Target | None = None, /, **inputs: Any) -> None:
        if inputs:
            self._set_inputs(inputs)
        if axis is not None:
            self.axis = axis
        enable = self.enable
        rising = enable and not self._last_enable
        self._last_enable = enable
        if not enable:
            self._disabled()
            return
        try:
            self._enabled(self._axis(), rising)
            self.error, self.error_id, self.message = False, _NO_ERROR, ""
        except CommandRejected as rejected:
            self.done = False
            self.error, self.error_id, self.message = True, rejected.error_id, rejected.message

    def _enabled(self, axis: Target, rising: bool) -> None:
        raise NotImplementedError

    def _disabled(self) -> None:
        self.done = self.error = False
        self.error_id = _NO_ERROR
        self.message = ""
