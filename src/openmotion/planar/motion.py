"""Planning of a planar mover's own motions: pure functions from the current kinematic state of
each coordinate to one constant-jerk ``Profile`` per coordinate (TF5430 §6.1.9, §7.2.2.8).

Dynamics (§6.1.1, §6.1.9): the planners take resolved ``Limits`` per coordinate group (XY, Z,
A, B, C); options.py turns a command's constraint into them. The XY limits hold tangentially
to the path.

MoveToPosition: from rest, or while the mover already moves along the line to the target, the
path is that straight line. One 1-D plan on the arc length s is mapped to x and y by the
direction cosines, so both profiles are exact, the path is exactly straight, the tangential
limits hold exactly and the duration is the 1-D time-optimal one. With a C target, the slower
of path and C sets the duration and the other is replanned with ruckig's minimum duration, so
both end together. From rest with acceleration equal to deceleration (the usual command, and
the mover's default dynamics) both come in closed form instead (``trajectory.double_s``,
D-139): the same optimum, and the faster one cruises slower to end with the other.

Decision (§6.1.9, digest §8 q16): a target off the current line of motion (a new command while
the mover moves in another direction) first brakes to rest along the current path with the XY
deceleration and jerk, then takes the straight line. The route is then two known straight
pieces, which the planar group can reserve exactly, and no tangential limit is exceeded at the
corner; a blended 2-D curve (ruckig's multi-DoF synchronisation) would cut the corner through
area nobody reserved and meets the tangential limits only with per-axis limits scaled by 1/√2.

Decision (§4.2): with a C target the whole C motion of MoveToPosition must stay in one C window,
since X and Y cannot move in a CRotation mode and only MoveC may enter one; otherwise the
command is rejected with PLANAR_POSITION_LIMIT. The C target is absolute (NonModulo, MoveC's
default): MoveToPosition has no modulo options.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from openmotion.core.compiled import compiled
from openmotion.core.enums import ModuloDirection
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.area_kernels import straight_area_numbers
from openmotion.planar.rotation import CWindows, monotonic, move_c_target
from openmotion.planar.tolerances import (
    ACROSS_PRECISION,
    PATH_PRECISION,
    PREDICTION_DISTANCE,
    PREDICTION_MARGIN,
    PREDICTION_TIME,
    REST_PRECISION,
    SYNC_TIME_PRECISION,
)
from openmotion.trajectory.double_s import rest_to_rest, synchronised
from openmotion.trajectory.plan import Limits, plan_position, plan_position_in, plan_stop
from openmotion.trajectory.segments import KinematicState, Profile

_SYNC_ROUNDS = 4  #: at most this many stretching rounds until path and C agree


@dataclass(frozen=True, slots=True)
class PositionLimits:
    """The hidden Minimum/Maximum Position of one coordinate (§6.1.1, from V3.1.10.30)."""

    minimum: float = -math.inf  #: [mm] or [°]
    maximum: float = math.inf  #: [mm] or [°]

    def check(self, profile: Profile, coordinate: str) -> None:
        """Reject (PLANAR_POSITION_LIMIT) a target outside the limits, or a path that leaves
        them further than its start lies outside (a mover outside may come back in)."""
        if self.minimum == -math.inf and self.maximum == math.inf:
            return
        end = float(profile.p[-1])
        if not self.minimum <= end <= self.maximum:
            raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                                  f"{coordinate} target {end:g} outside "
                                  f"[{self.minimum:g}, {self.maximum:g}]")
        start = float(profile.p[0])
        low, high = profile.position_extrema()
        slack = PATH_PRECISION * max(1.0, abs(low), abs(high))
        if low < min(self.minimum, start) - slack or high > max(self.maximum, start) + slack:
            raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                                  f"{coordinate} path reaches [{low:g}, {high:g}], outside "
                                  f"[{self.minimum:g}, {self.maximum:g}]")


UNLIMITED = PositionLimits()


@dataclass(frozen=True, slots=True)
class PlanarMotion:
    """The X, Y and (when commanded) C profiles of one motion, all starting at its start."""

    x: Profile
    y: Profile
    c: Profile | None  #: None: the motion leaves C alone
    c_start: float  #: [°] orientation at the start, reported by ``sample`` when ``c`` is None
    #: the arc length [mm] from the start when x and y run forward on one straight line from
    #: it (x = x0 + ux s, y = y0 + uy s) and c never turns back; None when a lead brakes on
    #: another line first or a motion turns back. The planar group then needs only the ends
    #: of the runs it cuts the path into (mover.py)
    s: Profile | None = None
    #: ``area_kernels.straight_area_numbers`` of the motion from its start, when the planner
    #: was given the ``sweep`` and computed them in its own compiled pass (else None)
    swept: tuple | None = field(default=None, compare=False)

    @property
    def duration(self) -> float:
        """[s] until every coordinate has reached its end state."""
        return max(p.duration for p in (self.x, self.y, self.c) if p is not None)

    def sample(self, time_step: float) -> tuple[np.ndarray, np.ndarray]:
        """Times [s] and (x, y, c) rows every ``time_step`` from start to end, plus every
        segment boundary, so the polyline through the points has every corner of the path
        (the planar group's swept-area check)."""
        if not time_step > 0.0:
            raise ValueError(f"time_step must be > 0, not {time_step}")
        end = self.duration
        profiles = [p for p in (self.x, self.y, self.c) if p is not None]
        steps = np.arange(math.ceil(end / time_step)) * time_step
        times = np.unique(np.concatenate([steps, [end], *(p.t[p.t <= end] for p in profiles)]))
        c = _positions(self.c, times) if self.c is not None else np.full(times.size, self.c_start)
        return times, np.column_stack((_positions(self.x, times), _positions(self.y, times), c))


def _positions(profile: Profile, times: np.ndarray) -> np.ndarray:
    k = np.maximum(np.searchsorted(profile.t, times, side="right") - 1, 0)
    dt = times - profile.t[k]
    return profile.p[k] + dt * (profile.v[k] + dt * (profile.a[k] / 2.0
                                                     + dt * profile.j[k] / 6.0))


def sample_path(plans: Sequence[tuple[Profile, float]], start: float, time_step: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """Times [s] after ``start`` and positions (one column per plan) of profiles that each
    started at its own time t0 [s], at ``sample_times``. A plan that has ended and rests
    shows its end position."""
    moving = [running(plan, start) for plan in plans]
    live = [plan for plan, run in zip(plans, moving, strict=True) if run]
    times = sample_times(live, start, time_step)
    path = np.empty((times.size, len(plans)))
    if live:
        path[:, [k for k, run in enumerate(moving) if run]] = _positions_at(live, times).T
    for k, (profile, _) in enumerate(plans):
        if not moving[k]:
            path[:, k] = profile.p[-1]
    return times - start, path


def sample_times(plans: Sequence[tuple[Profile, float]], start: float, time_step: float
                 ) -> np.ndarray:
    """Absolute times [s] every ``time_step`` from ``start`` until the last of the running
    ``plans`` (profile, t0) has ended, plus every later segment boundary (the corners of the
    path); times closer than 1e-12 s to the one before are dropped."""
    end = max((t0 + p.duration for p, t0 in plans), default=start)
    grid = start + np.arange(math.ceil(max(end - start, 0.0) / time_step) + 1) * time_step
    corners = np.concatenate([t0 + p.t for p, t0 in plans]) if plans else grid[:0]
    times = np.concatenate((grid, corners[corners > start], (end,)))
    times.sort()
    times = times[:np.searchsorted(times, end, side="right")]
    keep = np.empty(times.size, dtype=bool)
    keep[0] = True
    np.greater(times[1:] - times[:-1], 1e-12, out=keep[1:])
    return times[keep]


def _positions_at(plans: Sequence[tuple[Profile, float]], times: np.ndarray) -> np.ndarray:
    """(plans, times) positions of each profile started at its t0 at the absolute ``times``
    (its start position before t0): ``_positions`` for all plans in one evaluation."""
    starts = {t0 for _, t0 in plans}
    if len(starts) == 1:  # the usual case: all start together
        rel = np.maximum(times - starts.pop(), 0.0)
        shifted = [rel] * len(plans)
    else:
        rel = np.maximum(times - np.array([[t0] for _, t0 in plans]), 0.0)
        shifted = list(rel)
    index = np.empty((len(plans), times.size), dtype=np.intp)
    for row, (profile, _) in enumerate(plans):
        index[row] = np.searchsorted(profile.t, shifted[row], side="right")
    first = np.cumsum([0] + [profile.data.shape[1] for profile, _ in plans[:-1]])[:, None]
    index += first - 1
    np.maximum(index, first, out=index)  # the segment that holds each time
    t, p, v, a, j = np.concatenate([profile.data for profile, _ in plans], axis=1)[:, index]
    dt = rel - t
    return p + dt * (v + dt * (a / 2.0 + dt * j / 6.0))


def running(plan: tuple[Profile, float], start: float) -> bool:
    """The profile still moves after ``start`` (or cruises on forever)."""
    profile, t0 = plan
    return t0 + profile.duration > start or bool(profile.v[-1] != 0.0)


def plan_move_to_position(
    start: tuple[KinematicState, KinematicState, KinematicState],
    target: Sequence[float],
    limits: Limits,
    c_limits: Limits | None = None,
    *,
    x_limits: PositionLimits = UNLIMITED,
    y_limits: PositionLimits = UNLIMITED,
    c_windows: CWindows | None = None,
    sweep: Sequence[float] | None = None,
) -> PlanarMotion:
    """MoveToPosition (§7.2.2.8.1) from ``start`` (x, y, c) to ``target`` (x, y) or (x, y, c).

    ``limits`` are the tangential XY limits; ``c_limits`` are needed with a C target.
    Rejections: PLANAR_INVALID_INPUT (target not finite), PLANAR_POSITION_LIMIT (x or y limits,
    or a C motion leaving its window when ``c_windows`` is given).

    ``sweep``: the last eight arguments of ``area_kernels.straight_area_numbers`` after the
    plans (the start [s], on to the noise) for the swept area a planar group will ask for;
    a turning move from rest then carries those numbers (``PlanarMotion.swept``), computed
    in the planner's compiled pass (``reservation.straight_sweep`` makes them).
    """
    x, y, c = start
    if len(target) not in (2, 3) or (len(target) == 3 and c_limits is None):
        raise ValueError("target is (x, y) or (x, y, c), and a C target needs c_limits")
    tx, ty = _finite(target[0], "x"), _finite(target[1], "y")
    if len(target) == 3 and x.velocity == y.velocity == x.acceleration == y.acceleration == 0.0:
        found = _turning_rest_move(x.position, y.position, tx, ty, limits, c,
                                   _finite(target[2], "c"), c_limits, c_windows,  # type: ignore[arg-type]
                                   sweep)
        if found is not None:
            x_limits.check(found.x, "x")
            y_limits.check(found.y, "y")
            return found
    lead = None if _on_line(x, y, tx, ty, limits) else _xy_brake(x, y, limits)
    lead_time = 0.0 if lead is None else max(lead[0].duration, lead[1].duration)
    line = _Line(x, y, tx, ty) if lead is None else _Line(lead[0].end, lead[1].end, tx, ty)
    c_target = None if len(target) == 2 else _finite(target[2], "c")
    c_monotonic = True
    rest = None if lead is not None else _rest_move(line, limits, c, c_target, c_limits)
    if rest is not None:
        s, c_profile = rest
    elif c_target is None:
        s, c_profile = plan_position(line.s_start, line.length, limits), None
    else:
        s, c_profile = _synchronise(line, limits, lead_time, c, c_target, c_limits)
        c_monotonic = monotonic(c_profile)
    if c_profile is not None and c_windows is not None \
            and not c_windows.contains_motion(c_profile, c_monotonic):
        raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                              f"c {c.position:g} -> {c_profile.end.position:g} leaves its "
                              f"C window; only MoveC rotates outside the windows (§4.2)")
    px, py = line.profiles(s)
    if lead is not None:
        px = Profile.concatenate(_pad(lead[0], lead_time), px)
        py = Profile.concatenate(_pad(lead[1], lead_time), py)
    x_limits.check(px, "x")
    y_limits.check(py, "y")
    straight = lead is None and c_monotonic and (rest is not None or monotonic(s))
    return PlanarMotion(px, py, c_profile, c.position, s if straight else None)


def _turning_rest_move(x0: float, y0: float, tx: float, ty: float, limits: Limits,
                       c: KinematicState, c_target: float, c_limits: Limits,
                       c_windows: CWindows | None, sweep: Sequence[float] | None
                       ) -> PlanarMotion | None:
    """``plan_move_to_position`` of a mover at rest in x and y (velocity and acceleration
    exactly 0) with a C target, when ``_rest_move`` plans it in closed form: the same numbers
    from one compiled call (``_synchronised_line``, with the swept area's numbers when
    ``sweep`` is given), with the C window check on the extremes of C. None when
    ``_rest_move`` would not plan it (then the general way does)."""
    length = math.hypot(tx - x0, ty - y0)  # as _Line has them
    if length > 0.0:
        ux, uy = (tx - x0) / length, (ty - y0) / length
    else:
        ux, uy = 1.0, 0.0
    if not (limits.acceleration == limits.deceleration and length >= PREDICTION_DISTANCE
            and c.velocity == c.acceleration == 0.0
            and c_limits.acceleration == c_limits.deceleration
            and abs(c_target - c.position) >= PREDICTION_DISTANCE):
        return None
    numbers = (length, limits.velocity, limits.acceleration, limits.jerk, c.position, c_target,
               c_limits.velocity, c_limits.acceleration, c_limits.jerk, x0, ux, tx, y0, uy, ty)
    swept = None
    if sweep is None:
        s, rotation, px, py, c_low, c_high = _synchronised_line(*numbers)
    else:
        s, rotation, px, py, c_low, c_high, swept = _synchronised_line_area(*numbers, *sweep)
    if c_windows is not None and not c_windows.contains_interval(c_low, c_high):
        raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                              f"c {c.position:g} -> {rotation[1, -1]:g} leaves its "
                              f"C window; only MoveC rotates outside the windows (§4.2)")
    s_profile = Profile.from_data(s)
    return PlanarMotion(Profile.from_data(px), Profile.from_data(py),
                        Profile.from_data(rotation), c.position, s_profile, swept)


