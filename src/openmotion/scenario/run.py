"""Run a scenario in virtual time: build the runtime, fire the timeline, record, check.

The timeline is a runtime program (phase 1 of the cycle): entries are looked at in file order,
each sees the effects of the ones before it, and every command goes through the public Axis
methods, as a user's script would. Block entries (a jog, a feed, the override filter, the
stepper) start programs that call their block every cycle, before the entries are looked at
(programs.py). Recording and checks are observers (phase 4). Nothing here reads the wall
clock, so two runs of one scenario give bit-identical traces and summaries.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from openmotion.axis.commands import Command, CommandStatus
from openmotion.axis.probe import InputRef, abort_probe, arm_probe
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.planar.routing.plans import RoutePlans
from openmotion.rail.stations import StationLine, StationRow
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.coordinated_machine import AxesGroupRow, AxesGroups, axes_group_table
from openmotion.scenario.cyclic import BlockEntry
from openmotion.scenario.groups import CaGroups, GroupRow, MoverRow
from openmotion.scenario.load import load_scenario
from openmotion.scenario.planar import PLANAR_ENTRIES
from openmotion.scenario.planar_machine import PlanarMachine, PlanarMoverRow, planar_table
from openmotion.scenario.planar_routing import Route, RouterSpec
from openmotion.scenario.planar_tracks import PlanarTrackRow, riders_table, track_table
from openmotion.scenario.programs import BlockPrograms, cycle_of
from openmotion.scenario.queries import outputs_text, pick
from openmotion.scenario.schema import (
    AbortTrigger,
    CommandCheck,
    Condition,
    Entry,
    Home,
    PlcEvent,
    Power,
    PowerOff,
    Scenario,
    SignalCheck,
    TouchProbe,
)
from openmotion.scenario.signals import RunSignals
from openmotion.scenario.stations import build_planar_line, station_table
from openmotion.scenario.transport import CA_ENTRIES, SetGap
from openmotion.trace.plot import figure_signals
from openmotion.trace.record import Trace, TraceRecorder
from openmotion.trace.signals import describe

if TYPE_CHECKING:
    from rich.console import RenderableType

#: ``progress(now, total)``: simulated seconds so far and in all (None while unknown).
Progress = Callable[[float, float | None], Any]
SUMMARY_WIDTH = 100  #: columns of the plain-text summary (and of the golden .out files)
PROGRESS_EVERY = 250  #: cycles between two progress calls
_OPERATORS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
              "==": operator.eq}
#: commands that keep the run going until they end, whatever their ``in_velocity`` says (a
#: superposition sets it when its distance can be done in full)
_UNTIL_FINISHED = frozenset({"move_superimposed"})
#: commands whose block runs to the end of the run: they never keep the run going
_TO_THE_END = frozenset({"override_filter", "power_stepper"})
_RESULT_STYLE = {"DONE": "green", "ABORTED": "yellow", "ERROR": "red", "BUSY": "cyan"}


@dataclass(frozen=True)
class CommandRow:
    """The outcome of one timeline entry."""

    id: str  #: the entry's id, or ``#<number>`` in timeline order
    axis: str
    command: str
    issued_at: float | None  #: [s]; None when the entry never fired
    ended_at: float | None  #: [s]; None while busy
    result: str  #: DONE, ABORTED, ERROR, BUSY or NOT ISSUED
    error: str  #: ErrorId name of an error, else ""
    message: str  #: error or abort reason, and any warnings
    value: float | None = None  #: the command's result value (a touch_probe's position, a
    #: move_superimposed's actual distance, an override_filter's percent)
    value_detail: str = ""  #: the summary's text for the value, when more than ``value X``
    #: (or a result without a number: read_axis_components)


@dataclass(frozen=True)
class CheckRow:
    name: str
    passed: bool
    detail: str  #: the value seen, or why the check failed


@dataclass
class ScenarioResult:
    """Everything a run produced; nothing in it depends on the wall clock."""

    scenario: Scenario
    commands: list[CommandRow]
    checks: list[CheckRow]
    trace: Trace
    cycles: int
    end_time: float  #: simulated seconds
    ca_movers: list[MoverRow] = field(default_factory=list)  #: every CA mover at the end
    ca_groups: list[GroupRow] = field(default_factory=list)  #: each CA group's minimum gap
    planar_movers: list[PlanarMoverRow] = field(default_factory=list)  #: each at the end
    axes_groups: list[AxesGroupRow] = field(default_factory=list)  #: each at the end
    planar_tracks: list[PlanarTrackRow] = field(default_factory=list)  #: each at the end
    #: (line, station) of every station line at the end (rail/stations.py)
    stations: list[tuple[str, StationRow]] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        """True when every check passed (a scenario without checks passes)."""
        return all(check.passed for check in self.checks)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON output; times rounded to 1e-9 s."""
        def clean(row: Any) -> dict[str, Any]:
            return {k: round(v, 9) if isinstance(v, float) else v for k, v in asdict(row).items()}

        return {"scenario": self.scenario.name, "passed": self.passed, "cycles": self.cycles,
                "cycle_time": self.scenario.cycle_time, "end_time": round(self.end_time, 9),
                "commands": [clean(row) for row in self.commands],
                "checks": [clean(row) for row in self.checks],
                **({"ca_groups": [clean(row) for row in self.ca_groups],
                    "ca_movers": [clean(row) for row in self.ca_movers]}
                   if self.ca_groups else {}),
                **({"planar_movers": [self._planar_mover(clean(row))
                                      for row in self.planar_movers]}
                   if self.planar_movers else {}),
                **({"planar_tracks": [clean(row) for row in self.planar_tracks]}
                   if self.planar_tracks else {}),
                **({"axes_groups": [clean(row) for row in self.axes_groups]}
                   if self.axes_groups else {}),
                **({"stations": [{"line": line, **clean(row)} for line, row in self.stations]}
                   if self.stations else {}),
                "trace": {"rows": len(self.trace), "columns": list(self.trace.columns)}}

    def _planar_mover(self, row: dict[str, Any]) -> dict[str, Any]:
        """A planar mover's JSON row: ``track`` and ``s`` only when there are tracks."""
        if not self.planar_tracks:
            del row["track"], row["s"]
        return row

    def renderable(self) -> RenderableType:
        """The summary as rich renderables: a header, the commands table, the checks table."""
        from rich import box
        from rich.console import Group
        from rich.table import Table
        from rich.text import Text

        digits = _time_digits(self.scenario.cycle_time)
        axes, movers = len(self.scenario.axes), len(self.planar_movers)
        objects = [f"{axes} {'axis' if axes == 1 else 'axes'}"] if axes or not movers else []
        if movers:
            objects.append(f"{movers} planar mover{'' if movers == 1 else 's'}")
        if self.planar_tracks:
            count = len(self.planar_tracks)
            objects.append(f"{count} planar track{'' if count == 1 else 's'}")
        if self.axes_groups:
            count = len(self.axes_groups)
            objects.append(f"{count} axes group{'' if count == 1 else 's'}")
        header = Text(f"{self.scenario.name}: {', '.join(objects)}, {self.cycles} "
                      f"cycles of {self.scenario.cycle_time * 1000:g} ms = "
                      f"{self.end_time:.{digits}f} s simulated")
        commands = Table(box=box.SIMPLE, title_justify="left", title="Commands")
        for name, justify in (("id", "left"), ("axis", "left"), ("command", "left"),
                              ("issued [s]", "right"), ("ended [s]", "right"),
                              ("result", "left"), ("detail", "left")):
            commands.add_column(Text(name), justify=justify,  # type: ignore[arg-type]
                                no_wrap=name != "detail", overflow="fold")
        for row in self.commands:
            detail = ": ".join(part for part in (row.error, row.message) if part)
            if row.value is not None or row.value_detail:
                shown = row.value_detail or f"value {_number(row.value)}"
                detail = "; ".join(part for part in (shown, detail) if part)
            commands.add_row(*map(Text, (row.id, row.axis, row.command,
                                         _time(row.issued_at, digits),
                                         _time(row.ended_at, digits))),
                             Text(row.result, style=_RESULT_STYLE.get(row.result, "")),
                             Text(detail))
        parts: list[RenderableType] = [header, commands]
        if self.ca_groups:
            parts += self._ca_renderables(digits)
        if self.stations:
            parts.append(station_table(self.stations))
        if self.planar_movers:
            parts.append(planar_table(self.planar_movers, _number))
        if self.planar_tracks:
            parts += [track_table(self.planar_tracks, _number),
                      riders_table(self.planar_movers, _number)]
        if self.axes_groups:
            parts.append(axes_group_table(self.axes_groups, _number))
        if self.checks:
            checks = Table(box=box.SIMPLE, title_justify="left", title="Checks")
            for name in ("check", "result", "detail"):
                checks.add_column(Text(name), overflow="fold")
            for check in self.checks:
                checks.add_row(Text(check.name), Text("PASS", style="green") if check.passed
                               else Text("FAIL", style="bold red"), Text(check.detail))
            parts.append(checks)
        failed = sum(not check.passed for check in self.checks)
        parts.append(Text("no checks" if not self.checks else
                          f"{len(self.checks) - failed} of {len(self.checks)} checks passed"
                          + ("" if self.passed else f", {failed} FAILED")))
        return Group(*parts)

    def _ca_renderables(self, digits: int) -> list[RenderableType]:
        """The CA movers table and one minimum-gap line per group."""
        from rich import box
        from rich.table import Table
        from rich.text import Text

        table = Table(box=box.SIMPLE, title_justify="left", title="CA movers")
        for name in ("group", "mover", "order", "position [mm]", "gap [mm]", "min gap [mm]",
                     "min at [s]"):
            table.add_column(Text(name), justify="left" if name in ("group", "mover")
                             else "right", no_wrap=True)
        for row in self.ca_movers:
            table.add_row(row.group, row.mover, str(row.order), _number(row.position),
                          *(_number(value) if value is not None else "-"
                            for value in (row.gap, row.minimum_gap)),
                          _time(row.minimum_at, digits))
        lines = [Text(f"{group.name}: minimum gap: " + (
            "-" if group.minimum_gap is None else f"{_number(group.minimum_gap)} mm "
            f"({group.mover}, t={_time(group.minimum_at, digits)} s)") + f"; {group.state}")
            for group in self.ca_groups]
        return [table, *lines, Text("")]

    def summary(self, width: int = SUMMARY_WIDTH) -> str:
        """The summary as plain text, as ``openmotion run`` prints it and the .out files hold."""
        from io import StringIO

        from rich.console import Console

        buffer = StringIO()
        console = Console(file=buffer, width=width, color_system=None, force_terminal=False,
                          highlight=False, emoji=False, legacy_windows=False)
        console.print(self.renderable())
        return "\n".join(line.rstrip() for line in buffer.getvalue().splitlines()) + "\n"


