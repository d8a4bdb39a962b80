"""Options, constraints, status structures and mover parameters against the manual (TF5430
§7.2.1.2, §6.1.1, §6.1.9). Values the manual leaves out ("...") are ours: only their
consistency is tested here.
"""

from __future__ import annotations

import math
import re
from dataclasses import FrozenInstanceError, fields, replace
from typing import Any

import pytest

from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.core.special_values import MC_DEFAULT, MC_IGNORE, MC_MAXIMUM
from openmotion.planar.enums import (
    CoordinateMode,
    ExternalSetPositionMode,
    ModuloDirection,
    MoverCommandMode,
    PlanarState,
    SyncDirections,
    TrackOperationMode,
)
from openmotion.planar.options import (
    CDT_MCTOPLC_PLANAR_ENVIRONMENT_STD,
    CDT_MCTOPLC_PLANAR_GROUP_STD,
    CDT_MCTOPLC_PLANAR_MOVER,
    CDT_MCTOPLC_PLANAR_TRACK_STD,
    DynamicConstraint_PathXY,
    IPlcDynamicConstraint,
    MoverVector,
    PlanarMoverParameters,
    ST_AdoptTrackOrientationOptions,
    ST_EndAtTrackAdvancedOptions,
    ST_ExternalSetpointGenerationOptions,
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    ST_JoinTrackOptions,
    ST_LeaveTrackOptions,
    ST_MoveCOptions,
    ST_MoveOnTrackOptions,
    ST_MoveToPositionOptions,
    ST_StartFromTrackAdvancedOptions,
    command_dynamics,
)
from openmotion.trajectory.plan import Limits

D, SYNC = ModuloDirection, SyncDirections

#: struct -> (section, [(manual field, manual default)]) in the manual's order
MANUAL_STRUCTS: dict[type, tuple[str, list[tuple[str, Any]]]] = {
    ST_AdoptTrackOrientationOptions: ("7.2.1.2.4", [
        ("additionalTurns", 0), ("direction", D.SHORTEST_WAY)]),
    ST_EndAtTrackAdvancedOptions: ("7.2.1.2.5", [
        ("thisTrackPartPositionIndex", 0), ("otherTrackPartPositionIndex", 0),
        ("linkOnlyInSpecifiedPartPositions", False)]),
    ST_ExternalSetpointGenerationOptions: ("7.2.1.2.6", [
        ("mode", ExternalSetPositionMode.ABSOLUTE)]),
    ST_GearInPosOnTrackOptions: ("7.2.1.2.7", [
        ("gap", 200.0), ("inSyncToleranceDistance", 0.0),
        ("directionSlaveSyncPosition", D.NON_MODULO), ("moduloToleranceSlaveSyncPosition", 0.0),
        ("allowedSlaveSyncDirections", SYNC.POSITIVE)]),
    ST_GearInPosOnTrackWithMasterMoverOptions: ("7.2.1.2.8", [
        ("gap", 200.0), ("inSyncToleranceDistance", 0.0),
        ("directionSlaveSyncPosition", D.NON_MODULO), ("moduloToleranceSlaveSyncPosition", 0.0),
        ("directionMasterSyncPosition", D.NON_MODULO),
        ("moduloToleranceMasterSyncPosition", 0.0),
        ("allowedSlaveSyncDirections", SYNC.POSITIVE), ("followMover", False)]),
    ST_JoinTrackOptions: ("7.2.1.2.9", [("useOrientation", True)]),
    ST_LeaveTrackOptions: ("7.2.1.2.10", [("useOrientation", True)]),
    ST_MoveCOptions: ("7.2.1.2.11", [("additionalTurns", 0), ("direction", D.NON_MODULO)]),
    ST_MoveOnTrackOptions: ("7.2.1.2.12", [
        ("gap", 200.0), ("direction", D.NON_MODULO), ("additionalTurns", 0),
        ("moduloTolerance", 0.0)]),
    ST_MoveToPositionOptions: ("7.2.1.2.13", [("useOrientation", True)]),
    ST_StartFromTrackAdvancedOptions: ("7.2.1.2.14", [
        ("thisTrackPartPositionIndex", 0), ("otherTrackPartPositionIndex", 0),
        ("linkOnlyInSpecifiedPartPositions", False)]),
}


def snake(name: str) -> str:
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


