"""Property-test helpers: hypothesis strategies for limits, kinematic states and moves.

Public (style.md §1), so that users can write property tests for their own machines with the
strategies we use ourselves. This is the only module that imports hypothesis, which keeps it an
optional extra (``pip install openmotion[test]``).

The strategies mirror the distributions of ruckig's own test suite (``test/test_target.cpp``):

* a state is at rest with a probability: ruckig draws a non-zero current velocity with
  probability 0.9 and a non-zero current acceleration with probability 0.8;
* limits span several decades (``limits``), and a separate strategy draws high limits for
  short moves (``high_limits``, ruckig's ``limit_dist_high``, 10 to 1e6);
* invalid draws are rejected by the test with ``assume(within_limits(...))``, never patched.

Units: mm, mm/s, mm/s², mm/s³ and s, as everywhere in openmotion.

Example::

    from hypothesis import assume, given
    from openmotion.testing import (
        ceil_to_cycle, moves, ruckig_duration, run_single_move, within_limits,
    )

    @given(case=moves(symmetric=True))
    def test_move_is_time_optimal(case):
        assume(within_limits(case.start, case.limits))
        trace = run_single_move(case)
        assert trace.reached(case.target)
        assert trace.duration <= ceil_to_cycle(ruckig_duration(case)) + trace.cycle_time
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np
from hypothesis import strategies as st
from ruckig import ControlInterface, InputParameter, Ruckig, Trajectory

from openmotion.axis.axis import Axis
from openmotion.axis.drive import DriveModel
from openmotion.core.enums import Direction
from openmotion.runtime.runtime import Runtime
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.planar import (
        MC_PlanarEnvironment,
        MC_PlanarGroup,
        MC_PlanarMover,
        MC_PlanarTrack,
    )

__all__ = [
    "RUCKIG_PRECISION",
    "MoveCase",
    "SetpointRecorder",
    "SetpointTrace",
    "assert_continuous",
    "assert_traces_equal",
    "assert_within_limits",
    "ceil_to_cycle",
    "enabled_line",
    "enabled_movers",
    "high_limits",
    "join_all",
    "kinematic_states",
    "limits",
    "moves",
    "ruckig_duration",
    "ruckig_reverses",
    "ruckig_trajectory",
    "run_schedule",
    "run_single_move",
    "single_axis",
    "within_limits",
]

MoveKind = Literal["position", "velocity", "stop"]
SIGNALS = ("position", "velocity", "acceleration", "jerk", "actual")
REL = 1e-9  #: relative tolerance of every limit check (performance.md: 1e-9 relative)
_REVERSAL_TOLERANCE = 1e-9  #: relative, as trajectory/plan.py decides a reversal
#: ruckig's absolute end-state precision (Profile::p_precision, v_precision, a_precision)
RUCKIG_PRECISION = (1e-8, 1e-8, 1e-10)
_PLACE_HORIZON = 1.0  #: [s] the placed state is continued this long (until the next command)


# -- cases ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class MoveCase:
    """One command from one kinematic state: what ``run_single_move`` executes.

    ``kind`` "position": MC_MoveAbsolute to ``target`` [mm] with all four ``limits``;
    "velocity": MC_MoveVelocity to the signed velocity ``target`` [mm/s];
    "stop": MC_Stop with ``limits.deceleration`` and ``limits.jerk`` (``target`` is 0).
    The axis is sized to ``limits`` (defaults and maxima).
    """

    start: KinematicState
    target: float
    limits: Limits
    kind: MoveKind = "position"

    @property
    def stop_limits(self) -> Limits:
        """The limits a stop keeps: its deceleration for both signs, no velocity bound."""
        return Limits(math.inf, self.limits.deceleration, self.limits.deceleration,
                      self.limits.jerk)

    @property
    def effective_limits(self) -> Limits:
        """The limits the setpoint must keep for this case."""
        return self.stop_limits if self.kind == "stop" else self.limits


# -- strategies -------------------------------------------------------------------------------


def _three_digits(value: float) -> float:
    """Round to three significant digits: falsifying examples stay readable."""
    return float(f"{value:.3g}")


def _decades(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Log-uniform-ish between 10**lo and 10**hi, three significant digits."""
    return st.floats(lo, hi).map(lambda exponent: _three_digits(10.0**exponent))


