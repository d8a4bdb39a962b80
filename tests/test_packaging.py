"""Issue 18: the wheel a user installs carries the shipped examples and the viewer's files, and
``python -m openmotion`` runs from it in any directory (CI also installs it into a fresh
environment: .ci/run)."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import openmotion
from openmotion.examples import examples_dir

CHECKOUT = Path(__file__).resolve().parents[1]
VIEWER_FILES = ("index.html", "viewer.css", "viewer.js")


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    env = {**os.environ, "OPENMOTION_PRECOMPILE": "0"}  # .ci/run builds the compiled one
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(out),
                    str(CHECKOUT)], check=True, capture_output=True, timeout=600, env=env)
    (built,) = out.glob("openmotion-*.whl")
    return built


def test_the_wheel_carries_every_example_and_the_viewer(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    shipped = sorted(p.name for p in (CHECKOUT / "examples").iterdir()
                     if p.suffix in (".yaml", ".out"))
    assert len(shipped) >= 38
    for name in shipped:
        assert f"openmotion/examples/{name}" in names, name
    for name in VIEWER_FILES:
        assert f"openmotion/viewer/static/{name}" in names, name
    assert "openmotion/__main__.py" in names


def test_the_unpacked_wheel_runs_examples_by_name_from_another_directory(
        wheel: Path, tmp_path: Path) -> None:
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {**os.environ, "PYTHONPATH": str(site)}  # the wheel's openmotion, not the checkout's

    def openmotion_(*arguments: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "openmotion", *arguments], cwd=elsewhere,
                              env=env, capture_output=True, text=True, timeout=300)

    listed = openmotion_("examples")
    assert listed.returncode == 0, listed.stderr
    assert str(site / "openmotion" / "examples") in listed.stderr
    run = openmotion_("run", "--quiet")
    assert run.returncode == 0, run.stderr
    assert (elsewhere / "trace.csv").exists()
    check = openmotion_("check", "modulo_rotary")
    assert check.returncode == 0 and str(site) in check.stdout


def test_a_checkout_reads_its_own_examples_folder() -> None:
    if (Path(openmotion.__file__).parent / "examples" / "single_move.yaml").exists():
        pytest.skip("running from an installed wheel")
    assert examples_dir() == CHECKOUT / "examples"
