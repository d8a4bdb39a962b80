"""Administration blocks (TcMC §4; rules 100-115, 126-127), MC_Stop (§3.15; rules 68-76) and
MC_Home (§3.14; rules 64-67).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

import openmotion as om
from openmotion.plcopen import (
    MC_ChangeDynParam,
    MC_GearIn,
    MC_GearOut,
    MC_Home,
    MC_MoveAbsolute,
    MC_MoveRelative,
    MC_MoveVelocity,
    MC_Power,
    MC_ReadActualPosition,
    MC_ReadAxisError,
    MC_ReadBoolParameter,
    MC_ReadParameter,
    MC_ReadParameterSet,
    MC_ReadStatus,
    MC_Reset,
    MC_SetActualPosition,
    MC_SetOverride,
    MC_SetReferenceFlag,
    MC_Stop,
    MC_WriteBoolParameter,
    MC_WriteParameter,
)

ErrorId = om.ErrorId
P = om.AxisPara
S = om.AxisState
R = om.ReferenceMode
CYCLE = 0.001
LAG = om.DriveModel(model="lag", time_constant=0.01, dead_time=0.002)


def powered_axis(**overrides: Any) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x", **overrides)
    assert axis.power()
    return rt, axis


class Trace:
    def __init__(self) -> None:
        self.p: list[float] = []
        self.v: list[float] = []
        self.a: list[float] = []

    def sample(self, axis: om.Axis) -> None:
        self.p.append(axis.set_position)
        self.v.append(axis.set_velocity)
        self.a.append(axis.set_acceleration)

    def max_dv(self) -> float:
        return max(abs(b - a) for a, b in zip(self.v, self.v[1:], strict=False))

    def peak_jerk(self) -> float:
        return max(abs(b - a) for a, b in zip(self.a, self.a[1:], strict=False)) / CYCLE


def run(rt: om.Runtime, axis: om.Axis, program: Callable[[], Any],
        until: Callable[[], bool], max_cycles: int = 20000) -> Trace:
    """Call ``program`` every cycle (then sample) until ``until()``; step in between."""
    trace = Trace()
    for _ in range(max_cycles):
        program()
        trace.sample(axis)
        if until():
            return trace
        rt.step()
    raise AssertionError(f"not reached within {max_cycles} cycles")


def cruise(rt: om.Runtime, axis: om.Axis, velocity: float = 200.0, **dynamics: Any):
    move = MC_MoveVelocity(axis)
    run(rt, axis, lambda: move(execute=True, velocity=velocity, **dynamics),
        lambda: move.in_velocity)
    return move


# -- MC_Power (§4.1; rules 100-102) ----------------------------------------------------------


def test_power_status_follows_enable() -> None:
    """Rule 100: Status TRUE only while Enable is TRUE and the drive is ready."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    power = MC_Power(axis)
    power(enable=False)
    assert not power.status and axis.state is S.DISABLED
    power(enable=True)
    assert power.status and not power.error and axis.state is S.STANDSTILL
    for _ in range(10):
        rt.step()
        power(enable=True)
        assert power.status
    power(enable=False)
    assert not power.status and axis.state is S.DISABLED


def test_power_off_aborts_the_move_and_disables() -> None:
    """Rule 101 [P]: Enable FALSE → Status FALSE, the running move is aborted, and move
    commands are refused with AXIS_DISABLED."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    power, move = MC_Power(axis), MC_MoveAbsolute(axis)
    run(rt, axis, lambda: (power(enable=True), move(execute=True, position=500.0,
                                                    velocity=100.0)),
        lambda: axis.set_position > 10.0)
    power(enable=False)
    move(execute=True)
    assert move.command_aborted and not move.done
    assert axis.state is S.DISABLED and axis.set_velocity == 0.0
    frozen = axis.set_position
    for _ in range(50):
        rt.step()
        power(enable=False)
    assert axis.set_position == frozen
    again = MC_MoveRelative(axis)
    again(execute=True, distance=5.0, velocity=10.0)
    assert again.error and again.error_id == ErrorId.AXIS_DISABLED


def test_power_with_a_drive_that_is_not_ready() -> None:
    """Rule 100: Status includes the drive's ready signal; not ready → error, disabled."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.drive_ready = False
    power = MC_Power(axis)
    power(enable=True)
    assert not power.status
    assert power.error and power.error_id == ErrorId.DRIVE_NOT_READY
    assert axis.state is S.DISABLED
    axis.drive_ready = True
    power(enable=True)
    assert power.status and not power.error and axis.state is S.STANDSTILL


def test_power_override_50_halves_the_velocities() -> None:
    """Rule 102: Override 50 % → all profile velocities halved."""
    results = {}
    for override in (100.0, 50.0):
        rt = om.Runtime()
        axis = rt.add_axis("x")
        power, move = MC_Power(axis), MC_MoveAbsolute(axis)
        trace = run(rt, axis, lambda power=power, move=move, override=override: (
            power(enable=True, override=override),
            move(execute=True, position=400.0, velocity=200.0)), lambda move=move: move.done)
        assert axis.override == pytest.approx(override / 100.0)
        assert axis.override_value == round(override * 10_000)  # the PlcToNc DWORD (§4.1)
        results[override] = (max(trace.v), len(trace.v))
    assert results[100.0][0] == pytest.approx(200.0, rel=1e-9)
    assert results[50.0][0] == pytest.approx(100.0, rel=1e-9)
    assert results[50.0][1] > 1.8 * results[100.0][1]  # takes about twice as long
    assert axis.override_value == 500_000
    rt, axis = powered_axis()
    power, velocity = MC_Power(axis), MC_MoveVelocity(axis)
    run(rt, axis, lambda: (power(enable=True, override=50.0),
                           velocity(execute=True, velocity=300.0)),
        lambda: velocity.in_velocity)
    assert axis.set_velocity == pytest.approx(150.0, rel=1e-12)


@pytest.mark.parametrize("override", [-1.0, 100.5, float("nan")])
def test_power_bad_override_is_an_error(override: float) -> None:
    rt, axis = powered_axis()
    power = MC_Power(axis)
    power(enable=True, override=override)
    assert power.error and power.error_id == ErrorId.INVALID_OVERRIDE
    assert power.status and axis.override == 1.0


