"""Tests for the benchmark peers: the stream is reproducible and both peers really do the work."""

from __future__ import annotations

import math

import pytest
import ruckig

from openmotion.bench import peers
from openmotion.bench.peers import StreamCommand

MOVE = {"velocity": 200.0, "acceleration": 2000.0, "deceleration": 2000.0, "jerk": 20000.0}


def _abs(cycle: int, axis: int, target: float) -> StreamCommand:
    return StreamCommand(cycle=cycle, axis=axis, kind="absolute", value=target, **MOVE)


def _vel(cycle: int, axis: int, velocity: float) -> StreamCommand:
    params = {**MOVE, "velocity": abs(velocity)}
    return StreamCommand(cycle=cycle, axis=axis, kind="velocity", value=velocity, **params)


# Axis 0 is retargeted mid-motion (cycle 60), so the final position proves the takeover.
ABSOLUTE_ONLY = [_abs(0, 0, 40.0), _abs(0, 1, -25.0), _abs(10, 2, 12.5), _abs(60, 0, -10.0)]


def test_stream_is_deterministic_and_sorted() -> None:
    a = peers.random_command_stream(50, 2000, seed=7)
    assert a == peers.random_command_stream(50, 2000, seed=7)
    assert a != peers.random_command_stream(50, 2000, seed=8)
    keys = [(c.cycle, c.axis) for c in a]
    assert keys == sorted(keys)
    assert len(set(keys)) == len(keys)


def test_stream_ranges_and_mix() -> None:
    stream = peers.random_command_stream(200, 5000, seed=1, rate=2.0, cycle_time=0.001)
    expected = 200 * 5.0 * 2.0  # axes * seconds * rate
    assert 0.85 * expected < len(stream) < 1.15 * expected
    absolute = [c for c in stream if c.kind == "absolute"]
    velocity = [c for c in stream if c.kind == "velocity"]
    assert len(absolute) + len(velocity) == len(stream)
    assert 0.6 < len(absolute) / len(stream) < 0.8
    assert all(0 <= c.cycle < 5000 and 0 <= c.axis < 200 for c in stream)
    assert all(-500.0 <= c.value <= 500.0 for c in absolute)
    assert all(50.0 <= abs(c.value) <= 500.0 and c.velocity == abs(c.value) for c in velocity)
    assert any(c.value < 0 for c in velocity) and any(c.value > 0 for c in velocity)
    for c in stream:
        assert 50.0 <= c.velocity <= 500.0
        assert 500.0 <= c.acceleration <= 5000.0 and 500.0 <= c.deceleration <= 5000.0
        assert 5000.0 <= c.jerk <= 50000.0
        assert isinstance(c.cycle, int) and isinstance(c.value, float)


def test_stream_edge_cases() -> None:
    assert peers.random_command_stream(0, 100) == []
    assert peers.random_command_stream(5, 0) == []
    with pytest.raises(ValueError):
        peers.random_command_stream(-1, 10)


def test_index_rejects_unknown_axis_and_drops_late_commands() -> None:
    with pytest.raises(ValueError):
        peers._by_cycle([_abs(0, 3, 1.0)], 3, 10)
    slots = peers._by_cycle([_abs(2, 0, 1.0), _abs(10, 0, 2.0)], 1, 10)
    assert [len(s) for s in slots] == [0, 0, 1] + [0] * 7


def test_ruckig_loop_returns_positive_seconds() -> None:
    stream = peers.random_command_stream(3, 200, seed=0, rate=20.0)
    assert stream
    seconds = peers.run_ruckig_loop(3, stream, 200)
    assert isinstance(seconds, float) and seconds > 0.0


def test_ruckig_loop_reaches_last_absolute_targets() -> None:
    run = peers._drive_ruckig(3, ABSOLUTE_ONLY, 1000)
    assert run.final_positions == pytest.approx([-10.0, -25.0, 12.5], abs=1e-9)
    early = peers._drive_ruckig(3, ABSOLUTE_ONLY, 30)  # stepped, not run to completion
    assert 0.0 < early.final_positions[0] < 40.0


def test_ruckig_loop_velocity_command_keeps_moving() -> None:
    run = peers._drive_ruckig(1, [_vel(0, 0, -100.0)], 500)
    # 0.5 s at -100 mm/s minus the jerk-limited ramp-up: clearly negative, bounded by v * t.
    assert -50.0 < run.final_positions[0] < -30.0


