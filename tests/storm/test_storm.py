"""The command storm of issue 19 in the suite, and the checks that its checker can fail.

``test_storm_*`` run ``OPENMOTION_STORM_OPS`` random operations (default
``storm.DEFAULT_OPERATIONS``, about 20 s) from ``OPENMOTION_STORM_SEED``; the ``slow`` variants
run ``OPENMOTION_STORM_SLOW_OPS`` (default 10⁵) with ``pytest -m slow tests/storm``.

Each asserts no violation at all; the exceptions the rules allow are documented once, in
``storm.EXCEPTIONS``. A failure prints the first violations with the seed, the operation
index and a minimal reproduction that uses the public API only.
"""

from __future__ import annotations

import importlib.util
import math
import os
import sys
from pathlib import Path
from typing import Any

import pytest

from openmotion import AxisState
from openmotion.axis.commands import Command
from openmotion.plcopen import ExecuteBlock, FunctionBlock, MC_SetActualPosition

_spec = importlib.util.spec_from_file_location("storm", Path(__file__).with_name("storm.py"))
storm = importlib.util.module_from_spec(_spec)
sys.modules["storm"] = storm
_spec.loader.exec_module(storm)

SEED = int(os.environ.get("OPENMOTION_STORM_SEED", "19"))
OPERATIONS = int(os.environ.get("OPENMOTION_STORM_OPS", str(storm.DEFAULT_OPERATIONS)))
SLOW_OPERATIONS = int(os.environ.get("OPENMOTION_STORM_SLOW_OPS", "100000"))
SHOWN = 2  #: new violations shrunk and printed in a failure message

def _describe(report: storm.Report, violations: list[storm.Violation]) -> str:
    for violation in violations[:SHOWN]:
        violation.minimal = storm.shrink(violation)
    counts: dict[str, int] = {}
    for v in violations:
        counts[v.invariant] = counts.get(v.invariant, 0) + 1
    return (f"{len(violations)} violation(s) in {report.operations} operations "
            f"(seed {report.seed}): {counts}\n\n"
            + "\n\n".join(v.report(report.seed) for v in violations[:SHOWN]))


@pytest.fixture(scope="module")
def report() -> storm.Report:
    return storm.run_storm(SEED, OPERATIONS)


@pytest.fixture(scope="module")
def slow_report() -> storm.Report:
    return storm.run_storm(SEED, SLOW_OPERATIONS)


def test_storm_breaks_no_invariant(report):
    """Limits, continuity, state, handshake and liveness (storm.py's docstring cites each
    rule) hold in every cycle, with only the exceptions EXCEPTIONS documents."""
    assert not report.violations, _describe(report, report.violations)


@pytest.mark.slow
def test_slow_storm_breaks_no_invariant(slow_report):
    """Issue 19's goal: 0 violations over >= 10⁵ operations."""
    assert slow_report.operations >= 100_000 or "OPENMOTION_STORM_SLOW_OPS" in os.environ
    assert not slow_report.violations, _describe(slow_report, slow_report.violations)


def test_every_exception_gives_its_reason_and_citation():
    """The documented exceptions live in one table, each with why and where it is decided."""
    assert storm.EXCEPTIONS
    for waiver in storm.EXCEPTIONS:
        assert waiver.reason and waiver.citation, waiver.name
        assert waiver.waives <= {"jump.position", "jump.velocity", "jump.acceleration"}


# -- the checker can fail ------------------------------------------------------------------------

def _quiet_storm() -> storm.Storm:
    """Every axis powered and at rest; the blocks checked as in a storm."""
    s = storm.Storm(seed=0)
    for name in s.axes:
        s.give(name, "power", enable=True)
    s.run(2)
    return s


@pytest.fixture
def lenient(monkeypatch):
    """The storm checks the block outputs itself instead of asserting in them."""
    monkeypatch.setattr(FunctionBlock, "strict", False)


def test_a_setpoint_jump_is_a_violation_with_a_reproduction(lenient, monkeypatch):
    """MC_SetActualPosition at rest shifts the set position: a jump that no exception
    waives (the block is not among the storm's, so its jump is documented nowhere there)."""
    monkeypatch.setitem(storm.BLOCKS, "set_position", MC_SetActualPosition)
    s = _quiet_storm()
    s.give("x", "move_relative", execute=True, distance=10.0, velocity=100.0)
    s.run(400)
    s.give("x", "move_relative", execute=False)
    s.give("x", "set_position", execute=True, position=50.0)
    s.run(3)
    jumps = [v for v in s.violations if v.invariant == "jump.position"]
    assert [(v.axis, v.cycles) for v in jumps] == [("x", 1)], s.violations
    jumps[0].minimal = storm.shrink(jumps[0])
    assert [a.block for a in jumps[0].minimal] == ["set_position"]
    assert "x_set_position = MC_SetActualPosition(x)" in jumps[0].report(0)


def test_power_off_mid_move_is_waived(lenient):
    """D-019: disabling freezes the setpoint; EXCEPTIONS waives exactly that jump."""
    s = _quiet_storm()
    s.give("x", "move_velocity", execute=True, velocity=800.0)
    s.run(300)
    assert s.axes["x"].set_velocity == 800.0
    s.give("x", "power", enable=False)
    s.run(2)
    s.give("x", "power", enable=True)
    s.run(2)
    assert s.axes["x"].state is AxisState.STANDSTILL
    assert s.violations == []


class _Stuck(ExecuteBlock):
    """A block whose command never ends, whatever the axis does."""

    def _issue(self, axis: Any) -> Command:
        command = Command("stuck", 0.0)
        command.status = command.status.ACTIVE
        return command


class _Liar(_Stuck):
    """A block that shows Done and Busy together."""

    def _refresh(self, execute: bool) -> None:
        self.busy = self.done = execute


def test_a_hanging_command_is_a_violation(lenient, monkeypatch):
    monkeypatch.setitem(storm.BLOCKS, "stuck", _Stuck)
    s = _quiet_storm()
    s.give("y", "stuck", execute=True)
    s.run(storm.HANG_CYCLES + 5)
    assert [(v.invariant, v.axis) for v in s.violations] == [("hang", "y")]


def test_a_broken_handshake_is_a_violation(lenient, monkeypatch):
    monkeypatch.setitem(storm.BLOCKS, "liar", _Liar)
    s = _quiet_storm()
    s.give("z", "liar", execute=True)
    s.run(2)
    assert {v.invariant for v in s.violations} == {"handshake.busy_with_result"}


def test_a_storm_is_the_same_for_the_same_seed():
    """A seed and an operation index reproduce a violation only if the storm is
    deterministic."""
    a, b = storm.run_storm(5, 150), storm.run_storm(5, 150)
    assert (a.cycles, [(v.invariant, v.cycle) for v in a.violations]) == (
        b.cycles, [(v.invariant, v.cycle) for v in b.violations])
    assert a.cycles > 150 and math.isfinite(a.seconds)