# -- MC_Reset (§4.2; rule 103) --------------------------------------------------------------


def _following_error_fault(rt: om.Runtime, axis: om.Axis) -> MC_MoveVelocity:
    move = MC_MoveVelocity(axis)
    run(rt, axis, lambda: move(execute=True, velocity=300.0),
        lambda: axis.state is S.ERROR_STOP, max_cycles=3000)
    return move


def test_reset_waits_for_rest_then_clears_the_error_and_takes_the_actual_position() -> None:
    """Rule 103, TcMC §4.2/§3.5: MC_Reset clears ErrorStop (once the error reaction has
    stopped the axis) and sets set position := actual position (following error cleared)."""
    rt = om.Runtime()
    axis = rt.add_axis("x", drive=om.DriveModel(model="lag", time_constant=0.05,
                                                dead_time=0.002), max_position_lag=2.0)
    axis.power()
    _following_error_fault(rt, axis)
    assert axis.set_velocity != 0.0  # the error reaction still brakes
    reset, status = MC_Reset(axis), MC_ReadStatus(axis)
    reset(execute=True)
    assert reset.busy and not reset.done
    actual_at_reset = None
    for _ in range(3000):
        actual = axis.position
        reset(execute=True)
        if reset.done:
            actual_at_reset = actual
            break
        assert axis.state is S.ERROR_STOP
        rt.step()
    assert actual_at_reset is not None
    status(enable=True)
    assert not status.error_stop and status.standstill
    assert axis.axis_error_id == ErrorId.NO_ERROR
    assert axis.set_position == axis.position
    assert axis.following_error == 0.0
    # the set position moved back from where the error reaction stopped it
    assert abs(axis.set_position - actual_at_reset) < 0.5
    move = MC_MoveRelative(axis)  # and the axis is usable again
    start = axis.set_position
    run(rt, axis, lambda: move(execute=True, distance=10.0, velocity=10.0), lambda: move.done)
    assert axis.set_position == pytest.approx(start + 10.0, abs=1e-9)


def test_reset_of_a_powered_off_error_goes_to_disabled() -> None:
    """§1.2 [P]: ErrorStop + Enable FALSE, then MC_Reset → Disabled."""
    rt = om.Runtime()
    axis = rt.add_axis("x", drive=LAG, max_position_lag=1.0)
    axis.power()
    _following_error_fault(rt, axis)
    axis.power(False)
    assert axis.state is S.ERROR_STOP
    reset = MC_Reset(axis)
    run(rt, axis, lambda: reset(execute=True), lambda: reset.done)
    assert axis.state is S.DISABLED


# -- MC_ReadStatus, MC_ReadActualPosition, MC_ReadAxisError (§4.3-4.5; rules 104, 105) -------

FLAGS = ("error_stop", "stopping", "standstill", "discrete_motion", "continuous_motion",
         "homing_busy", "homing", "accelerating", "decelerating", "constant_velocity")


def _flags(status: MC_ReadStatus) -> set[str]:
    return {flag for flag in FLAGS if getattr(status, flag)}


def test_read_status_through_a_move_velocity_and_a_stop() -> None:
    """Rule 105, TcMC §4.4: the state flags and the profile sub-states."""
    rt, axis = powered_axis()
    status, move, stop = MC_ReadStatus(axis), MC_MoveVelocity(axis), MC_Stop(axis)
    status(enable=True)
    assert status.done and _flags(status) == {"standstill"}
    seen = []
    for cycle in range(400):
        move(execute=True, velocity=100.0)
        stop(execute=200 <= cycle < 300)
        status(enable=True)
        flags = frozenset(_flags(status))
        if not seen or seen[-1] != flags:
            seen.append(flags)
        rt.step()
    assert seen == [
        {"continuous_motion"},  # the call that issued it, before the first step
        {"continuous_motion", "accelerating"},
        {"continuous_motion", "constant_velocity"},
        {"stopping", "constant_velocity"},  # the call that issued MC_Stop
        {"stopping", "decelerating"},
        {"stopping"},  # at rest, held by MC_Stop.Execute
        {"standstill"},  # after its falling edge
    ]


def test_read_status_discrete_motion_and_deceleration() -> None:
    rt, axis = powered_axis()
    status, move = MC_ReadStatus(axis), MC_MoveAbsolute(axis)
    seen = []
    run(rt, axis, lambda: (move(execute=True, position=100.0, velocity=100.0),
                           status(enable=True), seen.append(frozenset(_flags(status)))),
        lambda: move.done)
    phases = [flags for k, flags in enumerate(seen) if k == 0 or seen[k - 1] != flags]
    assert phases == [
        {"discrete_motion"},
        {"discrete_motion", "accelerating"},
        {"discrete_motion", "constant_velocity"},
        {"discrete_motion", "decelerating"},
        {"discrete_motion"},  # at the target, waiting for the §7.1 target window time
        {"standstill"},  # Done
    ]
    status(enable=False)
    assert not status.done and not _flags(status)


def test_read_status_synchronized_motion_while_geared() -> None:
    """Rules 105, 92, TcMC §4.4, §3.17, §3.20: MC_ReadStatus on the slave shows
    SynchronizedMotion from the coupling to the decoupling, whatever the master does;
    after MC_GearOut in motion it shows ContinuousMotion at constant velocity."""
    rt = om.Runtime()
    master, slave = rt.add_axis("m"), rt.add_axis("s")
    master.power()
    slave.power()
    status, gear, out = MC_ReadStatus(slave), MC_GearIn(slave), MC_GearOut(slave)
    status(enable=True)
    assert _flags(status) == {"standstill"} and not status.synchronized_motion
    gear(execute=True, master=master, ratio_numerator=1, ratio_denominator=2)
    status(enable=True)
    assert gear.in_gear and status.synchronized_motion and _flags(status) == set()
    master.move_velocity(200.0)
    seen = []
    for _ in range(300):
        rt.step()
        status(enable=True)
        assert status.synchronized_motion and not status.standstill
        seen.append(frozenset(_flags(status)))
    assert seen[0] == {"accelerating"} and seen[-1] == {"constant_velocity"}
    assert slave.set_velocity == pytest.approx(100.0, abs=1e-9)
    out(execute=True)
    rt.step()
    status(enable=True)
    assert out.done and not status.synchronized_motion
    assert _flags(status) == {"continuous_motion", "constant_velocity"}


