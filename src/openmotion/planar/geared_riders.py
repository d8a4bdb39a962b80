"""Geared riders: movers on tracks that follow a master (an axis or another mover) through
their GearSync, kept on the path they may use (§6.2.8, gearing.py starts them; traffic.py).

Each cycle a geared rider proposes its sync's step. Before it is first in sync it comes to
rest rather than turn against its allowed sync direction or run off its path (D-197); a
master faster than the command's velocity is followed at that velocity; a step that could
take it past an end of its path stops it there and its command fails. followMover makes the
master's way the slave's as it goes on (D-149); a path ending in a closed loop goes on lap
by lap (D-148); a master that leaves its track ends the coupling (D-145).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.riders import GEAR, Leg, Rail, Rider, ahead_legs, brakes_harder
from openmotion.planar.tolerances import WAY_PRECISION
from openmotion.rail.braking import brake_envelope, brake_state
from openmotion.rail.gap_control import TOLERANCE, Pairs
from openmotion.rail.gear import SYNCING, GearSync
from openmotion.trajectory.plan import (
    VELOCITY_TOLERANCE,
    Limits,
    plan_position,
    plan_stop,
    plan_velocity,
)
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.planar.feedback import PlanarCommand
    from openmotion.planar.traffic import Traffic

_RESYNC = 0.05  #: a master velocity change of this share of the slave's limit re-plans its sync
_CREEP = 0.01  #: [mm] a geared rider at rest with less room than this waits (``_no_room``)
_REACH_SAMPLES = 4096  #: states of a sync plan checked at most (``_sync_reach``)


class GearedRiders:
    """The geared riders of the traffic: their start, their steps, their path and its end."""

    def __init__(self, traffic: Traffic) -> None:
        self.traffic = traffic
        self.tables = traffic.cycle_tables

    def start(self, rider: Rider, route: list[Leg], coupling: Any, gap: float,
              command: PlanarCommand) -> None:
        """Start a gear-in: the rider follows ``coupling`` (gearing.py) along ``route``."""
        t = self.traffic
        k = rider.slot
        shift = route[0].base - float(t.base[k])
        t.abort(rider)
        t.rebase(k, shift)
        rider.route, rider.gap, rider.limits = route, gap, coupling.sync.limits
        t.routed(rider)
        rider.command, rider.gear = command, coupling
        t.set_halting(rider, False)
        rider.target = math.nan
        t.load(rider)
        t.mode[k] = GEAR
        self.tables.forget()
        command.start()

    def master_gone(self, rider: Rider, now: float) -> None:
        """``rider``'s master mover leaves the traffic (LeaveTrack): the coupling ends. The
        rider brakes to a stop with its command's dynamics (a Halt's), no longer geared,
        and its command then ends in error (D-145); nothing keeps the master's rider."""
        t = self.traffic
        coupling = rider.gear
        name = getattr(coupling.master.owner, "name", "the master")
        coupling.master, coupling.follow = None, False
        coupling.stopping = True
        coupling.failed = (ErrorId.PLANAR_WRONG_MODE,
                           f"the master mover {name} left its track: the coupling ended "
                           "and the mover stopped (§6.2.9)")
        assert rider.limits is not None
        profile = t.routes.stop_profile(rider, rider.limits)
        t.set_halting(rider, True)
        rider.target = profile.end.position
        t.target[rider.slot] = rider.target
        t.follow(rider, profile, rider.target, now)
        if rider.command is not None:
            rider.command.in_sync = False
            rider.owner.awake = True

    def master(self, coupling: Any, proposal: list[np.ndarray] | None = None
               ) -> tuple[float, float, float, float]:
        """The master's set values of this cycle: an axis's (evaluated before the planar
        system), a master mover's ``proposal`` when it is known, else its values."""
        if coupling.master is not None and proposal is not None:
            k = coupling.master.slot
            return (float(proposal[0][k] - self.traffic.shift[k]), float(proposal[1][k]),
                    float(proposal[2][k]), float(proposal[3][k]))
        from openmotion.planar.gearing import master_state

        return master_state(coupling, self.traffic)

    def steps(self, geared: np.ndarray, now: float, proposal: list[np.ndarray],
              pairs: Pairs) -> None:
        """Proposals of geared riders: the sync's, kept on the path the slave may use. One
        whose next step could take it past an end of that path (braking with its hardest
        dynamics) stops there instead, and its command fails (§6.2.8). A slave whose master
        is geared too comes after it, so it reads its master's step of this cycle."""
        t = self.traffic
        cycle_time = t.cycle_time
        for k in self._masters_first(geared):
            rider = t.riders[k]
            coupling = rider.gear
            self._extend_follow(rider, coupling)
            state = (float(t.p[k]), float(t.v[k]), float(t.a[k]))
            master = self.master(coupling, proposal)
            sync = coupling.sync
            if sync.phase == SYNCING and coupling.planned_v is not None and \
                    abs(master[1] - coupling.planned_v) > _RESYNC * sync.limits.velocity:
                coupling.resync = True  # planned again after this cycle's step
            if coupling.planned_v is None:
                coupling.planned_v = master[1]
            if coupling.braked and self._brakes_on(k, rider.limits):
                # held by gap control or a switch zone harder than the command's dynamics
                # release without turning round: the brake goes on to rest (the sync is
                # planned again from each braked state, and from rest it starts clean)
                step = tuple(float(x[0]) for x in brake_state(
                    t.p[k:k + 1], t.v[k:k + 1], t.a[k:k + 1], t.brake_deceleration[k:k + 1],
                    t.brake_jerk[k:k + 1], cycle_time))
                coupling.sync.held(now, tuple(step[:3]), master)
                for field_, value in zip(proposal, step, strict=True):
                    field_[k] = value  # inside last cycle's envelope, which was clear
                if rider.command is not None:
                    rider.command.in_sync = False
                continue
            coupling.braked = False
            try:
                step = coupling.sync.step(now, state, master, cycle_time)
            except CommandRejected as rejected:  # no sync plan: stop, then end in error
                coupling.failed = (rejected.error_id, rejected.message)
                assert rider.limits is not None
                self._stop_following(rider, t.routes.stop_profile(rider, rider.limits),
                                     proposal)
                continue
            astray = step is not None and self._astray(rider, coupling, now, master)
            if step is not None and state[1] != 0.0 and \
                    (astray or _turns_against(coupling, step, rider.limits.jerk)):
                # before the first sync it comes to rest rather than turn (§6.1.9) or run
                # off its path (D-197), and synchronises again from each step of that (its
                # sync's own plan went on)
                step = plan_velocity(KinematicState(*state), 0.0, rider.limits).at(cycle_time)
                coupling.sync.held(now, tuple(step[:3]), master)
            limit = rider.limits.velocity
            chasing = step is not None and not coupling.sync.in_sync \
                and abs(_released(step, rider.limits.jerk)) > limit * (1.0 + VELOCITY_TOLERANCE)
            if chasing:  # a master faster than the command's velocity: follow at that (§6.2.8)
                step = plan_velocity(KinematicState(*state), math.copysign(limit, step[1]),
                                     rider.limits).at(cycle_time)
            if step is not None and state[1] == 0.0 and state[2] == 0.0 and \
                    self._no_room(k, step[1], pairs):
                # at its stop line or gap already: it waits there, synchronising again
                step = (state[0], 0.0, 0.0, 0.0)
                coupling.sync.held(now, state, master)
            if step is None:  # waiting: brake with the command's dynamics
                limits = rider.limits
                step = tuple(float(x[0]) for x in brake_state(
                    t.p[k:k + 1], t.v[k:k + 1], t.a[k:k + 1],
                    np.array([limits.deceleration]), np.array([limits.jerk]), cycle_time))
            lo, hi = brake_envelope(np.array([step[0]]), np.array([step[1]]),
                                    np.array([step[2]]), t.brake_deceleration[k:k + 1],
                                    t.brake_jerk[k:k + 1])
            self._extend_loop(rider, coupling, float(hi[0]))
            # never back over the start of the track it is on: the legs behind are gone
            low = max(coupling.low, rider.route[0].base)
            behind = lo[0] < low - TOLERANCE
            if _waits(coupling, state, step, behind or astray):
                proposal[0][k], proposal[1][k], proposal[2][k], proposal[3][k] = \
                    state[0], 0.0, 0.0, 0.0
                coupling.sync.held(now, state, master)
                _show_in_sync(rider, coupling, state, master)
                continue
            if hi[0] > coupling.high + TOLERANCE or behind:
                bound = coupling.high if hi[0] > coupling.high + TOLERANCE else low
                self._stop_at(rider, bound, proposal)
                continue
            for field_, value in zip(proposal, step, strict=True):
                field_[k] = value
            if chasing:  # the sync is planned again from where the mover now is
                try:
                    coupling.sync.held(now, tuple(step[:3]), master)
                except CommandRejected as rejected:
                    coupling.failed = (rejected.error_id, rejected.message)
                    self._stop_following(rider, t.routes.stop_profile(rider, rider.limits),
                                         proposal)
                    continue
            _show_in_sync(rider, coupling, state, master)

    def after_filter(self, now: float, braking: np.ndarray) -> None:
        """After gap control and the switch zones: a geared rider they braked, or whose
        master changed its velocity a lot since its sync was planned, plans its sync again
        from where it is now."""
        t = self.traffic
        geared = t.mode == GEAR
        for k in np.flatnonzero(geared & (braking | self._resync(geared))).tolist():
            coupling = t.riders[k].gear
            master = self.master(coupling)
            coupling.sync.held(now, (float(t.p[k]), float(t.v[k]), float(t.a[k])), master)
            coupling.planned_v, coupling.resync = master[1], False
            coupling.braked = bool(braking[k])

    def _masters_first(self, geared: np.ndarray) -> list[int]:
        """The geared riders, each after its master when that is geared too."""
        order = geared.tolist()
        if len(order) < 2:
            return order
        among = set(order)
        riders = self.traffic.riders

        def depth(k: int) -> int:
            count, rider = 0, riders[k]
            while count < len(order):
                master = rider.gear.master if rider.gear is not None else None
                if master is None or master.slot not in among:
                    break
                count, rider = count + 1, master
            return count

        return sorted(order, key=depth)

    def _no_room(self, k: int, velocity: float, pairs: Pairs) -> bool:
        """Whether a rider at rest has less than ``_CREEP`` room the way ``velocity`` goes
        (a neighbour's envelope or a stop line): a step would only be braked again, and the
        two would alternate while it creeps up to the bound."""
        room_lo, room_hi = self.traffic.pairs.room(pairs)
        p = float(self.traffic.p[k])
        return (velocity > 0.0 and float(room_hi[k]) - p < _CREEP) or \
            (velocity < 0.0 and p - float(room_lo[k]) < _CREEP)

    def _brakes_on(self, k: int, limits: Limits) -> bool:
        """Whether rider ``k`` moves and brakes harder than ``limits`` take back without
        turning it round (``brakes_harder``)."""
        t = self.traffic
        v = float(t.v[k])
        if v == 0.0:
            return False
        sign = 1.0 if v > 0.0 else -1.0
        return bool(brakes_harder(np.array(sign * v), np.array(sign * float(t.a[k])),
                                  np.array(limits.deceleration), np.array(limits.jerk)))

    def _resync(self, geared: np.ndarray) -> np.ndarray:
        """Geared riders whose master changed its velocity a lot since their sync was
        planned: planned again (the sync is planned for the master's velocity of its start;
        a master that stops or speeds up must not leave the slave creeping)."""
        out = np.zeros(geared.size, dtype=bool)
        riders = self.traffic.riders
        for k in np.flatnonzero(geared).tolist():
            out[k] = riders[k].gear.resync
        return out

    def _astray(self, rider: Rider, coupling: Any, now: float,
                master: tuple[float, float, float, float]) -> bool:
        """Whether the sync plan of a slave not yet in sync would take it off its path at
        the end its sync point comes from: below the start of its path while the coupled
        position moves forwards, or past the end while it moves backwards (with the master
        going on at its present velocity). A later plan meets the sync point further inside
        the path, so the slave waits for it (D-197): with allowedSlaveSyncDirections Both
        that is the way it goes whenever Positive or Negative alone would sync (§6.2.8,
        §7.2.1.2.7). Off the other end waiting does not help, and the plan is followed to
        the path end, where the command fails as before."""
        sync = coupling.sync
        if sync.synced_once or sync.phase != SYNCING or sync.profile is None:
            return False
        velocity = sync.coupled(*master)[1]
        if velocity == 0.0:
            return False
        t = self.traffic
        k, low = rider.slot, max(coupling.low, rider.route[0].base)
        deceleration, jerk = float(t.brake_deceleration[k]), float(t.brake_jerk[k])
        if velocity > 0.0:  # only the start counts
            return _sync_reach(sync, now, master, t.cycle_time, deceleration, jerk, low,
                               math.inf)[0] < low - TOLERANCE
        if self._loops_on(rider, coupling):  # a loop has no end forwards
            return False
        return _sync_reach(sync, now, master, t.cycle_time, deceleration, jerk, -math.inf,
                           coupling.high)[1] > coupling.high + TOLERANCE

    def _stop_at(self, rider: Rider, bound: float, proposal: list[np.ndarray]) -> None:
        """A geared rider stops exactly at ``bound``, the end of its path, with its hardest
        dynamics; its command then ends in error (§6.2.8)."""
        t = self.traffic
        k = rider.slot
        hard = Limits(max(float(abs(t.v[k])), rider.limits.velocity),
                      float(t.brake_deceleration[k]), float(t.brake_deceleration[k]),
                      float(t.brake_jerk[k]))
        start = KinematicState(float(t.p[k]), float(t.v[k]), float(t.a[k]))
        try:
            profile = plan_position(start, bound, hard)
        except CommandRejected:
            profile = plan_stop(start, hard.deceleration, hard.jerk)
        end = "end" if bound >= t.p[k] else "start"
        refused = rider.gear.blocked
        if end == "end" and refused is not None:  # the way goes on, but not granted (D-149)
            rider.gear.failed = (refused.error_id,
                                 f"followMover: {refused.message}; the mover stopped before "
                                 "that track (§4.3, §6.5)",
                                 getattr(refused, "object_info", None))
        elif end == "end":
            rider.gear.failed = (ErrorId.PLANAR_PATH_END,
                                 "the master would take the mover past the end of its path "
                                 "(its track, or the last track of its trail): it stopped "
                                 "there (§6.2.8)")
        else:
            rider.gear.failed = (ErrorId.PLANAR_PATH_END,
                                 f"the master would take the mover back past the start of "
                                 f"{getattr(rider.track, 'name', 'its track')}, which a "
                                 "geared mover does not cross backwards: it stopped there "
                                 "(§6.2.8)")
        self._stop_following(rider, profile, proposal)

    def _stop_following(self, rider: Rider, profile: Profile,
                        proposal: list[np.ndarray]) -> None:
        """A geared rider follows ``profile`` (from the last cycle) to rest, halting; its
        command ends with ``gear.failed`` once it stands."""
        rider.gear.stopping = True
        self.traffic.set_halting(rider, True)
        rider.target = profile.end.position
        self.traffic.target[rider.slot] = rider.target
        self.traffic.follow_from_last_cycle(rider, profile, rider.target, proposal)
        if rider.command is not None and rider.command.in_sync:
            rider.command.in_sync = False
            rider.owner.awake = True  # the feedback shows it next cycle

    def _extend_follow(self, rider: Rider, coupling: Any) -> None:
        """followMover: the master's way is the slave's too. A leg of the master lies on the
        slave's odometer at its path coordinate plus ``coupling.offset``, so laps of a loop
        match as well as tracks: the master's legs beyond the slave's route are appended, and
        a leg ahead of the slave that the master's way has replaced since (a new command of
        the master, or a lap the slave added alone) is replaced. A track the slave did not
        hold yet is admitted first (``_admit``); where it is refused the slave's way ends
        before it (D-149)."""
        master = coupling.master
        if not coupling.follow or master is None:
            return
        way, moved = ahead_legs(master.route), float(self.traffic.shift[master.slot])
        seen = coupling.seen  # (the list, its length, its last leg, the master's shift)
        if seen and seen[0] is way and seen[1] == len(way) and seen[2] is way[-1] and \
                seen[3] == moved and coupling.blocked is None:
            return  # nothing new since the last cycle
        coupling.seen, coupling.blocked = (way, len(way), way[-1], moved), None
        route, shift = rider.route, coupling.offset - moved
        after, changed = route[1] if len(route) > 1 else None, False
        start = max(coupling.joined, route[0].base) - WAY_PRECISION
        for leg in way:
            at = leg.base + shift
            if at < start:
                continue  # the master's way before the stretch the two share, or behind
            j = next((i for i, mine in enumerate(route)
                      if abs(mine.base - at) <= WAY_PRECISION), None)
            if j is not None and route[j].track is leg.track:
                continue
            if j == 0 or (j is None and abs(at - coupling.high) > WAY_PRECISION):
                break  # the slave is on another track there already, or the legs do not meet
            if j is not None:  # the master's way leaves the one the slave had ahead
                del route[j:]
                coupling.high, changed = at, True
            if not _admit(rider, coupling, leg.track):
                break
            route.append(Leg(leg.track, at))
            coupling.high, changed = at + leg.track.length, True
        if changed:
            self.traffic.routed(rider)
            self.tables.pairs = None
            if (route[1] if len(route) > 1 else None) is not after:
                self.tables.geometry = None  # its next track is part of the geometry

    def _extend_loop(self, rider: Rider, coupling: Any, reach: float) -> None:
        """A geared path that ends in a closed loop has no end forwards: the loop's legs go
        on lap by lap, one lap beyond ``reach`` (where the slave could stop at the latest),
        so the slave goes round as long as its master drives it (D-148). A follower does so
        only while its master's way ends in that loop as well (else the master's way is its
        way)."""
        last = rider.route[-1]
        loop = last.track
        end = last.base + loop.length
        if end >= reach + loop.length or not self._loops_on(rider, coupling):
            return
        single = len(rider.route) == 1
        while end < reach + loop.length:
            rider.route.append(Leg(loop, end))
            end += loop.length
        coupling.high = end
        self.traffic.routed(rider)
        self.tables.pairs = None
        if single:
            self.tables.geometry = None

    def _loops_on(self, rider: Rider, coupling: Any) -> bool:
        """Whether the geared path goes on round a closed loop at its end (``_extend_loop``)."""
        loop = rider.route[-1].track
        if not self.tables.track_info(loop).closed:
            return False
        return not coupling.follow or (coupling.master is not None
                                       and coupling.master.route[-1].track is loop)


