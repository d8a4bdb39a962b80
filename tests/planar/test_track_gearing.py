"""Gear-in on tracks: GearInPosOnTrack, GearInPosOnTrackWithMasterMover, the track trail
(TF5430 §6.2.8, §6.2.9, §6.2.12, §6.8.1)."""

from __future__ import annotations

import math
from unittest import mock

import pytest

import openmotion as om
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar import (
    DynamicConstraint_PathXY,
    MC_PlanarFeedbackGearInPosOnTrack,
    MC_PlanarFeedbackGearInPosOnTrackWithMasterMover,
    MC_PlanarMover,
    MC_PlanarTrack,
    MC_PlanarTrackTrail,
    MoverVector,
    PlanarMoverParameters,
    PlanarState,
    PositionXYC,
    ST_GearInPosOnTrackWithMasterMoverOptions,
)
from openmotion.transport.gear import GearSync


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
