"""The time law along a path: arc length s(t) over pieces with caps (PLCopen Part 4 §5.3-§5.6).

The geometry (geometry/path.py, blend.py) is parameterised by arc length; the axes group turns
its commands into ``Piece``s, each with caps on path speed, acceleration, deceleration and jerk
and a cap on the speed at its end. ``TimeLaw`` decides how fast to run along them: jerk-limited,
never backwards, within every cap, as fast as the caps allow. It plans on events and
evaluates stored constant-jerk segments every cycle (docs/architecture.md, "Plan on events").

Zones. A zone is a maximal run of pieces whose junctions do not bind: the exit cap is at least
the smaller velocity cap, the space is the same, and the zone's velocity caps lie within 0.95 of
each other. The zone's caps are the minima over its pieces, so keeping them keeps every piece's.
Within a zone, one leg runs from the current state to the zone's end; at a binding junction
the acceleration is zero and the speed is the junction speed of a forward/backward pass. With
a = 0 at both ends the time-optimal leg is ramp - cruise - ramp (timing_kernels.leg), the shape
ruckig would give; ruckig plans only legs that start with a != 0 (after an append, an override
or a resume while moving).

Look-ahead. A path may have 10 000+ pieces. The backward pass covers a window of whole zones
that assumes rest at its end; the window grows until the junction speeds it fixes no longer
depend on that assumption over half of it (timing_kernels.look_ahead), and the motion looks
again before it enters a zone whose speeds would. Each event costs the window, each cycle one
segment evaluation. On a dense path (chords with tiny blend contours) the speed is carried
through every junction the caps allow: its zones hold caps within 0.95 of each other, short
fast pieces between slower ones join them (the bump rule), and the contours' velocity caps,
which their curvature rate sets (limits.py), are all that slows it (D-134; `bench path` sets
the mean speed against the fastest profile under the caps and under the axes' own limits).

Dense profile (D-335). Zones return to a = 0 at every junction and run at their smallest cap.
A dense path (``append(..., dense=True)`` on a law that has not started) runs instead by one
profile from rest to rest that ramps the acceleration at the start of each piece with the
piece's jerk cap and holds it to the piece's end (dense_timing.py), checked segment by
segment against the caps before it runs. While it runs, a stop brakes at once piece by
piece (``_dense_brake``, D-362), an override change brakes it to rest under the old factors
and runs on by zones (``set_factors``), and appended pieces follow its end, where it rests.

Stops (§5.13-§5.16). ``stop`` brakes with the requested deceleration and jerk, lowered to the
smallest caps of the pieces within the braking distance. Where that brake would pass a junction
faster than its caps allow (a corner the plan slows for, the path's end), the motion follows
the plan, never speeding up, and brakes as soon as the brake fits.

Override (§5.28). ``set_factors`` scales velocity and exit caps by the velocity factor,
acceleration and deceleration by the acceleration factor, jerk by the jerk factor. Lowered caps
bind from where they can be reached: a faster motion brakes into them with the current
deceleration, and legs it cannot finish in time brake across junctions (docs/decisions.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from openmotion.coordinated.dense_timing import check, junction_speeds, release, split
from openmotion.coordinated.dense_timing import profile as dense_profile
from openmotion.coordinated.timing_kernels import (
    leg,
    look_ahead,
    other_end,
    zones,
)
from openmotion.coordinated.tolerances import (
    ABSOLUTE_SLACK,
    LENGTH_TOLERANCE,
    RELATIVE_TOLERANCE,
    SPEED_FLOOR,
    ZERO_ACCELERATION,
)
from openmotion.core.errors import CommandRejected
from openmotion.trajectory.plan import Limits, plan_position, plan_stop, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

_MAX_EVENTS = 1_000_000  #: legs one sample may run through before we call it a bug
_TAIL_TRIES = 256  #: junctions before the end a dense profile tries to brake from
_BRAKE_PASSES = 12  #: times a dense stop's brake widens the pieces whose caps it takes


@dataclass(frozen=True, slots=True)
class Piece:
    """A stretch of path with its caps, as the axes group derives them from its commands."""

    length: float  #: arc length [mm] > 0
    velocity: float  #: cap on the path speed on the whole piece [mm/s] > 0
    acceleration: float  #: cap on speeding up [mm/s²] > 0
    deceleration: float  #: cap on slowing down [mm/s²] > 0
    jerk: float  #: cap on |ds³/dt³| [mm/s³] > 0
    #: cap on the speed at the piece's end [mm/s]: 0 stops there (Buffered, TMNone, a corner
    #: without contour), math.inf leaves only the two pieces' own caps. The path's end is
    #: always a stop; the cap applies to the junction once more path is appended.
    exit_velocity: float
    space: int = 0  #: pieces of different spaces (ACS, MCS moves) meet with a stop


@dataclass(frozen=True, slots=True)
class Work:
    """What one ``sample`` (or event call) cost, for ``openmotion bench``."""

    zones: int = 0  #: zones the look-ahead passes scanned
    pieces: int = 0  #: pieces scanned by brakes
    legs: int = 0  #: legs planned
    ruckig: int = 0  #: legs planned by ruckig (those starting with a != 0)


# rows of the piece and zone tables
_END, _LEN, _V, _A, _D, _J, _EXIT, _SPACE, _ZONING = range(9)  # pieces
_ZSTART, _ZEND, _ZV, _ZVMAX, _ZA, _ZD, _ZJ, _ZEXIT = range(8)  # zones

_RUN, _PENDING, _BRAKE, _REST = "run", "pending", "brake", "rest"


class _Rows:
    """Float rows that grow at the end: the piece and zone tables."""

    def __init__(self, rows: int) -> None:
        self.data = np.zeros((rows, 16))
        self.n = 0

    def extend(self, block: np.ndarray) -> None:
        m = block.shape[1]
        if self.n + m > self.data.shape[1]:
            grown = np.zeros((self.data.shape[0], max(2 * self.data.shape[1], self.n + m)))
            grown[:, :self.n] = self.data[:, :self.n]
            self.data = grown
        self.data[:, self.n:self.n + m] = block
        self.n += m

    def row(self, r: int) -> np.ndarray:
        return self.data[r, :self.n]


class _Leg:
    """Constant-jerk segments from absolute time ``t0``, used until ``end`` after it.

    At ``end`` the state is ``final`` (s, v, a) exactly; the next leg starts there.
    """

    __slots__ = ("t0", "data", "t", "p", "v", "a", "j", "end", "final", "zone", "k", "rates",
                 "profile")

    def __init__(self, t0: float, data: np.ndarray, end: float,
                 final: tuple[float, float, float], zone: int) -> None:
        self.t0, self.data, self.end, self.final, self.zone = t0, data, end, final, zone
        self.t, self.p, self.v, self.a, self.j = data.tolist()
        self.k = 0
        #: the acceleration and jerk factors whose caps the leg keeps (None: a fallback brake)
        self.rates: tuple[float, float] | None = None
        self.profile = False  #: a dense path's whole profile (dense_timing.py), not a zone's

    @classmethod
    def hold(cls, t0: float, s: float, zone: int) -> _Leg:
        return cls(t0, np.array([[0.0], [s], [0.0], [0.0], [0.0]]), math.inf, (s, 0.0, 0.0),
                   zone)

    def at(self, time: float) -> tuple[float, float, float, float]:
        dt = time - self.t0
        t, k, last = self.t, self.k, len(self.t) - 1
        while k < last and t[k + 1] <= dt:
            k += 1
        self.k = k
        d = dt - t[k]
        p0, v0, a0, j = self.p[k], self.v[k], self.a[k], self.j[k]
        return (p0 + d * (v0 + d * (0.5 * a0 + d * j / 6.0)), v0 + d * (a0 + 0.5 * d * j),
                a0 + d * j, j)


@dataclass(slots=True)
class _Window:
    z0: int
    speeds: list[float]  #: junction speed at the end of zone z0 + k
    n: int
    k_exact: int  #: speeds[:k_exact + 1] do not depend on the rest assumed at the window's end


@dataclass(frozen=True, slots=True)
class _StopRequest:
    deceleration: float
    jerk: float
    keep: bool
    by_override: bool = False


class TimeLaw:
    """s(t) >= 0 along a growing list of pieces; planned on events, evaluated every cycle.

    ``start_time`` [s] is when the motion starts with ``start_velocity`` [mm/s] and
    ``start_acceleration`` [mm/s²] (a group that aborts a path motion starts the new one from
    the old state; append its path before the first sample). Changes from ``append`` take
    effect at the last sample (D-001), so call ``sample`` every cycle. ``record=True`` keeps
    every leg in ``history`` as (start time, time used, Profile) for tests and plots.
    """

    def __init__(self, start_time: float, start_velocity: float = 0.0,
                 start_acceleration: float = 0.0, record: bool = False) -> None:
        if start_velocity < 0.0:
            raise ValueError("the start velocity along a path is >= 0")
        self._time = float(start_time)
        self._state = (0.0, float(start_velocity), float(start_acceleration), 0.0)
        self._pieces = _Rows(9)
        self._zones = _Rows(8)
        self._length = 0.0
        self._factors = (1.0, 1.0, 1.0)
        self._velocity_factor = 1.0  #: the last velocity factor > 0: the caps while paused
        #: acceleration and jerk factors the motion was planned with before an override drop;
        #: brakes may use them until a leg under the new factors has run to its end
        self._planned_rates = (1.0, 1.0)
        self._mode = _RUN
        self._stop: _StopRequest | None = None
        self._leg: _Leg | None = None
        self._dirty = True  #: the path changed: re-plan from the last sample
        self._window: _Window | None = None
        self._span = 0.0
        self._work = [0, 0, 0, 0]
        self._last_work = Work()
        #: the segments of a dense path's profile, built when its pieces were appended to a
        #: law at rest (D-335); installed by the first plan, dropped by anything else
        self._profile: np.ndarray | None = None
        #: override factors set while a profile ran: applied once its pause came to rest
        self._deferred: tuple[float, float, float] | None = None
        self.history: list[tuple[float, float, Profile]] | None = [] if record else None

    # -- the path ------------------------------------------------------------------------------

    def append(self, pieces: Sequence[Piece], dense: bool = False) -> None:
        """More path at the end; the motion re-plans from the last sample to run on into it.

        ``dense``: the pieces are a dense path (coordinated/dense.py). Appended to a law that
        has not started, at rest and without an override, the motion runs them by one profile
        that changes the acceleration on the lines (dense_timing.py, D-335) where that
        profile keeps every cap; else by zones."""
        if not pieces:
            return
        fresh = dense and self._leg is None and self._pieces.n == 0 and self._state == \
            (0.0, 0.0, 0.0, 0.0) and self._factors == (1.0, 1.0, 1.0) and self._stop is None
        if self._stop is not None and not self._stop.keep and self._mode != _REST:
            raise RuntimeError("the path cannot grow while a stop brakes (Part 4 §5.13)")
        block = np.array([(p.length, p.velocity, p.acceleration, p.deceleration, p.jerk,
                           p.exit_velocity, p.space) for p in pieces], dtype=float).T
        _check(block)
        self._extend(block)
        self._profile = self._dense_profile() if fresh else None
        if self._mode == _REST and self._stop is not None and not self._stop.keep:
            self._mode, self._stop = _RUN, None  # a finished MC_GroupStop: the next motion
        self._window = None
        if self._mode in (_RUN, _PENDING):
            self._dirty = True  # re-plan lazily from the last sample

    def _extend(self, block: np.ndarray) -> None:
        lengths, vel, acc, dec, jerk, exit_, space = block
        pieces, zone_rows = self._pieces, self._zones
        count = len(lengths)
        ends = np.cumsum(np.concatenate(([self._length], lengths)))[1:]
        previous = np.zeros(9)
        if pieces.n:
            last, z = pieces.n - 1, zone_rows.n - 1
            pd, zd = pieces.data, zone_rows.data
            previous[:] = (1.0, pd[_ZONING, last], pd[_EXIT, last], pd[_SPACE, last],
                           zd[_ZV, z], zd[_ZVMAX, z], zd[_ZA, z], zd[_ZD, z], zd[_ZJ, z])
        starts, zoning = zones(vel, acc, dec, jerk, exit_, space, lengths, previous)
        old_last = pieces.n - 1
        pieces.extend(np.vstack((ends, lengths, vel, acc, dec, jerk, exit_, space, zoning)))
        first = np.flatnonzero(starts)
        joined = first[0] if first.size else count
        if joined:  # the first pieces extend the last zone, whose caps they keep
            z = zone_rows.n - 1
            zone_rows.data[_ZEND, z] = ends[joined - 1]
            zone_rows.data[_ZVMAX, z] = max(zone_rows.data[_ZVMAX, z], zoning[:joined].max())
            changes = joined < count and space[joined - 1] != space[joined]
            zone_rows.data[_ZEXIT, z] = 0.0 if changes else exit_[joined - 1]
        elif old_last >= 0 and pieces.data[_SPACE, old_last] != space[0]:
            zone_rows.data[_ZEXIT, zone_rows.n - 1] = 0.0  # the old last zone meets a new space
        if first.size:
            begin = np.concatenate(([self._length], ends))[first]
            last_piece = np.concatenate((first[1:], [count])) - 1
            exits = exit_[last_piece].copy()
            following = last_piece + 1 < count
            changes = np.zeros(len(first), dtype=bool)
            changes[following] = space[last_piece[following]] != space[last_piece[following] + 1]
            exits[changes] = 0.0
            zone_rows.extend(np.vstack((
                begin, ends[last_piece], np.minimum.reduceat(zoning, first),
                np.maximum.reduceat(zoning, first), np.minimum.reduceat(acc, first),
                np.minimum.reduceat(dec, first), np.minimum.reduceat(jerk, first), exits)))
        self._length = float(ends[-1])

    @property
    def length(self) -> float:
        """Total arc length of the path [mm]; a stop that drops pieces shortens it."""
        return self._length

    def speed_limits(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(length [mm], velocity cap, exit cap [mm/s]) of every piece, as appended (copies;
        ``openmotion bench path`` sets the achieved speed against them)."""
        pieces = self._pieces
        return (pieces.row(_LEN).copy(), pieces.row(_V).copy(), pieces.row(_EXIT).copy())

    def locate(self, s: float) -> tuple[int, float]:
        """(piece index, arc length within it) of ``s``; indices count from the first piece
        ever appended, so the group can map them to its commands. A junction belongs to the
        piece after it, the path's end to the last piece."""
        pieces = self._pieces
        if not pieces.n:
            raise ValueError("the path has no pieces")
        ends = pieces.row(_END)
        k = min(int(np.searchsorted(ends, s, side="right")), pieces.n - 1)
        return k, s - (ends[k - 1] if k else 0.0)

    # -- cycle ---------------------------------------------------------------------------------

    def sample(self, now: float) -> tuple[float, float, float, float]:
        """(s, v, a, j) at ``now`` [s]: plans on the events due, then evaluates one segment."""
        if now < self._time:
            raise ValueError(f"time went backwards: {now!r} < {self._time!r}")
        self._work = [0, 0, 0, 0]
        self._advance(now)
        if self._mode == _PENDING and not self._try_brake(now, self._state[:3]) \
                and self.standing:
            self._finish_stop(now, self._state[0], self._leg.zone)
        if self._deferred is not None and self._mode == _REST:
            factors, self._deferred = self._deferred, None
            self.set_factors(now, *factors)
        self._last_work = Work(*self._work)
        return self._state

    @property
    def last_work(self) -> Work:
        """What the last ``sample`` cost."""
        return self._last_work

    def _advance(self, now: float) -> None:
        """Run through the legs ending up to ``now``, then evaluate."""
        if self._dirty:
            self._dirty = False
            self._plan_from(self._time, self._state[:3], changed_path=self._leg is not None)
        for _ in range(_MAX_EVENTS):
            leg_ = self._leg
            if now < leg_.t0 + leg_.end:
                break
            if leg_.rates is not None and leg_.rates == self._factors[1:]:
                # a leg planned under the factors set now has run: the motion no longer
                # needs the rates of an earlier override (a leg planned before a drop of the
                # jerk factor that ends after it does not count: the next leg may still need
                # the old rates to reach the junction speed that leg was planned for)
                self._planned_rates = self._factors[1:]
            self._next_leg(leg_.t0 + leg_.end, leg_.final, leg_.zone)
        else:
            raise RuntimeError("the time law made no progress (a bug: please report it)")
        s, v, a, j = self._leg.at(now)
        previous = self._state[0]
        s = min(max(s, previous), self._leg_limit())  # round-off must not move s backwards
        self._state = (s, max(v, 0.0), a, j)
        self._time = now

    def _leg_limit(self) -> float:
        return self._leg.final[0] if math.isfinite(self._leg.end) else self._length

    def _next_leg(self, time: float, final: tuple[float, float, float], zone: int) -> None:
        s, v, a = final
        if self._mode == _BRAKE:
            self._mode = _REST
            self._install(_Leg.hold(time, s, zone))
            return
        if self._mode == _PENDING and self._try_brake(time, final):
            return
        if self._mode == _PENDING and v == 0.0 and a == 0.0:
            self._finish_stop(time, s, zone)
            return
        if s >= self._length:
            self._install(_Leg.hold(time, self._length, self._zones.n - 1))
            return
        zones = self._zones
        if s >= zones.data[_ZEND, zone]:
            zone += 1
        self._install(self._zone_leg(time, final, zone))

    def _install(self, new: _Leg) -> None:
        old = self._leg
        if self.history is not None and old is not None:
            self.history[-1] = (old.t0, new.t0 - old.t0, self.history[-1][2])
        if self.history is not None:
            self.history.append((new.t0, new.end, Profile.from_data(new.data)))
        self._leg = new

    def _plan_from(self, time: float, state: tuple[float, float, float],
                   changed_path: bool = False) -> None:
        s, v, a = state
        if self._mode in (_BRAKE, _REST) and self._leg is not None:
            return
        if self._mode == _REST or not self._pieces.n or (s >= self._length and v == 0.0):
            if v > 0.0 or a != 0.0:
                raise RuntimeError("a moving time law needs path: append pieces first")
            self._install(_Leg.hold(time, s, max(self._zones.n - 1, 0)))
            return
        zone = min(int(np.searchsorted(self._zones.row(_ZEND), s, side="right")),
                   self._zones.n - 1)
        if changed_path and self._on_profile():
            return  # the profile ends at rest where the path ended; the new pieces follow
        if not changed_path:
            if self._profile is not None and self._factors == (1.0, 1.0, 1.0) \
                    and state == (0.0, 0.0, 0.0) and self._mode == _RUN:
                self._install(self._profile_leg(time))
                return
            self._install(self._zone_leg(time, state, zone))
            return
        new, _ = self._replanned(time, state, zone)
        if new is not self._leg:
            self._install(new)

    def _dense_profile(self) -> np.ndarray | None:
        """The segments of the dense profile over all pieces from rest to rest, or None where
        it cannot keep every cap (module dense_timing): up to a junction near the end, then
        ruckig's brake to the end within the smallest caps of the pieces left."""
        pieces = self._pieces
        lengths, vel, acc, dec, jerk = (pieces.row(r) for r in (_LEN, _V, _A, _D, _J))
        targets = junction_speeds(lengths, vel, acc, dec, pieces.row(_EXIT),
                                  pieces.row(_SPACE))
        if not targets[1:-1].size or targets[1:-1].min() <= 0.0:
            return None
        data, states, reached = dense_profile(lengths, vel, acc, dec, jerk, targets)
        ends = pieces.row(_END)
        for m in range(reached, max(reached - _TAIL_TRIES, 0), -1):
            time, v, a = states[:, m]
            s = float(ends[m - 1])
            limits = Limits(float(vel[m:].min()), float(acc[m:].min()), float(dec[m:].min()),
                            float(jerk[m:].min()))
            # a start at the cap that still accelerates passes it before the jerk can
            # bring the acceleration down: ruckig's tail would then break the cap
            if v + max(a, 0.0) ** 2 / (2.0 * limits.jerk) > \
                    limits.velocity * (1.0 + RELATIVE_TOLERANCE) \
                    or not -limits.deceleration <= a <= limits.acceleration:
                continue
            try:
                tail = plan_position(KinematicState(s, v, a), self._length, limits)
            except CommandRejected:
                continue
            if not _keeps(tail, (s, v, a), limits):
                continue
            head = data[:, :int(np.searchsorted(data[0], time, side="left"))]
            rest = tail.data.copy()
            rest[0] += time
            rest[1, -1] = self._length
            if check(np.hstack((head, rest[:, :1])), ends, vel, acc, dec, jerk) < 0:
                return np.hstack((head, rest))
        return None

    def _profile_leg(self, time: float) -> _Leg:
        data, self._profile = self._profile, None
        self._work[2] += 1
        new = _Leg(time, data, float(data[0, -1]), (self._length, 0.0, 0.0),
                   self._zones.n - 1)
        new.profile, new.rates = True, self._factors[1:]
        return new

    def _replanned(self, time: float, state: tuple[float, float, float], zone: int
                   ) -> tuple[_Leg, bool]:
        """The leg to run on after the path changed under the motion (``append``,
        ``trim_last``), and whether it ends where the look-ahead assumed: at or below its
        junction speed, with a = 0. A leg re-planned from a != 0 (ruckig's, or a brake cut at
        the junction) may miss that by a little, and the legs after it, planned from a = 0
        at each junction, then by far: a stop corner passed at speed, a contour entered at
        20 times its speed cap (tests/coordinated/test_properties.py). Where the leg under
        way still ends as the new look-ahead wants (the new path asks nothing of its zone),
        it is kept."""
        new = self._zone_leg(time, state, zone)
        if self._lands(new, zone):
            return new, True
        old = self._leg
        if self._mode == _RUN and old is not None and not old.profile and old.zone == zone \
                and old.t0 + old.end > time and old.final[0] == self._zones.data[_ZEND, zone] \
                and self._lands(old, zone):
            return old, True
        return new, False

    def _lands(self, leg_: _Leg, zone: int) -> bool:
        w = self._window
        k = zone - w.z0 if w is not None else -1
        target = w.speeds[k] if w is not None and 0 <= k < w.n else 0.0
        _, acc, dec, _ = self._caps(zone)
        _, reached, final_a = leg_.final
        return reached <= target * (1.0 + RELATIVE_TOLERANCE) + ABSOLUTE_SLACK \
            and abs(final_a) <= ZERO_ACCELERATION * max(acc, dec)

    # -- legs ----------------------------------------------------------------------------------

    def _caps(self, zone: int) -> tuple[float, float, float, float]:
        _, fa, fj = self._factors
        fv = self._velocity_factor
        zd = self._zones.data
        return zd[_ZV, zone] * fv, zd[_ZA, zone] * fa, zd[_ZD, zone] * fa, zd[_ZJ, zone] * fj

    def _look(self, zone: int, s: float) -> _Window:
        zr = self._zones
        _, fa, fj = self._factors
        fv = self._velocity_factor
        speeds, n, k_exact, span, scanned = look_ahead(
            zr.row(_ZSTART), zr.row(_ZEND), zr.row(_ZV), zr.row(_ZA), zr.row(_ZD), zr.row(_ZJ),
            zr.row(_ZEXIT), zone, s, fv, fa, fj, 0.5 * self._span)
        self._span = span
        self._work[0] += scanned
        self._window = _Window(zone, speeds.tolist(), n, k_exact)
        return self._window

    def _zone_leg(self, time: float, state: tuple[float, float, float], zone: int) -> _Leg:
        """The leg through ``zone`` to its end, at the junction speed of the look-ahead."""
        s = state[0]
        w = self._window
        k = zone - w.z0 if w is not None else -1
        if w is None or not 0 <= k <= w.k_exact:
            w, k = self._look(zone, s), 0
        return self._leg_to(time, state, zone, self._zones.data[_ZEND, zone], w.speeds[k])

    def _leg_to(self, time: float, state: tuple[float, float, float], zone: int, end: float,
                target: float) -> _Leg:
        """The leg to (``end``, ``target``, a = 0), time-optimal under the caps set now. After
        an override drop the motion may not reach the target in time; then, in this order: the
        rates it was planned with, the lowest speed above the target it can reach with them,
        and as a last resort a brake raised just enough to keep the next stop."""
        self._work[2] += 1
        caps = self._caps(zone)
        new = self._leg_within(time, state, zone, end, target, caps)
        if new is not None:
            new.rates = self._factors[1:]
            return new
        v_max, acc, dec, jerk = caps
        zd = self._zones.data
        fa, fj = self._planned_rates
        planned = (v_max, max(acc, zd[_ZA, zone] * fa), max(dec, zd[_ZD, zone] * fa),
                   max(jerk, zd[_ZJ, zone] * fj))
        if planned != caps:
            new = self._leg_within(time, state, zone, end, target, planned)
            if new is not None:
                return new
        above = _reachable_above(state, end - state[0], target, *planned[1:])
        if above is not None:
            new = self._leg_within(time, state, zone, end, above, (max(v_max, above),
                                                                   *planned[1:]))
            if new is not None:
                return new
        return self._brake_leg(time, state, zone, end, target, planned)

    def _leg_within(self, time: float, state: tuple[float, float, float], zone: int,
                    end: float, target: float,
                    caps: tuple[float, float, float, float]) -> _Leg | None:
        """A leg keeping ``caps`` to (``end``, u, a = 0), u <= ``target`` as high as it can
        reach, or None when even the lowest such u lies out of reach."""
        s, v, a = state
        v_max, acc, dec, jerk = caps
        if self._mode == _PENDING:
            v_max = min(v_max, v)  # a stop in waiting never speeds up (§5.13)
        if abs(a) <= ZERO_ACCELERATION * max(acc, dec):
            a = 0.0
        if a == 0.0 and v <= v_max:
            data, reached, ok = leg(v, end - s, target, v_max, acc, dec, jerk)
            if ok:
                return self._closed_leg(time, s, end, data, reached, zone)
        else:
            if a > 0.0 and v + a * a / (2.0 * jerk) > v_max:  # a lower jerk factor would
                jerk = max(jerk, self._zones.data[_ZJ, zone] * self._planned_rates[1])  # overshoot
            reach = min(target, _reach(v, a, end - s, acc, jerk))
            new = self._ruckig_leg(time, state, zone, end, reach, Limits(v_max, acc, dec, jerk))
            if new is not None:
                return new
        # the target lies where a brake under way cannot end with a = 0: the distance of a
        # jerk-limited brake to speed u is not monotone in u, so take the best reachable one
        lower = _reachable_below(state, end - s, target, acc, dec, jerk)
        if lower is None:
            return None
        if a == 0.0 and v <= v_max:
            data, reached, ok = leg(v, end - s, lower, v_max, acc, dec, jerk)
            if ok:
                return self._closed_leg(time, s, end, data, reached, zone)
        new = self._ruckig_leg(time, state, zone, end, lower, Limits(max(v_max, v), acc, dec,
                                                                     jerk))
        if new is not None:
            return new
        return _cut(time, _velocity_change(KinematicState(s, v, a), lower, dec, jerk, acc), end,
                    zone)

    def _closed_leg(self, time: float, s: float, end: float, data: np.ndarray, reached: float,
                    zone: int) -> _Leg:
        data[1] += s
        data[1, -1] = end
        return _Leg(time, data, data[0, -1], (end, reached, 0.0), zone)

    def _ruckig_leg(self, time: float, state: tuple[float, float, float], zone: int,
                    end: float, target: float, limits: Limits) -> _Leg | None:
        self._work[3] += 1
        try:
            profile = plan_position(KinematicState(*state), end, limits, target)
        except CommandRejected:
            return None
        if not _keeps(profile, state, limits):
            return None
        return _Leg(time, profile.data, profile.duration, (end, target, 0.0), zone)

    def _brake_leg(self, time: float, state: tuple[float, float, float], zone: int,
                   end: float, target: float, caps: tuple[float, float, float, float]) -> _Leg:
        """The last resort after an override drop: brake towards ``target`` with the rates the
        motion was planned with, raised just enough to rest by the next stop, cut at ``end``."""
        s, v, a = state
        _, acc, dec, jerk = caps
        scale = _scale_to_stop(state, dec, jerk, self._next_stop(zone))
        profile = _velocity_change(KinematicState(s, v, a), target, dec * scale, jerk * scale,
                                   acc * scale)
        return _cut(time, profile, end, zone)

    def _next_stop(self, zone: int) -> float:
        w = self._window
        if w is not None:
            for k in range(max(zone - w.z0, 0), w.n):
                if w.speeds[k] == 0.0:
                    return self._zones.data[_ZEND, w.z0 + k]
        return self._length

    # -- stops ---------------------------------------------------------------------------------

    def stop(self, now: float, deceleration: float, jerk: float, keep: bool) -> None:
        """Brake to rest along the path (MC_GroupStop, MC_GroupHalt: ``keep=False`` drops the
        path beyond the rest point; MC_GroupInterrupt: ``keep=True``, ``resume`` continues).

        ``deceleration`` [mm/s²] and ``jerk`` [mm/s³] are lowered to the caps of the pieces
        within the braking distance."""
        if deceleration <= 0.0 or jerk <= 0.0:
            raise ValueError("stop deceleration and jerk must be > 0")
        self._begin_stop(now, _StopRequest(deceleration, jerk, keep))

    def _begin_stop(self, now: float, request: _StopRequest) -> None:
        now = self._move_to(now)
        self._profile = None
        old = self._stop
        if old is not None:  # a stop that drops the path is not undone by a later interrupt
            request = _StopRequest(request.deceleration, request.jerk, request.keep and old.keep,
                                   request.by_override and old.by_override)
        self._stop = request
        if self._mode == _REST:
            if not request.keep:
                self._truncate(self._state[0])
            return
        braking, self._mode = self._mode == _BRAKE, _PENDING
        if self._try_brake(now, self._state[:3]):
            return
        if braking:  # the brake under way rests earlier than the new one could start
            self._mode = _BRAKE
            if not request.keep:
                self._truncate(self._leg.final[0])
        elif self.standing:
            self._finish_stop(now, self._state[0], self._leg.zone)

    def resume(self, now: float) -> None:
        """Continue after ``stop(keep=True)`` (MC_GroupContinue), from where the motion is;
        under a velocity override of 0 it continues once the override rises."""
        stop = self._stop
        if stop is None or not stop.keep or self._deferred is not None:
            return
        if self._on_profile():  # the stop has not braked yet: the profile simply runs on
            now = self._move_to(now)
            self._stop, self._mode = None, _RUN
            return
        if self._factors[0] > 0.0:
            self._restart(now)
        else:
            self._stop = _StopRequest(stop.deceleration, stop.jerk, True, by_override=True)

    def _restart(self, now: float) -> None:
        now = self._move_to(now)
        self._stop, self._mode, self._window = None, _RUN, None
        self._plan_from(now, self._state[:3])

    def _move_to(self, now: float) -> float:
        """Bring the state to ``now`` (events included) and return the time it holds."""
        if now > self._time:
            self._advance(now)
        return self._time

    def _finish_stop(self, time: float, s: float, zone: int) -> None:
        self._mode = _REST
        if not self._stop.keep:
            self._truncate(s)
        self._install(_Leg.hold(time, s, zone))

    def _try_brake(self, time: float, state: tuple[float, float, float]) -> bool:
        """Start the stop's brake if it keeps every cap it passes; True when it did."""
        request = self._stop
        profile, ok = self._stop_brake(state, request.deceleration, request.jerk)
        if not ok and self._on_profile():
            dense = self._dense_brake(state, request.deceleration, request.jerk)
            profile, ok = (dense, True) if dense is not None else (profile, False)
        if not ok:
            return False
        rest = float(profile.p[-1])
        zone = min(int(np.searchsorted(self._zones.row(_ZEND), rest, side="left")),
                   self._zones.n - 1)
        self._mode = _BRAKE
        if not request.keep:
            self._truncate(rest)
            zone = min(zone, self._zones.n - 1)
        self._install(_Leg(time, profile.data, profile.duration, (rest, 0.0, 0.0), zone))
        return True

    def _brake_rates(self, state: tuple[float, float, float], deceleration: float,
                     jerk: float) -> tuple[float, float]:
        """The requested rates, lowered to the smallest caps of the pieces within the
        braking distance."""
        _, fa, fj = self._factors
        pieces = self._pieces
        ends = pieces.row(_END)
        k0 = min(int(np.searchsorted(ends, state[0], side="right")), pieces.n - 1)
        dec_row, jerk_row = pieces.row(_D), pieces.row(_J)
        deceleration = min(deceleration, fa * float(dec_row[k0]))
        jerk = min(jerk, fj * float(jerk_row[k0]))
        for _ in range(64):
            rest = plan_stop(KinematicState(*state), deceleration, jerk).p[-1]
            k1 = max(min(int(np.searchsorted(ends, rest, side="left")), pieces.n - 1), k0)
            self._work[1] += k1 - k0 + 1
            lower = (min(deceleration, fa * float(dec_row[k0:k1 + 1].min())),
                     min(jerk, fj * float(jerk_row[k0:k1 + 1].min())))
            if lower == (deceleration, jerk):
                break
            deceleration, jerk = lower
        return deceleration, jerk

    def _dense_brake(self, state: tuple[float, float, float], deceleration: float,
                     jerk: float) -> Profile | None:
        """A stop's brake from a dense profile under way (D-362), or None where none keeps
        every cap. The profile holds the acceleration on the contours, whose jerk caps are
        small, and changes it on the lines, so one set of rates cannot brake it: the
        acceleration falls at once with each piece's own jerk cap (``release``), and the
        last stretch is ruckig's stop with the smallest deceleration and jerk caps of the
        pieces it covers, which ends at rest with a = 0. The requested rates first, the
        pieces' own caps where those pass a slower piece too fast."""
        s, v, a = state
        pieces = self._pieces
        fv = self._velocity_factor
        _, fa, fj = self._factors
        ends = pieces.row(_END)
        vel, acc = pieces.row(_V) * fv, pieces.row(_A) * fa
        dec, jerk_caps = pieces.row(_D) * fa, pieces.row(_J) * fj
        k0 = min(int(np.searchsorted(ends, s, side="right")), pieces.n - 1)
        requests = [(deceleration, jerk)]
        if math.isfinite(deceleration) or math.isfinite(jerk):
            requests.append((math.inf, math.inf))
        for rate, jerk_limit in requests:
            capped = np.minimum(jerk_caps, jerk_limit)
            k1 = k0
            for _ in range(_BRAKE_PASSES):
                low = min(rate, float(dec[k0:k1 + 1].min()))
                land = float(capped[k0:k1 + 1].min())
                head, moving = release(s, v, a, ends, capped, low, land)
                self._work[1] += k1 - k0 + 1
                if not moving:
                    break
                _, s1, v1, a1, _ = head[:, -1]
                tail = plan_stop(KinematicState(s1, v1, a1), low, land)
                rest = float(tail.p[-1])
                if rest > self._length:
                    break
                k_rest = min(int(np.searchsorted(ends, rest, side="left")), pieces.n - 1)
                if k_rest > k1:  # the brake reaches pieces with lower caps: take them in
                    k1 = k_rest
                    continue
                data = tail.data.copy()
                data[0] += head[0, -1]
                data = np.hstack((head[:, :-1], data))
                if check(split(data, ends), ends, vel, acc, dec, jerk_caps) < 0:
                    data[1, -1] = rest
                    return Profile.from_data(data)
                break
        return None

    def _stop_brake(self, state: tuple[float, float, float], deceleration: float,
                    jerk: float) -> tuple[Profile, bool]:
        """The stop's brake and whether it keeps the velocity and exit caps on its way."""
        s, v, a = state
        deceleration, jerk = self._brake_rates(state, deceleration, jerk)
        profile = plan_stop(KinematicState(s, v, a), deceleration, jerk)
        rest = float(profile.p[-1])
        if rest > self._length or (profile.velocity_extrema()[0]
                                   < -RELATIVE_TOLERANCE * max(v, SPEED_FLOOR)):
            return profile, False  # past the end, or a jerk too low to brake without reversing
        fv = self._velocity_factor
        pieces = self._pieces
        ends = pieces.row(_END)
        k0 = min(int(np.searchsorted(ends, s, side="right")), pieces.n - 1)
        k1 = min(int(np.searchsorted(ends, rest, side="left")), pieces.n - 1)
        peak = v + a * a / (2.0 * jerk) if a > 0.0 else v
        if peak > fv * pieces.data[_V, k0] * (1.0 + RELATIVE_TOLERANCE):
            return profile, False
        if k1 == k0:
            return profile, True
        inner = slice(k0, k1)  # junctions at the ends of pieces k0 .. k1 - 1
        caps = np.minimum(pieces.data[_EXIT, inner], pieces.data[_V, k0 + 1:k1 + 1]) * fv
        caps[pieces.data[_SPACE, inner] != pieces.data[_SPACE, k0 + 1:k1 + 1]] = 0.0
        self._work[1] += k1 - k0
        for k in np.flatnonzero(caps * (1.0 + RELATIVE_TOLERANCE) < peak):  # the others hold anyway
            junction = float(ends[k0 + k])
            if _speed_at(profile, junction) > caps[k] * (1.0 + RELATIVE_TOLERANCE) + ABSOLUTE_SLACK:
                return profile, False
        # |a| exceeds the brake's own rates only while it releases the start acceleration, so
        # a piece whose caps lie below |a0| is checked where the brake enters it
        fa = self._factors[1]
        after = slice(k0 + 1, k1 + 1)
        bound = (pieces.data[_A, after] if a > 0.0 else pieces.data[_D, after]) * fa
        for k in np.flatnonzero(bound * (1.0 + RELATIVE_TOLERANCE) < abs(a)):
            entry = profile.at(_time_at(profile, float(ends[k0 + k])))[2]
            if abs(entry) > bound[k] * (1.0 + RELATIVE_TOLERANCE) and entry * a > 0.0:
                return profile, False
        return profile, True

    def rest_point(self) -> float:
        """Where s comes to rest if ``stop`` is called now with the pieces' own deceleration
        and jerk: exact when the brake keeps the caps at once, else an upper bound (the next
        stop of the plan)."""
        if self._mode in (_BRAKE, _REST):
            return self._leg.final[0] if self._mode == _BRAKE else self._state[0]
        s, v, a, _ = self._state
        if not self._pieces.n:
            return s
        profile, ok = self._stop_brake((s, v, a), math.inf, math.inf)
        if ok:
            return float(profile.p[-1])
        return self._next_stop(self._leg.zone if self._leg is not None else 0)

    def _truncate(self, rest: float) -> None:
        """Drop the path beyond ``rest``: the piece holding it ends there (MC_GroupStop)."""
        pieces, zones = self._pieces, self._zones
        if not pieces.n:
            return
        k = int(np.searchsorted(pieces.row(_END), rest, side="left"))
        if k >= pieces.n:
            return
        start = pieces.data[_END, k - 1] if k else 0.0
        if rest <= start and k:
            pieces.n = k
        else:
            pieces.data[_END, k], pieces.data[_LEN, k] = rest, rest - start
            pieces.n = k + 1
        pieces.data[_EXIT, pieces.n - 1] = 0.0
        z = int(np.searchsorted(zones.row(_ZEND), rest, side="left"))
        zones.n = min(z + 1, zones.n)
        zones.data[_ZEND, zones.n - 1] = rest
        zones.data[_ZEXIT, zones.n - 1] = 0.0
        self._length = float(rest) if rest > start or not k else float(start)
        self._window = None

    def _on_profile(self) -> bool:
        """A dense profile is under way (not yet ended, the stop's brake not yet taken)."""
        leg_ = self._leg
        return leg_ is not None and leg_.profile and self._mode in (_RUN, _PENDING) \
            and self._time < leg_.t0 + leg_.end

    def trim_last(self, length: float, exit_velocity: float) -> bool:
        """Shorten the last piece to ``length`` and give it ``exit_velocity``: a blend
        contour replaces its end (Part 4 §7.3.3). False, and nothing changes, when the
        motion could no longer stop before the new end (then the corner stays a stop)."""
        pieces = self._pieces
        if not pieces.n or self._mode != _RUN or not length > 0.0 or self._on_profile():
            return False
        last = pieces.n - 1
        start = pieces.data[_END, last] - pieces.data[_LEN, last]
        end = start + length
        if end > self._length or self._state[0] >= end or self.rest_point() > end:
            return False
        zones, z = self._zones, self._zones.n - 1
        kept = (pieces.n, pieces.data[:, last].copy(), zones.n, zones.data[:, z].copy(),
                self._length)
        self._truncate(end)
        pieces.data[_EXIT, pieces.n - 1] = exit_velocity
        zones.data[_ZEXIT, zones.n - 1] = exit_velocity
        if not self._replans_as_looked_ahead():  # keep the old end: the corner stays a stop
            pieces.n, pieces.data[:, last], zones.n, zones.data[:, z], self._length = kept
            self._window = None
            return False
        self._dirty = True
        return True

    def _replans_as_looked_ahead(self) -> bool:
        """Whether the motion, re-planned on the shortened path, still ends its leg where the
        look-ahead assumes (``_replanned``): a shorter path under a motion still speeding up
        may need more than it can, although it could brake to rest in time (``rest_point``)."""
        s = self._state[0]
        zone = min(int(np.searchsorted(self._zones.row(_ZEND), s, side="right")),
                   self._zones.n - 1)
        self._window = None
        _, lands = self._replanned(self._time, self._state[:3], zone)
        self._window = None
        return lands

    # -- override ------------------------------------------------------------------------------

    def set_factors(self, now: float, velocity: float = 1.0, acceleration: float = 1.0,
                    jerk: float = 1.0) -> None:
        """MC_GroupSetOverride (§5.28): scale the caps from now on. Velocity 0 pauses the
        motion like ``stop(keep=True)`` with the pieces' own rates; > 0 again continues."""
        if velocity < 0.0 or acceleration <= 0.0 or jerk <= 0.0:
            raise ValueError("override factors: velocity >= 0, acceleration and jerk > 0")
        factors = (float(velocity), float(acceleration), float(jerk))
        if factors == self._factors:
            return
        now = self._move_to(now)
        self._profile = None
        if self._on_profile() and velocity > 0.0:
            # the zone legs cannot take over a profile under way: it brakes to rest with the
            # factors it was planned with (a pause), then runs on under the new ones (D-335)
            if self._deferred is None:
                self._begin_stop(now, _StopRequest(math.inf, math.inf, True, by_override=True))
            self._deferred = factors
            return
        self._deferred = None
        old = self._factors
        self._planned_rates = (max(self._planned_rates[0], old[1]),
                               max(self._planned_rates[1], old[2]))
        self._factors, self._window = factors, None
        if velocity > 0.0:
            self._velocity_factor = factors[0]
        if velocity == 0.0:
            if self._stop is None:
                self._begin_stop(now, _StopRequest(math.inf, math.inf, True, by_override=True))
            return
        if self._stop is not None and self._stop.by_override:
            self._restart(now)
        elif self._mode == _RUN:
            self._plan_from(now, self._state[:3])

    # -- state ---------------------------------------------------------------------------------

    @property
    def done(self) -> bool:
        """At rest at the end of all pieces."""
        s, v, a, _ = self._state
        return v == 0.0 and a == 0.0 and s >= self._length and self._mode in (_RUN, _REST)

    @property
    def standing(self) -> bool:
        """v == 0 and a == 0 at the last sample."""
        return self._state[1] == 0.0 and self._state[2] == 0.0


