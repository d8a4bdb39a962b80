"""Kinematic transformations ACS <-> MCS (PLCopen Part 4 §2.1.1, §5.8.1)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from openmotion.coordinated.kinematics import (
    CartesianGantry,
    Configuration,
    DeltaRobot,
    Kinematics,
    Scara,
)
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId

TOL = 1e-9  #: [mm] and [rad]; angles are compared in degrees, so the check is stricter
UNREACHABLE = ErrorId.TARGET_UNREACHABLE

SCARA = Scara(300.0, 250.0, z_axis=True, c_axis=True)
DELTA = DeltaRobot(base_radius=200.0, effector_radius=50.0, upper_arm=300.0, forearm=800.0)
GANTRY = CartesianGantry(("y", "x", "z", "c"), sign=(1, -1, 1, -1), offset=(0, 100, -5, 90))


def finite(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False)


def elbow_angles(configuration: Configuration) -> st.SearchStrategy[float]:
    """Elbow angles of one configuration, 1° clear of the stretched and folded singularities."""
    angles = finite(1.0, 179.0)
    return angles if configuration is Configuration.ELBOW_DOWN else angles.map(lambda a: -a)


def scara_acs(configuration: Configuration) -> st.SearchStrategy[np.ndarray]:
    return st.tuples(finite(-179.9, 179.9), elbow_angles(configuration), finite(-200.0, 0.0),
                     finite(-400.0, 400.0)).map(np.array)


# --- Cartesian gantry ---------------------------------------------------------------------------

def test_gantry_maps_each_axis_to_its_coordinate_with_sign_and_offset():
    assert GANTRY.coordinates == ("x", "y", "z", "c")
    # axis 1 drives y, axis 2 drives x reversed with +100, axis 3 z -5, axis 4 c reversed +90
    assert GANTRY.forward([10.0, 20.0, 30.0, 40.0]) == pytest.approx([80.0, 10.0, 25.0, 50.0])
    assert GANTRY.inverse([80.0, 10.0, 25.0, 50.0]) == pytest.approx([10.0, 20.0, 30.0, 40.0])


def test_neutral_gantry_is_the_identity():
    """§5.8.1: with the neutral transformation, MCS positions are the ACS positions."""
    neutral = CartesianGantry()
    q = np.array([[1.5, -2.0, 3.25], [0.0, 0.0, 0.0]])
    assert np.array_equal(neutral.forward(q), q)
    assert np.array_equal(neutral.inverse(q), q)
    assert np.array_equal(neutral.jacobian(q[0]), np.eye(3))


@given(q=st.tuples(*[finite(-1e4, 1e4)] * 4).map(np.array))
def test_gantry_round_trips(q):
    assert GANTRY.inverse(GANTRY.forward(q)) == pytest.approx(q, abs=TOL)
    assert GANTRY.forward(GANTRY.inverse(q)) == pytest.approx(q, abs=TOL)


@pytest.mark.parametrize("kwargs", [
    {"mapping": ("x", "x")}, {"mapping": ("x", "w")}, {"mapping": ()},
    {"mapping": ("x", "y"), "sign": (1, 2)}, {"mapping": ("x", "y"), "offset": (0, math.nan)},
])
def test_gantry_configuration_errors(kwargs):
    with pytest.raises(ConfigError):
        CartesianGantry(**kwargs)


# --- SCARA --------------------------------------------------------------------------------------

@pytest.mark.parametrize("configuration", list(Configuration))
@given(data=st.data())
def test_scara_inverse_of_forward_is_identity(configuration, data):
    q = data.draw(scara_acs(configuration))
    assert SCARA.configuration(q) is configuration
    assert SCARA.inverse(SCARA.forward(q), configuration) == pytest.approx(q, abs=TOL)


@pytest.mark.parametrize("configuration", list(Configuration))
@given(radius=finite(50.0, 550.0), angle=finite(-180.0, 180.0), z=finite(-200.0, 0.0),
       c=finite(-400.0, 400.0))
def test_scara_forward_of_inverse_is_identity_over_the_workspace(configuration, radius, angle, z,
                                                                 c):
    """The whole ring |l1 - l2| <= r <= l1 + l2, its borders included."""
    x = np.array([radius * math.cos(math.radians(angle)), radius * math.sin(math.radians(angle)),
                  z, c])
    assert SCARA.forward(SCARA.inverse(x, configuration)) == pytest.approx(x, abs=TOL)


def test_scara_reaches_an_interior_point_in_two_configurations():
    """§2.1.1 Fig. 4: elbow down and elbow up give different axes and the same TCP."""
    x = np.array([400.0, 150.0, -50.0, 30.0])
    down = SCARA.inverse(x, Configuration.ELBOW_DOWN)
    up = SCARA.inverse(x, Configuration.ELBOW_UP)
    assert down[1] > 0.0 > up[1]
    assert down[1] == pytest.approx(-up[1])
    assert SCARA.forward(down) == pytest.approx(SCARA.forward(up), abs=TOL)
    assert np.array_equal(SCARA.inverse(x), down)  # ELBOW_DOWN unless told otherwise


def test_scara_concrete_pose():
    arm = Scara(300.0, 250.0)
    assert arm.forward([0.0, 90.0]) == pytest.approx([300.0, 250.0], abs=1e-12)
    assert arm.inverse([300.0, 250.0]) == pytest.approx([0.0, 90.0], abs=TOL)
    assert arm.inverse([300.0, 250.0], Configuration.ELBOW_UP) == pytest.approx(
        [2 * math.degrees(math.atan2(250.0, 300.0)), -90.0], abs=TOL)


@pytest.mark.parametrize("configuration", list(Configuration))
def test_scara_at_full_stretch_both_configurations_meet(configuration):
    arm = Scara(300.0, 250.0)
    stretched = arm.forward([30.0, 0.0])  # r rounds to 550 +- 1e-13: still inside
    # the elbow angle goes with the square root of the distance to the border here, so a
    # rounding of 1e-13 mm is worth up to 1e-6° (the price of the singularity, not a bug)
    assert arm.inverse(stretched, configuration) == pytest.approx([30.0, 0.0], abs=1e-6)
    assert arm.inverse([550.0, 0.0], configuration) == pytest.approx([0.0, 0.0], abs=TOL)


@pytest.mark.parametrize("elbow", [0.0, 180.0])
def test_scara_inverse_velocity_is_rejected_where_singular(elbow):
    arm = Scara(300.0, 300.0)
    with pytest.raises(CommandRejected, match="singular") as caught:
        arm.inverse_velocity([20.0, elbow], [10.0, 0.0])
    assert caught.value.error_id is ErrorId.KINEMATICS_SINGULAR
    assert np.all(np.isfinite(arm.forward_velocity([20.0, elbow], [10.0, 5.0])))


@pytest.mark.parametrize(("target", "message"), [
    ([551.0, 0.0, 0.0, 0.0], r"\(551, 0\) is out of reach: 551 mm from the base, "
                             r"the arm reaches 50 to 550 mm"),
    ([0.0, 49.0, 0.0, 0.0], r"49 mm from the base, the arm reaches 50 to 550 mm"),
])
def test_scara_rejects_targets_out_of_reach(target, message):
    with pytest.raises(CommandRejected, match=message) as caught:
        SCARA.inverse(target)
    assert caught.value.error_id is UNREACHABLE


def test_scara_rejection_names_the_point_of_a_batch():
    targets = np.array([[300.0, 0.0, 0.0, 0.0], [0.0, 600.0, 0.0, 0.0]])
    with pytest.raises(CommandRejected, match=r"\(point 1 of 2\)"):
        SCARA.inverse(targets)


def test_scara_limits_shift_by_a_turn_or_reject():
    arm = Scara(300.0, 250.0, limits=[(0.0, 360.0), (-150.0, 150.0)])
    assert arm.inverse([0.0, -550.0]) == pytest.approx([270.0, 0.0], abs=TOL)
    with pytest.raises(CommandRejected, match=r"needs axis 2 at 160.*limits \[-150, 150\]") as c:
        arm.inverse(arm.forward([10.0, 160.0]))
    assert c.value.error_id is UNREACHABLE


def test_scara_configuration_errors():
    with pytest.raises(ConfigError, match="l2"):
        Scara(300.0, 0.0)
    with pytest.raises(ConfigError, match="limits"):
        Scara(300.0, 250.0, limits=[(10.0, -10.0), None])


# --- delta robot --------------------------------------------------------------------------------

def knees_out(q: np.ndarray) -> bool:
    """Every elbow lies clearly outside the line from its shoulder to its wrist."""
    u = np.array([[math.cos(a), math.sin(a), 0.0] for a in np.radians([0.0, 120.0, 240.0])])
    wrist = DELTA.forward(q) + (DELTA.effector_radius - DELTA.base_radius) * u
    t = np.radians(q)
    side = -(wrist @ u.T).diagonal() * np.sin(t) - wrist[:, 2] * np.cos(t)
    return bool(np.all(side > 1.0))


delta_acs = st.tuples(*[finite(-40.0, 80.0)] * 3).map(np.array)


def test_delta_concrete_pose():
    """All arms horizontal: the platform hangs straight below the centre."""
    depth = math.sqrt(800.0**2 - 450.0**2)
    assert DELTA.forward([0.0, 0.0, 0.0]) == pytest.approx([0.0, 0.0, -depth], abs=1e-9)
    assert DELTA.inverse([0.0, 0.0, -depth]) == pytest.approx([0.0, 0.0, 0.0], abs=TOL)


@given(q=delta_acs)
def test_delta_inverse_of_forward_is_identity(q):
    assume(knees_out(q))
    assert DELTA.inverse(DELTA.forward(q)) == pytest.approx(q, abs=TOL)


@given(radius=finite(0.0, 300.0), angle=finite(-180.0, 180.0), z=finite(-1000.0, -650.0))
def test_delta_forward_of_inverse_is_identity_over_the_workspace(radius, angle, z):
    x = np.array([radius * math.cos(math.radians(angle)), radius * math.sin(math.radians(angle)),
                  z])
    assert DELTA.forward(DELTA.inverse(x)) == pytest.approx(x, abs=TOL)


def test_delta_rejects_targets_out_of_reach():
    with pytest.raises(CommandRejected, match=r"\(0, 0, -2000\) is out of reach of arm 1") as c:
        DELTA.inverse([0.0, 0.0, -2000.0])
    assert c.value.error_id is UNREACHABLE
    with pytest.raises(CommandRejected, match="out of reach of arm 2"):
        DELTA.inverse([1000.0, 0.0, -300.0])


def test_delta_rejects_axis_positions_it_cannot_assemble():
    short = DeltaRobot(200.0, 50.0, 300.0, 100.0)
    with pytest.raises(CommandRejected, match="cannot be assembled") as caught:
        short.forward([0.0, 0.0, 0.0])
    assert caught.value.error_id is UNREACHABLE


def test_delta_limits():
    limited = DeltaRobot(200.0, 50.0, 300.0, 800.0, limits=[(-30.0, 60.0)] * 3)
    with pytest.raises(CommandRejected, match="needs axis 1 at 70"):
        limited.inverse(DELTA.forward([70.0, 20.0, 20.0]))


def test_delta_has_no_configuration_to_choose():
    assert DELTA.configuration([10.0, 20.0, 30.0]) is None
    with pytest.raises(CommandRejected, match="no configuration") as caught:
        DELTA.inverse([0.0, 0.0, -800.0], Configuration.ELBOW_UP)
    assert caught.value.error_id is ErrorId.INVALID_CONFIGURATION


# --- all models: Jacobian, velocities, vectorisation, bad input ---------------------------------

MODELS = [GANTRY, Scara(300.0, 250.0), SCARA, DELTA]
SAMPLE_ACS = {
    id(GANTRY): [[10.0, -20.0, 30.0, 45.0], [0.0, 0.0, 0.0, 0.0]],
    id(MODELS[1]): [[30.0, 45.0], [-120.0, -100.0], [170.0, 10.0]],
    id(SCARA): [[30.0, 45.0, -10.0, 5.0], [-120.0, -100.0, -150.0, 200.0]],
    id(DELTA): [[20.0, 30.0, 40.0], [-20.0, 60.0, 0.0], [0.0, 0.0, 0.0]],
}


def numeric_jacobian(model: Kinematics, q: np.ndarray, h: float = 1e-5) -> np.ndarray:
    columns = []
    for k in range(model.n_axes):
        step = np.zeros(model.n_axes)
        step[k] = h
        columns.append((model.forward(q + step) - model.forward(q - step)) / (2 * h))
    return np.stack(columns, axis=1)


@pytest.mark.parametrize("model", MODELS, ids=lambda m: type(m).__name__)
def test_jacobian_matches_finite_differences(model):
    q = np.array(SAMPLE_ACS[id(model)])
    analytic = model.jacobian(q)
    assert analytic.shape == (len(q), len(model.coordinates), model.n_axes)
    for qi, ji in zip(q, analytic, strict=True):
        np.testing.assert_allclose(ji, numeric_jacobian(model, qi), rtol=1e-6, atol=1e-6)


@given(q=delta_acs, qd=st.tuples(*[finite(-500.0, 500.0)] * 3).map(np.array))
def test_delta_velocity_maps_undo_each_other(q, qd):
    v = DELTA.forward_velocity(q, qd)
    assert DELTA.inverse_velocity(q, v) == pytest.approx(qd, abs=1e-6)


@pytest.mark.parametrize("configuration", list(Configuration))
@given(data=st.data())
def test_scara_velocity_maps_undo_each_other(configuration, data):
    q = data.draw(scara_acs(configuration))
    qd = data.draw(st.tuples(*[finite(-500.0, 500.0)] * 4).map(np.array))
    assert SCARA.inverse_velocity(q, SCARA.forward_velocity(q, qd)) == pytest.approx(qd, abs=1e-6)


@pytest.mark.parametrize("model", MODELS, ids=lambda m: type(m).__name__)
def test_maps_are_vectorised(model):
    q = np.array(SAMPLE_ACS[id(model)])
    x = model.forward(q)
    np.testing.assert_allclose(x, [model.forward(qi) for qi in q], rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(model.inverse(x), [model.inverse(xi) for xi in x],
                               rtol=0.0, atol=1e-12)
    velocity = np.ones(model.n_axes)  # one velocity for every point
    expected = [model.forward_velocity(qi, velocity) for qi in q]
    np.testing.assert_allclose(model.forward_velocity(q, velocity), expected, rtol=0.0,
                               atol=1e-12)
    speeds = model.forward_velocity(q, velocity)
    np.testing.assert_allclose(model.inverse_velocity(q, speeds), np.ones_like(q), atol=1e-9)


@pytest.mark.parametrize("bad", [[1.0, 2.0], [1.0, math.nan, 0.0], [[[1.0, 2.0, 3.0]]]], ids=str)
def test_bad_positions_are_rejected_as_invalid_position(bad):
    with pytest.raises(CommandRejected) as caught:
        DELTA.inverse(bad)
    assert caught.value.error_id is ErrorId.INVALID_POSITION


def test_bad_velocities_are_rejected_as_invalid_velocity():
    with pytest.raises(CommandRejected, match="MCS velocity values must be finite") as caught:
        DELTA.inverse_velocity([10.0, 20.0, 30.0], [0.0, math.inf, 0.0])
    assert caught.value.error_id is ErrorId.INVALID_VELOCITY
