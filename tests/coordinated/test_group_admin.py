"""The Part 4 axes group at work: grouping, life cycle, states, reads and override.

PLCopen Part 4 §3-§5 (digest §2, §3; rules 22-44, 48-61, 67-70, 90-95 of digest §6).
tests/coordinated/test_states.py checks the state tables on their own; here a real
``AxesGroup`` with real axes runs them, through the Python API (methods returning a
``Command``) and through the FBs.

Timing convention as in tests/transport/test_blocks.py: every FB is called once per cycle,
before ``rt.step()``; a rising edge acts at once, so its outputs show in the same call.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import openmotion as om
from openmotion.coordinated.blocks import (
    MC_AddAxisToGroup,
    MC_GroupDisable,
    MC_GroupEnable,
    MC_GroupHalt,
    MC_GroupHome,
    MC_GroupReadActualPosition,
    MC_GroupReadConfiguration,
    MC_GroupReadError,
    MC_GroupReadStatus,
    MC_GroupReset,
    MC_GroupSetOverride,
    MC_GroupStop,
    MC_MoveLinearAbsolute,
    MC_MoveLinearRelative,
    MC_RemoveAxisFromGroup,
    MC_UngroupAllAxes,
)
from openmotion.coordinated.frames import Frame
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem
from openmotion.coordinated.kinematics import CartesianGantry
from openmotion.coordinated.states import AxesGroupState
from openmotion.core.enums import AxisState, BufferMode, ReferenceMode
from openmotion.plcopen.stop import MC_Stop

G = AxesGroupState
S = AxisState
ErrorId = om.ErrorId
AXIS = {"max_velocity": 1000.0, "max_acceleration": 20000.0, "max_deceleration": 20000.0,
        "max_jerk": 1.0e6}
TOL = 1e-6  #: [mm]


def group_of(*start: float, enable: bool = True, **parameters: Any
             ) -> tuple[om.Runtime, AxesGroup, list[om.Axis]]:
    """Powered axes at ``start`` with IdentInGroup 1, 2, ... in a new group."""
    rt = om.Runtime()
    group = AxesGroup(rt, "g")
    axes = []
    for ident, position in enumerate(start, 1):
        axis = rt.add_axis(f"a{ident}", position=position, **{**AXIS, **parameters})
        assert axis.power()
        assert group.add_axis(axis, ident).done
        axes.append(axis)
    if enable:
        assert group.enable().done
    return rt, group, axes


def drive(rt: om.Runtime, *calls: Callable[[], Any], until: Callable[[], bool],
          limit: int = 20000) -> int:
    """Call ``calls`` and step until ``until()`` holds after the calls; the cycles taken."""
    for cycle in range(limit):
        for call in calls:
            call()
        if until():
            return cycle
        rt.step()
    raise AssertionError(f"not reached within {limit} cycles")


def outputs(fb: Any) -> tuple[bool, bool, bool, bool, bool]:
    """busy, active, done, command_aborted, error."""
    return fb.busy, fb.active, fb.done, fb.command_aborted, fb.error


def tcp(group: AxesGroup, coord: CoordSystem = CoordSystem.MCS) -> np.ndarray:
    return group.position(coord)


def set_velocities(group: AxesGroup) -> np.ndarray:
    return np.array([axis.set_velocity for axis in group.axes])


def moving_group(**parameters: Any) -> tuple[om.Runtime, AxesGroup, list[om.Axis], om.Command]:
    """A three-axis group cruising on a 200 mm line at 100 mm/s."""
    rt, group, axes = group_of(0.0, 0.0, 0.0, **parameters)
    move = group.move_linear_absolute([200.0, 0.0, 0.0], velocity=100.0)
    rt.run(0.3)
    assert move.active and group.state is G.MOVING
    return rt, group, axes, move


def homing_group() -> tuple[om.Runtime, AxesGroup, list[om.Axis], om.Command]:
    """A group whose members search the next sync pulse (10 mm away): homing for a while."""
    rt, group, axes = group_of(-7.0, -7.0, reference_mode=ReferenceMode.SYNC_PULSE)
    home = group.home([1.0, 2.0])
    rt.step()
    assert home.busy and group.state is G.HOMING
    return rt, group, axes, home


def in_state(state: G) -> tuple[om.Runtime, AxesGroup, list[om.Axis]]:
    """A group brought to ``state`` by the commands that lead there."""
    if state is G.DISABLED:
        return group_of(0.0, 0.0, 0.0, enable=False)
    if state is G.HOMING:
        rt, group, axes, _ = homing_group()
        return rt, group, axes
    if state is G.STANDBY:
        return group_of(0.0, 0.0, 0.0)
    rt, group, axes, _ = moving_group()
    if state is G.STOPPING:
        assert group.stop().busy
    elif state is G.ERROR_STOP:
        axes[1].fault(ErrorId.FOLLOWING_ERROR, "test fault")
        rt.step()
    assert group.state is state
    return rt, group, axes


ALL = [G.DISABLED, G.STANDBY, G.HOMING, G.MOVING, G.STOPPING, G.ERROR_STOP]


# -- grouping and life cycle (§4.1, §5.1-§5.6; rules 22-35) -----------------------------------


def test_rule22_a_new_group_is_empty_and_disabled():
    rt = om.Runtime()
    group = AxesGroup(rt, "g")
    status = MC_GroupReadStatus(group)
    status(enable=True)
    assert group.members == {} and group.axes == []
    assert group.state is G.DISABLED
    assert status.valid and status.group_disabled
    assert not (status.group_standby or status.group_moving or status.group_error_stop)


def test_rule23_a_taken_ident_in_group_is_an_error_and_changes_nothing():
    rt, group, (a1, a2) = group_of(0.0, 0.0, enable=False)
    a3 = rt.add_axis("a3", **AXIS)
    add = MC_AddAxisToGroup(group)
    add(execute=True, axis=a3, ident_in_group=2)
    assert outputs(add) == (False, False, False, False, True)
    assert add.error_id is ErrorId.IDENT_IN_USE
    assert group.members == {1: a1, 2: a2}
    assert a3.group is None and group.state is G.DISABLED


def test_rule23_an_axis_of_another_group_is_refused():
    rt, group, (a1,) = group_of(0.0, enable=False)
    other = AxesGroup(rt, "other")
    command = other.add_axis(a1, 1)
    assert command.error and command.error_id is ErrorId.AXIS_IN_OTHER_GROUP
    assert other.members == {} and a1.group is group


@pytest.mark.parametrize("state", [G.DISABLED, G.STANDBY], ids=lambda s: s.name)
def test_rule24_adding_axes_in_disabled_and_standby_keeps_the_state(state):
    rt, group, axes = in_state(state)
    extra = rt.add_axis("extra", position=5.0, **AXIS)
    extra.power()
    add = MC_AddAxisToGroup(group)
    add(execute=True, axis=extra, ident_in_group=7)
    assert outputs(add) == (False, False, True, False, False)
    assert group.members[7] is extra and group.state is state
    assert tcp(group, CoordSystem.ACS).tolist() == [0.0, 0.0, 0.0, 5.0]


@pytest.mark.parametrize("state", [G.HOMING, G.MOVING, G.STOPPING, G.ERROR_STOP],
                         ids=lambda s: s.name)
def test_rule24_adding_axes_in_other_states_is_refused(state):
    rt, group, axes = in_state(state)
    extra = rt.add_axis("extra", **AXIS)
    extra.power()
    command = group.add_axis(extra, 9)
    assert command.error and command.error_id is not ErrorId.NO_ERROR
    assert 9 not in group.members and group.state is state and extra.group is None


@pytest.mark.parametrize(("state", "error_id"), [
    (G.HOMING, ErrorId.GROUP_HOMING), (G.MOVING, ErrorId.GROUP_MOVING),
    (G.STOPPING, ErrorId.GROUP_STOPPING)], ids=lambda v: getattr(v, "name", ""))
def test_rule25_remove_while_homing_moving_or_stopping_is_refused(state, error_id):
    rt, group, axes = in_state(state)
    remove = MC_RemoveAxisFromGroup(group)
    remove(execute=True, ident_in_group=2)
    assert outputs(remove) == (False, False, False, False, True)
    assert remove.error_id is error_id
    assert group.members[2] is axes[1] and axes[1].group is group
    assert group.state is state


def test_rule26_removing_the_last_axis_disables_the_group():
    rt, group, (a1,) = group_of(3.0)
    remove = MC_RemoveAxisFromGroup(group)
    remove(execute=True, ident_in_group=1)
    assert remove.done
    assert group.members == {} and group.state is G.DISABLED
    assert a1.group is None and a1.state is S.STANDSTILL


def test_rule26_removing_the_last_axis_in_error_stop_disables_the_group():
    rt, group, (a1,) = group_of(0.0)
    a1.fault(ErrorId.FOLLOWING_ERROR, "test fault")
    rt.step()
    assert group.state is G.ERROR_STOP
    assert group.remove_axis(1).done
    assert group.state is G.DISABLED and group.members == {}


def test_rule27_removing_another_axis_keeps_standby():
    rt, group, (a1, a2, a3) = group_of(1.0, 2.0, 3.0)
    assert group.remove_axis(2).done
    assert group.state is G.STANDBY
    assert group.axes == [a1, a3] and a2.group is None
    assert tcp(group, CoordSystem.ACS).tolist() == [1.0, 3.0]
    move = a2.move_absolute(20.0, velocity=100.0)  # a single axis again
    rt.run_until(move)
    assert move.done and a2.position == pytest.approx(20.0, abs=TOL)


def test_rule28_ungroup_all_leaves_no_axis_and_every_axis_standing_still():
    rt, group, axes = group_of(1.0, 2.0, 3.0)
    ungroup = MC_UngroupAllAxes(group)
    ungroup(execute=True)
    assert outputs(ungroup) == (False, False, True, False, False)
    assert group.members == {} and group.state is G.DISABLED
    assert all(a.group is None and a.state is S.STANDSTILL for a in axes)


def test_rule28_ungroup_in_error_stop_keeps_the_faulty_axis_in_error():
    rt, group, axes = in_state(G.ERROR_STOP)
    rt.run(0.2)
    assert group.ungroup_all().done
    assert group.state is G.DISABLED
    assert [a.state for a in axes] == [S.STANDSTILL, S.ERROR_STOP, S.STANDSTILL]


def test_rule29_ungroup_while_moving_is_an_error_and_the_move_goes_on():
    rt, group, axes, move = moving_group()
    ungroup = MC_UngroupAllAxes(group)
    ungroup(execute=True)
    assert ungroup.error and ungroup.error_id is ErrorId.GROUP_MOVING
    assert len(group.members) == 3 and group.state is G.MOVING
    rt.run_until(move, timeout=5.0)
    assert move.done
    assert np.allclose(tcp(group), [200.0, 0.0, 0.0], atol=TOL, rtol=0.0)


def test_rule30_enable_a_disabled_group():
    rt, group, axes = group_of(0.0, 0.0, enable=False)
    enable = MC_GroupEnable(group)
    enable(execute=True)
    assert outputs(enable) == (False, False, True, False, False)
    assert group.state is G.STANDBY


def test_rule31_enable_an_empty_group_is_an_error():
    rt = om.Runtime()
    group = AxesGroup(rt, "g")
    enable = MC_GroupEnable(group)
    enable(execute=True)
    assert enable.error and enable.error_id is ErrorId.GROUP_EMPTY
    assert group.state is G.DISABLED


def test_rule32_enable_and_disable_leave_member_power_alone():
    rt, group, (a1, a2) = group_of(0.0, 0.0, enable=False)
    a2.power(False)
    assert group.enable().done
    assert (a1.powered, a2.powered) == (True, False)
    assert group.disable().done
    assert (a1.powered, a2.powered) == (True, False)
    assert (a1.state, a2.state) == (S.STANDSTILL, S.DISABLED)


@pytest.mark.parametrize("state", ALL, ids=lambda s: s.name)
def test_rule33_disable_works_in_every_state(state):
    rt, group, axes = in_state(state)
    disable = MC_GroupDisable(group)
    disable(execute=True)
    assert outputs(disable) == (False, False, True, False, False)
    assert group.state is G.DISABLED
    rt.run(0.05)
    assert group.state is G.DISABLED
    assert np.all(set_velocities(group) == 0.0)
    assert all(a.state is not S.SYNCHRONIZED_MOTION for a in axes)


def test_rule33_disable_while_moving_holds_the_members_where_they_are():
    rt, group, axes, move = moving_group()
    where = tcp(group, CoordSystem.ACS)
    assert group.disable().done
    assert move.aborted
    rt.run(0.05)
    assert np.array_equal(tcp(group, CoordSystem.ACS), where)


def test_rule33_disable_while_homing_aborts_group_home():
    rt, group, axes, home = homing_group()
    assert group.disable().done
    rt.run(0.1)
    assert home.aborted
    assert all(a.state is not S.HOMING for a in axes)


def test_rule34_read_configuration_in_acs_gives_the_member():
    rt, group, (a1, a2, a3) = group_of(0.0, 0.0, 0.0)
    read = MC_GroupReadConfiguration(group)
    for ident, axis in ((1, a1), (2, a2), (3, a3)):
        read(enable=True, coord_system=CoordSystem.ACS, ident_in_group=ident)
        assert read.valid and not read.error
        assert read.axis_ref is axis
    read(enable=True, ident_in_group=4)
    assert read.error and read.error_id is ErrorId.AXIS_NOT_IN_GROUP
    read(enable=False)
    assert not read.valid and read.axis_ref is None


def test_rule35_read_configuration_in_mcs_is_a_virtual_axis_on_the_tcp():
    rt, group, axes = group_of(1.0, 2.0, enable=False)
    # axis 1 drives y, axis 2 drives x backwards from 100: MCS differs from ACS
    gantry = CartesianGantry(("y", "x"), sign=(1.0, -1.0), offset=(0.0, 100.0))
    assert group.set_kinematics(gantry).done
    assert group.enable().done
    read = MC_GroupReadConfiguration(group)
    read(enable=True, coord_system=CoordSystem.MCS, ident_in_group=1)
    assert read.valid
    x = read.axis_ref
    assert x.position == pytest.approx(98.0, abs=1e-12)  # x = 100 - axis 2
    move = group.move_linear_absolute([40.0, 30.0], velocity=100.0)
    for _ in range(200):
        rt.step()
        assert x.position == pytest.approx(tcp(group)[0], abs=1e-12)
    rt.run_until(move, timeout=5.0)
    assert x.position == pytest.approx(40.0, abs=TOL)
    assert tcp(group, CoordSystem.ACS) == pytest.approx([30.0, 60.0], abs=TOL)


# -- states and member axes (§3, Table 5; rules 36-44, 48) --------------------------------------


def test_rule36_a_motion_makes_the_group_moving_and_members_synchronized():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[30.0, 40.0, 0.0], velocity=100.0)
    assert outputs(move) == (True, True, False, False, False)
    assert group.state is G.MOVING
    assert all(a.state is S.SYNCHRONIZED_MOTION for a in axes)


def test_rule37_standby_after_the_last_motion_is_done():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    first, second = MC_MoveLinearAbsolute(group), MC_MoveLinearRelative(group)
    first(execute=True, position=[20.0, 0.0, 0.0], velocity=100.0)
    second(execute=True, distance=[0.0, 20.0, 0.0], velocity=100.0,
           buffer_mode=BufferMode.BUFFERED)
    assert outputs(second) == (True, False, False, False, False)  # buffered: busy only
    drive(rt, first, second, until=lambda: first.done)
    assert group.state is G.MOVING and second.active  # the second one takes over at once
    drive(rt, first, second, until=lambda: second.done)
    assert outputs(second) == (False, False, True, False, False)
    rt.step()
    assert group.state is G.STANDBY
    assert all(a.state is S.STANDSTILL for a in axes)
    assert np.allclose(tcp(group), [20.0, 20.0, 0.0], atol=TOL, rtol=0.0)


def test_rule38_stop_is_stopping_at_once_and_done_in_the_first_cycle_at_rest():
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True, deceleration=500.0)
    assert group.state is G.STOPPING
    assert all(a.state is S.SYNCHRONIZED_MOTION for a in axes)  # Table 5
    assert outputs(stop) == (True, True, False, False, False)
    assert move.aborted
    while True:
        rt.step()
        stop()
        at_rest = bool(np.all(set_velocities(group) == 0.0))
        assert stop.done is at_rest
        if at_rest:
            break
    assert group.state is G.STOPPING


def test_rule39_stopping_holds_while_execute_then_standby_with_outputs_reset():
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True)
    drive(rt, stop, until=lambda: stop.done)
    for _ in range(50):  # t2: at rest, Execute still TRUE
        rt.step()
        stop()
        assert group.state is G.STOPPING
        assert (stop.done, stop.busy, stop.active) == (True, True, True)
    stop(execute=False)  # t3
    assert outputs(stop) == (False, False, False, False, False)
    rt.step()
    assert group.state is G.STANDBY
    assert all(a.state is S.STANDSTILL for a in axes)


def test_rule40_a_short_stop_pulse_ends_stopping_at_standstill():
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True)
    rt.step()
    stop(execute=False)
    assert stop.busy and group.state is G.STOPPING
    seen_done = 0
    while group.state is G.STOPPING:
        rt.step()
        stop()
        seen_done += stop.done
    assert group.state is G.STANDBY
    assert np.all(set_velocities(group) == 0.0)
    assert seen_done == 1 and stop.done  # shown for one call, Execute being FALSE
    stop()
    assert outputs(stop) == (False, False, False, False, False)


def test_rules41_42_fig12_stop_refuses_moves_until_released():
    """§5.13 Fig. 12: edge 1 starts a move, the stop aborts it, edge 2 is refused with an
    FB error only, edge 3 after the stop was released moves the group."""
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    exe1, stop = MC_MoveLinearRelative(group), MC_GroupStop(group)
    exe1(execute=True, distance=[100.0, 0.0, 0.0], velocity=100.0)  # edge 1
    drive(rt, exe1, until=lambda: group.position(CoordSystem.MCS)[0] > 20.0)
    stop(execute=True)
    exe1()
    assert outputs(exe1) == (False, False, False, True, False)
    exe1(execute=False)
    rt.step()
    exe1(execute=True)  # edge 2, while Stop.Execute is TRUE
    assert outputs(exe1) == (False, False, False, False, True)
    assert exe1.error_id is ErrorId.GROUP_STOPPING
    assert group.state is G.STOPPING  # not GroupErrorStop
    drive(rt, stop, exe1, until=lambda: stop.done)
    at = tcp(group).copy()
    stop(execute=False)
    exe1(execute=False)
    rt.step()
    assert group.state is G.STANDBY
    exe1(execute=True)  # edge 3
    assert outputs(exe1) == (True, True, False, False, False)
    drive(rt, exe1, until=lambda: exe1.done)
    assert np.allclose(tcp(group), at + [100.0, 0.0, 0.0], atol=TOL, rtol=0.0)


@pytest.mark.parametrize("intruder", ["halt", "move", "stop"])
def test_rule43_neither_halt_nor_a_move_aborts_a_stop(intruder):
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True)
    rt.step()
    if intruder == "halt":
        command = group.halt()
    elif intruder == "move":
        command = group.move_linear_absolute([0.0, 50.0, 0.0])
    else:
        command = group.stop()
    assert command.error and command.error_id is ErrorId.GROUP_STOPPING
    stop()
    assert stop.busy and stop.active and not stop.command_aborted
    assert group.state is G.STOPPING


def test_rule43_disable_aborts_a_stop():
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True)
    rt.step()
    assert group.disable().done
    stop()
    assert outputs(stop) == (False, False, False, True, False)
    assert group.state is G.DISABLED


def test_rule44_stop_aborts_the_active_and_every_buffered_motion():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    moves = [MC_MoveLinearRelative(group) for _ in range(3)]
    for index, fb in enumerate(moves):
        fb(execute=True, distance=[0.0, 30.0, 0.0] if index % 2 else [30.0, 0.0, 0.0],
           velocity=100.0, buffer_mode=BufferMode.ABORTING if index == 0
           else BufferMode.BUFFERED)
    drive(rt, *moves, until=lambda: tcp(group)[0] > 10.0)
    stop = MC_GroupStop(group)
    stop(execute=True)
    for fb in moves:
        fb()
        assert outputs(fb) == (False, False, False, True, False)


def test_rule48_power_off_of_a_member_aborts_the_stop_and_disables_the_group():
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True, deceleration=100.0)
    rt.step()
    axes[2].power(False)
    rt.step()
    stop()
    assert outputs(stop) == (False, False, False, True, False)
    assert group.state is G.DISABLED


# -- errors (§3.1, §3.2, §5.18, §5.19, Note 2; rules 49-54) --------------------------------


@pytest.mark.parametrize("state", [G.STANDBY, G.HOMING, G.MOVING, G.STOPPING],
                         ids=lambda s: s.name)
def test_rules49_54_a_member_in_error_stop_puts_the_group_in_group_error_stop(state):
    rt, group, axes = in_state(state)
    axes[0].fault(ErrorId.FOLLOWING_ERROR, "test fault")
    rt.step()
    assert group.state is G.ERROR_STOP
    assert group.error_id is ErrorId.GROUP_ERROR


def test_rule49_a_real_following_error_stops_a_moving_group():
    rt = om.Runtime()
    group = AxesGroup(rt, "g")
    lagging = rt.add_axis("lagging", drive=om.DriveModel(model="lag", time_constant=0.05),
                          max_position_lag=0.5, **AXIS)
    fine = rt.add_axis("fine", **AXIS)
    for ident, axis in enumerate((lagging, fine), 1):
        axis.power()
        group.add_axis(axis, ident)
    group.enable()
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[100.0, 100.0], velocity=200.0)
    drive(rt, move, until=lambda: group.state is not G.MOVING, limit=3000)
    assert group.state is G.ERROR_STOP and lagging.state is S.ERROR_STOP
    assert outputs(move) == (False, False, False, False, True)
    assert move.error_id is ErrorId.GROUP_ERROR


def test_rule50_group_error_stop_leaves_the_healthy_members_alone():
    rt, group, axes, move = moving_group()
    axes[0].fault(ErrorId.FOLLOWING_ERROR, "test fault")
    rt.run(0.5)
    assert group.state is G.ERROR_STOP
    assert axes[0].state is S.ERROR_STOP
    assert axes[1].state is not S.ERROR_STOP and axes[2].state is not S.ERROR_STOP
    assert axes[1].powered and axes[2].powered
    assert np.all(set_velocities(group) == 0.0)  # each healthy axis braked on its own


def member_jump(rt: om.Runtime, axis: om.Axis, cycles: int = 50) -> float:
    """The largest change of ``axis``' set position in one cycle over ``cycles`` cycles."""
    largest, previous = 0.0, axis.set_position
    for _ in range(cycles):
        rt.step()
        largest = max(largest, abs(axis.set_position - previous))
        previous = axis.set_position
    return largest