def _velocity_change(start: KinematicState, target: float, deceleration: float,
                     jerk: float, acceleration: float | None = None) -> Profile:
    """The fastest change from ``start`` to speed ``target`` with these rates. The velocity
    limit is finite: plan_velocity takes a state as moving relative to it."""
    acceleration = deceleration if acceleration is None else acceleration
    return plan_velocity(start, target, Limits(max(start.velocity, target), acceleration,
                                               deceleration, jerk))


def _check(block: np.ndarray) -> None:
    lengths, vel, acc, dec, jerk, exit_, _ = block
    finite = np.isfinite(block[:5]).all()
    if not finite or min(lengths.min(), vel.min(), acc.min(), dec.min(), jerk.min()) <= 0.0:
        raise ValueError("pieces need finite length and caps > 0")
    if np.isnan(exit_).any() or exit_.min() < 0.0:
        raise ValueError("exit velocities must be >= 0 (math.inf: no cap)")


def _reachable_below(state: tuple[float, float, float], length: float, target: float,
                     acc: float, dec: float, jerk: float) -> float | None:
    """The highest speed <= ``target`` the motion can change to within ``length`` (ending
    with a = 0), None if none can: a scan from the top, then bisection at the edge found."""
    start = KinematicState(*state)

    def fits(u: float) -> bool:
        change = _velocity_change(start, u, dec, jerk, acc)
        return (change.velocity_extrema()[0] >= -RELATIVE_TOLERANCE * max(state[1], SPEED_FLOOR)
                and change.p[-1] - state[0] <= length * (1.0 + LENGTH_TOLERANCE))

    grid = [target * k / 32 for k in range(32, -1, -1)]
    for upper, lower in zip([None, *grid], grid, strict=False):
        if fits(lower):
            if upper is None:
                return lower
            for _ in range(40):
                middle = 0.5 * (lower + upper)
                lower, upper = (middle, upper) if fits(middle) else (lower, middle)
            return lower
    return None


