"""The Execute/Done protocol of the execute blocks (TcMC §7.1, digest §1.3-1.5; rules 1-16).

Timing convention of the runtime: an FB called in a cycle shows the state after the previous
motion step; a rising edge is planned at once (busy in the same call); an input error shows in
the same call. Every block is called once per cycle, before ``rt.step()``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import pytest

import openmotion as om
from openmotion.plcopen import (
    MC_ChangeDynParam,
    MC_Halt,
    MC_Home,
    MC_MoveAbsolute,
    MC_MoveAbsoluteOrRestart,
    MC_MoveModulo,
    MC_MoveRelative,
    MC_MoveVelocity,
    MC_NewPos,
    MC_NewPosAndVelo,
    MC_Power,
    MC_ReadActualPosition,
    MC_ReadParameterSet,
    MC_Reset,
    MC_SetActualPosition,
    MC_SetOverride,
    MC_Stop,
)

ErrorId = om.ErrorId
LAG = om.DriveModel(model="lag", time_constant=0.01, dead_time=0.002)


def powered_axis(**overrides: Any) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x", **overrides)
    assert axis.power()
    return rt, axis


def outputs(fb: Any) -> tuple[bool, bool, bool, bool]:
    return fb.busy, fb.done, fb.command_aborted, fb.error


@dataclass
class Case:
    """An execute block that completes with Done, and how to set it up."""

    name: str
    make: Callable[[om.Axis], Any]
    inputs: dict[str, Any]
    prepare: Callable[[om.Runtime, om.Axis], Any] = lambda rt, axis: None
    axis_overrides: dict[str, Any] = field(default_factory=dict)

    def __str__(self) -> str:
        return self.name


def _moving(rt: om.Runtime, axis: om.Axis) -> MC_MoveAbsolute:
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=500.0, velocity=100.0)
    for _ in range(150):  # cruising at 100 mm/s
        rt.step()
    assert axis.set_velocity == pytest.approx(100.0)
    return move


DONE_CASES = [
    Case("MC_MoveAbsolute", MC_MoveAbsolute, {"position": 20.0, "velocity": 200.0}),
    Case("MC_MoveRelative", MC_MoveRelative, {"distance": -20.0, "velocity": 200.0}),
    Case("MC_MoveModulo", MC_MoveModulo, {"position": 20.0, "velocity": 200.0}),
    Case("MC_MoveAbsoluteOrRestart", MC_MoveAbsoluteOrRestart,
         {"position": 20.0, "velocity": 200.0}),
    Case("MC_Halt", MC_Halt, {}, prepare=_moving),
    Case("MC_Stop", MC_Stop, {}, prepare=_moving),
    Case("MC_Home", MC_Home, {"position": 3.0},
         axis_overrides={"reference_mode": om.ReferenceMode.DIRECT}),
    Case("MC_Reset", MC_Reset, {}),
    Case("MC_SetActualPosition", MC_SetActualPosition, {"position": 7.0}),
    Case("MC_SetOverride", MC_SetOverride, {"override": 80.0}),
    Case("MC_ReadParameterSet", MC_ReadParameterSet, {}),
    Case("MC_NewPos", MC_NewPos, {"new_pos": 300.0}, prepare=_moving),
    Case("MC_NewPosAndVelo", MC_NewPosAndVelo, {"new_pos": 300.0, "new_velo": 50.0},
         prepare=_moving),
    Case("MC_ChangeDynParam", MC_ChangeDynParam,
         {"acceleration": 4000.0, "deceleration": 4000.0, "jerk": 40000.0}, prepare=_moving),
]


def _setup(case: Case):
    rt, axis = powered_axis(**case.axis_overrides)
    keep = case.prepare(rt, axis)
    fb = case.make(axis)
    return rt, axis, fb, keep


def _run_until_done(rt: om.Runtime, fb: Any, execute: Callable[[int], bool],
                    inputs: dict[str, Any] | None = None,
                    max_cycles: int = 3000) -> list[tuple[bool, bool, bool, bool]]:
    """Call ``fb`` each cycle with execute(i) until 30 cycles after its first Done.

    Call 0 is the rising edge and passes ``inputs``.
    """
    history = []
    first_done = None
    for i in range(max_cycles):
        fb(execute=execute(i), **(inputs if i == 0 and inputs else {}))
        history.append(outputs(fb))
        if fb.done and first_done is None:
            first_done = i
        if first_done is not None and i >= first_done + 30:
            return history
        assert not fb.error, (fb.error_id, fb.message)
        rt.step()
    raise AssertionError(f"{type(fb).__name__} never done")


# -- rule 1: rising edge only -----------------------------------------------------------------


def test_nothing_happens_while_execute_stays_false() -> None:
    """Rule 1: an execute block with execute FALSE starts nothing, whatever its inputs."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    for _ in range(100):
        move(execute=False, position=50.0, velocity=100.0)
        assert outputs(move) == (False, False, False, False)
        rt.step()
    assert axis.set_position == 0.0
    assert axis.state is om.AxisState.STANDSTILL


