"""Planning of free planar motions: dynamics resolution, MoveToPosition on a straight line with
tangential limits and synchronised C, MoveZ/A/B/C and Halt (TF5430 §6.1.3, §6.1.5, §6.1.9,
§7.2.2.8; digest-planar-concepts §3.10, §5.3, §5.6, §5.9). ruckig is the time-optimal oracle."""

from __future__ import annotations

import math
from unittest import mock

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from ruckig import InputParameter, Ruckig, RuckigError, Trajectory

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar import motion as motion_module
from openmotion.planar.area_kernels import straight_runs
from openmotion.planar.motion import (
    PlanarMotion,
    PositionLimits,
    _positions,
    _positions_at,
    plan_axis_move,
    plan_halt,
    plan_move_to_position,
    plan_position,
    rest_to_rest_time,
    running,
    sample_times,
)
from openmotion.planar.reservation import (
    MOVER_HEIGHT,
    MOVER_WIDTH,
    RELEASE_STEP,
    straight_run_area,
    straight_run_pieces,
    straight_sweep,
    travel_runs,
)
from openmotion.planar.rotation import CWindows
from openmotion.trajectory.evaluate import SegmentTable
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import KinematicState, Profile

XY = Limits(1000.0, 5000.0, 4000.0, 50000.0)  # [mm/s, mm/s², mm/s², mm/s³], acc != dec
C = Limits(360.0, 3600.0, 3600.0, 36000.0)  # [°/s ...]
REST = KinematicState(0.0)
EPS = 1e-9


def _at_rest(x: float = 0.0, y: float = 0.0, c: float = 0.0) -> tuple[KinematicState, ...]:
    return KinematicState(x), KinematicState(y), KinematicState(c)


def _evaluate(profile: Profile, times: np.ndarray) -> np.ndarray:
    """Rows p, v, a, j of ``profile`` at ``times`` (the cubic of every segment)."""
    k = np.maximum(np.searchsorted(profile.t, times, side="right") - 1, 0)
    dt = times - profile.t[k]
    p0, v0, a0, j = profile.p[k], profile.v[k], profile.a[k], profile.j[k]
    return np.array((p0 + dt * (v0 + dt * (a0 / 2.0 + dt * j / 6.0)),
                     v0 + dt * (a0 + dt * j / 2.0), a0 + dt * j, j))


def _dense(motion: PlanarMotion, n: int = 4001) -> tuple[np.ndarray, np.ndarray]:
    times = np.linspace(0.0, motion.duration, n)
    return _evaluate(motion.x, times), _evaluate(motion.y, times)


def _distance_from_line(points: np.ndarray, start: tuple[float, float],
                        end: tuple[float, float]) -> np.ndarray:
    direction = np.subtract(end, start) / math.dist(start, end)
    rel = points - np.asarray(start)
    return np.abs(rel[:, 0] * direction[1] - rel[:, 1] * direction[0])


def _assert_tangential_limits(motion: PlanarMotion, limits: Limits) -> None:
    """Path velocity, acceleration (speeding up / slowing down) and jerk within the limits."""
    x, y = _dense(motion)
    speed = np.hypot(x[1], y[1])
    acc = np.hypot(x[2], y[2])
    along = x[1] * x[2] + y[1] * y[2]  # > 0 speeding up
    assert speed.max() <= limits.velocity * (1 + EPS)
    assert acc[along > 0].max(initial=0.0) <= limits.acceleration * (1 + EPS)
    assert acc[along < 0].max(initial=0.0) <= limits.deceleration * (1 + EPS)
    assert np.hypot(x[3], y[3]).max() <= limits.jerk * (1 + EPS)


def _ruckig_duration(distance: float, limits: Limits, velocity: float = 0.0) -> float:
    """The oracle: ruckig's 1-DoF time-optimal duration from ``velocity`` >= 0 to rest
    ``distance`` >= 0 ahead (one direction, so the signed acceleration limits are exact)."""
    for factor in (1.0, 1.0 - 1e-12, 1.0 - 1e-10):  # ruckig's step 1 fails on rare inputs,
        inp = InputParameter(1)  # as in trajectory/plan.py: limits a hair lower then
        inp.current_position, inp.target_position = [0.0], [distance]
        inp.current_velocity = [velocity]
        inp.max_velocity, inp.max_jerk = [limits.velocity], [limits.jerk * factor]
        inp.max_acceleration = [limits.acceleration * factor]
        inp.min_acceleration = [-limits.deceleration * factor]
        trajectory = Trajectory(1)
        try:
            Ruckig(1).calculate(inp, trajectory)
        except RuckigError:
            continue
        return trajectory.duration
    raise AssertionError("the ruckig oracle failed")