def _reachable_above(state: tuple[float, float, float], length: float, target: float,
                     acc: float, dec: float, jerk: float) -> float | None:
    """The lowest speed >= ``target`` the motion can change to within ``length`` (ending
    with a = 0), None if none can: a scan from ``target`` up to the speed it would keep if
    the acceleration were taken away, then bisection at the edge found."""
    s, v, a = state
    start = KinematicState(s, v, a)
    top = max(v + a * abs(a) / (2.0 * jerk), target)

    def fits(u: float) -> bool:
        change = _velocity_change(start, u, dec, jerk, acc)
        return (change.velocity_extrema()[0] >= -RELATIVE_TOLERANCE * max(v, SPEED_FLOOR)
                and change.p[-1] - s <= length * (1.0 + LENGTH_TOLERANCE))

    grid = [target + (top - target) * k / 32 for k in range(33)]
    for lower, upper in zip([None, *grid], grid, strict=False):
        if fits(upper):
            if lower is None:
                return upper
            for _ in range(40):
                middle = 0.5 * (lower + upper)
                lower, upper = (lower, middle) if fits(middle) else (middle, upper)
            return upper
    return None


def _reach(v: float, a: float, length: float, acc: float, jerk: float) -> float:
    """A speed surely reachable with a = 0 within ``length`` from (v, a): take the
    acceleration away first, then ramp up (a lower bound of the best)."""
    t = abs(a) / jerk
    j = -math.copysign(jerk, a)
    released = v + t * (a + 0.5 * t * j)
    distance = t * (v + t * (0.5 * a + t * j / 6.0))
    if released <= 0.0 or distance >= length:
        return max(released, 0.0)
    return other_end(released, length - distance, acc, jerk)