def _or_zero(draw: st.DrawFn, strategy: st.SearchStrategy[float], nonzero: float) -> float:
    """ruckig's ``fill_or_zero``: a value with probability ``nonzero``, else 0 (shrinks to 0)."""
    if draw(st.integers(0, 99)) < round(100 * (1.0 - nonzero)):
        return 0.0
    return draw(strategy)


@st.composite
def limits(draw: st.DrawFn, symmetric: bool = False) -> Limits:
    """Limits spanning several decades: velocity 0.1 to 1e4 mm/s, acceleration and jerk
    from the time to reach them (1 ms to 0.3 s), so that every move lasts at most a few
    seconds. ``symmetric``: deceleration == acceleration; otherwise deceleration is 0.2 to 5
    times the acceleration (equal with probability 0.2).
    """
    velocity = draw(_decades(-1.0, 4.0))
    acceleration = _three_digits(velocity / draw(_decades(-3.0, math.log10(0.3))))
    deceleration = acceleration
    if not symmetric and draw(st.integers(0, 9)) >= 2:
        deceleration = _three_digits(acceleration * draw(_decades(-0.7, 0.7)))
    jerk = _three_digits(max(acceleration, deceleration) / draw(_decades(-3.0, math.log10(0.3))))
    return Limits(velocity, acceleration, deceleration, jerk)


@st.composite
def high_limits(draw: st.DrawFn, symmetric: bool = False) -> Limits:
    """ruckig's high-limit strategy: every limit independently from 10 to 1e6."""
    velocity, acceleration, jerk = (draw(_decades(1.0, 6.0)) for _ in range(3))
    deceleration = acceleration if symmetric else draw(_decades(1.0, 6.0))
    return Limits(velocity, acceleration, deceleration, jerk)


@st.composite
def kinematic_states(
    draw: st.DrawFn,
    limits: Limits,
    beyond_limits: bool = False,
    velocity_probability: float = 0.9,
    acceleration_probability: float = 0.8,
) -> KinematicState:
    """A state with velocity and acceleration within ``limits`` (a fraction of them).

    Velocity is non-zero with ``velocity_probability``, acceleration with
    ``acceleration_probability`` (ruckig's 0.9 and 0.8). Acceleration is bounded by
    ``limits.acceleration`` while speeding up (or from rest) and ``limits.deceleration`` while
    slowing down. ``beyond_limits`` draws up to three times the limits (ruckig's brake
    pre-phase). A state within the limits may still be bound to exceed one (velocity overshoot
    while the acceleration is brought to zero): reject those with ``within_limits``.
    """
    reach = 3.0 if beyond_limits else 1.0
    fraction = st.floats(-reach, reach, allow_subnormal=False)
    position = _or_zero(draw, st.floats(-1e3, 1e3, allow_subnormal=False), 0.9)
    velocity = _or_zero(draw, fraction, velocity_probability) * limits.velocity
    share = _or_zero(draw, fraction, acceleration_probability)
    bound = limits.acceleration if share * velocity >= 0.0 else limits.deceleration
    return KinematicState(position, velocity, share * bound)


@st.composite
def _high_states(draw: st.DrawFn) -> KinematicState:
    """ruckig's high-limit test: positions ~ N(0, 4), dynamics ~ N(0, 0.8), mostly zero."""
    small = st.floats(-2.0, 2.0, allow_subnormal=False)
    return KinematicState(draw(st.floats(-16.0, 16.0, allow_subnormal=False)),
                          _or_zero(draw, small, 0.1), _or_zero(draw, small, 0.1))