def test_holding_execute_never_starts_a_second_command() -> None:
    """Rule 1: after Done, a held execute with new inputs does not move the axis again."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    for _ in range(2000):
        move(execute=True, position=20.0, velocity=200.0)
        if move.done:
            break
        rt.step()
    assert move.done
    for _ in range(200):
        move(execute=True, position=80.0, velocity=200.0)  # new inputs, no new edge
        assert move.done and not move.busy
        rt.step()
    assert axis.set_position == 20.0


def test_a_new_rising_edge_starts_the_new_inputs() -> None:
    """Rule 1: FALSE→TRUE with new inputs starts a new command."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    _run_until_done(rt, move, lambda i: True, {"position": 20.0, "velocity": 200.0})
    move(execute=False)
    rt.step()
    move(execute=True, position=-10.0, velocity=200.0)
    assert move.busy
    while not move.done:
        rt.step()
        move(execute=True)
    assert axis.set_position == -10.0


# -- rules 3 and 4: persistence and pulses -----------------------------------------------------


@pytest.mark.parametrize("case", DONE_CASES, ids=str)
def test_done_stays_while_execute_stays_true(case: Case) -> None:
    """Rule 3, TcMC §7.1 fig. 1: Done stays TRUE while Execute stays TRUE, then falls."""
    rt, axis, fb, _keep = _setup(case)
    history = _run_until_done(rt, fb, lambda i: True, case.inputs)
    first = next(i for i, h in enumerate(history) if h[1])
    assert all(h == (False, True, False, False) for h in history[first:])
    assert all(not h[1] for h in history[:first])
    fb(execute=False)
    assert outputs(fb) == (False, False, False, False)
    assert fb.error_id == ErrorId.NO_ERROR


@pytest.mark.parametrize("case", DONE_CASES, ids=str)
def test_done_is_a_one_cycle_pulse_after_a_short_execute(case: Case) -> None:
    """Rule 4, TcMC §7.1 fig. 2: Execute dropped before completion → Done for one cycle."""
    rt, axis, fb, _keep = _setup(case)
    history = _run_until_done(rt, fb, lambda i: i == 0, case.inputs)
    done_cycles = [i for i, h in enumerate(history) if h[1]]
    assert len(done_cycles) == 1
    first = done_cycles[0]
    assert history[first] == (False, True, False, False)
    assert all(h == (False, False, False, False) for h in history[first + 1:])


def test_command_aborted_follows_the_same_hold_and_pulse_rule() -> None:
    """Rule 13 with §7.1 (PLCopen for CommandAborted): held while Execute TRUE, else a pulse."""
    for hold in (True, False):
        rt, axis = powered_axis()
        move, stop = MC_MoveAbsolute(axis), MC_Stop(axis)
        move(execute=True, position=500.0, velocity=100.0)
        rt.step()
        move(execute=hold)
        rt.step()
        stop(execute=True)
        seen = []
        for _ in range(20):
            move(execute=hold)
            seen.append(move.command_aborted)
            assert not move.done and not move.error and not move.busy
            rt.step()
        assert seen == ([True] * 20 if hold else [True] + [False] * 19)
        if hold:
            move(execute=False)
            assert not move.command_aborted


def test_error_follows_the_same_hold_and_pulse_rule() -> None:
    """Rule 12 with §1.3 [P]: Error (and ErrorID) held while Execute TRUE, else one call."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=1.0, velocity=-5.0)
    assert move.error and move.error_id == ErrorId.INVALID_VELOCITY and not move.busy
    for _ in range(10):
        rt.step()
        move(execute=True)
        assert move.error and move.error_id == ErrorId.INVALID_VELOCITY
    move(execute=False)
    assert not move.error and move.error_id == ErrorId.NO_ERROR
    move(execute=True, velocity=-5.0)  # a pulse: error in the edge call only
    assert move.error
    move(execute=False)
    assert not move.error and move.error_id == ErrorId.NO_ERROR


# -- busy, active, outputs reset on a new edge -----------------------------------------------


def test_busy_and_active_from_the_edge_in_the_same_call() -> None:
    """§1.3: Busy TRUE from the Execute edge (same call); Active while it controls the axis."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=50.0, velocity=100.0)
    assert move.busy and move.active and not move.done
    buffered = MC_MoveAbsolute(axis)
    buffered(execute=True, position=80.0, velocity=100.0, buffer_mode=om.BufferMode.BUFFERED)
    assert buffered.busy and not buffered.active  # waits for the first one
    while not move.done:
        rt.step()
        move(execute=True)
        buffered(execute=True)
        assert move.busy != move.done
    assert not move.active
    assert buffered.active  # took over when the first one was done


