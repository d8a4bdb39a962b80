"""One cyclic task with virtual time: programs, systems, observers (architecture §cycle).

``run`` and ``run_until`` only loop ``step``, as SimPy's ``Environment.run`` loops ``step``.
A cycle runs the programs, then every system's motion phase, then every system's drive
phase, then the observers; within a phase, in the order things were added (kernel/system.py),
so the same scenario gives a bit-identical trace. FB outputs a program reads in cycle k show
the motion state after cycle k-1; a command issued in cycle k shapes the setpoint of cycle k
(docs/decisions.md D-001). This module knows no kind of system.

Quiet stretches (docs/runtime.md, D-275): ``run`` and ``run_until(command)`` advance the
cycles in which nothing can happen in bulk rather than one ``step`` each. A cycle needs its
own step when a program or a per-cycle observer runs, or when a system says it must
(``quiet_until``, kernel/system.py); every other cycle gives the same state through
``advance_quietly``, so a run is bit for bit the same stepped or in bulk.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from typing import Any

import numpy as np

from openmotion.core.checks import non_negative_number, positive_number
from openmotion.core.errors import ConfigError
from openmotion.kernel.command import Command
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
        self._bulk: bool | None = None  #: may quiet stretches run in bulk (None: ask again)

    # -- building ------------------------------------------------------------------------------

    def add_program(self, program: Program) -> Program:
        """Run ``program()`` at the start of every cycle (a PLC task body)."""
        self._programs.append(program)
        self._bulk = None
        return program

    def add_observer(self, observer: Observer) -> Observer:
        """Call ``observer(runtime)`` at the end of every cycle (traces, viewers).

        An observer that also has ``observe_block(runtime, blocks)`` lets quiet stretches run
        in bulk: it is called once after each stretch instead, with ``blocks`` mapping each
        system's name to that system's samples of every cycle of the stretch (the axes: an
        ``AxisBlock``); ``blocks["times"]`` holds the cycles' times. Any other observer makes
        every cycle a step of its own."""
        self._observers.append(observer)
        self._bulk = None
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
        self._bulk = None
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
        """Run for ``seconds`` of virtual time (rounded to whole cycles; 0 runs none), quiet
        stretches in bulk. NaN, infinite or negative: ``ConfigError``."""
        if not (type(seconds) is float and 0.0 <= seconds < math.inf):  # the common case
            seconds = non_negative_number(seconds, "run: seconds")
        target = self.cycle + round(seconds / self.cycle_time)
        while self.cycle < target:
            quiet = self._quiet_cycles(target - self.cycle)
            if quiet:
                self._advance_quietly(quiet)
            else:
                self.step()

    def run_until(self, predicate: Callable[[], bool] | Command, timeout: float = 60.0) -> float:
        """Step until ``predicate()`` is true (or a Command finishes); returns ``now``.

        A Command is asked after each quiet stretch, run in bulk (nothing in it can finish a
        command); any other predicate after every cycle, each cycle a step. Raises
        ``TimeoutError`` naming the predicate and the time when ``timeout`` seconds of
        virtual time pass first (0: the predicate is asked once, without a step). A
        ``timeout`` that is NaN, infinite or negative is a ``ConfigError``.
        """
        timeout = non_negative_number(timeout, "run_until: timeout")
        bulk = isinstance(predicate, Command)
        if bulk:
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
            quiet = self._quiet_cycles(deadline - self.cycle) if bulk else 0
            if quiet:
                self._advance_quietly(quiet)
            else:
                self.step()
        return self.now

    # -- quiet stretches -----------------------------------------------------------------------

    def _may_bulk(self) -> bool:
        """No program, only observers that take blocks, only systems that know their quiet
        stretches, and the kernel's own ``step`` (a paced runtime waits in its step)."""
        if self._bulk is None:
            self._bulk = (
                not self._programs
                and type(self).step is CyclicRuntime.step
                and all(callable(getattr(o, "observe_block", None)) for o in self._observers)
                and all(callable(getattr(s, "quiet_until", None))
                        and callable(getattr(s, "advance_quietly", None)) for s in self._systems)
            )
        return self._bulk

    def _quiet_cycles(self, limit: int) -> int:
        """How many of the next ``limit`` cycles may run in bulk: those before the first
        cycle whose ``now`` reaches the earliest ``quiet_until`` of the systems."""
        if limit <= 0 or not self._may_bulk():
            return 0
        until = math.inf
        for system in self._systems:
            until = min(until, system.quiet_until())
            if until == -math.inf:
                return 0
        if until == math.inf:
            return limit
        cycle_time = self.cycle_time
        last = max(math.ceil(until / cycle_time) - 1, self.cycle)  # then exactly, as step
        while (last + 1) * cycle_time < until:  # computes now: cycle * cycle_time < until
            last += 1
        while last > self.cycle and last * cycle_time >= until:
            last -= 1
        return min(limit, last - self.cycle)

    def _advance_quietly(self, cycles: int) -> None:
        """Run ``cycles`` quiet cycles in bulk (``_quiet_cycles``): each system's phases of
        all of them at once, then the observers' blocks."""
        first, last = self.cycle + 1, self.cycle + cycles
        now = last * self.cycle_time
        times = np.arange(first, last + 1) * self.cycle_time if self._observers else None
        blocks: dict[str, Any] = {"times": times}
        for system in self._systems:
            blocks[system.name] = system.advance_quietly(  # type: ignore[attr-defined]
                now, cycles, times)
        self.cycle, self.now = last, now
        for observer in self._observers:
            observer.observe_block(self, blocks)  # type: ignore[attr-defined]
