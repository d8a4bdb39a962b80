"""Geo-compensation (TF5410 §4.1, §8.2, §9.2; digest D1.11, D3.2, D5 T18; D-070 to D-073).

The starter kit: 3000 mm, curve radius R = 500/pi mm (two 1000 mm straights, two 500 mm
curves), x = 0 where the upper-left curve ends; a template with y = 100 mm.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import openmotion as om
from openmotion.core.special_values import MC_INVALID
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    CompensationType,
    MC_AddAxisToGroup,
    MC_GroupEnable,
    MC_HaltCA,
    MC_MoveAbsoluteCA,
    MC_MoveRelativeCA,
    MC_RegisterCompensation,
    MC_TransformPosition,
    MoverTemplate,
    ST_HaltCAOptions,
    ST_MoveAbsoluteCAOptions,
    ST_MoveRelativeCAOptions,
    StarterKitGeometry,
)

ErrorId = om.ErrorId
AXIS = {"max_velocity": 1000.0, "max_acceleration": 5000.0, "max_deceleration": 20000.0,
        "max_jerk": 1.0e6}
R = 500.0 / math.pi
Y = 100.0
T = 0x01010010  #: the OTCID of the template
OTHER = 0x01010011  #: a second template (y = 50)
VELOCITY, ACCELERATION = 400.0, 2000.0


def starter_kit(*positions: float, register: bool = True
                ) -> tuple[om.Runtime, CaGroup, list[om.Axis]]:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=3000.0)
    geo = group.tracks.geo
    geo.set_geometry(StarterKitGeometry())
    geo.add_template(MoverTemplate(T, y_shift=Y))
    geo.add_template(MoverTemplate(OTHER, y_shift=50.0))
    axes = []
    for ident, position in enumerate(positions, 1):
        axis = rt.add_axis(f"m{ident}", position=position, **AXIS)
        assert axis.power()
        MC_AddAxisToGroup(group)(execute=True, axis=axis,
                                 ident_in_group=UDINT_TO_IDENTINGROUP(ident))
        if register:
            fb = MC_RegisterCompensation(axis)
            fb(execute=True, compensation_type=CompensationType.GEO, compensation_id=T)
            assert fb.done, fb.message
        axes.append(axis)
    MC_GroupEnable(group)(execute=True)
    return rt, group, axes


def run_move(rt: om.Runtime, axis: om.Axis, geometry: StarterKitGeometry, **inputs: Any
             ) -> tuple[MC_MoveAbsoluteCA, np.ndarray]:
    """MC_MoveAbsoluteCA to the end, sampling (position, velocity, acceleration) per cycle."""
    fb = MC_MoveAbsoluteCA(axis)
    samples = []
    for _ in range(20000):
        fb(execute=True, velocity=VELOCITY, acceleration=ACCELERATION,
           deceleration=ACCELERATION, **inputs)
        if not fb.busy:
            return fb, np.array(samples)
        rt.step()
        samples.append((axis.set_position, axis.set_velocity, axis.set_acceleration))
    raise AssertionError("the move did not end")


# -- the geometry --------------------------------------------------------------------------------


def test_starter_kit_numbers():
    g = StarterKitGeometry()
    assert g.curve_radius == pytest.approx(R, abs=1e-12)
    assert g.straight_length == pytest.approx(1000.0, abs=1e-9)
    assert g.tcp_lap(Y) == pytest.approx(3000.0 + 2 * math.pi * Y, abs=1e-9)
    # the upper straight [0, 1000), the right curve, the lower straight, the left curve
    assert [g.curvature(x) for x in (0.0, 999.0, 1000.0, 1499.0, 1500.0, 2499.0, 2500.0,
                                     2999.0, 3000.0)] == [0.0, 0.0, 1 / R, 1 / R, 0.0, 0.0,
                                                          1 / R, 1 / R, 0.0]


@pytest.mark.parametrize("offset", [0.0, 123.4, -700.0])
@pytest.mark.parametrize("y", [0.0, 100.0, 37.5])
def test_absolute_to_tcp_to_absolute_round_trip_everywhere(offset, y):
    """T18: the round trip equals the input to 1e-9, over laps forwards and backwards."""
    g = StarterKitGeometry(rail_offset=offset)
    x = np.linspace(-6000.0, 9000.0, 150001)
    back = g.tcp_to_motor(g.motor_to_tcp(x, y), y)
    assert np.max(np.abs(back - x)) <= 1e-9
    assert g.motor_to_tcp(0.0, y) == 0.0  # the TCP frame starts at the TCP of x = 0
    assert g.motor_to_tcp(3000.0, y) == pytest.approx(g.tcp_lap(y), abs=1e-9)
    assert np.all(np.diff(g.motor_to_tcp(x, y)) > 0.0)  # monotone


def test_on_a_straight_tcp_and_motor_distances_agree():
    g = StarterKitGeometry()
    assert g.motor_to_tcp(900.0, Y) - g.motor_to_tcp(100.0, Y) == pytest.approx(800.0,
                                                                                  abs=1e-9)
    assert g.motor_to_tcp(2400.0, Y) - g.motor_to_tcp(1600.0, Y) == pytest.approx(800.0,
                                                                                   abs=1e-9)


def test_in_a_curve_tcp_distance_is_motor_distance_times_r_plus_y_over_r():
    g = StarterKitGeometry()
    for a, b in ((1100.0, 1400.0), (2550.0, 2950.0), (1000.0, 1500.0)):
        assert g.motor_to_tcp(b, Y) - g.motor_to_tcp(a, Y) == pytest.approx(
            (b - a) * (R + Y) / R, abs=1e-9)
    # one half curve: 250 mm on the motor path, 250 + 50 pi mm on the TCP path
    assert g.motor_to_tcp(1250.0, Y) == pytest.approx(1000.0 + 250.0 + Y * math.pi / 2,
                                                      abs=1e-9)


def test_a_positive_rail_offset_moves_the_zero_further_along_the_path():
    g = StarterKitGeometry(rail_offset=100.0)
    assert g.curvature(899.0) == 0.0 and g.curvature(900.0) == 1 / R
    assert g.motor_to_tcp(1400.0, Y) - g.motor_to_tcp(900.0, Y) == pytest.approx(
        500.0 * (R + Y) / R, abs=1e-9)


@pytest.mark.parametrize(("make", "match"), [
    (lambda: StarterKitGeometry(curve_radius=3000.0 / (2 * math.pi)), "leave straights"),
    (lambda: StarterKitGeometry(curve_radius=0.0), "> 0"),
    (lambda: StarterKitGeometry(rail_offset=math.nan), "finite"),
    (lambda: MoverTemplate(T, y_shift=-1.0), ">= 0"),
    (lambda: MoverTemplate(0), "OTCID"),
    (lambda: MoverTemplate(True), "OTCID"),
], ids=["no-straights", "radius-0", "offset-nan", "y<0", "id-0", "id-bool"])
def test_bad_geometry_or_template_is_a_config_error(make, match):
    with pytest.raises(om.ConfigError, match=match):
        make()


def test_geometry_must_fit_the_group():
    rt = om.Runtime()
    with pytest.raises(om.ConfigError, match="ring"):
        CaGroup(rt, "open", rail_length=3000.0, rail_is_ring=False).tracks.geo.set_geometry(
            StarterKitGeometry())
    geo = CaGroup(rt, "ca", rail_length=2000.0).tracks.geo
    with pytest.raises(om.ConfigError, match="add the geometry first"):
        geo.add_template(MoverTemplate(T))
    with pytest.raises(om.ConfigError, match="rail_length 3000"):
        geo.set_geometry(StarterKitGeometry())
    geo.set_geometry(StarterKitGeometry(rail_length=2000.0))
    geo.add_template(MoverTemplate(T))
    with pytest.raises(om.ConfigError, match="exists already"):
        geo.add_template(MoverTemplate(T, y_shift=5.0))


# -- MC_TransformPosition and MC_RegisterCompensation --------------------------------------------


def transform(group: CaGroup, **inputs: Any) -> MC_TransformPosition:
    fb = MC_TransformPosition(group)
    fb(execute=True, **inputs)
    return fb


def test_transform_position_absolute_to_tcp_and_back():
    """T18 (§9.2.1.2 sample): fbAbsoluteToTcp, then fbTcpToAbsolute."""
    _, group, _ = starter_kit()
    to_tcp = transform(group, origin_oid=0, destination_oid=T, origin_position=1250.0)
    assert to_tcp.done and not to_tcp.busy
    assert to_tcp.destination_position == pytest.approx(1250.0 + Y * math.pi / 2, abs=1e-9)
    back = transform(group, origin_oid=T, destination_oid=0,
                     origin_position=to_tcp.destination_position)
    assert back.destination_position == pytest.approx(1250.0, abs=1e-9)
    same = transform(group, origin_oid=0, destination_oid=0, origin_position=1250.0)
    assert same.destination_position == 1250.0
    between = transform(group, origin_oid=T, destination_oid=OTHER,
                        origin_position=to_tcp.destination_position)
    assert between.destination_position == pytest.approx(1250.0 + 50.0 * math.pi / 2,
                                                         abs=1e-9)


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"origin_oid": 0, "destination_oid": 99}, ErrorId.UNKNOWN_TEMPLATE),
    ({"origin_oid": 99, "destination_oid": 0}, ErrorId.UNKNOWN_TEMPLATE),
    ({"origin_oid": 0, "destination_oid": T, "origin_position": MC_INVALID},
     ErrorId.INVALID_POSITION),
    ({"origin_oid": 0, "destination_oid": T, "origin_position": math.inf},
     ErrorId.INVALID_POSITION),
], ids=["unknown-destination", "unknown-origin", "mc-invalid", "inf"])
def test_transform_position_bad_input(inputs, error_id):
    _, group, _ = starter_kit()
    fb = transform(group, **inputs)
    assert fb.error and fb.error_id is error_id and fb.destination_position == 0.0


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"compensation_id": T}, ErrorId.INVALID_COMPENSATION_TYPE),  # the PLC default INVALID
    ({"compensation_type": CompensationType.GEO, "compensation_id": 99},
     ErrorId.UNKNOWN_TEMPLATE),
    ({"compensation_type": CompensationType.GEO, "compensation_id": 0},
     ErrorId.UNKNOWN_TEMPLATE),
], ids=["type-invalid", "unknown-id", "id-0"])
def test_register_compensation_bad_input(inputs, error_id):
    _, _, (axis,) = starter_kit(500.0, register=False)
    fb = MC_RegisterCompensation(axis)
    fb(execute=True, **inputs)
    assert fb.error and fb.error_id is error_id


def test_register_compensation_outside_a_ca_group_is_an_error():
    rt = om.Runtime()
    axis = rt.add_axis("alone", **AXIS)
    fb = MC_RegisterCompensation(axis)
    fb(execute=True, compensation_type=CompensationType.GEO, compensation_id=T)
    assert fb.error and fb.error_id is ErrorId.AXIS_NOT_IN_GROUP


# -- moves with reference systems ----------------------------------------------------------------


@pytest.mark.parametrize(("field", "oid", "register", "error_id"), [
    ("position_reference_system", T, False, ErrorId.COMPENSATION_NOT_REGISTERED),
    ("dynamics_reference_system", T, False, ErrorId.COMPENSATION_NOT_REGISTERED),
    ("position_reference_system", OTHER, True, ErrorId.COMPENSATION_NOT_REGISTERED),
    ("dynamics_reference_system", 99, True, ErrorId.UNKNOWN_TEMPLATE),
], ids=["position-unregistered", "dynamics-unregistered", "another-template", "unknown"])
def test_a_reference_system_the_axis_did_not_register_is_an_error(field, oid, register,
                                                                   error_id):
    _, _, (axis,) = starter_kit(500.0, register=register)
    fb = MC_MoveAbsoluteCA(axis)
    fb(execute=True, position=900.0, velocity=VELOCITY,
       options=ST_MoveAbsoluteCAOptions(**{field: oid}))
    assert fb.error and fb.error_id is error_id


def test_a_position_on_the_tcp_path_ends_at_its_motor_position():
    rt, group, (axis,) = starter_kit(500.0)
    g = group.tracks.geo.geometry
    target = 1250.0 + Y * math.pi / 2  # the TCP of the middle of the right curve
    fb, _ = run_move(rt, axis, g, position=target,
                     options=ST_MoveAbsoluteCAOptions(position_reference_system=T))
    assert fb.done
    assert axis.set_position == pytest.approx(1250.0, abs=1e-9)
    modulo, _ = run_move(rt, axis, g, position=g.tcp_lap(Y) - 1.0,
                         direction=om.transport.ModuloDirection.POSITIVE,
                         options=ST_MoveAbsoluteCAOptions(position_reference_system=T))
    assert modulo.done  # TCP 1 mm before the lap's end: motor 1 mm before 3000 (left curve)
    assert axis.set_position == pytest.approx(3000.0 - R / (R + Y), abs=1e-9)


def tcp_dynamics(samples: np.ndarray, g: StarterKitGeometry) -> tuple[np.ndarray, np.ndarray]:
    """TCP speed and tangential acceleration: the motor's times (1 + y * curvature)."""
    factor = 1.0 + Y * g.curvature(samples[:, 0])
    return np.abs(samples[:, 1]) * factor, np.abs(samples[:, 2]) * factor


