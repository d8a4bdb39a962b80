"""Equivalence of two paths (style.md §4.4): our stored segments against ruckig, and our two
evaluators (``Profile.at`` and the numpy ``SegmentTable``) against each other.

Profiles come from plan.py for random limits and start states, also beyond the limits, where
ruckig prepends a brake pre-phase, and with acc != dec, where a reversal becomes a turn
through zero velocity (two ruckig pieces, D-201; those have no single ruckig trajectory to
compare with).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, example, given, reject
from hypothesis import strategies as st
from ruckig import RuckigError

from openmotion.core.errors import CommandRejected
from openmotion.testing import (
    MoveCase,
    kinematic_states,
    limits,
    ruckig_reverses,
    ruckig_trajectory,
)
from openmotion.trajectory.evaluate import SegmentTable
from openmotion.trajectory.plan import Limits, plan_position, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

REL = 1e-9
#: ruckig reaches a target position to this absolute precision (its p_precision); the
#: profile's open segment is then pinned to the exact target (plan.py)
RUCKIG_POSITION_PRECISION = 1e-8

# hypothesis writes a patch for a failing example with libcst, whose import warns; under
# filterwarnings = error that would turn the falsifying example into a pytest INTERNALERROR.
pytestmark = pytest.mark.filterwarnings("ignore:mypy_extensions.TypedDict:DeprecationWarning")


@st.composite
def planned_cases(draw: st.DrawFn) -> MoveCase:
    """A position or velocity move from a state within or (half the time) beyond the limits."""
    kind = draw(st.sampled_from(["position", "velocity"]))
    lim = draw(limits())
    start = draw(kinematic_states(lim, beyond_limits=draw(st.booleans())))
    if kind == "position":
        target = start.position + draw(st.floats(-1.0, 1.0)) * lim.velocity
    else:
        target = draw(st.floats(-1.0, 1.0)) * lim.velocity
    return MoveCase(start, target, lim, kind)


def _plan(case: MoveCase) -> Profile:
    try:
        if case.kind == "position":
            return plan_position(case.start, case.target, case.limits)
        return plan_velocity(case.start, case.target, case.limits)
    except CommandRejected:
        reject()  # ruckig cannot plan this input; test_moves reports rejections


def _sanitised(case: MoveCase) -> MoveCase:
    """The start state plan.py hands to ruckig (D-021): an acceleration below 1e-10 of the
    limits is evaluation residue (0), a velocity within 1e-12 of the limit is the limit."""
    start, lim = case.start, case.limits
    velocity, acceleration = start.velocity, start.acceleration
    if abs(acceleration) <= 1e-10 * max(lim.acceleration, lim.deceleration):
        acceleration = 0.0
    if abs(abs(velocity) - lim.velocity) <= 1e-12 * lim.velocity:
        velocity = math.copysign(lim.velocity, velocity)
    return replace(case, start=KinematicState(start.position, velocity, acceleration))


def _single_call(case: MoveCase):  # noqa: ANN202 - ruckig.Trajectory
    """ruckig's trajectory for ``case`` when plan.py used exactly that one call: not for a
    position move that starts above the velocity limit towards its target (ramped down to
    the limit first, D-021); with acc != dec not where the move reverses (start velocity, or
    at rest the start acceleration, pointing away from the target, or an overshoot: a turn
    through zero velocity, D-201)."""
    start, lim = case.start, case.limits
    heading = np.sign(case.target - start.position) if case.kind == "position" else 0.0
    heading = heading or np.sign(case.target) or np.sign(start.velocity)
    if case.kind == "position":
        assume(not (abs(start.velocity) > lim.velocity and np.sign(start.velocity) == heading))
    try:
        trajectory = ruckig_trajectory(_sanitised(case))
        reverses = ruckig_reverses(case)
    except RuckigError:
        reject()
    if case.limits.acceleration != case.limits.deceleration:
        assume(not reverses)
        assume((np.sign(start.velocity) or np.sign(start.acceleration)) * heading >= 0.0)
    return trajectory


def _times(draw: st.DrawFn, profile: Profile, count: int = 40) -> np.ndarray:
    """Increasing times: random ones past the end, plus every segment boundary and its
    neighbours."""
    horizon = 1.2 * profile.duration + 1e-3
    random = draw(st.lists(st.floats(0.0, horizon), min_size=1, max_size=count))
    edges = np.concatenate([profile.t, profile.t * (1 - 1e-12), profile.t + 1e-9])
    return np.unique(np.concatenate([np.asarray(random), edges[edges >= 0.0]]))


def _scales(profile: Profile, samples: np.ndarray) -> tuple[float, float, float]:
    """Natural magnitudes of position, velocity and acceleration: the largest values at the
    segment boundaries (ruckig's arrays; a is piecewise linear) and at the samples."""
    return tuple(
        max(float(np.max(np.abs(x))), float(np.max(np.abs(y))), 1e-300)
        for x, y in zip((profile.p, profile.v, profile.a), samples, strict=True)
    )


def _close(ours: np.ndarray, theirs: np.ndarray, what: str, scale: float, rate: float = 0.0,
           clock: float = 0.0, rel: float = REL) -> None:
    """Equal within ``rel`` of the signal's natural magnitude ``scale``, plus what the clock's
    resolution allows: the table works in absolute time, so a sample ``t`` after the row's
    start is off by a few ulp of ``clock`` (the absolute time), times the signal's ``rate``."""
    if ours.size == 0:
        return
    tolerance = rel * scale + rate * 8.0 * float(np.spacing(clock))
    error = np.abs(ours - theirs)
    k = int(np.argmax(error))
    assert error[k] <= tolerance, (
        f"{what}: {ours[k]!r} != {theirs[k]!r} (error {error[k]:.3g}, scale {scale:.3g}, "
        f"tolerance {tolerance:.3g}) at sample {k}"
    )


def _rates(samples: np.ndarray, profile: Profile) -> tuple[float, float, float]:
    """Largest |v|, |a|, |j|: how fast position, velocity and acceleration change."""
    return (float(np.max(np.abs(samples[1]))), float(np.max(np.abs(samples[2]))),
            float(np.max(np.abs(profile.j))))


def _table_samples(profiles: list[Profile], offsets: list[float], times: np.ndarray):
    """Evaluate every profile in one SegmentTable (row i installed at ``offsets[i]``) at
    ``offsets[i] + times`` per row... all rows share the clock, so sample at common instants
    and return, per row, the times relative to its offset and the p, v, a samples."""
    table = SegmentTable(capacity=2)  # grows: exercises _allocate
    rows = [table.add(profile.end, 0.0) for profile in profiles]
    for row, profile, offset in zip(rows, profiles, offsets, strict=True):
        table.install(row, profile, offset)
    start = max(offsets)
    out = np.zeros((len(rows), 3, len(times)))
    p, v, a, j = (np.zeros(table.capacity) for _ in range(4))
    n = len(rows)
    for i, time in enumerate(times):
        table.evaluate(start + time, p, v, a, j)
        out[:, 0, i], out[:, 1, i], out[:, 2, i] = p[:n], v[:n], a[:n]
    return [(start + times) - offset for offset in offsets], out


def _at_end_band(relative: np.ndarray, profile: Profile, clock: float) -> np.ndarray:
    """Samples within the clock's resolution of the profile end, where the table (absolute
    time) may evaluate either the last moving segment or the open one."""
    return np.abs(relative - profile.duration) <= 8.0 * float(np.spacing(clock))


def _reference(ours: np.ndarray, moving: np.ndarray, pinned: np.ndarray,
               band: np.ndarray) -> np.ndarray:
    """What the table must match: the moving reference before the end (NaN after it), the
    pinned end state after it, and in the end band whichever of the two it is nearer to
    (they differ by the end pin: ruckig reaches the commanded end only to its own
    precision)."""
    nearer = np.where(np.abs(ours - moving) <= np.abs(ours - pinned), moving, pinned)
    return np.where(band, nearer, np.where(np.isnan(moving), pinned, moving))


def _pinned(profile: Profile, relative: np.ndarray) -> np.ndarray:
    return np.array([profile.at(max(float(t), profile.duration))[:3] for t in relative]).T


@given(case=planned_cases(), data=st.data())
def test_segment_table_matches_ruckig_at_time(case, data):
    """SegmentTable rows, installed at a random absolute time (up to hours of run time),
    give ruckig's ``Trajectory.at_time`` within 1e-9 relative, brake pre-phases included.

    After the end the row holds the commanded end state exactly (plan.py pins it; ruckig
    reaches it only to its own precision, p_precision = 1e-8 absolute).
    """
    trajectory = _single_call(case)
    profile = _plan(case)
    times = _times(data.draw, profile)
    offset = data.draw(st.sampled_from([0.0, 0.001, 3600.0]) | st.floats(0.0, 1e4))
    relative, samples = _table_samples([profile], [offset], times)
    rel_t, ours = relative[0], samples[0]
    clock = offset + float(times[-1])
    band = _at_end_band(rel_t, profile, clock)
    before = rel_t < profile.duration
    theirs = np.array([[x[0] for x in trajectory.at_time(float(t))] for t in rel_t]).T
    moving = np.where(before, theirs, np.nan)
    reference = _reference(ours, moving, _pinned(profile, rel_t), band)
    scales, rates = _scales(profile, ours), _rates(ours, profile)
    for index, name in enumerate(("position", "velocity", "acceleration")):
        _close(ours[index], reference[index], name, scales[index], rates[index], clock)
    end = np.flatnonzero(~before & ~band)
    if case.kind == "position":
        assert np.all(ours[0, end] == case.target), "position at the end is not the target"
    assert np.all(ours[1, end] == (0.0 if case.kind == "position" else case.target))
    assert np.all(ours[2, end] == 0.0)


@given(cases=st.lists(planned_cases(), min_size=1, max_size=4), data=st.data())
def test_profile_at_matches_segment_table_rows(cases, data):
    """Bulk evaluation of several rows (installed at different times, crossing segments at
    different cycles) equals ``Profile.at`` per row; ``SegmentTable.state`` agrees too."""
    profiles = [_plan(case) for case in cases]
    offsets = data.draw(st.lists(st.floats(0.0, 10.0), min_size=len(cases),
                                 max_size=len(cases)))
    times = _times(data.draw, max(profiles, key=lambda p: p.duration))
    relative, samples = _table_samples(profiles, offsets, times)
    clock = max(offsets) + float(times[-1])
    for row, profile in enumerate(profiles):
        at = np.array([profile.at(float(t))[:3] for t in relative[row]]).T
        band = _at_end_band(relative[row], profile, clock)
        reference = _reference(samples[row], at, _pinned(profile, relative[row]), band)
        scales, rates = _scales(profile, samples[row]), _rates(samples[row], profile)
        for index, name in enumerate(("position", "velocity", "acceleration")):
            _close(samples[row, index], reference[index], f"row {row} {name}", scales[index],
                   rates[index], clock)
    profile, offset = profiles[0], offsets[0]
    table = SegmentTable()
    row = table.add(profile.end, 0.0)
    table.install(row, profile, offset)
    states = np.array([(s.position, s.velocity, s.acceleration)
                       for s in (table.state(row, offset + t) for t in relative[0])]).T
    at = np.array([profile.at(float(t))[:3] for t in relative[0]]).T
    pinned = _pinned(profile, relative[0])
    pinned[2] = 0.0  # state() gives the exact end state in the open segment
    band = _at_end_band(relative[0], profile, clock)
    moving = np.where(relative[0] < profile.duration, at, np.nan)
    reference = _reference(states, moving, pinned, band)
    scales, rates = _scales(profile, at), _rates(at, profile)
    for index, name in enumerate(("position", "velocity", "acceleration")):
        _close(states[index], reference[index], f"state {name}", scales[index], rates[index],
               clock)


@given(cases=st.lists(planned_cases(), min_size=1, max_size=4), data=st.data())
def test_states_of_several_rows_are_state_bit_for_bit(cases, data):
    """``SegmentTable.states`` (compiled, a planar move starts x, y and c from it) gives
    exactly what ``state`` gives row by row: inside the cached segment, after a bulk
    evaluation moved it, and at times that need a search."""
    table = SegmentTable()
    rows = [table.add(KinematicState(0.0), 0.0) for _ in cases]
    for row, case in zip(rows, cases, strict=True):
        table.install(row, _plan(case), data.draw(st.floats(0.0, 5.0)))
    buffers = [np.zeros(table.capacity) for _ in range(4)]
    for now in data.draw(st.lists(st.floats(0.0, 20.0), min_size=1, max_size=5)):
        if data.draw(st.booleans()):
            table.evaluate(now, *buffers)
        time = data.draw(st.sampled_from([now, now + 0.001])) if data.draw(st.booleans()) \
            else data.draw(st.floats(0.0, 20.0))
        assert table.states(rows, time) == [table.state(row, time) for row in rows]


@given(case=planned_cases(), data=st.data())
def test_remaining_profile_continues_the_row(case, data):
    """``SegmentTable.remaining`` (where a running motion still goes: software limits
    written during it, D-179) starts with ``state`` at that time and follows the row from
    there; before the row's start, in a segment, and in the open segment."""
    profile = _plan(case)
    table = SegmentTable()
    row = table.add(KinematicState(0.0), 0.0)
    offset = data.draw(st.floats(0.0, 5.0))
    table.install(row, profile, offset)
    time = offset + data.draw(st.floats(0.0, 1.2)) * profile.duration
    rest = table.remaining(row, time)
    start = table.state(row, time)
    assert (rest.p[0], rest.v[0], rest.a[0]) == (start.position, start.velocity,
                                                  start.acceleration)
    scale = max(1.0, float(np.max(np.abs(profile.p))), float(np.max(np.abs(profile.v))),
                float(np.max(np.abs(profile.a))))
    for dt in np.linspace(0.0, max(profile.duration + offset - time, 0.0) + 0.5, 41):
        state = table.state(row, time + float(dt))
        ours = rest.at(float(dt))[:2]
        assert ours == pytest.approx((state.position, state.velocity), abs=1e-9 * scale)


def _dense(profile: Profile, points: int = 4001) -> tuple[np.ndarray, float]:
    grid = np.linspace(0.0, profile.duration, points)
    times = np.unique(np.concatenate([grid, profile.t]))
    return times, float(grid[1] - grid[0]) if points > 1 else 0.0


@given(case=planned_cases())
@example(case=MoveCase(KinematicState(0.0, 0.012215087194318908), 0.0,
                       Limits(1000.0, 10000.0, 10000.0, 1e6), "position"))
def test_extrema_match_dense_sampling(case):
    """velocity_extrema and position_extrema bound every sample of a dense grid (which holds
    every segment boundary) and are within the grid's reach of it: an interior extremum is
    where the derivative is zero, so the nearest grid point is at most
    max|second derivative|·h²/8 away (h the grid step).

    Tolerance 1e-9 relative with the kernel's own floor of 1 (mm, mm/s; jobs.py, plan.py);
    for positions at least ruckig's absolute precision: the open segment is pinned to the
    commanded end state, which ruckig only reaches to that precision, so a microscopic move
    (a reversal of a micrometre) can end with a step of some nanometres that no extremum of
    the pinned profile shows.
    """
    profile = _plan(case)
    times, h = _dense(profile)
    samples = np.array([profile.at(float(t)) for t in times]).T
    p, v, a, j = samples
    for (lo, hi), values, curvature, name in (
        (profile.velocity_extrema(), v, np.max(np.abs(j)), "velocity"),
        (profile.position_extrema(), p, np.max(np.abs(a)), "position"),
    ):
        slack = REL * max(float(np.max(np.abs(values))), 1.0)
        if name == "position":
            slack = max(slack, RUCKIG_POSITION_PRECISION)
        reach = curvature * h * h / 8.0 + slack
        assert lo <= values.min() + slack and hi >= values.max() - slack, (
            f"{name} extrema [{lo!r}, {hi!r}] miss samples [{values.min()!r}, {values.max()!r}]"
        )
        assert lo >= values.min() - reach and hi <= values.max() + reach, (
            f"{name} extrema [{lo!r}, {hi!r}] beyond the samples [{values.min()!r}, "
            f"{values.max()!r}] by more than {reach!r}"
        )
