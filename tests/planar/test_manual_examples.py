"""The worked examples of the TF5430 manual (§6.1.3-6.1.8, §6.3.2, §6.4.2, §6.6.1, §6.7.1,
§6.7.2) with the manual's numbers.

Each example runs its PLC program: ``cycle()`` is the body of MAIN (a CASE on ``state``), and
``rt.step()`` is what the manual's ``Update()`` calls do after END_CASE. The program reads the
status published in the previous cycle, as a PLC does. The manual's watch windows are checked
once the program is in its last state and the movers stand.

The simulation has no levitation noise: where the manual shows z = 2.005..., a = -0.00078...
(the XPlanar simulation of the processing unit, §6.1.4), we expect exact zeros. Where the
manual's numbers contradict each other (digest-planar-concepts §8), the test follows the
consistent reading and says which.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace

import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarFeedback,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarPart,
    MC_PlanarTrack,
    MoverCommandMode,
    MoverVector,
    Part,
    PartLayout,
    PartPosition,
    PlanarMoverParameters,
    PlanarObjectType,
    PlanarState,
    Pose,
    PositionXYC,
)

ENABLED = PlanarState.ENABLED
FREE = MoverCommandMode.FREE_MOVEMENT
EXACT = 1e-9  #: [mm], [°] the manual's 100 / 0.9999999999... are the target itself
FIRST_MOVER = 0x05110010  #: MoverOID of the first mover (§6.1.8 watch window)
FIRST_OBJECT = 0x05120010  #: the first group or environment (§6.4.2, §6.7.2: 85065744)
CS_1 = 0x01010060  #: the coordinate system of §6.1.4 / §6.1.7 (PhysicalAreaID 16842848)
CS_2 = 0x010100A0  #: coordinate system two of §6.6.1
PART_1 = 0x01010020  #: the left part (not printed; next to 16#01010030 in the same range)
PART_2 = 0x01010030  #: the right part of §6.1.4, part two of §6.6.1
PART_3 = 0x01010080  #: the elevator of §6.6.1


def run(rt: om.Runtime, program: Callable[[], None], until: Callable[[], bool],
        timeout: float = 10.0) -> int:
    """The PLC task: MAIN's body, then the runtime exchanges the data (the Update() calls),
    until ``until()`` holds at the start of a cycle. Returns the cycles it took."""
    for cycle in range(round(timeout / rt.cycle_time)):
        if until():
            return cycle
        program()
        rt.step()
    raise AssertionError(f"not reached within {timeout} s")


def vector(mover: MC_PlanarMover) -> tuple[float, ...]:
    p = mover.mc_to_plc.set.set_pos
    return (p.x, p.y, p.z, p.a, p.b, p.c)


def assert_at(mover: MC_PlanarMover, *expected: float) -> None:
    assert vector(mover) == pytest.approx(expected, abs=EXACT), vector(mover)


def standing(*movers: MC_PlanarMover) -> bool:
    return not any(m.mc_to_plc.std.busy.busy_mover for m in movers)


def two_parts() -> PartLayout:
    """§6.1.4 / §6.1.7: two static one-stator parts side by side, one coordinate system; the
    right part's frame is the system's shifted by 240 mm in x."""
    return PartLayout([CS_1], [Part(PART_1, [(0.0, 0.0)], [PartPosition(CS_1, Pose())]),
                               Part(PART_2, [(0.0, 0.0)], [PartPosition(CS_1, Pose(240.0))])])


def max_brake(speed: float, mover: MC_PlanarMover) -> float:
    """The time-optimal stopping distance from ``speed`` (no acceleration) with the mover's
    maximum XY dynamics, where StopExternalSetpointGeneration brakes (§6.1.6)."""
    limits = mover.parameters.maximum_dynamic_xy
    if speed >= limits.deceleration ** 2 / limits.jerk:
        return speed ** 2 / (2 * limits.deceleration) + speed * limits.deceleration / (
            2 * limits.jerk)
    return speed * math.sqrt(speed / limits.jerk)


# -- §6.1.3 ------------------------------------------------------------------------------------


def test_6_1_3_creating_and_moving_planar_movers():
    rt = om.Runtime()
    mover = MC_PlanarMover(rt, PlanarMoverParameters(simulation_mode=True))
    target_position = PositionXYC()
    state = 0
    seen: list[PlanarState] = []

    def main() -> None:
        nonlocal state
        seen.append(mover.state)
        match state:
            case 0:
                mover.enable()
                state = 1
            case 1:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 2
            case 2:
                target_position.set_values_xy(100, 100)
                mover.move_to_position(target_position, None, None)
                state = 3

    run(rt, main, lambda: state == 3 and standing(mover))
    assert list(dict.fromkeys(seen)) == [PlanarState.DISABLED, PlanarState.ENABLING, ENABLED]
    assert_at(mover, 100.0, 100.0, 0.0, 0.0, 0.0, 0.0)
    assert (mover.error, mover.error_id) == (False, 0)
    assert mover.mc_to_plc.set.physical_area_id == 0
    assert mover.mc_to_plc.std.mover_oid == FIRST_MOVER
    assert mover.command_mode is FREE
    assert mover.mc_to_plc.set.set_velo == MoverVector()


# -- §6.1.4 ------------------------------------------------------------------------------------


def test_6_1_4_moving_a_planar_mover_to_planar_parts():
    """Target (100, 100) on the right part 16#01010030; the mover starts at P1 = (120, 120),
    the middle of the left part. SetPos is shown in the coordinate system: (340, 100)."""
    rt = om.Runtime()
    MC_PlanarEnvironment(rt, layout=two_parts())
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(120, 120)))
    target_position = PositionXYC()
    state = 0

    def main() -> None:
        nonlocal state
        match state:
            case 0:
                mover.enable()
                state = 1
            case 1:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 2
            case 2:
                target_position.set_values_xyc_reference_id(100, 100, 0, 0x01010030)
                mover.move_to_position(target_position, None, None)
                state = 3

    run(rt, main, lambda: state == 3 and standing(mover))
    assert_at(mover, 340.0, 100.0, 0.0, 0.0, 0.0, 0.0)  # the manual's z, a, b, c: noise
    assert mover.mc_to_plc.set.physical_area_id == 16842848 == CS_1
    assert (mover.error, mover.error_id) == (False, 0)
    assert mover.get_position_on_current_part() == PositionXYC(100.0, 100.0, 0.0, PART_2)


# -- §6.1.5 ------------------------------------------------------------------------------------


def test_6_1_5_auxiliary_axes_move_together():
    """MoveA, MoveB, MoveC and MoveZ in one cycle run side by side: none aborts another."""
    rt = om.Runtime()
    mover = MC_PlanarMover(rt)
    target_a, target_b, target_c, target_z = 1.0, -1.0, 3.0, 5.0
    commands = []
    state = 0

    def main() -> None:
        nonlocal state
        match state:
            case 0:
                mover.enable()
                state = 1
            case 1:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 2
            case 2:
                commands.append(mover.move_a(target_a, None))
                commands.append(mover.move_b(target_b, None))
                commands.append(mover.move_c(target_c, None, None))
                commands.append(mover.move_z(target_z, None))
                state = 3

    run(rt, main, lambda: state == 3 and standing(mover))
    assert_at(mover, 0.0, 0.0, 5.0, 1.0, -1.0, 3.0)
    assert [c.done for c in commands] == [True] * 4, commands
    assert (mover.error, mover.error_id) == (False, 0)
    assert mover.command_mode is FREE  # 3° is inside the C window ±15°


# -- §6.1.6 ------------------------------------------------------------------------------------


def test_6_1_6_external_setpoint_generation():
    """The printed program never sets ``jerk`` and stops in ``case 5`` while the profile ends
    in state 4, yet the result is state 6 at x = 1007.249774 (digest §8.2). Consistent
    reading: jerk starts at +1 mm/s³ and state 4 stops the generation and goes to 6. The
    profile (a: 0 -> 10 -> 0 mm/s²) ends at x = 1000.30 mm with v = 100.02 mm/s; the mover
    then brakes with its maximum dynamics. The manual's 7 mm brake belongs to maximum
    dynamics it does not print; ours (PlanarMoverParameters) give their own exact distance."""
    rt = om.Runtime()
    mover = MC_PlanarMover(rt)
    p = v = a = MoverVector()
    deltat, jerk = 0.001, 1.0
    state = 0
    sent: list[tuple[float, float, float]] = []

    def main() -> None:
        nonlocal state, p, v, a, jerk
        if sent:  # the mover follows the setpoints exactly, one cycle after the call
            s = mover.mc_to_plc.set
            assert (s.set_pos.x, s.set_velo.x, s.set_acc.x) == sent.pop()
            assert mover.command_mode is MoverCommandMode.EXTERNAL_SETPOINT_GENERATION
        match state:
            case 0:
                mover.enable()
                state = 1
            case 1:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 2
            case 2:
                p, v, a = replace(p, x=0.0), replace(v, x=0.0), replace(a, x=0.0)
                mover.start_external_setpoint_generation()
                mover.set_external_setpoint(p, v, a)
                sent.append((p.x, v.x, a.x))
                state = 3
            case 3:
                velo, acc = v.x, a.x
                p = replace(p, x=p.x + deltat * velo + deltat * deltat / 2 * acc
                            + deltat * deltat * deltat / 6 * jerk)
                v = replace(v, x=v.x + deltat * acc + deltat * deltat / 2 * jerk)
                a = replace(a, x=a.x + deltat * jerk)
                mover.set_external_setpoint(p, v, a)
                sent.append((p.x, v.x, a.x))
                if a.x >= 10.0:
                    jerk = -1
                if a.x <= 0.0:
                    state = 4
            case 4:
                mover.stop_external_setpoint_generation()
                state = 6

    run(rt, main, lambda: state == 6 and standing(mover), timeout=30.0)
    assert (p.x, v.x) == (pytest.approx(1000.30, abs=0.01), pytest.approx(100.02, abs=0.01))
    # state 4 sends no setpoint: one more cycle at v, then the brake with maximum dynamics
    end = p.x + v.x * deltat + max_brake(v.x, mover)
    assert_at(mover, end, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert end > 1000.4
    assert (mover.error, mover.error_id) == (False, 0)
    assert mover.command_mode is FREE


# -- §6.1.7 ------------------------------------------------------------------------------------


def profile_to_parts(rt: om.Runtime, mover: MC_PlanarMover, feedback: MC_PlanarFeedback,
                     turn_at: float, reference: Callable[[float], tuple[int, float]],
                     watch: Callable[[], None] = lambda: None,
                     until: Callable[[], bool] | None = None) -> tuple[MoverVector, ...]:
    """§6.1.7's program (deltat 0.01 s, jerk ±10 mm/s³), reversing the jerk at
    ``a.x >= turn_at``; ``reference(x)`` gives (refsys, x in that frame) for each setpoint.
    It runs until state 5 with the mover standing, or the mover errs (or ``until()``)."""
    p = v = a = MoverVector()
    deltat, jerk = 0.01, 0.0
    state = 0

    def main() -> None:
        nonlocal state, p, v, a, jerk
        watch()
        match state:
            case 0:
                mover.enable()
                state = 1
            case 1:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 2
            case 2:
                p = mover.mc_to_plc.set.set_pos
                v, a = replace(v, x=0.0), replace(a, x=0.0)
                mover.start_external_setpoint_generation()
                refsys, x = reference(p.x)
                mover.set_external_setpoint_reference_id(feedback, replace(p, x=x), v, a, refsys)
                jerk = 10
                state = 3
            case 3:
                velo, acc = v.x, a.x
                p = replace(p, x=p.x + deltat * velo + deltat * deltat / 2 * acc
                            + deltat * deltat * deltat / 6 * jerk)
                v = replace(v, x=velo + deltat * acc + deltat * deltat / 2 * jerk)
                a = replace(a, x=acc + deltat * jerk)
                refsys, x = reference(p.x)
                mover.set_external_setpoint_reference_id(feedback, replace(p, x=x), v, a, refsys)
                if a.x >= turn_at:
                    jerk = -10
                if a.x <= 0.0:
                    state = 4
            case 4:
                mover.stop_external_setpoint_generation()
                state = 5

    run(rt, main, until or (lambda: state == 5 and standing(mover) or mover.error),
        timeout=60.0)
    return p, v, a


def parts_runtime() -> tuple[om.Runtime, MC_PlanarMover, MC_PlanarFeedback]:
    rt = om.Runtime(cycle_time=0.01)  # deltat = 0.01 s: the program's cycle
    MC_PlanarEnvironment(rt, layout=two_parts())
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(120, 120)))
    return rt, mover, MC_PlanarFeedback()


@pytest.mark.parametrize("refsys", [0, CS_1, PART_1], ids=["zero", "system", "part-one"])
def test_6_1_7_external_setpoints_on_part_one(refsys: int):
    """The printed profile (jerk 10, up to a = 100 mm/s², deltat 0.01) would travel about
    10 m, yet the result is x = 223.2495 on the first part (digest §8.3). Consistent reading:
    the profile turns at a = 20 mm/s² (80 mm of travel at 40 mm/s), so the mover stays on
    part 1, where 0, the coordinate system and part 1 all name the frame of the setpoints."""
    rt, mover, feedback = parts_runtime()
    busy_from_state_2: list[bool] = []

    def watch() -> None:
        if mover.command_mode is MoverCommandMode.EXTERNAL_SETPOINT_GENERATION:
            busy_from_state_2.append(feedback.busy and not feedback.error)

    p, v, _ = profile_to_parts(rt, mover, feedback, 20.0, lambda x: (refsys, x), watch)
    end = p.x + v.x * 0.01 + max_brake(v.x, mover)
    assert_at(mover, end, 120.0, 0.0, 0.0, 0.0, 0.0)
    assert 200.0 < end < 240.0  # "It has not left the first part"
    assert mover.get_position_on_current_part().reference_id == PART_1
    assert mover.mc_to_plc.set.physical_area_id == 16842848
    assert (mover.error, mover.error_id, mover.command_mode) == (False, 0, FREE)
    # the feedback is Busy from state 2 on, and Stop does not make it Done
    assert busy_from_state_2 and all(busy_from_state_2)
    assert (feedback.busy, feedback.done, feedback.error) == (True, False, False)


def test_6_1_7_crossing_to_part_two_with_each_reference():
    """"If the object ID of the first part is specified and the limit to the second part is
    exceeded, the object ID of the second part must be used and the x-coordinate reduced by
    240 (at the same time!). The object ID of the global coordinate system works regardless
    of which part you are on. ... zero is accepted as an alternative." All three must give
    the same motion; the profile turns at a = 30 mm/s² and ends on part 2."""
    references = {
        "parts": lambda x: (PART_1, x) if x < 240.0 else (PART_2, x - 240.0),
        "system": lambda x: (CS_1, x),
        "zero": lambda x: (0, x),
    }
    traces = {}
    for name, reference in references.items():
        rt, mover, feedback = parts_runtime()
        trace: list[tuple[float, ...]] = []
        profile_to_parts(rt, mover, feedback, 30.0, reference,
                         lambda mover=mover, trace=trace: trace.append(vector(mover)))
        assert (mover.error, feedback.error) == (False, False), (name, mover.message)
        assert mover.get_position_on_current_part().reference_id == PART_2
        assert mover.mc_to_plc.set.physical_area_id == CS_1
        traces[name] = trace
    assert traces["parts"] == traces["system"] == traces["zero"]
    assert 300.0 < traces["parts"][-1][0] < 480.0


def test_6_1_7_a_wrong_reference_shows_on_the_feedback():
    """Keeping part 1's id past x = 240 is "an incorrect RefSysId for the position" (§6.1.7):
    the error of the generation shows on the feedback after the next call, with its own id."""
    rt, mover, feedback = parts_runtime()
    # the program has no error handling: it goes on calling until the feedback shows one
    profile_to_parts(rt, mover, feedback, 30.0, lambda x: (PART_1, x),
                     until=lambda: feedback.error)
    assert mover.error and mover.error_id == ErrorId.INVALID_REFERENCE_ID, mover.message
    assert 240.0 < mover.position.x < 260.0  # it stopped just past the edge of part 1
    assert not feedback.busy and not feedback.done
    assert feedback.error_id == ErrorId.INVALID_REFERENCE_ID, (feedback.error_id,
                                                               feedback.message)


def test_6_1_7_zero_is_the_coordinate_system_in_a_static_layout():
    """"As the configuration is static, zero is accepted as an alternative for the global
    coordinate system ID": the printed profile, which runs off both parts, must meet the same
    fate with 0 as with 16#01010060."""
    outcomes = []
    for refsys in (0, CS_1):
        rt, mover, feedback = parts_runtime()
        profile_to_parts(rt, mover, feedback, 100.0, lambda x, refsys=refsys: (refsys, x))
        outcomes.append((mover.state, mover.error_id, feedback.error, round(mover.position.x, 6)))
    assert outcomes[0] == outcomes[1]


