"""docs/part4-coverage.md stays true: the tests it names exist, every exported Part 4 block
has one row with a known status, and a block marked supported has the optional inputs
Part 4 gives it (§5, §6; issue 20 points 4 and 6)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import openmotion.coordinated.blocks as blocks

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "part4-coverage.md"
STATUSES = {"supported", "partial", "not supported"}
#: the E inputs of Part 4's tables (§5.7, §5.13, §5.14, §6.3-§6.7), by our input names
OPTIONAL_INPUTS = {
    "MC_GroupHome": {"position", "coord_system", "buffer_mode"},
    "MC_GroupStop": {"deceleration", "jerk", "buffer_mode"},
    "MC_GroupHalt": {"deceleration", "jerk", "buffer_mode"},
    "MC_SyncAxisToGroup": {"ratio_numerator", "ratio_denominator", "acceleration",
                           "deceleration", "jerk", "coord_system", "buffer_mode"},
    "MC_SyncGroupToAxis": {"mode", "tuc_numerator", "tuc_denominator", "acceleration",
                           "deceleration", "jerk", "coord_system", "buffer_mode"},
    "MC_SetDynCoordTransform": {"mode", "coord_system", "buffer_mode"},
    "MC_TrackConveyorBelt": {"conveyor_belt", "initial_object_position", "coord_system",
                             "buffer_mode"},
    "MC_TrackRotaryTable": {"rotary_table", "initial_object_position", "coord_system",
                            "buffer_mode"},
}


def _blocks() -> dict[str, list[str]]:
    text = PAGE.read_text(encoding="utf-8")
    match = re.search(r"^## Blocks\n(.*?)(?=^## )", text, flags=re.S | re.M)
    assert match, f"no section '## Blocks' in {PAGE.name}"
    rows = [[cell.strip() for cell in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
            for line in match.group(1).splitlines() if line.startswith("| MC_")]
    names = [row[0] for row in rows]
    assert len(names) == len(set(names)), "a block with two rows"
    return {row[0]: row for row in rows}


def test_every_named_test_exists() -> None:
    refs = set(re.findall(r"(tests/[\w/]+\.py)::(\w+)", PAGE.read_text(encoding="utf-8")))
    missing = []
    for path, function in sorted(refs):
        file = ROOT / path
        source = file.read_text(encoding="utf-8") if file.is_file() else ""
        if not re.search(rf"^\s*def {function}\(", source, flags=re.M):
            missing.append(f"{path}::{function}")
    assert refs and not missing, f"{PAGE.name} names tests that do not exist: {missing}"


def test_every_exported_block_has_one_row_with_a_known_status() -> None:
    rows = _blocks()
    exported = [name for name in blocks.__all__ if name.startswith("MC_")]
    assert sorted(rows) == sorted(exported)
    unknown = {name: row[3] for name, row in rows.items() if row[3] not in STATUSES}
    assert not unknown, unknown


@pytest.mark.parametrize("name", sorted(OPTIONAL_INPUTS))
def test_a_supported_block_has_its_optional_inputs(name: str) -> None:
    row = _blocks()[name]
    missing = OPTIONAL_INPUTS[name] - set(getattr(blocks, name).INPUTS)
    assert row[3] != "supported" or not missing, f"{name} is marked supported, lacks {missing}"
    assert "absent" not in row[2] or missing, f"{name}'s row says an input is absent"
    assert not missing  # issue 20 point 6: they are all there now