@st.composite
def moves(draw: st.DrawFn, kind: MoveKind = "position", symmetric: bool = False,
          high: bool | None = None, onward: bool = False) -> MoveCase:
    """A start state, a target and limits.

    "position": with ``limits()``, a start state from ``kinematic_states`` and a target up to
    one second of travel at the velocity limit away (the same as the start with probability
    0.05); or with ``high_limits()``, ruckig's small positions and a state mostly at rest.
    ``high``: None mixes the two 9:1 (like ruckig's suite), True/False forces one.
    "velocity": a signed target velocity within the velocity limit (never 0: that is
    MC_Halt). "stop": brakes with ``limits.deceleration`` and ``limits.jerk``. Velocity
    moves and stops use ``limits()`` only: with high limits they would run for hours.
    ``onward``: the target (position, or velocity sign) lies in the direction of the start
    velocity, so the move need not reverse from the start (it still may by overshooting).
    """
    if high and kind != "position":
        raise ValueError("high limits are drawn for position moves only")
    if high is None:
        high = kind == "position" and draw(st.integers(0, 9)) == 9
    if high:
        lim = draw(high_limits(symmetric))
        start = draw(_high_states())
        target = draw(st.floats(-16.0, 16.0, allow_subnormal=False))
    else:
        lim = draw(limits(symmetric))
        start = draw(kinematic_states(lim))
        if kind == "position":
            travel = _or_zero(draw, st.floats(-1.0, 1.0, allow_subnormal=False), 0.95)
            target = start.position + travel * lim.velocity
        elif kind == "velocity":
            speed = draw(st.floats(1e-3, 1.0)) * lim.velocity
            target = speed if draw(st.booleans()) else -speed
        else:
            target = 0.0
    if onward and kind != "stop":
        origin = start.position if kind == "position" else 0.0
        if (target - origin) * start.velocity < 0.0:
            target = origin - (target - origin)  # mirrored onto the side the axis heads to
    return MoveCase(start, target, lim, kind)


def within_limits(state: KinematicState, limits: Limits, rel: float = REL) -> bool:
    """``state`` lies within ``limits`` and no limit has to be exceeded from it.

    Checks |v| <= velocity, |a| <= acceleration while speeding up (or from rest) and
    <= deceleration while slowing down, and that bringing the acceleration to zero with the
    jerk limit neither overshoots the velocity limit nor, while slowing down harder than
    ``limits.acceleration`` allows for speeding up, crosses zero velocity (after the crossing
    the axis would speed up with that acceleration).
    """
    v, a = state.velocity, state.acceleration
    slowing = a * v < 0.0
    bound = limits.deceleration if slowing else limits.acceleration
    if abs(v) > limits.velocity * (1 + rel) or abs(a) > bound * (1 + rel):
        return False
    if abs(v + a * abs(a) / (2.0 * limits.jerk)) > limits.velocity * (1 + rel):
        return False
    if slowing and abs(a) > limits.acceleration:
        velocity_lost = (a * a - limits.acceleration**2) / (2.0 * limits.jerk)
        return abs(v) >= velocity_lost * (1 + rel)
    return True


# -- the oracle -------------------------------------------------------------------------------


def _sign(value: float) -> int:
    return (value > 0.0) - (value < 0.0)


def _direction(case: MoveCase) -> int:
    """The direction plan.py maps acceleration and deceleration for (module docstring)."""
    if case.kind == "position":
        return _sign(case.target - case.start.position) or _sign(case.start.velocity)
    return _sign(case.target) or _sign(case.start.velocity)


def ruckig_trajectory(case: MoveCase) -> Trajectory:
    """ruckig's one-call trajectory for ``case``, with plan.py's acc/dec mapping.

    Speeding up in the direction of motion is bounded by ``acceleration``, slowing down by
    ``deceleration`` (mirrored for motion in -x); stops use their deceleration both ways.
    Raises ``ruckig.RuckigError`` when ruckig cannot plan the input.
    """
    start, lim = case.start, case.effective_limits
    inp = InputParameter(1)
    inp.current_position = [start.position]
    inp.current_velocity = [start.velocity]
    inp.current_acceleration = [start.acceleration]
    inp.target_acceleration = [0.0]
    if case.kind == "position":
        inp.control_interface = ControlInterface.Position
        inp.target_position = [case.target]
        inp.target_velocity = [0.0]
        inp.max_velocity = [lim.velocity]
    else:
        inp.control_interface = ControlInterface.Velocity
        inp.target_velocity = [case.target]
    up, down = lim.acceleration, lim.deceleration
    if _direction(case) < 0:
        up, down = down, up
    inp.max_acceleration = [up]
    inp.min_acceleration = [-down]
    inp.max_jerk = [lim.jerk]
    trajectory = Trajectory(1)
    Ruckig(1).calculate(inp, trajectory)
    return trajectory


