"""MC_GearInPosCA: a CA mover synchronises to a master and then follows it (§9.1.1.1.4).

In sync the slave's setpoint is ``SlaveSyncPosition + ratio * (master - MasterSyncPosition)``
on the master's *set* values, in the same cycle (no offset, V3.2.27). Synchronising is planned
in the master's frame: the *sync error* ``e = slave - coupled(master)`` is brought to rest at
0 by a time-optimal profile (ruckig), and the slave's setpoint is ``coupled(master) + e(t)``.
The strategies differ in when that profile starts and how fast it is (§9.4.1.5):

* EARLY: at once (after MasterStartDistance), full dynamics; in sync as early as possible.
* LATE: as late as possible: when the full-dynamics profile just fits before the master
  reaches MasterSyncPosition. A master that accelerates after StartSync is an error.
* SLOW: at once, stretched so that it ends when the master reaches MasterSyncPosition.

Gap control has priority: when it brakes a slave in sync, InSync falls and the slave
synchronises again (EARLY, with the AfterSync dynamics). The command never ends Done.

The restrictions of ST_GearInPosCAOptions (§9.1.2.1) hold for the profile the slave drives,
not for the unrestricted one (D-204): when the strategy's profile breaks one, the slave
*holds* (brakes to rest with its sync dynamics, StartSync TRUE) and tries again every cycle,
so that it syncs as soon as a compliant profile exists ("wait, then sync forwards"). Only
when holding cannot lead to one is the sync impossible (SYNC_FAILED).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.rail.braking import brake_envelope, brake_state
from openmotion.rail.enums import MasterSignalCorrection, SyncStrategy
from openmotion.rail.tolerances import (
    PROFILE_END_TOLERANCE,
    RELATIVE_TOLERANCE,
    SAMPLE_TIME_TOLERANCE,
    SIGNAL_TOLERANCE,
)
from openmotion.trajectory.plan import Limits, plan_position, plan_position_in, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

#: WAITING: before the sync phase (MasterStartDistance, Late's start); HOLDING: in the sync
#: phase, at rest until a profile that keeps the options' restrictions exists (D-204)
WAITING, SYNCING, IN_SYNC, HOLDING = 0, 1, 2, 3
_ROUNDING = 64.0 * sys.float_info.epsilon  #: relative rounding of a second difference
_AT_REST = 1e9  #: [s] far enough into any brake to be at rest


@dataclass
class GearSync:
    """The coupling of one slave: its parameters and where the synchronisation stands."""

    master_row: int
    ratio: float
    master_sync_position: float
    slave_sync_position: float
    strategy: SyncStrategy
    start_distance: float | None  #: None = MC_IGNORE: start at once
    limits: Limits  #: sync phase
    after_sync: Limits  #: re-synchronising after gap control held the slave
    override_restrictions: bool = False
    undershoot_allowed: bool = True  #: MasterVelocityUndershootAllowed
    overshoot_allowed: bool = True  #: MasterVelocityOvershootAllowed
    reversal_allowed: bool = True  #: DirectionReversalAllowed
    minimal_slave_position: float | None = None  #: MinimalSlavePosition (None: MC_IGNORE)
    #: MasterSignalCorrection (D-205); NONE: the master's set values as they are
    signal_correction: MasterSignalCorrection = MasterSignalCorrection.NONE
    master_max_jerk: float = math.inf  #: bounds what the master can do within a cycle
    axis_limits: Limits | None = None  #: the slave's maxima: a stretched sync stays within
    phase: int = WAITING
    synced_once: bool = False
    profile: Profile | None = None  #: the sync error over time, from ``started``
    started: float = 0.0
    start_sync: bool = False  #: MC_GearInPosCA.StartSync
    in_sync: bool = False  #: MC_GearInPosCA.InSync
    error: tuple[ErrorId, str] | None = None
    _previous_master: tuple[float, float, float, float] | None = None
    _planned_for: float = 0.0  #: master velocity the sync was timed for
    _stretch_from: float | None = None  #: master position where a stretched profile starts
    _hold_limits: Limits | None = None  #: the dynamics of the sync a hold waits for
    _no_turn: bool = False  #: held by gap control: the re-sync must not turn the slave round
    #: (time, the master's set values as reported) of the last two cycles (D-205)
    _history: tuple[tuple[float, tuple[float, float, float, float]], ...] = ()
    _signal: tuple[float, tuple[float, float, float, float]] | None = None  #: (now, signal)

    def coupled(self, mp: float, mv: float, ma: float, mj: float
                ) -> tuple[float, float, float, float]:
        r = self.ratio
        return (self.slave_sync_position + r * (mp - self.master_sync_position), r * mv,
                r * ma, r * mj)

    def step(self, now: float, slave: tuple[float, float, float],
             master: tuple[float, float, float, float], cycle_time: float
             ) -> tuple[float, float, float, float] | None:
        """The slave's proposal for this cycle; None = stand (waiting or holding)."""
        if self.error is not None:
            return None
        master = self.master_signal(now, master, cycle_time)
        mp, mv, ma, mj = master
        cp, cv, ca, cj = self.coupled(mp, mv, ma, mj)
        if self.phase == WAITING and self._may_start(now, slave, master, cycle_time):
            self._begin(now, cycle_time, slave, self._previous_master, master, self.limits)
            self._planned_for = mv
        elif self.phase == HOLDING:
            self._begin(now, cycle_time, slave, self._previous_master, master,
                        self._hold_limits or self.limits, early=self._no_turn)
            self._planned_for = mv
        if self.phase in (WAITING, HOLDING):
            self._previous_master = master
            return None
        if self.phase == SYNCING:
            return self._syncing(now, slave, master, cycle_time)
        self._previous_master = master
        return cp, cv, ca, cj

    def _syncing(self, now: float, slave: tuple[float, float, float],
                 master: tuple[float, float, float, float], cycle_time: float
                 ) -> tuple[float, float, float, float] | None:
        """A step of the sync profile: the coupled motion plus the sync error."""
        mp, mv, ma, mj = master
        stretched = self._stretch_from is not None
        if (self.strategy is SyncStrategy.LATE and not self.synced_once
                and not self.override_restrictions
                and abs(ma) > RELATIVE_TOLERANCE * max(1.0, abs(mv))):
            self.error = (ErrorId.SYNC_FAILED, "the master accelerated after StartSync "
                          "(SyncStrategy Late)")
            return None
        if (self.strategy is SyncStrategy.SLOW and not self.synced_once and not stretched
                and abs(mv - self._planned_for) > RELATIVE_TOLERANCE * max(1.0, abs(mv))):
            # the master changed speed: plan the rest again to arrive in time (§9.4.1.5)
            self._begin(now, cycle_time, slave, self._previous_master, master, self.limits)
            self._planned_for = mv
        elif stretched:
            error, at = self._stretched(master)
            if error is None:  # beyond the slave's maxima: within them from here on
                assert self.axis_limits is not None
                self._begin(now, cycle_time, slave, self._previous_master, master,
                            self.axis_limits, early=True)
        if self.phase == HOLDING:
            self._previous_master = master
            return None
        assert self.profile is not None
        if self._stretch_from is None:
            at = now - self.started
            error = self.profile.at(at)
        self._previous_master = master
        cp, cv, ca, cj = self.coupled(mp, mv, ma, mj)
        if at >= self.profile.duration - PROFILE_END_TOLERANCE:
            self.phase, self.start_sync, self.in_sync = IN_SYNC, False, True
            self.synced_once = True
            self._stretch_from = None
            return cp, cv, ca, cj
        ep, ev, ea, ej = error
        return cp + ep, cv + ev, ca + ea, cj + ej

    def held(self, now: float, slave: tuple[float, float, float],
             master: tuple[float, float, float, float]) -> None:
        """Gap control braked the slave: synchronise again from where it is, as fast as it
        may: after the first sync with the AfterSync dynamics and no restrictions (they
        shape only the sync phase, §9.1.2.1); before it with the sync dynamics and the
        restrictions (D-204). A re-sync that would turn the braked slave round (gap control
        brakes harder than these dynamics can let go) waits: the slave brakes on to rest,
        or until a re-sync that does not turn it fits (D-206)."""
        if self.phase in (WAITING, HOLDING) or self.error is not None:
            return
        master = self.master_signal(now, master, 0.0)
        self.in_sync = False
        self._stretch_from = None
        self._hold_limits = self.after_sync if self.synced_once else self.limits
        self._no_turn = True
        try:
            self._begin(now, 0.0, slave, master, master, self._hold_limits, early=True)
        except CommandRejected as rejected:
            self.error = (rejected.error_id, rejected.message)

    def prime(self, master_then: tuple[float, float, float, float]) -> None:
        """The master's set values of the cycle before the first step (position, velocity,
        acceleration, jerk). The sync is planned from the slave's state of that cycle, so it
        needs the master's of the same cycle; without a prime the first step takes the
        master's values one cycle back along its jerk (an axis, evaluated before the group)."""
        self._previous_master = master_then

    def master_signal(self, now: float, master: tuple[float, float, float, float],
                      cycle_time: float) -> tuple[float, float, float, float]:
        """The master's set values as the coupling reads them (§9.1.2.6, D-205).

        AUTO corrects a signal whose velocity and acceleration do not fit its positions
        (a master fed from outside, MC_ExtSetPointGenFeed): the position change since the
        last cycle must be the one the last reported state leads to, within what the
        master's maximum jerk can change in one cycle; if not, velocity and acceleration
        are taken from the last three positions (backward differences, jerk 0). The
        position itself is never changed, so in sync the slave keeps the exact relation.
        NONE reads the values as they are. Read once per cycle (``now``)."""
        if self._signal is not None and self._signal[0] == now:
            return self._signal[1]
        signal, history, expected = master, [], now - cycle_time
        for then, values in reversed(self._history):  # samples of the cycles just before
            if cycle_time <= 0.0 or abs(then - expected) > SAMPLE_TIME_TOLERANCE * cycle_time:
                break
            history.insert(0, values)
            expected -= cycle_time
        if self.signal_correction is MasterSignalCorrection.AUTO and history:
            signal = self._corrected(master, history, cycle_time)
        self._history = (self._history + ((now, master),))[-2:]
        self._signal = (now, signal)
        return signal

    def seed(self, now: float, master: tuple[float, float, float, float]) -> None:
        """The master's set values when the command was given (``now``: the last cycle), so
        that its first step can already check the signal (D-205)."""
        self._history = ((now, master),)

    def _corrected(self, master: tuple[float, float, float, float],
                   history: list[tuple[float, float, float, float]], cycle_time: float
                   ) -> tuple[float, float, float, float]:
        """``master``, or its velocity and acceleration from its positions (D-205)."""
        p = master[0]
        p1, v1, a1, j1 = history[-1]  # as reported in the last cycle
        predicted = p1 + cycle_time * (v1 + cycle_time * (a1 / 2.0 + cycle_time * j1 / 6.0))
        bound = self.master_max_jerk * cycle_time ** 3 / 3.0  # a jerk swing of ±max within a cycle
        slack = SIGNAL_TOLERANCE * max(1.0, abs(p), abs(p - p1))
        if abs(p - predicted) <= bound + slack:
            return master
        if len(history) < 2:
            return p, (p - p1) / cycle_time, 0.0, 0.0
        p2 = history[-2][0]
        acceleration = (p - 2.0 * p1 + p2) / (cycle_time * cycle_time)
        # the rounding of three positions is no acceleration (Late would take it for one)
        rounding = _ROUNDING * max(1.0, abs(p), abs(p1), abs(p2)) / (cycle_time * cycle_time)
        if abs(acceleration) <= rounding:
            acceleration = 0.0
        return p, (3.0 * p - 4.0 * p1 + p2) / (2.0 * cycle_time), acceleration, 0.0

    def _may_start(self, now: float, slave: tuple[float, float, float],
                   master: tuple[float, float, float, float], cycle_time: float) -> bool:
        if self._previous_master is None:  # the master of the slave's cycle: no jump back
            mp, mv, ma, mj = master
            step = cycle_time  # one cycle back along the master's cubic
            self._previous_master = (
                mp - step * (mv - step * (ma / 2.0 - step * mj / 6.0)),
                mv - step * (ma - step * mj / 2.0), ma - step * mj, mj)
        mp, mv = master[0], master[1]
        if self.start_distance is not None:
            threshold = self.master_sync_position - self.start_distance
            if (self.start_distance > 0 and mp < threshold) or \
                    (self.start_distance < 0 and mp > threshold):
                return False
        if self.strategy is not SyncStrategy.LATE or mv == 0.0:
            return True
        remaining = (self.master_sync_position - mp) / mv  # time until the master is there
        if remaining <= 0.0:
            return True
        try:
            lead, main = self._error_profiles(slave, master, self.limits)
        except CommandRejected:
            return True
        needed = main.duration + (0.0 if lead is None else lead.duration)
        return needed >= remaining - cycle_time

    def _begin(self, now: float, cycle_time: float, slave: tuple[float, float, float],
               master_then: tuple[float, float, float, float],
               master_now: tuple[float, float, float, float], limits: Limits,
               early: bool = False) -> None:
        """Start (or go on with) the sync phase: the strategy's profile if it keeps the
        options' restrictions; else hold and try again next cycle; SYNC_FAILED when holding
        cannot lead to a compliant profile either (§9.1.2.1, D-204)."""
        broken = self._plan(now, cycle_time, slave, master_then, master_now, limits, early)
        if broken is None:
            if not (self._no_turn and self._turns(slave, master_then)):
                self._no_turn = False
                return
        else:
            hopeless = self._hold_breaks(slave, master_now, limits)
            if hopeless is not None:
                raise CommandRejected(ErrorId.SYNC_FAILED, f"{broken}, and {hopeless}")
        self.phase, self.start_sync, self.profile = HOLDING, True, None
        self._hold_limits = limits
        self._stretch_from = None

    def _turns(self, slave: tuple[float, float, float],
               master: tuple[float, float, float, float]) -> bool:
        """Whether the planned profile turns the moving slave round."""
        assert self.profile is not None
        _, cv, _, _ = self.coupled(*master)
        v = slave[1]
        low, high = self.profile.velocity_extrema()
        tolerance = RELATIVE_TOLERANCE * max(1.0, abs(v), self.limits.velocity)
        return (v > tolerance and cv + low < -tolerance) or \
            (v < -tolerance and cv + high > tolerance)

    def _plan(self, now: float, cycle_time: float, slave: tuple[float, float, float],
              master_then: tuple[float, float, float, float],
              master_now: tuple[float, float, float, float], limits: Limits,
              early: bool = False) -> str | None:
        """Plan the sync error from the last sample (``now - cycle_time``, where ``slave`` and
        ``master_then`` are), timed with the master as it is ``now``. Returns the restriction
        the plan breaks (before the first sync), or None once it is the slave's profile."""
        mp, mv = master_now[0], master_now[1]
        remaining = (self.master_sync_position - mp) / mv + cycle_time if mv else math.inf
        timed = not early and self.strategy is not SyncStrategy.EARLY and \
            math.isfinite(remaining) and remaining > 0.0
        lead, main = self._error_profiles(slave, master_then, limits,
                                          remaining if timed else None)
        profile = main if lead is None else Profile.concatenate(lead, main)
        broken = None if self.synced_once else self._breaks(
            main, profile, slave, master_then, self._direction(slave, master_now))
        if broken is not None:
            return broken
        self.phase, self.start_sync, self.started = SYNCING, True, now - cycle_time
        self.profile = profile
        self._stretch_from = None
        if timed and self.override_restrictions and mv != 0.0 and not self.synced_once \
                and self.axis_limits is not None:
            self._stretch_from = master_then[0]  # follows the master's travel (§9.1.2.1)
        return None

    def _stretched(self, master: tuple[float, float, float, float]
                   ) -> tuple[tuple[float, float, float, float] | None, float]:
        """OverrideSlaveDynamicRestrictions (§9.1.2.1, D-206): the planned profile runs on
        the master's travel, not on time, so a faster master compresses it and a slower one
        stretches it; the slave is still in sync when the master is at MasterSyncPosition.
        (None, _) when the compressed profile would pass the slave's maxima."""
        assert self.profile is not None and self._stretch_from is not None
        mp, mv, ma, mj = master
        planned = self._planned_for
        at = max((mp - self._stretch_from) / planned, 0.0)
        s, ds, dds = mv / planned, ma / planned, mj / planned  # dτ/dt and its derivatives
        ep, e1, e2, e3 = self.profile.at(at)
        ev = e1 * s
        ea = e2 * s * s + e1 * ds
        ej = e3 * s ** 3 + 3.0 * e2 * s * ds + e1 * dds
        maxima = self.axis_limits
        assert maxima is not None
        _, cv, ca, _ = self.coupled(*master)
        v, a = cv + ev, ca + ea
        tolerance = 1.0 + RELATIVE_TOLERANCE
        if abs(v) > maxima.velocity * tolerance or \
                a > maxima.acceleration * tolerance or -a > maxima.deceleration * tolerance:
            return None, at
        return (ep, ev, ea, ej), at

    def _direction(self, slave: tuple[float, float, float],
                   master: tuple[float, float, float, float]) -> float:
        """The sync direction of DirectionReversalAllowed (§9.1.2.1): the sign of the slave's
        velocity at the sync point, ratio × the master's velocity there. The master's is
        foreseen from its present state: the way it moves, else the way it accelerates,
        else the way to MasterSyncPosition; with none of these, the way the slave goes."""
        mp, mv, ma, _ = master
        cp, _, _, _ = self.coupled(*master)
        for value in (self.ratio * mv, self.ratio * ma,
                      self.ratio * (self.master_sync_position - mp), slave[1], cp - slave[0]):
            if value != 0.0:
                return 1.0 if value > 0.0 else -1.0
        return 1.0

    def _breaks(self, main: Profile, profile: Profile, slave: tuple[float, float, float],
                master: tuple[float, float, float, float], direction: float) -> str | None:
        """The first restriction of ST_GearInPosCAOptions the planned profile breaks, with
        the master at its present velocity, or None (§9.1.2.1). Under- and overshoot are
        judged after the lead that first brings the slave to the master's velocity
        (``main``); reversal and MinimalSlavePosition on all of it."""
        cp, cv, _, _ = self.coupled(*master)
        tolerance = RELATIVE_TOLERANCE * max(1.0, abs(cv), self.limits.velocity)
        low, high = main.velocity_extrema()  # of the sync error's velocity
        sign = 1.0 if cv >= 0.0 else -1.0
        error_low, error_high = (low, high) if sign > 0 else (-high, -low)
        if not self.undershoot_allowed and error_low < -tolerance:
            return ("the slave would be slower than the master "
                    "(MasterVelocityUndershootAllowed FALSE)")
        if not self.overshoot_allowed and error_high > tolerance:
            return ("the slave would be faster than the master "
                    "(MasterVelocityOvershootAllowed FALSE)")
        low, high = profile.velocity_extrema()
        along = cv + low if direction > 0 else -(cv + high)  # the slave's lowest, along it
        if not self.reversal_allowed and along < -tolerance:
            return "the slave would move against the sync direction (DirectionReversalAllowed " \
                "FALSE)"
        if self.minimal_slave_position is not None:
            data = profile.data.copy()  # the slave itself: error + coupled motion
            data[1] += cp + cv * data[0]
            data[2] += cv
            lowest, _ = Profile.from_data(data).position_extrema()
            if lowest < self.minimal_slave_position - tolerance:
                return f"the slave would pass below MinimalSlavePosition " \
                    f"{self.minimal_slave_position:g}"
        return None

    def _hold_breaks(self, slave: tuple[float, float, float],
                     master: tuple[float, float, float, float], limits: Limits) -> str | None:
        """Why holding (braking to rest with the sync dynamics, then waiting) cannot lead
        to a compliant sync, or None (D-204). Holding helps only while the coupled position
        lies behind the slave's rest point in the sync direction, so that it comes nearer;
        a slave that moves against the sync direction, or stops below MinimalSlavePosition,
        breaks the restriction already."""
        cp, cv, _, _ = self.coupled(*master)
        p, v, a = slave
        tolerance = RELATIVE_TOLERANCE * max(1.0, abs(cv), limits.velocity)
        if not self.undershoot_allowed and abs(cv) > tolerance:
            return "holding would leave it slower than the master"
        direction = self._direction(slave, master)
        if not self.reversal_allowed and v * direction < -tolerance:
            return "it moves against the sync direction already"
        state = (np.array([p]), np.array([v]), np.array([a]),
                 np.array([limits.deceleration]), np.array([limits.jerk]))
        lo, _ = brake_envelope(*state)
        stop = float(brake_state(*state, _AT_REST)[0][0])
        if self.minimal_slave_position is not None and \
                float(lo[0]) < self.minimal_slave_position - tolerance:
            return "it cannot stop above MinimalSlavePosition"
        if (cp - stop) * direction >= 0.0:
            return "waiting cannot help (the coupled position does not come nearer)"
        return None

    def _error_profiles(self, slave: tuple[float, float, float],
                        master: tuple[float, float, float, float], limits: Limits,
                        duration: float | None = None) -> tuple[Profile | None, Profile]:
        """The sync error brought to rest at 0: time-optimal, or lasting ``duration`` (so
        that the slave is in sync exactly when the master reaches MasterSyncPosition).

        If the options forbid the slave to be slower (faster) than the master and it is so
        now, a lead first brings it to the master's velocity as fast as the sync dynamics
        allow (§9.1.2.1); the sync profile starts from there."""
        cp, cv, ca, _ = self.coupled(*master)
        e = KinematicState(slave[0] - cp, slave[1] - cv, slave[2] - ca)
        relative = Limits(max(limits.velocity - abs(cv), 1e-3 * limits.velocity),
                          limits.acceleration, limits.deceleration, limits.jerk)
        lead = None
        toward = e.velocity if cv >= 0.0 else -e.velocity  # > 0: the slave is faster
        tolerance = RELATIVE_TOLERANCE * max(1.0, abs(cv), limits.velocity)
        if (not self.undershoot_allowed and toward < -tolerance) or \
                (not self.overshoot_allowed and toward > tolerance):
            lead = plan_velocity(e, 0.0, relative)
            e = lead.end
            if duration is not None:
                duration -= lead.duration
        if duration is not None and duration > 0.0:
            try:
                return lead, plan_position_in(e, 0.0, relative, duration)
            except CommandRejected:
                pass  # cannot be stretched that far: as fast as possible
        return lead, plan_position(e, 0.0, relative)
