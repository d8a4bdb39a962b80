"""Path moves of the Part 4 axes group: lines, circles, direct moves, stop, halt, interrupt.

PLCopen Part 4 §5.13-§5.16, §5.20-§5.27 (digest §3.13-§3.27; rules 45, 47, 62-66, 71-89 of
digest §6), with the manual's worked examples and their numbers:

- §5.14 Fig. 14: an arc from S (10, 10, 0) through (30, 30, 0) to E (50, 10, 0), halted and
  executed again; every point of it is 20 mm from (30, 10, 0);
- §5.25 Fig. 19: a MoveDirectRelative with Distance (10, 20) aborts a linear move from
  (10, 10) to (80, 35) where the TCP is at (44.5, 21.63) and ends at (54.5, 41.63);
- §5.13 Fig. 13: a stop on the contour between two blended lines from (20, 20); the manual
  gives only the start, the targets here are ours.

FBs are called once per cycle before ``rt.step()``, as in tests/transport/test_blocks.py.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import openmotion as om
from openmotion.coordinated.blocks import (
    MC_GroupContinue,
    MC_GroupHalt,
    MC_GroupInterrupt,
    MC_GroupStop,
    MC_MoveCircularAbsolute,
    MC_MoveCircularRelative,
    MC_MoveDirectAbsolute,
    MC_MoveDirectRelative,
    MC_MoveLinearAbsolute,
    MC_MoveLinearRelative,
    MC_MovePath,
    MC_PathSelect,
)
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem, TransitionMode
from openmotion.coordinated.kinematics import Scara
from openmotion.coordinated.states import AxesGroupState
from openmotion.core.enums import BufferMode
from openmotion.geometry.path import CircMode, PathChoice

G = AxesGroupState
ErrorId = om.ErrorId
AXIS = {"max_velocity": 1000.0, "max_acceleration": 20000.0, "max_deceleration": 20000.0,
        "max_jerk": 1.0e6}
TOL = 1e-6  #: [mm]
FAST = {"acceleration": 4000.0, "deceleration": 4000.0, "jerk": 1.0e5}


def group_of(*start: float, cycle_time: float = 0.001, **parameters: Any
             ) -> tuple[om.Runtime, AxesGroup, list[om.Axis]]:
    """Powered axes at ``start`` (IdentInGroup 1, 2, ...) in an enabled group."""
    rt = om.Runtime(cycle_time)
    group = AxesGroup(rt, "g")
    axes = []
    for ident, position in enumerate(start, 1):
        axis = rt.add_axis(f"a{ident}", position=position, **{**AXIS, **parameters})
        assert axis.power()
        assert group.add_axis(axis, ident).done
        axes.append(axis)
    assert group.enable().done
    return rt, group, axes


def tcp(group: AxesGroup) -> np.ndarray:
    return group.position(CoordSystem.MCS)


def speed(group: AxesGroup) -> float:
    return group.velocity(CoordSystem.MCS)[1]


def outputs(fb: Any) -> tuple[bool, bool, bool, bool, bool]:
    """busy, active, done, command_aborted, error."""
    return fb.busy, fb.active, fb.done, fb.command_aborted, fb.error


def trace(rt: om.Runtime, group: AxesGroup, until: Callable[[], bool],
          *calls: Callable[[], Any], limit: int = 20000) -> tuple[np.ndarray, np.ndarray]:
    """TCP positions (MCS) and path speeds after every cycle, calling ``calls`` before each
    step, until ``until()`` holds after the calls."""
    points, speeds = [tcp(group)], [speed(group)]
    for _ in range(limit):
        for call in calls:
            call()
        if until():
            return np.array(points), np.array(speeds)
        rt.step()
        points.append(tcp(group))
        speeds.append(speed(group))
    raise AssertionError(f"not reached within {limit} cycles")


def distance_to_segment(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    t = np.clip((points - a) @ ab / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(points - (a + t[:, None] * ab), axis=1)


def distance_to_polyline(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    best = np.full(len(points), np.inf)
    for a, b in zip(line[:-1], line[1:], strict=True):
        if np.linalg.norm(b - a) > 0.0:
            best = np.minimum(best, distance_to_segment(points, a, b))
    return best


# -- MC_MoveLinearAbsolute / Relative (§5.20, §5.21; rules 71-75) ------------------------------


def test_rules71_72_linear_absolute_runs_on_the_segment_and_ends_at_the_position():
    rt, group, axes = group_of(10.0, 20.0, 30.0)
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[70.0, -20.0, 50.0], velocity=150.0, **FAST)
    assert outputs(move) == (True, True, False, False, False)
    points, _ = trace(rt, group, lambda: move.done, move)
    assert outputs(move) == (False, False, True, False, False)
    target = np.array([70.0, -20.0, 50.0])
    assert np.allclose(tcp(group), target, atol=TOL, rtol=0.0)
    assert np.allclose(group.position(CoordSystem.ACS), target, atol=TOL, rtol=0.0)
    start = np.array([10.0, 20.0, 30.0])
    assert distance_to_segment(points, start, target).max() <= TOL
    progress = (points - start) @ (target - start)
    assert np.all(np.diff(progress) >= -1e-9)  # forward only
    move(execute=False)
    assert outputs(move) == (False, False, False, False, False)


@pytest.mark.parametrize("vel_factor", [1.0, 0.5])
def test_rule73_path_dynamics_stay_within_the_inputs_times_the_override(vel_factor):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    assert group.set_override(vel_factor).done
    v, a, d, j = 150.0, 800.0, 600.0, 20000.0
    move = group.move_linear_absolute([60.0, 80.0, 0.0], velocity=v, acceleration=a,
                                      deceleration=d, jerk=j)
    speeds, accelerations = [], []
    while not move.done:
        rt.step()
        speeds.append(speed(group))
        accelerations.append(group.acceleration(CoordSystem.MCS)[1])
    speeds, accelerations = np.array(speeds), np.array(accelerations)
    assert speeds.max() <= v * vel_factor * (1 + 1e-9)
    assert speeds.max() >= v * vel_factor * (1 - 1e-9)  # 100 mm is long enough to cruise
    assert accelerations.max() <= a * (1 + 1e-9)
    assert accelerations.min() >= -d * (1 + 1e-9)
    jerk = np.abs(np.diff(accelerations)) / rt.cycle_time
    assert jerk.max() <= j * (1 + 1e-6)


@pytest.mark.parametrize(("name", "value", "error_id"), [
    ("velocity", 0.0, ErrorId.INVALID_VELOCITY), ("velocity", -10.0, ErrorId.INVALID_VELOCITY),
    ("acceleration", 0.0, ErrorId.INVALID_ACCELERATION),
    ("deceleration", -1.0, ErrorId.INVALID_DECELERATION), ("jerk", 0.0, ErrorId.INVALID_JERK),
    ("velocity", float("nan"), ErrorId.INVALID_VELOCITY)], ids=str)
def test_rule74_dynamics_not_above_zero_are_errors(name, value, error_id):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[10.0, 0.0, 0.0], **{name: value})
    assert outputs(move) == (False, False, False, False, True)
    assert move.error_id is error_id
    assert group.state is G.STANDBY
    rt.run(0.05)
    assert np.array_equal(tcp(group), [0.0, 0.0, 0.0])


def test_rule75_linear_relative_from_the_start_and_buffered_from_the_previous_end():
    rt, group, axes = group_of(5.0, 6.0, 7.0)
    first, second = MC_MoveLinearRelative(group), MC_MoveLinearRelative(group)
    first(execute=True, distance=[10.0, 0.0, 0.0], **FAST)
    second(execute=True, distance=[0.0, 10.0, -7.0], buffer_mode=BufferMode.BUFFERED, **FAST)
    trace(rt, group, lambda: first.done, first, second)
    # at E1; the rest may fall between two samples, and in one cycle (jerk 1e5 mm/s³, 1 ms)
    # the next move gets at most j·dt³ = 1e-4 mm away
    assert np.allclose(tcp(group), [15.0, 6.0, 7.0], atol=1e-4, rtol=0.0)
    trace(rt, group, lambda: second.done, first, second)
    assert np.allclose(tcp(group), [15.0, 16.0, 0.0], atol=TOL, rtol=0.0)


# -- MC_MoveCircularAbsolute / Relative (§5.22, §5.23; rules 76-84) ---------------------------

S, AUX, E, CENTER = (np.array(p) for p in ((10.0, 10.0, 0.0), (30.0, 30.0, 0.0),
                                          (50.0, 10.0, 0.0), (30.0, 10.0, 0.0)))


def test_rule76_border_fig14_every_point_is_20_from_the_centre_and_passes_the_aux_point():
    rt, group, axes = group_of(*S)
    move = MC_MoveCircularAbsolute(group)
    move(execute=True, circ_mode=CircMode.BORDER, aux_point=AUX, end_point=E, **FAST)
    points, _ = trace(rt, group, lambda: move.done, move)
    assert np.abs(np.linalg.norm(points - CENTER, axis=1) - 20.0).max() <= TOL
    assert np.all(points[:, 1] >= 10.0 - TOL)  # the upper half, through (30, 30)
    assert points[:, 1].max() == pytest.approx(30.0, abs=1e-3)
    assert np.all(np.abs(points[:, 2]) <= TOL)
    assert np.allclose(tcp(group), E, atol=TOL, rtol=0.0)
    length = np.linalg.norm(np.diff(points, axis=0), axis=1).sum()
    assert length == pytest.approx(20.0 * math.pi, abs=1e-3)  # 180°


@pytest.mark.parametrize(("circ_mode", "aux", "end"), [
    (CircMode.BORDER, (20.0, 20.0, 0.0), (30.0, 30.0, 0.0)),  # rule 77: on one line
    (CircMode.BORDER, (20.0, 5.0, 0.0), (10.0, 10.0, 0.0)),  # rule 83: back to the start
    (CircMode.CENTER, (0.0, 10.0, 0.0), (0.0, 22.0, 0.0)),  # rule 78: radii 10 and 12
    (CircMode.CENTER, (10.0, 0.0, 0.0), (10.0, -10.0, 0.0)),  # rule 79: 180°
    (CircMode.CENTER, (0.0, 0.0, 0.0), (10.0, 10.0, 0.0)),  # rule 83: full circle
    (CircMode.RADIUS, (0.0, 0.0, 5.0), (30.0, 10.0, 0.0)),  # rule 82: radius 5 < 10
    (CircMode.RADIUS, (0.0, 0.0, 50.0), (10.0, 10.0, 0.0)),  # rule 83: full circle
], ids=["border-line", "border-full", "center-radii", "center-180", "center-full",
        "radius-short", "radius-full"])
def test_rules77_78_79_82_83_circles_that_do_not_exist_are_errors(circ_mode, aux, end):
    rt, group, axes = group_of(10.0, 10.0, 0.0)
    move = MC_MoveCircularAbsolute(group)
    move(execute=True, circ_mode=circ_mode, aux_point=aux, end_point=end)
    assert outputs(move) == (False, False, False, False, True)
    assert move.error_id is ErrorId.INVALID_PATH_GEOMETRY
    assert group.state is G.STANDBY


def test_rule80_center_path_choice_picks_one_of_two_arcs_of_the_circle():
    lengths, midpoints = {}, {}
    for choice in PathChoice:
        rt, group, axes = group_of(10.0, 0.0, 0.0)
        move = group.move_circular_absolute([0.0, 0.0, 0.0], [0.0, 10.0, 0.0],
                                            CircMode.CENTER, choice, **FAST)
        points, _ = trace(rt, group, lambda m=move: m.done)
        assert np.abs(np.linalg.norm(points, axis=1) - 10.0).max() <= TOL
        assert np.allclose(tcp(group), [0.0, 10.0, 0.0], atol=TOL, rtol=0.0)
        lengths[choice] = np.linalg.norm(np.diff(points, axis=0), axis=1).sum()
        midpoints[choice] = points[len(points) // 2]
    assert lengths[PathChoice.COUNTERCLOCKWISE] == pytest.approx(5.0 * math.pi, abs=1e-3)
    assert lengths[PathChoice.CLOCKWISE] == pytest.approx(15.0 * math.pi, abs=1e-3)
    assert sum(lengths.values()) == pytest.approx(20.0 * math.pi, abs=2e-3)  # 2πr
    assert midpoints[PathChoice.COUNTERCLOCKWISE][0] > 0.0  # short way: first quadrant
    assert midpoints[PathChoice.CLOCKWISE][0] < 0.0  # long way round


def test_rule81_radius_absolute_aux_50_0_0_gives_a_circle_parallel_to_y_z():
    """§5.22: AuxPoint (50, 0, 0) in MCS is the plane's normal, its length the radius 50;
    the arc turns right-handed about +x."""
    rt, group, axes = group_of(20.0, 0.0, 0.0)
    move = MC_MoveCircularAbsolute(group)
    move(execute=True, circ_mode=CircMode.RADIUS, aux_point=[50.0, 0.0, 0.0],
         end_point=[20.0, 60.0, 0.0], **FAST)
    points, _ = trace(rt, group, lambda: move.done, move)
    assert np.abs(points[:, 0] - 20.0).max() <= TOL  # the plane x = 20
    centre = np.array([20.0, 30.0, 40.0])  # the short circle through start and end
    assert np.abs(np.linalg.norm(points - centre, axis=1) - 50.0).max() <= TOL
    turning = np.cross(points[:-1] - centre, np.diff(points, axis=0)) @ [1.0, 0.0, 0.0]
    assert np.all(turning >= 0.0) and turning.max() > 0.0
    assert np.allclose(tcp(group), [20.0, 60.0, 0.0], atol=TOL, rtol=0.0)


def test_rule84_circular_relative_fig14_with_offsets_from_the_start():
    rt, group, axes = group_of(*S)
    move = MC_MoveCircularRelative(group)
    move(execute=True, circ_mode=CircMode.BORDER, aux_point=AUX - S, end_point=E - S, **FAST)
    points, _ = trace(rt, group, lambda: move.done, move)
    assert np.abs(np.linalg.norm(points - CENTER, axis=1) - 20.0).max() <= TOL
    assert np.allclose(tcp(group), E, atol=TOL, rtol=0.0)


def test_rule84_radius_relative_normal_from_the_start_turns_about_minus_y():
    """§5.23: AuxPoint (0, -30, 0) relative to the start: a circle of radius 30 in a plane
    parallel to x-z, turning right-handed about -y (against the right-hand rule about +y)."""
    rt, group, axes = group_of(10.0, 10.0, 0.0)
    move = group.move_circular_relative([0.0, -30.0, 0.0], [30.0, 0.0, 30.0], CircMode.RADIUS,
                                        **FAST)
    points, _ = trace(rt, group, lambda: move.done)
    assert np.abs(points[:, 1] - 10.0).max() <= TOL  # the plane y = 10
    centre = np.array([10.0, 10.0, 30.0])  # the short circle through start and end
    assert np.abs(np.linalg.norm(points - centre, axis=1) - 30.0).max() <= TOL
    turning = np.cross(points[:-1] - centre, np.diff(points, axis=0)) @ [0.0, -1.0, 0.0]
    assert np.all(turning >= 0.0) and turning.max() > 0.0
    assert np.allclose(tcp(group), [40.0, 10.0, 30.0], atol=TOL, rtol=0.0)


def test_rule108_speed_on_a_small_circle_respects_the_axes_acceleration():
    rt, group, axes = group_of(5.0, 0.0, 0.0, max_acceleration=2000.0,
                               max_deceleration=2000.0, acceleration=2000.0,
                               deceleration=2000.0)
    move = group.move_circular_absolute([0.0, 0.0, 0.0], [0.0, 5.0, 0.0], CircMode.CENTER,
                                        PathChoice.CLOCKWISE, velocity=500.0, **FAST)
    _, speeds = trace(rt, group, lambda: move.done)
    assert speeds.max() <= math.sqrt(2000.0 * 5.0) * (1 + 1e-9)  # v²/r within a_max
    accelerations = []
    move = group.move_circular_absolute([0.0, 0.0, 0.0], [5.0, 0.0, 0.0], CircMode.CENTER,
                                        PathChoice.CLOCKWISE, velocity=500.0, **FAST)
    while not move.done:
        rt.step()
        accelerations.append([a.set_acceleration for a in axes])
    assert np.abs(accelerations).max() <= 2000.0 * (1 + 1e-6)


# -- MC_MoveDirectAbsolute / Relative (§5.24, §5.25; rules 85-87) -----------------------------


def test_rule85_direct_move_keeps_every_axis_in_its_limits_and_all_end_together():
    rt = om.Runtime()
    group = AxesGroup(rt, "g")
    slow = rt.add_axis("slow", **{**AXIS, "max_velocity": 50.0, "max_acceleration": 500.0,
                                  "max_deceleration": 500.0, "acceleration": 500.0,
                                  "deceleration": 500.0})
    quick = rt.add_axis("quick", **AXIS)
    for ident, axis in enumerate((slow, quick), 1):
        axis.power()
        group.add_axis(axis, ident)
    group.enable()
    move = MC_MoveDirectAbsolute(group)
    move(execute=True, position=[100.0, -60.0], coord_system=CoordSystem.ACS)
    samples = []
    while not move.done:
        rt.step()
        move()
        samples.append([slow.set_velocity, quick.set_velocity, slow.set_acceleration])
    samples = np.array(samples)
    assert np.abs(samples[:, 0]).max() <= 50.0 * (1 + 1e-9)
    assert np.abs(samples[:, 2]).max() <= 500.0 * (1 + 1e-6)
    moving = np.abs(samples[:, :2]) > 0.0
    assert np.array_equal(moving[:, 0], moving[:, 1])  # start and end in the same cycle
    assert group.position(CoordSystem.ACS) == pytest.approx([100.0, -60.0], abs=TOL)


def test_rule86_fig19_direct_relative_aborts_the_line_at_44_5_21_63_and_ends_at_54_5_41_63():
    """§5.25 Fig. 19 (MCS): a line from p0 (10, 10) to p1 (80, 35), aborted by a
    MoveDirectRelative with Distance (10, 20) where the TCP is at (44.5, 21.63).

    The manual's abort point lies 0.69 mm off its line; here the line is moved by that
    amount (a dry run finds where the TCP is in the cycle of the abort), so the TCP is at
    (44.5, 21.63) exactly when the direct move starts.
    """
    p0, p1, abort = np.array([10.0, 10.0]), np.array([80.0, 35.0]), np.array([44.5, 21.63])

    def run(shift: np.ndarray, abort_cycle: int | None) -> tuple[Any, ...]:
        rt, group, axes = group_of(*(p0 + shift))
        line, direct = MC_MoveLinearAbsolute(group), MC_MoveDirectRelative(group)
        line(execute=True, position=p1 + shift, velocity=100.0)
        cycle = 0

        def before_abort() -> bool:
            if abort_cycle is None:
                return tcp(group)[0] < abort[0]
            return cycle < abort_cycle

        while before_abort():
            rt.step()
            line()
            cycle += 1
        return rt, group, line, direct, cycle

    _, group, *_, cycle = run(np.zeros(2), None)
    rt, group, line, direct, _ = run(abort - tcp(group), cycle)
    assert tcp(group) == pytest.approx(abort, abs=1e-9)
    direct(execute=True, distance=[10.0, 20.0], coord_system=CoordSystem.MCS)
    line()
    assert outputs(line) == (False, False, False, True, False)  # CommandAborted
    assert direct.busy and direct.active and not direct.error
    while not direct.done:
        rt.step()
        direct()
        line()
    assert outputs(direct) == (False, False, True, False, False)
    assert tcp(group) == pytest.approx([54.5, 41.63], abs=TOL)


def test_rule87_direct_move_of_a_scara_is_no_straight_line_in_mcs():
    rt, group, axes = group_of(0.0, 90.0)
    assert group.disable().done
    assert group.set_kinematics(Scara(300.0, 200.0)).done
    assert group.enable().done
    start = tcp(group)
    assert start == pytest.approx([300.0, 200.0], abs=1e-9)
    move = group.move_direct_absolute([100.0, 350.0], coord_system=CoordSystem.MCS)
    points, _ = trace(rt, group, lambda: move.done)
    assert tcp(group) == pytest.approx([100.0, 350.0], abs=TOL)
    off_chord = distance_to_segment(np.c_[points, np.zeros(len(points))],
                                    np.r_[start, 0.0], np.array([100.0, 350.0, 0.0]))
    assert off_chord.max() > 1.0


# -- MC_PathSelect, MC_MovePath (§5.26, §5.27; rules 88, 89) -----------------------------------

PATH = [{"line": [40.0, 0.0, 0.0]}, {"line": [40.0, 40.0, 0.0]},  # then back down round
        {"arc": [0.0, 40.0, 0.0], "aux": [20.0, 20.0, 0.0], "circ_mode": "BORDER"}]


def test_rules88_89_path_select_then_move_path_to_its_end():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    select, move = MC_PathSelect(group), MC_MovePath(group)
    select(execute=True, path_description=PATH)
    assert outputs(select) == (False, False, True, False, False)
    assert select.path_data is not None
    move(execute=True, path_data=select.path_data, velocity=200.0, **FAST)
    assert move.busy and move.active
    points, _ = trace(rt, group, lambda: move.done, move)
    assert np.allclose(tcp(group), [0.0, 40.0, 0.0], atol=TOL, rtol=0.0)
    # a reversal: an exact stop at (40, 40), between two samples (jerk 1e5, 1 ms)
    assert np.linalg.norm(points - [40.0, 40.0, 0.0], axis=1).min() <= 1e5 * 1e-9
    on_arc = points[(np.abs(points[:, 0] - 40.0) > TOL) & (points[:, 1] > 1.0)]
    assert len(on_arc) > 100
    assert np.abs(np.linalg.norm(on_arc - [20.0, 40.0, 0.0], axis=1) - 20.0).max() <= TOL


def test_rule107_path_select_keeps_the_deviation_at_a_tangent_joint():
    """§7.4.5: e is the shortest distance between the programmed corner, here the tangent
    joint of a line and an arc, and the contour (default e = 0.1 mm). 0.1 ms cycles: at
    200 mm/s the samples lie 0.02 mm apart, so the sampled closest approach is within 5e-4 mm
    of the contour's (1 ms samples, 0.2 mm apart, can miss it by 0.04 mm)."""
    rt, group, axes = group_of(0.0, 0.0, 0.0, cycle_time=1e-4)
    select, move = MC_PathSelect(group), MC_MovePath(group)
    select(execute=True, path_description=[
        {"line": [40.0, 0.0, 0.0]}, {"line": [40.0, 40.0, 0.0]},
        {"arc": [0.0, 40.0, 0.0], "aux": [20.0, 60.0, 0.0], "circ_mode": "BORDER"}])
    joint = np.array([40.0, 40.0, 0.0])
    _, contour, arc = select.path_data.elements
    assert contour.distance_to(joint) == pytest.approx(0.1, abs=1e-9)
    move(execute=True, path_data=select.path_data, velocity=200.0, **FAST)
    points, _ = trace(rt, group, lambda: move.done, move, limit=100000)
    assert np.linalg.norm(points - joint, axis=1).min() <= 0.1 + 1e-3
    on_arc = points[(points[:, 1] > 40.0) & (points[:, 0] < arc.start[0] - TOL)]
    assert len(on_arc) > 100  # past the contour the TCP is back on the programmed arc
    assert np.abs(np.linalg.norm(on_arc - [20.0, 40.0, 0.0], axis=1) - 20.0).max() <= TOL
    assert np.allclose(tcp(group), [0.0, 40.0, 0.0], atol=TOL, rtol=0.0)