@pytest.mark.parametrize("struct", MANUAL_STRUCTS, ids=lambda s: s.__name__)
def test_fields_and_defaults_are_the_manuals(struct: type):
    section, manual = MANUAL_STRUCTS[struct]
    assert [f.name for f in fields(struct)] == [snake(name) for name, _ in manual], section
    instance = struct()
    for name, default in manual:
        value = getattr(instance, snake(name))
        assert value == default and type(value) is type(default), f"§{section} {name}"
    instance.check()  # the defaults are valid


def test_options_are_frozen_and_misspelt_fields_fail_at_once():
    with pytest.raises(FrozenInstanceError):
        ST_MoveOnTrackOptions().gap = 10.0  # type: ignore[misc]
    with pytest.raises(TypeError, match="additonal_turns"):
        ST_MoveCOptions(additonal_turns=1)  # type: ignore[call-arg]


def test_the_two_connection_options_are_distinct_types():
    assert ST_StartFromTrackAdvancedOptions() != ST_EndAtTrackAdvancedOptions()


VALID = [
    ST_MoveCOptions(2, D.POSITIVE), ST_MoveCOptions(1, D.NEGATIVE),
    ST_AdoptTrackOrientationOptions(0, D.NON_MODULO),
    ST_MoveOnTrackOptions(50.0, D.SHORTEST_WAY, 0, 5.0), ST_MoveOnTrackOptions(0.0, 1, 3, 1.0),
    ST_GearInPosOnTrackOptions(direction_slave_sync_position=D.POSITIVE,
                               modulo_tolerance_slave_sync_position=2.0,
                               allowed_slave_sync_directions=SYNC.BOTH),
    ST_GearInPosOnTrackWithMasterMoverOptions(direction_master_sync_position=D.SHORTEST_WAY,
                                              modulo_tolerance_master_sync_position=1.0),
    ST_ExternalSetpointGenerationOptions(ExternalSetPositionMode.RELATIVE),
    ST_StartFromTrackAdvancedOptions(1, 2, True),
]


@pytest.mark.parametrize("options", VALID, ids=repr)
def test_valid_options_pass(options: Any):
    options.check()


INVALID = [  # (options, error id, words of the message)
    (ST_MoveCOptions(1, D.NON_MODULO), ErrorId.INVALID_MODULO_OPTIONS, "Positive or Negative"),
    (ST_MoveCOptions(1, D.SHORTEST_WAY), ErrorId.INVALID_MODULO_OPTIONS, "not SHORTEST_WAY"),
    (ST_AdoptTrackOrientationOptions(1), ErrorId.INVALID_MODULO_OPTIONS, "additional_turns"),
    (ST_MoveCOptions(-1, D.POSITIVE), ErrorId.PLANAR_INVALID_INPUT, "UDINT"),
    (ST_MoveCOptions(2**32, D.POSITIVE), ErrorId.PLANAR_INVALID_INPUT, "UDINT"),
    (ST_MoveCOptions(1.0, D.POSITIVE), ErrorId.PLANAR_INVALID_INPUT, "UDINT"),  # type: ignore
    (ST_MoveCOptions(0, 7), ErrorId.PLANAR_INVALID_INPUT, "not an MC_DIRECTION"),  # type: ignore
    (ST_MoveOnTrackOptions(modulo_tolerance=1.0), ErrorId.INVALID_MODULO_OPTIONS,
     "must be 0 with NonModulo"),
    (ST_MoveOnTrackOptions(gap=-1.0), ErrorId.PLANAR_INVALID_INPUT, "gap"),
    (ST_MoveOnTrackOptions(gap=math.nan), ErrorId.PLANAR_INVALID_INPUT, "gap"),
    (ST_MoveOnTrackOptions(direction=D.POSITIVE, modulo_tolerance=-1.0),
     ErrorId.PLANAR_INVALID_INPUT, "modulo_tolerance"),
    (ST_GearInPosOnTrackOptions(in_sync_tolerance_distance=math.inf),
     ErrorId.PLANAR_INVALID_INPUT, "in_sync_tolerance_distance"),
    (ST_GearInPosOnTrackOptions(modulo_tolerance_slave_sync_position=1.0),
     ErrorId.INVALID_MODULO_OPTIONS, "slave sync position"),
    (ST_GearInPosOnTrackOptions(allowed_slave_sync_directions=0),  # type: ignore[arg-type]
     ErrorId.PLANAR_INVALID_INPUT, "MC_SYNC_DIRECTIONS"),
    (ST_GearInPosOnTrackWithMasterMoverOptions(gap=-5.0), ErrorId.PLANAR_INVALID_INPUT, "gap"),
    (ST_GearInPosOnTrackWithMasterMoverOptions(modulo_tolerance_master_sync_position=1.0),
     ErrorId.INVALID_MODULO_OPTIONS, "master sync position"),
    (ST_ExternalSetpointGenerationOptions(ExternalSetPositionMode.NONE),
     ErrorId.PLANAR_INVALID_INPUT, "Absolute or Relative"),
    (ST_EndAtTrackAdvancedOptions(-1), ErrorId.PLANAR_INVALID_INPUT,
     "this_track_part_position_index"),
    (ST_StartFromTrackAdvancedOptions(0, True), ErrorId.PLANAR_INVALID_INPUT,  # type: ignore
     "other_track_part_position_index"),
]


