"""``openmotion bench fbcall``: the cost of one PLC-style evaluation of ``MC_MoveAbsolute``.

A PLC program calls every FB instance every cycle, mostly with unchanged inputs while the
command runs, so this is the per-block floor of any program. Measured with ``execute`` held
TRUE after the rising edge, while the move is busy (the common path), in two forms: with the
inputs passed as keywords on each call, as PLC code reads, and as a bare ``fb()`` call on
stored inputs. ``FunctionBlock.strict`` (a test-only invariant check) is off while timing,
as it is for users. ``Runtime.step()`` with one moving axis is measured for context.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from typing import Any

import openmotion as om
from openmotion.kernel.handshake import FunctionBlock
from openmotion.plcopen import MC_MoveAbsolute

REPEATS = 7
FAR = 1.0e6  #: a target so far away that the move stays busy through every repeat [mm]


def _busy_axis() -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime(cycle_time=0.001)
    axis = rt.add_axis("x", max_velocity=1000.0)
    axis.power()
    return rt, axis


def _per_call_us(call: Callable[[], Any], calls: int) -> float:
    """Median over ``REPEATS`` runs of ``calls`` calls, in µs per call (loop included)."""
    samples = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        for _ in range(calls):
            call()
        samples.append((time.perf_counter() - start) / calls * 1e6)
    return statistics.median(samples)


def run_fbcall(calls: int = 200_000) -> dict[str, Any]:
    """µs per unchanged-input ``MC_MoveAbsolute`` call, and µs per 1-axis ``Runtime.step()``."""
    strict = FunctionBlock.strict
    FunctionBlock.strict = False
    try:
        rt, axis = _busy_axis()
        fb = MC_MoveAbsolute(axis)
        fb(axis, execute=True, position=FAR, velocity=50.0)  # the rising edge starts the move
        rt.step()
        if not fb.busy:
            raise RuntimeError(f"MC_MoveAbsolute did not start: {fb.error_id.name} {fb.message}")

        def keywords() -> None:
            fb(axis, execute=True, position=FAR, velocity=50.0)

        keyword_us = _per_call_us(keywords, calls)
        bare_us = _per_call_us(fb, calls)
        busy = fb.busy and not fb.done
        empty_us = _per_call_us(lambda: None, calls)
        steps = max(calls // 20, 1000)
        step_us = _per_call_us(rt.step, steps)
        moving = axis.set_velocity != 0.0
    finally:
        FunctionBlock.strict = strict
    return {
        "calls": calls,
        "repeats": REPEATS,
        "fb_call_us": keyword_us,
        "fb_call_bare_us": bare_us,
        "empty_call_us": empty_us,
        "still_busy": busy,
        "step_1_axis_us": step_us,
        "step_axis_moving": moving,
    }
