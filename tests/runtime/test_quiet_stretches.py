"""Quiet stretches (kernel/runtime.py, D-275): ``run`` and ``run_until(command)`` advance the
cycles before the next event in bulk, and the result is bit for bit that of one ``step`` per
cycle: the same setpoint and actual samples, the same handshake edges at the same cycles."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.axis.drive import DriveModel

CYCLE = 0.001
LIMITS = {"max_velocity": 500.0, "acceleration": 5000.0, "deceleration": 5000.0,
          "jerk": 50000.0, "max_acceleration": 5000.0, "max_deceleration": 5000.0,
          "max_jerk": 50000.0}
Issue = Callable[[], om.Command]


class Tape:
    """Records every cycle's kernel rows (set p, v, a, j, actual p, v) and the cycle at which
    each command's status or in_velocity changed; takes blocks too (``observe_block``).

    A change made between cycles (a command issued, one it aborts) shows at the next cycle
    observed; a block shows its changes at its first cycle, so a change inside a block,
    which must not happen, would show at another cycle than stepping gives."""

    def __init__(self, rt: om.Runtime, commands: list[om.Command], blocks: bool) -> None:
        self.kernel = rt.axis_system.kernel
        self.commands = commands
        self.samples: list[np.ndarray] = []
        self.edges: list[tuple[int, int, int, bool]] = []
        self.calls: list[tuple[str, int, int]] = []  #: ("step", c, c) or ("block", first, last)
        self._seen: dict[int, tuple[int, bool]] = {}
        if blocks:
            self.observe_block = self._observe_block

    def __call__(self, rt: om.Runtime) -> None:
        self.calls.append(("step", rt.cycle, rt.cycle))
        n = self.kernel.size
        self.samples.append(self.kernel.fields[:6, :n].copy()[None])
        self._edges(rt.cycle)

    def _observe_block(self, rt: om.Runtime, blocks: dict[str, Any]) -> None:
        block = blocks["axes"]
        first = rt.cycle - block.times.shape[0] + 1
        assert np.array_equal(blocks["times"], np.arange(first, rt.cycle + 1) * rt.cycle_time)
        self.calls.append(("block", first, rt.cycle))
        self.samples.append(np.stack((block.set_p, block.set_v, block.set_a, block.set_j,
                                      block.act_p, block.act_v), axis=1))
        self._edges(first)

    def _edges(self, cycle: int) -> None:
        for index, command in enumerate(self.commands):
            state = (int(command.status), command.in_velocity)
            if self._seen.get(index) != state:
                self._seen[index] = state
                self.edges.append((cycle, index, *state))

    def trace(self) -> bytes:
        return np.concatenate(self.samples).tobytes() if self.samples else b""


def random_plan(seed: int, n_axes: int, cycles: int) -> list[tuple[int, int, str, tuple]]:
    """(cycle, axis, kind, arguments): moves, velocity moves, halts, stops, superpositions,
    a few in the same cycle, at about 4 per axis and second."""
    rng = np.random.default_rng(seed)
    plan = []
    for _ in range(int(rng.poisson(4.0 * n_axes * cycles * CYCLE)) + 1):
        cycle, axis = int(rng.integers(0, cycles)), int(rng.integers(0, n_axes))
        kind = str(rng.choice(["absolute", "absolute", "relative", "velocity", "halt", "stop",
                               "superimposed"]))
        v, acc, dec = rng.uniform(50, 500), rng.uniform(500, 5000), rng.uniform(500, 5000)
        jerk = rng.uniform(5000, 50000)
        if kind == "absolute":
            args: tuple = (rng.uniform(-200, 200), v, acc, dec, jerk)
        elif kind == "relative":
            args = (rng.uniform(-50, 50), v, acc, dec, jerk)
        elif kind == "velocity":
            args = (v, rng.choice([om.Direction.POSITIVE, om.Direction.NEGATIVE]), acc, dec,
                    jerk)
        elif kind in ("halt", "stop"):
            args = (rng.uniform(2000, 5000), jerk)
        else:
            args = (rng.uniform(-5, 5), rng.uniform(5, 50), rng.uniform(50, 500), 1000.0)
        plan.append((cycle, axis, kind, args))
    plan.sort(key=lambda item: (item[0], item[1]))
    return plan


def build(n_axes: int, lag_axis: bool) -> tuple[om.Runtime, list[om.Axis]]:
    rt = om.Runtime(CYCLE)
    axes = [rt.add_axis(f"a{i}", **LIMITS) for i in range(n_axes)]
    if lag_axis:
        axes.append(rt.add_axis("lag", drive=DriveModel("lag", time_constant=0.004), **LIMITS))
    for axis in axes:
        axis.power()
    return rt, axes


def issue(axis: om.Axis, kind: str, args: tuple) -> om.Command:
    method = {"absolute": axis.move_absolute, "relative": axis.move_relative,
              "velocity": axis.move_velocity, "halt": axis.halt, "stop": axis.stop,
              "superimposed": axis.move_superimposed}[kind]
    return method(*args)


def run_plan(plan: list, n_axes: int, cycles: int, mode: str,
             lag_axis: bool = False) -> tuple[Tape, list[om.Command], om.Runtime]:
    """``mode``: "stepped" (one step per cycle), "bulk" (run between the commands, a block
    observer) or "blind" (run between the commands, no observer at all)."""
    rt, axes = build(n_axes, lag_axis)
    commands: list[om.Command] = []
    tape = Tape(rt, commands, blocks=mode == "bulk")
    if mode != "blind":
        rt.add_observer(tape)
    by_cycle: dict[int, list] = {}
    for cycle, axis, kind, args in plan:
        by_cycle.setdefault(cycle, []).append((axes[axis], kind, args))
    for cycle in range(cycles + 1):
        if mode == "stepped":
            if cycle:
                rt.step()
        elif cycle in by_cycle or cycle == cycles:
            rt.run((cycle - rt.cycle) * CYCLE)
        else:
            continue
        assert rt.cycle == cycle
        for axis, kind, args in by_cycle.get(cycle, []):
            commands.append(issue(axis, kind, args))
    return tape, commands, rt


def outcome(commands: list[om.Command]) -> list[tuple]:
    return [(c.kind, int(c.status), c.in_velocity, c.issued_at, c.ended_at, int(c.error_id))
            for c in commands]


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_axes=st.integers(1, 4))
def test_bulk_runs_of_random_command_streams_give_the_stepped_trace_bit_for_bit(seed, n_axes):
    cycles = 1500
    plan = random_plan(seed, n_axes, cycles)
    stepped, stepped_commands, rt_stepped = run_plan(plan, n_axes, cycles, "stepped")
    bulk, bulk_commands, _ = run_plan(plan, n_axes, cycles, "bulk")
    assert bulk.trace() == stepped.trace()
    assert bulk.edges == stepped.edges
    assert outcome(bulk_commands) == outcome(stepped_commands)
    assert any(kind == "block" for kind, *_ in bulk.calls)  # the bulk path ran
    blind, blind_commands, rt_blind = run_plan(plan, n_axes, cycles, "blind")
    assert outcome(blind_commands) == outcome(stepped_commands)
    n = rt_stepped.axis_system.kernel.size
    assert rt_blind.axis_system.kernel.fields[:, :n].tobytes() == \
        rt_stepped.axis_system.kernel.fields[:, :n].tobytes()
    assert (rt_blind.cycle, rt_blind.now) == (rt_stepped.cycle, rt_stepped.now)


def test_a_lag_drive_makes_every_cycle_a_step_and_the_trace_stays_the_same():
    plan = random_plan(7, 2, 600)
    stepped, stepped_commands, _ = run_plan(plan, 2, 600, "stepped", lag_axis=True)
    bulk, bulk_commands, _ = run_plan(plan, 2, 600, "bulk", lag_axis=True)
    assert [kind for kind, *_ in bulk.calls] == ["step"] * 600
    assert bulk.trace() == stepped.trace() and bulk.edges == stepped.edges
    assert outcome(bulk_commands) == outcome(stepped_commands)


def first_cycle_at_or_after(time: float) -> int:
    cycle = max(math.ceil(time / CYCLE) - 1, 0)
    while cycle * CYCLE < time:
        cycle += 1
    return cycle


def test_events_force_steps_exactly_where_they_are_due():
    """A move: one block up to the cycle before its profile ends, a step there (the Done
    window opens: target monitoring, 20 ms), one block up to the cycle before it closes, a
    step there (Done), then one block to the end."""
    rt, (axis,) = build(1, lag_axis=False)
    tape = Tape(rt, [], blocks=True)
    rt.add_observer(tape)
    command = axis.move_absolute(100.0, 200.0, 2000.0, 2000.0, 20000.0)
    tape.commands.append(command)
    end = first_cycle_at_or_after(float(rt.axis_system.kernel.segments.end[axis.row]))
    rt.run(2.0)
    done = round(command.ended_at / CYCLE)
    assert command.done and end + 15 < done < 2000
    assert tape.calls == [("block", 1, end - 1), ("step", end, end), ("block", end + 1, done - 1),
                          ("step", done, done), ("block", done + 1, 2000)]
    assert [edge[0] for edge in tape.edges] == [1, done]  # Busy/Active at 1, Done at done
    stepped, (twin,) = build(1, lag_axis=False)
    twin.move_absolute(100.0, 200.0, 2000.0, 2000.0, 20000.0)
    for _ in range(2000):
        stepped.step()
    assert twin.queue.jobs() == [] and twin.state == axis.state


@pytest.mark.parametrize("monitoring", ["target", "range", "none"])
def test_the_done_window_ends_in_the_cycle_stepping_gives(monitoring):
    ends = []
    for bulk in (False, True):
        rt, (axis,) = build(1, lag_axis=False)
        axis.parameters.enable_target_position_monitoring = monitoring == "target"
        axis.parameters.enable_position_range_monitoring = monitoring == "range"
        axis.parameters.target_position_monitoring_time = 0.0137
        command = axis.move_relative(7.0, 50.0, 500.0, 500.0, 5000.0)
        if bulk:
            rt.run(1.0)
        else:
            for _ in range(1000):
                rt.step()
        ends.append((command.ended_at, int(command.status), axis.state))
    assert ends[0] == ends[1] and ends[0][1] == int(om.CommandStatus.DONE)


def test_run_until_a_command_stops_at_the_cycle_stepping_gives():
    rt_a, (a,) = build(1, lag_axis=False)
    rt_b, (b,) = build(1, lag_axis=False)
    move_a = a.move_absolute(50.0, 100.0, 1000.0, 1000.0, 10000.0)
    move_b = b.move_absolute(50.0, 100.0, 1000.0, 1000.0, 10000.0)
    stepped = rt_a.run_until(lambda: move_a.done)  # a callable: asked after every cycle
    bulk = rt_b.run_until(move_b)
    assert (bulk, rt_b.cycle, move_b.ended_at) == (stepped, rt_a.cycle, move_a.ended_at)
    assert b.set_position == a.set_position == 50.0
    with pytest.raises(TimeoutError, match="after 0.1 s"):
        rt_b.run_until(b.move_absolute(0.0, 10.0), timeout=0.1)
    assert rt_b.cycle == rt_a.cycle + 100  # the timeout is exact in bulk too
    rt_b.run(0.01)  # still usable
    assert rt_b.cycle == rt_a.cycle + 110


@pytest.mark.parametrize("with_program", [True, False])
def test_a_program_or_a_per_cycle_observer_makes_every_cycle_a_step(with_program):
    rt, (axis,) = build(1, lag_axis=False)
    calls: list[int] = []
    tape = Tape(rt, [], blocks=True)
    rt.add_observer(tape)
    if with_program:
        rt.add_program(lambda: calls.append(rt.cycle))
    else:
        rt.add_observer(lambda runtime: calls.append(runtime.cycle))
    axis.move_velocity(100.0)
    rt.run(0.5)
    assert calls == list(range(1, 501))
    assert [kind for kind, *_ in tape.calls] == ["step"] * 500


def test_a_runtime_without_axes_runs_in_one_block_and_keeps_its_clock():
    rt = om.Runtime(CYCLE)
    tape = Tape(rt, [], blocks=True)
    rt.add_observer(tape)
    rt.run(1.0)
    assert tape.calls == [("block", 1, 1000)]
    assert (rt.cycle, rt.now) == (1000, 1000 * CYCLE)
    axis = rt.add_axis("late")  # starts at the last sample time
    axis.power()
    move = axis.move_relative(1.0, 10.0)
    assert rt.run_until(move) > 1.0


def test_a_lag_axis_added_to_a_runtime_that_ran_without_axes_follows_from_its_first_cycle():
    stepped = om.Runtime(CYCLE)
    for _ in range(3):
        stepped.step()  # no axes yet: the motion phase did the drives' work too
    axis = stepped.add_axis("lag", drive=DriveModel("lag", time_constant=0.004), **LIMITS)
    axis.power()
    axis.move_relative(5.0, 100.0, 1000.0, 1000.0, 10000.0)
    stepped.step()
    kernel = stepped.axis_system.kernel
    assert 0.0 < kernel.act_p[0] < kernel.set_p[0]  # the lag filter ran in the drive phase
