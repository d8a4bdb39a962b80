"""The CA blocks (TF5410 §9.1.1.1, §9.3.1; digest D2, D3.1, D3.3, D5 T12, T13, T16).

Timing convention as in tests/plcopen/test_handshake.py: every block is called once per cycle,
before ``rt.step()``; a rising edge acts at once, so its outputs show in the same call.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import pytest

import openmotion as om
from openmotion.plcopen import MC_Power
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GroupState,
    MC_AddAxisToGroup,
    MC_GroupDisable,
    MC_GroupEnable,
    MC_GroupHalt,
    MC_GroupReadError,
    MC_GroupReadStatus,
    MC_GroupReset,
    MC_GroupStop,
    MC_HaltCA,
    MC_MoveAbsoluteCA,
    MC_MoveRelativeCA,
    MC_RemoveAxisFromGroup,
    MC_UngroupAllAxes,
    ST_HaltCAOptions,
    ST_MoveAbsoluteCAOptions,
    ST_MoveRelativeCAOptions,
)

ErrorId = om.ErrorId
U = UDINT_TO_IDENTINGROUP
MAX_VELOCITY = 1000.0
AXIS = {"max_velocity": MAX_VELOCITY, "max_deceleration": 20000.0, "max_jerk": 1.0e6}


def ring(*positions: float, enable: bool = True, **parameters: Any
         ) -> tuple[om.Runtime, CaGroup, list[om.Axis]]:
    """Powered axes at ``positions`` in a CA group on a 3000 mm ring, enabled."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", **{"rail_length": 3000.0, **parameters})
    axes = []
    for ident, position in enumerate(positions, 1):
        axis = rt.add_axis(f"m{ident}", position=position, **AXIS)
        assert axis.power()
        add = MC_AddAxisToGroup(group)
        add(execute=True, axis=axis, ident_in_group=U(ident))
        assert add.done, add.message
        axes.append(axis)
    if enable:
        MC_GroupEnable(group)(execute=True)
        assert group.state is GroupState.STANDBY
    return rt, group, axes


def drive(rt: om.Runtime, *blocks: Any, until: Callable[[], bool], limit: int = 20000) -> int:
    """Call ``blocks`` and step until ``until()`` holds after the calls; the cycles taken."""
    for cycle in range(limit):
        for block in blocks:
            block()
        if until():
            return cycle
        rt.step()
    raise AssertionError(f"not reached within {limit} cycles")


def outputs(fb: Any) -> tuple[bool, bool, bool, bool]:
    return fb.busy, fb.done, fb.command_aborted, fb.error


def moving(rt: om.Runtime, axis: om.Axis, position: float = 2500.0) -> MC_MoveAbsoluteCA:
    """A long CA move of ``axis``, cruising."""
    move = MC_MoveAbsoluteCA(axis)
    move(execute=True, position=position, velocity=500.0)
    drive(rt, move, until=lambda: axis.set_velocity == pytest.approx(500.0))
    return move


# -- the handshake of each block ----------------------------------------------------------------


@dataclass
class Case:
    name: str
    make: Callable[[CaGroup, list[om.Axis]], Any]
    inputs: dict[str, Any]
    prepare: Callable[[om.Runtime, list[om.Axis]], Any] = lambda rt, axes: None

    def __str__(self) -> str:
        return self.name


MOTION_DONE = [
    Case("MC_MoveAbsoluteCA", lambda g, a: MC_MoveAbsoluteCA(a[0]),
         {"position": 1500.0, "velocity": 500.0}),
    Case("MC_MoveRelativeCA", lambda g, a: MC_MoveRelativeCA(a[0]),
         {"distance": 300.0, "velocity": 500.0}),
    Case("MC_HaltCA", lambda g, a: MC_HaltCA(a[0]), {},
         prepare=lambda rt, a: moving(rt, a[0])),
    Case("MC_GroupHalt", lambda g, a: MC_GroupHalt(g), {},
         prepare=lambda rt, a: moving(rt, a[0])),
]