@compiled
def _synchronised_line(distance: float, velocity: float, acceleration: float, jerk: float,
                       c0: float, c_target: float, c_velocity: float, c_acceleration: float,
                       c_jerk: float, x0: float, ux: float, tx: float, y0: float, uy: float,
                       ty: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                           float, float]:
    """``synchronised`` path and rotation, the path mapped to x and y (``_along_line``),
    and the lowest and highest c of the rotation (it never turns back): a turning
    MoveToPosition from rest in one call."""
    s, rotation = synchronised(distance, velocity, acceleration, jerk, c0, c_target,
                               c_velocity, c_acceleration, c_jerk)
    px, py = _along_line(s, x0, ux, tx, y0, uy, ty)
    low = high = rotation[1, 0]
    for k in range(1, rotation.shape[1]):
        low, high = min(low, rotation[1, k]), max(high, rotation[1, k])
    return s, rotation, px, py, low, high


@compiled
def _synchronised_line_area(distance: float, velocity: float, acceleration: float,
                            jerk: float, c0: float, c_target: float, c_velocity: float,
                            c_acceleration: float, c_jerk: float, x0: float, ux: float,
                            tx: float, y0: float, uy: float, ty: float, start: float,
                            step: float, release_step: float, span: float, hx: float,
                            hy: float, noise: float):  # noqa: ANN201 - the tuple below
    """``_synchronised_line`` and then ``straight_area_numbers`` of its x, y and rotation
    started at ``start``, each running as ``running`` tells (the swept area a planar group
    asks for, ``mover._future_area``), in one call."""
    s, rotation, px, py, low, high = _synchronised_line(
        distance, velocity, acceleration, jerk, c0, c_target, c_velocity, c_acceleration,
        c_jerk, x0, ux, tx, y0, uy, ty)
    moving_x = start + px[0, px.shape[1] - 1] > start or px[2, px.shape[1] - 1] != 0.0
    moving_y = start + py[0, py.shape[1] - 1] > start or py[2, py.shape[1] - 1] != 0.0
    turning = start + rotation[0, rotation.shape[1] - 1] > start \
        or rotation[2, rotation.shape[1] - 1] != 0.0
    swept = straight_area_numbers(s, px, start, moving_x, py, start, moving_y, rotation, start,
                                  turning, turning, start, step, release_step, span, hx, hy,
                                  noise)
    return s, rotation, px, py, low, high, swept


