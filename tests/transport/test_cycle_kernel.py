"""The CA cycle in one compiled call (transport/cycle_kernel.py, D-281) against the numpy
formulation (``GroupCycle.compiled_cycle = False``): the same setpoints, modes and command
outcomes bit for bit, cycle by cycle, in every gap control mode and direction, with queues,
aborts, group halts and standby gap control."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

import openmotion as om
import openmotion.transport.cycle as group_cycle
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GapControlDirection,
    GapControlMode,
    ModuloDirection,
)
from openmotion.transport.cycle import GroupCycle
from openmotion.transport.cycle_kernel import group_step

LIMITS = {"max_velocity": 4000.0, "acceleration": 10000.0, "deceleration": 10000.0,
          "jerk": 100000.0, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
          "max_jerk": 100000.0}
SPACING = 300.0


def _traffic(n: int, cycle_time: float, modes: list[GapControlMode], cycles: int,
             halt_at: int | None = None, **parameters: object
             ) -> tuple[np.ndarray, list[str]]:
    """Random modulo targets on a ring (as ``bench ca``): every cycle's setpoints and modes,
    and the end status of every command."""
    rng = np.random.default_rng(7)
    rt = om.Runtime(cycle_time)
    group = CaGroup(rt, "ca", rail_length=SPACING * n, default_gap=100.0, **parameters)
    axes = []
    for i in range(n):
        axis = rt.add_axis(f"m{i}", position=i * SPACING, **LIMITS)
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
        axes.append(axis)
    group.enable()
    rows = np.array([a.row for a in axes])
    commands: list[om.Command | None] = [None] * n
    issued: list[om.Command] = []
    scale = max(1, round(0.001 / cycle_time))  # commands renewed as often in time
    renew = rng.integers(1, 400, n) * scale
    trace = []
    for cycle in range(cycles):
        if cycle == halt_at:
            issued.append(group.halt())
        elif halt_at is None or cycle < halt_at or cycle > halt_at + 300:
            for i, axis in enumerate(axes):
                command = commands[i]
                if command is None or command.finished or cycle >= renew[i]:
                    commands[i] = group.move_absolute(
                        axis, float(rng.uniform(0.0, SPACING * n)),
                        float(rng.uniform(500.0, 3000.0)), direction=ModuloDirection.POSITIVE,
                        gap_control_mode=modes[i % len(modes)])
                    issued.append(commands[i])
                    renew[i] = cycle + rng.integers(40, 400) * scale
        rt.step()
        k = rt.axis_system.kernel
        trace.append(np.concatenate([k.set_p[rows], k.set_v[rows], k.set_a[rows],
                                     k.set_j[rows], group.mode.astype(float)]))
    return np.array(trace), [c.status.name for c in issued]


def _both(monkeypatch: pytest.MonkeyPatch, run: Callable[[], tuple[np.ndarray, list[str]]]
          ) -> tuple[tuple[np.ndarray, list[str]], tuple[np.ndarray, list[str]]]:
    monkeypatch.setattr(GroupCycle, "compiled_cycle", True)
    compiled = run()
    monkeypatch.setattr(GroupCycle, "compiled_cycle", False)
    return compiled, run()


def _assert_same(compiled: tuple[np.ndarray, list[str]],
                 reference: tuple[np.ndarray, list[str]]) -> None:
    (trace, statuses), (trace_ref, statuses_ref) = compiled, reference
    differ = np.flatnonzero((trace.view(np.int64) != trace_ref.view(np.int64)).any(axis=1))
    assert differ.size == 0, f"first cycle that differs: {differ[:1]}"
    assert statuses == statuses_ref
    assert "DONE" in statuses  # queues formed and dissolved: the events ran


STANDARD, FAST = GapControlMode.STANDARD, GapControlMode.FAST


@pytest.mark.parametrize("cycle_time", [0.001, 0.00025])
@pytest.mark.parametrize("modes", [[STANDARD], [FAST], [STANDARD, FAST]],
                         ids=["standard", "fast", "mixed"])
def test_traffic_is_the_same_bit_for_bit(monkeypatch: pytest.MonkeyPatch, cycle_time: float,
                                         modes: list[GapControlMode]) -> None:
    cycles = round(1.5 / cycle_time) if cycle_time >= 0.001 else round(0.75 / cycle_time)
    _assert_same(*_both(monkeypatch, lambda: _traffic(8, cycle_time, modes, cycles)))


@pytest.mark.parametrize("direction", [GapControlDirection.POSITIVE, GapControlDirection.BOTH])
def test_halt_and_standby_gap_control_are_the_same(monkeypatch: pytest.MonkeyPatch,
                                                   direction: GapControlDirection) -> None:
    """Halting movers (their brake, their end at rest), idle movers giving way."""
    _assert_same(*_both(monkeypatch, lambda: _traffic(
        6, 0.001, [STANDARD, FAST], 1200, halt_at=500, gap_control_direction=direction,
        standby_gap_control=True, active_gap_establishing=True)))


def test_the_compiled_cycle_is_the_one_that_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """On by default: a plain ring takes the compiled call in every moving cycle."""
    calls = []

    def spy(*args: object) -> object:
        calls.append(args[1])
        return group_step(*args)

    monkeypatch.setattr(group_cycle, "group_step", spy)
    assert GroupCycle.compiled_cycle is True
    trace, statuses = _traffic(4, 0.00025, [STANDARD], 400)
    assert len(calls) == 400 and trace.shape == (400, 4 * 5) and statuses