def _keeps(profile: Profile, state: tuple[float, float, float], limits: Limits) -> bool:
    """ruckig's leg never moves backwards and keeps the caps (those the start keeps)."""
    _, v, a = state
    lo, hi = profile.velocity_extrema()
    top = max(limits.velocity, v + max(a, 0.0) ** 2 / (2.0 * limits.jerk))
    accelerations = profile.a
    return bool(
        lo >= -RELATIVE_TOLERANCE * limits.velocity and hi <= top * (1.0 + RELATIVE_TOLERANCE)
        and accelerations.max() <= max(limits.acceleration, a) * (1.0 + RELATIVE_TOLERANCE)
        and accelerations.min() >= min(-limits.deceleration, a) * (1.0 + RELATIVE_TOLERANCE)
        and np.abs(profile.j).max() <= limits.jerk * (1.0 + RELATIVE_TOLERANCE)
    )


def _scale_to_stop(state: tuple[float, float, float], dec: float, jerk: float,
                   stop_at: float) -> float:
    """The least factor on the rates with which a brake rests by ``stop_at`` without
    reversing: 1 normally; more only when an override drop left no other way."""
    def rest(scale: float) -> float:
        profile = plan_stop(KinematicState(*state), dec * scale, jerk * scale)
        if profile.velocity_extrema()[0] < -RELATIVE_TOLERANCE * max(state[1], SPEED_FLOOR):
            return math.inf
        return float(profile.p[-1])

    if rest(1.0) <= stop_at:
        return 1.0
    lo, hi = 1.0, 2.0
    while rest(hi) > stop_at and hi < 1e12:
        lo, hi = hi, 2.0 * hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if rest(mid) <= stop_at else (mid, hi)
    return hi