def test_ruckig_widen_acceleration_recovers_rejected_input() -> None:
    # Exact state from a random stream where ruckig's velocity interface raised in step 1.
    inp = ruckig.InputParameter(1)
    inp.control_interface = ruckig.ControlInterface.Velocity
    inp.current_position = [-22.085273902030558]
    inp.current_velocity = [-386.4661122254108]
    inp.current_acceleration = [-2899.9442995429404]
    inp.target_velocity = [236.89167716228295]
    inp.max_velocity = [236.89167716228295]
    inp.max_acceleration = [3427.2840305712252]
    inp.min_acceleration = [-2834.3154969006023]
    inp.max_jerk = [19268.35497828148]
    otg, out = ruckig.Ruckig(1, 0.001), ruckig.OutputParameter(1)
    peers._widen_ruckig_acceleration(inp)
    assert inp.min_acceleration[0] < -2899.9442995429404
    assert inp.max_acceleration[0] == 3427.2840305712252
    assert otg.update(inp, out) == ruckig.Result.Working


def test_pyplcopen_returns_positive_seconds() -> None:
    pytest.importorskip("pyplcopen")
    stream = peers.random_command_stream(3, 200, seed=0, rate=20.0)
    seconds = peers.run_pyplcopen(3, stream, 200)
    assert isinstance(seconds, float) and seconds > 0.0


def test_pyplcopen_missing_gives_none(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(peers, "_import_pyplcopen", lambda: None)
    assert peers.run_pyplcopen(3, ABSOLUTE_ONLY, 10) is None


def test_pyplcopen_axes_move_and_take_over() -> None:
    pytest.importorskip("pyplcopen")
    stream = peers.random_command_stream(3, 200, seed=0, rate=20.0)
    moved = peers._drive_pyplcopen(3, stream, 200)
    assert moved is not None
    assert any(p != 0.0 for p in moved.final_positions)

    done = peers._drive_pyplcopen(3, ABSOLUTE_ONLY, 1000)
    assert done is not None
    assert done.final_positions == pytest.approx([-10.0, -25.0, 12.5], abs=1e-9)


def test_pyplcopen_steps_one_cycle_per_cycle_call() -> None:
    plc = pytest.importorskip("pyplcopen")
    cfg = plc.CycleConfig.at_1khz()
    cmd = _abs(0, 0, 40.0)
    args = (
        cmd.value,
        cfg.velocity_to_cycle(cmd.velocity),
        cfg.acceleration_to_cycle(cmd.acceleration),
        cfg.acceleration_to_cycle(cmd.deceleration),
        cfg.jerk_to_cycle(cmd.jerk),
    )
    for k in (1, 5, 50):
        stepped = peers._drive_pyplcopen(1, [cmd], k)
        assert stepped is not None
        reference = plc.AxisSim()  # pyplcopen's own internal loop, stopped after k cycles
        reference.power_on()
        with pytest.raises(RuntimeError, match="timed out"):
            reference.move_absolute(*args, max_cycles=k)
        assert stepped.final_positions[0] == reference.command_position()
        assert 0.0 < stepped.final_positions[0] < 40.0


def test_pyplcopen_velocity_command_moves_at_commanded_speed() -> None:
    pytest.importorskip("pyplcopen")
    run = peers._drive_pyplcopen(1, [_vel(0, 0, -100.0)], 500)
    assert run is not None
    # pyplcopen 0.21 steps straight to the target velocity: exactly v * t.
    assert math.isclose(run.final_positions[0], -50.0, abs_tol=1e-6)


def test_pyplcopen_infeasible_move_is_reissued() -> None:
    pytest.importorskip("pyplcopen")
    # At cycle 65 the axis accelerates at ~3000 mm/s^2, above the new command's 803 mm/s^2
    # deceleration: pyplcopen rejects it as infeasible, the driver re-issues it.
    stream = [
        StreamCommand(0, 0, "absolute", -317.0, 313.0, 4958.0, 4526.0, 47042.0),
        StreamCommand(65, 0, "absolute", -14.46, 207.0, 2103.0, 803.0, 26803.0),
    ]
    run = peers._drive_pyplcopen(1, stream, 1000)
    assert run is not None
    assert run.reissued == 1
    assert run.final_positions[0] == pytest.approx(-14.46, abs=1e-9)
