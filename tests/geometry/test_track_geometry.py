"""Planar track geometry: exact lengths, G2 everywhere, exact arc length, closest points.

TF5430 §6.2 (tracks must be C² at every point, §6.2.10), the geometry methods of
MC_PlanarTrack (§7.2.2.10) and the track coordinates of the worked examples §6.2.4-§6.2.12
(digest-planar-concepts §6). Random tracks are polylines and chains of lines and arcs with
gaps, shared corners and tangent joins.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
import shapely
from hypothesis import assume, given
from hypothesis import strategies as st

from openmotion.core.errors import ConfigError
from openmotion.geometry.track import PieceKind, TrackPath, TrackPose, joins_smoothly
from openmotion.geometry.track_elements import ANGLE_TOLERANCE

EXACT = 1e-9  #: [mm] the accuracy the track promises for positions and arc lengths
STEP = 1e-4  #: [mm] finite-difference step along the track


def line_track(*points: tuple[float, float]) -> TrackPath:
    """AppendLine between consecutive pairs of points: (a, b), (c, d), ..."""
    track = TrackPath()
    for start, end in zip(points[::2], points[1::2], strict=True):
        track.append_line(start, end)
    return track


def boundaries(track: TrackPath) -> list[float]:
    """Arc lengths where one piece meets the next (and 0 on a closed loop)."""
    inner = [piece.start for piece in track.pieces[1:]]
    return [0.0, *inner] if track.closed else inner


def assert_g2(track: TrackPath) -> None:
    """Position, heading and curvature continuous at every joint; the curvature is the rate
    of the heading (a centred difference across each joint and along the track). Headings
    within ``ANGLE_TOLERANCE`` count as equal, so a joint may keep a kink that small."""
    length = track.length
    dense = np.linspace(0.0, length, 4001)
    rate = np.max(np.abs(np.diff(track.curvatures_at(dense)))) / (dense[1] - dense[0])
    for b in boundaries(track):
        x, y, heading, curvature = track.frame_at(np.array([b - 1e-9, b + 1e-9]))
        assert math.hypot(x[1] - x[0], y[1] - y[0]) <= 2e-9 + EXACT
        assert abs(math.remainder(heading[1] - heading[0], 2 * math.pi)) <= 1e-7
        assert abs(curvature[1] - curvature[0]) <= 1e-7
    s = np.concatenate([boundaries(track), np.linspace(STEP, length - STEP, 97)])
    if not track.closed:
        s = s[(s >= STEP) & (s <= length - STEP)]
    heading = track.headings_at(np.concatenate([s - STEP, s + STEP]))
    turned = np.remainder(heading[s.size:] - heading[:s.size] + math.pi, 2 * math.pi) - math.pi
    np.testing.assert_allclose(turned / (2 * STEP), track.curvatures_at(s),
                               atol=1e-6 + 2 * rate * STEP + ANGLE_TOLERANCE / STEP)


def assert_unit_speed(track: TrackPath, samples: int = 400) -> None:
    """s is the arc length: chords of ``STEP`` are ``STEP`` long up to the curvature term
    and the round-off of the positions (1e-12 mm)."""
    s = np.linspace(0.0, track.length - STEP, samples)
    chord = np.linalg.norm(track.positions_at(s + STEP) - track.positions_at(s), axis=-1)
    kappa = track.max_curvature
    assert np.all(np.abs(chord - STEP) <= STEP * (kappa * STEP) ** 2 / 24 + 1e-11)


def assert_round_trip(track: TrackPath, s: np.ndarray) -> None:
    """The closest track point to position_at(s) is that point, at s."""
    points = track.positions_at(s)
    back = track.arc_lengths_closest_to(points)
    np.testing.assert_allclose(track.positions_at(back), points, rtol=0, atol=EXACT)
    if shapely.LineString(track.positions_at(np.linspace(0, track.length, 2000))).is_simple:
        gap = np.abs(back - s)
        if track.closed:
            gap = np.minimum(gap, track.length - gap)
        assert np.all(gap <= EXACT), gap.max()


def transition_lengths(track: TrackPath) -> list[float]:
    return [p.end - p.start for p in track.pieces if p.kind == PieceKind.TRANSITION]


# -- lines and arcs are exact ----------------------------------------------------------------

def test_line_length_and_points_are_exact():
    track = line_track((100.0, 100.0), (860.0, 100.0))  # §6.2.8
    assert track.length == 760.0
    assert track.position_at(600.0) == (700.0, 100.0)
    assert track.max_curvature == 0.0


@pytest.mark.parametrize(("clockwise", "quarters"), [(False, 1), (True, 3)])
def test_arc_turns_as_appendcircle_says(clockwise: bool, quarters: int):
    """§7.2.2.10.4: from start about center to end, clockwise or not."""
    track = TrackPath()
    track.append_circle((100.0, 0.0), (0.0, 100.0), (0.0, 0.0), clockwise)
    assert track.length == pytest.approx(quarters * 50.0 * math.pi, rel=1e-15)
    x, y, heading, curvature = track.frame_at(np.array([quarters * 25.0 * math.pi]))
    sign = -1.0 if clockwise else 1.0
    phi = sign * quarters * math.pi / 4  # half way round
    assert (x[0], y[0]) == pytest.approx((100 * math.cos(phi), 100 * math.sin(phi)), abs=1e-12)
    assert curvature[0] == sign / 100.0
    assert (math.cos(heading[0]), math.sin(heading[0])) == pytest.approx(
        (math.cos(phi + sign * math.pi / 2), math.sin(phi + sign * math.pi / 2)), abs=1e-12)


def test_full_circle_and_its_closed_loop():
    """An end equal to the start is the full circle; CloseLoop then adds nothing."""
    track = TrackPath()
    track.append_circle((300.0, 200.0), (300.0, 200.0), (200.0, 200.0), False)
    track.close_loop()
    assert track.length == pytest.approx(200.0 * math.pi, rel=1e-15)
    assert [p.kind for p in track.pieces] == [PieceKind.ARC]
    s = np.linspace(-500.0, 1500.0, 41)
    np.testing.assert_allclose(track.positions_at(s), track.positions_at(s + track.length),
                               atol=1e-12)
    assert_round_trip(track, np.linspace(0.0, track.length, 50, endpoint=False))


def test_lookups_take_arrays_of_any_shape_and_match_scalar_calls():
    track = TrackPath()
    track.append_line((0.0, 0.0), (100.0, 0.0))
    track.append_circle((100.0, 0.0), (150.0, 50.0), (100.0, 50.0), False)
    s = np.linspace(-10.0, track.length + 10.0, 24).reshape(4, 6)
    assert track.positions_at(s).shape == (4, 6, 2)
    for value, point in zip(s.ravel(), track.positions_at(s).reshape(-1, 2), strict=True):
        assert track.position_at(float(value)) == tuple(point)
    assert track.position_at(-5.0) == (0.0, 0.0)  # clamped on an open track


# -- transitions ---------------------------------------------------------------------------

def test_a_corner_at_a_shared_point_is_rounded_g2():
    track = TrackPath()
    for point in [(0.0, 0.0), (200.0, 0.0), (200.0, 100.0), (50.0, 250.0)]:
        track.append_position(point)
    kinds = [p.kind for p in track.pieces]
    assert kinds == [PieceKind.LINE, PieceKind.TRANSITION] * 2 + [PieceKind.LINE]
    # each corner takes a quarter of the shorter neighbour from both sides
    assert track.pieces[0].end == pytest.approx(200.0 - 25.0, abs=1e-12)
    assert_g2(track)
    assert_unit_speed(track)


def test_a_tangent_line_arc_join_gets_a_curvature_transition():
    """0 -> 1/R is a curvature step: §6.2.10 forbids it, so it is rounded."""
    track = TrackPath()
    track.append_line((0.0, 0.0), (300.0, 0.0))
    track.append_circle((300.0, 0.0), (350.0, 50.0), (300.0, 50.0), False)
    assert [p.kind for p in track.pieces] == [PieceKind.LINE, PieceKind.TRANSITION,
                                              PieceKind.ARC]
    quarter = 25.0 * math.pi
    assert track.pieces[1].start == pytest.approx(300.0 - quarter / 4, abs=1e-12)
    assert track.pieces[1].max_curvature < 1.2 / 50.0
    assert_g2(track)


def test_transition_lengths_are_exact_arc_lengths():
    """Equal to blend.py's own evaluation of the same curve (the Contour behind the piece,
    which integrates and inverts the arc length independently) and to a fine polyline."""
    track = line_track((250.0, 120.0), (650.0, 120.0), (700.0, 170.0), (800.0, 450.0))
    piece = track._assembled()[0][1]
    assert piece.length == pytest.approx(piece.contour.length, abs=EXACT)
    s = np.linspace(0.0, piece.length, 2001)
    np.testing.assert_allclose(track.positions_at(track.pieces[1].start + s),
                               piece.contour.position(s)[:, :2], rtol=0, atol=EXACT)
    s = np.linspace(track.pieces[1].start, track.pieces[1].end, 200_001)
    polyline = np.linalg.norm(np.diff(track.positions_at(s), axis=0), axis=1).sum()
    assert polyline == pytest.approx(track.pieces[1].end - track.pieces[1].start, abs=1e-7)


def test_max_curvature_bounds_every_sample():
    track = line_track((0.0, 0.0), (100.0, 0.0), (150.0, 30.0), (150.0, 200.0))
    for piece in track.pieces:
        s = np.linspace(piece.start, piece.end, 5001)
        sampled = np.abs(track.curvatures_at(s)).max()
        assert sampled <= piece.max_curvature * (1 + 1e-9) + 1e-15
        assert sampled >= piece.max_curvature * (1 - 1e-6)


def test_closed_rounded_rectangle_loop_length():
    """Four sides with 40 mm corners left open (as §6.2.11 leaves them): four congruent
    transitions; one lap is the sides plus four transitions, and s wraps."""
    track = line_track((40.0, 0.0), (360.0, 0.0), (400.0, 40.0), (400.0, 160.0),
                       (360.0, 200.0), (40.0, 200.0), (0.0, 160.0), (0.0, 40.0))
    track.close_loop()
    corners = transition_lengths(track)
    assert len(corners) == 4
    np.testing.assert_allclose(corners, corners[0], rtol=0, atol=EXACT)
    assert 20.0 * math.pi < corners[0] < 80.0  # longer than a quarter circle, shorter than legs
    assert track.length == pytest.approx(2 * 320.0 + 2 * 120.0 + 4 * corners[0], abs=EXACT)
    assert track.position_at(track.length + 10.0) == pytest.approx((50.0, 0.0), abs=1e-12)
    assert_g2(track)
    assert_round_trip(track, np.linspace(0.0, track.length, 400, endpoint=False))


def test_closed_loop_of_lines_and_tangent_arcs():
    """A rounded rectangle drawn with AppendCircle at shared points: eight curvature steps,
    eight transitions, and a lap close to the drawn one."""
    track = TrackPath()
    r = 50.0
    track.append_line((r, 0.0), (400.0 - r, 0.0))
    track.append_circle((400.0 - r, 0.0), (400.0, r), (400.0 - r, r), False)
    track.append_line((400.0, r), (400.0, 200.0 - r))
    track.append_circle((400.0, 200.0 - r), (400.0 - r, 200.0), (400.0 - r, 200.0 - r), False)
    track.append_line((400.0 - r, 200.0), (r, 200.0))
    track.append_circle((r, 200.0), (0.0, 200.0 - r), (r, 200.0 - r), False)
    track.append_line((0.0, 200.0 - r), (0.0, r))
    track.append_circle((0.0, r), (r, 0.0), (r, r), False)
    track.close_loop()
    assert len(transition_lengths(track)) == 8
    drawn = 2 * (400.0 - 2 * r) + 2 * (200.0 - 2 * r) + 2 * math.pi * r
    assert abs(track.length - drawn) < 0.01 * drawn
    assert track.start_pose.x > r  # the closing corner rounding moved s = 0 along the line
    assert_g2(track)
    assert_unit_speed(track)
    assert_round_trip(track, np.linspace(0.0, track.length, 300, endpoint=False))


# -- the manual's tracks (digest-planar-concepts §6) ----------------------------------------

def test_joining_and_moving_track_6_2_4():
    track = line_track((0.0, 0.0), (400.0, 0.0))
    assert track.length == 400.0
    assert track.position_at(150.0) == (150.0, 0.0)
    assert track.arc_length_closest_to((240.0, 0.0)) == 240.0  # mover two joins at 240


def test_tracks_across_parts_6_2_5():
    """track_two starts from track_one's end (240, 120); its line starts at (260, 120), so
    a straight 20 mm connector; position 150 is x = 390."""
    one = line_track((40.0, 120.0), (240.0, 120.0))
    two = TrackPath()
    two.start_from(one)
    two.append_line((260.0, 120.0), (440.0, 120.0))
    assert one.length == 200.0 and two.length == 200.0
    assert [p.kind for p in two.pieces] == [PieceKind.LINE, PieceKind.LINE]
    assert two.position_at(150.0) == (390.0, 120.0)
    assert one.arc_length_closest_to((120.0, 120.0)) == 80.0


def test_network_6_2_10():
    """Only the straight sections are given; every blending is generated and G2."""
    one = line_track((250.0, 120.0), (650.0, 120.0), (700.0, 170.0), (800.0, 450.0),
                     (650.0, 500.0), (250.0, 500.0))
    two = TrackPath()
    two.start_from(one)
    two.append_line((200.0, 450.0), (200.0, 170.0))
    two.end_at(one)
    three, four = TrackPath(), TrackPath()
    three.start_from(one)
    three.append_line((200.0, 500.0), (120.0, 500.0))
    four.start_from(one)
    four.append_line((200.0, 550.0), (200.0, 750.0))
    for track in (one, two, three, four):
        assert_g2(track)
    for after in (two, three, four):
        assert joins_smoothly(one.end_pose, after.start_pose)
    assert joins_smoothly(two.end_pose, one.start_pose)  # the loop one -> two -> one
    assert three.length == pytest.approx(130.0, abs=1e-12) and three.max_curvature == 0.0
    corner = transition_lengths(two)
    assert corner[0] == pytest.approx(corner[1], abs=EXACT)  # two congruent 50 x 50 corners
    assert two.length == pytest.approx(280.0 + 2 * corner[0], abs=EXACT)
    assert four.length == pytest.approx(200.0 + corner[0], abs=EXACT)


def test_network_on_parts_6_2_11():
    """Track two and track three have the same length (the manual says so): 320 mm of lines
    and two congruent 40 x 40 corners each. Part 2 sits at (480, 0) or (480, 480)."""

    def three_at(dx: float, dy: float) -> TrackPath:
        def at(x: float, y: float) -> tuple[float, float]:
            return x + dx, y + dy
        return line_track(at(0, 360), at(80, 360), at(120, 320), at(120, 160),
                          at(80, 120), at(0, 120))

    lower, upper = three_at(480.0, 0.0), three_at(480.0, 480.0)
    two, one = TrackPath(), TrackPath()
    two.start_from(upper)
    two.append_line((440.0, 600.0), (400.0, 600.0))
    two.append_line((360.0, 560.0), (360.0, 400.0))
    two.append_line((400.0, 360.0), (440.0, 360.0))
    two.end_at(lower)
    one.start_from(lower)
    one.append_line((440.0, 120.0), (160.0, 120.0))
    one.append_line((120.0, 160.0), (120.0, 800.0))
    one.append_line((160.0, 840.0), (440.0, 840.0))
    one.end_at(upper)
    corner = transition_lengths(lower)[0]
    assert two.length == pytest.approx(lower.length, abs=EXACT)
    assert lower.length == pytest.approx(320.0 + 2 * corner, abs=EXACT)
    assert one.length == pytest.approx(1280.0 + 2 * corner, abs=EXACT)
    assert transition_lengths(one) == pytest.approx([corner, corner], abs=EXACT)
    assert joins_smoothly(one.end_pose, upper.start_pose)
    assert joins_smoothly(two.end_pose, lower.start_pose)
    # the 50 mm corners of §6.2.10 are these scaled by 1.25
    assert transition_lengths(line_track((0, 0), (10, 0), (60, 50), (60, 60)))[0] == (
        pytest.approx(1.25 * corner, abs=EXACT))


def test_switch_branches_6_2_12():
    """out1 and out2 leave track_in's end (400, 360) as mirror images about y = 360."""
    track_in = line_track((100.0, 360.0), (400.0, 360.0))
    out1, out2 = TrackPath(), TrackPath()
    out1.start_from(track_in)
    out1.append_line((450.0, 410.0), (860.0, 620.0))
    out2.start_from(track_in)
    out2.append_line((450.0, 310.0), (860.0, 100.0))
    assert track_in.length == 300.0
    assert out1.length == pytest.approx(out2.length, abs=EXACT)
    assert out1.length == pytest.approx(transition_lengths(out1)[0] + math.hypot(410, 210),
                                        abs=EXACT)
    s = np.linspace(0.0, out1.length, 101)
    x1, y1, h1, k1 = out1.frame_at(s)
    x2, y2, h2, k2 = out2.frame_at(s)
    np.testing.assert_allclose(np.stack([x2, 720.0 - y2, -h2, -k2]),
                               np.stack([x1, y1, h1, k1]), atol=1e-9)
    assert_g2(out1)
    assert_round_trip(out1, s)


