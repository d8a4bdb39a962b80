"""Caps on the path parameter keep every axis within its limits (PLCopen Part 4 §5.20-§5.25).

The module's claim is about *any* s(t) within the caps, so the main check takes the worst case
pointwise: at dense arc lengths every combination of s' in [0, V], s'' = -D or A and
s''' = ±J, with the element's exact derivatives (tangent, curvature vector and its rate).
A second check drives the element with a real jerk-limited profile over its length (ruckig,
through ``plan_position``). Elements are drawn in 3-D: lines in any direction, arcs of any
radius, plane and sweep, blend contours between random line pairs; axis limits span decades.
For the SCARA the derivatives come from inverse kinematics and finite differences only.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from openmotion.coordinated.kinematics import CartesianGantry, DeltaRobot, Scara
from openmotion.coordinated.limits import (
    SAMPLED_MARGIN,
    DirectLine,
    cartesian_limits,
    direct_limits,
    limits_from_bounds,
    line_limits,
    path_limits,
    sampled_limits,
)
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.geometry.blend import _peaks, corner_distance_blend
from openmotion.geometry.path import Arc, Line
from openmotion.trajectory.plan import Limits, plan_position
from openmotion.trajectory.segments import KinematicState, Profile

EXACT = 1 + 1e-9  #: the proven cases: limits hold to round-off
#: the profile's own settings win where they ask for more (nightly); 150 is the floor
EXAMPLES = settings(max_examples=max(150, settings.default.max_examples), deadline=None)
NEUTRAL = CartesianGantry()
SWAPPED = CartesianGantry(("y", "c", "x", "z"), sign=(1, -1, -1, 1), offset=(5, 0, 0, -3))
PLANAR = CartesianGantry(("x", "y"))
SCARA = Scara(300.0, 250.0, z_axis=True, c_axis=True)
ANGLES = [0, 1, 3]  #: SCARA axes in degrees: theta1, theta2, theta4

unit = (st.tuples(*[st.floats(-1.0, 1.0)] * 3).map(np.array)
        .filter(lambda v: np.linalg.norm(v) > 0.1).map(lambda v: v / np.linalg.norm(v)))
points = st.tuples(*[st.floats(-300.0, 300.0)] * 3).map(np.array)


def decades(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(math.log10(low), math.log10(high)).map(lambda e: 10.0**e)


@st.composite
def axis_limits(draw, n: int) -> list[Limits]:
    """Per axis: limits over several decades, acceleration and deceleration often equal."""
    result = []
    for _ in range(n):
        acceleration = draw(decades(10.0, 1e5))
        deceleration = draw(st.one_of(st.just(acceleration), decades(10.0, 1e5)))
        result.append(Limits(draw(decades(1.0, 1e4)), acceleration, deceleration,
                             draw(decades(100.0, 1e8))))
    return result


commanded = st.one_of(
    st.just(Limits(math.inf, math.inf, math.inf, math.inf)),
    st.builds(Limits, decades(1.0, 1e4), decades(10.0, 1e5), decades(10.0, 1e5),
              decades(100.0, 1e8)))


def perpendicular(draw, direction):
    other = np.cross(direction, draw(unit))
    assume(np.linalg.norm(other) > 0.1)
    return other / np.linalg.norm(other)


@st.composite
def lines(draw):
    start = draw(points)
    return Line(start, start + draw(st.floats(0.5, 500.0)) * draw(unit))


@st.composite
def arcs(draw):
    center, radius = draw(points), draw(decades(0.5, 500.0))
    u = draw(unit)
    v = perpendicular(draw, u)
    sweep = draw(st.floats(0.02, 2 * math.pi - 0.02))
    start = center + radius * u
    end = center + radius * (math.cos(sweep) * u + math.sin(sweep) * v)
    assume(np.linalg.norm(end - start) > 1e-3)
    return Arc(start, end, center, np.cross(u, v))


@st.composite
def contours(draw):
    corner, t_in = draw(points), draw(unit)
    turn = draw(st.one_of(st.floats(1e-3, 0.1), st.floats(0.1, math.pi - 0.1),
                          st.floats(math.pi - 0.1, math.pi - 1e-3)))
    t_out = math.cos(turn) * t_in + math.sin(turn) * perpendicular(draw, t_in)
    before = Line(corner - draw(st.floats(1.0, 300.0)) * t_in, corner)
    after = Line(corner, corner + draw(st.floats(1.0, 300.0)) * t_out)
    distance = draw(st.floats(0.05, 1.0)) * min(before.length, after.length) / 2
    return corner_distance_blend(before, after, distance).contour


elements = st.one_of(lines(), arcs(), contours())


def derivatives(element, s):
    """Exact t, k, k' at arc lengths s, each (len(s), 3)."""
    return element.tangent(s), element.curvature_vector(s), element.curvature_rate(s)