def test_read_status_error_stop_and_read_axis_error() -> None:
    """Rules 105, 103: Errorstop flag and MC_ReadAxisError's axis_error_id (D-012)."""
    rt = om.Runtime()
    axis = rt.add_axis("x", drive=LAG, max_position_lag=1.0)
    axis.power()
    status, error = MC_ReadStatus(axis), MC_ReadAxisError(axis)
    error(enable=True)
    assert error.done and error.axis_error_id == ErrorId.NO_ERROR and not error.error
    _following_error_fault(rt, axis)
    status(enable=True)
    error(enable=True)
    assert status.error_stop and not status.continuous_motion
    assert error.axis_error_id == ErrorId.FOLLOWING_ERROR and not error.error
    assert error.axis_error_message
    reset = MC_Reset(axis)
    run(rt, axis, lambda: reset(execute=True), lambda: reset.done)
    error(enable=True)
    assert error.axis_error_id == ErrorId.NO_ERROR


def test_read_actual_position_is_the_actual_position() -> None:
    """Rule 104, TcMC §4.3: the actual (encoder) position, not the set position."""
    rt = om.Runtime()
    axis = rt.add_axis("x", drive=LAG)
    axis.power()
    read, move = MC_ReadActualPosition(axis), MC_MoveVelocity(axis)
    for _ in range(100):
        move(execute=True, velocity=100.0)
        read(enable=True)
        assert read.done and read.position == axis.position
        rt.step()
    assert read.position != axis.set_position  # the lag drive trails


def test_read_status_homing_busy_while_homing_then_homing_once_referenced() -> None:
    """TcMC §4.4 (D-192): Homing is TRUE once the axis is referenced; the reference
    search itself is the Homing state, shown by ``homing_busy``."""
    rt, axis = powered_axis(position=50.0, reference_cam=(10.0, 20.0))
    home, status = MC_Home(axis), MC_ReadStatus(axis)
    status(enable=True)
    assert not status.homing and not status.homing_busy
    home(execute=True)
    status(enable=True)
    assert status.homing_busy and not status.homing and not status.standstill
    run(rt, axis, lambda: (home(execute=True), status(enable=True)), lambda: home.done)
    assert status.homing and not status.homing_busy and status.standstill


def test_read_status_homing_follows_the_reference_flag() -> None:
    """TcMC §4.4 with §4.15 (D-192): MC_SetReferenceFlag(TRUE) makes Homing TRUE,
    FALSE takes it back; the state flags are untouched."""
    rt, axis = powered_axis()
    status, flag = MC_ReadStatus(axis), MC_SetReferenceFlag(axis)
    status(enable=True)
    assert not status.homing
    for value in (True, False):
        flag(execute=True, reference_flag=value)
        assert flag.done
        flag(execute=False)
        status(enable=True)
        assert status.homing is value and status.standstill and not status.homing_busy


# -- parameters (§4.6-4.11, §6.1; rules 106-111, 143) -----------------------------------------

#: TcMC §6.1: the BOOL parameters; every other number is LREAL (1043 is a DWORD number)
BOOL_NUMBERS = {4, 5, 6, 1015, 1017, 1019, 1022, 1024, 1027, 1029, 1033, 1035, 1037, 1042, 1046}
ALL_NUMBERS = list(range(1, 17)) + list(range(1000, 1049)) + [2000, 2001, 2002]
READ_ONLY = [1, 10, 11, 1000, 2000, 2001, 2002]


def test_axis_para_numbers_match_the_manual() -> None:
    """Rule 143, TcMC §6.1: the enum anchors and the complete numbering."""
    assert sorted(int(n) for n in P) == ALL_NUMBERS
    assert (P.CommandedPosition, P.MaxJerk, P.AxisId, P.AxisModuloToleranceWindow,
            P.AxisUnitInterpretation, P.AxisTargetPosition, P.AxisRemainingDistanceToGo) == (
        1, 16, 1000, 1045, 1048, 2000, 2002)


@pytest.mark.parametrize("number", ALL_NUMBERS)
def test_every_parameter_is_readable_with_its_type(number: int) -> None:
    """Rules 106, 108: each number reads with its block and type; the other block gives
    PARAMETER_TYPE_MISMATCH."""
    rt, axis = powered_axis()
    real, boolean = MC_ReadParameter(axis), MC_ReadBoolParameter(axis)
    real(enable=True, parameter_number=number)
    boolean(enable=True, parameter_number=number)
    right, wrong = (boolean, real) if number in BOOL_NUMBERS else (real, boolean)
    assert right.done and not right.error
    assert type(right.value) is (bool if number in BOOL_NUMBERS else float)
    assert wrong.error and wrong.error_id == ErrorId.PARAMETER_TYPE_MISMATCH and not wrong.done


@pytest.mark.parametrize(("number", "field"), [
    (P.AxisAcc, "acceleration"), (P.AxisDec, "deceleration"), (P.AxisJerk, "jerk"),
    (P.AxisVeloMax, "max_velocity"), (P.AxisPositionRangeWindow, "position_range_window"),
    (P.AxisTargetPositionWindow, "target_position_window"),
    (P.AxisModuloToleranceWindow, "modulo_tolerance_window"),
    (P.AxisEncoderModuloValue, "modulo_period"), (P.AxisMaxPosLagValue, "max_position_lag"),
])
def test_read_parameter_returns_the_configured_value(number: P, field: str) -> None:
    """Rule 106: e.g. 1004 AxisAcc returns the configured default acceleration."""
    rt, axis = powered_axis(acceleration=1234.5, deceleration=2345.5, jerk=34567.5,
                            max_velocity=777.0, position_range_window=0.25,
                            target_position_window=0.125, modulo_tolerance_window=1.5,
                            modulo_period=400.0, max_position_lag=3.5)
    read = MC_ReadParameter(axis)
    read(enable=True, parameter_number=number)
    assert read.value == getattr(axis.parameters, field)


