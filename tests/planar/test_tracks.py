"""Movers on planar tracks: JoinTrack, MoveOnTrack, LeaveTrack, Halt, track modes, gaps
and switches (TF5430 §4.3, §6.2.2, §6.2.4, §6.2.5, §6.2.10)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.enums import ModuloDirection
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.planar import (
    CoordinateMode,
    DynamicConstraint_PathXY,
    MC_PlanarEnvironment,
    MC_PlanarFeedback,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarPart,
    MoverCommandMode,
    Part,
    PartLayout,
    PartPosition,
    PlanarObjectInfo,
    PlanarObjectType,
    PlanarState,
    Pose,
    PositionXYC,
    ST_EndAtTrackAdvancedOptions,
    ST_StartFromTrackAdvancedOptions,
    TrackOperationMode,
)
from openmotion.planar.options import ST_JoinTrackOptions, ST_MoveOnTrackOptions
from openmotion.planar.track import MC_PlanarTrack
from openmotion.testing import enabled_line as _line
from openmotion.testing import enabled_loop
from openmotion.testing import enabled_movers as _movers
from openmotion.testing import join_all as _joined

ON_TRACK = MoverCommandMode.ON_TRACK


def _run_until(rt: om.Runtime, *commands: object, timeout: float = 20.0) -> None:
    assert rt.run_until(lambda: all(c.done for c in commands), timeout=timeout), \
        [(c.kind, c.busy, c.error, c.message) for c in commands]


# -- §6.2.4 ------------------------------------------------------------------------------------


def test_6_2_4_two_movers_join_and_move_on_one_track():
    """§6.2.4: a 400 mm line, movers at x = 0 and 240 join in one cycle, then move to 150
    and 350 in one cycle; they end there, 200 mm (the default gap) apart."""
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (0.0, 0.0), (240.0, 0.0))
    track = MC_PlanarTrack(rt)
    track.append_line(PositionXYC(0.0, 0.0), PositionXYC(400.0, 0.0))
    track.enable()  # same cycle as the geometry (§6.2.4 state 0)
    rt.step()
    rt.step()
    assert track.mc_to_plc_std.state is PlanarState.ENABLED
    assert track.operation_mode is TrackOperationMode.STANDING
    assert track.get_length() == pytest.approx(400.0, abs=1e-9)
    _joined(rt, track, one, two)
    assert one.command_mode is ON_TRACK and two.command_mode is ON_TRACK
    assert track.mc_to_plc_std.mover_count_on_track == 2
    assert one.mc_to_plc.set_on_track.set_pos == pytest.approx(0.0, abs=1e-9)
    assert two.mc_to_plc.set_on_track.set_pos == pytest.approx(240.0, abs=1e-9)
    first, second = one.move_on_track(None, 150.0), two.move_on_track(None, 350.0)
    rt.step()
    rt.step()
    assert track.operation_mode is TrackOperationMode.MOVING
    assert track.mc_to_plc_std.moving_mover_count == 2
    _run_until(rt, first, second)
    assert one.mc_to_plc.set_on_track.set_pos == pytest.approx(150.0, abs=1e-9)
    assert two.mc_to_plc.set_on_track.set_pos == pytest.approx(350.0, abs=1e-9)
    assert (one.position.x, one.position.y) == pytest.approx((150.0, 0.0), abs=1e-9)
    assert (two.position.x, two.position.y) == pytest.approx((350.0, 0.0), abs=1e-9)
    assert one.mc_to_plc.set_on_track.track_oid == track.oid
    assert not one.error and not two.error
    rt.step()
    assert track.operation_mode is TrackOperationMode.STANDING


def test_join_moves_the_mover_onto_the_nearest_track_point_and_turns_it_along():
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (120.0, 60.0))
    track = _line(rt, (0.0, 120.0), (480.0, 120.0))
    join = mover.join_track(track)
    rt.step()
    rt.step()
    assert mover.command_mode is MoverCommandMode.JOINING_TRACK
    assert track.operation_mode is TrackOperationMode.CONFIGURING
    _run_until(rt, join)
    assert (mover.position.x, mover.position.y) == pytest.approx((120.0, 120.0), abs=1e-9)
    assert mover.mc_to_plc.set_on_track.set_pos == pytest.approx(120.0, abs=1e-9)
    assert mover.command_mode is ON_TRACK
    assert track.operation_mode is TrackOperationMode.STANDING


# -- gap keeping ----------------------------------------------------------------------------------


def test_a_mover_queues_one_gap_behind_a_standing_mover_and_goes_on_when_it_leaves():
    rt = om.Runtime(0.001)
    a, b = _movers(rt, (0.0, 0.0), (480.0, 0.0))
    track = _line(rt, (0.0, 0.0), (1200.0, 0.0))
    _joined(rt, track, a, b)
    move = a.move_on_track(None, 1000.0)
    rt.run(3.0)
    assert move.busy and not move.done  # waiting, not failed
    assert a.mc_to_plc.set_on_track.set_pos == pytest.approx(280.0, abs=1e-6)
    ahead = b.move_on_track(None, 1200.0)
    _run_until(rt, ahead)
    _run_until(rt, move)
    assert a.mc_to_plc.set_on_track.set_pos == pytest.approx(1000.0, abs=1e-9)


def test_the_gap_of_the_command_is_kept():
    rt = om.Runtime(0.001)
    a, b = _movers(rt, (0.0, 0.0), (700.0, 0.0))
    track = _line(rt, (0.0, 0.0), (1200.0, 0.0))
    _joined(rt, track, a, b)
    move = a.move_on_track(None, 650.0, options=ST_MoveOnTrackOptions(gap=300.0))
    rt.run(3.0)
    assert move.busy
    assert a.mc_to_plc.set_on_track.set_pos == pytest.approx(400.0, abs=1e-6)


def test_movers_in_a_row_never_come_closer_than_their_gap():
    rt = om.Runtime(0.001)
    movers = _movers(rt, *((x, 0.0) for x in (0.0, 240.0, 480.0, 720.0)))
    track = _line(rt, (0.0, 0.0), (1500.0, 0.0))
    _joined(rt, track, *movers)
    moves = [m.move_on_track(None, 1500.0) for m in movers[:3]]
    closest = math.inf
    for _ in range(3000):
        rt.step()
        xs = sorted(m.position.x for m in movers)
        closest = min(closest, *(b - a for a, b in zip(xs, xs[1:], strict=False)))
    assert closest >= 200.0 - 1e-6
    assert [m.mc_to_plc.set_on_track.set_pos for m in movers] == pytest.approx(
        [120.0, 320.0, 520.0, 720.0], abs=1e-6)
    assert all(move.busy for move in moves)


# -- acceptance (§4.2, §4.3) ---------------------------------------------------------------------


def test_join_is_refused_while_the_track_is_moving_and_a_move_while_it_is_configuring():
    rt = om.Runtime(0.001)
    a, b, c = _movers(rt, (0.0, 0.0), (600.0, 0.0), (600.0, 240.0))
    track = _line(rt, (0.0, 0.0), (1200.0, 0.0))
    _joined(rt, track, a, b)
    a.move_on_track(None, 300.0)
    rt.step()
    join = c.join_track(track)
    rt.step()
    assert join.error and join.error_id == ErrorId.PLANAR_WRONG_MODE
    leave = b.leave_track(PositionXYC(600.0, 480.0))
    rt.step()
    assert leave.error and leave.error_id == ErrorId.PLANAR_WRONG_MODE
    rt.run(2.0)
    join = c.join_track(track)
    rt.step()
    move = b.move_on_track(None, 900.0)
    rt.step()
    assert move.error and move.error_id == ErrorId.PLANAR_WRONG_MODE
    assert "Configuring" in move.message


def test_track_commands_of_a_mover_on_no_track_are_refused_by_mode():
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (0.0, 0.0))
    track = _line(rt, (0.0, 0.0), (400.0, 0.0))
    move = mover.move_on_track(track, 100.0)
    rt.step()
    assert move.error and move.error_id == ErrorId.PLANAR_WRONG_MODE
    assert "JoinTrack first" in move.message


def test_a_target_off_the_track_is_refused():
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (0.0, 0.0))
    track = _line(rt, (0.0, 0.0), (400.0, 0.0))
    _joined(rt, track, mover)
    for bad in (-1.0, 400.5, math.nan):
        move = mover.move_on_track(None, bad)
        rt.step()
        assert move.error, bad
        assert move.error_id in (ErrorId.PLANAR_POSITION_LIMIT, ErrorId.PLANAR_INVALID_INPUT)
    assert mover.mc_to_plc.set_on_track.set_pos == pytest.approx(0.0, abs=1e-12)


def test_a_track_without_geometry_cannot_be_enabled():
    rt = om.Runtime(0.001)
    track = MC_PlanarTrack(rt)
    enable = track.enable()
    rt.step()
    assert enable.error and enable.error_id == ErrorId.PLANAR_INVALID_INPUT
    assert track.operation_mode is TrackOperationMode.UNINITIALIZED
    assert track.get_length() == 0.0  # connected, no geometry yet (D-150)


@pytest.mark.parametrize("ranges", [(1.0,), (1.0, 2.0, 3.0), (-1.0, 0.0), (math.nan, 1.0),
                                    ("250", 250.0), (True, 250.0), 250.0])
def test_manual_collision_ranges_are_two_numbers_at_least_zero(ranges):
    rt = om.Runtime(0.001)
    with pytest.raises(ConfigError,
                       match=r"collision.ranges.*(two numbers >= 0|must be a (finite )?number)"):
        MC_PlanarTrack(rt, "t", collision_ranges=ranges)
    track = MC_PlanarTrack(rt, "u", collision_ranges=[100, 0])
    assert track.collision_ranges == (100.0, 0.0)


@pytest.mark.parametrize("reference", [1.0, "16#01010000", None, True])
def test_a_track_point_with_a_reference_id_that_is_no_int_is_a_type_error(reference):
    rt = om.Runtime(0.001)
    track = MC_PlanarTrack(rt)
    with pytest.raises(TypeError, match="reference id must be an int"):
        track.append_position(PositionXYC(0.0, 0.0, 0.0, reference))
    with pytest.raises(TypeError, match="reference id must be an int"):
        track.append_line(PositionXYC(0.0, 0.0), PositionXYC(100.0, 0.0, 0.0, reference))
    rt.step()
    assert track.get_length() == 0.0  # nothing was queued


def test_an_enabled_track_keeps_its_geometry():
    rt = om.Runtime(0.001)
    track = _line(rt, (0.0, 0.0), (400.0, 0.0))
    rt.step()
    append = track.append_line(PositionXYC(500.0, 0.0), PositionXYC(600.0, 0.0))
    rt.step()
    assert append.error and append.error_id == ErrorId.PLANAR_WRONG_STATE
    assert track.get_length() == pytest.approx(400.0)


# -- leave, halt ----------------------------------------------------------------------------------


def test_leave_track_uncouples_and_moves_freely():
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (0.0, 0.0))
    track = _line(rt, (0.0, 0.0), (400.0, 0.0))
    _joined(rt, track, mover)
    leave = mover.leave_track(PositionXYC(200.0, 240.0))
    rt.step()
    rt.step()
    assert mover.command_mode is MoverCommandMode.LEAVING_TRACK
    assert track.mc_to_plc_std.mover_count_on_track == 0
    _run_until(rt, leave)
    assert mover.command_mode is MoverCommandMode.FREE_MOVEMENT
    assert (mover.position.x, mover.position.y) == pytest.approx((200.0, 240.0), abs=1e-9)
    assert mover.mc_to_plc.set_on_track.track_oid == 0


def test_halt_on_a_track_stops_short_of_the_target():
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (0.0, 0.0))
    track = _line(rt, (0.0, 0.0), (2000.0, 0.0))
    _joined(rt, track, mover)
    move = mover.move_on_track(None, 2000.0)
    rt.run(0.3)
    halt = mover.halt()
    _run_until(rt, halt)
    assert move.aborted
    s = mover.mc_to_plc.set_on_track
    assert 0.0 < s.set_pos < 2000.0 and s.set_velo == 0.0


def test_a_halt_too_weak_to_stop_before_the_track_end_stops_exactly_there():
    """§6.1.9, §6.2.2, D-155: at 2000 mm/s 400 mm before the end of an open track, a Halt
    with 1000 mm/s² would need 2 m; the mover brakes harder and stops exactly at the end
    (its arc length went on to 3200 mm on a 1500 mm track, x stuck at the end)."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    track = _line(rt, (0.0, 0.0), (1500.0, 0.0))
    _joined(rt, track, mover)
    mover.move_on_track(None, 1400.0)
    while mover.mc_to_plc.set_on_track.set_pos < 1100.0:
        rt.step()
    assert mover.mc_to_plc.set_on_track.set_velo == pytest.approx(2000.0)
    halt = mover.halt(DynamicConstraint_PathXY(2000.0, 1000.0, 1000.0, 10000.0))
    furthest, x = 0.0, [mover.pose.x]
    while not halt.done:
        rt.step()
        furthest = max(furthest, mover.mc_to_plc.set_on_track.set_pos)
        x.append(mover.pose.x)
    s = mover.mc_to_plc.set_on_track
    assert s.set_pos == pytest.approx(1500.0, abs=1e-6) and furthest <= 1500.0 + 1e-6
    assert s.set_velo == 0.0 and mover.pose.x == pytest.approx(1500.0, abs=1e-6)
    steps = np.diff(np.array(x))
    assert steps.max() <= 2.0 + 1e-9 and np.all(np.abs(np.diff(steps)) < 0.1)  # no jump


