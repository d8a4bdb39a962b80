"""MC_SyncGroupToAxis (PLCopen Part 4 §6.4): the path parameter follows a master axis.

The group runs a path prepared by MC_PathSelect, but its arc length s is not planned in time:
it is coupled to the master's set position, s = ratio x (master - master at the start), like a
cam whose profile is the path. Engaging synchronises with the CA gear's Early sync
(``transport.gear.GearSync``, through its public interface): from the group's state the
coupling error is brought to zero with the command's acceleration, deceleration and jerk, so
the axes never jump; ``InSync`` from then on (§6.4). The master running backwards runs the
group back along the path.

Mode: non-periodic paths end: the group stops exactly at the path's end (or start) with the
command's dynamics and waits there, out of sync, until the master comes back. Periodic paths
must end where they start; s is taken modulo the path length.

``CamLaw`` stands in for the group's ``TimeLaw``: it samples s every cycle and locates it on
the path pieces the time law was built with. Override has no effect on a slave group (rule
97). A stop (MC_GroupStop, or any other motion command, rule 118) brakes s along the path.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import TYPE_CHECKING

from openmotion.coordinated.tolerances import CLOSED_PATH_TOLERANCE
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.rail.enums import SyncStrategy
from openmotion.rail.gear import GearSync
from openmotion.trajectory.plan import Limits, plan_position, plan_stop
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.axis.commands import Command
    from openmotion.coordinated.timing import TimeLaw


class PathMode(IntEnum):
    """MC_PathMode (§6.4): what happens at the end of the path."""

    NON_PERIODIC = 0
    PERIODIC = 1


class CamLaw:
    """s(t) of a group synchronised to ``master`` on the path of ``law``."""

    def __init__(self, law: TimeLaw, master: Axis, ratio: float, mode: PathMode,
                 limits: Limits, command: Command, cycle_time: float) -> None:
        self.law, self.master, self.mode = law, master, mode
        self.length = law.length
        self.command = command
        self.cycle_time = cycle_time
        self.sync = GearSync(master_row=-1, ratio=ratio, master_sync_position=master.set_position,
                             slave_sync_position=0.0, strategy=SyncStrategy.EARLY,
                             start_distance=None, limits=limits, after_sync=limits)
        self.limits = limits
        self.state = (0.0, 0.0, 0.0)  #: s, v, a at the last sample
        self._brake: tuple[Profile, float] | None = None
        self._stopping = False  #: MC_GroupStop or another command: the cam has ended

    # -- the TimeLaw interface the path motion uses ------------------------------------------

    def locate(self, s: float) -> tuple[int, float]:
        return self.law.locate(s)

    @property
    def done(self) -> bool:
        return self._stopping and self.standing

    @property
    def standing(self) -> bool:
        return self.state[1] == 0.0 and self.state[2] == 0.0

    def set_factors(self, now: float, velocity: float, acceleration: float, jerk: float) -> None:
        """Override has no effect on a group that follows a master (§5.28, rule 97)."""

    def stop(self, now: float, deceleration: float, jerk: float, keep: bool) -> None:
        """Brake along the path with ``deceleration`` and ``jerk``: the coupling ends."""
        del keep
        self._stopping = True
        self._start_brake(now, plan_stop(self._kinematic(), deceleration, jerk))

    def sample(self, now: float) -> tuple[float, float, float, float]:
        if self._brake is not None:
            profile, start = self._brake
            s, v, a, j = profile.at(now - start)
            if now - start >= profile.duration:
                s, v, a, j = profile.end.position, 0.0, 0.0, 0.0
                if not self._stopping:  # at an end of a non-periodic path: wait there
                    self._brake = None
                    self.sync.held(now, (s, 0.0, 0.0), self._master())
        else:
            s, v, a, j = self._follow(now)
        self.state = (s, v, a)
        self.command.in_velocity = self.sync.in_sync and self._brake is None
        if self.mode is PathMode.PERIODIC:
            return s % self.length, v, a, j
        return s, v, a, j

    # -- coupling ---------------------------------------------------------------------------

    def _master(self) -> tuple[float, float, float, float]:
        m = self.master
        return m.set_position, m.set_velocity, m.set_acceleration, m.set_jerk

    def _kinematic(self) -> KinematicState:
        return KinematicState(*self.state)

    def _start_brake(self, now: float, profile: Profile) -> None:
        self._brake = (profile, now - self.cycle_time)
        self.sync.in_sync = False

    def _follow(self, now: float) -> tuple[float, float, float, float]:
        """The sync's step, kept on a non-periodic path: one that could not stop before an
        end of the path with the command's dynamics brakes exactly onto that end."""
        try:
            proposal = self.sync.step(now, self.state, self._master(), self.cycle_time)
        except CommandRejected:
            proposal = None
        if proposal is None:
            profile = plan_stop(self._kinematic(), self.limits.deceleration, self.limits.jerk)
            return profile.at(self.cycle_time)
        if self.mode is PathMode.NON_PERIODIC:
            s, v, a, j = proposal
            # the group follows the master's acceleration and jerk (ratio x), which may be
            # above the command's: it can brake at least as hard as it is moving now
            deceleration = max(self.limits.deceleration, abs(a))
            jerk = max(self.limits.jerk, abs(j))
            stop = plan_stop(KinematicState(s, v, a), deceleration, jerk).end.position
            end = self.length if stop > self.length else 0.0 if stop < 0.0 else None
            if end is not None:
                hard = Limits(max(abs(self.state[1]), self.limits.velocity), deceleration,
                              deceleration, jerk)
                try:
                    profile = plan_position(self._kinematic(), end, hard)
                except CommandRejected:
                    profile = plan_stop(self._kinematic(), hard.deceleration, hard.jerk)
                self._start_brake(now, profile)
                return profile.at(self.cycle_time)
        return proposal


def check_periodic(start: tuple[float, ...], end: tuple[float, ...]) -> None:
    """A periodic cam needs a path that ends where it starts."""
    if math.dist(start, end) > CLOSED_PATH_TOLERANCE:
        raise CommandRejected(ErrorId.INVALID_MODE, "Mode periodic needs a path that ends "
                              "where it starts (§6.4)")