def gantry_axes(gantry, values):
    """MCS path values (..., 3) as values of the gantry's axes (..., n_axes); a sign flips a
    whole axis and so changes no magnitude below, and orientation axes stand still."""
    out = np.zeros(values.shape[:-1] + (gantry.n_axes,))
    for k, name in enumerate(gantry.mapping):
        if name in "xyz":
            out[..., k] = values[..., "xyz".index(name)]
    return out


def caps_of(limits: Limits) -> list[float]:
    return [limits.velocity, limits.acceleration, limits.deceleration, limits.jerk]


def arrays(limits):
    return np.array([[x.velocity, x.acceleration, x.deceleration, x.jerk] for x in limits]).T


def assert_worst_case_within(q_s, q_ss, q_sss, caps, limits, straight, tolerance=EXACT):
    """Every s' in [0, V], s'' in {-D, A}, s''' = ±J at every sample: axes within limits."""
    v, acc, dec, jerk = arrays(limits)
    sd = np.linspace(0.0, caps.velocity, 17)[:, None, None, None, None]
    sdd = np.array([-caps.deceleration, caps.acceleration])[:, None, None, None]
    sddd = np.array([-caps.jerk, caps.jerk])[:, None, None]
    assert np.all(np.abs(q_s) * caps.velocity <= v * tolerance)
    acceleration = q_s * sdd + q_ss * sd**2  # (17, 2, 1, samples, axes)
    # on a straight element speeding the path up speeds every axis up
    allowed = np.where(sdd > 0, acc, dec) if straight else np.minimum(acc, dec)
    assert np.all(np.abs(acceleration) <= allowed * tolerance)
    third = q_s * sddd + 3 * q_ss * sd * sdd + q_sss * sd**3
    assert np.all(np.abs(third) <= jerk * tolerance)


def sample(profile: Profile, count: int = 3001):
    """s, s', s'', s''' at ``count`` times and at every segment start."""
    times = np.union1d(np.linspace(0.0, profile.duration, count), profile.t)
    k = np.clip(np.searchsorted(profile.t, times, side="right") - 1, 0, None)
    dt = times - profile.t[k]
    p, v, a, j = profile.p[k], profile.v[k], profile.a[k], profile.j[k]
    return (p + dt * (v + dt * (a / 2 + dt * j / 6)), v + dt * (a + dt * j / 2), a + dt * j,
            j)


def drive(element, caps):
    """The time-optimal rest-to-rest profile over the element within the caps."""
    profile = plan_position(KinematicState(0.0), element.length, caps)
    s, sd, sdd, sddd = sample(profile)
    assert np.all(sd >= -1e-9 * caps.velocity) and s.max() <= element.length * (1 + 1e-9)
    return np.clip(s, 0.0, element.length), sd, sdd, sddd


# --- Cartesian gantry: proven caps --------------------------------------------------------------

