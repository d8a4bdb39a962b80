"""Blend contours: G2 joins, corner distance and deviation honoured, bounded curvature.

Part 4 §7.4.4 and §7.4.5 (digest rules 106, 107, 111). Corners are drawn at random in 3-D: the
turn from nearly straight to nearly reversing, line-line, line-arc, arc-line and arc-arc, the
arcs in random planes, the requested distance up to beyond the half-segment limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.geometry.blend import (
    Blend,
    Contour,
    corner_distance_blend,
    max_corner_deviation_blend,
)
from openmotion.geometry.path import Arc, Line, Segment

EXACT = 1e-9
unit = (st.tuples(*[st.floats(-1.0, 1.0)] * 3).map(np.array)
        .filter(lambda v: np.linalg.norm(v) > 0.1).map(lambda v: v / np.linalg.norm(v)))
turns = st.one_of(st.floats(1e-4, 0.1), st.floats(0.1, math.pi - 0.1),
                  st.floats(math.pi - 0.1, math.pi - 1e-3))


def perpendicular(draw, direction):
    other = np.cross(direction, draw(unit))
    assume(np.linalg.norm(other) > 0.1)
    return other / np.linalg.norm(other)


@dataclass
class Corner:
    before: Segment
    after: Segment
    corner: np.ndarray
    turn: float  #: [rad] between the tangents at the corner


@st.composite
def corners(draw):
    corner = draw(st.tuples(*[st.floats(-300.0, 300.0)] * 3).map(np.array))
    t_in = draw(unit)
    turn = draw(turns)
    t_out = math.cos(turn) * t_in + math.sin(turn) * perpendicular(draw, t_in)
    segments = []
    for tangent, arriving in ((t_in, True), (t_out, False)):
        length = draw(st.floats(1.0, 300.0))
        if draw(st.booleans()):
            far = corner - length * tangent if arriving else corner + length * tangent
            segments.append(Line(far, corner) if arriving else Line(corner, far))
            continue
        axis = perpendicular(draw, tangent)  # the arc turns right-handed about it
        radius = draw(st.floats(1.0, 300.0))
        sweep = draw(st.floats(0.05, 2 * math.pi - 0.05))
        outward = np.cross(tangent, axis)  # from the centre to the corner
        center = corner - radius * outward
        angle = -sweep if arriving else sweep
        far = center + radius * (math.cos(angle) * outward + math.sin(angle) * tangent)
        segments.append(Arc(far, corner, center, axis) if arriving
                        else Arc(corner, far, center, axis))
    return Corner(segments[0], segments[1], corner, turn)


def half_segment_limit(c: Corner) -> float:
    return min(np.linalg.norm(c.before.position(c.before.length / 2) - c.corner),
               np.linalg.norm(c.after.position(c.after.length / 2) - c.corner))


def arc_turn(c: Corner, distance: float) -> float:
    """[rad] How far the arcs next to the corner turn on their pieces ``distance`` [mm] (a
    straight distance) from it: what the contour replaces besides the corner."""
    return sum(2.0 * math.asin(min(1.0, distance / (2.0 * s.radius)))
               for s in (c.before, c.after) if isinstance(s, Arc))


def left_to_half_turn(c: Corner) -> float:
    """[rad] π minus the turn between the segments' own tangents at the corner (they differ
    from the drawn turn by round-off, which near a reversal is large against π - turn)."""
    t0, t1 = c.before.tangent(c.before.length), c.after.tangent(0.0)
    return 2.0 * math.atan2(np.linalg.norm(t0 + t1), np.linalg.norm(t0 - t1))


def widest_distance(c: Corner) -> float:
    """The largest corner distance (module text of blend.py): half of either segment, and the
    trimmed arcs turning by at most 3/4 of what the corner's turn leaves to a half turn."""
    budget = 0.75 * left_to_half_turn(c)
    lo, hi = 0.0, half_segment_limit(c)
    if arc_turn(c, hi) <= budget:
        return hi
    for _ in range(200):
        middle = 0.5 * (lo + hi)
        lo, hi = (middle, hi) if arc_turn(c, middle) <= budget else (lo, middle)
    return lo