def test_status_parameters_during_a_move() -> None:
    """§6.1: 1 CommandedPosition, 10 ActualVelocity, 11 CommandedVelocity, 2000
    AxisTargetPosition, 2001 remaining time, 2002 remaining distance."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    run(rt, axis, lambda: move(execute=True, position=300.0, velocity=100.0),
        lambda: axis.set_position > 100.0)
    values = {}
    for number in (1, 10, 11, 2000, 2001, 2002):
        read = MC_ReadParameter(axis)
        read(enable=True, parameter_number=number)
        assert read.done
        values[number] = read.value
    assert values[1] == axis.set_position
    assert values[10] == pytest.approx(100.0, rel=1e-6)
    assert values[11] == pytest.approx(100.0, rel=1e-12)
    assert values[2000] == 300.0
    assert values[2002] == pytest.approx(300.0 - axis.set_position, abs=1e-12)
    assert values[2001] == pytest.approx(values[2002] / 100.0, abs=0.05)


@pytest.mark.parametrize("number", [17, 999, 0, -1, 1049, 1999, 2003])
def test_unknown_parameter_number(number: int) -> None:
    """Rule 107, TcMC §6.1: an undefined number → INVALID_PARAMETER_NUMBER, all four blocks."""
    rt, axis = powered_axis()
    for block, value in ((MC_ReadParameter, None), (MC_ReadBoolParameter, None),
                         (MC_WriteParameter, 1.0), (MC_WriteBoolParameter, True)):
        fb = block(axis)
        inputs = {"parameter_number": number}
        if value is not None:
            inputs["value"] = value
        fb(enable=True, **inputs)
        assert fb.error and fb.error_id == ErrorId.INVALID_PARAMETER_NUMBER and not fb.done
        fb(enable=False)
        assert not fb.error and fb.error_id == ErrorId.NO_ERROR


@pytest.mark.parametrize("number", READ_ONLY)
def test_read_only_parameters_cannot_be_written(number: int) -> None:
    """Rule 110, TcMC §6.1: 2000-2002 (and the status values 1, 10, 11, 1000) are read-only."""
    rt, axis = powered_axis()
    write = MC_WriteParameter(axis)
    write(enable=True, parameter_number=number, value=5.0)
    assert write.error and write.error_id == ErrorId.PARAMETER_READ_ONLY
    assert axis.set_position == 0.0


@pytest.mark.parametrize(("block", "number", "value"), [
    (MC_WriteParameter, 1015, 1.0), (MC_WriteBoolParameter, 1004, True),
])
def test_write_with_the_wrong_type(block, number: int, value) -> None:
    """Rule 108 for writing: PARAMETER_TYPE_MISMATCH, the parameter unchanged."""
    rt, axis = powered_axis()
    before = (axis.parameters.enable_min_soft_limit, axis.parameters.acceleration)
    write = block(axis)
    write(enable=True, parameter_number=number, value=value)
    assert write.error and write.error_id == ErrorId.PARAMETER_TYPE_MISMATCH
    assert (axis.parameters.enable_min_soft_limit, axis.parameters.acceleration) == before


def test_write_acceleration_then_a_move_with_zero_uses_it() -> None:
    """Rule 109: WriteParameter(1004, v), ReadParameter(1004) = v, and a move with
    Acceleration 0 accelerates with v."""
    rt, axis = powered_axis()
    write, read, move = MC_WriteParameter(axis), MC_ReadParameter(axis), MC_MoveAbsolute(axis)
    write(enable=True, parameter_number=P.AxisAcc, value=1500.0)
    assert write.done and not write.error
    read(enable=True, parameter_number=P.AxisAcc)
    assert read.value == 1500.0
    trace = run(rt, axis, lambda: move(execute=True, position=600.0, velocity=1000.0,
                                        acceleration=0.0), lambda: move.done)
    assert max(trace.a) == pytest.approx(1500.0, rel=1e-9)
    assert min(trace.a) == pytest.approx(-5000.0, rel=1e-9)  # deceleration unchanged


def test_write_bool_parameter_switches_a_monitor() -> None:
    """MC_WriteBoolParameter(1017 AxisEnMaxSoftPosLimit) enables the limit."""
    rt, axis = powered_axis(max_soft_limit=10.0)
    write, move = MC_WriteBoolParameter(axis), MC_MoveAbsolute(axis)
    write(enable=True, parameter_number=P.AxisEnMaxSoftPosLimit, value=True)
    assert write.done and axis.parameters.enable_max_soft_limit is True
    move(execute=True, position=20.0, velocity=100.0)
    assert move.error and move.error_id == ErrorId.TARGET_BEYOND_SOFT_LIMIT


def test_write_an_invalid_value_is_refused() -> None:
    """A value the configuration does not allow (negative acceleration) is not written."""
    rt, axis = powered_axis()
    write = MC_WriteParameter(axis)
    write(enable=True, parameter_number=P.AxisAcc, value=-1.0)
    assert write.error and write.error_id == ErrorId.INVALID_PARAMETER_VALUE
    assert axis.parameters.acceleration == 5000.0


def test_read_mode_once_and_cyclic() -> None:
    """Rule 111, TcMC §6.4: ONCE reads at the Enable edge only; CYCLIC every cycle."""
    rt, axis = powered_axis()
    once, cyclic, move = MC_ReadParameter(axis), MC_ReadParameter(axis), MC_MoveVelocity(axis)
    values_once, values_cyclic = [], []
    for _ in range(50):
        move(execute=True, velocity=100.0)
        once(enable=True, parameter_number=P.CommandedPosition, read_mode=om.ReadMode.ONCE)
        cyclic(enable=True, parameter_number=P.CommandedPosition,
               read_mode=om.ReadMode.CYCLIC)
        assert once.done and cyclic.done
        values_once.append(once.value)
        values_cyclic.append(cyclic.value)
        assert cyclic.value == axis.set_position
        rt.step()
    assert len(set(values_once)) == 1 and values_once[0] == 0.0
    assert len(set(values_cyclic)) == 50
    once(enable=False)
    once(enable=True)  # a new edge reads again
    assert once.value == axis.set_position


def test_read_parameter_set() -> None:
    """TcMC §4.8: the whole parameter set (ST_AxisParameterSet) on an Execute edge."""
    rt, axis = powered_axis(acceleration=1234.0)
    read = MC_ReadParameterSet(axis)
    read(execute=True)
    assert read.done and not read.busy
    assert read.parameter["acceleration"] == 1234.0
    assert read.parameter["modulo_period"] == axis.parameters.modulo_period
    assert len(read.parameter) >= 50


# -- MC_SetActualPosition (§4.12; rule 112) ---------------------------------------------------


def test_set_actual_position_at_standstill() -> None:
    """Rule 112: actual and set position become p; no motion; Done at once."""
    rt, axis = powered_axis(drive=LAG)
    setter = MC_SetActualPosition(axis)
    setter(execute=True, position=-123.25)
    assert setter.done
    assert axis.position == -123.25 and axis.set_position == -123.25
    for _ in range(50):
        rt.step()
    assert axis.position == pytest.approx(-123.25, abs=1e-12)
    assert axis.set_velocity == 0.0


def test_set_actual_position_while_moving_is_refused() -> None:
    """Open Q26, our reading: standstill only → AXIS_NOT_STANDSTILL; the move goes on."""
    rt, axis = powered_axis()
    move = cruise(rt, axis, 100.0)
    setter = MC_SetActualPosition(axis)
    setter(execute=True, position=0.0)
    assert setter.error and setter.error_id == ErrorId.AXIS_NOT_STANDSTILL
    move(execute=True)
    assert move.busy and move.in_velocity


# -- MC_SetOverride (§4.14; rule 115) ----------------------------------------------------------

DYN = {"acceleration": 1000.0, "deceleration": 1000.0, "jerk": 10000.0}


def test_override_zero_pauses_the_move_and_it_resumes() -> None:
    """§4.23.1 / rule 115: override 0 halts the profile without aborting the job; the move
    resumes and completes when the override returns; no velocity jump on the way."""
    rt, axis = powered_axis()
    move, override = MC_MoveAbsolute(axis), MC_SetOverride(axis)
    trace = run(rt, axis, lambda: move(execute=True, position=200.0, velocity=100.0, **DYN),
                lambda: axis.set_position > 50.0)
    override(execute=True, override=0.0)
    assert override.done
    paused = run(rt, axis, lambda: (move(execute=True), override(execute=True)),
                 lambda: axis.set_velocity == 0.0 and not axis.has_job)
    for _ in range(300):
        rt.step()
        move(execute=True)
        paused.sample(axis)
        assert move.busy and not move.command_aborted and not move.done
    assert paused.v[-1] == 0.0 and len(set(paused.p[-100:])) == 1
    assert axis.state is S.DISCRETE_MOTION
    override(execute=False)
    override(execute=True, override=100.0)
    resumed = run(rt, axis, lambda: (move(execute=True), override(execute=True)),
                  lambda: move.done)
    assert axis.set_position == 200.0
    for part in (trace, paused, resumed):
        assert part.max_dv() <= 1000.0 * CYCLE * (1 + 1e-9)
    assert max(resumed.v) == pytest.approx(100.0, rel=1e-9)


def test_override_change_without_velocity_jump_or_dip() -> None:
    """Rule 115: override 100 → 50 takes the velocity from 100 down to 50 within the
    acceleration limit and without undershooting 50 (no near stop)."""
    rt, axis = powered_axis()
    move, override = MC_MoveAbsolute(axis), MC_SetOverride(axis)
    run(rt, axis, lambda: move(execute=True, position=300.0, velocity=100.0, **DYN),
        lambda: axis.set_velocity == pytest.approx(100.0))
    override(execute=True, override=50.0)
    trace = run(rt, axis, lambda: (move(execute=True), override(execute=True)),
                lambda: axis.set_position > 150.0)
    assert trace.max_dv() <= 1000.0 * CYCLE * (1 + 1e-9)
    assert trace.v[-1] == pytest.approx(50.0, rel=1e-9)
    assert min(trace.v) >= 50.0 * (1 - 1e-9)
    run(rt, axis, lambda: move(execute=True), lambda: move.done)
    assert axis.set_position == 300.0


@pytest.mark.parametrize("value", [-5.0, 150.0, float("inf"), float("nan")])
def test_set_override_bad_value(value: float) -> None:
    rt, axis = powered_axis()
    override = MC_SetOverride(axis)
    override(execute=True, override=value)
    assert override.error and override.error_id == ErrorId.INVALID_OVERRIDE
    assert axis.override == 1.0


# -- MC_ChangeDynParam (§4.20; rules 126, 127) ------------------------------------------------


def test_change_dyn_param_applies_and_is_retriggerable() -> None:
    """Rule 126: new acc/dec/jerk apply to the running move; a new edge changes them again."""
    rt, axis = powered_axis()
    move, change = MC_MoveAbsolute(axis), MC_ChangeDynParam(axis)
    run(rt, axis, lambda: move(execute=True, position=400.0, velocity=200.0, **DYN),
        lambda: axis.set_velocity == pytest.approx(200.0))
    change(execute=True, acceleration=3000.0, deceleration=3000.0, jerk=30000.0)
    assert change.done and not change.error
    change(execute=False)
    change(execute=True, acceleration=2000.0, deceleration=2000.0, jerk=20000.0)
    assert change.done and not change.error
    trace = run(rt, axis, lambda: (move(execute=True), change(execute=True)),
                lambda: move.done)
    assert axis.set_position == 400.0
    assert min(trace.a) == pytest.approx(-2000.0, rel=1e-9)  # the latest values brake
    # time-optimal from the change: 370 mm at 200 mm/s plus the 2000 mm/s² braking
    assert len(trace.v) * CYCLE < 370.0 / 200.0 + 0.2 + 0.05
    assert trace.peak_jerk() == pytest.approx(20000.0, rel=1e-6)


def _changed_to(**dynamics: float) -> Trace:
    """A fast move whose dynamics are changed 5 cycles after the start, on an axis with the
    defaults 1500 / 2500 mm/s² and 20000 mm/s³; sampled from the change to Done."""
    rt, axis = powered_axis(acceleration=1500.0, deceleration=2500.0, jerk=20000.0)
    move, change = MC_MoveAbsolute(axis), MC_ChangeDynParam(axis)
    for _ in range(5):
        move(execute=True, position=600.0, velocity=400.0, acceleration=4000.0,
             deceleration=4000.0, jerk=100000.0)
        rt.step()
    assert 0.0 < axis.set_acceleration < 1500.0  # still ramping up the acceleration
    change(execute=True, **dynamics)
    assert change.done and not change.error, change.message
    trace = run(rt, axis, lambda: (move(execute=True), change(execute=True)),
                lambda: move.done)
    assert axis.set_position == 600.0
    return trace


def test_change_dyn_param_zero_means_the_axis_defaults() -> None:
    """Rule 9, TcMC §4.20: Acceleration/Deceleration/Jerk = 0 set the axis defaults
    AxisAcc/AxisDec/AxisJerk (1004-1006) for the rest of the move, the same profile as
    given explicitly (the move itself started with 4000 / 4000 / 100000)."""
    zero = _changed_to(acceleration=0.0, deceleration=0.0, jerk=0.0)
    assert max(zero.a) == pytest.approx(1500.0, rel=1e-9)
    assert min(zero.a) == pytest.approx(-2500.0, rel=1e-9)
    assert zero.peak_jerk() == pytest.approx(20000.0, rel=1e-6)
    explicit = _changed_to(acceleration=1500.0, deceleration=2500.0, jerk=20000.0)
    assert zero.p == explicit.p and zero.v == explicit.v and zero.a == explicit.a


def test_change_dyn_param_rejected_near_the_target() -> None:
    """Rule 127: lower deceleration near the target would overshoot → 0x427F; the running
    profile keeps its dynamics and ends exactly at the target."""
    rt, axis = powered_axis()
    move, change = MC_MoveAbsolute(axis), MC_ChangeDynParam(axis)
    run(rt, axis, lambda: move(execute=True, position=100.0, velocity=200.0,
                               deceleration=2000.0, jerk=20000.0),
        lambda: axis.set_position > 85.0)
    change(execute=True, deceleration=200.0, jerk=2000.0)
    assert change.error and change.error_id == ErrorId.DYN_TARGET_OVERSHOT == 0x427F
    trace = run(rt, axis, lambda: move(execute=True), lambda: move.done)
    assert max(trace.p) <= 100.0 + 1e-9 and axis.set_position == 100.0
    assert min(trace.a) == pytest.approx(-2000.0, rel=1e-9)


def test_change_dyn_param_rejected_during_a_stop() -> None:
    """Rule 127: a stop with its own dynamics is in progress → 0x425D."""
    rt, axis = powered_axis()
    cruise(rt, axis)
    stop, change = MC_Stop(axis), MC_ChangeDynParam(axis)
    stop(execute=True)
    change(execute=True, deceleration=200.0, jerk=2000.0)
    assert change.error and change.error_id == ErrorId.DYN_STRICTER_STOP_ACTIVE == 0x425D


def test_change_dyn_param_rejected_in_the_acceleration_phase() -> None:
    """Rule 127: accelerating, a lower jerk cannot take the acceleration away in time; the
    velocity would exceed the travel velocity → 0x423A; the profile stays within it."""
    rt, axis = powered_axis()
    move, change = MC_MoveVelocity(axis), MC_ChangeDynParam(axis)
    run(rt, axis, lambda: move(execute=True, velocity=100.0),
        lambda: axis.set_acceleration >= 900.0)
    change(execute=True, acceleration=5000.0, jerk=1000.0)
    assert change.error and change.error_id == ErrorId.DYN_VELOCITY_EXCEEDED == 0x423A
    trace = run(rt, axis, lambda: move(execute=True), lambda: move.in_velocity)
    assert max(trace.v) <= 100.0 * (1 + 1e-9)


@pytest.mark.parametrize(("cycles", "jerk"), [(30, 10000.0), (40, 25000.0), (40, 10000.0)],
                         ids=["mild", "medium", "strong"])
def test_change_dyn_param_rejected_in_the_braking_phase(cycles: int, jerk: float) -> None:
    """Rule 127: braking, a lower jerk cannot take the deceleration away in time; the
    direction would reverse → 0x4289 (however far it would reverse)."""
    rt, axis = powered_axis()
    cruise(rt, axis, 100.0)
    slower, change = MC_MoveVelocity(axis), MC_ChangeDynParam(axis)
    slower(execute=True, velocity=1.0)
    for _ in range(cycles):
        rt.step()
        slower(execute=True)
    assert axis.set_acceleration < 0.0
    assert axis.set_acceleration ** 2 / (2 * jerk) > axis.set_velocity  # would reverse
    change(execute=True, deceleration=5000.0, jerk=jerk)
    assert change.error and change.error_id == ErrorId.DYN_DIRECTION_REVERSAL == 0x4289
    trace = run(rt, axis, lambda: slower(execute=True), lambda: slower.in_velocity)
    assert min(trace.v) >= 1.0 - 1e-9


def test_change_dyn_param_optimisation_not_possible() -> None:
    """Rule 127, D-050: limits far below the running state (v = 90 mm/s, a = 3000 mm/s²)
    leave the planner without a profile: "internal optimisation not possible" → 0x427E, not
    NO_PROFILE; the running profile keeps its dynamics and ends at the target."""
    rt, axis = powered_axis()
    move, change = MC_MoveAbsolute(axis), MC_ChangeDynParam(axis)
    move(execute=True, position=800.0, velocity=800.0)
    for _ in range(60):
        rt.step()
        move(execute=True)
    change(execute=True, acceleration=10.0, deceleration=10.0, jerk=10.0)
    assert change.error and change.error_id == ErrorId.DYN_OPTIMISATION_FAILED == 0x427E
    trace = run(rt, axis, lambda: move(execute=True), lambda: move.done)
    assert axis.set_position == 800.0
    assert max(trace.a) == pytest.approx(5000.0, rel=1e-9)  # the axis defaults, unchanged
    assert min(trace.a) == pytest.approx(-5000.0, rel=1e-9)


@pytest.mark.parametrize("paused", [False, True], ids=["same_cycle", "override_0"])
def test_change_dyn_param_on_a_move_at_rest_applies(paused: bool) -> None:
    """Rule 126: a positioning at rest (set velocity 0: issued in the same cycle, or paused by
    override 0) takes new dynamics; with no velocity to give the direction, the target does,
    so nothing is "overshot" (no 0x427F)."""
    rt, axis = powered_axis()
    move, change = MC_MoveAbsolute(axis), MC_ChangeDynParam(axis)
    override = MC_SetOverride(axis)
    move(execute=True, position=600.0, velocity=400.0)
    if paused:
        run(rt, axis, lambda: move(execute=True), lambda: axis.set_position > 50.0)
        override(execute=True, override=0.0)
        run(rt, axis, lambda: move(execute=True),
            lambda: axis.set_velocity == 0.0 and not axis.has_job)
        assert axis.set_position < 600.0 and move.busy
    change(execute=True, acceleration=3000.0, deceleration=3000.0, jerk=30000.0)
    assert change.done and not change.error
    override(execute=False)
    override(execute=True, override=100.0)
    trace = run(rt, axis, lambda: move(execute=True), lambda: move.done)
    assert axis.set_position == 600.0
    assert max(trace.a) == pytest.approx(3000.0, rel=1e-9)
    assert min(trace.a) == pytest.approx(-3000.0, rel=1e-9)
    assert trace.peak_jerk() == pytest.approx(30000.0, rel=1e-6)


def test_change_dyn_param_on_a_standing_axis() -> None:
    rt, axis = powered_axis()
    change = MC_ChangeDynParam(axis)
    change(execute=True, acceleration=100.0)
    assert change.error and change.error_id == ErrorId.AXIS_NOT_MOVING


# -- MC_Stop (§3.15; rules 68-76) ------------------------------------------------------------


def _brake(rt: om.Runtime, axis: om.Axis, stop: MC_Stop, **inputs: Any) -> Trace:
    stop(execute=True, **inputs)
    return run(rt, axis, lambda: stop(execute=True), lambda: stop.done)


def test_stop_done_only_at_standstill_without_job() -> None:
    """Rule 68: Done TRUE only when the axis has no job and stands still; rule 76: the
    move is aborted."""
    rt, axis = powered_axis()
    move = cruise(rt, axis)
    stop = MC_Stop(axis)
    stop(execute=True)
    move(execute=True)
    assert move.command_aborted
    while not stop.done:
        assert axis.set_velocity != 0.0 or axis.has_job
        rt.step()
        stop(execute=True)
    assert axis.set_velocity == 0.0 and not axis.has_job


def test_stop_with_zero_inputs_uses_the_moves_dynamics() -> None:
    """Rule 69, TcMC §3.15: Deceleration = Jerk = 0 → the running move's values."""
    rt, axis = powered_axis()
    cruise(rt, axis, deceleration=1000.0, jerk=10000.0)
    trace = _brake(rt, axis, MC_Stop(axis))
    assert min(trace.a) == pytest.approx(-1000.0, rel=1e-9)
    assert trace.peak_jerk() == pytest.approx(10000.0, rel=1e-6)


