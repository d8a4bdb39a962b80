"""Movers on tracks: the 1-D motion along a track network and its collision avoidance.

A mover coupled to a track (a *rider*) moves along an arc-length coordinate. Its plan is a
1-D profile on an *odometer* q that runs on along its route: q = base + s, where s is the
arc length on the track it is on and ``base`` is where that track starts on the route. The
odometer stays continuous across track transitions, so a route through a network is one
time-optimal, jerk-limited profile (§6.2.2, §6.2.5).

Every cycle (phase 2, after the planar system evaluated its setpoint table) each rider
proposes its next state: its profile's, a tracking step when it is held, or standing still.
The gap filter of the CA group (``transport.gap_control.filter_steps``, through its public
interface) then makes every rider brake whose proposal would let it come closer than its
gap to the rider ahead of it on its path (§6.1.9, §6.2.2). Pairs are measured along the
path, centre to centre: the rider ahead may be on a later track of the route, and its
position is shifted into the follower's odometer by the difference of the two bases.

Switches (§6.2.2, Collision Ranges): near a vertex where more than two track ends meet,
movers on different tracks may meet although neither is on the other's path. Each rider has
a *zone* at each switch of its track: the stretch within max(collision range, gap) of the
switch. A rider whose brake envelope (where it could still stop) reaches into its zone
*holds* the switch. A rider that wants to enter its zone while another rider holds the same
switch from a track that is not on its path ahead is stopped at its zone boundary: the
last safe stop point (§6.2.2, the two examples where mover 2 waits at the start of the
collision range or one gap before the end of its track). docs/planar-tracks.md has the
argument and the choices.

Then the odometers are mapped to x, y and (when the orientation follows the track) c, with
their velocities and accelerations, and written into the planar system's setpoint rows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.trajectory.plan import Limits, plan_position, plan_stop
from openmotion.trajectory.segments import KinematicState, Profile
from openmotion.transport.braking import brake_envelope, brake_state
from openmotion.transport.gap_control import TOLERANCE, Pairs, filter_steps
from openmotion.transport.kernels import candidates

if TYPE_CHECKING:
    from openmotion.planar.feedback import PlanarCommand

IDLE, FOLLOW, HELD, GEAR = 0, 1, 2, 3
_EXTEND = 5.0  #: [mm] a queue end that moved on this far gets a new profile
_HORIZON_TRACKS = 8  #: a path ahead is searched this many tracks beyond the route at most


class Rail(Protocol):
    """What the traffic needs of a track: its length and its curve."""

    index: int
    length: float

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                               np.ndarray]:
        """x, y, heading [rad] and curvature [1/mm] at the arc lengths ``s``."""
        ...


class Network(Protocol):
    """The connections of the tracks."""

    def successors(self, track: Rail) -> list[Rail]:
        """Tracks that start where ``track`` ends and may be entered now."""
        ...

    def switches(self, track: Rail) -> tuple[Any, Any]:
        """The switch at the start and at the end of ``track`` (None where there is none)."""
        ...

    def collision_ranges(self, track: Rail) -> tuple[float, float]:
        """Collision range at the start and at the end of ``track`` [mm]."""
        ...


class Owner(Protocol):
    """The mover a rider belongs to: told when its command ends."""

    _awake: bool  #: publish its status at the end of this cycle

    def _on_track_finished(self, command: PlanarCommand | None) -> None: ...


@dataclass
class Leg:
    """One track of a route and where it starts on the odometer."""

    track: Rail
    base: float


@dataclass
class Rider:
    """A mover coupled to a track."""

    owner: Owner
    track: Rail
    s: float  #: arc length on ``track`` [mm] (the position before the first cycle)
    row: int  #: the planar system's table row of the odometer profile
    rows: tuple[int, int, int]  #: rows of x, y and c
    gap: float
    brake: tuple[float, float]  #: deceleration and jerk gap control brakes with
    oriented: bool  #: c follows the track's heading
    c: float  #: c [deg] (set when the orientation follows the track)
    route: list[Leg] = field(default_factory=list)  #: the legs ahead, the current first
    command: PlanarCommand | None = None
    limits: Limits | None = None
    target: float = 0.0  #: odometer target of the command
    halting: bool = False
    gear: Any = None  #: a gearing.Coupling while the rider is geared to a master
    slot: int = -1


class Traffic:
    """Every rider of one planar system, in arrays the cycle works on."""

    def __init__(self, network: Network, cycle_time: float) -> None:
        self.network = network
        self.dt = cycle_time
        self.riders: list[Rider] = []
        self._arrays(0)
        self._pairs: Pairs | None = None
        self._env: tuple[np.ndarray, np.ndarray] | None = None

    def _arrays(self, n: int) -> None:
        self.p, self.v, self.a = np.zeros(n), np.zeros(n), np.zeros(n)
        self.mode = np.zeros(n, dtype=np.int64)
        self.goal = np.zeros(n)  #: where the running profile ends (the target, or a queue)
        self.lim = np.ones((4, n))
        self.bdec, self.bjerk, self.gap = np.ones(n), np.ones(n), np.zeros(n)
        self.base = np.zeros(n)
        self.shift = np.zeros(n)  #: sum of odometer shifts: p - shift is the path coordinate

    # -- riders ----------------------------------------------------------------------------------

    def couple(self, rider: Rider) -> None:
        """``rider`` stands on its track at ``rider.s`` from now on."""
        old = [(r, *self._state(r)) for r in self.riders]
        self.riders.append(rider)
        rider.route = [Leg(rider.track, 0.0)]
        self._rebuild(old + [(rider, rider.s, 0.0, 0.0, IDLE, rider.s, 0.0)])

    def uncouple(self, rider: Rider) -> None:
        old = [(r, *self._state(r)) for r in self.riders if r is not rider]
        self.riders.remove(rider)
        self._rebuild(old)

    def _state(self, r: Rider) -> tuple[float, float, float, int, float, float]:
        k = r.slot
        return (float(self.p[k]), float(self.v[k]), float(self.a[k]), int(self.mode[k]),
                float(self.goal[k]), float(self.shift[k]))

    def _rebuild(self, states: list[tuple]) -> None:
        """New arrays in rider order (a coupling or uncoupling: rare)."""
        self._arrays(len(states))
        for k, (r, p, v, a, mode, goal, shift) in enumerate(states):
            r.slot = k
            self.p[k], self.v[k], self.a[k], self.mode[k], self.goal[k] = p, v, a, mode, goal
            self.shift[k] = shift
            self.base[k] = r.route[0].base if r.route else 0.0
            self._load(r)
        self._dirty()

    def _load(self, r: Rider) -> None:
        k = r.slot
        lim = r.limits
        if lim is not None:
            self.lim[:, k] = (lim.velocity, lim.acceleration, lim.deceleration, lim.jerk)
        self.bdec[k], self.bjerk[k] = r.brake
        self.gap[k] = r.gap

    def _dirty(self) -> None:
        self._pairs = None
        self._env = None

    def position(self, rider: Rider) -> tuple[Rail, float, float, float]:
        """Track, arc length, velocity and acceleration of ``rider`` now."""
        k = rider.slot
        return rider.track, float(self.p[k] - self.base[k]), float(self.v[k]), float(self.a[k])

    def moving(self, rider: Rider) -> bool:
        return bool(self.mode[rider.slot] != IDLE)

    def path_state(self, rider: Rider) -> tuple[float, float, float, float]:
        """The rider's path coordinate (its arc length summed over the tracks it travelled,
        §6.1.9), velocity, acceleration and jerk: a master mover's values."""
        k = rider.slot
        return float(self.p[k] - self.shift[k]), float(self.v[k]), float(self.a[k]), 0.0

    def path_coordinate(self, rider: Rider, track: Rail, s: float) -> float | None:
        """Path coordinate of arc length ``s`` on ``track``: the rider's track or a track of
        its route ahead; None otherwise."""
        k = rider.slot
        for leg in rider.route:
            if leg.track is track:
                return leg.base + s - float(self.shift[k])
        if rider.track is track:
            return float(self.base[k]) + s - float(self.shift[k])
        return None

    # -- commands --------------------------------------------------------------------------------

    def ride(self, rider: Rider, route: list[Leg], target: float, limits: Limits, gap: float,
             command: PlanarCommand, now: float) -> None:
        """Start ``command``: move along ``route`` (the current track first, at its base) to
        the odometer ``target``. Raises ``CommandRejected`` when no profile exists."""
        k = rider.slot
        shift = route[0].base - float(self.base[k])  # a new odometer origin
        start = KinematicState(float(self.p[k]) + shift, float(self.v[k]), float(self.a[k]))
        profile = plan_position(start, target, limits)
        self._abort(rider, f"aborted by {command.kind}")
        self._rebase(k, shift)
        rider.route, rider.limits, rider.gap, rider.target = route, limits, gap, target
        rider.command, rider.halting = command, False
        self._load(rider)
        self._follow(rider, profile, target, now)
        command.started()

    def halt(self, rider: Rider, limits: Limits, command: PlanarCommand | None,
             now: float) -> None:
        """Stop on the track with ``limits`` (§6.1.9 Halt); Done at rest."""
        k = rider.slot
        start = KinematicState(float(self.p[k]), float(self.v[k]), float(self.a[k]))
        profile = plan_stop(start, limits.deceleration, limits.jerk)
        self._abort(rider, "aborted by Halt")
        rider.limits, rider.command, rider.halting = limits, command, True
        rider.target = profile.end.position
        self._load(rider)
        self._follow(rider, profile, rider.target, now)
        if command is not None:
            command.started()

    def gear(self, rider: Rider, route: list[Leg], coupling: Any, gap: float,
             command: PlanarCommand, now: float) -> None:
        """Start a gear-in: the rider follows ``coupling`` (gearing.py) along ``route``."""
        k = rider.slot
        shift = route[0].base - float(self.base[k])
        self._abort(rider, f"aborted by {command.kind}")
        self._rebase(k, shift)
        rider.route, rider.gap, rider.limits = route, gap, coupling.sync.limits
        rider.command, rider.halting, rider.gear = command, False, coupling
        rider.target = math.nan
        self._load(rider)
        self.mode[k] = GEAR
        self._dirty()
        del now
        command.started()

    def _abort(self, rider: Rider, message: str) -> None:
        del message
        rider.gear = None
        if rider.command is not None:
            rider.command.aborted()
            rider.command = None

    def _rebase(self, k: int, shift: float) -> None:
        if shift:
            self.shift[k] += shift
            self.p[k] += shift
            self.goal[k] += shift
            self.base[k] += shift
            self._env = None
            self._pairs = None

    def _follow(self, rider: Rider, profile: Profile, goal: float, now: float) -> None:
        self.table.install(rider.row, profile, now)
        self.mode[rider.slot] = FOLLOW
        self.goal[rider.slot] = goal
        self._dirty()

    # -- the cycle -------------------------------------------------------------------------------

    table: Any = None  #: the planar system's SegmentTable (set by the system)

    def advance(self, now: float, values: list[np.ndarray]) -> None:
        """Phase 2: proposals, the gap filter, the switch zones, transitions, setpoints.
        ``values`` are the system's p, v, a, j rows, evaluated for ``now``."""
        n = len(self.riders)
        if n == 0 or not (self.mode != IDLE).any():
            return
        self._now = now
        rows = self._rows()
        nxt = [self.p.copy(), np.zeros(n), np.zeros(n), np.zeros(n)]
        known = (np.zeros(n, dtype=bool), np.empty(n), np.empty(n))
        follow = self.mode == FOLLOW
        for field_, column in zip(nxt, values, strict=True):
            field_[follow] = column[rows[follow]]
        idle = self.mode == IDLE
        known[0][idle], known[1][idle], known[2][idle] = True, self.p[idle], self.p[idle]
        pairs = self._pair_list()
        queued = np.flatnonzero(follow & (self.goal != self._targets()))
        if queued.size:
            self._extend(queued, nxt, pairs)
        held = np.flatnonzero(self.mode == HELD)
        if held.size:
            self._track(held, nxt, known, pairs)
        geared = np.flatnonzero(self.mode == GEAR)
        if geared.size:
            self._gear_steps(geared, now, nxt)
        cur = (self.p, self.v, self.a)
        braking, lo, hi = filter_steps(cur, self._envelope(), nxt, self.dt, self.bdec,
                                       self.bjerk, pairs, known)
        kept = self._keep_out(nxt, lo, hi, braking)
        if kept.size:  # their followers may have to brake now too
            mask = np.ones(n, dtype=bool)
            more, lo, hi = filter_steps(cur, self._envelope(), nxt, self.dt, self.bdec,
                                        self.bjerk, pairs, (mask, lo, hi))
            braking |= more
            braking[kept] = True
        self.p, self.v, self.a = nxt[0], nxt[1], nxt[2]
        self._env = (lo, hi)
        self.mode[braking & (self.mode == FOLLOW)] = HELD
        for k in np.flatnonzero(braking & (self.mode == GEAR)).tolist():
            coupling = self.riders[k].gear
            coupling.sync.held(now, (float(self.p[k]), float(self.v[k]), float(self.a[k])),
                               self._master(coupling))
        self._transitions()
        self._write(values)
        self._events(now, values)

    def _envelope(self) -> tuple[np.ndarray, np.ndarray]:
        if self._env is None:
            self._env = brake_envelope(self.p, self.v, self.a, self.bdec, self.bjerk)
        return self._env

    def _pair_list(self) -> Pairs:
        """Each rider with the rider ahead on its path (cached until a rider changes track or
        route)."""
        if self._pairs is None:
            succ, pred, offset = [], [], []
            on_track: dict[int, list[Rider]] = {}
            for r in self.riders:
                on_track.setdefault(r.track.index, []).append(r)
            for m in self.riders:
                ahead = self._ahead(m, on_track)
                if ahead is not None:
                    k, shift = ahead
                    succ.append(m.slot)
                    pred.append(k.slot)
                    offset.append(shift)
            s = np.array(succ, dtype=np.int64)
            self._pairs = Pairs(s, np.array(pred, dtype=np.int64), np.array(offset, dtype=float),
                                self.gap[s], np.zeros(s.size, dtype=bool), True)
        return self._pairs

    def _ahead(self, m: Rider, on_track: dict[int, list[Rider]]) -> tuple[Rider, float] | None:
        """The nearest rider in front of ``m`` on its route (then on the one way on, if the
        network leaves one), and the shift of its odometer into ``m``'s."""
        s_m = float(self.p[m.slot] - self.base[m.slot])
        legs = list(m.route)
        last = legs[-1].track
        base = legs[-1].base + last.length
        for _ in range(_HORIZON_TRACKS):  # the unique way on after the route
            following = self.network.successors(last)
            if len(following) != 1:
                break
            last = following[0]
            legs.append(Leg(last, base))
            base += last.length
        for i, leg in enumerate(legs):
            best: Rider | None = None
            for r in on_track.get(leg.track.index, ()):
                if r is m:
                    continue
                s = float(self.p[r.slot] - self.base[r.slot])
                if i == 0 and s <= s_m:
                    continue
                if best is None or s < float(self.p[best.slot] - self.base[best.slot]):
                    best = r
            if best is not None:
                return best, leg.base - float(self.base[best.slot])
        return None

    def _track(self, held: np.ndarray, nxt: list[np.ndarray],
               known: tuple[np.ndarray, np.ndarray, np.ndarray], pairs: Pairs) -> None:
        """Held riders: a fresh profile once the way to the target (or to the end of the
        queue) is clear; else the most progressive constant-jerk step that keeps clear of the
        neighbours as they are now (transport.kernels.candidates), else a brake."""
        room_lo, room_hi = self._room(pairs)
        lo, hi = self._envelope()
        for k in held.tolist():
            rider = self.riders[k]
            assert rider.limits is not None
            sign = 1.0 if rider.target >= self.p[k] else -1.0
            goal = min(rider.target, room_hi[k]) if sign > 0 else max(rider.target, room_lo[k])
            at_rest = self.v[k] == 0.0 and self.a[k] == 0.0
            if at_rest and (goal - self.p[k]) * sign <= TOLERANCE:  # waiting in a queue
                nxt[0][k], nxt[1][k], nxt[2][k], nxt[3][k] = self.p[k], 0.0, 0.0, 0.0
                known[0][k], known[1][k], known[2][k] = True, self.p[k], self.p[k]
                continue
            lim = rider.limits
            u, b = sign * float(self.v[k]), sign * float(self.a[k])
            # the command's dynamics can take this state over without turning round
            gentle = (b <= lim.acceleration * (1 + 1e-12) and b >= -lim.deceleration * (1 + 1e-12)
                      and u >= 0.0 and u + b * abs(b) / (2.0 * lim.jerk) >= -1e-9 * lim.velocity
                      and abs(self.v[k]) <= lim.velocity * (1 + 1e-12))
            c_lo, c_hi = brake_envelope(self.p[k:k + 1], self.v[k:k + 1], self.a[k:k + 1],
                                        np.array([lim.deceleration]), np.array([lim.jerk]))
            if gentle and (c_hi[0] <= goal + TOLERANCE if sign > 0
                           else c_lo[0] >= goal - TOLERANCE):
                try:
                    profile = plan_position(KinematicState(float(self.p[k]), float(self.v[k]),
                                                           float(self.a[k])), goal, lim)
                except CommandRejected:
                    profile = None
                if profile is not None:
                    self.table.install(rider.row, profile, self._now - self.dt)
                    self.mode[k] = FOLLOW
                    self.goal[k] = goal
                    for field_, value in zip(nxt, profile.at(self.dt), strict=True):
                        field_[k] = value
                    continue
            out, env = np.empty((4, self.p.size)), np.empty((2, self.p.size))
            fitted = candidates(
                np.array([k]), self.dt, self.p, self.v, self.a,
                np.full(self.p.size, sign), np.full(self.p.size, rider.target),
                self.lim[0], self.lim[1], self.lim[2], self.lim[3], self.bdec, self.bjerk,
                np.minimum(room_lo, lo), np.maximum(room_hi, hi), out, env)
            if fitted[0]:
                for field_, column in zip(nxt, out, strict=True):
                    field_[k] = column[k]
                known[0][k], known[1][k], known[2][k] = True, env[0, k], env[1, k]
                continue
            # no step fits: the command's brake, or the hardest one where gap control braked
            # the rider beyond what the command's brake takes back without turning round
            hard = b < -lim.deceleration or u + b * abs(b) / (2.0 * lim.jerk) < 0.0
            dec, jerk = (self.bdec[k], self.bjerk[k]) if hard else (lim.deceleration, lim.jerk)
            step = brake_state(self.p[k:k + 1], self.v[k:k + 1], self.a[k:k + 1],
                               np.array([dec]), np.array([jerk]), self.dt)
            for field_, value in zip(nxt, step, strict=True):
                field_[k] = float(value[0])

    def _master(self, coupling: Any, nxt: list[np.ndarray] | None = None
                ) -> tuple[float, float, float, float]:
        """The master's set values of this cycle: an axis's (evaluated before the planar
        system), a master mover's proposal (``nxt``) when it is known, else its values."""
        if coupling.master is not None and nxt is not None:
            k = coupling.master.slot
            return (float(nxt[0][k] - self.shift[k]), float(nxt[1][k]), float(nxt[2][k]),
                    float(nxt[3][k]))
        from openmotion.planar.gearing import master_state

        return master_state(coupling, self)

    def _gear_steps(self, geared: np.ndarray, now: float, nxt: list[np.ndarray]) -> None:
        """Proposals of geared riders: the sync's, kept on the path the slave may use. One
        whose next step could take it past an end of that path (braking with its hardest
        dynamics) stops there instead, and its command fails (§6.2.8)."""
        for k in geared.tolist():
            rider = self.riders[k]
            coupling = rider.gear
            self._extend_follow(rider, coupling)
            state = (float(self.p[k]), float(self.v[k]), float(self.a[k]))
            master = self._master(coupling, nxt)
            try:
                proposal = coupling.sync.step(now, state, master, self.dt)
            except CommandRejected as rejected:
                proposal, coupling.failed = None, (rejected.error_id, rejected.message)
            if proposal is None:  # waiting or failed: brake with the command's dynamics
                lim = rider.limits
                proposal = tuple(float(x[0]) for x in brake_state(
                    self.p[k:k + 1], self.v[k:k + 1], self.a[k:k + 1],
                    np.array([lim.deceleration]), np.array([lim.jerk]), self.dt))
            lo, hi = brake_envelope(np.array([proposal[0]]), np.array([proposal[1]]),
                                    np.array([proposal[2]]), self.bdec[k:k + 1],
                                    self.bjerk[k:k + 1])
            behind = lo[0] < coupling.low - TOLERANCE
            if self._waits(coupling, state, proposal, behind):
                nxt[0][k], nxt[1][k], nxt[2][k], nxt[3][k] = state[0], 0.0, 0.0, 0.0
                coupling.sync.held(now, state, master)
                continue
            if hi[0] > coupling.high + TOLERANCE or behind:
                bound = coupling.high if hi[0] > coupling.high + TOLERANCE else coupling.low
                self._stop_at(rider, bound, nxt)
                continue
            for field_, value in zip(nxt, proposal, strict=True):
                field_[k] = value
            if rider.command is not None:
                cp = coupling.sync.coupled(*master)[0]
                in_sync = coupling.sync.in_sync or (
                    coupling.tolerance > 0.0 and abs(state[0] - cp) <= coupling.tolerance)
                if in_sync != rider.command.in_sync:
                    rider.command.in_sync = in_sync
                    rider.owner._awake = True  # the feedback shows it next cycle

    @staticmethod
    def _waits(coupling: Any, state: tuple[float, float, float],
               proposal: tuple[float, ...], behind: bool) -> bool:
        """A slave at rest that has not been in sync yet stays where it is when the sync
        would start it in a direction ``allowedSlaveSyncDirections`` forbids, or behind the
        start of its path (§6.2.8, §7.2.1.2.7): it synchronises again from there next cycle,
        with the master further on."""
        if coupling.sync.synced_once or state[1] != 0.0 or state[2] != 0.0:
            return False
        velocity = proposal[1]
        from openmotion.planar.enums import SyncDirections

        wrong = (velocity < 0.0 and coupling.directions is SyncDirections.POSITIVE) or \
            (velocity > 0.0 and coupling.directions is SyncDirections.NEGATIVE)
        return wrong or behind

    def _stop_at(self, rider: Rider, bound: float, nxt: list[np.ndarray]) -> None:
        """A geared rider stops exactly at ``bound``, the end of its path, with its hardest
        dynamics; its command then ends in error (§6.2.8)."""
        k = rider.slot
        hard = Limits(max(float(abs(self.v[k])), rider.limits.velocity), float(self.bdec[k]),
                      float(self.bdec[k]), float(self.bjerk[k]))
        start = KinematicState(float(self.p[k]), float(self.v[k]), float(self.a[k]))
        try:
            profile = plan_position(start, bound, hard)
        except CommandRejected:
            profile = plan_stop(start, hard.deceleration, hard.jerk)
        end = "end" if bound >= self.p[k] else "start"
        rider.gear.failed = (ErrorId.PLANAR_PATH_END,
                             f"the master would take the mover past the {end} of its path "
                             "(its track, or the last track of its trail): it stopped there "
                             "(§6.2.8)")
        rider.gear.stopping = True
        rider.halting, rider.target = True, profile.end.position
        self.table.install(rider.row, profile, self._now - self.dt)
        self.mode[k] = FOLLOW
        self.goal[k] = rider.target
        for field_, value in zip(nxt, profile.at(self.dt), strict=True):
            field_[k] = value
        if rider.command is not None:
            rider.command.in_sync = False

    def _extend_follow(self, rider: Rider, coupling: Any) -> None:
        """followMover: the master's way beyond the slave's route is the slave's too."""
        if not coupling.follow or coupling.master is None:
            return
        last = rider.route[-1].track
        way = [leg.track for leg in coupling.master.route]
        if last not in way or way[-1] is last:
            return
        base = rider.route[-1].base + last.length
        for track in way[way.index(last) + 1:]:
            rider.route.append(Leg(track, base))
            base += track.length
        coupling.high = base
        self._pairs = None

    def _targets(self) -> np.ndarray:
        return np.fromiter((r.target for r in self.riders), dtype=float, count=len(self.riders))

    def _extend(self, queued: np.ndarray, nxt: list[np.ndarray], pairs: Pairs) -> None:
        """Riders following a profile to the end of a queue get a new one, further on, once
        the room ahead has grown by more than ``_EXTEND`` (no stop and go behind a mover that
        drives away)."""
        room_lo, room_hi = self._room(pairs)
        for k in queued.tolist():
            rider = self.riders[k]
            assert rider.limits is not None
            forward = rider.target >= self.goal[k]
            goal = min(rider.target, room_hi[k]) if forward else max(rider.target, room_lo[k])
            if abs(goal - self.goal[k]) <= _EXTEND and goal != rider.target:
                continue
            if (goal - self.goal[k]) * (1.0 if forward else -1.0) <= 0.0:
                continue
            try:
                profile = plan_position(KinematicState(float(self.p[k]), float(self.v[k]),
                                                       float(self.a[k])), goal, rider.limits)
            except CommandRejected:
                continue
            self.table.install(rider.row, profile, self._now - self.dt)
            self.goal[k] = goal
            for field_, value in zip(nxt, profile.at(self.dt), strict=True):
                field_[k] = value

    def _room(self, pairs: Pairs) -> tuple[np.ndarray, np.ndarray]:
        """Where each rider may stop given its neighbours' brake envelopes now."""
        lo, hi = self._envelope()
        n = self.p.size
        room_hi, room_lo = np.full(n, np.inf), np.full(n, -np.inf)
        if pairs.succ.size:
            np.minimum.at(room_hi, pairs.succ, lo[pairs.pred] + pairs.offset - pairs.gap)
            np.maximum.at(room_lo, pairs.pred, hi[pairs.succ] + pairs.gap - pairs.offset)
        for k, (low, high) in self._stop_lines.items():
            room_lo[k], room_hi[k] = max(room_lo[k], low), min(room_hi[k], high)
        return room_lo, room_hi

    _now: float = 0.0

    def _keep_out(self, nxt: list[np.ndarray], lo: np.ndarray, hi: np.ndarray,
                  braking: np.ndarray) -> np.ndarray:
        """The switch rule (§6.2.2): a rider whose next step would take its brake envelope
        into a switch zone that another rider holds from a track off its path brakes
        instead (its brake stays behind the zone boundary: the envelope of a brake is
        inside the envelope it starts from). Writes the brakes into ``nxt``, ``lo`` and
        ``hi``; returns the riders it braked."""
        lines = self._stop_lines = self._zone_lines(lo, hi)
        if not lines:
            return np.empty(0, dtype=np.int64)
        out = []
        for k, (low, high) in lines.items():
            if (hi[k] > high + TOLERANCE or lo[k] < low - TOLERANCE) and not braking[k]:
                out.append(k)
        slots = np.array(out, dtype=np.int64)
        if slots.size:
            step = brake_state(self.p[slots], self.v[slots], self.a[slots], self.bdec[slots],
                               self.bjerk[slots], self.dt)
            for field_, value in zip(nxt, step, strict=True):
                field_[slots] = value
            lo[slots], hi[slots] = brake_envelope(nxt[0][slots], nxt[1][slots],
                                                  nxt[2][slots], self.bdec[slots],
                                                  self.bjerk[slots])
        return slots

    _stop_lines: dict[int, tuple[float, float]] = {}  # noqa: RUF012 - replaced per cycle

    def _zone_lines(self, lo: np.ndarray, hi: np.ndarray) -> dict[int, tuple[float, float]]:
        """Odometer bounds (low, high) of the riders kept out of a switch zone this cycle.

        A rider is in its zone at the switch at the end of its track when its envelope
        reaches within max(collision range at end, gap) of the track end, and at the switch
        at its start within max(collision range at start, gap) of the start. Holders (in a
        zone now) keep the switch; riders that enter a zone are decided in rider order: the
        first whom no holder from a track off its path blocks becomes a holder too."""
        lo_now, hi_now = self._envelope()
        zones: dict[Any, list[tuple[int, bool, float, float]]] = {}
        for r in self.riders:
            k = r.slot
            start, end = self.network.switches(r.track)
            if start is None and end is None:
                continue
            cr_start, cr_end = self.network.collision_ranges(r.track)
            base, length = float(self.base[k]), r.track.length
            if end is not None:
                line = base + length - max(cr_end, float(self.gap[k]))
                zones.setdefault(end, []).append(
                    (k, hi_now[k] > line + TOLERANCE, -math.inf, line))
            if start is not None:
                line = base + max(cr_start, float(self.gap[k]))
                zones.setdefault(start, []).append(
                    (k, lo_now[k] < line - TOLERANCE, line, math.inf))
        lines: dict[int, tuple[float, float]] = {}
        for entries in zones.values():
            if len(entries) < 2:
                continue
            holders = [k for k, inside, _, _ in entries if inside]
            for k, inside, low, high in entries:
                if inside:
                    continue
                wants = hi[k] > high + TOLERANCE or lo[k] < low - TOLERANCE
                blocked = any(self._conflict(k, h) for h in holders)
                if blocked:
                    lines[k] = (low, high)
                elif wants:
                    holders.append(k)
        return lines

    def _conflict(self, k: int, h: int) -> bool:
        """Riders ``k`` and ``h`` near one switch may meet: on different tracks, and neither
        on the path ahead of the other (those keep their gap as a pair)."""
        a, b = self.riders[k], self.riders[h]
        if a.track is b.track:
            return False
        return all(leg.track is not b.track for leg in a.route) and \
            all(leg.track is not a.track for leg in b.route)

    def _transitions(self) -> None:
        """Riders past the end of their track's leg go on to the next leg of their route."""
        for r in self.riders:
            k = r.slot
            while len(r.route) > 1 and self.p[k] - self.base[k] >= r.track.length - 1e-12 \
                    and self.p[k] > r.route[1].base - 1e-12:
                r.route.pop(0)
                r.track = r.route[0].track
                self.base[k] = r.route[0].base
                self._pairs = None

    def _write(self, values: list[np.ndarray]) -> None:
        """x, y (and c) of every rider from its track's curve."""
        by_track: dict[int, list[Rider]] = {}
        for r in self.riders:
            by_track.setdefault(r.track.index, []).append(r)
        p_all, v_all, a_all, j_all = values
        for riders in by_track.values():
            track = riders[0].track
            slots = np.fromiter((r.slot for r in riders), dtype=np.int64, count=len(riders))
            s = np.clip(self.p[slots] - self.base[slots], 0.0, track.length)
            x, y, heading, curvature = track.frame_at(s)
            v, a = self.v[slots], self.a[slots]
            cos, sin = np.cos(heading), np.sin(heading)
            normal = curvature * v * v
            for i, r in enumerate(riders):
                rx, ry, rc = r.rows
                p_all[rx], p_all[ry] = x[i], y[i]
                v_all[rx], v_all[ry] = cos[i] * v[i], sin[i] * v[i]
                a_all[rx] = cos[i] * a[i] - sin[i] * normal[i]
                a_all[ry] = sin[i] * a[i] + cos[i] * normal[i]
                j_all[rx] = j_all[ry] = 0.0
                if r.oriented:
                    turn = math.degrees(heading[i]) - r.c
                    r.c += (turn + 180.0) % 360.0 - 180.0
                    p_all[rc] = r.c
                    v_all[rc] = math.degrees(curvature[i] * v[i])
                    a_all[rc] = math.degrees(curvature[i] * a[i])
                    j_all[rc] = 0.0

    def _events(self, now: float, values: list[np.ndarray]) -> None:
        """Commands that reached their targets end (Done); riders at rest become idle."""
        ended = np.flatnonzero((self.mode == FOLLOW) & (self.table.end[self._rows()] <= now))
        for k in ended.tolist():
            rider = self.riders[k]
            if rider.halting or abs(self.goal[k] - rider.target) <= TOLERANCE:
                self.mode[k] = IDLE
                self.v[k] = self.a[k] = 0.0
                command, rider.command = rider.command, None
                rider.halting = False
                if rider.gear is not None and rider.gear.failed is not None and command:
                    command.rejected(*rider.gear.failed)
                rider.gear = None
                rider.route = rider.route[:1]
                self._hold(rider, values)
                rider.owner._on_track_finished(command)
            else:
                self.mode[k] = HELD  # queued behind a rider: wait for room
        held = np.flatnonzero(self.mode == HELD)
        for k in held.tolist():
            rider = self.riders[k]
            if rider.halting and self.v[k] == 0.0 and self.a[k] == 0.0:
                self.mode[k] = IDLE
                command, rider.command = rider.command, None
                rider.halting = False
                self._hold(rider, values)
                rider.owner._on_track_finished(command)

    def _hold(self, rider: Rider, values: list[np.ndarray]) -> None:
        """A rider at rest: its x, y and c rows hold where it stands (cycles in which no
        rider moves leave the rows to the table)."""
        for row in rider.rows:
            self.table.install(row, Profile.hold(KinematicState(float(values[0][row]))),
                               self._now)
            values[1][row] = values[2][row] = values[3][row] = 0.0

    def _rows(self) -> np.ndarray:
        return np.fromiter((r.row for r in self.riders), dtype=np.int64, count=len(self.riders))


def network_of(system: Any) -> Any:
    """The TrackNetwork of a planar system (made with its first track)."""
    if system.network is None:
        from openmotion.planar.network import TrackNetwork

        system.network = TrackNetwork()
    return system.network


def traffic_of(system: Any) -> Traffic:
    """The movers on the tracks of a planar system."""
    if system.traffic is None:
        system.traffic = Traffic(network_of(system), system.cycle_time)
        system.traffic.table = system.table
    return system.traffic
