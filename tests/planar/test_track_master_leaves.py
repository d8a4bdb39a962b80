"""A master mover that leaves its track ends the couplings of its slaves (D-145): each
slave brakes to a stop on its track and its GearInPosOnTrackWithMasterMover ends in error
(PLANAR_WRONG_MODE, naming the master), whatever the order the movers joined their tracks
in; no slave keeps the master's stale slot (TF5430 §6.2.9, §7.2.2.8.3, §7.2.2.8.6)."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.planar import (
    MC_PlanarFeedbackGearInPosOnTrackWithMasterMover,
    MC_PlanarMover,
    PositionXYC,
)
from openmotion.testing import enabled_line as _line
from openmotion.testing import enabled_movers as _movers


def _setup(order: str, slave_sync: float = 0.0):
    """Master, slave and a third mover on three parallel tracks, joined in ``order`` (a
    string of 'm', 's', 't'); the slave geared to the master."""
    rt = om.Runtime(0.001)
    master, slave, third = _movers(rt, (100.0, 620.0), (100.0, 100.0), (600.0, 1000.0))
    tracks = {"m": _line(rt, (100.0, 620.0), (860.0, 620.0)),
              "s": _line(rt, (100.0, 100.0), (860.0, 100.0)),
              "t": _line(rt, (100.0, 1000.0), (1500.0, 1000.0))}
    movers = {"m": master, "s": slave, "t": third}
    for key in order:
        join = movers[key].join_track(tracks[key])
        rt.run_until(lambda join=join: join.done, timeout=10.0)
    feedback = MC_PlanarFeedbackGearInPosOnTrackWithMasterMover()
    gear = slave.gear_in_pos_on_track_with_master_mover(master, None, 0.0, tracks["m"],
                                                        slave_sync, tracks["s"],
                                                        feedback=feedback)
    return rt, master, slave, third, gear, feedback


def _check_ended(master: MC_PlanarMover, slave: MC_PlanarMover, gear, feedback) -> None:
    assert gear.error and not gear.busy
    assert gear.error_id is ErrorId.PLANAR_WRONG_MODE
    assert master.name in gear.message
    assert feedback.error and not feedback.in_sync
    s = slave.mc_to_plc
    assert s.set_on_track.set_velo == 0.0 and not s.std.busy.busy_mover


@pytest.mark.parametrize("order", ["mts", "mst", "smt", "tms"])
def test_master_leaving_ends_the_slaves_gear_and_a_third_mover_goes_on(order):
    """The reviewer's case (t17): the slave, in sync with a standing master, stays where it
    is; its gear ends in error; the third mover's MoveOnTrack is not disturbed."""
    rt, master, slave, third, gear, feedback = _setup(order)
    rt.run(0.5)
    assert gear.busy and feedback.in_sync
    leave = master.leave_track(PositionXYC(300.0, 800.0))
    rt.run(0.01)
    move = third.move_on_track(None, 1300.0)
    rt.run_until(lambda: not move.busy and not gear.busy, timeout=10.0)
    _check_ended(master, slave, gear, feedback)
    assert slave.mc_to_plc.set_on_track.set_pos == pytest.approx(0.0, abs=1e-9)
    assert move.done and third.mc_to_plc.set_on_track.set_pos == pytest.approx(1300.0)
    rt.run_until(lambda: not leave.busy, timeout=10.0)
    assert leave.done
    rt.run(1.0)  # nothing moves the slave afterwards
    assert slave.mc_to_plc.set_on_track.set_pos == pytest.approx(0.0, abs=1e-9)
    assert not gear.busy and gear.error_id is ErrorId.PLANAR_WRONG_MODE


@pytest.mark.parametrize("order", ["mst", "mts"])
def test_a_synchronising_slave_brakes_to_a_stop_when_its_master_leaves(order):
    """The slave is on its way to its sync position (700 while the master stands at its
    sync position 0) when the master leaves: it brakes with its command's dynamics, short of
    700, and stays there."""
    rt, master, slave, third, gear, feedback = _setup(order, slave_sync=700.0)
    rt.run_until(lambda: slave.mc_to_plc.set_on_track.set_pos > 100.0, timeout=10.0)
    assert gear.busy and slave.mc_to_plc.set_on_track.set_velo > 0.0
    master.leave_track(PositionXYC(300.0, 800.0))
    rt.run_until(lambda: not gear.busy, timeout=10.0)
    _check_ended(master, slave, gear, feedback)
    stop = slave.mc_to_plc.set_on_track.set_pos
    assert 100.0 < stop < 700.0
    rt.run(1.0)
    assert slave.mc_to_plc.set_on_track.set_pos == stop
    assert third.mc_to_plc.set_on_track.set_pos == pytest.approx(500.0)  # where it joined


def test_the_slave_takes_a_new_command_after_its_master_left():
    rt, master, slave, _, gear, _ = _setup("mst")
    rt.run(0.2)
    master.leave_track(PositionXYC(300.0, 800.0))
    rt.run_until(lambda: not gear.busy, timeout=10.0)
    move = slave.move_on_track(None, 500.0)
    rt.run_until(lambda: not move.busy, timeout=30.0)
    assert move.done and slave.mc_to_plc.set_on_track.set_pos == pytest.approx(500.0)
