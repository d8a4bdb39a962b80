"""C windows, CRotation command modes and C modulo targets (TF5430 §4.2, §6.1.8, §6.1.9,
§6.2.6, §6.2.7; digest-planar-concepts §3.8, §3.9)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from openmotion.core.enums import ModuloDirection
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.planar.enums import MoverCommandMode
from openmotion.planar.motion import plan_move_c
from openmotion.planar.rotation import (
    CWindows,
    _swept_c,
    mode_after_c_motion,
    mode_at_enable,
    mode_during_c_motion,
    modulo_target,
    monotonic,
    move_c_target,
    xy_locked,
)
from openmotion.trajectory.plan import Limits, plan_position, plan_position_in
from openmotion.trajectory.segments import KinematicState

FREE = MoverCommandMode.FREE_MOVEMENT
ON_TRACK = MoverCommandMode.ON_TRACK
C_FREE = MoverCommandMode.C_ROTATION_FREE_MOVEMENT
C_TRACK = MoverCommandMode.C_ROTATION_ON_TRACK
POS, NEG = ModuloDirection.POSITIVE, ModuloDirection.NEGATIVE
SHORT, ABS = ModuloDirection.SHORTEST_WAY, ModuloDirection.NON_MODULO
C_LIMITS = Limits(360.0, 3600.0, 3600.0, 36000.0)
WINDOWS = CWindows(-15.0, 15.0)


def test_windows_of_the_manual_example():
    """§4.2: limits ±15° give four windows at 90° spacing."""
    assert WINDOWS.windows() == ((-15.0, 15.0), (75.0, 105.0), (165.0, 195.0), (255.0, 285.0))


def test_asymmetric_limits_shift_every_window():
    assert CWindows(-10.0, 20.0).windows()[1:3] == ((80.0, 110.0), (170.0, 200.0))


@pytest.mark.parametrize("c", [0.0, 15.0, -15.0, 3.0, 75.0, 90.0, 105.0, 165.0, 190.0, 195.0,
                               255.0, 285.0, 360.0, -90.0, 450.0, -360.0 - 14.0])
def test_orientations_inside_a_window(c):
    """Windows repeat modulo 360° (digest §8 q17): 360 is window 1, -90 window 4."""
    assert WINDOWS.contains(c)


@pytest.mark.parametrize("c", [20.0, 15.001, 45.0, 74.9, 106.0, 200.0, 300.0, -20.0, 380.0])
def test_orientations_outside_every_window(c):
    assert not WINDOWS.contains(c)


@pytest.mark.parametrize(("low", "high", "inside"), [
    (0.0, 3.0, True),  # §6.1.5: MoveC 3° never leaves window 1
    (-15.0, 15.0, True),
    (80.0, 100.0, True),
    (355.0, 365.0, True),  # window 1 seen one turn on
    (0.0, 20.0, False),  # §6.1.8
    (10.0, 80.0, False),  # starts in window 1, ends in window 2: not ONE window
    (0.0, 90.0, False),
    (-20.0, -16.0, False),
])
def test_swept_interval_inside_one_window(low, high, inside):
    assert WINDOWS.contains_interval(low, high) is inside


def test_float_residue_at_a_window_edge_stays_inside():
    assert WINDOWS.contains(-15.0 - 1e-13)
    assert WINDOWS.contains_interval(-15.0 - 1e-13, 15.0 + 1e-13)


@pytest.mark.parametrize(("minimum", "maximum"), [(20.0, -20.0), (math.nan, 15.0),
                                                  (-15.0, math.inf)])
def test_bad_c_limits_are_configuration_errors(minimum, maximum):
    with pytest.raises(ConfigError):
        CWindows(minimum, maximum)


def _rotate(mode: MoverCommandMode, c: float, target: float) -> tuple[MoverCommandMode, ...]:
    """Modes during and after a MoveC from ``c`` to the absolute ``target``."""
    profile = plan_move_c(KinematicState(c), target, C_LIMITS)
    during = mode_during_c_motion(mode, profile, WINDOWS)
    return during, mode_after_c_motion(during, profile.end.position, WINDOWS)


def test_manual_6_1_8_move_c_20_then_90():
    """§6.1.8: MoveC 20° leaves window 1 and stays in CRotationFreeMovement; a MoveC to 90°
    ends in window 2 and returns to FreeMovement."""
    assert mode_at_enable(0.0, WINDOWS) == FREE
    assert _rotate(FREE, 0.0, 20.0) == (C_FREE, C_FREE)
    assert _rotate(C_FREE, 20.0, 90.0) == (C_FREE, FREE)


def test_manual_6_1_5_small_rotation_stays_free():
    assert _rotate(FREE, 0.0, 3.0) == (FREE, FREE)


def test_manual_6_2_6_on_track_20_and_90():
    """§6.2.6: both movers are in CRotationOnTrack while rotating; 20° stays there, 90° ends in
    window 2 and is back OnTrack."""
    assert _rotate(ON_TRACK, 0.0, 20.0) == (C_TRACK, C_TRACK)
    assert _rotate(ON_TRACK, 0.0, 90.0) == (C_TRACK, ON_TRACK)


def test_manual_6_2_7_on_track_190_ends_in_window_3():
    assert _rotate(ON_TRACK, 0.0, 190.0) == (C_TRACK, ON_TRACK)


def test_rotation_back_into_a_window_from_outside():
    assert _rotate(C_FREE, 20.0, 10.0) == (C_FREE, FREE)


def test_mode_after_enable_outside_every_window():
    assert mode_at_enable(20.0, WINDOWS) == C_FREE


@pytest.mark.parametrize("mode", [MoverCommandMode.JOINING_TRACK,
                                  MoverCommandMode.EXTERNAL_SETPOINT_GENERATION])
def test_other_modes_are_not_changed_by_c(mode):
    assert _rotate(mode, 0.0, 20.0) == (mode, mode)


def test_xy_is_locked_only_in_the_c_rotation_modes():
    assert [m for m in MoverCommandMode if xy_locked(m)] == [C_FREE, C_TRACK]


#: (direction, start, position, additional turns, tolerance, absolute target); modulus 360°
MODULO_ROWS = [
    (ABS, 20.0, 400.0, 0, 0.0, 400.0),  # NonModulo: the position is absolute
    (ABS, 20.0, -30.0, 0, 0.0, -30.0),
    (POS, 350.0, 10.0, 0, 0.0, 370.0),
    (POS, 350.0, 10.0, 1, 0.0, 730.0),
    (NEG, 10.0, 350.0, 0, 0.0, -10.0),
    (NEG, 10.0, 350.0, 2, 0.0, -730.0),
    (SHORT, 350.0, 10.0, 0, 0.0, 370.0),
    (SHORT, 10.0, 350.0, 0, 0.0, -10.0),
    (POS, 10.5, 10.0, 0, 0.0, 370.0),  # without a window: a whole turn
    (POS, 10.5, 10.0, 0, 1.0, 10.0),  # inside the window: the short way back (§6.1.9)
    (POS, 10.5, 10.0, 1, 1.0, 370.0),  # turns add to the short way
    (NEG, 9.5, 10.0, 0, 1.0, 10.0),
    (NEG, 9.5, 10.0, 0, 0.0, -350.0),
    (POS, 720.0, 90.0, 0, 0.0, 810.0),  # the start's own turns are kept
]


@pytest.mark.parametrize("row", MODULO_ROWS, ids=str)
def test_modulo_target_rules(row):
    direction, start, position, turns, tolerance, expected = row
    assert modulo_target(start, position, direction, turns, 360.0, tolerance) == \
        pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize(("direction", "turns", "tolerance", "error_id"), [
    (ABS, 1, 0.0, ErrorId.INVALID_MODULO_OPTIONS),  # turns need positive or negative
    (SHORT, 1, 0.0, ErrorId.INVALID_MODULO_OPTIONS),
    (ABS, 0, 1.0, ErrorId.INVALID_MODULO_OPTIONS),  # a window needs a modulo direction
    (POS, -1, 0.0, ErrorId.PLANAR_INVALID_INPUT),  # UDINT
    (POS, 0, -1.0, ErrorId.PLANAR_INVALID_INPUT),
    (POS, 0, math.nan, ErrorId.PLANAR_INVALID_INPUT),
    (7, 0, 0.0, ErrorId.PLANAR_INVALID_INPUT),
])
def test_modulo_option_rules(direction, turns, tolerance, error_id):
    with pytest.raises(CommandRejected) as rejected:
        modulo_target(0.0, 10.0, direction, turns, 360.0, tolerance)
    assert rejected.value.error_id == error_id


@pytest.mark.parametrize(("direction", "position", "error_id"), [
    (POS, 400.0, ErrorId.INVALID_TARGET_POSITION),  # a modulo target lies in [0, modulus]
    (ABS, math.nan, ErrorId.PLANAR_INVALID_INPUT),
    (ABS, math.inf, ErrorId.PLANAR_INVALID_INPUT),
])
def test_bad_c_targets(direction, position, error_id):
    with pytest.raises(CommandRejected) as rejected:
        move_c_target(0.0, position, direction, 0)
    assert rejected.value.error_id == error_id


def test_mover_tolerance_window_applies_to_modulo_directions_only():
    """The window is a mover parameter (§6.1.1): an absolute MoveC ignores it."""
    assert move_c_target(10.5, 10.0, ABS, 0, 360.0, 1.0) == 10.0
    assert move_c_target(10.5, 10.0, POS, 0, 360.0, 1.0) == pytest.approx(10.0)
    assert move_c_target(10.5, 10.0, POS, 0, 360.0, 0.0) == pytest.approx(370.0)


def test_c_modulus_other_than_360():
    assert move_c_target(80.0, 10.0, POS, 1, modulus=90.0) == pytest.approx(190.0)


def test_c_modulus_must_be_positive():
    with pytest.raises(ConfigError):
        move_c_target(0.0, 10.0, POS, 0, modulus=0.0)


def test_move_c_reaches_the_modulo_target_exactly():
    profile = plan_move_c(KinematicState(350.0), 10.0, C_LIMITS, POS, additional_turns=1)
    assert profile.end == KinematicState(730.0)
    assert profile.position_extrema() == (350.0, 730.0)


@given(c0=st.floats(-20.0, 20.0),
       velocity=st.one_of(st.just(0.0), st.floats(-300.0, -1e-3), st.floats(1e-3, 300.0)),
       target=st.floats(-20.0, 20.0), lasting=st.one_of(st.none(), st.floats(1e-3, 1.0)))
def test_the_swept_c_of_a_plan_is_its_position_extrema(c0, velocity, target, lasting):
    """A C motion that never turns back has its extremes at segment boundaries; one that
    turns back is searched for turning points. Both agree with ``position_extrema`` to float
    residue (which the windows' 1e-9 degrees absorb). Velocities and durations stay above
    1e-3 (deg/s, s): below, ruckig's minimum-duration mode fails on float residue, which no
    mover produces (its C plans start from rest or from a running plan)."""
    start = KinematicState(c0, velocity)
    c = plan_position(start, target, C_LIMITS) if lasting is None else \
        plan_position_in(start, target, C_LIMITS, lasting)
    low, high = c.position_extrema()
    assert _swept_c(c) == pytest.approx((low, high), abs=1e-12)
    if monotonic(c):  # it never turns back: its extremes are where it starts and ends
        assert (low, high) == pytest.approx(sorted((c0, target)), abs=1e-9)
