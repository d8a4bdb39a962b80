"""Sweep files: a base scenario, the parameters to vary, the metrics to collect.

Loading validates the file (pydantic, unknown keys are errors), reads the base scenario (a
path relative to the sweep file, or a shipped example's name) and checks every parameter
path against it, so that a misspelt path is one ``SweepError`` naming the file, line and
field before any point runs (docs/sweeps.md).
"""

from __future__ import annotations

import math
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    StrictInt,
    Tag,
    ValidationError,
    model_validator,
)

from openmotion.core.errors import ConfigError
from openmotion.examples import find_example
from openmotion.scenario import Problem, ScenarioError, parse_scenario
from openmotion.scenario.load import node_at
from openmotion.scenario.reading import Refused, ScenarioLoader, max_bytes, read_text
from openmotion.sweep import paths
from openmotion.sweep.metrics import METRIC_KINDS, Metric, metric_kind

RESERVED_COLUMNS = ("index", "point_id", "seed", "sample", "repeat", "status", "error",
                    "scenario_hash", "openmotion_version")  #: the table's own columns
RANDOM_KINDS = ("uniform", "integers", "choice")  #: value kinds drawn per point
VALUE_KINDS = ("values", "linspace", *RANDOM_KINDS)


class Linspace(BaseModel):
    """``num`` evenly spaced values from ``start`` to ``stop``, both included."""

    model_config = ConfigDict(extra="forbid")
    start: float
    stop: float
    num: StrictInt = Field(ge=1)


class Parameter(BaseModel):
    """One varied parameter: where it goes (``path``, or ``first``: lists that keep their
    first N items) and its values (a list, a linspace, or a seeded random draw)."""

    model_config = ConfigDict(extra="forbid")
    path: str | None = None
    first: list[str] | None = Field(default=None, min_length=1)
    name: str | None = Field(default=None, min_length=1)  #: column name; default the path
    values: list[Any] | None = Field(default=None, min_length=1)
    linspace: Linspace | None = None
    uniform: tuple[float, float] | None = None
    integers: tuple[StrictInt, StrictInt] | None = None
    choice: list[Any] | None = Field(default=None, min_length=1)

    @model_validator(mode="after")
    def _one_target_one_kind(self) -> Parameter:
        if (self.path is None) == (self.first is None):
            raise ValueError("give either path (the value's place in the scenario) or first "
                             "(lists that keep their first N items)")
        for text in [self.path] if self.path is not None else self.first or []:
            paths.parse_path(text)  # a ConfigError is a ValueError: pydantic reports it
        if self.first is not None and self.name is None:
            raise ValueError("name: required with first (it names the column)")
        kinds = [kind for kind in VALUE_KINDS if getattr(self, kind) is not None]
        if len(kinds) != 1:
            raise ValueError(f"give exactly one of {', '.join(VALUE_KINDS)}"
                             + (f" (got {', '.join(kinds)})" if kinds else ""))
        if self.uniform is not None and not (math.isfinite(self.uniform[0])
                                             and self.uniform[0] < self.uniform[1]
                                             and math.isfinite(self.uniform[1])):
            raise ValueError(f"uniform: must be [low, high] with low < high, got "
                             f"{list(self.uniform)}")
        if self.integers is not None and self.integers[0] > self.integers[1]:
            raise ValueError(f"integers: must be [low, high] with low <= high, got "
                             f"{list(self.integers)}")
        return self

    @property
    def column(self) -> str:
        return self.name or str(self.path)

    @property
    def random(self) -> bool:
        return any(getattr(self, kind) is not None for kind in RANDOM_KINDS)

    def listed(self) -> list[Any]:
        """The values of a list or linspace parameter."""
        if self.linspace is not None:
            start, stop, num = self.linspace.start, self.linspace.stop, self.linspace.num
            return [start] if num == 1 else \
                [start + (stop - start) * i / (num - 1) for i in range(num)]
        return list(self.values or [])


