"""Footprints, swept areas and the group's area reservation (TF5430 §6.3, §6.4, §6.7.2)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given
from hypothesis import strategies as st

from openmotion.bench.planar_admission import (
    measure_admission,
    overlapping_pairs,
    reference_blocker,
)
from openmotion.core.errors import ConfigError
from openmotion.planar.enums import PlanarObjectType
from openmotion.planar.reservation import (
    MemberId,
    ReservationRegistry,
    SweptArea,
    footprint,
    footprint_area,
    straight_swept_area,
    swept_area,
    travel_runs,
)
from openmotion.planar.stators import StatorField

MOVER_ONE = MemberId(PlanarObjectType.MOVER, 0x05110010)
MOVER_TWO = MemberId(PlanarObjectType.MOVER, 0x05110020)
MOVER_THREE = MemberId(PlanarObjectType.MOVER, 0x05110030)
ENVIRONMENT = MemberId(PlanarObjectType.ENVIRONMENT, 0x05120010)
TRACK = MemberId(PlanarObjectType.TRACK, 0x05120030)


def line(start: tuple[float, ...], end: tuple[float, ...], samples: int = 201) -> np.ndarray:
    """A straight path x, y, c sampled evenly (c = 0 unless given)."""
    a, b = np.zeros(3), np.zeros(3)
    a[:len(start)], b[:len(end)] = start, end
    return a + np.linspace(0.0, 1.0, samples)[:, None] * (b - a)


def dense_footprints(path: np.ndarray, per_step: int = 6, **size: float) -> np.ndarray:
    """Footprints between the samples too: centre on the chord, c monotone but not in step."""
    f = np.linspace(0.0, 1.0, per_step, endpoint=False)
    poses = [np.column_stack([a[:2] + f[:, None] * (b[:2] - a[:2]), a[2] + f**2 * (b[2] - a[2])])
             for a, b in zip(path[:-1], path[1:], strict=True)]
    poses.append(path[-1:])
    return np.array([footprint(*p, **size) for p in np.concatenate(poses)], dtype=object)


def covers_all(area: shapely.Geometry, footprints: np.ndarray) -> bool:
    grown = shapely.buffer(area, 1e-6, join_style="mitre")
    return bool(shapely.covers(grown, footprints).all())


# --- footprints and swept areas -------------------------------------------------------------

def test_footprint_is_the_mover_square_turned_about_its_centre() -> None:
    assert footprint(0.0, 0.0).equals(shapely.box(-77.5, -77.5, 77.5, 77.5))
    turned = footprint(10.0, 20.0, 45.0)
    assert turned.area == pytest.approx(155.0**2)
    assert turned.bounds[2] == pytest.approx(10.0 + 155.0 / math.sqrt(2.0))
    assert footprint(0.0, 0.0, 90.0, width=100.0, height=50.0).equals(
        shapely.box(-25.0, -50.0, 25.0, 50.0))
    assert footprint(0.0, 0.0, margin=5.0).equals(shapely.box(-82.5, -82.5, 82.5, 82.5))


@pytest.mark.parametrize("end", [(1000.0, 0.0), (300.0, -450.0)])
@pytest.mark.parametrize("release_step", [None, 100.0])
def test_straight_move_is_exactly_the_hull(end: tuple[float, float],
                                           release_step: float | None) -> None:
    area = swept_area(line((0.0, 0.0, 10.0), (*end, 10.0)), release_step=release_step)
    hull = shapely.convex_hull(shapely.union(footprint(0.0, 0.0, 10.0), footprint(*end, 10.0)))
    assert area.geometry.symmetric_difference(hull).area < 1e-6


def test_release_step_cuts_a_long_move_into_pieces_in_path_order() -> None:
    area = swept_area(line((0.0, 0.0), (1000.0, 0.0), samples=1001), release_step=100.0)
    assert len(area.pieces) == 10
    assert list(area.until) == list(range(100, 1001, 100))
    assert swept_area(line((0.0, 0.0), (1000.0, 0.0)), release_step=None).pieces.size == 1


def test_standing_path_is_the_footprint() -> None:
    area = swept_area(np.array([[5.0, 6.0, 30.0]]))
    assert area.geometry.equals(footprint(5.0, 6.0, 30.0))


@st.composite
def paths(draw: st.DrawFn) -> np.ndarray:
    """Up to 12 samples, steps up to 60 mm and 40 degrees, sometimes no move or no turn."""
    k = draw(st.integers(1, 12))
    start = [draw(st.floats(-300, 300)), draw(st.floats(-300, 300)), draw(st.floats(-180, 180))]
    step = st.one_of(st.just(0.0), st.floats(-60.0, 60.0))
    turn = st.one_of(st.just(0.0), st.floats(-40.0, 40.0))
    steps = [[draw(step), draw(step), draw(turn)] for _ in range(k - 1)]
    return np.cumsum(np.array([start, *steps]), axis=0)


@given(path=paths(), width=st.floats(40.0, 200.0), height=st.floats(40.0, 200.0),
       margin=st.sampled_from([0.0, 5.0]))
def test_swept_area_contains_every_intermediate_footprint(
        path: np.ndarray, width: float, height: float, margin: float) -> None:
    area = swept_area(path, width=width, height=height, margin=margin, release_step=50.0)
    assert covers_all(area.geometry, dense_footprints(path, width=width, height=height,
                                                      margin=margin))


@given(path=paths(), progress=st.floats(0.0, 1.0))
def test_after_release_the_reservation_holds_every_future_footprint(
        path: np.ndarray, progress: float) -> None:
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE, footprint(*path[0]))
    assert registry.request(MOVER_ONE, swept_area(path, release_step=30.0)) is None
    sample = int(progress * (len(path) - 1))
    registry.release(MOVER_ONE, sample)
    assert covers_all(registry.reserved(MOVER_ONE), dense_footprints(path[sample:]))


@pytest.mark.parametrize(("name", "path"), [
    ("arc", np.column_stack([300 * np.cos(np.linspace(0, np.pi / 2, 1001)),
                             300 * np.sin(np.linspace(0, np.pi / 2, 1001)), np.zeros(1001)])),
    ("spin in place", line((0.0, 0.0, 0.0), (0.0, 0.0, 360.0), samples=1001)),
    ("turning a little", line((0.0, 0.0, -15.0), (1000.0, 300.0, 15.0), samples=1001)),
])
def test_swept_area_is_close_to_the_exact_one(name: str, path: np.ndarray) -> None:
    """Each 100 mm piece is a hull: on the arc (R 300) it bridges the sagitta
    100² / (8 * 300) = 4.2 mm; a turn between samples widens it by r times the turn; a
    straight move that turns holds both end angles of a run (3 degrees per 100 mm here:
    r * 3 degrees = 5.7 mm)."""
    area = swept_area(path)
    exact = shapely.union_all(dense_footprints(path, per_step=1))
    assert area.geometry.covers(exact.buffer(-1e-6)), name
    bound = {"arc": 4.5, "spin in place": 1.5, "turning a little": 6.0}[name]
    assert shapely.hausdorff_distance(area.geometry, exact) < bound


def test_coarse_big_turn_is_covered_by_a_disc() -> None:
    area = swept_area(np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 90.0]]))
    radius = math.hypot(77.5, 77.5)
    assert area.geometry.covers(shapely.Point(0.0, 0.0).buffer(radius - 1e-6))
    assert area.geometry.area < 1.01 * shapely.LineString([(0, 0), (10, 0)]).buffer(radius).area


@st.composite
def straight_paths(draw: st.DrawFn) -> np.ndarray:
    """A straight move from rest, smoothstep-timed, sometimes turning up to 20 degrees, often
    along an axis (touching edges), sampled 2 to 120 times."""
    start = np.array([draw(st.floats(-500, 500)), draw(st.floats(-500, 500)),
                      draw(st.sampled_from([0.0, 90.0, -12.5, 33.0]))])
    step = st.one_of(st.just(0.0), st.just(240.0), st.floats(-600.0, 600.0))
    end = start + [draw(step), draw(step), draw(st.one_of(st.just(0.0), st.floats(-20, 20)))]
    s = np.linspace(0.0, 1.0, draw(st.integers(2, 120)))
    return start + (s * s * (3.0 - 2.0 * s))[:, None] * (end - start)


@given(path=straight_paths(), release_step=st.sampled_from([None, 100.0, 37.0]))
def test_straight_swept_area_from_run_ends_is_swept_area_of_the_samples(
        path: np.ndarray, release_step: float | None) -> None:
    """Equivalence: the cover of a straight move built from the ends of its runs (what a
    mover does for a straight MoveToPosition) has swept_area's pieces, bounds and samples."""
    sampled = swept_area(path, release_step=release_step)
    travel = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(path[:, :2], axis=0).T))])
    _, ends = travel_runs(travel, release_step)
    from_ends = straight_swept_area(path[[0, *ends]].tolist(), ends)
    assert from_ends is not None
    assert np.array_equal(from_ends.until, sampled.until)
    assert np.array_equal(from_ends.bounds, sampled.bounds)
    assert all(a.equals_exact(b, 0.0) for a, b in zip(from_ends.pieces, sampled.pieces,
                                                       strict=True))


