"""Gear-in on tracks: GearInPosOnTrack, GearInPosOnTrackWithMasterMover, the track trail
(TF5430 §6.2.8, §6.2.9, §6.2.12, §6.8.1), closed loops and modulo sync positions (D-148),
a follower's later tracks in a group (D-149)."""

from __future__ import annotations

import math
from unittest import mock

import pytest

import openmotion as om
from openmotion.core.enums import ModuloDirection
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar import (
    DynamicConstraint_PathXY,
    MC_PlanarFeedbackGearInPosOnTrack,
    MC_PlanarFeedbackGearInPosOnTrackWithMasterMover,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarTrack,
    MC_PlanarTrackTrail,
    MoverVector,
    PlanarMoverParameters,
    PlanarObjectInfo,
    PlanarObjectType,
    PlanarState,
    PositionXYC,
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
)
from openmotion.rail.gear import GearSync
from openmotion.testing import enabled_line, enabled_loop, enabled_movers, join_all


def _mover(rt: om.Runtime, x: float = 0.0, y: float = 0.0) -> MC_PlanarMover:
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x, y)))
    mover.enable()
    rt.run(0.005)
    return mover


def _track(rt: om.Runtime, *points: tuple[float, float], after: MC_PlanarTrack | None = None
           ) -> MC_PlanarTrack:
    track = MC_PlanarTrack(rt)
    if after is not None:
        track.start_from_track(after)
    for a, b in zip(points[::2], points[1::2], strict=True):
        track.append_line(PositionXYC(*a), PositionXYC(*b))
    track.enable()
    rt.run_until(lambda: track.state is PlanarState.ENABLED, timeout=1.0)
    return track


def _join(rt: om.Runtime, mover: MC_PlanarMover, track: MC_PlanarTrack) -> None:
    join = mover.join_track(track)
    rt.run_until(lambda: join.done, timeout=10.0)


def _axis(rt: om.Runtime) -> om.Axis:
    axis = rt.add_axis("master")
    axis.power()
    rt.run(0.01)
    return axis


def test_6_2_8_a_mover_follows_an_axis_one_to_one():
    """§6.2.8: track (100,100)-(860,100); the axis moves to 600 at 30 mm/s; gear-in with
    both sync positions 100: the mover cruises at 30 mm/s with the axis and stands at 600."""
    rt = om.Runtime(0.001)
    track = _track(rt, (100.0, 100.0), (860.0, 100.0))
    mover = _mover(rt)
    _join(rt, mover, track)
    axis = _axis(rt)
    axis.move_absolute(600.0, 30.0, acceleration=100.0, deceleration=100.0, jerk=100.0)
    rt.step()
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    gear = mover.gear_in_pos_on_track(axis, None, 100.0, 100.0, track, feedback=feedback)
    rt.run(8.0)
    s = mover.mc_to_plc.set_on_track
    assert s.set_velo == pytest.approx(30.0, abs=1e-9)
    assert s.set_pos == pytest.approx(axis.set_position, abs=1e-9)
    assert feedback.in_sync and feedback.active and not feedback.error
    rt.run(20.0)
    s = mover.mc_to_plc.set_on_track
    assert s.set_pos == pytest.approx(600.0, abs=1e-9) and s.set_velo == 0.0
    assert gear.active  # coupled until another command (§6.2.8)


def test_6_2_8_variant_the_mover_stops_at_the_track_end_with_an_error():
    rt = om.Runtime(0.001)
    track = _track(rt, (100.0, 100.0), (860.0, 100.0))
    mover = _mover(rt)
    _join(rt, mover, track)
    axis = _axis(rt)
    axis.move_absolute(1200.0, 300.0, acceleration=1000.0, deceleration=1000.0, jerk=10000.0)
    rt.step()
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    mover.gear_in_pos_on_track(axis, None, 0.0, 0.0, track, feedback=feedback)
    rt.run(6.0)
    assert feedback.error and feedback.error_id == ErrorId.PLANAR_PATH_END
    assert not feedback.in_sync
    s = mover.mc_to_plc.set_on_track
    assert s.set_pos == pytest.approx(760.0, abs=1e-9) and s.set_velo == 0.0
    assert mover.state is PlanarState.ENABLED  # the command fails, not the mover


def test_6_8_1_a_trail_takes_the_slave_onto_the_next_track():
    """§6.8.1: track 1 (100,100)-(400,100), track 2 from it to (860,100); trail [1, 2]; the
    axis moves to 700; the mover ends on track 2 at 400 (= 700 - 300)."""
    rt = om.Runtime(0.001)
    one = _track(rt, (100.0, 100.0), (400.0, 100.0))
    two = _track(rt, (500.0, 100.0), (860.0, 100.0), after=one)
    assert two.get_length() == pytest.approx(460.0, abs=1e-9)
    mover = _mover(rt)
    _join(rt, mover, one)
    axis = _axis(rt)
    axis.move_absolute(700.0, 30.0, acceleration=100.0, deceleration=100.0, jerk=100.0)
    rt.step()
    trail = MC_PlanarTrackTrail()
    assert trail.add_track(one) and trail.add_track(two)
    gear = mover.gear_in_pos_on_track(axis, trail, 100.0, 100.0, one)
    rt.run(30.0)
    s = mover.mc_to_plc.set_on_track
    assert s.track_oid == two.oid
    assert s.set_pos == pytest.approx(400.0, abs=1e-9) and s.set_velo == 0.0
    assert gear.active and not gear.error


