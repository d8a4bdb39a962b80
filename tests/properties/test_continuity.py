"""No jump in position, velocity or acceleration across aborts, overrides and blends.

style.md §4.3 (invariant "continuous across every abort and blend"). A move is interrupted at
a random cycle, including the cycles around its end, by another move (Aborting), a
MoveVelocity, a Stop or Halt, an override change, or a modification (MC_NewPos,
MC_NewPosAndVelo, MC_ChangeDynParam); and 2-3 moves run as a Blending*/Buffered sequence.
Every pair of consecutive samples, switch cycles included, satisfies
(``assert_continuous``):

* |Δp - (v₀+v₁)·dt/2| <= j_max·dt³/12 (trapezoid error of a C¹ velocity with |v''| <= j_max),
* |Δv| <= a_max·dt, |Δa| <= j_max·dt, each times (1 + 1e-9) plus rounding,

with a_max and j_max the largest acceleration/deceleration and jerk of the commands involved
(a replanned profile brakes an acceleration beyond its own limits with its own jerk).
"""

from __future__ import annotations

import math

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from openmotion.core.enums import BufferMode, Direction, NewPosAndVeloMode
from openmotion.plcopen import MC_SetOverride
from openmotion.testing import assert_continuous, limits, run_schedule, single_axis
from openmotion.trajectory.plan import Limits

CYCLE = 0.001

# hypothesis writes a patch for a failing example with libcst, whose import warns; under
# filterwarnings = error that would turn the falsifying example into a pytest INTERNALERROR.
pytestmark = pytest.mark.filterwarnings("ignore:mypy_extensions.TypedDict:DeprecationWarning")


def _envelope(*limit_sets: Limits) -> Limits:
    return Limits(*(max(getattr(x, name) for x in limit_sets)
                    for name in ("velocity", "acceleration", "deceleration", "jerk")))


def _bounds(*limit_sets: Limits) -> tuple[float, float]:
    env = _envelope(*limit_sets)
    return max(env.acceleration, env.deceleration), env.jerk


def _assert_smooth(trace, axis, *limit_sets: Limits) -> None:  # noqa: ANN001
    """Continuous at every sample, and within the axis limits: max_velocity is a hard limit
    (D-020: a switch raises a low jerk up to max_jerk rather than pass it)."""
    acceleration, jerk = _bounds(*limit_sets)
    assert_continuous(trace, acceleration, jerk)
    p = axis.parameters
    for name, limit in (("velocity", p.max_velocity), ("jerk", p.max_jerk),
                        ("acceleration", max(p.max_acceleration, p.max_deceleration))):
        assert trace.peak(name) <= limit * (1 + 1e-9), (
            f"|{name}| reaches {trace.peak(name)!r}, the axis limit is {limit!r}"
        )


def _move(axis, target: float, lim: Limits, mode: BufferMode = BufferMode.ABORTING):  # noqa: ANN001, ANN202
    return axis.move_absolute(target, lim.velocity, lim.acceleration, lim.deceleration,
                              lim.jerk, mode)


@st.composite
def first_moves(draw: st.DrawFn) -> tuple[Limits, float]:
    """Limits and a target from 0: up to one second of travel at the velocity limit."""
    lim = draw(limits())
    travel = draw(st.floats(-1.0, 1.0))
    return lim, travel * lim.velocity


@st.composite
def related_limits(draw: st.DrawFn, base: Limits) -> Limits:
    """Each limit of ``base`` times 0.5 to 2: interrupting commands with other dynamics, on
    the same time scale (a 100x slower second move would only make the test slow)."""
    factor = st.floats(-0.3, 0.3).map(lambda exponent: 10.0**exponent)
    return Limits(*(float(f"{getattr(base, name) * draw(factor):.3g}")
                    for name in ("velocity", "acceleration", "deceleration", "jerk")))


@st.composite
def move_pairs(draw: st.DrawFn) -> tuple[tuple[Limits, float], tuple[Limits, float]]:
    """A first move from 0 and a second one (limits related to the first, travel up to one
    second at its velocity limit from the first target)."""
    lim1, target1 = draw(first_moves())
    lim2 = draw(related_limits(lim1))
    return (lim1, target1), (lim2, draw(st.floats(-1.0, 1.0)) * lim2.velocity)