def test_a_compensated_move_keeps_the_tcp_within_the_commanded_dynamics():
    """T18: DynamicsReferenceSystem = template; through the right curve (1000 to 1500)."""
    rt, group, (axis,) = starter_kit(500.0)
    g = group.tracks.geo.geometry
    fb, samples = run_move(rt, axis, g, position=2200.0,
                           options=ST_MoveAbsoluteCAOptions(dynamics_reference_system=T))
    assert fb.done and axis.set_position == pytest.approx(2200.0, abs=1e-9)
    assert any("TCP of mover template" in w for w in fb.command.warnings)
    curve = g.curvature(samples[:, 0]) > 0.0
    assert curve.sum() > 50  # the motion spends many cycles in the curve
    v_tcp, a_tcp = tcp_dynamics(samples, g)
    assert v_tcp.max() <= VELOCITY * (1 + 1e-9)
    assert a_tcp.max() <= ACCELERATION * (1 + 1e-9)
    # the motor runs at R/(R+y) of the commanded velocity, so the TCP reaches it in the curve
    assert np.abs(samples[:, 1]).max() == pytest.approx(VELOCITY * R / (R + Y), rel=1e-9)
    assert v_tcp[curve].max() == pytest.approx(VELOCITY, rel=1e-9)


def test_without_compensation_the_tcp_is_faster_than_commanded_in_the_curve():
    rt, group, (axis,) = starter_kit(500.0)
    g = group.tracks.geo.geometry
    _, samples = run_move(rt, axis, g, position=2200.0)
    v_tcp, _ = tcp_dynamics(samples, g)
    assert v_tcp.max() == pytest.approx(VELOCITY * (R + Y) / R, rel=1e-9)


