"""ACS, MCS and PCS of a running axes group: transforms, ExecutionMode, SetPosition, reads.

PLCopen Part 4 §2.1, §3.3, §5.8-§5.12 (digest §1.1-§1.2, §2.4, §3.8-§3.12; rules 1-16 and
19-21 of digest §6; rules 17 and 18, the moving PCS, are in test_tracking.py). The frames
and kinematics themselves are tested in test_frames.py and test_kinematics.py; here they
work inside a group, through the FBs.

The §5.8.2 example {50, 50, 0, 0, 0, 30} puts the PCS origin at MCS (50, 50, 0), turned 30°
about z, so PCS (10, 0, 0) is MCS (50 + 10 cos 30°, 50 + 10 sin 30°, 0) =
(58.660254, 55.0, 0) (decisions D-101).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import openmotion as om
from openmotion.coordinated.blocks import (
    MC_GroupReadActualAcceleration,
    MC_GroupReadActualPosition,
    MC_GroupReadActualVelocity,
    MC_GroupSetPosition,
    MC_MoveDirectAbsolute,
    MC_MoveLinearAbsolute,
    MC_MoveLinearRelative,
    MC_ReadCartesianTransform,
    MC_ReadCoordinateTransform,
    MC_ReadKinTransform,
    MC_SetCartesianTransform,
    MC_SetCoordinateTransform,
    MC_SetKinTransform,
)
from openmotion.coordinated.frames import Frame
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem
from openmotion.coordinated.kinematics import CartesianGantry, Scara
from openmotion.coordinated.states import AxesGroupState, ExecutionMode
from openmotion.core.enums import BufferMode

G = AxesGroupState
ACS, MCS, PCS = CoordSystem.ACS, CoordSystem.MCS, CoordSystem.PCS
ErrorId = om.ErrorId
AXIS = {"max_velocity": 1000.0, "max_acceleration": 20000.0, "max_deceleration": 20000.0,
        "max_jerk": 1.0e6}
TOL = 1e-6  #: [mm]
EXAMPLE = {"trans_x": 50.0, "trans_y": 50.0, "trans_z": 0.0, "rot_x": 0.0, "rot_y": 0.0,
           "rot_z": 30.0}  #: §5.8.2 {50, 50, 0, 0, 0, 30}
EXAMPLE_PCS_10 = [50.0 + 10.0 * math.cos(math.radians(30.0)), 55.0, 0.0]  #: (58.660254, 55, 0)
FAST = {"velocity": 200.0, "acceleration": 4000.0, "deceleration": 4000.0, "jerk": 1.0e5}


def group_of(*start: float, idents: tuple[int, ...] | None = None, enable: bool = True,
             **parameters: Any) -> tuple[om.Runtime, AxesGroup, list[om.Axis]]:
    rt = om.Runtime()
    group = AxesGroup(rt, "g")
    axes = []
    for index, position in enumerate(start):
        axis = rt.add_axis(f"a{index + 1}", position=position, **{**AXIS, **parameters})
        assert axis.power()
        ident = index + 1 if idents is None else idents[index]
        assert group.add_axis(axis, ident).done
        axes.append(axis)
    if enable:
        assert group.enable().done
    return rt, group, axes


def read(group: AxesGroup, coord: CoordSystem) -> np.ndarray:
    fb = MC_GroupReadActualPosition(group)
    fb(enable=True, coord_system=coord)
    assert fb.valid and not fb.error
    return fb.position


def finish(rt: om.Runtime, *fbs: Any, limit: int = 20000) -> None:
    """Step, calling ``fbs``, until the last of them is Done."""
    for _ in range(limit):
        for fb in fbs:
            fb()
        if fbs[-1].done:
            return
        rt.step()
    raise AssertionError("not done")


def set_example(group: AxesGroup, **inputs: Any) -> MC_SetCartesianTransform:
    fb = MC_SetCartesianTransform(group)
    fb(execute=True, **{**EXAMPLE, **inputs})
    return fb


# -- coordinate systems of the inputs (§2.1; rules 1, 4, 6, 7) -------------------------------


def test_rule7_the_example_transform_maps_pcs_10_0_0_to_mcs_58_66_55_0():
    rt, group, axes = group_of(50.0, 50.0, 0.0)
    fb = set_example(group)
    assert fb.done and not fb.busy
    assert read(group, PCS) == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)  # its origin
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[10.0, 0.0, 0.0], coord_system=PCS, **FAST)
    finish(rt, move)
    assert read(group, MCS) == pytest.approx(EXAMPLE_PCS_10, abs=TOL)
    assert read(group, PCS) == pytest.approx([10.0, 0.0, 0.0], abs=TOL)
    assert read(group, MCS) == pytest.approx([58.660254038, 55.0, 0.0], abs=TOL)
    transform = MC_ReadCartesianTransform(group)
    transform(enable=True)
    assert transform.valid
    assert (transform.trans_x, transform.trans_y, transform.rot_z) == pytest.approx(
        (50.0, 50.0, 30.0), abs=1e-12)


@pytest.mark.parametrize(("coord", "mcs"), [(MCS, [10.0, 0.0, 0.0]), (PCS, EXAMPLE_PCS_10)],
                         ids=["MCS", "PCS"])
def test_rule1_a_move_reads_its_position_in_its_own_coord_system(coord, mcs):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    set_example(group)
    for move in (MC_MoveLinearAbsolute(group), MC_MoveDirectAbsolute(group)):
        move(execute=True, position=[10.0, 0.0, 0.0], coord_system=coord)
        finish(rt, move)
        assert read(group, MCS) == pytest.approx(mcs, abs=TOL)
        group.move_direct_absolute([0.0, 0.0, 0.0])
        rt.run(2.0)


def test_rule1_a_pcs_move_is_a_straight_line_in_the_mcs_too():
    rt, group, axes = group_of(50.0, 50.0, 0.0)
    set_example(group)
    move = group.move_linear_relative([10.0, 0.0, 0.0], coord_system=PCS)
    points = []
    while not move.done:
        rt.step()
        points.append(read(group, MCS))
    direction = np.array([math.cos(math.radians(30.0)), math.sin(math.radians(30.0)), 0.0])
    offsets = np.array(points) - [50.0, 50.0, 0.0]
    assert np.abs(np.cross(offsets, direction)).max() <= TOL


def test_rule4_neutral_kinematics_mcs_equals_acs():
    rt, group, axes = group_of(1.0, 2.0, 3.0)
    kin = MC_SetKinTransform(group)
    kin(execute=True, kin_transform=CartesianGantry())
    assert kin.done and not kin.error
    move = group.move_direct_absolute([40.0, -20.0, 10.0])
    while not move.done:
        rt.step()
        assert np.array_equal(read(group, MCS), read(group, ACS))


def test_rule6_all_zero_cartesian_transform_makes_pcs_equal_mcs():
    rt, group, axes = group_of(12.0, -3.0, 7.0)
    set_example(group)
    assert not np.allclose(read(group, PCS), read(group, MCS))
    zero = MC_SetCartesianTransform(group)
    zero(execute=True, trans_x=0.0, trans_y=0.0, trans_z=0.0, rot_x=0.0, rot_y=0.0, rot_z=0.0)
    assert zero.done
    assert np.array_equal(read(group, PCS), read(group, MCS))


# -- kinematics (§2.1.1, §5.8.1; rules 2, 3, 5) -----------------------------------------------


def test_rule5_a_kinematics_for_another_axis_count_is_an_error_and_changes_nothing():
    rt, group, axes = group_of(300.0, 200.0, 0.0)
    before = MC_ReadKinTransform(group)
    before(enable=True)
    old, mcs = before.kin_transform, read(group, MCS)
    kin = MC_SetKinTransform(group)
    kin(execute=True, kin_transform=Scara(300.0, 200.0))  # two axes, the group has three
    assert (kin.done, kin.busy, kin.error) == (False, False, True)
    assert kin.error_id is ErrorId.INVALID_CONFIGURATION
    before()
    assert before.kin_transform is old
    assert np.array_equal(read(group, MCS), mcs)
    assert group.state is G.STANDBY


def test_rule5_something_else_than_a_kinematics_is_an_error():
    rt, group, axes = group_of(0.0, 0.0)
    kin = MC_SetKinTransform(group)
    kin(execute=True, kin_transform="scara")
    assert kin.error and kin.error_id is ErrorId.INVALID_MODE


def test_rule2_a_scara_group_moves_a_straight_line_in_mcs_and_lands_on_it():
    rt, group, axes = group_of(0.0, 90.0)
    assert group.set_kinematics(Scara(300.0, 200.0)).done
    assert read(group, MCS) == pytest.approx([300.0, 200.0], abs=1e-9)
    target = np.array([150.0, 300.0])
    move = group.move_linear_absolute(target, velocity=200.0)
    points = []
    while not move.done:
        rt.step()
        points.append(read(group, MCS))
    chord = (target - [300.0, 200.0]) / np.linalg.norm(target - [300.0, 200.0])
    offsets = np.array(points) - [300.0, 200.0]
    assert np.abs(offsets[:, 0] * chord[1] - offsets[:, 1] * chord[0]).max() <= TOL
    assert read(group, MCS) == pytest.approx(target, abs=TOL)
    acs = read(group, ACS)
    assert group.kinematics.forward(acs) == pytest.approx(target, abs=TOL)
    assert group.kinematics.inverse(target) == pytest.approx(acs, abs=1e-6)


def test_rule2_a_line_through_the_unreachable_centre_is_refused_before_it_moves():
    rt, group, axes = group_of(0.0, 90.0)
    assert group.set_kinematics(Scara(300.0, 200.0)).done
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[-300.0, -200.0], velocity=200.0)  # through (0, 0)
    assert move.error and move.error_id is ErrorId.TARGET_UNREACHABLE
    rt.run(0.1)
    assert group.state is G.STANDBY
    assert read(group, MCS) == pytest.approx([300.0, 200.0], abs=1e-9)


def test_rule3_the_scara_elbow_configurations_reach_one_point_two_ways():
    scara = Scara(300.0, 200.0)
    point = np.array([150.0, 300.0])
    down, up = (scara.inverse(point, c) for c in scara.configurations)
    assert not np.allclose(down, up)
    assert scara.forward(down) == pytest.approx(point, abs=1e-9)
    assert scara.forward(up) == pytest.approx(point, abs=1e-9)


# -- transforms and the group (§5.8; rules 8-13) --------------------------------------------


def test_rule8_two_cartesian_transforms_compose():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    set_example(group)
    second = MC_SetCartesianTransform(group)
    second(execute=True, trans_x=10.0)
    expected = Frame.from_cartesian(**dict(zip(
        ("trans_x", "trans_y", "trans_z", "rot_angle1", "rot_angle2", "rot_angle3"),
        EXAMPLE.values(), strict=True))).compose(Frame.from_cartesian(10.0))
    transform = MC_ReadCoordinateTransform(group)
    transform(enable=True)
    assert transform.coord_transform.translation == pytest.approx(expected.translation)
    cartesian = MC_ReadCartesianTransform(group)  # §5.8.5: the resulting transformation
    cartesian(enable=True)
    assert (cartesian.trans_x, cartesian.trans_y, cartesian.trans_z, cartesian.rot_z) == \
        pytest.approx([*EXAMPLE_PCS_10, 30.0], abs=1e-9)  # the second one in the first's PCS
    assert read(group, PCS) == pytest.approx(  # and PCS <-> MCS uses it
        expected.inverse().apply([0.0, 0.0, 0.0]), abs=1e-9)


def test_rule8_all_zeros_deselect_the_pcs_and_set_coordinate_transform_replaces():
    rt, group, axes = group_of(1.0, 2.0, 3.0)
    set_example(group)
    zeros = MC_SetCartesianTransform(group)
    zeros(execute=True)  # §5.8.2: {0, 0, 0, 0, 0, 0} de-selects the PCS
    assert zeros.done and read(group, PCS) == pytest.approx([1.0, 2.0, 3.0], abs=1e-12)
    set_example(group)
    coord = MC_SetCoordinateTransform(group)
    coord(execute=True, coord_transform=Frame.from_cartesian(5.0))  # §5.8.3: sets the PCS
    assert coord.done and read(group, PCS) == pytest.approx([-4.0, 2.0, 3.0], abs=1e-12)


def test_rules9_10_set_coordinate_transform_starts_no_motion_and_keeps_the_state():
    rt, group, axes = group_of(5.0, 6.0, 7.0)
    acs = read(group, ACS)
    fb = MC_SetCoordinateTransform(group)
    fb(execute=True, coord_transform=Frame.from_cartesian(1.0, 2.0, 3.0, rot_angle3=90.0))
    assert fb.done
    assert group.state is G.STANDBY
    for _ in range(20):
        rt.step()
        assert np.array_equal(read(group, ACS), acs)
        assert all(a.set_velocity == 0.0 for a in axes)
    assert read(group, PCS) == pytest.approx([4.0, -4.0, 4.0], abs=1e-12)
    transform = MC_ReadCoordinateTransform(group)
    transform(enable=True)
    assert transform.coord_transform.translation.tolist() == [1.0, 2.0, 3.0]


@pytest.mark.parametrize("fb_type", [MC_SetKinTransform, MC_SetCartesianTransform,
                                     MC_SetCoordinateTransform], ids=lambda t: t.__name__)
def test_rule10_transform_fbs_never_change_the_state_of_a_moving_group(fb_type):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[60.0, 0.0, 0.0])
    rt.run(0.1)
    inputs = {MC_SetKinTransform: {"kin_transform": CartesianGantry()},
              MC_SetCartesianTransform: EXAMPLE,
              MC_SetCoordinateTransform: {"coord_transform": Frame.from_cartesian(5.0)}}
    fb = fb_type(group)
    fb(execute=True, **inputs[fb_type])
    assert fb.done and group.state is G.MOVING
    finish(rt, move)
    assert read(group, MCS) == pytest.approx([60.0, 0.0, 0.0], abs=TOL)  # MCS unaffected


def two_moves(rt: om.Runtime, group: AxesGroup) -> tuple[MC_MoveLinearAbsolute, ...]:
    first, second = MC_MoveLinearAbsolute(group), MC_MoveLinearAbsolute(group)
    first(execute=True, position=[30.0, 0.0, 0.0])
    second(execute=True, position=[30.0, 30.0, 0.0], buffer_mode=BufferMode.BUFFERED)
    rt.run(0.1)
    first()
    second()
    assert first.active and second.busy
    return first, second


def test_rule11_immediately_takes_effect_in_the_same_cycle():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    first, second = two_moves(rt, group)
    fb = set_example(group, execution_mode=ExecutionMode.IMMEDIATELY)
    assert fb.done and first.active
    mcs = read(group, MCS)
    expected = Frame.from_cartesian(50.0, 50.0, 0.0, 0.0, 0.0, 30.0).inverse().apply(mcs)
    assert read(group, PCS) == pytest.approx(expected, abs=1e-12)


def test_rule12_delayed_takes_effect_when_the_running_motion_ends():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    first, second = two_moves(rt, group)
    fb = set_example(group, execution_mode=ExecutionMode.DELAYED)
    while not first.done:
        assert fb.busy and not fb.done
        assert np.array_equal(read(group, PCS), read(group, MCS))  # not yet
        rt.step()
        first()
        second()
        fb()
    assert fb.done and not fb.busy
    assert not np.allclose(read(group, PCS), read(group, MCS))
    assert second.busy  # the queued motion still runs


def test_rule13_queued_waits_for_every_motion_issued_before():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    first, second = two_moves(rt, group)
    fb = set_example(group, execution_mode=ExecutionMode.QUEUED)
    while not second.done:
        assert fb.busy and not fb.done
        assert np.array_equal(read(group, PCS), read(group, MCS))
        rt.step()
        first()
        second()
        fb()
    assert fb.done
    assert read(group, PCS) == pytest.approx(
        Frame.from_cartesian(50.0, 50.0, 0.0, 0.0, 0.0, 30.0).inverse().apply(
            [30.0, 30.0, 0.0]), abs=TOL)


@pytest.mark.parametrize("mode", [ExecutionMode.DELAYED, ExecutionMode.QUEUED])
def test_rules12_13_delayed_and_queued_act_at_once_at_rest(mode):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    fb = set_example(group, execution_mode=mode)
    assert fb.done


# -- MC_GroupSetPosition (§5.9; rules 14-16) ----------------------------------------------------


def offset_group() -> tuple[om.Runtime, AxesGroup, list[om.Axis]]:
    """ACS, MCS and PCS all different: y runs backwards from 100, and the example PCS."""
    rt, group, axes = group_of(10.0, 20.0, 30.0, enable=False)
    gantry = CartesianGantry(("x", "y", "z"), sign=(1.0, -1.0, 1.0), offset=(0.0, 100.0, 0.0))
    assert group.set_kinematics(gantry).done
    assert group.enable().done
    set_example(group)
    return rt, group, axes


def test_rule14_set_position_moves_nothing_and_reads_back():
    rt, group, axes = offset_group()
    fb = MC_GroupSetPosition(group)
    fb(execute=True, position=[1.0, 2.0, 3.0], coord_system=ACS)
    assert fb.done and not fb.error
    assert group.state is G.STANDBY
    for _ in range(10):
        rt.step()
        assert all(a.set_velocity == 0.0 for a in axes)
        assert read(group, ACS).tolist() == [1.0, 2.0, 3.0]


def test_rules15_16_set_position_in_acs_moves_mcs_and_pcs_along():
    rt, group, axes = offset_group()
    fb = MC_GroupSetPosition(group)
    fb(execute=True, position=[5.0, 5.0, 5.0], coord_system=ACS, relative=True)
    assert fb.done
    assert read(group, ACS) == pytest.approx([15.0, 25.0, 35.0], abs=1e-12)
    mcs = read(group, MCS)
    assert mcs == pytest.approx([15.0, 75.0, 35.0], abs=1e-12)
    assert read(group, PCS) == pytest.approx(
        Frame.from_cartesian(50.0, 50.0, 0.0, 0.0, 0.0, 30.0).inverse().apply(mcs), abs=1e-9)


def test_rules15_16_set_position_in_mcs_moves_pcs_but_not_acs():
    rt, group, axes = offset_group()
    acs, pcs = read(group, ACS), read(group, PCS)
    fb = MC_GroupSetPosition(group)
    fb(execute=True, position=[1.0, 2.0, 3.0], coord_system=MCS)  # absolute by default
    assert fb.done
    assert np.array_equal(read(group, ACS), acs)
    assert read(group, MCS) == pytest.approx([1.0, 2.0, 3.0], abs=1e-12)
    assert not np.allclose(read(group, PCS), pcs)
    fb(execute=False)
    fb(execute=True, position=[10.0, 0.0, -1.0], coord_system=MCS, relative=True)
    assert read(group, MCS) == pytest.approx([11.0, 2.0, 2.0], abs=1e-12)
    assert np.array_equal(read(group, ACS), acs)


def test_rule16_set_position_in_pcs_absolute_and_relative():
    rt, group, axes = offset_group()
    acs, mcs = read(group, ACS), read(group, MCS)
    fb = MC_GroupSetPosition(group)
    fb(execute=True, position=[0.0, 0.0, 0.0], coord_system=PCS)
    assert fb.done
    assert read(group, PCS) == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    fb(execute=False)
    fb(execute=True, position=[3.0, -4.0, 1.0], coord_system=PCS, relative=True)
    assert read(group, PCS) == pytest.approx([3.0, -4.0, 1.0], abs=1e-9)
    assert np.array_equal(read(group, ACS), acs) and np.array_equal(read(group, MCS), mcs)
    move = group.move_linear_absolute([3.0, 6.0, 1.0], coord_system=PCS, **FAST)
    rt.run_until(move)
    assert read(group, PCS) == pytest.approx([3.0, 6.0, 1.0], abs=TOL)  # the new PCS holds


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"position": [1.0, 2.0]}, ErrorId.INVALID_POSITION),
    ({"position": [1.0, float("inf"), 3.0]}, ErrorId.INVALID_POSITION),
    ({"position": [1.0, 2.0, 3.0], "coord_system": 9}, ErrorId.INVALID_MODE)], ids=str)
def test_set_position_with_bad_inputs_is_an_error(inputs, error_id):
    rt, group, axes = group_of(1.0, 2.0, 3.0)
    fb = MC_GroupSetPosition(group)
    fb(execute=True, **inputs)
    assert fb.error and fb.error_id is error_id
    assert read(group, ACS).tolist() == [1.0, 2.0, 3.0]


def test_set_position_while_moving_is_refused():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    group.move_linear_absolute([50.0, 0.0, 0.0])
    rt.run(0.1)
    fb = MC_GroupSetPosition(group)
    fb(execute=True, position=[0.0, 0.0, 0.0])
    assert fb.error and fb.error_id is ErrorId.GROUP_MOVING


@pytest.mark.parametrize("mode", [BufferMode.BUFFERED, BufferMode.BLENDING_NEXT],
                         ids=lambda m: m.name)
def test_buffered_set_position_waits_for_the_motion(mode):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move = MC_MoveLinearRelative(group)
    move(execute=True, distance=[50.0, 0.0, 0.0])
    fb = MC_GroupSetPosition(group)
    fb(execute=True, position=[0.0, 0.0, 0.0], buffer_mode=mode)
    assert fb.busy and not fb.active and not fb.error  # D-130: Blending acts as Buffered
    finish(rt, move, fb)
    assert move.done
    assert read(group, ACS).tolist() == [0.0, 0.0, 0.0]
    rt.step()
    assert group.state is G.STANDBY


# -- reads (§5.10-§5.12; rules 19-21) ------------------------------------------------------------


def test_rule19_acs_values_come_in_ident_in_group_order():
    rt, group, axes = group_of(1.0, 2.0, 3.0, idents=(3, 1, 2))
    assert read(group, ACS).tolist() == [2.0, 3.0, 1.0]  # idents 1, 2, 3
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[20.0, 30.0, 10.0], coord_system=ACS)
    finish(rt, move)
    assert [a.position for a in axes] == pytest.approx([10.0, 20.0, 30.0], abs=TOL)


def test_rules20_21_velocity_and_acceleration_in_each_system():
    rt, group, axes = group_of(0.0, 0.0, enable=False)
    assert group.set_kinematics(CartesianGantry(("x", "y"), sign=(1.0, -1.0))).done
    assert group.enable().done
    fb = MC_SetCartesianTransform(group)
    fb(execute=True, rot_z=90.0)
    move = group.move_linear_absolute([60.0, 80.0], velocity=100.0)  # direction (0.6, 0.8)
    velocity = {c: MC_GroupReadActualVelocity(group) for c in (ACS, MCS, PCS)}
    acceleration = {c: MC_GroupReadActualAcceleration(group) for c in (ACS, MCS)}
    path_accelerations = []
    cruise_checked = False
    while not move.done:
        rt.step()
        for coord, read_v in velocity.items():
            read_v(enable=True, coord_system=coord)
            assert read_v.valid and read_v.path_velocity >= 0.0
        for coord, read_a in acceleration.items():
            read_a(enable=True, coord_system=coord)
        v, a = velocity[MCS].velocity, acceleration[MCS].acceleration
        path = velocity[MCS].path_velocity
        assert path == pytest.approx(np.linalg.norm(v), abs=1e-9)
        assert velocity[ACS].velocity == pytest.approx([v[0], -v[1]], abs=1e-9)
        assert velocity[PCS].velocity == pytest.approx([v[1], -v[0]], abs=1e-9)  # turned -90°
        assert acceleration[ACS].acceleration == pytest.approx([a[0], -a[1]], abs=1e-6)
        path_accelerations.append(acceleration[MCS].path_acceleration)
        if path == pytest.approx(100.0, rel=1e-12):
            assert v == pytest.approx([60.0, 80.0], abs=1e-9)
            cruise_checked = True
    assert cruise_checked
    signs = np.sign(np.array(path_accelerations))
    assert signs.max() == 1.0 and signs.min() == -1.0
    first_negative = int(np.argmax(signs < 0))
    assert np.all(signs[:first_negative] >= 0.0)  # speeding up, then slowing down
    assert np.all(signs[first_negative:] <= 0.0)