# -- §6.1.8 ------------------------------------------------------------------------------------


def test_6_1_8_c_rotation_free_movement():
    rt = om.Runtime()
    mover = MC_PlanarMover(rt)
    target_position_c = 0.0
    state = 0

    def main() -> None:
        nonlocal state, target_position_c
        match state:
            case 0:
                mover.enable()
                state = 1
            case 1:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 2
            case 2:
                target_position_c = 20.0
                mover.move_c(target_position_c, None, None)
                state = 3

    run(rt, main, lambda: state == 3 and standing(mover))
    assert_at(mover, 0.0, 0.0, 0.0, 0.0, 0.0, 20.0)
    std = mover.mc_to_plc.std
    assert (std.mover_oid, std.group_oid, std.state, std.error_code) == (
        0x05110010, 0x00000000, ENABLED, 0)
    assert std.command_mode is MoverCommandMode.C_ROTATION_FREE_MOVEMENT  # 20° > 15°
    assert (mover.error, mover.error_id) == (False, 0)
    # "A further movement of the C-axis up to e.g. 90° would change the command mode back to
    # Free Movement after completion of the command."
    turn = mover.move_c(90.0)
    modes = []
    run(rt, lambda: modes.append(mover.command_mode), lambda: turn.done and standing(mover))
    assert set(modes) == {MoverCommandMode.C_ROTATION_FREE_MOVEMENT}
    rt.step()
    assert mover.command_mode is FREE
    assert_at(mover, 0.0, 0.0, 0.0, 0.0, 0.0, 90.0)