def test_a_compensated_move_on_a_straight_keeps_the_full_dynamics():
    rt, group, (axis,) = starter_kit(100.0)
    fb, samples = run_move(rt, axis, group.tracks.geo.geometry, position=900.0,
                           options=ST_MoveAbsoluteCAOptions(dynamics_reference_system=T))
    assert fb.done
    assert np.abs(samples[:, 1]).max() == pytest.approx(VELOCITY, rel=1e-9)


def halt_in_curve(**options: Any) -> tuple[MC_HaltCA, np.ndarray, StarterKitGeometry]:
    """A mover cruising into the right curve (1000 to 1500) halts at 1050: samples until
    standstill."""
    rt, group, (axis,) = starter_kit(500.0)
    g = group.tracks.geo.geometry
    move, halt = MC_MoveAbsoluteCA(axis), MC_HaltCA(axis)
    move(execute=True, position=2500.0, velocity=VELOCITY, acceleration=ACCELERATION,
         deceleration=ACCELERATION)
    rt.run_until(lambda: axis.set_position >= 1050.0)
    samples = []
    for _ in range(5000):
        halt(execute=True, deceleration=ACCELERATION, jerk=AXIS["max_jerk"],
             options=ST_HaltCAOptions(**options))
        if halt.done or halt.error:
            return halt, np.array(samples), g
        rt.step()
        samples.append((axis.set_position, axis.set_velocity, axis.set_acceleration))
    raise AssertionError("the halt did not end")