def test_straight_swept_area_refuses_a_big_turn_per_run() -> None:
    """Beyond 20 degrees within a run the cover of the samples is tighter: None."""
    assert straight_swept_area([[0.0, 0.0, 0.0], [50.0, 0.0, 25.0]], [1]) is None


@given(path=straight_paths())
def test_pieces_are_built_when_needed_and_bounds_are_theirs(path: np.ndarray) -> None:
    area = swept_area(path)
    assert all(polygon is None for polygon in area.polygons)  # nothing built yet
    assert area.piece(0) is area.piece(0)
    assert np.array_equal(area.bounds, shapely.bounds(area.pieces))


@given(x=st.floats(-1000, 1000), y=st.floats(-1000, 1000),
       c=st.one_of(st.sampled_from([0.0, 90.0, -180.0, 45.0]), st.floats(-400, 400)),
       width=st.floats(40.0, 200.0), margin=st.sampled_from([0.0, 5.0]))
def test_footprint_area_is_the_footprint(x: float, y: float, c: float, width: float,
                                         margin: float) -> None:
    area = footprint_area(x, y, c, width, 155.0, margin)
    polygon = footprint(x, y, c, width, 155.0, margin)
    assert area.piece(0).equals_exact(polygon, 0.0)
    assert area.bounds[0].tolist() == list(polygon.bounds) and area.until[0] > 10**12