# MoveToPosition ---------------------------------------------------------------------------------

def test_manual_6_1_3_move_to_100_100():
    """§6.1.3: from (0, 0) with default dynamics to (100, 100): exactly there, straight,
    time-optimal, and C untouched."""
    motion = plan_move_to_position(_at_rest(), (100.0, 100.0), XY)
    assert (motion.x.end, motion.y.end) == (KinematicState(100.0), KinematicState(100.0))
    assert motion.c is None
    assert motion.duration == pytest.approx(_ruckig_duration(math.hypot(100, 100), XY), abs=EPS)
    x, y = _dense(motion)
    assert _distance_from_line(np.column_stack((x[0], y[0])), (0, 0), (100, 100)).max() <= EPS
    _assert_tangential_limits(motion, XY)


def test_samples_for_the_swept_area():
    motion = plan_move_to_position(_at_rest(c=7.0), (300.0, -40.0), XY)
    times, points = motion.sample(0.01)
    assert times[0] == 0.0 and times[-1] == motion.duration
    assert np.all(np.diff(times) <= 0.01 + EPS)
    assert set(motion.x.t) <= set(times)  # every segment boundary is a sample
    assert points[0].tolist() == [0.0, 0.0, 7.0] and points[-1].tolist() == [300.0, -40.0, 7.0]
    with pytest.raises(ValueError):
        motion.sample(0.0)


def test_profiles_install_in_the_segment_table():
    """A mover owns one table row per coordinate: the bulk evaluator reproduces the samples."""
    motion = plan_move_to_position((KinematicState(0.0, 300.0), KinematicState(0.0),
                                    KinematicState(0.0)), (0.0, 200.0, 10.0), XY, C)
    table = SegmentTable(capacity=3)
    for profile in (motion.x, motion.y, motion.c):
        table.install(table.add(REST, 0.0), profile, 0.0)
    times, points = motion.sample(0.005)
    out = np.zeros((4, 3))
    for time, point in zip(times, points, strict=True):
        table.evaluate(time, *out)
        assert out[0] == pytest.approx(point, abs=1e-9)


@pytest.mark.parametrize(("xy_target", "c_target"), [
    ((500.0, 0.0), 5.0),  # the path is slower: C is stretched
    ((1.0, 1.0), 14.0),  # C is slower: the path is stretched
])
def test_c_ends_with_the_path(xy_target, c_target):
    motion = plan_move_to_position(_at_rest(), (*xy_target, c_target), XY, C,
                                   c_windows=CWindows())
    assert motion.x.duration == pytest.approx(motion.c.duration, abs=EPS)
    assert motion.c.end == KinematicState(c_target)
    slower = max(_ruckig_duration(math.hypot(*xy_target), XY), _ruckig_duration(c_target, C))
    assert motion.duration == pytest.approx(slower, abs=EPS)
    x, y = _dense(motion)
    points = np.column_stack((x[0], y[0]))
    assert _distance_from_line(points, (0, 0), xy_target).max() <= EPS
    _assert_tangential_limits(motion, XY)


def test_c_leaving_its_window_is_rejected():
    """Only MoveC may rotate out of a window (§4.2): X and Y are locked outside."""
    with pytest.raises(CommandRejected) as rejected:
        plan_move_to_position(_at_rest(), (100.0, 0.0, 90.0), XY, C, c_windows=CWindows())
    assert rejected.value.error_id == ErrorId.PLANAR_POSITION_LIMIT


def test_moving_along_the_line_keeps_going():
    """A new target ahead on the current line: no stop, the 1-D plan from the moving state."""
    start = (KinematicState(0.0, 600.0), KinematicState(0.0), KinematicState(0.0))
    motion = plan_move_to_position(start, (400.0, 0.0), XY)
    x, y = _dense(motion)
    assert x[1].min() >= -EPS and np.abs(y[0]).max() == 0.0
    assert motion.x.end == KinematicState(400.0)
    assert motion.duration == pytest.approx(_ruckig_duration(400.0, XY, 600.0), abs=EPS)