@EXAMPLES
@given(element=elements, data=st.data(), gantry=st.sampled_from([NEUTRAL, SWAPPED]))
def test_any_path_speed_within_the_caps_keeps_every_gantry_axis_within_its_limits(
        element, data, gantry):
    limits = data.draw(axis_limits(gantry.n_axes))
    caps = cartesian_limits(element, gantry, limits, data.draw(commanded))
    s = np.linspace(0.0, element.length, 2001)
    t, k, rate = (gantry_axes(gantry, x) for x in derivatives(element, s))
    assert_worst_case_within(t, k, rate, caps, limits, straight=isinstance(element, Line))


@EXAMPLES
@given(element=elements, data=st.data())
def test_a_jerk_limited_profile_at_the_caps_keeps_every_axis_within_its_limits(element, data):
    limits = data.draw(axis_limits(3))
    caps = cartesian_limits(element, NEUTRAL, limits, data.draw(commanded))
    s, sd, sdd, sddd = drive(element, caps)
    t, k, rate = derivatives(element, s)
    sd, sdd, sddd = sd[:, None], sdd[:, None], sddd[:, None]
    v, acc, dec, jerk = arrays(limits)
    velocity = t * sd
    acceleration = t * sdd + k * sd**2
    speeding_up = velocity * acceleration > 0
    assert np.all(np.abs(velocity) <= v * EXACT)
    assert np.all(np.abs(acceleration) <= np.where(speeding_up, acc, dec) * EXACT)
    assert np.all(np.abs(t * sddd + 3 * k * sd * sdd + rate * sd**3) <= jerk * EXACT)


@EXAMPLES
@given(element=lines(), data=st.data())
def test_line_caps_are_exact_each_at_its_binding_axis_or_the_command(element, data):
    """On a line the caps are time-optimal: each is the command or puts one axis at its
    limit exactly (the module text: V = min(Velocity, v/|t|), ...)."""
    limits, command = data.draw(axis_limits(3)), data.draw(commanded)
    caps = cartesian_limits(element, NEUTRAL, limits, command)
    t = np.abs(element.direction)
    for cap, wanted, limit in zip(caps_of(caps), caps_of(command), arrays(limits),
                                  strict=True):
        binding = np.max(t * cap / limit)
        assert cap == wanted or binding == pytest.approx(1.0, rel=1e-12)
        assert cap <= wanted and binding <= EXACT


@given(data=st.data(), directions=st.lists(unit, min_size=1, max_size=20))
def test_many_lines_at_once_equal_one_at_a_time(data, directions):
    limits, command = data.draw(axis_limits(4)), data.draw(commanded)
    lengths = data.draw(st.lists(st.floats(0.5, 100.0), min_size=len(directions),
                                 max_size=len(directions)))
    chords = np.array(directions) * np.array(lengths)[:, None]
    caps = line_limits(chords, SWAPPED, limits, command)
    for row, chord in zip(caps, chords, strict=True):
        one = cartesian_limits(Line([0.0, 0.0, 0.0], chord), SWAPPED, limits, command)
        assert row.tolist() == caps_of(one)  # the same arithmetic: bit for bit


def test_arc_caps_by_hand():
    """A half circle of radius 50 in x-y: the y axis (v 500, a 5000) binds the velocity
    through its centripetal term, V = sqrt(a·R/2), and keeps half its acceleration."""
    arc = Arc.from_border([0.0, 0.0, 0.0], [50.0, 50.0, 0.0], [100.0, 0.0, 0.0])
    limits = [Limits(1000, 10000, 8000, 1e6), Limits(500, 5000, 5000, 5e5),
              Limits(200, 2000, 2000, 1e5)]
    caps = cartesian_limits(arc, NEUTRAL, limits, Limits(800, 2e4, 2e4, 2e6))
    assert caps.velocity == pytest.approx(math.sqrt(5000 * 50 / 2), rel=1e-12)
    assert caps.acceleration == caps.deceleration == pytest.approx(2500, rel=1e-12)
    # jerk: j - R·V³ - 3·K·V·A with T = 1, K = 1/R, R = 1/R² on the y axis
    v = caps.velocity
    assert caps.jerk == pytest.approx(5e5 - v**3 / 2500 - 3 * v * 2500 / 50, rel=1e-12)


