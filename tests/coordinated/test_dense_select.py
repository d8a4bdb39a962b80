"""MC_PathSelect's bulk route for runs of lines (coordinated/dense.py, D-290).

The bulk route must give the path the corner-by-corner loop gives, to round-off: the same
elements and exits, the same contours, the same caps; and the same errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import openmotion as om
from openmotion.bench.path import gantry
from openmotion.coordinated import dense, paths
from openmotion.coordinated.blocks import MC_PathSelect
from openmotion.coordinated.dense import DENSE_MIN, derivative_bounds
from openmotion.coordinated.dense_timing import planned_time
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import TransitionMode
from openmotion.coordinated.limits import DENSE_SHARES, cartesian_limits, many_limits
from openmotion.coordinated.limits_bridge import axis_limits, caps_for_many, dense_path
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.geometry.blend import Contour
from openmotion.trajectory.plan import Limits

ROUND_OFF = 1e-9  #: [mm] and relative: what the two routes may differ by


def wave(n: int) -> np.ndarray:
    """``n`` + 1 points of a wavy line in ``n`` chords of about 0.2 mm: curvature up to ~2/mm."""
    x = np.linspace(0.0, 0.2 * n, n + 1)
    return np.column_stack([x, 0.5 * np.sin(x), np.zeros_like(x)])


def group_at(point: np.ndarray) -> AxesGroup:
    return gantry(om.Runtime(cycle_time=0.001), point[:2])


def both(points: np.ndarray, mode: TransitionMode, value: float,
         monkeypatch: pytest.MonkeyPatch) -> tuple[paths.PathData, paths.PathData]:
    """(bulk, corner by corner) PathData of lines through ``points``."""
    group = group_at(points[0])
    description = [{"line": p.tolist()} for p in points[1:]]
    bulk = paths.select_path(group, description, mode=mode, parameter=value)
    monkeypatch.setattr(paths, "DENSE_MIN", 10**9)
    single = paths.select_path(group, description, mode=mode, parameter=value)
    monkeypatch.undo()
    return bulk, single


def assert_same(bulk: paths.PathData, single: paths.PathData) -> None:
    assert bulk.exits == single.exits
    assert len(bulk.elements) == len(single.elements)
    assert bulk.length == pytest.approx(single.length, rel=ROUND_OFF)
    for a, b in zip(bulk.elements, single.elements, strict=True):
        assert type(a) is type(b)
        assert a.length == pytest.approx(b.length, rel=ROUND_OFF, abs=ROUND_OFF)
        s = np.linspace(0.0, min(a.length, b.length), 5)
        np.testing.assert_allclose(a.position(s), b.position(s), atol=ROUND_OFF, rtol=0)
        np.testing.assert_allclose(a.tangent(s), b.tangent(s), atol=ROUND_OFF, rtol=0)
        if isinstance(a, Contour):
            np.testing.assert_allclose(a.derivative_bounds(), b.derivative_bounds(),
                                       rtol=ROUND_OFF, atol=ROUND_OFF)


@pytest.mark.parametrize(("mode", "value"), [(TransitionMode.TM_MAX_CORNER_DEVIATION, 0.02),
                                             (TransitionMode.TM_CORNER_DISTANCE, 0.03)])
def test_a_run_of_lines_in_bulk_is_the_corner_by_corner_path(
        mode: TransitionMode, value: float, monkeypatch: pytest.MonkeyPatch) -> None:
    bulk, single = both(wave(200), mode, value, monkeypatch)
    assert sum(isinstance(e, Contour) for e in bulk.elements) == 198  # 199 lines after the first
    assert_same(bulk, single)


def test_corners_that_need_a_root_search_go_corner_by_corner_within_the_run(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # 1e-3 mm: the widest contour deviates more at about half of the corners (the sharper)
    calls: list[int] = []
    one_corner = paths._contour

    def counted(*args: object) -> object:
        calls.append(1)
        return one_corner(*args)

    monkeypatch.setattr(paths, "_contour", counted)
    points = wave(150)
    group = group_at(points[0])
    description = [{"line": p.tolist()} for p in points[1:]]
    bulk = paths.select_path(group, description, parameter=1e-3)
    assert 20 < len(calls) < 120  # some of the 148 corners, not all
    monkeypatch.setattr(paths, "DENSE_MIN", 10**9)
    single = paths.select_path(group, description, parameter=1e-3)
    assert len(calls) > 148
    assert_same(bulk, single)


def test_a_corner_that_turns_back_stops_in_the_bulk_route_too(
        monkeypatch: pytest.MonkeyPatch) -> None:
    points = wave(60)
    points = np.vstack([points, points[-2::-1][:30]])  # back along the same chords
    bulk, single = both(points, TransitionMode.TM_MAX_CORNER_DEVIATION, 0.02, monkeypatch)
    assert 0.0 in bulk.exits[:-1]  # the reversal is an exact stop
    assert_same(bulk, single)


def test_coincident_points_in_a_run_name_the_element_and_the_block_works_after() -> None:
    points = wave(40)
    group = group_at(points[0])
    description = [{"line": p.tolist()} for p in points[1:]]
    description.insert(25, {"line": points[25].tolist()})  # element 25 repeats element 24
    select = MC_PathSelect(group)
    select(execute=True, path_description=description)
    assert select.error and select.error_id is ErrorId.INVALID_PATH_GEOMETRY
    assert "element 25: line: start and end coincide" in select.message
    with pytest.raises(CommandRejected, match="element 25"):
        paths.select_path(group, description)
    select(execute=False)
    select(execute=True, path_description=[{"line": p.tolist()} for p in points[1:]])
    assert select.done and select.path_data.count == 40


def test_bulk_caps_of_contours_are_the_caps_element_by_element() -> None:
    points = wave(80)
    group = group_at(points[0])
    data = paths.select_path(group, [{"line": p.tolist()} for p in points[1:]],
                             parameter=0.02)
    contours = [e for e in data.elements if isinstance(e, Contour)]
    expected = np.array([c.derivative_bounds() for c in contours])  # one by one
    fresh = [Contour(c.start, c.tangent(0.0), c.curvature_vector(0.0), c.end,
                     c.tangent(c.length), c.curvature_vector(c.length),
                     float(np.linalg.norm(c.control_offsets[1]))) for c in contours]
    bounds = dense.derivative_bounds(fresh)
    np.testing.assert_allclose(bounds, expected, rtol=1e-8, atol=1e-12)
    limits = axis_limits(group)
    commanded = Limits(250.0, 5000.0, 5000.0, 1e6)
    caps = many_limits(bounds, group.spaces.kinematics, limits, commanded)
    one = [cartesian_limits(c, group.spaces.kinematics, limits, commanded) for c in contours]
    one = np.array([[c.velocity, c.acceleration, c.deceleration, c.jerk] for c in one])
    np.testing.assert_allclose(caps, one, rtol=1e-12)
    assert math.isfinite(caps.min()) and caps.min() > 0.0


def test_dense_shares_keep_the_proof_and_bad_ones_are_refused() -> None:
    """Any shares that leave the path some jerk give caps within the budget (D-336): the
    curvature-rate and turning terms at V and M stay within their shares; shares that leave
    none are a ConfigError, and the call works again with good ones."""
    points = wave(40)
    group = group_at(points[0])
    data = paths.select_path(group, [{"line": p.tolist()} for p in points[1:]],
                             mode=TransitionMode.TM_MAX_CORNER_DEVIATION, parameter=0.05)
    bounds = derivative_bounds([e for e in data.elements if type(e) is Contour])
    limits, commanded = axis_limits(group), Limits(250.0, 5000.0, 5000.0, 1e6)
    jerk = 1e6  # the axes' max_jerk (bench.path.gantry)
    for rate, turning in DENSE_SHARES:
        caps = many_limits(bounds, group.spaces.kinematics, limits, commanded,
                           rate_share=rate, turning_share=turning)
        v, m = caps[:, 0], np.maximum(caps[:, 1], caps[:, 2])
        r, k = bounds[:, 2, :2].max(axis=1), bounds[:, 1, :2].max(axis=1)
        assert np.all(r * v**3 <= rate * jerk * (1 + ROUND_OFF))
        assert np.all(3.0 * k * v * m <= turning * jerk * (1 + ROUND_OFF))
        assert caps[:, 3].min() > 0.0
    with pytest.raises(ConfigError, match="leave the path a part of the jerk"):
        many_limits(bounds, group.spaces.kinematics, limits, commanded, rate_share=0.9,
                    turning_share=0.1)
    assert many_limits(bounds, group.spaces.kinematics, limits, commanded).shape == \
        (len(bounds), 4)


def test_a_dense_path_takes_the_shares_that_plan_fastest() -> None:
    """MC_MovePath's caps of a dense path's contours are those of the shares whose profile
    plans the shortest time (D-336); a path of 15 contours keeps D-134's shares."""
    points = wave(40)
    group = group_at(points[0])
    data = paths.select_path(group, [{"line": p.tolist()} for p in points[1:]],
                             mode=TransitionMode.TM_MAX_CORNER_DEVIATION, parameter=0.05)
    dynamics = (250.0, 5000.0, 5000.0, 1e6)
    caps = np.array(caps_for_many(group, data.elements, "MCS", dynamics))
    lengths = np.array([e.length for e in data.elements])
    contours = [i for i, e in enumerate(data.elements) if type(e) is Contour]
    bounds = derivative_bounds([data.elements[i] for i in contours])
    times = []
    for rate, turning in DENSE_SHARES:
        trial = caps.copy()
        trial[contours] = many_limits(bounds, group.spaces.kinematics, axis_limits(group),
                                      Limits(*dynamics), rate_share=rate,
                                      turning_share=turning)
        times.append(planned_time(lengths, trial[:, 0], trial[:, 1], trial[:, 2]))
        if np.array_equal(trial, caps):
            chosen = times[-1]
    assert chosen == min(times)
    few = data.elements[:2 * (DENSE_MIN - 1)]
    assert not dense_path(group, few, "MCS")
    plain = np.array(caps_for_many(group, few, "MCS", dynamics))
    one = cartesian_limits(few[1], group.spaces.kinematics, axis_limits(group),
                           Limits(*dynamics))
    np.testing.assert_array_equal(plain[1], [one.velocity, one.acceleration, one.deceleration,
                                             one.jerk])


