"""The PLCopen single-axis state machine as TcMC maps onto it (digest §1.2, Open Q1/Q2).

Two parts: every transition and every rejection that exists now, as tables; then a hypothesis
``RuleBasedStateMachine`` that drives one axis with random command sequences and checks the
invariants after every step.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

import openmotion as om
from openmotion.plcopen import (
    MC_ChangeDynParam,
    MC_Halt,
    MC_Home,
    MC_MoveAbsolute,
    MC_MoveModulo,
    MC_MoveRelative,
    MC_MoveVelocity,
    MC_NewPos,
    MC_Power,
    MC_Reset,
    MC_SetActualPosition,
    MC_Stop,
)

S = om.AxisState
E = om.ErrorId
CYCLE = 0.001

# -- entering each state ------------------------------------------------------------------------


def enter(state: S) -> tuple[om.Runtime, om.Axis, list]:
    """A runtime with one axis in ``state``; the list keeps the FBs that hold it there."""
    rt = om.Runtime()
    axis = rt.add_axis("x", reference_cam=(-1000.0, -990.0), max_soft_limit=0.5)
    keep: list = []
    if state is S.DISABLED:
        return rt, axis, keep
    axis.power()
    if state is S.DISCRETE_MOTION:
        keep.append(MC_MoveAbsolute(axis))
        keep[-1](execute=True, position=100.0, velocity=100.0)
    elif state is S.CONTINUOUS_MOTION:
        keep.append(MC_MoveVelocity(axis))
        keep[-1](execute=True, velocity=100.0, direction=om.Direction.NEGATIVE)
    elif state is S.STOPPING:
        keep.append(MC_MoveVelocity(axis))
        keep[-1](execute=True, velocity=100.0, direction=om.Direction.NEGATIVE)
        rt.run(0.02)
        keep.append(MC_Stop(axis))
        keep[-1](execute=True)  # held: the axis stays in Stopping
    elif state is S.HOMING:
        keep.append(MC_Home(axis))
        keep[-1](execute=True)
    elif state is S.ERROR_STOP:
        axis.parameters.enable_max_soft_limit = True
        keep.append(MC_MoveVelocity(axis))
        keep[-1](execute=True, velocity=100.0)
        rt.run_until(lambda: axis.state is S.ERROR_STOP, timeout=1.0)
        rt.run(0.05)
    rt.run(0.02)
    assert axis.state is state
    return rt, axis, keep


def _issue(cls: type, **inputs: Any) -> Callable[[om.Axis], Any]:
    def issue(axis: om.Axis) -> Any:
        fb = cls(axis)
        fb(execute=True, **inputs)
        return fb
    issue.__name__ = cls.__name__
    return issue


COMMANDS = {
    "MoveAbsolute": _issue(MC_MoveAbsolute, position=-50.0, velocity=100.0),
    "MoveRelative": _issue(MC_MoveRelative, distance=-50.0, velocity=100.0),
    "MoveModulo": _issue(MC_MoveModulo, position=200.0, velocity=100.0,
                         direction=om.Direction.NEGATIVE),
    "MoveVelocity": _issue(MC_MoveVelocity, velocity=50.0, direction=om.Direction.NEGATIVE),
    "Halt": _issue(MC_Halt),
    "Stop": _issue(MC_Stop),
    "Home": _issue(MC_Home),
    "NewPos": _issue(MC_NewPos, new_pos=-80.0),
    "ChangeDynParam": _issue(MC_ChangeDynParam, acceleration=5000.0, deceleration=5000.0,
                             jerk=50000.0),
    "SetActualPosition": _issue(MC_SetActualPosition, position=-7.0),
}

D, SS, DM, CM, ST, ES, HO = (S.DISABLED, S.STANDSTILL, S.DISCRETE_MOTION, S.CONTINUOUS_MOTION,
                             S.STOPPING, S.ERROR_STOP, S.HOMING)

#: (state, command) -> state right after an accepted command, or the rejection's error id
OUTCOME: dict[tuple[S, str], S | E] = {}
for _state, _refusal in ((D, E.AXIS_DISABLED), (ES, E.AXIS_IN_ERROR_STOP),
                         (ST, E.AXIS_STOPPING), (HO, E.AXIS_HOMING)):
    for _command in COMMANDS:
        OUTCOME[_state, _command] = _refusal
OUTCOME.update({
    (SS, "MoveAbsolute"): DM, (SS, "MoveRelative"): DM, (SS, "MoveModulo"): DM,
    (SS, "MoveVelocity"): CM, (SS, "Halt"): DM, (SS, "Stop"): ST, (SS, "Home"): HO,
    (SS, "NewPos"): E.AXIS_NOT_MOVING, (SS, "ChangeDynParam"): E.AXIS_NOT_MOVING,
    (SS, "SetActualPosition"): SS,
    (DM, "MoveAbsolute"): DM, (DM, "MoveRelative"): DM, (DM, "MoveModulo"): DM,
    (DM, "MoveVelocity"): CM, (DM, "Halt"): DM, (DM, "Stop"): ST,
    (DM, "Home"): E.AXIS_NOT_STANDSTILL, (DM, "NewPos"): DM, (DM, "ChangeDynParam"): DM,
    (DM, "SetActualPosition"): E.AXIS_NOT_STANDSTILL,
    (CM, "MoveAbsolute"): DM, (CM, "MoveRelative"): DM, (CM, "MoveModulo"): DM,
    (CM, "MoveVelocity"): CM, (CM, "Halt"): DM, (CM, "Stop"): ST,
    (CM, "Home"): E.AXIS_NOT_STANDSTILL, (CM, "NewPos"): DM, (CM, "ChangeDynParam"): CM,
    (CM, "SetActualPosition"): E.AXIS_NOT_STANDSTILL,
    # a stop is always possible while moving, also during homing (§3.15)
    (ST, "Stop"): ST, (HO, "Stop"): ST,
    # TcMC §4.20: MC_ChangeDynParam during a stop has its own id
    (ST, "ChangeDynParam"): E.DYN_STRICTER_STOP_ACTIVE,
    # MC_SetActualPosition works without power and in ErrorStop at rest (Open Q26, D-018)
    (D, "SetActualPosition"): D, (ES, "SetActualPosition"): ES,
})
STATES = (D, SS, DM, CM, ST, ES, HO)
assert len(OUTCOME) == len(STATES) * len(COMMANDS)


@pytest.mark.parametrize(("state", "command"), list(OUTCOME),
                         ids=[f"{s.name}-{c}" for s, c in OUTCOME])
def test_command_in_state(state: S, command: str) -> None:
    """Digest §1.2 as a table: the state after an accepted command, or the refusal's id;
    a refused command leaves the state alone and the axis usable."""
    rt, axis, keep = enter(state)
    expected = OUTCOME[state, command]
    fb = COMMANDS[command](axis)
    if isinstance(expected, S):
        assert not fb.error, (fb.error_id, fb.message)
        assert axis.state is expected
        if command == "SetActualPosition":
            assert axis.position == -7.0
    else:
        assert fb.error and fb.error_id == expected, (fb.error_id, fb.message)
        assert fb.message
        assert not fb.busy and not fb.done
        assert axis.state is state
        rt.step()
        assert axis.state is state or state in (DM, CM, HO)  # moving states move on
    rt.run(0.01)  # no exception escapes the next cycles


# -- events -------------------------------------------------------------------------------------


def test_disabled_to_standstill_on_power() -> None:
    rt, axis, _ = enter(D)
    power = MC_Power(axis)
    power(enable=True)
    assert power.status and axis.state is SS


@pytest.mark.parametrize("state", [SS, DM, CM, ST, HO])
def test_power_off_from_any_state_disables(state: S) -> None:
    """§1.2: MC_Power.Enable FALSE → Disabled (the running command is aborted)."""
    rt, axis, keep = enter(state)
    MC_Power(axis)(enable=False)
    assert axis.state is D
    for fb in keep:
        fb(execute=True)
        assert not fb.busy
    rt.run(0.01)
    assert axis.state is D and axis.set_velocity == 0.0


def test_power_off_in_error_stop_keeps_error_stop_until_reset() -> None:
    """PLCopen Part 1: ErrorStop → Disabled only through MC_Reset with Status FALSE."""
    rt, axis, _ = enter(ES)
    MC_Power(axis)(enable=False)
    assert axis.state is ES
    reset = MC_Reset(axis)
    reset(execute=True)
    rt.run_until(lambda: (reset(execute=True), reset.done)[1], timeout=1.0)
    assert axis.state is D


def test_error_stop_to_standstill_on_reset() -> None:
    rt, axis, _ = enter(ES)
    assert axis.axis_error_id == E.SOFT_LIMIT_REACHED
    reset = MC_Reset(axis)
    rt.run_until(lambda: (reset(execute=True), reset.done)[1], timeout=1.0)
    assert axis.state is SS and axis.axis_error_id == E.NO_ERROR


def test_reset_outside_error_stop_changes_nothing() -> None:
    rt, axis, _ = enter(SS)
    reset = MC_Reset(axis)
    reset(execute=True)
    assert reset.done and axis.state is SS


@pytest.mark.parametrize("state", [DM, CM])
def test_moving_to_error_stop_on_an_axis_error(state: S) -> None:
    """§1.2: an axis error (here the software limit, reached by a velocity move) → ErrorStop."""
    rt, axis, keep = enter(state)
    axis.parameters.max_soft_limit = axis.set_position + 20.0
    axis.parameters.enable_max_soft_limit = True
    go = MC_MoveVelocity(axis)
    go(execute=True, velocity=200.0)
    rt.run_until(lambda: axis.state is ES, timeout=2.0)
    assert axis.axis_error_id == E.SOFT_LIMIT_REACHED


def test_discrete_motion_to_standstill_when_done() -> None:
    rt, axis, keep = enter(DM)
    move = keep[0]
    rt.run_until(lambda: (move(execute=True), move.done)[1], timeout=5.0)
    assert axis.state is SS


def test_stopping_to_standstill_after_release_at_rest() -> None:
    """§3.15 + PLCopen: Stopping holds while Execute is TRUE, at rest too; after the
    falling edge → StandStill."""
    rt, axis, keep = enter(ST)
    stop = keep[-1]
    rt.run_until(lambda: (stop(execute=True), stop.done)[1], timeout=2.0)
    for _ in range(50):
        stop(execute=True)
        rt.step()
        assert axis.state is ST
    stop(execute=False)
    rt.step()
    assert axis.state is SS


def test_stopping_released_before_rest_ends_in_standstill() -> None:
    rt, axis, keep = enter(ST)
    stop = keep[-1]
    stop(execute=False)
    rt.step()
    assert axis.state is ST  # still braking
    rt.run_until(lambda: axis.state is SS, timeout=2.0)
    assert axis.set_velocity == 0.0


def test_halt_to_standstill_when_done() -> None:
    rt, axis, _ = enter(CM)
    halt = MC_Halt(axis)
    halt(execute=True)
    assert axis.state is DM
    rt.run_until(lambda: (halt(execute=True), halt.done)[1], timeout=2.0)
    assert axis.state is SS


def test_homing_to_standstill_when_done() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x", reference_mode=om.ReferenceMode.DIRECT)
    axis.power()
    home = MC_Home(axis)
    home(execute=True)
    assert axis.state is HO
    rt.run_until(lambda: (home(execute=True), home.done)[1], timeout=1.0)
    assert axis.state is SS and axis.homed


# -- the stateful test --------------------------------------------------------------------------

LIMIT = 100.0  #: enabled software limits ±LIMIT: velocity moves can fault (ErrorStop)
VMAX = 500.0  #: the axis maximum velocity, a hard limit (D-020)
MOVING = {DM, CM}
REFUSAL = {D: E.AXIS_DISABLED, ES: E.AXIS_IN_ERROR_STOP, ST: E.AXIS_STOPPING,
           HO: E.AXIS_HOMING}
THEN = st.integers(0, 100)  #: cycles run after a command (so time passes between commands)
JERKS = (20000.0, 50000.0)  #: every command uses one of these (or the default 50000)
ACCELS = (2000.0, 5000.0)


class AxisMachine(RuleBasedStateMachine):
    """One axis driven by FBs; the model knows which states each command allows."""

    @initialize()
    def start(self) -> None:
        self.rt = om.Runtime()
        self.axis = self.rt.add_axis(
            "x", enable_min_soft_limit=True, min_soft_limit=-LIMIT, enable_max_soft_limit=True,
            max_soft_limit=LIMIT, max_velocity=VMAX)
        self.power = MC_Power(self.axis)
        self.power_enable = True
        self.power(self.axis, enable=True)
        self.fbs: list[list[Any]] = []  #: [fb, execute level]
        self.stop: MC_Stop | None = None
        self.allowed: set[S] = {SS}
        self.may_fault = False
        self.exempt = True  # the next cycle may jump (power on/off, reset)
        self.error_reaction = False  # braking with the axis maxima after an axis error
        self.steep_switch = False  # D-020: a higher jerk keeps the velocity below the maximum
        self.last = self._sample()

    # helpers

    def _sample(self) -> tuple[float, float, float]:
        a = self.axis
        return a.set_position, a.set_velocity, a.set_acceleration

    def _issue(self, fb: Any, jerk: float = min(JERKS), **inputs: Any) -> bool:
        """Issue a command; returns True if accepted. A refusal must name the state.

        ``jerk`` is the jerk the command brakes an acceleration with: if that would carry the
        velocity past the axis maximum, the kernel may use a higher one (D-020).
        """
        before = self.axis.state
        v, a = self.axis.set_velocity, self.axis.set_acceleration
        steep = v * a > 0.0 and abs(v) + a * a / (2.0 * jerk) > VMAX * (1 - 1e-6)
        if not isinstance(fb, MC_Halt | MC_Stop | MC_Reset):
            inputs["jerk"] = jerk
        fb(self.axis, execute=True, **inputs)
        self.fbs.append([fb, True])
        self.fbs[:] = self.fbs[-6:]
        if fb.error:
            expected = REFUSAL.get(before)
            if expected is not None:
                assert fb.error_id == expected, (before, fb.error_id, fb.message)
            assert self.axis.state is before
            return False
        self.steep_switch = steep
        return True

    def _release(self, fb: Any) -> None:
        """Falling edge of ``fb``'s Execute; it never rises again."""
        fb(execute=False)
        for entry in self.fbs:
            if entry[0] is fb:
                entry[1] = False

    def _motion(self, allowed: set[S], may_fault: bool) -> None:
        self.allowed = set(allowed)
        self.may_fault = may_fault

    # rules

    @rule(position=st.floats(-LIMIT, LIMIT), velocity=st.floats(10.0, VMAX),
          jerk=st.sampled_from(JERKS), acceleration=st.sampled_from(ACCELS), then=THEN)
    def move_absolute(self, position: float, velocity: float, jerk: float,
                      acceleration: float, then: int) -> None:
        if self._issue(MC_MoveAbsolute(), jerk, position=position, velocity=velocity,
                       acceleration=acceleration, deceleration=acceleration):
            self._motion({DM, SS}, False)
        self.run(then)

    @rule(velocity=st.floats(10.0, VMAX), negative=st.booleans(),
          jerk=st.sampled_from(JERKS), acceleration=st.sampled_from(ACCELS), then=THEN)
    def move_velocity(self, velocity: float, negative: bool, jerk: float,
                      acceleration: float, then: int) -> None:
        direction = om.Direction.NEGATIVE if negative else om.Direction.POSITIVE
        if self._issue(MC_MoveVelocity(), jerk, velocity=velocity, direction=direction,
                       acceleration=acceleration, deceleration=acceleration):
            self._motion({CM}, True)  # it may run into a software limit: ErrorStop
        self.run(then)

    @rule(then=THEN)
    def halt(self, then: int) -> None:
        if self._issue(MC_Halt(), 50000.0):  # the axis default jerk
            self._motion({DM, SS}, False)
        self.run(then)

    @rule(then=THEN)
    def stop(self, then: int) -> None:
        stop = MC_Stop()
        if self._issue(stop):
            if self.stop is not None:
                self._release(self.stop)
            self.stop = stop
            self._motion({ST}, False)
        self.run(then)

    @rule(then=THEN)
    def release_stop(self, then: int) -> None:
        if self.stop is not None:
            self._release(self.stop)
            self.stop = None
            if self.allowed == {ST}:
                self.allowed = {ST, SS}
        self.run(then)

    @rule(then=THEN)
    def power_off(self, then: int) -> None:
        self.power_enable = False
        was = self.axis.state
        self.power(self.axis, enable=False)
        self.allowed = {ES} if was is ES else {D}
        self.may_fault = False
        self.exempt = True
        self.run(then)

    @rule(then=THEN)
    def power_on(self, then: int) -> None:
        self.power_enable = True
        was = self.axis.state
        self.power(self.axis, enable=True)
        assert self.power.status
        if was is D:
            self.allowed = {SS}
            self.exempt = True
        self.run(then)

    @rule(then=THEN)
    def reset(self, then: int) -> None:
        was = self.axis.state
        if self._issue(MC_Reset()) and was is ES:
            self.allowed = {ES, SS if self.axis.powered else D}
            self.may_fault = False
            self.exempt = True
        self.run(then)

    @rule(cycles=st.integers(1, 300))
    def run(self, cycles: int) -> None:
        """Run ``cycles`` PLC cycles, calling every FB and checking every cycle."""
        axis = self.axis
        for _ in range(cycles):
            self.power(axis, enable=self.power_enable)
            for entry in self.fbs:
                fb, level = entry
                # Execute stays TRUE while busy (MC_Stop: while it holds), never rises again
                entry[1] = fb is self.stop or (level and fb.busy)
                fb(execute=entry[1])
            self._check_cycle()
            self.rt.step()
            if axis.state is S.ERROR_STOP and ES not in self.allowed:
                assert self.may_fault, "unexpected ErrorStop"
                assert axis.axis_error_id == E.SOFT_LIMIT_REACHED
                self.allowed = {ES}
                self.error_reaction = True
            self._check_continuity()
            if len(self.allowed) == 2 and axis.state in self.allowed and axis.state is not ST \
                    and axis.state is not DM and axis.state is not ES:
                self.allowed = {axis.state}  # settled: StandStill or Disabled
            assert axis.state in self.allowed, (axis.state, self.allowed)

    # invariants

    def _check_cycle(self) -> None:
        for fb, _ in self.fbs:
            assert not (fb.done and fb.busy)
            assert fb.done + fb.command_aborted + fb.error <= 1
            assert fb.error or fb.error_id == E.NO_ERROR

    def _check_continuity(self) -> None:
        p, v, a = self._sample()
        p0, v0, a0 = self.last
        self.last = (p, v, a)
        if self.exempt:
            self.exempt = False
            return
        assert abs(v) <= VMAX * (1 + 1e-9), v
        assert abs(p - p0) <= VMAX * CYCLE * (1 + 1e-9) + 1e-9, (p0, p)
        if self.error_reaction:
            # the error reaction brakes with the axis maxima (max_deceleration/max_jerk)
            params = self.axis.parameters
            assert abs(v - v0) <= params.max_deceleration * CYCLE * (1 + 1e-9) + 1e-9
            assert abs(a - a0) <= params.max_jerk * CYCLE * (1 + 1e-9) + 1e-6
            if v == 0.0 and a == 0.0:
                self.error_reaction = False
            return
        assert abs(v - v0) <= max(ACCELS) * CYCLE * (1 + 1e-9) + 1e-9, (v0, v)
        jerk = self.axis.parameters.max_jerk if self.steep_switch else max(JERKS)
        assert abs(a - a0) <= jerk * CYCLE * (1 + 1e-9) + 1e-6, (a0, a)

    @invariant()
    def state_is_allowed(self) -> None:
        if not hasattr(self, "axis"):
            return
        assert self.axis.state in self.allowed, (self.axis.state, self.allowed)

    @invariant()
    def limits_hold(self) -> None:
        if hasattr(self, "axis"):
            assert -LIMIT - 1e-9 <= self.axis.set_position <= LIMIT + 1e-9


_default = settings.default
AxisMachine.TestCase.settings = settings(
    _default,
    max_examples=40 if _default.max_examples <= 60 else _default.max_examples,
    stateful_step_count=30,
    deadline=None,
)
TestAxisStateMachine = AxisMachine.TestCase
