"""MC_PlanarMover rules a review against TF5430 found missing: wrong input types fail at the
call, a mover joining a group while it moves holds its way, relative external setpoints keep
collision avoidance (§4.2) and turn with their frame, MoveC out of its window only with X and
Y at rest (§4.2), Halt ends external setpoints (§6.1.7) and is never refused (D-084), and the
published ErrorCode."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.planar import (
    DynamicConstraint_PathXY,
    ExternalSetPositionMode,
    MC_PlanarEnvironment,
    MC_PlanarFeedback,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarTrack,
    MC_PlanarTrackTrail,
    MoverCommandMode,
    MoverVector,
    PlanarMoverParameters,
    PlanarObjectType,
    PlanarState,
    PositionXYC,
    ST_ExternalSetpointGenerationOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    ST_JoinTrackOptions,
    ST_MoveCOptions,
    ST_MoveToPositionOptions,
)
from openmotion.planar.frames import Pose
from openmotion.planar.parts import Part, PartLayout, PartPosition

CS_1 = 0x01010060
PART_1, PART_2 = 0x01010020, 0x01010030
SLOW = DynamicConstraint_PathXY(200.0, 1000.0, 1000.0, 10000.0)
RELATIVE = ST_ExternalSetpointGenerationOptions(ExternalSetPositionMode.RELATIVE)


def _movers(*starts: tuple[float, float], group: bool = True, stators: int = 0):
    """Enabled movers at ``starts``; with ``group`` all in one enabled group, with the
    environment of a row of ``stators`` stators when there are any."""
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt) if stators else None
    for i in range(stators):
        environment.add_stator(240.0 * i, 0.0)
    if environment is not None:
        environment.create_boundary()
    planar_group = MC_PlanarGroup(rt)
    planar_group.enable()
    movers = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x, y)))
              for x, y in starts]
    for mover in movers:
        mover.enable()
    rt.run(0.002)
    if group:
        for mover in movers:
            mover.add_to_group(planar_group)
        if environment is not None:
            environment.add_to_group(planar_group)
        rt.step()
    return rt, planar_group, movers


# -- wrong input types: a Python error at the call, nothing lost in the cycle -----------------

@pytest.mark.parametrize("call", [
    lambda m, g: m.move_to_position(PositionXYC(1.0, 1.0, 0.0, 1.5)),
    lambda m, g: m.move_to_position(PositionXYC(1.0, 1.0, 0.0, None)),
    lambda m, g: m.move_to_position(PositionXYC(1.0, 1.0), None, ST_MoveCOptions()),
    lambda m, g: m.move_c(10.0, None, ST_MoveToPositionOptions()),
    lambda m, g: m.move_z(1.0, 5.0),
    lambda m, g: m.halt(2.0),
    lambda m, g: m.add_to_group(None),
    lambda m, g: m.add_to_group(m),
    lambda m, g: m.start_external_setpoint_generation(ST_MoveCOptions()),
    lambda m, g: m.set_external_setpoint_reference_id(None, MoverVector(), MoverVector(),
                                                      MoverVector(), 2.5),
], ids=["float reference id", "no reference id", "options of MoveC", "options of MoveToPosition",
        "number as constraint", "number as halt constraint", "no group", "a mover as group",
        "options of MoveC for external setpoints", "float reference id of a setpoint"])
def test_a_wrong_input_type_is_a_type_error_at_the_call(call):
    rt, group, (mover, other) = _movers((120.0, 120.0), (600.0, 120.0), group=False)
    with pytest.raises(TypeError, match="must be|needs"):
        call(mover, group)
    command = other.move_to_position(PositionXYC(700.0, 120.0))
    rt.run(1.0)
    assert command.done and other.position.x == 700.0  # the cycle ran on, nothing lost
    assert mover.state is PlanarState.ENABLED and not mover.error


# -- AddToGroup while moving -----------------------------------------------------------------

def test_a_mover_joining_its_group_while_moving_holds_the_rest_of_its_way():
    """Its standing footprint alone would let another member be admitted onto its path."""
    rt, group, (a, b) = _movers((0.0, 0.0), (1000.0, 300.0), group=False)
    b.add_to_group(group)
    rt.step()
    move = a.move_to_position(PositionXYC(1000.0, 0.0), SLOW)
    rt.run(0.2)
    join = a.add_to_group(group)
    rt.step()
    assert join.done
    low_x, _, high_x, _ = group.reserved(a.member).bounds
    assert low_x < a.position.x - 77.0 and high_x == pytest.approx(1077.5)
    feedback = MC_PlanarFeedback()
    b.move_to_position(PositionXYC(1000.0, 0.0), None, None, feedback)
    rt.step()
    assert feedback.error and feedback.error_id == ErrorId.PLANAR_COLLISION
    assert (feedback.object_info.object_type, feedback.object_info.id) == \
        (PlanarObjectType.MOVER, a.oid)
    rt.run(6.0)
    assert move.done and a.position.x == 1000.0
    assert group.reserved(a.member).bounds == pytest.approx((922.5, -77.5, 1077.5, 77.5))


# -- relative external setpoints keep collision avoidance (§4.2) -----------------------------

def _push(rt, mover, feedback, step: float, cycles: int, reference: int = 0) -> float:
    """Relative setpoints growing by ``step`` in x each cycle, until an error or ``cycles``."""
    offset = 0.0
    for _ in range(cycles):
        offset += step
        mover.set_external_setpoint_reference_id(feedback, MoverVector(x=offset),
                                                 MoverVector(), MoverVector(), reference)
        rt.step()
        if mover.error:
            break
    return offset


def test_a_relative_offset_into_another_member_is_an_error_naming_it():
    rt, group, (a, b) = _movers((120.0, 120.0), (360.0, 120.0))
    start = a.start_external_setpoint_generation(RELATIVE)
    feedback = MC_PlanarFeedback()
    _push(rt, a, feedback, 0.5, 400)
    assert a.error and a.error_id == ErrorId.PLANAR_COLLISION
    assert f"16#{b.oid:08X}" in a.message
    assert start.error and start.error_id == ErrorId.PLANAR_COLLISION
    # the footprints touched at most: a stood at x <= 360 - 155
    assert a.position.x <= 205.0 + 1e-9
    assert a.footprint().intersection(b.footprint()).area == 0.0


def test_a_relative_offset_off_the_surface_is_an_error_naming_the_environment():
    rt, group, (a,) = _movers((120.0, 120.0), stators=2)
    a.start_external_setpoint_generation(RELATIVE)
    _push(rt, a, MC_PlanarFeedback(), 0.5, 1000)
    assert a.error and a.error_id == ErrorId.PLANAR_COLLISION and "environment" in a.message
    assert a.position.x + 77.5 <= 480.0 + 1e-6  # the footprint stayed on the stators


def test_the_group_holds_where_a_relative_offset_took_the_mover():
    """While the offset runs and after Stop, no other member is admitted onto the mover."""
    rt, group, (a, b) = _movers((120.0, 120.0), (600.0, 120.0))
    a.start_external_setpoint_generation(RELATIVE)
    feedback = MC_PlanarFeedback()
    offset = _push(rt, a, feedback, 0.5, 200)
    assert not a.error and a.position.x == pytest.approx(120.0 + offset)
    # the offset moved a 100 mm beyond the path its commands reserved (x 42.5..197.5)
    refused = b.move_to_position(PositionXYC(120.0 + offset + 110.0, 120.0))
    a.set_external_setpoint_reference_id(feedback, MoverVector(x=offset), MoverVector(),
                                         MoverVector(), 0)  # a setpoint every cycle
    rt.step()
    assert refused.error and refused.error_id == ErrorId.PLANAR_COLLISION
    a.set_external_setpoint_reference_id(feedback, MoverVector(x=offset), MoverVector(),
                                         MoverVector(), 0)
    stop = a.stop_external_setpoint_generation()
    rt.run(0.01)
    assert stop.done and a.command_mode is MoverCommandMode.FREE_MOVEMENT
    assert a.position.x == pytest.approx(120.0 + offset)
    assert group.reserved(a.member).bounds == pytest.approx(
        (42.5 + offset, 42.5, 197.5 + offset, 197.5))


def test_relative_offsets_turn_with_their_frame_but_do_not_move_with_its_origin():
    """An offset given on a part turned by 90 degrees is turned, not placed on the part."""
    layout = PartLayout([CS_1], [Part(PART_1, [(0.0, 0.0)], [PartPosition(CS_1, Pose())]),
                                 Part(PART_2, [(0.0, 0.0)],
                                      [PartPosition(CS_1, Pose(480.0, 0.0, 90.0))])])
    rt = om.Runtime()
    MC_PlanarEnvironment(rt, layout=layout)
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(120.0, 120.0)))
    mover.enable()
    rt.run(0.02)
    mover.start_external_setpoint_generation(RELATIVE)
    feedback = MC_PlanarFeedback()
    for reference, expected in ((CS_1, (121.0, 120.0)), (0, (121.0, 120.0)),
                                (PART_1, (121.0, 120.0)), (PART_2, (120.0, 121.0))):
        mover.set_external_setpoint_reference_id(feedback, MoverVector(x=1.0), MoverVector(),
                                                 MoverVector(), reference)
        rt.step()
        assert not mover.error, mover.message
        assert (mover.position.x, mover.position.y) == pytest.approx(expected, abs=1e-12)


# -- MoveC out of the C window (§4.2) --------------------------------------------------------

def test_move_c_out_of_its_window_is_refused_while_x_and_y_move():
    rt, group, (mover,) = _movers((0.0, 0.0), group=False)
    move = mover.move_to_position(PositionXYC(1000.0, 0.0), SLOW,
                                  ST_MoveToPositionOptions(use_orientation=False))
    rt.run(0.5)
    out = mover.move_c(45.0)
    rt.step()
    assert out.error and out.error_id == ErrorId.PLANAR_WRONG_MODE
    inside = mover.move_c(10.0)  # within the window of +-15 degrees: allowed
    rt.step()
    assert inside.active and move.active
    rt.run(6.0)
    assert move.done and inside.done and mover.position.c == 10.0
    turn = mover.move_c(45.0)  # standing: the mover may turn out of the window
    rt.run(1.0)
    assert turn.done and mover.command_mode is MoverCommandMode.C_ROTATION_FREE_MOVEMENT


# -- Halt -------------------------------------------------------------------------------------

def test_halt_ends_absolute_external_setpoints_and_brakes_to_rest():
    """§6.1.7: the stream's feedback is not aborted by a Halt; the generation ends and the
    mover stops with the Halt's dynamics, in FreeMovement, without an error."""
    rt, group, (mover,) = _movers((0.0, 0.0), group=False)
    stream = MC_PlanarFeedback()
    start = mover.start_external_setpoint_generation(None, stream)
    x = 0.0
    for _ in range(100):
        x += 0.1
        mover.set_external_setpoint_reference_id(stream, MoverVector(x=x),
                                                 MoverVector(x=100.0), MoverVector(), 0)
        rt.step()
    halt = mover.halt()
    rt.step()
    assert mover.command_mode is MoverCommandMode.FREE_MOVEMENT and start.aborted
    for _ in range(50):  # setpoints after the halt are ignored
        mover.set_external_setpoint_reference_id(stream, MoverVector(x=x), MoverVector(),
                                                 MoverVector(), 0)
        rt.step()
    rt.run(0.5)
    assert halt.done and not mover.error and not stream.error
    assert mover.mc_to_plc.set.set_velo.x == 0.0 and x < mover.position.x < x + 5.0