def _interrupt_cycle(axis, fraction: float) -> int:  # noqa: ANN001
    """A cycle from the start to a little past the end of the running profile."""
    return round(fraction * math.ceil(axis.remaining_time / CYCLE))


_fractions = st.floats(0.0, 1.1)


@given(pair=move_pairs(), fraction=_fractions)
def test_abort_by_move_is_continuous(pair, fraction):
    (lim1, target1), (lim2, travel2) = pair
    rt, axis = single_axis(_envelope(lim1, lim2), CYCLE)
    _move(axis, target1, lim1)
    k = _interrupt_cycle(axis, fraction)
    trace = run_schedule(rt, axis, {k: lambda: _move(axis, target1 + travel2, lim2)})
    _assert_smooth(trace, axis, lim1, lim2)


@given(pair=move_pairs(), speed=st.floats(0.01, 1.0), negative=st.booleans(),
       fraction=_fractions)
@example(  # a 1e-12 mm move ends at once, pinned to its target: a step within ruckig's precision
    pair=((Limits(1.0, 100.0, 100.0, 1e5), 1e-12), (Limits(1.0, 1000.0, 1000.0, 1e5), 0.0)),
    speed=1.0, negative=True, fraction=0.0)
def test_abort_by_move_velocity_is_continuous(pair, speed, negative, fraction):
    (lim1, target1), (second, _) = pair
    rt, axis = single_axis(_envelope(lim1, second), CYCLE)
    _move(axis, target1, lim1)
    k = _interrupt_cycle(axis, fraction)
    direction = Direction.NEGATIVE if negative else Direction.POSITIVE

    def interrupt() -> None:
        axis.move_velocity(speed * second.velocity, direction, second.acceleration,
                           second.deceleration, second.jerk)

    trace = run_schedule(rt, axis, {k: interrupt})
    _assert_smooth(trace, axis, lim1, second)


@given(pair=move_pairs(), own_dynamics=st.booleans(), halt=st.booleans(), fraction=_fractions)
def test_abort_by_stop_or_halt_is_continuous(pair, own_dynamics, halt, fraction):
    """MC_Stop or MC_Halt with their own deceleration and jerk, or with the defaults (Stop: 0,
    the running move's; Halt: the axis defaults, here the running move's too)."""
    (lim1, target1), (stop, _) = pair
    rt, axis = single_axis(_envelope(lim1, stop) if own_dynamics else lim1, CYCLE)
    _move(axis, target1, lim1)
    k = _interrupt_cycle(axis, fraction)
    dec, jerk = (stop.deceleration, stop.jerk) if own_dynamics else (0.0, 0.0)
    command = axis.halt if halt else axis.stop
    trace = run_schedule(rt, axis, {k: lambda: command(dec, jerk)})
    _assert_smooth(trace, axis, *((lim1, stop) if own_dynamics else (lim1,)))
    assert trace.velocity[-1] == 0.0 and trace.acceleration[-1] == 0.0


@given(pair=move_pairs(), how=st.sampled_from(["new_position", "new_position_and_velocity",
                                               "change_dynamics"]), fraction=_fractions)
def test_modification_is_continuous(pair, how, fraction):
    """MC_NewPos, MC_NewPosAndVelo (position and velocity) and MC_ChangeDynParam on the
    running move; a refused modification (TcMC §4.20's unsafe cases) leaves it running."""
    (lim1, target1), (lim2, travel2) = pair
    rt, axis = single_axis(_envelope(lim1, lim2), CYCLE)
    _move(axis, target1, lim1)
    k = _interrupt_cycle(axis, fraction)

    def modify() -> None:
        if how == "new_position":
            axis.new_position(target1 + travel2)
        elif how == "new_position_and_velocity":
            axis.new_position_and_velocity(NewPosAndVeloMode.CHANGE_POS_AND_VELO,
                                           target1 + travel2, lim2.velocity)
        else:
            axis.change_dynamics(lim2.acceleration, lim2.deceleration, lim2.jerk)

    trace = run_schedule(rt, axis, {k: modify})
    _assert_smooth(trace, axis, lim1, lim2)


