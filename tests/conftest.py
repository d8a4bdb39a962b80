"""Shared test set-up: hypothesis profiles and the versions that matter in the header."""

from __future__ import annotations

import os

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


def pytest_report_header(config: pytest.Config) -> str:
    return f"numpy {numpy.__version__}, ruckig {ruckig.__version__}"


@pytest.fixture(autouse=True)
def strict_blocks():
    """Every FB checks its output invariants (never done and busy together, ...)."""
    FunctionBlock.strict = True
    yield
    FunctionBlock.strict = False