def test_commanded_dynamics_cap_everything():
    line = Line([0.0, 0.0, 0.0], [10.0, 0.0, 0.0])
    fast = [Limits(1e4, 1e6, 1e6, 1e9)] * 3
    command = Limits(100.0, 1000.0, 500.0, 1e5)
    assert cartesian_limits(line, NEUTRAL, fast, command) == command


def test_orientation_axes_stand_still_and_undriven_coordinates_are_rejected():
    line = Line([0.0, 0.0, 0.0], [0.0, 0.0, 10.0])
    limits = [Limits(100.0, 1000.0, 1000.0, 1e5)] * 4
    caps = cartesian_limits(line, SWAPPED, limits, Limits(1e9, 1e9, 1e9, 1e9))
    assert caps.velocity == 100.0  # only the z axis moves, the c axis does not
    with pytest.raises(CommandRejected) as info:
        cartesian_limits(line, PLANAR, limits[:2], Limits(1e9, 1e9, 1e9, 1e9))
    assert info.value.error_id == ErrorId.TARGET_UNREACHABLE
    assert "moves along z" in info.value.message
    flat = Arc.from_border([0.0, 0.0, 5.0], [1.0, 1.0, 5.0], [2.0, 0.0, 5.0])
    assert cartesian_limits(flat, PLANAR, limits[:2], Limits(1e9, 1e9, 1e9, 1e9)).velocity > 0


def test_axis_limits_must_match_the_axes():
    with pytest.raises(ConfigError, match="need 3 entries"):
        cartesian_limits(Line([0, 0, 0], [1.0, 0, 0]), NEUTRAL, [Limits(1, 1, 1, 1)] * 2,
                         Limits(1, 1, 1, 1))


# --- element derivatives and their bounds (geometry/path.py, geometry/blend.py) ----------------

@given(element=st.one_of(arcs(), contours()))
def test_curvature_rate_is_the_derivative_of_the_curvature_vector(element):
    s = np.linspace(0.0, element.length, 4001)
    h = s[1] - s[0]
    _, k, rate = derivatives(element, s)
    expected = (k[:-4] - 8 * k[1:-3] + 8 * k[3:-1] - k[4:]) / (12 * h)  # error h⁴/30·k⁽⁵⁾
    noise = 1e-12 * np.abs(k).max() / h  # round-off of the curvature vector over 4h
    assert np.abs(rate[2:-2] - expected).max() <= 1e-5 * np.abs(rate).max() + noise


@given(element=elements)
def test_derivative_bounds_hold_and_are_tight(element):
    s = np.linspace(0.0, element.length, 4001)
    dense = np.array([np.abs(x).max(axis=0) for x in derivatives(element, s)])
    bounds = element.derivative_bounds()
    assert np.all(dense <= bounds * EXACT + 1e-300)
    if not isinstance(element, Line | Arc) and element.max_curvature * element.length > 50:
        return  # a sharp peak near a cusp falls between the dense samples
    assert np.all(bounds <= dense * (1 + 1e-3) + 1e-12 * bounds.max(axis=1, keepdims=True))
    assert element.max_curvature_rate == pytest.approx(
        np.linalg.norm(element.curvature_rate(s), axis=1).max(), rel=1e-3, abs=1e-12)


@pytest.mark.parametrize("width", [1e-3, 1e-4, 1e-6])
@pytest.mark.parametrize("centre", [0.3, 0.7071, 0.999])
def test_peak_bounds_zoom_in_on_sharp_peaks(width, centre):
    """The bound machinery of Contour.derivative_bounds where a peak is far narrower than
    its samples: it must zoom in and still bound the peak, just above it."""
    def f(u):
        return np.stack([1 / (1 + ((u - centre) / width) ** 2), np.abs(np.sin(40 * u))], -1)

    bounds = _peaks(f)
    assert np.all(bounds >= 1.0) and np.all(bounds <= 1.0 + 2e-4)