def test_a_weak_halt_on_a_closed_loop_goes_on_round_the_loop():
    """A Halt that needs more than the rest of the route on a closed loop goes on round the
    loop, lap by lap, and stops where its dynamics take it (§6.1.9)."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt)
    length = loop.get_length()
    (mover,) = _movers(rt, (100.0, 0.0))
    _joined(rt, loop, mover)
    mover.move_on_track(None, length - 100.0)
    rt.run(0.8)
    moved = mover.mc_to_plc.set_on_track
    start, v = moved.set_pos, moved.set_velo
    assert v > 1000.0 and moved.set_acc == 0.0  # cruising (as fast as the corners allow)
    halt = mover.halt(DynamicConstraint_PathXY(2000.0, 200.0, 200.0, 2000.0))
    travelled, last = 0.0, start
    while not halt.done:
        rt.step()
        now = mover.mc_to_plc.set_on_track.set_pos
        assert 0.0 <= now < length  # on the loop: the arc length goes round, not on
        travelled += (now - last) % length
        last = now
    assert travelled > length  # round the seam at least once, with no stop at it
    assert travelled == pytest.approx(v * v / (2 * 200.0) + v * 200.0 / (2 * 2000.0), rel=0.02)


# -- networks (§6.2.2, §6.2.10) -------------------------------------------------------------------


def _merge(rt: om.Runtime, ranges: tuple[float, float] | None) -> tuple[MC_PlanarTrack, ...]:
    """t1 and t2 both end where t3 starts: a switch with two incoming tracks."""
    t3 = MC_PlanarTrack(rt, "t3")
    t3.append_line(PositionXYC(720.0, 240.0), PositionXYC(1680.0, 240.0))
    t1 = MC_PlanarTrack(rt, "t1", collision_ranges=ranges)
    t1.append_line(PositionXYC(0.0, 240.0), PositionXYC(480.0, 240.0))
    t1.end_at_track(t3)
    t2 = MC_PlanarTrack(rt, "t2", collision_ranges=ranges)
    t2.append_line(PositionXYC(0.0, 720.0), PositionXYC(480.0, 720.0))
    t2.end_at_track(t3)
    for track in (t3, t1, t2):
        track.enable()
    rt.step()
    rt.step()
    return t1, t2, t3


def test_links_make_a_switch_and_routes_cross_it():
    rt = om.Runtime(0.001)
    t1, t2, t3 = _merge(rt, None)
    assert t1.subsequent_tracks == [t3.oid] and t2.subsequent_tracks == [t3.oid]
    assert sorted(t3.previous_tracks) == sorted([t1.oid, t2.oid])
    (mover,) = _movers(rt, (100.0, 240.0))
    _joined(rt, t1, mover)
    move = mover.move_on_track(t3, 300.0)
    _run_until(rt, move)
    assert mover.mc_to_plc.set_on_track.track_oid == t3.oid
    assert (mover.position.x, mover.position.y) == pytest.approx((1020.0, 240.0), abs=1e-6)


def test_a_track_that_cannot_be_reached_is_refused():
    rt = om.Runtime(0.001)
    t1, t2, t3 = _merge(rt, None)
    (mover,) = _movers(rt, (1000.0, 240.0))
    _joined(rt, t3, mover)
    move = mover.move_on_track(t1, 100.0)
    rt.step()
    assert move.error and move.error_id == ErrorId.PLANAR_INVALID_INPUT
    assert "cannot be reached" in move.message


@pytest.mark.parametrize(("ranges", "gap", "wait"), [
    ((300.0, 300.0), 200.0, 300.0),  # the collision range binds: it waits at its start
    ((100.0, 100.0), 200.0, 200.0),  # the gap binds: one gap before the switch
])
def test_at_a_switch_the_second_mover_waits_at_its_last_safe_stop(ranges, gap, wait):
    """§6.2.2: a mover holds the switch; the other stops at the start of its collision range
    or one gap before the end of its track, whichever is further from the switch."""
    rt = om.Runtime(0.001)
    t1, t2, t3 = _merge(rt, ranges)
    here = t1.get_position_at(t1.get_length() - 50.0)
    there = t2.get_position_at(t2.get_length() - 420.0)
    a, b = _movers(rt, (here.x, here.y), (there.x, there.y))
    _joined(rt, t1, a)
    _joined(rt, t2, b)
    options = ST_MoveOnTrackOptions(gap=gap)
    second = b.move_on_track(t3, 300.0, options=options)  # a stands in its zone: it holds
    rt.run(3.0)
    assert second.busy
    s = b.mc_to_plc.set_on_track
    assert s.track_oid == t2.oid and s.set_velo == 0.0
    assert s.set_pos == pytest.approx(t2.get_length() - wait, abs=1e-6)
    first = a.move_on_track(t3, 600.0, options=options)
    closest = math.inf
    for _ in range(3000):
        rt.step()
        sa, sb = a.mc_to_plc.set_on_track, b.mc_to_plc.set_on_track
        if sa.track_oid == t3.oid:  # b follows a along its path: the arc length between
            ahead = sa.set_pos + (t2.get_length() - sb.set_pos if sb.track_oid == t2.oid
                                  else -sb.set_pos)
            closest = min(closest, ahead)
    _run_until(rt, first, second)
    assert closest >= gap - 1e-6  # b never comes closer than its gap along its path


@settings(max_examples=10, deadline=None)
@given(targets=st.lists(st.floats(0.0, 1200.0), min_size=3, max_size=3),
       gaps=st.lists(st.sampled_from([160.0, 200.0, 260.0]), min_size=3, max_size=3),
       order=st.permutations([0, 1, 2]))
def test_movers_on_a_line_never_undercut_their_gap_and_reachable_targets_are_reached(
        targets, gaps, order):
    rt = om.Runtime(0.001)
    movers = _movers(rt, (0.0, 0.0), (400.0, 0.0), (800.0, 0.0))
    track = _line(rt, (0.0, 0.0), (1200.0, 0.0))
    _joined(rt, track, *movers)
    moves = {}
    for i in order:
        moves[i] = movers[i].move_on_track(None, targets[i],
                                           options=ST_MoveOnTrackOptions(gap=gaps[i]))
    for _ in range(4000):
        rt.step()
        s = [m.mc_to_plc.set_on_track.set_pos for m in movers]
        for k in range(2):  # the order on the line never changes; the follower keeps its gap
            assert s[k + 1] - s[k] >= min(gaps[k], gaps[k + 1]) - 1e-6
        if all(c.done or not c.busy for c in moves.values()):
            break
    spaced = all(targets[k + 1] - targets[k] >= max(gaps) for k in range(2))
    if spaced:
        assert all(c.done for c in moves.values())
        assert [m.mc_to_plc.set_on_track.set_pos for m in movers] == pytest.approx(targets,
                                                                                   abs=1e-9)


def test_a_closed_loop_is_travelled_forwards_with_positive_direction():
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (0.0, 0.0))
    loop = MC_PlanarTrack(rt)
    for a, b in (((0.0, 0.0), (720.0, 0.0)), ((960.0, 240.0), (960.0, 480.0)),
                 ((720.0, 720.0), (0.0, 720.0)), ((-240.0, 480.0), (-240.0, 240.0))):
        loop.append_line(PositionXYC(*a), PositionXYC(*b))
    loop.close_loop()
    loop.enable()
    rt.step()
    rt.step()
    assert loop.closed_loop
    _joined(rt, loop, mover)
    start = mover.mc_to_plc.set_on_track.set_pos
    move = mover.move_on_track(None, start - 10.0 if start >= 10.0 else loop.get_length() - 10.0,
                               options=ST_MoveOnTrackOptions(direction=ModuloDirection.POSITIVE))
    rt.step()
    rt.step()
    assert mover.mc_to_plc.set_on_track.set_velo > 0.0  # forwards, the long way round
    _run_until(rt, move, timeout=30.0)


# -- worked examples with numbers ------------------------------------------------------------------


def test_6_5_a_track_in_a_group_is_refused_while_a_mover_stands_on_it():
    """§6.5: mover two stands on the track's surface, so mover one's first MoveOnTrack is
    refused naming mover two; after mover two has moved to (240, 320) the same command
    takes mover one to track position 150 = (150, 0)."""
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (0.0, 0.0), (240.0, 0.0))
    group = MC_PlanarGroup(rt)
    track = MC_PlanarTrack(rt)
    track.append_line(PositionXYC(0.0, 0.0), PositionXYC(400.0, 0.0))
    track.enable()
    group.enable()
    rt.run(0.005)
    joins = [one.add_to_group(group), two.add_to_group(group), track.add_to_group(group)]
    rt.step()
    rt.step()
    assert all(j.done for j in joins), [j.message for j in joins]
    assert track.mc_to_plc_std.group_oid == group.oid
    _joined(rt, track, one)
    feedback = MC_PlanarFeedback()
    first = one.move_on_track(None, 150.0, feedback=feedback)
    away = two.move_to_position(PositionXYC(240.0, 320.0))
    rt.step()
    rt.step()
    assert feedback.error and feedback.error_id == ErrorId.PLANAR_COLLISION
    assert feedback.object_info == PlanarObjectInfo(PlanarObjectType.MOVER, two.oid)
    assert first.error
    _run_until(rt, away)
    second = one.move_on_track(None, 150.0)
    rt.step()
    rt.step()
    assert track.operation_mode is TrackOperationMode.MOVING
    assert track in _holders(group)
    _run_until(rt, second)
    assert (one.position.x, one.position.y) == pytest.approx((150.0, 0.0), abs=1e-9)
    assert (two.position.x, two.position.y) == pytest.approx((240.0, 320.0), abs=1e-9)
    assert not one.error and not two.error
    rt.step()
    assert track not in _holders(group)  # Standing again: the surface is free


def _holders(group: MC_PlanarGroup) -> list[MC_PlanarTrack]:
    return [t for t in group.system.network.tracks if not group.reserved(t.member).is_empty]


def test_a_free_move_across_a_moving_track_is_refused_naming_the_track():
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (0.0, 0.0), (720.0, 360.0))
    group = MC_PlanarGroup(rt)
    track = MC_PlanarTrack(rt)
    track.append_line(PositionXYC(0.0, 0.0), PositionXYC(1440.0, 0.0))
    track.enable()
    group.enable()
    rt.run(0.005)
    for obj in (one, two, track):
        obj.add_to_group(group)
    rt.step()
    _joined(rt, track, one)
    one.move_on_track(None, 1400.0)
    rt.step()
    cross = two.move_to_position(PositionXYC(720.0, -360.0))
    rt.step()
    assert cross.error and cross.error_id == ErrorId.PLANAR_COLLISION
    assert cross.object_info == PlanarObjectInfo(PlanarObjectType.TRACK, track.oid)


def test_a_mover_in_a_group_moves_only_on_tracks_of_its_group():
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (0.0, 0.0))
    group = MC_PlanarGroup(rt)
    group.enable()
    track = _line(rt, (0.0, 0.0), (400.0, 0.0))
    mover.add_to_group(group)
    rt.step()
    _joined(rt, track, mover)
    move = mover.move_on_track(None, 200.0)
    rt.step()
    assert move.error and move.error_id == ErrorId.PLANAR_NOT_IN_GROUP


def test_6_2_5_a_mover_crosses_onto_the_track_that_starts_from_its_track():
    """§6.2.5 (its geometry, without the parts): track one (40,120)-(240,120); track two
    starts from it and appends (260,120)-(440,120), so a straight 20 mm joins them and track
    two is 200 long. The mover at (120,120) joins at 80 and moves to 150 on track two:
    x = 390."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (120.0, 120.0))
    one, two = MC_PlanarTrack(rt), MC_PlanarTrack(rt)
    one.append_line(PositionXYC(40.0, 120.0), PositionXYC(240.0, 120.0))
    two.start_from_track(one)
    two.append_line(PositionXYC(260.0, 120.0), PositionXYC(440.0, 120.0))
    one.enable()
    two.enable()
    rt.run(0.005)
    assert one.get_length() == pytest.approx(200.0, abs=1e-9)
    assert two.get_length() == pytest.approx(200.0, abs=1e-9)
    assert one.subsequent_tracks == [two.oid] and two.previous_tracks == [one.oid]
    _joined(rt, one, mover)
    assert mover.mc_to_plc.set_on_track.set_pos == pytest.approx(80.0, abs=1e-9)
    move = mover.move_on_track(two, 150.0)
    _run_until(rt, move)
    s = mover.mc_to_plc.set_on_track
    assert s.track_oid == two.oid and s.set_pos == pytest.approx(150.0, abs=1e-9)
    assert (mover.position.x, mover.position.y, mover.position.c) == pytest.approx(
        (390.0, 120.0, 0.0), abs=1e-9)


