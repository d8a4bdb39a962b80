"""Positioning and velocity blocks (TcMC §3.1-3.8; rules 17-27), PLCopen buffer modes,
dynamics inputs (TcMC §1.9 / TF5410 §11.2 special values) and software limits (TcMC §6.1).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

import openmotion as om
from openmotion.plcopen import (
    MC_Halt,
    MC_MoveAbsolute,
    MC_MoveAbsoluteOrRestart,
    MC_MoveModulo,
    MC_MoveRelative,
    MC_MoveVelocity,
    MC_NewPos,
    MC_NewPosAndVelo,
    MC_ReadStatus,
)

ErrorId = om.ErrorId
S = om.AxisState
B = om.BufferMode
N = om.NewPosAndVeloMode
POS, NEG = om.Direction.POSITIVE, om.Direction.NEGATIVE
CYCLE = 0.001
LAG = om.DriveModel(model="lag", time_constant=0.01, dead_time=0.002)


def powered_axis(**overrides: Any) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x", **overrides)
    assert axis.power()
    return rt, axis


class Trace:
    """Setpoint samples, one per cycle, taken at the FB calls (after the previous step)."""

    def __init__(self) -> None:
        self.p: list[float] = []
        self.v: list[float] = []
        self.a: list[float] = []

    def sample(self, axis: om.Axis) -> None:
        self.p.append(axis.set_position)
        self.v.append(axis.set_velocity)
        self.a.append(axis.set_acceleration)

    def peak_jerk(self) -> float:
        return max(abs(b - a) for a, b in zip(self.a, self.a[1:], strict=False)) / CYCLE


def run(rt: om.Runtime, axis: om.Axis, program: Callable[[], Any],
        until: Callable[[], bool], max_cycles: int = 20000) -> Trace:
    """Call ``program`` every cycle (then sample) until ``until()``; step in between."""
    trace = Trace()
    for _ in range(max_cycles):
        program()
        trace.sample(axis)
        if until():
            return trace
        rt.step()
    raise AssertionError(f"not reached within {max_cycles} cycles")


# -- rules 17, 18 --------------------------------------------------------------------------------


@pytest.mark.parametrize("target", [100.0, -37.5, 0.001, 1234.567])
def test_move_absolute_ends_exactly_at_the_target(target: float) -> None:
    """Rule 17, TcMC §3.1/§7.1: set position exactly p; actual within the target window."""
    rt, axis = powered_axis(drive=LAG)
    move = MC_MoveAbsolute(axis)
    trace = run(rt, axis, lambda: move(execute=True, position=target, velocity=200.0),
                lambda: move.done)
    assert axis.set_position == target
    assert abs(axis.position - target) <= axis.parameters.target_position_window
    assert axis.state is S.STANDSTILL
    assert max(abs(v) for v in trace.v) <= 200.0 * (1 + 1e-9)
    lo, hi = min(trace.p), max(trace.p)  # no overshoot of the target
    assert lo >= min(0.0, target) - 1e-9 and hi <= max(0.0, target) + 1e-9


def test_move_relative_refers_to_the_set_position() -> None:
    """Rule 18, TcMC §3.2/§3.5: target = set position at the start + distance (not actual)."""
    rt, axis = powered_axis(drive=LAG)
    velocity, relative = MC_MoveVelocity(axis), MC_MoveRelative(axis)
    run(rt, axis, lambda: velocity(execute=True, velocity=150.0), lambda: velocity.in_velocity)
    for _ in range(20):
        rt.step()
    start = axis.set_position
    assert abs(axis.following_error) > 1.0  # actual differs clearly from set
    run(rt, axis, lambda: relative(execute=True, distance=40.0, velocity=150.0),
        lambda: relative.done)
    assert axis.set_position == pytest.approx(start + 40.0, abs=1e-9)


@pytest.mark.parametrize("distance", [25.0, -25.0, 0.0])
def test_move_relative_from_standstill(distance: float) -> None:
    rt, axis = powered_axis(position=10.0)
    move = MC_MoveRelative(axis)
    run(rt, axis, lambda: move(execute=True, distance=distance, velocity=100.0),
        lambda: move.done)
    assert axis.set_position == pytest.approx(10.0 + distance, abs=1e-12)


# -- rules 19-21: MC_MoveVelocity ---------------------------------------------------------------


@pytest.mark.parametrize(("direction", "sign"), [(POS, 1.0), (NEG, -1.0)])
def test_move_velocity_in_velocity_and_direction(direction: om.Direction, sign: float) -> None:
    """Rules 19/20, TcMC §3.3: InVelocity FALSE on the ramp, TRUE once at ±Velocity."""
    rt, axis = powered_axis()
    move = MC_MoveVelocity(axis)
    trace = run(rt, axis, lambda: move(execute=True, velocity=120.0, direction=direction),
                lambda: move.in_velocity)
    assert axis.set_velocity == pytest.approx(sign * 120.0, abs=1e-9)
    assert len(trace.v) > 10  # a real ramp, during which InVelocity was FALSE
    assert all(abs(v) < 120.0 - 1e-9 for v in trace.v[:-2])
    assert all(v * sign >= 0.0 for v in trace.v)
    assert axis.state is S.CONTINUOUS_MOTION


def test_move_velocity_runs_on_without_done() -> None:
    """Rule 21 [P]: MC_MoveVelocity never ends by itself; Busy and InVelocity stay."""
    rt, axis = powered_axis()
    move = MC_MoveVelocity(axis)
    run(rt, axis, lambda: move(execute=True, velocity=50.0), lambda: move.in_velocity)
    start = axis.set_position
    for _ in range(2000):
        move(execute=False)  # dropping execute does not end it either
        assert move.busy and move.in_velocity and not move.done
        rt.step()
    assert axis.set_position == pytest.approx(start + 50.0 * 2.0, rel=1e-9)
    assert axis.state is S.CONTINUOUS_MOTION


def test_move_velocity_current_direction_keeps_the_direction() -> None:
    """MC_Current_Direction (TcMC §6.2): a moving axis keeps its direction of travel."""
    rt, axis = powered_axis()
    first, second = MC_MoveVelocity(axis), MC_MoveVelocity(axis)
    run(rt, axis, lambda: first(execute=True, velocity=80.0, direction=NEG),
        lambda: first.in_velocity)
    run(rt, axis, lambda: second(execute=True, velocity=30.0, direction=om.Direction.CURRENT),
        lambda: second.in_velocity)
    assert axis.set_velocity == pytest.approx(-30.0, abs=1e-9)


# -- rules 22, 23: MC_MoveAbsoluteOrRestart ---------------------------------------------------


def test_absolute_or_restart_from_standstill_is_move_absolute() -> None:
    """Rule 22, TcMC §3.6: from standstill it is MC_MoveAbsolute, sample for sample."""
    traces = []
    for cls in (MC_MoveAbsolute, MC_MoveAbsoluteOrRestart):
        rt, axis = powered_axis()
        fb = cls(axis)
        inputs = {"position": 77.0, "velocity": 123.0, "acceleration": 2000.0,
                  "deceleration": 1500.0, "jerk": 30000.0}
        traces.append(run(rt, axis, lambda fb=fb, inputs=inputs: fb(execute=True, **inputs),
                          lambda fb=fb: fb.done))
    assert traces[0].p == traces[1].p
    assert traces[0].v == traces[1].v


def test_absolute_or_restart_retargets_and_keeps_its_start_dynamics() -> None:
    """Rule 23, TcMC §3.6: a new edge while moving changes target and velocity; the
    acceleration/deceleration/jerk given at that edge are ignored."""
    rt, axis = powered_axis()
    move = MC_MoveAbsoluteOrRestart(axis)
    slow = {"acceleration": 1000.0, "deceleration": 1000.0, "jerk": 10000.0}
    run(rt, axis, lambda: move(execute=True, position=100.0, velocity=100.0, **slow),
        lambda: axis.set_velocity == pytest.approx(100.0))
    move(execute=False)
    rt.step()
    fast = {"acceleration": 10000.0, "deceleration": 10000.0, "jerk": 1.0e5}
    move(execute=True, position=60.0, velocity=40.0, **fast)
    assert move.busy and not move.command_aborted and not move.error
    trace = run(rt, axis, lambda: move(execute=True), lambda: move.done)
    assert axis.set_position == pytest.approx(60.0, abs=1e-9)
    assert max(abs(a) for a in trace.a) <= 1000.0 * (1 + 1e-9)
    assert trace.peak_jerk() <= 10000.0 * (1 + 1e-6)
    assert abs(trace.v[-50]) <= 40.0 * (1 + 1e-9)  # the new velocity applies


# -- rules 24-27: MC_NewPos, MC_NewPosAndVelo ---------------------------------------------------


@pytest.mark.parametrize("new_target", [150.0, 40.0], ids=["further", "nearer"])
def test_new_pos_redirects_and_is_done_at_once(new_target: float) -> None:
    """Rule 24, TcMC §3.7: Done = accepted, before the axis arrives; the move goes there.

    The original MC_MoveAbsolute then reports Done at the new target (digest Open Q12,
    our reading).
    """
    rt, axis = powered_axis()
    move, new_pos = MC_MoveAbsolute(axis), MC_NewPos(axis)
    run(rt, axis, lambda: move(execute=True, position=100.0, velocity=100.0),
        lambda: axis.set_position > 25.0)
    new_pos(execute=True, new_pos=new_target)
    assert new_pos.done and not new_pos.error
    assert abs(axis.set_position - new_target) > 5.0  # not there yet
    trace = run(rt, axis, lambda: move(execute=True), lambda: move.done or move.command_aborted)
    assert move.done
    assert axis.set_position == pytest.approx(new_target, abs=1e-9)
    assert max(trace.p) <= new_target + 1e-9


def test_new_pos_on_a_standing_axis_is_an_error() -> None:
    """Rule 25, TcMC §3.7: MC_NewPos needs an axis in motion."""
    rt, axis = powered_axis()
    new_pos = MC_NewPos(axis)
    new_pos(execute=True, new_pos=10.0)
    assert new_pos.error and new_pos.error_id == ErrorId.AXIS_NOT_MOVING
    for _ in range(10):
        rt.step()
    assert axis.set_position == 0.0


@pytest.mark.parametrize(
    ("mode", "inputs", "end"),
    [(N.CHANGE_VELO_AT_SWITCHPOS, {"new_velo": 40.0}, 200.0),
     (N.CHANGE_POS_AT_SWITCHPOS, {"new_pos": 150.0}, 150.0),
     (N.CHANGE_POS_AND_VELO_AT_SWITCHPOS, {"new_pos": 150.0, "new_velo": 40.0}, 150.0)],
    ids=lambda value: value.name if isinstance(value, N) else None,
)
def test_new_pos_and_velo_at_switch_position(mode: N, inputs: dict, end: float) -> None:
    """Rule 26, TcMC §3.8: nothing changes before ActivationPos; then the new values apply."""
    rt, axis = powered_axis()
    move, change = MC_MoveAbsolute(axis), MC_NewPosAndVelo(axis)
    run(rt, axis, lambda: move(execute=True, position=200.0, velocity=100.0),
        lambda: axis.set_velocity == pytest.approx(100.0))
    change(execute=True, mode=mode, activation_pos=100.0, **inputs)
    assert change.busy and not change.done
    before = run(rt, axis, lambda: (move(execute=True), change(execute=True)),
                 lambda: axis.set_position >= 100.0)
    assert all(v == pytest.approx(100.0) for v in before.v)  # untouched before the switch
    after = run(rt, axis, lambda: (move(execute=True), change(execute=True)),
                lambda: move.done)
    assert change.done
    assert axis.set_position == pytest.approx(end, abs=1e-9)
    if "new_velo" in inputs:
        cruise = [v for v in after.v if abs(v - 40.0) < 1e-9]
        assert len(cruise) > 100  # cruised at the new velocity
        assert max(after.v[len(after.v) // 2:]) <= 40.0 + 1e-9


def test_new_pos_and_velo_reach_velo_at_pos() -> None:
    """Rule 27, TcMC §3.8: REACH_VELO_AT_POS: the set velocity equals NewVelo exactly when
    the set position reaches ActivationPos; the ramp starts before it."""
    rt, axis = powered_axis()
    move, change = MC_MoveAbsolute(axis), MC_NewPosAndVelo(axis)
    run(rt, axis, lambda: move(execute=True, position=300.0, velocity=100.0),
        lambda: axis.set_velocity == pytest.approx(100.0))
    change(execute=True, mode=N.REACH_VELO_AT_POS, new_velo=50.0, activation_pos=150.0)
    trace = run(rt, axis, lambda: (move(execute=True), change(execute=True)),
                lambda: axis.set_position >= 150.0)
    # the cycle in which the set position passes 150 (0.1 mm per cycle at most)
    assert trace.v[-1] == pytest.approx(50.0, abs=0.5)
    assert trace.v[-2] == pytest.approx(50.0, abs=0.5)
    assert min(trace.v) >= 50.0 - 1e-6  # a monotonic change 100 → 50, no dip
    assert any(v < 99.0 for v in trace.v[:-20])  # the ramp began well before 150
    run(rt, axis, lambda: move(execute=True), lambda: move.done)
    assert axis.set_position == pytest.approx(300.0, abs=1e-9)


def test_new_pos_and_velo_change_velo_is_monotonic() -> None:
    """TcMC §3.8 CHANGE_VELO from 100 to 50 mm/s: the set velocity goes down to 50 without
    dipping below it (a jerk-limited velocity change, not a near stop)."""
    rt, axis = powered_axis()
    move, change = MC_MoveAbsolute(axis), MC_NewPosAndVelo(axis)
    run(rt, axis, lambda: move(execute=True, position=300.0, velocity=100.0),
        lambda: axis.set_velocity == pytest.approx(100.0))
    change(execute=True, mode=N.CHANGE_VELO, new_velo=50.0)
    assert change.done
    trace = run(rt, axis, lambda: move(execute=True),
                lambda: axis.set_velocity == pytest.approx(50.0))
    for _ in range(100):
        rt.step()
        trace.sample(axis)
    assert min(trace.v) >= 50.0 * (1 - 1e-9)
    assert all(b <= a + 1e-9 for a, b in zip(trace.v, trace.v[1:], strict=False))


# -- MC_Halt --------------------------------------------------------------------------------


def test_halt_brakes_with_its_dynamics_and_is_done_at_rest() -> None:
    """MC_Halt (PLCopen Part 1): brake to rest in DiscreteMotion; Done at standstill."""
    rt, axis = powered_axis()
    move, halt, status = MC_MoveVelocity(axis), MC_Halt(axis), MC_ReadStatus(axis)
    run(rt, axis, lambda: move(execute=True, velocity=200.0), lambda: move.in_velocity)
    halt(execute=True, deceleration=1000.0, jerk=20000.0)
    status(enable=True)
    assert status.discrete_motion and halt.busy
    trace = run(rt, axis, lambda: (move(execute=True), halt(execute=True)), lambda: halt.done)
    assert move.command_aborted
    assert axis.set_velocity == 0.0 and axis.state is S.STANDSTILL
    assert min(trace.a) == pytest.approx(-1000.0, rel=1e-6)
    # braking distance v²/(2d) + v·d/(2j) for a jerk-limited stop from 200 mm/s
    assert trace.p[-1] - trace.p[0] == pytest.approx(200.0**2 / 2000.0 + 200.0 * 1000.0
                                                     / 40000.0, rel=1e-3)


def test_halt_can_be_aborted_by_a_move() -> None:
    """PLCopen Part 1: unlike MC_Stop, a halting axis accepts a new move (Halt aborted)."""
    rt, axis = powered_axis()
    move, halt, back = MC_MoveVelocity(axis), MC_Halt(axis), MC_MoveAbsolute(axis)
    run(rt, axis, lambda: move(execute=True, velocity=200.0), lambda: move.in_velocity)
    halt(execute=True)
    rt.step()
    back(execute=True, position=0.0, velocity=100.0)
    halt(execute=True)
    assert halt.command_aborted and back.busy and not back.error
    run(rt, axis, lambda: back(execute=True), lambda: back.done)
    assert axis.set_position == 0.0


# -- buffer modes ---------------------------------------------------------------------------


def test_buffered_starts_after_the_previous_done() -> None:
    """PLCopen Buffered: the second move starts only when the first reports Done."""
    rt, axis = powered_axis(drive=LAG)
    first, second = MC_MoveAbsolute(axis), MC_MoveAbsolute(axis)
    first(execute=True, position=100.0, velocity=200.0)
    second(execute=True, position=50.0, velocity=200.0, buffer_mode=B.BUFFERED)
    assert second.busy and not second.active
    first_done = None
    trace = Trace()
    for cycle in range(5000):
        first(execute=True)
        second(execute=True)
        trace.sample(axis)
        if first.done and first_done is None:
            first_done = cycle
            assert second.active
        if first_done is None:
            assert not second.active
            assert axis.set_position <= 100.0 + 1e-9
        if second.done:
            break
        rt.step()
    assert first_done is not None and second.done
    # between the end of the first profile and its Done the set position stood at 100
    reached = trace.p.index(100.0)
    assert first_done - reached >= 19  # §7.1 target monitoring: 20 ms in the window
    assert all(p == 100.0 for p in trace.p[reached:first_done + 1])
    assert axis.set_position == 50.0


BLEND_CASES = [
    # mode, v1, v2, expected velocity at the first target
    (B.BLENDING_LOW, 100.0, 200.0, 100.0),
    (B.BLENDING_LOW, 200.0, 100.0, 100.0),
    (B.BLENDING_PREVIOUS, 100.0, 200.0, 100.0),
    (B.BLENDING_PREVIOUS, 200.0, 100.0, 200.0),
    (B.BLENDING_NEXT, 100.0, 200.0, 200.0),
    (B.BLENDING_NEXT, 200.0, 100.0, 100.0),
    (B.BLENDING_HIGH, 100.0, 200.0, 200.0),
    (B.BLENDING_HIGH, 200.0, 100.0, 200.0),
]


@pytest.mark.parametrize(("mode", "v1", "v2", "expected"), BLEND_CASES,
                         ids=[f"{m.name}-{v1:g}-{v2:g}" for m, v1, v2, _ in BLEND_CASES])
def test_blending_passes_the_first_target_at_the_modes_velocity(mode, v1, v2, expected) -> None:
    """PLCopen Part 1 blending: the first target is passed without stopping, at
    min(v1, v2) (Low), v1 (Previous), v2 (Next) or max(v1, v2) (High) — all feasible here
    (300 mm at 5000 mm/s² reach either velocity easily)."""
    rt, axis = powered_axis()
    first, second = MC_MoveAbsolute(axis), MC_MoveAbsolute(axis)
    first(execute=True, position=300.0, velocity=v1)
    second(execute=True, position=600.0, velocity=v2, buffer_mode=mode)
    trace = run(rt, axis, lambda: (first(execute=True), second(execute=True)),
                lambda: second.done)
    assert first.done or not first.busy
    assert axis.set_position == 600.0
    k = next(i for i, p in enumerate(trace.p) if p >= 300.0)
    assert trace.v[k] == pytest.approx(expected, abs=expected * CYCLE * 50)
    assert min(trace.v[k - 50:k + 50]) > 0.5 * min(v1, v2)  # no stop at the first target
    assert max(trace.v) <= max(v1, v2) * (1 + 1e-9)


def test_blending_with_opposite_directions_passes_at_zero_velocity() -> None:
    """PLCopen Part 1: a blend that reverses direction passes the first target at v = 0."""
    rt, axis = powered_axis()
    first, second = MC_MoveAbsolute(axis), MC_MoveAbsolute(axis)
    first(execute=True, position=100.0, velocity=100.0)
    second(execute=True, position=0.0, velocity=100.0, buffer_mode=B.BLENDING_HIGH)
    trace = run(rt, axis, lambda: (first(execute=True), second(execute=True)),
                lambda: second.done)
    top = max(trace.p)  # reaches 100 (between two samples at most), does not overshoot
    assert 100.0 - 1e-5 <= top <= 100.0 + 1e-9
    k = trace.p.index(top)
    assert abs(trace.v[k]) <= 0.05  # v = 0 at the turn; j·dt²/2 between samples
    assert all(v >= 0.0 for v in trace.v[:k]) and all(v <= 0.0 for v in trace.v[k + 1:])
    assert axis.set_position == 0.0


# -- dynamics inputs -----------------------------------------------------------------------


def _peak_accel(value) -> tuple[float, float]:
    """Peak |acceleration| and jerk of a long move with acceleration/jerk ``value``."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    trace = run(rt, axis, lambda: move(execute=True, position=400.0, velocity=1000.0,
                                        acceleration=value, deceleration=value, jerk=value),
                lambda: move.done or move.error)
    assert move.done, (move.error_id, move.message)
    return max(abs(a) for a in trace.a), trace.peak_jerk()


