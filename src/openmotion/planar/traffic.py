"""Movers on tracks: the 1-D motion along a track network and its collision avoidance.

A mover coupled to a track (a *rider*) moves along an arc-length coordinate. Its plan is a
1-D profile on an *odometer* q that runs on along its route: q = base + s, where s is the
arc length on the track it is on and ``base`` is where that track starts on the route. The
odometer stays continuous across track transitions, so a route through a network is one
time-optimal, jerk-limited profile (§6.2.2, §6.2.5).

Every cycle (phase 2, after the planar system evaluated its setpoint table) each rider
proposes its next state: its profile's, a tracking step when it is held, or standing still.
The gap filter of the CA group (``transport.gap_control.filter_steps``, compiled for these
pairs: ``traffic_kernels.gap_filter``) then makes every rider brake whose proposal would let
it come closer than its gap to the rider ahead of it on its path (§6.1.9, §6.2.2). Pairs
are measured along the path, centre to centre: the rider ahead may be on a later track of
the route, and its position is shifted into the follower's odometer by the difference of the
two bases.

A route back over the seam of a closed track (MoveOnTrack Negative or ShortestWay round a
loop, D-147) has legs of decreasing base: the loop at 0, -L, -2L, ... A rider on such a
route goes on to its next leg when it passes below the start of its current one. Pairs are
kept in the odometer's direction as always (each rider with the one ahead of it); the rider
going back is the leader of the rider that comes first behind it along its legs, so that
rider keeps the larger gap to it (a leader going back) before it crosses the seam. It
passes the seam's switch backwards onto the end of its own track, so riders that would pass
onto its track at its start meet it there rather than follow it.

Switches (§6.2.2, Collision Ranges): near a vertex where more than two track ends meet,
movers on different tracks may meet although neither is on the other's path. Each rider has
a *zone* at each switch of its track: the stretch within max(collision range, gap) of the
switch. A rider whose brake envelope (where it could still stop) reaches into its zone
*holds* the switch. A rider that wants to enter its zone while another rider holds the same
switch from a track that is not on its path ahead is stopped at its zone boundary: the
last safe stop point (§6.2.2, the two examples where mover 2 waits at the start of the
collision range or one gap before the end of its track). Riders that hold one switch from
conflicting tracks at once (they joined there, or a new route made them conflict) keep
their footprints apart. docs/planar-tracks.md has the argument and the choices.

Then the odometers are mapped to x, y and (when the orientation follows the track) c, with
their velocities and accelerations, and written into the planar system's setpoint rows.

Planning (profiles, commands, the rider objects) happens here, on events; what the cycle asks
of every rider runs in compiled loops (``traffic_kernels``, ``track_atlas``, D-143) that do
the arithmetic of the numpy formulation they replaced, so the motion is the same bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from itertools import accumulate
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.track_atlas import Atlas
from openmotion.planar.traffic_kernels import (
    conflicts,
    ended,
    extensions,
    gap_filter,
    group_by_track,
    held_plans,
    held_steps,
    in_order,
    neighbours,
    out_of_bounds,
    pair_gaps,
    past_ends,
    proposals,
    resting,
    rooms,
    stretch_hits,
    stretch_samples,
    turning_gaps,
    write_setpoints,
    zone_entries,
    zone_holders,
    zone_lines,
)
from openmotion.rail.braking import brake_envelope, brake_state
from openmotion.rail.gap_control import TOLERANCE, Pairs
from openmotion.rail.gear import SYNCING, GearSync
from openmotion.trajectory.plan import Limits, plan_position, plan_stop, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.planar.feedback import PlanarCommand

IDLE, FOLLOW, HELD, GEAR = 0, 1, 2, 3
_RESYNC = 0.05  #: a master velocity change of this share of the slave's limit re-plans its sync
_EXTEND = 5.0  #: [mm] a queue end that moved on this far gets a new profile
_HORIZON_TRACKS = 8  #: a path ahead is searched this many tracks beyond the route at most
#: [mm] riders this close to a zone get its stop line (held riders plan their goal with it);
#: further away they cannot reach the zone within a cycle
_ZONE_LOOKAHEAD = 1000.0
_PAST = 1e-6  #: [mm] a motion that stops this far past the end of its way is refused
_CREEP = 0.01  #: [mm] a geared rider at rest with less room than this waits (``_no_room``)
_CLEAR_STEP = 2.0  #: [mm] footprints of riders holding one switch together are sampled so
_CLEAR_SAMPLES = 32  #: ... this many steps on each side of an envelope (the horizon)
_SAME = 1e-6  #: [mm] legs of a master and its follower that start this close are one place
_REACH_SAMPLES = 4096  #: states of a sync plan checked at most (``_sync_reach``)


class Rail(Protocol):
    """What the traffic needs of a track: its length and its curve (the track atlas reads
    the curve's flat table and the placement, ``track_atlas.Atlas``)."""

    index: int  #: its place in the network's ``tracks``
    length: float
    path: Any  #: its TrackPath (``max_curvature`` [1/mm])

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                               np.ndarray]:
        """x, y, heading [rad] and curvature [1/mm] at the arc lengths ``s``."""
        ...

    def placement(self) -> Any:
        """Where the track's part frame lies now (a planar Pose; the identity without
        parts): ``frame_at`` is the curve placed so."""
        ...


class Network(Protocol):
    """The connections of the tracks."""

    tracks: list[Any]  #: every track, at its ``index``
    version: int  #: changes whenever links, a geometry or a track state change

    def successors(self, track: Rail) -> list[Rail]:
        """Tracks that start where ``track`` ends and may be entered now."""
        ...

    def switches(self, track: Rail) -> tuple[Any, Any]:
        """The switch at the start and at the end of ``track`` (None where there is none)."""
        ...

    def collision_ranges(self, track: Rail) -> tuple[float, float]:
        """Collision range at the start and at the end of ``track`` [mm]."""
        ...

    def refresh(self) -> None:
        """Once per cycle: notice parts that changed position (links across parts)."""
        ...

    def closed_loop(self, track: Rail) -> bool:
        """Whether ``track`` ends where it starts."""
        ...

    def way_on(self, track: Rail, limit: int) -> list[Rail]:
        """The tracks after ``track`` while there is a single way on, ``limit`` at most."""
        ...

    def placed(self) -> bool:
        """Whether parts can place the tracks (else each lies where its geometry says)."""
        ...


class Owner(Protocol):
    """The mover a rider belongs to: told when its command ends, asked before its geared
    way goes on over tracks it did not hold at the start (followMover, D-149)."""

    awake: bool  #: publish its status at the end of this cycle

    #: ``track_finished(command)``: its track command ended (or its halt);
    #: ``admit_way(tracks)``: raises ``CommandRejected`` when it may not move onto ``tracks``
    port: Any


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
    #: the gap its switch zones are measured with (NaN: its gap): a larger gap widens them
    #: only once the rider is outside the wider ones, so that it enters them by the entry
    #: check like any other rider (D-136)
    zone_gap: float = math.nan
    half: tuple[float, float] = (77.5, 77.5)  #: half its width and height [mm] (footprint)


