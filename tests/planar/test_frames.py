"""Planar frames (TF5430 §5.1): rigid transforms between a part frame and its coordinate system."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st
from shapely.affinity import affine_transform
from shapely.geometry import box

from openmotion.planar.frames import Pose, cos_sin

coordinates = st.floats(-1e4, 1e4, allow_nan=False)
angles = st.one_of(st.sampled_from([0.0, 90.0, -90.0, 180.0, 270.0, 360.0, 450.0]),
                   st.floats(-720.0, 720.0, allow_nan=False))
poses = st.builds(Pose, coordinates, coordinates, angles)


@pytest.mark.parametrize(("c", "expected"), [
    (0.0, (1.0, 0.0)), (90.0, (0.0, 1.0)), (180.0, (-1.0, 0.0)), (270.0, (0.0, -1.0)),
    (-90.0, (0.0, -1.0)), (450.0, (0.0, 1.0)), (-360.0, (1.0, 0.0)),
])
def test_quarter_turns_are_exact(c, expected):
    assert cos_sin(c) == expected


def test_other_angles_use_the_math_library():
    assert cos_sin(30.0) == pytest.approx((3**0.5 / 2, 0.5), abs=1e-15)


def test_compose_translates_then_rotates_the_inner_pose():
    assert Pose(240.0, 0.0, 0.0).compose(Pose(100.0, 100.0, 5.0)) == (340.0, 100.0, 5.0)
    assert Pose(480.0, 0.0, 90.0).compose(Pose(100.0, 20.0, 0.0)) == (460.0, 100.0, 90.0)
    assert Pose(0.0, 0.0, 180.0).compose(Pose(240.0, 240.0, 10.0)) == (-240.0, -240.0, 190.0)


@pytest.mark.parametrize("c", [0.0, 90.0, 180.0, 270.0, -90.0, 630.0])
def test_round_trips_at_quarter_turns_are_exact(c):
    part = Pose(720.0, -240.0, c)
    local = Pose(123.25, 480.0, 3.0)
    assert part.inverse().compose(part.compose(local)) == local
    assert part.compose(part.inverse()) == (0.0, 0.0, 0.0)


def test_affine_places_a_stator_on_the_grid_exactly():
    stator = affine_transform(box(0.0, 0.0, 240.0, 240.0), Pose(480.0, 240.0, 90.0).affine())
    assert sorted(stator.exterior.coords)[:4] == [
        (240.0, 240.0), (240.0, 480.0), (480.0, 240.0), (480.0, 480.0)]


@given(frame=poses, pose=poses)
def test_inverse_undoes_compose(frame, pose):
    back = frame.inverse().compose(frame.compose(pose))
    assert back == pytest.approx(pose, abs=1e-9)


@given(outer=poses, middle=poses, inner=poses)
def test_compose_is_associative(outer, middle, inner):
    left = outer.compose(middle).compose(inner)
    right = outer.compose(middle.compose(inner))
    assert left == pytest.approx(right, abs=1e-8)


@given(frame=poses)
def test_inverse_of_inverse_is_the_frame(frame):
    assert frame.inverse().inverse() == pytest.approx(frame, abs=1e-9)