@pytest.mark.parametrize(("value", "accel", "jerk"), [
    (0.0, 5000.0, 50000.0),  # TcMC §1.9: 0 = axis default (1004-1006)
    (om.MC_DEFAULT, 5000.0, 50000.0),  # TF5410 §11.2
    (om.MC_MAXIMUM, 20000.0, 1.0e6),  # the axis maxima (PLCopen 12-16)
], ids=["zero", "MC_DEFAULT", "MC_MAXIMUM"])
def test_dynamics_special_values(value, accel: float, jerk: float) -> None:
    peak_accel, peak_jerk = _peak_accel(value)
    assert peak_accel == pytest.approx(accel, rel=1e-6)
    assert peak_jerk == pytest.approx(jerk, rel=1e-3)


#: axis defaults 1004-1006 that differ from each other and from the built-in defaults, so
#: that a swapped or ignored default shows
DEFAULT_DYNAMICS = {"acceleration": 1500.0, "deceleration": 2500.0, "jerk": 20000.0}
ZERO_DYNAMICS = {"acceleration": 0.0, "deceleration": 0.0, "jerk": 0.0}


def _positioning(cls: type, inputs: dict, dynamics: dict) -> Trace:
    rt, axis = powered_axis(**DEFAULT_DYNAMICS)
    fb = cls(axis)
    trace = run(rt, axis, lambda: fb(execute=True, velocity=400.0, **inputs, **dynamics),
                lambda: fb.done or fb.error)
    assert fb.done, (fb.error_id, fb.message)
    assert axis.set_position == pytest.approx(300.0, abs=1e-9)
    return trace


