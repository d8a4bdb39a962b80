"""The PLC programs behind block entries (scenario/cyclic.py): each calls its block per cycle.

When a block entry fires, the run starts its program: the program makes the function block and
calls it at once (the firing cycle), then once per cycle in the runtime's program phase,
*before* the timeline's entries are looked at, so that a condition on the entry sees this
cycle's block outputs. Programs run in the order their entries fired. A program's ``command``
is the entry's record for its row, its conditions and its checks; it mirrors the block's
outputs. Time is the runtime's virtual time only.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import ClassVar

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.axis.stepper import StepperTerminal
from openmotion.core.enums import AxisState
from openmotion.core.errors import ErrorId
from openmotion.plcopen.external import MC_ExtSetPointGenFeed
from openmotion.plcopen.jog import MC_Jog
from openmotion.plcopen.move import MC_MoveAbsoluteOrRestart
from openmotion.plcopen.override_filter import MC_OverrideFilter
from openmotion.plcopen.reference import MC_ReadAxisComponents, MC_SetReferenceFlag
from openmotion.plcopen.stepper import MC_PowerStepper
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.cyclic import (
    BlockEntry,
    EnableExternalSetpoints,
    InjectStall,
    Jog,
    MoveAbsoluteOrRestart,
    OverrideFilter,
    PowerStepper,
    ReadAxisComponents,
    ReleaseStall,
    SetReferenceFlag,
    _Call,
)
from openmotion.scenario.schema import Condition, ProbeSpec

Holds = Callable[[Condition], bool]  #: the run's condition test


def cycle_of(seconds: float, cycle_time: float) -> int:
    """The first cycle whose time is at or after ``seconds``."""
    return math.ceil(round(seconds / cycle_time, 6))


def _motion_cycle(rt: Runtime) -> int:
    """The cycle whose motion step a call now shapes: calls at t = 0, before the first cycle
    (entries at ``at: 0``), shape cycle 1, just as calls in cycle 1's program phase do."""
    return max(rt.cycle, 1)


def _done(kind: str, now: float, value: object = None) -> Command:
    command = Command(kind, now)
    command.value = value
    command.end(CommandStatus.DONE, now)
    return command


class Program:
    """One block entry's program; ``__call__`` runs one cycle and says whether to go on."""

    keeps_running: ClassVar[bool] = True  #: the run is not at rest while the program runs

    def __init__(self, command: Command) -> None:
        self.command = command

    def __call__(self) -> bool:
        raise NotImplementedError

    def replace(self, now: float) -> None:
        """A later entry of the same kind took over the axis: the record ends aborted."""
        self.command.end(CommandStatus.ABORTED, now,
                          message=f"replaced by a later {self.command.kind} entry")


class JogProgram(Program):
    """MC_Jog with its key TRUE from the firing cycle until released, until not busy."""

    def __init__(self, rt: Runtime, axis: Axis, entry: Jog, holds: Holds) -> None:
        super().__init__(Command(entry.command, rt.now))
        self.rt, self.entry, self.holds = rt, entry, holds
        self.block = MC_Jog(axis, **entry.arguments())
        self.fired = rt.cycle
        self.release_cycle = _motion_cycle(rt) + max(1, cycle_of(entry.hold, rt.cycle_time))
        self.pressed = True

    def __call__(self) -> bool:
        entry, rt = self.entry, self.rt
        if self.pressed and rt.cycle > self.fired:
            self.pressed = not (self.holds(entry.release_when) if entry.release_when is not None
                                else rt.cycle >= self.release_cycle)
        block, command = self.block, self.command
        block(**{entry.key: self.pressed})
        if block.busy:
            command.status = CommandStatus.ACTIVE if block.active else CommandStatus.BUFFERED
            return True
        status = (CommandStatus.ERROR if block.error else CommandStatus.ABORTED
                  if block.command_aborted else CommandStatus.DONE)
        motion = block.command
        command.end(status, rt.now, block.error_id, block.message)
        if motion is not None and motion.ended_at is not None:
            command.ended_at = max(motion.ended_at, command.issued_at)  # when the motion ended
        return False


