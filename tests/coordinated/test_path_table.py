"""TF5410 §9.3's path tables on the Part 4 group (coordinated/path_table.py; issue 20
point 8): the *Preparation blocks, MC_PATH_DATA_REF with ClearPath, MC_MovePath over it,
blockers, dwell times, coordinate transforms in the table, and the data types' numbers.

The manual's one worked example is the centre-point sample of §9.3.1.2.4 (N10-N40); the
other tests take the rules of §9.3.1.1.10, §9.3.1.2.3-§9.3.1.2.9 and §9.3.2 one by one.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import openmotion as om
from openmotion.coordinated.blocks import (
    MC_BlockerPreparation,
    MC_DwellTimePreparation,
    MC_GroupHalt,
    MC_GroupReadBlockerStatus,
    MC_GroupStop,
    MC_MoveCircularAbsolutePreparation,
    MC_MoveLinearAbsolute,
    MC_MoveLinearAbsolutePreparation,
    MC_MovePath,
    MC_ReleaseBlocker,
    MC_SetCoordinateTransformPreparation,
)
from openmotion.coordinated.frames import Frame
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem, PathDynamics
from openmotion.coordinated.path_table import (
    MAX_ROWS,
    MC_COORD_REF,
    MC_PATH_DATA_REF,
    ROW_BYTES,
    McCircMode,
    McCircPathChoice,
    McTransitionMode,
)
from openmotion.coordinated.states import AxesGroupState
from openmotion.core.enums import BufferMode
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE, MC_MAXIMUM

G = AxesGroupState
ErrorId = om.ErrorId
B = BufferMode
AXIS = {"max_velocity": 5000.0, "max_acceleration": 50000.0, "max_deceleration": 50000.0,
        "max_jerk": 1.0e7}
DYNAMICS = PathDynamics(velocity=500.0, acceleration=10000.0, deceleration=10000.0,
                        jerk=1.0e6, max_velocity=5000.0, max_acceleration=20000.0,
                        max_deceleration=20000.0, max_jerk=1.0e7)
TOL = 1e-6  #: [mm]
CYCLE = 0.001  #: [s]
#: [mm/s] the path speed of the sample nearest an exact stop: the rest falls between two
#: samples (a 1 ms cycle from 10000 mm/s² takes the speed to 0 within one cycle)
STOPPED = 1.0
NEAR = 1e-3  #: [mm] samples this near a corner count as at it


def group_of(*start: float) -> tuple[om.Runtime, AxesGroup]:
    """Powered axes at ``start`` (a Cartesian gantry, IdentInGroup 1, 2, ...), enabled."""
    rt = om.Runtime(CYCLE)
    group = AxesGroup(rt, "g", DYNAMICS)
    for ident, position in enumerate(start, 1):
        axis = rt.add_axis(f"a{ident}", position=position, **AXIS)
        assert axis.power()
        assert group.add_axis(axis, ident).done
    assert group.enable().done
    return rt, group


def tcp(group: AxesGroup) -> np.ndarray:
    return group.position(CoordSystem.MCS, actual=False)


def run(rt: om.Runtime, group: AxesGroup, fb: Any, until: Callable[[], bool],
        *calls: Callable[[], Any], limit: int = 20000) -> tuple[np.ndarray, np.ndarray]:
    """Call ``fb(execute=True)`` and ``calls`` every cycle, step, and record the TCP and the
    path speed after each step, until ``until()`` holds after the calls."""
    points, speeds = [tcp(group)], [group.motion.path_velocity]
    for _ in range(limit):
        fb(execute=True)
        for call in calls:
            call()
        if until():
            return np.array(points), np.array(speeds)
        rt.step()
        points.append(tcp(group))
        speeds.append(group.motion.path_velocity)
    raise AssertionError(f"not reached within {limit} cycles")


def outputs(fb: Any) -> tuple[bool, bool, bool, bool, bool]:
    """busy, active, done, command_aborted, error."""
    return fb.busy, fb.active, fb.done, fb.command_aborted, fb.error


def line(path: MC_PATH_DATA_REF, position: list[float], **inputs: Any
         ) -> MC_MoveLinearAbsolutePreparation:
    fb = MC_MoveLinearAbsolutePreparation()
    fb(path, position=position, **{"velocity": 500.0, "buffer_mode": B.BUFFERED, **inputs})
    assert not fb.error, fb.message
    return fb


def centre_point_sample() -> MC_PATH_DATA_REF:
    """§9.3.1.2.4, "Sample of center point programming": N10 line, N20 and N30 quarter
    circles about centres given as AuxPoint (both CounterClockwise), N40 line; Buffered with
    mcTransModeNone and two transition parameters 0, as the sample sets them."""
    path = MC_PATH_DATA_REF(4096)  # Buffer: ARRAY[1..4096] OF BYTE
    lin, circ = MC_MoveLinearAbsolutePreparation(), MC_MoveCircularAbsolutePreparation()
    common = {"buffer_mode": B.BUFFERED, "transition_mode": McTransitionMode.NONE,
              "transition_parameter": [0.0, 0.0]}
    lin(path, position=[200, 0, 0], velocity=3000, invoke_id=10, **common)
    assert not lin.error, lin.message
    for end, centre, invoke in (([300, -100, 0], [200, -100, 0], 20),
                                ([400, -200, 0], [400, -100, 0], 30)):
        circ(path, circ_mode=McCircMode.CENTER, end_point=end, aux_point=centre,
             path_choice=McCircPathChoice.COUNTERCLOCKWISE, velocity=1000, invoke_id=invoke,
             **common)
        assert not circ.error, circ.message
    lin(path, position=[600, -200, 100], velocity=3000, invoke_id=40, **common)
    assert not lin.error, lin.message
    return path


# -- the manual's sample (§9.3.1.2.4) ------------------------------------------------------------


def test_9_3_1_2_4_centre_point_sample_n10_to_n40_runs_its_two_quarter_circles():
    """N20 turns about (200, -100, 0) and N30 about (400, -100, 0), each a quarter circle of
    radius 100 (CounterClockwise about the normal the cross product gives: the short arc);
    mcTransModeNone stops at every transition (§9.3.2.5); the arcs keep their 1000 mm/s."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = centre_point_sample()
    assert (path.filled_rows, path.occupied_buffer) == (4, 4 * ROW_BYTES)
    move = MC_MovePath(group)
    points, speeds = run(rt, group, lambda **_: move(execute=True, path_data=path),
                         lambda: move.done or move.error)
    assert not move.error, move.message
    assert tcp(group).tolist() == pytest.approx([600.0, -200.0, 100.0], abs=TOL)
    n20 = points[(points[:, 0] > 200.0 + TOL) & (points[:, 0] < 300.0 - TOL)]
    n30 = points[(points[:, 0] > 300.0 + TOL) & (points[:, 0] < 400.0 - TOL)]
    assert len(n20) > 50 and len(n30) > 50
    for arc, centre in ((n20, [200.0, -100.0]), (n30, [400.0, -100.0])):
        assert np.linalg.norm(arc[:, :2] - centre, axis=1) == pytest.approx(100.0, abs=TOL)
        assert np.all(np.abs(arc[:, 2]) <= TOL)
    # quarters, not three quarters: the path never leaves the band the two quarters span
    below = points[:, 1] < -TOL
    assert np.all(points[below, 0] >= 200.0 - TOL) and np.all(points[:, 1] <= TOL)
    assert np.all(points[points[:, 0] > 400.0 + TOL, 1] == pytest.approx(-200.0, abs=TOL))
    on_arcs = (points[:, 0] > 200.0 + TOL) & (points[:, 0] < 400.0 - TOL)
    assert speeds[on_arcs].max() <= 1000.0 * (1 + 1e-9)
    assert speeds.max() > 1000.0  # the lines run faster (3000 is clamped to the maximum)
    for corner in ([200.0, 0.0, 0.0], [300.0, -100.0, 0.0], [400.0, -200.0, 0.0]):
        near = np.linalg.norm(points - corner, axis=1) <= NEAR
        assert near.any() and speeds[near].min() <= STOPPED, corner  # an exact stop
    assert group.state is G.STANDBY


