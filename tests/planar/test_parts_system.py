"""Parts with movers, the environment and a group in the running system (TF5430 §6.4, §6.6,
MC_PlanarPart §7.2.2.9).

test_parts.py checks ``Part`` and ``PartLayout`` on their own; here the runtime drives them:
which mover states keep the parts on, how a mover's Reset waits for its part, when
ActivatePosition may move a part, the group's boundary following the parts, and
MC_PlanarPart.Initialize. Layouts are the manual's: the two parts of §6.1.4 / §6.1.7 and the
elevator of §6.6.1.
"""

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
    MC_PlanarPart,
    MoverVector,
    Part,
    PartLayout,
    PartPosition,
    PlanarMoverParameters,
    PlanarObjectInfo,
    PlanarObjectType,
    PlanarState,
    Pose,
    PositionXYC,
    ST_ExternalSetpointGenerationOptions,
)

S = PlanarState
CS_1, CS_2 = 0x01010060, 0x010100A0  #: §6.1.4 / §6.6.1
PART_1, PART_2, PART_3 = 0x01010020, 0x01010030, 0x01010080  #: §6.1.4, §6.6.1
SLOW = DynamicConstraint_PathXY(50.0, 500.0, 500.0, 5000.0)  #: [mm/s, mm/s², mm/s², mm/s³]


def two_parts() -> PartLayout:
    """§6.1.4: two static one-stator parts side by side in one coordinate system."""
    return PartLayout([CS_1], [Part(PART_1, [(0.0, 0.0)], [PartPosition(CS_1, Pose())]),
                               Part(PART_2, [(0.0, 0.0)], [PartPosition(CS_1, Pose(240.0))])])


def elevator(index: int) -> PartLayout:
    """§6.6.1: parts 1 and 2 at the origins of CS 1 and CS 2, part 3 above either (index 1 in
    CS 1, index 2 in CS 2; above is inferred from SetPos.y > 300 on it)."""
    lift = Part(PART_3, [(0.0, 0.0)], [PartPosition(CS_1, Pose(0.0, 240.0)),
                                      PartPosition(CS_2, Pose(0.0, 240.0))], position_index=index)
    return PartLayout([CS_1, CS_2], [Part(PART_1, [(0.0, 0.0)], [PartPosition(CS_1, Pose())]),
                                     Part(PART_2, [(0.0, 0.0)], [PartPosition(CS_2, Pose())]),
                                     lift])


def on(rt: om.Runtime, layout: PartLayout, x: float, y: float, part: int
       ) -> tuple[MC_PlanarEnvironment, MC_PlanarMover]:
    """The environment and an enabled mover at (x, y) on ``part``."""
    environment = MC_PlanarEnvironment(rt, layout=layout)
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x, y),
                                                     part_oid=part))
    mover.enable()
    rt.run(0.01)
    assert mover.state is S.ENABLED
    return environment, mover


def states(layout: PartLayout) -> list[PlanarState]:
    return [part.state for part in layout.parts.values()]


def quick_stop(rt: om.Runtime, mover: MC_PlanarMover, layout: PartLayout
               ) -> list[list[PlanarState]]:
    """A QuickStop error: external setpoints started and none fed (§6.1.6). Returns the part
    states of the cycles until the mover shows Error."""
    mover.start_external_setpoint_generation()
    seen = []
    while mover.state is not S.ERROR:
        rt.step()
        seen.append(states(layout))
    assert mover.error_id == ErrorId.PLANAR_EXT_SETPOINT
    return seen


def run_until(rt: om.Runtime, done, timeout: float = 10.0) -> None:
    for _ in range(round(timeout / rt.cycle_time)):
        if done():
            return
        rt.step()
    raise AssertionError(f"not reached within {timeout} s")


# --- which movers keep the parts on (§6.6) ---------------------------------------------------