# --- MC_MoveDirect*: lines in ACS ---------------------------------------------------------------

@given(data=st.data(), n=st.integers(1, 6))
def test_direct_caps_are_exact_and_keep_every_axis_within_its_limits(data, n):
    start = np.array(data.draw(st.lists(st.floats(-500, 500), min_size=n, max_size=n)))
    end = np.array(data.draw(st.lists(st.floats(-500, 500), min_size=n, max_size=n)))
    assume(np.linalg.norm(end - start) > 1e-3)
    line, limits = DirectLine(start, end), data.draw(axis_limits(n))
    caps = direct_limits(line, limits)
    u = np.abs(line.direction)
    for cap, limit in zip(caps_of(caps), arrays(limits), strict=True):
        assert np.max(u * cap / limit) == pytest.approx(1.0, rel=1e-12)  # §2.3: one at its limit
    s, sd, sdd, sddd = drive(line, caps)
    q = line.position(s)
    assert np.allclose(q[-1], end) and np.array_equal(line.position(line.length), end)
    assert_worst_case_within(line.tangent(s), np.zeros_like(q), np.zeros_like(q), caps, limits,
                             straight=True)


def test_direct_line_rejects_bad_input():
    with pytest.raises(CommandRejected) as info:
        DirectLine([1.0, 2.0], [1.0, 2.0])
    assert info.value.error_id == ErrorId.INVALID_PATH_GEOMETRY
    with pytest.raises(CommandRejected):
        DirectLine([1.0, 2.0], [1.0, 2.0, 3.0])
    with pytest.raises(CommandRejected):
        DirectLine([1.0, math.nan], [1.0, 2.0])


# --- non-Cartesian kinematics: sampled caps -----------------------------------------------------

def in_ring(element, inner=110.0, outer=520.0) -> bool:
    r = np.hypot(*element.position(np.linspace(0.0, element.length, 2001))[:, :2].T)
    return bool(r.min() >= inner and r.max() <= outer)


@st.composite
def ring_points(draw):
    radius, angle = draw(st.floats(130.0, 500.0)), draw(st.floats(-math.pi, math.pi))
    return np.array([radius * math.cos(angle), radius * math.sin(angle),
                     draw(st.floats(-150.0, 0.0))])


@st.composite
def scara_elements(draw):
    kind = draw(st.sampled_from(["line", "arc", "contour"]))
    a, b, c = draw(ring_points()), draw(ring_points()), draw(ring_points())
    try:
        if kind == "line":
            element = Line(a, b)
        elif kind == "arc":
            element = Arc.from_border(a, b, c)
        else:
            element = corner_distance_blend(Line(a, b), Line(b, c),
                                            draw(st.floats(1.0, 50.0))).contour
    except CommandRejected:
        assume(False)
    assume(element.length > 1.0 and in_ring(element))
    return element


def scara_derivatives(element, s, h=0.05):
    """q_s, q_ss, q_sss of the SCARA axes from inverse kinematics and finite differences
    (a five-point stencil h apart, kept inside the element), unwrapped across ±180°."""
    centre = np.clip(s, 2 * h, element.length - 2 * h)
    stencil = centre + h * np.arange(-2, 3)[:, None]
    xyz = element.position(stencil.ravel())
    mcs = np.column_stack([xyz, np.full(len(xyz), 30.0)])  # c held at 30°
    q = SCARA.inverse(mcs).reshape(5, len(s), 4)
    q[..., ANGLES] = np.unwrap(q[..., ANGLES], period=360.0, axis=0)
    q_s = (q[0] - 8 * q[1] + 8 * q[3] - q[4]) / (12 * h)
    q_ss = (q[1] - 2 * q[2] + q[3]) / h**2
    q_sss = (-q[0] + 2 * q[1] - 2 * q[3] + q[4]) / (2 * h**3)
    return q_s, q_ss, q_sss