def test_plain_lines_read_in_one_go_are_the_lines_read_one_by_one() -> None:
    points = wave(30)
    group = group_at(points[0])
    flat = paths.select_path(group, [{"line": p[:2].tolist()} for p in points[1:]])
    spelled = paths.select_path(group, [{"line": p[:2].tolist(), "transition_mode":
                                         TransitionMode.TM_MAX_CORNER_DEVIATION,
                                         "transition_parameter": 0.1} for p in points[1:]])
    assert flat.exits == spelled.exits and flat.count == spelled.count == 30
    for a, b in zip(flat.elements, spelled.elements, strict=True):
        np.testing.assert_array_equal(a.start, b.start)
        np.testing.assert_array_equal(a.end, b.end)


def test_a_bad_point_among_plain_lines_is_named() -> None:
    points = wave(30)
    group = group_at(points[0])
    description = [{"line": p.tolist()} for p in points[1:]]
    description[7] = {"line": [1.0, math.nan, 0.0]}
    with pytest.raises(CommandRejected, match="element 7") as rejected:
        paths.select_path(group, description)
    assert rejected.value.error_id is ErrorId.INVALID_POSITION
    description[7] = {"line": [1.0, 2.0, 3.0, 4.0]}
    with pytest.raises(CommandRejected, match="element 7: line needs 1 to 3 coordinates"):
        paths.select_path(group, description)
    description[7] = {"line": points[8].tolist()}
    assert paths.select_path(group, description).count == 30