def test_halt_is_not_refused_in_a_group_that_is_not_enabled():
    rt, group, (mover,) = _movers((0.0, 0.0))
    move = mover.move_to_position(PositionXYC(2000.0, 0.0), SLOW)
    rt.run(0.5)
    group.disable()
    rt.run(0.01)
    halt = mover.halt()
    rt.run(0.5)
    assert halt.done and move.aborted and mover.mc_to_plc.set.set_velo.x == 0.0


# -- the published error code -----------------------------------------------------------------

def test_the_published_error_code_is_the_error_id():
    rt, group, (mover,) = _movers((0.0, 0.0), group=False)
    mover.start_external_setpoint_generation()
    rt.run(0.01)  # no setpoint: PLANAR_EXT_SETPOINT
    assert mover.state is PlanarState.ERROR
    assert mover.mc_to_plc.std.error_code == ErrorId.PLANAR_EXT_SETPOINT != 0
    mover.reset()
    rt.run(0.01)
    assert mover.state is PlanarState.ENABLED and mover.mc_to_plc.std.error_code == 0


def test_add_to_group_of_an_environment_or_a_track_needs_a_group():
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    track = MC_PlanarTrack(rt)
    for member in (environment, track):
        with pytest.raises(TypeError, match="needs an MC_PlanarGroup"):
            member.add_to_group(None)


