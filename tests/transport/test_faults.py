"""A CA group when a member fails or loses power (issue 19 points 4 and 6; D-183, D-184).

Each mover brakes with its maximum deceleration and jerk from the state of the last cycle,
in the cycle the fault is seen; a mover that loses power runs out on that same brake rather
than stopping dead (D-183). Braking movers report Stopping (ErrorStop if they failed
themselves) and StandStill or Disabled only at rest (TcMC state diagram, D-184).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

import openmotion as om
from openmotion.core.enums import AxisState
from openmotion.core.errors import ErrorId
from openmotion.trajectory.plan import plan_stop
from openmotion.trajectory.segments import KinematicState
from openmotion.transport import UDINT_TO_IDENTINGROUP, CaGroup, GapControlMode, GroupState

GAP = 100.0
TOLERANCE = 1e-9  #: [mm] as gap_control.TOLERANCE
DYNAMICS = {"max_velocity": 2000.0, "acceleration": 10000.0, "deceleration": 10000.0,
            "jerk": 1e6, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
            "max_jerk": 1e6}
CRUISE = 300  #: cycles until every mover cruises


def convoy(mode: GapControlMode, n: int = 2, velocity: float = 1500.0, ring: bool = False,
           spacing: float = GAP) -> tuple[om.Runtime, CaGroup, list[om.Axis]]:
    """``n`` movers one gap apart, all moving forwards at ``velocity`` after CRUISE cycles;
    CA order: the mover with the largest position first (§8.1.1)."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=3000.0 if ring else 100_000.0, rail_is_ring=ring,
                    default_gap=GAP, default_gap_control_mode=mode)
    axes = []
    for i in range(n):
        axis = rt.add_axis(f"m{i}", position=i * spacing, **DYNAMICS)
        axis.power()
        assert group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1)).done
        axes.append(axis)
    assert group.enable().done
    for axis in reversed(axes):
        assert not group.move_relative(axis, 50_000.0, velocity).error
    for _ in range(CRUISE):
        rt.step()
    return rt, group, axes


class Watch:
    """Run to rest, recording the smallest gap, the largest velocity step per cycle and the
    cycles where a mover said StandStill or Disabled while it moved."""

    def __init__(self, rt: om.Runtime, group: CaGroup, axes: list[om.Axis]) -> None:
        self.rt, self.group, self.axes = rt, group, axes
        self.min_gap = float(group.gaps().min())
        self.max_step = 0.0
        self.false_rest: list[tuple[str, str, float]] = []
        self.states: dict[str, list[AxisState]] = {a.name: [] for a in axes}
        self.last = np.array([a.set_velocity for a in axes])  # before the fault is injected

    def run(self, cycles: int = 2000, each: Callable[[int], None] | None = None) -> None:
        for cycle in range(cycles):
            if each is not None:
                each(cycle)
            self.rt.step()
            self.min_gap = min(self.min_gap, float(self.group.gaps().min()))
            v = np.array([a.set_velocity for a in self.axes])
            self.max_step = max(self.max_step, float(np.abs(v - self.last).max()))
            self.last = v
            for axis in self.axes:
                self.states[axis.name].append(axis.state)
                if axis.state in (AxisState.STANDSTILL, AxisState.DISABLED) and (
                        axis.set_velocity != 0.0 or axis.set_acceleration != 0.0):
                    self.false_rest.append((axis.name, axis.state.name, axis.set_velocity))


# -- point 6: a mover that loses power keeps the others' gaps (D-183) ---------------------------

@pytest.mark.parametrize("mode", [GapControlMode.STANDARD, GapControlMode.FAST])
def test_leader_powered_off_at_1500_mm_s_keeps_the_gap(mode: GapControlMode) -> None:
    """Issue 19 point 6: two movers at 1500 mm/s, gap 100, the leader loses power. The
    follower brakes in the same cycle from the last safe state (not one cycle late: 98.5 mm
    in Standard before), and the leader runs out on its brake rather than stopping dead
    (28.75 mm in Fast before). D-183."""
    rt, group, (follower, leader) = convoy(mode)
    assert group.order == ["m1", "m0"]
    watch = Watch(rt, group, [follower, leader])
    leader.power(False)
    watch.run()
    assert watch.min_gap >= GAP - TOLERANCE
    assert group.state is GroupState.NOT_READY
    assert watch.false_rest == []