@pytest.mark.parametrize("bad", [np.zeros((0, 3)), np.zeros((4, 2)), np.array([[0, 0, np.nan]])])
def test_malformed_path_is_a_value_error(bad: np.ndarray) -> None:
    with pytest.raises(ValueError, match="path"):
        swept_area(bad)


def test_bad_sizes_are_config_errors() -> None:
    with pytest.raises(ConfigError, match="width and height"):
        footprint(0.0, 0.0, width=0.0)
    with pytest.raises(ConfigError, match="margin"):
        swept_area(line((0.0, 0.0), (1.0, 0.0)), margin=-1.0)
    with pytest.raises(ConfigError, match="release_step"):
        swept_area(line((0.0, 0.0), (1.0, 0.0)), release_step=0.0)


# --- the registry ---------------------------------------------------------------------------

def two_movers(first: MemberId = MOVER_ONE, second: MemberId = MOVER_TWO) -> ReservationRegistry:
    """§6.3.2: mover one stands at (0, 0), mover two at (240, 0), both in the group."""
    registry = ReservationRegistry()
    positions = {MOVER_ONE: (0.0, 0.0), MOVER_TWO: (240.0, 0.0)}
    for member in (first, second):
        assert registry.add_member(member, footprint(*positions[member])) is None
    return registry


