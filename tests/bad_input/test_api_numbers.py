"""Bad numbers given to the Python API (issue 18, point 4).

Configuration calls (constructors, ``add_...``, run calls) refuse NaN, ±inf, text, None and
bools with a ``ConfigError`` naming the field (core/checks.py); commands answer with their
block's error id and never raise. Every case checks that what was built before stays usable:
a valid call succeeds next and a move completes. A planar mover goes only where stators carry
it (docs/decisions.md D-163).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest

import openmotion as om
from openmotion.coordinated.frames import Frame, LinearFrame
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import PathDynamics
from openmotion.coordinated.kinematics import CartesianGantry, DeltaRobot, Scara
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarFeedback,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarTrack,
    MC_PlanarTrackTrail,
    MoverVector,
    Part,
    PartLayout,
    PartPosition,
    PlanarMoverParameters,
    PlanarObjectType,
    PlanarState,
    Pose,
    PositionXYC,
    StatorField,
)
from openmotion.plcopen import MC_WriteParameter
from openmotion.testing import enabled_loop, join_all
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    CaGroupParameters,
    MC_AddAxisToGroup,
    MC_GroupEnable,
    MC_MoveAbsoluteCA,
    MoverTemplate,
    StarterKitGeometry,
)

ConfigError = om.ConfigError
ErrorId = om.ErrorId
NAN, INF = math.nan, math.inf
#: what a number input must refuse; each id names the case in the report
NOT_FINITE = [pytest.param(NAN, id="nan"), pytest.param(INF, id="inf"),
              pytest.param(-INF, id="-inf")]
NOT_A_NUMBER = [pytest.param("abc", id="text"), pytest.param(None, id="None"),
                pytest.param(True, id="bool")]
BAD = NOT_FINITE + NOT_A_NUMBER
FINITE_MESSAGE = r"must be a (finite )?number"


def refused(field: str) -> Any:
    """``pytest.raises`` for a ConfigError naming ``field``."""
    return pytest.raises(ConfigError, match=rf"{field}: {FINITE_MESSAGE}")


def completes_a_move(rt: om.Runtime, name: str = "ok") -> None:
    """The runtime still builds an axis and runs a move to its end."""
    axis = rt.add_axis(name, position=1.0)
    axis.power()
    move = axis.move_absolute(11.0, 100.0)
    rt.run_until(move, timeout=5.0)
    assert move.done and axis.position == pytest.approx(11.0)


# -- the runtime ----------------------------------------------------------------------------------


@pytest.mark.parametrize("value", [*BAD, pytest.param(0.0, id="zero"),
                                   pytest.param(-0.001, id="negative")])
def test_runtime_cycle_time_must_be_a_finite_number_above_zero(value: object) -> None:
    with pytest.raises(ConfigError, match=r"cycle_time: must be a (finite )?number"):
        om.Runtime(value)  # type: ignore[arg-type]
    completes_a_move(om.Runtime(0.001))


@pytest.mark.parametrize("value", BAD)
def test_add_axis_refuses_a_start_position_that_is_no_finite_number(value: object) -> None:
    rt = om.Runtime()
    with refused("position"):
        rt.add_axis("x", position=value)  # type: ignore[arg-type]
    assert "x" not in rt.axes  # the name stays free
    completes_a_move(rt, "x")


@pytest.mark.parametrize("field", ["max_velocity", "acceleration", "max_jerk", "modulo_period",
                                   "min_soft_limit", "calibration_value",
                                   "jog_increment_forward", "target_position_window",
                                   "encoder_offset", "sync_pulse_offset"])
@pytest.mark.parametrize("value", BAD)
def test_every_axis_parameter_number_is_checked(field: str, value: object) -> None:
    rt = om.Runtime()
    with refused(field):
        rt.add_axis("x", **{field: value})
    with refused(field):
        om.AxisParameters(**{field: value})
    completes_a_move(rt, "x")


@pytest.mark.parametrize("value", ["yes", 1, None])
def test_an_axis_flag_must_be_a_bool(value: object) -> None:
    with pytest.raises(ConfigError, match="enable_min_soft_limit: must be True or False"):
        om.Runtime().add_axis("x", enable_min_soft_limit=value)


def test_a_refused_override_leaves_the_callers_parameters_as_they_were() -> None:
    rt = om.Runtime()
    parameters = om.AxisParameters(max_velocity=500.0)
    with refused("max_velocity"):
        rt.add_axis("x", parameters=parameters, max_velocity=NAN)
    assert parameters.max_velocity == 500.0
    axis = rt.add_axis("x", parameters=parameters, max_velocity=800.0)
    assert axis.parameters.max_velocity == 800.0 and parameters.max_velocity == 500.0


@pytest.mark.parametrize("cam", [(NAN, 1.0), (0.0, "b"), 5.0])
def test_a_reference_cam_is_two_finite_numbers(cam: object) -> None:
    with pytest.raises(ConfigError, match="reference_cam"):
        om.Runtime().add_axis("x", reference_cam=cam)


@pytest.mark.parametrize("field", ["time_constant", "dead_time"])
@pytest.mark.parametrize("value", [*BAD, pytest.param(-0.01, id="negative")])
def test_drive_model_numbers(field: str, value: object) -> None:
    with pytest.raises(ConfigError, match=rf"{field}: must be a (finite )?number"):
        om.DriveModel("lag", **{field: value})
    rt = om.Runtime()
    with pytest.raises(ConfigError, match="drive must be a DriveModel"):
        rt.add_axis("x", drive="lag")  # type: ignore[arg-type]
    assert rt.add_axis("x", drive=om.DriveModel("lag", time_constant=0.002)).drive.model == "lag"


@pytest.mark.parametrize("value", [*BAD, pytest.param(0.0, id="zero")])
def test_paced_runtime_factor(value: object) -> None:
    with pytest.raises(ConfigError, match=r"factor: must be a (finite )?number"):
        om.PacedRuntime(factor=value)  # type: ignore[arg-type]
    wall = [0.0]
    rt = om.PacedRuntime(factor=2.0, clock=lambda: wall[0], sleep=lambda s: None)
    rt.run(0.01)
    assert rt.cycle == 10


@pytest.mark.parametrize("seconds", [*BAD, pytest.param(-1.0, id="negative")])
def test_run_refuses_a_duration_that_is_not_finite_or_negative(seconds: object) -> None:
    rt = om.Runtime()
    with pytest.raises(ConfigError, match=r"run: seconds: must be a (finite )?number"):
        rt.run(seconds)  # type: ignore[arg-type]
    assert rt.cycle == 0
    rt.run(0.0)  # nothing to run: allowed
    assert rt.cycle == 0
    rt.run(0.01)
    assert rt.cycle == 10
    completes_a_move(rt)


@pytest.mark.parametrize("timeout", [*BAD, pytest.param(-1.0, id="negative")])
def test_run_until_refuses_a_timeout_that_is_not_finite_or_negative(timeout: object) -> None:
    rt = om.Runtime()
    with pytest.raises(ConfigError, match=r"run_until: timeout: must be a (finite )?number"):
        rt.run_until(lambda: rt.cycle >= 3, timeout=timeout)  # type: ignore[arg-type]
    assert rt.cycle == 0
    assert rt.run_until(lambda: rt.cycle >= 3, timeout=1.0) == pytest.approx(0.003)


def test_run_until_with_no_time_asks_the_predicate_once() -> None:
    rt = om.Runtime()
    assert rt.run_until(lambda: True, timeout=0.0) == 0.0
    with pytest.raises(TimeoutError):
        rt.run_until(lambda: False, timeout=0)
    assert rt.cycle == 0


# -- axis commands answer with their error id ------------------------------------------------------

AxisCall = Callable[[om.Axis, object], om.Command]
AXIS_COMMANDS: list[tuple[str, AxisCall, ErrorId]] = [
    ("move_absolute.position", lambda a, v: a.move_absolute(v, 100.0), ErrorId.INVALID_POSITION),
    ("move_absolute.velocity", lambda a, v: a.move_absolute(5.0, v), ErrorId.INVALID_VELOCITY),
    ("move_absolute.jerk", lambda a, v: a.move_absolute(5.0, 100.0, jerk=v),
     ErrorId.INVALID_JERK),
    ("move_relative.distance", lambda a, v: a.move_relative(v, 100.0), ErrorId.INVALID_POSITION),
    ("move_modulo.position", lambda a, v: a.move_modulo(v, 100.0), ErrorId.INVALID_POSITION),
    ("move_velocity.velocity", lambda a, v: a.move_velocity(v), ErrorId.INVALID_VELOCITY),
    ("halt.deceleration", lambda a, v: a.halt(v), ErrorId.INVALID_DECELERATION),
    ("stop.deceleration", lambda a, v: a.stop(v), ErrorId.INVALID_DECELERATION),
    ("stop.jerk", lambda a, v: a.stop(1000.0, v), ErrorId.INVALID_JERK),
    ("home.position", lambda a, v: a.home(v), ErrorId.INVALID_POSITION),
    ("set_actual_position", lambda a, v: a.set_actual_position(v), ErrorId.INVALID_POSITION),
    ("set_override", lambda a, v: a.set_override(v), ErrorId.INVALID_OVERRIDE),
]


@pytest.mark.parametrize(("name", "call", "error_id"), AXIS_COMMANDS,
                         ids=[name for name, _, _ in AXIS_COMMANDS])
@pytest.mark.parametrize("value", BAD)
def test_axis_commands_answer_a_bad_number_with_their_error_id(
        name: str, call: AxisCall, error_id: ErrorId, value: object) -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    rt.step()
    command = call(axis, value)
    rt.step()
    assert command.error and command.error_id == error_id, (name, command)
    if axis.state is om.AxisState.STOPPING:  # MC_Stop stops all the same (D-023)
        rt.run_until(lambda: axis.state is om.AxisState.STANDSTILL, timeout=5.0)
    move = axis.move_absolute(10.0, 100.0)
    rt.run_until(move, timeout=5.0)
    assert move.done and axis.position == pytest.approx(10.0)


@pytest.mark.parametrize("value", BAD)
def test_a_gear_ratio_that_is_no_finite_number(value: object) -> None:
    rt = om.Runtime()
    slave, master = rt.add_axis("s"), rt.add_axis("m")
    slave.power(), master.power()
    rt.step()
    gear = slave.gear_in(master, value)  # type: ignore[arg-type]
    assert gear.error_id == ErrorId.INVALID_GEAR_RATIO
    assert slave.gear_in(master, 2.0).active
    assert slave.set_gear_ratio(value).error_id == ErrorId.INVALID_GEAR_RATIO  # type: ignore
    assert slave.set_gear_ratio(1.0).done


@pytest.mark.parametrize("value", BAD)
def test_write_parameter_refuses_a_value_that_is_no_finite_number(value: object) -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    write = MC_WriteParameter(axis)
    write(enable=True, parameter_number=om.AxisPara.AxisVeloMax, value=value)
    assert write.error and write.error_id == ErrorId.INVALID_PARAMETER_VALUE
    assert axis.parameters.max_velocity == 1000.0
    write(enable=False)
    write(enable=True, parameter_number=om.AxisPara.AxisVeloMax, value=500.0)
    assert not write.error and axis.parameters.max_velocity == 500.0


# -- CA groups (TF5410) ----------------------------------------------------------------------------


@pytest.mark.parametrize("field", ["rail_length", "default_gap", "default_velocity",
                                   "default_jerk"])
@pytest.mark.parametrize("value", BAD)
def test_ca_group_parameters(field: str, value: object) -> None:
    rt = om.Runtime()
    parameters = CaGroupParameters()
    with refused(field):
        CaGroup(rt, "ca", parameters, **{field: value})
    assert getattr(parameters, field) == getattr(CaGroupParameters(), field)  # untouched
    assert CaGroup(rt, "ca", parameters, rail_length=2000.0).parameters.rail_length == 2000.0
    completes_a_move(rt)


@pytest.mark.parametrize("value", BAD)
def test_ca_parts_and_geometry(value: object) -> None:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=3000.0)
    with refused("start"):
        group.tracks.add_part(11, value, 1000.0)  # type: ignore[arg-type]
    with refused("end"):
        group.tracks.add_part(11, 0.0, value)  # type: ignore[arg-type]
    assert group.tracks.add_part(11, 0.0, 1000.0).length == 1000.0
    with refused("StarterKitGeometry.rail_offset"):
        StarterKitGeometry(rail_offset=value)  # type: ignore[arg-type]
    with refused("MoverTemplate.y_shift"):
        MoverTemplate(1, y_shift=value)  # type: ignore[arg-type]
    assert MoverTemplate(1, y_shift=50.0).y_shift == 50.0


@pytest.mark.parametrize(("field", "error_id"), [("position", ErrorId.INVALID_POSITION),
                                                 ("velocity", ErrorId.INVALID_VELOCITY),
                                                 ("gap", ErrorId.INVALID_GAP)])
@pytest.mark.parametrize("value", BAD)
def test_ca_moves_answer_a_bad_number_with_their_error_id(field: str, error_id: ErrorId,
                                                          value: object) -> None:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=3000.0)
    axes = []
    for ident, position in enumerate((0.0, 500.0), 1):
        axis = rt.add_axis(f"m{ident}", position=position)
        axis.power()
        MC_AddAxisToGroup(group)(execute=True, axis=axis, ident_in_group=UDINT_TO_IDENTINGROUP(
            ident))
        axes.append(axis)
    MC_GroupEnable(group)(execute=True)
    bad = MC_MoveAbsoluteCA(axes[0])
    bad(execute=True, **{"position": 100.0, "velocity": 100.0, field: value})
    rt.step()
    bad()
    assert bad.error and bad.error_id == error_id
    move = MC_MoveAbsoluteCA(axes[0])
    move(execute=True, position=100.0, velocity=100.0)
    while not move.done:
        assert not move.error, move.message
        rt.step()
        move()
    assert axes[0].position == pytest.approx(100.0)


# -- coordinated motion (PLCopen Part 4) -----------------------------------------------------------


@pytest.mark.parametrize("value", BAD)
def test_kinematics_numbers(value: object) -> None:
    with refused("l1"):
        Scara(value, 200.0)  # type: ignore[arg-type]
    with refused("upper_arm"):
        DeltaRobot(100.0, 30.0, value, 300.0)  # type: ignore[arg-type]
    with refused(r"offset\[1\]"):
        CartesianGantry(("x", "y"), offset=[0.0, value])  # type: ignore[list-item]
    with refused(r"limits\[0\]\[0\]"):
        Scara(200.0, 200.0, limits=[(value, 90.0), None])  # type: ignore[list-item]
    assert Scara(200.0, 200.0).forward([0.0, 0.0]).tolist() == [400.0, 0.0]


@pytest.mark.parametrize("value", BAD)
def test_path_dynamics_and_frames(value: object) -> None:
    with refused("max_velocity"):
        PathDynamics(max_velocity=value)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="dynamics must be a PathDynamics"):
        AxesGroup(om.Runtime(), "g", dynamics={"velocity": 10.0})  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="a frame needs"):
        Frame(translation=("a", 0.0, 0.0))
    with refused(r"velocity\[0\]"):
        LinearFrame(Frame(), (value, 0.0, 0.0))  # type: ignore[arg-type]
    with refused("start_time"):
        LinearFrame(Frame(), (1.0, 0.0, 0.0), value)  # type: ignore[arg-type]
    assert LinearFrame(Frame(), (1.0, 0.0, 0.0))(2.0).frame.translation.tolist() == [
        2.0, 0.0, 0.0]


@pytest.mark.parametrize("value", BAD)
def test_a_group_move_answers_a_bad_coordinate_with_invalid_position(value: object) -> None:
    rt = om.Runtime()
    group = AxesGroup(rt, "g", PathDynamics())
    for ident in (1, 2):
        axis = rt.add_axis(f"a{ident}")
        axis.power()
        assert group.add_axis(axis, ident).done
    assert group.enable().done
    bad = group.move_linear_absolute([value, 10.0], velocity=100.0)
    rt.step()
    assert bad.error_id == ErrorId.INVALID_POSITION
    move = group.move_linear_absolute([10.0, 10.0], velocity=100.0)
    rt.run_until(move, timeout=5.0)
    assert move.done and group.acs_set().tolist() == pytest.approx([10.0, 10.0])


# -- planar (TF5430) -------------------------------------------------------------------------------


def stator_field(rt: om.Runtime, columns: int = 4, rows: int = 4) -> MC_PlanarEnvironment:
    """An environment of ``columns`` x ``rows`` stators from (0, 0), its boundary made."""
    environment = MC_PlanarEnvironment(rt)
    for i in range(columns):
        for j in range(rows):
            environment.add_stator(240.0 * i, 240.0 * j)
    environment.create_boundary()
    rt.step()
    return environment


def enabled_mover(rt: om.Runtime, x: float = 120.0, y: float = 120.0) -> MC_PlanarMover:
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x, y)))
    enable = mover.enable()
    rt.run_until(lambda: enable.done, timeout=1.0)
    return mover


def moves_to(rt: om.Runtime, mover: MC_PlanarMover, x: float, y: float) -> None:
    move = mover.move_to_position(PositionXYC(x, y))
    rt.run_until(lambda: move.done or move.error, timeout=10.0)
    assert move.done, move.message
    assert mover.pose[:2] == pytest.approx((x, y))


@pytest.mark.parametrize("coordinate", ["x", "y", "c", "z"])
@pytest.mark.parametrize("value", BAD)
def test_a_mover_start_position_must_be_finite_numbers(coordinate: str, value: object) -> None:
    rt = om.Runtime()
    stator_field(rt)
    start = {"x": 120.0, "y": 120.0, coordinate: value}
    with refused(f"initial_position.{coordinate}"):
        PlanarMoverParameters(initial_position=MoverVector(**start))  # type: ignore[arg-type]
    assert rt.cycle == 1 and not PlanarMoverParameters().initial_position.x
    mover = enabled_mover(rt)
    moves_to(rt, mover, 600.0, 600.0)


@pytest.mark.parametrize(("field", "parameters"), [
    ("mover_width", {"mover_width": "wide"}),
    ("c_coordinate_modulus", {"c_coordinate_modulus": True}),
    ("minimum_position.x", {"minimum_position": MoverVector(NAN, -INF, 0.0, -5.0, -5.0, -15.0)}),
    ("maximum_position.z", {"maximum_position": MoverVector(INF, INF, "6", 5.0, 5.0, 15.0)}),
    ("maximum_position_lag_value.c",
     {"maximum_position_lag_value": MoverVector(5.0, 5.0, 2.0, 2.0, 2.0, NAN)}),
    ("simulation_mode", {"simulation_mode": 1}),
    ("part_oid", {"part_oid": 1.5}),
    ("initial_position", {"initial_position": (120.0, 120.0)}),
])
def test_planar_mover_parameters_name_the_bad_field(field: str,
                                                     parameters: dict[str, Any]) -> None:
    with pytest.raises(ConfigError, match=rf"^{field}: must be"):
        PlanarMoverParameters(**parameters)
    rt = om.Runtime()
    with pytest.raises(ConfigError, match="parameters: must be a PlanarMoverParameters"):
        MC_PlanarMover(rt, parameters)  # type: ignore[arg-type]
    moves_to(rt, enabled_mover(rt), 500.0, 120.0)


@pytest.mark.parametrize("value", BAD)
def test_add_stator_answers_a_bad_corner_with_its_error_id(value: object) -> None:
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    feedback = MC_PlanarFeedback()
    bad = environment.add_stator(value, 0.0, feedback)  # type: ignore[arg-type]
    good = environment.add_stator(0.0, 0.0)
    rt.step()
    assert bad.error and feedback.error_id == ErrorId.PLANAR_INVALID_INPUT
    assert "lower_x: must be a finite number" in bad.message
    assert good.done and environment.mc_to_plc_std.stator_count == 1


@pytest.mark.parametrize("value", BAD)
def test_stator_fields_and_parts_in_python_set_up(value: object) -> None:
    with refused("lower_y"):
        StatorField([(0.0, value)])  # type: ignore[list-item]
    with refused(r"origin\[0\]"):
        StatorField.rectangular(2, 2, origin=(value, 0.0))  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="columns and rows must be ints"):
        StatorField.rectangular(2.5, 2)  # type: ignore[arg-type]
    with refused(r"stators\[1\]\[0\]"):
        Part(0x01010001, [(0.0, 0.0), (value, 0.0)],
             [PartPosition(0x01010000, Pose())])  # type: ignore[list-item]
    with refused("pose.c"):
        PartPosition(0x01010000, Pose(0.0, 0.0, value))  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"positions\[1\]: must be a PartPosition"):
        Part(0x01010001, [(0.0, 0.0)], [(0x01010000, Pose())])  # type: ignore[list-item]
    part = Part(0x01010001, [(0.0, 0.0), (240.0, 0.0)], [PartPosition(0x01010000, Pose())])
    with pytest.raises(ConfigError, match="parts: must be Part objects"):
        PartLayout([0x01010000], [part, 0x01010002])  # type: ignore[list-item]
    assert PartLayout([0x01010000], [part]).parts[0x01010001] is part
    assert len(part.stators) == 2 and len(StatorField.rectangular(2, 2)) == 4


@pytest.mark.parametrize("value", BAD)
def test_track_numbers(value: object) -> None:
    rt = om.Runtime()
    with refused("max_mover_width"):
        MC_PlanarTrack(rt, max_mover_width=value)  # type: ignore[arg-type]
    with refused(r"collision_ranges\[1\]"):
        MC_PlanarTrack(rt, collision_ranges=(100.0, value))  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="part_oid must be an object id"):
        MC_PlanarTrack(rt, part_oid="part")  # type: ignore[arg-type]
    track = MC_PlanarTrack(rt)
    bad = track.append_line(PositionXYC(value, 0.0), PositionXYC(500.0, 0.0))  # no exception
    good = track.append_line(PositionXYC(0.0, 0.0), PositionXYC(500.0, 0.0))
    rt.step()
    assert bad.error_id == ErrorId.PLANAR_INVALID_INPUT and "x: must be a finite" in bad.message
    assert good.done and track.get_length() == pytest.approx(500.0)


def test_a_trail_holds_tracks_only() -> None:
    rt = om.Runtime()
    trail = MC_PlanarTrackTrail()
    with pytest.raises(TypeError, match="a trail holds MC_PlanarTrack objects"):  # D-142
        trail.add_track(0x05120010)  # type: ignore[arg-type]
    assert trail.add_track(enabled_loop(rt)) and not trail.error


@pytest.mark.parametrize("value", BAD)
def test_track_commands_answer_a_bad_number_with_their_error_id(value: object) -> None:
    rt = om.Runtime()
    loop = enabled_loop(rt)
    mover = enabled_mover(rt, 0.0, 0.0)
    join_all(rt, loop, mover)
    master = rt.add_axis("master")
    master.power()
    trail = MC_PlanarTrackTrail()
    assert trail.add_track(loop)
    commands = [mover.move_on_track(None, value),  # type: ignore[arg-type]
                mover.gear_in_pos_on_track(master, trail, value, 100.0, loop),  # type: ignore
                mover.gear_in_pos_on_track(master, trail, 100.0, value, loop)]  # type: ignore
    rt.run(0.003)
    assert [c.error_id for c in commands] == [ErrorId.PLANAR_INVALID_INPUT] * 3
    move = mover.move_on_track(None, 500.0)
    rt.run_until(lambda: move.done, timeout=5.0)


# -- a planar mover goes only where stators carry it (D-163) ---------------------------------------


def assert_off_stators(command: Any, feedback: MC_PlanarFeedback,
                       environment: MC_PlanarEnvironment) -> None:
    """Refused as a group refuses a move over the edge (§6.7.2): 33158, the environment."""
    assert command.error and feedback.error and not feedback.busy
    assert feedback.error_id == ErrorId.PLANAR_COLLISION == 33158
    assert feedback.object_info.object_type is PlanarObjectType.ENVIRONMENT
    assert feedback.object_info.id == environment.oid
    assert "no stator carries the mover" in command.message


@pytest.mark.parametrize("target", [(5000.0, 120.0), (120.0, -130.0), (1000.0, 1000.0)])
def test_an_ungrouped_mover_is_not_sent_off_the_stators(target: tuple[float, float]) -> None:
    rt = om.Runtime()
    environment = stator_field(rt)
    mover = enabled_mover(rt)
    feedback = MC_PlanarFeedback()
    move = mover.move_to_position(PositionXYC(*target), feedback=feedback)
    rt.run(0.002)
    assert_off_stators(move, feedback, environment)
    assert mover.pose[:2] == (120.0, 120.0) and mover.state is PlanarState.ENABLED
    moves_to(rt, mover, 840.0, 840.0)  # the far corner's centre: on the stators


def test_a_path_over_a_gap_between_stators_is_refused() -> None:
    """Both ends on stators of an L, the straight line between them over none."""
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    for corner in ((0.0, 0.0), (240.0, 0.0), (480.0, 0.0), (0.0, 240.0), (0.0, 480.0)):
        environment.add_stator(*corner)
    environment.create_boundary()
    rt.step()
    mover = enabled_mover(rt, 600.0, 120.0)
    feedback = MC_PlanarFeedback()
    move = mover.move_to_position(PositionXYC(120.0, 600.0), feedback=feedback)
    rt.run(0.002)
    assert_off_stators(move, feedback, environment)
    moves_to(rt, mover, 120.0, 120.0)  # round the corner, on the stators
    moves_to(rt, mover, 120.0, 600.0)


def test_a_group_without_the_environment_keeps_its_movers_on_the_stators() -> None:
    rt = om.Runtime()
    environment = stator_field(rt)
    group = MC_PlanarGroup(rt)
    group.enable()
    mover = enabled_mover(rt)
    join = mover.add_to_group(group)
    rt.run_until(lambda: join.done, timeout=1.0)
    feedback = MC_PlanarFeedback()
    move = mover.move_to_position(PositionXYC(5000.0, 120.0), feedback=feedback)
    rt.run(0.002)
    assert_off_stators(move, feedback, environment)
    moves_to(rt, mover, 600.0, 120.0)


def test_leaving_a_track_for_a_point_off_the_stators_is_refused() -> None:
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    for i in range(8):
        for j in range(5):
            environment.add_stator(-480.0 + 240.0 * i, -240.0 + 240.0 * j)
    environment.create_boundary()
    loop = enabled_loop(rt)
    mover = enabled_mover(rt, 0.0, 0.0)
    join_all(rt, loop, mover)
    feedback = MC_PlanarFeedback()
    leave = mover.leave_track(PositionXYC(0.0, -400.0), feedback=feedback)
    rt.run(0.002)
    assert_off_stators(leave, feedback, environment)
    leave = mover.leave_track(PositionXYC(0.0, -120.0))
    rt.run_until(lambda: leave.done or leave.error, timeout=5.0)
    assert leave.done, leave.message


def test_a_mover_off_every_stator_cannot_be_enabled() -> None:
    rt = om.Runtime()
    environment = stator_field(rt)
    mover = MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(3000.0, 0.0)))
    feedback = MC_PlanarFeedback()
    enable = mover.enable(feedback)
    rt.run(0.005)
    assert_off_stators(enable, feedback, environment)
    assert mover.state is PlanarState.DISABLED and not mover.error
    placed = mover.set_position(PositionXYC(360.0, 360.0))  # Disabled: it may be put anywhere
    rt.step()
    assert placed.done
    enable = mover.enable()
    rt.run_until(lambda: enable.done, timeout=1.0)
    moves_to(rt, mover, 600.0, 120.0)


def test_without_a_boundary_the_stators_are_unknown_and_nothing_is_checked() -> None:
    """Pure simulation: no environment, or stators without CreateBoundary (§6.4)."""
    rt = om.Runtime()
    mover = enabled_mover(rt)
    moves_to(rt, mover, 5000.0, 120.0)
    environment = MC_PlanarEnvironment(rt)
    environment.add_stator(0.0, 0.0)
    rt.step()
    moves_to(rt, mover, -3000.0, 0.0)
    environment.create_boundary()
    rt.step()
    feedback = MC_PlanarFeedback()
    move = mover.move_to_position(PositionXYC(100.0, 100.0), feedback=feedback)
    rt.run(0.002)
    assert_off_stators(move, feedback, environment)  # it stands off them: no way back
    halt = mover.halt()  # a halt is never refused (D-084)
    rt.run(0.002)
    assert halt.done