def test_six_movers_fast_ring_at_1800_mm_s_never_pass_through_each_other() -> None:
    """Issue 19 point 6: a 6-mover Fast ring at 1800 mm/s; any one mover losing power left
    two movers passing through each other before (gap -7 mm and less). D-183."""
    for off in range(6):
        rt, group, axes = convoy(GapControlMode.FAST, n=6, velocity=1800.0, ring=True)
        watch = Watch(rt, group, axes)
        group.movers[off].axis.power(False)
        watch.run()
        assert watch.min_gap >= GAP - TOLERANCE, f"mover {off} off: gap {watch.min_gap}"


def test_a_mover_without_power_runs_out_on_its_maximum_brake() -> None:
    """D-183: the powered-off mover's setpoint follows its brake with maximum deceleration and
    jerk from its last state (Stopping), and it is Disabled only once at rest (D-184)."""
    rt, group, (follower, leader) = convoy(GapControlMode.FAST)
    state = KinematicState(leader.set_position, leader.set_velocity, leader.set_acceleration)
    stop = plan_stop(state, DYNAMICS["max_deceleration"], DYNAMICS["max_jerk"]).end.position
    leader.power(False)
    rt.step()
    assert leader.state is AxisState.STOPPING and not leader.powered
    assert 0.0 < leader.set_velocity < state.velocity  # the first cycle of its brake
    watch = Watch(rt, group, [follower, leader])
    watch.run()
    assert leader.state is AxisState.DISABLED and leader.set_velocity == 0.0
    assert leader.set_position == pytest.approx(stop, abs=1e-6)
    assert watch.max_step <= DYNAMICS["max_deceleration"] * rt.cycle_time * (1 + 1e-9)


def test_power_back_during_the_run_out_lets_the_brake_finish_then_standby() -> None:
    """MC_Power on again while the mover runs out does not freeze it: the brake goes on
    (D-183); the group stays NotReady until every mover rests, then Standby, and moves."""
    rt, group, (follower, leader) = convoy(GapControlMode.FAST)
    watch = Watch(rt, group, [follower, leader])
    leader.power(False)
    watch.run(cycles=20)
    assert leader.set_velocity > 0.0
    assert leader.power()
    watch.run(cycles=1)
    assert leader.state is AxisState.STOPPING and leader.set_velocity > 0.0
    assert group.state is GroupState.NOT_READY
    watch.run()
    assert watch.min_gap >= GAP - TOLERANCE and watch.false_rest == []
    assert watch.max_step <= DYNAMICS["max_deceleration"] * rt.cycle_time * (1 + 1e-9)
    assert group.state is GroupState.STANDBY
    assert leader.state is AxisState.STANDSTILL
    move = group.move_relative(leader, 200.0, 500.0)
    rt.run_until(lambda: move.done, timeout=5.0)


# -- point 4: the state of braking movers (D-184) ----------------------------------------------

def test_movers_braking_after_a_group_error_report_stopping_until_rest() -> None:
    """Issue 19 point 4: after a member's error the others braked while reporting StandStill
    (up to 1150 mover-cycles in a 6-mover run). Now: Stopping while they move, StandStill at
    rest; the failed mover ErrorStop throughout (TcMC state diagram, Part 4 §3.1; D-184)."""
    rt, group, axes = convoy(GapControlMode.STANDARD, n=6, velocity=1800.0, ring=True)
    failed = group.movers[2].axis
    watch = Watch(rt, group, axes)
    failed.fault(ErrorId.FOLLOWING_ERROR, "test")
    watch.run()
    assert group.state is GroupState.ERROR_STOP
    assert watch.false_rest == []
    for axis in axes:
        seen = watch.states[axis.name]
        if axis is failed:
            assert set(seen) == {AxisState.ERROR_STOP}
        else:
            assert seen[0] is AxisState.STOPPING and seen[-1] is AxisState.STANDSTILL
    assert watch.min_gap >= GAP - TOLERANCE
    assert watch.max_step <= DYNAMICS["max_deceleration"] * rt.cycle_time * (1 + 1e-9)