def ruckig_duration(case: MoveCase) -> float:
    """Time-optimal duration [s] of ``case`` by ruckig (see ``ruckig_trajectory``)."""
    return float(ruckig_trajectory(case).duration)


def ruckig_reverses(case: MoveCase) -> bool:
    """The move reverses its direction of motion: the start velocity points away from the
    target, or ruckig's one-call profile crosses zero velocity (beyond plan.py's tolerance).

    With acceleration != deceleration such a profile cannot keep both limits, so openmotion
    turns through zero velocity in two pieces instead (docs/decisions.md D-201): ruckig's
    duration is then no reference (``openmotion.bench.otg_oracle`` is).
    """
    if case.start.velocity * _direction(case) < 0.0:
        return True
    profile = ruckig_trajectory(case).profiles[0][0]
    lo = hi = profile.v[0] if profile.brake.duration <= 0.0 else profile.brake.v[0]
    for phase in (profile.brake, profile, profile.accel):
        if phase is not profile and phase.duration <= 0.0:
            continue
        for k, dt in enumerate(phase.t):
            v0, a0, j = phase.v[k], phase.a[k], phase.j[k]
            candidates = [v0, v0 + dt * (a0 + dt * j / 2.0)]
            if j != 0.0 and 0.0 < -a0 / j < dt:
                tm = -a0 / j
                candidates.append(v0 + tm * (a0 + tm * j / 2.0))
            lo, hi = min(lo, *candidates), max(hi, *candidates)
    tolerance = _REVERSAL_TOLERANCE * max(abs(lo), abs(hi), 1.0)
    return hi > tolerance if _direction(case) < 0 else lo < -tolerance


def ceil_to_cycle(duration: float, cycle_time: float = 0.001) -> float:
    """``duration`` rounded up to whole cycles [s]: when a sampled setpoint can get there."""
    return math.ceil(duration / cycle_time) * cycle_time


# -- running ----------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SetpointTrace:
    """Setpoints of one axis, one sample per cycle; sample 0 is the state a command was
    planned from (the last sample before it), so ``time[k] = k * cycle_time`` after issue."""

    cycle_time: float
    position: np.ndarray  #: set position [mm]
    velocity: np.ndarray  #: [mm/s]
    acceleration: np.ndarray  #: [mm/s²]
    jerk: np.ndarray  #: [mm/s³]
    actual: np.ndarray  #: actual position [mm] (the drive model's output)
    time: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "time", np.arange(len(self.position)) * self.cycle_time)

    def __len__(self) -> int:
        return len(self.position)

    def peak(self, signal: str) -> float:
        """Largest magnitude of ``signal`` over the trace."""
        return float(np.max(np.abs(getattr(self, signal))))

    def arrival(self, value: float, signal: str = "position") -> float | None:
        """Time of the first sample from which ``signal`` stays bit-equal to ``value``."""
        values = getattr(self, signal)
        off = np.flatnonzero(values != value)
        if off.size == 0:
            return 0.0
        k = int(off[-1]) + 1
        return None if k == len(values) else k * self.cycle_time

    def reached(self, value: float, signal: str = "position") -> bool:
        """``signal`` is exactly ``value`` at the end, for at least the last two samples."""
        arrival = self.arrival(value, signal)
        return arrival is not None and arrival < self.time[-1]

    @property
    def duration(self) -> float:
        """Time until the motion is in its end state: velocity, acceleration and jerk at their
        final values from then on, and the position too when the end state is rest."""
        signals = ["velocity", "acceleration", "jerk"]
        if self.velocity[-1] == 0.0:
            signals.append("position")
        times = [self.arrival(float(getattr(self, s)[-1]), s) for s in signals]
        return max(t for t in times if t is not None)


class SetpointRecorder:
    """Observer that records one axis' setpoints each cycle, starting with the current one."""

    def __init__(self, runtime: Runtime, axis: Axis) -> None:
        self.cycle_time = runtime.cycle_time
        self.axis = axis
        self.samples: list[tuple[float, float, float, float, float]] = []
        self(runtime)
        runtime.add_observer(self)

    def __call__(self, runtime: Runtime) -> None:
        x = self.axis
        self.samples.append((x.set_position, x.set_velocity, x.set_acceleration, x.set_jerk,
                             x.position))

    def trace(self) -> SetpointTrace:
        columns = np.array(self.samples, dtype=float).reshape(-1, 5).T.copy()
        return SetpointTrace(self.cycle_time, *columns)