@pytest.mark.parametrize(("cls", "inputs"), [
    (MC_MoveRelative, {"distance": 300.0}),
    (MC_MoveModulo, {"position": 300.0, "direction": POS}),
    (MC_MoveAbsoluteOrRestart, {"position": 300.0}),
], ids=["MC_MoveRelative", "MC_MoveModulo", "MC_MoveAbsoluteOrRestart"])
def test_zero_dynamics_mean_the_axis_defaults_on_positioning_blocks(cls, inputs) -> None:
    """Rule 9, TcMC §3.2, §3.4, §3.6 (from standstill): Acceleration, Deceleration and Jerk
    = 0 use AxisAcc/AxisDec/AxisJerk (1004-1006): the profile peaks at exactly those values
    and equals, sample for sample, the one with the defaults given explicitly."""
    zero = _positioning(cls, inputs, ZERO_DYNAMICS)
    explicit = _positioning(cls, inputs, DEFAULT_DYNAMICS)
    assert max(zero.a) == pytest.approx(1500.0, rel=1e-9)
    assert min(zero.a) == pytest.approx(-2500.0, rel=1e-9)
    assert zero.peak_jerk() == pytest.approx(20000.0, rel=1e-3)
    assert max(zero.v) == pytest.approx(400.0, rel=1e-9)
    assert zero.p == explicit.p and zero.v == explicit.v and zero.a == explicit.a


