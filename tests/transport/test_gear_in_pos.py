"""MC_GearInPosCA (TF5410 §9.1.1.1.4, §9.4.1.5; digest D5 T15).

A CA slave syncs to a PTP master that starts accelerating when the command becomes active;
same distances and dynamics for every strategy.
"""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    MC_GearInPosCA,
    ST_GearInPosCAOptions,
    SyncMode,
    SyncStrategy,
)

LIMITS = {"max_velocity": 4000.0, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
          "max_jerk": 1e5, "acceleration": 5000.0, "deceleration": 5000.0, "jerk": 50000.0}
MSP, SSP = 1000.0, 1500.0  # the slave is at 1500 when the master is at 1000


def setup(ring: bool = False) -> tuple[om.Runtime, CaGroup, om.Axis, om.Axis]:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=ring, rail_length=10000.0)
    master = rt.add_axis("master", max_velocity=2000.0, max_acceleration=10000.0,
                         max_deceleration=10000.0, max_jerk=1e5)
    master.power()
    slave = rt.add_axis("slave", position=0.0, **LIMITS)
    slave.power()
    group.add_axis(slave, UDINT_TO_IDENTINGROUP(1))
    group.enable()
    return rt, group, master, slave


def run_sync(strategy: SyncStrategy, **inputs: object) -> dict:
    rt, group, master, slave = setup()
    master.move_velocity(500.0)  # still accelerating when the command becomes active
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, strategy,
                                velocity=2000.0, **inputs)
    seen: dict = {"start": None, "in_sync": None, "command": command}
    peak = 0.0
    for _ in range(3000):
        rt.step()
        start_sync, in_sync = group.sync_state(command)
        if start_sync and seen["start"] is None:
            seen["start"] = rt.now
        if in_sync and seen["in_sync"] is None:
            seen["in_sync"] = (rt.now, master.set_position, slave.set_position)
        if seen["in_sync"] is not None:  # the relation holds from InSync on
            assert slave.set_position == pytest.approx(SSP + (master.set_position - MSP),
                                                       abs=1e-9)
        peak = max(peak, abs(slave.set_acceleration))
    seen["peak_acceleration"] = peak
    return seen


def test_late_starts_as_late_as_possible_and_arrives_when_the_master_is_at_msp() -> None:
    late = run_sync(SyncStrategy.LATE)
    assert late["start"] == pytest.approx(0.95)  # not at once: as late as possible
    t, master, slave = late["in_sync"]
    assert (master, slave) == (pytest.approx(MSP, abs=1e-9), pytest.approx(SSP, abs=1e-9))
    assert late["command"].busy and not late["command"].done  # GearInPosCA has no Done


def test_slow_starts_at_once_and_arrives_at_the_same_point_with_reduced_dynamics() -> None:
    slow, early = run_sync(SyncStrategy.SLOW), run_sync(SyncStrategy.EARLY)
    assert slow["start"] == pytest.approx(0.001)
    t, master, slave = slow["in_sync"]
    assert (master, slave) == (pytest.approx(MSP, abs=1e-9), pytest.approx(SSP, abs=1e-9))
    assert slow["peak_acceleration"] < early["peak_acceleration"]


def test_early_starts_at_once_with_full_dynamics_and_is_in_sync_first() -> None:
    early, late = run_sync(SyncStrategy.EARLY), run_sync(SyncStrategy.LATE)
    assert early["start"] == pytest.approx(0.001)
    assert early["in_sync"][0] < late["in_sync"][0]
    assert early["in_sync"][1] < MSP  # in sync before the master reaches MSP


def test_late_fails_when_the_master_accelerates_after_start_sync() -> None:
    rt, group, master, slave = setup()
    master.move_velocity(200.0)
    rt.run(0.5)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.LATE,
                                velocity=2000.0)
    rt.run_until(lambda: group.sync_state(command)[0], timeout=10.0)
    master.move_velocity(600.0)
    rt.run_until(lambda: command.finished, timeout=2.0)
    assert command.error and command.error_id is ErrorId.SYNC_FAILED
    rt.run(1.0)
    assert slave.set_velocity == 0.0  # the slave braked to rest