def test_a_halt_with_tcp_dynamics_in_a_curve_keeps_the_tcp_deceleration():
    """MC_HaltCA with DynamicsReferenceSystem = template (§9.1.2.4): the stop meets the curve,
    so the motor brakes at R/(R+y) of the deceleration and the TCP at no more than it."""
    halt, samples, g = halt_in_curve(dynamics_reference_system=T)
    assert halt.done, halt.message
    assert any("the stop meets a curve" in w for w in halt.command.warnings)
    _, a_tcp = tcp_dynamics(samples, g)
    assert a_tcp.max() <= ACCELERATION * (1 + 1e-9)
    assert np.abs(samples[:, 2]).max() == pytest.approx(ACCELERATION * R / (R + Y), rel=1e-6)


def test_a_halt_on_the_motor_path_in_a_curve_brakes_the_tcp_harder():
    halt, samples, g = halt_in_curve()
    assert halt.done
    _, a_tcp = tcp_dynamics(samples, g)
    assert a_tcp.max() == pytest.approx(ACCELERATION * (R + Y) / R, rel=1e-6)


def test_a_halt_may_only_name_the_registered_template():
    halt, _, _ = halt_in_curve(dynamics_reference_system=OTHER)
    assert halt.error and halt.error_id is ErrorId.COMPENSATION_NOT_REGISTERED


