"""The planar machine of one run: built and set up before t = 0, fed by the timeline, read.

The run builds the ``planar`` block (scenario/planar.py) in its order, so the OIDs are those
TwinCAT hands out: movers 16#05110010, 16#05110020, ...; the environment, then the groups,
16#05120010, ... ``set_up`` then gives the environment its stators and boundary, enables the
groups and movers with ``enable`` and lets each enabled group take the environment and its
movers (AddToGroup, in the listed order). The planar API decides a call in the motion phase of
the next cycle, so the setup takes three cycles; they run before anything else is on the
runtime, and the clock then starts again at 0, so that every object is ready at t = 0, as an
enabled CA group is (docs/scenarios.md). Only standing planar objects saw those cycles.

A timeline entry's row is a ``Command`` that mirrors the method's PlanarCommand once per cycle
(observer phase): BUSY while sent or active, then DONE, ABORTED or ERROR; a refused command
says ``rejected (33158) by mover 16#05110010``: the error number and the blocking object.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.planar import (
    CommandPhase,
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    PlanarCommand,
    PlanarObjectType,
    PlanarState,
)
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.planar import (
    AddToGroup,
    Loc,
    PlanarEntry,
    PlanarGroupEntry,
    PlanarSpec,
)
from openmotion.trace.record import TIME, Trace, TraceRecorder

if TYPE_CHECKING:
    from rich.table import Table

SETUP_CYCLES = 10  #: the setup must be over within this many cycles (it takes three)


@dataclass(frozen=True)
class PlanarMoverRow:
    """One planar mover at the end of a run: its published set values."""

    mover: str
    oid: int  #: its object id (16#05110010 ...)
    group: str  #: the planar group it is in; "" for none
    state: str  #: PlanarState name in lower case
    x: float  #: [mm]
    y: float  #: [mm]
    z: float  #: [mm]
    a: float  #: [°]
    b: float  #: [°]
    c: float  #: [°]


class PlanarMachine:
    """The planar objects of one run: built, set up, fed by the timeline, read by signals."""

    def __init__(self, rt: Runtime, spec: PlanarSpec | None) -> None:
        self.rt = rt
        self.spec = spec
        self.environment: MC_PlanarEnvironment | None = None
        self.movers: dict[str, MC_PlanarMover] = {}
        self.groups: dict[str, MC_PlanarGroup] = {}
        self._group_names: dict[int, str] = {}  #: OID -> name, for the rows
        self._open: list[tuple[PlanarCommand, Command]] = []  #: issued, not yet ended
        if spec is None:
            return
        if spec.environment is not None:
            self.environment = MC_PlanarEnvironment(rt)
        for group in spec.groups:
            self.groups[group.name] = MC_PlanarGroup(rt, group.name)
            self._group_names[self.groups[group.name].oid] = group.name
        for mover in spec.movers:
            self.movers[mover.name] = MC_PlanarMover(rt, mover.build(), mover.name)

    def set_up(self) -> list[tuple[Loc, str]]:
        """Stators, boundary, Enable, AddToGroup, in the cycles before t = 0; returns what
        failed as (field path, message). Call it before anything else is on the runtime."""
        spec, rt = self.spec, self.rt
        if spec is None:
            return []
        steps: list[tuple[Loc, str, PlanarCommand]] = []
        if self.environment is not None and spec.environment is not None:
            for index, corner in enumerate(spec.environment.corners()):
                steps.append((("environment",), f"stator {index}",
                              self.environment.add_stator(*corner)))
            steps.append((("environment",), "boundary", self.environment.create_boundary()))
        for index, group in enumerate(spec.groups):
            if group.enable:
                steps.append((("groups", index), "enable", self.groups[group.name].enable()))
        for index, mover in enumerate(spec.movers):
            if mover.enable:
                steps.append((("movers", index), "enable", self.movers[mover.name].enable()))
        self._settle(steps)
        for index, group in enumerate(spec.groups):
            target = self.groups[group.name]
            if group.enable and self.environment is not None and spec.has_environment(index):
                steps.append((("groups", index, "environment"), f"joining group {group.name}",
                              self.environment.add_to_group(target)))
            for loc, name in spec.members(index) if group.enable else []:
                steps.append((loc, f"joining group {group.name}",
                              self.movers[name].add_to_group(target)))
        self._settle(steps)
        rt.cycle, rt.now = 0, 0.0  # the setup happened before t = 0 (module docstring)
        return [(loc, f"{what}: {self._failure(command)}") for loc, what, command in steps
                if not command.done]

    def _failure(self, command: PlanarCommand) -> str:
        """Why a setup command did not end Done, naming the blocking object."""
        if not command.error:
            return f"still {command.phase.name.lower()} after {SETUP_CYCLES} cycles"
        error = f"{command.error_id.name} ({int(command.error_id)})"
        info = command.object_info
        if info.object_type is PlanarObjectType.INVALID:
            return f"{error}: {command.message}"
        if info.object_type is PlanarObjectType.ENVIRONMENT:
            return f"{error}: the footprint is not on the stators"
        name = next(name for name, mover in self.movers.items() if mover.oid == info.id)
        return f"{error}: the footprint meets mover {name} (16#{info.id:08X})"

    def _settle(self, steps: list[tuple[Loc, str, PlanarCommand]]) -> None:
        for _ in range(SETUP_CYCLES):
            if not any(command.busy for _, _, command in steps):
                return
            self.rt.step()

    # -- the timeline ------------------------------------------------------------------------

    def issue(self, entry: PlanarEntry | PlanarGroupEntry) -> Command:
        """Call the entry's method now; the row follows its PlanarCommand (``watch``)."""
        target: Any = self.groups[entry.group] if isinstance(entry, PlanarGroupEntry) \
            else self.movers[entry.mover]
        arguments = tuple(self.groups[name] for name in entry.arguments()) \
            if isinstance(entry, AddToGroup) else entry.arguments()
        planar = getattr(target, entry.method)(*arguments)
        command = Command(entry.command, self.rt.now)
        self._open.append((planar, command))
        return command

    def watch(self) -> None:
        """Mirror every open PlanarCommand onto its row's Command (observer phase)."""
        still = []
        for planar, command in self._open:
            command.warnings = list(planar.warnings)
            if planar.busy:
                if planar.phase is CommandPhase.ACTIVE:
                    command.status = CommandStatus.ACTIVE
                still.append((planar, command))
                continue
            accepted = command.status is CommandStatus.ACTIVE
            command._end(_STATUS[planar.phase], self.rt.now, planar.error_id,
                         self.outcome(planar, accepted))
        self._open = still

    def outcome(self, planar: PlanarCommand, accepted: bool) -> str:
        """An error as the rows show it: ``rejected (33158) by mover 16#05110010``; without
        a blocking object, the reason."""
        if planar.phase is not CommandPhase.ERROR:
            return ""
        verb = "failed" if accepted else "rejected"
        info = planar.object_info
        if info.object_type is PlanarObjectType.INVALID:
            return f"{verb} ({int(planar.error_id)}): {planar.message}"
        return f"{verb} ({int(planar.error_id)}) by {info.object_type.name.lower()} " \
               f"16#{info.id:08X}"

    @property
    def busy(self) -> bool:
        """A mover moves (or brakes) or a transition runs: the run goes on."""
        return any(mover.mc_to_plc.std.busy.busy_mover or mover.state in _TRANSITIONAL
                   for mover in self.movers.values()) or any(
            group.state in _TRANSITIONAL for group in self.groups.values())

    # -- signals -----------------------------------------------------------------------------

    def signal(self, subject: str, prop: str) -> float | None:
        """A mover's signal or a planar group's ``state``; None when ``subject`` is not
        planar."""
        group = self.groups.get(subject)
        if group is not None:
            return float(group.state)
        mover = self.movers.get(subject)
        if mover is None:
            return None
        if prop == "state":
            return float(mover.state)
        if prop == "velocity":
            velocity = mover.mc_to_plc.set.set_velo
            return math.hypot(velocity.x, velocity.y)
        return float(getattr(mover.position, prop))

    def reading(self, name: str) -> tuple[float, str, bool] | None:
        """(value, its text, whether it is a name) of a planar signal; None for others."""
        subject, _, prop = name.partition(".")
        value = self.signal(subject, prop)
        if value is None:
            return None
        if prop == "state":
            return value, PlanarState(int(value)).name.lower(), True
        return value, "", False

    def rows(self) -> list[PlanarMoverRow]:
        rows = []
        for name, mover in self.movers.items():
            p = mover.position
            rows.append(PlanarMoverRow(name, mover.oid,
                                       self._group_names.get(mover.mc_to_plc.std.group_oid, ""),
                                       mover.state.name.lower(), p.x, p.y, p.z, p.a, p.b, p.c))
        return rows


