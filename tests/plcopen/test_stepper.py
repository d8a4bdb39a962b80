"""MC_PowerStepper and the simulated KL2531/KL2541 terminal (TcMC §4.23, §6.6-6.8;
rules 136-141).

The moves run on a lag drive (first order 10 ms behind a 2 ms dead time) with the NC's own
following-error monitoring switched off, as §4.23.1 asks: MaxPosLag 5 mm, filter 20 ms. A move
to 100 mm at 100 mm/s; the terminal stalls for 200 ms at t = 0.3 s (set position ≈ 27 mm).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest

import openmotion as om
from openmotion.axis.stepper import (
    STATUS2_OVERTEMPERATURE,
    STATUS_ERROR,
    STATUS_READY,
    STATUS_STALL_BITS,
    StepperTerminal,
)
from openmotion.plcopen.move import MC_MoveAbsolute
from openmotion.plcopen.stepper import (
    DestallDetectMode,
    DestallMode,
    MC_PowerStepper,
    PowerStepperParams,
)

ErrorId = om.ErrorId
S = om.AxisState
Detect = DestallDetectMode
Mode = DestallMode
CYCLE = 0.001
LAG = om.DriveModel(model="lag", time_constant=0.01, dead_time=0.002)
MAX_LAG, FILTER = 5.0, 0.02
TARGET, VELOCITY = 100.0, 100.0
STALL_AT, STALL_FOR = 0.3, 0.2


@dataclass
class Sample:
    t: float
    following_error: float
    set_velocity: float
    override: float
    state: om.AxisState
    busy: bool
    aborted: bool


@dataclass
class Run:
    axis: om.Axis
    stepper: MC_PowerStepper
    move: MC_MoveAbsolute
    terminal: StepperTerminal
    samples: list[Sample] = field(default_factory=list)

    def first(self, predicate) -> Sample:  # noqa: ANN001 - a lambda on Sample
        return next(s for s in self.samples if predicate(s))


def stall_run(detect: Detect, mode: Mode, enable: bool = True, override: float = 80.0,
              stall_for: float | None = STALL_FOR, homed: bool = True,
              max_cycles: int = 4000) -> Run:
    rt = om.Runtime(CYCLE)
    axis = rt.add_axis("x", drive=LAG, enable_position_lag_monitoring=False,
                       max_position_lag=MAX_LAG, position_lag_filter_time=FILTER)
    axis.homed = homed
    terminal = StepperTerminal(axis)
    params = PowerStepperParams(detect, mode, destall_enable=enable)
    run = Run(axis, MC_PowerStepper(axis, destall_params=params), MC_MoveAbsolute(axis),
              terminal)
    for _ in range(max_cycles):
        if abs(rt.now - STALL_AT) < CYCLE / 2:
            terminal.inject_stall(stall_for)
        run.stepper(enable=True, override=override, kl_status=terminal.status,
                    kl_status2=terminal.status2)
        run.move(execute=True, position=TARGET, velocity=VELOCITY)
        run.samples.append(Sample(rt.now, axis.following_error, axis.set_velocity,
                                  axis.override, axis.state, run.move.busy,
                                  run.move.command_aborted))
        if run.move.done or run.move.command_aborted or run.move.error:
            break
        rt.step()
    return run


# -- the terminal --------------------------------------------------------------------------

def test_terminal_stall_blocks_the_mechanics_and_sets_bits_1_to_3_for_its_duration() -> None:
    rt = om.Runtime(CYCLE)
    axis = rt.add_axis("x")
    axis.power()
    terminal = StepperTerminal(axis)
    assert terminal.status == STATUS_READY == 0x01 and terminal.status2 == 0
    axis.move_velocity(50.0)
    rt.run(0.1)
    terminal.inject_stall(duration=0.05)
    assert terminal.status == 0x0F  # ready + bits 1-3
    held = axis.position
    rt.run(0.049)
    assert axis.position == held and terminal.stalled
    assert axis.following_error > 2.0  # the setpoint went on: 49 ms at 50 mm/s
    rt.step()  # t = start + 50 ms: released in this motion step
    assert not terminal.stalled and terminal.status == STATUS_READY
    rt.step()
    assert axis.position == axis.set_position  # the ideal drive follows again at once


def test_terminal_release_and_error_bits() -> None:
    rt = om.Runtime(CYCLE)
    axis = rt.add_axis("x")
    terminal = StepperTerminal(axis)
    terminal.inject_stall()  # until released
    rt.run(1.0)
    assert terminal.status & STATUS_STALL_BITS == STATUS_STALL_BITS
    terminal.release()
    assert terminal.status == STATUS_READY
    terminal.set_error(STATUS2_OVERTEMPERATURE | 0x0100)
    assert terminal.status2 == 0x0120 and terminal.status == STATUS_READY | STATUS_ERROR
    terminal.clear_error(STATUS2_OVERTEMPERATURE)
    assert terminal.status2 == 0x0100 and terminal.status == STATUS_READY  # warning only
    with pytest.raises(ValueError, match="duration"):
        terminal.inject_stall(-1.0)


# -- rule 137: Lagging + SetError ----------------------------------------------------------

def test_rule_137_lagging_set_error_after_the_filter_time() -> None:
    run = stall_run(Detect.LAGGING, Mode.SET_ERROR)
    axis = run.axis
    assert axis.state is S.ERROR_STOP
    assert axis.axis_error_id == ErrorId.STEPPER_STALL == 0x4636
    assert "reporting error 0x4636 (stall error)" in axis.axis_error_message
    assert run.move.command_aborted and axis.homed  # SetError keeps the reference
    over = run.first(lambda s: abs(s.following_error) > MAX_LAG)
    fault = run.first(lambda s: s.state is S.ERROR_STOP)
    # over the limit on 21 consecutive calls (21 ms > 20 ms) like the NC monitoring
    assert round((fault.t - over.t) / CYCLE) == 20
    assert STALL_AT < over.t < STALL_AT + 0.06  # 100 mm/s builds 5 mm in about 40 ms
    assert not run.stepper.error  # the stall is an axis error, not a block error


@pytest.mark.parametrize(("stall_for", "cycles_over", "stall"), [(0.068, 20, False),
                                                                  (0.069, 21, True)])
def test_rule_137_the_filter_time_boundary(stall_for: float, cycles_over: int,
                                           stall: bool) -> None:
    """20 calls over the limit (20 ms, not longer than the filter time): no stall; 21: stall."""
    run = stall_run(Detect.LAGGING, Mode.SET_ERROR, stall_for=stall_for)
    over = [s for s in run.samples if abs(s.following_error) > MAX_LAG]
    assert len(over) == cycles_over
    assert round((over[-1].t - over[0].t) / CYCLE) == cycles_over - 1  # consecutive
    assert (run.axis.axis_error_id == ErrorId.STEPPER_STALL) is stall
    assert run.move.done is not stall


# -- rule 138: SetErrNonRef ------------------------------------------------------------------

def test_rule_138_set_err_non_ref_also_clears_homed() -> None:
    run = stall_run(Detect.LAGGING, Mode.SET_ERR_NON_REF)
    assert run.axis.state is S.ERROR_STOP
    assert run.axis.axis_error_id == ErrorId.STEPPER_STALL
    assert not run.axis.homed


# -- rule 139: UseOverride -------------------------------------------------------------------

def test_rule_139_use_override_freezes_the_profile_and_finishes_at_the_target() -> None:
    run = stall_run(Detect.LAGGING, Mode.USE_OVERRIDE, override=80.0)
    axis, samples = run.axis, run.samples
    held = run.first(lambda s: s.override == 0.0)
    over = run.first(lambda s: abs(s.following_error) > MAX_LAG)
    assert round((held.t - over.t) / CYCLE) == 20  # same detection as rule 137
    during = [s for s in samples if held.t <= s.t < STALL_AT + STALL_FOR]
    stopped = [s for s in during if s.set_velocity == 0.0]
    assert stopped, "the profile froze"
    assert all(s.set_velocity == 0.0 for s in during if s.t >= stopped[0].t)
    # no abort, no state change, the command stays busy
    assert all(s.state is S.DISCRETE_MOTION and s.busy and not s.aborted for s in during)
    assert axis.axis_error_id == ErrorId.NO_ERROR
    # after the release the drive catches up; then the application's 80 % returns (Q31)
    restored = run.first(lambda s: s.t > held.t and s.override != 0.0)
    assert restored.override == 0.8
    assert restored.t > STALL_AT + STALL_FOR
    assert abs(restored.following_error) <= MAX_LAG
    assert max(s.set_velocity for s in samples if s.t > restored.t) == pytest.approx(80.0)
    assert run.move.done and not run.move.command_aborted
    assert axis.set_position == TARGET
    assert abs(axis.position - TARGET) <= axis.parameters.position_range_window
    assert axis.state is S.STANDSTILL and not run.stepper.override_held


def test_rule_139_override_stays_zero_while_the_axis_remains_blocked() -> None:
    run = stall_run(Detect.LAGGING, Mode.USE_OVERRIDE, stall_for=None, max_cycles=1500)
    last = run.samples[-1]
    assert last.override == 0.0 and last.set_velocity == 0.0
    assert last.state is S.DISCRETE_MOTION and last.busy and not run.move.done


# -- rule 140: Encoderless ---------------------------------------------------------------------

def powered_standstill(params: PowerStepperParams) -> tuple[om.Runtime, om.Axis,
                                                            MC_PowerStepper]:
    rt = om.Runtime(CYCLE)
    axis = rt.add_axis("x", drive=LAG, enable_position_lag_monitoring=False)
    axis.homed = True
    stepper = MC_PowerStepper(axis, destall_params=params)
    stepper(enable=True)
    rt.step()
    return rt, axis, stepper


@pytest.mark.parametrize("bit", [1, 2, 3])
def test_rule_140_encoderless_any_of_bits_1_to_3_is_a_stall(bit: int) -> None:
    _, axis, stepper = powered_standstill(
        PowerStepperParams(Detect.ENCODERLESS, Mode.SET_ERR_NON_REF, destall_enable=True))
    stepper(kl_status=1 << bit)
    assert axis.state is S.ERROR_STOP and axis.axis_error_id == 0x4636 and not axis.homed


@pytest.mark.parametrize("status", [0x01, 0x10, 0x11, 0x20, 0x80, 0xF1])
def test_rule_140_other_bits_are_no_stall(status: int) -> None:
    rt, axis, stepper = powered_standstill(
        PowerStepperParams(Detect.ENCODERLESS, Mode.SET_ERROR, destall_enable=True))
    for _ in range(50):
        stepper(kl_status=status)
        rt.step()
    assert axis.state is S.STANDSTILL and axis.homed and stepper.status


def test_rule_140_encoderless_during_a_move_reacts_on_the_first_call() -> None:
    run = stall_run(Detect.ENCODERLESS, Mode.SET_ERROR)
    fault = run.first(lambda s: s.state is S.ERROR_STOP)
    assert fault.t == pytest.approx(STALL_AT)  # the bits are set before the call at 0.3 s
    assert run.axis.axis_error_id == ErrorId.STEPPER_STALL


def test_encoderless_use_override_holds_until_the_bits_clear() -> None:
    run = stall_run(Detect.ENCODERLESS, Mode.USE_OVERRIDE)
    held = [s for s in run.samples if s.override == 0.0]
    assert held[0].t == pytest.approx(STALL_AT)
    # the timed release happens in the motion step of 0.5 s: the call at 0.499 s still holds
    assert held[-1].t == pytest.approx(STALL_AT + STALL_FOR - CYCLE)
    assert run.move.done and run.axis.set_position == TARGET


# -- rule 136: DestallEnable FALSE -------------------------------------------------------------

@pytest.mark.parametrize("detect", [Detect.LAGGING, Detect.ENCODERLESS])
@pytest.mark.parametrize("mode", [Mode.SET_ERROR, Mode.SET_ERR_NON_REF, Mode.USE_OVERRIDE])
def test_rule_136_destall_enable_false_never_reacts(detect: Detect, mode: Mode) -> None:
    run = stall_run(detect, mode, enable=False)
    assert max(abs(s.following_error) for s in run.samples) > 10.0  # a real stall happened
    assert all(s.override == 0.8 for s in run.samples)
    assert run.axis.axis_error_id == ErrorId.NO_ERROR and run.axis.homed
    assert run.move.done and run.axis.set_position == TARGET


@pytest.mark.parametrize(("detect", "mode"), [(Detect.NONE, Mode.SET_ERROR),
                                              (Detect.LAGGING, Mode.NONE)])
def test_detect_none_or_mode_none_never_reacts(detect: Detect, mode: Mode) -> None:
    run = stall_run(detect, mode)
    assert run.move.done and run.axis.axis_error_id == ErrorId.NO_ERROR


# -- rule 141: StatusMonEnable -----------------------------------------------------------------

def test_rule_141_status_mon_enable_reports_terminal_errors() -> None:
    rt, axis, stepper = powered_standstill(PowerStepperParams(status_mon_enable=True))
    terminal = StepperTerminal(axis)
    terminal.set_error(0x0100)  # a warning bit: not reported
    stepper(kl_status=terminal.status, kl_status2=terminal.status2)
    terminal.inject_stall()  # stall bits are no error bits
    stepper(kl_status=terminal.status, kl_status2=terminal.status2)
    assert axis.state is S.STANDSTILL
    terminal.set_error(STATUS2_OVERTEMPERATURE)
    stepper(kl_status=terminal.status, kl_status2=terminal.status2)
    assert axis.state is S.ERROR_STOP and axis.axis_error_id == ErrorId.DRIVE_NOT_READY
    assert "KL_Status2 16#0120" in axis.axis_error_message


def test_rule_141_status_byte_error_bit_alone_and_off_when_disabled() -> None:
    _, axis, stepper = powered_standstill(PowerStepperParams(status_mon_enable=False))
    stepper(kl_status=STATUS_ERROR, kl_status2=0x00FF)
    assert axis.state is S.STANDSTILL
    stepper(destall_params=PowerStepperParams(status_mon_enable=True))
    assert axis.state is S.ERROR_STOP and axis.axis_error_id == ErrorId.DRIVE_NOT_READY


# -- MC_Power behaviour ------------------------------------------------------------------------

def test_mc_power_behaviour_status_override_and_errors() -> None:
    rt = om.Runtime(CYCLE)
    axis = rt.add_axis("x")
    stepper = MC_PowerStepper(axis)
    assert stepper.destall_params == PowerStepperParams()
    assert stepper.destall_params is not MC_PowerStepper(axis).destall_params
    stepper(enable=True, override=68.123)
    assert stepper.status and axis.powered and axis.state is S.STANDSTILL
    assert axis.override == pytest.approx(0.68123)
    stepper(enable_positive=False)
    assert not axis.enable_positive
    stepper(override=120.0)
    assert stepper.error and stepper.error_id == ErrorId.INVALID_OVERRIDE
    stepper(override=50.0)
    assert not stepper.error and axis.override == 0.5
    axis.drive_ready = False
    stepper()
    assert not stepper.status and stepper.error_id == ErrorId.DRIVE_NOT_READY
    axis.drive_ready = True
    stepper(enable=False)
    assert not stepper.status and not stepper.error and axis.state is S.DISABLED


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"destall_params": PowerStepperParams(destall_mode=7)}, ErrorId.INVALID_MODE),
    ({"destall_params": "on"}, ErrorId.INVALID_MODE),
    ({"kl_status": 256}, ErrorId.INVALID_PARAMETER_VALUE),
    ({"kl_status2": -1}, ErrorId.INVALID_PARAMETER_VALUE),
    ({"kl_status": 1.5}, ErrorId.INVALID_PARAMETER_VALUE),
])
def test_bad_inputs_are_block_errors_but_power_still_works(inputs: dict,
                                                           error_id: ErrorId) -> None:
    rt = om.Runtime(CYCLE)
    axis = rt.add_axis("x")
    stepper = MC_PowerStepper(axis)
    stepper(enable=True, **inputs)
    assert stepper.error and stepper.error_id == error_id and stepper.status
    with pytest.raises(TypeError, match="did you mean 'kl_status'"):
        stepper(kl_statu=1)