def test_a_quick_stop_error_keeps_the_parts_on_through_the_reset():
    rt = om.Runtime()
    layout = two_parts()
    _, mover = on(rt, layout, 120.0, 120.0, PART_1)
    assert all(seen == [S.ENABLED, S.ENABLED] for seen in quick_stop(rt, mover, layout))
    rt.run(0.05)
    assert states(layout) == [S.ENABLED, S.ENABLED]
    feedback = MC_PlanarFeedback()
    mover.reset(feedback)
    run_until(rt, lambda: not feedback.busy)
    assert (feedback.done, mover.state, mover.error, mover.error_id) == (True, S.ENABLED,
                                                                         False, 0)
    assert states(layout) == [S.ENABLED, S.ENABLED]
    move = mover.move_to_position(PositionXYC(100.0, 100.0, 0.0, PART_2))  # §6.1.4's target
    run_until(rt, lambda: not move.busy)
    assert move.done and mover.pose == (340.0, 100.0, 0.0)


@pytest.mark.parametrize("when", ["error", "reset"])
def test_a_disable_during_the_error_switches_the_parts_off(when):
    """§6.6: a Disable in the error (or while the Reset runs) makes the reaction Abort: the
    parts go off, and the Reset ends Disabled, needing only an error-free part."""
    rt = om.Runtime()
    layout = two_parts()
    _, mover = on(rt, layout, 120.0, 120.0, PART_1)
    quick_stop(rt, mover, layout)
    reset = MC_PlanarFeedback()
    if when == "reset":
        mover.reset(reset)
    mover.disable()
    rt.run(0.01)
    assert states(layout) == [S.DISABLED, S.DISABLED]
    if when == "error":
        assert mover.state is S.ERROR
        mover.reset(reset)
    run_until(rt, lambda: not reset.busy)
    assert (reset.done, mover.state, mover.error) == (True, S.DISABLED, False)
    assert states(layout) == [S.DISABLED, S.DISABLED]


def test_a_force_disabled_part_takes_the_mover_into_an_abort_error():
    """§6.6: ForceDisable sets the movers on the part into error (Abort: the parts go off);
    after AllowEnable the mover's Reset ends Disabled, and Enable brings all back."""
    rt = om.Runtime()
    layout = two_parts()
    environment, mover = on(rt, layout, 120.0, 120.0, PART_1)
    part = MC_PlanarPart()
    part.initialize(PART_1, environment)
    part.force_disable()
    rt.run(0.02)
    assert (mover.state, mover.error_id) == (S.ERROR, ErrorId.PLANAR_PART_NOT_ENABLED)
    assert states(layout) == [S.DISABLED, S.DISABLED]
    reset = MC_PlanarFeedback()
    mover.reset(reset)
    run_until(rt, lambda: not reset.busy)  # still force-disabled: an Abort reset ends Disabled
    assert (reset.done, mover.state) == (True, S.DISABLED)
    enable = MC_PlanarFeedback()
    mover.enable(enable)
    rt.run(0.02)
    assert (enable.error, enable.error_id, mover.state) == (True, ErrorId.PLANAR_PART_NOT_ENABLED,
                                                            S.ERROR)
    part.allow_enable()
    mover.reset()
    rt.run(0.02)
    mover.enable(enable)
    run_until(rt, lambda: not enable.busy)
    assert (enable.done, mover.state, states(layout)) == (True, S.ENABLED, [S.ENABLED] * 2)


def test_the_parts_go_off_only_after_the_disabling_mover_is_off():
    """§6.6: the last mover's Disable switches the parts off once the mover is off; while it
    brakes they stay on."""
    rt = om.Runtime()
    layout = two_parts()
    _, mover = on(rt, layout, 120.0, 120.0, PART_1)
    mover.move_to_position(PositionXYC(360.0, 120.0, 0.0, CS_1),
                           DynamicConstraint_PathXY(100.0, 100.0, 100.0, 1000.0))
    rt.run(0.5)
    mover.disable()
    cycles = []
    for _ in range(2000):
        rt.step()
        cycles.append((mover.state, mover.mc_to_plc.set.set_velo.x, states(layout)))
        if cycles[-1][2] == [S.DISABLED, S.DISABLED]:
            break
    braking = [cycle for cycle in cycles if cycle[0] is S.DISABLING]
    assert len(braking) > 10 and braking[0][1] > 0.0  # it was moving
    assert all(parts == [S.ENABLED, S.ENABLED] for _, _, parts in braking)
    assert [(state, parts) for state, _, parts in cycles[len(braking):]] == [
        (S.DISABLED, [S.ENABLED, S.ENABLED]), (S.DISABLED, [S.DISABLED, S.DISABLED])]