@pytest.mark.parametrize("case", MOTION_DONE, ids=str)
def test_motion_block_is_busy_then_done_while_execute(case: Case):
    rt, group, axes = ring(1000.0, 0.0)
    keep = case.prepare(rt, axes)
    fb = case.make(group, axes)
    fb(execute=True, **case.inputs)
    assert (fb.busy, fb.active, fb.done, fb.error_id) == (True, True, False, ErrorId.NO_ERROR)
    calls = [fb, keep] if keep is not None else [fb]
    drive(rt, *calls, until=lambda: not fb.busy)
    assert outputs(fb) == (False, True, False, False) and not fb.active
    for _ in range(3):  # Done stays while execute stays TRUE
        fb()
        rt.step()
        assert outputs(fb) == (False, True, False, False)
        assert fb.error_id is ErrorId.NO_ERROR
    fb(execute=False)
    assert outputs(fb) == (False, False, False, False)


@pytest.mark.parametrize("case", MOTION_DONE, ids=str)
def test_motion_block_done_shows_one_call_after_execute_fell(case: Case):
    rt, group, axes = ring(1000.0, 0.0)
    case.prepare(rt, axes)
    fb = case.make(group, axes)
    fb(execute=True, **case.inputs)
    rt.step()
    fb(execute=False)
    assert fb.busy
    drive(rt, fb, until=lambda: fb.done)
    rt.step()
    fb()
    assert outputs(fb) == (False, False, False, False)


ADMIN_DONE = [
    Case("MC_AddAxisToGroup", lambda g, a: MC_AddAxisToGroup(g),
         {"ident_in_group": U(9)}),  # the axis is added by the test
    Case("MC_RemoveAxisFromGroup", lambda g, a: MC_RemoveAxisFromGroup(g),
         {"ident_in_group": U(2)}),
    Case("MC_UngroupAllAxes", lambda g, a: MC_UngroupAllAxes(g), {}),
    Case("MC_GroupEnable", lambda g, a: MC_GroupEnable(g), {}),
    Case("MC_GroupDisable", lambda g, a: MC_GroupDisable(g), {}),
    Case("MC_GroupReset", lambda g, a: MC_GroupReset(g), {}),
]


@pytest.mark.parametrize("case", ADMIN_DONE, ids=str)
def test_admin_block_is_done_in_the_call_and_clears_on_the_falling_edge(case: Case):
    rt, group, axes = ring(1000.0, 0.0)
    inputs = dict(case.inputs)
    if case.name == "MC_AddAxisToGroup":
        inputs["axis"] = rt.add_axis("extra", position=2000.0, **AXIS)
    fb = case.make(group, axes)
    fb(execute=True, **inputs)
    assert outputs(fb) == (False, True, False, False), fb.message
    assert fb.error_id is ErrorId.NO_ERROR
    rt.step()
    fb()
    assert fb.done
    fb(execute=False)
    assert outputs(fb) == (False, False, False, False)


ERRORS = [
    Case("MC_MoveAbsoluteCA", lambda g, a: MC_MoveAbsoluteCA(a[0]),
         {"position": 1500.0, "velocity": 0.0}),
    Case("MC_MoveRelativeCA", lambda g, a: MC_MoveRelativeCA(a[0]), {"velocity": 500.0}),
    Case("MC_HaltCA", lambda g, a: MC_HaltCA(a[0]), {"jerk": 99.0}),
    Case("MC_AddAxisToGroup", lambda g, a: MC_AddAxisToGroup(g),
         {"axis": None, "ident_in_group": 3}),  # a plain integer is no IdentInGroup
    Case("MC_RemoveAxisFromGroup", lambda g, a: MC_RemoveAxisFromGroup(g),
         {"ident_in_group": U(1)}, prepare=lambda rt, a: moving(rt, a[0])),
    Case("MC_GroupEnable", lambda g, a: MC_GroupEnable(g), {}),
    Case("MC_GroupHalt", lambda g, a: MC_GroupHalt(g), {"deceleration": 0.5}),
    Case("MC_GroupStop", lambda g, a: MC_GroupStop(g), {"jerk": 99.0}),
]
ERROR_IDS = {
    "MC_MoveAbsoluteCA": ErrorId.INVALID_VELOCITY, "MC_MoveRelativeCA": ErrorId.INVALID_POSITION,
    "MC_HaltCA": ErrorId.INVALID_JERK, "MC_AddAxisToGroup": ErrorId.INVALID_IDENT,
    "MC_RemoveAxisFromGroup": ErrorId.AXIS_MOVING, "MC_GroupEnable": ErrorId.GROUP_EMPTY,
    "MC_GroupHalt": ErrorId.INVALID_DECELERATION, "MC_GroupStop": ErrorId.INVALID_JERK,
}