# -- connections -----------------------------------------------------------------------------

def test_start_and_end_connections_match_curved_poses():
    """StartFromTrack / EndAtTrack against tracks that end (start) on arcs."""
    ring = TrackPath()
    ring.append_circle((100.0, 0.0), (0.0, 100.0), (0.0, 0.0), False)
    branch = TrackPath()
    branch.start_from(ring)
    branch.append_line((-60.0, 160.0), (-200.0, 160.0))
    branch.end_at(TrackPose(-260.0, 100.0, -math.pi / 2, -1.0 / 60.0))
    assert joins_smoothly(ring.end_pose, branch.start_pose)
    assert joins_smoothly(branch.end_pose, TrackPose(-260.0, 100.0, -math.pi / 2, -1 / 60))
    assert_g2(branch)


def test_a_line_starting_tangentially_at_the_other_tracks_curved_end():
    """Only a curvature step: the line gives up a quarter for the transition."""
    ring = TrackPath()
    ring.append_circle((100.0, 0.0), (0.0, 100.0), (0.0, 0.0), False)
    branch = TrackPath()
    branch.start_from(ring)
    branch.append_line((0.0, 100.0), (-200.0, 100.0))
    assert [p.kind for p in branch.pieces] == [PieceKind.TRANSITION, PieceKind.LINE]
    assert branch.pieces[1].end - branch.pieces[1].start == pytest.approx(150.0, abs=1e-12)
    assert joins_smoothly(ring.end_pose, branch.start_pose)
    assert_g2(branch)