@pytest.mark.parametrize("ratio", [0.8, -0.5])
def test_ratio_scales_the_slave_velocity(ratio: float) -> None:
    rt, group, master, slave = setup()
    master.move_velocity(500.0)
    command = group.gear_in_pos(master, slave, ratio, 1, MSP, SSP, SyncStrategy.EARLY,
                                velocity=3000.0)
    rt.run_until(lambda: group.sync_state(command)[1], timeout=10.0)
    rt.run(0.2)
    assert slave.set_velocity == pytest.approx(ratio * master.set_velocity, abs=1e-9)


@pytest.mark.parametrize("distance", [300.0, -300.0])
def test_master_start_distance_delays_the_start(distance: float) -> None:
    rt, group, master, slave = setup()
    if distance < 0:  # master coming from above, moving down
        master.set_actual_position(2000.0)
        rt.step()
        master.move_velocity(500.0, direction=om.Direction.NEGATIVE)
    else:
        master.move_velocity(500.0)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.EARLY,
                                master_start_distance=distance, velocity=3000.0)
    rt.run_until(lambda: group.sync_state(command)[0], timeout=10.0)
    threshold = MSP - distance
    assert abs(master.set_position - threshold) <= 500.0 * 0.001 + 1e-9  # within a cycle


def test_both_master_velocity_flags_false_is_an_error() -> None:
    rt, group, master, slave = setup()
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, velocity=1000.0,
                                master_velocity_undershoot_allowed=False,
                                master_velocity_overshoot_allowed=False)
    assert command.error and command.error_id is ErrorId.INVALID_SYNC_OPTIONS


def test_an_aborting_move_decouples() -> None:
    rt, group, master, slave = setup()
    master.move_velocity(500.0)
    gear = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.EARLY,
                             velocity=3000.0)
    rt.run_until(lambda: group.sync_state(gear)[1], timeout=10.0)
    move = group.move_absolute(slave, slave.set_position + 200.0, 1000.0)
    assert gear.aborted and group.sync_state(gear) == (False, False)
    rt.run_until(lambda: move.done, timeout=10.0)


def test_in_sync_falls_when_gap_control_holds_the_slave_and_recovers() -> None:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=False, rail_length=10000.0)
    master = rt.add_axis("master", max_velocity=2000.0)
    master.power()
    blocker = rt.add_axis("blocker", position=3000.0, **LIMITS)
    slave = rt.add_axis("slave", position=0.0, **LIMITS)
    for i, axis in enumerate((blocker, slave)):
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
    group.enable()
    master.move_velocity(500.0)
    gear = group.gear_in_pos(master, slave, 1.0, 1, 0.0, 0.0, SyncStrategy.EARLY,
                             velocity=3000.0)
    rt.run_until(lambda: group.sync_state(gear)[1], timeout=10.0)
    rt.run_until(lambda: not group.sync_state(gear)[1], timeout=10.0)  # the blocker stands
    assert slave.set_position <= 3000.0 - 100.0 + 1e-9
    group.move_absolute(blocker, 9000.0, 3000.0)  # the way clears: the slave syncs again
    rt.run_until(lambda: group.sync_state(gear)[1], timeout=10.0)
    assert slave.set_position == pytest.approx(master.set_position, abs=1e-9)
    assert min(group.gaps()) >= 100.0 - 1e-9


def test_the_block_shows_start_sync_and_in_sync() -> None:
    rt, group, master, slave = setup()
    master.move_velocity(500.0)
    fb = MC_GearInPosCA(slave, master=master, master_sync_position=MSP,
                        slave_sync_position=SSP, sync_strategy=SyncStrategy.EARLY,
                        velocity=3000.0, options=ST_GearInPosCAOptions())
    fb(execute=True)
    rt.step()
    fb()
    assert fb.busy and fb.active and fb.start_sync and not fb.in_sync
    while not fb.in_sync:
        rt.step()
        fb()
    assert not fb.start_sync and not fb.done
    group.halt_axis(slave)
    fb()
    assert fb.command_aborted and not fb.busy and not fb.in_sync


def test_overshoot_forbidden_fails_when_the_slave_must_catch_up() -> None:
    rt, group, master, slave = setup()
    master.move_velocity(500.0)
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, SyncStrategy.EARLY,
                                velocity=3000.0, master_velocity_overshoot_allowed=False)
    rt.run_until(lambda: command.finished, timeout=2.0)
    assert command.error and command.error_id is ErrorId.SYNC_FAILED
    assert "Overshoot" in command.message


