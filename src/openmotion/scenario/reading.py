"""Scenario text to YAML nodes, refusing hostile input before any expensive work.

A file is read only up to a size bound and must be UTF-8 text made of the characters YAML
allows; its nodes are composed by a composer that bounds the nesting depth and the number of
nodes that aliases repeat, so that neither a deeply nested file nor an alias bomb reaches
the constructor, the duplicate-key walk or pydantic (D-160, D-161, D-162; the "Limits"
section of docs/scenarios.md). libyaml scans and parses when PyYAML has it (ten times
faster than the pure-Python parser); the composer is always the bounded one below.
"""

from __future__ import annotations

import gc
import os
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import yaml
from yaml.composer import Composer
from yaml.constructor import SafeConstructor
from yaml.events import AliasEvent, MappingStartEvent, ScalarEvent, SequenceStartEvent
from yaml.nodes import ScalarNode
from yaml.parser import Parser
from yaml.reader import Reader
from yaml.resolver import Resolver
from yaml.scanner import Scanner

try:
    from yaml.cyaml import CParser
except ImportError:  # PyYAML built without libyaml
    CParser = None

DEFAULT_MAX_BYTES = 2 * 1024 * 1024  #: size bound of a scenario file [bytes] (D-160)
MAX_BYTES_VARIABLE = "OPENMOTION_MAX_SCENARIO_BYTES"  #: environment variable that sets it
MAX_DEPTH = 100  #: nested mappings and sequences; the composer recurses per level (D-161)
MAX_ALIAS_NODES = 100_000  #: nodes that all aliases of one file may repeat together (D-162)

_TOO_DEEP = f"nested deeper than {MAX_DEPTH} levels of mappings and sequences"
#: what YAML 1.1 allows in a stream (the pure-Python reader's own check, run once up front)
_NON_PRINTABLE = re.compile("[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd"
                            "\U00010000-\U0010ffff]")


def yaml_problem(exc: yaml.MarkedYAMLError) -> tuple[int, str]:
    """Line and message of a YAML error; libyaml's own depth bound (1000) speaks as ours."""
    mark = exc.problem_mark or exc.context_mark
    line = mark.line + 1 if mark else 0
    if exc.problem == "exceeded maximum nesting depth":  # libyaml scans ahead on a line
        return line, _TOO_DEEP
    return line, f"invalid YAML: {exc.problem}"


class Refused(Exception):
    """The input is refused by a bound; ``line`` is 1-based, 0 when it has none."""

    def __init__(self, line: int, message: str) -> None:
        super().__init__(message)
        self.line = line
        self.message = message


def max_bytes(given: int | None = None) -> int:
    """The size bound: ``given``, else the environment variable, else the default."""
    if given is not None:
        if isinstance(given, bool) or not isinstance(given, int) or given <= 0:
            raise ValueError(f"max_bytes must be a whole number of bytes > 0, got {given!r}")
        return given
    raw = os.environ.get(MAX_BYTES_VARIABLE, "").strip()
    if not raw:
        return DEFAULT_MAX_BYTES
    try:
        value = int(raw)
    except ValueError:
        value = 0
    if value <= 0:
        raise Refused(0, f"{MAX_BYTES_VARIABLE} must be a whole number of bytes > 0, "
                         f"got {raw!r}")
    return value


def read_text(path: str | Path, limit: int) -> str:
    """The file's text; ``Refused`` before reading a file over ``limit`` bytes, and for
    bytes that are not UTF-8 text. ``OSError`` when it cannot be read."""
    with open(path, "rb") as stream:  # a pipe or /dev/stdin works too
        size = os.fstat(stream.fileno()).st_size
        if size > limit:
            raise Refused(0, _too_large(size, limit))
        data = stream.read(limit + 1)  # st_size is 0 for pipes and devices
    if len(data) > limit:
        raise Refused(0, _too_large(None, limit))
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        check_text(data[:exc.start].decode("utf-8"), limit)  # an earlier NUL speaks first
        raise Refused(data.count(b"\n", 0, exc.start) + 1,
                      f"not a UTF-8 text file (invalid UTF-8 at byte offset {exc.start}: "
                      f"0x{data[exc.start]:02x})") from None
    check_text(text, limit)
    return text


def check_text(text: str, limit: int) -> None:
    """``Refused`` for text over ``limit`` UTF-8 bytes or with a character YAML forbids."""
    if len(text) > limit or (4 * len(text) > limit and _utf8_size(text) > limit):
        raise Refused(0, _too_large(None, limit))
    bad = _NON_PRINTABLE.search(text)
    if bad is not None:
        offset = _utf8_size(text[:bad.start()])
        raise Refused(text.count("\n", 0, bad.start()) + 1,
                      f"not a UTF-8 text file (non-printable character "
                      f"U+{ord(bad.group()):04X} at byte offset {offset})")


def _utf8_size(text: str) -> int:
    return len(text.encode("utf-8", "surrogatepass"))


def _too_large(size: int | None, limit: int) -> str:
    held = f"{size} bytes, more" if size is not None else "more"
    return (f"too large: {held} than the limit of {limit} bytes (set {MAX_BYTES_VARIABLE} "
            f"to change it)")


