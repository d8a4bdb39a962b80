"""MCS <-> PCS frames (PLCopen Part 4 §2.1, §2.2, §5.8.2, §5.8.5)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from openmotion.coordinated.frames import (
    CartesianTransform,
    Frame,
    FrameMotion,
    LinearFrame,
)
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId

lengths = st.floats(-1e3, 1e3, allow_nan=False)
angles = st.floats(-720.0, 720.0, allow_nan=False)
frames = st.builds(Frame.from_cartesian, lengths, lengths, lengths, angles, angles, angles)
points = st.tuples(lengths, lengths, lengths).map(np.array)

COS30 = math.sqrt(3.0) / 2.0

# §5.8.2: MC_SetCartesianTransform with {50, 50, 0, 0, 0, 30}: the PCS origin at MCS (50, 50, 0),
# its axes turned 30° about Z. Points given in PCS and their MCS coordinates (derived by hand).
SPEC_EXAMPLE = [
    ((0.0, 0.0, 0.0), (50.0, 50.0, 0.0)),
    ((10.0, 0.0, 0.0), (50.0 + 10.0 * COS30, 55.0, 0.0)),  # (58.660254, 55, 0)
    ((0.0, 10.0, 0.0), (45.0, 50.0 + 10.0 * COS30, 0.0)),  # (45, 58.660254, 0)
    ((20.0, 10.0, 5.0), (50.0 + 20.0 * COS30 - 5.0, 60.0 + 10.0 * COS30, 5.0)),  # (62.32, 68.66, 5)
]


@pytest.mark.parametrize(("pcs", "mcs"), SPEC_EXAMPLE, ids=str)
def test_spec_example_maps_pcs_points_into_mcs(pcs, mcs):
    frame = Frame.from_cartesian(50, 50, 0, 0, 0, 30)
    assert frame.apply(pcs) == pytest.approx(mcs, abs=1e-12)
    assert frame.inverse().apply(mcs) == pytest.approx(pcs, abs=1e-12)


def test_spec_example_concrete_numbers():
    frame = Frame.from_cartesian(*CartesianTransform(50, 50, 0, 0, 0, 30))
    assert frame.apply([10.0, 0.0, 0.0]) == pytest.approx([58.660254038, 55.0, 0.0], abs=1e-9)
    assert frame.apply([20.0, 10.0, 5.0]) == pytest.approx([62.320508076, 68.660254038, 5.0],
                                                          abs=1e-9)


def test_all_zeros_deselect_the_pcs():
    """§5.8.2: {0, 0, 0, 0, 0, 0} makes PCS coordinates equal MCS coordinates."""
    frame = Frame.from_cartesian()
    assert frame == Frame()
    assert np.array_equal(frame.matrix(), np.eye(4))


@pytest.mark.parametrize(("values", "axes"), [
    ((0, 0, 0, 90, 0, 0), [[1, 0, 0], [0, 0, 1], [0, -1, 0]]),  # about X: y -> z
    ((0, 0, 0, 0, 90, 0), [[0, 0, -1], [0, 1, 0], [1, 0, 0]]),  # about Y: z -> x
    ((0, 0, 0, 0, 0, 90), [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]),  # about Z: x -> y
    # Z first, then about the new X: x' = y, then y'' = z and z'' = x
    ((0, 0, 0, 90, 0, 90), [[0, 1, 0], [0, 0, 1], [1, 0, 0]]),
], ids=str)
def test_rotation_convention_is_z_then_new_y_then_new_x(values, axes):
    """Rows are the PCS x, y and z axes seen from the MCS (quarter turns are exact)."""
    frame = Frame.from_cartesian(*values)
    assert np.array_equal(frame.rotation.T, np.array(axes, dtype=float))


@given(values=st.tuples(lengths, lengths, lengths, st.floats(-179.0, 179.0),
                        st.floats(-89.0, 89.0), st.floats(-179.0, 179.0)))
def test_cartesian_reads_back_the_values_set(values):
    assert Frame.from_cartesian(*values).cartesian() == pytest.approx(values, abs=1e-9)


@given(frame=frames)
def test_cartesian_values_rebuild_the_frame(frame):
    again = Frame.from_cartesian(*frame.cartesian())
    assert again.matrix() == pytest.approx(frame.matrix(), abs=1e-9)


@pytest.mark.parametrize("angle2", [90.0, -90.0])
def test_cartesian_at_gimbal_lock_keeps_the_rotation(angle2):
    frame = Frame.from_cartesian(1, 2, 3, 25.0, angle2, 40.0)
    values = frame.cartesian()
    assert values.rot_angle1 == 0.0
    assert values.rot_angle2 == pytest.approx(angle2)
    assert Frame.from_cartesian(*values).matrix() == pytest.approx(frame.matrix(), abs=1e-12)


@given(frame=frames, point=points)
def test_inverse_undoes_apply(frame, point):
    assert frame.inverse().apply(frame.apply(point)) == pytest.approx(point, abs=1e-9)


@given(outer=frames, inner=frames, point=points)
def test_compose_chains_two_active_transforms(outer, inner, point):
    """§5.8.2/§5.8.5: the combination maps like the two applied one after the other."""
    chained = outer.compose(inner)
    assert chained.apply(point) == pytest.approx(outer.apply(inner.apply(point)), abs=1e-9)
    assert chained.matrix() == pytest.approx(outer.matrix() @ inner.matrix(), abs=1e-9)


@given(a=frames, b=frames, c=frames)
def test_compose_is_associative(a, b, c):
    left = a.compose(b).compose(c).matrix()
    assert left == pytest.approx(a.compose(b.compose(c)).matrix(), abs=1e-9)


def test_apply_is_vectorised_over_points():
    frame = Frame.from_cartesian(10, -20, 30, 15, -25, 35)
    many = np.random.default_rng(7).uniform(-500, 500, (50, 3))
    expected = np.array([frame.apply(p) for p in many])
    np.testing.assert_allclose(frame.apply(many), expected, rtol=0.0, atol=1e-12)
    assert frame.apply(many).shape == (50, 3)


def test_velocities_and_accelerations_only_rotate():
    frame = Frame.from_cartesian(50, 50, 0, 0, 0, 30)
    assert frame.rotate([10.0, 0.0, 0.0]) == pytest.approx([10 * COS30, 5.0, 0.0], abs=1e-12)
    many = np.array([[1.0, 2.0, 3.0], [0.0, 0.0, 0.0]])
    assert np.array_equal(frame.rotate(many)[1], [0.0, 0.0, 0.0])


def test_non_finite_fb_inputs_are_rejected_with_the_field_named():
    with pytest.raises(CommandRejected, match="rot_angle2 must be finite") as caught:
        Frame.from_cartesian(0, 0, 0, 0, math.nan, 0)
    assert caught.value.error_id is ErrorId.INVALID_PARAMETER_VALUE


@pytest.mark.parametrize(("rotation", "translation"), [
    ([[2, 0, 0], [0, 1, 0], [0, 0, 1]], (0, 0, 0)),  # not orthonormal
    ([[-1, 0, 0], [0, 1, 0], [0, 0, 1]], (0, 0, 0)),  # a mirror
    (None, (0, 0)),
    (None, (0, math.inf, 0)),
])
def test_frame_construction_checks_its_matrix(rotation, translation):
    with pytest.raises(ConfigError):
        Frame(rotation, translation)


def test_frames_are_immutable_values():
    frame = Frame.from_cartesian(1, 2, 3, 4, 5, 6)
    assert frame == Frame.from_cartesian(1, 2, 3, 4, 5, 6)
    assert hash(frame) == hash(Frame.from_cartesian(1, 2, 3, 4, 5, 6))
    with pytest.raises(ValueError, match="read-only"):
        frame.translation[0] = 0.0


def test_linear_frame_slides_with_the_belt():
    """§2.2, §6.6: a product frame on a belt moving along its x axis at 100 mm/s."""
    belt = LinearFrame(Frame.from_cartesian(500, 0, 0, 0, 0, 90), (0.0, 100.0, 0.0),
                       start_time=2.0)
    assert belt(2.0).frame == belt.start
    motion = belt(3.5)
    assert motion.frame.translation == pytest.approx([500.0, 150.0, 0.0])
    assert np.array_equal(motion.frame.rotation, belt.start.rotation)
    # a point that holds its place in the PCS moves in the MCS with the belt
    np.testing.assert_allclose(motion.point_velocity([[10.0, 20.0, 0.0], [-3.0, 4.0, 5.0]]),
                               [[0.0, 100.0, 0.0]] * 2)
    # moving at 10 mm/s along the product's x (the MCS y): 110 mm/s in the MCS
    assert motion.point_velocity([0, 0, 0], [10, 0, 0]) == pytest.approx([0.0, 110.0, 0.0])


def test_linear_frame_rejects_a_bad_velocity():
    with pytest.raises(ConfigError, match="velocity"):
        LinearFrame(Frame(), (0.0, math.nan, 0.0))


def test_point_velocity_matches_finite_differences_on_a_turning_frame():
    """The w x r term, with w in °/s: a table turning at 45 °/s about Z, moving along X."""
    def placement(now: float) -> Frame:
        return Frame.from_cartesian(100.0 + 20.0 * now, 0.0, 10.0, 0.0, 0.0, 45.0 * now)

    def point(now: float) -> np.ndarray:
        return np.array([30.0 + 5.0 * now, -10.0, 2.0])  # moves in the table frame

    now, h = 0.7, 1e-6
    motion = FrameMotion(placement(now), np.array([20.0, 0.0, 0.0]), np.array([0.0, 0.0, 45.0]))
    numeric = (placement(now + h).apply(point(now + h))
               - placement(now - h).apply(point(now - h))) / (2 * h)
    assert motion.point_velocity(point(now), [5.0, 0.0, 0.0]) == pytest.approx(numeric, abs=1e-6)