@st.composite
def scara_limits(draw):
    limits = draw(axis_limits(4))
    return [Limits(min(x.velocity, 720.0), x.acceleration, x.deceleration, x.jerk)
            for x in limits]


@settings(max_examples=max(100, settings.default.max_examples), deadline=None)
@given(element=scara_elements(), limits=scara_limits(), command=commanded)
def test_scara_axes_stay_within_their_limits_by_the_sampled_caps(element, limits, command):
    caps = sampled_limits(element, SCARA, limits, command, orientation={"c": 30.0})
    assert caps == path_limits(element, SCARA, limits, command, orientation={"c": 30.0})
    s = np.linspace(0.0, element.length, 801)
    q_s, q_ss, q_sss = scara_derivatives(element, s)
    # the caps hold for any s(t); the finite differences here err by far less than 1e-3
    assert_worst_case_within(q_s, q_ss, q_sss, caps, limits, straight=False,
                             tolerance=1 + 1e-3)
    # and a real profile at the caps, joint by joint
    s, sd, sdd, sddd = drive(element, caps)
    q_s, q_ss, q_sss = scara_derivatives(element, s)
    sd, sdd, sddd = sd[:, None], sdd[:, None], sddd[:, None]
    v, acc, dec, jerk = arrays(limits)
    assert np.all(np.abs(q_s * sd) <= v * (1 + 1e-3))
    assert np.all(np.abs(q_s * sdd + q_ss * sd**2) <= np.minimum(acc, dec) * (1 + 1e-3))
    assert np.all(np.abs(q_s * sddd + 3 * q_ss * sd * sdd + q_sss * sd**3) <= jerk * (1 + 1e-3))


@pytest.mark.parametrize("element", [
    Line([-300.0, -100.0, 0.0], [300.0, 200.0, 0.0]),
    Arc.from_border([-300.0, -200.0, 0.0], [0.0, 80.0, 0.0], [300.0, -200.0, 0.0]),
])
def test_sampled_caps_match_the_proven_ones_on_a_gantry(element):
    """The sampling machinery on a map whose bounds are known: a gantry, where it must give
    the proven budget with the derivative peaks times SAMPLED_MARGIN, to the 1 % it settles."""
    limits = [Limits(300.0, 3000.0, 3000.0, 3e4), Limits(200.0, 1000.0, 1000.0, 1e5),
              Limits(50.0, 500.0, 500.0, 5e3)]
    command = Limits(math.inf, math.inf, math.inf, math.inf)
    sampled = sampled_limits(element, NEUTRAL, limits, command)
    proven = limits_from_bounds(SAMPLED_MARGIN * element.derivative_bounds(), limits, command)
    assert caps_of(sampled) == pytest.approx(caps_of(proven), rel=0.01)


def test_delta_robot_profile_within_limits():
    delta = DeltaRobot(base_radius=200.0, effector_radius=50.0, upper_arm=300.0, forearm=800.0)
    element = Arc.from_border([-150.0, 0.0, -800.0], [0.0, 120.0, -760.0], [150.0, 0.0, -800.0])
    limits = [Limits(200.0, 2000.0, 2000.0, 2e4)] * 3
    caps = path_limits(element, delta, limits, Limits(1e4, 1e5, 1e5, 1e7))
    s, sd, sdd, sddd = drive(element, caps)
    h = 0.05
    centre = np.clip(s, 2 * h, element.length - 2 * h)
    q = delta.inverse(element.position((centre + h * np.arange(-2, 3)[:, None]).ravel()))
    q = q.reshape(5, len(s), 3)
    q_s = (q[0] - 8 * q[1] + 8 * q[3] - q[4]) / (12 * h)
    q_ss = (q[1] - 2 * q[2] + q[3]) / h**2
    q_sss = (-q[0] + 2 * q[1] - 2 * q[3] + q[4]) / (2 * h**3)
    sd, sdd, sddd = sd[:, None], sdd[:, None], sddd[:, None]
    assert np.abs(q_s * sd).max() <= 200.0
    assert np.abs(q_s * sdd + q_ss * sd**2).max() <= 2000.0
    assert np.abs(q_s * sddd + 3 * q_ss * sd * sdd + q_sss * sd**3).max() <= 2e4


