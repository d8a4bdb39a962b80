"""What a CA group does when a member fails or loses power (D-065, D-183, D-184).

Gap control runs while the group is enabled and its members are healthy. A member in
ErrorStop puts the group in GroupErrorStop, a member that loses power makes it NotReady
(TF5410 §7, state diagram; D-065). Either way every command ends and every mover brakes to
rest with its maximum deceleration and jerk: the brake that every envelope of gap control
assumes. The brakes start from the state of the last cycle, the one gap control left safe,
and they are the first step of this cycle, so no mover takes one more step of its command.

A mover that lost power brakes too: its setpoint is where the model has the mover, and a
mover without power cannot stop on the spot (D-183). Whatever else writes the row while it
brakes (MC_Power freezing the setpoint, an error reaction planned from a stale profile), the
group puts the brake back. Braking together from a safe state keeps every pair safe, in
Standard and in Fast (docs/collision-avoidance.md, Faults).

While a mover brakes it reports Stopping (ErrorStop if it failed itself); at rest StandStill,
or Disabled without power (TcMC state diagram; D-184). The group leaves NotReady, and
MC_GroupReset ends, only once every brake has ended.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from openmotion.axis.commands import CommandStatus
from openmotion.core.enums import AxisState
from openmotion.core.errors import ErrorId
from openmotion.trajectory.plan import plan_stop
from openmotion.trajectory.segments import KinematicState
from openmotion.transport.cycle_kernel import all_at
from openmotion.transport.enums import GroupState
from openmotion.transport.movers import IDLE, FaultBrake, Mover

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

FAULT_STATES = (GroupState.NOT_READY, GroupState.ERROR_STOP)  #: the only states with brakes
#: states a braking mover reports as Stopping: the motion states and those of a mover at rest
_SHOWN_STOPPING = (AxisState.STANDSTILL, AxisState.DISCRETE_MOTION,
                   AxisState.CONTINUOUS_MOTION, AxisState.DISABLED)


class GroupFaults:
    """The fault reactions of ``CaGroup`` (a mixin: the state lives in the group)."""

    def _watch_members(self) -> None:
        """Member errors stop the group; a member losing power makes it NotReady (§7)."""
        lost, self._power_lost = self._power_lost, None  # also if MC_Power came back since
        if self.state in (GroupState.DISABLED, GroupState.ERROR_STOP):
            return
        if lost is None and all_at(self.kernel.monitored, self.rows):  # powered, no errors
            if self.state is GroupState.NOT_READY:
                self._check_ready()
            return
        failed = [m for m in self.movers if m.axis.state is AxisState.ERROR_STOP]
        if failed:
            self._error(failed[0].axis.axis_error_id, f"{failed[0].axis.name}: "
                        f"{failed[0].axis.axis_error_message}")
            return
        if self.state is GroupState.NOT_READY:
            self._check_ready()
        elif lost is not None or any(not m.axis.powered for m in self.movers):
            off = lost or next(m.axis.name for m in self.movers if not m.axis.powered)
            self._brake_all(CommandStatus.ABORTED, f"{off} was disabled")
            self.state = GroupState.NOT_READY

    def _error(self, error_id: ErrorId, message: str) -> None:
        """GroupErrorStop: every command ends in error, every mover brakes at its maximum."""
        self.error_id = ErrorId.GROUP_ERROR if error_id is ErrorId.NO_ERROR else error_id
        self._brake_all(CommandStatus.ERROR, f"group error: {message}")
        self.state = GroupState.ERROR_STOP

    def _brake_all(self, status: CommandStatus, message: str) -> None:
        """End every command and brake every mover, powered or not, with its maximum
        dynamics from the state of the last cycle (a mover braking already goes on)."""
        now = self.runtime.now
        error_id = ErrorId.GROUP_ERROR if status is CommandStatus.ERROR else ErrorId.NO_ERROR
        for mover in self.movers:
            for job in ([mover.job] if mover.job else []) + mover.queue:
                job.command.end(status, now, error_id, message)
            mover.job = None
            mover.queue.clear()
            self.mode[mover.slot] = IDLE
            if mover.brake is None:
                slot = mover.slot
                start = KinematicState(float(self.p[slot]), float(self.v[slot]),
                                       float(self.a[slot]))
                profile = plan_stop(start, float(self.bdec[slot]), float(self.bjerk[slot]))
                self._install_brake(mover, FaultBrake(now - self.runtime.cycle_time, profile), now)
        for command in (self._stop, self._halt):
            if command is not None:
                command.end(status, now, error_id, message)
        self._stop = self._halt = None
        self.pairs_changed()
        self._env = None

    def member_power_changed(self, axis: Axis) -> None:
        """MC_Power switched a member (Runtime phase 1, or between cycles), and the axis froze
        its setpoint. A mover that brakes goes on braking; a mover that moves and lost power
        starts its brake from its last state at once (D-183). The others follow in phase 2."""
        if self.state is GroupState.DISABLED:
            return
        self._fresh()
        mover, now = self.mover_of(axis), self.kernel.sample_time  # the time of the last state
        if not axis.powered:
            self._power_lost = axis.name  # the group reacts in phase 2 (_watch_members)
        if mover.brake is None and not axis.powered:
            slot = mover.slot
            if self.v[slot] == 0.0 and self.a[slot] == 0.0:
                return  # at rest: nothing to run out
            start = KinematicState(float(self.p[slot]), float(self.v[slot]), float(self.a[slot]))
            mover.brake = FaultBrake(now, plan_stop(start, float(self.bdec[slot]),
                                                    float(self.bjerk[slot])))
        if mover.brake is not None:
            self._install_brake(mover, mover.brake, now)

    def _install_brake(self, mover: Mover, brake: FaultBrake, now: float) -> None:
        """Let the mover follow ``brake``; its setpoint of this cycle is the brake's."""
        k, row = self.kernel, mover.axis.row
        k.segments.install(row, brake.profile, brake.start)
        brake.end = float(k.segments.end[row])
        k.set_p[row], k.set_v[row], k.set_a[row], k.set_j[row] = brake.profile.at(
            now - brake.start)
        mover.brake = brake
        self._show_brake(mover, now)

    def _follow_brakes(self, now: float) -> None:
        """Keep the running brakes (MC_Power or an error reaction may have planned the row
        anew) and end those that reached rest."""
        k = self.kernel
        for mover in self.movers:
            brake = mover.brake
            if brake is None:
                continue
            if k.segments.end[mover.axis.row] != brake.end:  # someone else planned the row
                self._install_brake(mover, brake, now)
            else:
                self._show_brake(mover, now)

    def _show_brake(self, mover: Mover, now: float) -> None:
        """Stopping while the brake runs; at its end StandStill, or Disabled without power.
        ErrorStop stays as it is."""
        axis = mover.axis
        assert mover.brake is not None
        if now < mover.brake.end:
            if axis.state in _SHOWN_STOPPING:
                axis.state = AxisState.STOPPING
            return
        self._stand(mover)

    def _stand(self, mover: Mover) -> None:
        """The mover rests (its brake ended, or the group stopped it at once): StandStill, or
        Disabled without power; ErrorStop stays."""
        mover.brake = None
        axis = mover.axis
        if axis.state in (AxisState.STOPPING, AxisState.DISCRETE_MOTION,
                          AxisState.CONTINUOUS_MOTION):
            axis.state = AxisState.STANDSTILL if axis.powered else AxisState.DISABLED

    @property
    def _braking(self) -> bool:
        """Some mover still brakes after a fault."""
        return any(m.brake is not None for m in self.movers)