@pytest.mark.parametrize("inputs", [{"deceleration": 3000.0}, {"jerk": 30000.0}],
                         ids=["dec-only", "jerk-only"])
def test_stop_with_one_value_only_does_not_apply_it(inputs: dict) -> None:
    """Rule 70, TcMC §3.15: a non-zero value without its partner is not applied; no error."""
    rt, axis = powered_axis()
    cruise(rt, axis, deceleration=1000.0, jerk=10000.0)
    stop = MC_Stop(axis)
    trace = _brake(rt, axis, stop, **inputs)
    assert not stop.error
    assert min(trace.a) == pytest.approx(-1000.0, rel=1e-9)
    assert trace.peak_jerk() == pytest.approx(10000.0, rel=1e-6)


@pytest.mark.parametrize(("dec", "jerk"), [(3000.0, 30000.0), (500.0, 5000.0)],
                         ids=["harder", "softer"])
def test_stop_with_given_dynamics_applies_them(dec: float, jerk: float) -> None:
    """Rules 71/72 (7-phase generator): harder and, where safe, softer values apply."""
    rt, axis = powered_axis()
    v = 400.0  # > dec²/jerk: the deceleration reaches its limit
    cruise(rt, axis, v, deceleration=1000.0, jerk=10000.0)
    stop = MC_Stop(axis)
    trace = _brake(rt, axis, stop, deceleration=dec, jerk=jerk)
    assert not stop.error
    assert min(trace.a) == pytest.approx(-dec, rel=1e-9)
    assert trace.p[-1] - trace.p[0] == pytest.approx(v * v / (2 * dec) + v * dec / (2 * jerk),
                                                     rel=1e-3)