def test_hose_reach_of_two_diverging_lines():
    """Lines leaving one point 60° apart: the distance grows as s·sin 60°."""
    up = line_track((0.0, 0.0), (500.0 * math.cos(0.5236), 500.0 * math.sin(0.5236)))
    down = line_track((0.0, 0.0), (500.0 * math.cos(0.5236), -500.0 * math.sin(0.5236)))
    reach = 100.0 / math.sin(2 * 0.5236)
    assert up.hose_reach(down, 100.0) == pytest.approx(reach, abs=1e-8)
    back_up = line_track(up.position_at(500.0), (0.0, 0.0))
    back_down = line_track(down.position_at(500.0), (0.0, 0.0))
    assert back_up.hose_reach(back_down, 100.0, from_end=True) == pytest.approx(reach, abs=1e-8)
    assert up.hose_reach(down, 1000.0) == up.length


# -- bad input -------------------------------------------------------------------------------

def closed_square() -> TrackPath:
    track = line_track((0, 0), (100, 0), (100, 100), (0, 100))
    track.close_loop()
    return track


@pytest.mark.parametrize(("build", "message"), [
    (lambda t: t.append_line((1.0, 2.0), (1.0, 2.0)), "zero length"),
    (lambda t: t.append_line((0.0, math.nan), (1.0, 2.0)), "finite"),
    (lambda t: t.append_line((0.0, 0.0), (math.inf, 2.0)), "finite"),
    (lambda t: t.append_circle((5.0, 5.0), (6.0, 6.0), (5.0, 5.0), False), "radius 0"),
    (lambda t: t.append_circle((10.0, 0.0), (0.0, 11.0), (0.0, 0.0), False), "from the centre"),
    (lambda t: t.close_loop(), "at least one"),
    (lambda t: t.end_at(line_track((0, 0), (1, 0))), "no start"),
    (lambda t: (t.append_line((0, 0), (100, 0)), t.append_line((100, 0), (0, 0))),
     "turns back"),
    (lambda t: (t.append_line((0, 0), (100, 0)), t.close_loop()), "no smooth transition"),
    (lambda t: (t.append_position((0, 0)), t.start_from(line_track((0, 0), (1, 0)))),
     "before the first"),
    (lambda t: (t.start_from(line_track((0, 0), (100, 0))), t.append_line((100, 0), (100, 50))),
     "cannot be rounded"),
    (lambda t: t.start_from(TrackPose(0.0, math.nan, 0.0, 0.0)), "finite"),
    (lambda t: t.length, "no geometry"),
    (lambda t: (t.append_position((0, 0)), t.position_at(0.0)), "no geometry"),
    (lambda t: (t.append_line((0, 0), (100, 0)), t.position_at(math.nan)), "finite"),
    (lambda t: (t.append_line((0, 0), (100, 0)), t.arc_length_closest_to((0, math.nan))),
     "finite"),
    (lambda t: (t.append_line((0, 0), (100, 0)), t.hose_reach(t, 0.0)), "positive"),
])
def test_bad_geometry_is_refused_with_a_reason(build, message: str):
    with pytest.raises(ConfigError, match=message):
        build(TrackPath())