# --- ActivatePosition and the movers (§6.6, §6.6.1) --------------------------------------

def test_a_part_does_not_move_under_a_moving_mover():
    """A mover leaving the elevator: ActivatePosition is refused, the move goes on to its
    target in CS 1; once the mover stands on part 1 the elevator may go."""
    rt = om.Runtime()
    layout = elevator(1)
    environment, mover = on(rt, layout, 120.0, 120.0, PART_3)
    part = MC_PlanarPart()
    part.initialize(PART_3, environment)
    move = MC_PlanarFeedback()
    mover.move_to_position(PositionXYC(120.0, 120.0, 0.0, PART_1), SLOW, None, move)
    rt.run(0.5)
    activate = MC_PlanarFeedback()
    part.activate_position(2, activate)
    rt.step()
    assert (activate.error, activate.error_id) == (True, ErrorId.PLANAR_WRONG_STATE)
    assert "mover1" in activate.message and "standstill" in activate.message
    assert (part.position_index, mover.coordinate_system) == (1, CS_1)
    assert mover.mc_to_plc.set.set_velo.y == pytest.approx(-50.0)
    run_until(rt, lambda: not move.busy)
    assert move.done and mover.pose == (120.0, 120.0, 0.0)
    assert mover.get_position_on_current_part() == PositionXYC(120.0, 120.0, 0.0, PART_1)
    part.activate_position(2, activate)
    rt.step()
    assert activate.done and part.position_index == 2 and mover.coordinate_system == CS_1


def test_a_part_does_not_move_away_under_a_mover_driving_onto_it():
    rt = om.Runtime()
    environment, mover = on(rt, elevator(1), 120.0, 120.0, PART_1)
    part = MC_PlanarPart()
    part.initialize(PART_3, environment)
    mover.move_to_position(PositionXYC(120.0, 120.0, 0.0, PART_3), SLOW)
    rt.step()  # the footprint is still on part 1 only; its motion ends on part 3
    activate = part.activate_position(2)
    rt.step()
    assert activate.error_id == ErrorId.PLANAR_WRONG_STATE
    run_until(rt, lambda: mover.state is S.ENABLED and not mover.mc_to_plc.std.busy.busy_mover)
    assert mover.pose == (120.0, 360.0, 0.0)


def test_a_part_does_not_move_under_a_mover_that_external_setpoints_drive():
    rt = om.Runtime()
    environment, mover = on(rt, elevator(1), 120.0, 120.0, PART_3)
    part = MC_PlanarPart()
    part.initialize(PART_3, environment)
    mover.start_external_setpoint_generation(ST_ExternalSetpointGenerationOptions(
        ExternalSetPositionMode.RELATIVE))
    zero = MoverVector()
    for _ in range(3):
        mover.set_external_setpoint(zero, zero, zero)
        rt.step()
    activate = part.activate_position(2)
    mover.set_external_setpoint(zero, zero, zero)
    rt.step()
    assert (activate.error_id, mover.state) == (ErrorId.PLANAR_WRONG_STATE, S.ENABLED)
    mover.stop_external_setpoint_generation()
    rt.step()
    activate = part.activate_position(2)
    rt.step()
    assert activate.done and mover.coordinate_system == CS_2


