"""The scenarios of the TF5410 manual as tests with their numbers (digest D5 T1-T11).

T12-T14 and T16 are in test_blocks.py and test_modulo.py, T15 in test_gear_in_pos.py.
Defaults unless stated: ring, rail 3000 mm, default gap 100 mm, Standard, direction Both.
"""

from __future__ import annotations

import numpy as np
import pytest

import openmotion as om
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GapControlDirection,
    GapControlMode,
    GroupState,
)

XTS = {"max_velocity": 4000.0, "acceleration": 10000.0, "deceleration": 10000.0,
       "jerk": 100000.0, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
       "max_jerk": 100000.0}


def group_of(positions: list[float], **parameters: object) -> tuple[om.Runtime, CaGroup,
                                                                    list[om.Axis]]:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", **parameters)
    axes = []
    for i, position in enumerate(positions):
        axis = rt.add_axis(f"m{i + 1}", position=position, **XTS)
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
        axes.append(axis)
    assert group.enable().done
    return rt, group, axes


def run(rt: om.Runtime, group: CaGroup, seconds: float) -> tuple[float, float]:
    """Run; the smallest and largest setpoint gap seen (every cycle)."""
    low, high = np.inf, 0.0
    for _ in range(round(seconds / rt.cycle_time)):
        rt.step()
        gaps = group.gaps()
        gaps = gaps[np.isfinite(gaps)]
        low, high = min(low, gaps.min()), max(high, gaps.max())
    return low, high


# -- T1 basics (§8.1.1) ---------------------------------------------------------------------


def test_t1_ca_order_follows_positions_not_identities() -> None:
    rt, group, axes = group_of([600.0, 1350.0, 150.0, 900.0])
    assert group.order == ["m2", "m4", "m1", "m3"]  # the largest position is first
    assert group.state is GroupState.STANDBY and group.axes_count == 4


def test_t1_equal_positions_the_last_added_is_first() -> None:
    rt, group, axes = group_of([0.0, 0.0, 0.0])
    assert group.order == ["m3", "m2", "m1"]


def test_t1_enable_moves_nobody_and_violated_gaps_stay() -> None:
    rt, group, axes = group_of([0.0, 50.0, 80.0])
    rt.run(0.5)
    assert [a.set_position for a in axes] == [0.0, 50.0, 80.0]


def test_t1_ten_movers_line_up_behind_the_leader() -> None:
    starts = [150.0 * i for i in range(10)]
    rt, group, axes = group_of(starts)
    commands = [group.move_absolute(a, 2500.0, 1000.0) for a in axes]
    low, _ = run(rt, group, 3.0)
    ends = sorted((a.set_position for a in axes), reverse=True)
    assert ends == [2500.0 - 100.0 * k for k in range(10)]  # exactly
    assert low >= 100.0 - 1e-9
    leader = max(range(10), key=lambda i: starts[i])
    assert commands[leader].done
    assert all(c.busy for i, c in enumerate(commands) if i != leader)  # queued: Busy (D-062)
    assert group.predecessor(axes[leader]) is axes[0]  # the leader's predecessor: the last


# -- T2 / T3 Standard and Fast (§8.1.2) -------------------------------------------------------


@pytest.mark.parametrize("mode", [GapControlMode.STANDARD, GapControlMode.FAST])
def test_t2_t3_four_movers_one_lap(mode: GapControlMode) -> None:
    rt, group, axes = group_of([0.0, -100.0, -200.0, -300.0], default_gap_control_mode=mode)
    for axis in axes:
        group.move_absolute(axis, 3000.0, 1000.0)
    first_motion: dict[str, float] = {}
    low, high = np.inf, 0.0
    for _ in range(5000):
        rt.step()
        for axis in axes:
            if axis.set_velocity > 0.0:
                first_motion.setdefault(axis.name, rt.now)
            assert axis.set_velocity >= 0.0  # nobody is pushed backwards
        gaps = group.gaps()[1:]
        low, high = min(low, gaps.min()), max(high, gaps.max())
    assert [a.set_position for a in axes] == [3000.0, 2900.0, 2800.0, 2700.0]
    assert low >= 100.0 - 1e-9
    if mode is GapControlMode.STANDARD:  # fan out while accelerating, one after another
        assert high > 200.0
        assert sorted(first_motion.values()) == list(first_motion.values())
        assert len(set(first_motion.values())) == 4
    else:  # all start together with full dynamics; gaps stay at the minimum
        assert set(first_motion.values()) == {0.001}
        assert high <= 100.0 + 1e-6


def test_t4_both_and_fast_is_accepted() -> None:
    rt, group, axes = group_of([0.0, -100.0], gap_control_direction=GapControlDirection.BOTH,
                               default_gap_control_mode=GapControlMode.FAST)
    command = group.move_absolute(axes[1], 500.0, 1000.0, gap_control_mode=GapControlMode.FAST)
    assert not command.error  # V3.3.19 profile (digest D1.7)


# -- T5 reverse motion (§8.1.3) ---------------------------------------------------------------