def test_overshoot_forbidden_is_fine_when_the_slave_only_falls_back() -> None:
    rt, group, master, slave = setup()  # master standing at 0: the slave goes back to -200
    command = group.gear_in_pos(master, slave, 1.0, 1, 0.0, -200.0, SyncStrategy.EARLY,
                                velocity=3000.0, master_velocity_overshoot_allowed=False)
    rt.run_until(lambda: group.sync_state(command)[1], timeout=5.0)
    assert slave.set_position == pytest.approx(-200.0, abs=1e-9)


def test_undershoot_forbidden_fails_when_the_slave_would_be_slower() -> None:
    rt, group, master, slave = setup()
    command = group.gear_in_pos(master, slave, 1.0, 1, 0.0, -200.0, SyncStrategy.EARLY,
                                velocity=3000.0, master_velocity_undershoot_allowed=False)
    rt.run_until(lambda: command.finished, timeout=2.0)
    assert command.error_id is ErrorId.SYNC_FAILED and "Undershoot" in command.message


def sync_with_lead(**options: object) -> tuple[object, list[tuple[float, float, float]]]:
    """The master cruises at 500 mm/s; the slave stands far behind its coupled position, so
    it is slower than the master when the command starts. Samples (t, v_master, v_slave)."""
    rt, group, master, slave = setup()
    master.move_velocity(500.0)
    rt.run(0.3)
    command = group.gear_in_pos(master, slave, 1.0, 1, master.set_position + 500.0, 1000.0,
                                SyncStrategy.EARLY, velocity=3000.0, **options)
    samples = []
    for _ in range(3000):
        rt.step()
        samples.append((rt.now, master.set_velocity, slave.set_velocity))
        if command.finished or group.sync_state(command)[1]:
            break
    return command, samples, group


def test_undershoot_forbidden_first_brings_the_slave_to_the_master_velocity() -> None:
    """MasterVelocityUndershootAllowed FALSE (§9.1.2.1): the slave, slower than the master at
    the start, accelerates to the master's velocity as fast as it can and from then on is
    never slower than the master while it catches up."""
    command, samples, group = sync_with_lead(master_velocity_undershoot_allowed=False)
    assert not command.error, command.message
    assert group.sync_state(command)[1]  # in sync
    reached = next(k for k, (_, vm, vs) in enumerate(samples) if vs >= vm - 1e-9)
    assert all(vs >= vm - 1e-6 for _, vm, vs in samples[reached:])
    assert any(vs > vm + 1.0 for _, vm, vs in samples[reached:])  # it did catch up


def test_overshoot_forbidden_still_fails_when_the_slave_must_catch_up_after_the_lead() -> None:
    command, _, _ = sync_with_lead(master_velocity_overshoot_allowed=False)
    assert command.error and command.error_id is ErrorId.SYNC_FAILED


@pytest.mark.parametrize(("minimum", "ok"), [(-300.0, True), (-100.0, False)])
def test_minimal_slave_position(minimum: float, ok: bool) -> None:
    rt, group, master, slave = setup()
    command = group.gear_in_pos(master, slave, 1.0, 1, 0.0, -200.0, SyncStrategy.EARLY,
                                velocity=3000.0, minimal_slave_position=minimum)
    if ok:
        rt.run_until(lambda: group.sync_state(command)[1], timeout=5.0)
        assert slave.set_position == pytest.approx(-200.0, abs=1e-9)
    else:
        rt.run_until(lambda: command.finished, timeout=2.0)
        assert command.error_id is ErrorId.SYNC_FAILED and "MinimalSlavePosition" in \
            command.message


@pytest.mark.parametrize("allowed", [True, False])
def test_direction_reversal(allowed: bool) -> None:
    """The slave far ahead of its coupled position: the fastest sync moves it backwards;
    with DirectionReversalAllowed FALSE it waits and syncs forwards (§9.1.2.1, D-204)."""
    rt, group, master, slave = setup()
    master.move_velocity(100.0)
    rt.run(0.5)
    command = group.gear_in_pos(master, slave, 1.0, 1, 1000.0, 400.0, SyncStrategy.EARLY,
                                velocity=3000.0, direction_reversal_allowed=allowed)
    lowest = 0.0
    for _ in range(8000):
        rt.step()
        lowest = min(lowest, slave.set_velocity)
        if command.finished or group.sync_state(command)[1]:
            break
    assert group.sync_state(command)[1], command.message
    assert lowest < 0.0 if allowed else lowest >= 0.0