@pytest.mark.parametrize("append", [
    lambda t: t.append_position((5.0, 5.0)),
    lambda t: t.append_line((0.0, 0.0), (5.0, 5.0)),
    lambda t: t.append_circle((0.0, 0.0), (5.0, 5.0), (5.0, 0.0), True),
    lambda t: t.close_loop(),
    lambda t: t.end_at(line_track((0, 0), (1, 0))),
])
def test_nothing_follows_a_closed_loop_or_an_end_at_another_track(append):
    with pytest.raises(ConfigError, match="closed loop"):
        append(closed_square())
    ended = line_track((0.0, 0.0), (100.0, 0.0))
    ended.end_at(line_track((200.0, 0.0), (300.0, 0.0)))
    with pytest.raises(ConfigError, match="ends at another track"):
        append(ended)


def test_a_refused_element_leaves_the_track_unchanged():
    track = line_track((0.0, 0.0), (100.0, 0.0))
    with pytest.raises(ConfigError):
        track.append_line((100.0, 0.0), (50.0, 0.0))
    assert track.length == 100.0 and len(track.pieces) == 1
    track.append_position((100.0, 80.0))
    assert_g2(track)


# -- properties over random tracks ---------------------------------------------------------

@st.composite
def polylines(draw) -> TrackPath:
    """AppendPosition vertices: steps 20-400 mm, turns up to 150° either way, maybe closed."""
    heading = draw(st.floats(-math.pi, math.pi))
    point = (draw(st.floats(-500.0, 500.0)), draw(st.floats(-500.0, 500.0)))
    track = TrackPath()
    track.append_position(point)
    for _ in range(draw(st.integers(1, 6))):
        heading += draw(st.floats(-2.6, 2.6))
        step = draw(st.floats(20.0, 400.0))
        point = (point[0] + step * math.cos(heading), point[1] + step * math.sin(heading))
        track.append_position(point)
    if draw(st.booleans()):
        try:
            track.close_loop()
        except ConfigError:  # the closing transition would cusp or cross itself
            assume(False)
    return track


