"""One cyclic task with virtual time: programs, systems, observers (architecture §cycle).

``run`` and ``run_until`` only loop ``step``, as SimPy's ``Environment.run`` loops ``step``.
A cycle runs the programs, then every system's motion phase, then every system's drive
phase, then the observers; within a phase, in the order things were added (kernel/system.py),
so the same scenario gives a bit-identical trace. FB outputs a program reads in cycle k show
the motion state after cycle k-1; a command issued in cycle k shapes the setpoint of cycle k
(docs/decisions.md D-001). This module knows no kind of system.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from typing import Any

from openmotion.core.checks import non_negative_number, positive_number
from openmotion.core.errors import ConfigError
from openmotion.kernel.system import System

Program = Callable[[], Any]
Observer = Callable[[Any], Any]


class CyclicRuntime:
    """Virtual-time cyclic runtime with no system of its own. ``cycle_time`` in seconds."""

    def __init__(self, cycle_time: float = 0.001) -> None:
        self.cycle_time = positive_number(cycle_time, "cycle_time")
        self.cycle = 0  #: number of completed cycles
        self.now = 0.0  #: virtual time [s], always cycle * cycle_time
        self._programs: list[Program] = []
        self._observers: list[Observer] = []
        self._systems: list[System] = []
        self._monitored: list[Any] = []  #: the systems that have a drive phase
        self._serials: Counter[str] = Counter()

    # -- building ------------------------------------------------------------------------------

    def add_program(self, program: Program) -> Program:
        """Run ``program()`` at the start of every cycle (a PLC task body)."""
        self._programs.append(program)
        return program

    def add_observer(self, observer: Observer) -> Observer:
        """Call ``observer(runtime)`` at the end of every cycle (traces, viewers)."""
        self._observers.append(observer)
        return observer

    def add_system(self, system: System) -> System:
        """Let ``system`` run in every cycle from the next one, after the systems added before.

        A system is added once; anything without ``advance`` and ``objects`` is refused."""
        if not isinstance(system, System):
            raise ConfigError(f"add_system: {system!r} has no advance(now) and objects()")
        if any(known is system for known in self._systems):
            raise ConfigError(f"add_system: {system!r} is added already")
        self._systems.append(system)
        if callable(getattr(system, "monitor", None)):
            self._monitored.append(system)
        return system

    @property
    def systems(self) -> tuple[System, ...]:
        """The systems in the order they run (the order they were added)."""
        return tuple(self._systems)

    def serial(self, kind: str) -> int:
        """1, 2, 3, ... per ``kind``: stable object numbers that no other kind shifts."""
        self._serials[kind] += 1
        return self._serials[kind]

    def rewind(self) -> None:
        """Set the clock back to t = 0 after set-up cycles (a scenario enables its planar
        objects before its timeline starts); each system with ``rewind()`` is told first and
        may refuse with a ``ConfigError``, leaving the clock as it was."""
        for system in self._systems:
            rewind = getattr(system, "rewind", None)
            if callable(rewind):
                rewind()
        self.cycle, self.now = 0, 0.0

    # -- running -------------------------------------------------------------------------------

    def step(self) -> None:
        """Advance virtual time by one cycle."""
        self.cycle += 1
        now = self.now = self.cycle * self.cycle_time  # from the integer count: no drift
        for program in self._programs:
            program()
        for system in self._systems:  # looked up each cycle: a profiler may wrap advance
            system.advance(now)
        for system in self._monitored:
            system.monitor(now)
        for observer in self._observers:
            observer(self)

    def run(self, seconds: float) -> None:
        """Run for ``seconds`` of virtual time (rounded to whole cycles; 0 runs none).
        NaN, infinite or negative: ``ConfigError``."""
        seconds = non_negative_number(seconds, "run: seconds")
        for _ in range(round(seconds / self.cycle_time)):
            self.step()

    def run_until(self, predicate: Callable[[], bool] | Any, timeout: float = 60.0) -> float:
        """Step until ``predicate()`` is true (or a command handle is ``finished``); returns
        ``now``.

        Raises ``TimeoutError`` naming the predicate and the time when ``timeout`` seconds of
        virtual time pass first (0: the predicate is asked once, without a step). A
        ``timeout`` that is NaN, infinite or negative is a ``ConfigError``.
        """
        timeout = non_negative_number(timeout, "run_until: timeout")
        if not callable(predicate) and hasattr(predicate, "finished"):
            command = predicate
            predicate = lambda: command.finished  # noqa: E731 - a named closure reads worse
        elif not callable(predicate):
            raise TypeError(
                f"run_until needs a callable, e.g. lambda: cmd.done, not {predicate!r}"
            )
        deadline = self.cycle + round(timeout / self.cycle_time)
        while not predicate():
            if self.cycle >= deadline:
                name = getattr(predicate, "__qualname__", repr(predicate))
                raise TimeoutError(
                    f"run_until({name}) still false at t={self.now:.6g} s after {timeout} s"
                )
            self.step()
        return self.now
