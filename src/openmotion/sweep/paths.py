"""Addresses into a scenario document: ``axes[0].position``, ``timeline[go1].velocity``,
``timeline[*].velocity``.

A path is a dotted chain of mapping keys; ``[n]`` picks a list item by index, ``[name]`` the
item whose ``name`` or ``id`` is ``name`` (so a path survives reordering the file), ``[*]``
every item. The last key of a path may be missing from its mapping: setting it adds it (a
field left at its default in the base scenario).
"""

from __future__ import annotations

import re
from typing import Any

from openmotion.core.errors import ConfigError

WILDCARD = "*"  #: ``[*]``: every item of a list
_KEY = r"[A-Za-z_][A-Za-z0-9_]*"
_PART = re.compile(rf"({_KEY})|\[([^\[\].]+)\]")
_WHOLE = re.compile(rf"{_KEY}(\[[^\[\].]+\])*(\.{_KEY}(\[[^\[\].]+\])*)*")
_ITEM_KEYS = ("name", "id")  #: the keys ``[name]`` matches, in this order


def parse_path(text: str) -> tuple[str | int, ...]:
    """The steps of a path: keys (str), indexes (int), names (``"=name"``) and ``"*"``."""
    if not _WHOLE.fullmatch(text):
        raise ConfigError(f"{text!r} is not a path like axes[0].position, "
                          "timeline[go1].velocity or timeline[*].velocity")
    steps: list[str | int] = []
    for key, item in _PART.findall(text):
        item = item.strip()
        if key:
            steps.append(key)
        elif re.fullmatch(r"-?\d+", item):
            steps.append(int(item))
        else:
            steps.append(WILDCARD if item == WILDCARD else "=" + item)
    return tuple(steps)


def targets(document: Any, path: str) -> list[tuple[Any, str | int]]:
    """Every (container, key) the path ends at; ``ConfigError`` naming the first step that
    does not resolve."""
    steps = parse_path(path)
    found: list[tuple[Any, str | int]] = [(None, "")]
    nodes = [document]
    for number, step in enumerate(steps):
        last = number == len(steps) - 1
        where = _shown(steps[:number]) or "the document"
        found = []
        for node in nodes:
            found += _step(node, step, where, last)
        nodes = [container[key] for container, key in found
                 if not (isinstance(container, dict) and key not in container)]
    return found


def get(document: Any, path: str) -> list[Any]:
    """The values a path addresses (missing last keys left out)."""
    return [container[key] for container, key in targets(document, path)
            if not (isinstance(container, dict) and key not in container)]


def assign(document: Any, path: str, value: Any) -> None:
    """Set every place the path addresses to ``value`` (in place)."""
    for container, key in targets(document, path):
        container[key] = value


def _step(node: Any, step: str | int, where: str, last: bool) -> list[tuple[Any, str | int]]:
    if isinstance(step, str) and not step.startswith("=") and step != WILDCARD:
        if not isinstance(node, dict):
            raise ConfigError(f"{where} is not a mapping, so it has no key {step!r}")
        if step not in node and not last:
            raise ConfigError(f"{where} has no key {step!r}"
                              + (f" (keys: {', '.join(map(str, node))})" if node else ""))
        return [(node, step)]
    if not isinstance(node, list):
        raise ConfigError(f"{where} is not a list, so it has no item [{_item(step)}]")
    if step == WILDCARD:
        return [(node, index) for index in range(len(node))]
    if isinstance(step, int):
        if not -len(node) <= step < len(node):
            raise ConfigError(f"{where}[{step}]: index out of range ({where} has "
                              f"{len(node)} items)")
        return [(node, step % len(node))]
    name = step[1:]
    for index, item in enumerate(node):
        if isinstance(item, dict) and any(str(item.get(key)) == name for key in _ITEM_KEYS):
            return [(node, index)]
    raise ConfigError(f"{where} has no item with name or id {name!r}")


def _item(step: str | int) -> str:
    return str(step)[1:] if isinstance(step, str) and step.startswith("=") else str(step)


def _shown(steps: tuple[str | int, ...]) -> str:
    text = ""
    for step in steps:
        if isinstance(step, str) and not step.startswith("=") and step != WILDCARD:
            text += f".{step}" if text else step
        else:
            text += f"[{_item(step)}]"
    return text