def single_axis(limits: Limits, cycle_time: float = 0.001, drive: DriveModel | None = None,
                position: float = 0.0, **parameters: object) -> tuple[Runtime, Axis]:
    """A runtime with one powered axis "x" whose defaults and maxima are ``limits``."""
    rt = Runtime(cycle_time)
    axis = rt.add_axis(
        "x", drive=drive, position=position, max_velocity=limits.velocity,
        acceleration=limits.acceleration, max_acceleration=limits.acceleration,
        deceleration=limits.deceleration, max_deceleration=limits.deceleration,
        jerk=limits.jerk, max_jerk=limits.jerk, **parameters,
    )
    axis.power(True)
    return rt, axis


def _place(axis: Axis, state: KinematicState) -> None:
    """Put the setpoint of a resting ``axis`` at ``state``, as the last sample.

    The one helper that reaches into the kernel: it installs a zero-jerk profile starting at
    ``state`` at the last sample time and re-samples, so that the next command is planned
    from exactly ``state``. Hook wanted from the kernel owner instead:
    ``Axis.place(state: KinematicState) -> None`` (standstill, no job: the setpoint state at
    the last sample becomes ``state`` and continues with zero jerk until the next command).
    """
    p, v, a = state.position, state.velocity, state.acceleration
    h = _PLACE_HORIZON
    profile = Profile(
        np.array([0.0, h]), np.array([p, p + h * (v + h * a / 2.0)]), np.array([v, v + h * a]),
        np.array([a, 0.0]), np.zeros(2),
    )
    axis.queue.install(profile, has_job=False)
    kernel = axis.kernel
    kernel.evaluate(kernel.sample_time)


def _issue(axis: Axis, case: MoveCase):  # noqa: ANN202 - Command
    lim = case.limits
    if case.kind == "position":
        return axis.move_absolute(case.target, lim.velocity, lim.acceleration, lim.deceleration,
                                  lim.jerk)
    if case.kind == "velocity":
        direction = Direction.POSITIVE if case.target > 0.0 else Direction.NEGATIVE
        return axis.move_velocity(abs(case.target), direction, lim.acceleration,
                                  lim.deceleration, lim.jerk)
    return axis.stop(lim.deceleration, lim.jerk)


def run_single_move(case: MoveCase, cycle_time: float = 0.001,
                    drive: DriveModel | None = None, settle_cycles: int = 5,
                    max_cycles: int = 200_000) -> SetpointTrace:
    """Run ``case`` on a fresh single-axis runtime and return the setpoints from issue on.

    The axis is sized to ``case.limits`` and placed at ``case.start`` exactly; the command is
    issued between cycles, so sample 0 is the start state. The runtime steps until the
    profile has ended, then ``settle_cycles`` more. A rejected command raises
    ``AssertionError`` (valid cases must be accepted).
    """
    rt, axis = single_axis(case.limits, cycle_time, drive, position=case.start.position)
    _place(axis, case.start)
    recorder = SetpointRecorder(rt, axis)
    command = _issue(axis, case)
    if command.error:
        raise AssertionError(f"{case.kind} command rejected: {command!r}")
    cycles = 0
    while axis.has_job and cycles < max_cycles:
        rt.step()
        cycles += 1
    for _ in range(settle_cycles):
        rt.step()
    return recorder.trace()


def run_schedule(runtime: Runtime, axis: Axis, schedule: Mapping[int, Callable[[], object]],
                 settle_cycles: int = 5, max_cycles: int = 200_000) -> SetpointTrace:
    """Record ``axis`` while ``schedule[k]()`` is called between cycles, after k cycles.

    Runs until every scheduled call is made and the axis is idle (no profile running, no
    command active except a MoveVelocity at speed), then ``settle_cycles`` more. Sample 0 is
    the setpoint before the first cycle.
    """
    recorder = SetpointRecorder(runtime, axis)
    last = max(schedule, default=0)
    for cycle in range(max_cycles):
        if cycle in schedule:
            schedule[cycle]()
        active = axis.active_command
        if cycle >= last and not axis.has_job and (active is None or active.in_velocity):
            break
        runtime.step()
    for _ in range(settle_cycles):
        runtime.step()
    return recorder.trace()