@pytest.mark.parametrize(("options", "error_id", "words"), INVALID, ids=lambda v: repr(v)[:60])
def test_invalid_options_are_rejected(options: Any, error_id: ErrorId, words: str):
    with pytest.raises(CommandRejected, match=re.escape(words)) as rejected:
        options.check()
    assert rejected.value.error_id is error_id


# -- dynamic constraints (§6.1.9) ------------------------------------------------------------------

DEFAULT = Limits(2000.0, 10000.0, 10000.0, 200000.0)
MAXIMUM = Limits(4000.0, 20000.0, 20000.0, 400000.0)


def test_no_constraint_means_the_movers_default_dynamics():
    warnings: list[str] = []
    assert command_dynamics(None, DEFAULT, MAXIMUM, warnings) == DEFAULT and warnings == []


def test_path_constraint_takes_its_values_and_defaults_the_rest():
    constraint = DynamicConstraint_PathXY(velocity=500.0, acceleration=MC_DEFAULT,
                                          jerk=MC_IGNORE)
    assert isinstance(constraint, IPlcDynamicConstraint)
    warnings: list[str] = []
    assert command_dynamics(constraint, DEFAULT, MAXIMUM, warnings) == Limits(
        500.0, 10000.0, 10000.0, 400000.0)
    assert warnings == []
    assert DynamicConstraint_PathXY().resolve(DEFAULT, MAXIMUM, []) == DEFAULT


def test_values_above_the_maximum_are_clipped_with_a_warning():
    """§6.1.9: reduced to the mover's maximum, a warning, and the command still runs."""
    warnings: list[str] = []
    limits = DynamicConstraint_PathXY(9000.0, 1.0e5, 50.0, 10.0).resolve(DEFAULT, MAXIMUM,
                                                                         warnings)
    assert limits == Limits(4000.0, 20000.0, 50.0, 10.0)
    assert warnings == [
        "constraint velocity 9000 clipped to the mover maximum 4000 (§6.1.9)",
        "constraint acceleration 100000 clipped to the mover maximum 20000 (§6.1.9)",
    ]


@pytest.mark.parametrize("value", [0.0, -1.0, math.nan, math.inf, MC_MAXIMUM, True, "fast"])
def test_invalid_constraint_values_are_rejected(value: Any):
    with pytest.raises(CommandRejected, match="constraint deceleration") as rejected:
        DynamicConstraint_PathXY(deceleration=value).resolve(DEFAULT, MAXIMUM, [])
    assert rejected.value.error_id is ErrorId.PLANAR_INVALID_INPUT


# -- status structures -----------------------------------------------------------------------------