def test_a_trail_refuses_tracks_that_do_not_follow_or_repeat():
    rt = om.Runtime(0.001)
    one = _track(rt, (100.0, 100.0), (400.0, 100.0))
    other = _track(rt, (100.0, 400.0), (400.0, 400.0))
    trail = MC_PlanarTrackTrail()
    assert trail.add_track(one)
    assert not trail.add_track(one) and "already" in trail.message
    assert not trail.add_track(other) and trail.error
    assert trail.tracks == [one]


def test_6_2_9_a_mover_follows_a_master_mover_on_a_parallel_track():
    """§6.2.9: master and slave tracks of 760 mm; the master moves to 500; the slave,
    geared with both sync positions 100, stops at 500 too."""
    rt = om.Runtime(0.001)
    master_track = _track(rt, (100.0, 620.0), (860.0, 620.0))
    slave_track = _track(rt, (100.0, 100.0), (860.0, 100.0))
    master, slave = _mover(rt, 100.0, 620.0), _mover(rt, 100.0, 100.0)
    _join(rt, master, master_track)
    _join(rt, slave, slave_track)
    move = master.move_on_track(None, 500.0)
    rt.step()
    feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover()
    slave.gear_in_pos_on_track_with_master_mover(master, None, 100.0, master_track, 100.0,
                                                 slave_track, feedback=feedback)
    rt.run_until(lambda: move.done, timeout=20.0)
    rt.run(1.0)
    assert slave.mc_to_plc.set_on_track.set_pos == pytest.approx(500.0, abs=1e-9)
    assert feedback.active and feedback.in_sync


def test_6_2_12_follow_mover_takes_the_master_s_branch_at_the_switch():
    """§6.2.12: track_in (100,360)-(400,360); out1 and out2 start from it; the master goes
    to 500 on out1; the slave, geared 210/10 with followMover, trails it by 200 onto out1
    and stands at 300 there."""
    rt = om.Runtime(0.001)
    track_in = _track(rt, (100.0, 360.0), (400.0, 360.0))
    out1 = _track(rt, (450.0, 410.0), (860.0, 620.0), after=track_in)
    out2 = _track(rt, (450.0, 310.0), (860.0, 100.0), after=track_in)
    assert sorted(track_in.subsequent_tracks) == sorted([out1.oid, out2.oid])
    master, slave = _mover(rt, 300.0, 360.0), _mover(rt, 100.0, 360.0)
    _join(rt, master, track_in)
    _join(rt, slave, track_in)
    move = master.move_on_track(out1, 500.0)
    rt.step()
    options = ST_GearInPosOnTrackWithMasterMoverOptions(follow_mover=True)
    gear = slave.gear_in_pos_on_track_with_master_mover(master, None, 210.0, track_in, 10.0,
                                                        track_in, options=options)
    rt.run_until(lambda: move.done, timeout=30.0)
    rt.run(2.0)
    m, s = master.mc_to_plc.set_on_track, slave.mc_to_plc.set_on_track
    assert (m.track_oid, s.track_oid) == (out1.oid, out1.oid)
    assert m.set_pos == pytest.approx(500.0, abs=1e-9)
    assert s.set_pos == pytest.approx(300.0, abs=1e-9) and s.set_velo == 0.0
    assert gear.active and not gear.error


def test_a_gear_in_to_a_moving_master_starts_where_the_slave_stands():
    """The slave stands at 1000 when it gears in to an axis cruising at 500 mm/s (its coupled
    position lies ahead): its first setpoints run on from rest without a jump. Found by the
    track properties: the sync was planned with the master of this cycle as if it were last
    cycle's, so the slave jumped back by the master's travel in one cycle (0.5 mm). Fixed
    (D-137): the axis's values one cycle back along its jerk."""
    rt = om.Runtime(0.001)
    track = _track(rt, (0.0, 0.0), (3000.0, 0.0))
    mover = _mover(rt, 1000.0, 0.0)
    _join(rt, mover, track)
    axis = _axis(rt)
    axis.move_absolute(5000.0, 500.0)
    rt.run(1.0)
    assert axis.set_velocity == pytest.approx(500.0)
    mover.gear_in_pos_on_track(axis, None, axis.set_position + 500.0, 2000.0, track)
    last = mover.mc_to_plc.set_on_track.set_pos
    for _ in range(50):
        rt.step()
        now = mover.mc_to_plc.set_on_track.set_pos
        assert now >= last - 1e-9, now - last
        last = now