def test_stretched_c_heading_away_brakes_first():
    """C turning away from its target while a long path sets the time: with unequal
    acceleration and deceleration ruckig's stretched profile would reverse under the wrong
    bound, so C brakes to rest first; it still ends with the path, within its limits."""
    c_limits = Limits(360.0, 3600.0, 900.0, 36000.0)
    start = (KinematicState(0.0), KinematicState(0.0), KinematicState(0.0, -200.0))
    motion = plan_move_to_position(start, (1000.0, 0.0, 10.0), XY, c_limits)
    assert motion.c.duration == pytest.approx(motion.x.duration, abs=EPS)
    assert motion.c.end == KinematicState(10.0)
    c = _evaluate(motion.c, np.linspace(0.0, motion.duration, 4001))
    speeding_up = c[1] * c[2] > 0.0
    assert np.abs(c[2][speeding_up]).max() <= c_limits.acceleration * (1 + EPS)
    assert np.abs(c[2][~speeding_up]).max() <= c_limits.deceleration * (1 + EPS)


def test_moving_off_the_line_brakes_then_goes_straight():
    """Decision: a target off the line of motion brakes to rest along the current direction,
    then the straight line (two known pieces for the planar group). Braking from 800 mm/s
    with D = 4000 mm/s², J = 50000 mm/s³ takes 0.08 + 0.12 + 0.08 s over 400 mm/s * 0.28 s."""
    start = (KinematicState(0.0, 800.0), KinematicState(0.0), KinematicState(0.0))
    motion = plan_move_to_position(start, (0.0, 200.0), XY)
    corner_time = _corner_time(motion)
    corner = motion.x.at(corner_time)[0]
    assert (corner_time, corner) == pytest.approx((0.28, 112.0), abs=EPS)
    times, points = motion.sample(0.001)
    braking = times <= corner_time
    assert np.abs(points[braking, 1]).max() == 0.0
    assert _distance_from_line(points[~braking, :2], (corner, 0.0), (0.0, 200.0)).max() <= EPS
    assert (motion.x.end, motion.y.end) == (KinematicState(0.0), KinematicState(200.0))
    _assert_tangential_limits(motion, XY)


def test_moving_to_the_current_position_brakes_and_comes_back():
    start = (KinematicState(10.0, 0.0), KinematicState(20.0, -500.0), KinematicState(0.0))
    motion = plan_move_to_position(start, (10.0, 20.0), XY)
    assert (motion.x.end, motion.y.end) == (KinematicState(10.0), KinematicState(20.0))
    assert motion.x.position_extrema() == (10.0, 10.0)
    _assert_tangential_limits(motion, XY)


def test_curved_start_brakes_within_the_path_limits():
    """Velocity and acceleration not parallel (a track arc, external setpoints): each axis
    brakes with the limits / √2, so the vector stays within the path limits."""
    start = (KinematicState(0.0, 500.0, 0.0), KinematicState(0.0, 0.0, 2000.0), REST)
    motion = plan_move_to_position(start, (-300.0, 100.0), XY)
    assert (motion.x.end, motion.y.end) == (KinematicState(-300.0), KinematicState(100.0))
    _assert_tangential_limits(motion, XY)


def _corner_time(motion: PlanarMotion) -> float:
    """When the braking piece comes to rest (the first later segment boundary at rest)."""
    at_rest = (motion.x.v == 0.0) & (motion.y.v == 0.0) & (motion.x.t > 0.0)
    return float(motion.x.t[np.flatnonzero(at_rest)[0]])


@pytest.mark.parametrize(("start", "target"), [
    (_at_rest(), (600.0, 0.0)),  # the target is outside
    ((KinematicState(400.0, 1000.0), REST, REST), (0.0, 300.0)),  # braking overshoots
])
def test_xy_position_limits(start, target):
    limits = PositionLimits(-500.0, 500.0)
    with pytest.raises(CommandRejected) as rejected:
        plan_move_to_position(start, target, XY, x_limits=limits, y_limits=limits)
    assert rejected.value.error_id == ErrorId.PLANAR_POSITION_LIMIT


