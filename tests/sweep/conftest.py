"""Sweep test set-up: a short base scenario and sweep files written for each test."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

BASE = Path(__file__).with_name("short_move.yaml")  #: one axis, one 20 mm move
METRICS = [{"signal": "x.set_position", "stats": ["max", "final"]},
           {"signal": "x.set_velocity", "stats": ["max"]},
           {"commands": ["done", "error"]}, {"run": ["end_time", "cycles"]},
           {"cycle_cost": True}]


def sweep_text(**fields: Any) -> str:
    data = {"scenario": str(BASE), "metrics": METRICS, **fields}
    return yaml.safe_dump({k: v for k, v in data.items() if v is not None}, sort_keys=False)


@pytest.fixture
def write_sweep(tmp_path: Path):
    """``write_sweep(**fields) -> path`` of a sweep file on the short move (the fields
    replace the defaults; None drops one)."""
    def write(name: str = "sweep.yaml", **fields: Any) -> Path:
        path = tmp_path / name
        path.write_text(sweep_text(**fields), encoding="utf-8")
        return path

    return write