def run_scenario(source: str | Path | Scenario, progress: Progress | None = None,
                 figure: bool = False, *, keep: int | None = None,
                 stream: str | Path | None = None, chunk: int | None = None) -> ScenarioResult:
    """Run a scenario file (or model) to its end; ``progress`` is called now and then. With
    ``figure`` the trace also records what the scenario's default figure needs (x, y, c of
    every planar mover, else set position and gap of every CA mover: ``figure_signals``),
    after the scenario's own signals. ``keep`` or ``stream`` replace the ``record`` section's
    way of keeping the trace, ``chunk`` its chunk size (``TraceRecorder``, D-188); a
    streamed run's ``trace`` reads its columns from the directory when first used."""
    scenario = source if isinstance(source, Scenario) else load_scenario(source)
    return ScenarioRun(scenario, figure, _trace_mode(scenario, keep, stream, chunk)).run(progress)


def _router_spec(scenario: Scenario) -> RouterSpec | None:
    """planar.router, or its defaults when only the timeline has ``route`` entries."""
    planar = scenario.planar
    if planar is not None and planar.router is not None:
        return planar.router
    return RouterSpec() if any(isinstance(entry, Route) for entry in scenario.timeline) \
        else None


def _trace_mode(scenario: Scenario, keep: int | None, stream: str | Path | None,
                chunk: int | None) -> dict[str, Any]:
    """The recorder's keep, stream and chunk: the scenario's, or the caller's."""
    record = scenario.record
    mode: dict[str, Any] = {"keep": record.keep, "stream": record.stream,
                            "chunk": record.chunk}
    if keep is not None or stream is not None:
        mode = {"keep": keep, "stream": stream, "chunk": None}
    if chunk is not None:
        mode["chunk"] = chunk
    return mode