@pytest.mark.parametrize(("mode", "expected"), [(SyncMode.POSITIVE, 3100.0),
                                                (SyncMode.NEGATIVE, 100.0),
                                                (SyncMode.NON_MODULO, 100.0)])
def test_sync_mode_picks_the_slave_sync_position_on_the_ring(mode: SyncMode,
                                                             expected: float) -> None:
    """§9.4.1.4: with a modulo sync mode SlaveSyncPosition is a position on the ring, the
    next one from the slave in that direction; NonModulo takes it as absolute."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=3000.0)
    master = rt.add_axis("master", max_velocity=2000.0)
    master.power()
    slave = rt.add_axis("slave", position=2900.0, **LIMITS)
    slave.power()
    group.add_axis(slave, UDINT_TO_IDENTINGROUP(1))
    group.enable()
    command = group.gear_in_pos(master, slave, 1.0, 1, 0.0, 100.0, SyncStrategy.EARLY,
                                sync_mode=mode, velocity=3000.0)
    rt.run_until(lambda: group.sync_state(command)[1], timeout=5.0)
    assert slave.set_position == pytest.approx(expected, abs=1e-9)  # master stands at 0


def test_a_modulo_sync_mode_on_an_open_rail_is_an_error() -> None:
    rt, group, master, slave = setup()
    command = group.gear_in_pos(master, slave, 1.0, 1, MSP, SSP, sync_mode=SyncMode.POSITIVE,
                                velocity=1000.0)
    assert command.error and command.error_id is ErrorId.MODULO_ON_OPEN_RAIL


@pytest.mark.parametrize("strategy", [SyncStrategy.EARLY, SyncStrategy.SLOW])
def test_a_standing_slave_starts_smoothly_to_a_cruising_master(strategy: SyncStrategy) -> None:
    """The sync starts from the slave's state of the last cycle with the master's of that
    cycle: a slave standing at 0 behind a master cruising at 500 mm/s starts with the jerk of
    its default jerk, not with a jump back by the master's travel in one cycle (0.5 mm)."""
    rt, group, master, slave = setup()
    master.move_velocity(500.0)
    rt.run(1.0)
    assert master.set_velocity == pytest.approx(500.0)
    group.gear_in_pos(master, slave, 1.0, 1, 3000.0, 3500.0, strategy, velocity=2000.0)
    positions = []
    for _ in range(20):
        rt.step()
        positions.append(slave.set_position)
        assert abs(slave.set_acceleration) <= LIMITS["max_acceleration"] * (1 + 1e-9)
    assert positions[0] == pytest.approx(LIMITS["jerk"] * 0.001 ** 3 / 6.0, rel=1e-6)
    assert all(b >= a for a, b in zip(positions, positions[1:], strict=False))


def test_a_slave_held_by_gap_control_stops_and_waits_without_turning_round() -> None:
    """Gap control brakes the slave in sync harder than its sync dynamics (3000 mm/s²,
    30000 mm/s³) could let go of; the re-sync then brakes on to rest behind the standing
    blocker and waits there, never backwards (D-206). Before, each re-sync from the braked
    state swung the slave back at up to 780 mm/s, again and again."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=False, rail_length=20000.0)
    master = rt.add_axis("master", max_velocity=2000.0)
    master.power()
    blocker = rt.add_axis("blocker", position=3000.0, **LIMITS)
    slave = rt.add_axis("slave", position=0.0, **LIMITS)
    for i, axis in enumerate((blocker, slave)):
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
    group.enable()
    master.move_velocity(500.0)
    gear = group.gear_in_pos(master, slave, 1.0, 1, 0.0, 0.0, SyncStrategy.EARLY,
                             velocity=2500.0, acceleration=3000.0, deceleration=3000.0,
                             jerk=30000.0)
    rt.run_until(lambda: group.sync_state(gear)[1], timeout=10.0)
    rt.run_until(lambda: not group.sync_state(gear)[1], timeout=10.0)
    for _ in range(1500):
        rt.step()
        assert slave.set_velocity >= 0.0
    assert (slave.set_position, slave.set_velocity) == (pytest.approx(2900.0), 0.0)
    assert gear.busy and not group.sync_state(gear)[1]
