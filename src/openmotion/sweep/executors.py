"""Where the points run: a local process pool (the default) or a Ray cluster.

Both yield ``(point, row)`` as points finish, in any order; the sweep orders the table by
point index, so the executor never shows in the result. A point whose worker process dies is
run again, ``retries`` times at most; after that its row says the worker died (D-252).

The pool is our own, one pipe per worker process: unlike ``concurrent.futures``, whose pool
breaks as a whole when one worker dies, it knows which point was in the dead process and
starts a new worker in its place. Workers are forked (where the platform can): they start
in milliseconds with the runner and its compiled loops already loaded, and never import the
caller's ``__main__`` again as spawned processes do.
"""

from __future__ import annotations

import contextlib
import gc
import multiprocessing
import multiprocessing.connection
import os
import signal
from collections import Counter, deque
from collections.abc import Iterator
from typing import Any

from openmotion.sweep.metrics import Metric
from openmotion.sweep.points import Point
from openmotion.sweep.worker import PointHook, failed_row, run_point

DEFAULT_RETRIES = 2  #: new attempts for a point whose worker died
POOL_QUEUE_DEPTH = 2  #: points sent to a pool worker ahead: it never waits for the parent
STOP_TIMEOUT = 2.0  #: seconds a worker gets to stop before it is terminated
RAY_OBJECT_STORE_BYTES = 100 * 1024 * 1024  #: a local cluster's object store (rows are tiny)
RAY_IN_FLIGHT_PER_CPU = 2  #: tasks submitted per cluster CPU ahead of the results
Results = Iterator[tuple[Point, dict[str, Any]]]


def default_workers() -> int:
    """The CPUs this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def _died(code: int | None, attempts: int) -> dict[str, Any]:
    return {**failed_row(f"worker died (exit code {code}) on each of {attempts} attempts"),
            "lost": True}


class _Worker:
    def __init__(self, context: Any, metrics: list[Metric], on_point: PointHook | None) -> None:
        self.connection, child = context.Pipe()
        self.process = context.Process(target=_serve, args=(child, metrics, on_point),
                                       daemon=True, name="openmotion-sweep-worker")
        self.process.start()
        child.close()

    def stop(self) -> None:
        with contextlib.suppress(OSError):
            self.connection.send(None)
        self.process.join(STOP_TIMEOUT)
        if self.process.is_alive():
            self.process.terminate()
            self.process.join()
        self.connection.close()


def _serve(connection: Any, metrics: list[Metric], on_point: PointHook | None) -> None:
    """A pool process: run the points it is sent until it is sent None."""
    gc.freeze()  # the heap inherited from the parent: no collection walks (and copies) it
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C is the parent's to handle
    while (point := connection.recv()) is not None:
        connection.send(run_point(point, metrics, on_point))


class ProcessPool:
    """``workers`` local processes, each running its points in the order sent. Each has the
    next point waiting in its pipe, so that it never idles while the parent, on a loaded
    machine, waits to be scheduled."""

    def __init__(self, metrics: list[Metric], workers: int | None = None,
                 retries: int = DEFAULT_RETRIES, on_point: PointHook | None = None) -> None:
        self.metrics, self.on_point, self.retries = metrics, on_point, retries
        self.workers = workers or default_workers()
        methods = multiprocessing.get_all_start_methods()
        self._context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
        self._started: list[_Worker] = []

    def _start(self) -> _Worker:
        worker = _Worker(self._context, self.metrics, self.on_point)
        self._started.append(worker)
        return worker

    def results(self, points: list[Point]) -> Results:
        waiting = deque(points)
        queued = {self._start(): deque() for _ in range(min(self.workers, len(points)))}
        attempts: Counter[int] = Counter()
        while waiting or any(queued.values()):
            for worker, sent in queued.items():
                while waiting and len(sent) < POOL_QUEUE_DEPTH:
                    sent.append(waiting.popleft())
                    worker.connection.send(sent[-1])
            busy = [worker for worker, sent in queued.items() if sent]
            ready = set(multiprocessing.connection.wait(
                [w.connection for w in busy] + [w.process.sentinel for w in busy]))
            for worker in busy:
                if worker.connection not in ready and worker.process.sentinel not in ready:
                    continue
                rows, alive = self._receive(worker)
                for row in rows:
                    yield queued[worker].popleft(), row
                if alive:
                    continue
                lost = queued.pop(worker)
                queued[self._start()] = deque()
                if not lost:
                    continue
                point = lost.popleft()  # the one it was running; the rest never started
                waiting.extendleft(reversed(lost))
                attempts[point.index] += 1
                if attempts[point.index] > self.retries:
                    yield point, _died(worker.process.exitcode, attempts[point.index])
                else:
                    waiting.appendleft(point)

    @staticmethod
    def _receive(worker: _Worker) -> tuple[list[dict[str, Any]], bool]:
        """The rows the worker has sent, and whether it lives (a dead one is joined)."""
        rows = []
        try:
            while worker.connection.poll():
                rows.append(worker.connection.recv())
            if worker.process.is_alive():
                return rows, True
        except (EOFError, OSError):
            pass
        worker.process.join()
        worker.connection.close()
        return rows, False

    def close(self) -> None:
        for worker in self._started:
            if worker.process.exitcode is None:
                worker.stop()
        self._started.clear()


class RayExecutor:
    """Points as Ray tasks. ``address`` None starts a local cluster on 127.0.0.1 with
    ``workers`` CPUs; an address (``auto``, ``ray://host:10001``, ``host:6379``) joins one.
    A Ray session already running in this process is used as it is, and left running."""

    def __init__(self, metrics: list[Metric], address: str | None = None,
                 workers: int | None = None, retries: int = DEFAULT_RETRIES,
                 on_point: PointHook | None = None) -> None:
        import ray

        self.metrics, self.on_point, self.retries = metrics, on_point, retries
        self._ray = ray
        self._pending: dict[Any, Point] = {}
        self._started = not ray.is_initialized()
        if not self._started:
            return
        options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False,
                                   "configure_logging": False}
        if address is None:
            ray.init(num_cpus=workers or default_workers(), _node_ip_address="127.0.0.1",
                     object_store_memory=RAY_OBJECT_STORE_BYTES, **options)
        else:
            ray.init(address=address, **options)

    def results(self, points: list[Point]) -> Results:
        ray = self._ray
        task = ray.remote(num_cpus=1, max_retries=self.retries)(run_point)
        metrics, on_point = ray.put(self.metrics), ray.put(self.on_point)
        window = max(1, int(ray.cluster_resources().get("CPU", 1)) * RAY_IN_FLIGHT_PER_CPU)
        waiting = deque(points)
        while waiting or self._pending:
            while waiting and len(self._pending) < window:
                point = waiting.popleft()
                self._pending[task.remote(point, metrics, on_point)] = point
            ready, _ = ray.wait(list(self._pending), num_returns=1)
            for reference in ready:
                point = self._pending.pop(reference)
                try:
                    row = ray.get(reference)
                except ray.exceptions.RayError as exc:  # the worker died every attempt
                    row = {**failed_row(f"worker died on each of {self.retries + 1} attempts: "
                                        f"{type(exc).__name__}"), "lost": True}
                yield point, row

    def close(self) -> None:
        for reference in self._pending:
            self._ray.cancel(reference, force=True)
        self._pending.clear()
        if self._started:
            self._ray.shutdown()
