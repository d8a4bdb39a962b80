"""MC_GearInPosCA: the options' restrictions hold for the profile the slave drives
(TF5410 §9.1.2.1, D-204).

"Restricting the synchronization profile could make synchronization impossible": an error
only then. A restriction that the fastest profile breaks is kept by waiting (the slave holds
at rest) and then syncing; SYNC_FAILED only when no wait can lead to a compliant sync.
"""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.transport import UDINT_TO_IDENTINGROUP, CaGroup, SyncStrategy

MSP, SSP = 1000.0, 500.0  # the coupled position starts 500 mm behind the slave


def setup() -> tuple[om.Runtime, CaGroup, om.Axis, om.Axis]:
    """Open rail, one mover at 0, a master axis at 0; default axis parameters."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=False, rail_length=10000.0)
    master = rt.add_axis("master")
    master.power()
    slave = rt.add_axis("slave", position=0.0)
    slave.power()
    group.add_axis(slave, UDINT_TO_IDENTINGROUP(1))
    group.enable()
    return rt, group, master, slave


def run_issue_case(**options: object) -> dict:
    """The issue's case: master to 200 mm/s with the command, Early, MSP 1000, SSP 500."""
    rt, group, master, slave = setup()
    master.move_velocity(200.0)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.EARLY,
                                velocity=500.0, **options)
    seen = {"command": command, "lowest": 0.0, "slowest": 0.0, "in_sync": None}
    for _ in range(5000):
        rt.step()
        seen["lowest"] = min(seen["lowest"], slave.set_position)
        seen["slowest"] = min(seen["slowest"], slave.set_velocity)
        if group.sync_state(command)[1]:
            seen["in_sync"] = (master.set_position, slave.set_position)
            break
        if command.finished:
            break
    return seen


def test_the_fastest_sync_of_the_issue_case_dips_below_minus_280() -> None:
    """The unrestricted (fastest) profile goes back first: the case the options restrict."""
    free = run_issue_case()
    assert free["in_sync"] is not None
    assert free["lowest"] == pytest.approx(-284.6, abs=0.1)
    assert free["slowest"] < 0.0


def test_direction_reversal_forbidden_waits_and_syncs_forwards() -> None:
    """§9.1.2.1 DirectionReversalAllowed FALSE: the slave never moves backwards (the sync
    direction is the master's, forwards); it stands until a forward sync fits, then syncs
    (D-204). Before: SYNC_FAILED in the first cycle."""
    seen = run_issue_case(direction_reversal_allowed=False)
    assert not seen["command"].error, seen["command"].message
    assert seen["in_sync"] is not None
    master, slave = seen["in_sync"]
    assert slave == pytest.approx(SSP + master - MSP, abs=1e-9)
    assert seen["slowest"] >= 0.0 and seen["lowest"] >= 0.0


def test_minimal_slave_position_is_kept_by_waiting() -> None:
    """§9.1.2.1 MinimalSlavePosition -100: the slave waits until a sync that stays above
    -100 fits, then syncs; it dips close to the bound but not below (D-204)."""
    seen = run_issue_case(minimal_slave_position=-100.0)
    assert not seen["command"].error, seen["command"].message
    assert seen["in_sync"] is not None
    assert -100.0 - 1e-9 <= seen["lowest"] < -90.0


@pytest.mark.parametrize("strategy", [SyncStrategy.LATE, SyncStrategy.SLOW])
def test_late_and_slow_keep_the_restrictions_and_their_sync_point(
        strategy: SyncStrategy) -> None:
    """Late and Slow with both restrictions: in sync when the master is at MSP (within its
    travel of one cycle), never backwards, never below the minimum."""
    rt, group, master, slave = setup()
    master.move_velocity(200.0)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, strategy, velocity=500.0,
                                direction_reversal_allowed=False, minimal_slave_position=-1.0)
    slowest = 0.0
    while not group.sync_state(command)[1]:
        rt.step()
        slowest = min(slowest, slave.set_velocity)
        assert not command.finished, command.message
        assert slave.set_position >= -1.0
    assert master.set_position == pytest.approx(MSP, abs=200.0 * rt.cycle_time)
    assert slowest >= 0.0


def test_a_slave_moving_against_the_sync_direction_cannot_sync_without_reversing() -> None:
    """The slave runs backwards at 500 mm/s when the command comes; the master moves
    forwards: any sync turns it round, so with DirectionReversalAllowed FALSE the sync is
    impossible (§9.1.2.1): SYNC_FAILED at once, and the slave brakes. The group stays
    usable: a new command on the slave runs to its end."""
    rt, group, master, slave = setup()
    group.move_absolute(slave, -5000.0, 500.0)
    master.move_velocity(200.0)
    rt.run(0.5)
    assert slave.set_velocity == pytest.approx(-500.0)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.EARLY,
                                velocity=500.0, direction_reversal_allowed=False)
    rt.step()
    assert command.error and command.error_id is ErrorId.SYNC_FAILED
    assert "DirectionReversalAllowed" in command.message
    assert "against the sync direction already" in command.message
    move = group.move_absolute(slave, 0.0, 500.0)
    rt.run_until(lambda: move.done, timeout=10.0)
    assert slave.set_position == pytest.approx(0.0)


def test_a_coupled_position_running_away_below_the_minimum_cannot_be_met() -> None:
    """The master runs backwards: the coupled position (-500 and falling) lies below
    MinimalSlavePosition -100 and moves away from it; waiting cannot help: SYNC_FAILED."""
    rt, group, master, slave = setup()
    master.move_velocity(200.0, direction=om.Direction.NEGATIVE)
    rt.run(0.5)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.EARLY,
                                velocity=500.0, minimal_slave_position=-100.0)
    rt.step()
    assert command.error and command.error_id is ErrorId.SYNC_FAILED
    assert "MinimalSlavePosition" in command.message and "waiting cannot help" in \
        command.message
    assert slave.set_velocity == 0.0  # it never moved