def test_xy_target_on_the_limit_is_allowed():
    limits = PositionLimits(-500.0, 500.0)
    motion = plan_move_to_position(_at_rest(), (500.0, -500.0), XY, x_limits=limits,
                                   y_limits=limits)
    assert motion.y.end == KinematicState(-500.0)


@pytest.mark.parametrize("target", [(math.nan, 0.0), (0.0, math.inf), (0.0, 0.0, math.nan)])
def test_target_must_be_finite(target):
    with pytest.raises(CommandRejected) as rejected:
        plan_move_to_position(_at_rest(), target, XY, C)
    assert rejected.value.error_id == ErrorId.PLANAR_INVALID_INPUT


def test_c_target_needs_c_limits():
    with pytest.raises(ValueError):
        plan_move_to_position(_at_rest(), (0.0, 0.0, 10.0), XY)


# MoveZ / MoveA / MoveB and Halt -----------------------------------------------------------------

@pytest.mark.parametrize(("coordinate", "target"), [("z", 5.0), ("a", 1.0), ("b", -1.0)])
def test_manual_6_1_5_auxiliary_axes(coordinate, target):
    """§6.1.5: z 5 mm, a 1°, b -1° reached exactly (the manual shows 0.9999999999)."""
    profile = plan_axis_move(REST, target, Limits(50.0, 500.0, 500.0, 5000.0),
                             PositionLimits(-5.0, 5.0), coordinate)
    assert profile.end == KinematicState(target)


def test_auxiliary_target_outside_its_limits():
    with pytest.raises(CommandRejected) as rejected:
        plan_axis_move(REST, 5.5, Limits(50.0, 500.0, 500.0, 5000.0), PositionLimits(0.0, 5.0))
    assert rejected.value.error_id == ErrorId.PLANAR_POSITION_LIMIT


def test_auxiliary_overshoot_beyond_its_limits():
    with pytest.raises(CommandRejected) as rejected:
        plan_axis_move(KinematicState(4.0, 50.0), 4.5, Limits(50.0, 500.0, 500.0, 5000.0),
                       PositionLimits(0.0, 5.0))
    assert rejected.value.error_id == ErrorId.PLANAR_POSITION_LIMIT


def test_auxiliary_from_outside_may_come_back():
    profile = plan_axis_move(KinematicState(7.0), 5.0, Limits(50.0, 500.0, 500.0, 5000.0),
                             PositionLimits(0.0, 5.0))
    assert profile.end == KinematicState(5.0)


def test_halt_stops_xy_on_its_path_and_every_other_coordinate():
    moving = plan_move_to_position(_at_rest(), (300.0, 400.0), XY)
    t = moving.duration / 3.0
    states = {name: KinematicState(*profile.at(t)[:3])
              for name, profile in (("x", moving.x), ("y", moving.y))}
    states |= {"z": KinematicState(1.0, 20.0, 0.0), "c": REST}
    aux = Limits(50.0, 500.0, 400.0, 5000.0)
    halted = plan_halt(states, {"xy": XY, "z": aux, "c": C})
    assert list(halted) == ["x", "y", "z", "c"]
    motion = PlanarMotion(halted["x"], halted["y"], None, 0.0)
    x, y = _dense(motion)
    assert _distance_from_line(np.column_stack((x[0], y[0])), (0, 0), (300, 400)).max() <= EPS
    assert np.all(x[1] >= -EPS) and halted["x"].end.velocity == 0.0
    _assert_tangential_limits(motion, XY)
    assert halted["z"].end.velocity == 0.0 and halted["z"].end.position > 1.0
    assert halted["c"].duration == 0.0


# properties -------------------------------------------------------------------------------------

def _limits() -> st.SearchStrategy[Limits]:
    """Limits over several decades, acceleration and deceleration drawn apart."""
    decades = st.floats(0.0, 3.0).map(lambda e: 10.0 ** e)
    return st.builds(lambda v, a, d, j: Limits(10.0 * v, 100.0 * a, 100.0 * d, 1000.0 * j),
                     decades, decades, decades, decades)


coordinate = st.floats(-2000.0, 2000.0, allow_nan=False)


speeds = st.one_of(st.just(0.0), st.floats(1e-3, 1.0), st.floats(-1.0, -1e-3))