@given(first=first_moves(), overrides=st.lists(st.floats(0.0, 100.0), min_size=1, max_size=3),
       fractions=st.lists(_fractions, min_size=3, max_size=3), by_block=st.booleans())
@example(  # ruckig could not plan a cruise at 4e-214 mm/s: ErrorStop (fixed, D-022)
    first=(Limits(1.0, 10.0, 10.0, 100.0), 1.0), overrides=[3.9411104200116837e-212],
    fractions=[0.0, 0.0, 0.0], by_block=False)
def test_override_change_is_continuous(first, overrides, fractions, by_block):
    """Up to three override changes (0-100 %) at random cycles, through axis.set_override or
    the MC_SetOverride block called in a program (planned in the cycle it is called)."""
    lim1, target1 = first
    rt, axis = single_axis(lim1, CYCLE)
    _move(axis, target1, lim1)
    block = MC_SetOverride(axis)
    pending: dict[int, float] = {}
    if by_block:
        rt.add_program(lambda: block(execute=rt.cycle + 1 in pending,
                                     override=pending.get(rt.cycle + 1, 100.0)))
    schedule = {}
    for percent, fraction in zip(overrides, fractions, strict=False):
        k = _interrupt_cycle(axis, fraction) + len(schedule)  # distinct cycles
        if by_block:
            pending[k] = percent
            schedule[k] = lambda: None
        else:
            schedule[k] = lambda percent=percent: axis.set_override(percent)
    last = max(schedule)
    schedule[last + 1] = lambda: axis.set_override(100.0)  # resume so the move can end
    pending.pop(last + 1, None)
    trace = run_schedule(rt, axis, schedule)
    _assert_smooth(trace, axis, lim1)
    assert axis.set_position == target1


@given(moves=st.lists(first_moves(), min_size=2, max_size=3),
       modes=st.lists(st.sampled_from([BufferMode.BLENDING_LOW, BufferMode.BLENDING_PREVIOUS,
                                       BufferMode.BLENDING_NEXT, BufferMode.BLENDING_HIGH,
                                       BufferMode.BUFFERED]), min_size=2, max_size=2))
@example(  # zero-length moves end in the cycle they start: the next starts a cycle late
    moves=[(Limits(1.0, 10.0, 10.0, 100.0), 0.0), (Limits(1.0, 10.0, 10.0, 100.0), 0.0),
           (Limits(1.0, 10.0, 10.0, 100.0), 1.0)],
    modes=[BufferMode.BLENDING_LOW, BufferMode.BLENDING_LOW])
@example(  # sub-cycle moves blended at speed: the middle one fails to plan (NO_PROFILE)
    moves=[(Limits(100.0, 1e6, 1e6, 1e9), 1e-4), (Limits(100.0, 1e6, 1e6, 1e9), 1e-4),
           (Limits(100.0, 1e6, 1e6, 1e9), 1.0)],
    modes=[BufferMode.BLENDING_NEXT, BufferMode.BLENDING_NEXT])
def test_blending_sequence_is_continuous(moves, modes):
    """2-3 moves issued together; each later one blends (or buffers) onto the one before.
    Travels are relative to the previous target, so both same-direction (blended at speed)
    and reversing pairs (blended at rest) occur."""
    rt, axis = single_axis(_envelope(*(lim for lim, _ in moves)), CYCLE)
    commands = []

    def issue() -> None:
        target = 0.0
        for index, (lim, travel) in enumerate(moves):
            target += travel
            mode = BufferMode.ABORTING if index == 0 else modes[index - 1]
            commands.append(_move(axis, target, lim, mode))

    trace = run_schedule(rt, axis, {0: issue})
    assert not any(command.error for command in commands), commands
    _assert_smooth(trace, axis, *(lim for lim, _ in moves))
    assert axis.set_position == sum(travel for _, travel in moves)
