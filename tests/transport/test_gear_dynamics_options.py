"""MC_GearInPosCA's dynamics options (TF5410 §9.1.2.1, §8.1.4, §9.4.1.5; D-206).

* AfterSyncVelocity/Acceleration/Deceleration/Jerk: the slave's limits once it has been in
  sync, e.g. when it synchronises again after gap control held it.
* GearInPosDefaultDynamicsAfterSync (CA group parameter): what MC_DEFAULT means there, the
  job's own dynamics (JobDynamics) or the slave's maxima with the jerk unlimited
  (MaximumSlaveDynamics; here the axis' max_jerk).
* OverrideSlaveDynamicRestrictions: Late and Slow stretch or compress their planned
  profile when the master changes speed instead of failing (Late) or re-planning (Slow).
"""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GearInPosDefaultDynamicsAfterSync,
    SyncStrategy,
)

SLAVE = {"max_velocity": 3000.0, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
         "max_jerk": 1e5, "acceleration": 5000.0, "deceleration": 5000.0, "jerk": 50000.0}
BLOCKER = {"max_velocity": 8000.0, "max_acceleration": 20000.0, "max_deceleration": 20000.0,
           "max_jerk": 1e6}
JOB = {"velocity": 2500.0, "acceleration": 3000.0, "deceleration": 3000.0, "jerk": 30000.0}
FAR = 1500.0  #: [mm] a blocker this far ahead no longer brakes the slave


def resync(default: GearInPosDefaultDynamicsAfterSync = (
        GearInPosDefaultDynamicsAfterSync.JOB_DYNAMICS), **options: float) -> dict:
    """The slave syncs (Early) to a master at 500 mm/s, runs into a standing blocker, is held
    there for 4 s, then the blocker leaves fast and the slave catches up with the coupled
    position (2000 mm ahead by then). Peaks of the catch-up: velocity and acceleration
    over all of it; deceleration and jerk once the blocker is far ahead."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=False, rail_length=100000.0,
                    gear_in_pos_default_dynamics_after_sync=default)
    master = rt.add_axis("master", max_velocity=2000.0)
    master.power()
    blocker = rt.add_axis("blocker", position=3000.0, **BLOCKER)
    slave = rt.add_axis("slave", position=0.0, **SLAVE)
    for i, axis in enumerate((blocker, slave)):
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
    group.enable()
    master.move_velocity(500.0)
    gear = group.gear_in_pos(master, slave, 1.0, 1, 0.0, 0.0, SyncStrategy.EARLY, **JOB,
                             **options)
    rt.run_until(lambda: group.sync_state(gear)[1], timeout=10.0)
    rt.run_until(lambda: not group.sync_state(gear)[1], timeout=10.0)  # held by the blocker
    rt.run(4.0)
    group.move_absolute(blocker, 90000.0, 8000.0, acceleration=20000.0, deceleration=20000.0,
                        jerk=1e6)
    peak = {"velocity": 0.0, "acceleration": 0.0, "deceleration": 0.0, "jerk": 0.0}
    before = slave.set_acceleration
    while not group.sync_state(gear)[1]:
        rt.step()
        a = slave.set_acceleration
        peak["velocity"] = max(peak["velocity"], slave.set_velocity)
        peak["acceleration"] = max(peak["acceleration"], a)
        if blocker.set_position - slave.set_position > FAR:
            peak["deceleration"] = max(peak["deceleration"], -a)
            peak["jerk"] = max(peak["jerk"], abs(a - before) / rt.cycle_time)
        before = a
        assert rt.now < 30.0 and not gear.finished
    assert slave.set_position == pytest.approx(master.set_position, abs=1e-9)  # in sync again
    return peak


def test_after_sync_options_limit_the_resync() -> None:
    """AfterSync* = 1500 mm/s, 2000 mm/s², 1000 mm/s², 20000 mm/s³: the catch-up after the
    first sync reaches exactly these, not the job's 2500 / 3000 / 3000 / 30000."""
    peak = resync(after_sync_velocity=1500.0, after_sync_acceleration=2000.0,
                  after_sync_deceleration=1000.0, after_sync_jerk=20000.0)
    assert peak == {"velocity": pytest.approx(1500.0), "acceleration": pytest.approx(2000.0),
                    "deceleration": pytest.approx(1000.0), "jerk": pytest.approx(20000.0)}


def test_job_dynamics_is_the_default_after_sync() -> None:
    """GearInPosDefaultDynamicsAfterSync JobDynamics (the default, §8.1.4): MC_DEFAULT
    AfterSync* are the job's Velocity, Acceleration, Deceleration and Jerk."""
    peak = resync()
    assert peak == {"velocity": pytest.approx(2500.0), "acceleration": pytest.approx(3000.0),
                    "deceleration": pytest.approx(3000.0), "jerk": pytest.approx(30000.0)}