def test_rule50_healthy_members_brake_from_where_they_are():
    rt, group, axes, move = moving_group()  # axis 1 at 20 mm, 100 mm/s
    axes[1].fault(ErrorId.FOLLOWING_ERROR, "test fault")
    assert member_jump(rt, axes[0]) <= 100.0 * rt.cycle_time * (1 + 1e-6)
    assert axes[0].set_position > 20.0


def test_rule48_power_loss_of_a_member_holds_the_others_where_they_are():
    rt, group, axes, move = moving_group()
    axes[2].power(False)
    assert member_jump(rt, axes[0]) <= 100.0 * rt.cycle_time * (1 + 1e-6)
    assert group.state is G.DISABLED


REFUSED_IN_ERROR_STOP: dict[str, Callable[[om.Runtime, AxesGroup], om.Command]] = {
    "MoveLinearAbsolute": lambda rt, g: g.move_linear_absolute([1.0, 0.0, 0.0]),
    "MoveLinearRelative": lambda rt, g: g.move_linear_relative([1.0, 0.0, 0.0]),
    "MoveCircularAbsolute": lambda rt, g: g.move_circular_absolute([1.0, 1.0, 0.0],
                                                                   [2.0, 0.0, 0.0]),
    "MoveDirectAbsolute": lambda rt, g: g.move_direct_absolute([1.0, 0.0, 0.0]),
    "MoveDirectRelative": lambda rt, g: g.move_direct_relative([1.0, 0.0, 0.0]),
    "GroupHalt": lambda rt, g: g.halt(),
    "GroupStop": lambda rt, g: g.stop(),
    "GroupInterrupt": lambda rt, g: g.interrupt(),
    "GroupContinue": lambda rt, g: g.continue_(),
    "GroupHome": lambda rt, g: g.home(),
    "GroupEnable": lambda rt, g: g.enable(),
    "GroupSetPosition": lambda rt, g: g.set_position([0.0, 0.0, 0.0]),
    "SetKinTransform": lambda rt, g: g.set_kinematics(CartesianGantry()),
    "SetCartesianTransform": lambda rt, g: g.set_cartesian_transform(Frame()),
    "AddAxisToGroup": lambda rt, g: g.add_axis(rt.add_axis("new", **AXIS), 8),
}


