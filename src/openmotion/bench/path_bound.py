"""What the axes allow along a path: the bounds ``bench path`` sets its mean speed against.

Two bounds of the mean path speed, each from a speed limit per piece of the path:

- ``steady``: the steady speed of each element (``limits.steady_speed``: the highest constant
  speed at which no axis exceeds its velocity, acceleration or jerk limit, at the element's
  peaks of tangent, curvature and curvature rate), and the commanded velocity. It ignores the
  budget's shares: what the physics of the geometry allows a motion that holds its speed over
  each element (over a 0.1 mm contour at 70 mm/s that is 1.5 ms, too short to do much else);
- ``caps``: the time law's velocity caps of the pieces (limits.py, with the shares), which the
  look-ahead may reach at best.

The profile under either is the fastest from rest to rest with the commanded path
acceleration and deceleration, jerk ignored: the forward and backward passes over the limits,
then ramp - cruise - ramp on each piece. No motion within the same speed limits and rates is
faster, so the look-ahead loses what the achieved mean lies below ``caps``, and the shares
of the budget what ``caps`` lies below ``steady``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from openmotion.coordinated.kinematics import CartesianGantry, Kinematics
from openmotion.coordinated.limits import steady_speed
from openmotion.trajectory.plan import Limits


def steady_speeds(elements: Sequence[Any], kinematics: Kinematics,
                  axis_limits: Sequence[Limits], velocity: float) -> np.ndarray:
    """Per element, its steady speed [mm/s], at most ``velocity`` (the commanded one); a
    Cartesian gantry only (its bounds are the elements' own)."""
    if not isinstance(kinematics, CartesianGantry):
        raise TypeError(f"steady speeds need a CartesianGantry, got {type(kinematics).__name__}")
    gantry = kinematics
    return np.array([min(velocity, steady_speed(e, gantry, axis_limits)) for e in elements])


def fastest_time(lengths: np.ndarray, speeds: np.ndarray, acceleration: float,
                 deceleration: float, exits: np.ndarray | None = None) -> float:
    """Duration [s] of the fastest motion from rest to rest over pieces of ``lengths`` [mm],
    each at most at its ``speeds`` [mm/s] and each junction at most at ``exits`` (the cap at
    a piece's end, default none), speeding up by at most ``acceleration`` and slowing down by
    at most ``deceleration`` [mm/s²], jerk ignored."""
    lengths, speeds = np.asarray(lengths, dtype=float), np.asarray(speeds, dtype=float)
    n = len(lengths)
    junction = np.minimum(speeds[:-1], speeds[1:])
    if exits is not None:
        junction = np.minimum(junction, np.asarray(exits, dtype=float)[:-1])
    w = np.concatenate(([0.0], junction, [0.0])).tolist()  # w[i]: speed where piece i begins
    rise, fall = (2.0 * acceleration * lengths).tolist(), (2.0 * deceleration * lengths).tolist()
    for i in range(n - 1, 0, -1):
        w[i] = min(w[i], math.sqrt(w[i + 1] ** 2 + fall[i]))
    for i in range(1, n):
        w[i] = min(w[i], math.sqrt(w[i - 1] ** 2 + rise[i - 1]))
    w0, w1 = np.array(w[:-1]), np.array(w[1:])
    peak = np.sqrt((acceleration * deceleration * 2.0 * lengths + deceleration * w0**2
                    + acceleration * w1**2) / (acceleration + deceleration))
    top = np.minimum(speeds, peak)
    up = (top**2 - w0**2) / (2.0 * acceleration)
    down = (top**2 - w1**2) / (2.0 * deceleration)
    cruise = np.maximum(lengths - up - down, 0.0) / top
    return float(np.sum((top - w0) / acceleration + (top - w1) / deceleration + cruise))