def queue_in_curve(register_behind: bool = True) -> tuple[float, float, StarterKitGeometry,
                                                         CaGroup]:
    """A mover queues one gap of 100 mm behind a mover standing at 1300 in the right curve
    (1000 to 1500): the motor positions (ahead, behind) it ends at."""
    rt, group, (ahead, behind) = starter_kit(1300.0, 500.0, register=False)
    for axis in (ahead, behind) if register_behind else (ahead,):
        MC_RegisterCompensation(axis)(execute=True, compensation_type=CompensationType.GEO,
                                      compensation_id=T)
    fb = MC_MoveAbsoluteCA(behind)
    for _ in range(5000):
        fb(execute=True, position=1350.0, velocity=VELOCITY, gap=100.0)
        rt.step()
        assert behind.set_velocity >= 0.0  # a queued mover never turns back (§3)
    assert fb.busy  # queued: Done only at its target (D-062)
    return ahead.set_position, behind.set_position, group.tracks.geo.geometry, group


def test_a_compensated_mover_keeps_its_gap_on_the_tcp_path():
    """T18 gap (§9.1.1.1.1, D-073): the successor registered a template, so its gap is the
    distance of the TCP paths; in the curve the motors come as close as 100 R/(R+y)."""
    ahead, behind, g, group = queue_in_curve()
    tcp_gap = g.motor_to_tcp(ahead, Y) - g.motor_to_tcp(behind, Y)
    assert tcp_gap == pytest.approx(100.0, abs=1e-6)
    assert ahead - behind == pytest.approx(100.0 * R / (R + Y), abs=1e-6)
    assert group.gaps()[1] == pytest.approx(100.0, abs=1e-6)  # the gap signal is the TCP gap


def test_without_a_template_the_gap_stays_on_the_motor_path():
    ahead, behind, g, group = queue_in_curve(register_behind=False)
    assert ahead - behind == pytest.approx(100.0, abs=1e-6)
    assert group.gaps()[1] == pytest.approx(100.0, abs=1e-6)


def test_a_relative_distance_on_the_tcp_path_ends_where_the_tcp_has_gone_that_far():
    rt, group, (axis,) = starter_kit(900.0)  # on the upper straight, before the right curve
    g = group.tracks.geo.geometry
    fb = MC_MoveRelativeCA(axis)
    for _ in range(20000):
        fb(execute=True, distance=300.0, velocity=VELOCITY, acceleration=ACCELERATION,
           deceleration=ACCELERATION,
           options=ST_MoveRelativeCAOptions(position_reference_system=T,
                                            dynamics_reference_system=T))
        if not fb.busy:
            break
        rt.step()
    assert fb.done, fb.message
    # 100 mm of straight, then 200 mm of TCP arc = 200 R / (R + y) of motor arc
    assert axis.set_position == pytest.approx(1000.0 + 200.0 * R / (R + Y), abs=1e-9)
    assert g.motor_to_tcp(axis.set_position, Y) - g.motor_to_tcp(900.0, Y) == \
        pytest.approx(300.0, abs=1e-9)