@pytest.mark.parametrize("case", ERRORS, ids=str)
def test_block_error_shows_while_execute_with_its_id(case: Case):
    rt, group, axes = ring(1000.0, 0.0)
    case.prepare(rt, axes)
    if case.name == "MC_GroupEnable":
        group = CaGroup(rt, "empty")
    inputs = dict(case.inputs)
    if case.name == "MC_AddAxisToGroup":
        inputs["axis"] = rt.add_axis("extra", position=2000.0, **AXIS)
    fb = case.make(group, axes)
    fb(execute=True, **inputs)
    assert outputs(fb) == (False, False, False, True)
    assert fb.error_id is ERROR_IDS[case.name], fb.message
    rt.step()
    fb()
    assert fb.error and fb.error_id is ERROR_IDS[case.name]
    fb(execute=False)
    assert outputs(fb) == (False, False, False, False)
    assert fb.error_id is ErrorId.NO_ERROR


ABORTS = [
    ("MC_MoveAbsoluteCA", lambda g, a: MC_MoveAbsoluteCA(a[0]),
     {"position": 2500.0, "velocity": 500.0}),
    ("MC_MoveRelativeCA", lambda g, a: MC_MoveRelativeCA(a[0]),
     {"distance": 1500.0, "velocity": 500.0}),
    ("MC_HaltCA", lambda g, a: MC_HaltCA(a[0]), {"deceleration": 1.0, "jerk": 100.0}),
    ("MC_GroupHalt", lambda g, a: MC_GroupHalt(g), {"deceleration": 1.0, "jerk": 100.0}),
]


@pytest.mark.parametrize(("name", "make", "inputs"), ABORTS, ids=[a[0] for a in ABORTS])
def test_motion_block_is_aborted_by_a_new_move(name: str, make: Any, inputs: dict):
    rt, group, axes = ring(1000.0, 0.0)
    moving(rt, axes[0], 2900.0)
    fb = make(group, axes)
    fb(execute=True, **inputs)
    for _ in range(20):
        fb()
        rt.step()
    assert fb.busy and fb.active
    other = MC_MoveAbsoluteCA(axes[0])
    other(execute=True, position=2000.0, velocity=200.0)
    rt.step()
    fb()
    assert outputs(fb) == (False, False, True, False) and not fb.active
    assert fb.error_id is ErrorId.NO_ERROR
    fb()
    assert fb.command_aborted  # stays while execute
    fb(execute=False)
    assert outputs(fb) == (False, False, False, False)


def test_read_blocks_are_valid_and_busy_while_enabled():
    rt, group, _ = ring(1000.0, 0.0)
    for fb in (MC_GroupReadStatus(group), MC_GroupReadError(group)):
        fb(enable=True)
        assert (fb.valid, fb.busy, fb.error, fb.error_id) == (True, True, False, 0)
        rt.step()
        fb()
        assert fb.valid and fb.busy
        fb(enable=False)
        assert (fb.valid, fb.busy, fb.error) == (False, False, False)


# -- Python errors: misspelt inputs, missing references -----------------------------------------


