"""``openmotion bench sweep``: what the executors cost per point.

The same short points (one axis, one move of about 0.2 s simulated: the overhead shows, not
the simulation) run three ways:

- serial: one after another in this process (``run_point``, warm), the floor;
- the process pool with ``workers`` processes (``run_sweep``, no output directory);
- Ray: a local cluster of ``workers`` CPUs started on 127.0.0.1 first (its start is timed
  apart), then the same sweep on it twice: the first sweep starts the cluster's worker
  processes, which load openmotion and its compiled loops on their first task (seconds,
  as for a user's first sweep); the next one finds them loaded, as every later sweep on a
  standing cluster does (D-354).

Per executor: points per second, seconds per point, the overhead per point (worker seconds
spent per point beyond the serial seconds: ``wall * workers / points - serial``) and the
efficiency per worker (``rate / (workers * serial rate)``; 1 is perfect scaling). For serial
and the pool also the CPU seconds per point (this process and the pool's workers), which the
machine's load does not change: their difference is the pool's own cost. Wall
times on a shared machine depend on its load: the one-minute load average at the start is
part of the result.
"""

from __future__ import annotations

import os
import resource
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

Progress = Callable[[str], None] | None
POINTS = 200
WORKERS = 2
BASE = """\
name: bench point
cycle_time: 0.001
axes:
  - name: x
    parameters: {max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0,
                 jerk: 200000.0}
timeline:
  - {id: enable, at: 0.0, axis: x, command: power}
  - {id: go, when: enable.done, axis: x, command: move_absolute, position: 20.0,
     velocity: 200.0}
record:
  signals: [x.set_position, x.set_velocity]
checks:
  - {command: go, result: done}
"""
SWEEP = """\
scenario: base.yaml
parameters:
  - path: timeline[go].velocity
    linspace: {{start: 100.0, stop: 400.0, num: {points}}}
metrics:
  - {{signal: x.set_velocity, stats: [max]}}
  - {{run: [end_time, cycles]}}
"""


def run_sweep_bench(points: int = POINTS, workers: int = WORKERS, ray: bool = True,
                    progress: Progress = None) -> dict[str, Any]:
    """Serial, pool and (with ``ray``) Ray figures for ``points`` short points."""
    from openmotion.sweep import compared, expand, load_sweep, run_sweep
    from openmotion.sweep.worker import run_point

    with tempfile.TemporaryDirectory(prefix="openmotion-bench-sweep-") as folder:
        Path(folder, "base.yaml").write_text(BASE, encoding="utf-8")
        Path(folder, "sweep.yaml").write_text(SWEEP.format(points=points), encoding="utf-8")
        sweep = load_sweep(Path(folder, "sweep.yaml"))
    expanded = expand(sweep)
    run_point(expanded[0], sweep.metrics)  # loads the compiled loops: not a point's cost
    _say(progress, f"sweep: {points} points one after another in this process")
    started, cpu = time.perf_counter(), _cpu()
    for point in expanded:
        run_point(point, sweep.metrics)
    serial = time.perf_counter() - started
    results: dict[str, Any] = {"points": points, "workers": workers,
                               "load_average": os.getloadavg()[0],
                               "serial": {**_figures(points, serial, 1, serial),
                                          "cpu_s_per_point": (_cpu() - cpu) / points}}
    _say(progress, f"sweep: the process pool, {workers} workers")
    started, cpu = time.perf_counter(), _cpu()
    pool = run_sweep(sweep, workers=workers)
    results["pool"] = {**_figures(points, time.perf_counter() - started, workers, serial),
                       "cpu_s_per_point": (_cpu() - cpu) / points,
                       "failed": int((pool["status"] != "done").sum())}
    results["ray"] = None
    if ray:
        results["ray"] = _ray(sweep, points, workers, serial, progress)
        table = results["ray"].pop("table")
        results["ray"]["same_table"] = bool(compared(table, sweep).equals(compared(pool, sweep)))
    return results


def _ray(sweep: Any, points: int, workers: int, serial: float,
         progress: Progress) -> dict[str, Any]:
    import ray

    from openmotion.sweep import run_sweep
    from openmotion.sweep.executors import RAY_OBJECT_STORE_BYTES

    _say(progress, f"sweep: starting a local Ray cluster of {workers} CPUs")
    started = time.perf_counter()
    ray.init(num_cpus=workers, include_dashboard=False, _node_ip_address="127.0.0.1",
             object_store_memory=RAY_OBJECT_STORE_BYTES, log_to_driver=False,
             configure_logging=False)
    start = time.perf_counter() - started
    try:
        _say(progress, "sweep: the same points on Ray")
        started = time.perf_counter()
        table = run_sweep(sweep, workers=workers, ray=True)
        figures = _figures(points, time.perf_counter() - started, workers, serial)
        _say(progress, "sweep: the same points on Ray again, its workers loaded")
        started = time.perf_counter()
        again = run_sweep(sweep, workers=workers, ray=True)
        figures["next"] = {**_figures(points, time.perf_counter() - started, workers, serial),
                           "failed": int((again["status"] != "done").sum())}
    finally:
        ray.shutdown()
    return {**figures, "start_s": start, "failed": int((table["status"] != "done").sum()),
            "table": table}


def _figures(points: int, wall: float, workers: int, serial: float) -> dict[str, Any]:
    rate, serial_rate = points / wall, points / serial
    return {"wall_s": wall, "points_per_s": rate, "s_per_point": wall / points,
            "overhead_s_per_point": wall * workers / points - serial / points,
            "efficiency_per_worker": rate / (workers * serial_rate)}


def _cpu() -> float:
    """CPU seconds of this process and of its finished children (the pool's workers)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), \
        resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _say(progress: Progress, text: str) -> None:
    if progress is not None:
        progress(text)