# -- §6.3.2 ------------------------------------------------------------------------------------


def test_6_3_2_creating_and_moving_planar_movers_with_group():
    """Both movers are commanded in one cycle: mover one moves to (0, 240); mover two's move to
    the origin is rejected, "because Mover one still stood there". Neither mover errs."""
    rt = om.Runtime()
    mover_one = MC_PlanarMover(rt)
    mover_two = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x=240)))
    group = MC_PlanarGroup(rt)
    pos1, pos2 = PositionXYC(), PositionXYC()
    moves = []
    state = 0

    def main() -> None:
        nonlocal state
        match state:
            case 0:
                mover_one.enable()
                mover_two.enable()
                state = 1
            case 1:
                if mover_one.mc_to_plc.std.state is ENABLED and \
                        mover_two.mc_to_plc.std.state is ENABLED:
                    state = 2
            case 2:
                group.enable()
                state = 3
            case 3:
                if group.mc_to_plc_std.state is ENABLED:
                    state = 4
            case 4:
                mover_one.add_to_group(group)
                mover_two.add_to_group(group)
                state = 5
            case 5:
                if mover_one.mc_to_plc.std.group_oid == group.mc_to_plc_std.group_oid and \
                        mover_two.mc_to_plc.std.group_oid == group.mc_to_plc_std.group_oid:
                    state = 6
            case 6:
                pos1.set_values_xy(0, 240)
                pos2.set_values_xy(0, 0)
                moves.append(mover_one.move_to_position(pos1, None, None))
                moves.append(mover_two.move_to_position(pos2, None, None))
                state = 7

    run(rt, main, lambda: state == 7 and standing(mover_one, mover_two))
    assert_at(mover_one, 0.0, 240.0, 0.0, 0.0, 0.0, 0.0)
    assert_at(mover_two, 240.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for mover in (mover_one, mover_two):
        assert (mover.error, mover.error_id) == (False, 0)
        assert mover.mc_to_plc.std.group_oid == group.oid == FIRST_OBJECT
    assert moves[0].done
    assert moves[1].error and moves[1].error_id == ErrorId.PLANAR_COLLISION == 33158
    assert (moves[1].object_info.object_type, moves[1].object_info.id) == (
        PlanarObjectType.MOVER, mover_one.oid)


# -- §6.4.2 ------------------------------------------------------------------------------------


def test_6_4_2_configuring_the_stator_area_and_boundary():
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    state = 0

    def main() -> None:
        nonlocal state
        match state:
            case 0:
                environment.add_stator(0.0, 0.0)
                environment.add_stator(240.0, 0.0)
                environment.add_stator(0.0, 240.0)
                environment.add_stator(240.0, 240.0)
                environment.create_boundary()
                state = 1

    run(rt, main, lambda: state == 1 and environment.mc_to_plc_std.stator_count > 0)
    std = environment.mc_to_plc_std
    assert (std.environment_oid, std.group_oid, std.stator_count,
            std.boundary_element_count) == (0x05120010, 0, 4, 8)
    assert (environment.error, environment.error_id) == (False, 0)
    assert environment.surface.bounds == (0.0, 0.0, 480.0, 480.0)
    assert environment.surface.area == 480.0 * 480.0


# -- §6.6.1 ------------------------------------------------------------------------------------


def test_6_6_1_the_mover_rides_the_elevator():
    """Part 1 at the origin of CS 1, part 2 (16#01010030) at the origin of CS 2 (16#010100A0),
    part 3 (16#01010080) above either (index 1 in CS 1, index 2 in CS 2; above is inferred:
    SetPos.y > 300 on it), starting in CS 2. The mover starts in the middle of part 1."""
    rt = om.Runtime()
    elevator = Part(PART_3, [(0.0, 0.0)], [PartPosition(CS_1, Pose(0.0, 240.0)),
                                          PartPosition(CS_2, Pose(0.0, 240.0))], position_index=2)
    layout = PartLayout([CS_1, CS_2], [
        Part(PART_1, [(0.0, 0.0)], [PartPosition(CS_1, Pose())]),
        Part(PART_2, [(0.0, 0.0)], [PartPosition(CS_2, Pose())]), elevator])
    environment = MC_PlanarEnvironment(rt, layout=layout)
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(120, 120),
                                                     part_oid=PART_1))
    part_three = MC_PlanarPart()
    target_position = PositionXYC()
    state = 0
    seen: dict[int, tuple[tuple[float, ...], int]] = {}

    def main() -> None:
        nonlocal state
        match state:
            case 0:
                part_three.initialize(0x01010080, environment)
                state = 1
            case 1:
                if part_three.is_initialized:
                    state = 2
            case 2:
                mover.enable()
                state = 3
            case 3:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 4
            case 4:
                part_three.activate_position(1)
                state = 5
            case 5:
                if part_three.position_index == 1:
                    state = 6
            case 6:
                target_position.set_values_xyc_reference_id(120, 120, 0, part_three.part_oid)
                mover.move_to_position(target_position, None, None)
                state = 7
            case 7:
                if mover.mc_to_plc.set.set_pos.y > 300 and not mover.mc_to_plc.std.busy.busy_xyc:
                    state = 8
            case 8:
                part_three.activate_position(2)
                state = 9
            case 9:
                if part_three.position_index == 2:
                    state = 10
            case 10:
                target_position.set_values_xyc_reference_id(120, 120, 0, 0x01010030)  # part 2
                mover.move_to_position(target_position, None, None)
                state = 11
        seen.setdefault(state, (vector(mover), mover.mc_to_plc.set.physical_area_id))

    run(rt, main, lambda: state == 11 and standing(mover))
    assert seen[8] == ((120.0, 360.0, 0.0, 0.0, 0.0, 0.0), CS_1)  # on part 3 in CS 1
    assert seen[10] == ((120.0, 360.0, 0.0, 0.0, 0.0, 0.0), CS_2)  # carried to CS 2
    assert_at(mover, 120.0, 120.0, 0.0, 0.0, 0.0, 0.0)
    assert mover.mc_to_plc.set.physical_area_id == 0x010100A0
    assert state == 0x0B
    assert (mover.error, mover.error_id) == (False, 0)
    # the last mover left CS 1: its part is off; CS 2's parts are on (§6.6)
    assert [layout.part(oid).state for oid in (PART_1, PART_2, PART_3)] == [
        PlanarState.DISABLED, ENABLED, ENABLED]