def test_maximum_slave_dynamics_after_sync() -> None:
    """MaximumSlaveDynamics (§8.1.4): the slave's maximum velocity (3000), acceleration and
    deceleration (10000), the jerk only bounded by the axis' max_jerk (1e5)."""
    peak = resync(GearInPosDefaultDynamicsAfterSync.MAXIMUM_SLAVE_DYNAMICS)
    assert peak["velocity"] == pytest.approx(3000.0)
    assert 3000.0 < peak["acceleration"] <= 10000.0 * (1 + 1e-9)
    assert peak["deceleration"] == pytest.approx(10000.0)
    assert peak["jerk"] == pytest.approx(1e5)


def test_an_after_sync_option_replaces_only_its_own_default() -> None:
    """AfterSyncVelocity 1500 with MaximumSlaveDynamics: the velocity is 1500, the
    deceleration still the slave's maximum."""
    peak = resync(GearInPosDefaultDynamicsAfterSync.MAXIMUM_SLAVE_DYNAMICS,
                  after_sync_velocity=1500.0)
    assert peak["velocity"] == pytest.approx(1500.0)
    assert peak["deceleration"] == pytest.approx(10000.0, rel=1e-2)


MSP, SSP = 1000.0, 1500.0
FB_ACCELERATION = 2000.0  #: the job's acceleration and deceleration
AXIS_MAXIMUM = 10000.0  #: the slave's maximum acceleration and deceleration


def speed_change(strategy: SyncStrategy, override: bool, new_velocity: float) -> dict:
    """The master runs at 200 mm/s; 50 ms after StartSync it changes to ``new_velocity``
    (at 500 mm/s²). Where the slave is in sync, and its peak acceleration magnitude."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=False, rail_length=10000.0)
    master = rt.add_axis("master", max_velocity=2000.0)
    master.power()
    slave = rt.add_axis("slave", position=0.0, max_velocity=4000.0,
                        max_acceleration=AXIS_MAXIMUM, max_deceleration=AXIS_MAXIMUM,
                        max_jerk=1e5, jerk=50000.0)
    slave.power()
    group.add_axis(slave, UDINT_TO_IDENTINGROUP(1))
    group.enable()
    master.move_velocity(200.0)
    rt.run(0.5)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, strategy, velocity=2000.0,
                                acceleration=FB_ACCELERATION, deceleration=FB_ACCELERATION,
                                override_slave_dynamic_restrictions=override)
    rt.run_until(lambda: group.sync_state(command)[0], timeout=10.0)
    rt.run(0.05)
    master.move_velocity(new_velocity, acceleration=500.0, deceleration=500.0)
    peak = 0.0
    while not (group.sync_state(command)[1] or command.finished):
        rt.step()
        peak = max(peak, abs(slave.set_acceleration))
    return {"command": command, "peak": peak,
            "in_sync": (master.set_position, slave.set_position)}


def test_late_without_override_fails_when_the_master_speeds_up() -> None:
    seen = speed_change(SyncStrategy.LATE, False, 300.0)
    assert seen["command"].error and seen["command"].error_id is ErrorId.SYNC_FAILED


@pytest.mark.parametrize("new_velocity", [300.0, 150.0])
def test_late_with_override_compresses_or_stretches_its_profile(new_velocity: float) -> None:
    """OverrideSlaveDynamicRestrictions TRUE: no error; the profile follows the master's
    travel, so the slave is in sync when the master is at MSP (within one cycle of its
    travel). Compressed (master faster) it passes the job's 2000 mm/s² but never the axis
    maximum; stretched (master slower) it stays within the job's limits."""
    seen = speed_change(SyncStrategy.LATE, True, new_velocity)
    assert not seen["command"].error, seen["command"].message
    master, slave = seen["in_sync"]
    assert master == pytest.approx(MSP, abs=new_velocity * 0.001 + 1e-9)
    assert slave == pytest.approx(SSP + master - MSP, abs=1e-9)
    if new_velocity > 200.0:
        assert FB_ACCELERATION * 2 < seen["peak"] <= AXIS_MAXIMUM * (1 + 1e-9)
    else:
        assert seen["peak"] <= FB_ACCELERATION * (1 + 1e-9)


def test_slow_recomputes_without_override_and_stretches_with_it() -> None:
    """Slow, master from 200 to 300 mm/s: without the override the profile is planned again
    within the job's limits (the master's own 500 mm/s² comes on top); with it the first
    profile is compressed, harder than that. Both are in sync at MSP."""
    planned = speed_change(SyncStrategy.SLOW, False, 300.0)
    stretched = speed_change(SyncStrategy.SLOW, True, 300.0)
    for seen in (planned, stretched):
        assert not seen["command"].error
        assert seen["in_sync"][0] == pytest.approx(MSP, abs=0.3 + 1e-9)
    assert planned["peak"] <= FB_ACCELERATION + 500.0 + 1e-6
    assert stretched["peak"] > planned["peak"] + 1000.0
