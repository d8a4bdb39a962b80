"""Moving coordinate systems and synchronisation of the Part 4 axes group (§2.2, §6).

Rules 17, 18 and 114-124 of digest §6: MC_TrackConveyorBelt, MC_TrackRotaryTable,
MC_SetDynCoordTransform and MC_SyncAxisToGroup. The belt, the table and the slave are
ordinary axes outside the group, moved by their own single-axis commands.

FBs are called once per cycle before ``rt.step()``, as in tests/transport/test_blocks.py.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import openmotion as om
from openmotion.coordinated.blocks import (
    MC_GroupStop,
    MC_MoveLinearAbsolute,
    MC_PathSelect,
    MC_ReadCoordinateTransform,
    MC_SetCartesianTransform,
    MC_SetDynCoordTransform,
    MC_SyncAxisToGroup,
    MC_SyncGroupToAxis,
    MC_TrackConveyorBelt,
    MC_TrackRotaryTable,
)
from openmotion.coordinated.frames import Frame
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem
from openmotion.coordinated.states import AxesGroupState
from openmotion.core.enums import AxisState

G = AxesGroupState
MCS, PCS = CoordSystem.MCS, CoordSystem.PCS
ErrorId = om.ErrorId
AXIS = {"max_velocity": 1000.0, "max_acceleration": 20000.0, "max_deceleration": 20000.0,
        "max_jerk": 1.0e6}
TOL = 1e-6  #: [mm]
#: the belt frame: at MCS (0, 100, 0), turned 90° about z, so the belt runs along MCS +y
BELT_ORIGIN = [0.0, 100.0, 0.0, 0.0, 0.0, 90.0]
OBJECT = [20.0, 5.0, 0.0, 0.0, 0.0, 0.0]  #: the object on the belt (belt frame)
FAST = {"velocity": 200.0, "acceleration": 4000.0, "deceleration": 4000.0, "jerk": 1.0e5}


def cell(*start: float) -> tuple[om.Runtime, AxesGroup, list[om.Axis], om.Axis]:
    """An enabled x-y-z group at ``start`` and a powered belt (or table) axis at 0."""
    rt = om.Runtime()
    group = AxesGroup(rt, "robot")
    axes = []
    for ident, position in enumerate(start, 1):
        axis = rt.add_axis(f"a{ident}", position=position, **AXIS)
        axis.power()
        assert group.add_axis(axis, ident).done
        axes.append(axis)
    assert group.enable().done
    belt = rt.add_axis("belt", **AXIS)
    belt.power()
    return rt, group, axes, belt


def run(rt: om.Runtime, cycles: int, *fbs: Any) -> None:
    for _ in range(cycles):
        rt.step()
        for fb in fbs:
            fb()


def track(group: AxesGroup, belt: om.Axis) -> MC_TrackConveyorBelt:
    fb = MC_TrackConveyorBelt(group)
    fb(execute=True, conveyor_belt=belt, conveyor_belt_origin=BELT_ORIGIN,
       initial_object_position=OBJECT)
    return fb


def pcs_origin(group: AxesGroup) -> np.ndarray:
    read = MC_ReadCoordinateTransform(group)
    read(enable=True)
    assert read.valid
    return read.coord_transform.translation.copy()


# -- MC_TrackConveyorBelt (§6.6; rules 119-122, 17, 18) ----------------------------------------


def test_rule119_tracking_starts_no_motion_and_keeps_the_state():
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    belt.move_velocity(100.0)
    fb = track(group, belt)  # Done once set, not Busy (§3.3), Active while tracking (D-131)
    assert (fb.done, fb.busy, fb.active, fb.error) == (True, False, True, False)
    run(rt, 300, fb)
    assert fb.done and fb.active and not fb.busy and not fb.command_aborted
    assert group.state is G.STANDBY
    assert group.position(MCS).tolist() == [0.0, 0.0, 0.0]
    assert all(a.set_velocity == 0.0 for a in axes)


@pytest.mark.parametrize("kind", ["belt", "table", "dyn"])
def test_rules119_124_tracking_fbs_report_done_once_the_transform_is_set(kind):
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    if kind == "belt":
        fb = track(group, belt)
    elif kind == "table":
        fb = MC_TrackRotaryTable(group)
        fb(execute=True, rotary_table=belt, rotary_table_origin=[0.0] * 6)
    else:
        master = AxesGroup(rt, "master")
        fb = MC_SetDynCoordTransform(group)
        fb(execute=True, master=master)
    run(rt, 5, fb)
    assert fb.done and fb.active and not fb.busy  # §3.3: Busy falls with Done
    fb(execute=False)  # Done is a result: reset by the falling edge; the tracking goes on
    assert not fb.done and fb.active and not fb.busy
    run(rt, 5, fb)
    assert fb.active and group.spaces.dynamic is not None
    other = MC_SetCartesianTransform(group)
    other(execute=True, trans_x=1.0)
    fb()  # CommandAborted shows for one call with Execute low, then every output is reset
    assert (fb.done, fb.busy, fb.active, fb.command_aborted) == (False, False, False, True)
    fb()
    assert not (fb.done or fb.busy or fb.active or fb.command_aborted)


def test_rule120_the_pcs_starts_at_origin_and_object_and_rides_on_the_belt():
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    belt.move_absolute(30.0, velocity=500.0)  # the belt moves on by itself ...
    run(rt, 20)
    start = belt.set_position
    fb = track(group, belt)  # ... counted from where it is when the FB starts
    origin = Frame.from_cartesian(*BELT_ORIGIN).compose(Frame.from_cartesian(*OBJECT))
    assert pcs_origin(group) == pytest.approx(origin.translation, abs=1e-12)  # (-5, 120, 0)
    assert origin.translation == pytest.approx([-5.0, 120.0, 0.0], abs=1e-12)
    run(rt, 400, fb)
    travel = belt.set_position - start
    assert travel > 10.0
    assert pcs_origin(group) == pytest.approx([-5.0, 120.0 + travel, 0.0], abs=1e-12)


def test_rule120_an_origin_given_as_an_array_works_too():
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    fb = MC_TrackConveyorBelt(group)
    fb(execute=True, conveyor_belt=belt, conveyor_belt_origin=np.array(BELT_ORIGIN),
       initial_object_position=np.array(OBJECT))
    assert fb.done and fb.active and not fb.error
    assert pcs_origin(group) == pytest.approx([-5.0, 120.0, 0.0], abs=1e-12)


def test_rules121_17_after_a_pcs_move_the_tcp_rides_on_the_belt():
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    belt.move_velocity(50.0)
    fb, move = track(group, belt), MC_MoveLinearAbsolute(group)
    move(execute=True, position=[10.0, 0.0, 0.0], coord_system=PCS, **FAST)  # GotoP at t0
    while not move.done:
        rt.step()
        fb()
        move()
    assert group.position(PCS) == pytest.approx([10.0, 0.0, 0.0], abs=TOL)  # t1: at P
    belt_then, mcs_then = belt.set_position, group.position(MCS)
    for _ in range(300):
        rt.step()
        fb()
        assert group.position(PCS) == pytest.approx([10.0, 0.0, 0.0], abs=TOL)
        travel = belt.set_position - belt_then
        assert group.position(MCS) == pytest.approx(mcs_then + [0.0, travel, 0.0], abs=TOL)
        assert group.state is G.MOVING  # following the product (rule 17)
    assert belt.set_position - belt_then == pytest.approx(15.0, abs=1e-9)  # 0.3 s at 50 mm/s
    assert fb.active


def test_rule18_a_later_mcs_move_ends_the_following():
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    belt.move_velocity(50.0)
    fb = track(group, belt)
    rt.run_until(group.move_linear_absolute([10.0, 0.0, 0.0], coord_system=PCS, **FAST))
    run(rt, 100, fb)
    back = group.move_linear_absolute([0.0, 0.0, 0.0], coord_system=MCS, **FAST)  # W_MCS
    rt.run_until(back)
    rt.step()
    assert group.state is G.STANDBY
    held = group.position(MCS)
    assert held == pytest.approx([0.0, 0.0, 0.0], abs=TOL)
    pcs = group.position(PCS)
    run(rt, 200, fb)
    assert np.array_equal(group.position(MCS), held)  # still, although the PCS moves on
    assert group.position(PCS)[0] == pytest.approx(pcs[0] - 10.0, abs=1e-9)  # belt x
    assert fb.active



@pytest.mark.parametrize("replace", ["cartesian", "table"])
def test_rule122_another_transform_of_the_pcs_aborts_the_tracking(replace):
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    belt.move_velocity(50.0)
    fb = track(group, belt)
    run(rt, 100, fb)
    if replace == "cartesian":
        other = MC_SetCartesianTransform(group)
        other(execute=True, trans_x=7.0)
    else:
        other = MC_TrackRotaryTable(group)
        other(execute=True, rotary_table=rt.add_axis("table", **AXIS),
              rotary_table_origin=[7.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    fb()
    assert (fb.busy, fb.active, fb.command_aborted, fb.error) == (False, False, True, False)
    assert not other.error
    run(rt, 100, fb)
    assert pcs_origin(group) == pytest.approx([7.0, 0.0, 0.0], abs=1e-12)  # the belt is gone


def test_rule122_a_following_group_holds_where_it_is_when_the_tracking_ends():
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    belt.move_velocity(50.0)
    fb = track(group, belt)
    rt.run_until(group.move_linear_absolute([10.0, 0.0, 0.0], coord_system=PCS, **FAST))
    run(rt, 50, fb)
    where = group.position(MCS)
    other = MC_SetCartesianTransform(group)
    other(execute=True)
    run(rt, 20, fb)
    assert group.position(MCS) == pytest.approx(where, abs=1.0)


# -- MC_TrackRotaryTable (§6.7; rule 123) -------------------------------------------------------


def test_rule123_the_pcs_turns_with_the_table():
    rt, group, axes, table = cell(0.0, 0.0, 0.0)
    origin = [100.0, 50.0, 0.0, 0.0, 0.0, 0.0]  #: the table axis stands at MCS (100, 50)
    obj = [30.0, 0.0, 0.0, 0.0, 0.0, 0.0]  #: the object 30 mm from the table axis
    fb = MC_TrackRotaryTable(group)
    fb(execute=True, rotary_table=table, rotary_table_origin=origin,
       initial_object_position=obj)
    assert fb.done and fb.active
    move = group.move_linear_absolute([0.0, 0.0, 0.0], coord_system=PCS, **FAST)
    rt.run_until(move)
    assert group.position(MCS) == pytest.approx([130.0, 50.0, 0.0], abs=TOL)
    turn = table.move_absolute(90.0, velocity=180.0)  # degrees
    while not turn.done:
        rt.step()
        fb()
        angle = math.radians(table.set_position)
        expected = [100.0 + 30.0 * math.cos(angle), 50.0 + 30.0 * math.sin(angle), 0.0]
        assert group.position(MCS) == pytest.approx(expected, abs=TOL)
        assert group.position(PCS) == pytest.approx([0.0, 0.0, 0.0], abs=TOL)
    assert group.position(MCS) == pytest.approx([100.0, 80.0, 0.0], abs=TOL)
    read = MC_ReadCoordinateTransform(group)
    read(enable=True)
    assert read.coord_transform.rotation == pytest.approx(
        Frame.from_cartesian(rot_angle3=90.0).rotation, abs=1e-12)


# -- MC_SetDynCoordTransform (§6.5; rule 124) ---------------------------------------------------


def test_rule124_the_pcs_of_the_slave_group_rides_on_the_master_tcp():
    rt, group, axes, _ = cell(0.0, 0.0, 0.0)
    master = AxesGroup(rt, "master")
    for ident, name in enumerate("uvw", 1):
        axis = rt.add_axis(name, position=10.0 * ident, **AXIS)
        axis.power()
        master.add_axis(axis, ident)
    master.enable()
    fb = MC_SetDynCoordTransform(group)
    fb(execute=True, master=master, coord_transform=[0.0, 0.0, 5.0, 0.0, 0.0, 0.0])
    assert fb.done and fb.active and not fb.error
    assert pcs_origin(group) == pytest.approx([10.0, 20.0, 35.0], abs=1e-12)
    move = master.move_linear_absolute([60.0, -20.0, 30.0], **FAST)
    while not move.done:
        rt.step()
        fb()
        tcp = master.position(MCS, actual=False)
        assert pcs_origin(group) == pytest.approx(tcp + [0.0, 0.0, 5.0], abs=1e-12)
    assert group.state is G.STANDBY


def test_rule124_a_group_cannot_follow_itself():
    rt, group, axes, _ = cell(0.0, 0.0, 0.0)
    fb = MC_SetDynCoordTransform(group)
    fb(execute=True, master=group)
    assert fb.error and fb.error_id is ErrorId.INVALID_MODE


# -- MC_SyncAxisToGroup (§6.3; rules 114-116) ---------------------------------------------------


def cruising(velocity: float = 100.0) -> tuple[om.Runtime, AxesGroup, om.Axis, om.Command]:
    rt, group, axes, slave = cell(0.0, 0.0, 0.0)
    move = group.move_linear_absolute([300.0, 0.0, 0.0], velocity=velocity)
    rt.run(0.4)
    assert group.velocity(MCS)[1] == pytest.approx(velocity, rel=1e-12)
    return rt, group, slave, move


def test_rule114_slave_ramps_to_ratio_times_path_speed_then_in_sync():
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, ratio_numerator=3, ratio_denominator=2, acceleration=500.0)
    assert sync.busy and sync.active and not sync.in_sync
    assert slave.state is AxisState.SYNCHRONIZED_MOTION
    previous, cycles = slave.set_velocity, 0
    while not sync.in_sync:
        rt.step()
        sync()
        cycles += 1
        assert abs(slave.set_velocity - previous) <= 500.0 * rt.cycle_time * (1 + 1e-9)
        previous = slave.set_velocity
    # jerk-limited with the slave's default jerk (MC_DEFAULT, D-193): 0.3 s + a / j
    ramp = 150.0 / 500.0 + 500.0 / slave.parameters.jerk
    assert cycles == pytest.approx(ramp / rt.cycle_time, abs=1.0)
    start, length = slave.set_position, 0.0
    for _ in range(200):
        rt.step()
        sync()
        path = group.velocity(MCS)[1]
        length += path * rt.cycle_time
        assert sync.in_sync
        assert slave.set_velocity == pytest.approx(1.5 * path, rel=1e-12)
    assert slave.set_position - start == pytest.approx(1.5 * length, abs=TOL)


def test_rule114_in_sync_stays_true_while_the_group_slows_down():
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, acceleration=5000.0)
    while not move.done:
        rt.step()
        sync()
    assert sync.in_sync and sync.active
    run(rt, 5, sync)
    assert slave.set_velocity == 0.0 and sync.in_sync


def test_rule115_a_single_axis_command_to_the_slave_ends_the_coupling():
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, acceleration=5000.0)
    run(rt, 100, sync)
    assert sync.in_sync
    halt = slave.halt()
    assert not halt.error
    run(rt, 1, sync)
    assert (sync.busy, sync.active, sync.command_aborted, sync.in_sync) == (
        False, False, True, False)
    rt.run_until(halt)
    assert slave.state is AxisState.STANDSTILL and move.busy  # the group goes on


def test_rule116_a_new_edge_with_a_new_ratio_changes_it_without_a_stop():
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, ratio_numerator=2, acceleration=1000.0)
    run(rt, 300, sync)
    assert slave.set_velocity == pytest.approx(200.0, rel=1e-12)
    sync(execute=False)
    sync(execute=True, ratio_numerator=1)
    lowest = slave.set_velocity
    for _ in range(200):
        rt.step()
        sync()
        lowest = min(lowest, slave.set_velocity)
    assert lowest == pytest.approx(100.0, rel=1e-12)  # from 200 down to 100, never 0
    assert slave.set_velocity == pytest.approx(100.0, rel=1e-12) and sync.in_sync


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"ratio_denominator": 0}, ErrorId.INVALID_GEAR_RATIO),
    ({"ratio_numerator": float("nan")}, ErrorId.INVALID_GEAR_RATIO),
    ({"acceleration": -1.0}, ErrorId.INVALID_ACCELERATION)], ids=str)
def test_sync_axis_to_group_with_bad_inputs_is_an_error(inputs, error_id):
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, **inputs)
    assert sync.error and sync.error_id is error_id
    assert slave.state is AxisState.STANDSTILL


def test_a_member_cannot_be_the_slave():
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=group.axes[0])
    assert sync.error and sync.error_id is ErrorId.AXIS_IN_GROUP


# -- MC_SyncGroupToAxis (§6.4; rules 46, 97, 117, 118) ------------------------------------------

CAM_PATH = [{"line": [100.0, 0.0, 0.0]}, {"line": [100.0, 50.0, 0.0]}]
SYNC = {k: v for k, v in FAST.items() if k != "velocity"}  #: §6.4 has no velocity input


def cam(mode: int = 0, **inputs: Any) -> tuple[om.Runtime, AxesGroup, om.Axis, Any]:
    """The group at the origin; a path 100 along x, then 50 along y; a master axis."""
    rt, group, _, master = cell(0.0, 0.0, 0.0)
    select = MC_PathSelect(group)
    select(execute=True, path_description=CAM_PATH)
    assert select.done
    sync = MC_SyncGroupToAxis(group)
    sync(execute=True, master=master, path_data=select.path_data, mode=mode, **SYNC, **inputs)
    return rt, group, master, sync


def test_rule117_the_group_follows_the_master_along_the_path():
    rt, group, master, sync = cam(tuc_numerator=1, tuc_denominator=2)
    assert sync.busy and sync.active and not sync.in_sync and not sync.error
    assert group.state is G.MOVING
    master.move_absolute(100.0, 100.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    run(rt, 300, sync)
    assert sync.in_sync
    for _ in range(1000):  # in sync the arc length is half the master's travel
        rt.step()
        sync()
        s = master.set_position / 2.0
        expected = [s, 0.0, 0.0] if s <= 100.0 else [100.0, s - 100.0, 0.0]
        assert group.position(MCS)[:3] == pytest.approx(expected, abs=TOL)
    assert master.set_velocity == 0.0  # at rest: the group at rest too (rule 117)
    assert group.velocity(MCS)[1] == pytest.approx(0.0, abs=TOL)
    assert sync.active and not sync.done  # it never ends by itself


def test_rule117_a_master_already_running_is_caught_up_within_the_limits():
    rt, group, _, master = cell(0.0, 0.0, 0.0)
    select = MC_PathSelect(group)
    select(execute=True, path_description=[{"line": [400.0, 0.0, 0.0]}])
    master.move_velocity(100.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    rt.run(0.3)
    sync = MC_SyncGroupToAxis(group)
    sync(execute=True, master=master, path_data=select.path_data, **SYNC)
    previous = 0.0
    for _ in range(600):
        rt.step()
        sync()
        v = group.velocity(MCS)[1]
        assert abs(v - previous) <= FAST["acceleration"] * rt.cycle_time * (1 + 1e-9) + 1e-9
        previous = v
    assert sync.in_sync
    assert group.velocity(MCS)[1] == pytest.approx(100.0, abs=1e-6)


def test_rule118_group_stop_or_another_motion_ends_the_coupling():
    rt, group, master, sync = cam()
    master.move_velocity(20.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    run(rt, 200, sync)
    stop = MC_GroupStop(group)
    stop(execute=True, deceleration=4000.0, jerk=1.0e5)
    sync()
    assert sync.command_aborted and not sync.in_sync
    run(rt, 300, stop)
    assert group.velocity(MCS)[1] == pytest.approx(0.0, abs=TOL)
    rt, group, master, sync = cam()
    master.move_velocity(20.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    run(rt, 200, sync)
    move = group.move_linear_absolute([0.0, 0.0, 0.0], velocity=100.0, **{
        k: v for k, v in FAST.items() if k != "velocity"})
    sync()
    assert sync.command_aborted
    rt.run_until(lambda: move.done, timeout=5.0)


def test_a_non_periodic_path_stops_exactly_at_its_end():
    rt, group, master, sync = cam()
    master.move_absolute(1000.0, 200.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    run(rt, 8000, sync)
    assert group.position(MCS)[:3] == pytest.approx([100.0, 50.0, 0.0], abs=1e-9)
    assert group.velocity(MCS)[1] == pytest.approx(0.0, abs=TOL)
    assert sync.active and not sync.in_sync  # waits at the end, out of sync


def test_a_periodic_path_must_be_closed_and_bad_conversions_are_errors():
    rt, group, master, sync = cam(mode=1)
    assert sync.error and sync.error_id is ErrorId.INVALID_MODE
    assert group.state is G.STANDBY
    for numerator, denominator in ((1, 0), ([1, 2], [1, 1]), (float("nan"), 1)):
        rt, group, master, sync = cam(tuc_numerator=numerator, tuc_denominator=denominator)
        assert sync.error and sync.error_id is ErrorId.INVALID_GEAR_RATIO, (numerator,
                                                                            denominator)


def test_override_does_not_act_on_a_slave_group():
    rt, group, master, sync = cam()
    master.move_velocity(20.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    run(rt, 500, sync)
    group.set_override(0.5)
    run(rt, 100, sync)
    assert group.velocity(MCS)[1] == pytest.approx(20.0, abs=1e-6)  # rule 97


# -- MC_SyncGroupToAxis on a moving group, BufferMode (§6.4; issue 20 point 4, D-193) --------


def moving_to_y(rt_group: tuple[om.Runtime, AxesGroup, list[om.Axis], om.Axis]
                ) -> tuple[Any, Any]:
    """The group runs from the origin towards (0, 80, 0) at 100 mm/s; the path of CAM_PATH
    selected. Returns the move and the PathData."""
    rt, group, _, master = rt_group
    select = MC_PathSelect(group)
    select(execute=True, path_description=CAM_PATH)
    move = group.move_linear_absolute([0.0, 80.0, 0.0], velocity=100.0, **SYNC)
    rt.run(0.3)
    assert move.active and group.velocity(MCS)[1] == pytest.approx(100.0, rel=1e-9)
    return move, select.path_data


def test_sync_group_to_axis_aborting_takes_over_a_moving_group():
    """§6.4 gives MC_SyncGroupToAxis a BufferMode and asks no standstill: Aborting aborts
    the moving group's command, brakes along its path (no turn off it) and couples at the
    rest point; the path runs from there with s = master travel since then (D-193). Before
    issue 20 it was refused with GROUP_MOVING."""
    rt, group, axes, master = cell(0.0, 0.0, 0.0)
    move, path = moving_to_y((rt, group, axes, master))
    sync = MC_SyncGroupToAxis(group)
    sync(execute=True, master=master, path_data=path, **SYNC)
    assert not sync.error and sync.busy and sync.active
    assert move.aborted and group.state is G.MOVING
    run(rt, 200, sync)  # brakes along y, then holds: the master stands
    rest = group.position(MCS)[:3]
    assert rest[0] == pytest.approx(0.0, abs=TOL) and 20.0 < rest[1] < 80.0
    assert group.velocity(MCS)[1] == pytest.approx(0.0, abs=TOL)
    master.move_absolute(50.0, 100.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    run(rt, 1500, sync)
    assert sync.in_sync and sync.active
    way = np.array([100.0, 0.0, 0.0]) - rest
    expected = rest + 50.0 * way / np.linalg.norm(way)  # 50 mm along the path's first line
    assert group.position(MCS)[:3] == pytest.approx(expected.tolist(), abs=TOL)


@pytest.mark.parametrize("mode", [1, 4], ids=["buffered", "blending_next"])
def test_sync_group_to_axis_buffered_waits_for_the_motion_before_it(mode):
    """Buffered (and a Blending mode, which acts as Buffered: no transition input) couples
    when the motion before it is over, Busy and not Active until then (§7.3, D-193)."""
    rt, group, axes, master = cell(0.0, 0.0, 0.0)
    move, path = moving_to_y((rt, group, axes, master))
    sync = MC_SyncGroupToAxis(group)
    sync(execute=True, master=master, path_data=path, buffer_mode=mode, **SYNC)
    assert sync.busy and not sync.active and not sync.error
    while not move.done:
        rt.step()
        sync()
        assert not move.aborted
    rt.step()
    sync()
    assert sync.active and group.state is G.MOVING
    assert group.position(MCS)[:3] == pytest.approx([0.0, 80.0, 0.0], abs=TOL)
    master.move_absolute(40.0, 100.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    run(rt, 1500, sync)
    way = np.array([100.0, -80.0, 0.0]) / math.hypot(100.0, 80.0)
    assert group.position(MCS)[:3] == pytest.approx((np.array([0.0, 80.0, 0.0])
                                                     + 40.0 * way).tolist(), abs=TOL)


def test_a_waiting_sync_group_to_axis_is_aborted_by_an_aborting_move():
    rt, group, axes, master = cell(0.0, 0.0, 0.0)
    move, path = moving_to_y((rt, group, axes, master))
    sync = MC_SyncGroupToAxis(group)
    sync(execute=True, master=master, path_data=path, buffer_mode=1, **SYNC)
    other = group.move_linear_absolute([10.0, 0.0, 0.0], velocity=100.0)
    sync()
    assert sync.command_aborted and other.busy


# -- MC_SyncAxisToGroup: position lock and its optional inputs (§6.3; point 4, 6, D-193) ----


def test_sync_axis_to_group_locks_in_position_while_the_path_accelerates_harder():
    """§6.3: the slave ramps up to the ratio and locks in position: from then on it is the
    odometer of the path, also where the path accelerates faster than the slave's ramp-in
    acceleration (500 here against 4000). Before issue 20 only the velocity followed, at
    most 500 mm/s² (D-193)."""
    rt, group, axes, slave = cell(0.0, 0.0, 0.0)
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, ratio_numerator=3, ratio_denominator=2, acceleration=500.0)
    run(rt, 2, sync)
    assert sync.in_sync  # at rest: ratio x 0 reached at once
    start = slave.set_position
    move = group.move_linear_absolute([100.0, 0.0, 0.0], **FAST)
    while not move.done:
        rt.step()
        sync()
        assert sync.in_sync
        assert slave.set_velocity == pytest.approx(1.5 * group.velocity(MCS)[1], abs=1e-9)
    assert slave.set_position - start == pytest.approx(150.0, abs=1e-3)


def test_sync_axis_to_group_ramps_with_its_deceleration_and_jerk():
    """Deceleration bounds the ramp when the slave's speed falls, Jerk the change of its
    acceleration (§6.3, D-193)."""
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, ratio_numerator=2, acceleration=5000.0)
    run(rt, 300, sync)
    assert sync.in_sync and slave.set_velocity == pytest.approx(200.0, rel=1e-12)
    sync(execute=False)
    sync(execute=True, ratio_numerator=1, deceleration=200.0, jerk=2.0e4)
    previous_v, previous_a, cycles = slave.set_velocity, slave.set_acceleration, 0
    while not sync.in_sync:
        rt.step()
        sync()
        cycles += 1
        assert previous_v - slave.set_velocity <= 200.0 * rt.cycle_time * (1 + 1e-9)
        assert abs(slave.set_acceleration - previous_a) <= 2.0e4 * rt.cycle_time * (1 + 1e-6)
        previous_v, previous_a = slave.set_velocity, slave.set_acceleration
    assert cycles * rt.cycle_time == pytest.approx(100.0 / 200.0 + 200.0 / 2.0e4, abs=0.002)


def test_sync_axis_to_group_measures_the_path_in_its_coord_system():
    """CoordSystem (§6.3): a group at rest in the MCS on a moving PCS travels relative to the
    PCS at the belt's speed (D-193)."""
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    slave = rt.add_axis("slave", **AXIS)
    slave.power()
    track(group, belt)
    belt.move_velocity(50.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    in_pcs, in_mcs = MC_SyncAxisToGroup(group), MC_SyncAxisToGroup(group)
    in_pcs(execute=True, slave=slave, coord_system=PCS, acceleration=5000.0)
    run(rt, 500, in_pcs)
    assert in_pcs.in_sync and slave.set_velocity == pytest.approx(50.0, rel=1e-9)
    in_mcs(execute=True, slave=slave, coord_system=MCS, acceleration=5000.0)
    run(rt, 500, in_mcs)
    assert in_mcs.in_sync and slave.set_velocity == 0.0


def test_buffered_sync_axis_to_group_waits_for_the_slaves_own_move():
    """BufferMode (§6.3): Buffered starts after the slave's own command; Aborting (the
    default) takes the slave over at once (D-193)."""
    rt, group, slave, move = cruising()
    own = slave.move_absolute(20.0, 100.0)
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, buffer_mode=1, acceleration=5000.0)
    assert sync.busy and not sync.active
    while not own.done:
        rt.step()
        sync()
        assert not own.aborted and not sync.active
    run(rt, 100, sync)
    assert sync.active and sync.in_sync
    assert slave.set_velocity == pytest.approx(group.velocity(MCS)[1], rel=1e-9)


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"deceleration": -1.0}, ErrorId.INVALID_DECELERATION),
    ({"jerk": 0.0}, ErrorId.INVALID_JERK),
    ({"coord_system": 9}, ErrorId.INVALID_MODE),
    ({"buffer_mode": 9}, ErrorId.INVALID_MODE)], ids=str)
