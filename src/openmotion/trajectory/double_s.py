"""Rest-to-rest moves with equal acceleration and deceleration, in closed form (numba).

From rest to rest, with one bound on speeding up and slowing down, the time-optimal
jerk-limited move is the symmetric "double S": jerk up to the acceleration peak, hold it, jerk
down to the cruise speed, cruise, and the mirror image to rest. Seven phases at most, each
known from the distance and the limits, so the plan is a handful of arithmetic, not a call to
ruckig and a flattening of its result. A planar MoveToPosition, which usually starts from
rest, plans one for its path and one for its C rotation in the cycle it is executed.

Lasting longer (``duration`` above the optimum): the same shape with a lower cruise speed, the
acceleration peak and the jerk kept as long as the speed allows it, so a synchronised motion
still starts and ends as briskly as its limits let it and only cruises slower (D-139). Ruckig's
minimum-duration profiles may take other shapes of the same duration.

The tests hold the optimum to ruckig's (tests/trajectory/test_double_s.py).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from openmotion.core.compiled import compiled

_MIN_PHASE = 1e-12  #: [s] shorter phases are dropped, as the ruckig plans drop them


@compiled
def optimal_duration(distance: float, velocity: float, acceleration: float,
                     jerk: float) -> float:
    """[s] of the time-optimal move over ``distance`` (either sign) from rest to rest."""
    peak = _peak_speed(abs(distance), velocity, acceleration, jerk)
    return _duration(abs(distance), peak, acceleration, jerk)


@compiled
def rest_to_rest(start: float, target: float, velocity: float, acceleration: float,
                 jerk: float, duration: float) -> NDArray[np.float64]:
    """Profile data (rows t, p, v, a, j; the last column the open end segment at rest on
    ``target``) of the move from rest at ``start`` to rest at ``target``, time-optimal, or
    lasting ``duration`` [s] where that is longer."""
    d = abs(target - start)
    sign = 1.0 if target >= start else -1.0
    peak = _peak_speed(d, velocity, acceleration, jerk)
    optimum = _duration(d, peak, acceleration, jerk)
    if duration > optimum and d > 0.0:
        peak = _stretched_speed(d, acceleration, jerk, duration)
    t1, t2 = _ramp(peak, acceleration, jerk)
    t4 = max(duration, optimum) - 2.0 * (2.0 * t1 + t2) if d > 0.0 else 0.0
    t4 = max(t4, 0.0)
    jerks = (sign * jerk, 0.0, -sign * jerk, 0.0, -sign * jerk, 0.0, sign * jerk)
    phases = (t1, t2, t1, t4, t1, t2, t1)
    kept_jerk, kept_time = np.empty(7), np.empty(7)
    count = 0
    for k in range(7):  # without a cruise the two middle jerk phases are one, as in ruckig
        if phases[k] <= _MIN_PHASE:
            continue
        if count and kept_jerk[count - 1] == jerks[k]:
            kept_time[count - 1] += phases[k]
        else:
            kept_jerk[count], kept_time[count] = jerks[k], phases[k]
            count += 1
    out = np.zeros((5, count + 1))
    time = v = a = 0.0
    p = start
    for n in range(count):
        dt, j = kept_time[n], kept_jerk[n]
        out[0, n], out[1, n], out[2, n], out[3, n], out[4, n] = time, p, v, a, j
        p = p + dt * (v + dt * (a / 2.0 + dt * j / 6.0))
        v = v + dt * (a + dt * j / 2.0)
        a = a + dt * j
        time += dt
    n = count
    out[0, n] = time
    out[1, n] = target  # pinned: the target is reached exactly
    return out


@compiled
def synchronised(distance: float, velocity: float, acceleration: float, jerk: float,
                 start: float, target: float, c_velocity: float, c_acceleration: float,
                 c_jerk: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Two rest-to-rest moves ending together: 0 to ``distance`` (a path) and ``start`` to
    ``target`` (a rotation), the slower time-optimal and the other lasting as long."""
    end = max(optimal_duration(distance, velocity, acceleration, jerk),
              optimal_duration(target - start, c_velocity, c_acceleration, c_jerk))
    return (rest_to_rest(0.0, distance, velocity, acceleration, jerk, end),
            rest_to_rest(start, target, c_velocity, c_acceleration, c_jerk, end))


@compiled
def _peak_speed(d: float, velocity: float, acceleration: float, jerk: float) -> float:
    """The cruise (or top) speed of the time-optimal move over ``d`` >= 0."""
    t1, t2 = _ramp(velocity, acceleration, jerk)
    if d >= velocity * (2.0 * t1 + t2):  # both ramps to the velocity limit fit: cruise
        return velocity
    corner = acceleration * acceleration / jerk  # the slowest speed whose ramp holds a peak
    if d >= 2.0 * acceleration * corner / jerk:  # the acceleration limit is still reached
        return (math.sqrt(corner * corner + 4.0 * acceleration * d) - corner) / 2.0
    return (d * math.sqrt(jerk) / 2.0) ** (2.0 / 3.0)  # only the jerk limits


@compiled
def _ramp(speed: float, acceleration: float, jerk: float) -> tuple[float, float]:
    """(jerk phase, constant-acceleration phase) [s] of a ramp from rest to ``speed``."""
    if speed * jerk >= acceleration * acceleration:
        return acceleration / jerk, speed / acceleration - acceleration / jerk
    return math.sqrt(speed / jerk), 0.0


@compiled
def _duration(d: float, speed: float, acceleration: float, jerk: float) -> float:
    """[s] of the move over ``d`` cruising at ``speed`` (two ramps and the cruise)."""
    if d == 0.0:
        return 0.0
    t1, t2 = _ramp(speed, acceleration, jerk)
    return d / speed + 2.0 * t1 + t2


@compiled
def _stretched_speed(d: float, acceleration: float, jerk: float, duration: float) -> float:
    """The cruise speed at which the move over ``d`` lasts ``duration``: d / v + ramp = T,
    which falls as v grows, so one root on each side of a² / j."""
    corner = acceleration * acceleration / jerk
    rest = duration - acceleration / jerk  # T = d / v + v / a + a / j with a peak held
    disc = rest * rest - 4.0 * d / acceleration
    if disc >= 0.0 and rest > 0.0:
        speed = 2.0 * d / (rest + math.sqrt(disc))  # the smaller root, without cancellation
        if speed >= corner:
            return speed
    # no peak held: T = d / v + 2 u with u = sqrt(v / j), so 2 u³ - T u² + d / j = 0, one
    # root in (0, T / 4] (a cruise of zero or more), found by bisection then Newton
    low, high = 0.0, duration / 4.0
    u = high
    for _ in range(200):
        u = (low + high) / 2.0
        if 2.0 * u * u * u - duration * u * u + d / jerk > 0.0:
            low = u
        else:
            high = u
        if high - low <= 1e-15 * high:
            break
    for _ in range(3):
        slope = 6.0 * u * u - 2.0 * duration * u
        if slope == 0.0:
            break
        u -= (2.0 * u * u * u - duration * u * u + d / jerk) / slope
    return jerk * u * u