@pytest.mark.parametrize("name", sorted(REFUSED_IN_ERROR_STOP))
def test_rule51_group_error_stop_refuses_every_other_fb(name):
    rt, group, axes = in_state(G.ERROR_STOP)
    command = REFUSED_IN_ERROR_STOP[name](rt, group)
    assert command.error
    assert command.error_id is ErrorId.GROUP_IN_ERROR
    assert group.state is G.ERROR_STOP


def test_rule51_reads_and_override_work_in_group_error_stop():
    rt, group, axes = in_state(G.ERROR_STOP)
    position = MC_GroupReadActualPosition(group)
    override = MC_GroupSetOverride(group)
    position(enable=True)
    override(enable=True, vel_factor=0.5)
    assert position.valid and override.enabled
    assert group.state is G.ERROR_STOP


def test_rules52_53_69_reset_clears_the_group_error_and_leaves_other_fbs_alone():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move, reset, read = (MC_MoveLinearAbsolute(group), MC_GroupReset(group),
                         MC_GroupReadError(group))
    move(execute=True, position=[200.0, 0.0, 0.0], velocity=100.0)
    read(enable=True)
    assert read.valid and read.group_error_id is ErrorId.NO_ERROR
    drive(rt, move, until=lambda: tcp(group)[0] > 10.0)
    axes[1].fault(ErrorId.FOLLOWING_ERROR, "test fault")
    drive(rt, move, read, until=lambda: group.state is G.ERROR_STOP)
    assert read.valid and read.group_error_id is ErrorId.GROUP_ERROR
    assert move.error and move.error_id is ErrorId.GROUP_ERROR
    drive(rt, move, read, until=lambda: np.all(set_velocities(group) == 0.0))
    member_reset = axes[1].reset()  # MC_Reset of the member first
    rt.run_until(member_reset, timeout=1.0)
    reset(execute=True)
    read()
    assert outputs(reset) == (False, False, True, False, False)
    assert group.state is G.STANDBY
    assert read.group_error_id is ErrorId.NO_ERROR
    assert all(a.state is S.STANDSTILL for a in axes)
    move()  # Execute still TRUE: the error stays (rule 53)
    assert move.error and move.error_id is ErrorId.GROUP_ERROR
    move(execute=False)
    assert not move.error