def test_softer_stop_near_the_target_does_not_overshoot_it() -> None:
    """Rule 73, TcMC §3.15 case 1: softer values that would overshoot the target are not
    applied; the axis stops no later than the target; Error stays FALSE."""
    rt, axis = powered_axis()
    move = MC_MoveAbsolute(axis)
    run(rt, axis, lambda: move(execute=True, position=100.0, velocity=200.0,
                               deceleration=1000.0, jerk=10000.0),
        lambda: axis.set_position > 70.0)
    stop = MC_Stop(axis)
    trace = _brake(rt, axis, stop, deceleration=200.0, jerk=2000.0)
    assert not stop.error
    assert max(trace.p) <= 100.0 + 1e-9
    assert axis.set_position <= 100.0 + 1e-9


def test_second_softer_stop_does_not_soften_the_first() -> None:
    """Rule 74, TcMC §3.15 case 2: a stricter stop runs; a softer second stop keeps it."""
    rt, axis = powered_axis()
    cruise(rt, axis, 400.0)
    first = MC_Stop(axis)
    first(execute=True, deceleration=3000.0, jerk=30000.0)
    start = axis.set_position
    rt.step()
    rt.step()
    second = MC_Stop(axis)
    trace = _brake(rt, axis, second, deceleration=500.0, jerk=5000.0)
    assert not second.error
    assert min(trace.a) == pytest.approx(-3000.0, rel=1e-9)
    assert trace.peak_jerk() <= 30000.0 * (1 + 1e-6)
    stricter = 400.0 ** 2 / (2 * 3000.0) + 400.0 * 3000.0 / (2 * 30000.0)
    assert trace.p[-1] - start == pytest.approx(stricter, rel=1e-3)