class FeedProgram(Program):
    """MC_ExtSetPointGenEnable, then MC_ExtSetPointGenFeed every cycle from another axis or a
    raised cosine, for ``feed_for`` or as long as the axis takes fed setpoints.

    The entry's record follows the external generation, not the enable's Done: busy while
    the axis takes fed setpoints; done when disable_external_setpoints ends it, aborted when
    another command takes over, an error with the axis' error id when an axis error ends it
    (EXT_SETPOINT_MISSING once the feed stops). A rejected enable is the record's error.
    """

    def __init__(self, rt: Runtime, axis: Axis, entry: EnableExternalSetpoints) -> None:
        enable = axis.enable_external_setpoints(**entry.arguments())
        super().__init__(enable if enable.error else Command(entry.command, rt.now))
        self.rt, self.axis = rt, axis
        self.generation = None if enable.error else axis.active_command
        self.source = None if entry.feed.axis is None else rt.axes[entry.feed.axis]
        self.sine = entry.feed.sine
        self.start = rt.now
        self.offset = axis.set_position if self.sine is None or self.sine.offset is None \
            else self.sine.offset
        self.until = None if entry.feed_for is None \
            else _motion_cycle(rt) + cycle_of(entry.feed_for, rt.cycle_time)

    def __call__(self) -> bool:
        generation, command = self.generation, self.command
        if generation is None or command.finished:
            return False
        if generation.finished:
            axis = self.axis
            if generation.aborted and axis.state is AxisState.ERROR_STOP:
                command.end(CommandStatus.ERROR, self.rt.now, axis.axis_error_id,
                             axis.axis_error_message)
            else:
                command.end(generation.status, self.rt.now, message=generation.message)
            command.ended_at = generation.ended_at
            return False
        command.status = CommandStatus.ACTIVE
        if self.until is None or self.rt.cycle < self.until:
            position, velocity, acceleration = self.setpoint()
            direction = (velocity > 0.0) - (velocity < 0.0)
            MC_ExtSetPointGenFeed(position, velocity, acceleration, direction, self.axis)
        return True

    def setpoint(self) -> tuple[float, float, float]:
        """Position, velocity, acceleration to feed now: the source's values of the cycle
        before, or offset + amplitude (1 - cos ωτ) / 2 and its derivatives."""
        if self.source is not None:
            source = self.source
            return source.set_position, source.set_velocity, source.set_acceleration
        assert self.sine is not None
        omega = 2.0 * math.pi / self.sine.period
        half, phase = self.sine.amplitude / 2.0, omega * (self.rt.now - self.start)
        return (self.offset + half * (1.0 - math.cos(phase)), half * omega * math.sin(phase),
                half * omega * omega * math.cos(phase))


class OverrideFilterProgram(Program):
    """MC_OverrideFilter on the entry's raw steps; its filtered percent goes to the axis."""

    keeps_running = False

    def __init__(self, rt: Runtime, axis: Axis, entry: OverrideFilter) -> None:
        super().__init__(Command(entry.command, rt.now))
        self.rt, self.axis = rt, axis
        self.block = MC_OverrideFilter(rt, **entry.arguments())
        self.raw = [(cycle_of(time, rt.cycle_time), value) for time, value in entry.raw]
        self.applied: float | None = None

    def __call__(self) -> bool:
        cycle = self.rt.cycle
        due = [value for first, value in self.raw if first <= cycle]
        if not due:
            return True
        block, command = self.block, self.command
        block(override_value_raw=due[-1])
        if block.error:
            command.end(CommandStatus.ERROR, self.rt.now, block.error_id, block.message)
            return False
        command.status = CommandStatus.ACTIVE
        percent = command.value = block.override_percent_filtered
        if percent != self.applied:
            self.axis.set_override(percent)
            self.applied = percent
        return True


class StepperProgram(Program):
    """MC_PowerStepper (Enable TRUE) fed with the status of the axis' simulated terminal."""

    keeps_running = False

    def __init__(self, rt: Runtime, axis: Axis, entry: PowerStepper,
                 terminal: StepperTerminal) -> None:
        super().__init__(Command(entry.command, rt.now))
        self.rt, self.axis, self.terminal = rt, axis, terminal
        self.block = MC_PowerStepper(axis, **entry.arguments())

    def __call__(self) -> bool:
        block, terminal = self.block, self.terminal
        block(kl_status=terminal.status, kl_status2=terminal.status2)
        if block.error:
            self.command.end(CommandStatus.ERROR, self.rt.now, block.error_id, block.message)
            return False
        self.command.status = CommandStatus.ACTIVE if block.status else CommandStatus.BUFFERED
        return True


class StallProgram(Program):
    """Calls nothing: keeps the run going until a timed stall has ended."""

    def __init__(self, command: Command, terminal: StepperTerminal) -> None:
        super().__init__(command)
        self.terminal = terminal

    def __call__(self) -> bool:
        return self.terminal.stalled


def components_text(components: dict[str, dict]) -> str:
    """MC_ReadAxisComponents' output, short: encoder, drive and lag monitoring."""
    encoder, drive, controller = (components[key] for key in ("encoder", "drive", "controller"))
    lag = (f"lag monitoring {controller['max_position_lag']:g} mm for "
           f"{controller['position_lag_filter_time']:g} s"
           if controller["enable_position_lag_monitoring"] else "lag monitoring off")
    return (f"encoder scaling {encoder['scaling_factor']:g}, offset {encoder['offset']:g}, "
            f"reference {encoder['reference_mode'].name.lower()}; drive {drive['model']} "
            f"(time constant {drive['time_constant']:g} s, dead time {drive['dead_time']:g} s);"
            f" {lag}")