def _time_digits(cycle_time: float) -> int:
    return max(3, -math.floor(math.log10(cycle_time) + 1e-9))


def _time(value: float | None, digits: int) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


def _number(value: float) -> str:
    """A value for the summary: 6 decimals at most, so that golden files survive libm noise."""
    text = f"{value:.6f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def _value_of(command: Command | None) -> float | None:
    """The command's numeric result value, if any: a touch_probe's recorded position, the
    actual distance of a move_superimposed (whose value is (velocity diff, distance, length))."""
    value = None if command is None else command.value
    if isinstance(value, dict):  # a query's outputs: a check names one (``output``)
        return None
    if isinstance(value, tuple) and len(value) == _SUPERPOSITION_VALUES:
        value = value[1]
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    return None


_SUPERPOSITION_VALUES = 3  #: (ActualVelocityDiff, ActualDistance, ActualLength)


def _value_detail(command: Command | None) -> str:
    """The summary's text for a value with parts (a move_superimposed's actual values) or
    for a text value (read_axis_components)."""
    value = None if command is None else command.value
    if isinstance(value, str):
        return value
    if isinstance(value, dict):
        return outputs_text(value, _number)
    if isinstance(value, tuple) and len(value) == _SUPERPOSITION_VALUES:
        velocity_diff, distance, length = (_number(float(part)) for part in value)
        return f"distance {distance}, velocity diff {velocity_diff}, length {length}"
    return ""