def test_a_sync_that_finds_no_plan_stops_the_mover_and_ends_in_error():
    """When the sync cannot be planned (ruckig finds no profile, an option it cannot keep),
    the geared mover brakes to rest with its command's dynamics and the command then ends in
    that error; it is not left busy."""
    rt = om.Runtime(0.001)
    track = _track(rt, (0.0, 0.0), (2000.0, 0.0))
    mover = _mover(rt, 100.0, 0.0)
    _join(rt, mover, track)
    axis = _axis(rt)
    axis.move_velocity(200.0)
    rt.step()
    gear = mover.gear_in_pos_on_track(axis, None, 0.0, 500.0, track)  # ahead: it starts
    rt.run(0.3)
    assert gear.active and mover.mc_to_plc.set_on_track.set_velo > 50.0
    with mock.patch.object(GearSync, "step",
                           side_effect=CommandRejected(ErrorId.NO_PROFILE, "no sync plan")):
        rt.run(1.0)
    assert gear.error and gear.error_id == ErrorId.NO_PROFILE and not gear.busy
    assert mover.mc_to_plc.set_on_track.set_velo == 0.0
    position = mover.mc_to_plc.set_on_track.set_pos
    rt.run(0.5)
    assert mover.mc_to_plc.set_on_track.set_pos == position


def test_a_moving_slave_never_turns_against_its_allowed_sync_direction():
    """§6.1.9: allowedSlaveSyncDirections (Positive by default) holds in the whole sync phase,
    also for a slave that is moving when it gears in: one that cannot stop at its sync point
    comes to rest beyond it, never turning back, and syncs once the master comes."""
    rt = om.Runtime(0.001)
    track = _track(rt, (0.0, 0.0), (3000.0, 0.0))
    mover = _mover(rt, 100.0, 0.0)
    _join(rt, mover, track)
    axis = _axis(rt)
    mover.move_on_track(None, 2500.0)
    rt.run(0.6)
    start = mover.mc_to_plc.set_on_track
    assert start.set_velo == pytest.approx(2000.0)
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    mover.gear_in_pos_on_track(axis, None, 0.0, start.set_pos + 50.0, track, feedback=feedback)
    lowest = math.inf
    for _ in range(1500):
        rt.step()
        lowest = min(lowest, mover.mc_to_plc.set_on_track.set_velo)
    rest = mover.mc_to_plc.set_on_track
    assert lowest >= -1e-9 and rest.set_velo == 0.0 and not feedback.in_sync  # was -260
    assert rest.set_pos > start.set_pos + 50.0  # beyond the sync point: it waits there
    axis.move_velocity(100.0)
    for _ in range(6000):
        rt.step()
        lowest = min(lowest, mover.mc_to_plc.set_on_track.set_velo)
    assert lowest >= -1e-9 and feedback.in_sync
    assert mover.mc_to_plc.set_on_track.set_velo == pytest.approx(100.0)


def test_a_slave_held_at_a_switch_waits_at_its_last_safe_stop_and_syncs_once_free():
    """§6.2.2, §6.2.8: a slave in sync runs up to a switch another mover holds; it brakes
    to its last safe stop and waits there (it did move back at up to 95 mm/s and to and
    fro around the line), out of sync; once the switch is free it synchronises, follows the
    master through the switch and stops one gap behind the mover ahead without jitter."""
    rt = om.Runtime(0.001)
    t3 = _track(rt, (720.0, 240.0), (1680.0, 240.0))
    t1 = MC_PlanarTrack(rt, "t1", collision_ranges=(300.0, 300.0))
    t2 = MC_PlanarTrack(rt, "t2", collision_ranges=(300.0, 300.0))
    for track, y in ((t1, 240.0), (t2, 720.0)):
        track.append_line(PositionXYC(0.0, y), PositionXYC(480.0, y))
        track.end_at_track(t3)
        track.enable()
    rt.run(0.005)
    here = t1.get_position_at(t1.get_length() - 50.0)
    there = t2.get_position_at(t2.get_length() - 700.0)
    holder, slave = _mover(rt, here.x, here.y), _mover(rt, there.x, there.y)
    _join(rt, holder, t1)
    _join(rt, slave, t2)
    axis = _axis(rt)
    trail = MC_PlanarTrackTrail()
    assert trail.add_track(t2) and trail.add_track(t3)
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    slave.gear_in_pos_on_track(axis, trail, 1000.0, 300.0, t3, feedback=feedback)
    axis.move_absolute(2000.0, 200.0)
    line = t2.get_length() - 300.0  # the start of its collision range
    velocities = []
    for _ in range(3000):
        rt.step()
        velocities.append(slave.mc_to_plc.set_on_track.set_velo)
    s = slave.mc_to_plc.set_on_track
    assert s.track_oid == t2.oid and s.set_pos == pytest.approx(line, abs=0.011)
    assert s.set_pos <= line and min(velocities) >= 0.0 and not feedback.in_sync
    assert velocities[-800:] == [0.0] * 800  # it stands: no creeping to and fro
    holder.move_on_track(t3, 900.0)
    seen_in_sync, velocities = False, []
    for _ in range(5000):
        rt.step()
        seen_in_sync |= feedback.in_sync
        velocities.append(slave.mc_to_plc.set_on_track.set_velo)
    s = slave.mc_to_plc.set_on_track
    assert seen_in_sync and feedback.busy and not feedback.error
    assert s.track_oid == t3.oid and s.set_pos == pytest.approx(700.0, abs=0.011)
    assert min(velocities) >= 0.0 and velocities[-500:] == [0.0] * 500
    assert not feedback.in_sync  # the master went on: the slave waits behind the holder