def rejection(call) -> CommandRejected:
    with pytest.raises(CommandRejected) as info:
        call()
    return info.value


LIMITS4 = [Limits(360.0, 3600.0, 3600.0, 3.6e4)] * 4
NONE = Limits(math.inf, math.inf, math.inf, math.inf)


def test_a_path_through_the_inner_hole_is_unreachable():
    line = Line([-200.0, 10.0, 0.0], [200.0, 10.0, 0.0])  # passes 10 mm from the base
    error = rejection(lambda: sampled_limits(line, SCARA, LIMITS4, NONE))
    assert error.error_id == ErrorId.TARGET_UNREACHABLE
    assert "out of reach" in error.message and "Line(" in error.message


def test_a_path_through_a_singular_pose_is_rejected_naming_it():
    folded = Scara(250.0, 250.0)  # folded flat at the base: singular there
    line = Line([-100.0, 0.0, 0.0], [100.0, 0.0, 0.0])
    error = rejection(lambda: sampled_limits(line, folded, LIMITS4[:2], NONE))
    assert error.error_id == ErrorId.KINEMATICS_SINGULAR
    assert "(0, 0" in error.message or "(-0, 0" in error.message


def test_a_path_grazing_a_singular_pose_is_rejected():
    """0.01 mm off the folded pose, with no sample near it at first: the steep rise of the
    axis speeds shows it, and no spacing down to 32768 samples resolves it."""
    folded = Scara(250.0, 250.0)
    line = Line([-100.0, 0.01, 0.0], [100.37, 0.01, 0.0])
    error = rejection(lambda: sampled_limits(line, folded, LIMITS4[:2], NONE))
    assert error.error_id == ErrorId.KINEMATICS_SINGULAR
    assert "too close to a singular pose" in error.message
    x, y = map(float, re.search(r"near MCS position \(([^,]+), ([^,]+),", error.message).groups())
    assert math.hypot(x, y) < 0.05  # it names the point next to the folded pose


def test_a_path_near_a_singular_pose_gets_caps_that_hold_there():
    """1 mm off the folded pose the axis speeds peak sharply; the samples must resolve it."""
    folded = Scara(250.0, 250.0)
    line = Line([-100.0, 1.0, 0.0], [100.37, 1.0, 0.0])
    caps = sampled_limits(line, folded, LIMITS4[:2], NONE)
    s, h = np.union1d(np.linspace(0.0, line.length, 2001), np.linspace(95.0, 105.0, 20001)), 1e-3
    stencil = np.clip(s, 2 * h, line.length - 2 * h) + h * np.arange(-2, 3)[:, None]
    q = folded.inverse(line.position(stencil.ravel())[:, :2]).reshape(5, len(s), 2)
    q = np.unwrap(q, period=360.0, axis=0)
    q_s = (q[0] - 8 * q[1] + 8 * q[3] - q[4]) / (12 * h)
    q_ss = (q[1] - 2 * q[2] + q[3]) / h**2
    q_sss = (-q[0] + 2 * q[1] - 2 * q[3] + q[4]) / (2 * h**3)
    assert_worst_case_within(q_s, q_ss, q_sss, caps, LIMITS4[:2], straight=False,
                             tolerance=1 + 1e-3)


def test_a_scara_without_z_rejects_a_path_that_climbs():
    flat = Scara(300.0, 250.0)
    line = Line([300.0, 0.0, 0.0], [300.0, 100.0, 10.0])
    error = rejection(lambda: sampled_limits(line, flat, LIMITS4[:2], NONE))
    assert error.error_id == ErrorId.TARGET_UNREACHABLE and "moves along z" in error.message