MetricEntry = Annotated[
    typing.Union[tuple(Annotated[kind, Tag(name)]  # noqa: UP007 (a union built at run time)
                       for name, kind in METRIC_KINDS.items())],
    Discriminator(metric_kind, custom_error_type="metric_kind",
                  custom_error_message=f"give exactly one of {', '.join(METRIC_KINDS)}")]


class SweepSpec(BaseModel):
    """A sweep file (docs/sweeps.md, "Sweep files")."""

    model_config = ConfigDict(extra="forbid")
    name: str = ""
    description: str = ""
    scenario: str = Field(min_length=1)  #: a path relative to the sweep file, or an example
    seed: StrictInt = Field(default=0, ge=0)
    repeat: StrictInt = Field(default=1, ge=1)  #: runs of each combination, own seed each
    samples: StrictInt = Field(default=1, ge=1)  #: random draws of each combination
    combine: Literal["grid", "zip"] = "grid"  #: of the list parameters
    parameters: list[Parameter] = []
    metrics: list[MetricEntry] = Field(min_length=1)  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _distinct_columns(self) -> SweepSpec:
        seen: set[str] = set(RESERVED_COLUMNS)
        names = [p.column for p in self.parameters]
        names += [c for metric in self.metrics for c in metric.columns()]
        for name in names:
            if name in seen:
                raise ValueError(f"column {name!r} given twice (or a reserved name: "
                                 f"{', '.join(RESERVED_COLUMNS)}); set a parameter's or "
                                 "metric's name")
            seen.add(name)
        if self.combine == "zip":
            lengths = {p.column: len(p.listed()) for p in self.parameters if not p.random}
            if len(set(lengths.values())) > 1:
                raise ValueError("combine zip: the list parameters must have equal lengths, "
                                 f"got {lengths}")
        return self


class SweepError(ConfigError):
    """A sweep file is invalid; ``problems`` lists everything wrong, the message the first."""

    def __init__(self, problems: list[Problem]) -> None:
        self.problems = problems
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        super().__init__(f"{problems[0]}{more}")


@dataclass(frozen=True)
class Sweep:
    """A loaded sweep: its file, the validated spec, and the base scenario document."""

    file: str
    spec: SweepSpec
    scenario_file: Path
    base: dict[str, Any]  #: the base scenario as plain data (anchors resolved)

    @property
    def metrics(self) -> list[Metric]:
        return list(self.spec.metrics)


def load_sweep(path: str | Path) -> Sweep:
    """Read and validate a sweep file and its base scenario; ``SweepError`` names the file,
    line and field of each problem."""
    file = str(path)
    root, data = _read(path, file)
    try:
        spec = SweepSpec.model_validate(data)
    except ValidationError as exc:
        raise SweepError(sorted((_problem(error, root, file) for error in exc.errors()),
                                key=lambda p: p.line)) from None
    scenario_file = _scenario_file(spec.scenario, Path(path).parent)
    if scenario_file is None:
        raise SweepError([Problem(file, _line(root, ("scenario",)), "scenario",
                                  f"{spec.scenario!r}: no such file (beside the sweep file) "
                                  "and no shipped example of that name")])
    text = _scenario_text(scenario_file, file, _line(root, ("scenario",)))
    try:
        parse_scenario(text, str(scenario_file))
    except ScenarioError as exc:
        raise SweepError([Problem(file, _line(root, ("scenario",)), "scenario",
                                  f"the base scenario is invalid: {p}") for p in exc.problems]) \
            from None
    base = _document(text, str(scenario_file))[1]
    problems = [problem for number, parameter in enumerate(spec.parameters)
                for problem in _check_targets(parameter, number, base, root, file)]
    if problems:
        raise SweepError(problems)
    return Sweep(file, spec, scenario_file, base)


