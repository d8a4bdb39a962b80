"""Every file in examples/ runs, its checks pass and its summary equals the golden .out file.

After an intended change of behaviour, regenerate a golden file with
``openmotion run examples/<name>.yaml --trace /tmp/trace.csv > examples/<name>.out``
(piped stdout is exactly the plain-text summary) and review the diff.
"""

from __future__ import annotations

import difflib
from pathlib import Path

import pytest

from openmotion.scenario import examples_dir, run_scenario

EXAMPLES = sorted(examples_dir().glob("*.yaml"))


def test_the_shipped_examples_are_there() -> None:
    names = {path.stem for path in EXAMPLES}
    assert {"single_move", "modulo_rotary", "abort_and_blend", "flying_saw",
            "touch_probe", "jog_and_feed", "ca_starter_kit", "ca_standard_vs_fast",
            "ca_gear_in_pos", "ca_tracks", "planar_two_movers", "planar_choreography",
            "planar_parts", "gantry_contour", "scara_pick_place", "conveyor_pick",
            "planar_track_join", "planar_track_network", "planar_track_station",
            "planar_routing"} <= names


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda path: path.stem)
def test_example_runs_passes_its_checks_and_matches_its_golden_summary(path: Path) -> None:
    result = run_scenario(path)
    assert result.checks, "an example without checks proves nothing"
    failed = [check for check in result.checks if not check.passed]
    assert not failed, failed
    golden = path.with_suffix(".out")
    assert golden.exists(), f"{golden.name} is missing"
    expected, actual = golden.read_text(encoding="utf-8"), result.summary()
    diff = "".join(difflib.unified_diff(expected.splitlines(True), actual.splitlines(True),
                                        str(golden.name), "current run"))
    assert actual == expected, diff
