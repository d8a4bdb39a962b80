"""When MC_Move…Done becomes TRUE (TcMC §7.1; digest §1.6; rules 5-8) and the monitors behind
it: in-target timeout (1027/1028) and following-error monitoring (1019-1021).

All runs use a lag drive (first order 10 ms behind a 2 ms dead time), so the actual position
trails the set position and the windows matter.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import pytest

import openmotion as om
from openmotion.plcopen import (
    MC_MoveAbsolute,
    MC_MoveAbsoluteOrRestart,
    MC_MoveVelocity,
    MC_ReadAxisError,
)

ErrorId = om.ErrorId
S = om.AxisState
CYCLE = 0.001
LAG = om.DriveModel(model="lag", time_constant=0.01, dead_time=0.002)
TARGET = 100.0


@dataclass
class Sample:
    done: bool
    busy: bool
    has_job: bool
    error: float  #: |actual - target|
    set_position: float


@dataclass
class Run:
    samples: list[Sample] = field(default_factory=list)

    @property
    def done_at(self) -> int:
        return next(i for i, s in enumerate(self.samples) if s.done)

    @property
    def profile_end(self) -> int:
        """First sample where the setpoint generator has no job any more."""
        return next(i for i, s in enumerate(self.samples) if not s.has_job)


def move_with(range_on: bool, target_on: bool, max_cycles: int = 5000,
              block: type = MC_MoveAbsolute, **overrides: Any
              ) -> tuple[Run, om.Axis, MC_MoveAbsolute]:
    rt = om.Runtime()
    axis = rt.add_axis("x", drive=LAG, enable_position_range_monitoring=range_on,
                       enable_target_position_monitoring=target_on, **overrides)
    axis.power()
    move = block(axis)
    run = Run()
    for _ in range(max_cycles):
        move(execute=True, position=TARGET, velocity=200.0)
        run.samples.append(Sample(move.done, move.busy, axis.has_job,
                                  abs(axis.position - TARGET), axis.set_position))
        if move.done or move.error or move.command_aborted:
            break
        rt.step()
    return run, axis, move


def test_both_monitors_on_done_after_the_monitoring_time_in_the_target_window() -> None:
    """Rule 6, §7.1 case 1: Done = NOT HasJob AND IsAtTargetPosition, i.e. the actual
    position stayed inside the target window (1025) for the monitoring time (1026)."""
    window, time = 0.01, 0.03
    run, axis, move = move_with(True, True, target_position_window=window,
                                target_position_monitoring_time=time)
    assert move.done
    done, end = run.done_at, run.profile_end
    needed = round(time / CYCLE)
    # counted only after HasJob fell (§7.1); the cycle in which the profile ends counts
    assert done - end >= needed - 1
    inside = run.samples[done - needed + 1:done + 1]
    assert all(s.error <= window for s in inside)
    # and not later than needed: the window was met continuously from done - needed + 1
    assert run.samples[done - needed].error > window or done - needed < end
    assert run.samples[end].error > window  # the window really delayed Done


def test_range_monitor_only_done_when_inside_the_range_window() -> None:
    """Rule 7, §7.1 case 2: Done = NOT HasJob AND InPositionWindow (1023)."""
    window = 0.005
    run, axis, move = move_with(True, False, position_range_window=window,
                                target_position_monitoring_time=1.0)
    assert move.done
    done = run.done_at
    assert not run.samples[done].has_job
    assert run.samples[done].error <= window
    # the first sample without job inside the window is the Done sample
    first_ok = next(i for i, s in enumerate(run.samples) if not s.has_job and s.error <= window)
    assert done == first_ok
    assert run.samples[run.profile_end].error > window  # the window delayed it


def test_both_monitors_off_done_at_the_end_of_the_profile_despite_following_error() -> None:
    """Rule 8, §7.1 case 3: Done as soon as HasJob is FALSE, following error or not."""
    run, axis, move = move_with(False, False, position_range_window=1e-6,
                                target_position_window=1e-6)
    assert move.done
    done = run.done_at
    assert done == run.profile_end
    assert run.samples[done].set_position == TARGET
    assert run.samples[done].error > 1e-3  # the actual position is still on its way


def test_target_monitor_only_uses_the_at_target_rule() -> None:
    """§7.1 leaves out range OFF + target ON (Open Q6); our decision: the at-target rule,
    as in case 1."""
    window, time = 0.01, 0.03
    run, axis, move = move_with(False, True, target_position_window=window,
                                target_position_monitoring_time=time,
                                position_range_window=1e-9)  # would block case 2
    assert move.done
    done, needed = run.done_at, round(time / CYCLE)
    assert done - run.profile_end >= needed - 1
    assert all(s.error <= window for s in run.samples[done - needed + 1:done + 1])


@pytest.mark.parametrize(("range_on", "target_on"),
                         [(True, True), (True, False), (False, False), (False, True)])
@pytest.mark.parametrize("block", [MC_MoveAbsolute, MC_MoveAbsoluteOrRestart])
def test_done_never_while_the_axis_has_a_job(range_on: bool, target_on: bool,
                                             block: type) -> None:
    """Rule 5, §7.1/§3.6: Done is never TRUE while AxisHasJob is TRUE."""
    run, axis, move = move_with(range_on, target_on, block=block)
    assert move.done
    assert not any(s.done and s.has_job for s in run.samples)
    assert not any(s.done and s.busy for s in run.samples)


def test_default_monitoring_done_about_20_cycles_after_the_profile() -> None:
    """Defaults: range window 5, target window 2 mm for 0.02 s → Done 20 cycles after the
    end of the profile (the actual position is inside 2 mm already; the cycle in which the
    profile ends is the first monitored one)."""
    run, axis, move = move_with(True, True)
    assert 19 <= run.done_at - run.profile_end <= 20
    assert axis.set_position == TARGET


# -- in-target timeout ---------------------------------------------------------------------


def test_in_target_timeout_error_when_the_window_cannot_be_met() -> None:
    """1027/1028: a target window the lag drive cannot reach within the timeout → the axis
    goes to ErrorStop IN_TARGET_TIMEOUT and the move FB reports CommandAborted."""
    timeout = 0.015
    run, axis, move = move_with(True, True, target_position_window=1e-9,
                                enable_in_target_timeout=True, in_target_timeout=timeout)
    assert move.command_aborted and not move.done
    assert axis.state is S.ERROR_STOP
    assert axis.axis_error_id == ErrorId.IN_TARGET_TIMEOUT
    elapsed = len(run.samples) - 1 - run.profile_end
    assert round(timeout / CYCLE) - 1 <= elapsed <= round(timeout / CYCLE) + 1
    read = MC_ReadAxisError(axis)
    read(enable=True)
    assert read.axis_error_id == ErrorId.IN_TARGET_TIMEOUT and not read.error


def test_in_target_timeout_not_reached_when_the_window_is_met() -> None:
    """1027/1028: with a reachable window the timeout does not fire; Done comes normally."""
    run, axis, move = move_with(True, True, enable_in_target_timeout=True,
                                in_target_timeout=0.5)
    assert move.done and axis.state is S.STANDSTILL


def test_in_target_timeout_disabled_waits_without_error() -> None:
    """1027 FALSE: an unreachable window only delays Done; no error within a long wait."""
    run, axis, move = move_with(True, True, max_cycles=1500, target_position_window=0.0,
                                enable_in_target_timeout=False, in_target_timeout=0.001)
    assert axis.state is not S.ERROR_STOP
    assert move.busy or move.done
    assert axis.set_position == TARGET


# -- following-error monitoring -------------------------------------------------------------


def test_following_error_gives_error_stop_with_a_controlled_stop() -> None:
    """1019-1021: following error above the limit longer than the filter time → ErrorStop
    FOLLOWING_ERROR; the setpoint brakes without a jump; the move reports CommandAborted."""
    rt = om.Runtime()
    axis = rt.add_axis("x", drive=LAG, max_position_lag=1.0, position_lag_filter_time=0.005)
    axis.power()
    move = MC_MoveVelocity(axis)
    p, v, a, lag = [], [], [], []
    fault_at = None
    for cycle in range(1500):
        move(execute=True, velocity=300.0)
        p.append(axis.set_position)
        v.append(axis.set_velocity)
        a.append(axis.set_acceleration)
        lag.append(abs(axis.following_error))
        if axis.state is S.ERROR_STOP and fault_at is None:
            fault_at = cycle
        rt.step()
    assert fault_at is not None
    assert axis.axis_error_id == ErrorId.FOLLOWING_ERROR
    assert move.command_aborted and not move.busy and not move.error
    # the limit was exceeded for longer than the filter time before the fault
    over = [e > 1.0 for e in lag[:fault_at]]
    assert all(over[-5:])
    assert not all(over[-7:])  # not much longer either: 5 ms filter, 1 ms cycles
    # controlled stop: the set velocity goes to 0, continuously
    assert v[-1] == 0.0 and axis.set_velocity == 0.0
    params = axis.parameters
    for k in range(1, len(v)):
        assert abs(v[k] - v[k - 1]) <= params.max_deceleration * CYCLE * (1 + 1e-9) + 1e-9
        assert abs(p[k] - p[k - 1]) <= 300.0 * CYCLE * (1 + 1e-9)
    assert axis.state is S.ERROR_STOP


def test_following_error_monitoring_off_never_faults() -> None:
    """1019 FALSE: the same move with monitoring off runs on."""
    rt = om.Runtime()
    axis = rt.add_axis("x", drive=LAG, max_position_lag=1.0, position_lag_filter_time=0.005,
                       enable_position_lag_monitoring=False)
    axis.power()
    move = MC_MoveVelocity(axis)
    for _ in range(500):
        move(execute=True, velocity=300.0)
        rt.step()
    assert axis.state is S.CONTINUOUS_MOTION and move.in_velocity
    assert abs(axis.following_error) > 1.0