def test_a_master_faster_than_the_command_is_followed_at_the_command_velocity():
    """§6.2.8: with a velocity limit below the master's the mover still tries to synchronise:
    it runs at its limit, never above, and syncs once the master is slow enough."""
    rt = om.Runtime(0.001)
    track = _track(rt, (0.0, 0.0), (8000.0, 0.0))
    mover = _mover(rt, 100.0, 0.0)
    _join(rt, mover, track)
    axis = _axis(rt)
    axis.move_velocity(500.0)
    rt.run(0.5)
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    mover.gear_in_pos_on_track(axis, None, axis.set_position, 200.0, track,
                               DynamicConstraint_PathXY(velocity=100.0), feedback=feedback)
    fastest = 0.0
    for _ in range(3000):
        rt.step()
        fastest = max(fastest, mover.mc_to_plc.set_on_track.set_velo)
    assert fastest <= 100.0 * (1 + 1e-9) and not feedback.in_sync and not feedback.error
    assert mover.mc_to_plc.set_on_track.set_velo == pytest.approx(100.0)
    axis.move_velocity(20.0)  # the master slows: the mover catches up and syncs
    rt.run_until(lambda: feedback.in_sync, timeout=60.0)
    for _ in range(1000):
        rt.step()
        fastest = max(fastest, mover.mc_to_plc.set_on_track.set_velo)
    assert fastest <= 100.0 * (1 + 1e-9)
    assert mover.mc_to_plc.set_on_track.set_velo == pytest.approx(20.0)


# -- closed loops and modulo sync positions (D-148) -------------------------------------------


def _slave_on_loop(rt: om.Runtime, x: float = 300.0) -> tuple[MC_PlanarTrack, MC_PlanarMover,
                                                                om.Axis]:
    loop = enabled_loop(rt, name="loop")
    (mover,) = enabled_movers(rt, (x, 0.0))
    join_all(rt, loop, mover)
    return loop, mover, _axis(rt)


def _within(position: float, expected: float, length: float) -> float:
    """The distance of two arc lengths on a loop of ``length``."""
    d = (position - expected) % length
    return min(d, length - d)


def test_a_slave_on_a_closed_loop_goes_round_with_its_axis_master():
    """§6.2.8 on a closed loop: the axis moves 3.5 loop lengths; the slave, geared 0/300 on
    the loop without a trail, goes round with it in sync (its arc length is 300 + axis modulo
    the length) and never stops at the seam. It stopped there with PLANAR_PATH_END before."""
    rt = om.Runtime(0.001)
    loop, mover, axis = _slave_on_loop(rt)
    length = loop.get_length()
    axis.move_absolute(3.5 * length, 1000.0, acceleration=2000.0, deceleration=2000.0,
                       jerk=20000.0)
    rt.step()
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    gear = mover.gear_in_pos_on_track(axis, None, 0.0, 300.0, loop, feedback=feedback)
    laps, last = 0, mover.mc_to_plc.set_on_track.set_pos
    for _ in range(14000):
        rt.step()
        s = mover.mc_to_plc.set_on_track
        assert s.track_oid == loop.oid and 0.0 <= s.set_pos < length
        laps += s.set_pos < last - length / 2
        last = s.set_pos
        if feedback.in_sync:
            assert _within(s.set_pos, 300.0 + axis.set_position, length) < 1e-6
    assert laps == 3 and axis.set_position == pytest.approx(3.5 * length)
    s = mover.mc_to_plc.set_on_track
    assert s.set_pos == pytest.approx((300.0 + 3.5 * length) % length, abs=1e-6)
    assert s.set_velo == 0.0 and feedback.in_sync and gear.active and not gear.error


def test_a_slave_driven_back_over_a_loop_s_start_stops_there_with_an_error():
    """§6.2.8, D-154: after a lap forwards the master turns back; the slave follows it back
    in sync until it must brake for the start of the loop (of the lap it is on), stops
    exactly there and the gear-in ends in PLANAR_PATH_END."""
    rt = om.Runtime(0.001)
    loop, mover, axis = _slave_on_loop(rt)
    length = loop.get_length()
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    mover.gear_in_pos_on_track(axis, None, 0.0, 300.0, loop, feedback=feedback)
    rt.step()
    forwards = axis.move_absolute(length, 1000.0, acceleration=2000.0, deceleration=2000.0,
                                  jerk=20000.0)
    assert rt.run_until(lambda: forwards.done, timeout=10.0)
    assert mover.mc_to_plc.set_on_track.set_pos == pytest.approx(300.0, abs=1e-6)
    assert feedback.in_sync
    axis.move_absolute(0.0, 200.0)
    lowest = math.inf
    assert rt.run_until(lambda: not feedback.busy, timeout=10.0)
    for _ in range(50):
        rt.step()
        lowest = min(lowest, mover.mc_to_plc.set_on_track.set_pos)
    s = mover.mc_to_plc.set_on_track
    assert feedback.error and feedback.error_id == ErrorId.PLANAR_PATH_END
    assert "start of loop" in feedback.message
    assert s.track_oid == loop.oid and s.set_velo == 0.0
    assert s.set_pos == pytest.approx(0.0, abs=1e-6) and lowest >= -1e-9


