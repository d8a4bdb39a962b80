"""The brake of gap control (rail/braking.py, compiled in kernels.py) against the
planner's own stop (trajectory.plan.plan_stop): the same states at every instant, and an
envelope that holds every position the brake passes, turning states included."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from openmotion.rail.braking import brake_envelope, brake_state
from openmotion.trajectory.plan import plan_stop
from openmotion.trajectory.segments import KinematicState

states = st.tuples(
    st.floats(-1000.0, 1000.0),  # p
    st.floats(-3000.0, 3000.0),  # v
    st.floats(-20000.0, 20000.0),  # a: beyond dec too (a mover braked harder than its own)
    st.floats(1000.0, 20000.0),  # dec
    st.floats(1e4, 1e6),  # jerk
)


#: a velocity the stop planner (ruckig) ends on as rest [mm/s]
RESIDUAL_VELOCITY = 1e-12


@settings(deadline=None, max_examples=300)
@given(state=states, fraction=st.floats(0.0, 1.2))
@example(state=(0.0, 0.0, 1e-05, 1000.0, 50000.0), fraction=1.125)
def test_brake_state_is_the_planned_stop(state, fraction) -> None:
    p, v, a, dec, jerk = state
    stop = plan_stop(KinematicState(p, v, a), dec, jerk)
    t = fraction * stop.duration
    got = brake_state(*(np.array([x]) for x in state), t)[:3]  # the jerk of an instant on
    want = stop.at(t)[:3]  # a phase boundary is either phase's: compare p, v, a
    scale = max(1.0, abs(p), abs(v), abs(a) * 1e-3)
    # the planner drops phases under 1e-12 s: an acceleration a jerk takes away within one
    # (a <= jerk x 1e-12) is left out of its profile, so a is compared to the deceleration
    sizes = (scale, scale, max(scale, dec))
    # a velocity of femtometres per second left once the acceleration is taken away is rest
    # to the planner, while the closed form brakes it, with a peak of sqrt(jerk x velocity)
    release = v + a * abs(a) / (2.0 * jerk)
    residual = math.sqrt(2.0 * jerk * abs(release)) if abs(release) <= RESIDUAL_VELOCITY else 0.0
    for g, w, name, size, extra in zip(got, want, ("p", "v", "a"), sizes, (0.0, 0.0, residual),
                                       strict=True):
        assert abs(float(g[0]) - w) <= 1e-9 * size + extra, (name, float(g[0]), w)


@settings(deadline=None, max_examples=300)
@given(state=states)
def test_envelope_holds_every_position_of_the_brake(state) -> None:
    p, v, a, dec, jerk = state
    stop = plan_stop(KinematicState(p, v, a), dec, jerk)
    times = np.linspace(0.0, stop.duration, 2001)
    positions = np.array([stop.at(t)[0] for t in times])
    (lo,), (hi,) = brake_envelope(*(np.array([x]) for x in state))
    tolerance = 1e-9 * max(1.0, abs(p), abs(v))
    assert lo <= positions.min() + tolerance and hi >= positions.max() - tolerance
    # and no wider than the brake goes (the dense samples miss at most a sliver)
    step = stop.duration / 2000
    slack = (abs(v) + abs(a) * stop.duration + jerk * stop.duration ** 2) * step + tolerance
    assert lo >= positions.min() - slack and hi <= positions.max() + slack


def test_a_turning_brake_reaches_back() -> None:
    """Braking harder than it may (v = 100, a = -20000 with dec 5000): the velocity turns
    negative long before the acceleration is back, so the envelope reaches far below the
    start."""
    state = (0.0, 100.0, -20000.0, 5000.0, 1e5)
    (lo,), (hi,) = brake_envelope(*(np.array([x]) for x in state))
    stop = plan_stop(KinematicState(0.0, 100.0, -20000.0), 5000.0, 1e5)
    positions = [stop.at(t)[0] for t in np.linspace(0.0, stop.duration, 4001)]
    assert lo < 0.0 and -1e-9 <= min(positions) - lo < 1e-5  # exact extremes, samples near
    assert -1e-9 <= hi - max(positions) < 1e-5
