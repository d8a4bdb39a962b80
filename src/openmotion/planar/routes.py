"""Routes of riders on tracks: a MoveOnTrack or a Halt along the legs of a route, kept on its
way, and the passage from one leg to the next (traffic.py).

A route through the network is one time-optimal, jerk-limited profile on the rider's
odometer (§6.2.2, §6.2.5). From the end of a track a mover goes on only onto the next track
of its route, and back over a track's start only on a route back over a loop's seam
(D-147): a motion that would run past an end of its way is refused, and a stop that would
stops exactly at that end (D-155); on a closed loop the way goes on lap by lap instead.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.riders import HELD, Leg, Rider, ascending, backwards, brakes_harder
from openmotion.planar.tolerances import MIN_STOP_VELOCITY, TRACK_END_PRECISION, WAY_PRECISION
from openmotion.planar.traffic_kernels import past_ends
from openmotion.rail.braking import brake_envelope
from openmotion.trajectory.plan import Limits, plan_position, plan_stop
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.planar.feedback import PlanarCommand
    from openmotion.planar.traffic import Traffic


class Routes:
    """The traffic's MoveOnTrack and Halt, and its riders' passage along their routes."""

    def __init__(self, traffic: Traffic) -> None:
        self.traffic = traffic
        self.tables = traffic.cycle_tables

    def ride(self, rider: Rider, route: list[Leg], target: float, limits: Limits, gap: float,
             command: PlanarCommand, now: float) -> None:
        """Start ``command``: move along ``route`` (the current track first, at its base) to
        the odometer ``target``. Raises ``CommandRejected`` when no profile exists."""
        t = self.traffic
        k = rider.slot
        shift = route[0].base - float(t.base[k])  # a new odometer origin
        start = KinematicState(float(t.p[k]) + shift, float(t.v[k]), float(t.a[k]))
        sign = 1.0 if target >= start.position else -1.0
        # gap control may brake a rider moving towards the target harder than the command's
        # dynamics take back without turning round: it goes on held, braking so, and plans
        # from rest (``Traffic._track_held``)
        u = sign * start.velocity
        hard = u > 0.0 and bool(brakes_harder(np.array(u), np.array(sign * start.acceleration),
                                              np.array(limits.deceleration),
                                              np.array(limits.jerk)))
        profile = None if hard else plan_position(start, target, limits, closed_form=True)
        self._check_stops_on_way(k, start, profile, route)
        t.abort(rider)
        t.rebase(k, shift)
        rider.route, rider.limits, rider.gap, rider.target = route, limits, gap, target
        t.routed(rider)
        rider.command = command
        t.set_halting(rider, False)
        t.load(rider)
        if profile is None:
            t.mode[k] = HELD
            self.tables.forget()
        else:
            t.follow(rider, profile, target, now)
        command.start()

    def _check_stops_on_way(self, k: int, start: KinematicState, profile: Profile | None,
                            route: list[Leg]) -> None:
        """A MoveOnTrack whose motion (its profile, or gap control's brake from a hard
        brake) would run past an end of its way is refused: from the end of a track a mover
        goes on only onto the next one of its route, and back over a track's start only on
        a route back over a loop's seam (§6.2.2, D-147). The command before it goes on."""
        t = self.traffic
        if profile is not None:
            lo, hi = profile.position_extrema()
        else:
            lo_a, hi_a = brake_envelope(*(np.array([x]) for x in (
                start.position, start.velocity, start.acceleration, t.brake_deceleration[k],
                t.brake_jerk[k])))
            lo, hi = float(lo_a[0]), float(hi_a[0])
        legs = ascending(route)
        first, last = legs[0], legs[-1]
        end = last.base + last.track.length
        if hi > end + WAY_PRECISION or lo < first.base - WAY_PRECISION:
            track, where = (last.track, "end") if hi > end + WAY_PRECISION \
                else (first.track, "start")
            raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                                  f"MoveOnTrack: with these dynamics the mover cannot stop "
                                  f"before the {where} of {getattr(track, 'name', track)}, "
                                  "and it changes track only from the end of one to the "
                                  "start of the next on its way (§6.2.2)")

    def halt(self, rider: Rider, limits: Limits, command: PlanarCommand | None,
             now: float) -> None:
        """Stop on the track with ``limits`` (§6.1.9 Halt); Done at rest."""
        t = self.traffic
        profile = self.stop_profile(rider, limits)
        t.abort(rider)
        rider.limits, rider.command = limits, command
        t.set_halting(rider, True)
        rider.target = profile.end.position
        t.load(rider)
        t.follow(rider, profile, rider.target, now)
        if command is not None:
            command.start()

    def stop_profile(self, rider: Rider, limits: Limits) -> Profile:
        """A stop from the rider's state with ``limits``' deceleration and jerk (or its gap
        control brake, where that brakes harder: no turning round)."""
        t = self.traffic
        k = rider.slot
        start = KinematicState(float(t.p[k]), float(t.v[k]), float(t.a[k]))
        deceleration, jerk = limits.deceleration, limits.jerk
        u = abs(start.velocity)
        b = math.copysign(1.0, start.velocity) * start.acceleration
        if u > 0.0 and brakes_harder(np.array(u), np.array(b), np.array(deceleration),
                                     np.array(jerk)):
            deceleration, jerk = rider.brake  # gap control brakes harder: no turn round
        return self._within_way(rider, start, plan_stop(start, deceleration, jerk))

    def _within_way(self, rider: Rider, start: KinematicState, stop: Profile) -> Profile:
        """A stop that would run past an end of the rider's way (a Halt weaker than the
        motion it stops) brakes harder and stops exactly at that end, with gap control's
        brake at most: a mover leaves a track only onto the next one of its route (§6.2.2,
        D-155). On a closed loop the way goes on instead, lap by lap."""
        lo, hi = stop.position_extrema()
        route = rider.route
        legs = ascending(route)
        first, last = legs[0], legs[-1]
        end = last.base + last.track.length
        if lo >= first.base - WAY_PRECISION and hi <= end + WAY_PRECISION:
            return stop
        loop = last.track if hi > end + WAY_PRECISION else first.track
        if self.tables.track_info(loop).closed:
            length = loop.length
            if hi > end + WAY_PRECISION and not backwards(route):
                while end < hi + WAY_PRECISION:
                    route.append(Leg(loop, end))
                    end += length
            elif lo < first.base - WAY_PRECISION and (backwards(route) or len(route) == 1):
                low = first.base
                while low > lo - WAY_PRECISION:
                    low -= length
                    route.append(Leg(loop, low))
            else:
                return self._stop_at_bound(rider, start, stop, first.base, end, lo, hi)
            self.traffic.routed(rider)
            self.tables.forget_routes()
            return stop
        return self._stop_at_bound(rider, start, stop, first.base, end, lo, hi)

    def _stop_at_bound(self, rider: Rider, start: KinematicState, stop: Profile, low: float,
                       high: float, lo: float, hi: float) -> Profile:
        """``_within_way``'s stop exactly at the way's end (``high``) or start (``low``)."""
        t = self.traffic
        k = rider.slot
        bound = high if hi > high + WAY_PRECISION else low
        hard = Limits(max(abs(start.velocity), float(t.limits[0, k]), MIN_STOP_VELOCITY),
                      float(t.brake_deceleration[k]), float(t.brake_deceleration[k]),
                      float(t.brake_jerk[k]))
        try:
            clamped = plan_position(start, bound, hard)
        except CommandRejected:
            return stop
        c_lo, c_hi = clamped.position_extrema()
        return clamped if c_lo >= low - WAY_PRECISION and c_hi <= high + WAY_PRECISION \
            else stop

    def transitions(self) -> None:
        """Riders past the end of their track's leg go on to the next leg of their route;
        on a route back over a loop's seam, riders below the start of theirs (D-147)."""
        t = self.traffic
        length = self.tables.geometry_now().length
        for k in past_ends(t.p, t.base, length).tolist():
            r = t.riders[k]
            while len(r.route) > 1 and self._passed(k, r.route):
                r.route.pop(0)
                r.track = r.route[0].track
                t.routed(r)
                t.base[k] = r.route[0].base
                self.tables.forget_routes()

    def _passed(self, k: int, route: list[Leg]) -> bool:
        """Whether rider ``k`` has left the first leg of ``route`` for the second: past its
        end (to ``TRACK_END_PRECISION``, as ``past_ends``), or below its start on a route
        back."""
        t = self.traffic
        s = float(t.p[k] - t.base[k])
        if route[1].base > route[0].base:
            return s >= route[0].track.length - TRACK_END_PRECISION
        return s < 0.0
