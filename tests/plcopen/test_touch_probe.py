"""MC_TouchProbe / MC_AbortTrigger (TcMC §4.21, §4.22, structures §6.3; rules 128-135)."""

from __future__ import annotations

from typing import Any

import pytest

import openmotion as om
from openmotion.axis.probe import (
    PROBE_ALREADY_ARMED,
    InputRef,
    ProbeSignal,
    SignalEdge,
    TouchProbeSource,
    TouchProbeState,
    armed_cycle,
)
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.plcopen.touch_probe import MC_AbortTrigger, MC_TouchProbe

V = 100.0  # mm/s; the ramp to V ends after a few ms


def rig(**signal: Any) -> tuple[om.Runtime, om.Axis, list[tuple[float, float]]]:
    """A powered axis with a probe input and a trace of (time, actual position) per cycle."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    assert axis.power()
    if signal:
        ProbeSignal(axis, **signal)
    samples: list[tuple[float, float]] = []
    rt.add_observer(lambda r: samples.append((r.now, axis.position)))
    return rt, axis, samples


def run_fb(rt: om.Runtime, fb: MC_TouchProbe, seconds: float) -> None:
    for _ in range(round(seconds / rt.cycle_time)):
        fb()
        rt.step()
    fb()


def test_rule_128_latch_is_the_edge_position_not_a_sample() -> None:
    """§4.21: the hardware latch is independent of the cycle time."""
    rt, axis, samples = rig(positions=[(123.4567, 150.25)])
    ref = InputRef()
    tp = MC_TouchProbe(axis)
    tp(execute=True, trigger_input=ref)
    assert tp.busy and not tp.done and ref.probe_state is TouchProbeState.ACTIVATED
    axis.move_velocity(V)
    run_fb(rt, tp, 1.5)
    assert tp.done and not tp.busy
    assert tp.recorded_position == pytest.approx(123.4567, abs=1e-9)
    assert min(abs(p - 123.4567) for _, p in samples) > 1e-3  # between two samples
    assert ref.probe_state is TouchProbeState.INACTIVE


def test_rule_128_falling_edge_and_latch_without_fb_calls() -> None:
    """§4.21, §6.3 Edge: the falling edge; the latch works while the FB is not called."""
    rt, axis, _ = rig(positions=[(123.4567, 150.25)])
    ref = InputRef(edge=SignalEdge.FALLING)
    tp = MC_TouchProbe(axis)
    tp(execute=True, trigger_input=ref)
    tp(execute=False)  # a pulse: the cycle stays armed
    axis.move_velocity(V)
    rt.run(2.0)  # the FB is not called at all
    assert tp.busy
    tp()
    assert tp.done and tp.recorded_position == pytest.approx(150.25, abs=1e-9)
    tp()
    assert not tp.done and not tp.busy  # short pulse: Done for one call
    assert tp.recorded_position == pytest.approx(150.25, abs=1e-9)  # holds its value


def test_rule_128_time_edge_interpolated_at_constant_velocity() -> None:
    """§4.21: an external edge at t = 1.0004 s, between the samples at 1.000 and 1.001 s."""
    rt, axis, samples = rig(times=[(1.0004, 2.0)])
    axis.move_velocity(V)
    ref = InputRef()
    tp = MC_TouchProbe(axis, execute=True, trigger_input=ref)
    tp()
    rt.run(1.1)
    tp()
    at = dict(samples)
    t0 = next(t for t in at if abs(t - 1.0) < 1e-9)
    exact = at[t0] + V * (1.0004 - t0)
    assert tp.done
    assert tp.recorded_position == pytest.approx(exact, abs=1e-9)
    assert abs(tp.recorded_position - at[t0]) > 0.03  # not the sample position


def test_negative_travel_enters_the_interval_at_its_upper_end() -> None:
    """§6.3 Edge: the signal rises where the axis enters the TRUE range."""
    rt, axis, _ = rig(positions=[(-80.0, -40.125)])
    tp = MC_TouchProbe(axis, trigger_input=InputRef())
    tp(execute=True)
    axis.move_velocity(V, direction=om.Direction.NEGATIVE)
    run_fb(rt, tp, 1.0)
    assert tp.done and tp.recorded_position == pytest.approx(-40.125, abs=1e-9)


def test_rule_129_window_rejects_and_rearms() -> None:
    """§4.21 WindowOnly: a trigger outside is rejected, the latch re-armed, Done later."""
    rt, axis, _ = rig(positions=[(50.0, 60.0), (150.5, 160.0), (250.0, 260.0)])
    ref = InputRef()
    tp = MC_TouchProbe(axis)
    tp(execute=True, trigger_input=ref, window_only=True, first_position=140.0,
       last_position=170.0)
    axis.move_velocity(V)
    run_fb(rt, tp, 1.0)
    cycle = armed_cycle(ref)
    assert cycle is not None and cycle.rejected == [pytest.approx(50.0)]
    assert tp.busy and not tp.done
    run_fb(rt, tp, 1.0)
    assert tp.done and tp.recorded_position == pytest.approx(150.5, abs=1e-9)
    run_fb(rt, tp, 1.5)  # the edge at 250 is not recorded any more
    assert tp.done and tp.recorded_position == pytest.approx(150.5, abs=1e-9)


def test_rule_129_window_bounds_are_inclusive() -> None:
    """Q35: [FirstPosition, LastPosition] is closed."""
    rt, axis, _ = rig(positions=[(100.0, 120.0)])
    tp = MC_TouchProbe(axis, trigger_input=InputRef(), window_only=True,
                       first_position=90.0, last_position=100.0)
    tp(execute=True)
    axis.move_velocity(V)
    run_fb(rt, tp, 1.2)
    assert tp.done and tp.recorded_position == 100.0


def test_rule_130_modulo_window_wraps() -> None:
    """§4.21 figure B, §6.3 ModuloPositions: 350..10 on a 360 axis takes 355 and 5, not 180."""
    rt, axis, _ = rig(positions=[(180.0, 181.0), (355.0, 356.0), (365.0, 366.0)])
    ref = InputRef(modulo_positions=True)
    tp = MC_TouchProbe(axis, trigger_input=ref, window_only=True, first_position=350.0,
                       last_position=10.0)
    tp(execute=True)
    axis.move_velocity(V)
    run_fb(rt, tp, 2.5)
    assert armed_cycle(ref).rejected == [pytest.approx(180.0)]
    run_fb(rt, tp, 1.1)
    assert tp.done and tp.recorded_position == pytest.approx(355.0, abs=1e-9)
    tp(execute=False)
    tp(execute=True)  # a new cycle after Done
    assert tp.busy
    run_fb(rt, tp, 0.2)
    assert tp.done and tp.recorded_position == pytest.approx(5.0, abs=1e-9)  # 365 modulo


def test_rule_130_modulo_window_without_wrap() -> None:
    """§4.21 figure A: First < Last repeats every period; 375 is 15 in 10..20."""
    rt, axis, _ = rig(positions=[(15.5, 16.0), (375.0, 376.0)])
    ref = InputRef(modulo_positions=True)
    tp = MC_TouchProbe(axis, trigger_input=ref, window_only=True, first_position=10.0,
                       last_position=20.0)
    axis.move_velocity(V)
    rt.run(1.0)  # past the first mark before arming
    tp(execute=True)
    run_fb(rt, tp, 3.0)
    assert tp.done and tp.recorded_position == pytest.approx(15.0, abs=1e-9)


def test_rule_131_absolute_window_exists_once() -> None:
    """§4.21, §6.3: ModuloPositions FALSE: a trigger at First + period is rejected."""
    rt, axis, _ = rig(positions=[(465.0, 470.0)])
    ref = InputRef()
    tp = MC_TouchProbe(axis, trigger_input=ref, window_only=True, first_position=100.0,
                       last_position=110.0)
    tp(execute=True)
    axis.move_velocity(V)
    run_fb(rt, tp, 5.0)
    assert tp.busy and not tp.done
    assert armed_cycle(ref).rejected == [pytest.approx(465.0)]


def test_rule_132_dropping_execute_keeps_the_cycle() -> None:
    """§4.21 note: only Done, Error or CommandAborted end a cycle; no second cycle while armed."""
    rt, axis, _ = rig(positions=[(50.0, 60.0)])
    ref = InputRef()
    tp = MC_TouchProbe(axis, trigger_input=ref)
    tp(execute=True)
    run_fb(rt, tp, 0.01)
    tp(execute=False)
    run_fb(rt, tp, 0.01)
    assert tp.busy and ref.probe_state is TouchProbeState.ACTIVATED
    tp(execute=True)  # same instance: ignored while armed (Busy gate)
    assert tp.busy and not tp.error
    other = MC_TouchProbe(axis, trigger_input=ref)
    other(execute=True)  # another instance on the armed InputRef
    assert other.error and other.error_id == PROBE_ALREADY_ARMED and not other.busy
    axis.move_velocity(V)
    run_fb(rt, tp, 1.0)
    assert tp.done and tp.recorded_position == pytest.approx(50.0, abs=1e-9)


def test_rule_133_abort_trigger() -> None:
    """§4.22: MC_AbortTrigger with the same InputRef interrupts the cycle."""
    rt, axis, _ = rig(positions=[(50.0, 60.0), (80.0, 90.0)])
    ref = InputRef()
    tp = MC_TouchProbe(axis, trigger_input=ref)
    abort = MC_AbortTrigger(axis, trigger_input=ref)
    tp(execute=True)
    tp(execute=False)
    run_fb(rt, tp, 0.01)
    abort(execute=True)
    assert abort.done and not abort.busy and not abort.error
    assert ref.probe_state is TouchProbeState.ABORTED
    tp()
    assert tp.command_aborted and not tp.busy and not tp.done
    tp()
    assert not tp.command_aborted  # shown for one call (Execute was FALSE)
    axis.move_velocity(V)
    run_fb(rt, tp, 0.7)
    assert not tp.done  # the edge at 50 finds the latch disarmed
    tp(execute=True)  # a new cycle can start now
    assert tp.busy and ref.probe_state is TouchProbeState.ACTIVATED
    run_fb(rt, tp, 0.5)
    assert tp.done and tp.recorded_position == pytest.approx(80.0, abs=1e-9)
    abort(execute=False)
    abort(execute=True)  # nothing armed: nothing to interrupt
    assert abort.done


def test_rule_133_abort_needs_the_same_input_ref() -> None:
    """§4.22: the same MC_InputRef structure; an equal-looking copy does not abort."""
    rt, axis, _ = rig(positions=[(50.0, 60.0)])
    ref = InputRef()
    tp = MC_TouchProbe(axis, trigger_input=ref, execute=True)
    tp()
    MC_AbortTrigger(axis, trigger_input=InputRef(), execute=True)()
    assert tp.busy and ref.probe_state is TouchProbeState.ACTIVATED


def test_rule_134_plc_event_records_the_cycle_position() -> None:
    """§6.3 PlcEvent: a rising edge records the current position (cycle resolution)."""
    rt, axis, samples = rig()
    ref = InputRef(touch_probe=TouchProbeSource.PLC_EVENT, plc_event=True)
    tp = MC_TouchProbe(axis, trigger_input=ref, execute=True)
    axis.move_velocity(V)
    run_fb(rt, tp, 0.3)
    assert tp.busy  # TRUE at the Execute edge is no rising edge
    ref.plc_event = False
    run_fb(rt, tp, 0.1)
    ref.plc_event = True  # raised by the PLC in the next cycle
    tp()
    rt.step()
    tp()
    assert tp.done
    assert tp.recorded_position == samples[-1][1]  # the position at the end of that cycle


def test_rule_135_touch_probe_2_to_4_unsupported() -> None:
    """§6.3 E_TouchProbe: only TouchProbe1 is supported; others are an FB error."""
    _, axis, _ = rig()
    for source in (2, 3, 4, 7):
        ref = InputRef(touch_probe=source)
        tp = MC_TouchProbe(axis, trigger_input=ref, execute=True)
        tp()
        assert tp.error and tp.error_id == ErrorId.INVALID_MODE and not tp.busy
        assert ref.probe_state is TouchProbeState.INACTIVE


def test_bad_windows_are_errors() -> None:
    """Q35: an empty absolute window, or modulo bounds outside 0..period, can never be Done."""
    _, axis, _ = rig()
    cases = [
        (InputRef(), 20.0, 10.0),
        (InputRef(), float("nan"), 10.0),
        (InputRef(modulo_positions=True), 0.0, 400.0),
    ]
    for ref, first, last in cases:
        tp = MC_TouchProbe(axis, trigger_input=ref, window_only=True, first_position=first,
                           last_position=last, execute=True)
        tp()
        assert tp.error and tp.error_id == ErrorId.INVALID_POSITION


def test_sensor_stays_put_when_coordinates_shift() -> None:
    """§4.12 with §4.21: the probe sits at a machine position; results are displayed ones."""
    rt, axis, _ = rig(positions=[(50.0, 60.0)])
    axis.set_actual_position(1000.0)
    tp = MC_TouchProbe(axis, trigger_input=InputRef(), execute=True)
    axis.move_velocity(V)
    run_fb(rt, tp, 0.7)
    assert tp.done and tp.recorded_position == pytest.approx(1050.0, abs=1e-9)


def test_signal_configuration_errors() -> None:
    _, axis, _ = rig()
    with pytest.raises(ConfigError):
        ProbeSignal(axis, positions=[(10.0, 5.0)])
    with pytest.raises(ConfigError):
        ProbeSignal(axis, positions=[(0.0, 5.0), (5.0, 6.0)])
    with pytest.raises(ConfigError):
        ProbeSignal(axis, positions=[(0.0, 1.0)], times=[(0.0, 1.0)])
    with pytest.raises(TypeError):
        MC_TouchProbe(axis, execute=True)()
