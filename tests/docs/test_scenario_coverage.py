"""Scenario files reach every exported block and manual method, and the coverage pages'
scenario column says by what (issue 20, "Scenario files reach every block"; D-217).

The truth is the scenario layer's own registry, ``openmotion.scenario.coverage.reached()``,
derived from its timeline entries and file parts (their ``method``, ``block_type``,
``block``, docstring and ``blocks``), never from a list kept here. A block exported by
``openmotion.plcopen``, ``openmotion.coordinated.blocks`` or ``openmotion.transport``, or a
public method of a block ``openmotion.planar`` exports, fails these tests until an entry
reaches it and its page has a row whose scenario column names that entry.
"""

from __future__ import annotations

import inspect
import re
from collections.abc import Callable
from pathlib import Path

import pytest

import openmotion.coordinated.blocks as part4
import openmotion.planar as planar
import openmotion.plcopen as tcmc
import openmotion.transport as tf5410
from openmotion.scenario.coverage import reached
from openmotion.scenario.schema import TIMELINE_COMMANDS

ROOT = Path(__file__).resolve().parents[2]
#: public methods of the planar blocks that are the engine's helpers, not TF5430 methods a
#: PLC program calls (the page says so); anything else public needs a row and an entry
PLANAR_HELPERS = frozenset({
    "MC_PlanarEnvironment.carries", "MC_PlanarGroup.reserved", "MC_PlanarMover.footprint",
    "MC_PlanarTrack.arc_length_closest_to_pose", "MC_PlanarTrack.frame_at",
    "MC_PlanarTrack.part", "MC_PlanarTrack.placement", "MC_PlanarTrack.surface"})


def _blocks(module: object, prefixes: tuple[str, ...] = ("MC_",)) -> list[str]:
    return [name for name in module.__all__ if name.startswith(prefixes)]  # type: ignore[attr-defined]


def _planar_methods() -> list[str]:
    """``<block>.<method>`` of every public method of the MC_ classes openmotion.planar
    exports (inherited ones included: a feedback's Update), helpers left out."""
    return [f"{name}.{method}" for name in _blocks(planar)
            for method, _ in inspect.getmembers(getattr(planar, name), inspect.isfunction)
            if not method.startswith("_") and f"{name}.{method}" not in PLANAR_HELPERS]


#: page, its table's section, the names it must cover
FAMILIES: dict[str, tuple[str, str, Callable[[], list[str]]]] = {
    "tcmc": ("tcmc-coverage.md", "Blocks", lambda: _blocks(tcmc, ("MC_", "F_"))),
    "part4": ("part4-coverage.md", "Blocks", lambda: _blocks(part4)),
    "tf5410": ("tf5410-coverage.md", "Blocks", lambda: _blocks(tf5410)),
    "tf5430": ("tf5430-coverage.md", "Methods", _planar_methods),
}


def _table(page: str, section: str) -> dict[str, dict[str, str]]:
    """The rows of the section's table by their first cell, each as {column: cell}."""
    text = (ROOT / "docs" / page).read_text(encoding="utf-8")
    match = re.search(rf"^## {section}\n(.*?)(?=^## |\Z)", text, flags=re.S | re.M)
    assert match, f"no section '## {section}' in {page}"
    lines = [line for line in match.group(1).splitlines() if line.startswith("|")]
    split = [[cell.strip() for cell in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
             for line in lines]
    header, rows = split[0], split[2:]
    names = [row[0] for row in rows]
    assert len(names) == len(set(names)), f"{page}: a row twice"
    return {row[0]: dict(zip(header, row, strict=True)) for row in rows}


def _forms(cell: str) -> set[str]:
    return set(re.findall(r"`([^`]+)`", cell))


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_every_exported_block_or_method_is_reached_by_a_scenario_entry(family: str) -> None:
    """Issue 20: scenario files reach every block (method) the package exports."""
    _, _, names = FAMILIES[family]
    registry = reached()
    missing = [name for name in names() if name not in registry]
    assert not missing, f"exported, but no scenario entry reaches it: {missing}"


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_the_pages_scenario_column_is_the_registry(family: str) -> None:
    """Each exported name has one row, whose scenario column names exactly the entries and
    file parts that reach it."""
    page, section, names = FAMILIES[family]
    rows, registry = _table(page, section), reached()
    exported = names()
    no_row = [name for name in exported if name not in rows]
    assert not no_row, f"{page}: exported without a row: {no_row}"
    wrong = {name: (sorted(_forms(rows[name]["scenario"])), registry.get(name, []))
             for name in exported if _forms(rows[name]["scenario"]) != set(registry.get(name, []))}
    assert not wrong, f"{page}: scenario column (page, registry) differs: {wrong}"


@pytest.mark.parametrize("family", ["tf5410", "tf5430"])
def test_the_python_column_names_what_exists(family: str) -> None:
    """The new pages' Python column starts with the exported block (method); rows for
    names that are not exported any more fail."""
    page, section, names = FAMILIES[family]
    rows = _table(page, section)
    assert sorted(rows) == sorted(names()), f"{page}: rows and exports differ"
    for name, row in rows.items():
        first = re.findall(r"`([^`]+)`", row["Python"])[0]
        assert first == name
        block, _, method = first.partition(".")
        owner = getattr(family == "tf5410" and tf5410 or planar, block)
        assert not method or callable(getattr(owner, method))


def test_every_entry_is_run_by_a_scenario_test_or_example() -> None:
    """Each timeline command appears in a scenario test (tests/) or an example that the
    example tests run, so every block reached is reached by a test."""
    texts = [path.read_text(encoding="utf-8") for pattern in ("tests/**/*.py", "tests/**/*.yaml",
                                                               "examples/*.yaml")
             for path in ROOT.glob(pattern)]
    untested = [command for command in TIMELINE_COMMANDS
                if not any(re.search(rf"command: {command}\b", text) for text in texts)]
    assert not untested, f"timeline commands no scenario test uses: {untested}"


def test_a_new_exported_block_without_an_entry_fails(monkeypatch: pytest.MonkeyPatch) -> None:
    """The tests above fail for a block exported without a scenario entry or a row."""
    monkeypatch.setattr(tf5410, "__all__", [*tf5410.__all__, "MC_NewBlock"])
    with pytest.raises(AssertionError, match="MC_NewBlock"):
        test_every_exported_block_or_method_is_reached_by_a_scenario_entry("tf5410")
    with pytest.raises(AssertionError, match="MC_NewBlock"):
        test_the_pages_scenario_column_is_the_registry("tf5410")