@pytest.mark.parametrize(("make", "inputs", "hint"), [
    (lambda g, a: MC_MoveAbsoluteCA(a[0]), {"positon": 1.0}, "'position'"),
    (lambda g, a: MC_MoveRelativeCA(a[0]), {"distanse": 1.0}, "'distance'"),
    (lambda g, a: MC_HaltCA(a[0]), {"gapp": 1.0}, "'gap'"),
    (lambda g, a: MC_AddAxisToGroup(g), {"ident_in_grup": 1}, "'ident_in_group'"),
    (lambda g, a: MC_RemoveAxisFromGroup(g), {"ident_in_grop": 1}, "'ident_in_group'"),
    (lambda g, a: MC_UngroupAllAxes(g), {"exeute": True}, "'execute'"),
    (lambda g, a: MC_GroupEnable(g), {"exec": True}, "'execute'"),
    (lambda g, a: MC_GroupDisable(g), {"execut": True}, "'execute'"),
    (lambda g, a: MC_GroupReset(g), {"execude": True}, "'execute'"),
    (lambda g, a: MC_GroupHalt(g), {"decceleration": 1.0}, "'deceleration'"),
    (lambda g, a: MC_GroupStop(g), {"jerck": 1.0}, "'jerk'"),
    (lambda g, a: MC_GroupReadStatus(g), {"enabel": True}, "'enable'"),
    (lambda g, a: MC_GroupReadError(g), {"enabled": True}, "'enable'"),
], ids=lambda value: next(iter(value)) if isinstance(value, dict) else "")
def test_a_misspelt_input_is_a_type_error_with_a_suggestion(make, inputs, hint):
    _, group, axes = ring(1000.0)
    fb = make(group, axes)
    with pytest.raises(TypeError, match=rf"has no input '{next(iter(inputs))}' \(did you mean "
                                        rf"{hint}\?\)"):
        fb(**inputs)


def test_group_blocks_take_the_group_first_and_no_axis():
    _, group, axes = ring(1000.0)
    with pytest.raises(TypeError, match="needs an axes group"):
        MC_GroupEnable()(execute=True)
    with pytest.raises(TypeError, match="has no input 'axis'"):
        MC_GroupEnable(group)(execute=True, axis=axes[0])
    enable = MC_GroupEnable()
    enable(group, execute=True)
    assert enable.done and enable.axes_group is group


def test_options_of_another_block_are_a_type_error():
    _, _, axes = ring(1000.0)
    with pytest.raises(TypeError, match="ST_MoveAbsoluteCAOptions"):
        MC_MoveAbsoluteCA(axes[0])(execute=True, position=1.0, velocity=1.0,
                                   options=ST_HaltCAOptions())


def test_options_default_as_the_manual():
    assert ST_MoveAbsoluteCAOptions() == ST_MoveAbsoluteCAOptions(
        om.transport.GapControlMode.GROUP_DEFAULT, 0, 0, 0)
    assert ST_MoveRelativeCAOptions().position_reference_system == 0
    assert ST_HaltCAOptions().dynamics_reference_system == 0


TEMPLATE = 0x01010010  #: the OTCID of a mover template


@pytest.mark.parametrize(("make", "inputs", "error_id"), [
    (MC_MoveAbsoluteCA, {"position": 1.0, "velocity": 1.0,
                         "options": ST_MoveAbsoluteCAOptions(position_reference_system=TEMPLATE)},
     ErrorId.UNKNOWN_TEMPLATE),
    (MC_MoveAbsoluteCA, {"position": 1.0, "velocity": 1.0,
                         "options": ST_MoveAbsoluteCAOptions(dynamics_reference_system=TEMPLATE)},
     ErrorId.UNKNOWN_TEMPLATE),
    (MC_MoveRelativeCA, {"distance": 1.0, "velocity": 1.0,
                         "options": ST_MoveRelativeCAOptions(position_reference_system=TEMPLATE)},
     ErrorId.UNKNOWN_TEMPLATE),
    (MC_HaltCA, {"options": ST_HaltCAOptions(dynamics_reference_system=TEMPLATE)},
     ErrorId.UNKNOWN_TEMPLATE),
], ids=["absolute-position", "absolute-dynamics", "relative-position", "halt-dynamics"])
def test_a_reference_system_other_than_the_motor_path_is_an_error(make, inputs, error_id):
    """Without a mover template on the rail (tests/transport/test_geo.py) no reference
    system but 0 names anything."""
    _, _, axes = ring(1000.0)
    fb = make(axes[0])
    fb(execute=True, **inputs)
    assert fb.error and fb.error_id is error_id