@st.composite
def chains(draw) -> TrackPath:
    """Lines and arcs; each starts at the previous end (a corner or a tangent join) or after
    a gap, heading anywhere within 120° of the previous heading. Draws whose joins the track
    refuses (a transition that would cusp or cross itself) are rejected."""
    track = TrackPath()
    x, y, heading = 0.0, 0.0, draw(st.floats(-math.pi, math.pi))
    for _ in range(draw(st.integers(1, 5))):
        if draw(st.booleans()):  # a gap before the element
            aside = heading + draw(st.floats(-1.0, 1.0))
            gap = draw(st.floats(20.0, 200.0))
            x, y = x + gap * math.cos(aside), y + gap * math.sin(aside)
        heading += draw(st.sampled_from([0.0, draw(st.floats(-2.1, 2.1))]))
        if draw(st.booleans()):
            length = draw(st.floats(20.0, 400.0))
            end = (x + length * math.cos(heading), y + length * math.sin(heading))
            appended = _accepted(track.append_line, (x, y), end)
        else:
            radius = draw(st.floats(20.0, 300.0))
            sweep = draw(st.floats(0.2, 4.7)) * draw(st.sampled_from([-1.0, 1.0]))
            sense = math.copysign(1.0, sweep)
            cx = x - sense * radius * math.sin(heading)
            cy = y + sense * radius * math.cos(heading)
            phi = math.atan2(y - cy, x - cx) + sweep
            end = (cx + radius * math.cos(phi), cy + radius * math.sin(phi))
            appended = _accepted(track.append_circle, (x, y), end, (cx, cy), sweep < 0.0)
            heading += sweep
        assume(appended)
        x, y = end
    return track


