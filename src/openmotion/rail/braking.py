"""Jerk-limited braking to rest for many movers at once: the maths of gap control.

Collision avoidance rests on one question per mover and cycle: if it started braking now,
with its maximum deceleration ``dec`` and maximum jerk ``jerk``, where could it be until it
stands? The brake is the time-optimal change to velocity 0 (the closed form of
``trajectory.plan._velocity_profile``, here vectorised): at most three constant-jerk phases,
jerk towards the peak deceleration, hold it, jerk back to zero.

* :func:`brake_phases`: durations and jerks of the three phases, shape (N, 3).
* :func:`brake_state`: the state a time ``t`` into the brake (rest after its end).
* :func:`brake_envelope`: the interval ``[lo, hi]`` of positions the brake passes through.

Braking is *time-consistent*: braking from a state on a brake follows the rest of that same
brake, so its envelope is a sub-interval. docs/collision-avoidance.md builds the safety
argument on that.
"""

from __future__ import annotations

import numpy as np

from openmotion.rail.kernels import brake_states, envelopes, phase_table

Arrays = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def brake_phases(v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                 jerk: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(durations, jerks), each (N, 3): the time-optimal brake from (v, a) to rest: jerk
    towards the peak deceleration, hold it, jerk back to zero (kernels._phases)."""
    return phase_table(*(np.ascontiguousarray(x, dtype=float) for x in (v, a, dec, jerk)))


def brake_state(p: np.ndarray, v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                jerk: np.ndarray, t: float) -> Arrays:
    """(p, v, a, j) a time ``t`` [s] into the brake of each mover; at rest after its end
    (one compiled loop, kernels.py)."""
    return brake_states(*(np.ascontiguousarray(x, dtype=float) for x in (p, v, a, dec, jerk)),
                        float(t))


def brake_envelope(p: np.ndarray, v: np.ndarray, a: np.ndarray, dec: np.ndarray,
                   jerk: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi): lowest and highest position each mover passes while braking to rest.

    Usually the velocity keeps its sign while braking and the envelope is spanned by the
    start and the stop point. The velocity can change sign only in a state that brakes harder
    than it needs to: taking its acceleration away at once would already reverse it
    (``release`` and ``v`` of opposite signs). There the turning points are added. One
    compiled loop over the movers (kernels.envelope).
    """
    return envelopes(*(np.ascontiguousarray(x, dtype=float) for x in (p, v, a, dec, jerk)))