def test_sync_axis_to_group_with_bad_optional_inputs_is_an_error(inputs, error_id):
    rt, group, slave, move = cruising()
    sync = MC_SyncAxisToGroup(group)
    sync(execute=True, slave=slave, **inputs)
    assert sync.error and sync.error_id is error_id
    sync(execute=False)
    sync(execute=True, slave=slave, **{name: MC_SyncAxisToGroup.INPUTS[name] for name in inputs})
    assert sync.busy and not sync.error


# -- tracking FBs: BufferMode, CoordSystem, Mode (§6.5-§6.7; issue 20 point 6, D-194) --------


@pytest.mark.parametrize("kind", ["belt", "table", "dyn"])
def test_buffered_tracking_waits_for_the_motion_and_counts_from_then(kind):
    """§6.5-§6.7 give the tracking FBs a BufferMode: Buffered sets the moving PCS when the
    motion before it is over (Busy, not Active, not Done until then); a belt's travel counts
    from that cycle (D-194)."""
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    belt.move_velocity(50.0, acceleration=1000.0, deceleration=1000.0, jerk=1.0e5)
    move = group.move_linear_absolute([50.0, 0.0, 0.0], **FAST)
    if kind == "dyn":
        master = AxesGroup(rt, "master")
        axis = rt.add_axis("m1", **AXIS)
        axis.power()
        master.add_axis(axis, 1)
        master.enable()
        fb: Any = MC_SetDynCoordTransform(group)
        fb(execute=True, master=master, buffer_mode=1, mode=1)
    elif kind == "table":
        fb = MC_TrackRotaryTable(group)
        fb(execute=True, rotary_table=belt, rotary_table_origin=BELT_ORIGIN, buffer_mode=1)
    else:
        fb = MC_TrackConveyorBelt(group)
        fb(execute=True, conveyor_belt=belt, conveyor_belt_origin=BELT_ORIGIN,
           initial_object_position=OBJECT, buffer_mode=1)
    assert (fb.busy, fb.active, fb.done) == (True, False, False)
    while not move.done:
        assert not fb.done and group.spaces.dynamic is None
        rt.step()
        fb()
    assert fb.active and fb.done and group.spaces.dynamic is not None  # in the same cycle
    if kind == "belt":  # the object where it lay when the PCS was set, not at the call
        x, y, _ = pcs_origin(group)
        assert x == pytest.approx(-5.0, abs=TOL)
        assert 120.0 <= y <= 120.0 + 50.0 * 2.0 * rt.cycle_time


