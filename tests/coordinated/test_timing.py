"""The time law along a path (coordinated/timing.py; PLCopen Part 4 §5.3-§5.6, §5.13-§5.16,
§5.28; digest §5, §6.6).

The rules the time law guarantees, each checked analytically over every constant-jerk segment
it planned (``record=True``), not only at samples:

1. s, v and a are continuous; v >= 0; s never passes the path's end and ends on it bit for bit,
   at rest.
2. While s lies in piece k (junctions included), v, a and j keep piece k's caps (scaled by the
   override in effect) to 1e-9 relative.
3. At the end of piece k, v <= its exit cap; a cap of 0 (or a change of space) is an exact stop.
4. Time-optimal where it can be compared: one long piece takes ruckig's time; many short
   collinear pieces take as long as one piece of their length.
5. Deterministic: the same calls give the same samples bit for bit.

Then the events: appends while moving, stops (MC_GroupStop/Halt), interrupts and resumes
(MC_GroupInterrupt/Continue), overrides (MC_GroupSetOverride), and a dense path.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from openmotion.coordinated.timing import Piece, TimeLaw, Work
from openmotion.trajectory.plan import Limits, plan_position, plan_stop
from openmotion.trajectory.segments import KinematicState

CYCLE = 0.001
REL = 1e-9

# hypothesis writes a patch for a failing example with libcst, whose import warns
pytestmark = pytest.mark.filterwarnings("ignore:mypy_extensions.TypedDict:DeprecationWarning")

Factors = Callable[[float], tuple[float, float, float]]


# -- the analytic checker ---------------------------------------------------------------------


def _state(p: float, v: float, a: float, j: float, d: float) -> tuple[float, float, float]:
    return p + d * (v + d * (0.5 * a + d * j / 6.0)), v + d * (a + 0.5 * d * j), a + d * j


def _time_of(segment: tuple[float, float, float, float], duration: float, s: float) -> float:
    """When the (forward) segment reaches ``s``, by bisection."""
    lo, hi = 0.0, duration
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        lo, hi = (mid, hi) if _state(*segment, mid)[0] < s else (lo, mid)
    return hi


def _unscaled(_: float) -> tuple[float, float, float]:
    return 1.0, 1.0, 1.0


def violations(law: TimeLaw, pieces: list[Piece], factors: Factors = _unscaled) -> list[tuple]:
    """Every break of rules 1-3 in the legs ``law`` recorded, as readable tuples.

    A segment's stretch over piece k is found by inverting s(t); where that stretch is a
    sliver (round-off of the pinned leg ends, 1e-11 relative), only the continuous quantities
    are checked, at the segment end that touches the piece.
    """
    ends = np.cumsum([p.length for p in pieces])
    starts = np.concatenate(([0.0], ends[:-1]))
    rate_scale = max(max(p.acceleration, p.deceleration) for p in pieces)
    found: list[tuple] = []
    previous = None
    for t0, used, profile in law.history:
        t, p, v, a, j = profile.data
        if previous is not None:
            s1, v1, a1 = previous
            if (abs(p[0] - s1) > REL * max(abs(s1), 1.0) or abs(v[0] - v1) > REL * max(v1, 1.0)
                    or abs(a[0] - a1) > REL * rate_scale):
                found.append(("continuity", t0, (s1, v1, a1), (p[0], v[0], a[0])))
        for k in range(len(t)):
            if t[k] >= used:
                break
            end = min(t[k + 1] if k + 1 < len(t) else math.inf, used)
            segment = (p[k], v[k], a[k], j[k])
            if not math.isfinite(end):
                if v[k] != 0.0 or a[k] != 0.0:
                    found.append(("moving forever", t0, k))
                continue
            if end > t[k]:
                found += _segment_violations(segment, end - t[k], t0 + t[k], pieces, starts, ends,
                                             factors(t0 + t[k]))
        if math.isfinite(used):
            k = max(int(np.searchsorted(t, used, side="right")) - 1, 0)
            previous = _state(p[k], v[k], a[k], j[k], used - t[k])
        else:
            previous = None
    return found


def _segment_violations(segment: tuple[float, float, float, float], duration: float,
                        time: float, pieces: list[Piece], starts: np.ndarray, ends: np.ndarray,
                        factors: tuple[float, float, float]) -> list[tuple]:
    fv, fa, fj = factors
    p0, v0, a0, j0 = segment
    sa = p0
    sb, vb, ab = _state(*segment, duration)
    sliver, tight = 1e-11 * max(abs(sb), 1.0), 1e-12 * max(abs(sb), 1.0)
    found = []
    i = max(int(np.searchsorted(ends, sa - sliver, side="left")), 0)
    while i < len(pieces) and starts[i] <= sb + sliver:
        piece = pieces[i]
        v_max, acc, dec, jerk = (piece.velocity * fv, piece.acceleration * fa,
                                 piece.deceleration * fa, piece.jerk * fj)
        lo, hi = max(starts[i], sa), min(ends[i], sb)
        if hi - lo <= sliver:  # a touch at one end of the segment
            if lo <= hi + sliver:
                vt, at = (vb, ab) if abs(lo - sa) > abs(sb - hi) else (v0, a0)
                if vt > v_max * (1 + REL) or at > acc * (1 + REL) or at < -dec * (1 + REL):
                    found.append(("caps at a junction", time, i, vt, at))
            i += 1
            continue
        t1 = 0.0 if lo <= sa else _time_of(segment, duration, lo)
        t2 = duration if hi >= sb else _time_of(segment, duration, hi)
        speeds = [_state(*segment, t1)[1], _state(*segment, t2)[1]]
        if j0 != 0.0 and t1 < -a0 / j0 < t2:
            speeds.append(_state(*segment, -a0 / j0)[1])
        if max(speeds) > v_max * (1 + REL):
            found.append(("velocity", time, i, max(speeds), v_max))
        if min(speeds) < -REL * v_max:
            found.append(("backwards", time, i, min(speeds)))
        if max(a0 + j0 * t1, a0 + j0 * t2) > acc * (1 + REL):
            found.append(("acceleration", time, i, max(a0 + j0 * t1, a0 + j0 * t2), acc))
        if min(a0 + j0 * t1, a0 + j0 * t2) < -dec * (1 + REL):
            found.append(("deceleration", time, i, min(a0 + j0 * t1, a0 + j0 * t2), dec))
        if abs(j0) > jerk * (1 + REL):
            found.append(("jerk", time, i, j0, jerk))
        found += _exit_violations(segment, duration, time, i, pieces, ends, sa, sb, tight, fv)
        i += 1
    return found


def _exit_violations(segment: tuple[float, float, float, float], duration: float, time: float,
                     i: int, pieces: list[Piece], ends: np.ndarray, sa: float, sb: float,
                     tight: float, fv: float) -> list[tuple]:
    """Rule 3 at the end of piece i. A stop is checked by position (no motion through it),
    because inverting s(t) where the motion comes to rest is ill-conditioned."""
    if i == len(pieces) - 1:
        return []
    cap = pieces[i].exit_velocity * fv
    if pieces[i + 1].space != pieces[i].space:
        cap = 0.0
    if cap == 0.0:
        if sa < ends[i] - tight and sb > ends[i] + tight:
            return [("through a stop", time, i, sa, sb)]
        return []
    if sa <= ends[i] < sb:
        speed = _state(*segment, _time_of(segment, duration, ends[i]))[1]
        if speed > cap * (1 + REL) + 1e-6 * pieces[i].velocity * fv:
            return [("exit", time, i, speed, cap)]
    return []


# -- runs -------------------------------------------------------------------------------------


def run_to_end(law: TimeLaw, cycle: float = CYCLE, start: int = 1,
               limit: int = 2_000_000) -> tuple[float, list[tuple[float, float, float, float]]]:
    """Sample every cycle until done; the time it took and the samples."""
    samples = []
    for i in range(start, start + limit):
        samples.append(law.sample(i * cycle))
        if law.done:
            return i * cycle, samples
    raise AssertionError(f"not done after {limit} cycles: {samples[-1]}")


def line(length: float, velocity: float = 100.0, acceleration: float = 1000.0,
         deceleration: float = 1000.0, jerk: float = 1e4, exit_velocity: float = 0.0,
         space: int = 0) -> Piece:
    return Piece(length, velocity, acceleration, deceleration, jerk, exit_velocity, space)


def assert_rules(law: TimeLaw, pieces: list[Piece], factors: Factors = _unscaled) -> None:
    assert violations(law, pieces, factors) == []
    s, v, a, _ = law.sample(law._time)
    assert (s, v, a) == (law.length, 0.0, 0.0)


# -- rule 4: time-optimal ---------------------------------------------------------------------


@pytest.mark.parametrize("limits", [Limits(100.0, 1000.0, 1000.0, 1e4),
                                    Limits(250.0, 500.0, 2000.0, 5e3),
                                    Limits(2.0, 30.0, 10.0, 1e3)], ids=str)
@pytest.mark.parametrize("length", [0.01, 1.0, 100.0, 1000.0])
def test_one_piece_takes_ruckigs_time(limits, length):
    law = TimeLaw(0.0, record=True)
    pieces = [line(length, *(limits.velocity, limits.acceleration, limits.deceleration,
                             limits.jerk))]
    law.append(pieces)
    oracle = plan_position(KinematicState(0.0), length, limits).duration
    cycle = max(CYCLE, oracle / 2000)  # long moves: coarser cycles, the plan is the same
    duration, _ = run_to_end(law, cycle)
    assert duration <= math.ceil(oracle / cycle - 1e-9) * cycle + cycle + 1e-12
    assert_rules(law, pieces)


def _decades(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi).map(lambda exponent: float(f"{10.0 ** exponent:.3g}"))


@st.composite
def caps(draw: st.DrawFn) -> tuple[float, float, float, float]:
    """Caps spread over decades: velocity 1-1000 mm/s, acceleration and jerk from the time to
    reach them (1 ms to 0.3 s), deceleration 0.2-5 times the acceleration."""
    velocity = draw(_decades(0.0, 3.0))
    acceleration = float(f"{velocity / draw(_decades(-3.0, -0.5)):.3g}")
    deceleration = float(f"{acceleration * draw(_decades(-0.7, 0.7)):.3g}")
    jerk = float(f"{max(acceleration, deceleration) / draw(_decades(-3.0, -0.5)):.3g}")
    return velocity, acceleration, deceleration, jerk


@given(limits=caps(), length=_decades(-3.0, 3.0))
def test_one_piece_is_time_optimal_for_any_caps(limits, length):
    law = TimeLaw(0.0)
    law.append([line(length, *limits)])
    oracle = plan_position(KinematicState(0.0), length, Limits(*limits)).duration
    cycle = max(CYCLE, oracle / 2000)  # long moves: coarser cycles, the plan is the same
    duration, _ = run_to_end(law, cycle)
    assert duration <= math.ceil(oracle / cycle - 1e-9) * cycle + cycle + 1e-12


def test_short_collinear_pieces_run_like_one_piece():
    pieces = [line(0.1, exit_velocity=math.inf) for _ in range(999)] + [line(0.1)]
    law = TimeLaw(0.0, record=True)
    law.append(pieces)
    duration, samples = run_to_end(law)
    single = TimeLaw(0.0)
    single.append([line(100.0)])
    one, _ = run_to_end(single)
    assert max(v for _, v, _, _ in samples) == 100.0
    assert duration <= one * 1.01
    assert_rules(law, pieces)


def test_pieces_appended_one_by_one_before_the_start_run_like_one_piece():
    law = TimeLaw(0.0)
    for _ in range(99):
        law.append([line(1.0, exit_velocity=math.inf)])
    law.append([line(1.0)])
    duration, _ = run_to_end(law)
    single = TimeLaw(0.0)
    single.append([line(100.0)])
    assert duration <= run_to_end(single)[0] + CYCLE


# -- rules 1-3 on fixed paths -----------------------------------------------------------------


def test_exit_cap_zero_is_an_exact_stop_at_the_junction():
    pieces = [line(10.0, exit_velocity=0.0), line(10.0)]
    law = TimeLaw(0.0, record=True)
    law.append(pieces)
    run_to_end(law)
    assert any(profile.p[0] == 10.0 and profile.v[0] == 0.0 and profile.a[0] == 0.0
               for _, _, profile in law.history)  # a leg starts at rest on the junction
    assert_rules(law, pieces)


def test_a_change_of_space_is_a_stop():
    pieces = [line(10.0, exit_velocity=math.inf, space=0), line(10.0, space=1)]
    law = TimeLaw(0.0, record=True)
    law.append(pieces)
    run_to_end(law)
    assert any(profile.p[0] == 10.0 and profile.v[0] == 0.0 and profile.a[0] == 0.0
               for _, _, profile in law.history)
    assert_rules(law, pieces)


def test_a_slow_piece_between_fast_ones_is_run_at_its_cap():
    pieces = [line(50.0, exit_velocity=math.inf), line(5.0, velocity=20.0,
                                                        exit_velocity=math.inf), line(50.0)]
    law = TimeLaw(0.0, record=True)
    law.append(pieces)
    _, samples = run_to_end(law)
    inside = [v for s, v, _, _ in samples if 50.0 <= s <= 55.0]
    assert max(inside) <= 20.0
    assert max(v for _, v, _, _ in samples) == 100.0
    assert_rules(law, pieces)


def test_an_exit_cap_limits_the_junction_speed():
    pieces = [line(50.0, exit_velocity=30.0), line(50.0)]
    law = TimeLaw(0.0, record=True)
    law.append(pieces)
    run_to_end(law)
    assert_rules(law, pieces)
    t, s = _crossing(law, 50.0)
    assert law_speed(law, t) <= 30.0 * (1 + REL)


def _crossing(law: TimeLaw, position: float) -> tuple[float, float]:
    for t0, used, profile in law.history:
        if profile.p[0] <= position <= profile.p[-1]:
            k = max(int(np.searchsorted(profile.p, position, side="right")) - 1, 0)
            segment = (profile.p[k], profile.v[k], profile.a[k], profile.j[k])
            length = profile.t[k + 1] - profile.t[k] if k + 1 < len(profile.t) else used
            return t0 + profile.t[k] + _time_of(segment, length, position), position
    raise AssertionError(f"s never reached {position}")


def law_speed(law: TimeLaw, time: float) -> float:
    for t0, used, profile in law.history:
        if t0 <= time <= t0 + used:
            return profile.at(time - t0)[1]
    raise AssertionError(time)


# -- hypothesis: random paths and events ------------------------------------------------------


@st.composite
def pieces(draw: st.DrawFn, count: tuple[int, int] = (1, 50)) -> list[Piece]:
    """1-50 pieces, 1e-3 to 1e3 mm, caps over decades; exit caps 0, inf or in between;
    now and then a change of space."""
    result = []
    for _ in range(draw(st.integers(*count))):
        exit_velocity = draw(st.one_of(st.just(0.0), st.just(math.inf), _decades(0.0, 3.0)))
        result.append(Piece(draw(_decades(-3.0, 3.0)), *draw(caps()), exit_velocity,
                            draw(st.sampled_from([0] * 9 + [1]))))
    return result


def _cycle_for(path: list[Piece]) -> float:
    """A cycle that keeps runs to a few thousand samples: the plan does not depend on it."""
    estimate = sum(p.length / p.velocity + 2 * p.velocity / p.acceleration
                   + 2 * p.acceleration / p.jerk for p in path)
    return max(CYCLE, estimate / 2000)


@given(path=pieces())
def test_random_paths_keep_the_rules(path):
    law = TimeLaw(0.0, record=True)
    law.append(path)
    run_to_end(law, _cycle_for(path))
    assert_rules(law, path)


@given(path=pieces(), split=st.floats(0.0, 1.0), when=st.integers(0, 3000))
def test_appending_while_moving_keeps_the_rules(path, split, when):
    cut = max(1, round(split * len(path)))
    law = TimeLaw(0.0, record=True)
    law.append(path[:cut])
    cycle = _cycle_for(path)
    for i in range(1, when + 1):
        law.sample(i * cycle)
    law.append(path[cut:])
    run_to_end(law, cycle, start=when + 1)
    assert_rules(law, path)


EVENTS = st.lists(st.tuples(st.integers(1, 2500), st.sampled_from(
    ["stop", "interrupt", "resume", "override", "pause"]), _decades(0.0, 6.0),
    _decades(1.0, 8.0), st.floats(0.05, 1.5), st.floats(0.05, 1.5), st.floats(0.05, 1.5)),
    max_size=6)


@given(path=pieces(count=(1, 30)), events=EVENTS)
@example(path=[Piece(1.0, 1.0, 10.0, 10.0, 100.0, 0.0)] * 10
         + [Piece(1000.0, 1.0, 10.0, 10.0, 1e4, 0.0), Piece(1.0, 1.0, 3.16, 3.16, 31.6, 0.0)],
         events=[(1, "override", 1.0, 10.0, 1.0, 0.5, 1.0)])  # a last jerk phase of 2e-7 mm
@example(path=[Piece(1.0, 23.7, 2370.0, 2370.0, 23700.0, math.inf)]
         + [Piece(1.0, 1.0, 10.0, 10.0, 100.0, 0.0)] * 4,
         events=[(1, "stop", 1.0, 100.0, 1.0, 1.0, 1.0)])  # a gentle stop while a = -12.4
def test_stops_interrupts_and_overrides_keep_the_rules(path, events):
    run_events(path, events)


@pytest.mark.slow
@settings(max_examples=1000)
@given(path=pieces(count=(1, 30)), events=EVENTS)
def test_stops_interrupts_and_overrides_keep_the_rules_long(path, events):
    run_events(path, events)


def run_events(path: list[Piece], events: list[tuple], dense: bool = False) -> None:
    """Run ``path`` with the ``events`` at their cycles, then to its end, and check the
    rules. Override changes may keep the previous caps while the motion brakes into the new
    ones, so rule 2 is checked against the largest factors used so far."""
    law = TimeLaw(0.0, record=True)
    law.append(path, dense=dense)
    cycle = _cycle_for(path)
    largest = [1.0, 1.0, 1.0]
    history = [(0.0, (1.0, 1.0, 1.0))]
    schedule = {i: event for i, *event in sorted(events)}
    last = max(schedule, default=0)
    for i in range(1, 3_000_000):
        now = i * cycle
        law.sample(now)
        if i in schedule:
            kind, deceleration, jerk, *factors = schedule[i]
            if kind in ("stop", "interrupt"):
                law.stop(now, deceleration, jerk, keep=kind == "interrupt")
            elif kind == "resume":
                law.resume(now)
            else:
                factors[0] = 0.0 if kind == "pause" else factors[0]
                law.set_factors(now, *factors)
                largest = [max(x, y) for x, y in zip(largest, factors, strict=True)]
                history.append((now, tuple(largest)))
        if i > last:
            law.resume(now)
            if law._factors[0] == 0.0:
                law.set_factors(now, 1.0, *law._factors[1:])
                largest[0] = max(largest[0], 1.0)
                history.append((now, tuple(largest)))
            if law.done:
                break

    def factors_at(time: float) -> tuple[float, float, float]:
        return [f for t, f in history if t <= time + 1e-12][-1]

    assert_rules(law, path, factors_at)


def _alternating_path(slow: int) -> list[Piece]:
    """24 pieces: a fast start, a slowing piece with an exit cap, a crawl at 1 mm/s, then
    pieces alternating between 20 and 2 mm/s."""
    return [Piece(2.0, 20.0, 100.0, 100.0, 3348.0, math.inf),
            Piece(3.0, 18.0, 149.0, 149.0, 1000.0, 6.0),
            Piece(20.0, 1.0, 100.0, 100.0, 1008.0, 24.0)] + [
        Piece(1.0, 2.0 if k % 2 else 20.0, 100.0, 100.0, 1000.0, math.inf) for k in range(slow)]


def test_a_jerk_override_while_a_stop_waits_keeps_the_caps():
    """A stop that cannot brake yet follows the plan; a lower jerk factor set then must not
    make the next leg give up the junction speed the running leg was planned for. The rates
    the motion was planned with were forgotten as soon as that leg (planned under the old
    factors) ended, and the next leg entered the 1 mm/s piece at 13.5 mm/s."""
    run_events(_alternating_path(21), [(1, "stop", 10.0, 100.0, 1.0, 1.0, 1.0),
                                       (2, "override", 0.0, 0.0, 1.0, 1.0, 0.5)])


@st.composite
def alternating_pieces(draw: st.DrawFn) -> list[Piece]:
    """24 pieces alternating between fast and slow caps, exit caps open, closed or in
    between, one piece capped at 1 mm/s."""
    slow = draw(st.integers(0, 23))
    result = []
    for k in range(24):
        fast = k % 2 == 0
        velocity = 1.0 if k == slow else draw(
            st.floats(20.0, 300.0) if fast else st.floats(2.0, 60.0))
        rates = draw(st.floats(100.0, 5000.0))
        exit_velocity = draw(st.one_of(st.just(math.inf), st.just(0.0), st.floats(0.5, 50.0)))
        result.append(Piece(draw(st.floats(0.05, 20.0)), velocity, rates, rates,
                            draw(st.floats(1e3, 1e6)), exit_velocity))
    return result


@settings(max_examples=30)
@given(path=alternating_pieces(), when=st.integers(1, 300), later=st.integers(0, 300),
       kind=st.sampled_from(["stop", "interrupt"]), rates=st.tuples(
           st.floats(10.0, 1e5), st.floats(100.0, 1e8)), factors=st.sampled_from(
           [(1.0, 1.0, 0.5), (1.0, 0.5, 0.5), (0.5, 1.0, 0.5), (1.0, 1.0, 0.2)]))
def test_overrides_after_a_stop_keep_the_caps(path, when, later, kind, rates, factors):
    """A stop (or an interrupt) during a zone-timed path, then an override that lowers the
    jerk: every cap kept (the case above, found by this search)."""
    run_events(path, [(when, kind, *rates, 1.0, 1.0, 1.0),
                      (when + later, "override", 0.0, 0.0, *factors)])


# -- events -----------------------------------------------------------------------------------


def test_an_append_in_time_does_not_slow_the_cruise():
    first, second = [line(100.0, exit_velocity=math.inf)], [line(100.0)]
    law = TimeLaw(0.0, record=True)
    law.append(first)
    for i in range(1, 401):  # cruising at 100 mm/s by 0.4 s, long before the brake
        law.sample(i * CYCLE)
    law.append(second)
    duration, samples = run_to_end(law, start=401)
    at_once = TimeLaw(0.0)
    at_once.append(first + second)
    assert duration == run_to_end(at_once)[0]
    assert min(v for s, v, _, _ in samples if 50.0 < s < 150.0) == 100.0
    assert_rules(law, first + second)


def test_a_late_append_runs_on_from_the_brake_without_stopping():
    first, second = [line(20.0, exit_velocity=math.inf)], [line(100.0)]
    law = TimeLaw(0.0, record=True)
    law.append(first)
    i = 0
    while True:
        i += 1
        s, v, a, _ = law.sample(i * CYCLE)
        if a < 0.0 and v < 80.0:  # braking, not yet in the last jerk phase (v + a²/2j > 0)
            break
    law.append(second)
    _, samples = run_to_end(law, start=i + 1)
    assert min(v for s, v, _, _ in samples if s < 100.0) > 0.0
    assert_rules(law, first + second)


def test_appended_pieces_never_lower_the_caps_of_a_zone_already_planned():
    first = [line(100.0, exit_velocity=math.inf)]
    then = [line(1.0, exit_velocity=math.inf), line(1.0, velocity=90.0, exit_velocity=math.inf),
            line(50.0)]
    law = TimeLaw(0.0, record=True)
    law.append(first)
    for i in range(1, 301):
        law.sample(i * CYCLE)
    law.append(then)
    run_to_end(law, start=301)
    assert_rules(law, first + then)


def test_stop_brakes_at_once_and_drops_the_rest_of_the_path():
    path = [line(100.0, exit_velocity=math.inf), line(100.0)]
    law = TimeLaw(0.0, record=True)
    law.append(path)
    for i in range(1, 501):
        s, v, a, _ = law.sample(i * CYCLE)
    expected = plan_stop(KinematicState(s, v, a), 500.0, 1e4).p[-1]
    law.stop(500 * CYCLE, 500.0, 1e4, keep=False)
    duration, samples = run_to_end(law, start=501)
    assert law.length == expected == samples[-1][0]
    assert all(b[1] <= a[1] for a, b in zip(samples, samples[1:], strict=False))
    assert law.locate(law.length) == (0, expected)  # piece 0 ends there, piece 1 is gone
    assert_rules(law, path)
    law.append([line(10.0)])  # the next motion starts where the stop ended
    run_to_end(law, start=round(duration / CYCLE) + 1)
    assert law.length == expected + 10.0


def test_stop_keeps_the_plan_when_the_path_ends_sooner():
    path = [line(5.0)]
    law = TimeLaw(0.0, record=True)
    law.append(path)
    for i in range(1, 101):
        law.sample(i * CYCLE)
    law.stop(100 * CYCLE, 10.0, 1e4, keep=False)  # far too gentle for the 5 mm left
    run_to_end(law, start=101)
    assert law.length == 5.0
    assert_rules(law, path)


def test_interrupt_stands_still_and_resume_reaches_the_end():
    path = [line(100.0)]
    law = TimeLaw(0.0, record=True)
    law.append(path)
    for i in range(1, 301):
        law.sample(i * CYCLE)
    law.stop(300 * CYCLE, 1000.0, 1e4, keep=True)
    for i in range(301, 801):
        law.sample(i * CYCLE)
    assert law.standing and not law.done
    assert law.length == 100.0
    law.resume(800 * CYCLE)
    run_to_end(law, start=801)
    assert_rules(law, path)


def test_override_zero_pauses_and_override_again_continues():
    path = [line(100.0)]
    law = TimeLaw(0.0, record=True)
    law.append(path)
    for i in range(1, 301):
        law.sample(i * CYCLE)
    law.set_factors(300 * CYCLE, velocity=0.0)
    for i in range(301, 801):
        law.sample(i * CYCLE)
    assert law.standing and not law.done
    law.resume(800 * CYCLE)  # MC_GroupContinue does not lift an override of 0
    law.sample(801 * CYCLE)
    assert law.standing
    law.set_factors(801 * CYCLE, velocity=1.0)
    run_to_end(law, start=802)
    assert_rules(law, path)


def test_half_override_halves_the_cruise():
    path = [line(1000.0)]
    law = TimeLaw(0.0, record=True)
    law.append(path)
    for i in range(1, 501):
        law.sample(i * CYCLE)
    law.set_factors(500 * CYCLE, velocity=0.5)
    speeds = [law.sample(i * CYCLE)[1] for i in range(501, 1500)]
    assert speeds[-1] == 50.0
    assert all(b <= a for a, b in zip(speeds, speeds[1:], strict=False))
    run_to_end(law, start=1500)
    assert_rules(law, path, lambda t: (1.0, 1.0, 1.0))


def test_rest_point_is_where_the_stop_ends():
    path = [line(30.0, exit_velocity=math.inf), line(30.0, deceleration=200.0)]
    law = TimeLaw(0.0)
    law.append(path)
    for i in range(1, 251):
        law.sample(i * CYCLE)
    predicted = law.rest_point()
    law.stop(250 * CYCLE, math.inf, math.inf, keep=True)
    for i in range(251, 2000):
        s, *_ = law.sample(i * CYCLE)
    assert s == predicted


def test_locate_counts_pieces_from_the_first_append():
    law = TimeLaw(0.0)
    law.append([line(1.0, exit_velocity=math.inf), line(2.0, exit_velocity=math.inf)])
    law.append([line(3.0)])
    assert law.length == 6.0
    assert law.locate(0.0) == (0, 0.0)
    assert law.locate(1.0) == (1, 0.0)
    assert law.locate(4.5) == (2, 1.5)
    assert law.locate(6.0) == (2, 3.0)


def test_the_same_calls_give_the_same_samples():
    def run() -> list[tuple[float, float, float, float]]:
        law = TimeLaw(0.0)
        law.append([line(10.0, exit_velocity=math.inf), line(0.3, velocity=30.0,
                                                             exit_velocity=math.inf)])
        samples = [law.sample(i * CYCLE) for i in range(1, 50)]
        law.append([line(40.0)])
        law.set_factors(60 * CYCLE, 0.7, 0.8, 0.9)
        samples += [law.sample(i * CYCLE) for i in range(60, 200)]
        law.stop(200 * CYCLE, 800.0, 9e3, keep=True)
        law.resume(400 * CYCLE)
        return samples + run_to_end(law, start=400)[1]

    assert run() == run()


def test_dense_circle_runs_as_one_zone_near_the_cap():
    """10 000 chords with small blends whose caps alternate beyond 0.8: the blends bind, the
    short chords between them take the blend cap (the bump rule), so the whole path is one
    zone and one cheap leg after another."""
    length = 2.0 * math.pi * 100.0 / 10_000
    path = []
    for _ in range(10_000):
        path.append(line(0.8 * length, exit_velocity=math.inf))
        path.append(line(0.2 * length, velocity=70.0, acceleration=800.0, deceleration=800.0,
                         jerk=8e3, exit_velocity=math.inf))
    path[-1] = line(0.2 * length, velocity=70.0, acceleration=800.0, deceleration=800.0,
                    jerk=8e3)
    law = TimeLaw(0.0)
    law.append(path)
    work = Work()
    for i in range(1, 100_000):
        law.sample(i * CYCLE)
        work = max(work, law.last_work, key=lambda w: w.zones + w.legs + w.pieces)
        if law.done:
            break
    assert law.length / (i * CYCLE) > 0.95 * 70.0
    assert work.zones <= 2 and work.legs <= 2 and work.ruckig == 0


# -- a dense path's profile (dense_timing.py, D-335) -------------------------------------------


def dense_path(pairs: int = 400) -> list[Piece]:
    """Lines of 0.05 mm between contours of 0.1 mm, as MC_PathSelect makes them: the lines
    with the axes' whole rates, the contours with speed caps that change along the path
    (a slow stretch down to a tenth of the rest) and little jerk."""
    path = []
    for k in range(pairs):
        phase = 2.0 * math.pi * k / pairs
        cap = 80.0 * (1.0 + 0.4 * math.cos(3.0 * phase)) * (1.0 - 0.85 * math.exp(
            -((phase - 4.0) / 0.15) ** 2))
        path.append(line(0.05, velocity=250.0, acceleration=5000.0, deceleration=5000.0,
                         jerk=1e6, exit_velocity=math.inf))
        path.append(line(0.1, velocity=cap, acceleration=2000.0, deceleration=2000.0,
                         jerk=1e4, exit_velocity=math.inf))
    path[-1] = line(0.1, velocity=path[-1].velocity, acceleration=2000.0, deceleration=2000.0,
                    jerk=1e4)
    return path


def test_a_dense_profile_keeps_the_rules_and_beats_the_zones():
    """The profile holds the acceleration on each piece and changes it on the lines: every
    cap kept on every segment, the end exact, and faster than the zones (which run each
    stretch at its smallest cap and return to a = 0 between stretches)."""
    path = dense_path()
    dense = TimeLaw(0.0, record=True)
    dense.append(path, dense=True)
    dense_time, _ = run_to_end(dense)
    assert_rules(dense, path)
    zones = TimeLaw(0.0)
    zones.append(path)
    zone_time, _ = run_to_end(zones)
    assert dense_time < 0.9 * zone_time
    assert len(dense.history) <= 2  # the profile, then the rest at the end


def test_a_dense_profile_that_breaks_a_cap_is_not_used(monkeypatch):
    """Each profile is checked against its pieces' caps before it runs; one that fails runs
    by zones instead, exactly as a path appended without ``dense``."""
    path = dense_path(100)
    monkeypatch.setattr("openmotion.coordinated.timing.check", lambda *args: 0)
    refused = TimeLaw(0.0)
    refused.append(path, dense=True)
    zones = TimeLaw(0.0)
    zones.append(path)
    assert run_to_end(refused) == run_to_end(zones)


def test_a_dense_profile_needs_a_law_at_rest_without_override():
    """Appended to a law that moves, that has run, or under an override, dense pieces run by
    zones, exactly as without ``dense``."""
    path = dense_path(100)
    for setup in (lambda law: law.set_factors(0.0, 0.5), lambda law: law.append(path[:10]),
                  lambda law: law.sample(0.0)):
        dense, plain = TimeLaw(0.0), TimeLaw(0.0)
        for law, flag in ((dense, True), (plain, False)):
            setup(law)
            law.append(path[10:], dense=flag)
        assert run_to_end(dense) == run_to_end(plain)
    moving, plain = TimeLaw(0.0, start_velocity=10.0), TimeLaw(0.0, start_velocity=10.0)
    moving.append(path, dense=True)
    plain.append(path)
    assert run_to_end(moving) == run_to_end(plain)


def test_events_during_a_dense_profile():
    """A stop brakes the profile at once (D-362); an override change pauses
    the profile and runs on by zones under the new factors; pieces appended while it runs
    follow its end, where it rests (D-335). Every cap kept throughout."""
    path = dense_path()
    stopped = TimeLaw(0.0, record=True)
    stopped.append(path, dense=True)
    for i in range(1, 300):
        stopped.sample(i * CYCLE)
    stopped.stop(300 * CYCLE, 5000.0, 1e6, keep=False)
    run_to_end(stopped, start=300)
    assert_rules(stopped, path[:len(path)])
    assert stopped.length < sum(p.length for p in path)  # the path ends where it rested
    overridden = TimeLaw(0.0, record=True)
    overridden.append(path, dense=True)
    for i in range(1, 300):
        overridden.sample(i * CYCLE)
    overridden.set_factors(300 * CYCLE, 0.5)
    top = max(overridden.sample(i * CYCLE)[1] for i in range(300, 3000))
    assert_rules(overridden, path, lambda t: (1.0, 1.0, 1.0))
    run_to_end(overridden, start=3000)
    assert top <= 80.0 * 1.4  # never above the caps it had (the largest contour cap)
    grown = TimeLaw(0.0, record=True)
    grown.append(path[:-2], dense=True)
    for i in range(1, 300):
        grown.sample(i * CYCLE)
    grown.append(path[-2:])
    run_to_end(grown, start=300)
    assert_rules(grown, path)


def brake_after_stop(law: TimeLaw, when: int, cycle: float = CYCLE) -> list[tuple]:
    """Sample from cycle ``when`` (the stop's) until the motion stands; the samples that
    break the stop's promise (D-362): the acceleration rising while positive, or the speed
    rising once the acceleration was <= 0."""
    broken, previous = [], law.sample(when * cycle)
    for i in range(when + 1, when + 1_000_000):
        current = law.sample(i * cycle)
        if current[2] > 0.0 and current[2] > previous[2] * (1.0 + REL) + REL:
            broken.append(("acceleration rises", i, previous, current))
        if previous[2] <= 0.0 and current[1] > previous[1] * (1.0 + REL) + REL:
            broken.append(("speed rises", i, previous, current))
        previous = current
        if law.standing:
            return broken
    raise AssertionError("the stop never came to rest")


@pytest.mark.parametrize("when", [50, 240, 300, 500, 680, 900])
def test_a_stop_during_a_dense_profile_brakes_at_once(when):
    """MC_GroupStop during a dense path's profile brakes from the cycle it is given, the
    acceleration falling at once with each piece's jerk cap, every cap kept (D-362). The
    cycles are where the profile speeds up (50, 240, 300, 500, 680) or eases a brake (900):
    it used to run on along the profile, speeding up, until a brake with one set of rates
    kept every cap."""
    path = dense_path()
    law = TimeLaw(0.0, record=True)
    law.append(path, dense=True)
    for i in range(1, when):
        law.sample(i * CYCLE)
    law.stop(when * CYCLE, 5000.0, 1e6, keep=False)
    assert brake_after_stop(law, when) == []
    run_to_end(law, start=round(law._time / CYCLE) + 1)
    assert_rules(law, path)
    assert law.length < sum(p.length for p in path)


@st.composite
def dense_pieces(draw: st.DrawFn) -> list[Piece]:
    """16-60 alternating lines and contours with random caps, all junctions open."""
    result = []
    for k in range(draw(st.integers(16, 60))):
        fast = k % 2 == 0
        velocity = draw(st.floats(100.0, 300.0) if fast else st.floats(1.0, 120.0))
        rates = draw(st.floats(500.0, 5000.0))
        result.append(Piece(draw(st.floats(0.005, 0.3)), velocity, rates, rates * draw(
            st.floats(0.3, 3.0)), draw(st.floats(1e5, 1e6) if fast else st.floats(1e3, 1e5)),
            math.inf))
    return result


@given(path=dense_pieces(), events=EVENTS)
def test_dense_profiles_with_stops_interrupts_and_overrides_keep_the_rules(path, events):
    run_events(path, events, dense=True)


@settings(max_examples=15)
@given(path=dense_pieces(), when=st.floats(0.0, 1.0), keep=st.booleans(),
       rates=st.sampled_from([(math.inf, math.inf), (1e4, 1e7), (100.0, 1e4)]))
def test_stops_during_dense_profiles_never_speed_up(path, when, keep, rates):
    """Wherever a stop (or an interrupt) falls on a random dense path, whatever its rates:
    the motion never speeds up along the path beyond letting go of the acceleration it
    had, and keeps every cap (D-362)."""
    cycle = 0.0005
    duration = TimeLaw(0.0)
    duration.append(path, dense=True)
    end = round(run_to_end(duration, cycle)[0] / cycle)
    law = TimeLaw(0.0, record=True)
    law.append(path, dense=True)
    stop = max(1, round(when * end))
    for i in range(1, stop):
        law.sample(i * cycle)
    law.stop(stop * cycle, *rates, keep=keep)
    assert brake_after_stop(law, stop, cycle) == []
    law.resume(law._time)
    run_to_end(law, cycle, start=round(law._time / cycle) + 1)
    assert violations(law, path) == []


# -- refusals ---------------------------------------------------------------------------------


@pytest.mark.parametrize("piece", [line(0.0), line(1.0, velocity=0.0), line(1.0, jerk=-1.0),
                                   line(math.inf), line(1.0, exit_velocity=-1.0),
                                   line(1.0, exit_velocity=math.nan)])
def test_bad_pieces_are_refused(piece):
    with pytest.raises(ValueError):
        TimeLaw(0.0).append([piece])


def test_bad_calls_are_refused():
    law = TimeLaw(1.0)
    law.append([line(1.0)])
    law.sample(2.0)
    with pytest.raises(ValueError):
        law.sample(1.5)
    with pytest.raises(ValueError):
        law.set_factors(2.0, acceleration=0.0)
    with pytest.raises(ValueError):
        law.stop(2.0, 0.0, 1.0, keep=False)
    with pytest.raises(ValueError):
        TimeLaw(0.0, start_velocity=-1.0)


def test_a_dense_profile_never_reaches_a_slow_piece_still_accelerating() -> None:
    """Found by the nightly profile: the profile's tail began at the 1 mm/s cap with the
    acceleration still rising (42 mm/s²), so ruckig's brake to the end passed 1.9 mm/s."""
    head = [(0.19582961772890736, 100.0, 500.0, 350.0, 1e5),
            (0.019969283108408863, 73.23622352109602, 4036.7297342097445, 3304.4992091774707,
             1e3),
            (0.17660949776719503, 100.0, 500.0, 1464.912614173094, 1e5),
            (0.15276704268680438, 1.0, 500.0, 996.7500252752438, 70963.79824680975),
            (0.3, 100.0, 500.0, 150.0, 1e5),
            (0.13224016918513723, 1.0, 500.0, 1471.1394240585823, 24552.413466501486),
            (0.3, 100.0, 500.0, 150.0, 1e5),
            (0.005, 1.7988498246958904, 500.0, 150.0, 1e3),
            *[(0.005, 100.0, 500.0, 150.0, 1e5), (0.005, 1.0, 500.0, 150.0, 1e3)] * 2,
            (0.005, 100.0, 500.0, 150.0, 1e5),
            (0.005, 2.028206285905543, 2907.994682280403, 872.3984046841209, 1e3),
            (0.005, 100.0, 500.0, 150.0, 1e5)]
    tail = [(0.3, 1.0, 500.0, 150.0, 1e3), (0.3, 100.0, 500.0, 150.0, 1e5)] * 18
    path = [Piece(*row, math.inf, 0) for row in head + tail]
    run_events(path, [], dense=True)