def test_following_error_of_a_stalled_mover_brakes_the_group_in_time() -> None:
    """The drive's following-error monitor (Runtime phase 3) of a stalled mover: the group
    goes to GroupErrorStop and every mover brakes from the state of the fault's cycle."""
    rt, group, (follower, leader) = convoy(GapControlMode.FAST)
    # the mechanics stall: the actual position stops following
    rt.axis_system.kernel.set_blocked(leader.row, True)
    watch = Watch(rt, group, [follower, leader])
    watch.run()
    assert leader.state is AxisState.ERROR_STOP
    assert leader.axis_error_id is ErrorId.FOLLOWING_ERROR
    assert group.state is GroupState.ERROR_STOP and group.error_id is ErrorId.FOLLOWING_ERROR
    assert watch.min_gap >= GAP - TOLERANCE and watch.false_rest == []
    assert watch.max_step <= DYNAMICS["max_deceleration"] * rt.cycle_time * (1 + 1e-9)


def test_group_reset_waits_for_the_brakes_then_the_group_moves_again() -> None:
    """MC_GroupReset during the error reaction stays Busy until every mover rests (as MC_Reset
    does, D-019), so gap control never takes over a moving mover as if it stood (D-184)."""
    rt, group, (follower, leader) = convoy(GapControlMode.FAST)
    follower.fault(ErrorId.FOLLOWING_ERROR, "test")
    rt.step()
    reset = group.reset()
    assert reset.busy
    moving = 0
    while reset.busy:
        moving += not group.all_axes_standing
        rt.step()
    assert reset.done and moving > 10 and group.all_axes_standing
    assert group.state is GroupState.STANDBY
    assert (follower.state, leader.state) == (AxisState.STANDSTILL, AxisState.STANDSTILL)
    move = group.move_relative(follower, -300.0, 500.0)
    rt.run_until(lambda: move.done, timeout=5.0)


def test_a_braking_mover_is_removed_only_at_rest_and_then_stands() -> None:
    """MC_RemoveAxisFromGroup refuses a mover that still brakes (AXIS_MOVING, §9.3.1.1.8);
    once it rests it leaves the group in StandStill, or Disabled without power."""
    rt, group, (follower, leader) = convoy(GapControlMode.STANDARD)
    leader.power(False)
    rt.step()
    refused = group.remove_axis(UDINT_TO_IDENTINGROUP(2))
    assert refused.error and refused.error_id is ErrorId.AXIS_MOVING
    rt.run_until(lambda: group.all_axes_standing, timeout=5.0)
    removed = group.remove_axis(UDINT_TO_IDENTINGROUP(2))
    assert removed.done and leader.group is None
    assert leader.state is AxisState.DISABLED
    rt.step()
    assert group.state is GroupState.STANDBY and follower.state is AxisState.STANDSTILL


def test_power_off_and_on_within_one_cycle_still_stops_the_group() -> None:
    """A power blip (MC_Power off and on again before the next cycle) is a power loss: the
    group goes NotReady and every mover brakes (D-065, D-183); it moves again afterwards."""
    rt, group, (follower, leader) = convoy(GapControlMode.FAST)
    watch = Watch(rt, group, [follower, leader])
    leader.power(False)
    assert leader.power()
    watch.run(cycles=1)
    assert group.state is GroupState.NOT_READY
    assert (follower.state, leader.state) == (AxisState.STOPPING, AxisState.STOPPING)
    watch.run()
    assert watch.min_gap >= GAP - TOLERANCE and watch.false_rest == []
    assert group.state is GroupState.STANDBY and leader.state is AxisState.STANDSTILL
    move = group.move_relative(leader, 200.0, 500.0)
    rt.run_until(lambda: move.done, timeout=5.0)