def test_9_3_2_4_the_table_is_not_reset_by_execution_and_runs_again():
    """§9.3.2.4: the path table is not reset at execution; ClearPath() resets it."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = centre_point_sample()
    move = MC_MovePath(group)
    run(rt, group, lambda **_: move(execute=True, path_data=path), lambda: move.done)
    assert path.filled_rows == 4
    move(execute=False)
    assert group.move_linear_absolute([0.0, 0.0, 0.0], velocity=2000.0).busy
    rt.run_until(lambda: group.state is G.STANDBY, 10.0)
    run(rt, group, lambda **_: move(execute=True), lambda: move.done)
    assert tcp(group).tolist() == pytest.approx([600.0, -200.0, 100.0], abs=TOL)
    path.ClearPath()
    assert (path.filled_rows, path.occupied_buffer) == (0, 0)
    line(path, [0.0, 0.0, 0.0])
    assert path.filled_rows == 1


# -- MC_PATH_DATA_REF and the *Preparation blocks' checks --------------------------------------


def test_9_3_2_4_a_table_holds_30_rows_and_a_refused_row_leaves_it_as_it_was():
    """§9.3.1.2.3 / §9.3.2.4: at most 30 entries; the 31st is an error, the table stays
    usable: ClearPath() makes room again."""
    path = MC_PATH_DATA_REF()
    for index in range(MAX_ROWS):
        line(path, [float(index), 0.0, 0.0])
    fb = MC_MoveLinearAbsolutePreparation()
    fb(path, position=[99.0, 0.0, 0.0], velocity=100.0, buffer_mode=B.BUFFERED)
    assert fb.error and fb.error_id == ErrorId.PATH_TABLE_FULL
    assert "30 rows" in fb.message and path.filled_rows == MAX_ROWS
    for block, inputs in ((MC_BlockerPreparation(), {"blocker_id": 1}),
                          (MC_DwellTimePreparation(), {"dwell_time": 0.1})):
        block(path, **inputs)
        assert block.error_id == ErrorId.PATH_TABLE_FULL
    path.ClearPath()
    fb(path)
    assert not fb.error and path.filled_rows == 1


def test_9_3_2_4_occupied_buffer_counts_bytes_and_a_small_buffer_fills_first():
    path = MC_PATH_DATA_REF(2 * ROW_BYTES)
    line(path, [1.0, 0.0, 0.0])
    line(path, [2.0, 0.0, 0.0])
    assert path.occupied_buffer == 2 * ROW_BYTES
    fb = MC_DwellTimePreparation()
    fb(path, dwell_time=0.0)
    assert fb.error_id == ErrorId.PATH_TABLE_FULL and "2 rows" in fb.message
    with pytest.raises(om.ConfigError, match="buffer_size"):
        MC_PATH_DATA_REF(10)


BAD_ROWS = [
    # (block, inputs, error id): §9.3.1.2.3/4 inputs, §9.3.2.5 combinations, §9.3.2.2 circles
    ("line", {"velocity": om.MC_INVALID}, ErrorId.INVALID_VELOCITY),  # the default
    ("line", {"velocity": 0.0}, ErrorId.INVALID_VELOCITY),
    ("line", {"acceleration": 0.5}, ErrorId.INVALID_ACCELERATION),
    ("line", {"deceleration": -1.0}, ErrorId.INVALID_DECELERATION),
    ("line", {"jerk": 50.0}, ErrorId.INVALID_JERK),
    ("line", {"position": [1.0, 2.0]}, ErrorId.INVALID_POSITION),  # the table has 3
    ("line", {"position": [1.0, math.nan, 0.0]}, ErrorId.INVALID_POSITION),
    ("line", {"buffer_mode": B.ABORTING}, ErrorId.INVALID_BUFFER_MODE),  # not the first row
    ("line", {"buffer_mode": B.BLENDING_PREVIOUS}, ErrorId.INVALID_BUFFER_MODE),  # with None
    ("line", {"buffer_mode": B.BLENDING_LOW}, ErrorId.INVALID_BUFFER_MODE),
    ("line", {"transition_mode": McTransitionMode.CORNER_DISTANCE,
              "transition_parameter": [5.0]}, ErrorId.INVALID_BUFFER_MODE),  # with Buffered
    ("line", {"transition_mode": McTransitionMode.MAX_CORNER_DEVIATION,
              "buffer_mode": B.BLENDING_PREVIOUS}, ErrorId.INVALID_MODE),  # not implemented
    ("line", {"transition_mode": 0x1005}, ErrorId.INVALID_MODE),
    ("line", {"transition_mode": McTransitionMode.CORNER_DISTANCE,
              "buffer_mode": B.BLENDING_PREVIOUS}, ErrorId.INVALID_TRANSITION_PARAMETER),
    ("line", {"transition_mode": McTransitionMode.CORNER_DISTANCE_ADVANCED,
              "buffer_mode": B.BLENDING_PREVIOUS, "transition_parameter": [5.0]},
     ErrorId.INVALID_TRANSITION_PARAMETER),  # needs two
    ("line", {"transition_mode": McTransitionMode.CORNER_DISTANCE,
              "buffer_mode": B.BLENDING_PREVIOUS, "transition_parameter": [0.0]},
     ErrorId.INVALID_TRANSITION_PARAMETER),
    ("circle", {"circ_mode": McCircMode.INVALID}, ErrorId.INVALID_MODE),  # the default
    ("circle", {"path_choice": 0x3004}, ErrorId.INVALID_MODE),
    ("circle", {"aux_point": [50.0, 0.0]}, ErrorId.INVALID_POSITION),  # always 3 values
    ("circle", {"aux_point": [50.0, 10.0, 0.0]}, ErrorId.INVALID_PATH_GEOMETRY),  # off-centre
    ("circle", {"aux_point": [50.0, 0.0, 0.0], "end_point": [100.0, 0.0, 0.0]},
     ErrorId.INVALID_PATH_GEOMETRY),  # 180°: the plane is ambiguous
    ("circle", {"end_point": [0.0, 0.0, 0.0]}, ErrorId.INVALID_PATH_GEOMETRY),  # full circle
    ("circle", {"circ_mode": McCircMode.BORDER, "aux_point": [50.0, 0.0, 0.0],
                "end_point": [100.0, 0.0, 0.0]}, ErrorId.INVALID_PATH_GEOMETRY),  # collinear
    ("circle", {"circ_mode": McCircMode.RADIUS, "aux_point": [0.0, 0.0, 40.0],
                "end_point": [100.0, 0.0, 0.0]}, ErrorId.INVALID_PATH_GEOMETRY),  # r < chord/2
    ("blocker", {"blocker_id": 0}, ErrorId.INVALID_BLOCKER_ID),  # "any UDINT > 0"
    ("blocker", {"blocker_id": -3}, ErrorId.INVALID_BLOCKER_ID),
    ("blocker", {"blocker_id": 1.5}, ErrorId.INVALID_BLOCKER_ID),
    ("blocker", {"buffer_mode": B.BLENDING_PREVIOUS}, ErrorId.INVALID_BUFFER_MODE),
    ("dwell", {"dwell_time": -0.1}, ErrorId.INVALID_DWELL_TIME),
    ("dwell", {"dwell_time": math.inf}, ErrorId.INVALID_DWELL_TIME),
    ("dwell", {"buffer_mode": B.ABORTING}, ErrorId.INVALID_BUFFER_MODE),  # not the first row
    ("transform", {"coord_transform": "frame"}, ErrorId.INVALID_POSITION),
    ("transform", {"coord_transform": [1.0, 2.0]}, ErrorId.INVALID_POSITION),
]
GOOD = {
    "line": (MC_MoveLinearAbsolutePreparation,
             {"position": [10.0, 0.0, 0.0], "velocity": 100.0, "buffer_mode": B.BUFFERED}),
    "circle": (MC_MoveCircularAbsolutePreparation,
               {"circ_mode": McCircMode.CENTER, "aux_point": [50.0, 0.0, 0.0],
                "end_point": [50.0, 50.0, 0.0], "velocity": 100.0,
                "buffer_mode": B.BUFFERED}),
    "blocker": (MC_BlockerPreparation, {"blocker_id": 4}),
    "dwell": (MC_DwellTimePreparation, {"dwell_time": 0.5}),
    "transform": (MC_SetCoordinateTransformPreparation,
                  {"coord_transform": [10.0, 0.0, 0.0, 0.0, 0.0, 90.0]}),
}


@pytest.mark.parametrize(("kind", "bad", "error_id"), BAD_ROWS,
                         ids=[f"{k}-{'-'.join(b)}-{e.name}" for k, b, e in BAD_ROWS])
def test_a_bad_row_is_an_error_and_changes_nothing_then_a_good_one_goes_in(kind, bad, error_id):
    """Each refusal names its cause in error_id (§9.3.1.2.3-§9.3.1.2.9, §9.3.2.2, §9.3.2.5);
    the table keeps its rows (the first one, a line from the origin to (0, 0, 0) ... here
    (0, 0, 0) itself) and the same block takes a good row next."""
    path = MC_PATH_DATA_REF()
    line(path, [0.0, 0.0, 0.0], buffer_mode=B.ABORTING)  # the first row may abort
    before = path.rows
    block, good = GOOD[kind]
    fb = block()
    fb(path, **{**good, **bad})
    assert fb.error and fb.error_id == error_id, fb.message
    assert fb.message and path.rows == before
    fb(path, **{**{name: block.INPUTS[name] for name in bad}, **good})
    assert not fb.error and fb.error_id == ErrorId.NO_ERROR and path.filled_rows == 2


def test_9_3_1_2_3_special_values_and_mc_ignore_in_an_aux_point_are_taken():
    """Acceleration, Deceleration and Jerk take MC_DEFAULT and MC_MAXIMUM (§9.3.1.2.3);
    AuxPoint's component off the plane may be MC_IGNORE (§9.3.1.2.4)."""
    path = MC_PATH_DATA_REF()
    line(path, [100.0, 0.0, 0.0], acceleration=MC_MAXIMUM, deceleration=MC_DEFAULT,
         jerk=MC_MAXIMUM)
    circ = MC_MoveCircularAbsolutePreparation()
    circ(path, circ_mode=McCircMode.CENTER, aux_point=[100.0, 50.0, MC_IGNORE],
         end_point=[150.0, 50.0, 0.0], velocity=200.0, buffer_mode=B.BUFFERED)
    assert not circ.error, circ.message
    rt, group = group_of(0.0, 0.0, 0.0)
    move = MC_MovePath(group)
    run(rt, group, lambda **_: move(execute=True, path_data=path), lambda: move.done)
    assert tcp(group).tolist() == pytest.approx([150.0, 50.0, 0.0], abs=TOL)


