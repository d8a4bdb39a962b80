"""``python -m openmotion.warm`` fills numba's cache by running scenarios (D-158), and the
build environment that runs it has what a run imports."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
import tomllib
from pathlib import Path

import pytest

from openmotion.warm import main, scenario_files

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
#: one example of each kind of machine: what a scenario run imports
KINDS = ("single_move", "ca_tracks", "gantry_contour", "planar_parts", "planar_track_join")


def test_folders_give_their_scenarios_in_order(tmp_path: Path) -> None:
    for name in ("b.yaml", "a.yaml", "notes.txt"):
        (tmp_path / name).write_text("")
    files = scenario_files([tmp_path, EXAMPLES / "single_move.yaml"])
    assert [f.name for f in files] == ["a.yaml", "b.yaml", "single_move.yaml"]


def test_warm_runs_each_scenario_and_reports_the_ones_that_fail(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    missing = tmp_path / "missing.yaml"
    assert main([str(missing), str(EXAMPLES / "single_move.yaml")]) == 1
    out = capsys.readouterr().out
    assert re.search(r"missing\.yaml: [\d.]+ s \(ScenarioError: .*cannot read", out), out
    assert re.search(r"^single_move\.yaml: [\d.]+ s$", out, re.M), out
    assert "compiled loops cached in" in out
    assert main([str(EXAMPLES / "single_move.yaml")]) == 0  # and a good list warms cleanly


def test_the_build_environment_has_every_dependency_a_run_imports() -> None:
    """setup.py runs scenarios in pip's isolated build environment: it holds only
    ``[build-system] requires``, which must name each dependency a run imports, with the
    project's version."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    build = {_name(r): r for r in project["build-system"]["requires"]}
    code = textwrap.dedent(f"""
        import sys
        from importlib.metadata import packages_distributions
        from openmotion.warm import warm
        warm({[str(EXAMPLES / f"{kind}.yaml") for kind in KINDS]!r})
        owners = packages_distributions()
        print(sorted({{d for m in list(sys.modules) for d in owners.get(m.split(".")[0], [])}}))
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=dict(os.environ), check=True).stdout
    imported = {_name(d) for d in eval(out)}  # noqa: S307 - our own printed list
    for requirement in project["project"]["dependencies"]:
        if _name(requirement) in imported:
            assert build.get(_name(requirement)) == requirement, requirement


def _name(requirement: str) -> str:
    return re.split(r"[<>=!~\[; ]", requirement, maxsplit=1)[0].lower().replace("_", "-")