def test_all_outputs_reset_by_the_next_rising_edge() -> None:
    """§1.3 [P]: a rising edge clears Done/CommandAborted/Error of the previous command."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=1.0, velocity=0.0)
    assert move.error
    move(execute=False)
    move(execute=True, position=10.0, velocity=100.0)
    assert outputs(move) == (True, False, False, False)
    assert move.error_id == ErrorId.NO_ERROR
    while not move.done:
        rt.step()
        move(execute=True)
    move(execute=False)
    move(execute=True, position=30.0)  # falling and rising edge in consecutive calls
    assert outputs(move) == (True, False, False, False)


# -- rule 5, 12, 16: invariants over a busy sequence --------------------------------------------


def test_output_invariants_over_a_sequence_of_commands() -> None:
    """Rules 5, 12, 16: at most one of Done/Aborted/Error; ErrorID 0 unless Error; Done of a
    move never while the axis has a job; never Done and Busy together."""
    rt, axis = powered_axis(drive=LAG)
    a, b = MC_MoveAbsolute(axis), MC_MoveRelative(axis)
    v, s = MC_MoveVelocity(axis), MC_Stop(axis)
    schedule = {0: "a", 150: "b", 300: "v", 500: "s", 700: "a", 1500: "b"}
    execute = dict.fromkeys("abvs", False)
    seen_done = 0
    for cycle in range(2500):
        if cycle in schedule:
            name = schedule[cycle]
            execute = dict.fromkeys(execute, False)
            execute[name] = True
        a(execute=execute["a"], position=40.0 * (1 + cycle // 700), velocity=150.0)
        b(execute=execute["b"], distance=-15.0, velocity=150.0)
        v(execute=execute["v"], velocity=80.0)
        s(execute=execute["s"])
        if cycle == 600:
            execute["s"] = False
        for fb in (a, b, v, s):
            assert fb.done + fb.command_aborted + fb.error <= 1
            assert not (fb.busy and (fb.done or fb.command_aborted or fb.error))
            assert fb.error or fb.error_id == ErrorId.NO_ERROR
        for fb in (a, b):
            if fb.done:
                seen_done += 1
                assert not axis.has_job
        rt.step()
    assert seen_done > 0


# -- rules 13-15: aborts ------------------------------------------------------------------------


def test_stop_aborts_a_move_which_never_reports_done() -> None:
    """Rule 13, TcMC §3.1: MC_Stop → CommandAborted, never Done."""
    rt, axis = powered_axis()
    move, stop = MC_MoveAbsolute(axis), MC_Stop(axis)
    move(execute=True, position=100.0, velocity=100.0)
    for _ in range(100):
        rt.step()
        move(execute=True)
    stop(execute=True)
    move(execute=True)
    assert move.command_aborted and not move.busy
    for _ in range(2000):
        rt.step()
        move(execute=True)
        stop(execute=True)
        assert not move.done
    assert stop.done
    assert axis.set_position < 100.0


@pytest.mark.parametrize("replacement", ["MC_MoveAbsolute", "MC_MoveRelative", "MC_MoveVelocity",
                                         "MC_MoveModulo", "MC_Halt"])
def test_a_new_move_replaces_the_running_one(replacement: str) -> None:
    """Rule 14, TcMC §3.1: the replaced move reports CommandAborted; the new target wins."""
    rt, axis = powered_axis()
    first = MC_MoveAbsolute(axis)
    first(execute=True, position=200.0, velocity=100.0)
    for _ in range(100):
        rt.step()
        first(execute=True)
    blocks = {
        "MC_MoveAbsolute": (MC_MoveAbsolute, {"position": 30.0, "velocity": 100.0}, 30.0),
        "MC_MoveRelative": (MC_MoveRelative, {"distance": 10.0, "velocity": 100.0}, None),
        "MC_MoveVelocity": (MC_MoveVelocity, {"velocity": 50.0}, None),
        "MC_MoveModulo": (MC_MoveModulo, {"position": 45.0, "velocity": 100.0}, 45.0),
        "MC_Halt": (MC_Halt, {}, None),
    }
    cls, inputs, target = blocks[replacement]
    start = axis.set_position
    second = cls(axis)
    second(execute=True, **inputs)
    first(execute=True)
    assert first.command_aborted and not first.done
    assert second.busy
    for _ in range(2000):
        rt.step()
        first(execute=True)
        second(execute=True)
        assert not first.done
        if second.done:
            break
    if target is not None:
        assert axis.set_position == pytest.approx(target, abs=1e-9)
    if replacement == "MC_MoveRelative":
        assert axis.set_position == pytest.approx(start + 10.0, abs=1e-9)
    if replacement == "MC_MoveVelocity":
        assert second.in_velocity and axis.set_velocity == pytest.approx(50.0)
    if replacement == "MC_Halt":
        assert second.done and axis.set_velocity == 0.0 and axis.set_position < 200.0


def test_axis_error_aborts_the_move() -> None:
    """Rule 15, TcMC §3.1: an axis error during a move → the move FB reports CommandAborted."""
    rt, axis = powered_axis(drive=LAG, max_position_lag=0.5)
    move = MC_MoveAbsolute(axis)
    for _ in range(2000):
        move(execute=True, position=300.0, velocity=200.0)
        if not move.busy:
            break
        rt.step()
    assert move.command_aborted and not move.done
    assert axis.state is om.AxisState.ERROR_STOP
    assert axis.axis_error_id == ErrorId.FOLLOWING_ERROR


# -- misspelt input, wrong state -----------------------------------------------------------


@pytest.mark.parametrize(
    ("cls", "typo", "suggestion"),
    [(MC_MoveAbsolute, "positon", "position"), (MC_MoveVelocity, "velocty", "velocity"),
     (MC_MoveRelative, "distnace", "distance"), (MC_Stop, "exectue", "execute"),
     (MC_Power, "enabel", "enable"), (MC_ReadActualPosition, "enalbe", "enable")],
)
def test_misspelt_input_is_a_type_error_with_a_suggestion(cls, typo: str, suggestion: str) -> None:
    """Style §2: a misspelt input is a Python TypeError at once, naming the closest input."""
    rt, axis = powered_axis()
    fb = cls(axis)
    with pytest.raises(TypeError) as raised:
        fb(**{typo: 1.0})
    assert str(raised.value) == (
        f"{cls.__name__} has no input {typo!r} (did you mean {suggestion!r}?)"
    )
    with pytest.raises(TypeError, match=f"{cls.__name__} has no input"):
        cls(axis, **{typo: 1.0})
    assert axis.state is om.AxisState.STANDSTILL


def test_unrelated_input_name_has_no_suggestion() -> None:
    rt, axis = powered_axis()
    with pytest.raises(TypeError) as raised:
        MC_MoveAbsolute(axis)(execute=True, zzzzzz=1.0)
    assert str(raised.value) == "MC_MoveAbsolute has no input 'zzzzzz'"


def test_wrong_state_command_gives_its_error_id_and_the_axis_stays_usable() -> None:
    """Rule 101 / §1.2: a move on a disabled axis → AXIS_DISABLED; after power it moves."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=10.0, velocity=100.0)
    assert move.error and move.error_id == ErrorId.AXIS_DISABLED
    assert move.message
    assert axis.state is om.AxisState.DISABLED
    rt.step()
    move(execute=False)
    axis.power()
    move(execute=True)
    assert move.busy and not move.error
    while not move.done:
        rt.step()
        move(execute=True)
    assert axis.set_position == 10.0