@given(limits=_limits(), x0=coordinate, y0=coordinate, tx=coordinate, ty=coordinate,
       speed=speeds, along=st.booleans(), heading=st.floats(0.0, 2 * math.pi),
       c_target=st.one_of(st.none(), st.just(0.0),
                          st.floats(-14.0, 14.0).filter(lambda c: abs(c) > 1e-6)))
def test_any_move_is_straight_within_limits_and_exact(limits, x0, y0, tx, ty, speed, along,
                                                      heading, c_target):
    """From rest or moving (along the line or in any other direction): the end is exact, the
    tangential limits hold, the path is the line (or the current line of motion to a rest
    point, then the line), C ends with the path, and from rest the duration is ruckig's 1-D
    optimum."""
    length = math.hypot(tx - x0, ty - y0)
    assume(length > 1e-3)
    angle = math.atan2(ty - y0, tx - x0) if along else heading
    v = speed * limits.velocity
    start = (KinematicState(x0, v * math.cos(angle)), KinematicState(y0, v * math.sin(angle)),
             REST)
    target = (tx, ty) if c_target is None else (tx, ty, c_target)
    motion = plan_move_to_position(start, target, limits, C, c_windows=CWindows())
    assert (motion.x.end, motion.y.end) == (KinematicState(tx), KinematicState(ty))
    _assert_tangential_limits(motion, limits)
    _assert_on_route(motion, (x0, y0), angle, (tx, ty))
    if c_target is not None:
        assert motion.c.end == KinematicState(c_target)
        if c_target != 0.0:  # a C that does not move has nothing to synchronise
            assert motion.c.duration == pytest.approx(motion.x.duration, abs=EPS)
    if speed == 0.0:
        optimum = _ruckig_duration(length, limits)
        if c_target is not None:
            optimum = max(optimum, _ruckig_duration(abs(c_target), C))
        assert motion.duration == pytest.approx(optimum, abs=EPS * max(1.0, optimum))


def _assert_on_route(motion: PlanarMotion, start: tuple[float, float], heading: float,
                     target: tuple[float, float]) -> None:
    """Before a rest inside the motion the mover stays on its line of motion; from the last
    such rest (or from the start) it is on the straight line to the target."""
    times, points = motion.sample(motion.duration / 500.0)
    scale = EPS * max(1.0, *np.abs(points[:, :2]).ravel())
    rests = (motion.x.v == 0.0) & (motion.y.v == 0.0) & (motion.x.t > 0.0) & (
        motion.x.t < motion.x.duration)
    corner_time = float(motion.x.t[rests][-1]) if rests.any() else 0.0
    corner = tuple(points[np.searchsorted(times, corner_time), :2])
    before, after = times <= corner_time, times >= corner_time
    ahead = (start[0] + math.cos(heading), start[1] + math.sin(heading))
    assert _distance_from_line(points[before, :2], start, ahead).max(initial=0.0) <= scale
    if math.dist(corner, target) > 1e-6:
        assert _distance_from_line(points[after, :2], corner, target).max() <= scale


# The same motions for less work -----------------------------------------------------------------

def _equal_limits() -> st.SearchStrategy[Limits]:
    """Limits over several decades with acceleration equal to deceleration."""
    decades = st.floats(0.0, 3.0).map(lambda e: 10.0 ** e)
    return st.builds(lambda v, a, j: Limits(10.0 * v, 100.0 * a, 100.0 * a, 1000.0 * j),
                     decades, decades, decades)


@given(limits=_equal_limits(), distance=st.floats(1e-3, 5000.0))
def test_rest_to_rest_time_is_ruckigs_optimum(limits, distance):
    """The closed form that tells the faster of path and C (ruckig is the oracle)."""
    assert rest_to_rest_time(distance, limits) == pytest.approx(
        _ruckig_duration(distance, limits), rel=1e-9)
    assert rest_to_rest_time(-distance, limits) == rest_to_rest_time(distance, limits)


@given(limits=st.one_of(_equal_limits(), _limits()), c_limits=_equal_limits(),
       tx=coordinate, ty=coordinate, c0=st.floats(-14.0, 14.0), c_target=st.floats(-14.0, 14.0),
       speed=speeds)