@pytest.mark.parametrize("make", [MC_MoveAbsoluteCA, MC_MoveRelativeCA, MC_HaltCA])
def test_motion_block_on_an_axis_in_no_group_is_an_error(make):
    rt = om.Runtime()
    axis = rt.add_axis("alone", **AXIS)
    axis.power()
    fb = make(axis)
    fb(execute=True, velocity=100.0) if make is not MC_HaltCA else fb(execute=True)
    assert fb.error and fb.error_id is ErrorId.AXIS_NOT_IN_GROUP


# -- T12 buffer modes ---------------------------------------------------------------------------


def test_buffered_move_starts_when_the_first_is_done():
    rt, _, (x,) = ring(0.0)
    first, second = MC_MoveAbsoluteCA(x), MC_MoveAbsoluteCA(x)
    first(execute=True, position=1000.0, velocity=500.0)
    rt.step()
    second(execute=True, position=1500.0, velocity=500.0, buffer_mode=om.BufferMode.BUFFERED)
    assert second.busy and not second.active
    drive(rt, first, second, until=lambda: first.done)
    assert second.active and x.set_position == pytest.approx(1000.0)
    drive(rt, first, second, until=lambda: second.done)
    assert x.set_position == pytest.approx(1500.0)


def test_aborting_move_takes_over_and_the_first_shows_command_aborted():
    rt, _, (x,) = ring(0.0)
    first, second = MC_MoveAbsoluteCA(x), MC_MoveAbsoluteCA(x)
    first(execute=True, position=1000.0, velocity=500.0)
    for _ in range(300):
        first()
        rt.step()
    second(execute=True, position=500.0, velocity=500.0)
    first()
    assert first.command_aborted and not first.busy
    assert second.active
    drive(rt, first, second, until=lambda: second.done)
    assert x.set_position == pytest.approx(500.0)


def test_blending_buffer_mode_is_an_error():
    _, _, (x,) = ring(0.0)
    move = MC_MoveAbsoluteCA(x)
    move(execute=True, position=1000.0, velocity=500.0, buffer_mode=om.BufferMode.BLENDING_LOW)
    assert move.error and move.error_id is ErrorId.INVALID_BUFFER_MODE


# -- T13 parameter validation -------------------------------------------------------------------


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"velocity": om.MC_DEFAULT}, ErrorId.INVALID_VELOCITY),
    ({"velocity": 0.0}, ErrorId.INVALID_VELOCITY),
    ({"acceleration": 0.5}, ErrorId.INVALID_ACCELERATION),
    ({"jerk": 99.0}, ErrorId.INVALID_JERK),
    ({"jerk": om.MC_MAXIMUM}, ErrorId.INVALID_JERK),
    ({"position": om.MC_INVALID}, ErrorId.INVALID_POSITION),
], ids=["velocity-default", "velocity-0", "acceleration-0.5", "jerk-99", "jerk-maximum",
        "position-invalid"])
def test_invalid_input_fails_with_its_error_id(inputs, error_id):
    _, _, (x,) = ring(0.0)
    move = MC_MoveAbsoluteCA(x)
    move(execute=True, **{"position": 1000.0, "velocity": 500.0, **inputs})
    assert move.error and move.error_id is error_id


@pytest.mark.parametrize("velocity", [5000.0, om.MC_MAXIMUM], ids=["above-maximum", "maximum"])
def test_velocity_above_the_maximum_or_maximum_runs_at_max_velocity(velocity):
    rt, _, (x,) = ring(0.0)
    move = MC_MoveAbsoluteCA(x)
    move(execute=True, position=2000.0, velocity=velocity)
    assert move.busy and not move.error
    if velocity is not om.MC_MAXIMUM:
        assert any("clamped" in warning for warning in move.command.warnings)
    peak = 0.0

    def done() -> bool:
        nonlocal peak
        peak = max(peak, abs(x.set_velocity))
        return move.done

    drive(rt, move, until=done)
    assert peak == pytest.approx(MAX_VELOCITY)