def test_manual_632_second_mover_to_an_occupied_target_is_rejected() -> None:
    """§6.3.2: same cycle, mover one (0,0)->(0,240) then mover two (240,0)->(0,0)."""
    registry = two_movers()
    assert registry.request(MOVER_ONE, swept_area(line((0.0, 0.0), (0.0, 240.0)))) is None
    assert registry.request(MOVER_TWO, swept_area(line((240.0, 0.0), (0.0, 0.0)))) == MOVER_ONE
    assert registry.reserved(MOVER_TWO).equals(footprint(240.0, 0.0))  # nothing changed


def test_first_caller_wins_in_call_order() -> None:
    """Both want the free point (120, 240): whoever asks first gets it."""
    for first, second in ((MOVER_ONE, MOVER_TWO), (MOVER_TWO, MOVER_ONE)):
        registry = two_movers()
        start = {MOVER_ONE: (0.0, 0.0), MOVER_TWO: (240.0, 0.0)}
        assert registry.request(first, swept_area(line(start[first], (120.0, 240.0)))) is None
        assert registry.request(second, swept_area(line(start[second], (120.0, 240.0)))) == first


def test_own_area_never_blocks() -> None:
    registry = two_movers()
    assert registry.request(MOVER_ONE, swept_area(line((0.0, 0.0), (0.0, 50.0)))) is None
    assert registry.request(MOVER_ONE, swept_area(line((0.0, 0.0), (-50.0, 0.0)))) is None
    assert registry.reserved(MOVER_ONE).equals(
        swept_area(line((0.0, 0.0), (-50.0, 0.0))).geometry)  # replaced, not added


def test_touching_areas_do_not_block() -> None:
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE, footprint(0.0, 0.0))
    assert registry.add_member(MOVER_TWO, footprint(155.0, 0.0)) is None
    assert registry.request(MOVER_TWO, footprint(155.0, 155.0, 90.0)) is None
    assert registry.request(MOVER_TWO, footprint(154.9, 0.0)) == MOVER_ONE


def test_manual_672_leaving_the_surface_is_blocked_by_the_environment() -> None:
    """§6.7.2: one stator [-120, 120]²; a move to (100, 100) would reach 177.5 > 120."""
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE, footprint(0.0, 0.0))
    registry.add_member(ENVIRONMENT, StatorField([(-120.0, -120.0)]).create_boundary().surface)
    blocker = registry.request(MOVER_ONE, swept_area(line((0.0, 0.0), (100.0, 100.0))))
    assert blocker == ENVIRONMENT and blocker.id == 85065744
    assert registry.reserved(MOVER_ONE).equals(footprint(0.0, 0.0))
    assert registry.request(MOVER_ONE, swept_area(line((0.0, 0.0), (42.5, -42.5)))) is None
    assert registry.request(MOVER_ONE, swept_area(line((42.5, -42.5), (42.6, 0.0)))) \
        == ENVIRONMENT