def test_a_preparation_block_needs_a_table_and_names_a_misspelt_input():
    with pytest.raises(TypeError, match="path table"):
        MC_MoveLinearAbsolutePreparation()(position=[1.0, 0.0, 0.0], velocity=1.0)
    with pytest.raises(TypeError, match="did you mean 'velocity'"):
        MC_MoveLinearAbsolutePreparation()(MC_PATH_DATA_REF(), velocty=1.0)


# -- MC_MovePath (§9.3.1.2.5) ----------------------------------------------------------------


def test_9_3_1_2_5_move_path_over_an_empty_or_unfitting_table_is_an_error_and_moves_nothing():
    rt, group = group_of(0.0, 0.0)  # two axes: an MCS of x, y
    move = MC_MovePath(group)
    move(execute=True, path_data=MC_PATH_DATA_REF())
    assert move.error and move.error_id == ErrorId.PATH_TABLE_EMPTY
    move(execute=False)
    path = MC_PATH_DATA_REF()
    line(path, [10.0, 0.0, 0.0])  # three coordinates for a group of two
    move(execute=True, path_data=path)
    assert move.error and move.error_id == ErrorId.INVALID_POSITION and "row 1" in move.message
    assert group.state is G.STANDBY
    move(execute=False)
    path.ClearPath()
    line(path, [10.0, 5.0])
    run(rt, group, lambda **_: move(execute=True, path_data=path), lambda: move.done)
    assert tcp(group).tolist() == pytest.approx([10.0, 5.0], abs=TOL)


