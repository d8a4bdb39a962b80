"""`serve` benchmark: a machine paced by the wall clock while real clients read it.

N axes (100) move at constant, different velocities on a 1 ms cycle, paced by the wall
clock (``MachineHost``, D-256) and served by OPC UA and ADS at once. Two client processes,
each a real library, run for the same wall time:

- asyncua subscribes to 3 signals of each axis (300 values) at a 10 ms publishing and
  sampling interval and counts the notifications; a notification is lost when the
  subscription's message sequence numbers skip one, or a value arrives with the Overflow
  bit (the server's queue dropped one). Then it times reads of one value.
- pyads sum-reads 300 symbols every 10 ms (one request each), and times reads of one symbol
  by name (three requests: handle, read, release) and by handle.

The host measures how late each motion cycle finished against its wall-clock slot (p99 over
the run, after a warm-up). Clients run in their own processes. The run is made twice in one
benchmark: with the kernel in a process of its own (``ProcessHost``, what ``serve`` does,
D-320), and with the kernel on a thread of the servers' process (``MachineHost``), where it
competes with the servers' threads for the interpreter.
"""

from __future__ import annotations

import asyncio
import json
import subprocess
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np

SIGNALS = ("position", "velocity", "set_position")  #: per axis: OPC UA node ids
ADS_SIGNALS = ("ActPos", "ActVelo", "SetPos")  #: the same three as ADS symbols
INTERVAL = 0.010  #: the clients' sampling / polling interval [s]
READS = 300  #: single reads timed per client and kind
WARM_UP = 2.0  #: wall seconds before the clients start (servers and machine settle)

Progress = Callable[[str], Any] | None


def _machine(axes: int):  # noqa: ANN202 - a runtime
    from openmotion import Runtime

    rt = Runtime(0.001)
    for number in range(axes):
        axis = rt.add_axis(f"a{number}", max_velocity=5000.0, acceleration=20000.0,
                           deceleration=20000.0, jerk=200000.0)
        axis.power()
        axis.move_velocity(velocity=10.0 + number)  # every value changes every cycle
    return rt


KERNELS = ("process", "thread")  #: where the kernel steps: the first is the one judged


def run_serve(axes: int = 100, seconds: float = 10.0, progress: Progress = None) \
        -> dict[str, Any]:
    """Both kernels, one after the other; the figures of the kernel process at the top
    level, those of the kernel thread under ``thread``."""
    result = _run(axes, seconds, "process", progress)
    result["thread"] = _run(axes, seconds, "thread", progress)
    return result


def _run(axes: int, seconds: float, kernel: str, progress: Progress) -> dict[str, Any]:
    from openmotion.endpoints import MachineHost, ProcessHost, serve

    host = (ProcessHost if kernel == "process" else MachineHost)(_machine(axes), pace="wall")
    served = serve(host, opcua={"port": 0}, ads={"port": 0})
    if progress:
        progress(f"serve: starting OPC UA and ADS for {axes} axes, the kernel in a {kernel}")
    with served:
        opcua_url = served.urls()["opcua"]
        ads_port = served.endpoints["ads"].port
        time.sleep(WARM_UP)
        first = host.status()
        if progress:
            progress(f"serve: clients for {seconds:g} s")
        clients = [_client("opcua", opcua_url, axes, seconds),
                   _client("ads", str(ads_port), axes, seconds)]
        started = host.snapshot.cycle
        results = [_result(client) for client in clients]
        status = host.status()
        cycles = host.snapshot.cycle - started
    opcua, ads = results
    return {
        "kernel": kernel, "kernel_priority": getattr(host, "kernel_priority", None), "axes": axes,
        "cycle_ms": 1.0, "seconds": seconds, "cycles": cycles,
        "late_p99_ms": status.late_p99_ms, "late_max_ms": status.late_max_ms,
        "slips": status.slips - first.slips,
        "opcua": opcua, "ads": ads,
    }