@pytest.mark.parametrize("stators", [
    [(0.0, 0.0), (240.0, 0.0), (0.0, 240.0), (240.0, 240.0)],  # a square: checked by bounds
    [(0.0, 0.0), (240.0, 0.0), (0.0, 240.0)],  # an L: checked by shapely
])
def test_leaving_the_surface_is_decided_as_shapely_decides(stators: list) -> None:
    surface = StatorField(stators).create_boundary().surface
    grown = shapely.buffer(surface, 1e-6, join_style="mitre")
    rng = np.random.default_rng(11)
    registry = ReservationRegistry()
    registry.add_member(ENVIRONMENT, surface)
    registry.add_member(MOVER_ONE, footprint(120.0, 120.0))
    outcomes = set()
    for _ in range(300):
        target = rng.choice([77.5, 120.0, 362.5, 402.5, 480.0 - 77.5]) + rng.normal(0.0, 2.0, 2)
        area = swept_area(line((120.0, 120.0, 0.0), (*target, rng.choice([0.0, 7.0]))))
        expected = None if grown.covers(area.geometry) else ENVIRONMENT
        assert registry.blocker(MOVER_ONE, area) == expected
        outcomes.add(expected)
    assert outcomes == {None, ENVIRONMENT}


def test_environment_without_a_boundary_blocks_nothing() -> None:
    registry = ReservationRegistry()
    registry.add_member(ENVIRONMENT)
    registry.add_member(MOVER_ONE, footprint(0.0, 0.0))
    assert registry.request(MOVER_ONE, swept_area(line((0.0, 0.0), (5000.0, 0.0)))) is None


@pytest.mark.parametrize("environment_first", [True, False])
def test_the_blocker_named_is_the_first_in_member_order(environment_first: bool) -> None:
    surface = StatorField.rectangular(2, 1).create_boundary().surface  # [0, 480] x [0, 240]
    registry = ReservationRegistry()
    if environment_first:
        registry.add_member(ENVIRONMENT, surface)
    registry.add_member(MOVER_TWO, footprint(400.0, 120.0))
    registry.add_member(MOVER_THREE, footprint(240.0, 120.0))
    registry.add_member(MOVER_ONE, footprint(80.0, 120.0))
    if not environment_first:
        registry.add_member(ENVIRONMENT, surface)
    over_all = swept_area(line((80.0, 120.0), (600.0, 120.0)))  # meets both, leaves the surface
    expected = ENVIRONMENT if environment_first else MOVER_TWO
    assert registry.request(MOVER_ONE, over_all) == expected


def test_release_while_moving_lets_a_follower_in_earlier() -> None:
    """A leader drives (0,0)->(1000,0); a follower wants (300,0) once the leader is past."""
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE, footprint(0.0, 0.0))
    registry.add_member(MOVER_TWO, footprint(0.0, -200.0))
    path = line((0.0, 0.0), (1000.0, 0.0), samples=1001)
    assert registry.request(MOVER_ONE, swept_area(path)) is None
    follow = swept_area(line((0.0, -200.0), (300.0, -200.0)))
    to_lane = swept_area(line((300.0, -200.0), (300.0, 0.0)))
    assert registry.request(MOVER_TWO, follow) is None  # beside the lane: free
    assert registry.request(MOVER_TWO, to_lane) == MOVER_ONE
    registry.release(MOVER_ONE, 300)
    assert registry.request(MOVER_TWO, to_lane) == MOVER_ONE  # leader's footprint still there
    registry.release(MOVER_ONE, 500)  # the piece over samples 400..500 stays up to 500
    assert registry.request(MOVER_TWO, to_lane) == MOVER_ONE
    registry.release(MOVER_ONE, 501)  # at most a release step plus a footprint behind
    assert registry.request(MOVER_TWO, to_lane) is None
    assert overlapping_pairs(registry) == 0
    assert covers_all(registry.reserved(MOVER_ONE), dense_footprints(path[501::20]))


def test_release_keeps_the_last_piece_and_settle_shrinks_to_the_footprint() -> None:
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE, footprint(0.0, 0.0))
    path = line((0.0, 0.0), (1000.0, 0.0), samples=1001)
    registry.request(MOVER_ONE, swept_area(path))
    registry.release(MOVER_ONE, 5000)
    assert registry.piece_count == 1
    assert registry.reserved(MOVER_ONE).covers(footprint(1000.0, 0.0))
    registry.settle(MOVER_ONE, footprint(1000.0, 0.0))
    assert registry.reserved(MOVER_ONE).equals(footprint(1000.0, 0.0))