def test_a_target_far_off_every_part_is_an_error_id_not_an_overflow():
    """1e300 mm lies on no part: PLANAR_PART_NOT_ENABLED, and no numeric warning (warnings are
    errors in this suite) from the distance to a part."""
    layout = PartLayout([CS_1], [Part(PART_1, [(0.0, 0.0)], [PartPosition(CS_1, Pose())])])
    rt = om.Runtime()
    MC_PlanarEnvironment(rt, layout=layout)
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(120.0, 120.0)))
    mover.enable()
    rt.run(0.02)
    command = mover.move_to_position(PositionXYC(1e300, 120.0))
    rt.step()
    assert command.error and command.error_id == ErrorId.PLANAR_PART_NOT_ENABLED
    assert mover.position.x == 120.0


def test_halt_on_a_track_also_brakes_a_running_move_c_and_move_z():
    """§7.2.2.8.12: Halt stops every coordinate. On a track the track brakes x and y; a MoveC
    or MoveZ that runs brakes too and its command is aborted."""
    rt = om.Runtime()
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(100.0, 0.0)))
    mover.enable()
    track = MC_PlanarTrack(rt)
    track.append_line(PositionXYC(0.0, 0.0), PositionXYC(600.0, 0.0))
    track.enable()
    rt.run(0.01)
    join = mover.join_track(track, None, ST_JoinTrackOptions(use_orientation=False))
    rt.run_until(lambda: join.done, timeout=5.0)
    turn = mover.move_c(200.0)
    lift = mover.move_z(5.0)
    rt.run(0.05)
    halt = mover.halt()
    rt.run(0.5)
    assert halt.done and turn.aborted and lift.aborted
    c, z = mover.position.c, mover.position.z
    assert 0.0 < c < 30.0 and 0.0 < z < 5.0  # stopped on the way, far from 200 and 5
    velocity = mover.mc_to_plc.set.set_velo
    assert velocity.c == 0.0 and velocity.z == 0.0
    rt.run(0.5)
    assert (mover.position.c, mover.position.z) == (c, z)