# -- ContinuousUpdate ---------------------------------------------------------------------------


@pytest.mark.parametrize("continuous_update", [True, False])
def test_continuous_update_passes_the_gap_while_execute(continuous_update):
    rt, group, (x,) = ring(0.0)
    move = MC_MoveAbsoluteCA(x)
    move(execute=True, position=2000.0, velocity=500.0, gap=100.0,
         continuous_update=continuous_update)
    rt.step()
    move(gap=200.0)
    assert group.mover_of(x).gap == (200.0 if continuous_update else 100.0)


# -- T16 group administration -------------------------------------------------------------------


def test_add_and_remove_standing_axes_while_the_group_moves():
    rt, group, (leader, standing) = ring(1000.0, 0.0)
    move = moving(rt, leader)
    extra = rt.add_axis("extra", position=300.0, **AXIS)
    extra.power()
    add, remove = MC_AddAxisToGroup(group), MC_RemoveAxisFromGroup(group)
    add(execute=True, axis=extra, ident_in_group=U(3))
    remove(execute=True, ident_in_group=U(2))
    assert add.done and remove.done
    assert group.state is GroupState.MOVING and standing.group is None
    assert group.order == ["m1", "extra"]
    rt.step()
    assert leader.set_velocity == pytest.approx(500.0)  # the running move goes on
    drive(rt, move, until=lambda: move.done)
    assert leader.set_position == pytest.approx(2500.0)


def test_adding_or_removing_a_moving_axis_is_an_error():
    rt, group, (leader, _) = ring(1000.0, 0.0)
    moving(rt, leader)
    remove = MC_RemoveAxisFromGroup(group)
    remove(execute=True, ident_in_group=U(1))
    assert remove.error and remove.error_id is ErrorId.AXIS_MOVING
    outsider = rt.add_axis("outsider", position=2000.0, **AXIS)
    outsider.power()
    outsider.move_absolute(2500.0, 100.0)
    rt.step()
    add = MC_AddAxisToGroup(group)
    add(execute=True, axis=outsider, ident_in_group=U(3))
    assert add.error and add.error_id is ErrorId.AXIS_MOVING


def test_removing_a_non_member_is_done():
    _, group, _ = ring(1000.0, 0.0)
    remove = MC_RemoveAxisFromGroup(group)
    remove(execute=True, ident_in_group=U(42))
    assert remove.done and group.axes_count == 2


def test_reset_in_standby_is_done_and_changes_nothing():
    _, group, _ = ring(1000.0, 0.0)
    reset = MC_GroupReset(group)
    reset(execute=True)
    assert reset.done and group.state is GroupState.STANDBY


def test_enable_of_an_empty_group_is_an_error():
    rt = om.Runtime()
    enable = MC_GroupEnable(CaGroup(rt, "empty"))
    enable(execute=True)
    assert enable.error and enable.error_id is ErrorId.GROUP_EMPTY


def test_group_stop_holds_the_group_until_execute_falls():
    rt, group, (leader, follower) = ring(1000.0, 0.0)
    move = moving(rt, leader)
    stop = MC_GroupStop(group)
    stop(execute=True)
    assert move.command is not None
    rt.step()
    move()
    assert move.command_aborted and group.state is GroupState.STOPPING
    drive(rt, stop, until=lambda: stop.done)
    assert stop.busy and stop.active and group.all_axes_standing  # §9.3.1.2.2
    retry = MC_MoveAbsoluteCA(follower)
    for _ in range(5):
        stop()
        rt.step()
        assert group.state is GroupState.STOPPING and stop.done and stop.busy
    retry(execute=True, position=500.0, velocity=100.0)
    assert retry.error and retry.error_id is ErrorId.GROUP_STOPPING
    stop(execute=False)
    assert outputs(stop) == (False, False, False, False) and not stop.active
    rt.step()
    assert group.state is GroupState.STANDBY
    retry(execute=False)
    retry(execute=True)
    assert retry.busy