def test_rule52_one_group_reset_resets_a_faulty_member_and_the_group():
    rt, group, axes = in_state(G.ERROR_STOP)
    rt.run(0.2)  # the error reaction is over
    reset = MC_GroupReset(group)
    reset(execute=True)
    drive(rt, reset, until=lambda: not reset.busy, limit=100)
    assert reset.done and not reset.error
    assert group.state is G.STANDBY
    assert all(a.state is S.STANDSTILL for a in axes)


# -- homing (§5.7, Table 5; rules 55-57) ------------------------------------------------------


@pytest.mark.parametrize(("state", "error_id"), [
    (G.DISABLED, ErrorId.GROUP_NOT_ENABLED), (G.MOVING, ErrorId.GROUP_MOVING),
    (G.STOPPING, ErrorId.GROUP_STOPPING), (G.ERROR_STOP, ErrorId.GROUP_IN_ERROR)],
    ids=lambda v: getattr(v, "name", ""))
def test_rule55_group_home_outside_standby_is_an_error(state, error_id):
    rt, group, axes = in_state(state)
    home = MC_GroupHome(group)
    home(execute=True)
    assert outputs(home) == (False, False, False, False, True)
    assert home.error_id is error_id and group.state is state


def test_rule56_group_home_is_homing_then_standby_at_the_position_input():
    rt, group, axes = group_of(3.0, 4.0, reference_mode=ReferenceMode.DIRECT)
    home = MC_GroupHome(group)
    home(execute=True, position=[100.0, 200.0])
    assert home.busy and home.active
    assert group.state is G.HOMING
    drive(rt, home, until=lambda: home.done, limit=100)
    assert group.state is G.STANDBY
    assert tcp(group, CoordSystem.ACS).tolist() == pytest.approx([100.0, 200.0], abs=TOL)
    assert all(a.homed for a in axes)


