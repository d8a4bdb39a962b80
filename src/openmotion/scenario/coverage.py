"""Which blocks and methods scenario files reach, and through which part of a file (D-217).

Every timeline entry and every part of a file (the pydantic models of schema.py and its part
modules) reaches blocks (``MC_MoveAbsolute``) or methods (``MC_PlanarTrack.append_line``):

- an entry on a planar object reaches the method ``method`` of that object's block
  (``mover_enable``: ``MC_PlanarMover.enable``);
- an entry that calls a block itself reaches its ``block_type`` or its ``block``;
- otherwise an entry reaches the ``MC_`` and ``F_`` names of the first paragraph of its
  docstring (``MC_MoveAbsolute (TcMC §3.1).``);
- and any model adds the names of its own ``blocks`` (a part of the file that the run sets
  up before t = 0, such as ``planar.tracks``, says there what it calls).

``reached()`` is the registry the coverage pages' scenario column shows;
tests/docs/test_scenario_coverage.py checks the pages against it, and that every exported
block and manual method has a form in it.
"""

from __future__ import annotations

import re
import types
from collections.abc import Iterator
from typing import Annotated, Any, Union, get_args, get_origin

from pydantic import BaseModel

from openmotion.scenario.planar import PlanarEntry, PlanarGroupEntry
from openmotion.scenario.planar_objects import EnvironmentEntry, TrackEntry
from openmotion.scenario.planar_parts import PartEntry
from openmotion.scenario.schema import TIMELINE_COMMANDS, Scenario

#: the block whose method a planar entry calls, by the entry's base
PLANAR_TARGETS: tuple[tuple[type, str], ...] = (
    (PlanarEntry, "MC_PlanarMover"), (PlanarGroupEntry, "MC_PlanarGroup"),
    (PartEntry, "MC_PlanarPart"), (TrackEntry, "MC_PlanarTrack"),
    (EnvironmentEntry, "MC_PlanarEnvironment"))
_NAME = re.compile(r"\b(?:MC|F)_[A-Za-z0-9_]*[A-Za-z0-9]")


def own_blocks(model: type) -> tuple[str, ...]:
    """What ``model`` itself reaches (its nested models not included)."""
    names: list[str] = list(vars(model).get("blocks", ()))
    if model in TIMELINE_COMMANDS.values():
        names += _entry_blocks(model)
    return tuple(dict.fromkeys(names))


def _entry_blocks(model: type) -> list[str]:
    method = getattr(model, "method", "")
    for base, block in PLANAR_TARGETS:
        if issubclass(model, base) and method:
            return [f"{block}.{method}"]
    block_type = vars(model).get("block_type")
    if block_type is not None:
        return [block_type.__name__]
    block = vars(model).get("block")
    if isinstance(block, str) and block.startswith(("MC_", "F_")):
        return [block]
    first = (model.__doc__ or "").strip().split("\n\n")[0]
    return list(dict.fromkeys(_NAME.findall(first)))


def _models(annotation: Any) -> Iterator[tuple[type[BaseModel], bool]]:
    """The models in a field's annotation, each with whether it sits in a list."""
    origin = get_origin(annotation)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        yield annotation, False
    elif origin is Annotated:
        yield from _models(get_args(annotation)[0])
    elif origin in (Union, types.UnionType):
        for arg in get_args(annotation):
            yield from _models(arg)
    elif origin in (list, tuple):
        for arg in get_args(annotation):
            for model, _ in _models(arg):
                yield model, True


def _walk(model: type[BaseModel], path: str, seen: set[type]) -> Iterator[tuple[str, type]]:
    """(path, model) of ``model`` and every model nested in its fields."""
    yield path, model
    for name, field in model.model_fields.items():
        for nested, listed in _models(field.annotation):
            if nested not in seen:
                yield from _walk(nested, f"{path}.{name}{'[]' if listed else ''}".lstrip("."),
                                 seen | {nested})


def reached() -> dict[str, list[str]]:
    """Block or method -> the forms that reach it: an entry's ``command`` (``move_path``), or
    the path of a part of the file (``planar.tracks[].geometry[]``)."""
    found: dict[str, set[str]] = {}

    def add(names: tuple[str, ...], form: str) -> None:
        for name in names:
            found.setdefault(name, set()).add(form)

    for command, entry in TIMELINE_COMMANDS.items():
        for _, model in _walk(entry, "", {entry}):
            add(own_blocks(model), command)
    Scenario.model_rebuild()
    for name, field in Scenario.model_fields.items():
        if name == "timeline":
            continue
        for model, listed in _models(field.annotation):
            for path, nested in _walk(model, f"{name}{'[]' if listed else ''}", {model}):
                add(own_blocks(nested), path)
    return {name: sorted(forms) for name, forms in sorted(found.items())}