def _result_of(command: Command | None) -> str:
    if command is None:
        return "NOT ISSUED"
    return "BUSY" if command.status <= CommandStatus.ACTIVE else command.status.name


class ScenarioRun:
    """A scenario set up on its runtime: ``run`` steps it to its end; the viewer and the
    endpoints step it themselves (``scenario.live``) with ``program`` and ``observe`` added."""

    def __init__(self, scenario: Scenario, figure: bool = False,
                 trace_mode: dict[str, Any] | None = None) -> None:
        self.scenario = scenario
        self.rt = rt = Runtime(scenario.cycle_time)
        #: the planar objects, set up before t = 0: first, while nothing else is on the runtime
        self.planar = PlanarMachine(rt, scenario.planar)
        problems = self.planar.set_up()
        if problems:  # the scenario's validation did the same on a scratch runtime
            raise ConfigError("planar: " + "; ".join(
                f"{'.'.join(map(str, loc))}: {message}" for loc, message in problems))
        router = _router_spec(scenario)
        if router is not None:  # after the setup: its program runs before the timeline's
            self.planar.add_router(router)
        for spec in scenario.axes:
            axis = rt.add_axis(spec.name, parameters=spec.parameters.build(),
                               drive=spec.drive.build(), position=spec.position)
            if spec.probe is not None:
                spec.probe.build(axis)
        #: the CA groups, built after the axes (and enabled before the first cycle)
        self.ca = CaGroups(rt, scenario.ca_groups)
        #: stations on planar tracks: a line after the planar system (scenario/stations.py)
        self.planar_line = None if scenario.planar is None else build_planar_line(
            rt, self.planar.movers, self.planar.tracks, scenario.planar.stations,
            scenario.planar.routes)
        #: the axes groups (Part 4), built after the CA groups
        self.coordinated = AxesGroups(rt, scenario.axes_groups)
        self.entries = list(scenario.entries())
        self.fire_cycle = [None if entry.at is None else cycle_of(entry.at, rt.cycle_time)
                           for _, entry in self.entries]
        self.pending = list(range(len(self.entries)))
        self.issued: dict[int, Command] = {}
        self.by_id: dict[str, Command] = {}
        #: the MC_InputRef of each touch_probe entry, by entry id (or label)
        self.trigger_inputs: dict[str, InputRef] = {
            label: entry.trigger_input() for label, entry in self.entries
            if isinstance(entry, TouchProbe)}
        #: the programs that call the blocks of block entries (jog, feed, filter, stepper)
        self.blocks = BlockPrograms(rt, self.holds)
        planar = self.planar
        objects = [*filter(None, [planar.environment]), *planar.movers.values(),
                   *planar.groups.values(), *self.coordinated.groups.values(),
                   *filter(None, [RoutePlans.of(rt, create=False)])]
        signals = list(scenario.signals)
        if figure:
            needed = figure_signals(describe([*rt.axes.values(), *objects]))
            signals += [name for name in needed if name not in signals]
        self.recorder = TraceRecorder(rt, signals, scenario.record.every, objects=objects,
                                      title=scenario.name, **(trace_mode or {}))
        #: the signals conditions and checks read: the machine model's, by name
        self.signals = RunSignals(rt, lambda: list(planar.tracks))
        self.checks = [_CheckState(check, self) for check in scenario.checks]
        self.quiet_since: int | None = None  #: first cycle of the current rest

    # -- the cycle ---------------------------------------------------------------------------

    def program(self) -> None:
        """Runtime program: call the running blocks, feed the planar movers' external
        setpoints, then issue every entry that is due."""
        self.blocks()
        self.planar.feed()
        self.ca.release_due()
        self.coordinated.release_due()
        self.fire_due()

    def fire_due(self) -> None:
        """Issue every entry that is due, in timeline order."""
        for index in list(self.pending):
            _, entry = self.entries[index]
            due = self.fire_cycle[index]
            if (self.rt.cycle >= due) if due is not None else self.holds(entry.when):
                self.pending.remove(index)
                self.issue(index, entry)

    def issue(self, index: int, entry: Entry) -> None:
        if self.coordinated.owns(entry):
            self._issued(index, entry, self.coordinated.issue(entry))  # type: ignore[arg-type]
            return
        if isinstance(entry, CA_ENTRIES):
            self._issued(index, entry, self.ca.issue(entry, self.by_id))
            return
        if isinstance(entry, (*PLANAR_ENTRIES, Route)):
            self._issued(index, entry, self.planar.issue(entry))  # type: ignore[arg-type]
            return
        axis = self.rt.axes.get(entry.axis)  # none for get_version
        arguments = entry.arguments()
        for name in entry.axis_fields:
            arguments[name] = self.rt.axes[arguments[name]]
        if isinstance(entry, BlockEntry):
            command = self.blocks.start(entry)
        elif isinstance(entry, TouchProbe):
            label = self.entries[index][0]
            command = arm_probe(axis, self.trigger_inputs[label], **arguments)
        elif isinstance(entry, PlcEvent):  # the PLC writes TriggerInput.PlcEvent
            command = Command(entry.command, self.rt.now)
            self.trigger_inputs[entry.probe].plc_event = entry.value
            command.end(CommandStatus.DONE, self.rt.now)
        elif isinstance(entry, AbortTrigger):  # as MC_AbortTrigger: Done, armed or not
            command = Command(entry.command, self.rt.now)
            abort_probe(self.trigger_inputs[entry.probe], self.rt.now)
            command.status = CommandStatus.DONE
            command.ended_at = self.rt.now
        elif isinstance(entry, Power | PowerOff):
            command = Command(entry.command, self.rt.now)
            on = axis.power(**arguments)
            override = axis.set_override(entry.override) \
                if isinstance(entry, Power) and entry.override is not None else None
            if override is not None and override.error:
                command.status, command.error_id = CommandStatus.ERROR, override.error_id
                command.message = override.message
            elif on == arguments.get("enable", True):
                command.status = CommandStatus.DONE
            else:
                command.status, command.error_id = CommandStatus.ERROR, ErrorId.DRIVE_NOT_READY
                command.message = "the drive is not ready"
            command.ended_at = self.rt.now
        elif isinstance(entry, Home) and entry.calibration_cam is not None:
            cam = self.blocks.cam(axis, entry.calibration_cam)  # wired before the edge
            command = axis.home(**arguments)
            cam.follow(command)
        else:
            command = getattr(axis, entry.method)(**arguments)
        self._issued(index, entry, command)

    def _issued(self, index: int, entry: Entry, command: Command) -> None:
        self.issued[index] = command
        if entry.id is not None:
            self.by_id[entry.id] = command
        target = entry.axis if not isinstance(entry, SetGap) else next(
            (other.axis for _, other in self.entries if other.id == entry.move), "")
        self.recorder.follow(command, target, self.entries[index][0])
        for mover, handle in self.planar.route_handles(command).items():  # each mover's end
            self.recorder.follow(handle, mover, self.entries[index][0])

    def holds(self, condition: Condition | None) -> bool:
        if condition is None:
            return False
        if condition.operator is None:
            command = self.by_id.get(condition.subject)
            if condition.attribute == "in_gear" and command in self.ca.commands:
                return self.ca.commands[command].sync_state(command)[1]  # InSync
            if condition.attribute == "in_sync":  # a gear-in on a track: its InSync
                return command is not None and self.planar.in_sync(command)
            attribute = "active" if condition.attribute == "in_gear" else condition.attribute
            return command is not None and bool(getattr(command, attribute))
        value = self.signals.read(condition.signal)
        return _OPERATORS[condition.operator](value, condition.value)

    def observe(self, runtime: Runtime) -> None:
        self.ca.watch()
        self.planar.watch()
        for check in self.checks:
            check.observe()

    # -- running -----------------------------------------------------------------------------

    def run(self, progress: Progress | None) -> ScenarioResult:
        rt, scenario = self.rt, self.scenario
        self.fire_due()  # entries at t = 0 act before the first cycle, like a script would
        self.recorder.sample(rt)
        self.observe(rt)
        rt.add_program(self.program)
        rt.add_observer(self.recorder)
        rt.add_observer(self.observe)
        total = scenario.duration  # None: open-ended, ends once everything is at rest
        while not self.finished():
            rt.step()
            if progress is not None and rt.cycle % PROGRESS_EVERY == 0:
                progress(rt.now, total)
        if progress is not None:
            progress(rt.now, rt.now)
        for check in self.checks:
            check.finish()
        return ScenarioResult(scenario, self.rows(), [c.row() for c in self.checks],
                              self.recorder.trace, rt.cycle, rt.now, self.ca.mover_rows(),
                              self.ca.group_rows(), self.planar.rows(),
                              self.coordinated.rows(), self.planar.track_rows(),
                              self.station_rows())

    @property
    def station_lines(self) -> list[StationLine]:
        """Every station line, the CA groups' first."""
        return [*self.ca.lines, *filter(None, [self.planar_line])]

    def station_rows(self) -> list[tuple[str, StationRow]]:
        """(line, station row) of every station line."""
        return [(line.name, row) for line in self.station_lines for row in line.station_rows()]

    def finished(self) -> bool:
        """``duration`` is over; or ``settle_time`` after all came to rest, or the cap."""
        scenario, cycle = self.scenario, self.rt.cycle
        if scenario.duration is not None:
            return cycle >= cycle_of(scenario.duration, scenario.cycle_time)
        if not self.at_rest():
            self.quiet_since = None
        elif self.quiet_since is None:
            self.quiet_since = cycle
        settled = self.quiet_since is not None and \
            cycle - self.quiet_since >= cycle_of(scenario.settle_time, scenario.cycle_time)
        return settled or cycle >= cycle_of(scenario.max_duration, scenario.cycle_time)

    def at_rest(self) -> bool:
        """No ``at`` is still ahead, every command ended (or is at speed), no jog, feed or
        timed stall runs, no group_stop holds, no axis or planar mover moves. An override
        filter or a stepper block, which run to the end, do not count; nor does a busy CA
        command whose group stands still (a mover queued behind another stays Busy, TF5410
        §9.1.1.1.1), nor a busy move_on_track whose mover stands queued on its track. A CA
        mover stands with |v| and |a| at most 1e-9 of its maxima (groups.STANDING). A
        tracking or syncing command of an axes group runs in the background and does not
        count either; a group_stop that holds an axes group or a group that homes does."""
        cycle = self.rt.cycle
        if any(self.fire_cycle[i] is not None and self.fire_cycle[i] > cycle
               for i in self.pending) or any(c.waiting(cycle) for c in self.checks):
            return False
        if self.planar_line is not None and self.planar_line.busy:
            return False
        if self.blocks.busy or self.ca.busy or self.planar.busy or self.coordinated.busy or any(
                not (c.finished or c.in_velocity and c.kind not in _UNTIL_FINISHED)
                and not self.ca.waiting(c) and not self.coordinated.waiting(c)
                and not self.planar.waiting(c)
                for c in self.issued.values() if c.kind not in _TO_THE_END):
            return False
        if not all(map(self.ca.standing, self.ca.groups.values())):
            return False
        for axis in self.rt.axes.values():
            if axis.name in self.ca.group_of:
                continue  # stands with its group (above)
            active = axis.active_command
            if axis.moving and not (active is not None and active.in_velocity):
                return False
        return True

    def rows(self) -> list[CommandRow]:
        rows = []
        axis_of = {entry.id: entry.axis for _, entry in self.entries if entry.id is not None}
        for index, (label, entry) in enumerate(self.entries):
            command = self.issued.get(index)
            result = _result_of(command)
            error, message, warnings = "", "", []
            if command is not None:
                if command.error:
                    error = command.error_id.name
                message, warnings = command.message, list(command.warnings)
            text = "; ".join(part for part in [message, *warnings] if part)
            axis = axis_of.get(entry.move, "") if isinstance(entry, SetGap) else entry.axis
            rows.append(CommandRow(label, axis, entry.command,
                                   command.issued_at if command else None,
                                   command.ended_at if command else None, result, error, text,
                                   _value_of(command), _value_detail(command)))
        return rows