# -- assertions -------------------------------------------------------------------------------


def assert_traces_equal(a: SetpointTrace, b: SetpointTrace) -> None:
    """Bit-identical traces (same length, same float bits in every signal)."""
    assert a.cycle_time == b.cycle_time, f"cycle times {a.cycle_time} != {b.cycle_time}"
    assert len(a) == len(b), f"lengths {len(a)} != {len(b)}"
    for name in SIGNALS:
        x, y = getattr(a, name), getattr(b, name)
        differ = np.flatnonzero(x.view(np.uint64) != y.view(np.uint64))
        assert differ.size == 0, (
            f"{name} differs first at sample {differ[0]} (t={a.time[differ[0]]:.6g} s): "
            f"{x[differ[0]]!r} != {y[differ[0]]!r} ({differ.size} samples differ)"
        )


def assert_within_limits(trace: SetpointTrace, limits: Limits, rel: float = REL) -> None:
    """Every sample keeps ``limits`` within ``rel``: |v| <= velocity, |j| <= jerk, and |a| <=
    acceleration while speeding up (a·v > 0, or from rest) or deceleration while slowing down."""
    v, a, j = trace.velocity, trace.acceleration, trace.jerk
    slowing = a * v < 0.0
    bound = np.where(slowing, limits.deceleration, limits.acceleration)
    checks = (("velocity", np.abs(v), np.full(len(v), limits.velocity)),
              ("acceleration", np.abs(a), bound),
              ("jerk", np.abs(j), np.full(len(j), limits.jerk)))
    for name, value, limit in checks:
        over = np.flatnonzero(value > limit * (1 + rel))
        if over.size:
            k = int(over[0])
            phase = f" ({'slowing down' if slowing[k] else 'speeding up'})" \
                if name == "acceleration" else ""
            raise AssertionError(
                f"|{name}| {value[k]!r} > {limit[k]!r}{phase} at sample {k} "
                f"(t={trace.time[k]:.6g} s, v={v[k]!r}, a={a[k]!r}); "
                f"peak {value.max()!r}, {over.size} samples over"
            )


def assert_continuous(trace: SetpointTrace, acceleration: float, jerk: float,
                      rel: float = REL, tiny: float = 1e-12) -> None:
    """No jump between consecutive samples, switch cycles included.

    With ``dt`` the cycle time: |Δp - (v₀+v₁)·dt/2| <= jerk·dt³/12 (the trapezoid error of a
    C¹ velocity whose second derivative is bounded by ``jerk``), |Δv| <= acceleration·dt and
    |Δa| <= jerk·dt, each times (1 + ``rel``), plus ``tiny`` times the signal's scale
    (rounding) plus ruckig's absolute precision (``RUCKIG_PRECISION``): a profile's end is
    pinned to the commanded state, which ruckig reaches only to that precision.
    """
    dt = trace.cycle_time
    p, v, a = trace.position, trace.velocity, trace.acceleration
    scale_p = float(np.max(np.abs(p))) + trace.peak("velocity") * dt
    scale_v = trace.peak("velocity")
    scale_a = trace.peak("acceleration")
    eps_p, eps_v, eps_a = RUCKIG_PRECISION
    checks = (
        ("position", np.abs(np.diff(p) - (v[1:] + v[:-1]) * dt / 2.0),
         jerk * dt**3 / 12.0 * (1 + rel) + tiny * scale_p + eps_p),
        ("velocity", np.abs(np.diff(v)), acceleration * dt * (1 + rel) + tiny * scale_v + eps_v),
        ("acceleration", np.abs(np.diff(a)), jerk * dt * (1 + rel) + tiny * scale_a + eps_a),
    )
    for name, step, bound in checks:
        over = np.flatnonzero(step > bound)
        if over.size:
            k = int(over[0])
            raise AssertionError(
                f"{name} jumps between samples {k} and {k + 1} (t={trace.time[k]:.6g} s): "
                f"step {step[k]!r} > {bound!r}; p={p[k]!r}->{p[k + 1]!r}, "
                f"v={v[k]!r}->{v[k + 1]!r}, a={a[k]!r}->{a[k + 1]!r}"
            )


# -- planar set-ups -----------------------------------------------------------------------------