def test_rule56_members_show_synchronized_motion_while_the_group_homes():
    rt, group, axes, home = homing_group()
    while home.busy:
        assert all(a.state is S.SYNCHRONIZED_MOTION for a in axes)
        rt.step()
    assert home.done
    rt.step()
    assert all(a.state is S.STANDSTILL for a in axes)


def test_rule56_sync_pulse_homing_takes_its_time_and_ends_standby():
    rt, group, axes, home = homing_group()
    rt.run_until(home, timeout=2.0)
    assert home.done
    rt.step()
    assert group.state is G.STANDBY


@pytest.mark.parametrize("mode", [BufferMode.BUFFERED, BufferMode.BLENDING_LOW],
                         ids=lambda m: m.name)
def test_rule57_buffered_group_home_waits_for_the_motion(mode):
    rt, group, axes = group_of(0.0, 0.0, reference_mode=ReferenceMode.DIRECT)
    move, home = MC_MoveLinearAbsolute(group), MC_GroupHome(group)
    move(execute=True, position=[20.0, 0.0], velocity=100.0)
    home(execute=True, position=[0.0, 0.0], buffer_mode=mode)
    assert home.busy and not home.active and not home.error
    assert group.state is G.MOVING
    drive(rt, move, home, until=lambda: home.active, limit=2000)
    assert move.done and group.state is G.HOMING  # the home takes over when the move is Done
    drive(rt, move, home, until=lambda: home.done, limit=2000)
    assert tcp(group, CoordSystem.ACS).tolist() == pytest.approx([0.0, 0.0], abs=TOL)
    rt.step()
    assert group.state is G.STANDBY


def test_rule57_a_move_buffered_behind_a_buffered_home_runs_after_it():
    rt, group, axes = group_of(0.0, 0.0, reference_mode=ReferenceMode.DIRECT)
    move = group.move_linear_absolute([20.0, 0.0], velocity=100.0)
    home = group.home([100.0, 0.0], buffer_mode=BufferMode.BUFFERED)
    after = group.move_linear_relative([5.0, 0.0], buffer_mode=BufferMode.BUFFERED)
    assert after.busy and not after.active
    rt.run_until(home, timeout=2.0)
    assert move.done and home.done and after.busy
    rt.run_until(after, timeout=2.0)
    assert after.done
    assert tcp(group, CoordSystem.ACS).tolist() == pytest.approx([105.0, 0.0], abs=TOL)


@pytest.mark.parametrize("abort", ["move", "halt", "stop"])
def test_rule57_a_waiting_group_home_is_aborted_like_a_buffered_motion(abort):
    rt, group, axes = group_of(0.0, 0.0, reference_mode=ReferenceMode.DIRECT)
    group.move_linear_absolute([20.0, 0.0], velocity=100.0)
    home = group.home([0.0, 0.0], buffer_mode=BufferMode.BUFFERED)
    other = {"move": lambda: group.move_linear_absolute([0.0, 10.0]),
             "halt": group.halt, "stop": group.stop}[abort]()
    assert not other.error
    assert home.aborted
    rt.run(0.5)
    assert not any(a.homed for a in axes)


# -- member axes (§3.2; rules 58-61) ------------------------------------------------------------


def test_rule58_single_axis_stop_on_a_member_makes_the_group_moving():
    rt, group, (a1, a2) = group_of(0.0, 0.0)
    stop = a1.stop()
    assert not stop.error
    assert group.state is G.MOVING


def test_rule58_the_group_is_moving_while_the_member_stop_holds_then_standby():
    rt, group, (a1, a2) = group_of(0.0, 0.0)
    stop = MC_Stop(a1)
    stop(execute=True)
    assert stop.busy or stop.done
    assert group.state is G.MOVING and a1.state is S.STOPPING  # the member shows its own stop
    assert a2.state is S.SYNCHRONIZED_MOTION
    drive(rt, stop, until=lambda: stop.done, limit=100)
    rt.run(0.05)
    assert group.state is G.MOVING and a1.state is S.STOPPING  # Execute still TRUE
    stop(execute=False)
    rt.step()
    rt.step()
    assert group.state is G.STANDBY
    assert all(a.state is S.STANDSTILL for a in (a1, a2))
    assert group.move_linear_absolute([10.0, 0.0]).active  # the group moves again


def test_rule58_single_axis_home_on_a_resting_member_makes_the_group_moving():
    rt, group, (a1, a2) = group_of(3.0, 4.0, reference_mode=ReferenceMode.DIRECT)
    home = a1.home(10.0)
    assert not home.error
    assert group.state is G.MOVING
    rt.run_until(home, timeout=1.0)
    assert home.done and a1.position == pytest.approx(10.0, abs=TOL)
    rt.step()
    assert group.state is G.STANDBY and a1.state is S.STANDSTILL


def test_rule58_single_axis_home_on_a_moving_member_is_refused():
    rt, group, axes, move = moving_group()
    home = axes[0].home()
    assert home.error and home.error_id is ErrorId.AXIS_IN_GROUP
    assert move.active and group.state is G.MOVING


def test_rule58_single_axis_stop_on_a_member_of_a_moving_group_ends_the_group_motion():
    rt, group, axes, move = moving_group()  # axis 1 cruises at 100 mm/s
    buffered = group.move_linear_absolute([0.0, 0.0, 0.0], buffer_mode=BufferMode.BUFFERED)
    stop = axes[0].stop(deceleration=1000.0, jerk=1.0e5)
    assert not stop.error
    assert move.aborted and buffered.aborted  # the group motion ends (decisions D-129)
    assert group.state is G.MOVING and axes[0].state is S.STOPPING
    assert member_jump(rt, axes[0]) <= 100.0 * rt.cycle_time * (1 + 1e-6)  # brakes smoothly
    rt.run_until(stop, timeout=1.0)
    assert stop.done
    rt.step()
    assert group.state is G.STANDBY
    assert all(a.state is S.STANDSTILL and a.set_velocity == 0.0 for a in axes)


def test_rule58_single_axis_stop_on_a_homing_member_aborts_group_home():
    rt, group, axes, home = homing_group()
    stop = axes[0].stop()
    assert not stop.error
    assert home.aborted and group.state is G.MOVING
    rt.run_until(lambda: group.state is G.STANDBY, timeout=1.0)
    assert all(a.state is S.STANDSTILL and a.set_velocity == 0.0 for a in axes)
    assert not any(a.homed for a in axes)


