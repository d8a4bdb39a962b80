"""Buffer modes and transition modes of the Part 4 path moves (§2.4, §7; digest §5).

Rules 98-113 of digest §6. The scene is always one corner: MC_MoveLinearAbsolute from
(0, 0) to E1 = (L1, 0), then a second MC_MoveLinearAbsolute from there to (L1, L2), issued
at once with the BufferMode and TransitionMode under test (L1 = L2 = 50 mm unless a test
needs room for a longer contour). The contour's shape is ours (quintic, decisions D-103);
these tests check what Part 4 asks of any contour: where it
leaves and rejoins the lines, how close it passes the corner, its speed, and when the FBs
hand over.

FBs are called once per cycle before ``rt.step()``, as in tests/transport/test_blocks.py.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

import openmotion as om
from openmotion.coordinated.blocks import MC_MoveLinearAbsolute
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem, TransitionMode
from openmotion.core.enums import BufferMode

B = BufferMode
T = TransitionMode
ErrorId = om.ErrorId
AXIS = {"max_velocity": 1000.0, "max_acceleration": 20000.0, "max_deceleration": 20000.0,
        "max_jerk": 1.0e6}
TOL = 1e-6  #: [mm]
BLENDING = [B.BLENDING_LOW, B.BLENDING_PREVIOUS, B.BLENDING_NEXT, B.BLENDING_HIGH]
CONTOURS = [(T.TM_START_VELOCITY, 50.0), (T.TM_CONSTANT_VELOCITY, 50.0),
            (T.TM_CORNER_DISTANCE, 10.0), (T.TM_MAX_CORNER_DEVIATION, 2.0)]


def group_of(*start: float, **parameters: Any) -> tuple[om.Runtime, AxesGroup, list[om.Axis]]:
    rt = om.Runtime()
    group = AxesGroup(rt, "g")
    axes = []
    for ident, position in enumerate(start, 1):
        axis = rt.add_axis(f"a{ident}", position=position, **{**AXIS, **parameters})
        assert axis.power()
        assert group.add_axis(axis, ident).done
        axes.append(axis)
    assert group.enable().done
    return rt, group, axes


@dataclass
class Run:
    """One corner, sampled after every cycle."""

    points: np.ndarray  #: TCP (x, y) [mm]
    speeds: np.ndarray  #: path speed [mm/s]
    done_at: int  #: cycle in which the first FB showed Done
    active_at: int  #: cycle in which the second FB first showed Active
    corner: np.ndarray
    end: np.ndarray

    def off_lines(self) -> np.ndarray:
        """Distance of each sample from the two programmed segments."""
        x, y = self.points[:, 0], self.points[:, 1]
        cx, ey = self.corner[0], self.end[1]
        to_first = np.hypot(np.clip(x - cx, 0.0, None), y)  # segment (0, 0)-(cx, 0)
        to_second = np.hypot(x - cx, np.clip(y - ey, 0.0, None) + np.clip(-y, 0.0, None))
        return np.minimum(np.where(x <= cx, np.abs(y), to_first), to_second)

    def to_corner(self) -> np.ndarray:
        return np.linalg.norm(self.points - self.corner, axis=1)

    def speed_nearest_corner(self) -> float:
        return float(self.speeds[int(np.argmin(self.to_corner()))])


@functools.cache
def corner(buffer_mode: BufferMode = B.BUFFERED, mode: Any = T.TM_NONE,
           parameter: Any = None, v1: float = 100.0, v2: float = 100.0,
           legs: tuple[float, float] = (50.0, 50.0)) -> Run:
    """The corner run with these inputs; cached (tests only read it), so arguments must be
    hashable: a TransitionParameter is a number or a tuple."""
    rt, group, axes = group_of(0.0, 0.0)
    first, second = MC_MoveLinearAbsolute(group), MC_MoveLinearAbsolute(group)
    first(execute=True, position=[legs[0], 0.0], velocity=v1)
    second(execute=True, position=[legs[0], legs[1]], velocity=v2, buffer_mode=buffer_mode,
           transition_mode=mode, transition_parameter=parameter)
    assert not second.error, second.message
    points, speeds = [group.position(CoordSystem.MCS)], [0.0]
    done_at = active_at = -1
    for cycle in range(1, 20000):
        rt.step()
        first()
        second()
        points.append(group.position(CoordSystem.MCS))
        speeds.append(group.velocity(CoordSystem.MCS)[1])
        if first.done and done_at < 0:
            done_at = cycle
        if second.active and active_at < 0:
            active_at = cycle
        if second.done:
            break
    assert second.done and np.allclose(points[-1], [legs[0], legs[1]], atol=TOL, rtol=0.0)
    return Run(np.array(points), np.array(speeds), done_at, active_at,
               np.array([legs[0], 0.0]), np.array([legs[0], legs[1]]))


# -- Aborting (§7.3.1; rules 98, 109) -----------------------------------------------------------


def test_rule98_aborting_the_old_fb_is_aborted_when_the_new_one_is_active():
    rt, group, axes = group_of(0.0, 0.0)
    first, second = MC_MoveLinearAbsolute(group), MC_MoveLinearAbsolute(group)
    first(execute=True, position=[100.0, 0.0])
    for _ in range(300):
        rt.step()
        first()
    assert first.active
    second(execute=True, position=[0.0, 50.0], buffer_mode=B.ABORTING)
    first()
    assert (first.busy, first.active, first.command_aborted) == (False, False, True)
    assert second.busy and second.active
    while not second.done:
        rt.step()
        second()
    assert group.position(CoordSystem.MCS) == pytest.approx([0.0, 50.0], abs=TOL)


@pytest.mark.parametrize("mode", [T.TM_CORNER_DISTANCE, T.TM_MAX_CORNER_DEVIATION])
def test_rule109_aborting_with_a_corner_mode_is_an_error_and_aborts_nothing(mode):
    rt, group, axes = group_of(0.0, 0.0)
    first, second = MC_MoveLinearAbsolute(group), MC_MoveLinearAbsolute(group)
    first(execute=True, position=[100.0, 0.0])
    rt.run(0.2)
    second(execute=True, position=[0.0, 50.0], buffer_mode=B.ABORTING, transition_mode=mode,
           transition_parameter=[5.0])
    first()
    assert second.error and second.error_id is ErrorId.INVALID_MODE
    assert first.active and not first.command_aborted
    while not first.done:
        rt.step()
        first()
    assert group.position(CoordSystem.MCS) == pytest.approx([100.0, 0.0], abs=TOL)


# -- Buffered (§7.3.2; rules 99, 100) -----------------------------------------------------------


def test_rule99_buffered_stops_exactly_at_e1():
    run = corner(B.BUFFERED)
    assert run.off_lines().max() <= 1e-9  # no corner is cut: the path turns at E1
    # Done at E1 at rest; the rest may fall between two samples, and within one cycle
    # (the group's jerk 1e4 mm/s³, 1 ms) the next move gets j·dt³ away at j·dt²
    assert run.to_corner()[run.done_at] <= 1e4 * 1e-9
    assert run.speeds[run.done_at] <= 1e4 * 1e-6
    assert run.active_at == run.done_at


def test_rule100_buffered_does_not_evaluate_the_transition_mode():
    plain = corner(B.BUFFERED)
    for mode, parameter in CONTOURS:
        other = corner(B.BUFFERED, mode, parameter)
        assert np.array_equal(other.points, plain.points)
        assert (other.done_at, other.active_at) == (plain.done_at, plain.active_at)


# -- Blending (§7.3.3, §7.4; rules 101-108, 110, 111) --------------------------------------------


@pytest.mark.parametrize("buffer_mode", BLENDING, ids=lambda m: m.name)
def test_rule103_blending_with_tm_none_is_buffered(buffer_mode):
    plain = corner(B.BUFFERED)
    other = corner(buffer_mode, T.TM_NONE)
    assert np.array_equal(other.points, plain.points)


@pytest.mark.parametrize(("mode", "parameter"), CONTOURS, ids=lambda v: getattr(v, "name", v))
def test_rules101_111_a_contour_keeps_moving_and_never_reaches_the_corner(mode, parameter):
    run = corner(B.BLENDING_LOW, mode, parameter)
    assert np.all(run.speeds[1:-1] > 0.0)  # no stop between start and end
    assert run.to_corner().min() > 0.1  # the corner point E1 is not passed
    assert run.off_lines().max() > 0.1  # the path was changed


@pytest.mark.parametrize(("buffer_mode", "expected"), [
    (B.BLENDING_LOW, 40.0), (B.BLENDING_PREVIOUS, 100.0), (B.BLENDING_NEXT, 40.0),
    (B.BLENDING_HIGH, 100.0)], ids=lambda v: getattr(v, "name", v))
def test_rule102_transition_speed_of_each_blending_flavour(buffer_mode, expected):
    """v1 = 100, v2 = 40 mm/s; a long contour (corner distance 30 mm) lets the TCP reach the
    flavour's transition speed before the point nearest the corner."""
    run = corner(buffer_mode, T.TM_CORNER_DISTANCE, (30.0,), v1=100.0, v2=40.0,
                 legs=(100.0, 100.0))
    assert run.speed_nearest_corner() == pytest.approx(expected, rel=1e-6)
    assert run.speeds.max() <= 100.0 * (1 + 1e-9)