def enabled_movers(runtime: Runtime, *positions: tuple[float, float]) -> list[MC_PlanarMover]:
    """Planar movers standing at ``positions`` (x, y [mm]), enabled (five cycles run)."""
    from openmotion.planar import MC_PlanarMover, MoverVector, PlanarMoverParameters

    movers = [MC_PlanarMover(runtime, PlanarMoverParameters(initial_position=MoverVector(x, y)))
              for x, y in positions]
    for mover in movers:
        mover.enable()
    runtime.run(0.005)
    return movers


def grouped_field(nx: int, ny: int, starts: Sequence[tuple[float, float]],
                  holes: Collection[tuple[int, int]] = ()
                  ) -> tuple[Runtime, MC_PlanarEnvironment, MC_PlanarGroup, list[MC_PlanarMover]]:
    """An ``nx`` x ``ny`` stator field (leaving out the stators (i, j) in ``holes``) with
    movers m0, m1, ... enabled at ``starts`` [mm], they and the environment in one enabled
    group: where a router or a property test of a planar machine starts."""
    from openmotion.planar import (
        MC_PlanarEnvironment,
        MC_PlanarGroup,
        MC_PlanarMover,
        MoverVector,
        PlanarMoverParameters,
        PlanarState,
    )
    from openmotion.planar.stators import STATOR_SIZE

    runtime = Runtime()
    environment = MC_PlanarEnvironment(runtime)
    for i in range(nx):
        for j in range(ny):
            if (i, j) not in holes:
                environment.add_stator(STATOR_SIZE * i, STATOR_SIZE * j)
    environment.create_boundary()
    group = MC_PlanarGroup(runtime)
    group.enable()
    movers = [MC_PlanarMover(runtime, PlanarMoverParameters(initial_position=MoverVector(*s)),
                             name=f"m{k}") for k, s in enumerate(starts)]
    for mover in movers:
        mover.enable()
    runtime.run(0.002)
    for mover in movers:
        mover.add_to_group(group)
    environment.add_to_group(group)
    runtime.step()
    runtime.step()
    assert all(m.state is PlanarState.ENABLED and m.group is group for m in movers)
    return runtime, environment, group, movers


def enabled_line(runtime: Runtime, start: tuple[float, float], end: tuple[float, float],
                 after: MC_PlanarTrack | None = None, **parameters: object) -> MC_PlanarTrack:
    """A straight planar track from ``start`` to ``end`` [mm] (starting from the end of
    ``after`` when given), enabled; ``parameters`` go to ``MC_PlanarTrack``."""
    from openmotion.planar import MC_PlanarTrack, PlanarState, PositionXYC

    track = MC_PlanarTrack(runtime, **parameters)
    if after is not None:
        track.start_from_track(after)
    track.append_line(PositionXYC(*start), PositionXYC(*end))
    track.enable()
    assert runtime.run_until(lambda: track.state is PlanarState.ENABLED, timeout=1.0)
    return track


def enabled_loop(runtime: Runtime, **parameters: object) -> MC_PlanarTrack:
    """A closed planar track, enabled: a rectangle 960 x 720 mm with its corners rounded by
    the blends, starting at (0, 0) along +x, 3475.8 mm round; ``parameters`` go to
    ``MC_PlanarTrack``."""
    from openmotion.planar import MC_PlanarTrack, PlanarState, PositionXYC

    loop = MC_PlanarTrack(runtime, **parameters)
    for a, b in (((0.0, 0.0), (720.0, 0.0)), ((960.0, 240.0), (960.0, 480.0)),
                 ((720.0, 720.0), (0.0, 720.0)), ((-240.0, 480.0), (-240.0, 240.0))):
        loop.append_line(PositionXYC(*a), PositionXYC(*b))
    loop.close_loop()
    loop.enable()
    assert runtime.run_until(lambda: loop.state is PlanarState.ENABLED, timeout=1.0)
    assert loop.closed_loop
    return loop


def join_all(runtime: Runtime, track: MC_PlanarTrack, *movers: MC_PlanarMover) -> None:
    """Every mover joins ``track`` (in call order); runs until all joins are done."""
    joins = [mover.join_track(track) for mover in movers]
    assert runtime.run_until(lambda: all(join.done for join in joins), timeout=10.0)
