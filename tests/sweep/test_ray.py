"""Sweeps on a local Ray cluster (started by the sweep, 2 CPUs, stopped afterwards): the same
table as the process pool, bit for bit without the timing columns, with a worker killed
mid-sweep."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import pandas
import ray

from openmotion.sweep import compared, load_sweep, run_sweep
from openmotion.sweep.faults import FaultHook, runs

STOP_WAIT = 20.0  #: seconds Ray's processes get to end after the sweep
VELOCITY = {"path": "timeline[go].velocity", "linspace": {"start": 100.0, "stop": 400.0,
                                                          "num": 5}}
POSITION = {"path": "timeline[go].position", "values": [10.0, 20.0]}
MAX_VELOCITY = {"path": "axes[0].parameters.max_velocity", "values": [1000.0, -1.0]}


def _ray_processes() -> list[int]:
    """Ray's processes started from this one (the cluster's and its workers), from /proc."""
    parents: dict[int, int] = {}
    commands: dict[int, str] = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
            commands[int(entry.name)] = (entry / "cmdline").read_bytes().decode(
                errors="replace").replace("\0", " ")
        except OSError:
            continue
        parents[int(entry.name)] = int(stat.rsplit(")", 1)[1].split()[1])
    ours, found = {os.getpid()}, []
    for _ in range(len(parents)):
        more = {pid for pid, parent in parents.items() if parent in ours} - ours
        if not more:
            break
        ours |= more
    for pid in ours - {os.getpid()}:
        if "ray" in commands.get(pid, "").lower() and parents.get(pid) is not None:
            state = Path(f"/proc/{pid}/stat")
            if state.exists() and state.read_text().rsplit(")", 1)[1].split()[0] != "Z":
                found.append(pid)
    return found


def test_twenty_points_on_ray_give_the_pool_table_with_a_worker_killed(
        write_sweep, tmp_path: Path) -> None:
    sweep = load_sweep(write_sweep(parameters=[VELOCITY, POSITION, MAX_VELOCITY]))
    pool = run_sweep(sweep, tmp_path / "pool", workers=2)
    assert len(pool) == 20 and list(pool["status"]).count("failed") == 10
    markers = tmp_path / "markers"
    markers.mkdir()
    try:
        on_ray = run_sweep(sweep, tmp_path / "ray", workers=2, ray=True,
                           on_point=FaultHook(markers, exit_at=6))
    finally:
        deadline = time.monotonic() + STOP_WAIT
        while _ray_processes() and time.monotonic() < deadline:
            time.sleep(0.2)
        left = _ray_processes()
        for pid in left:  # ours: end them, then fail
            os.kill(pid, signal.SIGKILL)
    assert not left, left
    assert not ray.is_initialized()
    assert (markers / "exited").exists()
    assert runs(markers)[on_ray["point_id"][6]] == 2
    assert on_ray["status"][6] == "done"
    pandas.testing.assert_frame_equal(compared(pool, sweep), compared(on_ray, sweep),
                                      check_exact=True)
    assert (on_ray["cycle_cost.cpu"][on_ray["status"] == "done"] > 0).all()