class Traffic:
    """Every rider of one planar system, in arrays the cycle works on."""

    def __init__(self, network: Network, cycle_time: float) -> None:
        self.network = network
        self.dt = cycle_time
        self.riders: list[Rider] = []
        self._arrays(0)
        self._pairs: Pairs | None = None
        self._env: tuple[np.ndarray, np.ndarray] | None = None
        self.table: Any = None  #: the planar system's SegmentTable (set by traffic_of)
        self._now = 0.0
        self._values: list[np.ndarray] = []  #: the system's p, v, a, j rows of this cycle
        #: odometer bounds (low, high) of the riders kept out of a switch zone last cycle
        self._stop_lines: tuple[np.ndarray, ...] = _no_lines()
        self._widening = False  #: a rider's zones may widen to its gap (``_widen_zones``)
        self._held: tuple = ()  #: who holds which switch this cycle (``_holding``)
        self._clashes: dict[tuple, Any] = {}  #: ``_clash``'s answers (and what derives)
        self._merges: dict[tuple, list[list[int]]] = {}  #: ``_merging``'s groups
        self._merged: tuple[tuple, Pairs] | None = None  #: and its last pair list
        self._path_next = np.empty(0, dtype=np.int64)  #: next track of each path (_geometry)
        #: per rider holding a switch with others: the question asked and _clear_stretch's
        #: answer (kept while the riders and their routes stay; see _geometry)
        self._stretches: dict[int, tuple[tuple, tuple]] = {}
        self._atlas: Atlas | None = None  #: the curves of the network's tracks (``_atlas_of``)
        self._atlas_version = -1  #: the network's version the atlas was checked at
        self._network_version = -1  #: the network's version ``_geometry`` was built for
        self._cycle_tables: tuple | None = None  #: ``_tables`` of this cycle
        self._place = np.empty(0, dtype=np.int64)  #: per rider, its track's in ``by_track``
        #: the riders grouped by ``_place`` and where each group ends (``_geometry``)
        self._grouped = (np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64))
        self._near: tuple[Pairs, np.ndarray, np.ndarray] | None = None  #: ``_neighbours``
        self._rooms: tuple[np.ndarray, np.ndarray] | None = None  #: this cycle's ``_room``

    def _arrays(self, n: int) -> None:
        self.p, self.v, self.a = np.zeros(n), np.zeros(n), np.zeros(n)
        self.mode = np.zeros(n, dtype=np.int64)
        self.goal = np.zeros(n)  #: where the running profile ends (the target, or a queue)
        self.lim = np.ones((4, n))
        self.bdec, self.bjerk, self.gap = np.ones(n), np.ones(n), np.zeros(n)
        self.zgap = np.zeros(n)  #: the gap of the switch zones (``Rider.zone_gap``)
        self.base = np.zeros(n)
        self.shift = np.zeros(n)  #: sum of odometer shifts: p - shift is the path coordinate
        self.target = np.zeros(n)  #: odometer target of the command (NaN: geared)
        self.oriented = np.zeros(n, dtype=bool)  #: c follows the track's heading
        self.cdeg = np.zeros(n)  #: c [deg] of the oriented riders, unwrapped
        self.rested = np.zeros(n, dtype=bool)  #: at rest, its x, y, c rows held in the table
        self._geo: Any = None
        self._table_rows: tuple[np.ndarray, ...] | None = None  #: (``_geometry``)
        self._info: dict[int, tuple] = {}  #: ``_track_info`` of the network's version ...
        self._info_version = -1  #: ... this
        #: per rider, the index of its track and of the next track of its route (-1: none),
        #: kept as they change (``_routed``); ``_geometry`` takes a copy
        self._track_index = np.zeros(n, dtype=np.int64)
        #: per rider and track index: the track is its own or on its route (``_routed``),
        #: so a track's operation mode is one count (``riders_on``)
        self._use = np.zeros((n, max(1, len(getattr(self.network, "tracks", ())))), dtype=bool)
        self._uses: dict[int, set[int]] = {}  #: per rider, the track indices set in ``_use``
        self._next_index = np.full(n, -1, dtype=np.int64)
        #: per rider, whether its route goes back over the seam of its closed track (D-147)
        self._back = np.zeros(n, dtype=bool)

    # -- riders ----------------------------------------------------------------------------------

    def couple(self, rider: Rider) -> None:
        """``rider`` stands on its track at ``rider.s`` from now on."""
        self._keep_c()
        old = [(r, *self._state(r)) for r in self.riders]
        self.riders.append(rider)
        rider.route = [Leg(rider.track, 0.0)]
        self._rebuild(old + [(rider, rider.s, 0.0, 0.0, IDLE, rider.s, 0.0)])

    def uncouple(self, rider: Rider, now: float | None = None) -> None:
        """``rider`` is off its track from now on (LeaveTrack). Its own track command ends
        (Aborted), and every rider geared to it loses its master: it brakes to a stop and
        its gear-in ends in error (``_master_gone``, D-145). ``now``: the time of the last
        cycle (the traffic's last one when not given)."""
        now = self._now if now is None else now
        self._abort(rider, "aborted by LeaveTrack")
        for r in self.riders:
            if r is not rider and r.gear is not None and r.gear.master is rider:
                self._master_gone(r, now)
        self._keep_c()
        old = [(r, *self._state(r)) for r in self.riders if r is not rider]
        self.riders.remove(rider)
        self._rebuild(old)
        rider.slot = -1

    def _keep_c(self) -> None:
        """Before the arrays are rebuilt: each rider keeps its c and target."""
        for r in self.riders:
            r.c, r.target = float(self.cdeg[r.slot]), float(self.target[r.slot])
            r.zone_gap = float(self.zgap[r.slot])

    def _state(self, r: Rider) -> tuple[float, float, float, int, float, float]:
        k = r.slot
        return (float(self.p[k]), float(self.v[k]), float(self.a[k]), int(self.mode[k]),
                float(self.goal[k]), float(self.shift[k]))

    def _rebuild(self, states: list[tuple]) -> None:
        """New arrays in rider order (a coupling or uncoupling: rare). What is kept per slot
        across cycles (the stop lines) moves with its rider; a leaving rider's goes."""
        moved = {r.slot: k for k, (r, *_) in enumerate(states) if r.slot >= 0}
        riders, lows, highs = self._stop_lines
        keep = [i for i, k in enumerate(riders.tolist()) if k in moved]
        self._stop_lines = (np.array([moved[k] for k in riders[keep].tolist()], dtype=np.int64),
                            lows[keep].copy(), highs[keep].copy())
        self._arrays(len(states))
        for k, (r, p, v, a, mode, goal, shift) in enumerate(states):
            r.slot = k
            self.p[k], self.v[k], self.a[k], self.mode[k], self.goal[k] = p, v, a, mode, goal
            self.shift[k] = shift
            self.base[k] = r.route[0].base if r.route else 0.0
            self._load(r)
            self._routed(r)
        self._dirty()

    def _routed(self, r: Rider) -> None:
        """``r``'s track or route changed: its ``_track_index``, ``_next_index`` (the track it
        goes on to from the end of its own; none on a route back) and ``_back``."""
        back = backwards(r.route)
        k = r.slot
        self._track_index[k] = r.track.index
        used = self._uses.get(k)
        if used is not None:
            for index in used:
                self._use[k, index] = False
        used = {r.track.index, *(leg.track.index for leg in r.route)}
        self._uses[k] = used
        for index in used:
            if index >= self._use.shape[1]:
                self._widen_use(index + 1)
            self._use[k, index] = True
        self._next_index[r.slot] = r.route[1].track.index if len(r.route) > 1 and not back \
            else -1
        self._back[r.slot] = back

    def _widen_use(self, count: int) -> None:
        """Room in ``_use`` for ``count`` tracks (a track added after the riders came)."""
        wider = np.zeros((self._use.shape[0], count), dtype=bool)
        wider[:, :self._use.shape[1]] = self._use
        self._use = wider

    def riders_on(self, track: Rail, moving: bool) -> int:
        """How many riders use ``track``: with ``moving`` those that move on it or have it on
        the route ahead (§4.3: the track is Moving), else also those standing on it (a
        halted rider's unused legs do not count)."""
        index = track.index
        routed = self._use[:, index] & (self.mode != IDLE) if index < self._use.shape[1] \
            else np.zeros(self.mode.size, dtype=bool)
        if moving:
            return int(np.count_nonzero(routed))
        return int(np.count_nonzero(routed | (self._track_index == index)))

    def riders_at(self, track: Rail) -> int:
        """How many riders are on ``track``."""
        return int(np.count_nonzero(self._track_index == track.index))

    def _load(self, r: Rider) -> None:
        k = r.slot
        lim = r.limits
        if lim is not None:
            self.lim[:, k] = (lim.velocity, lim.acceleration, lim.deceleration, lim.jerk)
        self.bdec[k], self.bjerk[k] = r.brake
        self.gap[k] = r.gap
        r.zone_gap = r.gap if math.isnan(r.zone_gap) else min(r.zone_gap, r.gap)
        self.zgap[k] = r.zone_gap
        self._widening |= r.zone_gap < r.gap
        self.target[k] = r.target
        self.oriented[k], self.cdeg[k] = r.oriented, r.c

    def orient(self, rider: Rider, oriented: bool, c: float | None = None) -> None:
        """C follows the track (``oriented``) or its own commands; ``c`` [deg] where it is."""
        rider.oriented = oriented
        if c is not None:
            rider.c = c
        self.oriented[rider.slot] = oriented
        self.cdeg[rider.slot] = rider.c

    def _dirty(self) -> None:
        self._pairs = None
        self._env = None
        self._geo = None

    def _geometry(self) -> tuple[np.ndarray, ...]:
        """Per rider, what changes only with a track transition or a coupling: the table
        rows (odometer, x, y, c), its track's length, the switch ids at the track's start and
        end (-1: none) and the collision ranges there."""
        if self._geo is None:
            riders, network = self.riders, self.network
            if self._table_rows is None:  # fixed from the coupling on (``_rebuild``)
                xyc = np.array([r.rows for r in riders], dtype=np.int64).reshape(-1, 3)
                self._table_rows = (np.array([r.row for r in riders], dtype=np.int64),
                                    *(np.ascontiguousarray(x) for x in xyc.T))
            rows, xr, yr, cr = self._table_rows
            # what belongs to a track, once per track (riders' tracks in the order first met)
            track_of = self._track_index.copy()
            mine, ranked, ends = group_by_track(track_of)  # mine: each rider's track's place
            tails = ends.tolist()
            heads = [0, *tails[:-1]] if tails else []
            on = [riders[k].track for k in ranked[heads].tolist()]
            count = len(on)
            t_length, t_crs, t_cre = np.empty(count), np.empty(count), np.empty(count)
            t_sws, t_swe = np.full(count, -1, dtype=np.int64), np.full(count, -1, dtype=np.int64)
            t_closed = np.zeros(count, dtype=bool)
            t_next = np.full(count, -1, dtype=np.int64)  #: the one way on (-1: none or many)
            ids: dict[Any, int] = {}
            for i, t in enumerate(on):
                t_length[i] = t.length
                a, b, t_closed[i], t_next[i] = self._track_info(t)
                if a is not None:
                    t_sws[i] = ids.setdefault(a, len(ids))
                if b is not None:
                    t_swe[i] = ids.setdefault(b, len(ids))
                t_crs[i], t_cre[i] = network.collision_ranges(t)
            by_track = [(t, ranked[head:tail]) for t, head, tail
                        in zip(on, heads, tails, strict=True)]
            self._place, self._grouped = mine, (ranked, ends)
            length, crs, cre = t_length[mine], t_crs[mine], t_cre[mine]
            sws, swe = t_sws[mine], t_swe[mine]
            # the next track of each rider's route (-1: none): a rider that passes a switch
            # onto another rider's track keeps its gap to it as a pair (a route that comes
            # round a loop to that track much later does not relate them there); seam: the
            # rider's track is closed, so its riders meet at its switch when one leaves it;
            # back: its route goes back over that seam (it leaves at its start, D-147)
            next_of = self._next_index.copy()
            seam = t_closed[mine]
            back = self._back.copy()
            path_next = np.where(next_of >= 0, next_of, t_next[mine])  #: or the one way on
            path_next[back] = -1  # it goes back: no way on from the end of its track
            self._routes = (track_of, next_of, seam, back)
            self._path_next = path_next
            self._stretches, self._clashes, self._merges, self._merged = {}, {}, {}, None
            self._geo = (rows, xr, yr, cr, length, sws, swe, crs, cre, by_track)
        return self._geo

    def _track_info(self, t: Rail) -> tuple[Any, Any, bool, int]:
        """The switches at the start and at the end of track ``t`` (None: none), whether it
        is closed, and the one way on after it (its index; -1: none or several): the
        network's answers, kept until its version changes."""
        network = self.network
        if self._info_version != network.version:
            self._info, self._info_version = {}, network.version
        found = self._info.get(t.index)
        if found is None:
            a, b = network.switches(t)
            following = network.successors(t)
            if t in following:
                following = [t]
            found = self._info[t.index] = (a, b, network.closed_loop(t),
                                           following[0].index if len(following) == 1 else -1)
        return found

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
        sign = 1.0 if target >= start.position else -1.0
        # gap control may brake a rider moving towards the target harder than the command's
        # dynamics take back without turning round: it goes on held, braking so, and plans
        # from rest (_track)
        u = sign * start.velocity
        hard = u > 0.0 and bool(_hard(np.array(u), np.array(sign * start.acceleration),
                                      np.array(limits.deceleration), np.array(limits.jerk)))
        profile = None if hard else plan_position(start, target, limits, closed_form=True)
        self._check_stops_on_way(k, start, profile, route)
        self._abort(rider, f"aborted by {command.kind}")
        self._rebase(k, shift)
        rider.route, rider.limits, rider.gap, rider.target = route, limits, gap, target
        self._routed(rider)
        rider.command, rider.halting = command, False
        self._load(rider)
        if profile is None:
            self.mode[k] = HELD
            self._dirty()
        else:
            self._follow(rider, profile, target, now)
        command.start()

    def _check_stops_on_way(self, k: int, start: KinematicState, profile: Profile | None,
                            route: list[Leg]) -> None:
        """A MoveOnTrack whose motion (its profile, or gap control's brake from a hard
        brake) would run past an end of its way is refused: from the end of a track a mover
        goes on only onto the next one of its route, and back over a track's start only on
        a route back over a loop's seam (§6.2.2, D-147). The command before it goes on."""
        if profile is not None:
            lo, hi = profile.position_extrema()
        else:
            lo_a, hi_a = brake_envelope(*(np.array([x]) for x in (
                start.position, start.velocity, start.acceleration, self.bdec[k],
                self.bjerk[k])))
            lo, hi = float(lo_a[0]), float(hi_a[0])
        legs = ascending(route)
        first, last = legs[0], legs[-1]
        end = last.base + last.track.length
        if hi > end + _PAST or lo < first.base - _PAST:
            track, where = (last.track, "end") if hi > end + _PAST else (first.track, "start")
            raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                                  f"MoveOnTrack: with these dynamics the mover cannot stop "
                                  f"before the {where} of {getattr(track, 'name', track)}, "
                                  "and it changes track only from the end of one to the "
                                  "start of the next on its way (§6.2.2)")

    def halt(self, rider: Rider, limits: Limits, command: PlanarCommand | None,
             now: float) -> None:
        """Stop on the track with ``limits`` (§6.1.9 Halt); Done at rest."""
        profile = self._stop_profile(rider, limits)
        self._abort(rider, "aborted by Halt")
        rider.limits, rider.command, rider.halting = limits, command, True
        rider.target = profile.end.position
        self._load(rider)
        self._follow(rider, profile, rider.target, now)
        if command is not None:
            command.start()

    def _stop_profile(self, rider: Rider, limits: Limits) -> Profile:
        """A stop from the rider's state with ``limits``' deceleration and jerk (or its gap
        control brake, where that brakes harder: no turning round)."""
        k = rider.slot
        start = KinematicState(float(self.p[k]), float(self.v[k]), float(self.a[k]))
        dec, jerk = limits.deceleration, limits.jerk
        u = abs(start.velocity)
        b = math.copysign(1.0, start.velocity) * start.acceleration
        if u > 0.0 and _hard(np.array(u), np.array(b), np.array(dec), np.array(jerk)):
            dec, jerk = rider.brake  # gap control brakes harder: its brake, not a turn round
        return self._within_way(rider, start, plan_stop(start, dec, jerk))

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
        if lo >= first.base - _PAST and hi <= end + _PAST:
            return stop
        loop = last.track if hi > end + _PAST else first.track
        if self._track_info(loop)[2]:
            length = loop.length
            if hi > end + _PAST and not backwards(route):
                while end < hi + _PAST:
                    route.append(Leg(loop, end))
                    end += length
            elif lo < first.base - _PAST and (backwards(route) or len(route) == 1):
                low = first.base
                while low > lo - _PAST:
                    low -= length
                    route.append(Leg(loop, low))
            else:
                return self._stop_at_bound(rider, start, stop, first.base, end, lo, hi)
            self._routed(rider)
            self._pairs = None
            self._geo = None
            return stop
        return self._stop_at_bound(rider, start, stop, first.base, end, lo, hi)

    def _stop_at_bound(self, rider: Rider, start: KinematicState, stop: Profile, low: float,
                       high: float, lo: float, hi: float) -> Profile:
        """``_within_way``'s stop exactly at the way's end (``high``) or start (``low``)."""
        k = rider.slot
        bound = high if hi > high + _PAST else low
        hard = Limits(max(abs(start.velocity), float(self.lim[0, k]), 1e-9),
                      float(self.bdec[k]), float(self.bdec[k]), float(self.bjerk[k]))
        try:
            clamped = plan_position(start, bound, hard)
        except CommandRejected:
            return stop
        c_lo, c_hi = clamped.position_extrema()
        return clamped if c_lo >= low - _PAST and c_hi <= high + _PAST else stop

    def _master_gone(self, rider: Rider, now: float) -> None:
        """``rider``'s master mover leaves the traffic (LeaveTrack): the coupling ends. The
        rider brakes to a stop with its command's dynamics (a Halt's), no longer geared,
        and its command then ends in error (D-145); nothing keeps the master's rider."""
        coupling = rider.gear
        name = getattr(coupling.master.owner, "name", "the master")
        coupling.master, coupling.follow = None, False
        coupling.stopping = True
        coupling.failed = (ErrorId.PLANAR_WRONG_MODE,
                           f"the master mover {name} left its track: the coupling ended "
                           "and the mover stopped (§6.2.9)")
        assert rider.limits is not None
        profile = self._stop_profile(rider, rider.limits)
        rider.halting, rider.target = True, profile.end.position
        self.target[rider.slot] = rider.target
        self._follow(rider, profile, rider.target, now)
        if rider.command is not None:
            rider.command.in_sync = False
            rider.owner.awake = True

    def gear(self, rider: Rider, route: list[Leg], coupling: Any, gap: float,
             command: PlanarCommand) -> None:
        """Start a gear-in: the rider follows ``coupling`` (gearing.py) along ``route``."""
        k = rider.slot
        shift = route[0].base - float(self.base[k])
        self._abort(rider, f"aborted by {command.kind}")
        self._rebase(k, shift)
        rider.route, rider.gap, rider.limits = route, gap, coupling.sync.limits
        self._routed(rider)
        rider.command, rider.halting, rider.gear = command, False, coupling
        rider.target = math.nan
        self._load(rider)
        self.mode[k] = GEAR
        self._dirty()
        command.start()

    def _abort(self, rider: Rider, message: str) -> None:
        del message
        rider.gear = None
        if rider.command is not None:
            rider.command.abort()
            rider.command = None

    def _rebase(self, k: int, shift: float) -> None:
        if shift:
            self.shift[k] += shift
            self.p[k] += shift
            self.goal[k] += shift
            self.target[k] += shift
            self.base[k] += shift
            self._env = None
            self._pairs = None

    def _follow(self, rider: Rider, profile: Profile, goal: float, now: float) -> None:
        self.table.install(rider.row, profile, now)
        self.mode[rider.slot] = FOLLOW
        self.goal[rider.slot] = goal
        self._dirty()

    # -- the cycle -------------------------------------------------------------------------------

    def advance(self, now: float, values: list[np.ndarray]) -> None:
        """Phase 2: proposals, the gap filter, the switch zones, transitions, setpoints.
        ``values`` are the system's p, v, a, j rows, evaluated for ``now``."""
        n = len(self.riders)
        if n == 0 or not (self.mode != IDLE).any():
            return
        self._now, self._values = now, values
        self._rooms = self._cycle_tables = None
        self.network.refresh()
        if self._network_version != self.network.version:  # a part moved, a track changed:
            self._network_version = self.network.version  # switches, ranges, ways on
            self._dirty()
        *start, going, queued = proposals(self.mode, FOLLOW, IDLE, self._rows(), self.p,
                                          self.v, self.a, self.bjerk, self.goal, self.target,
                                          *values)
        nxt, known = list(start[:4]), tuple(start[4:])
        self._holding()
        pairs = self._merging(self._pair_list(going), going)
        if queued.size:
            self._extend(queued, nxt, pairs)
        held = np.flatnonzero(self.mode == HELD)
        if held.size:
            self._track(held, nxt, known, pairs)
        geared = np.flatnonzero(self.mode == GEAR)
        geared_any = bool(geared.size)  # nothing turns geared within the cycle
        if geared_any:
            self._gear_steps(geared, now, nxt, pairs)
        turning, pairs.gap = turning_gaps(nxt[1], nxt[2], self.bjerk, going, pairs.succ,
                                          pairs.pred, self.mode, IDLE, self.target, self.p,
                                          self.gap)  # and the gaps with them (_pair_gaps)
        braking, lo, hi = self._filter(nxt, pairs, known)
        kept = self._no_turning_back(pairs, turning & ~braking, nxt, lo, hi)
        braking[kept] = True
        kept = np.concatenate((kept, self._keep_out(nxt, lo, hi, braking)))
        if kept.size:  # their followers may have to brake now too
            more, lo, hi = self._filter(nxt, pairs, (np.ones(n, dtype=bool), lo, hi))
            braking |= more
            braking[kept] = True
        self.p, self.v, self.a = nxt[0], nxt[1], nxt[2]
        self._env = (lo, hi)
        self.mode[braking & (self.mode == FOLLOW)] = HELD
        geared = self.mode == GEAR
        for k in (np.flatnonzero(geared & (braking | self._resync(geared))).tolist()
                  if geared_any else ()):
            coupling = self.riders[k].gear
            master = self._master(coupling)
            coupling.sync.held(now, (float(self.p[k]), float(self.v[k]), float(self.a[k])),
                               master)
            coupling.planned_v, coupling.resync = master[1], False
            coupling.braked = bool(braking[k])
        self._transitions()
        self._write(values)
        self._events(now, values)

    def _filter(self, nxt: list[np.ndarray], pairs: Pairs,
                known: tuple[np.ndarray, np.ndarray, np.ndarray]
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The CA group's gap filter (``filter_steps``) on ``nxt``, compiled for the
        traffic's pairs (``traffic_kernels.gap_filter``): the riders that brake instead and
        the envelopes of ``nxt``."""
        lo_cur, hi_cur = self._envelope()
        return gap_filter(self.p, self.v, self.a, lo_cur, hi_cur, *nxt, self.dt, self.bdec,
                          self.bjerk, pairs.succ, pairs.pred, pairs.offset, pairs.gap, *known)

    def _envelope(self) -> tuple[np.ndarray, np.ndarray]:
        if self._env is None:
            self._env = brake_envelope(self.p, self.v, self.a, self.bdec, self.bjerk)
        return self._env

    def _pair_list(self, going: np.ndarray) -> Pairs:
        """Each rider with the rider ahead on its path (cached until a rider changes track or
        route): on its track the next one by arc length; the front rider of a track looks
        along its route (then along the one way on, if the network leaves one) for the first
        rider of each track. Their gaps: ``_pair_gaps`` with ``going``."""
        if self._pairs is None:
            self._geometry()
            mine = self._place  # riders by track (in ``by_track`` order), then arc length
            ranked = in_order(self.p - self.base, *self._grouped)
            same = mine[ranked[:-1]] == mine[ranked[1:]]
            succ, pred = ranked[:-1][same], ranked[1:][same]
            offset = self.base[succ] - self.base[pred]
            order = ranked.tolist()
            heads = np.flatnonzero(np.concatenate(([ranked.size > 0], ~same))).tolist()
            tails = [*heads[1:], len(order)] if heads else []
            first: dict[int, list[int]] = {}  #: per track, its first two riders
            for head, tail in zip(heads, tails, strict=True):
                first[self.riders[order[head]].track.index] = order[head:min(head + 2, tail)]
            fronts, leaders, shifts = [], [], []
            for tail in tails:
                m = order[tail - 1]
                ahead = self._ahead(self.riders[m], first)
                if ahead is not None:
                    fronts.append(m)
                    leaders.append(ahead[0])
                    shifts.append(ahead[1])
            if self._back.any():
                self._pairs_back(order, heads, tails, fronts, leaders, shifts)
            sa = np.concatenate((succ, np.array(fronts, dtype=np.int64)))
            pa = np.concatenate((pred, np.array(leaders, dtype=np.int64)))
            self._pairs = Pairs(sa, pa, np.concatenate((offset, np.array(shifts, dtype=float))),
                                self.gap[sa], np.zeros(sa.size, dtype=bool), True)
        self._pair_gaps(self._pairs, going)
        return self._pairs

    def _pair_gaps(self, pairs: Pairs, going: np.ndarray) -> None:
        """Each keeps its own gap to the mover in front of it in its direction of travel
        (§6.1.9): a leader that moves back onto its follower keeps the larger of the two
        gaps. Back: a MoveOnTrack behind it, or ``going`` (``traffic_kernels.going_back``,
        of its state and, once they are known, of this cycle's proposals: a geared slave held
        at rest by the gap goes back whenever its master still does)."""
        pairs.gap = pair_gaps(pairs.succ, pairs.pred, self.mode, IDLE, self.target, self.p,
                              going, self.gap)

    def _ahead(self, m: Rider, first: dict[int, list[int]]) -> tuple[int, float] | None:
        """The first rider on the tracks after ``m``'s along its route (then the one way on,
        if the network leaves one), and the shift of its odometer into ``m``'s. ``first``:
        the first two riders of each track with riders. A route back has no legs ahead."""
        legs = ahead_legs(m.route)
        for leg in legs[1:]:
            for k in first.get(leg.track.index, ()):
                if k != m.slot:
                    return k, leg.base - float(self.base[k])
        last = legs[-1].track
        base = legs[-1].base + last.length
        for track in self.network.way_on(last, _HORIZON_TRACKS):
            for k in first.get(track.index, ()):
                if k != m.slot:
                    return k, base - float(self.base[k])
            base += track.length
        return None

    def _pairs_back(self, order: list[int], heads: list[int], tails: list[int],
                    fronts: list[int], leaders: list[int], shifts: list[float]) -> None:
        """The pairs of the riders on a route back over a loop's seam (D-147), added to
        ``fronts``, ``leaders`` and ``shifts``: the first rider of a track (by arc length)
        whose route goes back leads the first rider behind it along its legs. That one may be
        paired with it already (its own way runs on round the loop), or not (it leaves the
        loop at the seam): then it keeps the gap only through this pair, before the rider
        going back crosses the seam towards it."""
        last: dict[int, list[int]] = {}  #: per track, its last two riders, the last first
        for head, tail in zip(heads, tails, strict=True):
            last[self.riders[order[head]].track.index] = order[max(head, tail - 2):tail][::-1]
        known = set(zip(fronts, leaders, strict=True))
        for head in heads:
            k = order[head]
            if not self._back[k]:
                continue
            behind = self._behind(self.riders[k], last)
            if behind is not None and (behind[0], k) not in known:
                fronts.append(behind[0])
                leaders.append(k)
                shifts.append(behind[1])

    def _behind(self, m: Rider, last: dict[int, list[int]]) -> tuple[int, float] | None:
        """The first rider behind ``m`` along its route back (on its legs after the first;
        the route ends at its target, so it looks no further), and the shift of ``m``'s
        odometer into that rider's. ``last``: the last two riders of each track."""
        for leg in m.route[1:]:
            for k in last.get(leg.track.index, ()):
                if k != m.slot:
                    return k, float(self.base[k]) - leg.base
        return None

    def _track(self, held: np.ndarray, nxt: list[np.ndarray],
               known: tuple[np.ndarray, np.ndarray, np.ndarray], pairs: Pairs) -> None:
        """Held riders: a fresh profile once the way to the target (or to the end of the
        queue) is clear; else the most progressive constant-jerk step that keeps clear of the
        neighbours as they are now (transport.kernels.candidates), else a brake."""
        room_lo, room_hi = self._room(pairs)
        ahead, behind = self._neighbours(pairs)
        sign, goal, fits, rest = held_plans(held, self.p, self.v, self.a, self.target,
                                            self.lim, room_lo, room_hi, self.mode, IDLE, ahead,
                                            behind, *nxt, *known)
        for i in np.flatnonzero(fits).tolist():
            k = int(held[i])
            rider = self.riders[k]
            assert rider.limits is not None
            try:
                profile = plan_position(KinematicState(float(self.p[k]), float(self.v[k]),
                                                       float(self.a[k])),
                                        float(goal[i]), rider.limits, closed_form=True)
            except CommandRejected:
                rest[i] = True
                continue
            self.table.install(rider.row, profile, self._now - self.dt)
            self.mode[k] = FOLLOW
            self.goal[k] = goal[i]
            for field_, value in zip(nxt, profile.at(self.dt), strict=True):
                field_[k] = value
        if rest.any():
            lo, hi = self._envelope()
            held_steps(held, sign, rest, self.dt, self.p, self.v, self.a, self.target,
                       self.lim, self.bdec, self.bjerk, room_lo, room_hi, lo, hi, *nxt, *known)

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

    def _gear_steps(self, geared: np.ndarray, now: float, nxt: list[np.ndarray],
                    pairs: Pairs) -> None:
        """Proposals of geared riders: the sync's, kept on the path the slave may use. One
        whose next step could take it past an end of that path (braking with its hardest
        dynamics) stops there instead, and its command fails (§6.2.8). A slave whose master
        is geared too comes after it, so it reads its master's step of this cycle."""
        for k in self._masters_first(geared):
            rider = self.riders[k]
            coupling = rider.gear
            self._extend_follow(rider, coupling)
            state = (float(self.p[k]), float(self.v[k]), float(self.a[k]))
            master = self._master(coupling, nxt)
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
                proposal = tuple(float(x[0]) for x in brake_state(
                    self.p[k:k + 1], self.v[k:k + 1], self.a[k:k + 1], self.bdec[k:k + 1],
                    self.bjerk[k:k + 1], self.dt))
                coupling.sync.held(now, tuple(proposal[:3]), master)
                for field_, value in zip(nxt, proposal, strict=True):
                    field_[k] = value  # inside last cycle's envelope, which was clear
                if rider.command is not None:
                    rider.command.in_sync = False
                continue
            coupling.braked = False
            try:
                proposal = coupling.sync.step(now, state, master, self.dt)
            except CommandRejected as rejected:  # no sync plan: stop, then end in error
                coupling.failed = (rejected.error_id, rejected.message)
                assert rider.limits is not None
                self._stop_following(rider, self._stop_profile(rider, rider.limits), nxt)
                continue
            astray = proposal is not None and self._astray(rider, coupling, now, master)
            if proposal is not None and state[1] != 0.0 and \
                    (astray or _turns_against(coupling, proposal, rider.limits.jerk)):
                # before the first sync it comes to rest rather than turn (§6.1.9) or run
                # off its path (D-197), and synchronises again from each step of that (its
                # sync's own plan went on)
                proposal = plan_velocity(KinematicState(*state), 0.0, rider.limits).at(self.dt)
                coupling.sync.held(now, tuple(proposal[:3]), master)
            limit = rider.limits.velocity
            chasing = proposal is not None and not coupling.sync.in_sync \
                and abs(_released(proposal, rider.limits.jerk)) > limit * (1.0 + 1e-9)
            if chasing:  # a master faster than the command's velocity: follow at that (§6.2.8)
                proposal = plan_velocity(KinematicState(*state),
                                         math.copysign(limit, proposal[1]),
                                         rider.limits).at(self.dt)
            if proposal is not None and state[1] == 0.0 and state[2] == 0.0 and \
                    self._no_room(k, proposal[1], pairs):
                # at its stop line or gap already: it waits there, synchronising again
                proposal = (state[0], 0.0, 0.0, 0.0)
                coupling.sync.held(now, state, master)
            if proposal is None:  # waiting: brake with the command's dynamics
                lim = rider.limits
                proposal = tuple(float(x[0]) for x in brake_state(
                    self.p[k:k + 1], self.v[k:k + 1], self.a[k:k + 1],
                    np.array([lim.deceleration]), np.array([lim.jerk]), self.dt))
            lo, hi = brake_envelope(np.array([proposal[0]]), np.array([proposal[1]]),
                                    np.array([proposal[2]]), self.bdec[k:k + 1],
                                    self.bjerk[k:k + 1])
            self._extend_loop(rider, coupling, float(hi[0]))
            # never back over the start of the track it is on: the legs behind are gone
            low = max(coupling.low, rider.route[0].base)
            behind = lo[0] < low - TOLERANCE
            if self._waits(coupling, state, proposal, behind or astray):
                nxt[0][k], nxt[1][k], nxt[2][k], nxt[3][k] = state[0], 0.0, 0.0, 0.0
                coupling.sync.held(now, state, master)
                self._show_in_sync(rider, coupling, state, master)
                continue
            if hi[0] > coupling.high + TOLERANCE or behind:
                bound = coupling.high if hi[0] > coupling.high + TOLERANCE else low
                self._stop_at(rider, bound, nxt)
                continue
            for field_, value in zip(nxt, proposal, strict=True):
                field_[k] = value
            if chasing:  # the sync is planned again from where the mover now is
                try:
                    coupling.sync.held(now, tuple(proposal[:3]), master)
                except CommandRejected as rejected:
                    coupling.failed = (rejected.error_id, rejected.message)
                    self._stop_following(rider, self._stop_profile(rider, rider.limits), nxt)
                    continue
            self._show_in_sync(rider, coupling, state, master)

    def _masters_first(self, geared: np.ndarray) -> list[int]:
        """The geared riders, each after its master when that is geared too."""
        order = geared.tolist()
        if len(order) < 2:
            return order
        among = set(order)

        def depth(k: int) -> int:
            count, rider = 0, self.riders[k]
            while count < len(order):
                master = rider.gear.master if rider.gear is not None else None
                if master is None or master.slot not in among:
                    break
                count, rider = count + 1, master
            return count

        return sorted(order, key=depth)

    @staticmethod
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

    def _no_room(self, k: int, velocity: float, pairs: Pairs) -> bool:
        """Whether a rider at rest has less than ``_CREEP`` room the way ``velocity`` goes
        (a neighbour's envelope or a stop line): a step would only be braked again, and the
        two would alternate while it creeps up to the bound."""
        room_lo, room_hi = self._room(pairs)
        p = float(self.p[k])
        return (velocity > 0.0 and float(room_hi[k]) - p < _CREEP) or \
            (velocity < 0.0 and p - float(room_lo[k]) < _CREEP)

    def _brakes_on(self, k: int, limits: Limits) -> bool:
        """Whether rider ``k`` moves and brakes harder than ``limits`` take back without
        turning it round (``_hard``)."""
        v = float(self.v[k])
        if v == 0.0:
            return False
        sign = 1.0 if v > 0.0 else -1.0
        return bool(_hard(np.array(sign * v), np.array(sign * float(self.a[k])),
                          np.array(limits.deceleration), np.array(limits.jerk)))

    def _resync(self, geared: np.ndarray) -> np.ndarray:
        """Geared riders whose master changed its velocity a lot since their sync was
        planned: planned again (the sync is planned for the master's velocity of its start;
        a master that stops or speeds up must not leave the slave creeping)."""
        out = np.zeros(geared.size, dtype=bool)
        for k in np.flatnonzero(geared).tolist():
            out[k] = self.riders[k].gear.resync
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
        k, low = rider.slot, max(coupling.low, rider.route[0].base)
        dec, jerk = float(self.bdec[k]), float(self.bjerk[k])
        if velocity > 0.0:  # only the start counts
            return _sync_reach(sync, now, master, self.dt, dec, jerk, low, math.inf)[0] < \
                low - TOLERANCE
        if self._loops_on(rider, coupling):  # a loop has no end forwards
            return False
        return _sync_reach(sync, now, master, self.dt, dec, jerk, -math.inf,
                           coupling.high)[1] > coupling.high + TOLERANCE

    @staticmethod
    def _waits(coupling: Any, state: tuple[float, float, float],
               proposal: tuple[float, ...], behind: bool) -> bool:
        """A slave at rest that has not been in sync yet stays where it is when the sync
        would start it in a direction ``allowedSlaveSyncDirections`` forbids, or behind the
        start of its path, or would take it off its path where waiting lets it sync further
        inside (``_astray``, D-197) (§6.2.8, §7.2.1.2.7): it synchronises again from there
        next cycle, with the master further on."""
        if coupling.sync.synced_once or state[1] != 0.0 or state[2] != 0.0:
            return False
        return _against(coupling, proposal[1]) or behind

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
        self._stop_following(rider, profile, nxt)

    def _stop_following(self, rider: Rider, profile: Profile, nxt: list[np.ndarray]) -> None:
        """A geared rider follows ``profile`` (from the last cycle) to rest, halting; its
        command ends with ``gear.failed`` once it stands."""
        k = rider.slot
        rider.gear.stopping = True
        rider.halting, rider.target = True, profile.end.position
        self.target[k] = rider.target
        self.table.install(rider.row, profile, self._now - self.dt)
        self.mode[k] = FOLLOW
        self.goal[k] = rider.target
        for field_, value in zip(nxt, profile.at(self.dt), strict=True):
            field_[k] = value
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
        way, moved = ahead_legs(master.route), float(self.shift[master.slot])
        seen = coupling.seen  # (the list, its length, its last leg, the master's shift)
        if seen and seen[0] is way and seen[1] == len(way) and seen[2] is way[-1] and \
                seen[3] == moved and coupling.blocked is None:
            return  # nothing new since the last cycle
        coupling.seen, coupling.blocked = (way, len(way), way[-1], moved), None
        route, shift = rider.route, coupling.offset - moved
        after, changed = route[1] if len(route) > 1 else None, False
        start = max(coupling.joined, route[0].base) - _SAME
        for leg in way:
            at = leg.base + shift
            if at < start:
                continue  # the master's way before the stretch the two share, or behind
            j = next((i for i, mine in enumerate(route) if abs(mine.base - at) <= _SAME), None)
            if j is not None and route[j].track is leg.track:
                continue
            if j == 0 or (j is None and abs(at - coupling.high) > _SAME):
                break  # the slave is on another track there already, or the legs do not meet
            if j is not None:  # the master's way leaves the one the slave had ahead
                del route[j:]
                coupling.high, changed = at, True
            if not self._admit(rider, coupling, leg.track):
                break
            route.append(Leg(leg.track, at))
            coupling.high, changed = at + leg.track.length, True
        if changed:
            self._routed(rider)
            self._pairs = None
            if (route[1] if len(route) > 1 else None) is not after:
                self._geo = None  # its next track is part of the geometry

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
        self._routed(rider)
        self._pairs = None
        if single:
            self._geo = None

    def _loops_on(self, rider: Rider, coupling: Any) -> bool:
        """Whether the geared path goes on round a closed loop at its end (``_extend_loop``)."""
        loop = rider.route[-1].track
        if not self._track_info(loop)[2]:
            return False
        return not coupling.follow or (coupling.master is not None
                                       and coupling.master.route[-1].track is loop)

    def _admit(self, rider: Rider, coupling: Any, track: Rail) -> bool:
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

    def _extend(self, queued: np.ndarray, nxt: list[np.ndarray], pairs: Pairs) -> None:
        """Riders following a profile to the end of a queue get a new one, further on, once
        the room ahead has grown by more than ``_EXTEND`` (no stop and go behind a mover that
        drives away)."""
        reach, grow = extensions(queued, self.target, self.goal, *self._room(pairs),
                                 self._neighbours(pairs)[0], self.v, self.a, self.mode, HELD,
                                 _EXTEND)
        for i in np.flatnonzero(grow).tolist():
            k = int(queued[i])
            rider = self.riders[k]
            assert rider.limits is not None
            try:
                profile = plan_position(KinematicState(float(self.p[k]), float(self.v[k]),
                                                       float(self.a[k])), float(reach[i]),
                                        rider.limits, closed_form=True)
            except CommandRejected:
                continue
            self.table.install(rider.row, profile, self._now - self.dt)
            self.goal[k] = reach[i]
            for field_, value in zip(nxt, profile.at(self.dt), strict=True):
                field_[k] = value

    def _neighbours(self, pairs: Pairs) -> tuple[np.ndarray, np.ndarray]:
        """The rider ahead of and behind each rider on its path (-1: none); kept with the
        pair list they come from."""
        if self._near is None or self._near[0] is not pairs:
            self._near = (pairs, *neighbours(self.p.size, pairs.succ, pairs.pred))
        return self._near[1], self._near[2]

    def _room(self, pairs: Pairs) -> tuple[np.ndarray, np.ndarray]:
        """Where each rider may stop given its neighbours' brake envelopes now (once per
        cycle: ``advance`` forgets it)."""
        if self._rooms is None:
            lo, hi = self._envelope()
            self._rooms = rooms(self.p.size, pairs.succ, pairs.pred, pairs.offset, pairs.gap,
                                lo, hi, *self._stop_lines)
        return self._rooms

    def _no_turning_back(self, pairs: Pairs, turning: np.ndarray, nxt: list[np.ndarray],
                         lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """A leader closer to its follower than their gap does not start to go back: one
        whose next step would (``turning``: ``going_back`` now, not before) brakes instead,
        and its brake from a state that does not turn round never does (§6.1.9). The filter
        lets such a step through while it keeps the envelope where it was, but the motion
        inside the envelope would still take the leader back towards a follower it is too
        close to already. Writes the brakes into ``nxt``, ``lo`` and ``hi``; returns the
        riders."""
        if not turning.any() or not pairs.succ.size:
            return np.empty(0, dtype=np.int64)
        s, k = pairs.succ, pairs.pred
        unsafe = hi[s] + pairs.gap > lo[k] + pairs.offset + TOLERANCE
        slots = np.unique(k[unsafe & turning[k]])
        self._brake(slots, nxt, lo, hi)
        return slots

    def _keep_out(self, nxt: list[np.ndarray], lo: np.ndarray, hi: np.ndarray,
                  braking: np.ndarray) -> np.ndarray:
        """The switch rule (§6.2.2): a rider whose next step would take its brake envelope
        into a switch zone that another rider holds from a track off its path brakes
        instead (its brake stays behind the zone boundary: the envelope of a brake is
        inside the envelope it starts from); riders that hold one switch from conflicting
        tracks at once keep their footprints apart (``_apart``). Writes the brakes into
        ``nxt``, ``lo`` and ``hi``; returns the riders it braked."""
        lines, contested = self._zone_lines(lo, hi)
        self._stop_lines = lines  # (riders, lows, highs): the rooms of the next cycle
        skip = np.zeros(self.p.size, dtype=bool)
        skip[list(contested)] = True
        slots = out_of_bounds(*lines, skip, braking, lo, hi)
        self._brake(slots, nxt, lo, hi)
        if contested:  # their stop lines narrow to where their footprints stay clear
            bounds = _lines_dict(lines)
            slots = np.concatenate((slots, self._apart(contested, bounds, nxt, lo, hi, braking)))
            self._stop_lines = _lines_arrays(bounds)
        return slots

    def _brake(self, slots: np.ndarray, nxt: list[np.ndarray], lo: np.ndarray,
               hi: np.ndarray) -> None:
        """``slots`` brake this cycle instead: their step and its envelope."""
        if not slots.size:
            return
        step = brake_state(self.p[slots], self.v[slots], self.a[slots], self.bdec[slots],
                           self.bjerk[slots], self.dt)
        for field_, value in zip(nxt, step, strict=True):
            field_[slots] = value
        lo[slots], hi[slots] = brake_envelope(nxt[0][slots], nxt[1][slots], nxt[2][slots],
                                              self.bdec[slots], self.bjerk[slots])

    def _holding(self) -> None:
        """Who holds which switch at the start of the cycle (``_held``): the riders whose
        envelope reaches into a zone, and among them those that hold one switch together
        with a rider of a conflicting track (``contested``, each with those riders).

        A rider is in its zone at the switch at the end of its track when its envelope
        reaches within max(collision range at end, gap) of the track end, and at the switch
        at its start within max(collision range at start, gap) of the start (the gap of its
        zones, ``Rider.zone_gap``), or anywhere on the track when the zone covers all of it
        (no point of the track is safe then)."""
        _, _, _, _, length, sws, swe, crs, cre, _ = self._geometry()
        lo_now, hi_now = self._envelope()
        if self._widening:
            self._widen_zones(length, crs, cre, sws >= 0, swe >= 0, lo_now, hi_now)
        end_line, start_line, in_end, in_start, k, end, switch = zone_holders(
            self.base, length, crs, cre, self.zgap, sws, swe, lo_now, hi_now)
        contested: dict[int, set[int]] = {}
        if k.size > 1:  # placed there, or a new route turned a pair into a conflict
            key = ("contested", k.tobytes(), end.tobytes())
            found = self._clashes.get(key)  # read only: kept while the holders stay
            if found is None:
                clash = self._clash(k, end, switch, k, end, switch)
                for i, j in zip(*np.nonzero(clash), strict=True):
                    contested.setdefault(int(k[i]), set()).add(int(k[j]))
                self._clashes[key] = found = contested
            contested = found
        self._held = (end_line, start_line, in_end, in_start, k, end, switch, contested)

    def _merging(self, pairs: Pairs, going: np.ndarray) -> Pairs:
        """``pairs`` and, for riders that hold a merge together from the ends of their
        tracks with one way on after it, a pair as if they were on that way already (the
        one nearer the switch ahead, unless it goes back): once the first passes the switch
        they are one, and the gap must be there then (§6.1.9)."""
        *_, k, end, switch, contested = self._held
        if not contested:
            return pairs
        key = (k.tobytes(), end.tobytes())
        groups = self._merges.get(key)
        if groups is None:  # the same riders hold for many cycles: grouped once
            path_next = self._path_next
            found: dict[tuple[int, int], list[int]] = {}
            for i in np.flatnonzero(end).tolist():
                r = int(k[i])
                if r in contested and path_next[r] >= 0:
                    found.setdefault((int(switch[i]), int(path_next[r])), []).append(r)
            groups = self._merges[key] = [g for g in found.values() if len(g) > 1]
        if not groups:
            return pairs
        exit_at = self.base + self._geometry()[4]  # the odometer of a track's end switch
        ahead = (exit_at - self.p).tolist()
        # a leader going back, away from the switch, is free of it: only the footprints
        back = ((self.mode != IDLE) & ((self.target < self.p) | going)).tolist()
        succ, pred = [], []
        for riders in groups:
            riders = sorted(riders, key=lambda r: (ahead[r], r))
            for f, lead in zip(riders[1:], riders[:-1], strict=True):
                if not back[lead]:
                    succ.append(f)
                    pred.append(lead)
        if not succ:
            return pairs
        order = (id(pairs), tuple(succ), tuple(pred))
        if self._merged is None or self._merged[0] != order:
            sa, pa = np.array(succ, dtype=np.int64), np.array(pred, dtype=np.int64)
            self._merged = (order, Pairs(
                np.concatenate((pairs.succ, sa)), np.concatenate((pairs.pred, pa)),
                np.concatenate((pairs.offset, exit_at[sa] - exit_at[pa])),
                np.concatenate((pairs.gap, self.gap[sa])),
                np.zeros(pairs.succ.size + sa.size, dtype=bool), True))
        merged = self._merged[1]
        self._pair_gaps(merged, going)
        return merged

    def _zone_lines(self, lo: np.ndarray, hi: np.ndarray
                    ) -> tuple[tuple[np.ndarray, ...], dict[int, set[int]]]:
        """Odometer bounds of the riders kept out of a switch zone this cycle (riders, lows,
        highs), and the contested holders (``_holding``). Holders keep the switch; riders that enter
        a zone are decided in rider order: the first whom no holder from a track off its
        path blocks becomes a holder too."""
        sws, swe = self._geometry()[5:7]
        end_line, start_line, in_end, in_start, hk, he, hs, contested = self._held
        if not hk.size:
            return _no_lines(), contested
        riders, lows, highs, entering = zone_lines(sws, swe, in_end, in_start, end_line,
                                                   start_line, lo, hi, _ZONE_LOOKAHEAD, hk, he,
                                                   hs, *self._routes)
        if entering.size <= 1:
            return (riders, lows, highs), contested
        k, end, switch, low, high, _ = zone_entries(  # the entries, as zone_lines saw them
            sws, swe, in_end, in_start, end_line, start_line, lo, hi, _ZONE_LOOKAHEAD)
        lines = _lines_dict((riders, lows, highs))
        # decided in rider order: the first of a conflict enters
        entering = entering[np.lexsort((k[entering], switch[entering]))]
        granted: dict[int, list[int]] = {}
        for i in entering.tolist():
            mine = granted.setdefault(int(switch[i]), [])
            if mine and self._conflicts(k[i:i + 1], end[i:i + 1], k[mine], end[mine]).any():
                _narrow(lines, int(k[i]), float(low[i]), float(high[i]))
            else:
                mine.append(i)
        return _lines_arrays(lines), contested

    def _widen_zones(self, length: np.ndarray, crs: np.ndarray, cre: np.ndarray,
                     has_start: np.ndarray, has_end: np.ndarray, lo_now: np.ndarray,
                     hi_now: np.ndarray) -> None:
        """A rider whose gap grew measures its zones with the larger gap once its envelope
        is outside them: inside, it would hold the switch at once, past the entry check."""
        if not self._widening:
            return
        k = np.flatnonzero(self.zgap < self.gap)
        self._widening = bool(k.size)
        if not k.size:
            return
        base, gap = self.base[k], self.gap[k]
        end = base + length[k] - np.maximum(cre[k], gap)
        start = base + np.maximum(crs[k], gap)
        inside = (has_end[k] & ((hi_now[k] > end + TOLERANCE) | (end <= base + TOLERANCE))) | \
            (has_start[k] & ((lo_now[k] < start - TOLERANCE)
                             | (start >= base + length[k] - TOLERANCE)))
        for slot in k[~inside].tolist():
            self.zgap[slot] = self.riders[slot].zone_gap = self.gap[slot]

    def _apart(self, contested: dict[int, set[int]], lines: dict[int, tuple[float, float]],
               nxt: list[np.ndarray], lo: np.ndarray, hi: np.ndarray,
               braking: np.ndarray) -> np.ndarray:
        """Riders that hold a switch from conflicting tracks at once (§6.2.2: every rider
        within its range there is part of the others' planning): in rider order, each may
        move only where its footprint stays clear of where the others can still be (their
        envelopes; for the ones decided this cycle, old and new). Safe by induction: a
        brake stays inside its old envelope, which was clear. Returns the riders it braked.
        """
        lo_now, hi_now = (x.tolist() for x in self._envelope())
        turns = {k: self._turn(k) for k in contested}
        seen: dict[int, tuple[float, float]] = {}
        out = []
        for k in sorted(contested):
            if self.mode[k] == IDLE:  # it stands: only in the others' way
                continue
            others = [(j, *seen.get(j, (lo_now[j], hi_now[j]))) for j in sorted(contested[k])]
            key = (lo_now[k], hi_now[k], turns[k], tuple((*o, turns[o[0]]) for o in others))
            cached = self._stretches.get(k)
            if cached is None or cached[0] != key:  # standing riders ask again and again
                cached = self._stretches[k] = (key, self._clear_stretch(k, *key[:2], others))
            scan, room = cached[1]
            _narrow(lines, k, *room)
            low, high = lines[k]
            low, high = max(low, scan[0]), min(high, scan[1])
            if not braking[k] and (hi[k] > high + TOLERANCE or lo[k] < low - TOLERANCE):
                out.append(k)
                self._brake(np.array([k]), nxt, lo, hi)
            seen[k] = (min(lo_now[k], float(lo[k])), max(hi_now[k], float(hi[k])))
        return np.array(out, dtype=np.int64)

    def _clear_stretch(self, k: int, low: float, high: float,
                       others: list[tuple[int, float, float]]
                       ) -> tuple[tuple[float, float], tuple[float, float]]:
        """The stretch of rider ``k``'s way around its envelope [low, high] on which its
        footprint stays clear of the footprints of ``others`` (rider, envelope) anywhere in
        their envelopes: searched ``_CLEAR_SAMPLES`` steps of ``_CLEAR_STEP`` on each side,
        footprints grown by what they can move between two samples. Returns the stretch
        searched and the stretch for planning (infinite on a side found clear to the
        horizon); both are the envelope itself where it is not clear already."""
        route = ascending(self.riders[k].route)
        start, end = route[0].base, route[-1].base + route[-1].track.length
        count, own = _CLEAR_SAMPLES, _sample_count(low, high)
        _, lows, highs = zip(*others, strict=True) if others else ((), (), ())
        q, at = stretch_samples(low, high, start, end, _CLEAR_STEP, count, own,
                                np.array(lows, dtype=float), np.array(highs, dtype=float),
                                np.array([_sample_count(*o[1:]) for o in others],
                                         dtype=np.int64))
        riders = [k, *(o[0] for o in others)]
        legs = [ascending(self.riders[r].route) for r in riders]
        xyc, curvature = self._atlas_of().along_routes(
            np.array([leg.track.index for route in legs for leg in route], dtype=np.int64),
            np.array([leg.base for route in legs for leg in route], dtype=float),
            np.array([0, *accumulate(len(route) for route in legs)], dtype=np.int64), q, at,
            self._tables())
        c = xyc[2]
        hx, hy, radius = np.empty(len(riders)), np.empty(len(riders)), np.empty(len(riders))
        for i, r in enumerate(riders):  # half sides grown by what a footprint can move
            # between two samples: half a step, and the turn of a corner along a curve
            bend = float(curvature[i])
            if not self.oriented[r]:  # c stands where its own commands left it
                c[at[i]:at[i + 1]] = math.radians(self._turn(r))
                bend = 0.0
            half_x, half_y = self.riders[r].half
            margin = 0.5 * _CLEAR_STEP * (1.0 + math.hypot(half_x, half_y) * bend)
            hx[i], hy[i] = half_x + margin, half_y + margin
            radius[i] = math.hypot(half_x + margin, half_y + margin)
        on_envelope, first_f, first_b = stretch_hits(xyc[0], xyc[1], np.cos(c), np.sin(c), at,
                                                     hx, hy, radius, own, count)
        if on_envelope:
            return (low, high), (low, high)
        top = float(q[own + first_f - 1]) if first_f else high
        bottom = float(q[own + count + first_b - 1]) if first_b else low
        return (bottom, top), (bottom if first_b < count else -math.inf,
                               top if first_f < count else math.inf)

    def _turn(self, k: int) -> float:
        """C [deg] of a rider whose c does not follow the track (0 for one whose does)."""
        if self.oriented[k]:
            return 0.0
        return float(self._values[0][self._geometry()[3][k]])

    def _clash(self, k: np.ndarray, end: np.ndarray, switch: np.ndarray, hk: np.ndarray,
               he: np.ndarray, hs: np.ndarray) -> np.ndarray:
        """``_conflicts`` of riders ``k`` with holders ``hk`` at the same switch, remembered
        while the routes stay (the same riders hold and wait at a switch for many cycles);
        the same dictionary keeps what ``_holding`` and ``_zone_lines`` derive from it."""
        key = (k.tobytes(), end.tobytes(), hk.tobytes(), he.tobytes())
        found = self._clashes.get(key)
        if found is None:
            if len(self._clashes) > 64:
                self._clashes.clear()
            found = self._clashes[key] = self._conflicts(k, end, hk, he) & \
                (switch[:, None] == hs[None, :])
        return found

    def _conflicts(self, slots: np.ndarray, ends: np.ndarray, holders: np.ndarray,
                   holder_ends: np.ndarray) -> np.ndarray:
        """Whether each of ``slots`` may meet each of ``holders`` at their switch, a matrix;
        ``ends``: at the end of its track (else at its start). Riders of two tracks meet
        unless one passes the switch onto the other's track where the other is (it keeps its
        gap to it as a pair): at the end of its track, the other's being the next on its
        route, the other at its start (not at the end of a closed one) and not on a route
        back over the seam there (it comes back to the switch and past it onto the loop's
        end, beside the one that would follow it; D-147). Riders of one closed track meet at
        the switch at its seam when one at its end leaves the track there (it turns off
        beside the one just past the seam)."""
        return conflicts(slots, ends, holders, holder_ends, *self._routes)

    def _transitions(self) -> None:
        """Riders past the end of their track's leg go on to the next leg of their route;
        on a route back over a loop's seam, riders below the start of theirs (D-147)."""
        length = self._geometry()[4]
        for k in past_ends(self.p, self.base, length).tolist():
            r = self.riders[k]
            while len(r.route) > 1 and self._passed(k, r.route):
                r.route.pop(0)
                r.track = r.route[0].track
                self._routed(r)
                self.base[k] = r.route[0].base
                self._pairs = None
                self._geo = None

    def _passed(self, k: int, route: list[Leg]) -> bool:
        """Whether rider ``k`` has left the first leg of ``route`` for the second: past its
        end (to 1e-12 mm, as ``past_ends``), or below its start on a route back."""
        s = float(self.p[k] - self.base[k])
        if route[1].base > route[0].base:
            return s >= route[0].track.length - 1e-12
        return s < 0.0

    def _write(self, values: list[np.ndarray]) -> None:
        """x, y (and c) of every moving rider from its track's curve, in one compiled pass
        (``write_setpoints``; a rider at rest holds its rows in the table, ``_hold``)."""
        _, xr, yr, cr, *_ = self._geometry()
        fresh = write_setpoints(self.mode, IDLE, self.p, self.v, self.a, self.base, self.rested,
                                self._routes[0], xr, yr, cr, self.oriented, self.cdeg, *values,
                                self._tables())
        for slot in fresh.tolist():
            self._hold(self.riders[slot], values)
            self.rested[slot] = True

    def _events(self, now: float, values: list[np.ndarray]) -> None:
        """Commands that reached their targets end (Done); riders at rest become idle."""
        for k in ended(self.mode, FOLLOW, self.table.end, self._rows(), now).tolist():
            rider = self.riders[k]
            if rider.halting or abs(self.goal[k] - self.target[k]) <= TOLERANCE:
                self.mode[k] = IDLE
                self.v[k] = self.a[k] = 0.0
                command, rider.command = rider.command, None
                rider.halting = False
                if rider.gear is not None and rider.gear.failed is not None and command:
                    command.reject(*rider.gear.failed)
                rider.gear = None
                if len(rider.route) > 1:  # its pairs and switch relations came from the route
                    rider.route = rider.route[:1]
                    self._routed(rider)
                    self._pairs = self._geo = None
                self._hold(rider, values)
                rider.owner.port.track_finished(command)
            else:
                self.mode[k] = HELD  # queued behind a rider: wait for room
        for k in resting(self.mode, HELD, self.v, self.a).tolist():
            rider = self.riders[k]
            if rider.halting:
                self.mode[k] = IDLE
                command, rider.command = rider.command, None
                rider.halting = False
                if rider.gear is not None and rider.gear.failed is not None and command:
                    command.reject(*rider.gear.failed)  # held by the gap filter meanwhile
                rider.gear = None
                self._hold(rider, values)
                rider.owner.port.track_finished(command)

    def _hold(self, rider: Rider, values: list[np.ndarray]) -> None:
        """A rider at rest: its x, y and c rows hold where it stands (cycles in which no
        rider moves leave the rows to the table). C only where it follows the track: else a
        MoveC may be turning it."""
        for row in (rider.rows if self.oriented[rider.slot] else rider.rows[:2]):
            self.table.install(row, Profile.hold(KinematicState(float(values[0][row]))),
                               self._now)
            values[1][row] = values[2][row] = values[3][row] = 0.0

    def _rows(self) -> np.ndarray:
        return self._geometry()[0]

    def _atlas_of(self) -> Atlas:
        """The atlas of the network's tracks (atlas id: the track's index), built again when
        a track or a table changed (a geometry changes only with the network's version)."""
        network = self.network
        if self._atlas is None or self._atlas_version != network.version:
            if self._atlas is None or not self._atlas.matches(network.tracks):
                self._atlas = Atlas(network.tracks)
            self._atlas_version = network.version
        return self._atlas

    def _tables(self) -> tuple:
        """The atlas's kernel arguments with the tracks' placements of this cycle (parts
        change position only between cycles; ``advance`` forgets them)."""
        if self._cycle_tables is None:
            self._cycle_tables = self._atlas_of().tables(self.network.placed())
        return self._cycle_tables


def backwards(route: list[Leg]) -> bool:
    """Whether ``route`` goes back over the seam of its closed track: its legs descend."""
    return len(route) > 1 and route[1].base < route[0].base


def ahead_legs(route: list[Leg]) -> list[Leg]:
    """The legs of ``route`` ahead on the odometer: all of a route forwards, the current one
    of a route back (its other legs lie behind)."""
    return route[:1] if backwards(route) else route


def ascending(route: list[Leg]) -> list[Leg]:
    """The legs of ``route`` by their base, lowest first (a route back, reversed)."""
    return route[::-1] if backwards(route) else route


def _no_lines() -> tuple[np.ndarray, ...]:
    """No stop lines: (riders, lows, highs)."""
    return np.empty(0, dtype=np.int64), np.empty(0), np.empty(0)


def _lines_dict(lines: tuple[np.ndarray, ...]) -> dict[int, tuple[float, float]]:
    """Stop lines as (riders, lows, highs) arrays to a dict rider: (low, high)."""
    riders, lows, highs = (x.tolist() for x in lines)
    return dict(zip(riders, zip(lows, highs, strict=True), strict=True))


def _lines_arrays(lines: dict[int, tuple[float, float]]) -> tuple[np.ndarray, ...]:
    """``_lines_dict`` back: (riders, lows, highs) in the dict's order."""
    return (np.fromiter(lines, np.int64, len(lines)),
            np.fromiter((b[0] for b in lines.values()), float, len(lines)),
            np.fromiter((b[1] for b in lines.values()), float, len(lines)))


def _narrow(lines: dict[int, tuple[float, float]], k: int, low: float, high: float) -> None:
    """Rider ``k`` stays within [low, high] too."""
    old = lines.get(k, (-math.inf, math.inf))
    lines[k] = (max(old[0], low), min(old[1], high))


def _sample_count(low: float, high: float) -> int:
    """How many odometer positions from ``low`` to ``high`` are no more than ``_CLEAR_STEP``
    apart (``traffic_kernels.stretch_samples`` spaces them evenly)."""
    return max(1, math.ceil((high - low) / _CLEAR_STEP) + 1)


def _hard(u: np.ndarray, b: np.ndarray, dec: np.ndarray, jerk: np.ndarray) -> np.ndarray:
    """Whether a rider moving at ``u`` with ``b`` (both towards its target) brakes harder than
    the deceleration ``dec`` and ``jerk`` of its command take back without turning it round:
    then only its own brake (gap control's, the hardest) stops it without going back."""
    return (b < -dec) | (u + b * np.abs(b) / (2.0 * jerk) < 0.0)


def network_of(system: Any) -> Any:
    """The TrackNetwork of a planar system (made with its first track)."""
    if system.network is None:
        from openmotion.planar.network import TrackNetwork

        system.network = TrackNetwork()
    return system.network


def traffic_of(system: Any) -> Traffic:
    """The movers on the tracks of a planar system. Its compiled loops load (or compile) when
    a cycle first needs each (``traffic_kernels.warm`` loads them all at once)."""
    if system.traffic is None:
        system.traffic = Traffic(network_of(system), system.cycle_time)
        system.traffic.table = system.table
    return system.traffic


def _against(coupling: Any, velocity: float) -> bool:
    """Whether a slave that has not been in sync yet would move at ``velocity`` against its
    ``allowedSlaveSyncDirections`` (§6.1.9: no back oscillation while it synchronises)."""
    if coupling.sync.synced_once:
        return False
    from openmotion.planar.enums import SyncDirections

    return (velocity < 0.0 and coupling.directions is SyncDirections.POSITIVE) or \
        (velocity > 0.0 and coupling.directions is SyncDirections.NEGATIVE)


def _turns_against(coupling: Any, proposal: tuple[float, ...], jerk: float) -> bool:
    """Whether a moving slave that has not been in sync yet would, from ``proposal`` (p, v,
    a), end up moving against its allowed sync direction: already, or because its
    acceleration can no longer be taken away (at ``jerk``) before the velocity crosses 0."""
    return _against(coupling, proposal[1]) or _against(coupling, _released(proposal, jerk))


def _sync_reach(sync: GearSync, now: float, master: tuple[float, float, float, float],
                dt: float, dec: float, jerk: float, low: float, high: float
                ) -> tuple[float, float]:
    """Lowest and highest position the rest of ``sync``'s plan (from ``now``) could take the
    slave to, in sync at its end included: the slave's state each cycle of the plan (the
    sync error's profile plus the coupled position, with the master going on at its present
    velocity) and where it could come to rest from there braking with ``dec`` and ``jerk``,
    as the path-end check in ``_gear_steps`` asks each cycle (a plan longer than
    ``_REACH_SAMPLES`` cycles is sampled that often). Far from ``low`` and ``high`` a cheaper
    bound that lies within them does (no state is sampled)."""
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
    travel = faster * ((push + 2.0 * dec) / jerk + faster / dec)
    if lowest - travel >= low and highest + travel <= high:
        return lowest - travel, highest + travel
    t, p, v, a, j = profile.data
    count = int(max(t[-1] - elapsed, 0.0) / dt) + 2
    step = dt if count <= _REACH_SAMPLES else (t[-1] - elapsed) / (_REACH_SAMPLES - 2)
    times = elapsed + step * np.arange(min(count, _REACH_SAMPLES))
    k_ = np.maximum(np.searchsorted(t, times, side="right") - 1, 0)
    h = times - t[k_]
    ps = p[k_] + h * (v[k_] + h * (a[k_] / 2.0 + h * j[k_] / 6.0)) + cp + cv * (times - elapsed)
    vs = v[k_] + h * (a[k_] + h * j[k_] / 2.0) + cv
    accelerations = a[k_] + h * j[k_]
    n = times.size
    lo, hi = brake_envelope(ps, vs, accelerations, np.full(n, dec), np.full(n, jerk))
    return min(lowest, float(lo.min())), max(highest, float(hi.max()))


def _released(proposal: tuple[float, ...], jerk: float) -> float:
    """The velocity at which a state (p, v, a, ...) comes out when its acceleration is taken
    away as fast as ``jerk`` allows."""
    velocity, acceleration = proposal[1], proposal[2]
    return velocity + acceleration * abs(acceleration) / (2.0 * jerk)
