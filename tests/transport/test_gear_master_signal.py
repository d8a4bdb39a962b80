"""MC_GearInPosCA's MasterSignalCorrection (TF5410 §9.1.2.1, §9.1.2.6; D-205).

The manual: the option says whether the master's input signal is corrected, Auto
(automatically) or None (not at all). Here a signal is corrected when its velocity and
acceleration do not fit its positions: they are then taken from the positions. The master
below is fed from outside (MC_ExtSetPointGenFeed, TcMC §4.18) with positions of a 200 mm/s
run but velocity and acceleration left at 0, as a position-only source would.
"""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    MasterSignalCorrection,
    MC_GearInPosCA,
    ST_GearInPosCAOptions,
    SyncStrategy,
)

MSP, SSP = 1000.0, 1500.0
SPEED = 200.0  #: [mm/s] of the fed master positions


def setup() -> tuple[om.Runtime, CaGroup, om.Axis, om.Axis]:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=False, rail_length=10000.0)
    master = rt.add_axis("master")
    master.power()
    slave = rt.add_axis("slave", position=0.0)
    slave.power()
    group.add_axis(slave, UDINT_TO_IDENTINGROUP(1))
    group.enable()
    return rt, group, master, slave


def feed(rt: om.Runtime, master: om.Axis, fed_velocity: float = 0.0) -> None:
    """One cycle of the fed master: the position of a 200 mm/s run, the given velocity."""
    master.feed_setpoint(SPEED * (rt.now + rt.cycle_time), fed_velocity, 0.0, 1)
    rt.step()


def run_fed(correction: MasterSignalCorrection, strategy: SyncStrategy) -> dict:
    rt, group, master, slave = setup()
    master.enable_external_setpoints()
    for _ in range(100):
        feed(rt, master)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, strategy, velocity=2000.0,
                                master_signal_correction=correction)
    while not group.sync_state(command)[1]:
        feed(rt, master)
        assert not command.finished, command.message
        assert rt.now < 10.0
    in_sync = (master.set_position, slave.set_position)
    feed(rt, master)
    return {"in_sync": in_sync, "travel": slave.set_position - in_sync[1],
            "velocity": slave.set_velocity}


def test_auto_takes_the_velocity_from_the_positions() -> None:
    """Auto: in sync the slave's set velocity is the master's real one (200 mm/s), so the
    slave's set values fit its own positions (0.2 mm per cycle)."""
    seen = run_fed(MasterSignalCorrection.AUTO, SyncStrategy.EARLY)
    assert seen["travel"] == pytest.approx(0.2, abs=1e-9)
    assert seen["velocity"] == pytest.approx(SPEED, rel=1e-9)


def test_none_takes_the_signal_as_it_is() -> None:
    """None: the fed velocity 0 is used; the slave moves 0.2 mm per cycle at velocity 0."""
    seen = run_fed(MasterSignalCorrection.NONE, SyncStrategy.EARLY)
    assert seen["travel"] == pytest.approx(0.2, abs=1e-9)
    assert seen["velocity"] == 0.0


def test_late_times_its_start_on_the_corrected_velocity() -> None:
    """Late (§9.4.1.5) is in sync when the master is at MSP only if it knows how fast the
    master comes: with Auto at (1000, 1500); with None the master seems to stand, the slave
    starts at once and is in sync long before (master at 184.2)."""
    auto = run_fed(MasterSignalCorrection.AUTO, SyncStrategy.LATE)
    assert auto["in_sync"] == (pytest.approx(MSP, abs=1e-6), pytest.approx(SSP, abs=1e-6))
    none = run_fed(MasterSignalCorrection.NONE, SyncStrategy.LATE)
    assert none["in_sync"][0] == pytest.approx(184.2, abs=1e-6)


def run_planned_master(correction: MasterSignalCorrection) -> list[tuple[float, float]]:
    rt, group, master, slave = setup()
    master.move_velocity(500.0)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.LATE,
                                velocity=2000.0, master_signal_correction=correction)
    trace = []
    for _ in range(3000):
        rt.step()
        trace.append((slave.set_position, slave.set_velocity))
    assert group.sync_state(command)[1]
    return trace


def test_a_master_whose_values_fit_its_positions_is_not_corrected() -> None:
    """A master on its own jerk-limited profile: Auto and None give the same trace, bit
    for bit."""
    assert run_planned_master(MasterSignalCorrection.AUTO) == \
        run_planned_master(MasterSignalCorrection.NONE)


def test_an_unknown_correction_is_an_error_and_the_block_defaults_to_auto() -> None:
    rt, group, master, slave = setup()
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, velocity=1000.0,
                                master_signal_correction=7)
    assert command.error and command.error_id is ErrorId.INVALID_MODE
    assert "master_signal_correction" in command.message
    assert ST_GearInPosCAOptions().master_signal_correction is MasterSignalCorrection.AUTO
    fb = MC_GearInPosCA(slave, master=master, master_sync_position=MSP,
                        slave_sync_position=SSP, velocity=1000.0,
                        options=ST_GearInPosCAOptions(
                            master_signal_correction=MasterSignalCorrection.NONE))
    fb(execute=True)
    assert fb.busy and not fb.error