def test_9_3_1_2_5_a_first_circle_that_does_not_exist_from_the_tcp_is_a_move_path_error():
    """The first row's circle starts where the TCP is: checked when MC_MovePath starts."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    circ = MC_MoveCircularAbsolutePreparation()
    circ(path, circ_mode=McCircMode.CENTER, aux_point=[40.0, 10.0, 0.0],
         end_point=[100.0, 0.0, 0.0], velocity=100.0, buffer_mode=B.BUFFERED)
    assert not circ.error  # nothing to check it against yet
    move = MC_MovePath(group)
    move(execute=True, path_data=path)
    rt.step()
    move(execute=True)
    assert move.error and move.error_id == ErrorId.INVALID_PATH_GEOMETRY
    assert not move.busy
    rt.step()
    assert group.state is G.STANDBY
    assert group.move_linear_absolute([1.0, 0.0, 0.0]).busy  # usable


def test_9_3_1_2_5_move_path_outputs_follow_the_handshake():
    """Busy from Execute, Active while it controls the group, Done after the last row."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    line(path, [50.0, 0.0, 0.0])
    line(path, [50.0, 50.0, 0.0])
    move = MC_MovePath(group)
    move(execute=True, path_data=path)
    assert move.busy and not move.done
    rt.step()
    move(execute=True)
    assert outputs(move) == (True, True, False, False, False)
    assert group.state is G.MOVING
    run(rt, group, move, lambda: move.done)
    assert outputs(move) == (False, False, True, False, False)
    assert group.state is G.STANDBY
    move(execute=False)
    assert not move.done