def test_softer_stop_in_the_acceleration_phase_does_not_exceed_the_velocity() -> None:
    """Rule 75, TcMC §3.15 case 3: accelerating, a softer jerk would carry the velocity
    above the travel velocity → stricter values kept, no error."""
    rt, axis = powered_axis()
    move = MC_MoveVelocity(axis)
    run(rt, axis, lambda: move(execute=True, velocity=100.0),
        lambda: axis.set_acceleration >= 2000.0)
    stop = MC_Stop(axis)
    trace = _brake(rt, axis, stop, deceleration=5000.0, jerk=1000.0)
    assert not stop.error
    assert max(trace.v) <= 100.0 * (1 + 1e-9)


def test_softer_stop_in_the_braking_phase_does_not_reverse() -> None:
    """Rule 75, TcMC §3.15 case 4: braking, a softer jerk would reverse the direction →
    stricter values kept, no error, no reversal."""
    rt, axis = powered_axis()
    cruise(rt, axis, 100.0)
    slower = MC_MoveVelocity(axis)
    slower(execute=True, velocity=1.0)
    for _ in range(40):
        rt.step()
        slower(execute=True)
    stop = MC_Stop(axis)
    trace = _brake(rt, axis, stop, deceleration=5000.0, jerk=10000.0)
    assert not stop.error
    assert min(trace.v) >= 0.0