def test_stop_holding_rejects_moves_then_releases() -> None:
    """§3.15 + PLCopen (digest Open Q1, our D-005): while MC_Stop.Execute is TRUE moves get
    AXIS_STOPPING; after its falling edge and standstill, the axis moves again."""
    rt, axis = powered_axis()
    stop, move = MC_Stop(axis), MC_MoveAbsolute(axis)
    stop(execute=True)
    for _ in range(5):
        rt.step()
        stop(execute=True)
    assert stop.done and axis.state is om.AxisState.STOPPING
    move(execute=True, position=5.0, velocity=100.0)
    assert move.error and move.error_id == ErrorId.AXIS_STOPPING
    move(execute=False)
    stop(execute=False)
    rt.step()
    assert axis.state is om.AxisState.STANDSTILL
    move(execute=True, position=5.0, velocity=100.0)
    assert move.busy
    while not move.done:
        rt.step()
        move(execute=True)
    assert axis.set_position == 5.0


# -- rule 2: enable blocks ----------------------------------------------------------------------


def test_enable_block_acts_every_cycle_while_enabled_and_stops_when_disabled() -> None:
    """Rule 2, TcMC §4.3: MC_ReadActualPosition follows the axis while Enable is TRUE."""
    rt, axis = powered_axis()
    read, move = MC_ReadActualPosition(axis), MC_MoveVelocity(axis)
    move(execute=True, velocity=100.0)
    for _ in range(50):
        rt.step()
        read(enable=True)
        assert read.done and read.position == axis.position
    assert read.position > 0.0
    read(enable=False)
    assert not read.done and not read.error
    frozen = read.position
    rt.step()
    read(enable=False)
    assert read.position == frozen != axis.position  # not read any more