def test_knowing_the_faster_motion_beforehand_plans_the_same(limits, c_limits, tx, ty, c0,
                                                             c_target, speed):
    """Equivalence: with the closed-form durations MoveToPosition skips the optimal plan of
    the faster of path and C, which only its duration served; the profiles are the same."""
    start = (KinematicState(0.0, speed * limits.velocity), KinematicState(0.0),
             KinematicState(c0))
    target = (tx, ty, c_target)
    fast = plan_move_to_position(start, target, limits, c_limits)
    with mock.patch.object(motion_module, "_faster_from_rest", return_value=None):
        full = plan_move_to_position(start, target, limits, c_limits)
    for name in "xyc":
        assert np.array_equal(getattr(fast, name).data, getattr(full, name).data)


@given(limits=_equal_limits(), c_limits=_equal_limits(), tx=coordinate, ty=coordinate,
       c0=st.floats(-14.0, 14.0), c_target=st.one_of(st.none(), st.floats(-14.0, 14.0)))
def test_a_move_from_rest_in_closed_form_is_ruckigs_move(limits, c_limits, tx, ty, c0,
                                                         c_target):
    """From rest with acceleration equal to deceleration the path and C are planned in closed
    form (trajectory.double_s): the duration of ruckig's plan, the same straight path to the
    same target, and the slower of path and C the same motion (D-139)."""
    assume(math.hypot(tx, ty) >= 1e-3 and (c_target is None or abs(c_target - c0) >= 1e-3))
    start = _at_rest(0.0, 0.0, c0)
    target = (tx, ty) if c_target is None else (tx, ty, c_target)
    fast = plan_move_to_position(start, target, limits, c_limits)
    with mock.patch.object(motion_module, "_rest_move", return_value=None):
        oracle = plan_move_to_position(start, target, limits, c_limits)
    assert fast.duration == pytest.approx(oracle.duration, rel=1e-9, abs=1e-12)
    assert fast.s is not None
    for name in "xyc":
        mine, theirs = getattr(fast, name), getattr(oracle, name)
        if theirs is None:
            assert mine is None
            continue
        assert mine.p[-1] == theirs.p[-1] and mine.p[0] == theirs.p[0]
    times = np.linspace(0.0, fast.duration, 33)
    s = _evaluate(fast.s, times)[0]
    length = math.hypot(tx, ty)
    assert np.allclose(_evaluate(fast.x, times)[0], tx / length * s, atol=1e-9 * length)
    assert np.allclose(_evaluate(fast.y, times)[0], ty / length * s, atol=1e-9 * length)
    path_time = rest_to_rest_time(length, limits)
    turn_time = 0.0 if c_target is None else rest_to_rest_time(c_target - c0, c_limits)
    slower = "x" if path_time >= turn_time else "c"
    scale = max(1.0, length) if slower == "x" else max(1.0, abs(c_target - c0))
    assert np.allclose(_evaluate(getattr(fast, slower), times)[0],
                       _evaluate(getattr(oracle, slower), times)[0], atol=1e-8 * scale)


@given(limits=_equal_limits(), c_limits=_equal_limits(), x0=coordinate, y0=coordinate,
       tx=coordinate, ty=coordinate, c0=st.floats(-14.0, 14.0), c_target=st.floats(-20.0, 20.0),
       start_time=st.floats(0.0, 5.0))
def test_a_turning_move_from_rest_is_planned_and_swept_as_the_general_way(
        limits, c_limits, x0, y0, tx, ty, c0, c_target, start_time):
    """Equivalence: a turning MoveToPosition from rest is planned in one compiled pass, with
    the numbers of its swept area when the planner is given the ``sweep`` (D-327): the same
    profiles, the same C window verdict and message as the general way, and the samples and
    pieces of ``straight_run_area`` of those profiles."""
    start, target = _at_rest(x0, y0, c0), (tx, ty, c_target)
    sweep = straight_sweep(start_time, 0.01)

    def plan(**options: object) -> PlanarMotion | str:
        try:
            return plan_move_to_position(start, target, limits, c_limits,
                                         c_windows=CWindows(), **options)
        except CommandRejected as rejected:
            return f"{rejected.error_id.name}: {rejected.message}"

    fast = plan(sweep=sweep)
    with mock.patch.object(motion_module, "_turning_rest_move", return_value=None):
        general = plan()
    if isinstance(general, str):
        assert fast == general
        return
    for name in ("x", "y", "c", "s"):
        mine, theirs = getattr(fast, name), getattr(general, name)
        assert (mine is None) == (theirs is None)
        assert mine is None or np.array_equal(mine.data, theirs.data)
    if fast.swept is None:  # not from rest in closed form: planned the general way
        return
    plans = [(fast.x, start_time), (fast.y, start_time), (fast.c, start_time)]
    moving = [running(plan, start_time) for plan in plans]
    expected = straight_run_area(fast.s, plans, moving, moving[2], start_time, 0.01)
    found = straight_run_pieces(fast.swept, MOVER_WIDTH / 2, MOVER_HEIGHT / 2)
    assert (found is None) == (expected is None)
    if expected is None:
        return
    assert np.array_equal(found[0], expected[0])
    mine, theirs = found[1], expected[1]
    for name in ("until", "bounds", "keys", "key"):
        assert np.array_equal(getattr(mine, name), getattr(theirs, name))
    for i in range(len(theirs.until)):
        assert np.array_equal(mine.outline(i), theirs.outline(i))