@pytest.mark.parametrize(("direction", "sync", "tolerance", "there", "synced"), [
    (ModuloDirection.POSITIVE, 100.0, 0.0, 100.0, True),  # a lap ahead: it drives round
    (ModuloDirection.NEGATIVE, 100.0, 0.0, 300.0, False),  # behind: it waits for the master
    (ModuloDirection.NON_MODULO, 100.0, 0.0, 300.0, False),  # as given: behind as well
    (ModuloDirection.NON_MODULO, 3400.0, 0.0, 3400.0, True),  # as given: ahead
    (ModuloDirection.SHORTEST_WAY, 3400.0, 0.0, 300.0, False),  # nearer behind the seam
    (ModuloDirection.POSITIVE, 280.0, 0.0, 280.0, True),  # a lap less 20 mm ahead
    (ModuloDirection.POSITIVE, 280.0, 50.0, 300.0, False),  # within the window: here
])
def test_a_modulo_slave_sync_position_on_a_loop_is_the_occurrence_its_direction_picks(
        direction: ModuloDirection, sync: float, tolerance: float, there: float,
        synced: bool):
    """D-148: the slave stands at 300 on the loop; the axis moves from 0 to 1000 with master
    sync 500. When the axis passes 500 the slave is at its sync position if that occurrence
    lies ahead (Early: in sync by then at the latest), or still waits at 300 for its coupled
    position to come up from behind. At the end every variant stands at sync + 500 on the
    loop, in sync."""
    rt = om.Runtime(0.001)
    loop, mover, axis = _slave_on_loop(rt)
    length = loop.get_length()
    axis.move_absolute(1000.0, 250.0, acceleration=1000.0, deceleration=1000.0, jerk=10000.0)
    rt.step()
    options = ST_GearInPosOnTrackOptions(direction_slave_sync_position=direction,
                                         modulo_tolerance_slave_sync_position=tolerance)
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    mover.gear_in_pos_on_track(axis, None, 500.0, sync, loop, options=options,
                               feedback=feedback)
    assert rt.run_until(lambda: axis.set_position >= 500.0, timeout=10.0)
    assert mover.mc_to_plc.set_on_track.set_pos == pytest.approx(there, abs=1e-6)
    assert feedback.in_sync is synced
    rt.run(4.0)
    s = mover.mc_to_plc.set_on_track
    assert _within(s.set_pos, sync + 500.0, length) < 1e-6 and s.set_velo == 0.0
    assert feedback.in_sync and not feedback.error