def test_rule58_single_axis_stop_while_the_group_stops_keeps_the_group_stop():
    rt, group, axes, move = moving_group()
    group_stop = MC_GroupStop(group)
    group_stop(execute=True)
    stop = MC_Stop(axes[0])
    stop(execute=True)
    assert not stop.error and group.state is G.STOPPING and group_stop.busy
    drive(rt, group_stop, stop, until=lambda: group_stop.done, limit=1000)
    assert all(a.set_velocity == 0.0 for a in axes)
    group_stop(execute=False)
    rt.step()
    assert group.state is G.MOVING  # the member's MC_Stop still holds (§3.2)
    stop(execute=False)
    rt.step()
    rt.step()
    assert group.state is G.STANDBY and axes[0].state is S.STANDSTILL


def test_rule59_single_axis_move_on_a_member_is_refused_and_the_group_moves_on():
    rt, group, axes, move = moving_group()
    single = axes[1].move_absolute(50.0, velocity=100.0)
    assert single.error and single.error_id is ErrorId.AXIS_IN_GROUP
    rt.run_until(move, timeout=5.0)
    assert move.done
    assert np.allclose(tcp(group), [200.0, 0.0, 0.0], atol=TOL, rtol=0.0)


def test_rule61_halt_keeps_moving_until_done_then_standby():
    rt, group, axes, move = moving_group()
    halt = MC_GroupHalt(group)
    halt(execute=True, deceleration=500.0)
    assert move.aborted
    assert outputs(halt) == (True, True, False, False, False)
    while not halt.done:
        assert group.state is G.MOVING
        rt.step()
        halt()
    assert np.all(set_velocities(group) == 0.0)
    rt.step()
    assert group.state is G.STANDBY


# -- reads (§5.17, §5.18, Part 1 Enable rules; rules 67-70) ------------------------------------

FLAGS = ("group_disabled", "group_standby", "group_homing", "group_moving", "group_stopping",
         "group_error_stop")


@pytest.mark.parametrize("state", ALL, ids=lambda s: s.name)
def test_rule67_read_status_shows_exactly_the_state(state):
    rt, group, axes = in_state(state)
    status = MC_GroupReadStatus(group)
    status(enable=True)
    assert status.valid
    shown = [flag for flag in FLAGS if getattr(status, flag)]
    assert shown == [FLAGS[ALL.index(state)]]
    assert not status.group_not_ready


def test_rule68_motion_flags_are_exclusive_and_follow_the_profile():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    status, move = MC_GroupReadStatus(group), MC_MoveLinearAbsolute(group)
    status(enable=True)
    assert not (status.accelerating or status.decelerating or status.constant_velocity)
    move(execute=True, position=[100.0, 0.0, 0.0], velocity=100.0)
    seen = []
    while not move.done:
        rt.step()
        move()
        status()
        flags = (status.accelerating, status.constant_velocity, status.decelerating)
        assert sum(flags) <= 1
        assert status.in_position is move.done
        if any(flags) and (not seen or seen[-1] != flags.index(True)):
            seen.append(flags.index(True))
    assert seen == [0, 1, 2]  # accelerating, constant, decelerating
    rt.step()
    status()
    assert not (status.accelerating or status.decelerating or status.constant_velocity)
    assert status.in_position


def test_rule70_enable_reads_are_valid_only_while_enabled():
    rt, group, axes = group_of(1.0, 2.0, 3.0)
    read = MC_GroupReadActualPosition(group)
    read(enable=True, coord_system=CoordSystem.ACS)
    assert read.valid and read.busy and not read.error
    assert read.position.tolist() == [1.0, 2.0, 3.0]
    read(enable=False)
    assert not (read.valid or read.busy or read.error)
    assert read.position is None


def test_rule70_a_read_that_fails_is_not_valid():
    rt, group, axes = group_of(1.0, 2.0, 3.0)
    read = MC_GroupReadActualPosition(group)
    read(enable=True, coord_system=CoordSystem.ACS)
    assert read.valid
    read(coord_system=99)
    assert read.error and read.error_id is ErrorId.INVALID_MODE
    assert not read.valid


# -- override (§5.28; rules 90-95) --------------------------------------------------------------


def path_speed_after(rt: om.Runtime, group: AxesGroup, seconds: float) -> float:
    rt.run(seconds)
    return group.velocity(CoordSystem.MCS)[1]


def test_rule90_factors_are_one_without_an_override():
    rt, group, axes, move = moving_group()
    assert group.factors == (1.0, 1.0, 1.0)
    assert path_speed_after(rt, group, 0.1) == pytest.approx(100.0, rel=1e-9)


def test_rule91_vel_factor_half_halves_the_path_speed():
    rt, group, axes, move = moving_group()
    override = MC_GroupSetOverride(group)
    override(enable=True, vel_factor=0.5)
    assert override.enabled and not override.error
    rt.step()
    assert 50.0 < group.velocity(CoordSystem.MCS)[1] < 100.0  # braking, within its limits
    assert path_speed_after(rt, group, 0.3) == pytest.approx(50.0, rel=1e-9)
    rt.run_until(move, timeout=10.0)
    assert np.allclose(tcp(group), [200.0, 0.0, 0.0], atol=TOL, rtol=0.0)


def test_rule92_vel_factor_zero_pauses_without_standby_and_resumes():
    rt, group, axes, move = moving_group()
    override = MC_GroupSetOverride(group)
    override(enable=True, vel_factor=0.0)
    rt.run(0.5)
    assert np.all(set_velocities(group) == 0.0)
    held = tcp(group).copy()
    rt.run(0.2)
    assert np.array_equal(tcp(group), held)
    assert group.state is G.MOVING and move.active and not move.done
    override(vel_factor=1.0)
    rt.run_until(move, timeout=10.0)
    assert move.done
    assert np.allclose(tcp(group), [200.0, 0.0, 0.0], atol=TOL, rtol=0.0)


@pytest.mark.parametrize("factors", [
    {"acc_factor": 0.0}, {"jerk_factor": 0.0}, {"vel_factor": -0.1}, {"acc_factor": -1.0},
    {"jerk_factor": float("nan")}], ids=str)
def test_rule93_bad_factors_are_errors_and_keep_the_previous_ones(factors):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    override = MC_GroupSetOverride(group)
    override(enable=True, vel_factor=0.8, acc_factor=0.6, jerk_factor=0.4)
    assert override.enabled
    override(**{"vel_factor": 0.8, "acc_factor": 0.6, "jerk_factor": 0.4, **factors})
    assert override.error and override.error_id is ErrorId.INVALID_OVERRIDE
    assert not override.enabled
    assert group.factors == (0.8, 0.6, 0.4)


def test_rule94_enable_low_keeps_the_last_factors():
    rt, group, axes, move = moving_group()
    override = MC_GroupSetOverride(group)
    override(enable=True, vel_factor=0.25)
    override(enable=False)
    assert not override.enabled
    assert group.factors == (0.25, 1.0, 1.0)
    assert path_speed_after(rt, group, 0.3) == pytest.approx(25.0, rel=1e-9)


def test_rule96_factors_above_one_are_clamped_to_one_with_a_warning():
    rt, group, axes, move = moving_group()
    command = group.set_override(1.5, 2.0, 1.0)
    assert command.done and len(command.warnings) == 2
    assert group.factors == (1.0, 1.0, 1.0)
    override = MC_GroupSetOverride(group)
    override(enable=True, vel_factor=3.0)
    assert override.enabled and not override.error
    assert path_speed_after(rt, group, 0.1) == pytest.approx(100.0, rel=1e-9)


