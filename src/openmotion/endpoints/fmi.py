"""A scenario as an FMI 2.0 co-simulation unit (FMU): its signals out, chosen commands in.

``export_fmu`` writes the FMU with pythonfmu (D-270): the scenario file and a small JSON
file of options travel in the FMU's resources; the FMU's class (``fmi_slave.MachineSlave``)
sets the scenario up again when an importer instantiates it, with the openmotion installed
in the importer's Python. ``MachineUnit`` is that machine as the FMU sees it, and knows
nothing of FMI libraries, so it is tested on its own.

- ``doStep`` advances whole cycles: a communication step that is not a whole number of
  cycles (or a step that does not start where the machine stands) is refused (``StepError``).
  The scenario's timeline and checks play as in ``openmotion run``; the machine goes on past
  the scenario's end, as a served one does.
- Outputs: signals of the machine model, ``<object>.<signal>``, Real with the signal's
  unit; by default those the scenario records (its trace's columns), or all (D-271).
- Inputs: the commands chosen by ``OBJECT.COMMAND`` (D-272). A command that starts a
  handle gets ``<object>.<command>.Execute`` and one input per wire input; its rising edge
  starts the command with the inputs of that moment, before the step's first cycle, and
  ``Done``, ``Busy``, ``Active``, ``CommandAborted``, ``Error``, ``ErrorID`` follow it. A
  level command (MC_Power) is applied before every step with its inputs; ``Status`` says
  what it returned.
"""

from __future__ import annotations

import difflib
import json
import math
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, fields, is_dataclass
from enum import Enum
from pathlib import Path
from typing import Any

from openmotion.core.errors import ConfigError, ErrorId
from openmotion.endpoints.wire import (
    HandleState,
    WireCommand,
    WireError,
    WireInput,
    WireKind,
    default_of,
    handle_state,
    wire_commands,
)
from openmotion.kernel.model import REQUIRED, MachineModel, Signal, machine
from openmotion.scenario.live import scenario_machine

__all__ = ["FmuVariable", "MachineUnit", "StepError", "export_fmu"]

MODEL_NAME = "OpenmotionMachine"  #: the FMU's model name and model identifier (its binary)
SCRIPT = "openmotion_fmu.py"  #: the module pythonfmu loads from the FMU's resources
OPTIONS = "openmotion_fmu.json"  #: what ``export_fmu`` chose, read again by the FMU
SCENARIO = "scenario.yaml"  #: the scenario, as a copy of the file exported
#: how far a step may be from a whole number of cycles, or a step's start from the machine's
#: time, in cycles: far below one cycle, far above the rounding of a sum of steps
CYCLE_TOLERANCE = 1e-6
#: ErrorID of a command whose inputs the wire refused (not a number, outside its range ...):
#: the command is not started and the machine is untouched
INPUT_ERROR = ErrorId.INVALID_PARAMETER_VALUE
HANDLE_OUTPUTS = ("Done", "Busy", "Active", "CommandAborted", "Error")  #: Boolean outputs
_SCRIPT_TEXT = '''"""The class an importer's pythonfmu loads (written by 'openmotion fmu')."""

from openmotion.endpoints.fmi_slave import MachineSlave

#: pythonfmu 0.7's binary drops a reference to this module's namespace at every
#: instantiation; MachineSlave gives one back each time, this one keeps it above zero between
PINNED = [globals()]


class OpenmotionMachine(MachineSlave):
    """The scenario in this FMU's resources, stepped whole cycles at a time."""
'''


class StepError(ConfigError):
    """A communication step the machine cannot take (not whole cycles, or not from now)."""


@dataclass
class FmuVariable:
    """One scalar of the FMU: what pythonfmu registers and the model description shows."""

    name: str
    type: str  #: "Real", "Integer", "Boolean" or "String"
    causality: str  #: "output" or "input"
    get: Callable[[], Any]
    set: Callable[[Any], None] | None = None
    unit: str = ""
    description: str = ""


# -- the machine as the FMU sees it -----------------------------------------------------------