def test_rule104_start_velocity_starts_the_contour_at_half_v1_whatever_the_flavour():
    runs = [corner(mode, T.TM_START_VELOCITY, (50.0,), v1=100.0, v2=100.0, legs=(100.0, 100.0))
            for mode in BLENDING]
    for run in runs[1:]:
        assert np.array_equal(run.points, runs[0].points)  # the flavour is not evaluated
    run = runs[0]
    assert run.speed_nearest_corner() == pytest.approx(50.0, rel=1e-6)
    nearest = int(np.argmin(run.to_corner()))
    cruising = np.flatnonzero(run.speeds > 99.0)
    before, after = cruising[cruising < nearest][-1], cruising[cruising > nearest][0]
    assert run.speeds[before:after].min() == pytest.approx(50.0, rel=1e-6)  # 50 %, not below


@pytest.mark.parametrize(("buffer_mode", "expected"), [
    (B.BLENDING_LOW, 40.0), (B.BLENDING_PREVIOUS, 50.0), (B.BLENDING_NEXT, 40.0),
    (B.BLENDING_HIGH, 50.0)], ids=lambda v: getattr(v, "name", v))
def test_rule105_constant_velocity_runs_the_contour_at_half_the_transition_speed(
        buffer_mode, expected):
    """v1 = 100, v2 = 80 mm/s, TPVelocity 50 %: the contour runs at 50 % of v_T."""
    run = corner(buffer_mode, T.TM_CONSTANT_VELOCITY, (50.0,), v1=100.0, v2=80.0,
                 legs=(100.0, 100.0))
    near = run.to_corner() < 45.0  # the widest contour: 50 mm either side of the corner
    assert run.speeds[near] == pytest.approx(np.full(near.sum(), expected), rel=1e-6)
    assert run.speed_nearest_corner() == pytest.approx(expected, rel=1e-6)