# -- §6.7.1 ------------------------------------------------------------------------------------


def test_6_7_1_creating_a_planar_mover_and_planar_feedback():
    rt = om.Runtime()
    mover = MC_PlanarMover(rt)
    feedback = MC_PlanarFeedback()
    target_position = PositionXYC()
    state = 0
    after_move_call: list[bool] = []

    def main() -> None:
        nonlocal state
        if state == 3 and not after_move_call:  # the reused feedback shows no stale Done
            after_move_call.append(feedback.busy and not feedback.done)
        match state:
            case 0:
                mover.enable(feedback)
                state = 1
            case 1:
                if feedback.done:
                    state = 2
            case 2:
                target_position.set_values_xy(1000, 1000)
                mover.move_to_position(target_position, None, None, feedback)
                state = 3

    run(rt, main, lambda: state == 3 and feedback.done)
    assert after_move_call == [True]
    assert_at(mover, 1000.0, 1000.0, 0.0, 0.0, 0.0, 0.0)
    assert (feedback.done, feedback.active, feedback.busy, feedback.aborted, feedback.error,
            feedback.error_id) == (True, False, False, False, False, 0)
    assert (mover.error, mover.error_id, mover.mc_to_plc.set.physical_area_id) == (False, 0, 0)
    assert standing(mover)