class CamProgram(Program):
    """MC_Home's bCalibrationCam driven by the PLC (TcMC §3.14): the axis' ``cam_input`` is
    the level of ``spec`` every cycle until the homing command ends, then None again."""

    keeps_running: ClassVar[bool] = False  #: the homing command keeps the run going

    def __init__(self, rt: Runtime, axis: Axis, spec: ProbeSpec) -> None:
        super().__init__(Command("calibration_cam", rt.now))
        self.rt, self.axis, self.spec = rt, axis, spec
        self.homing: Command | None = None
        self()

    def follow(self, homing: Command) -> None:
        self.homing = homing

    def __call__(self) -> bool:
        if self.homing is not None and self.homing.finished:
            self.axis.cam_input = None
            return False
        p, t = self.axis.position - self.axis.raw_offset, self.rt.now
        spans, at = (self.spec.times, t) if self.spec.times else (self.spec.positions, p)
        self.axis.cam_input = any(lo <= at < hi for lo, hi in spans)
        return True


class BlockPrograms:
    """The running programs of one run, and the stepper terminals of its axes (one per axis).

    Call it once per cycle. Feeding, the override filter and the stepper are one per axis: a
    later entry of the kind replaces the earlier one's program.
    """

    _ONE_PER_AXIS: ClassVar[tuple[type[Program], ...]] = (
        FeedProgram, OverrideFilterProgram, StepperProgram)

    def __init__(self, rt: Runtime, holds: Holds) -> None:
        self.rt, self.holds = rt, holds
        self.running: list[Program] = []
        self.terminals: dict[str, StepperTerminal] = {}
        #: the MC_MoveAbsoluteOrRestart block of each move_absolute_or_restart entry by id
        self.restartable: dict[str, MC_MoveAbsoluteOrRestart] = {}

    def __call__(self) -> None:
        self.running = [program for program in self.running if program()]

    @property
    def busy(self) -> bool:
        """A program that keeps the run going still runs (a jog, a feed, a timed stall)."""
        return any(program.keeps_running for program in self.running)

    def start(self, entry: BlockEntry) -> Command:
        """Carry out ``entry`` now: start its program (first call included) or act at once."""
        rt, axis = self.rt, self.rt.axes.get(entry.axis)  # none for get_version
        match entry:
            case Jog():
                return self._run(JogProgram(rt, axis, entry, self.holds), axis)
            case EnableExternalSetpoints():
                return self._run(FeedProgram(rt, axis, entry), axis)
            case OverrideFilter():
                return self._run(OverrideFilterProgram(rt, axis, entry), axis)
            case PowerStepper():
                return self._run(StepperProgram(rt, axis, entry, self.terminal(axis)), axis)
            case InjectStall():
                terminal = self.terminal(axis)
                terminal.inject_stall(entry.duration)
                command = _done(entry.command, rt.now)
                return command if entry.duration is None \
                    else self._run(StallProgram(command, terminal), axis)
            case ReleaseStall():
                if axis.name in self.terminals:
                    self.terminals[axis.name].release()
                return _done(entry.command, rt.now)
            case SetReferenceFlag():
                reference = MC_SetReferenceFlag(axis)
                reference(execute=True, **entry.arguments())
                return _done(entry.command, rt.now)
            case ReadAxisComponents():
                read = MC_ReadAxisComponents(axis)
                read(execute=True)
                return _done(entry.command, rt.now, components_text(read.axis_components))
            case MoveAbsoluteOrRestart():
                return self._move_or_restart(entry, axis)
            case _Call():
                return entry.call(axis, rt.now)
        raise TypeError(f"no program for {type(entry).__name__}")  # pragma: no cover

    def _move_or_restart(self, entry: MoveAbsoluteOrRestart, axis: Axis) -> Command:
        """A new MC_MoveAbsoluteOrRestart, or a new rising edge of the one of ``restart``."""
        block = self.restartable.get(entry.restart) if entry.restart is not None else None
        if block is not None and block.axis is not axis:
            command = Command(entry.command, self.rt.now)
            command.end(CommandStatus.ERROR, self.rt.now, ErrorId.INVALID_PARAMETER_VALUE,
                         f"restart: {entry.restart} moves axis {block.axis.name}, not "
                         f"{axis.name}")
            return command
        if block is None:
            block = MC_MoveAbsoluteOrRestart(axis)
        else:
            block(execute=False)
        block(execute=True, **entry.arguments())
        if entry.id is not None:
            self.restartable[entry.id] = block
        return block.command  # type: ignore[return-value] - an edge always leaves one

    def cam(self, axis: Axis, spec: ProbeSpec) -> CamProgram:
        """Drive the axis' calibration cam input from ``spec`` while a homing runs."""
        program = CamProgram(self.rt, axis, spec)
        self.running.append(program)
        return program

    def terminal(self, axis: Axis) -> StepperTerminal:
        """The axis' simulated stepper terminal, attached at its first use."""
        if axis.name not in self.terminals:
            self.terminals[axis.name] = StepperTerminal(axis)
        return self.terminals[axis.name]

    def _run(self, program: Program, axis: Axis) -> Command:
        if isinstance(program, self._ONE_PER_AXIS):
            for other in [p for p in self.running if type(p) is type(program)
                          and getattr(p, "axis", None) is axis]:
                other.replace(self.rt.now)
                self.running.remove(other)
        if program():
            self.running.append(program)
        return program.command

