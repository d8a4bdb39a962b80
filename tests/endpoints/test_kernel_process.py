"""A kernel in a process of its own (D-320): the same machine, the same values, the same
errors as on a kernel thread; snapshots cross whole through shared memory; a dead kernel
process is reported, never waited on for ever."""

from __future__ import annotations

import os
import signal
import threading
import time

import numpy as np
import pytest

from openmotion import Runtime
from openmotion.core.errors import ConfigError
from openmotion.endpoints import (
    HandleState,
    HostError,
    MachineHost,
    ProcessHost,
    Snapshot,
    SnapshotBoard,
    WireError,
    serve,
)
from openmotion.kernel.model import machine
from openmotion.scenario import examples_dir


def two_axes() -> Runtime:
    rt = Runtime(0.001)
    rt.add_axis("x")
    rt.add_axis("y")
    return rt


@pytest.fixture
def host():
    with ProcessHost(two_axes(), pace="lockstep") as served:
        yield served


def test_the_kernel_steps_in_another_process(host):
    assert host.kernel_pid not in (None, os.getpid())
    host.switch("x", "power")
    host.call("x", "move_velocity", {"velocity": 20.0})
    host.advance(100)
    # the servers' copy of the machine stays at rest: only the kernel process moves it
    assert host.machine.runtime.cycle == 0
    assert host.snapshot.cycle == 100


def test_a_move_follows_the_handshake_across_the_processes(host):
    assert host.switch("x", "power", {"enable": True}) is True
    ticket = host.call("x", "move_absolute", {"position": 10.0, "velocity": 100.0})
    started = host.handle(ticket)
    assert (started.busy, started.active, started.done) == (True, True, False)
    snapshot = host.run_for(1.0)
    ended = host.handle(ticket)
    assert (ended.busy, ended.done, ended.error, ended.error_id) == (False, True, False, 0)
    assert host.value("x.position", snapshot) == pytest.approx(10.0, abs=1e-9)
    assert snapshot.cycle == 1000


def test_the_kernel_process_matches_the_machine_stepped_by_hand_bit_for_bit(host):
    by_hand = two_axes()
    by_hand.axes["y"].power()
    by_hand.axes["y"].move_velocity(velocity=33.0)
    host.switch("y", "power")
    host.call("y", "move_velocity", {"velocity": 33.0})
    for cycles in (1, 7, 250):
        snapshot = host.advance(cycles)
        for _ in range(cycles):
            by_hand.step()
        expected = [signal.read() for signal in machine(by_hand).signals().values()]
        np.testing.assert_array_equal(snapshot.values, np.array(expected))


def test_a_thread_and_a_process_kernel_publish_the_same_snapshots():
    """A served example in lockstep: the same commands give the same values on both."""
    example = examples_dir() / "planar_two_movers.yaml"
    runs = []
    for cls in (MachineHost, ProcessHost):
        with cls.for_scenario(example, pace="lockstep") as served:
            runs.append([served.advance(n).values for n in (1, 10, 300)])
    for thread, process in zip(*runs, strict=True):
        np.testing.assert_array_equal(thread, process)


def test_bad_requests_fail_here_and_the_kernel_serves_on(host):
    with pytest.raises(WireError, match="position"):
        host.call("x", "move_absolute", {"position": "far"})
    with pytest.raises(ConfigError, match="no command 'fly'"):
        host.call("x", "fly")
    with pytest.raises(ConfigError, match="use switch"):
        host.call("x", "power")
    with pytest.raises(ConfigError, match="cycles must be a whole number"):
        host.advance(-1)
    with pytest.raises(HostError, match="code cannot be sent"):
        host.submit(lambda: None)
    # an error raised inside the kernel process comes back as itself
    with pytest.raises(ConfigError, match="no object 'z'"):
        host.call("z", "power")
    assert host.switch("x", "power") is True  # and the host is usable afterwards
    assert host.advance(2).cycle == 2


def test_a_wall_paced_kernel_process_moves_and_pauses():
    with ProcessHost(two_axes(), pace="wall") as host:
        host.switch("y", "power")
        host.call("y", "move_velocity", {"velocity": 50.0})
        first = host.wait_snapshot(host.snapshot.seq)
        later = host.wait_snapshot(first.seq + 20)
        assert later.cycle > first.cycle
        host.pause()  # taken between two batches: nothing is published after it
        paused = host.snapshot
        time.sleep(0.05)
        assert host.snapshot.cycle == paused.cycle  # nothing moves while paused
        status = host.status()
        assert status.paused and status.pace.value == "wall"
        host.resume()
        assert host.wait_snapshot(host.snapshot.seq).cycle > paused.cycle
        with pytest.raises(HostError, match="lockstep"):
            host.advance(1)


