"""`path` benchmark: an XY gantry runs a dense contour of 10 000 short lines (issue #7).

The contour is a rose curve r = R·(0.6 + 0.4·cos 5φ), closed, cut into ``segments`` chords
(0.14 mm each for 10 000), every corner rounded by a contour with TMMaxCornerDeviation
0.02 mm (MC_PathSelect), then run by one MC_MovePath at a commanded 250 mm/s. Two axes with
the default axis limits but 5000 mm/s² acceleration and deceleration.

Figures:
- ``planner_us``: what the group's own cycle (sampling the time law, placing the TCP,
  inverse kinematics, writing the setpoints, the look-ahead planning on events) costs per
  1 ms cycle, p50/p99/max over the run (the MC_MovePath cycle that appends the prepared
  pieces is reported apart as ``start_us``);
- ``select_ms``: MC_PathSelect's preparation (chords and contours), before the motion;
- path speed: mean (length / time), the fraction of time at the commanded speed, and the
  duration against a single time-optimal profile of the same length (a lower bound that
  ignores the curvature);
- the bounds of the mean path speed (path_bound.py): ``steady_bound_velocity`` from what the
  axes allow at a steady speed on each element (the physics of the geometry) and
  ``caps_bound_velocity`` from the time law's velocity caps (what the look-ahead may reach);
- ``limit_violations``: samples where an axis setpoint exceeds its velocity, acceleration or
  jerk limit (jerk as the change of acceleration over one cycle) by more than 1e-9 relative;
- ``end_error_mm``: the distance of the final position from the path's end.

No peer runs this: neither ruckig nor pyplcopen plans a path; ruckig's single-profile time is
the reference instead.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import openmotion as om
from openmotion.bench.path_bound import fastest_time, steady_speeds
from openmotion.coordinated.blocks import MC_MovePath, MC_PathSelect
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import TransitionMode
from openmotion.coordinated.limits_bridge import axis_limits
from openmotion.trajectory.plan import Limits, plan_position
from openmotion.trajectory.segments import KinematicState

RADIUS = 150.0  #: [mm] of the rose curve
VELOCITY = 250.0  #: [mm/s] commanded path velocity
ACCELERATION = 5000.0  #: [mm/s²] axis and path limit
JERK = 1_000_000.0  #: [mm/s³], the axes' default max_jerk
DEVIATION = 0.02  #: [mm] TMMaxCornerDeviation of the corners


def rose(segments: int) -> np.ndarray:
    """``segments`` + 1 points of the closed rose curve, starting at (R, 0)."""
    phi = np.linspace(0.0, 2.0 * math.pi, segments + 1)
    r = RADIUS * (0.6 + 0.4 * np.cos(5.0 * phi))
    points = np.column_stack([r * np.cos(phi), r * np.sin(phi)])
    points[-1] = points[0]
    return points


def gantry(rt: om.Runtime, start: np.ndarray) -> AxesGroup:
    """An enabled XY gantry group of two powered axes (the benchmark's limits) at ``start``."""
    axes = [rt.add_axis(name, position=float(value), max_acceleration=ACCELERATION,
                        max_deceleration=ACCELERATION, max_jerk=JERK)
            for name, value in zip(("x", "y"), start, strict=True)]
    for axis in axes:
        axis.power()
    rt.step()
    group = AxesGroup(rt, "gantry")
    for ident, axis in enumerate(axes, start=1):
        group.add_axis(axis, ident)
    group.enable()
    return group


def run_path(segments: int = 10_000, progress: Callable[[str], None] | None = None
             ) -> dict[str, Any]:
    rt = om.Runtime(cycle_time=0.001)
    points = rose(segments)
    group = gantry(rt, points[0])
    axes = group.axes
    description = [{"line": p.tolist()} for p in points[1:]]
    if progress is not None:
        progress(f"path: preparing {segments} segments (MC_PathSelect)")
    select = MC_PathSelect(group)
    began = time.perf_counter()
    select(execute=True, path_description=description,
           transition_mode=TransitionMode.TM_MAX_CORNER_DEVIATION,
           transition_parameter=DEVIATION)
    select_ms = (time.perf_counter() - began) * 1e3
    if not select.done:
        raise RuntimeError(f"MC_PathSelect failed: {select.message}")
    timings: list[float] = []
    advance = group.advance

    def timed(now: float) -> None:
        start = time.perf_counter()
        advance(now)
        timings.append(time.perf_counter() - start)

    group.advance = timed  # type: ignore[method-assign] # the group's motion phase, timed
    move = MC_MovePath(group)
    began = time.perf_counter()
    move(execute=True, path_data=select.path_data, velocity=VELOCITY,
         acceleration=ACCELERATION, deceleration=ACCELERATION, jerk=JERK)
    start_us = (time.perf_counter() - began) * 1e6
    if move.error:
        raise RuntimeError(f"MC_MovePath failed: {move.message}")
    geometry = [entry.geometry for _, entry in sorted(group.motion.entries.items())]
    lengths, caps, exits = group.motion.law.speed_limits()
    k, rows = rt.axis_system.kernel, group.rows
    limit_v = np.array([a.parameters.max_velocity for a in axes])
    limit_a = np.array([min(a.parameters.max_acceleration, a.parameters.max_deceleration)
                        for a in axes])
    limit_j = np.array([a.parameters.max_jerk for a in axes])
    previous_a = np.zeros(len(axes))
    violations = cycles = at_speed = 0
    speeds: list[float] = []
    budget = int(10 * select.path_data.length / VELOCITY / rt.cycle_time) + 10_000
    while move.busy and cycles < budget:
        rt.step()
        move()
        cycles += 1
        v, a = k.set_v[rows], k.set_a[rows]
        jerk = np.abs(a - previous_a) / rt.cycle_time
        previous_a = a.copy()
        over = (np.abs(v) > limit_v * (1 + 1e-9)) | (np.abs(a) > limit_a * (1 + 1e-9)) \
            | (jerk > limit_j * (1 + 1e-9))
        violations += int(over.any())
        speed = group.motion.path_velocity
        speeds.append(speed)
        at_speed += speed >= VELOCITY * (1 - 1e-6)
        if progress is not None and cycles % 5000 == 0:
            progress(f"path: {cycles} cycles")
    us = np.array(timings[1:]) * 1e6  # the first timed cycle is the MovePath's own
    length = float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))
    duration = cycles * rt.cycle_time
    reference = plan_position(KinematicState(0.0), length,
                              Limits(VELOCITY, ACCELERATION, ACCELERATION, JERK)).duration
    end = group.position(actual=False)
    limits = axis_limits(group)
    steady = steady_speeds(geometry, group.spaces.kinematics, limits, VELOCITY)
    run_length = float(lengths.sum())
    return {
        "segments": segments,
        "done": bool(move.done),
        "cycles": cycles,
        "path_length_mm": length,
        "select_ms": select_ms,
        "start_us": start_us,
        "planner_us_p50": float(np.percentile(us, 50)) if us.size else None,
        "planner_us_p99": float(np.percentile(us, 99)) if us.size else None,
        "planner_us_max": float(us.max()) if us.size else None,
        "mean_path_velocity": length / duration if duration else 0.0,
        "steady_bound_velocity": run_length / fastest_time(lengths, steady, ACCELERATION,
                                                           ACCELERATION),
        "caps_bound_velocity": run_length / fastest_time(lengths, caps, ACCELERATION,
                                                         ACCELERATION, exits),
        "commanded_velocity": VELOCITY,
        "time_at_commanded_speed": at_speed / max(cycles, 1),
        "duration_s": duration,
        "single_profile_s": reference,
        "limit_violations": violations,
        "end_error_mm": float(np.linalg.norm(end - points[-1])),
    }

