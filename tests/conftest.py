"""Shared test set-up: hypothesis profiles, the versions that matter in the header, and how
many processes run the suite (D-365)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy
import pytest
import ruckig
from hypothesis import HealthCheck, settings

from openmotion.kernel.handshake import FunctionBlock

settings.register_profile("dev", max_examples=60, deadline=None)
settings.register_profile(
    "ci", max_examples=60, deadline=None, derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("nightly", max_examples=2000, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci" if os.environ.get("CI") else "dev"))


@pytest.hookimpl(optionalhook=True)  # pytest without xdist (-p no:xdist) skips it
def pytest_xdist_auto_num_workers(config: pytest.Config) -> int | None:
    """``-n auto`` (pyproject's addopts): one worker per core for the suite or a folder of
    it, none (in this process) when the command names only test files or tests, where
    starting workers would cost more than it saves. PYTEST_XDIST_AUTO_NUM_WORKERS still
    decides when it is set (xdist's own hook reads it)."""
    if os.environ.get("PYTEST_XDIST_AUTO_NUM_WORKERS"):
        return None
    named = [a for a in config.args if not a.startswith("-")]
    if named and all("::" in a or Path(a).is_file() for a in named):
        return 0
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return 0 if (cores or 1) < 2 else cores


def pytest_report_header(config: pytest.Config) -> str:
    return f"numpy {numpy.__version__}, ruckig {ruckig.__version__}"


@pytest.fixture(autouse=True)
def strict_blocks():
    """Every FB checks its output invariants (never done and busy together, ...)."""
    FunctionBlock.strict = True
    yield
    FunctionBlock.strict = False