@pytest.mark.parametrize("state", ALL, ids=lambda s: s.name)
def test_rule95_override_never_changes_the_state(state):
    rt, group, axes = in_state(state)
    override = MC_GroupSetOverride(group)
    for factor in (0.0, 0.5, 1.0):
        override(enable=True, vel_factor=factor)
        assert override.enabled
        assert group.state is state


# -- compliance surface (§1.3.1, §2.4, Appendix 1; rules 125-127) --------------------------------

#: the B inputs and outputs of each block (digest §3), in our snake_case; RotAngle1..3 of
#: MC_SetCartesianTransform are rot_x, rot_y, rot_z (frames.py), AXES_GROUP_REF is axes_group
BASIC: dict[str, tuple[str, ...]] = {
    "MC_AddAxisToGroup": ("axis", "execute", "done", "error"),
    "MC_RemoveAxisFromGroup": ("execute", "done", "error"),
    "MC_UngroupAllAxes": ("execute", "done", "error"),
    "MC_GroupReadConfiguration": ("enable", "ident_in_group", "axis_ref", "valid", "error"),
    "MC_GroupEnable": ("execute", "done", "error"),
    "MC_GroupDisable": ("execute", "done", "error"),
    "MC_SetKinTransform": ("execute", "done", "error"),
    "MC_SetCartesianTransform": ("execute", "trans_x", "trans_y", "trans_z", "rot_x", "rot_y",
                                 "rot_z", "done", "error"),
    "MC_SetCoordinateTransform": ("execute", "done", "error"),
    "MC_ReadKinTransform": ("enable", "valid", "kin_transform", "error"),
    "MC_ReadCartesianTransform": ("enable", "valid", "trans_x", "trans_y", "trans_z", "rot_x",
                                  "rot_y", "rot_z", "error"),
    "MC_ReadCoordinateTransform": ("enable", "valid", "coord_transform", "error"),
    "MC_GroupSetPosition": ("execute", "position", "done", "error"),
    "MC_GroupReadActualPosition": ("enable", "valid", "position", "error"),
    "MC_GroupReadActualVelocity": ("enable", "valid", "velocity", "error"),
    "MC_GroupReadActualAcceleration": ("enable", "valid", "acceleration", "error"),
    "MC_GroupReadStatus": ("enable", "valid", *FLAGS, "error"),
    "MC_GroupReadError": ("enable", "valid", "error", "error_id", "group_error_id"),
    "MC_GroupReset": ("execute", "done", "error"),
    "MC_PathSelect": ("execute", "path_description", "path_data", "done", "error"),
    "MC_GroupSetOverride": ("enable", "vel_factor", "enabled", "error"),
    "MC_SetDynCoordTransform": ("execute", "master", "coord_transform", "done", "error"),
    "MC_GroupHome": ("execute", "position", "done", "error"),
    "MC_GroupStop": ("execute", "done", "error"),
    "MC_GroupHalt": ("execute", "done", "error"),
    "MC_GroupInterrupt": ("execute", "done", "error"),
    "MC_GroupContinue": ("execute", "done", "error"),
    "MC_MoveLinearAbsolute": ("execute", "position", "done", "error"),
    "MC_MoveLinearRelative": ("execute", "distance", "done", "error"),
    "MC_MoveCircularAbsolute": ("execute", "circ_mode", "aux_point", "end_point", "done",
                                "error"),
    "MC_MoveCircularRelative": ("execute", "circ_mode", "aux_point", "end_point", "done",
                                "error"),
    "MC_MoveDirectAbsolute": ("execute", "position", "done", "error"),
    "MC_MoveDirectRelative": ("execute", "distance", "done", "error"),
    "MC_MovePath": ("execute", "path_data", "done", "error"),
    "MC_SyncAxisToGroup": ("execute", "slave", "in_sync", "error"),
    "MC_TrackConveyorBelt": ("execute", "conveyor_belt_origin", "done", "error"),
    "MC_SyncGroupToAxis": ("execute", "master", "path_data", "in_sync", "error"),
    "MC_TrackRotaryTable": ("execute", "rotary_table_origin", "error"),
}


@pytest.mark.parametrize("name", sorted(BASIC))
def test_rule125_every_block_has_its_basic_inputs_and_outputs(name):
    import openmotion.coordinated.blocks as blocks

    assert name in blocks.__all__
    fb = getattr(blocks, name)()
    missing = [io for io in BASIC[name] if not hasattr(fb, io)]
    assert not missing, f"{name} lacks {missing}"


def test_rule125_every_exported_block_is_a_part4_block():
    import openmotion.coordinated.blocks as blocks

    assert sorted(blocks.__all__) == sorted(BASIC)


def test_rule126_transition_mode_numbers_are_the_manuals():
    from openmotion.coordinated.inputs import TransitionMode

    assert {m.name: int(m) for m in TransitionMode} == {
        "TM_NONE": 0, "TM_START_VELOCITY": 1, "TM_CONSTANT_VELOCITY": 2,
        "TM_CORNER_DISTANCE": 3, "TM_MAX_CORNER_DEVIATION": 4}
    assert [m.name for m in BufferMode] == ["ABORTING", "BUFFERED", "BLENDING_LOW",
                                            "BLENDING_PREVIOUS", "BLENDING_NEXT",
                                            "BLENDING_HIGH"]


def test_rule126_group_blocks_take_the_manuals_buffer_mode_numbers():
    """§2.4.2 Table 2 numbers BufferMode 0-5; core.enums.BufferMode keeps TcMC's numbers
    (BlendingLow 0x12 ...), so the group FBs read 0-5 as Part 4's (D-107)."""
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    first = group.move_linear_absolute([5.0, 0.0, 0.0], velocity=100.0)
    second = group.move_linear_absolute([5.0, 5.0, 0.0], velocity=100.0, buffer_mode=1)
    assert first.busy and second.busy and not second.active  # 1 = Buffered: it waits
    rt.run_until(second, 5.0)
    assert group.position(actual=False) == pytest.approx([5.0, 5.0, 0.0], abs=1e-9)


def test_rule126_a_buffer_mode_number_part4_does_not_know_is_an_error():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    command = group.move_linear_absolute([5.0, 0.0, 0.0], buffer_mode=7)
    assert command.error and command.error_id is ErrorId.INVALID_MODE


