"""The compiled admission loops against shapely: hulls of straight-move pieces and the exact
test of two convex pieces (area_kernels)."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given
from hypothesis import strategies as st

from openmotion.planar.area_kernels import (
    convex_hull,
    interiors_meet,
    line_piece_hull,
    line_piece_meets,
    meeting_pairs,
)
from openmotion.planar.reservation import footprint, footprint_area
from openmotion.planar.tolerances import DISTANCE_NOISE as NOISE

HALF = 77.5
coordinate = st.floats(-500.0, 500.0)
angle = st.one_of(st.sampled_from([0.0, 90.0, -90.0, 180.0, 45.0]), st.floats(-200.0, 200.0))
#: centres on the half-footprint grid, so that many footprints stand exactly edge to edge
grid = st.integers(-4, 4).map(lambda k: k * HALF)


@given(x0=coordinate, y0=coordinate, x1=coordinate, y1=coordinate, low=angle,
       span=st.one_of(st.just(0.0), st.floats(0.0, 20.0)))
def test_a_straight_pieces_outline_is_the_shapely_hull_of_its_corner_cloud(x0, y0, x1, y1, low,
                                                                            span):
    """The hull of the footprints at the lowest and highest c and the pushed-out apexes, at
    both ends of the run: the polygon shapely's convex hull of those points gives, up to
    rounding where a run is parallel to an edge (a point on the line kept or dropped)."""
    high = low + span
    outline = line_piece_hull(x0, y0, x1, y1, low, high, HALF, HALF, NOISE)
    corners = [footprint(0.0, 0.0, c, 2 * HALF, 2 * HALF).exterior.coords[:4]
               for c in (low, high)]
    cloud = np.concatenate(corners)
    if span > NOISE:
        out = np.cos(np.radians(span) / 2.0)
        middle = footprint(0.0, 0.0, (low + high) / 2.0, 2 * HALF, 2 * HALF).exterior.coords[:4]
        cloud = np.concatenate((cloud, np.array(middle) / out))
    points = np.concatenate((cloud + (x0, y0), cloud + (x1, y1)))
    reference = shapely.convex_hull(shapely.multipoints(points))
    polygon = shapely.polygons(outline)
    assert polygon.is_valid and polygon.exterior.is_ccw
    assert polygon.hausdorff_distance(reference) < 1e-9


@given(x0=grid, y0=grid, x1=grid, y1=grid, low=angle,
       span=st.one_of(st.just(0.0), st.floats(0.0, 20.0)), cx=grid, cy=grid, c=angle)
def test_a_pieces_first_exact_test_is_its_hull_and_interiors_meet(x0, y0, x1, y1, low, span,
                                                                   cx, cy, c):
    """Equivalence: ``line_piece_meets`` gives ``line_piece_hull``'s vertices and
    ``interiors_meet``'s verdict against another footprint, bit for bit (D-328)."""
    points = np.array([(x0, y0, low), (x1, y1, low + span)])
    low_high = np.array([low]), np.array([low + span])
    other = footprint_area(cx, cy, c).outline(0)
    hull, meets = line_piece_meets(points, *low_high, 0, HALF, HALF, NOISE, other)
    expected = line_piece_hull(x0, y0, x1, y1, low, low + span, HALF, HALF, NOISE)
    assert np.array_equal(hull, expected)
    assert meets == interiors_meet(expected, other)


@given(points=st.lists(st.tuples(grid, grid), min_size=3, max_size=12))
def test_convex_hull_is_shapelys_without_collinear_points(points):
    cloud = np.array(points, dtype=float)
    reference = shapely.convex_hull(shapely.multipoints(cloud))
    if reference.geom_type != "Polygon":  # collinear input: not a piece
        return
    outline = convex_hull(cloud)
    polygon = shapely.polygons(outline)
    assert polygon.exterior.is_ccw and shapely.equals(polygon, reference)
    assert len(outline) == len(shapely.simplify(reference, 0.0).exterior.coords) - 1