@pytest.mark.parametrize("description", [[], "line", [{"line": [1.0, 2.0]}, {"foo": 1}],
                                         [{"arc": [1.0, 0.0, 0.0]}]], ids=str)
def test_rule88_bad_path_descriptions_are_errors(description):
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    select = MC_PathSelect(group)
    select(execute=True, path_description=description)
    assert select.error and select.error_id is not ErrorId.NO_ERROR
    assert select.path_data is None


def test_rule88_move_path_without_path_data_is_an_error():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move = MC_MovePath(group)
    move(execute=True, path_data=None)
    assert outputs(move) == (False, False, False, False, True)
    assert move.error_id is ErrorId.INVALID_PATH_GEOMETRY
    assert group.state is G.STANDBY


# -- stop and halt on the path (§5.13, §5.14; rules 45, 47, 62, 63) ---------------------------


def fig14_arc(group: AxesGroup) -> MC_MoveCircularAbsolute:
    move = MC_MoveCircularAbsolute(group)
    move(execute=True, circ_mode=CircMode.BORDER, aux_point=AUX, end_point=E, velocity=100.0)
    return move


def test_rule63_fig14_halt_and_the_same_arc_again_stay_on_the_circle_and_end_at_e():
    rt, group, axes = group_of(*S)
    arc, halt = fig14_arc(group), MC_GroupHalt(group)
    before, _ = trace(rt, group, lambda: tcp(group)[0] >= 15.0, arc)  # S -> H
    halt(execute=True, deceleration=1000.0)
    arc()
    assert arc.command_aborted and halt.active
    braking, _ = trace(rt, group, lambda: speed(group) < 60.0, arc, halt)  # H -> R
    assert tcp(group)[0] < 30.0  # the aux point is still ahead
    again = fig14_arc(group)  # R: the same inputs, a new edge
    halt()
    assert outputs(halt) == (False, False, False, True, False)  # a move may abort a halt
    assert again.busy and again.active
    after, _ = trace(rt, group, lambda: again.done, again, halt)  # R -> E
    points = np.vstack([before, braking, after])
    assert np.abs(np.linalg.norm(points - CENTER, axis=1) - 20.0).max() <= TOL
    assert np.all(points[:, 1] >= 10.0 - TOL)
    assert np.allclose(tcp(group), E, atol=TOL, rtol=0.0)
    rt.step()
    assert group.state is G.STANDBY