def test_a_part_does_not_hit_a_standing_mover_reaching_over_its_edge():
    """A mover whose centre is on part 1 but whose footprint (155 mm, §6.1.1) reaches onto
    part 3 is not carried; the part would tear it: PLANAR_COLLISION naming the mover."""
    rt = om.Runtime()
    environment, mover = on(rt, elevator(1), 120.0, 200.0, PART_1)
    part = MC_PlanarPart()
    part.initialize(PART_3, environment)
    activate = MC_PlanarFeedback()
    part.activate_position(2, activate)
    rt.step()
    assert (activate.error_id, activate.object_info) == (
        ErrorId.PLANAR_COLLISION, PlanarObjectInfo(PlanarObjectType.MOVER, mover.oid))
    assert part.position_index == 1
    mover.move_to_position(PositionXYC(120.0, 162.5, 0.0, CS_1))  # edges touch: no overlap
    rt.run(1.0)
    part.activate_position(2, activate)
    rt.step()
    assert activate.done and part.position_index == 2


def test_a_standing_mover_rides_along_and_keeps_its_area_in_the_group():
    """A part moving within one coordinate system carries the mover on it, and the mover's
    reserved footprint goes with it."""
    rt = om.Runtime()
    shuttle = Part(PART_3, [(0.0, 0.0)], [PartPosition(CS_1, Pose(240.0, 0.0)),
                                         PartPosition(CS_1, Pose(240.0, 240.0))])
    layout = PartLayout([CS_1], [Part(PART_1, [(0.0, 0.0), (0.0, 240.0)],
                                      [PartPosition(CS_1, Pose())]), shuttle])
    environment, mover, group, part = grouped(rt, layout, PART_3)  # (360, 120) in CS 1
    activate = part.activate_position(2)
    rt.step()
    assert activate.done and mover.pose == (360.0, 360.0, 0.0)
    assert group.reserved(mover.member).equals(mover.footprint())
    assert environment.surface.bounds == (0.0, 0.0, 480.0, 480.0)
    assert environment.surface.area == 3 * 240.0 * 240.0


# --- the group's boundary follows the parts (§6.4, §6.6.1) --------------------------------

def grouped_elevator(index: int) -> tuple[om.Runtime, MC_PlanarEnvironment, MC_PlanarMover,
                                          MC_PlanarPart]:
    """§6.6.1 with the environment and the mover in a group, the boundary created while part 3
    is at ``index``."""
    rt = om.Runtime()
    environment, mover, group, part = grouped(rt, elevator(index), PART_1)
    assert part.is_initialized and len(group.members) == 2
    return rt, environment, mover, part


def grouped(rt: om.Runtime, layout: PartLayout, start_part: int
            ) -> tuple[MC_PlanarEnvironment, MC_PlanarMover, MC_PlanarGroup, MC_PlanarPart]:
    """A mover at (120, 120) on ``start_part`` and the environment (its boundary made) in an
    enabled group, and part 3's handle initialized."""
    environment, mover = on(rt, layout, 120.0, 120.0, start_part)
    group = MC_PlanarGroup(rt)
    environment.create_boundary()
    group.enable()
    rt.run(0.01)
    mover.add_to_group(group)
    environment.add_to_group(group)
    part = MC_PlanarPart()
    part.initialize(PART_3, environment)
    rt.run(0.01)
    return environment, mover, group, part


def test_the_mover_drives_onto_the_elevator_that_arrived_after_create_boundary():
    rt, environment, mover, part = grouped_elevator(2)
    assert environment.surface.bounds == (0.0, 0.0, 240.0, 240.0)
    part.activate_position(1)
    rt.step()
    assert environment.surface.bounds == (0.0, 0.0, 240.0, 480.0)
    assert environment.mc_to_plc_std.boundary_element_count == 6
    move = mover.move_to_position(PositionXYC(120.0, 120.0, 0.0, PART_3))
    run_until(rt, lambda: not move.busy)
    assert move.done and mover.mc_to_plc.set.set_pos.y == 360.0  # §6.6.1: SetPos.y > 300