# -- §6.7.2 ------------------------------------------------------------------------------------


def averting_collision(x: float, y: float) -> tuple[MC_PlanarMover, MC_PlanarEnvironment,
                                                    MC_PlanarFeedback]:
    """§6.7.2's program with the target (x, y): one stator [-120, 120]², the mover at (0, 0),
    environment and mover in a group. The environment is configured before the group, so it
    gets the first object id."""
    rt = om.Runtime()
    mover = MC_PlanarMover(rt)
    environment = MC_PlanarEnvironment(rt)
    group = MC_PlanarGroup(rt)
    feedback = MC_PlanarFeedback()
    target_position = PositionXYC()
    state = 0

    def main() -> None:
        nonlocal state
        match state:
            case 0:
                environment.add_stator(-120.0, -120.0)
                environment.create_boundary()
                state = 1
            case 1:
                mover.enable()
                group.enable()
                state = 2
            case 2:
                if mover.mc_to_plc.std.state is ENABLED and group.mc_to_plc_std.state is ENABLED:
                    state = 3
            case 3:
                mover.add_to_group(group)
                environment.add_to_group(group)
                state = 4
            case 4:
                if mover.mc_to_plc.std.group_oid > 0 and environment.mc_to_plc_std.group_oid > 0:
                    state = 5
            case 5:
                target_position.set_values_xy(x, y)
                mover.move_to_position(target_position, None, None, feedback)
                state = 6

    run(rt, main, lambda: state == 6 and not feedback.busy and standing(mover))
    return mover, environment, feedback


