"""The Part 4 axes-group state machine (PLCopen Part 4 §3.1-§3.3, §5; digest §2, §3, §6.3).

Tables first, written out here independently of the module: every transition, every
FB x state cell, the member coupling of §3.2 / Table 5; then the notes of the spec as short
scenarios, ExecutionMode, and a hypothesis run over random event sequences.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from openmotion.coordinated.states import (
    ACCEPTS,
    AUTOMATIC,
    EXECUTION_MODE_BLOCKS,
    START_EVENT,
    TRANSITIONS,
    AxesGroupState,
    ExecutionMode,
    GroupEvent,
    GroupStateMachine,
    accepting_states,
    check_accepts,
    check_member_accepts,
    commands_to_wait,
    member_command_event,
    member_event,
    member_state,
    next_state,
    stop_released,
)
from openmotion.core.enums import AxisState, BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.transport.enums import GroupState

G = AxesGroupState
V = GroupEvent
A = AxisState
ORDER = (G.DISABLED, G.STANDBY, G.HOMING, G.MOVING, G.STOPPING, G.ERROR_STOP)

# -- the states --------------------------------------------------------------------------------


def test_numbers_are_tf5410_group_state_numbers():
    for state in G:
        assert int(state) == int(GroupState[state.name])


def test_spec_names_are_the_read_status_flags():
    # §5.17: one output per state, spelt as in §3.1
    assert {s.spec_name for s in G} == {"GroupDisabled", "GroupStandby", "GroupMoving",
                                        "GroupHoming", "GroupStopping", "GroupErrorStop"}


# -- transitions (digest §2.2, rebuilt from §3.1 and Notes 1-6) ----------------------------------

TRANSITION_ROWS = [
    # (from, event, to, source)
    *[(s, V.DISABLE, G.DISABLED, "Note 6") for s in ORDER],
    *[(s, V.ERROR, G.ERROR_STOP, "§3.1 T14") for s in (G.STANDBY, G.HOMING, G.MOVING,
                                                          G.STOPPING)],
    *[(s, V.UNGROUP, G.DISABLED, "§5.3") for s in (G.DISABLED, G.STANDBY, G.ERROR_STOP)],
    *[(s, V.REMOVE_LAST_AXIS, G.DISABLED, "Note 4") for s in (G.DISABLED, G.STANDBY,
                                                                G.ERROR_STOP)],
    *[(s, V.MEMBER_POWER_OFF, G.DISABLED, "§5.13") for s in (G.HOMING, G.MOVING, G.STOPPING)],
    (G.DISABLED, V.ENABLE, G.STANDBY, "§5.5 T1"),
    (G.DISABLED, V.ADD_AXIS, G.DISABLED, "§4.1 T6"),
    (G.DISABLED, V.REMOVE_AXIS, G.DISABLED, "§4.1 T6"),
    (G.DISABLED, V.RESET, G.DISABLED, "decision §5.19"),
    (G.STANDBY, V.ENABLE, G.STANDBY, "decision digest q32"),
    (G.STANDBY, V.ADD_AXIS, G.STANDBY, "Note 5 T5"),
    (G.STANDBY, V.REMOVE_AXIS, G.STANDBY, "Note 5 T5"),
    (G.STANDBY, V.MOTION_START, G.MOVING, "Note 1 T9"),
    (G.STANDBY, V.HALT, G.MOVING, "Table 5 T9"),
    (G.STANDBY, V.HOME_START, G.HOMING, "§3.1 T7"),
    (G.STANDBY, V.STOP, G.STOPPING, "§5.13 T12"),
    (G.STANDBY, V.RESET, G.STANDBY, "decision digest q32"),
    (G.HOMING, V.HOME_END, G.STANDBY, "§5.7 T8"),
    (G.HOMING, V.STOP, G.STOPPING, "T12 inferred"),
    (G.MOVING, V.MOTION_START, G.MOVING, "Note 1 T10"),
    (G.MOVING, V.HALT, G.MOVING, "§5.14 T10"),
    (G.MOVING, V.HOME_START, G.HOMING, "§5.7 buffered"),
    (G.MOVING, V.MOTION_END, G.STANDBY, "§4.1 T11"),
    (G.MOVING, V.STOP, G.STOPPING, "§5.13 T12"),
    (G.STOPPING, V.STOP_RELEASED, G.STANDBY, "Note 3 T13"),
    (G.ERROR_STOP, V.REMOVE_AXIS, G.ERROR_STOP, "§5.2"),
    (G.ERROR_STOP, V.RESET, G.STANDBY, "§5.19 T15"),
]


@pytest.mark.parametrize(("state", "event", "target", "source"), TRANSITION_ROWS,
                         ids=lambda x: getattr(x, "name", x))
def test_transition(state, event, target, source):
    assert next_state(state, event) is target


def test_the_table_has_no_other_transition():
    assert set(TRANSITIONS) == {(s, e) for s, e, _, _ in TRANSITION_ROWS}


MISSING = [(s, e) for s in ORDER for e in V if (s, e) not in TRANSITIONS]


@pytest.mark.parametrize(("state", "event"), MISSING, ids=lambda x: x.name)
def test_an_event_without_transition(state, event):
    if event in AUTOMATIC:  # a dotted line that does not start here: nothing happens
        assert next_state(state, event) is state
    else:  # a commanded one: check_accepts refuses the FB before it gets here
        with pytest.raises(ValueError, match="check_accepts"):
            next_state(state, event)


# -- which FB may start in which state (digest §2.2, Note 2, §5.x notes) ------------------------

# One character per state in ORDER (Disabled, Standby, Homing, Moving, Stopping, ErrorStop):
# "." accepted, else the refusal: n GROUP_NOT_ENABLED, x NOTHING_TO_DO, h homing, m moving,
# s GROUP_STOPPING, e GROUP_IN_ERROR.
CELLS = {
    # administrative: grouping (§5.1-§5.6)
    "MC_AddAxisToGroup": "..hmse",  # §4.1: Disabled and Standby only
    "MC_RemoveAxisFromGroup": "..hms.",  # §5.2
    "MC_UngroupAllAxes": "..hms.",  # §5.3 (wins over Note 6, digest q2)
    "MC_GroupEnable": "..hmse",
    "MC_GroupDisable": "......",  # Note 6
    "MC_GroupReset": "..hms.",  # §5.19
    # administrative: transformations and path data (§5.8, §5.26); Note 2 bars the last two
    "MC_SetKinTransform": "....se",  # §4.1 step 5 links it while GroupDisabled
    "MC_SetCartesianTransform": "....se",
    "MC_SetCoordinateTransform": "....se",
    "MC_SetDynCoordTransform": "....se",
    "MC_PathSelect": "....se",
    # reads and override: never refused (§5.28 note 7: no influence on the state diagram)
    "MC_ReadKinTransform": "......",
    "MC_ReadCartesianTransform": "......",
    "MC_ReadCoordinateTransform": "......",
    "MC_GroupReadConfiguration": "......",
    "MC_GroupReadActualPosition": "......",
    "MC_GroupReadActualVelocity": "......",
    "MC_GroupReadActualAcceleration": "......",
    "MC_GroupReadStatus": "......",
    "MC_GroupReadError": "......",
    "MC_GroupSetOverride": "......",
    # motion (Note 1, Table 5)
    "MC_MoveLinearAbsolute": "n.h.se",
    "MC_MoveLinearRelative": "n.h.se",
    "MC_MoveCircularAbsolute": "n.h.se",
    "MC_MoveCircularRelative": "n.h.se",
    "MC_MoveDirectAbsolute": "n.h.se",
    "MC_MoveDirectRelative": "n.h.se",
    "MC_MovePath": "n.h.se",
    "MC_GroupHalt": "n.h.se",
    "MC_GroupContinue": "n.h.se",  # Standby: after MC_GroupReset (§5.16 second note)
    "MC_GroupInterrupt": "nxh.se",
    "MC_GroupStop": "n...se",  # a second stop is refused: only Disable aborts one (§5.13)
    "MC_GroupHome": "n.hmse",  # Aborting outside Standby is an error (§5.7)
    "MC_GroupSetPosition": "n.hmse",
    # synchronised motion (§6)
    "MC_SyncAxisToGroup": "n.h.se",
    "MC_SyncGroupToAxis": "n.h.se",
    "MC_TrackConveyorBelt": "n.h.se",
    "MC_TrackRotaryTable": "n.h.se",
}
BUFFERED_CELLS = {"MC_GroupHome": "n.h.se", "MC_GroupSetPosition": "n.h.se"}  # §5.7
CODES = {"n": ErrorId.GROUP_NOT_ENABLED, "x": ErrorId.NOTHING_TO_DO, "h": ErrorId.GROUP_HOMING,
         "m": ErrorId.GROUP_MOVING, "s": ErrorId.GROUP_STOPPING, "e": ErrorId.GROUP_IN_ERROR}


def cells(table: dict[str, str], mode: BufferMode) -> list[tuple[str, BufferMode, G, str]]:
    return [(block, mode, state, row[i]) for block, row in table.items()
            for i, state in enumerate(ORDER)]


@pytest.mark.parametrize(
    ("block", "mode", "state", "cell"),
    cells(CELLS, BufferMode.ABORTING) + cells(BUFFERED_CELLS, BufferMode.BUFFERED)
    + cells(BUFFERED_CELLS, BufferMode.BLENDING_HIGH),
    ids=lambda x: getattr(x, "name", x))
def test_fb_in_state(block, mode, state, cell):
    if cell == ".":
        check_accepts(state, block, mode)
        return
    with pytest.raises(CommandRejected) as rejected:
        check_accepts(state, block, mode)
    assert rejected.value.error_id is CODES[cell]
    assert block in rejected.value.message and state.spec_name in rejected.value.message


def test_every_fb_of_table_1_is_covered():
    assert len(CELLS) == 38  # §1.3: 33 in chapter 5, 5 in chapter 6
    assert set(ACCEPTS) == set(CELLS)


def test_only_the_set_transform_fbs_have_an_execution_mode():
    expected = {"MC_SetKinTransform", "MC_SetCartesianTransform", "MC_SetCoordinateTransform"}
    assert expected == EXECUTION_MODE_BLOCKS


def test_a_misspelt_fb_is_a_python_error():
    with pytest.raises(ValueError, match="did you mean 'MC_GroupStop'"):
        check_accepts(G.MOVING, "MC_GroupStp")


@pytest.mark.parametrize("block", sorted(START_EVENT))
def test_an_accepted_fb_always_has_its_transition(block):
    modes = (BufferMode.ABORTING, BufferMode.BUFFERED)
    for state in {s for mode in modes for s in accepting_states(block, mode)}:
        next_state(state, START_EVENT[block])  # no ValueError


@pytest.mark.parametrize("block", sorted(set(ACCEPTS) - set(START_EVENT)))
def test_other_fbs_leave_the_state_alone(block):
    machine = GroupStateMachine()
    machine.fire(V.ADD_AXIS)
    machine.fire(V.ENABLE)
    machine.fire(V.MOTION_START)
    assert machine.start(block) is G.MOVING


# -- the member axes (§3.2, Table 5) ----------------------------------------------------------

AXIS_ORDER = (A.DISABLED, A.STANDSTILL, A.HOMING, A.DISCRETE_MOTION, A.CONTINUOUS_MOTION,
              A.SYNCHRONIZED_MOTION, A.STOPPING, A.ERROR_STOP)
D, SS, H, DM, CM, SM, ST, ES = AXIS_ORDER
# group state a group FB led to -> what each member shows, columns in AXIS_ORDER
MEMBER_ROWS = {
    G.MOVING: (D, SM, SM, SM, SM, SM, SM, ES),  # Table 5 row 1
    G.HOMING: (D, SM, SM, SM, SM, SM, SM, ES),  # Table 5 row 4
    G.STOPPING: (D, SM, SM, SM, SM, SM, SM, ES),  # Table 5 row 2: no single-axis stop runs
    G.STANDBY: (D, SS, H, DM, CM, SS, ST, ES),  # Table 5 row 2; §3.2: not all need StandStill
    G.DISABLED: (D, SS, H, DM, CM, SS, ST, ES),  # §4.1: each axis ends in StandStill
    G.ERROR_STOP: AXIS_ORDER,  # §3.1, §3.2: axes not affected
}


@pytest.mark.parametrize(("group", "axis", "shown"),
                         [(g, a, row[i]) for g, row in MEMBER_ROWS.items()
                          for i, a in enumerate(AXIS_ORDER)],
                         ids=lambda x: x.name)
def test_member_state(group, axis, shown):
    assert member_state(group, axis) is shown


@pytest.mark.parametrize("state", ORDER, ids=lambda s: s.name)
def test_a_member_in_error_stop_puts_the_group_in_error(state):
    # §3.2: one axis in ErrorStop => the whole group; Disabled supervises nothing (decision)
    after = next_state(state, member_event(A.ERROR_STOP))
    assert after is (G.DISABLED if state is G.DISABLED else G.ERROR_STOP)


def test_group_error_stop_leaves_healthy_members_alone():
    # §3.1, digest rule 50
    assert all(member_state(G.ERROR_STOP, a) is a for a in AXIS_ORDER)


@pytest.mark.parametrize(("state", "after"), [
    (G.DISABLED, G.DISABLED), (G.STANDBY, G.STANDBY), (G.ERROR_STOP, G.ERROR_STOP),  # §3.2
    (G.HOMING, G.DISABLED), (G.MOVING, G.DISABLED), (G.STOPPING, G.DISABLED),  # §5.13
], ids=lambda x: x.name)
def test_a_member_losing_power(state, after):
    assert next_state(state, member_event(A.DISABLED)) is after


@pytest.mark.parametrize("axis", [a for a in A if a not in (A.DISABLED, A.ERROR_STOP)])
def test_other_member_states_mean_nothing_to_the_group(axis):
    assert member_event(axis) is None


# family -> one character per group state in ORDER: "." passes, "g" AXIS_IN_GROUP, s, e
MEMBER_CELLS = {
    "move": "gggg" + "se",  # §3.2 option 1
    "modify": "gggg" + "se",
    "set_position": "gggg" + "se",
    "home": "g.gg" + "se",  # §3.2: MC_Home on a member makes the group GroupMoving
    "stop": "......",  # §3.2: MC_Stop on a member makes the group GroupMoving; never refused
    "power": "......",  # §3.2: a member may be switched off
    "reset": "......",
    "read": "......",
}
MEMBER_CODES = {"g": ErrorId.AXIS_IN_GROUP, "s": ErrorId.GROUP_STOPPING,
                "e": ErrorId.GROUP_IN_ERROR}


@pytest.mark.parametrize(("family", "state", "cell"),
                         [(f, s, row[i]) for f, row in MEMBER_CELLS.items()
                          for i, s in enumerate(ORDER)],
                         ids=lambda x: getattr(x, "name", x))
def test_single_axis_command_on_a_member(family, state, cell):
    if cell == ".":
        check_member_accepts(state, family)
        return
    with pytest.raises(CommandRejected) as rejected:
        check_member_accepts(state, family)
    assert rejected.value.error_id is MEMBER_CODES[cell]


def test_an_unknown_family_is_a_python_error():
    with pytest.raises(ValueError, match="family"):
        check_member_accepts(G.STANDBY, "jog")


@pytest.mark.parametrize("state", ORDER, ids=lambda s: s.name)
@pytest.mark.parametrize("family", sorted(MEMBER_CELLS))
def test_member_command_event(state, family):
    expected = V.MOTION_START if family in ("stop", "home") and state is G.STANDBY else None
    assert member_command_event(state, family) is expected


# -- the notes of the spec as scenarios -------------------------------------------------------


def enabled(members: int = 2) -> GroupStateMachine:
    machine = GroupStateMachine()
    for _ in range(members):
        machine.accept("MC_AddAxisToGroup")
        machine.start("MC_AddAxisToGroup")
    machine.accept("MC_GroupEnable")
    machine.start("MC_GroupEnable")
    return machine


def issue(machine: GroupStateMachine, block: str,
          buffer_mode: BufferMode = BufferMode.ABORTING) -> G:
    machine.accept(block, buffer_mode)
    return machine.start(block)


def test_a_new_group_is_empty_and_disabled():
    machine = GroupStateMachine()  # §4.1, rule 22
    assert (machine.state, machine.members) == (G.DISABLED, 0)


def test_enable_needs_an_axis():
    with pytest.raises(CommandRejected) as rejected:  # Note 5, rule 31
        GroupStateMachine().accept("MC_GroupEnable")
    assert rejected.value.error_id is ErrorId.GROUP_EMPTY


def test_stop_holds_the_group_until_released():
    machine = enabled()
    assert issue(machine, "MC_MoveLinearAbsolute") is G.MOVING  # Fig. 12 edge 1
    assert issue(machine, "MC_GroupStop") is G.STOPPING
    with pytest.raises(CommandRejected) as rejected:  # Fig. 12 edge 2: an FB error only
        issue(machine, "MC_MoveLinearRelative")
    assert rejected.value.error_id is ErrorId.GROUP_STOPPING
    assert machine.state is G.STOPPING  # not GroupErrorStop (rule 41)
    assert not stop_released(done=True, execute=True)  # t2: still held (rule 39)
    assert machine.state is G.STOPPING
    assert stop_released(done=True, execute=False)  # t3
    assert machine.fire(V.STOP_RELEASED) is G.STANDBY
    assert issue(machine, "MC_MoveLinearRelative") is G.MOVING  # edge 3 starts (rule 42)


@pytest.mark.parametrize(("done", "execute", "released"), [
    (False, True, False), (True, True, False), (False, False, False), (True, False, True)])
def test_stop_released_is_note_3(done, execute, released):
    assert stop_released(done, execute) is released


def test_group_stop_in_group_stopping_is_refused_and_changes_nothing():
    machine = enabled()
    issue(machine, "MC_GroupStop")
    for block in ("MC_GroupStop", "MC_GroupHalt", "MC_MoveDirectAbsolute"):  # rule 43
        with pytest.raises(CommandRejected):
            issue(machine, block)
    assert machine.state is G.STOPPING
    assert issue(machine, "MC_GroupDisable") is G.DISABLED  # the only way to abort it


def test_an_error_while_stopping_goes_to_error_stop():
    machine = enabled()
    issue(machine, "MC_GroupStop")
    assert machine.fire(member_event(A.ERROR_STOP)) is G.ERROR_STOP  # Note 2, rule 54


@pytest.mark.parametrize("state", [s for s in ORDER if s is not G.ERROR_STOP],
                         ids=lambda s: s.name)
def test_reset_leaves_group_error_stop_only(state):
    assert next_state(G.ERROR_STOP, V.RESET) is G.STANDBY  # §5.19
    if (state, V.RESET) in TRANSITIONS:
        assert next_state(state, V.RESET) is state  # Done without effect
    else:
        with pytest.raises(CommandRejected):
            check_accepts(state, "MC_GroupReset")


def test_only_reset_disable_ungroup_and_reads_work_in_error_stop():
    refused = {b for b in ACCEPTS if G.ERROR_STOP not in accepting_states(b)}
    allowed = set(ACCEPTS) - refused  # Note 2, Note 6, §5.2, rule 51
    assert allowed == {"MC_GroupReset", "MC_GroupDisable", "MC_UngroupAllAxes",
                       "MC_RemoveAxisFromGroup", "MC_GroupSetOverride"} | {
        b for b in ACCEPTS if "Read" in b}


def test_disable_from_error_stop():
    machine = enabled()
    machine.fire(V.ERROR)
    assert issue(machine, "MC_GroupDisable") is G.DISABLED  # Note 6
    assert machine.members == 2
    assert issue(machine, "MC_GroupEnable") is G.STANDBY


def test_error_stop_then_reset_then_continue():
    machine = enabled()
    issue(machine, "MC_MoveCircularAbsolute")
    machine.fire(member_event(A.ERROR_STOP))
    assert issue(machine, "MC_GroupReset") is G.STANDBY
    assert issue(machine, "MC_GroupContinue") is G.MOVING  # §5.16 second note


def test_removing_axes():
    machine = enabled(members=2)
    assert issue(machine, "MC_RemoveAxisFromGroup") is G.STANDBY  # Note 5, rule 27
    assert issue(machine, "MC_RemoveAxisFromGroup") is G.DISABLED  # Note 4, rule 26
    assert machine.members == 0
    with pytest.raises(CommandRejected) as rejected:
        machine.accept("MC_RemoveAxisFromGroup")
    assert rejected.value.error_id is ErrorId.AXIS_NOT_IN_GROUP
    with pytest.raises(ValueError, match="no axis"):
        machine.fire(V.REMOVE_AXIS)


def test_removing_the_last_axis_in_error_stop():
    machine = enabled(members=1)
    machine.fire(V.ERROR)
    assert issue(machine, "MC_RemoveAxisFromGroup") is G.DISABLED  # §5.2, Note 4


def test_ungroup_empties_the_group():
    machine = enabled(members=3)
    assert issue(machine, "MC_UngroupAllAxes") is G.DISABLED  # §5.3
    assert machine.members == 0


def test_home_aborting_at_rest_then_done():
    machine = enabled()
    assert issue(machine, "MC_GroupHome") is G.HOMING  # §5.7, rule 56
    assert machine.fire(V.HOME_END) is G.STANDBY


def test_home_buffered_behind_a_move_takes_over():
    machine = enabled()
    issue(machine, "MC_MoveLinearAbsolute")
    with pytest.raises(CommandRejected):  # rule 55
        machine.accept("MC_GroupHome")
    machine.accept("MC_GroupHome", BufferMode.BLENDING_LOW)  # acts as Buffered (§5.7)
    assert machine.state is G.MOVING  # waits in the queue
    assert machine.start("MC_GroupHome") is G.HOMING  # its turn comes
    assert machine.fire(V.HOME_END) is G.STANDBY


def test_halt_is_moving_until_done_and_a_move_may_abort_it():
    machine = enabled()
    issue(machine, "MC_MoveCircularAbsolute")
    assert issue(machine, "MC_GroupHalt") is G.MOVING  # Table 5, rule 61
    assert issue(machine, "MC_MoveCircularAbsolute") is G.MOVING  # Fig. 14 R, rule 62
    assert issue(machine, "MC_GroupHalt") is G.MOVING
    assert machine.fire(V.MOTION_END) is G.STANDBY


def test_interrupt_and_continue_stay_moving():
    machine = enabled()
    issue(machine, "MC_MovePath")
    assert issue(machine, "MC_GroupInterrupt") is G.MOVING  # §5.15, rule 64
    assert issue(machine, "MC_GroupContinue") is G.MOVING  # §5.16


def test_single_axis_stop_on_a_member_makes_the_group_moving():
    machine = enabled()
    check_member_accepts(machine.state, "stop")
    assert machine.fire(member_command_event(machine.state, "stop")) is G.MOVING  # rule 58
    assert machine.fire(V.MOTION_END) is G.STANDBY


def test_a_motion_fb_puts_every_member_in_synchronized_motion():
    machine = enabled()  # rule 36
    state = issue(machine, "MC_MoveDirectRelative")
    assert [member_state(state, a) for a in (A.STANDSTILL, A.STANDSTILL)] == [SM, SM]
    assert member_state(machine.fire(V.MOTION_END), SM) is SS


def test_transforms_do_not_change_the_state():
    machine = GroupStateMachine()  # §4.1 step 5, rule 10
    issue(machine, "MC_AddAxisToGroup")
    assert issue(machine, "MC_SetKinTransform") is G.DISABLED
    issue(machine, "MC_GroupEnable")
    issue(machine, "MC_MoveLinearAbsolute")
    assert issue(machine, "MC_SetCartesianTransform") is G.MOVING


# -- ExecutionMode (§3.3) ----------------------------------------------------------------------

@pytest.mark.parametrize(("mode", "running", "buffered", "wait"), [
    (ExecutionMode.IMMEDIATELY, False, 0, 0), (ExecutionMode.IMMEDIATELY, True, 3, 0),
    (ExecutionMode.DELAYED, False, 0, 0), (ExecutionMode.DELAYED, True, 0, 1),
    (ExecutionMode.DELAYED, True, 3, 1),  # only the running one
    (ExecutionMode.QUEUED, False, 0, 0), (ExecutionMode.QUEUED, True, 0, 1),
    (ExecutionMode.QUEUED, True, 3, 4),  # every command issued before it
], ids=str)
def test_commands_to_wait(mode, running, buffered, wait):
    assert commands_to_wait(mode, running, buffered) == wait


@pytest.mark.parametrize(("running", "buffered"), [(False, 1), (True, -1)])
def test_commands_to_wait_rejects_an_impossible_queue(running, buffered):
    with pytest.raises(ValueError):
        commands_to_wait(ExecutionMode.QUEUED, running, buffered)


# -- random sequences --------------------------------------------------------------------------

ACTIONS = st.one_of(
    st.tuples(st.just("fb"), st.sampled_from(sorted(ACCEPTS)),
              st.sampled_from([BufferMode.ABORTING, BufferMode.BUFFERED])),
    st.tuples(st.just("auto"), st.sampled_from(sorted(AUTOMATIC, key=lambda e: e.value)),
              st.none()),
)


@settings(max_examples=150, deadline=None)
@given(st.lists(ACTIONS, max_size=40))
def test_random_sequences_keep_the_rules(actions):
    machine = GroupStateMachine()
    for kind, what, mode in actions:
        before = machine.state
        if kind == "auto":
            machine.fire(what)
        else:
            try:
                machine.accept(what, mode)
            except CommandRejected:
                assert machine.state is before  # an FB error changes nothing (§5.13 Fig. 12)
                continue
            machine.start(what)
        assert machine.members >= 0
        assert machine.members > 0 or machine.state is G.DISABLED  # Notes 4, 5
        if before is G.ERROR_STOP and machine.state is not G.ERROR_STOP:  # §3.1
            assert (what, machine.state) in {("MC_GroupReset", G.STANDBY),
                                             ("MC_GroupDisable", G.DISABLED),
                                             ("MC_UngroupAllAxes", G.DISABLED),
                                             ("MC_RemoveAxisFromGroup", G.DISABLED)}