@pytest.mark.parametrize("call", [
    lambda m, t, ax: m.join_track(None),
    lambda m, t, ax: m.move_on_track(1.5, 100.0),
    lambda m, t, ax: m.gear_in_pos_on_track(ax, None, 0.0, 100.0, None),
    lambda m, t, ax: m.gear_in_pos_on_track(ax, 1.0, 0.0, 100.0, t),
    lambda m, t, ax: m.gear_in_pos_on_track(None, None, 0.0, 100.0, t),
    lambda m, t, ax: m.gear_in_pos_on_track_with_master_mover(ax, None, 0.0, t, 100.0, t),
    lambda m, t, ax: m.gear_in_pos_on_track_with_master_mover(m, None, 0.0, None, 100.0, t),
], ids=["join no track", "move to a number", "gear to no track", "a number as trail",
        "no master axis", "an axis as master mover", "master on no track"])
def test_a_wrong_track_argument_is_a_type_error_at_the_call(call):
    rt = om.Runtime()
    axis = rt.add_axis("master")
    mover = MC_PlanarMover(rt)
    track = MC_PlanarTrack(rt)
    with pytest.raises(TypeError, match="must be"):
        call(mover, track, axis)
    rt.step()  # nothing was queued


def test_a_follower_synced_on_a_track_off_its_way_is_an_error_id():
    """followMover without a trail (§6.2.12): the slave's sync track must lie on its way along
    the master; one that does not is PLANAR_INVALID_INPUT, and the cycle runs on."""
    rt = om.Runtime()
    first, second = (MC_PlanarMover(rt, PlanarMoverParameters(
        initial_position=MoverVector(x, 0.0))) for x in (100.0, 400.0))
    first.enable()
    second.enable()
    a, elsewhere = MC_PlanarTrack(rt), MC_PlanarTrack(rt)
    a.append_line(PositionXYC(0.0, 0.0), PositionXYC(600.0, 0.0))
    elsewhere.append_line(PositionXYC(0.0, 400.0), PositionXYC(600.0, 400.0))
    a.enable()
    elsewhere.enable()
    rt.run(0.01)
    joins = [first.join_track(a), second.join_track(a)]
    rt.run_until(lambda: all(j.done for j in joins), timeout=5.0)
    gear = first.gear_in_pos_on_track_with_master_mover(
        second, None, 0.0, a, 100.0, elsewhere,
        options=ST_GearInPosOnTrackWithMasterMoverOptions(follow_mover=True))
    rt.step()
    rt.step()
    assert gear.error and gear.error_id == ErrorId.PLANAR_INVALID_INPUT
    assert "not on the slave's way" in gear.message


def test_a_trail_takes_only_tracks():
    with pytest.raises(TypeError, match="MC_PlanarTrack"):
        MC_PlanarTrackTrail().add_track(None)