class _Line:
    """The straight line from (x, y) to the target, with the start state projected on it."""

    def __init__(self, x: KinematicState, y: KinematicState, tx: float, ty: float) -> None:
        self.x0, self.y0, self.tx, self.ty = x.position, y.position, tx, ty
        self.length = math.hypot(tx - x.position, ty - y.position)
        if self.length > 0.0:
            self.ux, self.uy = (tx - x.position) / self.length, (ty - y.position) / self.length
        else:
            self.ux, self.uy = 1.0, 0.0
        self.s_start = KinematicState(0.0, self.ux * x.velocity + self.uy * y.velocity,
                                      self.ux * x.acceleration + self.uy * y.acceleration)

    def profiles(self, s: Profile) -> tuple[Profile, Profile]:
        """x and y of the arc-length profile ``s``, ending exactly on the target."""
        px, py = _along_line(s.data, self.x0, self.ux, self.tx, self.y0, self.uy, self.ty)
        return Profile.from_data(px), Profile.from_data(py)


def _along(s: Profile, origin: float, component: float) -> Profile:
    """One coordinate of a motion along a unit direction: origin + component * s(t)."""
    data = s.data * component
    data[0] = s.t
    data[1] += origin
    return Profile.from_data(data)


@compiled
def _along_line(s: np.ndarray, x0: float, ux: float, tx: float, y0: float, uy: float,
                ty: float) -> tuple[np.ndarray, np.ndarray]:
    """``_along`` for x and y in one compiled pass, the open segments on the target exactly
    (every MoveToPosition maps its arc length so)."""
    x, y = np.empty_like(s), np.empty_like(s)
    for k in range(s.shape[1]):
        x[0, k] = y[0, k] = s[0, k]
        x[1, k], y[1, k] = s[1, k] * ux + x0, s[1, k] * uy + y0
        for row in range(2, 5):
            x[row, k], y[row, k] = s[row, k] * ux, s[row, k] * uy
    x[1, s.shape[1] - 1], y[1, s.shape[1] - 1] = tx, ty
    return x, y