def test_modulo_sync_positions_need_a_closed_loop():
    """D-148: the manual offers the modulo options only on a closed loop. A lead-in track
    ends where the loop starts. A modulo direction for a sync position on the open lead-in
    is refused (INVALID_MODULO_OPTIONS), for the master's as for the slave's; on the loop
    ahead of the slave Positive is its first occurrence there, and Negative finds none
    behind the slave on its way (INVALID_DIRECTION)."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt, name="loop")
    lead = MC_PlanarTrack(rt, "lead")
    lead.append_line(PositionXYC(-400.0, -300.0), PositionXYC(-100.0, -300.0))
    lead.end_at_track(loop)
    lead.enable()
    rt.run(0.003)
    assert lead.subsequent_tracks == [loop.oid]
    mover, master = enabled_movers(rt, (-400.0, -300.0), (300.0, 0.0))
    join_all(rt, lead, mover)
    join_all(rt, loop, master)
    axis = _axis(rt)
    trail = MC_PlanarTrackTrail()
    assert trail.add_track(lead) and trail.add_track(loop)

    def gear(direction: ModuloDirection, track: MC_PlanarTrack) -> tuple[bool, ErrorId, str]:
        options = ST_GearInPosOnTrackOptions(direction_slave_sync_position=direction)
        command = mover.gear_in_pos_on_track(axis, trail, 0.0, 100.0, track, options=options)
        rt.step()
        return command.busy, command.error_id, command.message

    busy, error, message = gear(ModuloDirection.SHORTEST_WAY, lead)
    assert not busy and error == ErrorId.INVALID_MODULO_OPTIONS
    assert "closed-loop" in message and "lead" in message
    assert gear(ModuloDirection.POSITIVE, loop)[:2] == (True, ErrorId.NO_ERROR)
    assert gear(ModuloDirection.NEGATIVE, loop)[:2] == (False, ErrorId.INVALID_DIRECTION)
    options = ST_GearInPosOnTrackWithMasterMoverOptions(
        direction_master_sync_position=ModuloDirection.POSITIVE)
    command = master.gear_in_pos_on_track_with_master_mover(mover, None, 100.0, lead, 100.0,
                                                            loop, options=options)
    rt.step()
    assert command.error and command.error_id == ErrorId.INVALID_MODULO_OPTIONS


@pytest.mark.parametrize(("direction", "end"), [
    (ModuloDirection.POSITIVE, 900.0),  # 800 lies 200 ahead of the master: 500 + 1200 - 800
    (ModuloDirection.NON_MODULO, 900.0),
    (ModuloDirection.NEGATIVE, 900.0 + 3475.7966208946273),  # 800 a lap back: L less ahead
])
def test_a_modulo_master_sync_position_on_a_loop_is_taken_along_the_master_s_way(
        direction: ModuloDirection, end: float):
    """D-148: the master stands at 600 on the loop and moves to 1200; the slave on a
    straight track is geared with slave sync 500 to master sync 800. Positive takes the 800
    ahead of the master, Negative the one a lap behind it: the slave then syncs at once and
    ends a loop length further on."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt, name="loop")
    line = enabled_line(rt, (0.0, -1000.0), (5000.0, -1000.0))
    master, slave = enabled_movers(rt, (600.0, 0.0), (0.0, -1000.0))
    join_all(rt, loop, master)
    join_all(rt, line, slave)
    move = master.move_on_track(None, 1200.0, DynamicConstraint_PathXY(velocity=200.0))
    rt.step()
    options = ST_GearInPosOnTrackWithMasterMoverOptions(direction_master_sync_position=direction)
    feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover()
    slave.gear_in_pos_on_track_with_master_mover(master, None, 800.0, loop, 500.0, line,
                                                 options=options, feedback=feedback)
    assert rt.run_until(lambda: move.done, timeout=10.0)
    rt.run(0.5)
    s = slave.mc_to_plc.set_on_track
    assert s.set_pos == pytest.approx(end, abs=1e-6) and s.set_velo == 0.0
    assert feedback.in_sync and not feedback.error


def test_a_follower_goes_round_a_loop_behind_a_master_geared_on_it():
    """D-148 with followMover: the master, geared to an axis on the loop, goes round one and
    a half laps; the slave follows it 300 mm behind on the same loop, round as well. The
    follower's way is the master's, lap for lap."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt, name="loop")
    master, slave = enabled_movers(rt, (600.0, 0.0), (300.0, 0.0))
    join_all(rt, loop, master, slave)
    length = loop.get_length()
    axis = _axis(rt)
    axis.move_absolute(1.5 * length, 1000.0, acceleration=2000.0, deceleration=2000.0,
                       jerk=20000.0)
    rt.step()
    master_gear = master.gear_in_pos_on_track(axis, None, 0.0, 600.0, loop)
    rt.step()
    options = ST_GearInPosOnTrackWithMasterMoverOptions(follow_mover=True)
    feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover()
    slave.gear_in_pos_on_track_with_master_mover(master, None, 600.0, loop, 300.0, loop,
                                                 options=options, feedback=feedback)
    rt.run(7.0)
    m, s = master.mc_to_plc.set_on_track, slave.mc_to_plc.set_on_track
    assert m.set_pos == pytest.approx((600.0 + 1.5 * length) % length, abs=1e-6)
    assert _within(s.set_pos, m.set_pos - 300.0, length) < 1e-6 and s.set_velo == 0.0
    assert feedback.in_sync and not feedback.error and not master_gear.error


def test_a_geared_slave_does_not_go_back_over_the_start_of_a_later_track():
    """A master that drives the slave back past the start of the trail's second track: the
    slave stops at that start with PLANAR_PATH_END (§6.2.8), naming the track. It ran off the
    track's start before (the traffic leaves a track backwards only within it)."""
    rt = om.Runtime(0.001)
    one = enabled_line(rt, (100.0, 100.0), (400.0, 100.0))
    two = enabled_line(rt, (500.0, 100.0), (860.0, 100.0), after=one)
    (mover,) = enabled_movers(rt, (100.0, 100.0))
    join_all(rt, one, mover)
    axis = _axis(rt)
    axis.move_absolute(700.0, 300.0, acceleration=1000.0, deceleration=1000.0, jerk=10000.0)
    rt.step()
    trail = MC_PlanarTrackTrail()
    assert trail.add_track(one) and trail.add_track(two)
    gear = mover.gear_in_pos_on_track(axis, trail, 100.0, 100.0, one)
    rt.run(4.0)
    assert mover.mc_to_plc.set_on_track.track_oid == two.oid
    axis.move_absolute(100.0, 300.0, acceleration=1000.0, deceleration=1000.0, jerk=10000.0)
    rt.run(3.0)
    s = mover.mc_to_plc.set_on_track
    assert (s.track_oid, s.set_pos, s.set_velo) == (two.oid, 0.0, 0.0)
    assert gear.error and gear.error_id == ErrorId.PLANAR_PATH_END and two.name in gear.message