def test_a_move_back_that_cannot_stop_before_the_end_of_the_track_is_refused():
    """Track one (0,0)-(2000,0), track two starts from it. The mover runs at 2000 mm/s onto
    track two; 100 mm before the end of track one it is sent back to 500 on track one. With
    the command's dynamics it cannot stop before the end of track one, and from track two it
    may not come back (movers change track only from the end of one to the start of the
    next, §6.2.2): the command is refused and the mover goes on. Found by the track
    properties: the reversal ran past the end of track one while the mover stood at its end
    (D-137)."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    one, two = MC_PlanarTrack(rt), MC_PlanarTrack(rt)
    one.append_line(PositionXYC(0.0, 0.0), PositionXYC(2000.0, 0.0))
    two.start_from_track(one)
    two.append_line(PositionXYC(2000.0, 0.0), PositionXYC(3000.0, 0.0))
    one.enable()
    two.enable()
    rt.run(0.005)
    _joined(rt, one, mover)
    onward = mover.move_on_track(two, 900.0)
    assert rt.run_until(lambda: mover.mc_to_plc.set_on_track.set_pos > 1900.0, timeout=5.0)
    assert mover.mc_to_plc.set_on_track.set_velo == pytest.approx(2000.0)
    back = mover.move_on_track(one, 500.0)
    rt.step()
    assert back.error and back.error_id == ErrorId.PLANAR_POSITION_LIMIT, back.message
    _run_until(rt, onward)
    s = mover.mc_to_plc.set_on_track
    assert s.track_oid == two.oid and s.set_pos == pytest.approx(900.0, abs=1e-9)


def test_6_2_10_four_tracks_make_a_loop_and_a_switch():
    """§6.2.10: track one (three lines), track two from its end back to its start, tracks
    three and four from its end as well: the end of track one is a switch with three
    tracks leaving it; all four are Enabled and Standing, nobody on them."""
    rt = om.Runtime(0.001)
    one, two, three, four = (MC_PlanarTrack(rt) for _ in range(4))

    def p(x: float, y: float) -> PositionXYC:
        return PositionXYC(x, y)

    one.append_line(p(250, 120), p(650, 120))
    one.append_line(p(700, 170), p(700, 450))  # the digest's reading of (800, 450), §8
    one.append_line(p(650, 500), p(250, 500))
    two.start_from_track(one)
    two.append_line(p(200, 450), p(200, 170))
    two.end_at_track(one)
    three.start_from_track(one)
    three.append_line(p(200, 500), p(120, 500))
    four.start_from_track(one)
    four.append_line(p(200, 550), p(200, 750))
    for track in (one, two, three, four):
        track.enable()
    rt.run(0.005)
    for track in (one, two, three, four):
        std = track.mc_to_plc_std
        assert std.state is PlanarState.ENABLED
        assert std.operation_mode is TrackOperationMode.STANDING
        assert (std.mover_count_on_track, std.moving_mover_count, std.group_oid) == (0, 0, 0)
    assert sorted(one.subsequent_tracks) == sorted([two.oid, three.oid, four.oid])
    assert two.subsequent_tracks == [one.oid] and one.previous_tracks == [two.oid]
    assert one.network.switches(one)[1] is not None  # the end of track one
    assert not one.closed_loop
    again = one.append_line(p(250, 500), p(100, 500))  # frozen by the links
    rt.step()
    assert again.error and again.error_id == ErrorId.PLANAR_WRONG_STATE


# -- C on a track (§6.2.6, §6.2.7) ----------------------------------------------------------------


def _two_on_a_line(use_orientation: bool) -> tuple[om.Runtime, MC_PlanarTrack,
                                                    MC_PlanarMover, MC_PlanarMover]:
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (0.0, 0.0), (240.0, 0.0))
    track = _line(rt, (0.0, 0.0), (400.0, 0.0))
    options = ST_JoinTrackOptions(use_orientation=use_orientation)
    joins = [m.join_track(track, options=options) for m in (one, two)]
    _run_until(rt, *joins)
    return rt, track, one, two


def test_6_2_6_move_c_on_a_track_ends_in_c_rotation_on_track_outside_the_windows():
    """§6.2.6: joined without orientation; MoveC to 20 and to 90: both rotate in
    CRotationOnTrack; 20 lies in no C window (mover one stays CRotationOnTrack), 90 does
    (mover two is OnTrack again)."""
    rt, _, one, two = _two_on_a_line(False)
    first, second = one.move_c(20.0), two.move_c(90.0)
    rt.step()
    rt.step()
    assert one.command_mode is MoverCommandMode.C_ROTATION_ON_TRACK
    assert two.command_mode is MoverCommandMode.C_ROTATION_ON_TRACK
    _run_until(rt, first, second)
    rt.step()
    assert one.position.c == pytest.approx(20.0, abs=1e-9)
    assert two.position.c == pytest.approx(90.0, abs=1e-9)
    assert one.command_mode is MoverCommandMode.C_ROTATION_ON_TRACK
    assert two.command_mode is ON_TRACK
    stuck = one.move_on_track(None, 300.0)
    rt.step()
    assert stuck.error and stuck.error_id == ErrorId.PLANAR_WRONG_MODE


def test_6_2_7_adopt_track_orientation_couples_c_to_the_track_again():
    """§6.2.7: joined with orientation (C Dependent); MoveC to 20 and 190 makes C
    Independent; AdoptTrackOrientation turns both back to the track's heading the short way
    (0 and 360) and C is Dependent again."""
    rt, _, one, two = _two_on_a_line(True)
    assert one.mc_to_plc.coord_mode.c_coordinate_mode is CoordinateMode.DEPENDENT
    first, second = one.move_c(20.0), two.move_c(190.0)
    _run_until(rt, first, second)
    rt.step()
    assert one.mc_to_plc.coord_mode.c_coordinate_mode is CoordinateMode.INDEPENDENT
    assert one.command_mode is MoverCommandMode.C_ROTATION_ON_TRACK
    assert two.command_mode is ON_TRACK
    adopt = [m.adopt_track_orientation() for m in (one, two)]
    _run_until(rt, *adopt)
    rt.step()
    for mover in (one, two):
        modes = mover.mc_to_plc.coord_mode
        assert mover.command_mode is ON_TRACK
        assert modes.xy_coordinate_mode is CoordinateMode.DEPENDENT
        assert modes.z_coordinate_mode is CoordinateMode.INDEPENDENT
        assert modes.c_coordinate_mode is CoordinateMode.DEPENDENT
    assert one.position.c == pytest.approx(0.0, abs=1e-9)
    assert two.position.c == pytest.approx(360.0, abs=1e-9)  # 190 -> 360, the short way


def test_move_c_is_refused_while_the_mover_moves_on_its_track():
    rt, _, one, _ = _two_on_a_line(True)
    one.move_on_track(None, 100.0)
    rt.step()
    turn = one.move_c(10.0)
    rt.step()
    assert turn.error and turn.error_id == ErrorId.PLANAR_WRONG_MODE


# -- tracks on parts (§6.2.3, §6.2.11) -------------------------------------------------------------

CS = 0x01010010
PART_1, PART_2 = 0x01010020, 0x01010030


def _parts_6_2_11() -> tuple[om.Runtime, MC_PlanarEnvironment, PartLayout,
                              tuple[MC_PlanarTrack, MC_PlanarTrack, MC_PlanarTrack]]:
    """§6.2.11: part 1 (8 stators) and part 2 (2 stators) beside it, lower or upper. Track
    three makes a U-turn on part 2; tracks two and one on part 1 start from and end at it
    with the Advanced links."""
    layout = PartLayout([CS], [
        Part(PART_1, [(x, y) for x in (0.0, 240.0) for y in (0.0, 240.0, 480.0, 720.0)],
             [PartPosition(CS, Pose())]),
        Part(PART_2, [(0.0, 0.0), (0.0, 240.0)],
             [PartPosition(CS, Pose(480.0, 0.0)), PartPosition(CS, Pose(480.0, 480.0))]),
    ])
    rt = om.Runtime(0.001)
    environment = MC_PlanarEnvironment(rt, layout)
    one = MC_PlanarTrack(rt, "one", part_oid=PART_1)
    two = MC_PlanarTrack(rt, "two", part_oid=PART_1)
    three = MC_PlanarTrack(rt, "three", part_oid=PART_2)

    def on(part: int, x: float, y: float) -> PositionXYC:
        return PositionXYC(x, y, 0.0, part)

    for a, b in (((0, 360), (80, 360)), ((120, 320), (120, 160)), ((80, 120), (0, 120))):
        three.append_line(on(PART_2, *a), on(PART_2, *b))
    rt.step()
    two.start_from_track_advanced(three, ST_StartFromTrackAdvancedOptions(1, 2))
    for a, b in (((440, 600), (400, 600)), ((360, 560), (360, 400)), ((400, 360), (440, 360))):
        two.append_line(on(PART_1, *a), on(PART_1, *b))
    two.end_at_track_advanced(three, ST_EndAtTrackAdvancedOptions(1, 1))
    rt.step()
    one.start_from_track_advanced(three, ST_StartFromTrackAdvancedOptions(1, 1))
    for a, b in (((440, 120), (160, 120)), ((120, 160), (120, 800)), ((160, 840), (440, 840))):
        one.append_line(on(PART_1, *a), on(PART_1, *b))
    commands = [one.end_at_track_advanced(three, ST_EndAtTrackAdvancedOptions(1, 2))]
    commands += [t.enable() for t in (one, two, three)]
    rt.run(0.005)
    assert all(c.done for c in commands), [c.message for c in commands]
    return rt, environment, layout, (one, two, three)


def test_6_2_11_links_across_parts_hold_only_where_the_parts_meet():
    """Part 2 lower: two -> three -> one; upper: one -> three -> two. Tracks two and three
    have the same length."""
    _, _, layout, (one, two, three) = _parts_6_2_11()
    assert two.get_length() == pytest.approx(three.get_length(), abs=1e-9)
    # part 2 lower: track two ends where track three starts, three ends where one starts
    assert two.subsequent_tracks == [three.oid] and three.subsequent_tracks == [one.oid]
    assert one.subsequent_tracks == [] and three.previous_tracks == [two.oid]
    start = three.get_position_at(0.0)
    assert (start.x, start.y) == pytest.approx((480.0, 360.0), abs=1e-9)  # on the boundary
    layout.activate_position(PART_2, 2)
    assert one.subsequent_tracks == [three.oid] and three.subsequent_tracks == [two.oid]
    assert two.subsequent_tracks == [] and three.previous_tracks == [one.oid]
    start = three.get_position_at(0.0)  # the track moved with its part
    assert (start.x, start.y) == pytest.approx((480.0, 840.0), abs=1e-9)


def test_a_mover_on_a_track_of_a_part_rides_along_when_the_part_moves_and_drives_on():
    """§6.2.3, §6.2.11, §6.6.1: a mover joins track three on part 2 (placed away from the
    origin: it joins where it stands), stands while part 2 goes from lower to upper, moves
    with it, and then drives on over the link that holds there, three -> two."""
    rt, environment, _, (_, two, three) = _parts_6_2_11()
    here = three.get_position_at(100.0)
    mover, = _movers(rt, (here.x, here.y))
    _joined(rt, three, mover)
    assert mover.pose[:2] == pytest.approx((here.x, here.y), abs=1e-9)  # no move to join
    part = MC_PlanarPart()
    part.initialize(PART_2, environment)
    rt.step()
    lift = part.activate_position(2)
    rt.run(0.005)
    assert lift.done and mover.coordinate_system == CS
    assert mover.pose[:2] == pytest.approx((here.x, here.y + 480.0), abs=1e-9)
    lifted = three.get_position_at(100.0)
    assert (lifted.x, lifted.y) == pytest.approx((here.x, here.y + 480.0), abs=1e-9)
    move = mover.move_on_track(two, 200.0)
    path = [mover.pose[:2]]
    while move.busy or not path[1:]:
        rt.step()
        path.append(mover.pose[:2])
    assert move.done, move.message
    end = two.get_position_at(200.0)
    assert mover.pose[:2] == pytest.approx((end.x, end.y), abs=1e-6)
    steps = np.hypot(*np.diff(np.array(path), axis=0).T)
    assert steps.max() < 2000.0 * 0.001 + 1e-9  # at most the default velocity: no jump


def test_automatic_collision_ranges_across_parts_are_those_of_one_frame_and_follow_the_parts():
    """§6.2.2, §6.2.3: tracks p (part 1) and s (part 2) both start where r ends, at the
    edge between the parts: a switch. Their automatic ranges are those of the same tracks
    drawn without parts; when part 2 moves away the switch is gone and so are they."""

    def build(parts: bool) -> tuple[PartLayout | None, list[MC_PlanarTrack]]:
        rt = om.Runtime(0.001)
        layout = None
        if parts:
            layout = PartLayout([CS], [
                Part(PART_1, [(x, y) for x in (0.0, 240.0) for y in (0.0, 240.0)],
                     [PartPosition(CS, Pose())]),
                Part(PART_2, [(0.0, 0.0), (0.0, 240.0)],
                     [PartPosition(CS, Pose(480.0, 0.0)), PartPosition(CS, Pose(480.0, 480.0))])])
            MC_PlanarEnvironment(rt, layout)

        def track(name: str, part: int) -> MC_PlanarTrack:
            return MC_PlanarTrack(rt, name, part_oid=part) if parts else MC_PlanarTrack(rt, name)

        def at(part: int, x: float, y: float) -> PositionXYC:
            if not parts:
                return PositionXYC(x, y)
            return PositionXYC(x - (480.0 if part == PART_2 else 0.0), y, 0.0, part)

        r, p, s = track("r", PART_1), track("p", PART_1), track("s", PART_2)
        r.append_line(at(PART_1, 480.0, 0.0), at(PART_1, 480.0, 100.0))
        rt.step()
        p.start_from_track(r)
        p.append_line(at(PART_1, 380.0, 300.0), at(PART_1, 100.0, 300.0))
        s.start_from_track(r)
        s.append_line(at(PART_2, 580.0, 300.0), at(PART_2, 700.0, 300.0))
        enables = [t.enable() for t in (r, p, s)]
        rt.run(0.005)
        assert all(e.done for e in enables), [e.message for e in enables]
        return layout, [r, p, s]

    _, flat = build(False)
    layout, placed = build(True)
    assert placed[0].subsequent_tracks == [placed[1].oid, placed[2].oid]
    expected = [t.collision_ranges for t in flat]
    assert expected[1][0] > 300.0 and expected[2][0] > 300.0  # the branches share their start
    for track, ranges in zip(placed, expected, strict=True):
        assert track.collision_ranges == pytest.approx(ranges, abs=1e-6)
    layout.activate_position(PART_2, 2)
    assert placed[0].subsequent_tracks == [placed[1].oid]
    assert [t.collision_ranges for t in placed] == [(0.0, 0.0)] * 3


def test_a_track_point_in_a_coordinate_system_is_taken_into_the_part_frame():
    layout = PartLayout([CS], [Part(PART_2, [(0.0, 0.0), (0.0, 240.0)],
                                    [PartPosition(CS, Pose(480.0, 0.0))])])
    rt = om.Runtime(0.001)
    MC_PlanarEnvironment(rt, layout)
    track = MC_PlanarTrack(rt)  # the only part: it is on it
    track.append_line(PositionXYC(500.0, 120.0, 0.0, CS), PositionXYC(700.0, 120.0, 0.0, CS))
    track.enable()
    rt.run(0.003)
    assert track.part().oid == PART_2
    end = track.get_position_at(track.get_length())
    assert (end.x, end.y, end.reference_id) == pytest.approx((700.0, 120.0, CS), abs=1e-9)
    assert track.path.end_pose.x == pytest.approx(220.0)  # stored in the part frame