def _time_at(profile: Profile, s: float) -> float:
    """When the (forward) profile reaches position ``s``; its end if it never does."""
    p, t = profile.p, profile.t
    k = int(np.searchsorted(p, s, side="right")) - 1
    if k >= len(t) - 1:
        v = float(profile.v[-1])
        return float(t[-1]) + (s - float(p[-1])) / v if v > 0.0 else float(t[-1])
    k = max(k, 0)
    p0, v0, a0, j = (float(x) for x in profile.data[1:, k])
    lo, hi = 0.0, float(t[k + 1] - t[k])
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        position = p0 + mid * (v0 + mid * (0.5 * a0 + mid * j / 6.0))
        lo, hi = (mid, hi) if position < s else (lo, mid)
    return float(t[k]) + hi


def _speed_at(profile: Profile, s: float) -> float:
    return profile.at(_time_at(profile, s))[1]


def _cut(time: float, profile: Profile, end: float, zone: int) -> _Leg:
    """A leg of ``profile`` until it reaches ``end`` (or comes to rest before it)."""
    if float(profile.p[-1]) < end and profile.v[-1] == 0.0:
        rest = float(profile.p[-1])
        return _Leg(time, profile.data, profile.duration, (rest, 0.0, 0.0), zone)
    cut = _time_at(profile, end)
    _, v, a, _ = profile.at(cut)
    return _Leg(time, profile.data, cut, (end, max(v, 0.0), a), zone)


__all__ = ["Piece", "TimeLaw", "Work"]
