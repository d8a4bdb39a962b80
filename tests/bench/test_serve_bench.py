"""``openmotion bench serve``: both real clients run and the figures have their shape;
never timings (the goals are the benchmark's, not the test's)."""

from __future__ import annotations

import json

from openmotion.bench.runner import render, run_benchmark


def test_quick_serves_ten_axes_to_asyncua_and_pyads_at_once() -> None:
    result = run_benchmark("serve", quick=True)
    r = result["results"]
    assert r["axes"] == 10 and r["cycles"] > 0
    opcua, ads = r["opcua"], r["ads"]
    assert opcua["subscribed"] == 30 and opcua["notifications"] > 0 and opcua["messages"] > 0
    assert opcua["read_us"]["p50"] > 0
    assert ads["symbols"] == 30 and ads["sum_reads"] > 0
    assert ads["read_by_name_us"]["p50"] > ads["read_by_handle_us"]["p50"] > 0  # 3 requests
    assert set(result["goals"]) == {"lateness", "lost"}
    # judged on the kernel process (what serve runs); the kernel thread shown beside it
    assert r["kernel"] == "process" and r["kernel_priority"] in ("realtime", "nice -10", "normal")
    thread = r["thread"]
    assert thread["kernel"] == "thread" and thread["cycles"] > 0
    assert thread["opcua"]["notifications"] > 0 and thread["ads"]["sum_reads"] > 0
    json.loads(json.dumps(result, allow_nan=False))
    text = render(result)
    assert "read by handle" in text
    assert "kernel in a process" in text and "kernel in a thread" in text