#: §1.3.1: the manual's list of short names
SHORT = {
    "MC_AddAxisToGrp": "MC_AddAxisToGroup", "MC_RemAxisFromGrp": "MC_RemoveAxisFromGroup",
    "MC_UngroupAllAxes": "MC_UngroupAllAxes", "MC_GrpReadCfg": "MC_GroupReadConfiguration",
    "MC_GrpEnable": "MC_GroupEnable", "MC_GrpDisable": "MC_GroupDisable",
    "MC_GrpHome": "MC_GroupHome", "MC_SetKinTrans": "MC_SetKinTransform",
    "MC_SetCartTrans": "MC_SetCartesianTransform",
    "MC_SetCoordTrans": "MC_SetCoordinateTransform", "MC_ReadKinTrans": "MC_ReadKinTransform",
    "MC_ReadCartTrans": "MC_ReadCartesianTransform",
    "MC_ReadCoordTrans": "MC_ReadCoordinateTransform",
    "MC_GrpReadActPos": "MC_GroupReadActualPosition",
    "MC_GrpReadActVel": "MC_GroupReadActualVelocity",
    "MC_GrpReadActAcc": "MC_GroupReadActualAcceleration", "MC_GrpStop": "MC_GroupStop",
    "MC_SyncGrpToAxis": "MC_SyncGroupToAxis",
    "MC_GrpHalt": "MC_GroupHalt", "MC_GrpInterrupt": "MC_GroupInterrupt",
    "MC_GrpContinue": "MC_GroupContinue", "MC_GrpReadStatus": "MC_GroupReadStatus",
    "MC_GrpReadError": "MC_GroupReadError", "MC_GrpReset": "MC_GroupReset",
    "MC_MoveLinAbs": "MC_MoveLinearAbsolute", "MC_MoveLinRel": "MC_MoveLinearRelative",
    "MC_MoveCircAbs": "MC_MoveCircularAbsolute", "MC_MoveCircRel": "MC_MoveCircularRelative",
    "MC_MoveDirAbs": "MC_MoveDirectAbsolute", "MC_MoveDirRel": "MC_MoveDirectRelative",
    "MC_PathSelect": "MC_PathSelect", "MC_MovePath": "MC_MovePath",
    "MC_GrpSetOverride": "MC_GroupSetOverride", "MC_SyncAxisToGrp": "MC_SyncAxisToGroup",
    "MC_SetDynCoordTrans": "MC_SetDynCoordTransform",
    "MC_TrackConvBelt": "MC_TrackConveyorBelt", "MC_TrackRotaryTable": "MC_TrackRotaryTable",
}


@pytest.mark.parametrize("short", sorted(SHORT))
def test_rule127_short_names_are_the_same_classes(short):
    import openmotion.coordinated.blocks as blocks

    assert getattr(blocks, short) is getattr(blocks, SHORT[short])


# -- optional inputs of the stop blocks and MC_GroupHome (issue 20 point 6; D-194) ----------


@pytest.mark.parametrize("mode", [BufferMode.BUFFERED, BufferMode.BLENDING_NEXT],
                         ids=lambda m: m.name)
def test_buffered_group_stop_waits_for_the_motion_then_stops_at_rest(mode):
    """§5.13 gives MC_GroupStop a BufferMode (§7.3): Buffered starts after the motion
    before it; the Blending modes act as Buffered (D-194)."""
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True, buffer_mode=mode)
    assert outputs(stop) == (True, False, False, False, False)  # waits: Busy only
    assert move.active and group.state is G.MOVING
    drive(rt, stop, until=lambda: move.done)
    assert not move.aborted
    assert tcp(group).tolist() == pytest.approx([200.0, 0.0, 0.0], abs=TOL)
    drive(rt, stop, until=lambda: stop.done, limit=5)
    assert group.state is G.STOPPING and stop.busy and stop.active
    stop(execute=False)
    rt.step()
    assert group.state is G.STANDBY
    assert group.move_linear_absolute([0.0, 0.0, 0.0]).busy


def test_a_waiting_group_stop_released_early_ends_stopping_at_standstill():
    """Note 3: a short stop pulse still stops; released while it waited, the group is
    GroupStandby once the stop is Done (D-194)."""
    rt, group, axes, move = moving_group()
    stop = MC_GroupStop(group)
    stop(execute=True, buffer_mode=BufferMode.BUFFERED)
    stop(execute=False)
    assert stop.busy and not stop.active
    drive(rt, stop, until=lambda: move.done)
    run_cycles = drive(rt, stop, until=lambda: group.state is G.STANDBY, limit=5)
    assert run_cycles <= 2 and not stop.busy


@pytest.mark.parametrize("mode", [BufferMode.BUFFERED, BufferMode.BLENDING_LOW],
                         ids=lambda m: m.name)
def test_buffered_group_halt_is_done_when_the_motion_before_it_ends(mode):
    """§5.14 gives MC_GroupHalt a BufferMode: Buffered waits, the motion is not aborted,
    and the halt is Done at the rest point (D-194)."""
    rt, group, axes, move = moving_group()
    halt = MC_GroupHalt(group)
    halt(execute=True, buffer_mode=mode)
    assert outputs(halt) == (True, False, False, False, False)
    drive(rt, halt, until=lambda: halt.done)
    assert move.done and not move.aborted
    assert tcp(group).tolist() == pytest.approx([200.0, 0.0, 0.0], abs=TOL)
    rt.step()
    assert group.state is G.STANDBY


def test_group_halt_at_rest_is_done_at_once():
    """§5.14: Done when the velocity is zero; a halt of a standing group is Done in its
    call, and the group goes back to GroupStandby (it used to stay GroupMoving)."""
    rt, group, axes = group_of(0.0, 0.0)
    halt = MC_GroupHalt(group)
    halt(execute=True)
    assert halt.done and not halt.error
    rt.step()
    assert group.state is G.STANDBY
    assert group.move_linear_absolute([10.0, 0.0]).busy


def test_a_ca_group_stop_block_has_no_buffer_mode():
    """A CA group (TF5410 §9.3.1.2) knows only Aborting: another BufferMode is an FB error."""
    from openmotion.transport.group import CaGroup

    ca = CaGroup(om.Runtime(), "ca")
    stop = MC_GroupStop(ca)
    stop(execute=True, buffer_mode=BufferMode.BUFFERED)
    assert stop.error and stop.error_id is om.ErrorId.INVALID_MODE


@pytest.mark.parametrize("coord", [CoordSystem.MCS, CoordSystem.PCS], ids=lambda c: c.name)
def test_group_home_position_in_mcs_or_pcs_is_where_the_tcp_ends(coord):
    """§5.7 gives MC_GroupHome a CoordSystem: Position is read in it, so the TCP reads that
    position in that system after homing (D-194). The PCS is shifted by (10, 20, 0)."""
    rt, group, axes = group_of(3.0, 4.0, 0.0, reference_mode=ReferenceMode.DIRECT)
    assert group.set_cartesian_transform(Frame.from_cartesian(10.0, 20.0, 0.0)).done
    home = MC_GroupHome(group)
    home(execute=True, position=[100.0, 200.0, 5.0], coord_system=coord)
    drive(rt, home, until=lambda: home.done, limit=100)
    assert tcp(group, coord).tolist() == pytest.approx([100.0, 200.0, 5.0], abs=TOL)
    shift = [10.0, 20.0, 0.0] if coord is CoordSystem.PCS else [0.0, 0.0, 0.0]
    assert tcp(group, CoordSystem.ACS).tolist() == pytest.approx(
        np.add([100.0, 200.0, 5.0], shift).tolist(), abs=TOL)


def test_group_home_with_a_bad_coord_system_is_an_error():
    rt, group, axes = group_of(3.0, 4.0, reference_mode=ReferenceMode.DIRECT)
    home = MC_GroupHome(group)
    home(execute=True, position=[1.0, 2.0], coord_system=7)
    assert home.error and group.state is G.STANDBY
    home(execute=False)
    home(execute=True, position=[1.0, 2.0], coord_system=CoordSystem.ACS)
    assert home.busy