def test_stop_during_homing_aborts_it() -> None:
    """§1.2: MC_Stop in Homing → Stopping; MC_Home reports CommandAborted, not homed."""
    rt, axis = powered_axis(position=50.0, reference_cam=(10.0, 20.0))
    home, stop = MC_Home(axis), MC_Stop(axis)
    run(rt, axis, lambda: home(execute=True), lambda: axis.set_position < 45.0)
    stop(execute=True)
    home(execute=True)
    assert home.command_aborted and not home.done
    assert axis.state is S.STOPPING
    run(rt, axis, lambda: (home(execute=True), stop(execute=True)), lambda: stop.done)
    assert not axis.homed and axis.calibration_state == 0
    stop(execute=False)
    rt.step()
    assert axis.state is S.STANDSTILL


# -- MC_Home (§3.14; rules 64-66) -------------------------------------------------------------


def _home(mode: R, position: Any = om.DEFAULT_HOME_POSITION, start: float = 55.0,
          cam: Callable[[om.Axis], bool | None] = lambda axis: None, **overrides: Any):
    rt, axis = powered_axis(position=start, reference_mode=mode, calibration_value=7.0,
                            **overrides)
    home = MC_Home(axis)
    phases = []
    run(rt, axis, lambda: (home(execute=True, position=position, calibration_cam=cam(axis)),
                           phases.append(axis.calibration_state)),
        lambda: home.done or home.error or home.command_aborted)
    return rt, axis, home, phases


@pytest.mark.parametrize(("position", "value"), [(om.DEFAULT_HOME_POSITION, 7.0), (100.0, 100.0),
                                                 (-3.5, -3.5)], ids=["DEFAULT", "100", "-3.5"])
def test_home_cam_and_sync_pulse(position, value: float) -> None:
    """Rules 64-66: search the cam (negative), leave it, latch the next sync pulse; the
    pulse position (raw 30: pulses every 10 mm, cam [10, 20]) reads the home position."""
    rt, axis, home, phases = _home(R.CAM_AND_SYNC_PULSE, position, reference_cam=(10.0, 20.0))
    assert home.done and axis.homed and axis.state is S.STANDSTILL
    assert axis.calibration_state == 7
    assert axis.raw_offset == pytest.approx(value - 30.0, abs=1e-9)
    assert axis.position - axis.raw_offset > 30.0  # stopped after the pulse
    increasing = [p for k, p in enumerate(phases) if k == 0 or phases[k - 1] != p]
    assert increasing == sorted(increasing) and increasing[-1] == 7


def test_home_cam_references_on_the_falling_cam_edge() -> None:
    """Reference mode CAM: the position leaving the cam (raw 20) reads the home value."""
    rt, axis, home, _ = _home(R.CAM, reference_cam=(10.0, 20.0))
    assert home.done and axis.homed
    # sampled, so within one cycle of travel (backward velocity 10 mm/s → 0.01 mm)
    assert axis.raw_offset == pytest.approx(7.0 - 20.0, abs=0.011)


def test_home_sync_pulse_only() -> None:
    """Reference mode SYNC_PULSE: the next sync pulse in the homing direction (raw 50)."""
    rt, axis, home, _ = _home(R.SYNC_PULSE)
    assert home.done and axis.homed
    assert axis.raw_offset == pytest.approx(7.0 - 50.0, abs=1e-9)


@pytest.mark.parametrize(("position", "value"), [(om.DEFAULT_HOME_POSITION, 7.0), (3.0, 3.0)],
                         ids=["DEFAULT", "3"])
def test_home_direct(position, value: float) -> None:
    """Reference mode DIRECT: the current position reads the home position, no motion."""
    rt, axis, home, _ = _home(R.DIRECT, position)
    assert home.done and axis.homed
    assert axis.position == pytest.approx(value, abs=1e-12)
    assert axis.set_position == pytest.approx(value, abs=1e-12)


def test_home_with_the_cam_simulated_in_the_plc() -> None:
    """Rule 66, TcMC §3.14: hold bCalibrationCam TRUE at the start, release it once
    nCalibrationState >= 4; homing completes on the sync pulse."""
    released_at = []

    def cam(axis: om.Axis) -> bool:
        if axis.calibration_state >= 4:
            released_at.append(axis.calibration_state)
            return False
        return True

    rt, axis, home, phases = _home(R.CAM_AND_SYNC_PULSE, cam=cam)
    assert home.done and axis.homed
    assert released_at and min(released_at) >= 4
    assert 4 in phases and 7 in phases
    pulse_raw = axis.position - axis.raw_offset
    assert axis.raw_offset == pytest.approx(7.0 - round(pulse_raw / 10.0) * 10.0, abs=1e-9)


def test_home_without_any_cam_is_an_error() -> None:
    """Modes with a cam need reference_cam or the calibration_cam input → HOMING_FAILED."""
    rt, axis, home, _ = _home(R.CAM_AND_SYNC_PULSE)
    assert home.error and home.error_id == ErrorId.HOMING_FAILED
    assert not axis.homed and axis.state is S.STANDSTILL


def test_home_only_from_standstill() -> None:
    """§1.2: MC_Home only at standstill → AXIS_NOT_STANDSTILL while moving."""
    rt, axis = powered_axis(reference_mode=R.DIRECT)
    cruise(rt, axis, 50.0)
    home = MC_Home(axis)
    home(execute=True)
    assert home.error and home.error_id == ErrorId.AXIS_NOT_STANDSTILL