def test_a_dead_kernel_process_is_reported_and_requests_fail_fast(host):
    os.kill(host.kernel_pid, signal.SIGKILL)
    deadline = time.monotonic() + 5.0
    while host.running and time.monotonic() < deadline:
        time.sleep(0.01)
    assert not host.running
    with pytest.raises(HostError, match="kernel process ended"):
        host.advance(1)
    assert "kernel process ended" in host.status().failure
    assert host.snapshot.cycle == 0  # the last snapshot stays readable


def test_a_stopped_host_cannot_be_started_again():
    host = ProcessHost(two_axes(), pace="lockstep").start()
    host.stop()
    with pytest.raises(HostError, match="stopped"):
        host.start()
    with pytest.raises(HostError, match="not running"):
        host.advance(1)


def test_serve_runs_the_kernel_in_a_process_unless_told_otherwise():
    served = serve("single_move", pace="lockstep", ads={"port": 0})
    assert isinstance(served.host, ProcessHost)
    assert isinstance(serve("single_move", kernel="thread", ads=True).host, MachineHost)
    with pytest.raises(ConfigError, match="kernel must be one of process, thread"):
        serve("single_move", kernel="fibre", ads=True)
    with served:
        assert served.host.running and served.host.kernel_pid != os.getpid()
    assert not served.host.running


def snapshot_of(seq: int, size: int, handles: int = 0) -> Snapshot:
    """A snapshot whose every value is its ``seq``: a torn read would mix two."""
    return Snapshot(seq, seq, seq * 0.001, np.full(size, float(seq)),
                    {t: HandleState(busy=bool(seq % 2), error_id=seq) for t in range(handles)})


def test_a_reader_never_sees_half_of_a_snapshot():
    board = SnapshotBoard(4096)
    stop = threading.Event()

    def writer() -> None:
        seq = 1
        while not stop.is_set():
            board.write(snapshot_of(seq, 4096, handles=seq % 5))
            seq += 1

    thread = threading.Thread(target=writer)
    thread.start()
    try:
        seen = set()
        for _ in range(3000):
            snapshot = board.read()
            values = snapshot.values
            assert values.min() == values.max() == snapshot.seq == snapshot.cycle
            assert all(h.error_id == snapshot.seq for h in snapshot.handles.values())
            assert len(snapshot.handles) == snapshot.seq % 5
            seen.add(snapshot.seq)
    finally:
        stop.set()
        thread.join()
        board.close()
    assert len(seen) > 1  # the writer really wrote while we read


def test_a_board_keeps_only_running_commands_when_all_do_not_fit():
    board = SnapshotBoard(1, handle_bytes=4096)
    many = {t: HandleState(busy=t < 3, message="x" * 100) for t in range(200)}
    board.write(Snapshot(1, 1, 0.001, np.zeros(1), many))
    assert sorted(board.read().handles) == [0, 1, 2]
    board.close()


@pytest.mark.parametrize("priority", ["realtime", "nice", "normal"])
def test_the_kernel_thread_gets_the_priority_asked_for_where_the_system_allows(priority):
    with ProcessHost(two_axes(), pace="lockstep", priority=priority) as host:
        got = host.kernel_priority
        allowed = {"realtime": ("realtime", "nice -10", "normal"), "nice": ("nice -10", "normal"),
                   "normal": ("normal",)}[priority]
        assert got in allowed
        thread = host.kernel_thread_id  # what the scheduler says of it is what was reported
        policy = os.sched_getscheduler(thread)
        assert (policy == os.SCHED_FIFO) == (got == "realtime")
        if got != "realtime":
            ours = os.getpriority(os.PRIO_PROCESS, 0)
            assert os.getpriority(os.PRIO_PROCESS, thread) == \
                (max(-20, ours - 10) if got == "nice -10" else ours)
        assert host.advance(3).cycle == 3  # and it steps as before
    with pytest.raises(ConfigError, match="priority must be one of realtime, nice, normal"):
        ProcessHost(two_axes(), priority="urgent")
