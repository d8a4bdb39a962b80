"""YAML scenario files to ``Scenario`` models, with errors that name the file, line and field.

The YAML is composed into nodes first (their start marks carry the line numbers) and then
constructed; each pydantic error's ``loc`` is walked down the node tree to the line of the
offending key. Every problem of a file is collected, so ``openmotion check`` lists them all.
"""

from __future__ import annotations

import difflib
import re
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml
from pydantic import BaseModel, ValidationError

from openmotion.core.errors import ConfigError
from openmotion.scenario.schema import CHECKS, TIMELINE_COMMANDS, Scenario


class ScenarioLoader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 scalars: ``1e-9`` is a float, ``on``/``no`` stay strings."""


_BOOL = "tag:yaml.org,2002:bool"
ScenarioLoader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != _BOOL]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
ScenarioLoader.add_implicit_resolver(
    _BOOL, re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"), list("tTfF"))
ScenarioLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


@dataclass(frozen=True)
class Problem:
    """One thing wrong with a scenario file."""

    file: str
    line: int  #: 1-based; 0 when the file could not be read at all
    path: str  #: dotted field path, e.g. ``timeline[2].velocity``; empty for YAML syntax
    message: str

    def __str__(self) -> str:
        line = f":{self.line}" if self.line else ""
        where = f" {self.path}:" if self.path else ""
        return f"{self.file}{line}:{where} {self.message}"


class ScenarioError(ConfigError):
    """A scenario file is invalid; ``problems`` lists everything wrong, the message the first."""

    def __init__(self, problems: list[Problem]) -> None:
        self.problems = problems
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        super().__init__(f"{problems[0]}{more}")


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file; raises ``ScenarioError`` listing every problem."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise ScenarioError([Problem(str(path), 0, "", f"cannot read: {exc.strerror}")]) \
            from None
    return parse_scenario(text, str(path))


def parse_scenario(text: str, file: str = "<string>") -> Scenario:
    """Validate scenario YAML ``text``; ``file`` names it in error messages."""
    loader = ScenarioLoader(text)
    try:
        root = loader.get_single_node()
        data = loader.construct_document(root) if root is not None else None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark else 0
        raise ScenarioError([Problem(file, line, "", f"invalid YAML: {exc.problem}")]) from None
    finally:
        loader.dispose()
    if root is None or not isinstance(data, dict):
        raise ScenarioError([Problem(file, 1, "", "the file must hold a mapping with at least "
                                                  "'name' and 'axes' (or 'planar')")])
    problems = _duplicate_keys(root, (), file)
    try:
        scenario = Scenario.model_validate(data)
    except ValidationError as exc:
        problems += [_problem(error, root, file) for error in exc.errors()]
    if problems:
        raise ScenarioError(sorted(problems, key=lambda p: p.line))
    return scenario


# -- pydantic errors to problems -----------------------------------------------------------

_UNION_LISTS = ("timeline", "checks")  #: list fields whose items are tagged unions
#: error types whose message needs no "got <input>"
_SAYS_ENOUGH = {"missing", "extra_forbidden", "value_error", "assertion_error",
                "union_tag_invalid", "union_tag_not_found", "check_kind"}


def _problem(error: Any, root: yaml.Node, file: str) -> Problem:
    raw_loc = tuple(error["loc"])
    loc = _without_tags(raw_loc)
    kind, message = error["type"], str(error["msg"])
    if kind == "extra_forbidden":
        fields = _fields_at(raw_loc)
        message = f"unknown field {loc[-1]!r}" + (
            _suggestion(str(loc[-1]), fields) or f" (fields: {', '.join(fields)})")
    elif kind == "missing":
        message = "required field is missing"
    elif kind == "union_tag_invalid":
        tag = error["ctx"]["tag"]
        loc += ("command",)
        message = f"unknown command {tag!r}" + (
            _suggestion(str(tag), list(TIMELINE_COMMANDS))
            or f" (commands: {', '.join(TIMELINE_COMMANDS)})")
    elif kind == "union_tag_not_found":
        loc += ("command",)
        message = "required field is missing"
    else:
        message = re.sub(r"^(Value error|Assertion failed), ", "", message)
        message = re.sub(r"^Input should be ", "must be ", message)
        message = re.sub(r"^List should have at least (\d+) items?.*",
                         r"must hold at least \1 item(s)", message)
        field = re.match(r"^([a-z_]+): (.*)$", message, re.S)
        node = _node_at(root, loc)[0]
        if field and isinstance(node, yaml.MappingNode) and field.group(1) in _keys(node):
            loc, message = (*loc, field.group(1)), field.group(2)  # "max_velocity: must be > 0"
        elif kind not in _SAYS_ENOUGH and not isinstance(error.get("input"), dict | list):
            message = f"{message}, got {error.get('input')!r}"
    return Problem(file, _node_at(root, loc)[1], _dotted(loc), message)


def _without_tags(loc: tuple) -> tuple:
    """Drop the union tag pydantic puts after the index: ``timeline.3.halt.x`` -> ``.3.x``."""
    if len(loc) > 2 and loc[0] in _UNION_LISTS and isinstance(loc[1], int) \
            and isinstance(loc[2], str):
        return loc[:2] + loc[3:]
    return loc


def _dotted(loc: tuple) -> str:
    text = ""
    for part in loc:
        text += f"[{part}]" if isinstance(part, int) else f".{part}" if text else str(part)
    return text


def _keys(node: yaml.MappingNode) -> list[str]:
    return [key.value for key, _ in node.value if isinstance(key, yaml.ScalarNode)]


def _node_at(root: yaml.Node, loc: tuple) -> tuple[yaml.Node, int]:
    """The deepest node along ``loc`` and the 1-based line of its key (or of itself)."""
    node, line = root, root.start_mark.line
    for part in loc:
        if isinstance(node, yaml.MappingNode):
            found = [(key, value) for key, value in node.value
                     if isinstance(key, yaml.ScalarNode) and key.value == str(part)]
            if not found:
                break
            key, node = found[-1]  # the YAML constructor keeps the last duplicate too
            line = key.start_mark.line
        elif isinstance(node, yaml.SequenceNode) and isinstance(part, int) \
                and 0 <= part < len(node.value):
            node = node.value[part]
            line = node.start_mark.line
        else:
            break
    return node, line + 1


def _duplicate_keys(node: yaml.Node, loc: tuple, file: str) -> list[Problem]:
    problems: list[Problem] = []
    if isinstance(node, yaml.MappingNode):
        seen: set[str] = set()
        for key, value in node.value:
            name = key.value if isinstance(key, yaml.ScalarNode) else None
            if name in seen:
                problems.append(Problem(file, key.start_mark.line + 1, _dotted((*loc, name)),
                                        "duplicate key (the last one would win)"))
            seen.add(name)
            problems += _duplicate_keys(value, (*loc, name), file)
    elif isinstance(node, yaml.SequenceNode):
        for index, item in enumerate(node.value):
            problems += _duplicate_keys(item, (*loc, index), file)
    return problems


def _suggestion(word: str, choices: list[str]) -> str:
    close = difflib.get_close_matches(word, choices, n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _fields_at(raw_loc: tuple) -> list[str]:
    """Field names of the model holding the last key of ``raw_loc`` (for suggestions)."""
    model: Any = Scenario
    for part in raw_loc[:-1]:
        if isinstance(part, int):
            continue
        if isinstance(model, type) and issubclass(model, BaseModel) \
                and part in model.model_fields:
            model = _model_in(model.model_fields[part].annotation)
        else:
            model = {**TIMELINE_COMMANDS, **CHECKS}.get(str(part))
        if model is None:
            return []
    return list(model.model_fields) if isinstance(model, type) else []


def _model_in(annotation: Any) -> Any:
    """The one model inside ``list[...]``/``Optional``/``Annotated``; a union gives ``union``."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    models = {m for m in map(_model_in, typing.get_args(annotation)) if m is not None}
    return models.pop() if len(models) == 1 else ("union" if models else None)