def test_rule62_a_move_aborting_a_halt_never_reaches_standstill():
    rt, group, axes = group_of(*S)
    arc, halt = fig14_arc(group), MC_GroupHalt(group)
    trace(rt, group, lambda: tcp(group)[0] >= 15.0, arc)
    halt(execute=True, deceleration=1000.0)
    trace(rt, group, lambda: speed(group) < 60.0, arc, halt)
    again = fig14_arc(group)
    _, speeds = trace(rt, group, lambda: tcp(group)[0] >= 45.0, again, halt)
    assert speeds.min() > 0.0


def test_rule62_a_move_off_the_halted_path_still_stops_first():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move, halt = group.move_linear_absolute([100.0, 0.0, 0.0], velocity=100.0), MC_GroupHalt(group)
    trace(rt, group, lambda: tcp(group)[0] >= 20.0)
    halt(execute=True, deceleration=500.0)
    trace(rt, group, lambda: speed(group) < 60.0, halt)
    turn = MC_MoveLinearAbsolute(group)  # a corner: the direction cannot jump (D-132, D-110)
    turn(execute=True, position=[40.0, 50.0, 0.0], velocity=100.0)
    halt()
    assert move.aborted and halt.command_aborted and turn.active
    points, speeds = trace(rt, group, lambda: turn.done, turn, halt)
    rest = int(np.argmax(speeds == 0.0))
    assert rest > 0 and np.all(points[:rest + 1, 1] == 0.0)  # braked on the x line to rest
    assert np.allclose(tcp(group), [40.0, 50.0, 0.0], atol=TOL, rtol=0.0)