def test_mover_status_defaults():
    status = CDT_MCTOPLC_PLANAR_MOVER()
    assert (status.std.mover_oid, status.std.group_oid, status.std.error_code) == (0, 0, 0)
    assert status.std.state is PlanarState.DISABLED
    assert status.std.command_mode is MoverCommandMode.FREE_MOVEMENT
    assert (status.std.busy.busy_mover, status.std.busy.busy_xyc) == (False, False)
    assert status.set.set_pos == MoverVector(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert (status.set.dc_time_stamp, status.set.physical_area_id) == (0, 0)
    assert status.act.act_pos == MoverVector()
    assert {f.name for f in fields(status.coord_mode)} == {
        "xy_coordinate_mode", "z_coordinate_mode", "a_coordinate_mode", "b_coordinate_mode",
        "c_coordinate_mode"}
    assert all(getattr(status.coord_mode, f.name) is CoordinateMode.INDEPENDENT
               for f in fields(status.coord_mode))
    track = status.set_on_track
    assert (track.set_pos, track.set_velo, track.set_acc, track.set_jerk, track.track_oid) == (
        0.0, 0.0, 0.0, 0.0, 0)


def test_track_group_and_environment_status_fields():
    """The watch windows of §6.2.10, §6.3.1 and §6.4.2, in their order."""
    assert [f.name for f in fields(CDT_MCTOPLC_PLANAR_TRACK_STD)] == [
        "track_oid", "group_oid", "state", "operation_mode", "mover_count_on_track",
        "moving_mover_count"]
    assert CDT_MCTOPLC_PLANAR_TRACK_STD().operation_mode is TrackOperationMode.UNINITIALIZED
    assert [f.name for f in fields(CDT_MCTOPLC_PLANAR_GROUP_STD)] == [
        "group_oid", "state", "group_object_count"]
    assert [f.name for f in fields(CDT_MCTOPLC_PLANAR_ENVIRONMENT_STD)] == [
        "environment_oid", "group_oid", "stator_count", "boundary_element_count"]


def test_status_snapshots_are_frozen():
    with pytest.raises(FrozenInstanceError):
        CDT_MCTOPLC_PLANAR_TRACK_STD().state = PlanarState.ENABLED  # type: ignore[misc]


# -- mover init parameters (§6.1.1) ----------------------------------------------------------------


def test_mover_parameters_the_manual_prints():
    p = PlanarMoverParameters()
    assert (p.mover_width, p.mover_height) == (155.0, 155.0)
    assert (p.c_coordinate_modulus, p.c_coordinate_modulo_tolerance_window) == (360.0, 0.0)
    assert p.position_lag_monitoring_enabled is True
    assert p.simulation_mode is False  # the manual's default is hardware
    assert p.initial_position == MoverVector() and p.part_oid == 0


def test_c_limits_give_the_windows_of_the_manual():
    """§4.2 with the limits inferred from §6.1.8 (a MoveC to 20° leaves the first window)."""
    p = PlanarMoverParameters()
    assert (p.minimum_position.c, p.maximum_position.c) == (-15.0, 15.0)
    assert p.c_windows.windows() == ((-15.0, 15.0), (75.0, 105.0), (165.0, 195.0),
                                     (255.0, 285.0))
    assert (p.minimum_position.x, p.maximum_position.y) == (-math.inf, math.inf)  # §6.7.1


def test_examples_lie_within_the_limits():
    """§6.1.5 moves z to 5 mm, a to 1° and b to -1°."""
    p = PlanarMoverParameters()
    for name, target in (("z", 5.0), ("a", 1.0), ("b", -1.0)):
        assert getattr(p.minimum_position, name) <= target <= getattr(p.maximum_position, name)


@pytest.mark.parametrize("group", ["xy", "c", "z", "a", "b"])
def test_default_dynamics_lie_within_the_maxima(group: str):
    p = PlanarMoverParameters()
    default = getattr(p, f"default_dynamic_{group}")
    maximum = getattr(p, f"maximum_dynamic_{group}")
    assert all(0 < getattr(default, f.name) <= getattr(maximum, f.name) for f in fields(Limits))


BAD_PARAMETERS = [
    ({"mover_width": 0.0}, "mover_width"),
    ({"mover_height": math.nan}, "mover_height"),
    ({"c_coordinate_modulus": -360.0}, "c_coordinate_modulus"),
    ({"c_coordinate_modulo_tolerance_window": 180.0}, "c_coordinate_modulo_tolerance_window"),
    ({"c_coordinate_modulo_tolerance_window": -1.0}, "c_coordinate_modulo_tolerance_window"),
    ({"maximum_dynamic_z": Limits(0.0, 1.0, 1.0, 1.0)}, "maximum_dynamic_z.velocity"),
    ({"default_dynamic_xy": Limits(5000.0, 1.0, 1.0, 1.0)}, "default_dynamic_xy.velocity"),
    ({"default_dynamic_c": Limits(1.0, 1.0, 1.0, 0.0)}, "default_dynamic_c.jerk"),
    ({"minimum_position": MoverVector(c=20.0)}, "minimum_position.c"),
    ({"minimum_position": MoverVector(c=-math.inf)}, "minimum_position.c"),
    ({"maximum_position_lag_value": MoverVector(y=-1.0)}, "maximum_position_lag_value.y"),
    ({"maximum_position_lag_filter_time": MoverVector(b=math.inf)},
     "maximum_position_lag_filter_time.b"),
]


@pytest.mark.parametrize(("change", "field"), BAD_PARAMETERS, ids=[f for _, f in BAD_PARAMETERS])
def test_bad_parameters_name_the_field(change: dict[str, Any], field: str):
    with pytest.raises(ConfigError, match=rf"^{re.escape(field)}:"):
        replace(PlanarMoverParameters(), **change)