class _CheckState:
    """One check while the run goes on: when to evaluate it and what it found."""

    def __init__(self, check: SignalCheck | CommandCheck, run: ScenarioRun) -> None:
        self.check, self.run = check, run
        self.cycle = cycle_of(check.at, run.rt.cycle_time) \
            if isinstance(check.at, float) and check.when is None else None
        self.passed: bool | None = None
        self.detail = ""

    def waiting(self, cycle: int) -> bool:
        return self.cycle is not None and self.passed is None and cycle < self.cycle

    def observe(self) -> None:
        check, rt = self.check, self.run.rt
        if check.when is not None:
            if self.passed is None and self.run.holds(check.when):
                self.evaluate()
        elif check.at == "always":
            if self.passed is not False:
                self.evaluate()
        elif self.cycle is not None and self.passed is None and rt.cycle >= self.cycle:
            self.evaluate()

    def finish(self) -> None:
        check, now = self.check, self.run.rt.now
        if check.when is not None:
            if self.passed is None:
                self.passed, self.detail = False, f"'{check.when}' never held"
        elif check.at == "end":
            self.evaluate()
        elif self.passed is None:
            self.passed = False
            self.detail = f"the run ended at {now:.6g} s, before {check.at:.15g} s"

    def evaluate(self) -> None:
        now = f"t={self.run.rt.now:.6g} s: " if self.check.at == "always" else ""
        if isinstance(self.check, SignalCheck):
            self.passed, detail = self._signal(self.check)
        else:
            self.passed, detail = self._command(self.check)
        self.detail = now + detail if not self.passed else detail

    def _signal(self, check: SignalCheck) -> tuple[bool, str]:
        value, shown, named = self.run.signals.reading(check.signal)
        shown = shown or _number(value)
        expected = check.expected
        if expected is not None and not abs(value - expected) <= check.tolerance:
            return False, shown if named else f"{shown}, off by {_number(value - expected)}"
        if check.min is not None and not value >= check.min:
            return False, f"{shown} < min {_number(check.min)}"
        if check.max is not None and not value <= check.max:
            return False, f"{shown} > max {_number(check.max)}"
        return True, f"{shown}" if check.at != "always" else "held every cycle"

    def _command(self, check: CommandCheck) -> tuple[bool, str]:
        command = self.run.by_id.get(check.command)
        result = _result_of(command)
        detail = result + (f" {command.error_id.name}" if command and command.error else "")
        ok = result == check.result.upper()
        if ok and check.error_id is not None:
            ok = command is not None and command.error_id == check.error_id
        if check.value is not None:
            value = _value_of(command) if check.output is None else \
                pick(command.value if command is not None else None, check.output)
            if value is None and check.output is not None:
                return False, f"{detail}, no output {check.output}"
            if value is None:
                return False, f"{detail}, no value"
            detail += f" {_number(value)}"
            if ok and not abs(value - check.value) <= check.tolerance:
                return False, f"{detail}, off by {_number(value - check.value)}"
        return ok, detail

    def row(self) -> CheckRow:
        return CheckRow(self.check.name or self._describe(), bool(self.passed), self.detail)

    def _describe(self) -> str:
        check = self.check
        if check.when is not None:
            when = f"when {check.when}"
        else:
            when = f"at {check.at:.15g} s" if isinstance(check.at, float) else \
                {"end": "at end", "always": "always"}[check.at]
        if isinstance(check, CommandCheck):
            error = f" {check.error_id.name}" if check.error_id is not None else ""
            output = "" if check.output is None else f" {check.output}"
            value = "" if check.value is None else f"{output} value {check.value:.15g}" + (
                f" ± {check.tolerance:.15g}" if check.tolerance else "")
            return f"{check.command} {check.result}{error}{value} {when}"
        parts = []
        if isinstance(check.expect, str):
            parts.append(f"{check.signal} == {check.expect}")
        elif check.expect is not None:
            tolerance = f" ± {check.tolerance:.15g}" if check.tolerance else ""
            parts.append(f"{check.signal} == {check.expect:.15g}{tolerance}")
        low = "" if check.min is None else f"{check.min:.15g} <= "
        high = "" if check.max is None else f" <= {check.max:.15g}"
        if low or high:
            parts.append(f"{low}{check.signal}{high}")
        return f"{', '.join(parts)} {when}"