_STATUS = {CommandPhase.DONE: CommandStatus.DONE, CommandPhase.ABORTED: CommandStatus.ABORTED,
           CommandPhase.ERROR: CommandStatus.ERROR}
_TRANSITIONAL = (PlanarState.ENABLING, PlanarState.DISABLING, PlanarState.RESETTING,
                 PlanarState.ERROR_PENDING)


def planar_table(rows: list[PlanarMoverRow], number: Callable[[float], str]) -> Table:
    """The summary's ``Planar movers`` table: each mover's final set position."""
    from rich import box
    from rich.table import Table
    from rich.text import Text

    table = Table(box=box.SIMPLE, title_justify="left", title="Planar movers")
    for name in ("mover", "oid", "group", "state", "x [mm]", "y [mm]", "z [mm]", "a [°]",
                 "b [°]", "c [°]"):
        table.add_column(Text(name), justify="left" if name in ("mover", "oid", "group",
                                                                "state") else "right",
                         no_wrap=True)
    for row in rows:
        table.add_row(row.mover, f"16#{row.oid:08X}", row.group or "-", row.state,
                      *(number(value) for value in (row.x, row.y, row.z, row.a, row.b, row.c)))
    return table


class SignalRecorder:
    """A TraceRecorder for the axis signals plus the planar ones, as one Trace in the order
    of ``signals`` (a runtime observer, like TraceRecorder)."""

    def __init__(self, rt: Runtime, signals: list[str], every: int,
                 machine: PlanarMachine) -> None:
        self.signals = signals
        self.planar = [(name, *name.split(".", 1)) for name in signals
                       if name.split(".", 1)[0] in machine.movers]
        names = {name for name, _, _ in self.planar}
        self.axes = TraceRecorder(rt, [name for name in signals if name not in names], every)
        self.machine = machine
        self.every = every
        self._rows: list[list[float]] = []

    def __call__(self, runtime: Runtime) -> None:
        if runtime.cycle % self.every == 0:
            self.sample(runtime)

    def sample(self, runtime: Runtime) -> None:
        self.axes.sample(runtime)
        if self.planar:
            self._rows.append([self.machine.signal(subject, prop)  # type: ignore[misc]
                               for _, subject, prop in self.planar])

    @property
    def trace(self) -> Trace:
        axes = self.axes.trace
        if not self.planar:
            return axes
        planar = np.array(self._rows, dtype=np.float64).reshape(len(axes), len(self.planar))
        columns = {name: planar[:, k] for k, (name, _, _) in enumerate(self.planar)}
        columns.update({name: axes[name] for name in axes.signals})
        return Trace((TIME, *self.signals), np.column_stack(
            [axes.time, *(columns[name] for name in self.signals)]))

