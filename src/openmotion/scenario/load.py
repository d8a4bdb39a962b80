"""YAML scenario files to ``Scenario`` models, with errors that name the file, line and field.

The YAML is composed into nodes first (their start marks carry the line numbers) and then
constructed; each pydantic error's ``loc`` is walked down the node tree to the line of the
offending key. Every problem of a file is collected, so ``openmotion check`` lists them all.
"""

from __future__ import annotations

import difflib
import functools
import re
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml
from pydantic import BaseModel, ValidationError

from openmotion.core.errors import ConfigError
from openmotion.scenario import reading
from openmotion.scenario.reading import Refused
from openmotion.scenario.schema import CHECKS, TIMELINE_COMMANDS, Scenario


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


def load_scenario(path: str | Path, max_bytes: int | None = None) -> Scenario:
    """Read and validate a scenario file; raises ``ScenarioError`` listing every problem.

    A file over ``max_bytes`` (default: the ``OPENMOTION_MAX_SCENARIO_BYTES`` environment
    variable, else 2 MiB) is refused before it is read; see docs/scenarios.md, "Limits".
    """
    try:
        limit = reading.max_bytes(max_bytes)
        text = reading.read_text(path, limit)
    except OSError as exc:
        raise ScenarioError([Problem(str(path), 0, "", f"cannot read: {exc.strerror}")]) \
            from None
    except Refused as exc:
        raise ScenarioError([Problem(str(path), exc.line, "", exc.message)]) from None
    return _parse(text, str(path))


def parse_scenario(text: str, file: str = "<string>", max_bytes: int | None = None) -> Scenario:
    """Validate scenario YAML ``text``; ``file`` names it in error messages. The bounds of
    ``load_scenario`` apply (``max_bytes`` counts the UTF-8 bytes of ``text``)."""
    try:
        reading.check_text(text, reading.max_bytes(max_bytes))
    except Refused as exc:
        raise ScenarioError([Problem(file, exc.line, "", exc.message)]) from None
    return _parse(text, file)


def _parse(text: str, file: str) -> Scenario:
    with reading.gc_paused():  # until the nodes and data are freed: no collection walks them
        scenario, problems = _validate(text, file)
    if problems:
        raise ScenarioError(sorted(problems, key=lambda p: p.line))
    return scenario


def _validate(text: str, file: str) -> tuple[Scenario | None, list[Problem]]:
    root, data, problems = _nodes_and_data(text, file)
    if root is None or not isinstance(data, dict):
        raise ScenarioError([Problem(file, 1, "", "the file must hold a mapping with at least "
                                                  "'name' and 'axes' (or 'planar')")])
    try:
        return Scenario.model_validate(data), problems
    except ValidationError as exc:
        return None, problems + [_problem(error, root, file) for error in exc.errors()]


def _nodes_and_data(text: str, file: str) -> tuple[yaml.Node | None, Any, list[Problem]]:
    """The node tree (within the depth and alias bounds), its duplicate keys and its data."""
    loader = reading.ScenarioLoader(text)
    try:
        root = loader.get_single_node()
        if root is None:
            return None, None, []
        problems = _duplicate_keys(root, file)  # before the constructor flattens merge keys
        return root, loader.construct_document(root), problems
    except Refused as exc:
        raise ScenarioError([Problem(file, exc.line, "", exc.message)]) from None
    except yaml.MarkedYAMLError as exc:
        line, message = reading.yaml_problem(exc)
        raise ScenarioError([Problem(file, line, "", message)]) from None
    except yaml.YAMLError as exc:  # a reader error; check_text refuses what causes them
        raise ScenarioError([Problem(file, 0, "", f"invalid YAML: {exc}")]) from None
    finally:
        loader.dispose()


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
        node = node_at(root, loc)[0]
        if field and isinstance(node, yaml.MappingNode) and field.group(1) in _keys(node):
            loc, message = (*loc, field.group(1)), field.group(2)  # "max_velocity: must be > 0"
        elif kind not in _SAYS_ENOUGH and not isinstance(error.get("input"), dict | list):
            message = f"{message}, got {error.get('input')!r}"
    return Problem(file, node_at(root, loc)[1], _dotted(loc), message)


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


def node_at(root: yaml.Node, loc: tuple) -> tuple[yaml.Node, int]:
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


def _duplicate_keys(root: yaml.Node, file: str) -> list[Problem]:
    """Keys given twice in one mapping, from the nodes as composed (before merge keys are
    flattened, so ``<<: *defaults`` then a key overrides without a complaint). Each node is
    visited once, however many aliases refer to it."""
    problems: list[Problem] = []
    visited: set[int] = set()
    stack: list[tuple[yaml.Node, tuple]] = [(root, ())]
    while stack:
        node, loc = stack.pop()
        if id(node) in visited:
            continue
        visited.add(id(node))
        if isinstance(node, yaml.MappingNode):
            names: set[str | None] = set()
            children = []
            for key, value in node.value:
                name = key.value if isinstance(key, yaml.ScalarNode) else None
                if name in names:
                    problems.append(Problem(file, key.start_mark.line + 1,
                                            _dotted((*loc, name)),
                                            "duplicate key (the last one would win)"))
                names.add(name)
                children.append((value, (*loc, name)))
        elif isinstance(node, yaml.SequenceNode):
            children = [(item, (*loc, index)) for index, item in enumerate(node.value)]
        else:
            continue
        stack.extend(child for child in reversed(children)
                     if not isinstance(child[0], yaml.ScalarNode))
    return problems


def _suggestion(word: str, choices: list[str]) -> str:
    close = _closest(word, tuple(choices))
    return f" (did you mean {close!r}?)" if close else ""


@functools.lru_cache(maxsize=1024)  # a generated file repeats one misspelling many times
def _closest(word: str, choices: tuple[str, ...]) -> str | None:
    close = difflib.get_close_matches(word, choices, n=1)
    return close[0] if close else None


def _fields_at(raw_loc: tuple) -> list[str]:
    """Field names of the model holding the last key of ``raw_loc`` (for suggestions)."""
    return list(_fields_of(tuple(part for part in raw_loc[:-1] if not isinstance(part, int))))


@functools.lru_cache(maxsize=1024)  # walking the union annotations costs ~1 ms an error
def _fields_of(names: tuple[str, ...]) -> tuple[str, ...]:
    model: Any = Scenario
    for part in names:
        if isinstance(model, type) and issubclass(model, BaseModel) \
                and part in model.model_fields:
            model = _model_in(model.model_fields[part].annotation)
        else:
            model = {**TIMELINE_COMMANDS, **CHECKS}.get(str(part))
        if model is None:
            return ()
    return tuple(model.model_fields) if isinstance(model, type) else ()


def _model_in(annotation: Any) -> Any:
    """The one model inside ``list[...]``/``Optional``/``Annotated``; a union gives ``union``."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    models = {m for m in map(_model_in, typing.get_args(annotation)) if m is not None}
    return models.pop() if len(models) == 1 else ("union" if models else None)