def test_rule45_stop_on_an_arc_stays_on_it_and_the_speed_only_falls():
    rt, group, axes = group_of(*S)
    arc, stop = fig14_arc(group), MC_GroupStop(group)
    trace(rt, group, lambda: tcp(group)[0] >= 25.0, arc)
    stop(execute=True, deceleration=200.0)
    points, speeds = trace(rt, group, lambda: stop.done, stop)
    assert np.abs(np.linalg.norm(points - CENTER, axis=1) - 20.0).max() <= TOL
    assert np.all(np.diff(speeds) <= 1e-9) and speeds[-1] == 0.0
    assert points[-1][0] > points[0][0]  # braked forward along the arc


def test_rule47_stop_during_a_direct_move_keeps_each_axis_within_its_limits():
    rt, group, axes = group_of(0.0, 0.0, max_deceleration=1500.0, max_acceleration=1500.0,
                               acceleration=1500.0, deceleration=1500.0)
    move = group.move_direct_absolute([300.0, 100.0])
    rt.run(0.3)
    assert move.active
    stop = group.stop(deceleration=10000.0)
    decelerations = []
    while not stop.done:
        rt.step()
        decelerations.append([a.set_acceleration for a in axes])
    assert np.abs(decelerations).max() <= 1500.0 * (1 + 1e-6)


