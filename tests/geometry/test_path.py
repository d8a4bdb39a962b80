"""Lines and arcs: arc length, the three circle modes, PathChoice, degenerate input.

Part 4 §5.20-§5.23 (digest rules 72, 76-84). Arcs are drawn at random on circles in random
planes; the three CircModes must then describe the same circle.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.geometry.path import TOLERANCE, Arc, CircMode, Line, PathChoice

CCW, CW = PathChoice.COUNTERCLOCKWISE, PathChoice.CLOCKWISE
coordinate = st.floats(-500.0, 500.0)
points = st.tuples(coordinate, coordinate, coordinate).map(np.array)
directions = (st.tuples(*[st.floats(-1.0, 1.0)] * 3).map(np.array)
              .filter(lambda v: np.linalg.norm(v) > 0.1).map(lambda v: v / np.linalg.norm(v)))


def polyline_length(segment, n: int) -> float:
    """Length of the polyline through n + 1 points equally spaced in s, Richardson-extrapolated:
    the chord error falls with 1/n² on a smooth curve."""
    def chords(m: int) -> float:
        p = segment.position(np.linspace(0.0, segment.length, m + 1))
        return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
    return (4.0 * chords(2 * n) - chords(n)) / 3.0


@st.composite
def circles(draw):
    """(centre, radius, unit normal, start angle direction u, sweep) of a random arc."""
    center = draw(points)
    radius = draw(st.floats(0.5, 400.0))
    normal = draw(directions)
    seed = draw(directions)
    u = np.cross(normal, seed)
    assume(np.linalg.norm(u) > 0.1)
    return center, radius, normal, u / np.linalg.norm(u), draw(st.floats(0.05, 2 * math.pi - 0.05))


def on_circle(center, radius, normal, u, angle):
    return center + radius * (math.cos(angle) * u + math.sin(angle) * np.cross(normal, u))


def rejected(call, error_id=ErrorId.INVALID_PATH_GEOMETRY) -> str:
    with pytest.raises(CommandRejected) as info:
        call()
    assert info.value.error_id == error_id
    return info.value.message


# --- lines -----------------------------------------------------------------------------------

def test_line_evaluates_many_arc_lengths_at_once():
    line = Line([0.0, 0.0, 0.0], [30.0, 40.0, 0.0])
    s = np.array([-1.0, 0.0, 25.0, 50.0, 60.0])  # outside [0, length] is clamped
    np.testing.assert_allclose(line.position(s), [[0, 0, 0], [0, 0, 0], [15, 20, 0],
                                                  [30, 40, 0], [30, 40, 0]])
    assert line.length == 50.0
    assert line.tangent(s).shape == (5, 3) and line.curvature(s).shape == (5,)
    np.testing.assert_allclose(line.tangent(1.0), [0.6, 0.8, 0.0])
    assert line.curvature(1.0) == 0.0 and line.max_curvature == 0.0


@given(points, points)
def test_line_end_points_are_exact(a, b):
    assume(np.linalg.norm(b - a) > TOLERANCE)
    line = Line(a, b)
    assert np.array_equal(line.position(0.0), a)
    assert np.array_equal(line.position(line.length), b)
    part = line.substring(0.25 * line.length, 0.75 * line.length)
    np.testing.assert_allclose(part.position(0.0), 0.75 * a + 0.25 * b, atol=1e-9)


# --- arcs: length and derivatives ------------------------------------------------------------

@given(circles())
def test_arc_length_matches_dense_sampling(circle):
    center, radius, normal, u, sweep = circle
    arc = Arc(on_circle(*circle[:4], 0.0), on_circle(*circle[:4], sweep), center, normal)
    assert arc.length == pytest.approx(radius * sweep, rel=1e-12)
    assert abs(polyline_length(arc, 2000) - arc.length) <= 1e-9 * arc.length
    s = np.linspace(0.0, arc.length, 501)
    np.testing.assert_allclose(np.linalg.norm(arc.position(s) - center, axis=1), radius,
                               rtol=1e-12)


@given(circles())
def test_arc_tangent_and_curvature_are_the_derivatives_of_position(circle):
    center, radius, normal, u, sweep = circle
    arc = Arc(on_circle(*circle[:4], 0.0), on_circle(*circle[:4], sweep), center, normal)
    s = np.linspace(0.1, 0.9, 9) * arc.length
    h = 1e-4 * radius
    ahead, here, behind = arc.position(s + h), arc.position(s), arc.position(s - h)
    np.testing.assert_allclose(arc.tangent(s), (ahead - behind) / (2 * h), atol=1e-6)
    np.testing.assert_allclose(arc.curvature_vector(s) * radius,
                               (ahead - 2 * here + behind) / h**2 * radius, atol=1e-4)
    np.testing.assert_allclose(arc.curvature(s), 1.0 / radius, rtol=1e-12)
    # right-hand rule about the normal (§5.22)
    turning = np.cross(arc.tangent(s[0]), arc.curvature_vector(s[0]) * radius)
    np.testing.assert_allclose(turning, normal, atol=1e-9)


# --- the three circle modes ------------------------------------------------------------------

@given(circles(), st.floats(0.1, 0.9))
def test_the_three_circle_modes_give_the_same_arc(circle, fraction):
    center, radius, normal, u, sweep = circle
    assume(abs(sweep - math.pi) > 1e-3)  # CENTER cannot take a half circle
    start, end = on_circle(*circle[:4], 0.0), on_circle(*circle[:4], sweep)
    border = on_circle(*circle[:4], fraction * sweep)
    choice = CCW if sweep < math.pi else CW
    arcs = [Arc.from_circ_mode(CircMode.BORDER, start, border, end),
            Arc.from_circ_mode(CircMode.CENTER, start, center, end, choice),
            Arc.from_circ_mode(CircMode.RADIUS, start, radius * normal, end, choice)]
    s = np.linspace(0.0, 1.0, 11)
    for arc in arcs:
        np.testing.assert_allclose(arc.center, center, atol=1e-7 * max(1.0, radius))
        assert arc.radius == pytest.approx(radius, rel=1e-9)
        assert arc.sweep == pytest.approx(sweep, rel=1e-9)
        np.testing.assert_allclose(arc.normal, normal, atol=1e-9)
        np.testing.assert_allclose(arc.position(s * arc.length),
                                   arcs[0].position(s * arcs[0].length), atol=1e-7 * radius)
        assert np.array_equal(arc.position(arc.length), end)


def test_border_passes_the_aux_point_on_one_circle():
    """Part 4 §5.14 Fig. 14: S(10,10,0), Aux(30,30,0), E(50,10,0); digest rule 63."""
    arc = Arc.from_border([10.0, 10.0, 0.0], [30.0, 30.0, 0.0], [50.0, 10.0, 0.0])
    np.testing.assert_allclose(arc.center, [30.0, 10.0, 0.0], atol=1e-12)
    assert arc.radius == pytest.approx(20.0)
    np.testing.assert_allclose(arc.position(arc.length / 2), [30.0, 30.0, 0.0], atol=1e-12)


def test_radius_absolute_example():
    """§5.22: AuxPoint (50, 0, 0): plane parallel to y-z, radius 50, right-hand rule about x."""
    arc = Arc.from_radius([0.0, 0.0, 0.0], [0.0, 100.0, 0.0], [50.0, 0.0, 0.0])
    s = np.linspace(0.0, arc.length, 50)
    np.testing.assert_allclose(arc.position(s)[:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(arc.position(s) - arc.center, axis=1), 50.0)
    np.testing.assert_allclose(arc.position(arc.length / 2), [0.0, 50.0, -50.0], atol=1e-12)


def test_radius_relative_example_turns_against_the_right_hand_rule_about_y():
    """§5.23: a normal (0, -30, 0) from the start: radius 30, plane parallel to x-z."""
    arc = Arc.from_radius([0.0, 0.0, 0.0], [60.0, 0.0, 0.0], [0.0, -30.0, 0.0])
    np.testing.assert_allclose(arc.normal, [0.0, -1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(arc.position(arc.length / 2), [30.0, 0.0, -30.0], atol=1e-12)


# --- PathChoice ------------------------------------------------------------------------------

def test_center_path_choice_picks_the_short_or_the_long_sector():
    start, center, end = [10.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 10.0, 0.0]
    short = Arc.from_center(start, center, end, CCW)
    long = Arc.from_center(start, center, end, CW)
    assert short.sweep == pytest.approx(math.pi / 2) and long.sweep == pytest.approx(1.5 * math.pi)
    assert short.length + long.length == pytest.approx(2 * math.pi * 10.0)
    np.testing.assert_allclose(short.normal, [0.0, 0.0, 1.0])
    np.testing.assert_allclose(long.normal, [0.0, 0.0, -1.0])
    assert Arc.from_center(start, center, end).sweep == short.sweep  # default: short


@given(st.floats(0.51, 5.0))
def test_radius_path_choice_picks_the_circle_with_the_short_or_long_sector(ratio):
    start, end, normal = np.zeros(3), np.array([10.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    short = Arc.from_radius(start, end, 10.0 * ratio * normal, CCW)
    long = Arc.from_radius(start, end, 10.0 * ratio * normal, CW)
    assert short.sweep < math.pi < long.sweep
    assert short.sweep + long.sweep == pytest.approx(2 * math.pi)
    for arc in (short, long):  # both turn right-handed about the given vector
        np.testing.assert_allclose(arc.normal, normal, atol=1e-12)
        assert arc.radius == pytest.approx(10.0 * ratio)


def test_radius_of_exactly_half_the_chord_is_the_half_circle():
    arc = Arc.from_radius([0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 0.0, 5.0 - 0.5 * TOLERANCE])
    assert arc.sweep == pytest.approx(math.pi) and arc.radius == pytest.approx(5.0)


def test_center_within_tolerance_is_moved_onto_the_bisector():
    arc = Arc.from_center([10.0, 0.0, 0.0], [0.0, 0.3 * TOLERANCE, 0.0], [0.0, 10.0, 0.0])
    assert np.linalg.norm(arc.end - arc.center) == pytest.approx(arc.radius, abs=1e-12)


# --- degenerate input ------------------------------------------------------------------------

ORIGIN, X, Y = [0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]
DEGENERATE = {
    "line of zero length": lambda: Line(X, [10.0, 0.0, 0.5 * TOLERANCE]),
    "border collinear": lambda: Arc.from_border(ORIGIN, [5.0, 0.0, 0.0], X),
    "border aux beyond the end": lambda: Arc.from_border(ORIGIN, X, [5.0, 0.0, 0.0]),
    "border aux on the start": lambda: Arc.from_border(ORIGIN, ORIGIN, X),
    "border full circle": lambda: Arc.from_border(ORIGIN, X, ORIGIN),
    "center on the start": lambda: Arc.from_center(X, X, Y),
    "center not equidistant": lambda: Arc.from_center(X, ORIGIN, [0.0, 11.0, 0.0]),
    "center half circle": lambda: Arc.from_center(X, ORIGIN, [-10.0, 0.0, 0.0]),
    "center full circle": lambda: Arc.from_center(X, ORIGIN, X),
    "radius zero": lambda: Arc.from_radius(ORIGIN, X, ORIGIN),
    "radius below half the chord": lambda: Arc.from_radius(ORIGIN, X, [0.0, 0.0, 4.9]),
    "radius end off the plane": lambda: Arc.from_radius(ORIGIN, X, [1.0, 0.0, 10.0]),
    "radius full circle": lambda: Arc.from_radius(ORIGIN, ORIGIN, [0.0, 0.0, 10.0]),
    "arc radius mismatch": lambda: Arc(X, [0.0, 12.0, 0.0], ORIGIN, [0.0, 0.0, 1.0]),
    "arc off its plane": lambda: Arc(X, [0.0, 0.0, 10.0], ORIGIN, [0.0, 0.0, 1.0]),
}


@pytest.mark.parametrize("case", DEGENERATE, ids=str)
def test_degenerate_geometry_is_rejected(case):
    assert rejected(DEGENERATE[case])


@pytest.mark.parametrize("bad", [[0.0, math.nan, 0.0], [math.inf, 0.0, 0.0], [1.0, 2.0]])
def test_points_must_be_three_finite_numbers(bad):
    assert "end" in rejected(lambda: Line(ORIGIN, bad), ErrorId.INVALID_POSITION)


def test_unknown_circ_mode_is_rejected():
    rejected(lambda: Arc.from_circ_mode(7, ORIGIN, X, Y), ErrorId.INVALID_MODE)


def test_messages_name_the_problem():
    assert "half the chord" in rejected(DEGENERATE["radius below half the chord"])
    assert "one line" in rejected(DEGENERATE["border collinear"])