def _speed_change(dynamics: dict) -> Trace:
    """MC_MoveVelocity from rest to 600 mm/s, then a new edge down to 100 mm/s."""
    rt, axis = powered_axis(**DEFAULT_DYNAMICS)
    move = MC_MoveVelocity(axis)
    trace = run(rt, axis, lambda: move(execute=True, velocity=600.0, **dynamics),
                lambda: move.in_velocity)
    move(execute=False)
    rt.step()
    slower = run(rt, axis, lambda: move(execute=True, velocity=100.0, **dynamics),
                 lambda: move.in_velocity)
    for name in ("p", "v", "a"):
        getattr(trace, name).extend(getattr(slower, name))
    assert axis.set_velocity == pytest.approx(100.0, abs=1e-9)
    return trace


def test_zero_dynamics_mean_the_axis_defaults_on_move_velocity() -> None:
    """Rule 9, TcMC §3.3: speeding up uses AxisAcc and AxisJerk, slowing down AxisDec."""
    zero = _speed_change(ZERO_DYNAMICS)
    explicit = _speed_change(DEFAULT_DYNAMICS)
    assert max(zero.a) == pytest.approx(1500.0, rel=1e-9)
    assert min(zero.a) == pytest.approx(-2500.0, rel=1e-9)
    assert zero.peak_jerk() == pytest.approx(20000.0, rel=1e-3)
    assert zero.p == explicit.p and zero.v == explicit.v and zero.a == explicit.a


