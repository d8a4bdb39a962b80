"""Gap control under faults: random rails, movers and commands, with faults at random cycles.

A mover loses power (MC_Power off), a mover's drive reports a following error, or the PLC
takes a mover out of the group (MC_HaltCA, then MC_RemoveAxisFromGroup once it stands); some
cases then power the movers again and reset the group, and the commands go on. In every
cycle, for every member of the group:

* no setpoint gap below the gap (D-183: the others keep the gap to where a mover without
  power can be, which is its brake);
* the axis limits hold and the setpoint is continuous (no velocity step beyond what the
  deceleration allows in one cycle);
* StandStill and Disabled only at rest (D-184; issue 19 point 4), for removed movers too.

Commands and resets the group refuses in its fault states end with the documented error ids,
never with an exception.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.enums import AxisState, BufferMode
from openmotion.core.errors import ErrorId
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GapControlDirection,
    GapControlMode,
)

GAP_TOLERANCE = 1e-9  #: [mm] float slack of the gap check (gap_control.TOLERANCE)
LIMIT_SLACK = 1 + 1e-9  #: relative float slack of the limit checks
RUN_OUT_CYCLES = 400  #: after the last event: until all rest, at most this long (brakes
#: from the fastest mover take about 0.5 s here)
FAULTS = ("power_off", "following_error", "remove")
#: what the group answers a command in its fault states (TF5410 §7; D-065)
REFUSALS = {ErrorId.GROUP_NOT_ENABLED, ErrorId.GROUP_IN_ERROR, ErrorId.AXIS_DISABLED,
            ErrorId.AXIS_NOT_IN_GROUP, ErrorId.GROUP_STOPPING}


@st.composite
def fault_cases(draw: st.DrawFn) -> dict:
    n = draw(st.integers(2, 5))
    gap = draw(st.floats(0.0, 150.0))
    spacing = draw(st.floats(gap + 1.0, gap + 300.0))
    ring = draw(st.booleans())
    starts = [i * spacing + draw(st.floats(0.0, (spacing - gap) / 2)) for i in range(n)]
    movers = []
    for _ in range(n):
        dec = draw(st.floats(4000.0, 20000.0))
        jerk = draw(st.floats(1e5, 1e6))
        movers.append({"max_velocity": draw(st.floats(300.0, 2000.0)),
                       "acceleration": draw(st.floats(2000.0, 20000.0)), "deceleration": dec,
                       "jerk": jerk, "max_acceleration": 20000.0,
                       "max_deceleration": dec * draw(st.floats(1.0, 2.0)),
                       "max_jerk": jerk * draw(st.floats(1.0, 2.0))})
    commands = draw(st.lists(st.tuples(
        st.integers(0, 150),  # cycle
        st.integers(0, n - 1),  # mover
        st.sampled_from(["absolute", "relative", "halt"]),
        st.sampled_from([-1.0, 1.0]),  # direction
        st.floats(0.05, 1.0),  # target or distance, in half rail lengths
        st.floats(0.3, 1.0),  # velocity, fraction of the mover's maximum
        st.sampled_from([BufferMode.ABORTING, BufferMode.BUFFERED]),
        st.sampled_from([GapControlMode.STANDARD, GapControlMode.FAST]),
    ), min_size=1, max_size=12))
    # the mover of a fault: the k-th one moving at that cycle, if any moves (FaultRun.fault)
    faults, cycle = [], min(c[0] for c in commands)
    for _ in range(draw(st.integers(1, 3))):
        cycle += draw(st.integers(1, 150))
        faults.append((cycle, draw(st.integers(0, n - 1)), draw(st.sampled_from(FAULTS))))
    recover = draw(st.one_of(st.none(), st.integers(1, 200)))  # cycles after the first fault
    fast_default = draw(st.booleans())
    return {"n": n, "gap": gap, "ring": ring, "length": n * spacing, "starts": starts,
            "movers": movers, "commands": sorted(commands, key=lambda c: c[0]),
            "faults": faults, "recover": recover,
            "mode": GapControlMode.FAST if fast_default else GapControlMode.STANDARD}


class FaultRun:
    """One case: the group, its axes, the pending events and the per-cycle checks."""

    def __init__(self, case: dict) -> None:
        self.case = case
        self.rt = rt = om.Runtime()
        self.group = CaGroup(rt, "ca", rail_length=case["length"], rail_is_ring=case["ring"],
                             default_gap=case["gap"], default_gap_control_mode=case["mode"],
                             gap_control_direction=GapControlDirection.BOTH)
        self.axes: list[om.Axis] = []
        for i, (start, limits) in enumerate(zip(case["starts"], case["movers"], strict=True)):
            axis = rt.add_axis(f"m{i}", position=start, **limits)
            assert axis.power()
            assert self.group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1)).done
            self.axes.append(axis)
        assert self.group.enable().done
        self.removing: set[int] = set()  #: movers the PLC takes out once they stand
        self.rows = np.array([a.row for a in self.axes])
        movers = case["movers"]
        self.vmax = np.array([m["max_velocity"] for m in movers])
        self.amax = np.array([max(m["max_acceleration"], m["max_deceleration"]) for m in movers])
        self.jmax = np.array([m["max_jerk"] for m in movers])
        k = rt.axis_system.kernel
        self.last_v = k.set_v[self.rows].copy()

    def run(self) -> None:
        case = self.case
        commands, faults = list(case["commands"]), list(case["faults"])
        recover = None if case["recover"] is None else faults[0][0] + case["recover"]
        last = max(commands[-1][0], faults[-1][0], recover or 0)
        for cycle in range(last + RUN_OUT_CYCLES):
            while commands and commands[0][0] <= cycle:
                self.command(*commands.pop(0)[1:])
            while faults and faults[0][0] <= cycle:
                self.fault(*faults.pop(0)[1:])
            if cycle == recover:
                self.recover()
            self.take_out()
            self.rt.step()
            self.check()
            if cycle > last and not self.removing and self.resting():
                break

    def command(self, i: int, kind: str, sign: float, size: float, speed: float,
                buffer_mode: BufferMode, mode: GapControlMode) -> None:
        axis, group, amount = self.axes[i], self.group, sign * size
        if axis.group is not group:
            return
        velocity = speed * self.case["movers"][i]["max_velocity"]
        half = self.case["length"] / 2
        if kind == "absolute":
            command = group.move_absolute(axis, axis.set_position + amount * half, velocity,
                                          buffer_mode=buffer_mode, gap_control_mode=mode)
        elif kind == "relative":
            command = group.move_relative(axis, amount * half, velocity,
                                          buffer_mode=buffer_mode, gap_control_mode=mode)
        else:
            command = group.halt_axis(axis, gap_control_mode=mode)
        assert not command.error or command.error_id in REFUSALS, command.message

    def fault(self, i: int, kind: str) -> None:
        moving = [axis for axis in self.axes if axis.set_velocity != 0.0]
        axis = moving[i % len(moving)] if moving else self.axes[i]
        i = self.axes.index(axis)
        if kind == "power_off":
            axis.power(False)
        elif kind == "following_error":  # what the drive monitor reports (Runtime phase 3)
            axis.fault(ErrorId.FOLLOWING_ERROR, "injected following error")
        elif axis.group is self.group:
            self.removing.add(i)
            halt = self.group.halt_axis(axis)
            assert not halt.error or halt.error_id in REFUSALS, halt.message

    def take_out(self) -> None:
        """MC_RemoveAxisFromGroup, every cycle until the mover stands without a command."""
        for i in sorted(self.removing):
            command = self.group.remove_axis(UDINT_TO_IDENTINGROUP(i + 1))
            if command.done:
                self.removing.discard(i)
                assert self.axes[i].group is None
            else:
                assert command.error_id is ErrorId.AXIS_MOVING, command.message

    def recover(self) -> None:
        """Power every axis again and reset the group (Busy until the brakes end)."""
        for axis in self.axes:
            axis.power()
        reset = self.group.reset()
        assert not reset.error, reset.message

    def resting(self) -> bool:
        k = self.rt.axis_system.kernel
        return bool(np.all(k.set_v[self.rows] == 0.0) and np.all(k.set_a[self.rows] == 0.0))

    def check(self) -> None:
        rt, group, k = self.rt, self.group, self.rt.axis_system.kernel
        gaps = group.gaps()  # inf for a mover with no predecessor
        if gaps.size:
            assert gaps.min() >= self.case["gap"] - GAP_TOLERANCE, \
                f"gap {gaps.min()} below {self.case['gap']} at t={rt.now}, order {group.order}"
        v, a, j = k.set_v[self.rows], k.set_a[self.rows], k.set_j[self.rows]
        assert np.all(np.abs(v) <= self.vmax * LIMIT_SLACK), f"velocity {v} beyond {self.vmax}"
        assert np.all(np.abs(a) <= self.amax * LIMIT_SLACK), f"acceleration {a} at t={rt.now}"
        assert np.all(np.abs(j) <= self.jmax * LIMIT_SLACK), f"jerk {j} at t={rt.now}"
        step = np.abs(v - self.last_v)
        assert np.all(step <= self.amax * rt.cycle_time * LIMIT_SLACK + 1e-9), \
            f"velocity step {step} at t={rt.now}"
        self.last_v = v.copy()
        for axis in self.axes:
            if axis.state in (AxisState.STANDSTILL, AxisState.DISABLED):
                assert axis.set_velocity == 0.0 and axis.set_acceleration == 0.0, \
                    f"{axis.name} {axis.state.name} at v={axis.set_velocity} t={rt.now}"


@settings(deadline=None, max_examples=30)
@given(case=fault_cases())
def test_gaps_states_and_limits_hold_under_faults(case: dict) -> None:
    FaultRun(case).run()


@pytest.mark.slow
@settings(deadline=None, max_examples=10_000)
@given(case=fault_cases())
def test_gaps_states_and_limits_hold_under_faults_over_many_cases(case: dict) -> None:
    FaultRun(case).run()