# -- followMover in a group (D-149) -----------------------------------------------------------


def _switch_in_group(rt: om.Runtime, blocker_at: tuple[float, float]
                     ) -> tuple[MC_PlanarTrack, MC_PlanarTrack, list[MC_PlanarMover]]:
    """§6.2.12's switch (track_in, out1, out2) in a group with the slave and a third mover
    standing at ``blocker_at``; the master (290 on track_in) is in no group, so its own
    moves hold no band. The slave stands at 130 on track_in, its footprint on out1's band
    near the switch (it does not block its own way)."""
    track_in = enabled_line(rt, (100.0, 360.0), (400.0, 360.0))
    out1 = enabled_line(rt, (450.0, 410.0), (860.0, 620.0), after=track_in)
    out2 = enabled_line(rt, (450.0, 310.0), (860.0, 100.0), after=track_in)
    movers = enabled_movers(rt, (390.0, 360.0), (230.0, 360.0), blocker_at)
    group = MC_PlanarGroup(rt)
    group.enable()
    rt.run(0.005)
    adds = [m.add_to_group(group) for m in (*movers[1:], track_in, out1, out2)]
    rt.run(0.005)
    assert all(a.done for a in adds), [a.message for a in adds]
    join_all(rt, track_in, *movers[:2])
    return track_in, out1, movers


def test_a_follower_s_later_track_holds_its_band_while_followed():
    """D-149: the master turns onto out1 after the slave geared in with followMover; out1
    joins the slave's way then, and holds its band in the slave's group from then on until
    the slave's gear ends (its Halt). Before, only the tracks of the way at the start did."""
    rt = om.Runtime(0.001)
    track_in, out1, (master, slave, _) = _switch_in_group(rt, (800.0, 1200.0))
    options = ST_GearInPosOnTrackWithMasterMoverOptions(gap=100.0, follow_mover=True)
    gear = slave.gear_in_pos_on_track_with_master_mover(master, None, 290.0, track_in, 130.0,
                                                        track_in, options=options)
    rt.run(0.1)
    assert gear.active and track_in.band and not out1.band
    move = master.move_on_track(out1, 300.0)
    rt.run(0.05)
    assert out1.band
    assert rt.run_until(lambda: move.done, timeout=10.0)
    rt.run(1.0)
    s = slave.mc_to_plc.set_on_track
    assert (s.track_oid, s.set_pos) == (out1.oid, pytest.approx(140.0, abs=1e-6))
    assert gear.active and not gear.error and out1.band
    halt = slave.halt()
    rt.run(0.1)
    assert halt.done and not out1.band and not track_in.band


def test_a_follower_stops_before_a_track_its_group_does_not_grant():
    """D-149: a third mover of the group stands on out1's surface. The follower may not
    drive onto out1: it goes on to the end of track_in and stops there, and its gear-in
    ends in PLANAR_COLLISION naming out1 and (object_info) the mover in the way. The master,
    in no group, goes on."""
    rt = om.Runtime(0.001)
    track_in, out1, (master, slave, blocker) = _switch_in_group(rt, (800.0, 590.0))
    options = ST_GearInPosOnTrackWithMasterMoverOptions(gap=100.0, follow_mover=True)
    feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover()
    gear = slave.gear_in_pos_on_track_with_master_mover(master, None, 290.0, track_in, 130.0,
                                                        track_in, options=options,
                                                        feedback=feedback)
    rt.run(0.1)
    move = master.move_on_track(out1, 300.0)
    assert rt.run_until(lambda: not gear.busy, timeout=10.0)
    rt.run(0.1)
    s = slave.mc_to_plc.set_on_track
    assert (s.track_oid, s.set_pos, s.set_velo) == (track_in.oid, 300.0, 0.0)
    assert gear.error and gear.error_id == ErrorId.PLANAR_COLLISION
    assert out1.name in gear.message and not out1.band
    assert feedback.object_info == PlanarObjectInfo(PlanarObjectType.MOVER, blocker.oid)
    assert move.done and not move.error


# -- review findings (session 8) ------------------------------------------------------------------


def test_in_sync_drops_in_the_cycle_the_slave_brakes_for_its_path_end():
    """§6.2.8: the slave leaves sync when it must brake for the end of its path; the feedback
    showed inSync for the 89 braking cycles (35 mm behind the coupled position)."""
    rt = om.Runtime(0.001)
    track = enabled_line(rt, (100.0, 100.0), (860.0, 100.0))
    mover = _mover(rt, 100.0, 100.0)
    _join(rt, mover, track)
    axis = _axis(rt)
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    mover.gear_in_pos_on_track(axis, None, 0.0, 0.0, track, feedback=feedback)
    rt.step()
    axis.move_velocity(800.0, acceleration=1000.0, deceleration=1000.0, jerk=20000.0)
    seen_in_sync, braking_in_sync = False, 0
    while not feedback.error:
        rt.step()
        s = mover.mc_to_plc.set_on_track
        seen_in_sync |= feedback.in_sync
        braking_in_sync += s.set_acc < 0.0 and feedback.in_sync
    assert seen_in_sync and feedback.error_id == ErrorId.PLANAR_PATH_END
    assert braking_in_sync <= 1  # the cycle it starts to brake; the feedback shows the next