# -- blockers (§9.3.1.2.6-§9.3.1.2.8) ------------------------------------------------------------


def blocked_path(blocker_id: int = 7, **second: Any) -> MC_PATH_DATA_REF:
    """Line to (100, 0, 0), blocker, line to (100, 100, 0)."""
    path = MC_PATH_DATA_REF()
    line(path, [100.0, 0.0, 0.0])
    blocker = MC_BlockerPreparation()
    blocker(path, blocker_id=blocker_id, invoke_id=2)
    assert not blocker.error, blocker.message
    line(path, [100.0, 100.0, 0.0], **second)
    return path


def test_9_3_1_2_6_the_path_waits_at_a_blocker_moving_until_it_is_released():
    """§9.3.1.2.6: execution stops at the blocker until MC_ReleaseBlocker; the group stays
    "moving". §9.3.1.2.8: Blocked and BlockerId while it waits. §9.3.1.2.7: a wrong id is
    an error and releases nothing."""
    rt, group = group_of(0.0, 0.0, 0.0)
    move, status = MC_MovePath(group), MC_GroupReadBlockerStatus(group)
    move(execute=True, path_data=blocked_path(7))
    status(enable=True)
    assert (status.valid, status.blocked, status.blocker_id) == (True, False, 0)
    run(rt, group, move, lambda: status.blocked, lambda: status(enable=True))
    assert status.blocker_id == 7
    assert tcp(group).tolist() == pytest.approx([100.0, 0.0, 0.0], abs=TOL)
    for _ in range(100):
        rt.step()
        move(execute=True)
    assert tcp(group).tolist() == pytest.approx([100.0, 0.0, 0.0], abs=TOL)
    assert group.state is G.MOVING and group.motion.path_velocity == 0.0
    assert outputs(move) == (True, True, False, False, False)
    release = MC_ReleaseBlocker(group)
    release(execute=True, blocker_id=8)
    assert release.error and release.error_id == ErrorId.UNKNOWN_BLOCKER
    status(enable=True)
    assert status.blocked and status.blocker_id == 7
    release(execute=False)
    release(execute=True, blocker_id=7)
    assert release.done and not release.error
    status(enable=True)
    assert not status.blocked and status.blocker_id == 0
    run(rt, group, move, lambda: move.done)
    assert tcp(group).tolist() == pytest.approx([100.0, 100.0, 0.0], abs=TOL)
    assert group.state is G.STANDBY
    release(execute=False)
    release(execute=True, blocker_id=7)  # nothing runs any more
    assert release.error_id == ErrorId.UNKNOWN_BLOCKER


def test_9_3_1_2_7_a_blocker_released_early_is_passed_blending_where_the_segments_allow():
    """§9.3.1.2.7: released before the path reaches it, the blocker is passed, and the
    segments around it blend (CornerDistance 10, BlendingPrevious) as they still can: the
    path never stops at the corner. Not released, the same path stops there (§9.3.1.2.6)."""
    blend = {"buffer_mode": B.BLENDING_PREVIOUS,
             "transition_mode": McTransitionMode.CORNER_DISTANCE, "transition_parameter": [10.0]}
    rt, group = group_of(0.0, 0.0, 0.0)
    move, release = MC_MovePath(group), MC_ReleaseBlocker(group)
    move(execute=True, path_data=blocked_path(3, **blend))
    release(execute=True, blocker_id=3)  # at once, the path has only started
    assert release.done
    points, speeds = run(rt, group, move, lambda: move.done)
    corner = np.linalg.norm(points - [100.0, 0.0, 0.0], axis=1)
    assert corner.min() > 1.0  # a contour: the corner itself is not reached
    assert speeds[(corner < 20.0)].min() > 50.0  # and it keeps moving
    assert tcp(group).tolist() == pytest.approx([100.0, 100.0, 0.0], abs=TOL)