def test_power_off_of_a_member_during_a_stop_aborts_it():
    rt, group, (leader, follower) = ring(1000.0, 0.0)
    moving(rt, leader)
    stop = MC_GroupStop(group)
    stop(execute=True, deceleration=100.0)
    rt.step()
    stop()
    assert stop.busy and not stop.done
    MC_Power(follower)(enable=False)
    rt.step()
    stop()
    assert outputs(stop) == (False, False, True, False)
    assert group.state is GroupState.NOT_READY


def test_group_disable_while_moving_stops_every_mover_in_the_cycle():
    rt, group, axes = ring(1000.0, 500.0, 0.0)
    moves = [MC_MoveAbsoluteCA(axis) for axis in axes]
    for move, axis in zip(moves, axes, strict=True):
        move(execute=True, position=axis.set_position + 1000.0, velocity=500.0)
    drive(rt, *moves, until=lambda: all(abs(a.set_velocity) > 100.0 for a in axes))
    disable = MC_GroupDisable(group)
    disable(execute=True)
    assert disable.done and disable.command.warnings
    rt.step()
    assert [axis.set_velocity for axis in axes] == [0.0, 0.0, 0.0]
    assert group.state is GroupState.DISABLED
    for move in moves:
        move()
        assert move.command_aborted


# -- reading status and errors ------------------------------------------------------------------


def flags(status: MC_GroupReadStatus) -> set[str]:
    names = ("group_moving", "group_homing", "group_error_stop", "group_not_ready",
             "group_standby", "group_stopping", "group_disabled", "all_axes_standing")
    return {name for name in names if getattr(status, name)}


def test_group_read_status_through_a_move():
    rt, group, (x, _) = ring(1000.0, 0.0, enable=False)
    status = MC_GroupReadStatus(group)
    status(enable=True)
    assert flags(status) == {"group_disabled", "all_axes_standing"}
    MC_GroupEnable(group)(execute=True)
    status()
    assert flags(status) == {"group_standby", "all_axes_standing"}
    move = MC_MoveAbsoluteCA(x)
    move(execute=True, position=1500.0, velocity=500.0)
    rt.step()
    status()
    assert flags(status) == {"group_moving"}
    drive(rt, move, status, until=lambda: move.done)
    rt.step()
    status()
    assert flags(status) == {"group_standby", "all_axes_standing"}
    status(enable=False)
    assert flags(status) == set() and not status.valid


def test_group_read_error_after_a_member_fault_and_reset_recovery():
    rt, group, (leader, follower) = ring(1000.0, 0.0)
    move = moving(rt, leader)
    read = MC_GroupReadError(group)
    status = MC_GroupReadStatus(group)
    read(enable=True)
    assert read.group_error_id is ErrorId.NO_ERROR
    leader.fault(ErrorId.FOLLOWING_ERROR, "test")
    rt.step()
    read()
    status(enable=True)
    move()
    assert read.valid and not read.error and read.group_error_id is ErrorId.FOLLOWING_ERROR
    assert flags(status) == {"group_error_stop"}
    assert move.error and move.error_id is ErrorId.GROUP_ERROR
    retry = MC_MoveAbsoluteCA(follower)
    retry(execute=True, position=500.0, velocity=100.0)
    assert retry.error and retry.error_id is ErrorId.GROUP_IN_ERROR
    reset = MC_GroupReset(group)
    reset(execute=True)
    cycles = drive(rt, reset, until=lambda: not reset.busy)
    assert cycles > 0 and reset.done  # busy until the members' MC_Reset is through
    read()
    status()
    assert read.group_error_id is ErrorId.NO_ERROR
    assert flags(status) == {"group_standby", "all_axes_standing"}
    assert leader.state is om.AxisState.STANDSTILL
    again = MC_MoveAbsoluteCA(leader)
    again(execute=True, position=2000.0, velocity=500.0)
    drive(rt, again, until=lambda: again.done)
    assert leader.set_position == pytest.approx(2000.0)
