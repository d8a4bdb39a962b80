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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.trajectory.plan import Limits, plan_position, plan_position_in, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile
from openmotion.transport.enums import SyncStrategy

WAITING, SYNCING, IN_SYNC = 0, 1, 2


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
    phase: int = WAITING
    synced_once: bool = False
    profile: Profile | None = None  #: the sync error over time, from ``started``
    started: float = 0.0
    start_sync: bool = False  #: MC_GearInPosCA.StartSync
    in_sync: bool = False  #: MC_GearInPosCA.InSync
    error: tuple[ErrorId, str] | None = None
    _previous_master: tuple[float, float, float, float] | None = None
    _planned_for: float = 0.0  #: master velocity the sync was timed for

    def coupled(self, mp: float, mv: float, ma: float, mj: float
                ) -> tuple[float, float, float, float]:
        r = self.ratio
        return (self.slave_sync_position + r * (mp - self.master_sync_position), r * mv,
                r * ma, r * mj)

    def step(self, now: float, slave: tuple[float, float, float],
             master: tuple[float, float, float, float], cycle_time: float
             ) -> tuple[float, float, float, float] | None:
        """The slave's proposal for this cycle; None = stand (waiting)."""
        mp, mv, ma, mj = master
        cp, cv, ca, cj = self.coupled(mp, mv, ma, mj)
        if self.phase == WAITING and self._may_start(now, slave, master, cycle_time):
            self._plan(now, cycle_time, slave, self._previous_master, master, self.limits)
            self._planned_for = mv
        if self.phase == WAITING:
            self._previous_master = master
            return None
        if self.phase == SYNCING:
            if (self.strategy is SyncStrategy.LATE and not self.synced_once
                    and not self.override_restrictions and abs(ma) > 1e-9 * max(1.0, abs(mv))):
                self.error = (ErrorId.SYNC_FAILED, "the master accelerated after StartSync "
                              "(SyncStrategy Late)")
                return None
            if (self.strategy is SyncStrategy.SLOW and not self.synced_once
                    and abs(mv - self._planned_for) > 1e-9 * max(1.0, abs(mv))):
                # the master changed speed: stretch the rest to arrive in time again (§9.4.1.5)
                self._plan(now, cycle_time, slave, self._previous_master, master, self.limits)
                self._planned_for = mv
            assert self.profile is not None
            ep, ev, ea, ej = self.profile.at(now - self.started)
            self._previous_master = master
            if now - self.started >= self.profile.duration - 1e-12:
                self.phase, self.start_sync, self.in_sync = IN_SYNC, False, True
                self.synced_once = True
                return cp, cv, ca, cj
            return cp + ep, cv + ev, ca + ea, cj + ej
        self._previous_master = master
        return cp, cv, ca, cj

    def held(self, now: float, slave: tuple[float, float, float],
             master: tuple[float, float, float, float]) -> None:
        """Gap control braked the slave: synchronise again from where it is."""
        if self.phase == WAITING:
            return
        self.in_sync = False
        self.phase = SYNCING
        self._plan(now, 0.0, slave, master, master, self.after_sync, early=True)

    def prime(self, master_then: tuple[float, float, float, float]) -> None:
        """The master's set values of the cycle before the first step (position, velocity,
        acceleration, jerk). The sync is planned from the slave's state of that cycle, so it
        needs the master's of the same cycle; without a prime the first step takes the
        master's values one cycle back along its jerk (an axis, evaluated before the group)."""
        self._previous_master = master_then

    def _may_start(self, now: float, slave: tuple[float, float, float],
                   master: tuple[float, float, float, float], cycle_time: float) -> bool:
        if self._previous_master is None:  # the master of the slave's cycle: no jump back
            mp, mv, ma, mj = master
            dt = cycle_time
            self._previous_master = (mp - dt * (mv - dt * (ma / 2.0 - dt * mj / 6.0)),
                                     mv - dt * (ma - dt * mj / 2.0), ma - dt * mj, mj)
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

    def _plan(self, now: float, cycle_time: float, slave: tuple[float, float, float],
              master_then: tuple[float, float, float, float],
              master_now: tuple[float, float, float, float], limits: Limits,
              early: bool = False) -> None:
        """Plan the sync error from the last sample (``now - cycle_time``, where ``slave`` and
        ``master_then`` are), timed with the master as it is ``now``."""
        self.phase, self.start_sync, self.started = SYNCING, True, now - cycle_time
        mp, mv = master_now[0], master_now[1]
        remaining = (self.master_sync_position - mp) / mv + cycle_time if mv else math.inf
        timed = not early and self.strategy is not SyncStrategy.EARLY and \
            math.isfinite(remaining) and remaining > 0.0
        lead, main = self._error_profiles(slave, master_then, limits,
                                          remaining if timed else None)
        self.profile = main if lead is None else Profile.concatenate(lead, main)
        self._check_options(main, self.profile, slave, master_then)

    def _check_options(self, main: Profile, profile: Profile,
                       slave: tuple[float, float, float],
                       master: tuple[float, float, float, float]) -> None:
        """The sync phase's restrictions of ST_GearInPosCAOptions, judged on the planned
        profile with the master at its present velocity; a profile that breaks one is
        SYNC_FAILED ("synchronisation impossible under the Options restrictions", §9.1.2.1).
        Under- and overshoot are judged after the lead that first brings the slave to the
        master's velocity (``main``); reversal and MinimalSlavePosition on all of it.
        """
        cp, cv, _, _ = self.coupled(*master)
        direction = 1.0 if cv > 0.0 else -1.0 if cv < 0.0 else 1.0
        tolerance = 1e-9 * max(1.0, abs(cv), self.limits.velocity)
        low, high = main.velocity_extrema()  # of the sync error's velocity
        error_low, error_high = (low, high) if direction > 0 else (-high, -low)
        if not self.undershoot_allowed and error_low < -tolerance:
            raise CommandRejected(ErrorId.SYNC_FAILED, "the slave would be slower than the "
                                  "master (MasterVelocityUndershootAllowed FALSE)")
        if not self.overshoot_allowed and error_high > tolerance:
            raise CommandRejected(ErrorId.SYNC_FAILED, "the slave would be faster than the "
                                  "master (MasterVelocityOvershootAllowed FALSE)")
        low, high = profile.velocity_extrema()
        error_low = low if direction > 0 else -high
        if not self.reversal_allowed and abs(cv) + error_low < -tolerance:
            raise CommandRejected(ErrorId.SYNC_FAILED, "the slave would move against the "
                                  "sync direction (DirectionReversalAllowed FALSE)")
        if self.minimal_slave_position is not None:
            data = profile.data.copy()  # the slave itself: error + coupled motion
            data[1] += cp + cv * data[0]
            data[2] += cv
            lowest, _ = Profile.from_data(data).position_extrema()
            if lowest < self.minimal_slave_position - tolerance:
                raise CommandRejected(ErrorId.SYNC_FAILED, f"the slave would pass below "
                                      f"MinimalSlavePosition {self.minimal_slave_position:g}")

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
        tolerance = 1e-9 * max(1.0, abs(cv), limits.velocity)
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