def _admit(rider: Rider, coupling: Any, track: Rail) -> bool:
    """Whether the slave may go on onto ``track``: one of its route is held already;
    another is asked of its owner (in a group: the band, D-149) with the route before
    it, as a MoveOnTrack asks for its route (the movers on it do not block the band,
    the slave itself among them). A refusal is kept in ``coupling.blocked`` until the
    way is admitted."""
    if any(leg.track is track for leg in rider.route):
        return True
    try:
        rider.owner.port.admit_way([*(leg.track for leg in rider.route), track])
    except CommandRejected as refused:
        coupling.blocked = refused
        return False
    return True


def _show_in_sync(rider: Rider, coupling: Any, state: tuple[float, float, float],
                  master: tuple[float, ...]) -> None:
    """The command's inSync: the sync's, or within ``in_sync_tolerance_distance`` of
    the coupled position (§7.2.1.2.7); the feedback shows a change next cycle."""
    if rider.command is None:
        return
    cp = coupling.sync.coupled(*master)[0]
    in_sync = coupling.sync.in_sync or (
        coupling.tolerance > 0.0 and abs(state[0] - cp) <= coupling.tolerance)
    if in_sync != rider.command.in_sync:
        rider.command.in_sync = in_sync
        rider.owner.awake = True


def _waits(coupling: Any, state: tuple[float, float, float], step: tuple[float, ...],
           behind: bool) -> bool:
    """A slave at rest that has not been in sync yet stays where it is when the sync
    would start it in a direction ``allowedSlaveSyncDirections`` forbids, or behind the
    start of its path, or would take it off its path where waiting lets it sync further
    inside (``_astray``, D-197) (§6.2.8, §7.2.1.2.7): it synchronises again from there
    next cycle, with the master further on."""
    if coupling.sync.synced_once or state[1] != 0.0 or state[2] != 0.0:
        return False
    return _against(coupling, step[1]) or behind