def test_t5_both_holds_a_predecessor_moving_back_at_the_gap() -> None:
    rt, group, axes = group_of([500.0, 300.0], rail_is_ring=False)
    command = group.move_absolute(axes[0], 0.0, 1000.0)  # backwards, onto m2 at 300
    low, _ = run(rt, group, 2.0)
    assert axes[0].set_position == pytest.approx(400.0, abs=1e-9)
    assert low >= 100.0 - 1e-9 and command.busy


def test_t5_positive_does_not_protect_a_mover_moving_back() -> None:
    rt, group, axes = group_of([500.0, 300.0], rail_is_ring=False,
                               gap_control_direction=GapControlDirection.POSITIVE)
    command = group.move_absolute(axes[0], 0.0, 1000.0)
    rt.run(2.0)
    assert command.done and axes[0].set_position == 0.0  # through m2: the user's problem


# -- T6 / T8 / T9 standby gap control (§6, §9.3.1.2.1) ------------------------------------------


def test_t6_standby_gap_control_opens_the_gap_with_the_group_defaults() -> None:
    rt, group, axes = group_of([1000.0, 1050.0], rail_is_ring=False, standby_gap_control=True)
    peak_v = peak_a = 0.0
    for _ in range(2000):
        rt.step()
        peak_v = max(peak_v, abs(axes[0].set_velocity))
        peak_a = max(peak_a, abs(axes[0].set_acceleration))
    assert axes[1].set_position - axes[0].set_position == pytest.approx(100.0, abs=1e-9)
    assert axes[1].set_position == 1050.0  # the successor gives way
    assert peak_v == pytest.approx(150.0) and peak_a == pytest.approx(1000.0)
    assert group.state is GroupState.STANDBY


def test_t6_without_standby_nothing_moves() -> None:
    rt, group, axes = group_of([1000.0, 1050.0], rail_is_ring=False)
    rt.run(1.0)
    assert [a.set_position for a in axes] == [1000.0, 1050.0]


def test_t6_standby_pushes_down_the_row() -> None:
    rt, group, axes = group_of([1000.0, 1050.0, 1075.0], rail_is_ring=False,
                               standby_gap_control=True)
    rt.run(3.0)
    assert [a.set_position for a in axes] == pytest.approx([875.0, 975.0, 1075.0], abs=1e-9)


@pytest.mark.parametrize("mode", [GapControlMode.STANDARD, GapControlMode.FAST])
def test_positive_standby_gives_way_to_a_predecessor_moving_back(mode: GapControlMode) -> None:
    """§8.1.3: with direction Positive the successor alone keeps the gap; §6: standby gap
    control keeps it for movers without a command too (D-208). A predecessor backing at
    120 mm/s onto a standing successor took the gap to 60 mm of 140 before, though the
    standby dynamics (200 mm/s) could keep it; the row behind gives way in turn."""
    rt, group, axes = group_of([1200.0, 1000.0, 850.0], rail_is_ring=False,
                               standby_gap_control=True, default_gap=140.0,
                               default_velocity=200.0, default_gap_control_mode=mode,
                               gap_control_direction=GapControlDirection.POSITIVE)
    back = group.move_absolute(axes[0], 900.0, 120.0)
    peak = 0.0
    low = np.inf
    for _ in range(4000):
        rt.step()
        low = min(low, group.gaps()[1:].min())
        peak = max(peak, abs(axes[1].set_velocity), abs(axes[2].set_velocity))
    assert low >= 140.0 - 1e-9
    assert back.done and axes[0].set_position == 900.0  # the predecessor is not held
    assert [a.set_position for a in axes[1:]] == pytest.approx([760.0, 620.0], abs=1e-9)
    assert peak <= 200.0 * (1 + 1e-9)  # with the standby dynamics
    assert group.state is GroupState.STANDBY


def test_both_with_standby_holds_the_predecessor_and_the_successor_stays() -> None:
    """§8.1.3: with direction Both the predecessor keeps the gap itself: it waits one gap
    ahead and the standing successor does not move (D-208)."""
    rt, group, axes = group_of([1200.0, 1000.0], rail_is_ring=False, standby_gap_control=True,
                               default_gap=140.0, default_velocity=200.0)
    back = group.move_absolute(axes[0], 900.0, 120.0)
    low, _ = run(rt, group, 4.0)
    assert low >= 140.0 - 1e-9 and back.busy
    assert [a.set_position for a in axes] == pytest.approx([1140.0, 1000.0], abs=1e-9)


def test_t9_after_a_none_command_standby_keeps_the_last_valid_gap() -> None:
    rt, group, axes = group_of([1000.0, 1200.0], rail_is_ring=False, standby_gap_control=True)
    first = group.move_absolute(axes[0], 1000.5, 100.0, gap=150.0)  # gap 150 is valid now
    rt.run_until(lambda: first.done, timeout=5.0)
    none = group.move_absolute(axes[0], 1100.0, 500.0, gap_control_mode=GapControlMode.NONE)
    rt.run_until(lambda: none.done, timeout=5.0)  # closer than 150: nobody stops it
    assert axes[1].set_position - axes[0].set_position == pytest.approx(100.0)
    rt.run(3.0)  # standby restores the last valid gap, 150, not the default 100
    assert axes[1].set_position - axes[0].set_position == pytest.approx(150.0, abs=1e-9)


