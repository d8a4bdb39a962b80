"""docs/tcmc-coverage.md stays true: its tests exist, each TcMC rule 1-144 has one row, and
every exported MC_ block has a row."""

from __future__ import annotations

import re
from pathlib import Path

import openmotion.plcopen as blocks

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "tcmc-coverage.md"
RULES = range(1, 145)


def _section(title: str) -> list[list[str]]:
    """The table rows (cells stripped) of the section ``## title``, header rows left out."""
    text = PAGE.read_text(encoding="utf-8")
    match = re.search(rf"^## {title}\n(.*?)(?=^## |\Z)", text, flags=re.S | re.M)
    assert match, f"no section '## {title}' in {PAGE.name}"
    rows = [
        re.split(r"(?<!\\)\|", line.strip().strip("|"))
        for line in match.group(1).splitlines()
        if line.startswith("|")
    ]
    return [[cell.strip() for cell in row] for row in rows[2:]]


def test_every_named_test_exists() -> None:
    refs = set(re.findall(r"(tests/[\w/]+\.py)::(\w+)", PAGE.read_text(encoding="utf-8")))
    assert refs, "the page names no tests"
    sources: dict[str, str] = {}
    missing = []
    for path, function in sorted(refs):
        file = ROOT / path
        if not file.is_file():
            missing.append(f"{path} (no such file)")
            continue
        source = sources.setdefault(path, file.read_text(encoding="utf-8"))
        if not re.search(rf"^\s*(?:async\s+)?def {function}\(", source, flags=re.M):
            missing.append(f"{path}::{function}")
    assert not missing, f"{PAGE.name} names tests that do not exist: {missing}"


def test_every_rule_has_exactly_one_row() -> None:
    numbers = [int(row[0]) for row in _section("Rules") if row[0].isdigit()]
    duplicates = sorted({n for n in numbers if numbers.count(n) > 1})
    assert not duplicates, f"rules with more than one row: {duplicates}"
    assert sorted(numbers) == list(RULES), f"missing: {sorted(set(RULES) - set(numbers))}"


def test_every_rule_row_names_a_test_or_says_why_not() -> None:
    for row in _section("Rules"):
        tests = row[2]
        assert "::" in tests or tests in ("not yet", "none"), f"rule {row[0]}: {tests!r}"


def test_every_exported_block_has_a_row_that_is_not_not_yet() -> None:
    rows = {row[0]: row for row in _section("Blocks")}
    exported = [name for name in blocks.__all__ if name.startswith(("MC_", "F_"))]
    missing = [name for name in exported if name not in rows]
    assert not missing, f"exported blocks without a row in {PAGE.name}: {missing}"
    stale = [name for name in exported if "not yet" in rows[name][3]]
    assert not stale, f"exported blocks still marked 'not yet': {stale}"