def assert_joins_are_g2(blend: Blend, original: Corner) -> None:
    head, contour, tail = blend.before, blend.contour, blend.after
    # end points bit-exact: the path has no gap at all
    assert np.array_equal(contour.position(0.0), head.position(head.length))
    assert np.array_equal(contour.position(contour.length), tail.position(0.0))
    assert np.array_equal(head.start, original.before.start)
    assert np.array_equal(tail.end, original.after.end)
    # tangent and curvature vector continuous (curvature in 1/mm)
    for s_contour, segment, s_segment in ((0.0, head, head.length),
                                          (contour.length, tail, 0.0)):
        assert np.abs(contour.tangent(s_contour) - segment.tangent(s_segment)).max() <= EXACT
        assert np.abs(contour.curvature_vector(s_contour)
                      - segment.curvature_vector(s_segment)).max() <= EXACT


def assert_curvature_bounded(blend: Blend, original: Corner) -> None:
    contour = blend.contour
    kappa = contour.curvature(np.linspace(0.0, contour.length, 4001))
    assert math.isfinite(contour.max_curvature)
    assert kappa.max() <= contour.max_curvature * (1 + 1e-9)
    if isinstance(original.before, Line) and isinstance(original.after, Line):
        # within 1.27x the circular fillet with the same corner distance (module docstring)
        fillet = math.tan(original.turn / 2) / blend.corner_distance
        assert contour.max_curvature <= 1.27 * fillet
    # never much tighter than the circle through both ends that turns as far, nor than the
    # neighbours: this bounds κ·length too, which the sampled caps of a SCARA or delta robot
    # need (coordinated/limits.py); a contour next to a nearly reversing arc bent on 1/2000
    # of its length (D-138)
    t0, t1 = blend.before.tangent(blend.before.length), blend.after.tangent(0.0)
    turn = math.acos(float(np.clip(t0 @ t1, -1.0, 1.0)))
    chord = float(np.linalg.norm(contour.end - contour.start))
    ends = max(float(np.linalg.norm(blend.before.curvature_vector(blend.before.length))),
               float(np.linalg.norm(blend.after.curvature_vector(0.0))))
    assert contour.max_curvature <= 3.0 * max(2.0 * math.sin(turn / 2) / chord, ends)
    assert contour.max_curvature * contour.length <= 8.0
    # ... because the contour replaces less than half a turn of the path
    assert arc_turn(original, blend.corner_distance) <= 0.75 * left_to_half_turn(original) \
        + EXACT


@given(corners(), st.floats(0.02, 1.5))
def test_corner_distance_blend(c, fraction):
    limit = widest_distance(c)
    blend = corner_distance_blend(c.before, c.after, fraction * limit)
    if abs(fraction - 1.0) > 1e-12:  # the limit here is a bisection, blend.py's closed form
        assert blend.clamped == (fraction > 1.0)
    assert blend.corner_distance == pytest.approx(min(fraction, 1.0) * limit, rel=1e-12)
    for cut in (blend.before.end, blend.after.start):
        assert abs(np.linalg.norm(cut - c.corner) - blend.corner_distance) <= EXACT
    assert_joins_are_g2(blend, c)
    assert_curvature_bounded(blend, c)
    assert 0.0 < blend.corner_deviation <= blend.corner_distance  # the corner is not passed


@given(corners(), st.floats(0.01, 2.0))
def test_max_corner_deviation_blend(c, fraction):
    widest = corner_distance_blend(c.before, c.after, widest_distance(c)).corner_deviation
    deviation = fraction * widest
    blend = max_corner_deviation_blend(c.before, c.after, deviation)
    if blend.clamped:
        assert blend.corner_deviation <= deviation + EXACT
        assert fraction >= 1.0 - 1e-9
    else:
        assert abs(blend.corner_deviation - deviation) <= EXACT
    # an independent look: no sampled contour point comes nearer than the deviation
    contour = blend.contour
    s = np.linspace(0.0, contour.length, 4001)
    gaps = np.linalg.norm(contour.position(s) - c.corner, axis=1)
    assert gaps.min() >= blend.corner_deviation - EXACT
    # ... and one sample lies within half a step of the nearest point, on a curve that bends
    spread = (s[1] - s[0]) * math.sqrt(1.0 + contour.max_curvature * blend.corner_deviation)
    assert gaps.min() <= math.hypot(blend.corner_deviation, spread) + EXACT
    assert_joins_are_g2(blend, c)
    assert_curvature_bounded(blend, c)