def test_a_straight_move_from_rest_carries_its_arc_length():
    """``PlanarMotion.s``: x and y are x0 + ux s and y0 + uy s; none after a braking lead."""
    motion = plan_move_to_position(_at_rest(10.0, 20.0, 3.0), (310.0, -380.0, -9.0), XY, C)
    times = np.linspace(0.0, motion.duration, 101)
    s = _evaluate(motion.s, times)[0]
    assert np.allclose(_evaluate(motion.x, times)[0], 10.0 + 0.6 * s, atol=1e-9)
    assert np.allclose(_evaluate(motion.y, times)[0], 20.0 - 0.8 * s, atol=1e-9)
    assert np.all(np.diff(s) >= 0.0)
    moving = (KinematicState(0.0), KinematicState(0.0, 300.0), REST)
    assert plan_move_to_position(moving, (200.0, 0.0), XY).s is None


@st.composite
def _plans(draw: st.DrawFn) -> tuple[list[tuple[Profile, float]], float]:
    """x, y and c plans as a mover holds them: new ones from the start, older ones still
    running, standing ones, one cruising on."""
    start = draw(st.floats(0.0, 5.0))
    plans = []
    for _ in range(3):
        kind = draw(st.sampled_from(["new", "older", "standing", "cruising"]))
        p0 = draw(st.floats(-500.0, 500.0))
        if kind == "new":
            plans.append((plan_position(KinematicState(p0), draw(coordinate), XY), start))
        elif kind == "older":
            profile = plan_position(KinematicState(p0, draw(st.floats(-500.0, 500.0))),
                                    draw(coordinate), XY)
            plans.append((profile, start - draw(st.floats(0.0, 0.3))))
        elif kind == "standing":
            plans.append((Profile.hold(KinematicState(p0)), start - draw(st.floats(0.0, 1.0))))
        else:
            plans.append((Profile.hold(KinematicState(p0, 3.0)), start - 0.01))
    return plans, start


@given(plans=_plans(), distance=st.floats(0.0, 900.0), c_in_grid=st.booleans())
def test_straight_runs_are_the_sampled_numbers_of_the_straight_area(plans, distance, c_in_grid):
    """Equivalence, bit for bit: the compiled ``straight_runs`` gives the ``sample_times`` of
    the arc length s (and c), the ``travel_runs`` of s at them, and the x, y, c of the plans
    at the run ends as ``sample_path`` evaluates them (a resting plan: its end)."""
    plans, start = plans
    s = plan_position(KinematicState(0.0), distance, XY)
    (x, tx), (y, ty), (c, tc) = plans
    moving = [running(plan, start) for plan in plans]
    samples, ends, poses = straight_runs(s.data, x.data, tx, moving[0], y.data, ty, moving[1],
                                         c.data, tc, moving[2], c_in_grid, start, 0.01,
                                         RELEASE_STEP)
    grid = [(s, start), *([(c, tc)] if c_in_grid else [])]
    times = sample_times(grid, start, 0.01)
    assert np.array_equal(samples, times - start)
    assert np.array_equal(ends, travel_runs(_positions(s, samples), RELEASE_STEP)[1])
    at = times[[0, *ends.tolist()]]
    for k, plan in enumerate(plans):
        expected = _positions_at([plan], at)[0] if moving[k] else np.full(at.size, plan[0].p[-1])
        assert np.array_equal(poses[:, k], expected)