def _against(coupling: Any, velocity: float) -> bool:
    """Whether a slave that has not been in sync yet would move at ``velocity`` against its
    ``allowedSlaveSyncDirections`` (§6.1.9: no back oscillation while it synchronises)."""
    if coupling.sync.synced_once:
        return False
    from openmotion.planar.enums import SyncDirections

    return (velocity < 0.0 and coupling.directions is SyncDirections.POSITIVE) or \
        (velocity > 0.0 and coupling.directions is SyncDirections.NEGATIVE)


def _turns_against(coupling: Any, step: tuple[float, ...], jerk: float) -> bool:
    """Whether a moving slave that has not been in sync yet would, from ``step`` (p, v, a),
    end up moving against its allowed sync direction: already, or because its acceleration
    can no longer be taken away (at ``jerk``) before the velocity crosses 0."""
    return _against(coupling, step[1]) or _against(coupling, _released(step, jerk))


def _sync_reach(sync: GearSync, now: float, master: tuple[float, float, float, float],
                cycle_time: float, deceleration: float, jerk: float, low: float, high: float
                ) -> tuple[float, float]:
    """Lowest and highest position the rest of ``sync``'s plan (from ``now``) could take the
    slave to, in sync at its end included: the slave's state each cycle of the plan (the
    sync error's profile plus the coupled position, with the master going on at its present
    velocity) and where it could come to rest from there braking with ``deceleration`` and
    ``jerk``, as the path-end check in ``GearedRiders.steps`` asks each cycle (a plan longer
    than ``_REACH_SAMPLES`` cycles is sampled that often). Far from ``low`` and ``high`` a
    cheaper bound that lies within them does (no state is sampled)."""
    assert sync.profile is not None
    profile, elapsed = sync.profile, now - sync.started
    k = max(int(np.searchsorted(profile.t, elapsed, side="right")) - 1, 0)
    rest = profile.data[:, k:].copy()
    rest[1:, 0] = profile.at(elapsed)
    rest[0] = np.maximum(rest[0] - elapsed, 0.0)
    cp, cv, _, _ = sync.coupled(*master)
    rest[1] += cp + cv * rest[0]
    rest[2] += cv
    plan = Profile.from_data(rest)
    lowest, highest = plan.position_extrema()
    speed = max(abs(x) for x in plan.velocity_extrema())
    push = float(np.abs(rest[3]).max())  # |a| peaks at segment ends (constant jerk)
    # a brake from any state of the plan: at most ``faster`` fast, ramping to -dec and back
    faster = speed + push * push / (2.0 * jerk)
    travel = faster * ((push + 2.0 * deceleration) / jerk + faster / deceleration)
    if lowest - travel >= low and highest + travel <= high:
        return lowest - travel, highest + travel
    t, p, v, a, j = profile.data
    count = int(max(t[-1] - elapsed, 0.0) / cycle_time) + 2
    step = cycle_time if count <= _REACH_SAMPLES else (t[-1] - elapsed) / (_REACH_SAMPLES - 2)
    times = elapsed + step * np.arange(min(count, _REACH_SAMPLES))
    k_ = np.maximum(np.searchsorted(t, times, side="right") - 1, 0)
    h = times - t[k_]
    ps = p[k_] + h * (v[k_] + h * (a[k_] / 2.0 + h * j[k_] / 6.0)) + cp + cv * (times - elapsed)
    vs = v[k_] + h * (a[k_] + h * j[k_] / 2.0) + cv
    accelerations = a[k_] + h * j[k_]
    n = times.size
    lo, hi = brake_envelope(ps, vs, accelerations, np.full(n, deceleration), np.full(n, jerk))
    return min(lowest, float(lo.min())), max(highest, float(hi.max()))


def _released(step: tuple[float, ...], jerk: float) -> float:
    """The velocity at which a state (p, v, a, ...) comes out when its acceleration is taken
    away as fast as ``jerk`` allows."""
    velocity, acceleration = step[1], step[2]
    return velocity + acceleration * abs(acceleration) / (2.0 * jerk)
