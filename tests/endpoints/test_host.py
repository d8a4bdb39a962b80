"""The endpoints' host: one kernel thread steps the machine, clients read snapshots of one
cycle and start commands through the wire's checks (D-255, D-256)."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from openmotion import Runtime
from openmotion.core.enums import AxisState, BufferMode
from openmotion.core.errors import ConfigError
from openmotion.endpoints import HostError, MachineHost, Pace, WireError, WireKind
from openmotion.kernel.model import machine
from openmotion.scenario import examples_dir

EXAMPLES = examples_dir()


class FakeClock:
    """A wall clock that moves only when a test moves it (thread-safe enough: one float)."""

    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def two_axes() -> Runtime:
    rt = Runtime(0.001)
    rt.add_axis("x")
    rt.add_axis("y")
    return rt


@pytest.fixture
def lockstep():
    with MachineHost(two_axes(), pace="lockstep") as host:
        yield host


def test_a_move_started_by_a_client_runs_and_its_handle_follows_the_handshake(lockstep):
    assert lockstep.switch("x", "power", {"enable": True}) is True
    ticket = lockstep.call("x", "move_absolute", {"position": 10.0, "velocity": 100.0})
    started = lockstep.handle(ticket)
    assert (started.busy, started.active, started.done) == (True, True, False)
    snapshot = lockstep.run_for(1.0)
    ended = lockstep.handle(ticket)
    assert (ended.busy, ended.done, ended.error, ended.error_id) == (False, True, False, 0)
    assert lockstep.value("x.position", snapshot) == pytest.approx(10.0, abs=1e-9)
    assert snapshot.cycle == 1000


def test_a_lockstep_machine_matches_the_same_machine_stepped_by_hand_bit_for_bit(lockstep):
    """The host adds nothing to the motion: same commands, same cycles, same values."""
    by_hand = two_axes()
    by_hand.axes["y"].power()
    by_hand.axes["y"].move_velocity(velocity=33.0)
    lockstep.switch("y", "power")
    lockstep.call("y", "move_velocity", {"velocity": 33.0})
    for cycles in (1, 7, 250):
        snapshot = lockstep.advance(cycles)
        for _ in range(cycles):
            by_hand.step()
        expected = [signal.read() for signal in machine(by_hand).signals().values()]
        np.testing.assert_array_equal(snapshot.values, np.array(expected))


def test_a_snapshot_is_one_cycle_of_every_signal_of_the_model(lockstep):
    names = [f"{obj.name}.{signal.name}" for obj in lockstep.model for signal in obj.signals]
    assert list(lockstep.names) == names
    snapshot = lockstep.advance(3)
    assert snapshot.values.shape == (len(names),)
    assert (snapshot.cycle, snapshot.time) == (3, pytest.approx(0.003))
    assert lockstep.value("x.state", snapshot) == float(AxisState.DISABLED)


@pytest.mark.parametrize(("inputs", "message"), [
    ({"position": "far", "velocity": 1.0}, "takes a number or one of MC_DEFAULT"),
    ({"position": float("nan"), "velocity": 1.0}, "must be finite"),
    ({"position": True, "velocity": 1.0}, "takes a number"),
    ({"positon": 1.0, "velocity": 1.0}, "no input 'positon'"),
    ({"velocity": 1.0}, "'position' is required"),
    ({"position": 1.0, "velocity": 1.0, "buffer_mode": "SOMETIMES"}, "no BufferMode 'SOMETIMES'"),
    ({"position": 1.0, "velocity": 1.0, "buffer_mode": 99}, "99 is no BufferMode"),
])
def test_a_bad_input_is_refused_before_the_machine_is_touched(lockstep, inputs, message):
    lockstep.switch("x", "power")
    before = lockstep.advance(1)
    with pytest.raises(WireError, match=message):
        lockstep.call("x", "move_absolute", inputs)
    after = lockstep.advance(1)
    assert after.handles == before.handles  # no command was started
    assert lockstep.value("x.state", after) == float(AxisState.STANDSTILL)
    ticket = lockstep.call("x", "move_absolute", {"position": 1.0, "velocity": 10.0})
    assert lockstep.handle(ticket).busy  # and the host goes on serving


def test_enums_travel_by_name_or_number_and_special_values_by_name(lockstep):
    lockstep.switch("x", "power")
    first = lockstep.call("x", "move_absolute",
                          {"position": 5.0, "velocity": "MC_MAXIMUM", "buffer_mode": "aborting"})
    second = lockstep.call("x", "move_absolute", {
        "position": 8.0, "velocity": 10.0, "buffer_mode": int(BufferMode.BUFFERED)})
    lockstep.run_for(2.0)
    assert lockstep.handle(first).done and lockstep.handle(second).done
    assert lockstep.value("x.position") == pytest.approx(8.0, abs=1e-9)


def test_another_object_travels_by_its_name(lockstep):
    lockstep.switch("x", "power")
    lockstep.switch("y", "power")
    with pytest.raises(WireError, match="no Axis 'z'; one of x, y"):
        lockstep.call("y", "gear_in", {"master": "z", "ratio": 1.0})
    ticket = lockstep.call("y", "gear_in", {"master": "x", "ratio": 2.0})
    lockstep.call("x", "move_velocity", {"velocity": 10.0})
    lockstep.run_for(0.5)
    assert lockstep.handle(ticket).active  # coupled: the slave follows at twice the speed
    assert lockstep.value("y.velocity") == pytest.approx(20.0, abs=1e-9)


def test_levels_and_edges_are_not_confused(lockstep):
    with pytest.raises(ConfigError, match="use switch"):
        lockstep.call("x", "power")
    with pytest.raises(ConfigError, match="use call"):
        lockstep.switch("x", "halt")
    with pytest.raises(ConfigError, match="no command 'jump' served"):
        lockstep.call("x", "jump")
    with pytest.raises(ConfigError, match="no object 'w'"):
        lockstep.call("w", "halt")
    with pytest.raises(ConfigError, match="no command 424242"):
        lockstep.handle(424242)


def test_lockstep_controls_check_their_arguments(lockstep):
    for bad in (-1, 1.5, True, "3"):
        with pytest.raises(ConfigError, match="cycles must be a whole number"):
            lockstep.advance(bad)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="seconds must be a finite number"):
        lockstep.run_for(float("inf"))
    assert lockstep.advance(0).cycle == 0  # nothing broken


def test_a_wall_paced_machine_follows_the_clock_times_its_speed():
    clock = FakeClock()
    with MachineHost(two_axes(), clock=clock, speed=2.0) as host:
        with pytest.raises(HostError, match="advance needs pace 'lockstep'"):
            host.advance(1)
        first = host.snapshot
        time.sleep(0.05)  # the kernel thread anchors its pace at the fake clock's now
        clock.now += 0.050  # 50 ms of wall time at speed 2: 100 cycles due
        snapshot = _wait_for_cycle(host, first.cycle + 100)
        assert snapshot.cycle == first.cycle + 100
        host.pause()
        paused_at = host.snapshot.cycle
        clock.now += 1.0
        time.sleep(0.1)
        assert host.snapshot.cycle == paused_at  # a paused machine stands
        host.set_speed(1.0)
        host.resume()
        clock.now += 0.010  # no catching up after the pause: 10 cycles, not 1010
        assert _wait_for_cycle(host, paused_at + 10).cycle == paused_at + 10
        status = host.status()
        assert status.pace is Pace.WALL and status.speed == 1.0 and not status.paused
        assert "running ×1" in status.line()


def _wait_for_cycle(host: MachineHost, cycle: int, timeout: float = 5.0):
    deadline = time.monotonic() + timeout
    snapshot = host.snapshot
    while snapshot.cycle < cycle and time.monotonic() < deadline:
        snapshot = host.wait_snapshot(snapshot.seq, timeout=timeout)
    time.sleep(0.05)  # and no more cycles after it
    return host.snapshot


def test_bad_host_settings_are_config_errors():
    with pytest.raises(ConfigError, match="pace must be one of wall, lockstep"):
        MachineHost(two_axes(), pace="sometimes")
    with pytest.raises(ConfigError, match="speed must be a number"):
        MachineHost(two_axes(), speed=0)


def test_a_stopped_host_refuses_requests_and_counts_its_clients():
    host = MachineHost(two_axes(), pace=Pace.LOCKSTEP)
    with pytest.raises(HostError, match="not running"):
        host.advance(1)
    with host, host.client("opcua"), host.client("opcua"), host.client("ads"):
        assert host.status().clients == {"opcua": 2, "ads": 1}
        assert "clients: 1 ads, 2 opcua" in host.status().line()
    assert host.status().clients == {}
    with pytest.raises(HostError, match="not running"):
        host.call("x", "halt")


def test_requests_from_many_threads_each_get_their_own_answer(lockstep):
    lockstep.switch("x", "power")
    tickets: list[int] = []

    def client() -> None:
        tickets.append(lockstep.call("x", "move_relative", {"distance": 1.0, "velocity": 5.0,
                                                            "buffer_mode": "BUFFERED"}))

    threads = [threading.Thread(target=client) for _ in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert sorted(tickets) == list(range(1, 9))
    lockstep.run_for(5.0)
    assert all(lockstep.handle(ticket).done for ticket in tickets)
    assert lockstep.value("x.position") == pytest.approx(8.0, abs=1e-9)


def test_a_served_scenario_plays_its_timeline_and_serves_its_objects():
    """Every object of the model is served, each command with a wire form for every input
    it needs; a planar position travels as an array of three numbers."""
    with MachineHost.for_scenario(EXAMPLES / "planar_two_movers.yaml", pace="lockstep") as host:
        kinds = {obj.kind for obj in host.model}
        assert "planar_mover" in kinds
        mover = next(obj.name for obj in host.model if obj.kind == "planar_mover")
        move = host.command(mover, "move_to_position")
        target = next(put for put in move.inputs if put.name == "target")
        assert (target.kind, target.length) == (WireKind.VECTOR, 4)  # x, y, c, reference id
        assert all(put.kind is not WireKind.NONE for put in move.inputs)
        with pytest.raises(WireError, match="takes 1 to 4 numbers, not 5"):
            host.call(mover, "move_to_position", {"target": [1.0, 2.0, 3.0, 0.0, 5.0]})
        with pytest.raises(WireError, match="reference_id takes a whole number"):
            host.call(mover, "move_to_position", {"target": [1.0, 2.0, 3.0, 0.5]})
        before = host.snapshot.cycle
        assert host.run_for(0.1).cycle == before + 100