@pytest.mark.parametrize(("slave_sync", "in_sync"), [(495.0, True), (450.0, False)])
def test_a_waiting_slave_within_the_in_sync_tolerance_is_in_sync(slave_sync, in_sync):
    """§7.2.1.2.7: a slave at rest 5 mm ahead of its coupled position, which it may not go
    back to (Positive), is within inSyncToleranceDistance 10: inSync (it was False); 50 mm
    is not."""
    rt = om.Runtime(0.001)
    track = enabled_line(rt, (0.0, 0.0), (3000.0, 0.0))
    mover = _mover(rt, 500.0, 0.0)
    _join(rt, mover, track)
    axis = _axis(rt)
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    mover.gear_in_pos_on_track(axis, None, 0.0, slave_sync, track, options=(
        ST_GearInPosOnTrackOptions(in_sync_tolerance_distance=10.0)), feedback=feedback)
    rt.run(0.3)
    assert mover.mc_to_plc.set_on_track.set_pos == pytest.approx(500.0)
    assert feedback.in_sync is in_sync and feedback.busy


def test_a_slave_of_a_geared_master_mover_follows_its_master_s_step_of_the_same_cycle():
    """§6.2.9: B geared to mover A, A geared to an axis: in sync B is exactly 400 mm behind A
    every cycle (it was one cycle of travel, 1 mm at 1000 mm/s, behind), whichever joined
    first."""
    for a_first in (True, False):
        rt = om.Runtime(0.001)
        track = enabled_line(rt, (0.0, 0.0), (6000.0, 0.0))
        if a_first:  # the order of the rows and the riders
            a, b = _mover(rt, 500.0, 0.0), _mover(rt, 100.0, 0.0)
        else:
            b, a = _mover(rt, 100.0, 0.0), _mover(rt, 500.0, 0.0)
        for mover in ((a, b) if a_first else (b, a)):
            _join(rt, mover, track)
        axis = _axis(rt)
        feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover()
        a.gear_in_pos_on_track(axis, None, 0.0, 500.0, track)
        b.gear_in_pos_on_track_with_master_mover(a, None, 500.0, track, 100.0, track,
                                                 feedback=feedback)
        rt.step()
        axis.move_absolute(3000.0, 1000.0)
        worst, synced = 0.0, 0
        for _ in range(3500):
            rt.step()
            if feedback.in_sync:
                synced += 1
                apart = a.mc_to_plc.set_on_track.set_pos - b.mc_to_plc.set_on_track.set_pos
                worst = max(worst, abs(apart - 400.0))
        assert synced > 2000 and worst < 1e-9, (a_first, synced, worst)


def test_a_follow_mover_trail_must_hold_the_slave_s_track():
    """§6.8, §6.2.12: with followMover a trail that does not hold the slave's track is
    refused as without it (it was ignored, and the slave took the shortest way)."""
    rt = om.Runtime(0.001)
    one = enabled_line(rt, (0.0, 0.0), (1000.0, 0.0))
    two = enabled_line(rt, (1200.0, 200.0), (2000.0, 200.0), after=one)
    master, slave = _mover(rt, 500.0, 0.0), _mover(rt, 100.0, 0.0)
    _join(rt, master, one)
    _join(rt, slave, one)
    trail = MC_PlanarTrackTrail()
    assert trail.add_track(two)
    feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover()
    slave.gear_in_pos_on_track_with_master_mover(
        master, trail, 600.0, one, 200.0, one,
        options=ST_GearInPosOnTrackWithMasterMoverOptions(follow_mover=True),
        feedback=feedback)
    rt.run(0.003)
    assert feedback.error and feedback.error_id == ErrorId.PLANAR_INVALID_INPUT
    assert "does not hold the slave's track" in feedback.message


@pytest.mark.parametrize("value", ["yes", 2, None])
def test_follow_mover_must_be_a_bool(value):
    rt = om.Runtime(0.001)
    track = enabled_line(rt, (0.0, 0.0), (1000.0, 0.0))
    master, slave = _mover(rt, 500.0, 0.0), _mover(rt, 100.0, 0.0)
    _join(rt, master, track)
    _join(rt, slave, track)
    command = slave.gear_in_pos_on_track_with_master_mover(
        master, None, 600.0, track, 200.0, track,
        options=ST_GearInPosOnTrackWithMasterMoverOptions(follow_mover=value))
    rt.step()
    assert command.error and command.error_id == ErrorId.PLANAR_INVALID_INPUT
    assert "follow_mover: must be a BOOL" in command.message