def test_a_helix_with_an_arc_inside_is_rounded_alike_in_3d(
        monkeypatch: pytest.MonkeyPatch) -> None:
    phi = np.linspace(0.0, 3.0 * math.pi, 121)
    helix = np.column_stack([10.0 * np.cos(phi), 10.0 * np.sin(phi), 0.5 * phi])
    description: list[dict[str, object]] = [{"line": p.tolist()} for p in helix[1:61]]
    description.append({"arc": [helix[60, 0] + 10.0, helix[60, 1], helix[60, 2]],
                        "aux": [helix[60, 0] + 5.0, helix[60, 1] - 5.0, helix[60, 2]],
                        "circ_mode": "BORDER"})
    shifted = helix[61:] + np.array([10.0, 0.0, 0.0])
    description += [{"line": p.tolist()} for p in shifted]
    group = gantry(om.Runtime(cycle_time=0.001), helix[0, :2])
    bulk = paths.select_path(group, description, parameter=0.05)
    monkeypatch.setattr(paths, "DENSE_MIN", 10**9)
    single = paths.select_path(group, description, parameter=0.05)
    assert any(type(e).__name__ == "Arc" for e in bulk.elements)
    assert any(isinstance(e, Contour) and abs(e.end[2] - e.start[2]) > 1e-3
               for e in bulk.elements)  # contours that climb
    assert_same(bulk, single)