def _check_targets(parameter: Parameter, number: int, base: dict[str, Any], root: yaml.Node,
                   file: str) -> list[Problem]:
    """Every path of a parameter resolves in the base scenario; ``first`` addresses lists
    long enough for every value."""
    field = "path" if parameter.path is not None else "first"
    where = ("parameters", number, field)
    problems = []
    for text in [parameter.path] if parameter.path is not None else parameter.first or []:
        try:
            found = paths.get(base, text)
        except ConfigError as exc:
            problems.append(Problem(file, _line(root, where), _dotted(where), f"{text}: {exc}"))
            continue
        if parameter.first is None:
            continue
        counts = parameter.listed() if not parameter.random else list(parameter.integers or ())
        if parameter.uniform is not None or parameter.choice is not None or not all(
                isinstance(n, int) and not isinstance(n, bool) and n >= 0 for n in counts):
            problems.append(Problem(file, _line(root, where[:2]), _dotted(where[:2]),
                                    "first: the values must be whole numbers >= 0 (values or "
                                    "integers)"))
        elif not found or not all(isinstance(value, list) for value in found):
            problems.append(Problem(file, _line(root, where), _dotted(where),
                                    f"{text}: not a list"))
        elif max(counts) > min(len(value) for value in found):
            problems.append(Problem(file, _line(root, where), _dotted(where),
                                    f"{text}: has {min(len(v) for v in found)} items, fewer "
                                    f"than {max(counts)}"))
    return problems


def _scenario_file(name: str, folder: Path) -> Path | None:
    beside = folder / name
    if beside.is_file():
        return beside
    return find_example(name)


def _scenario_text(path: Path, file: str, line: int) -> str:
    try:
        return read_text(path, max_bytes())
    except OSError as exc:
        raise SweepError([Problem(file, line, "scenario",
                                  f"cannot read {path}: {exc.strerror}")]) from None
    except Refused as exc:
        raise SweepError([Problem(str(path), exc.line, "", exc.message)]) from None


def _read(path: str | Path, file: str) -> tuple[yaml.Node, Any]:
    try:
        text = read_text(path, max_bytes())
    except OSError as exc:
        raise SweepError([Problem(file, 0, "", f"cannot read: {exc.strerror}")]) from None
    except Refused as exc:
        raise SweepError([Problem(file, exc.line, "", exc.message)]) from None
    root, data = _document(text, file)
    if root is None or not isinstance(data, dict):
        raise SweepError([Problem(file, 1, "", "the file must hold a mapping with at least "
                                               "'scenario' and 'metrics'")])
    return root, data


def _document(text: str, file: str) -> tuple[yaml.Node | None, Any]:
    """Nodes (for line numbers) and plain data of YAML text, within the scenario bounds."""
    loader = ScenarioLoader(text)
    try:
        root = loader.get_single_node()
        return root, None if root is None else loader.construct_document(root)
    except Refused as exc:
        raise SweepError([Problem(file, exc.line, "", exc.message)]) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        raise SweepError([Problem(file, mark.line + 1 if mark else 0, "",
                                  f"invalid YAML: {getattr(exc, 'problem', exc)}")]) from None
    finally:
        loader.dispose()


def _problem(error: Any, root: yaml.Node, file: str) -> Problem:
    loc = tuple(error["loc"])
    if len(loc) > 2 and loc[0] == "metrics" and loc[2] in METRIC_KINDS:
        loc = loc[:2] + loc[3:]  # the union's tag
    kind, message = error["type"], str(error["msg"])
    if kind == "extra_forbidden":
        message = f"unknown field {loc[-1]!r}"
    elif kind == "missing":
        message = "required field is missing"
    else:
        message = message.removeprefix("Value error, ")
        message = message.replace("Input should be ", "must be ")
        if kind not in ("value_error", "metric_kind") and \
                not isinstance(error.get("input"), dict | list):
            message = f"{message}, got {error.get('input')!r}"
    return Problem(file, _line(root, loc), _dotted(loc), message)


def _dotted(loc: tuple) -> str:
    text = ""
    for part in loc:
        text += f"[{part}]" if isinstance(part, int) else f".{part}" if text else str(part)
    return text


def _line(root: yaml.Node, loc: tuple) -> int:
    """1-based line of the deepest node along ``loc`` (as the scenario loader finds it)."""
    return node_at(root, loc)[1]
