"""The cyclic runtime: virtual time, run/run_until, phase order, pacing."""

from __future__ import annotations

import pytest

import openmotion as om


def test_time_is_cycle_count_times_cycle_time():
    rt = om.Runtime(cycle_time=0.0005)
    rt.run(1.0)
    assert rt.cycle == 2000
    assert rt.now == 2000 * 0.0005


def test_run_until_returns_time_and_times_out_naming_predicate():
    rt = om.Runtime()
    assert rt.run_until(lambda: rt.cycle >= 5) == pytest.approx(0.005)

    def never() -> bool:
        return False

    with pytest.raises(TimeoutError, match="never"):
        rt.run_until(never, timeout=0.01)


def test_run_until_rejects_a_bool_with_a_hint():
    rt = om.Runtime()
    with pytest.raises(TypeError, match="lambda: cmd.done"):
        rt.run_until(True)  # type: ignore[arg-type]


def test_run_until_accepts_a_command():
    rt = om.Runtime()
    x = rt.add_axis("x")
    x.power()
    cmd = x.move_absolute(10.0, velocity=100.0)
    rt.run_until(cmd, timeout=2.0)
    assert cmd.done and x.set_position == 10.0


def test_programs_run_before_motion_and_observers_after():
    rt = om.Runtime()
    x = rt.add_axis("x")
    x.power()
    seen: list[tuple[str, float]] = []
    rt.add_program(lambda: seen.append(("program", x.set_position)))
    rt.add_observer(lambda runtime: seen.append(("observer", x.set_position)))
    x.move_velocity(100.0)
    rt.step()
    assert seen[0] == ("program", 0.0)  # programs see the previous motion step
    assert seen[1][0] == "observer" and seen[1][1] > 0.0


def test_invalid_cycle_time_is_a_config_error():
    with pytest.raises(om.ConfigError, match="cycle_time"):
        om.Runtime(cycle_time=0.0)


def test_duplicate_axis_and_unknown_parameter_are_config_errors():
    rt = om.Runtime()
    rt.add_axis("x")
    with pytest.raises(om.ConfigError, match="exists already"):
        rt.add_axis("x")
    with pytest.raises(om.ConfigError, match="max_velocty"):
        rt.add_axis("y", max_velocty=1.0)
    with pytest.raises(om.ConfigError, match="max_velocity"):
        rt.add_axis("z", max_velocity=-1.0)


def test_paced_runtime_waits_for_the_wall_clock_and_keeps_virtual_time():
    wall = [100.0]
    slept: list[float] = []

    def sleep(seconds: float) -> None:
        slept.append(seconds)
        wall[0] += seconds

    rt = om.PacedRuntime(cycle_time=0.01, clock=lambda: wall[0], sleep=sleep)
    rt.run(0.05)
    assert rt.cycle == 5
    assert sum(slept) == pytest.approx(0.05)
    assert rt.late_cycles == 0


def test_strict_paced_runtime_raises_when_it_falls_behind():
    wall = [0.0]

    def clock() -> float:
        wall[0] += 0.05  # every look at the clock costs 50 ms: hopelessly slow
        return wall[0]

    rt = om.PacedRuntime(cycle_time=0.001, strict=True, clock=clock, sleep=lambda s: None)
    with pytest.raises(om.FallingBehindError):
        rt.run(0.01)


def test_public_names_are_pinned():
    assert sorted(om.__all__) == sorted(
        ["DEFAULT_HOME_POSITION", "MC_DEFAULT", "MC_IGNORE", "MC_INVALID", "MC_MAXIMUM", "Axis",
         "AxisPara", "AxisParameters", "AxisState", "BufferMode", "Command", "CommandStatus",
         "ConfigError", "DecoupleMode", "Direction", "DriveModel", "ErrorId", "FallingBehindError",
         "NewPosAndVeloMode", "PacedRuntime", "ReadMode", "ReferenceMode", "Runtime",
         "SuperpositionMode", "TargetPositionType",
         "__version__"]
    )