@pytest.mark.parametrize("block", [MC_GroupHalt, MC_GroupStop], ids=lambda b: b.__name__)
def test_9_3_1_2_6_group_halt_or_stop_ends_the_path_and_releases_the_blocker(block):
    """§9.3.1.2.6: MC_GroupHalt or MC_GroupStop while the blocker waits ends the path and
    releases the blocker: MC_MovePath CommandAborted, Blocked FALSE."""
    rt, group = group_of(0.0, 0.0, 0.0)
    move, status = MC_MovePath(group), MC_GroupReadBlockerStatus(group)
    move(execute=True, path_data=blocked_path(5))
    run(rt, group, move, lambda: status.blocked, lambda: status(enable=True))
    brake = block(group)
    brake(execute=True)
    move(execute=True)
    assert outputs(move) == (False, False, False, True, False)
    status(enable=True)
    assert not status.blocked
    for _ in range(3):
        rt.step()
        brake(execute=False)
    assert group.state is G.STANDBY
    assert tcp(group).tolist() == pytest.approx([100.0, 0.0, 0.0], abs=TOL)
    assert group.release_blocker(5).error_id == ErrorId.UNKNOWN_BLOCKER


def test_disable_while_the_path_dwells_ends_the_table_and_a_group_error_makes_it_an_error():
    """D-213: MC_GroupDisable ends a table that holds (CommandAborted); a member in
    ErrorStop ends it with the group's error (Part 4 §3.1: GroupErrorStop)."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    line(path, [50.0, 0.0, 0.0])
    MC_DwellTimePreparation()(path, dwell_time=10.0)
    line(path, [50.0, 50.0, 0.0])
    move = MC_MovePath(group)
    run(rt, group, lambda **_: move(execute=True, path_data=path),
        lambda: group.motion.finished and move.active)
    assert group.disable().done
    move(execute=True)
    assert outputs(move) == (False, False, False, True, False)
    assert group.state is G.DISABLED
    assert group.enable().done
    move(execute=False)
    run(rt, group, lambda **_: move(execute=True),
        lambda: group.motion.finished and move.active and tcp(group)[0] == 50.0
        and tcp(group)[1] == 0.0 and group.state is G.MOVING)
    group.axes[1].fault(ErrorId.FOLLOWING_ERROR, "injected")  # a member fails
    rt.step()
    move(execute=True)
    assert move.error and move.error_id == ErrorId.GROUP_ERROR
    assert group.state is G.ERROR_STOP


def test_9_3_1_2_6_an_aborting_move_aborts_the_blocked_path_and_runs():
    """§9.3.1.2.6: a new job with BufferMode Aborting while the blocker waits aborts it."""
    rt, group = group_of(0.0, 0.0, 0.0)
    move, status = MC_MovePath(group), MC_GroupReadBlockerStatus(group)
    move(execute=True, path_data=blocked_path(5))
    run(rt, group, move, lambda: status.blocked, lambda: status(enable=True))
    other = MC_MoveLinearAbsolute(group)
    other(execute=True, position=[0.0, 50.0, 0.0], velocity=300.0)
    move(execute=True)
    assert move.command_aborted and not move.busy
    run(rt, group, other, lambda: other.done)
    assert tcp(group).tolist() == pytest.approx([0.0, 50.0, 0.0], abs=TOL)
    assert group.blocker_status() == (False, 0)


def test_a_buffered_move_issued_while_the_table_runs_waits_for_its_end():
    """D-213: a motion FB with a BufferMode other than Aborting, issued while MC_MovePath
    runs a table, starts when the table is over (here: after the blocker)."""
    rt, group = group_of(0.0, 0.0, 0.0)
    move, status = MC_MovePath(group), MC_GroupReadBlockerStatus(group)
    move(execute=True, path_data=blocked_path(5))
    other = MC_MoveLinearAbsolute(group)
    other(execute=True, position=[0.0, 100.0, 0.0], velocity=300.0,
          buffer_mode=BufferMode.BUFFERED)
    run(rt, group, move, lambda: status.blocked, lambda: status(enable=True), other)
    assert other.busy and not other.active
    assert group.release_blocker(5).done
    run(rt, group, move, lambda: move.done, other)
    assert other.busy
    run(rt, group, other, lambda: other.done)
    assert tcp(group).tolist() == pytest.approx([0.0, 100.0, 0.0], abs=TOL)


def test_9_3_1_2_8_read_blocker_status_is_not_valid_for_a_ca_group():
    """§9.3.1.2.8: Valid only for the MC Group Coordinated Motion."""
    from openmotion.transport.group import CaGroup

    rt = om.Runtime(CYCLE)
    status = MC_GroupReadBlockerStatus(CaGroup(rt))
    status(enable=True)
    assert (status.valid, status.blocked, status.blocker_id, status.error) == (
        False, False, 0, False)


# -- dwell times (§9.3.1.2.9) ------------------------------------------------------------------


def test_9_3_1_2_9_the_path_stands_for_the_dwell_time_then_goes_on():
    """§9.3.1.2.9: the path stands at velocity 0 for DwellTime (0.2 s: 200 cycles, one more
    for the next segment's first sample), the group stays moving."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    line(path, [100.0, 0.0, 0.0])
    dwell = MC_DwellTimePreparation()
    dwell(path, dwell_time=0.2)
    assert not dwell.error
    line(path, [100.0, 100.0, 0.0])
    move = MC_MovePath(group)
    states: list[G] = []
    points, _ = run(rt, group, lambda **_: move(execute=True, path_data=path),
                    lambda: move.done, lambda: states.append(group.state))
    at_corner = np.linalg.norm(points - [100.0, 0.0, 0.0], axis=1) <= TOL
    assert 200 <= at_corner.sum() <= 202
    assert all(state is G.MOVING for state in states[1:-1])


def test_9_3_1_2_9_a_dwell_time_of_zero_still_stops_where_the_segments_would_blend():
    """§9.3.1.2.9: "A DwellTime of zero leads to an exact stop, even if the surrounding
    segments would allow a transition with a velocity > 0"."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    line(path, [100.0, 0.0, 0.0])
    MC_DwellTimePreparation()(path, dwell_time=0.0)
    line(path, [100.0, 100.0, 0.0], buffer_mode=B.BLENDING_PREVIOUS,
         transition_mode=McTransitionMode.CORNER_DISTANCE, transition_parameter=[10.0])
    move = MC_MovePath(group)
    points, speeds = run(rt, group, lambda **_: move(execute=True, path_data=path),
                         lambda: move.done)
    near = np.linalg.norm(points - [100.0, 0.0, 0.0], axis=1) <= NEAR
    assert near.any() and speeds[near].min() <= STOPPED


# -- blending (§9.3.2.5) -------------------------------------------------------------------------


@pytest.mark.parametrize(("mode", "parameters", "start"), [
    (McTransitionMode.CORNER_DISTANCE, [10.0], 10.0),
    (McTransitionMode.CORNER_DISTANCE_ADVANCED, [10.0, 25.0], 10.0),  # r_in <= r_out
    (McTransitionMode.CORNER_DISTANCE_ADVANCED, [30.0, 12.0], 12.0),  # within r_out (D-213)
], ids=["corner_distance", "advanced", "advanced_r_out_smaller"])
def test_9_3_2_5_corner_distance_leaves_and_rejoins_the_lines_within_the_ball(
        mode, parameters, start):
    """§9.3.2.5: the transition parameters are a tolerance ball about the corner: the path
    leaves the first line at the corner distance (r_in) and is back on the second within
    r_out; no stop at the corner."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    line(path, [100.0, 0.0, 0.0])
    line(path, [100.0, 100.0, 0.0], buffer_mode=B.BLENDING_PREVIOUS, transition_mode=mode,
         transition_parameter=parameters)
    move = MC_MovePath(group)
    points, speeds = run(rt, group, lambda **_: move(execute=True, path_data=path),
                         lambda: move.done)
    off_first = points[(np.abs(points[:, 1]) > 1e-6) & (points[:, 0] < 100.0 - 1e-6)]
    assert off_first[:, 0].min() == pytest.approx(100.0 - start, abs=0.5)
    off_second = points[np.abs(points[:, 0] - 100.0) > 1e-6]
    assert off_second[:, 1].max() <= start + 0.5
    corner = np.linalg.norm(points - [100.0, 0.0, 0.0], axis=1)
    assert speeds[corner < 2.0 * start].min() > 50.0


# -- coordinate transforms in the table (§9.3.1.1.10) -----------------------------------------


def test_9_3_1_1_10_rows_after_a_transform_are_in_its_frame_and_the_path_blends_across():
    """§9.3.1.1.10: the change of reference system in the table applies to the rows after
    it: (50, 0, 0) in a frame at (100, 0, 0) turned 90° about z is (100, 50, 0) in the MCS.
    The path does not stop at the change (D-213), and the group's PCS is the new frame."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    line(path, [100.0, 0.0, 0.0])
    frame = Frame.from_cartesian(100.0, 0.0, 0.0, 0.0, 0.0, 90.0)
    transform = MC_SetCoordinateTransformPreparation()
    transform(path, coord_transform=MC_COORD_REF(frame, oid=0x01010010))
    assert not transform.error
    line(path, [50.0, 0.0, 0.0], buffer_mode=B.BLENDING_PREVIOUS,
         transition_mode=McTransitionMode.CORNER_DISTANCE, transition_parameter=[5.0])
    move = MC_MovePath(group)
    points, speeds = run(rt, group, lambda **_: move(execute=True, path_data=path),
                         lambda: move.done)
    assert tcp(group).tolist() == pytest.approx([100.0, 50.0, 0.0], abs=TOL)
    corner = np.linalg.norm(points - [100.0, 0.0, 0.0], axis=1)
    assert speeds[corner < 10.0].min() > 20.0
    assert group.spaces.frame(rt.now) == frame
    assert group.position(CoordSystem.PCS, actual=False).tolist() == pytest.approx(
        [50.0, 0.0, 0.0], abs=TOL)


def test_9_3_1_1_10_back_to_the_machine_frame_with_an_empty_coord_ref():
    """MC_COORD_REF() is the MCS: after it the rows are machine coordinates again."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    transform = MC_SetCoordinateTransformPreparation()
    transform(path, coord_transform=[0.0, 0.0, 10.0, 0.0, 0.0, 0.0])
    line(path, [10.0, 0.0, 0.0])
    transform(path, coord_transform=MC_COORD_REF())
    line(path, [20.0, 0.0, 0.0])
    move = MC_MovePath(group)
    points, _ = run(rt, group, lambda **_: move(execute=True, path_data=path),
                    lambda: move.done)
    assert np.any(np.all(np.abs(points - [10.0, 0.0, 10.0]) <= TOL, axis=1))
    assert tcp(group).tolist() == pytest.approx([20.0, 0.0, 0.0], abs=TOL)


# -- circles: MC_CIRC_MODE and MC_CIRC_PATHCHOICE (§9.3.2.2, §9.3.2.3) -------------------------

SHALLOW, DEEP = 100.0 - math.sqrt(100.0**2 - 50.0**2), 100.0 + math.sqrt(100.0**2 - 50.0**2)


@pytest.mark.parametrize(("choice", "normal", "side", "depth"), [
    # the figure's table: with the normal +z, CW arc 1, CCW and Short arc 3, Long arc 4;
    # with -z, CW arc 4, CCW and Short arc 2, Long arc 1
    (McCircPathChoice.CLOCKWISE, 1.0, 1.0, DEEP),
    (McCircPathChoice.COUNTERCLOCKWISE, 1.0, -1.0, SHALLOW),
    (McCircPathChoice.SHORT_SEGMENT, 1.0, -1.0, SHALLOW),
    (McCircPathChoice.LONG_SEGMENT, 1.0, -1.0, DEEP),
    (McCircPathChoice.CLOCKWISE, -1.0, -1.0, DEEP),
    (McCircPathChoice.COUNTERCLOCKWISE, -1.0, 1.0, SHALLOW),
    (McCircPathChoice.SHORT_SEGMENT, -1.0, 1.0, SHALLOW),
    (McCircPathChoice.LONG_SEGMENT, -1.0, 1.0, DEEP),
], ids=lambda v: getattr(v, "name", str(v)))
def test_9_3_2_2_radius_mode_picks_one_of_four_arcs_by_path_choice_and_normal(
        choice, normal, side, depth):
    """§9.3.2.2 mcCircModeRadius: AuxPoint is the normal, its length (100) the radius; the
    right-hand rule for every PathChoice but Clockwise (left-hand); CCW and Short <= 180°,
    CW and Long >= 180°. From (0, 0, 0) to (100, 0, 0) in the x-y plane the four arcs bulge
    to either side of the chord, 13.4 mm (short) or 186.6 mm (long)."""
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    circ = MC_MoveCircularAbsolutePreparation()
    line(path, [0.0, 0.0, 0.0])
    circ(path, circ_mode=McCircMode.RADIUS, aux_point=[0.0, 0.0, 100.0 * normal],
         end_point=[100.0, 0.0, 0.0], path_choice=choice, velocity=2000.0,
         buffer_mode=B.BUFFERED)
    assert not circ.error, circ.message
    move = MC_MovePath(group)
    points, _ = run(rt, group, lambda **_: move(execute=True, path_data=path),
                    lambda: move.done)
    y = points[:, 1] * side
    assert y.min() >= -TOL and y.max() == pytest.approx(depth, abs=0.01)  # sampled peak
    assert tcp(group).tolist() == pytest.approx([100.0, 0.0, 0.0], abs=TOL)


def test_9_3_2_2_border_mode_passes_the_aux_point_and_ignores_path_choice():
    rt, group = group_of(0.0, 0.0, 0.0)
    path = MC_PATH_DATA_REF()
    line(path, [0.0, 0.0, 0.0])
    circ = MC_MoveCircularAbsolutePreparation()
    circ(path, circ_mode=McCircMode.BORDER, aux_point=[50.0, 50.0, 0.0],
         end_point=[100.0, 0.0, 0.0], path_choice=McCircPathChoice.LONG_SEGMENT,
         velocity=500.0, buffer_mode=B.BUFFERED)
    move = MC_MovePath(group)
    points, _ = run(rt, group, lambda **_: move(execute=True, path_data=path),
                    lambda: move.done)
    assert np.linalg.norm(points[:, :2] - [50.0, 0.0], axis=1) == pytest.approx(50.0, abs=TOL)
    assert points[:, 1].max() == pytest.approx(50.0, abs=1e-3)


# -- the data types (§9.3.2) ---------------------------------------------------------------------


def test_9_3_2_the_data_types_take_this_manuals_numbers():
    assert {m.name: int(m) for m in McTransitionMode} == {
        "NONE": 0x1000, "START_VELOCITY": 0x1001, "CONSTANT_VELOCITY": 0x1002,
        "CORNER_DISTANCE": 0x1003, "MAX_CORNER_DEVIATION": 0x1004,
        "CORNER_DISTANCE_ADVANCED": 0x100A}
    assert {m.name: int(m) for m in McCircMode} == {
        "INVALID": 0, "BORDER": 0x2000, "CENTER": 0x2001, "RADIUS": 0x2002}
    assert {m.name: int(m) for m in McCircPathChoice} == {
        "CLOCKWISE": 0x3000, "COUNTERCLOCKWISE": 0x3001, "SHORT_SEGMENT": 0x3002,
        "LONG_SEGMENT": 0x3003}
    # MC_BUFFER_MODE as §9.4.1.1 numbers it: the numbers reach the blocks as they are
    path = MC_PATH_DATA_REF()
    line(path, [1.0, 0.0, 0.0], buffer_mode=0x0)
    line(path, [2.0, 0.0, 0.0], buffer_mode=0x13, transition_mode=0x1003,
         transition_parameter=[1.0])
    assert [row.buffer_mode for row in path.rows] == [B.ABORTING, B.BLENDING_PREVIOUS]
    assert MC_COORD_REF().frame == Frame() and MC_COORD_REF().oid == 0