def _on_line(x: KinematicState, y: KinematicState, tx: float, ty: float, limits: Limits) -> bool:
    """Whether the mover rests, or its velocity and acceleration point along the line to the
    target (then that line is its path without a corner)."""
    if _at_rest(x, y, limits):
        return True
    dx, dy = tx - x.position, ty - y.position
    length = math.hypot(dx, dy)
    if length == 0.0:
        return False
    across_v = (dx * y.velocity - dy * x.velocity) / length
    across_a = (dx * y.acceleration - dy * x.acceleration) / length
    return (abs(across_v) <= ACROSS_PRECISION * limits.velocity
            and abs(across_a) <= ACROSS_PRECISION * max(limits.acceleration, limits.deceleration))


def _at_rest(x: KinematicState, y: KinematicState, limits: Limits) -> bool:
    return (math.hypot(x.velocity, y.velocity) <= REST_PRECISION * limits.velocity
            and math.hypot(x.acceleration, y.acceleration)
            <= REST_PRECISION * max(limits.acceleration, limits.deceleration))


def _xy_brake(x: KinematicState, y: KinematicState, limits: Limits) -> tuple[Profile, Profile]:
    """X and Y braked to rest along their current path with the XY deceleration and jerk.

    A straight motion (velocity and acceleration parallel: every motion planned here) brakes
    on its line. A curved one (a track arc, external setpoints) brakes each axis with the
    limits divided by √2, so the vector of the two never exceeds the path limits.
    """
    if _at_rest(x, y, limits):
        return Profile.hold(KinematicState(x.position)), Profile.hold(KinematicState(y.position))
    speed = math.hypot(x.velocity, y.velocity)
    if speed > REST_PRECISION * limits.velocity:
        ux, uy = x.velocity / speed, y.velocity / speed
    else:
        size = math.hypot(x.acceleration, y.acceleration)
        ux, uy = x.acceleration / size, y.acceleration / size
    across = ux * y.acceleration - uy * x.acceleration
    if abs(across) <= ACROSS_PRECISION * max(limits.acceleration, limits.deceleration):
        s = KinematicState(0.0, ux * x.velocity + uy * y.velocity,
                           ux * x.acceleration + uy * y.acceleration)
        brake = plan_stop(s, limits.deceleration, limits.jerk)
        return _along(brake, x.position, ux), _along(brake, y.position, uy)
    deceleration, jerk = limits.deceleration / math.sqrt(2.0), limits.jerk / math.sqrt(2.0)
    return plan_stop(x, deceleration, jerk), plan_stop(y, deceleration, jerk)


