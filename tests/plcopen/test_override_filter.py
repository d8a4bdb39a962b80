"""MC_OverrideFilter (TcMC §4.19; digest rules 120-125, Open Q28, Q29)."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.core.override import DWORD_FULL_SCALE as FULL_SCALE
from openmotion.plcopen.override_filter import MC_OverrideFilter, quantise

ErrorId = om.ErrorId
FULL = 32767


def filter_on_runtime(**inputs: object) -> tuple[om.Runtime, MC_OverrideFilter]:
    rt = om.Runtime()  # 1 ms cycle
    return rt, MC_OverrideFilter(rt, **inputs)


def run(rt: om.Runtime, f: MC_OverrideFilter, cycles: int, **inputs: object) -> None:
    """Call the block, then step, ``cycles`` times (a PLC task calling it every cycle)."""
    for _ in range(cycles):
        f(**inputs)
        rt.step()


def check_scaling(f: MC_OverrideFilter) -> None:
    """Rule 125: the DWORD output is the percentage times 10 000."""
    assert f.override_value_filtered == round(f.override_percent_filtered * 10_000)
    assert isinstance(f.override_value_filtered, int)


# -- rule 121: quantisation ----------------------------------------------------------------------


def test_defaults_half_scale_is_a_multiple_of_half_a_percent_near_50() -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=16384)
    assert not f.error
    assert f.override_percent_filtered == 50.0
    assert f.override_value_filtered == 500_000
    assert (f.override_percent_filtered / 0.5).is_integer()
    check_scaling(f)


@pytest.mark.parametrize("raw", [0, 1, 81, 82, 163, 164, 5000, 12345, 16383, 20000, 32685,
                                 32686, 32766, 32767])
def test_default_output_is_always_a_multiple_of_the_step(raw: int) -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=raw)
    step = f.override_percent_filtered / 0.5
    assert step == int(step)
    assert abs(f.override_percent_filtered - raw / FULL * 100) <= 0.25 + 1e-12  # nearest step
    check_scaling(f)


def test_rounding_is_to_the_nearest_step_halves_up() -> None:
    """Q29: round, not floor. One step of 200 is 163.835 digits at the defaults."""
    assert quantise(81, 0, FULL, 200) == 0  # 0.494 step
    assert quantise(82, 0, FULL, 200) == 1  # 0.5005 step
    assert quantise(32685, 0, FULL, 200) == 199  # 199.4995
    assert quantise(32686, 0, FULL, 200) == 200  # 199.5056: 100 % within half a step of the top
    assert quantise(5, 0, 10, 2) == 1  # exactly half way: up
    assert quantise(1, 0, 8, 2) == 0 and quantise(7, 0, 8, 2) == 2  # 0.25, 1.75 steps


def test_other_step_counts_and_thresholds() -> None:
    rt, f = filter_on_runtime(override_steps=4, lower_override_threshold=1000,
                              upper_override_threshold=9000)
    f(override_value_raw=3000)  # 1/4 of the span
    assert f.override_percent_filtered == 25.0
    assert f.override_value_filtered == 250_000
    rt2, g = filter_on_runtime(override_steps=3)
    g(override_value_raw=FULL // 3 + 1)
    assert g.override_percent_filtered == pytest.approx(100 / 3)
    assert g.override_value_filtered == 333_333
    check_scaling(g)


# -- rule 122: clamping ---------------------------------------------------------------------------


def test_raw_below_lower_gives_0_and_above_upper_gives_100() -> None:
    rt, f = filter_on_runtime(lower_override_threshold=2000, upper_override_threshold=30000)
    f(override_value_raw=-5)
    assert (f.override_percent_filtered, f.override_value_filtered) == (0.0, 0)
    f(override_value_raw=1999)
    assert f.override_percent_filtered == 0.0
    f(override_value_raw=30001)
    assert (f.override_percent_filtered, f.override_value_filtered) == (100.0, FULL_SCALE)
    f(override_value_raw=1_000_000)
    assert f.override_percent_filtered == 100.0
    assert not f.error


# -- rule 123: recovery time ----------------------------------------------------------------------


def test_a_change_waits_for_the_recovery_time_then_catches_up_with_the_latest_value() -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=16384)  # t = 0: first value applies at once
    assert f.override_percent_filtered == 50.0
    rt.step()
    run(rt, f, 50, override_value_raw=8192)  # t = 1 ms ... 50 ms
    assert f.override_percent_filtered == 50.0  # held
    run(rt, f, 50, override_value_raw=24576)  # t = 51 ... 100 ms: a later value
    assert f.override_percent_filtered == 50.0
    run(rt, f, 49, override_value_raw=24576)  # t = 101 ... 149 ms
    assert rt.now == pytest.approx(0.150)
    assert f.override_percent_filtered == 50.0
    f(override_value_raw=24576)  # t = 150 ms: recovery over, the latest value applies
    assert f.override_percent_filtered == 75.0
    assert f.override_value_filtered == 750_000
    rt.step()
    # the change at 150 ms starts a new recovery time
    run(rt, f, 149, override_value_raw=16384)  # 151 ... 299 ms
    assert f.override_percent_filtered == 75.0
    f(override_value_raw=16384)  # 300 ms
    assert rt.now == pytest.approx(0.300)
    assert f.override_percent_filtered == 50.0


def test_a_value_that_went_away_during_the_recovery_is_never_shown() -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=16384)
    rt.step()
    run(rt, f, 100, override_value_raw=8192)
    run(rt, f, 100, override_value_raw=16384)  # back to the shown value before 150 ms
    assert f.override_percent_filtered == 50.0
    run(rt, f, 100, override_value_raw=16384)
    assert f.override_percent_filtered == 50.0


def test_recovery_time_is_an_input_in_seconds() -> None:
    rt, f = filter_on_runtime(override_recovery_time=0.010)
    f(override_value_raw=16384)
    rt.step()
    run(rt, f, 9, override_value_raw=8192)  # 1 ... 9 ms
    assert f.override_percent_filtered == 50.0
    f(override_value_raw=8192)  # 10 ms
    assert f.override_percent_filtered == 25.0
    rt2, g = filter_on_runtime(override_recovery_time=0.0)
    for raw in (16384, 8192, 24576):
        g(override_value_raw=raw)
    assert g.override_percent_filtered == 75.0


def test_a_clock_callable_works_as_well_as_a_runtime() -> None:
    t = [0.0]
    f = MC_OverrideFilter(lambda: t[0])
    f(override_value_raw=16384)
    t[0] = 0.1
    f(override_value_raw=8192)
    assert f.override_percent_filtered == 50.0
    t[0] = 0.15
    f()
    assert f.override_percent_filtered == 25.0


def test_a_float_input_that_is_a_whole_number_is_accepted() -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=16384.0)
    assert not f.error
    assert f.override_percent_filtered == 50.0


# -- rule 124: 0 % and 100 % at once --------------------------------------------------------------


def test_0_and_100_percent_apply_in_the_same_cycle() -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=16384)
    rt.step()
    f(override_value_raw=0)  # 1 ms after a change: still at once
    assert (f.override_percent_filtered, f.override_value_filtered) == (0.0, 0)
    rt.step()
    f(override_value_raw=FULL)
    assert (f.override_percent_filtered, f.override_value_filtered) == (100.0, FULL_SCALE)
    rt.step()
    f(override_value_raw=-100)  # clamped to 0 %: at once as well
    assert f.override_percent_filtered == 0.0


def test_after_a_jump_to_0_percent_an_intermediate_value_waits_again() -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=16384)
    rt.step()
    f(override_value_raw=0)  # t = 1 ms
    rt.step()
    run(rt, f, 149, override_value_raw=8192)  # 2 ... 150 ms
    assert f.override_percent_filtered == 0.0
    f(override_value_raw=8192)  # 151 ms
    assert f.override_percent_filtered == 25.0


# -- rule 120: errors -----------------------------------------------------------------------------


@pytest.mark.parametrize("inputs", [
    {"override_steps": 1},
    {"override_steps": 0},
    {"lower_override_threshold": 100, "upper_override_threshold": 100},
    {"lower_override_threshold": 200, "upper_override_threshold": 100},
    {"override_recovery_time": -0.001},
    {"override_recovery_time": float("nan")},
    {"override_value_raw": 12.5},
    {"override_value_raw": float("inf")},
    {"override_steps": True},
])
def test_bad_parameters_give_an_error_with_zero_outputs(inputs: dict[str, object]) -> None:
    rt, f = filter_on_runtime()
    f(override_value_raw=16384)
    assert f.override_percent_filtered == 50.0
    f(**{"override_value_raw": 16384, **inputs})
    assert f.error
    assert f.error_id == ErrorId.INVALID_PARAMETER_VALUE  # MC_ERROR_PARAMETER_NOT_CORRECT (Q28)
    assert f.message
    assert (f.override_percent_filtered, f.override_value_filtered) == (0.0, 0)


def test_the_error_clears_when_the_inputs_are_valid_again() -> None:
    rt, f = filter_on_runtime(override_steps=1)
    f(override_value_raw=16384)
    assert f.error
    rt.step()
    f(override_steps=200)  # 1 ms later: the first valid value applies at once
    assert not f.error
    assert f.error_id == ErrorId.NO_ERROR
    assert f.message == ""
    assert f.override_percent_filtered == 50.0


def test_a_misspelt_input_is_a_type_error_and_a_clock_is_required() -> None:
    rt, f = filter_on_runtime()
    with pytest.raises(TypeError, match="override_steps"):
        f(override_step=100)
    with pytest.raises(TypeError):
        MC_OverrideFilter(object())  # type: ignore[arg-type]


def test_the_filter_is_deterministic() -> None:
    def trace() -> list[int]:
        rt, f = filter_on_runtime()
        out = []
        for k in range(1000):  # a slow ramp with noise, then a jump to the top
            f(override_value_raw=30 * k + (k * 97) % 50 if k < 900 else FULL)
            out.append(f.override_value_filtered)
            check_scaling(f)
            rt.step()
        return out

    first = trace()
    assert first == trace()
    assert len(set(first)) > 5
