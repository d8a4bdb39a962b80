"""Movers on tracks: the 1-D motion along a track network and its collision avoidance.

A mover coupled to a track (a *rider*, riders.py) moves along an arc-length coordinate. Its
plan is a 1-D profile on an *odometer* q that runs on along its route: q = base + s, where s
is the arc length on the track it is on and ``base`` is where that track starts on the route.
The odometer stays continuous across track transitions, so a route through a network is one
time-optimal, jerk-limited profile (§6.2.2, §6.2.5).

Every cycle (phase 2, after the planar system evaluated its setpoint table) each rider
proposes its next state: its profile's, a tracking step when it is held, its sync's when it
is geared, or standing still. The gap filter of the CA group (``rail.gap_control``, compiled
for these pairs: ``traffic_kernels.gap_filter``) then makes every rider brake whose proposal
would let it come closer than its gap to the rider ahead of it on its path (§6.1.9, §6.2.2);
the switch rule stops riders short of a switch zone another rider holds (§6.2.2). Then the
odometers are mapped to x, y and (when the orientation follows the track) c, with their
velocities and accelerations, and written into the planar system's setpoint rows.

:class:`Traffic` is the registry of the riders with the arrays the cycle works on, and the
cycle itself (``advance``). It leaves each concern to a collaborator that holds it:

* rider_pairs.py -- each rider with the one ahead on its path, gaps, rooms, the gap filter;
* switch_zones.py -- who holds a switch, stop lines, footprints at a shared switch;
* geared_riders.py -- riders that follow a master (gear-in, followMover);
* routes.py -- MoveOnTrack and Halt along a route, and the passage from leg to leg;
* cycle_tables.py -- what the cycle derives and keeps between cycles, and when it forgets.

Planning (profiles, commands, the rider objects) happens on events; what the cycle asks of
every rider runs in compiled loops (``traffic_kernels``, ``track_atlas``, D-143) that do the
arithmetic of the numpy formulation they replaced, so the motion is the same bit for bit.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.core.errors import CommandRejected
from openmotion.planar.cycle_tables import CycleTables
from openmotion.planar.geared_riders import GearedRiders
from openmotion.planar.rider_pairs import RiderPairs
from openmotion.planar.riders import (
    FOLLOW,
    GEAR,
    HELD,
    IDLE,
    Leg,
    Network,
    Rail,
    Rider,
    ahead_legs,
    backwards,
)
from openmotion.planar.routes import Routes
from openmotion.planar.switch_zones import SwitchZones
from openmotion.planar.traffic_kernels import (
    ended,
    extensions,
    held_plans,
    held_steps,
    proposals,
    resting,
    turning_gaps,
    write_setpoints,
)
from openmotion.rail.braking import brake_envelope, brake_state
from openmotion.rail.gap_control import TOLERANCE, Pairs
from openmotion.trajectory.plan import Limits, plan_position
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.planar.feedback import PlanarCommand

#: the names riding.py, gearing.py and network.py import from here (riders.py holds them)
__all__ = ["Leg", "Rider", "Traffic", "ahead_legs", "backwards", "network_of", "traffic_of"]

_EXTEND = 5.0  #: [mm] a queue end that moved on this far gets a new profile


class Traffic:
    """Every rider of one planar system, in arrays the cycle works on."""

    def __init__(self, network: Network, cycle_time: float) -> None:
        self.network = network
        self.cycle_time = cycle_time
        self.riders: list[Rider] = []
        self.setpoint_table: Any = None  #: the planar system's SegmentTable (``traffic_of``)
        self.now = 0.0  #: the time of the last cycle
        self.values: list[np.ndarray] = []  #: the system's p, v, a, j rows of this cycle
        self.cycle_tables = CycleTables(self)
        self.pairs = RiderPairs(self)
        self.zones = SwitchZones(self)
        self.geared = GearedRiders(self)
        self.routes = Routes(self)
        self._arrays(0)

    def _arrays(self, n: int) -> None:
        self.p, self.v, self.a = np.zeros(n), np.zeros(n), np.zeros(n)
        self.mode = np.zeros(n, dtype=np.int64)
        self.goal = np.zeros(n)  #: where the running profile ends (the target, or a queue)
        #: the command's velocity, acceleration, deceleration and jerk, one row each
        self.limits = np.ones((4, n))
        self.brake_deceleration = np.ones(n)  #: gap control's brake
        self.brake_jerk = np.ones(n)
        self.gap = np.zeros(n)
        self.zone_gap = np.zeros(n)  #: the gap of the switch zones (``Rider.zone_gap``)
        self.base = np.zeros(n)
        self.shift = np.zeros(n)  #: sum of odometer shifts: p - shift is the path coordinate
        self.target = np.zeros(n)  #: odometer target of the command (NaN: geared)
        self.oriented = np.zeros(n, dtype=bool)  #: c follows the track's heading
        self.c = np.zeros(n)  #: c [deg] of the oriented riders, unwrapped
        self.rested = np.zeros(n, dtype=bool)  #: at rest, its x, y, c rows held in the table
        self.halting = np.zeros(n, dtype=bool)  #: ``Rider.halting`` (``set_halting``)
        self.cycle_tables.renew()
        #: per rider, the index of its track and of the next track of its route (-1: none),
        #: kept as they change (``routed``); the geometry takes a copy
        self.track_index = np.zeros(n, dtype=np.int64)
        #: per track index and rider: the track is its own or on its route (``routed``),
        #: so a track's operation mode is one count over a contiguous row (``riders_on``:
        #: every MoveOnTrack asks it of each track of its route)
        self._use = np.zeros((max(1, len(getattr(self.network, "tracks", ()))), n), dtype=bool)
        self._uses: dict[int, set[int]] = {}  #: per rider, the track indices set in ``_use``
        self.next_index = np.full(n, -1, dtype=np.int64)
        #: per rider, whether its route goes back over the seam of its closed track (D-147)
        self.back = np.zeros(n, dtype=bool)

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
        its gear-in ends in error (``GearedRiders.master_gone``, D-145). ``now``: the time
        of the last cycle (the traffic's last one when not given)."""
        now = self.now if now is None else now
        self.abort(rider)
        for r in self.riders:
            if r is not rider and r.gear is not None and r.gear.master is rider:
                self.geared.master_gone(r, now)
        self._keep_c()
        old = [(r, *self._state(r)) for r in self.riders if r is not rider]
        self.riders.remove(rider)
        self._rebuild(old)
        rider.slot = -1

    def _keep_c(self) -> None:
        """Before the arrays are rebuilt: each rider keeps its c and target."""
        for r in self.riders:
            r.c, r.target = float(self.c[r.slot]), float(self.target[r.slot])
            r.zone_gap = float(self.zone_gap[r.slot])

    def _state(self, r: Rider) -> tuple[float, float, float, int, float, float]:
        k = r.slot
        return (float(self.p[k]), float(self.v[k]), float(self.a[k]), int(self.mode[k]),
                float(self.goal[k]), float(self.shift[k]))

    def _rebuild(self, states: list[tuple]) -> None:
        """New arrays in rider order (a coupling or uncoupling: rare). What is kept per slot
        across cycles (the stop lines) moves with its rider; a leaving rider's goes."""
        self.zones.renumber({r.slot: k for k, (r, *_) in enumerate(states) if r.slot >= 0})
        self._arrays(len(states))
        for k, (r, p, v, a, mode, goal, shift) in enumerate(states):
            r.slot = k
            self.p[k], self.v[k], self.a[k], self.mode[k], self.goal[k] = p, v, a, mode, goal
            self.shift[k] = shift
            self.base[k] = r.route[0].base if r.route else 0.0
            self.load(r)
            self.routed(r)
        self.cycle_tables.forget()

    def routed(self, r: Rider) -> None:
        """``r``'s track or route changed: its ``track_index``, ``next_index`` (the track it
        goes on to from the end of its own; none on a route back) and ``back``."""
        back = backwards(r.route)
        k = r.slot
        self.cycle_tables.forget_look(k)
        self.track_index[k] = r.track.index
        used = self._uses.get(k)
        if used is not None:
            for index in used:
                self._use[index, k] = False
        used = {r.track.index, *(leg.track.index for leg in r.route)}
        self._uses[k] = used
        for index in used:
            if index >= self._use.shape[0]:
                self._widen_use(index + 1)
            self._use[index, k] = True
        self.next_index[r.slot] = r.route[1].track.index if len(r.route) > 1 and not back \
            else -1
        self.back[r.slot] = back

    def _widen_use(self, count: int) -> None:
        """Room in ``_use`` for ``count`` tracks (a track added after the riders came)."""
        wider = np.zeros((count, self._use.shape[1]), dtype=bool)
        wider[:self._use.shape[0]] = self._use
        self._use = wider

    def riders_on(self, track: Rail, moving: bool) -> int:
        """How many riders use ``track``: with ``moving`` those that move on it or have it on
        the route ahead (§4.3: the track is Moving), else also those standing on it (a
        halted rider's unused legs do not count)."""
        index = track.index
        routed = self._use[index] & (self.mode != IDLE) if index < self._use.shape[0] \
            else np.zeros(self.mode.size, dtype=bool)
        if moving:
            return int(np.count_nonzero(routed))
        return int(np.count_nonzero(routed | (self.track_index == index)))

    def riders_at(self, track: Rail) -> int:
        """How many riders are on ``track``."""
        return int(np.count_nonzero(self.track_index == track.index))

    def load(self, r: Rider) -> None:
        """``r``'s command, brake, gaps, target and orientation into the arrays."""
        k = r.slot
        limits = r.limits
        if limits is not None:
            self.limits[:, k] = (limits.velocity, limits.acceleration, limits.deceleration,
                                 limits.jerk)
        self.brake_deceleration[k], self.brake_jerk[k] = r.brake
        self.gap[k] = r.gap
        r.zone_gap = r.gap if math.isnan(r.zone_gap) else min(r.zone_gap, r.gap)
        self.zone_gap[k] = r.zone_gap
        self.zones.widening |= r.zone_gap < r.gap
        self.target[k] = r.target
        self.oriented[k], self.c[k] = r.oriented, r.c
        self.halting[k] = r.halting

    def set_halting(self, rider: Rider, halting: bool) -> None:
        """``rider`` stops to rest and its command ends there (a Halt, a geared rider
        stopping), or not; the array lets the cycle find the halting riders at rest without
        visiting every held one."""
        rider.halting = halting
        self.halting[rider.slot] = halting

    def orient(self, rider: Rider, oriented: bool, c: float | None = None) -> None:
        """C follows the track (``oriented``) or its own commands; ``c`` [deg] where it is."""
        rider.oriented = oriented
        if c is not None:
            rider.c = c
        self.oriented[rider.slot] = oriented
        self.c[rider.slot] = rider.c

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
        """MoveOnTrack along ``route`` to the odometer ``target`` (``Routes.ride``)."""
        self.routes.ride(rider, route, target, limits, gap, command, now)

    def halt(self, rider: Rider, limits: Limits, command: PlanarCommand | None,
             now: float) -> None:
        """Stop on the track with ``limits`` (``Routes.halt``)."""
        self.routes.halt(rider, limits, command, now)

    def gear(self, rider: Rider, route: list[Leg], coupling: Any, gap: float,
             command: PlanarCommand) -> None:
        """Start a gear-in along ``route`` (``GearedRiders.start``)."""
        self.geared.start(rider, route, coupling, gap, command)

    def abort(self, rider: Rider) -> None:
        """``rider``'s command ends (Aborted) and it is no longer geared: another command
        takes over, or it leaves its track."""
        rider.gear = None
        if rider.command is not None:
            rider.command.abort()
            rider.command = None

    def rebase(self, k: int, shift: float) -> None:
        """Rider ``k``'s odometer gets a new origin, ``shift`` further on (a new route)."""
        if shift:
            self.shift[k] += shift
            self.p[k] += shift
            self.goal[k] += shift
            self.target[k] += shift
            self.base[k] += shift
            self.cycle_tables.forget_motion()

    def follow(self, rider: Rider, profile: Profile, goal: float, now: float) -> None:
        """``rider`` follows ``profile`` (starting at ``now``) to ``goal``."""
        self.setpoint_table.install(rider.row, profile, now)
        self.mode[rider.slot] = FOLLOW
        self.goal[rider.slot] = goal
        self.cycle_tables.forget()

    def follow_from_last_cycle(self, rider: Rider, profile: Profile, goal: float,
                               proposal: list[np.ndarray]) -> None:
        """Within the cycle: ``rider`` follows ``profile`` from the last cycle's state to
        ``goal``, and proposes its step of this cycle."""
        k = rider.slot
        self.setpoint_table.install(rider.row, profile, self.now - self.cycle_time)
        self.mode[k] = FOLLOW
        self.goal[k] = goal
        for field_, value in zip(proposal, profile.at(self.cycle_time), strict=True):
            field_[k] = value

    # -- the cycle -------------------------------------------------------------------------------

    def advance(self, now: float, values: list[np.ndarray]) -> None:
        """Phase 2: proposals, the gap filter, the switch zones, transitions, setpoints.
        ``values`` are the system's p, v, a, j rows, evaluated for ``now``."""
        n = len(self.riders)
        if n == 0 or not (self.mode != IDLE).any():
            return
        tables = self.cycle_tables
        self.now, self.values = now, values
        tables.new_cycle()
        self.network.refresh()
        if tables.network_version != self.network.version:  # a part moved, a track changed:
            tables.network_version = self.network.version  # switches, ranges, ways on
            tables.forget()
        *start, going, queued = proposals(self.mode, FOLLOW, IDLE, self._rows(), self.p,
                                          self.v, self.a, self.brake_jerk, self.goal,
                                          self.target, *values)
        proposal, known = list(start[:4]), tuple(start[4:])
        self.zones.holding()
        pairs = self.pairs.merging(self.pairs.pair_list(going), going)
        if queued.size:
            self._extend_queued(queued, proposal, pairs)
        held = np.flatnonzero(self.mode == HELD)
        if held.size:
            self._track_held(held, proposal, known, pairs)
        geared = np.flatnonzero(self.mode == GEAR)
        geared_any = bool(geared.size)  # nothing turns geared within the cycle
        if geared_any:
            self.geared.steps(geared, now, proposal, pairs)
        turning, pairs.gap = turning_gaps(proposal[1], proposal[2], self.brake_jerk, going,
                                          pairs.succ, pairs.pred, self.mode, IDLE,
                                          self.target, self.p, self.gap)  # and the gaps
        braking, lo, hi = self.pairs.filter(proposal, pairs, known)
        kept = self.pairs.no_turning_back(pairs, turning & ~braking, proposal, lo, hi)
        braking[kept] = True
        kept = np.concatenate((kept, self.zones.keep_out(proposal, lo, hi, braking)))
        if kept.size:  # their followers may have to brake now too
            more, lo, hi = self.pairs.filter(proposal, pairs, (np.ones(n, dtype=bool), lo, hi))
            braking |= more
            braking[kept] = True
        self.p, self.v, self.a = proposal[0], proposal[1], proposal[2]
        tables.envelopes = (lo, hi)
        self.mode[braking & (self.mode == FOLLOW)] = HELD
        if geared_any:
            self.geared.after_filter(now, braking)
        self.routes.transitions()
        self._write(values)
        self._events(now, values)

    def brake(self, slots: np.ndarray, proposal: list[np.ndarray], lo: np.ndarray,
              hi: np.ndarray) -> None:
        """``slots`` brake this cycle instead: their step and its envelope."""
        if not slots.size:
            return
        step = brake_state(self.p[slots], self.v[slots], self.a[slots],
                           self.brake_deceleration[slots], self.brake_jerk[slots],
                           self.cycle_time)
        for field_, value in zip(proposal, step, strict=True):
            field_[slots] = value
        lo[slots], hi[slots] = brake_envelope(proposal[0][slots], proposal[1][slots],
                                              proposal[2][slots],
                                              self.brake_deceleration[slots],
                                              self.brake_jerk[slots])

    def _track_held(self, held: np.ndarray, proposal: list[np.ndarray],
                    known: tuple[np.ndarray, np.ndarray, np.ndarray], pairs: Pairs) -> None:
        """Held riders: a fresh profile once the way to the target (or to the end of the
        queue) is clear; else the most progressive constant-jerk step that keeps clear of the
        neighbours as they are now (``rail.kernels.candidates``), else a brake."""
        room_lo, room_hi = self.pairs.room(pairs)
        ahead, behind = self.pairs.neighbours(pairs)
        sign, goal, fits, rest = held_plans(held, self.p, self.v, self.a, self.target,
                                            self.limits, room_lo, room_hi, self.mode, IDLE,
                                            ahead, behind, *proposal, *known)
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
            self.follow_from_last_cycle(rider, profile, goal[i], proposal)
        if rest.any():
            lo, hi = self.cycle_tables.envelope()
            held_steps(held, sign, rest, self.cycle_time, self.p, self.v, self.a, self.target,
                       self.limits, self.brake_deceleration, self.brake_jerk, room_lo,
                       room_hi, lo, hi, *proposal, *known)

    def _extend_queued(self, queued: np.ndarray, proposal: list[np.ndarray],
                       pairs: Pairs) -> None:
        """Riders following a profile to the end of a queue get a new one, further on, once
        the room ahead has grown by more than ``_EXTEND`` (no stop and go behind a mover that
        drives away)."""
        reach, grow = extensions(queued, self.target, self.goal, *self.pairs.room(pairs),
                                 self.pairs.neighbours(pairs)[0], self.v, self.a, self.mode,
                                 HELD, _EXTEND)
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
            self.follow_from_last_cycle(rider, profile, reach[i], proposal)

    def _write(self, values: list[np.ndarray]) -> None:
        """x, y (and c) of every moving rider from its track's curve, in one compiled pass
        (``write_setpoints``; a rider at rest holds its rows in the table, ``_hold``)."""
        tables = self.cycle_tables
        geometry = tables.geometry_now()
        fresh = write_setpoints(self.mode, IDLE, self.p, self.v, self.a, self.base,
                                self.rested, tables.route_arrays[0], geometry.x_rows,
                                geometry.y_rows, geometry.c_rows, self.oriented, self.c,
                                *values, tables.placed_tables())
        for slot in fresh.tolist():
            self._hold(self.riders[slot], values)
            self.rested[slot] = True

    def _events(self, now: float, values: list[np.ndarray]) -> None:
        """Commands that reached their targets end (Done); riders at rest become idle."""
        for k in ended(self.mode, FOLLOW, self.setpoint_table.end, self._rows(), now).tolist():
            rider = self.riders[k]
            if rider.halting or abs(self.goal[k] - self.target[k]) <= TOLERANCE:
                self.mode[k] = IDLE
                self.v[k] = self.a[k] = 0.0
                command, rider.command = rider.command, None
                self.set_halting(rider, False)
                if rider.gear is not None and rider.gear.failed is not None and command:
                    command.reject(*rider.gear.failed)
                rider.gear = None
                if len(rider.route) > 1:  # its pairs and switch relations came from the route
                    rider.route = rider.route[:1]
                    self.routed(rider)
                    self.cycle_tables.forget_routes()
                self._hold(rider, values)
                rider.owner.port.track_finished(command)
            else:
                self.mode[k] = HELD  # queued behind a rider: wait for room
        resting_now = resting(self.mode, HELD, self.v, self.a)
        for k in resting_now[self.halting[resting_now]].tolist():
            rider = self.riders[k]
            if rider.halting:
                self.mode[k] = IDLE
                command, rider.command = rider.command, None
                self.set_halting(rider, False)
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
            self.setpoint_table.install(row, Profile.hold(KinematicState(float(values[0][row]))),
                                        self.now)
            values[1][row] = values[2][row] = values[3][row] = 0.0

    def _rows(self) -> np.ndarray:
        return self.cycle_tables.geometry_now().rows


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
        system.traffic.setpoint_table = system.table
    return system.traffic