def _accepted(append: Callable[..., None], *args: object) -> bool:
    """Call one of the track's append methods; False if the track refuses the element."""
    try:
        append(*args)
    except ConfigError:
        return False
    return True


def random_tracks() -> st.SearchStrategy[TrackPath]:
    return st.one_of(polylines(), chains())


@given(track=random_tracks())
def test_random_tracks_are_g2_with_exact_arc_length(track: TrackPath):
    assert_g2(track)
    assert_unit_speed(track, samples=200)


@given(track=random_tracks(), data=st.data())
def test_random_tracks_closest_point_round_trip(track: TrackPath, data: st.DataObject):
    joints = np.array([p.start for p in track.pieces])
    near = joints + np.array(data.draw(st.lists(st.floats(-1e-3, 1e-3), min_size=joints.size,
                                                max_size=joints.size)))
    s = np.clip(np.concatenate([np.linspace(0.0, track.length, 60), near]), 0, track.length)
    if track.closed:
        s = s[s < track.length]
    assert_round_trip(track, s)


@given(track=random_tracks(), offset=st.floats(-5.0, 5.0))
def test_random_tracks_closest_point_off_the_track(track: TrackPath, offset: float):
    """A point beside the track: no track point is nearer than the one returned."""
    s = np.linspace(0.0, track.length, 25)
    x, y, heading, _ = track.frame_at(s)
    points = np.stack([x - offset * np.sin(heading), y + offset * np.cos(heading)], axis=-1)
    found = track.positions_at(track.arc_lengths_closest_to(points))
    dense = track.positions_at(np.linspace(0.0, track.length, 20_001))
    nearest = np.min(np.linalg.norm(dense[None, :, :] - points[:, None, :], axis=-1), axis=1)
    assert np.all(np.linalg.norm(found - points, axis=-1) <= nearest + EXACT)