@given(corners())
def test_contour_arc_length_matches_dense_sampling(c):
    """Richardson on chord sums needs chords short against the radius of curvature: a contour
    bends on no less than 1/8 of its length (``assert_curvature_bounded``), so 4000 chords
    keep κ·Δs <= 0.002."""
    contour = corner_distance_blend(c.before, c.after, 0.5 * widest_distance(c)).contour
    assert contour.max_curvature * contour.length <= 8.0
    s = np.linspace(0.0, contour.length, 4001)
    p = contour.position(s)
    chords = np.linalg.norm(np.diff(p, axis=0), axis=1)
    # consecutive points s apart are a chord s apart, short of it by at most (κ·Δs)²·Δs/24
    ds, noise = s[1] - s[0], 1e-14 * max(1.0, np.abs(p).max())  # round-off of the coordinates
    assert np.all(chords <= ds + noise)
    assert np.all(chords >= ds * (1 - (contour.max_curvature * ds) ** 2 / 24) - noise)
    coarse, fine = chords.sum(), np.linalg.norm(np.diff(p[::2], axis=0), axis=1).sum()
    assert abs((4 * coarse - fine) / 3 - contour.length) <= 1e-9 * max(1.0, contour.length)


def test_line_line_right_angle_is_symmetric_and_scales_with_the_distance():
    before, after = Line([-50.0, 0.0, 0.0], [0.0, 0.0, 0.0]), Line([0.0, 0.0, 0.0], [0, 50.0, 0])
    small, large = (corner_distance_blend(before, after, d) for d in (2.0, 20.0))
    assert large.corner_deviation == pytest.approx(10 * small.corner_deviation, rel=1e-12)
    assert small.contour.max_curvature == pytest.approx(10 * large.contour.max_curvature,
                                                        rel=1e-9)
    middle = small.contour.position(small.contour.length / 2)
    np.testing.assert_allclose(middle[0], -middle[1], atol=1e-12)
    # the deviation request inverts the distance request
    again = max_corner_deviation_blend(before, after, small.corner_deviation)
    assert again.corner_distance == pytest.approx(2.0, rel=1e-9)


def test_evaluation_is_vectorised():
    contour = corner_distance_blend(Line([0, 0, 0], [10.0, 0, 0]),
                                    Line([10.0, 0, 0], [10.0, 10.0, 0]), 3.0).contour
    s = np.linspace(0.0, contour.length, 12).reshape(3, 4)
    assert contour.position(s).shape == (3, 4, 3) and contour.tangent(s).shape == (3, 4, 3)
    assert contour.curvature(s).shape == (3, 4)
    assert contour.position(1.0).shape == (3,) and np.ndim(contour.curvature(1.0)) == 0


def test_straight_continuation_gives_a_straight_contour():
    before, after = Line([0, 0, 0], [10.0, 0, 0]), Line([10.0, 0, 0], [20.0, 0, 0])
    blend = corner_distance_blend(before, after, 2.0)
    assert blend.contour.max_curvature <= 1e-15 and blend.contour.length == pytest.approx(4.0)
    widest = max_corner_deviation_blend(before, after, 1.0)  # no turn: no deviation at all
    assert widest.clamped and widest.corner_distance == 5.0 and widest.corner_deviation < 1e-15


def rejected(call) -> str:
    with pytest.raises(CommandRejected) as info:
        call()
    assert info.value.error_id == ErrorId.INVALID_PATH_GEOMETRY
    return info.value.message


A, B = Line([0.0, 0.0, 0.0], [10.0, 0.0, 0.0]), Line([10.0, 0.0, 0.0], [10.0, 10.0, 0.0])


@pytest.mark.parametrize("distance", [0.0, -1.0, math.nan, math.inf])
def test_distance_and_deviation_must_be_positive_lengths(distance):
    rejected(lambda: corner_distance_blend(A, B, distance))
    rejected(lambda: max_corner_deviation_blend(A, B, distance))


def test_segments_must_meet():
    assert "does not start" in rejected(
        lambda: corner_distance_blend(A, Line([10.0, 1.0, 0.0], [20.0, 1.0, 0.0]), 1.0))


def test_reversal_cannot_be_blended():
    assert "turns back" in rejected(
        lambda: corner_distance_blend(A, Line([10.0, 0.0, 0.0], [5.0, 0.0, 0.0]), 1.0))


def test_contour_rejects_a_cusp():
    x = np.array([1.0, 0.0, 0.0])
    rejected(lambda: Contour([0, 0, 0], x, [0, 0, 0], [0, 0, 0], -x, [0, 0, 0], 1.0))
    rejected(lambda: Contour([0, 0, 0], x, [0, 0, 0], [1, 0, 0], x, [0, 0, 0], 0.0))