@contextmanager
def gc_paused() -> Iterator[None]:
    """No cyclic garbage collection while a file becomes nodes, data and a model: each full
    collection walks every live node, which made a 1 MB file compose four times slower."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


class ScenarioResolver(Resolver):
    """YAML 1.2 scalars: ``1e-9`` is a float, ``on``/``no`` stay strings. The tag of a plain
    scalar depends on its text alone (no path resolvers), so each text is resolved once."""

    def __init__(self) -> None:
        super().__init__()
        self._scalar_tags: dict[str, str] = {}

    def resolve(self, kind: type, value: Any, implicit: Any) -> str:
        if kind is not yaml.ScalarNode or not implicit[0] or self.yaml_path_resolvers:
            return super().resolve(kind, value, implicit)
        tag = self._scalar_tags.get(value)
        if tag is None:
            tag = self._scalar_tags[value] = super().resolve(kind, value, implicit)
        return tag


_BOOL = "tag:yaml.org,2002:bool"
ScenarioResolver.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != _BOOL]
    for first, resolvers in Resolver.yaml_implicit_resolvers.items()
}
ScenarioResolver.add_implicit_resolver(
    _BOOL, re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$"), list("tTfF"))
ScenarioResolver.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


class BoundedComposer(Composer):
    """PyYAML's composer with two bounds checked as the nodes are made: the nesting depth
    (the composer recurses once per level) and the nodes repeated through aliases in all
    (each alias counts the whole subtree of its anchor, aliases inside it included)."""

    def __init__(self) -> None:
        super().__init__()
        self._counts: list[int] = []  #: nodes under each open collection, aliases expanded
        self._sizes: dict[str, int] = {}  #: anchor -> nodes of its finished subtree
        self._repeated = 0  #: nodes repeated through aliases so far

    def compose_node(self, parent: Any, index: Any) -> Any:
        event = self.peek_event()
        if type(event) is ScalarEvent and event.anchor is None and not self.yaml_path_resolvers:
            return self._scalar(event)
        if isinstance(event, AliasEvent):
            return self._alias(event, parent, index)
        if isinstance(event, MappingStartEvent | SequenceStartEvent) \
                and len(self._counts) >= MAX_DEPTH:
            raise Refused(event.start_mark.line + 1, _TOO_DEEP)
        self._counts.append(1)
        node = super().compose_node(parent, index)
        size = self._counts.pop()
        if self._counts:
            self._counts[-1] += size
        if event.anchor is not None:
            self._sizes[event.anchor] = size
        return node

    def _scalar(self, event: ScalarEvent) -> ScalarNode:
        """A scalar without an anchor, as the composer makes it without its generic steps
        (most nodes are such scalars; a third less time to compose a file)."""
        self.get_event()
        tag = event.tag
        if tag is None or tag == "!":
            tag = self.resolve(ScalarNode, event.value, event.implicit)
        if self._counts:
            self._counts[-1] += 1
        return ScalarNode(tag, event.value, event.start_mark, event.end_mark, style=event.style)

    def _alias(self, event: AliasEvent, parent: Any, index: Any) -> Any:
        if event.anchor in self.anchors and event.anchor not in self._sizes:
            raise Refused(event.start_mark.line + 1,
                          f"alias *{event.anchor} is inside the node it refers to")
        size = self._sizes.get(event.anchor, 0)  # 0: undefined, the composer says so
        self._repeated += size
        if self._repeated > MAX_ALIAS_NODES:
            raise Refused(event.start_mark.line + 1,
                          f"aliases repeat more than {MAX_ALIAS_NODES} nodes (aliases of "
                          f"aliases multiply)")
        if self._counts:
            self._counts[-1] += size
        return super().compose_node(parent, index)


class PythonScenarioLoader(Reader, Scanner, Parser, BoundedComposer, SafeConstructor,
                           ScenarioResolver):
    """The pure-Python loader, for a PyYAML built without libyaml."""

    def __init__(self, stream: str) -> None:
        Reader.__init__(self, stream)
        Scanner.__init__(self)
        Parser.__init__(self)
        BoundedComposer.__init__(self)
        SafeConstructor.__init__(self)
        ScenarioResolver.__init__(self)

    def fetch_flow_collection_start(self, TokenClass: type) -> None:  # noqa: N803
        """Refuse deep flow nesting as the scanner meets it: looking ahead for simple keys
        over a line of thousands of ``[`` costs it seconds before the composer sees one."""
        if self.flow_level >= MAX_DEPTH:
            raise Refused(self.get_mark().line + 1, _TOO_DEEP)
        super().fetch_flow_collection_start(TokenClass)


ScenarioLoader: type = PythonScenarioLoader
if CParser is not None:
    class LibyamlScenarioLoader(BoundedComposer, CParser, SafeConstructor, ScenarioResolver):
        """libyaml scans and parses; the bounded composer above composes."""

        def __init__(self, stream: str) -> None:
            CParser.__init__(self, stream)
            BoundedComposer.__init__(self)
            SafeConstructor.__init__(self)
            ScenarioResolver.__init__(self)

    ScenarioLoader = LibyamlScenarioLoader