def _client(kind: str, where: str, axes: int, seconds: float) -> subprocess.Popen[str]:
    return subprocess.Popen(  # noqa: S603 - our own module, our own arguments
        [sys.executable, "-m", "openmotion.bench.serve", kind, where, str(axes), str(seconds)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _result(client: subprocess.Popen[str]) -> dict[str, Any]:
    out, err = client.communicate(timeout=300)
    if client.returncode != 0:
        raise RuntimeError(f"a serve benchmark client failed: {err.strip()[-2000:]}")
    return json.loads(out)


def _percentiles(samples: list[float], scale: float = 1e6) -> dict[str, float]:
    values = np.array(samples) * scale
    return {"p50": float(np.percentile(values, 50)), "p99": float(np.percentile(values, 99))}


# -- the clients (each in its own process) -----------------------------------------------------

def opcua_client(url: str, axes: int, seconds: float) -> dict[str, Any]:

    return asyncio.run(_opcua(url, axes, seconds))


async def _opcua(url: str, axes: int, seconds: float) -> dict[str, Any]:
    from asyncua import Client, ua

    from openmotion.endpoints.opcua.space import NAMESPACE_URI

    class Handler:
        def __init__(self) -> None:
            self.values = 0
            self.overflows = 0

        def datachange_notification(self, node: Any, value: Any, data: Any) -> None:
            self.values += 1
            status = data.monitored_item.Value.StatusCode
            if status is not None and status.value & 0x80:  # InfoType DataValue, Overflow
                self.overflows += 1

    async with Client(url, timeout=30) as client:
        namespace = await client.get_namespace_index(NAMESPACE_URI)
        nodes = [client.get_node(ua.NodeId(f"a{k}.{name}", namespace))
                 for k in range(axes) for name in SIGNALS]
        handler = Handler()
        subscription = await client.create_subscription(INTERVAL * 1e3, handler)
        numbers: list[int] = []
        # asyncua hands each publish response to a callback its session keeps by
        # subscription id; wrapping it is the one way to see the messages' sequence numbers
        callbacks = client.uaclient.session._subscription_callbacks  # noqa: SLF001
        publish = callbacks[subscription.subscription_id]

        def counted(result: Any) -> Any:
            message = result.NotificationMessage
            if message.NotificationData:  # a keep-alive repeats the next number
                numbers.append(message.SequenceNumber)
            return publish(result)

        callbacks[subscription.subscription_id] = counted
        await subscription.subscribe_data_change(nodes, sampling_interval=INTERVAL * 1e3)
        await asyncio.sleep(seconds)
        await subscription.delete()
        gaps = sum(max(0, b - a - 1) for a, b in zip(numbers, numbers[1:], strict=False))
        times = []
        for _ in range(READS):
            start = time.perf_counter()
            await nodes[0].read_value()
            times.append(time.perf_counter() - start)
    return {"subscribed": len(nodes), "notifications": handler.values,
            "messages": len(numbers), "messages_per_second": len(numbers) / seconds,
            "lost": gaps + handler.overflows,
            "per_value_per_second": handler.values / len(nodes) / seconds,
            "read_us": _percentiles(times)}


def ads_client(port: str, axes: int, seconds: float) -> dict[str, Any]:
    import pyads

    connection = pyads.Connection("127.0.0.1.1.1", 851, f"127.0.0.1:{port}")
    connection.open()
    try:
        names = [f"a{k}.NcToPlc.{name}" for k in range(axes) for name in ADS_SIGNALS]
        sums, late = [], 0
        deadline = time.perf_counter() + seconds
        tick = time.perf_counter()
        while time.perf_counter() < deadline:
            start = time.perf_counter()
            values = connection.read_list_by_name(names)
            sums.append(time.perf_counter() - start)
            if len(values) != len(names):
                raise RuntimeError(f"a sum read gave {len(values)} of {len(names)} values")
            tick += INTERVAL
            wait = tick - time.perf_counter()
            if wait > 0:
                time.sleep(wait)
            else:
                late += 1
                tick = time.perf_counter()
        by_name, by_handle = [], []
        for _ in range(READS):
            start = time.perf_counter()
            connection.read_by_name(names[0], pyads.PLCTYPE_LREAL)
            by_name.append(time.perf_counter() - start)
        handle = connection.get_handle(names[0])
        for _ in range(READS):
            start = time.perf_counter()
            connection.read_by_name("", pyads.PLCTYPE_LREAL, handle=handle)
            by_handle.append(time.perf_counter() - start)
        connection.release_handle(handle)
    finally:
        connection.close()
    return {"symbols": len(names), "sum_reads": len(sums), "late_polls": late,
            "sum_read_ms": _percentiles(sums, 1e3), "read_by_name_us": _percentiles(by_name),
            "read_by_handle_us": _percentiles(by_handle)}


if __name__ == "__main__":
    kind, where, count, span = sys.argv[1:5]
    run = opcua_client if kind == "opcua" else ads_client
    print(json.dumps(run(where, int(count), float(span))))