def test_rule106_corner_distance_leaves_and_rejoins_the_lines_d_from_the_corner():
    d = 10.0
    run = corner(B.BLENDING_PREVIOUS, T.TM_CORNER_DISTANCE, (d,))
    far = run.to_corner() >= d + 1e-6
    assert run.off_lines()[far].max() <= 1e-9  # on the programmed lines outside the ball
    inside = run.to_corner() < d - 1e-3
    assert inside.any() and run.off_lines()[inside].max() > 1.0  # the contour inside it
    assert run.to_corner().min() > 0.0


@pytest.mark.parametrize("e", [0.5, 2.0])
def test_rule107_max_corner_deviation_passes_the_corner_at_e(e):
    run = corner(B.BLENDING_PREVIOUS, T.TM_MAX_CORNER_DEVIATION, (e,))
    assert run.to_corner().min() == pytest.approx(e, abs=1e-3)
    assert run.to_corner().min() <= e + 1e-3


def test_rule108_axes_stay_within_their_acceleration_on_a_tight_contour():
    rt, group, axes = group_of(0.0, 0.0, max_acceleration=2000.0, max_deceleration=2000.0,
                               acceleration=2000.0, deceleration=2000.0)
    group.move_linear_absolute([50.0, 0.0], velocity=300.0)
    second = group.move_linear_absolute([50.0, 50.0], velocity=300.0,
                                        buffer_mode=B.BLENDING_HIGH,
                                        transition_mode=T.TM_CORNER_DISTANCE,
                                        transition_parameter=[1.0])
    peak = 0.0
    while not second.done:
        rt.step()
        peak = max(peak, *(abs(a.set_acceleration) for a in axes))
    assert peak <= 2000.0 * (1 + 1e-6)


@pytest.mark.parametrize("buffer_mode", [B.BUFFERED, B.BLENDING_LOW], ids=lambda m: m.name)
def test_rules99_110_the_next_fb_is_active_in_the_cycle_the_previous_is_done(buffer_mode):
    """Whatever the TransitionMode, the hand-over is the same: Done and Active together."""
    runs = [corner(buffer_mode, mode, parameter)
            for mode, parameter in [(T.TM_NONE, None), *CONTOURS]]
    assert {run.active_at - run.done_at for run in runs} == {0}


# -- what is accepted (§2.4.3, §2.4.4; rules 109, 113; the matrix) -----------------------------