def _pad(profile: Profile, duration: float) -> Profile:
    """``profile`` resting at its end until ``duration`` (so a following piece starts then)."""
    rest = duration - profile.duration
    if rest <= 0.0:
        return profile
    end = profile.end.position
    return Profile.concatenate(profile, Profile([0.0, rest], [end, end], [0.0, 0.0],
                                                [0.0, 0.0], [0.0, 0.0]))


def _rest_move(line: _Line, limits: Limits, c: KinematicState, c_target: float | None,
               c_limits: Limits | None) -> tuple[Profile, Profile | None] | None:
    """The arc length and C profiles (C: None without a C target) of a move from rest with
    acceleration equal to deceleration, in closed form (``double_s``): the slower of path and
    C is time-optimal and the other lasts as long. None outside that case, or for moves
    shorter than ``PREDICTION_DISTANCE`` (ruckig plans those as before)."""
    s = line.s_start
    if not (s.velocity == s.acceleration == 0.0 and limits.acceleration == limits.deceleration
            and line.length >= PREDICTION_DISTANCE):
        return None
    v, a, j = limits.velocity, limits.acceleration, limits.jerk
    if c_target is None:
        return Profile.from_data(rest_to_rest(0.0, line.length, v, a, j, 0.0)), None
    if not (c_limits is not None and c.velocity == c.acceleration == 0.0
            and c_limits.acceleration == c_limits.deceleration
            and abs(c_target - c.position) >= PREDICTION_DISTANCE):
        return None
    path, rotation = synchronised(line.length, v, a, j, c.position, c_target,
                                  c_limits.velocity, c_limits.acceleration, c_limits.jerk)
    return Profile.from_data(path), Profile.from_data(rotation)