def _piece(draw: st.DrawFn) -> np.ndarray:
    x, y = draw(grid), draw(grid)
    if draw(st.booleans()):  # jittered off the grid
        x, y = x + draw(st.floats(-1.0, 1.0)), y + draw(st.floats(-1.0, 1.0))
    c = draw(st.sampled_from([0.0, 90.0, draw(st.floats(0.0, 90.0))]))
    length = draw(st.sampled_from([0.0, 2 * HALF, draw(st.floats(0.0, 300.0))]))
    heading = draw(st.sampled_from([0.0, 90.0, draw(st.floats(0.0, 360.0))]))
    dx, dy = length * np.cos(np.radians(heading)), length * np.sin(np.radians(heading))
    if heading in (0.0, 90.0):
        dx, dy = (length, 0.0) if heading == 0.0 else (0.0, length)
    return line_piece_hull(x, y, x + dx, y + dy, c, c + draw(st.sampled_from([0.0, 10.0])),
                           HALF, HALF, NOISE)


@given(data=st.data())
def test_interiors_meet_as_shapely_says_also_edge_to_edge(data):
    """Meeting is sharing interior points: pieces touching along an edge or at a corner
    (many here, on the half-footprint grid) do not meet, exactly as shapely decides."""
    first, second = _piece(data.draw), _piece(data.draw)
    a, b = shapely.polygons(first), shapely.polygons(second)
    assert interiors_meet(first, second) == (a.intersects(b) and not a.touches(b))


def test_footprints_side_by_side_touch_and_one_micrometre_closer_meet():
    left = footprint_area(0.0, 0.0).outline(0)
    assert not interiors_meet(left, footprint_area(155.0, 0.0).outline(0))
    assert not interiors_meet(left, footprint_area(155.0, 155.0).outline(0))
    assert interiors_meet(left, footprint_area(154.999, 0.0).outline(0))
    assert interiors_meet(left, footprint_area(10.0, 10.0, 45.0).outline(0))


def _reference_pairs(boxes, key, piece_keys, ranks, skip):
    """The candidate pairs as the registry built them in plain Python before they were
    compiled: slots near the whole key, then each piece's key, stable-sorted by rank."""
    near = [slot for slot in range(len(boxes)) if (boxes[slot] < key).all()
            and ranks[slot] not in skip.tolist()]
    if len(piece_keys) == 1:
        pairs = [(int(ranks[j]), 0, j) for j in near]
    else:
        pairs = [(int(ranks[j]), i, j) for i, k in enumerate(piece_keys) for j in near
                 if (boxes[j] < k).all()]
    return sorted(pairs, key=lambda pair: pair[0])


@given(seed=st.integers(0, 2**32 - 1), pieces=st.integers(1, 6), slots=st.integers(0, 40))
def test_meeting_pairs_are_the_near_boxes_in_rank_piece_and_slot_order(seed, pieces, slots):
    """The compiled broad phase finds the pairs the plain loops found, in the same order
    (rank, then piece, then slot), leaving out skipped ranks and free (+inf) slots."""
    rng = np.random.default_rng(seed)
    low = rng.uniform(0.0, 100.0, (slots, 2))
    boxes = np.concatenate((low, -(low + rng.uniform(1.0, 30.0, (slots, 2)))), axis=1)
    ranks = rng.integers(0, 6, slots)
    free = rng.random(slots) < 0.2
    boxes[free], ranks[free] = np.inf, -1
    piece_low = rng.uniform(0.0, 100.0, (pieces, 2))
    piece_keys = np.concatenate((piece_low + rng.uniform(1.0, 30.0, (pieces, 2)), -piece_low),
                                axis=1)
    key = piece_keys.max(axis=0)
    skip = np.array(rng.choice(6, size=int(rng.integers(0, 3)), replace=False), dtype=np.int64)
    pairs = meeting_pairs(boxes, key, piece_keys, ranks.astype(np.int64), skip)
    expected = _reference_pairs(boxes, key, piece_keys, ranks, skip)
    assert [tuple(p) for p in pairs.T.tolist()] == expected
