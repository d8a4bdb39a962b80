"""Planning with ruckig: position moves, velocity moves and stops from any kinematic state.

PLCopen has distinct acceleration and deceleration limits; ruckig has one signed pair
(``max_acceleration`` / ``min_acceleration``). For motion in one direction the pair maps
exactly: speeding up in +x is bounded by ``acceleration``, slowing down by ``deceleration``,
and mirrored for -x. With equal limits, or a move that keeps its direction, one ruckig call
is exact and time-optimal. A move that must turn back (its velocity passes through zero
towards the target) cannot be mapped as one piece, since each side of the zero needs the
other bound: it is planned as two pieces joined at zero velocity with a continuous
acceleration, each mapped exactly, the crossing chosen by a short search, and it is never
slower than the plan with both limits at the lower one (docs/decisions.md D-201, which
supersedes D-002's brake-to-rest then move; D-203 for velocity changes).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from ruckig import ControlInterface, InputParameter, Result, Ruckig, RuckigError, Trajectory

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.trajectory.double_s import rest_to_rest
from openmotion.trajectory.segments import KinematicState, Profile

_MIN_SEGMENT = 1e-12  #: [s] ruckig reports empty phases as ~1e-14 s: drop them
_CLOSED_FORM_DISTANCE = 1e-6  #: shorter rest-to-rest moves are left to ruckig
#: relative: a speed this far past the axis maximum is float residue, not a breach (D-177)
VELOCITY_TOLERANCE = 1e-9
_JERK_MARGIN = 1e-6  #: relative: a raised jerk is this much above the bare minimum (D-020)

_otg = Ruckig(1)
_input = InputParameter(1)
_trajectory = Trajectory(1)
_loaded: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)  #: limits given to ruckig
_given: tuple[float, float, float, float] | None = None  #: the limits ``_input`` holds now
_input.control_interface = ControlInterface.Position  # the one interface we plan with
_input.target_acceleration = [0.0]


@dataclass(frozen=True, slots=True)
class Limits:
    velocity: float  #: maximum velocity magnitude [mm/s]
    acceleration: float  #: speeding up [mm/s²]
    deceleration: float  #: slowing down [mm/s²]
    jerk: float  #: [mm/s³]

    def scaled_velocity(self, factor: float) -> Limits:
        if factor == 1.0:  # x * 1.0 is x: no new object for the common case
            return self
        return Limits(self.velocity * factor, self.acceleration, self.deceleration, self.jerk)


def plan_position(
    start: KinematicState, target: float, limits: Limits, target_velocity: float = 0.0,
    *, closed_form: bool = False,
) -> Profile:
    """Time-optimal move to ``target``, arriving with ``target_velocity`` (blending).

    ``closed_form``: from rest to rest with acceleration equal to deceleration, the double S
    of ``double_s`` instead of a ruckig call (the same optimum, D-139): for planners that make
    many plans per cycle (planar movers on tracks). Other callers keep ruckig's profiles bit
    for bit."""
    if closed_form and start.velocity == 0.0 and start.acceleration == 0.0 \
            and target_velocity == 0.0 and limits.acceleration == limits.deceleration \
            and abs(target - start.position) >= _CLOSED_FORM_DISTANCE:
        return Profile.from_data(rest_to_rest(start.position, target, limits.velocity,
                                              limits.acceleration, limits.jerk, 0.0))
    sign = _sign(target - start.position) or _sign(target_velocity) or _sign(start.velocity)
    if abs(start.velocity) > limits.velocity and _sign(start.velocity) == sign:
        ramped = _ramp_down_then_position(start, target, target_velocity, limits, sign)
        if ramped is not None:
            return ramped
    asymmetric = limits.acceleration != limits.deceleration
    if asymmetric and start.velocity * sign < -1e-12 * limits.velocity:  # heading away
        return _turn_back(start, target, target_velocity, limits, sign)
    try:
        profile = _ruckig_position(start, target, target_velocity, limits, sign)
    except CommandRejected:
        if start.velocity == 0.0 and start.acceleration == 0.0:
            raise
        profile = None  # a rare numerical failure of ruckig's step 1: brake, then move
    if profile is not None and (not asymmetric or not _reverses(profile, sign)):
        return profile
    if asymmetric:
        return _turn_back(start, target, target_velocity, limits, sign)
    return _brake_then_position(start, target, target_velocity, limits)


def _turn_back(
    start: KinematicState, target: float, target_velocity: float, limits: Limits, sign: int
) -> Profile:
    """A move that turns back with acceleration != deceleration (D-201): the fastest of the
    turn through zero velocity (``_through_zero``), the plan with both limits at the lower
    one (it keeps every bound) and brake-to-rest then move (D-002), so that raising a limit
    never makes a move slower. Durations first (cheap); only the fastest is built."""
    low = min(limits.acceleration, limits.deceleration)
    symmetric = Limits(limits.velocity, low, low, limits.jerk)
    turn = _through_zero(start, target, target_velocity, limits)
    if turn is not None and math.isfinite(turn[3]):
        stopped = turn[3]  # |a_c| = 0 is brake-to-rest then move, timed by the search
    else:
        brake = plan_velocity(start, 0.0, limits)
        rest = KinematicState(brake.end.position, 0.0, 0.0)
        stopped = brake.duration + _duration(rest, target, target_velocity, limits,
                                             _sign(target - rest.position)
                                             or _sign(target_velocity))
    options = sorted((
        (turn[0] if turn is not None else math.inf, 0),
        (_duration(start, target, target_velocity, symmetric, sign), 1),
        (stopped, 2),
    ))
    for duration, kind in options:
        if not math.isfinite(duration):
            break
        if kind == 0:
            assert turn is not None
            profile = _turn_profile(turn[1], turn[2], start, target, target_velocity, limits)
            if profile is not None:
                return profile
        elif kind == 1:
            try:
                return _ruckig_position(start, target, target_velocity, symmetric, sign)
            except CommandRejected:
                continue
        else:
            break
    return _brake_then_position(start, target, target_velocity, limits)


def _duration(start: KinematicState, target: float, target_velocity: float, limits: Limits,
              sign: int) -> float:
    """[s] of ruckig's move, without building the profile where ruckig solves it at once;
    else that of the plan with the limits lowered a hair (``_calculate``); inf where even
    that fails."""
    _load_state(start, limits, sign)
    _input.target_position = [target]
    _input.target_velocity = [target_velocity]
    try:
        if _otg.calculate(_input, _trajectory) in (Result.Working, Result.Finished):
            return _trajectory.duration
    except (RuckigError, RuntimeError, ValueError):
        pass
    try:
        return _ruckig_position(start, target, target_velocity, limits, sign).duration
    except CommandRejected:
        return math.inf


#: the turn's search: ruckig's velocity interface brakes to the crossing state, its position
#: interface goes on from there to the target (own instances: the plan's input stays loaded)
_turn = Ruckig(1)
_turn_trajectory = Trajectory(1)
_braking = InputParameter(1)
_braking.control_interface = ControlInterface.Velocity
_braking.target_velocity = [0.0]
_onward = InputParameter(1)
_onward.control_interface = ControlInterface.Position
_onward.current_velocity = [0.0]
_onward.target_acceleration = [0.0]
_CROSSING_MARGIN = 1e-9  #: relative: the largest crossing acceleration kept off its bound
_EDGE_PRECISION = 1e-4  #: relative: how closely the overshoot edge is found (feasible side)
_SATURATION_PROBE = 1e-3  #: relative: step below the chosen crossing acceleration
_EDGE_STEPS = 40  #: at most, of the root finding for the overshoot edge
_CROSSING_STEPS = 16  #: golden-section steps over the crossing acceleration (0.618^16 ~ 5e-4)
_TURN_TOLERANCE = 1e-9  #: relative: the second piece passing its ends by less is residue
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
#: the shortest stop from (v = 0, a = c): release c at full jerk (c³/3j²), then brake the
#: c²/2j gained with a triangle of peak c/√2 (c³/2√2j²)
_STOP_FROM_CROSSING = 1.0 / 3.0 + 1.0 / (2.0 * math.sqrt(2.0))


def _through_zero(
    start: KinematicState, target: float, target_velocity: float, limits: Limits
) -> tuple[float, float, int, float] | None:
    """Brake in the start's direction to zero velocity without stopping and go on towards
    the target at once (D-201): (duration, |a_c|, that direction, the duration with
    |a_c| = 0, i.e. brake-to-rest then move, or inf where that is outside the range), or None
    where no such profile keeps the bounds.

    At the crossing (position p_c, velocity 0, acceleration a_c pointing back) the
    acceleration is continuous, so |a_c| <= min(acceleration, deceleration). Before it the
    velocity falls (bound: deceleration), after it it rises (bound: acceleration); each
    piece is in one direction and ruckig plans it exactly with the mapped pair. For a given
    |a_c| the fastest first piece is also the shortest (brake as hard as the bounds allow),
    and the second piece only gains from a shorter way back, so p_c is where that braking
    ends: one search over |a_c|. The total time falls as |a_c| grows (the turn keeps more of
    its acceleration), up to the largest value the first piece allows (it must not reach
    zero velocity before its acceleration has turned round) or the second (it must not
    overshoot the target): that end is found directly and confirmed by a probe just below
    it; a golden section over the whole range runs where the probe disagrees.
    """
    moving = abs(start.velocity) > 1e-12 * max(limits.velocity, 1e-300)
    first = _sign(start.velocity) if moving else _sign(start.acceleration)
    if first == 0:
        return None
    jerk = limits.jerk
    speed = max(start.velocity * first, 0.0)  # towards ``first``
    push = start.acceleration * first  # > 0: still speeding up
    # braking from (speed, push) must turn the acceleration round to -|a_c| before the
    # velocity reaches zero: a straight jerk ramp changes it by (push² - a_c²) / 2 jerk; and
    # releasing |a_c| after the crossing carries the speed on by a_c² / 2 jerk
    top = min(limits.acceleration, limits.deceleration,
              math.sqrt(2.0 * jerk * speed + push * push) * (1.0 - _CROSSING_MARGIN),
              math.sqrt(2.0 * jerk * limits.velocity) * (1.0 - _CROSSING_MARGIN))
    bottom = math.sqrt(max(push * push - 2.0 * jerk * speed, 0.0)) if push < 0.0 else 0.0
    if bottom > top:
        return None
    _load_turn(start, target, target_velocity, limits, first)
    scale = abs(target - start.position) + speed * 1e-3

    def total(c: float) -> float:
        return _turn_duration(c, first, target, scale)

    def confirmed(c: float) -> float:
        """The duration at ``c`` where it is finite and no larger than just below ``c``."""
        value = total(c)
        return value if math.isfinite(value) and total(c * (1.0 - _SATURATION_PROBE)) >= value \
            else math.inf

    # to rest, a second piece that cannot stop short of the target needs no ruckig call
    edge = top if target_velocity != 0.0 else _overshoot_edge(bottom, top, first, target, jerk)
    if edge is not None:
        value = confirmed(edge)
        if math.isfinite(value):
            return value, edge, first, total(0.0) if bottom == 0.0 else math.inf
    best, value = golden_minimum(total, bottom, top, _CROSSING_STEPS)
    if not math.isfinite(value):
        return None
    return value, best, first, total(0.0) if bottom == 0.0 else math.inf


def _overshoot_edge(bottom: float, top: float, first: int, target: float,
                    jerk: float) -> float | None:
    """The largest |a_c| in [bottom, top] from whose crossing the second piece can still
    stop at the target without passing it (to rest: its distance covers the shortest stop
    from the crossing); None where not even ``bottom`` can. The room left falls as |a_c|
    grows: one velocity-interface call per step of regula falsi (Illinois)."""

    def room(c: float) -> float:
        _braking.target_acceleration = [-first * c]
        try:
            if _turn.calculate(_braking, _turn_trajectory) not in (Result.Working,
                                                                   Result.Finished):
                return math.nan
        except (RuckigError, RuntimeError, ValueError):
            return math.nan
        crossing = _turn_trajectory.profiles[0][0].p[-1]
        return (crossing - target) * first - _STOP_FROM_CROSSING * c**3 / (jerk * jerk)

    a, b = bottom, top
    fb = room(b)
    if fb >= 0.0:
        return top
    fa = room(a)
    if not (fa > 0.0 and fb < 0.0):
        return None
    side = 0
    for _ in range(_EDGE_STEPS):
        c = (a * fb - b * fa) / (fb - fa)
        fc = room(c)
        if not math.isfinite(fc):
            return None
        if fc > 0.0:
            a, fa = c, fc
            if side == 1:
                fb /= 2.0
            side = 1
        else:
            b, fb = c, fc
            if side == -1:
                fa /= 2.0
            side = -1
        if b - a <= _EDGE_PRECISION * b:
            break
    return a


def _load_turn(start: KinematicState, target: float, target_velocity: float,
               limits: Limits, first: int) -> None:
    """The start, the target and the mapped limits of both pieces into the search inputs."""
    _load_braking(start, limits, first)
    up, down = limits.acceleration, limits.deceleration
    _onward.max_velocity = [limits.velocity]
    _onward.max_jerk = [limits.jerk]
    _onward.target_position = [target]
    _onward.target_velocity = [target_velocity]
    if first > 0:  # braking a +x motion, then speeding up towards -x
        _onward.max_acceleration, _onward.min_acceleration = [down], [-up]
    else:
        _onward.max_acceleration, _onward.min_acceleration = [up], [-down]


_braking_given: tuple[KinematicState, Limits, int] | None = None  #: what ``_braking`` holds


def _load_braking(start: KinematicState, limits: Limits, first: int) -> None:
    """The start and the mapped limits of the first piece into its input, unless the same
    objects are loaded already (the turn's profile brakes from the state and with the limits
    its search used; each setter converts a list). Identity, not equality: -0.0 == 0.0, and
    the held objects cannot be freed and their ids reused."""
    global _braking_given
    held = _braking_given
    if held is not None and held[0] is start and held[1] is limits and held[2] == first:
        return
    up, down = limits.acceleration, limits.deceleration
    _braking.current_position = [start.position]
    _braking.current_velocity = [start.velocity]
    _braking.current_acceleration = [start.acceleration]
    _braking.max_velocity = [limits.velocity]
    _braking.max_jerk = [limits.jerk]
    if first > 0:  # braking a +x motion
        _braking.max_acceleration, _braking.min_acceleration = [up], [-down]
    else:
        _braking.max_acceleration, _braking.min_acceleration = [down], [-up]
    _braking_given = (start, limits, first)


def _turn_duration(c: float, first: int, target: float, scale: float) -> float:
    """[s] of the turn through the crossing with |a_c| = ``c``; inf where a piece fails or
    the second passes its ends (the inputs are loaded by ``_load_turn``). The first piece
    keeps its direction by the range of ``c`` (``_through_zero``); the profile built at the
    end is checked in full."""
    _braking.target_acceleration = [-first * c]
    try:
        if _turn.calculate(_braking, _turn_trajectory) not in (Result.Working,
                                                               Result.Finished):
            return math.inf
        duration = _turn_trajectory.duration
        crossing = _turn_trajectory.profiles[0][0].p[-1]
        _onward.current_position = [crossing]
        _onward.current_acceleration = [-first * c]
        if _turn.calculate(_onward, _turn_trajectory) not in (Result.Working, Result.Finished):
            return math.inf
    except (RuckigError, RuntimeError, ValueError):
        return math.inf
    extrema = _turn_trajectory.position_extrema[0]
    tolerance = _TURN_TOLERANCE * (abs(crossing - target) + scale)
    if extrema.min < min(crossing, target) - tolerance \
            or extrema.max > max(crossing, target) + tolerance:
        return math.inf  # it passes the target (or the crossing) and turns back
    return duration + _turn_trajectory.duration


def _turn_profile(c: float, first: int, start: KinematicState, target: float,
                  target_velocity: float, limits: Limits) -> Profile | None:
    """The turn through the crossing with |a_c| = ``c`` as one profile; None where a piece
    turns back itself or the second passes the velocity limit."""
    braking = _braked_to_crossing(start, c, first, limits)
    if braking is None:
        return None
    crossing = KinematicState(float(braking.p[-1]), 0.0, -first * c)
    try:
        onward = _ruckig_position(crossing, target, target_velocity, limits, -first)
    except CommandRejected:
        return None
    lo, hi = onward.velocity_extrema()
    if _reversed(lo, hi, -first) or max(-lo, hi) > limits.velocity * (1.0 + VELOCITY_TOLERANCE):
        return None
    return Profile.concatenate(braking, onward)


def _brake_then_position(
    start: KinematicState, target: float, target_velocity: float, limits: Limits
) -> Profile:
    brake = plan_velocity(start, 0.0, limits)
    rest = KinematicState(brake.end.position, 0.0, 0.0)
    sign = _sign(target - rest.position) or _sign(target_velocity)
    return Profile.concatenate(
        brake, _ruckig_position(rest, target, target_velocity, limits, sign)
    )


def _ramp_down_then_position(
    start: KinematicState, target: float, target_velocity: float, limits: Limits, sign: int
) -> Profile | None:
    """Too fast for the (new) velocity limit: ramp down to it first, as a controller does.

    Ruckig's own brake pre-phase ends with the acceleration still braking, so the velocity
    would dip below the limit and climb back (an override step would show it). None when
    the target comes too soon for the ramp; ruckig's profile is used then.
    """
    slow = plan_velocity(start, sign * limits.velocity, limits)
    if (target - slow.end.position) * sign <= 0.0:
        return None
    rest = _ruckig_position(slow.end, target, target_velocity, limits, sign)
    if _reverses(rest, sign):
        return None
    return Profile.concatenate(slow, rest)


def plan_velocity(start: KinematicState, velocity: float, limits: Limits) -> Profile:
    """Time-optimal change to the signed ``velocity``, then cruise at it forever."""
    moving = abs(start.velocity) > 1e-12 * max(limits.velocity, abs(velocity), 1e-300)
    heading = _sign(start.velocity) if moving else _sign(start.acceleration)
    if heading * velocity < 0.0 and limits.acceleration != limits.deceleration:
        return _turn_velocity(start, velocity, limits, heading)
    return _velocity_profile(start, velocity, limits)


def _turn_velocity(start: KinematicState, velocity: float, limits: Limits,
                   heading: int) -> Profile:
    """A velocity change through zero with acceleration != deceleration (D-203): the fastest
    of the turn through zero velocity, the change with both limits at the lower one and
    brake-to-rest then speed up (D-002).

    The crossing acceleration |a_c| (D-201) shortens both pieces as it grows, with no
    position to reach: so it is the largest value that the lower limit, the braking (its
    acceleration must turn round before the velocity reaches zero) and the new velocity (the
    a_c²/2j gained while |a_c| is released must pass neither it nor the velocity limit)
    allow.
    """
    low = min(limits.acceleration, limits.deceleration)
    jerk = limits.jerk
    speed = max(start.velocity * heading, 0.0)
    push = start.acceleration * heading
    top = min(low, math.sqrt(2.0 * jerk * speed + push * push),
              math.sqrt(2.0 * jerk * min(abs(velocity), limits.velocity))) \
        * (1.0 - _CROSSING_MARGIN)
    bottom = math.sqrt(max(push * push - 2.0 * jerk * speed, 0.0)) if push < 0.0 else 0.0
    # durations first (a velocity change lasts the same from any position), in the order the
    # fastest is chosen in, ties to the first; only the fastest is built
    lowered = Limits(limits.velocity, low, low, jerk)
    lowered_phases = _velocity_phases(start, velocity, lowered)
    brake_phases = _velocity_phases(start, 0.0, limits)  # plan_velocity's, to rest
    rest_phases = _velocity_phases(_REST, velocity, limits)
    candidates: list[tuple[float, int]] = [
        (_phases_duration(lowered_phases), 1),
        (_phases_duration(rest_phases) + _phases_duration(brake_phases), 2)]
    turn = onward = None
    if bottom <= top:
        turn = _braked_to_crossing(start, top, heading, limits)
        if turn is not None:
            crossing = KinematicState(float(turn.p[-1]), 0.0, -heading * top)
            onward = _velocity_profile(crossing, velocity, limits)
            if not _reverses(onward, -heading):
                candidates.insert(0, (onward.duration + turn.duration, 0))
    kind = min(candidates, key=lambda c: c[0])[1]
    if kind == 0:
        assert turn is not None and onward is not None
        return Profile.concatenate(turn, onward)
    if kind == 1:
        return _integrate(start, lowered_phases, velocity)
    brake = _integrate(start, brake_phases, 0.0)
    return Profile.concatenate(
        brake, _velocity_profile(KinematicState(brake.end.position), velocity, limits))


def _braked_to_crossing(start: KinematicState, c: float, heading: int,
                        limits: Limits) -> Profile | None:
    """Brake a motion towards ``heading`` to zero velocity with the acceleration at
    -heading·``c`` (ruckig's velocity interface, the deceleration bounding the braking);
    None where ruckig fails or the velocity passes zero before."""
    _load_braking(start, limits, heading)
    _braking.target_acceleration = [-heading * c]
    try:
        if _turn.calculate(_braking, _turn_trajectory) not in (Result.Working,
                                                               Result.Finished):
            return None
    except (RuckigError, RuntimeError, ValueError):
        return None
    braking = _segments(_turn_trajectory.profiles[0][0])
    return None if _reverses(braking, heading) else braking


def jerk_within_velocity(start: KinematicState, jerk: float, max_velocity: float,
                         max_jerk: float) -> float:
    """The jerk a plan from ``start`` must use so that the speed stays within ``max_velocity``.

    Taking an acceleration ``a`` away at jerk ``j`` carries the velocity on by ``a·|a|/2j``
    before any planner can turn it: past the maximum while speeding up, or through zero and
    on past the maximum the other way when a strong deceleration meets a soft jerk. So
    ``jerk`` is raised to the smallest value that releases ``a`` within ``max_velocity``, at
    most ``max_jerk`` (D-020, D-177). Every planner starting from a running state (stop,
    halt, a new move, a re-plan) takes its jerk from here.
    """
    v, a = start.velocity, start.acceleration
    if a == 0.0:
        return jerk
    ahead = v if a > 0.0 else -v  # the velocity in the direction the acceleration pushes
    if ahead + a * a / (2.0 * jerk) <= max_velocity * (1.0 + VELOCITY_TOLERANCE):
        return jerk
    room = max_velocity - ahead
    if room <= 0.0:
        return max(jerk, max_jerk)
    return max(jerk, min(a * a / (2.0 * room) * (1.0 + _JERK_MARGIN), max_jerk))


def plan_stop(start: KinematicState, deceleration: float, jerk: float) -> Profile:
    """Brake to rest with ``deceleration`` and ``jerk`` (MC_Stop, MC_Halt, error reactions)."""
    return _velocity_profile(start, 0.0, Limits(math.inf, deceleration, deceleration, jerk))


def _ruckig_position(
    start: KinematicState, target: float, target_velocity: float, limits: Limits, sign: int,
    minimum_duration: float | None = None,
) -> Profile:
    try:
        return _ruckig_position_once(start, target, target_velocity, limits, sign,
                                     minimum_duration)
    except CommandRejected:
        if limits.acceleration == limits.deceleration:
            raise
    # ruckig's step 1 fails on some short moves with unequal limits; equal limits at the
    # smaller one give the same profile where no acceleration limit is reached, and never
    # exceed either limit elsewhere (D-021)
    low = min(limits.acceleration, limits.deceleration)
    return _ruckig_position_once(start, target, target_velocity,
                                 Limits(limits.velocity, low, low, limits.jerk), sign,
                                 minimum_duration)


def _ruckig_position_once(
    start: KinematicState, target: float, target_velocity: float, limits: Limits, sign: int,
    minimum_duration: float | None = None,
) -> Profile:
    _load_state(start, limits, sign)
    _input.target_position = [target]
    _input.target_velocity = [target_velocity]
    if minimum_duration is None:
        return _with_exact_end(_calculate(), target, target_velocity)
    _input.minimum_duration = minimum_duration
    try:
        profile = _calculate()
    finally:
        _input.minimum_duration = None
    return _with_exact_end(profile, target, target_velocity)


def plan_position_in(start: KinematicState, target: float, limits: Limits,
                     duration: float) -> Profile:
    """A move to ``target`` from any state lasting at least ``duration`` [s] (ruckig's minimum
    duration); the time-optimal move where that is longer. MC_GearInPosCA's Late and Slow."""
    sign = _sign(target - start.position) or _sign(start.velocity) or 1
    return _ruckig_position(start, target, 0.0, limits, sign, duration)


def plan_in_time(distance: float, limits: Limits, duration: float | None) -> Profile:
    """A rest-to-rest move over ``distance`` lasting at least ``duration`` (ruckig's minimum
    duration: it lowers the velocity to fill the time). Superposition uses it (TcMC §3.10)."""
    sign = _sign(distance)
    return _ruckig_position(KinematicState(0.0), distance, 0.0, limits, sign, duration)


def _velocity_profile(start: KinematicState, velocity: float, limits: Limits) -> Profile:
    """Time-optimal change to ``velocity`` (ruckig's velocity interface, in closed form).

    A jerk-limited velocity change has at most three phases: jerk towards the peak
    acceleration, hold it, jerk back to zero. Solving it directly is exact and far cheaper
    than a ruckig call; tests/properties compares it with ruckig.
    """
    return _integrate(start, _velocity_phases(start, velocity, limits), velocity)


_REST = KinematicState(0.0)


def _velocity_phases(start: KinematicState, velocity: float,
                     limits: Limits) -> list[tuple[float, float]]:
    """The (jerk, duration) phases of ``_velocity_profile``: they depend on the start's
    velocity and acceleration only, not on its position."""
    sign = _sign(velocity) or _sign(start.velocity) or _sign(start.acceleration)
    if sign >= 0:
        up, down = limits.acceleration, limits.deceleration  # bounds of +a and of -a
    else:
        up, down = limits.deceleration, limits.acceleration
    jerk = limits.jerk
    v0, a0 = start.velocity, start.acceleration
    release = v0 + a0 * abs(a0) / (2.0 * jerk)  # velocity if a0 is taken away at once
    gap = velocity - release
    if gap == 0.0 or abs(gap) <= 1e-15 * max(abs(velocity), abs(v0), 1.0):
        phases = [(-math.copysign(jerk, a0), abs(a0) / jerk)] if a0 else []
    else:
        d = 1.0 if gap > 0.0 else -1.0
        bound = up if d > 0.0 else down
        peak_sq = jerk * d * (velocity - v0) + a0 * a0 / 2.0
        if peak_sq <= bound * bound:  # triangular: the peak stays below the bound
            peak, hold = d * math.sqrt(max(peak_sq, 0.0)), 0.0
        else:
            peak = d * bound
            gained = (peak * peak - a0 * a0) / (2.0 * math.copysign(jerk, peak - a0)) \
                if peak != a0 else 0.0
            hold = (velocity - v0 - gained - peak * abs(peak) / (2.0 * jerk)) / peak
        phases = [(math.copysign(jerk, peak - a0), abs(peak - a0) / jerk), (0.0, hold),
                  (-d * jerk, abs(peak) / jerk)]
    return phases


def _phases_duration(phases: list[tuple[float, float]]) -> float:
    """[s] of the profile ``_integrate`` makes of ``phases``: its sum, in its order."""
    total = 0.0
    for _, duration in phases:
        if duration > _MIN_SEGMENT:
            total = total + duration
    return total


def _integrate(start: KinematicState, phases: list[tuple[float, float]],
               velocity: float) -> Profile:
    """A profile from (jerk, duration) phases; the open segment cruises at ``velocity``."""
    t, p, v, a, j = [0.0], [start.position], [start.velocity], [start.acceleration], []
    for jerk, duration in phases:
        if duration <= _MIN_SEGMENT:
            continue
        p0, v0, a0 = p[-1], v[-1], a[-1]
        j.append(jerk)
        t.append(t[-1] + duration)
        p.append(p0 + duration * (v0 + duration * (a0 / 2.0 + duration * jerk / 6.0)))
        v.append(v0 + duration * (a0 + duration * jerk / 2.0))
        a.append(a0 + duration * jerk)
    v[-1], a[-1] = velocity, 0.0
    j.append(0.0)
    return Profile.from_data(np.array(t + p + v + a + j).reshape(5, len(t)))


def _load_state(start: KinematicState, limits: Limits, sign: int) -> None:
    velocity, acceleration = start.velocity, start.acceleration
    # Float residue of the evaluation (a ~1e-13 acceleration at v == v_max) can flip ruckig
    # to a valid but far slower profile type; such residue is no physical state: drop it.
    if abs(acceleration) <= 1e-10 * max(limits.acceleration, limits.deceleration):
        acceleration = 0.0
    if math.isfinite(limits.velocity) and abs(abs(velocity) - limits.velocity) <= (
        1e-12 * limits.velocity
    ):
        velocity = math.copysign(limits.velocity, velocity)
    _input.current_position = [start.position]
    _input.current_velocity = [velocity]
    _input.current_acceleration = [acceleration]
    global _loaded
    if sign >= 0:
        _loaded = (limits.velocity, limits.acceleration, -limits.deceleration, limits.jerk)
    else:
        _loaded = (limits.velocity, limits.deceleration, -limits.acceleration, limits.jerk)
    _give(_loaded)


def _give(values: tuple[float, float, float, float]) -> None:
    """Velocity, acceleration bounds and jerk into ruckig's input, when they changed (each
    setter converts a list: a plan that keeps its limits skips four)."""
    global _given
    if values != _given:
        _input.max_velocity = [values[0]]
        _input.max_acceleration = [values[1]]
        _input.min_acceleration = [values[2]]
        _input.max_jerk = [values[3]]
        _given = values


#: ruckig's community build fails on a few inputs in its numerical step 1; the same problem
#: with every limit lowered a hair solves. Lower limits cannot be exceeded, and the duration
#: grows by at most ~1e-6 relative: far below one cycle.
_RETRY_FACTORS = (1.0, 1.0 - 1e-12, 1.0 - 1e-10, 1.0 - 1e-8, 1.0 - 1e-6)


def _calculate() -> Profile:
    velocity, max_acc, min_acc, jerk = _loaded
    failure = ""
    for factor in _RETRY_FACTORS:
        if factor != 1.0:
            _give((velocity * factor, max_acc * factor, min_acc * factor, jerk * factor))
        try:
            result = _otg.calculate(_input, _trajectory)
        except (RuckigError, RuntimeError, ValueError) as exc:  # ruckig raises on inputs it
            # cannot plan; ValueError: a result code the Python enum does not know (-101)
            failure = str(exc).strip().splitlines()[0] if str(exc).strip() else "error"
            continue
        if result in (Result.Working, Result.Finished):
            return _segments(_trajectory.profiles[0][0])
        failure = result.name
    raise CommandRejected(ErrorId.NO_PROFILE, f"no trajectory (ruckig: {failure})")


def _segments(profile) -> Profile:  # noqa: ANN001 - ruckig.Profile has no public type
    """Flatten ruckig's brake and main phases into non-empty segments (those lasting longer
    than ``_MIN_SEGMENT``), and the end state after them.

    Ruckig's post-phase (``accel``) only serves target states beyond the limits, which we
    never command, so it is not read. Plain floats and one array built at the end: this runs
    on every plan, and for a handful of phases numpy and compiled calls cost more than the
    arithmetic (the same operations in the same order as before, so the same bits).
    """
    brake = profile.brake
    durations, jerks, ps, vs, accs = profile.t, profile.j, profile.p, profile.v, profile.a
    if brake.duration > 0.0:
        durations, jerks = brake.t + durations, brake.j + jerks
        ps, vs, accs = brake.p + ps, brake.v + vs, brake.a + accs
    t: list[float] = []
    p: list[float] = []
    v: list[float] = []
    a: list[float] = []
    j: list[float] = []
    total = 0.0
    for k, duration in enumerate(durations):
        if duration > _MIN_SEGMENT:
            t.append(total)
            p.append(ps[k])
            v.append(vs[k])
            a.append(accs[k])
            j.append(jerks[k])
            total += duration
    n = len(t)
    if n:
        dt = total - t[-1]
        p0, v0, a0, j0 = p[-1], v[-1], a[-1], j[-1]
        p.append(p0 + dt * (v0 + dt * (a0 / 2.0 + dt * j0 / 6.0)))
        v.append(v0 + dt * (a0 + dt * j0 / 2.0))
    else:
        p.append(ps[0])
        v.append(vs[0])
    t.append(total)
    a.append(0.0)
    j.append(0.0)
    return Profile.from_data(np.array(t + p + v + a + j).reshape(5, n + 1))


def _with_exact_end(profile: Profile, position: float, velocity: float) -> Profile:
    """Pin the open segment to the commanded end state, so targets are reached exactly."""
    data = profile.data
    data[1, -1] = position
    data[2, -1] = velocity
    return profile


def _reverses(profile: Profile, sign: int) -> bool:
    lo, hi = profile.velocity_extrema()
    return _reversed(lo, hi, sign)


def _reversed(lo: float, hi: float, sign: int) -> bool:
    """Velocity extrema ``lo``, ``hi`` of a motion towards ``sign`` pass zero (beyond float
    residue)."""
    tolerance = 1e-9 * max(abs(lo), abs(hi), 1.0)
    return hi > tolerance if sign < 0 else lo < -tolerance


def _sign(value: float) -> int:
    return int(value > 0.0) - int(value < 0.0)


def golden_minimum(function: Callable[[float], float], lo: float, hi: float,
                   steps: int) -> tuple[float, float]:
    """Golden-section search for the minimum of ``function`` on [lo, hi] in ``steps``
    narrowings: (argument, value), the better of the last two probes."""
    a, b = lo, hi
    x1, x2 = b - _GOLDEN * (b - a), a + _GOLDEN * (b - a)
    f1, f2 = function(x1), function(x2)
    for _ in range(steps):
        if f1 <= f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - _GOLDEN * (b - a)
            f1 = function(x1)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + _GOLDEN * (b - a)
            f2 = function(x2)
    return (x1, f1) if f1 <= f2 else (x2, f2)