def _synchronise(line: _Line, limits: Limits, lead_time: float, c: KinematicState,
                 c_target: float, c_limits: Limits) -> tuple[Profile, Profile]:
    """The arc-length and C profiles, the faster one stretched so that both end together.

    A stretched duration inside one of ruckig's blocked intervals ends later than asked; the
    other then follows it, so a few rounds settle any case. From rest with equal acceleration
    and deceleration the closed-form durations tell the faster one beforehand, so its
    time-optimal plan, which only its duration would serve, is not computed.
    """
    faster = _faster_from_rest(line, limits, lead_time, c, c_target, c_limits)
    if faster == "s":  # the first round's stretch, without the optimal plan of s
        rotation = plan_position(c, c_target, c_limits)
        s = _plan_lasting(line.s_start, line.length, limits, rotation.duration - lead_time)
    elif faster == "c":
        s = plan_position(line.s_start, line.length, limits)
        rotation = _plan_lasting(c, c_target, c_limits, lead_time + s.duration)
    else:
        s = plan_position(line.s_start, line.length, limits)
        rotation = plan_position(c, c_target, c_limits)
    for _ in range(_SYNC_ROUNDS - (faster is not None)):
        end = max(lead_time + s.duration, rotation.duration)
        if s.duration > 0.0 and lead_time + s.duration < end - SYNC_TIME_PRECISION:
            s = _plan_lasting(line.s_start, line.length, limits, end - lead_time)
        if rotation.duration > 0.0 and rotation.duration < end - SYNC_TIME_PRECISION:
            rotation = _plan_lasting(c, c_target, c_limits, end)
        if abs(lead_time + s.duration - rotation.duration) <= SYNC_TIME_PRECISION:
            break
    return s, rotation


def _faster_from_rest(line: _Line, limits: Limits, lead_time: float, c: KinematicState,
                      c_target: float, c_limits: Limits) -> str | None:
    """"s" or "c" when both start at rest, acceleration equals deceleration, both move at
    least ``PREDICTION_DISTANCE`` for at least ``PREDICTION_TIME`` (ruckig plans tinier
    moves as no move, or fails on them) and the closed-form durations differ by more than
    ``PREDICTION_MARGIN``; else None."""
    s = line.s_start
    if not (line.length >= PREDICTION_DISTANCE
            and abs(c_target - c.position) >= PREDICTION_DISTANCE
            and s.velocity == s.acceleration == c.velocity == c.acceleration == 0.0
            and limits.acceleration == limits.deceleration
            and c_limits.acceleration == c_limits.deceleration):
        return None
    path_time = rest_to_rest_time(line.length, limits)
    turn = rest_to_rest_time(c_target - c.position, c_limits)
    if min(path_time, turn) < PREDICTION_TIME:
        return None
    path = lead_time + path_time
    if path < turn - PREDICTION_MARGIN:
        return "s"
    if turn < path - PREDICTION_MARGIN:
        return "c"
    return None