def test_velocity_maximum_and_clamp_with_warning() -> None:
    """TF5410 D4.1 / our dynamics: velocity above the axis maximum is clamped (warning);
    MC_MAXIMUM means the maximum."""
    for velocity in (om.MC_MAXIMUM, 5000.0):
        rt, axis = powered_axis(max_velocity=300.0)
        move = MC_MoveAbsolute(axis)
        trace = run(rt, axis, lambda move=move, velocity=velocity: move(
            execute=True, position=500.0, velocity=velocity), lambda move=move: move.done)
        assert max(trace.v) == pytest.approx(300.0, rel=1e-9)
        warnings = move.command.warnings if move.command else []
        if velocity is om.MC_MAXIMUM:
            assert not warnings
        else:
            assert any("clamped" in w for w in warnings)
            assert not move.error


def test_velocity_has_no_default() -> None:
    """Velocity > 0 is required (TcMC §3.1); MC_DEFAULT has nothing to stand for."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    move(execute=True, position=5.0, velocity=om.MC_DEFAULT)
    assert move.error and move.error_id == ErrorId.INVALID_VELOCITY


# -- software limits ------------------------------------------------------------------------

LIMITS = {"enable_min_soft_limit": True, "min_soft_limit": -50.0,
          "enable_max_soft_limit": True, "max_soft_limit": 50.0}


@pytest.mark.parametrize(("cls", "inputs"), [
    (MC_MoveAbsolute, {"position": 60.0}), (MC_MoveAbsolute, {"position": -50.5}),
    (MC_MoveRelative, {"distance": 51.0}),
])
def test_target_beyond_an_enabled_soft_limit_is_rejected(cls, inputs) -> None:
    """TcMC §6.1 (1015-1018): a target beyond an enabled limit → TARGET_BEYOND_SOFT_LIMIT."""
    rt, axis = powered_axis(**LIMITS)
    move = cls(axis)
    move(execute=True, velocity=100.0, **inputs)
    assert move.error and move.error_id == ErrorId.TARGET_BEYOND_SOFT_LIMIT
    assert axis.state is S.STANDSTILL
    ok = MC_MoveAbsolute(axis)  # the axis stays usable; the limit itself is reachable
    run(rt, axis, lambda: ok(execute=True, position=50.0, velocity=100.0), lambda: ok.done)
    assert axis.set_position == 50.0


def test_limit_disabled_allows_the_target() -> None:
    rt, axis = powered_axis(**{**LIMITS, "enable_max_soft_limit": False})
    move = MC_MoveAbsolute(axis)
    run(rt, axis, lambda: move(execute=True, position=60.0, velocity=200.0), lambda: move.done)
    assert axis.set_position == 60.0


@pytest.mark.parametrize(("direction", "limit", "start"), [(POS, 50.0, 0.0), (NEG, -50.0, 45.0)])
def test_move_velocity_toward_a_limit_stops_exactly_at_it(direction, limit, start) -> None:
    """A MoveVelocity toward an enabled limit stops at the limit without overshoot; then the
    axis is in ErrorStop with SOFT_LIMIT_REACHED and the FB reports CommandAborted."""
    rt, axis = powered_axis(position=start, **LIMITS)
    move = MC_MoveVelocity(axis)
    trace = run(rt, axis, lambda: move(execute=True, velocity=500.0, direction=direction),
                lambda: axis.state is S.ERROR_STOP, max_cycles=5000)
    for _ in range(200):
        rt.step()
        move(execute=True)
        trace.sample(axis)
    assert axis.axis_error_id == ErrorId.SOFT_LIMIT_REACHED
    assert move.command_aborted and not move.busy
    overshoot = max(p - limit for p in trace.p) if limit > 0 else max(limit - p for p in trace.p)
    assert overshoot <= 1e-9
    assert axis.set_position == pytest.approx(limit, abs=1e-9)
    assert axis.set_velocity == 0.0


def test_move_velocity_toward_a_limit_is_continuous_motion_throughout() -> None:
    """§1.2: MC_MoveVelocity puts the axis in ContinuousMotion, also with a limit ahead."""
    rt, axis = powered_axis(**LIMITS)
    move, status = MC_MoveVelocity(axis), MC_ReadStatus(axis)
    move(execute=True, velocity=100.0)
    status(enable=True)
    assert status.continuous_motion and not status.discrete_motion
    states = set()
    run(rt, axis, lambda: (move(execute=True), states.add(axis.state)),
        lambda: axis.state is S.ERROR_STOP, max_cycles=5000)
    assert states == {S.CONTINUOUS_MOTION, S.ERROR_STOP}  # the last call sees the fault


def test_move_velocity_with_a_limit_far_ahead_reports_in_velocity() -> None:
    """Rule 19 with a software limit enabled far ahead: InVelocity once at speed."""
    rt, axis = powered_axis(**{**LIMITS, "max_soft_limit": 1000.0})
    move = MC_MoveVelocity(axis)
    run(rt, axis, lambda: move(execute=True, velocity=100.0),
        lambda: move.in_velocity or axis.set_position > 500.0)
    assert move.in_velocity
    assert axis.set_velocity == 100.0 and axis.state is S.CONTINUOUS_MOTION


def test_move_velocity_away_from_the_limit_is_not_affected() -> None:
    rt, axis = powered_axis(**{**LIMITS, "enable_min_soft_limit": False})
    move = MC_MoveVelocity(axis)
    run(rt, axis, lambda: move(execute=True, velocity=100.0, direction=NEG),
        lambda: move.in_velocity)
    assert axis.set_velocity == -100.0 and axis.state is S.CONTINUOUS_MOTION


def test_buffered_behind_move_velocity_starts_at_in_velocity() -> None:
    """PLCopen Part 1 (D-008): a command buffered behind MC_MoveVelocity starts when the
    velocity is reached (InVelocity); the velocity command shows CommandAborted (D-178)."""
    rt, axis = powered_axis()
    velocity, buffered = MC_MoveVelocity(axis), MC_MoveAbsolute(axis)
    velocity(execute=True, velocity=100.0)
    buffered(execute=True, position=50.0, velocity=100.0, buffer_mode=B.BUFFERED)
    assert buffered.busy and not buffered.active
    run(rt, axis, lambda: (velocity(execute=True), buffered(execute=True)),
        lambda: buffered.active)
    assert axis.set_velocity == pytest.approx(100.0, abs=1e-9)
    assert not velocity.busy and velocity.command_aborted and not velocity.in_velocity
    run(rt, axis, lambda: buffered(execute=True), lambda: buffered.done)
    assert axis.set_position == 50.0


def test_buffer_holds_sixteen_commands() -> None:
    """D-008: 16 commands wait behind the active one; the 17th gets BUFFER_FULL."""
    rt, axis = powered_axis()
    active = MC_MoveAbsolute(axis)
    active(execute=True, position=10.0, velocity=100.0)
    queued = [MC_MoveAbsolute(axis) for _ in range(17)]
    for k, fb in enumerate(queued):
        fb(execute=True, position=10.0 + k, velocity=100.0, buffer_mode=B.BUFFERED)
    assert all(fb.busy and not fb.error for fb in queued[:16])
    assert queued[16].error and queued[16].error_id == ErrorId.BUFFER_FULL
    run(rt, axis, lambda: [fb(execute=True) for fb in [active, *queued[:16]]],
        lambda: queued[15].done, max_cycles=60000)
    assert axis.set_position == 25.0


def test_new_pos_and_velo_reach_velo_at_pos_issued_during_the_ramp() -> None:
    """Rule 27 / D-024: issued while the axis still accelerates, the new velocity still
    holds at ActivationPos."""
    rt = om.Runtime()
    axis = rt.add_axis("x", acceleration=1000.0, deceleration=1000.0, jerk=10000.0)
    axis.power()
    move = axis.move_absolute(2000.0, velocity=200.0)
    rt.run(0.05)  # still ramping up
    assert 0.0 < axis.set_velocity < 200.0 and axis.set_acceleration > 0.0
    change = axis.new_position_and_velocity(om.NewPosAndVeloMode.REACH_VELO_AT_POS,
                                            om.MC_INVALID, 50.0, activation_position=150.0)
    while axis.set_position < 150.0:
        rt.step()
    assert change.done and not move.finished
    assert axis.set_velocity == pytest.approx(50.0, rel=1e-9)