def reference_path(start: np.ndarray, moves: list[dict[str, Any]]) -> np.ndarray:
    """The path two blended moves take without a stop, sampled finely (0.25 ms cycles: at
    most 0.025 mm apart, off the contour by less than 1e-5 mm)."""
    rt, group, axes = group_of(*start, cycle_time=2.5e-4)
    commands = [group.move_linear_absolute(**m) for m in moves]
    points, _ = trace(rt, group, lambda: commands[-1].done, limit=200000)
    return points


FIG13 = [
    {"position": [60.0, 20.0], "velocity": 100.0},
    {"position": [60.0, 60.0], "velocity": 100.0, "buffer_mode": BufferMode.BLENDING_PREVIOUS,
     "transition_mode": TransitionMode.TM_CONSTANT_VELOCITY, "transition_parameter": [50.0]},
]


def test_rules38_39_45_112_fig13_stop_on_a_blend_contour_brakes_along_it():
    """§5.13 Fig. 13: from (20, 20) two blended MoveLinearAbsolute with a constant contour
    velocity; the stop comes just after the TCP entered the contour."""
    start = np.array([20.0, 20.0])
    rt, group, axes = group_of(*start)
    lin1, lin2, stop = (MC_MoveLinearAbsolute(group), MC_MoveLinearAbsolute(group),
                        MC_GroupStop(group))
    lin1(execute=True, **FIG13[0])  # t0
    lin2(execute=True, **FIG13[1])
    assert lin1.active and lin2.busy and not lin2.active
    trace(rt, group, lambda: lin2.active, lin1, lin2)  # the TCP enters the contour
    assert lin1.done
    corner = np.array([60.0, 20.0])
    assert np.linalg.norm(tcp(group) - corner) > 0.0
    assert tcp(group)[0] < 60.0 and tcp(group)[1] > 20.0 - 1e-12
    stop(execute=True)  # t1
    lin2()
    assert group.state is G.STOPPING
    assert outputs(lin2) == (False, False, False, True, False)
    points, speeds = trace(rt, group, lambda: stop.done, stop, lin1, lin2)  # t1 -> t2
    assert np.all(np.diff(speeds) <= 1e-9) and speeds[-1] == 0.0  # path speed only falls
    reference = reference_path(start, FIG13)
    assert distance_to_polyline(points, reference).max() <= 1e-4  # along the contour
    assert np.linalg.norm(points[-1] - points[0]) > 1.0  # it did brake a while
    rt.run(0.1)
    stop()
    assert group.state is G.STOPPING and stop.done and stop.busy  # t2: Execute still TRUE
    stop(execute=False)  # t3
    assert outputs(stop) == (False, False, False, False, False)
    rt.step()
    assert group.state is G.STANDBY


