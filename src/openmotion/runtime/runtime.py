"""One cyclic task with virtual time: programs, motion, drives, observers (architecture §cycle).

``run`` and ``run_until`` only loop ``step``, as SimPy's ``Environment.run`` loops ``step``.
Within a phase, objects run in creation order, so the same scenario gives a bit-identical
trace. FB outputs a program reads in cycle k show the motion state after cycle k-1; a command
issued in cycle k shapes the setpoint of cycle k (docs/decisions.md D-001).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.axis.drive import DriveModel
from openmotion.axis.kernel import AxisKernel
from openmotion.axis.parameters import PARAMETER_FIELDS, AxisParameters
from openmotion.core.checks import finite_number, non_negative_number, positive_number
from openmotion.core.errors import ConfigError, ErrorId

Program = Callable[[], Any]
Observer = Callable[["Runtime"], Any]
Watcher = Callable[[float], bool]


class Runtime:
    """Virtual-time cyclic runtime. ``cycle_time`` in seconds (default 1 ms)."""

    def __init__(self, cycle_time: float = 0.001) -> None:
        self.cycle_time = positive_number(cycle_time, "cycle_time")
        self.cycle = 0  #: number of completed cycles
        self.now = 0.0  #: virtual time [s], always cycle * cycle_time
        self.axes: dict[str, Axis] = {}
        self._axis_list: list[Axis] = []
        self._kernel = AxisKernel(self.cycle_time)
        self._programs: list[Program] = []
        self._observers: list[Observer] = []
        self._watchers: list[tuple[int, int, Watcher]] = []
        self._systems: list[Callable[[float], Any]] = []  #: group motion after evaluation
        self._watch_serial = 0

    # -- building ------------------------------------------------------------------------------

    def add_axis(self, name: str, parameters: AxisParameters | None = None,
                 drive: DriveModel | None = None, position: float = 0.0, **overrides: Any) -> Axis:
        """Create an axis; keyword ``overrides`` set AxisParameters fields by name.

        ``position`` is where the axis stands [mm or °]. A value that is no finite number,
        here or in the parameters, is a ``ConfigError`` naming the field."""
        if not isinstance(name, str):
            raise ConfigError(f"axes: an axis name must be a str, got {name!r}")
        if name in self.axes:
            raise ConfigError(f"axes: an axis named {name!r} exists already")
        unknown = set(overrides) - PARAMETER_FIELDS
        if unknown:
            raise ConfigError(f"axis {name!r}: unknown parameter(s) {sorted(unknown)}")
        if parameters is not None and not isinstance(parameters, AxisParameters):
            raise ConfigError(f"axis {name!r}: parameters must be an AxisParameters, got "
                              f"{type(parameters).__name__}")
        if drive is not None and not isinstance(drive, DriveModel):
            raise ConfigError(f"axis {name!r}: drive must be a DriveModel, got "
                              f"{type(drive).__name__}")
        start = finite_number(position, f"axis {name!r}: position")
        try:
            if parameters is None:
                parameters = AxisParameters(**overrides)
            elif overrides:  # a copy: a refused override leaves the caller's object as it was
                parameters = replace(parameters, **overrides)
            else:
                parameters.validate()
        except (TypeError, ValueError) as exc:
            raise ConfigError(f"axis {name!r}: {exc}") from None
        drive = drive or DriveModel()
        alpha, dead = drive.coefficients(self.cycle_time)
        row = self._kernel.add(start, alpha, dead)
        axis = Axis(self, self._kernel, name, row, parameters, drive)
        self.axes[name] = axis
        self._axis_list.append(axis)
        return axis

    def add_program(self, program: Program) -> Program:
        """Run ``program()`` at the start of every cycle (a PLC task body)."""
        self._programs.append(program)
        return program

    def add_observer(self, observer: Observer) -> Observer:
        """Call ``observer(runtime)`` at the end of every cycle (traces, viewers)."""
        self._observers.append(observer)
        return observer

    def _add_system(self, advance: Callable[[float], Any]) -> None:
        """Let a motion system (a CA group) correct the setpoints of its axes every cycle,
        right after the profiles are evaluated and before the drives follow them."""
        self._systems.append(advance)

    def _watch(self, axis: Axis, watcher: Watcher) -> None:
        """Call ``watcher(now)`` after each motion step until it returns False."""
        self._watch_serial += 1
        self._watchers.append((axis.row, self._watch_serial, watcher))

    # -- running -------------------------------------------------------------------------------

    def step(self) -> None:
        """Advance virtual time by one cycle."""
        self.cycle += 1
        self.now = self.cycle * self.cycle_time  # from the integer count: no drift
        for program in self._programs:
            program()
        self._advance_motion()
        self._simulate_drives()
        for observer in self._observers:
            observer(self)

    def _advance_motion(self) -> None:
        kernel, now = self._kernel, self.now
        if kernel.size:  # a machine of planar movers only has no single axes to advance
            for row in kernel.overlay_ended(now).tolist():
                self._axis_list[row]._on_superposition_end()
            ended = kernel.ended(now)
            if ended.size:
                end = kernel.segments.end
                for row in ended.tolist():
                    self._axis_list[row]._on_profile_end(float(end[row]))
        kernel.evaluate(now)
        for _ in range(kernel.size):  # a faulted master changes its slaves' samples too
            bad = kernel.slave_violations()
            if not bad.size:
                break
            for row in bad.tolist():
                self._axis_list[row]._gear_limit_fault()
            kernel.evaluate(now, again=True)
        for advance in self._systems:
            advance(now)

    def _simulate_drives(self) -> None:
        kernel = self._kernel
        if not kernel.size:
            return
        kernel.simulate_drives()
        alarms = kernel.lag_alarms()
        if alarms.size:
            for row in alarms.tolist():
                axis = self._axis_list[row]
                axis._fault(ErrorId.FOLLOWING_ERROR,
                            f"following error {axis.following_error:.6g} beyond "
                            f"{axis.parameters.max_position_lag}")
        if self._watchers:
            watchers, self._watchers = sorted(self._watchers), []
            now = self.now
            keep = [item for item in watchers if item[2](now)]
            self._watchers = sorted(keep + self._watchers)

    def run(self, seconds: float) -> None:
        """Run for ``seconds`` of virtual time (rounded to whole cycles; 0 runs none).
        NaN, infinite or negative: ``ConfigError``."""
        seconds = non_negative_number(seconds, "run: seconds")
        for _ in range(round(seconds / self.cycle_time)):
            self.step()

    def run_until(self, predicate: Callable[[], bool] | Command, timeout: float = 60.0) -> float:
        """Step until ``predicate()`` is true (or a Command finishes); returns ``now``.

        Raises ``TimeoutError`` naming the predicate and the time when ``timeout`` seconds of
        virtual time pass first (0: the predicate is asked once, without a step). A
        ``timeout`` that is NaN, infinite or negative is a ``ConfigError``.
        """
        timeout = non_negative_number(timeout, "run_until: timeout")
        if isinstance(predicate, Command):
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