def rest_to_rest_time(distance: float, limits: Limits) -> float:
    """[s] of the time-optimal jerk-limited move over ``distance`` from rest to rest with
    acceleration equal to deceleration (the double S-curve: ramps of jerk, acceleration and
    cruise as far as the limits ``limits`` allow; ruckig is the oracle in the tests)."""
    d, v, a, j = abs(distance), limits.velocity, limits.acceleration, limits.jerk
    if v * j >= a * a:  # a full ramp to v holds the acceleration limit
        ramp = v / a + a / j  # [s] from rest to v
        if d >= v * ramp:
            return d / v + ramp
        if d >= 2.0 * a ** 3 / (j * j):  # no cruise, the acceleration limit still reached
            peak = (math.sqrt((a * a / j) ** 2 + 4.0 * a * d) - a * a / j) / 2.0
            return 2.0 * (peak / a + a / j)
    else:  # the ramp to v is triangular in acceleration
        ramp = math.sqrt(v / j)
        if d >= 2.0 * v * ramp:
            return d / v + 2.0 * ramp
    return 4.0 * (d / (2.0 * j)) ** (1.0 / 3.0)  # triangular: no limit but the jerk reached


def _plan_lasting(start: KinematicState, target: float, limits: Limits,
                  duration: float) -> Profile:
    """A move to ``target`` ending no sooner than ``duration`` (ruckig's minimum duration).

    Unequal acceleration and deceleration map onto ruckig one direction at a time (plan.py),
    so a stretched profile that reverses brakes to rest first and starts again from there.
    """
    profile = plan_position_in(start, target, limits, duration)
    if limits.acceleration == limits.deceleration or not _reverses(profile):
        return profile
    brake = plan_stop(start, limits.deceleration, limits.jerk)
    rest = KinematicState(brake.end.position)
    remaining = max(duration - brake.duration, 0.0)
    return Profile.concatenate(brake, plan_position_in(rest, target, limits, remaining))


def _reverses(profile: Profile) -> bool:
    low, high = profile.velocity_extrema()
    tolerance = 1e-9 * max(abs(low), abs(high), 1.0)
    return low < -tolerance and high > tolerance


def plan_axis_move(start: KinematicState, target: float, limits: Limits,
                   position_limits: PositionLimits = UNLIMITED, coordinate: str = "z") -> Profile:
    """MoveZ, MoveA, MoveB (§6.1.5, §7.2.2.8.7-9): the time-optimal move of one auxiliary
    coordinate, inside its position limits (PLANAR_POSITION_LIMIT)."""
    profile = plan_position(start, _finite(target, coordinate), limits)
    position_limits.check(profile, coordinate)
    return profile


def plan_move_c(start: KinematicState, position: float, limits: Limits,
                direction: ModuloDirection = ModuloDirection.NON_MODULO,
                additional_turns: int = 0, modulus: float = 360.0,
                tolerance_window: float = 0.0) -> Profile:
    """MoveC (§6.1.9, §7.2.2.8.10): the time-optimal rotation to the absolute C target that
    ``position`` and the modulo options give (rotation.move_c_target). C has no position
    limits; its windows decide the command mode (rotation.mode_during_c_motion)."""
    target = move_c_target(start.position, position, direction, additional_turns, modulus,
                           tolerance_window)
    return plan_position(start, target, limits)


def plan_halt(states: Mapping[str, KinematicState],
              limits: Mapping[str, Limits]) -> dict[str, Profile]:
    """Halt (§7.2.2.8.12): every coordinate in ``states`` ("x", "y", "z", "a", "b", "c")
    brakes to rest with the deceleration and jerk of its group in ``limits`` ("xy", "z", "a",
    "b", "c"); x and y brake together along their path with the tangential XY limits."""
    halted = {}
    for name, state in states.items():
        if name in ("x", "y"):
            if "x" not in halted:
                halted["x"], halted["y"] = _xy_brake(states["x"], states["y"], limits["xy"])
        else:
            halted[name] = plan_stop(state, limits[name].deceleration, limits[name].jerk)
    return halted


def _finite(value: float, coordinate: str) -> float:
    if not math.isfinite(value):
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"{coordinate} target {value} is not finite")
    return float(value)