# -- MC_GroupInterrupt, MC_GroupContinue (§5.15, §5.16; rules 64-66) --------------------------


def test_rules64_65_interrupt_keeps_the_move_busy_and_continue_finishes_it():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move, interrupt, resume = (MC_MoveLinearAbsolute(group), MC_GroupInterrupt(group),
                               MC_GroupContinue(group))
    move(execute=True, position=[100.0, 0.0, 0.0], velocity=100.0)
    trace(rt, group, lambda: tcp(group)[0] >= 30.0, move)
    interrupt(execute=True)
    move()
    assert interrupt.busy and not interrupt.error
    assert outputs(move) == (True, False, False, False, False)  # Busy, not Active (§5.15)
    trace(rt, group, lambda: interrupt.done, move, interrupt)
    assert speed(group) == 0.0 and np.all([a.set_velocity == 0.0 for a in axes])
    assert group.state is G.MOVING
    assert outputs(move) == (True, False, False, False, False)
    held = tcp(group).copy()
    rt.run(0.1)
    assert np.array_equal(tcp(group), held)
    resume(execute=True)
    assert resume.done and not resume.error
    rt.step()
    move()
    assert outputs(move) == (True, True, False, False, False)  # Active again
    trace(rt, group, lambda: move.done, move, resume)
    assert np.allclose(tcp(group), [100.0, 0.0, 0.0], atol=TOL, rtol=0.0)


def test_rule65_the_interrupted_move_is_active_when_continue_is_done():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    move = MC_MoveLinearAbsolute(group)
    move(execute=True, position=[100.0, 0.0, 0.0], velocity=100.0)
    trace(rt, group, lambda: tcp(group)[0] >= 30.0, move)
    interrupt = group.interrupt()
    trace(rt, group, lambda: interrupt.done, move)
    resume = MC_GroupContinue(group)
    resume(execute=True)
    move()
    assert resume.done
    assert move.active


def test_rule66_continue_without_an_interrupt_is_an_error():
    rt, group, axes = group_of(0.0, 0.0, 0.0)
    group.move_linear_absolute([100.0, 0.0, 0.0])
    rt.run(0.1)
    resume = MC_GroupContinue(group)
    resume(execute=True)
    assert resume.error and resume.error_id is ErrorId.NOTHING_TO_DO
    assert group.state is G.MOVING