def test_random_requests_agree_with_shapely_and_never_overlap() -> None:
    """Equivalence (style §4.4): the fast check == plain shapely on whole areas, per member."""
    rng = np.random.default_rng(7)
    registry = ReservationRegistry(capacity=4)
    members = [MemberId(PlanarObjectType.MOVER, i) for i in range(12)]
    registry.add_member(ENVIRONMENT, StatorField.rectangular(5, 5).create_boundary().surface)
    poses = {}
    for member in members:
        pose = rng.uniform(0.0, 1200.0, 2)
        if registry.add_member(member, footprint(*pose)) is None:
            poses[member] = pose
    for _ in range(150):
        member = list(poses)[int(rng.integers(len(poses)))]
        target = poses[member] + rng.uniform(-400.0, 400.0, 2)
        path = line((*poses[member], 0.0), (*target, rng.uniform(-90.0, 90.0)), samples=60)
        area = swept_area(path, release_step=80.0)
        expected = reference_blocker(registry, member, area)
        assert registry.request(member, area) == expected
        if expected is None:
            registry.release(member, int(rng.integers(len(path))))
            poses[member] = target
    assert overlapping_pairs(registry) == 0


def test_ignore_lets_a_track_reserve_its_band_over_its_own_movers() -> None:
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE, footprint(0.0, 0.0))
    registry.add_member(TRACK)
    band = swept_area(line((0.0, 0.0), (400.0, 0.0)), release_step=None).geometry
    assert registry.request(TRACK, band) == MOVER_ONE
    assert registry.request(TRACK, band, ignore=[MOVER_ONE]) is None
    assert registry.request(MOVER_ONE, footprint(0.0, 0.0)) == TRACK  # the band now blocks


def test_add_member_checks_and_remove_member_frees() -> None:
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE, footprint(0.0, 0.0))
    assert registry.add_member(MOVER_TWO, footprint(100.0, 0.0)) == MOVER_ONE
    assert MOVER_TWO not in registry
    registry.remove_member(MOVER_ONE)
    assert registry.add_member(MOVER_TWO, footprint(100.0, 0.0)) is None
    assert registry.members == (MOVER_TWO,)
    assert registry.reserved(MOVER_ONE).is_empty


def test_membership_errors_are_config_errors() -> None:
    registry = ReservationRegistry()
    registry.add_member(MOVER_ONE)
    registry.add_member(ENVIRONMENT)
    with pytest.raises(ConfigError, match="mover 0x5110010: is a member"):
        registry.add_member(MOVER_ONE)
    with pytest.raises(ConfigError, match="holds environment 0x5120010 already"):
        registry.add_member(MemberId(PlanarObjectType.ENVIRONMENT, 1))
    with pytest.raises(ConfigError, match="holds its surface"):
        registry.request(ENVIRONMENT, footprint(0.0, 0.0))
    with pytest.raises(KeyError):
        registry.request(MOVER_TWO, footprint(0.0, 0.0))


def test_swept_area_from_a_plain_geometry_is_one_piece_never_released() -> None:
    area = SweptArea.from_geometry(shapely.box(0.0, 0.0, 1.0, 1.0))
    assert len(area.pieces) == 1 and area.until[0] > 10**12


def test_admission_benchmark_runs_and_agrees_with_the_reference() -> None:
    result = measure_admission(movers=6, commands=40, seed=3)
    assert result["accepted"] + result["rejected"] == 40
    assert result["checked"] == 40 and result["mismatches"] == 0 and result["overlaps"] == 0
    assert result["admission_us_p50"] > 0.0 and result["admission_us_p99"] >= \
        result["admission_us_p50"]
    assert result == {**measure_admission(movers=6, commands=40, seed=3),
                      **{k: v for k, v in result.items() if k.endswith(("_p50", "_p99"))}}