@pytest.mark.parametrize("value", [5, 6, 7, 8, 9, 10, 42, -1])
def test_rule113_reserved_and_unknown_transition_modes_are_errors(value):
    rt, group, axes = group_of(0.0, 0.0)
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[10.0, 0.0], buffer_mode=B.BLENDING_LOW, transition_mode=value,
         transition_parameter=[1.0])
    assert move.error and move.error_id is ErrorId.INVALID_MODE
    assert group.state.name == "STANDBY"


#: our matrix (docs/part4-coverage.md): True = accepted
MATRIX = {
    B.ABORTING: {T.TM_NONE: True, T.TM_START_VELOCITY: True, T.TM_CONSTANT_VELOCITY: True,
                 T.TM_CORNER_DISTANCE: False, T.TM_MAX_CORNER_DEVIATION: False},
    B.BUFFERED: dict.fromkeys(T, True),
    **{mode: dict.fromkeys(T, True) for mode in BLENDING},
}


@pytest.mark.parametrize("transition", list(T), ids=lambda m: m.name)
@pytest.mark.parametrize("buffer_mode", list(B), ids=lambda m: m.name)
def test_the_buffer_mode_transition_mode_matrix(buffer_mode, transition):
    rt, group, axes = group_of(0.0, 0.0)
    first, second = MC_MoveLinearAbsolute(group), MC_MoveLinearAbsolute(group)
    first(execute=True, position=[40.0, 0.0])
    rt.run(0.05)
    second(execute=True, position=[40.0, 40.0], buffer_mode=buffer_mode,
           transition_mode=transition, transition_parameter=[5.0])
    accepted = MATRIX[buffer_mode][transition]
    assert second.error is not accepted
    if not accepted:
        assert second.error_id is ErrorId.INVALID_MODE


@pytest.mark.parametrize("parameter", [None, [0.0], [-2.0], [float("nan")], [101.0]],
                         ids=str)
@pytest.mark.parametrize("mode", [T.TM_START_VELOCITY, T.TM_CONSTANT_VELOCITY,
                                  T.TM_CORNER_DISTANCE, T.TM_MAX_CORNER_DEVIATION],
                         ids=lambda m: m.name)
def test_a_blending_contour_needs_a_sensible_parameter(mode, parameter):
    rt, group, axes = group_of(0.0, 0.0)
    group.move_linear_absolute([40.0, 0.0])
    command = group.move_linear_absolute([40.0, 40.0], buffer_mode=B.BLENDING_NEXT,
                                         transition_mode=mode, transition_parameter=parameter)
    percent = mode in (T.TM_START_VELOCITY, T.TM_CONSTANT_VELOCITY)
    if parameter == [101.0] and not percent:
        assert not command.error  # a distance of 101 mm is fine
    else:
        assert command.error and command.error_id is ErrorId.INVALID_MODE


# -- Aborting with a transition at speed (§7.4.2, §7.4.3; issue 20 point 5, D-195) ----------

JOIN = {"velocity": 200.0, "acceleration": 2000.0, "deceleration": 2000.0, "jerk": 1.0e5}


def aborted_at_speed(mode: TransitionMode, target: list[float], parameter: float = 50.0
                     ) -> tuple[om.Runtime, AxesGroup, Any, Any, np.ndarray, np.ndarray]:
    """A line along +x at 200 mm/s, aborted at x = 108 by a line to ``target`` with
    ``mode``; the path speed and the axes' set accelerations of every cycle until Done."""
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    first = group.move_linear_absolute([300.0, 0.0, 0.0], **JOIN)
    rt.run(0.6)
    assert group.motion.path_velocity == pytest.approx(200.0, rel=1e-12)
    second = group.move_linear_absolute(target, **JOIN, transition_mode=mode,
                                        transition_parameter=[parameter])
    assert first.aborted and second.active  # the hand-over of Aborting, in the call
    speeds, accelerations = [], []
    while not second.done:
        assert not second.error and rt.now < 5.0
        rt.step()
        speeds.append(group.motion.path_velocity)
        accelerations.append(group.kernel.set_a[group.rows].copy())
    return rt, group, first, second, np.array(speeds), np.array(accelerations)


def _smooth(rt: om.Runtime, accelerations: np.ndarray) -> None:
    """Axis accelerations change by at most the jerk per cycle: no jump at the abort."""
    steps = np.abs(np.diff(accelerations, axis=0)).max()
    assert steps <= JOIN["jerk"] * rt.cycle_time * (1 + 1e-6)