@pytest.mark.parametrize("coord", [CoordSystem.ACS, CoordSystem.MCS], ids=lambda c: c.name)
def test_only_the_pcs_can_be_the_tracked_coord_system(coord):
    """CoordSystem of the tracking FBs (§6.5-§6.7): only the PCS may move (D-194)."""
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    fb = MC_TrackConveyorBelt(group)
    fb(execute=True, conveyor_belt=belt, conveyor_belt_origin=BELT_ORIGIN, coord_system=coord)
    assert fb.error and fb.error_id is ErrorId.INVALID_MODE and group.spaces.dynamic is None
    fb(execute=False)
    fb(execute=True, conveyor_belt=belt, conveyor_belt_origin=BELT_ORIGIN,
       coord_system=CoordSystem.PCS)
    assert fb.done and fb.active


def test_set_dyn_coord_transform_checks_its_mode():
    """Mode (MC_PathMode, §6.5) is checked; it changes nothing in our system (D-194)."""
    rt, group, axes, belt = cell(0.0, 0.0, 0.0)
    master = AxesGroup(rt, "master")
    axis = rt.add_axis("m1", **AXIS)
    axis.power()
    master.add_axis(axis, 1)
    master.enable()
    fb = MC_SetDynCoordTransform(group)
    fb(execute=True, master=master, mode=5)
    assert fb.error and fb.error_id is ErrorId.INVALID_MODE
    fb(execute=False)
    fb(execute=True, master=master, mode=1)
    assert fb.done and fb.active