class MachineUnit:
    """A scenario stepped by communication steps of whole cycles (one thread, no host)."""

    def __init__(self, scenario: str | Path, commands: Sequence[str] = (),
                 signals: Sequence[str] | None = None) -> None:
        live = scenario_machine(scenario)
        self.runtime = live.runtime
        self.cycle_time: float = self.runtime.cycle_time
        self.model: MachineModel = machine(self.runtime)
        every = self.model.signals()
        names = list(every) if signals is None else list(dict.fromkeys(signals))
        self.signals: list[tuple[str, Signal]] = [
            (name, every[name] if name in every else self.model.signal(name)) for name in names]
        self.values = [0.0] * len(self.signals)
        self.ports: list[_EdgePort | _LevelPort] = [
            _port(self.command(name), self.model) for name in dict.fromkeys(commands)]
        self.log: Callable[[str], None] = lambda message: None  #: warnings to the importer
        self._read()
        self.variables: list[FmuVariable] = [*self._outputs(), *(
            variable for port in self.ports for variable in port.variables)]

    def command(self, qualified: str) -> WireCommand:
        """The served command ``OBJECT.COMMAND``; ``ConfigError`` naming the choices."""
        owner, dot, name = qualified.rpartition(".")
        if not dot or not owner or not name:
            raise ConfigError(f"command {qualified!r} is not 'OBJECT.COMMAND' (x.move_absolute)")
        objects = [obj for obj in self.model if obj.name == owner]
        if not objects:
            raise ConfigError(f"command {qualified!r}: no object {owner!r}; one of "
                              f"{', '.join(dict.fromkeys(obj.name for obj in self.model))}")
        served = [command for obj in objects for command in wire_commands(obj)]
        for command in served:
            if command.name == name:
                return command
        names = [command.name for command in served]
        close = difflib.get_close_matches(name, names, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise ConfigError(f"command {qualified!r}: {owner!r} has no command {name!r} an FMU "
                          f"can drive{hint}; one of {', '.join(names) or 'none'}")

    @property
    def now(self) -> float:
        return self.runtime.now

    def start(self) -> None:
        """The end of initialisation: the level commands take the inputs the importer set,
        so the outputs at t = 0 show them."""
        for port in self.ports:
            if isinstance(port, _LevelPort):
                port.apply(self)
        self._read()

    def step(self, current_time: float, step_size: float) -> None:
        """Advance ``step_size`` seconds from ``current_time``: whole cycles only."""
        cycle = self.cycle_time
        cycles = round(step_size / cycle)
        if not cycles >= 1 or abs(step_size / cycle - cycles) > CYCLE_TOLERANCE:
            raise StepError(f"the communication step {step_size!r} s is not a whole number "
                            f"of cycles of {cycle!r} s")
        if abs(current_time - self.runtime.now) > CYCLE_TOLERANCE * cycle:
            raise StepError(f"a step from t = {current_time!r} s, but the machine stands at "
                            f"t = {self.runtime.now!r} s (it starts at 0 and goes forward)")
        for port in self.ports:
            port.apply(self)
        for _ in range(cycles):
            self.runtime.step()
        self._read()
        for port in self.ports:
            port.observe()

    def _read(self) -> None:
        self.values[:] = [signal.read() for _, signal in self.signals]

    def _outputs(self) -> Iterable[FmuVariable]:
        for index, (name, signal) in enumerate(self.signals):
            dtype = signal.dtype
            what = (f"{dtype.__name__}: " + ", ".join(f"{m.value}={m.name}" for m in dtype)
                    if isinstance(dtype, type) and issubclass(dtype, Enum)
                    else "0 or 1" if dtype is bool else signal.spec.doc)
            yield FmuVariable(name, "Real", "output", _reader(self.values, index),
                              unit=signal.unit, description=what)


def _reader(values: list[float], index: int) -> Callable[[], float]:
    return lambda: values[index]  # ``values`` is refilled in place after every step


def _port(command: WireCommand, model: MachineModel) -> _EdgePort | _LevelPort:
    return _LevelPort(command, model) if command.spec.level else _EdgePort(command, model)


class _Inputs:
    """The FMU inputs of one command's wire inputs: their values, and the call's arguments."""

    def __init__(self, command: WireCommand, prefix: str, owner: Any) -> None:
        self.command = command
        self.values: dict[str, Any] = {}
        self.variables: list[FmuVariable] = []
        self.collect: list[Callable[[], tuple[str, Any] | None]] = []
        for put in command.inputs:
            self.collect.append(self._add(put, f"{prefix}.{put.name}", owner))

    def _variable(self, name: str, type_: str, start: Any, unit: str = "",
                  description: str = "") -> None:
        self.values[name] = start

        def put(value: Any) -> None:
            self.values[name] = value
        self.variables.append(FmuVariable(name, type_, "input", lambda: self.values[name],
                                          put, unit, description))

    def _add(self, put: WireInput, name: str, owner: Any) \
            -> Callable[[], tuple[str, Any] | None]:
        default = put.input.default
        given = default is not REQUIRED
        kind = put.kind
        if kind is WireKind.NUMBER:
            if not given:
                start, note = 0.0, "required"
            elif isinstance(default, int | float):
                start, note = float(default), "NaN: the input's default"
            else:  # MC_DEFAULT and its kin, or None: no number stands for them
                shown = "" if default is None else f" ({default_of(put)})"
                start, note = math.nan, f"NaN: the input's default{shown}"
            self._variable(name, "Real", start, put.input.unit, note)
            return lambda: None if given and math.isnan(self.values[name]) \
                else (put.name, self.values[name])
        if kind is WireKind.INTEGER:
            self._variable(name, "Integer", int(default) if given and default is not None
                           else 0)
            return lambda: (put.name, self.values[name])
        if kind is WireKind.BOOL:
            self._variable(name, "Boolean", bool(default) if given else False)
            return lambda: (put.name, bool(self.values[name]))
        if kind is WireKind.ENUM:
            return self._enum(put, name, default if given else None)
        if kind is WireKind.OBJECT:
            start = getattr(default, "name", "") if given and default is not None else ""
            self._variable(name, "String", start, description=f"an object's name ({put.type})"
                           + ("; empty: the input's default" if given else ""))
            return lambda: None if given and not self.values[name] \
                else (put.name, self.values[name])
        return self._vector(put, name, owner)

    def _enum(self, put: WireInput, name: str, default: Any) \
            -> Callable[[], tuple[str, Any] | None]:
        cls = put.type
        if cls is not None and all(isinstance(m.value, int) for m in cls):
            members = {m.value: m for m in cls}
            self._variable(name, "Integer", int(default.value) if default is not None
                           else min(members), description=", ".join(
                               f"{m.value}={m.name}" for m in cls))
            return lambda: (put.name, self.values[name])
        names = [m.name for m in cls] if cls is not None else list(put.input.choices)
        start = names.index(getattr(default, "name", default)) if default is not None else 0
        self._variable(name, "Integer", start,
                       description=", ".join(f"{i}={n}" for i, n in enumerate(names)))

        def pick() -> tuple[str, Any]:
            index = self.values[name]
            return put.name, names[index] if 0 <= index < len(names) else index
        return pick

    def _vector(self, put: WireInput, name: str, owner: Any) \
            -> Callable[[], tuple[str, Any]]:
        if put.type is not None and is_dataclass(put.type):
            parts = [f"{name}.{part.name}" for part in fields(put.type)]
        else:  # a position of an axes group: one number per axis of the group
            count = len(getattr(owner, "axes", ()))
            if count == 0:
                raise ConfigError(f"{self.command.name}: input {put.name!r} is an array "
                                  "whose length the FMU cannot know")
            parts = [f"{name}[{i}]" for i in range(1, count + 1)]
        for part in parts:
            self._variable(part, "Real", 0.0, put.input.unit)
        return lambda: (put.name, [self.values[part] for part in parts])

    def given(self) -> dict[str, Any]:
        """The inputs as a client sends them (those left at their default left out)."""
        return dict(pair for pair in (collect() for collect in self.collect)
                    if pair is not None)


class _EdgePort:
    """A command started by a rising edge of ``Execute`` (PLCopen's Execute/Done handshake)."""

    def __init__(self, command: WireCommand, model: MachineModel) -> None:
        self.command, self.model = command, model
        prefix = f"{command.owner.name}.{command.name}"
        self.inputs = _Inputs(command, prefix, command.owner.target)
        self.execute = False
        self.last_execute = False
        self.handle: Any = None
        self.state = HandleState()
        self.seen_end = False  #: the command had ended at the step before
        state = lambda attribute: lambda: getattr(self.state, attribute)  # noqa: E731
        self.variables = [
            FmuVariable(f"{prefix}.Execute", "Boolean", "input", lambda: self.execute,
                        self._set_execute, description="rising edge: start the command"),
            *self.inputs.variables,
            *(FmuVariable(f"{prefix}.{output}", "Boolean", "output", state(attribute))
              for output, attribute in zip(HANDLE_OUTPUTS, ("done", "busy", "active",
                                                            "command_aborted", "error"),
                                           strict=True)),
            FmuVariable(f"{prefix}.ErrorID", "Integer", "output", state("error_id"))]

    def _set_execute(self, value: Any) -> None:
        self.execute = bool(value)

    def apply(self, unit: MachineUnit) -> None:
        rising = self.execute and not self.last_execute
        self.last_execute = self.execute
        if not rising:
            return
        self.seen_end = False
        try:
            arguments = self.command.arguments(self.inputs.given(), self.model)
            self.handle = self.command.spec.start(**arguments)  # type: ignore[misc]
        except (ConfigError, TypeError, ValueError) as error:  # WireError, or a refusal
            # the machine raises rather than answers (a planar block's bad option): the FB's
            # error outputs, never a dead FMU
            self.handle = None
            self.state = HandleState(error=True, error_id=int(INPUT_ERROR), message=str(error))
            unit.log(f"{self.command.owner.name}.{self.command.name}: {error}")

    def observe(self) -> None:
        """The outputs after a step: the command's while Execute is TRUE. Execute FALSE
        resets the outputs of an ended command; of one that ended within this step, after
        showing them for this one step (PLCopen's rule, one communication step a cycle)."""
        if self.handle is not None:
            self.state = handle_state(self.handle)
        ended = not self.state.busy and self.state != HandleState()
        if ended and not self.execute and self.seen_end:
            self.handle, self.state, ended = None, HandleState(), False
        self.seen_end = ended


class _LevelPort:
    """A level command (MC_Power): applied before every step with its inputs."""

    def __init__(self, command: WireCommand, model: MachineModel) -> None:
        self.command, self.model = command, model
        prefix = f"{command.owner.name}.{command.name}"
        self.inputs = _Inputs(command, prefix, command.owner.target)
        self.status = False
        self.variables = [*self.inputs.variables, FmuVariable(
            f"{prefix}.Status", "Boolean", "output", lambda: self.status,
            description="what the command returned at the last step")]

    def apply(self, unit: MachineUnit) -> None:
        try:
            arguments = self.command.arguments(self.inputs.given(), self.model)
        except WireError as error:
            unit.log(f"{self.command.owner.name}.{self.command.name}: {error}")
            return
        self.status = bool(self.command.spec.start(**arguments))  # type: ignore[misc]

    def observe(self) -> None:
        pass


# -- export -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class FmuOptions:
    """What ``export_fmu`` chose: written into the FMU, read again by its class."""

    commands: list[str] = field(default_factory=list)
    signals: list[str] | None = None  #: None: every signal of the machine model
    stop_time: float = 1.0  #: the default experiment: the last row of the run's trace [s]
    step_size: float = 0.001  #: the default experiment: the trace's sampling period [s]
    description: str = ""

    @classmethod
    def read(cls, resources: str | Path) -> FmuOptions:
        data = json.loads((Path(resources) / OPTIONS).read_text(encoding="utf-8"))
        return cls(**data)


def export_fmu(scenario: str | Path, output: str | Path, *, commands: Sequence[str] = (),
               all_signals: bool = False, stop_time: float | None = None) -> Path:
    """Write ``scenario`` as a co-simulation FMU to ``output``; the path written.

    Outputs are the signals the scenario records (all of the machine model's with
    ``all_signals``), inputs the ``commands`` named ``OBJECT.COMMAND``. The FMU's default
    experiment steps at the trace's period and runs to ``stop_time``: by default the time of
    the last row of ``openmotion run``'s trace (the scenario's ``duration``, or where the run
    ends it, found by running it once). Raises ``ConfigError`` for a bad
    scenario or an unknown command before anything is written.
    """
    from openmotion.scenario.load import load_scenario
    from openmotion.scenario.programs import cycle_of
    from openmotion.scenario.run import run_scenario

    source, target = Path(scenario), Path(output)
    if target.suffix != ".fmu":
        raise ConfigError(f"output {str(target)!r}: an FMU file ends in .fmu")
    if not target.parent.is_dir():  # pythonfmu would make it: a typo would go unseen
        raise ConfigError(f"output {str(target)!r}: no directory {str(target.parent)!r}")
    model = load_scenario(source)
    signals = None if all_signals else list(model.signals)
    MachineUnit(source, commands, signals)  # every ConfigError now, not in the importer
    if stop_time is not None and not (math.isfinite(stop_time) and stop_time > 0):
        raise ConfigError(f"stop time must be a number > 0 [s], not {stop_time!r}")
    every, cycle = model.record.every, model.cycle_time
    if stop_time is None:  # the trace's last row: where the run ends, on the trace's period
        cycles = cycle_of(model.duration, cycle) if model.duration is not None else \
            run_scenario(model).cycles
        stop_time = cycles // every * every * cycle
    options = FmuOptions(list(dict.fromkeys(commands)), signals, float(stop_time),
                         cycle * every,
                         f"openmotion scenario {model.name!r}"
                         + (f": {model.description.strip()}" if model.description else ""))
    from pythonfmu import FmuBuilder

    path = list(sys.path)
    with tempfile.TemporaryDirectory(prefix="openmotion_fmu_") as temp:
        folder = Path(temp)
        script = folder / SCRIPT
        script.write_text(_SCRIPT_TEXT, encoding="utf-8")
        resources = folder / "resources"
        resources.mkdir()
        shutil.copyfile(source, resources / SCENARIO)
        (resources / OPTIONS).write_text(json.dumps(options.__dict__, indent=1),
                                         encoding="utf-8")
        try:
            built = FmuBuilder.build_FMU(script, dest=target, project_files=[
                resources / SCENARIO, resources / OPTIONS])
        finally:
            sys.path[:] = path  # the builder leaves the script's folder on it
    return Path(built)