def test_aborting_with_constant_velocity_joins_the_new_path_at_p_percent_of_its_velocity():
    """§7.4.3: with Aborting, the first FB is aborted and the group returns to the commanded
    path on a contour run at TPVelocity % of the transition velocity, here 50 % of the new
    FB's 200 mm/s (D-195). Before issue 20 it stopped (TMNone)."""
    rt, group, first, second, speeds, accelerations = aborted_at_speed(
        T.TM_CONSTANT_VELOCITY, [200.0, 150.0, 0.0])
    moving = speeds[:-1]
    assert moving.min() > 0.0  # never at rest between the two paths
    on_contour = np.isclose(moving, 100.0, rtol=1e-9)
    assert on_contour.sum() * rt.cycle_time > 0.1  # a stretch at constant 100 mm/s
    assert moving.max() <= 200.0 * (1 + 1e-9)
    assert group.position(CoordSystem.MCS, actual=False) == pytest.approx(
        [200.0, 150.0, 0.0], abs=TOL)
    _smooth(rt, accelerations)
    rt.step()
    assert group.state.name == "STANDBY"  # at rest after Done, and usable
    assert group.move_linear_absolute([0.0, 0.0, 0.0]).busy


def test_aborting_with_start_velocity_leaves_at_p_percent_of_the_aborted_velocity():
    """§7.4.2: the contour starts once the aborted motion has slowed to TPStartVelocity %
    of its Velocity (50 % of 200 mm/s) and the group never stops (D-195)."""
    rt, group, first, second, speeds, accelerations = aborted_at_speed(
        T.TM_START_VELOCITY, [200.0, 150.0, 0.0])
    low = speeds[:-1]
    assert low.min() > 0.0
    turn = int(np.argmin(low[: len(low) // 2]))
    assert low[turn] == pytest.approx(100.0, rel=1e-6)
    assert group.position(CoordSystem.MCS, actual=False) == pytest.approx(
        [200.0, 150.0, 0.0], abs=TOL)
    _smooth(rt, accelerations)


def test_aborting_with_constant_velocity_on_an_arc_keeps_the_acceleration_continuous():
    """The lead-out continues the arc the TCP is on (same curvature), so the abort does not
    change the axes' acceleration in a step (D-195)."""
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    first = group.move_circular_absolute([50.0, 50.0, 0.0], [100.0, 0.0, 0.0], velocity=100.0,
                                         acceleration=2000.0, deceleration=2000.0, jerk=1.0e5)
    rt.run(0.5)
    second = group.move_linear_absolute([150.0, 100.0, 0.0], velocity=100.0,
                                        acceleration=2000.0, deceleration=2000.0, jerk=1.0e5,
                                        transition_mode=T.TM_CONSTANT_VELOCITY,
                                        transition_parameter=[80.0])
    assert first.aborted and second.active
    speeds, accelerations = [], []
    while not second.done:
        assert rt.now < 5.0
        rt.step()
        speeds.append(group.motion.path_velocity)
        accelerations.append(group.kernel.set_a[group.rows].copy())
    assert min(speeds[:-1]) > 0.0
    _smooth(rt, np.array(accelerations))
    assert group.position(CoordSystem.MCS, actual=False) == pytest.approx(
        [150.0, 100.0, 0.0], abs=TOL)


def test_aborting_with_constant_velocity_stops_first_where_the_path_turns_back():
    """A new path straight back cannot be joined at speed: the group brakes to rest along the
    old path first, as with TMNone (D-110, D-195)."""
    rt, group, first, second, speeds, accelerations = aborted_at_speed(
        T.TM_CONSTANT_VELOCITY, [0.0, 0.0, 0.0])
    assert speeds[:-1].min() == 0.0
    assert group.position(CoordSystem.MCS, actual=False) == pytest.approx([0.0, 0.0, 0.0],
                                                                            abs=TOL)


@pytest.mark.parametrize("mode", [T.TM_START_VELOCITY, T.TM_CONSTANT_VELOCITY],
                         ids=lambda m: m.name)
def test_aborting_with_a_velocity_transition_needs_a_percentage(mode):
    """§7.4.2/§7.4.3: the percentage is now evaluated with Aborting too (D-195)."""
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move = group.move_linear_absolute([40.0, 0.0, 0.0], transition_mode=mode,
                                      transition_parameter=[150.0])
    assert move.error and move.error_id is ErrorId.INVALID_MODE
    assert group.move_linear_absolute([40.0, 0.0, 0.0], transition_mode=mode,
                                      transition_parameter=[50.0]).busy