def test_the_area_the_elevator_left_is_off_the_boundary():
    rt, environment, mover, part = grouped_elevator(1)
    part.activate_position(2)
    rt.step()
    assert environment.surface.bounds == (0.0, 0.0, 240.0, 240.0)
    assert environment.mc_to_plc_std.boundary_element_count == 4
    move = MC_PlanarFeedback()
    mover.move_to_position(PositionXYC(120.0, 230.0, 0.0, CS_1), None, None, move)
    rt.step()  # the footprint would reach 67.5 mm into the hole
    assert (move.error_id, move.object_info) == (
        ErrorId.PLANAR_COLLISION, PlanarObjectInfo(PlanarObjectType.ENVIRONMENT,
                                                   environment.oid))
    mover.move_to_position(PositionXYC(120.0, 162.5, 0.0, CS_1), None, None, move)
    run_until(rt, lambda: not move.busy)
    assert move.done


def test_activate_position_without_create_boundary_makes_no_boundary():
    rt = om.Runtime()
    environment, _ = on(rt, elevator(2), 120.0, 120.0, PART_1)
    part = MC_PlanarPart()
    part.initialize(PART_3, environment)
    part.activate_position(1)
    rt.run(0.01)
    assert part.position_index == 1
    assert environment.boundary is None and environment.mc_to_plc_std.boundary_element_count == 0


# --- MC_PlanarPart.Initialize (§7.2.2.9.1) ---------------------------------------------------

def test_initialize_reports_on_its_feedback_in_the_next_cycle():
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt, layout=elevator(2))
    part, feedback = MC_PlanarPart(), MC_PlanarFeedback()
    command = part.initialize(PART_3, environment, feedback)
    assert (part.is_initialized, feedback.busy, part.position_index, part.state) == (
        False, True, 0, S.DISABLED)
    rt.step()
    assert (command.done, feedback.done, part.is_initialized) == (True, True, True)
    assert (part.part_oid, part.position_index, part.get_position()) == (
        PART_3, 2, PositionXYC(0.0, 240.0, 0.0, CS_2))


@pytest.mark.parametrize("oid", [0x01010090, 0, CS_1, -1, "part 3", 1.5])
def test_initialize_with_an_oid_that_names_no_part_fails_on_the_feedback(oid):
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt, layout=elevator(2))
    part, feedback = MC_PlanarPart(), MC_PlanarFeedback()
    part.initialize(oid, environment, feedback)
    rt.step()
    assert (feedback.error, feedback.error_id, part.is_initialized) == (
        True, ErrorId.INVALID_REFERENCE_ID, False)
    assert "no part of the processing unit" in feedback.message
    assert (part.position_index, part.state, part.get_position()) == (0, S.DISABLED,
                                                                      PositionXYC())
    part.activate_position(1, feedback)  # the OID still names no part
    rt.step()
    assert feedback.error_id == ErrorId.INVALID_REFERENCE_ID


def test_initialize_without_parts_and_commands_before_initialize():
    rt = om.Runtime()
    feedback = MC_PlanarFeedback()
    part = MC_PlanarPart()
    part.activate_position(1, feedback)  # nothing to send it to: refused at once
    assert (feedback.error, feedback.error_id) == (True, ErrorId.INVALID_REFERENCE_ID)
    assert "not initialized" in feedback.message
    part.initialize(PART_3, MC_PlanarEnvironment(rt), feedback)  # no processing unit
    rt.step()
    assert (feedback.error_id, part.is_initialized) == (ErrorId.INVALID_REFERENCE_ID, False)
    assert "has no parts" in feedback.message


def test_initialize_misused_in_python_is_a_python_error():
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt, layout=elevator(2))
    with pytest.raises(TypeError):
        MC_PlanarPart().initialize(part_id=PART_3, environment=environment)
    with pytest.raises(TypeError, match="MC_PlanarEnvironment"):
        MC_PlanarPart().initialize(PART_3, None)