# -- T10 ContinuousUpdate, T11 a blocked mover ---------------------------------------------------


@pytest.mark.parametrize("continuous", [True, False])
def test_t10_continuous_update_takes_a_new_gap_at_once(continuous: bool) -> None:
    rt, group, axes = group_of([2000.0, 0.0], rail_is_ring=False)
    command = group.move_absolute(axes[1], 3000.0, 1000.0, continuous_update=continuous)
    rt.run(0.5)
    group.set_gap(command, 200.0)
    rt.run(3.0)
    expected = 200.0 if continuous else 100.0
    assert axes[0].set_position - axes[1].set_position == pytest.approx(expected, abs=1e-9)


def test_t11_a_mover_behind_a_standing_leader_waits_busy_then_goes_on() -> None:
    rt, group, axes = group_of([1000.0, 0.0], rail_is_ring=False)
    command = group.move_absolute(axes[1], 2000.0, 1000.0)
    rt.run(3.0)
    assert axes[1].set_position == pytest.approx(900.0, abs=1e-9)
    assert command.busy and command.active and not command.done
    group.move_absolute(axes[0], 2500.0, 1000.0)  # the leader moves on
    rt.run_until(lambda: command.done, timeout=5.0)
    assert axes[1].set_position == 2000.0


# -- T7 active gap establishing (§6, V3.3.19) ----------------------------------------------------


@pytest.mark.parametrize("establishing", [False, True])
def test_t7_active_gap_establishing(establishing: bool) -> None:
    rt, group, axes = group_of([1000.0, 1050.0], rail_is_ring=False,
                               active_gap_establishing=establishing)
    rt.run(2.0)
    gap = axes[1].set_position - axes[0].set_position
    if establishing:  # CA moves the successor back to the gap (V3.2 behaviour, D-067)
        assert gap == pytest.approx(100.0, abs=1e-9)
    else:  # V3.3 default: CA only delays and brakes, it never creates motion
        assert gap == 50.0


def test_t11_a_held_mover_with_softer_command_dynamics_never_turns_back() -> None:
    """Gap control may brake harder than the command (the axis maxima); the mover must not
    turn round to make up for it (a reproducer from review)."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca")
    axes = []
    for i, position in enumerate((1300.0, 500.0)):
        axis = rt.add_axis(f"m{i + 1}", position=position, max_deceleration=20000.0,
                           max_jerk=1e6)
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
        axes.append(axis)
    group.enable()
    command = group.move_absolute(axes[1], 1350.0, 400.0, gap=100.0)
    lowest = 0.0
    for _ in range(4000):
        rt.step()
        lowest = min(lowest, axes[1].set_velocity)
    assert lowest >= 0.0
    assert axes[1].set_position == pytest.approx(1200.0, abs=1e-9) and command.busy


def test_t1_cyclic_group_interface_after_enable() -> None:
    """§8.1.1 / §11.1: after MC_GroupEnable a PLC reads Standby and ten axes."""
    rt, group, axes = group_of([150.0 * i for i in range(10)])
    status = group.nc_to_plc
    assert status.group_state is GroupState.STANDBY and status.group_axes_count == 10
    assert status.is_enable_requested and status.group_error_id == 0
    assert int(status.group_type) == 1  # mcGroupTypeCA
    group.disable()
    assert group.nc_to_plc.group_state is GroupState.DISABLED
    assert not group.nc_to_plc.is_enable_requested


@pytest.mark.parametrize("stop", [False, True])
def test_t8_group_halt_with_standby_opens_the_gap_before_it_is_done(stop: bool) -> None:
    """§9.3.1.2.1: with standby gap control an undershot gap is opened before MC_GroupHalt
    is Done (we brake first, then open it, D-067); MC_GroupStop is Done at standstill."""
    rt, group, axes = group_of([1000.0, 800.0], rail_is_ring=False, standby_gap_control=True)
    group.move_absolute(axes[1], 960.0, 200.0, gap_control_mode=GapControlMode.NONE)
    rt.run_until(lambda: axes[1].set_position >= 920.0, timeout=5.0)  # gap 80 < 100
    command = group.stop() if stop else group.halt()
    rt.run_until(lambda: command.done, timeout=10.0)
    gap = axes[0].set_position - axes[1].set_position
    if stop:
        assert gap < 100.0 and group.state is GroupState.STOPPING
        command.release()
        rt.run(3.0)  # released: standby opens the gap now
        assert axes[0].set_position - axes[1].set_position == pytest.approx(100.0, abs=1e-9)
    else:
        assert gap == pytest.approx(100.0, abs=1e-9) and group.all_axes_standing