def test_6_7_2_averting_collision():
    mover, environment, feedback = averting_collision(100, 100)
    assert_at(mover, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert (mover.error, mover.error_id) == (False, 0)
    assert (feedback.done, feedback.active, feedback.busy, feedback.aborted, feedback.error,
            feedback.error_id) == (False, False, False, False, True, 33158)
    assert feedback.object_info.object_type is PlanarObjectType.ENVIRONMENT
    assert feedback.object_info.id == 85065744 == environment.oid
    std = environment.mc_to_plc_std
    assert (std.stator_count, std.boundary_element_count) == (1, 4)


@pytest.mark.parametrize(("x", "y"), [(42.5, -42.5), (-42.5, 0.0), (0.0, 42.5)])
def test_6_7_2_the_footprint_may_reach_the_boundary(x: float, y: float):
    """The rejection is geometric: 155 mm at (100, 100) reaches 177.5 > 120; a centre up to
    ±42.5 mm keeps the footprint on the stator, touching the boundary."""
    mover, _, feedback = averting_collision(x, y)
    assert feedback.done and not feedback.error
    assert_at(mover, x, y, 0.0, 0.0, 0.0, 0.0)


@pytest.mark.parametrize(("x", "y"), [(42.6, 0.0), (0.0, -42.51)])
def test_6_7_2_a_tenth_of_a_millimetre_beyond_is_refused(x: float, y: float):
    mover, environment, feedback = averting_collision(x, y)
    assert feedback.error and feedback.error_id == ErrorId.PLANAR_COLLISION
    assert feedback.object_info.id == environment.oid
    assert_at(mover, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


# -- §6.2.5 ------------------------------------------------------------------------------------


def test_6_2_5_moving_a_planar_mover_on_tracks_with_planar_parts():
    """Track one on the left part, track two on the right part starting from it; points
    given in the coordinate system 16#01010060. The mover at P1 = (120, 120) joins track one
    at 80 and moves to 150 on track two, over the part boundary: x = 390 (the manual's z, a,
    b are hardware noise). PhysicalAreaID 16842848."""
    rt = om.Runtime()
    MC_PlanarEnvironment(rt, layout=two_parts())
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(120, 120)))
    track_one = MC_PlanarTrack(rt, part_oid=PART_1)
    track_two = MC_PlanarTrack(rt, part_oid=PART_2)
    pos1, pos2 = PositionXYC(), PositionXYC()
    state = 0

    def main() -> None:
        nonlocal state
        match state:
            case 0:
                pos1.set_values_xyc_reference_id(40, 120, 0, CS_1)
                pos2.set_values_xyc_reference_id(240, 120, 0, CS_1)
                track_one.append_line(pos1, pos2)
                track_two.start_from_track(track_one)
                pos1.set_values_xyc_reference_id(260, 120, 0, CS_1)
                pos2.set_values_xyc_reference_id(440, 120, 0, CS_1)
                track_two.append_line(pos1, pos2)
                track_one.enable()
                track_two.enable()
                state = 1
            case 1:
                if track_one.mc_to_plc_std.state is ENABLED and \
                        track_two.mc_to_plc_std.state is ENABLED:
                    state = 2
            case 2:
                mover.enable()
                state = 3
            case 3:
                if mover.mc_to_plc.std.state is ENABLED:
                    state = 4
            case 4:
                mover.join_track(track_one, None, None)
                state = 5
            case 5:
                if mover.mc_to_plc.std.command_mode is MoverCommandMode.ON_TRACK:
                    state = 6
            case 6:
                mover.move_on_track(track_two, 150.0, None, None)
                state = 7

    run(rt, main, lambda: state == 7 and standing(mover)
        and mover.mc_to_plc.set_on_track.track_oid == track_two.oid)
    assert_at(mover, 390.0, 120.0, 0.0, 0.0, 0.0, 0.0)
    assert track_one.get_length() == pytest.approx(200.0, abs=EXACT)
    assert track_two.get_length() == pytest.approx(200.0, abs=EXACT)
    assert mover.mc_to_plc.set_on_track.set_pos == pytest.approx(150.0, abs=EXACT)
    assert mover.mc_to_plc.set.physical_area_id == 16842848 == CS_1
    assert (mover.error, mover.error_id) == (False, 0)
    assert mover.get_position_on_current_part() == pytest.approx(
        PositionXYC(150.0, 120.0, 0.0, PART_2))
