"""Moving coordinate systems and synchronisation with axes (Part 4 §6).

- ``ConveyorFrame`` / ``RotaryTableFrame``: the PCS of MC_TrackConveyorBelt and
  MC_TrackRotaryTable, placed every cycle from the set position of the belt or table axis
  (§6.6, §6.7). The belt carries the PCS along the x axis of ``origin``; the table turns it
  about the z axis of ``origin``.
- ``GroupFrame``: the PCS of a slave group riding on the TCP of a master group
  (MC_SetDynCoordTransform, §6.5).
- ``AxisSync``: MC_SyncAxisToGroup, an axis that ramps in to the path speed and then
  counts the path length, locked in position (§6.3).

The frames hold the command of the FB that made them: a transform FB that replaces the PCS
ends it with CommandAborted (§6.6, rule 122).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.coordinated.frames import Frame, FrameMotion
from openmotion.coordinated.inputs import CoordSystem
from openmotion.coordinated.tolerances import LOCK_SLACK
from openmotion.core.enums import AxisState
from openmotion.trajectory.plan import Limits, plan_velocity
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.coordinated.group import AxesGroup



@dataclass
class ConveyorFrame:
    """The object frame on a belt: origin, shifted by the belt's travel, then the object."""

    belt: Axis
    origin: Frame
    initial: Frame  #: where the object sits on the belt when the FB starts (belt frame)
    belt_start: float  #: belt set position when the FB started [mm]
    command: Command | None = field(default=None, compare=False)

    def __call__(self, now: float) -> FrameMotion:
        travel = self.belt.set_position - self.belt_start
        shifted = Frame(self.initial.rotation, self.initial.translation + (travel, 0.0, 0.0))
        frame = self.origin.compose(shifted)
        velocity = self.origin.rotate(np.array([self.belt.set_velocity, 0.0, 0.0]))
        return FrameMotion(frame, velocity, np.zeros(3))


@dataclass
class RotaryTableFrame:
    """The object frame on a turning table: origin, turned by the table angle, then object."""

    table: Axis
    origin: Frame
    initial: Frame
    table_start: float  #: table set position when the FB started [°]
    command: Command | None = field(default=None, compare=False)

    def __call__(self, now: float) -> FrameMotion:
        angle = self.table.set_position - self.table_start
        turn = Frame.from_cartesian(rot_angle3=angle)
        frame = self.origin.compose(turn.compose(self.initial))
        spin = self.origin.rotate(np.array([0.0, 0.0, self.table.set_velocity]))
        # the turning axis runs through the origin: the PCS origin moves with w x r
        velocity = np.cross(np.radians(spin), frame.translation - self.origin.translation)
        return FrameMotion(frame, velocity, spin)


@dataclass
class GroupFrame:
    """A slave group's PCS on the master group's TCP (MC_SetDynCoordTransform, §6.5)."""

    master: AxesGroup
    offset: Frame
    command: Command | None = field(default=None, compare=False)

    def __call__(self, now: float) -> FrameMotion:
        mcs = self.master.position(CoordSystem.MCS, actual=False)
        point = self.master.spaces.xyz(mcs)
        frame = Frame(np.eye(3), point).compose(self.offset)
        velocity = np.zeros(3)
        rows = self.master.rows
        if rows.size:
            acs = self.master.kernel.set_p[rows]
            mcs_v = self.master.kinematics.forward_velocity(acs, self.master.kernel.set_v[rows])
            velocity = self.master.spaces.xyz(mcs_v)
        return FrameMotion(frame, velocity, np.zeros(3))


def path_speed(group: AxesGroup, coord_system: CoordSystem) -> float:
    """The TCP's speed along its path in ``coord_system`` from this cycle's setpoints: the
    norm of the axis velocities (ACS), of the TCP velocity (MCS), or of the TCP velocity
    relative to the PCS, which a moving PCS carries along (§2.2)."""
    rows = group.rows
    if not rows.size:
        return 0.0
    k = group.kernel
    acs, vel = k.set_p[rows], k.set_v[rows]
    if coord_system is CoordSystem.ACS:
        return float(np.linalg.norm(vel))
    spaces = group.spaces
    mcs_v = spaces.xyz(group.kinematics.forward_velocity(acs, vel))
    if coord_system is CoordSystem.PCS and spaces.dynamic is not None:
        motion = spaces.dynamic(group.runtime.now)
        point = motion.frame.inverse().apply(spaces.xyz(spaces.to_mcs(acs)))
        mcs_v = mcs_v - motion.point_velocity(point)
    return float(np.linalg.norm(mcs_v))  # a static PCS turns the MCS velocity: same norm


@dataclass(frozen=True)
class SyncInputs:
    """MC_SyncAxisToGroup's inputs once checked (§6.3)."""

    ratio: float  #: RatioNumerator / RatioDenominator [slave units per mm of path]
    acceleration: float  #: while the slave's speed grows during the ramp-in [u/s²]
    deceleration: float  #: while it falls [u/s²]
    jerk: float  #: [u/s³]
    coord_system: CoordSystem  #: where the path length is measured


class AxisSync:
    """MC_SyncAxisToGroup (§6.3): ``slave`` counts the path length of ``group`` x ratio.

    Ramp-in: the slave's velocity approaches ratio x path speed, jerk-limited, with the
    command's acceleration (speeding up) and deceleration (slowing down), replanned every
    cycle as the target moves. Once it is reached, InSync, and the slave locks in position:
    from then on it is the odometer, position = position at the lock + ratio x path length
    travelled since (in ``coord_system``), its velocity ratio x path speed, whatever the
    ramp-in limits (decisions D-193). The group writes the slave's setpoint after its own
    axes every cycle; a single-axis command to the slave ends the coupling (CommandAborted).
    """

    def __init__(self, group: AxesGroup, slave: Axis, inputs: SyncInputs,
                 command: Command) -> None:
        self.group, self.slave, self.inputs = group, slave, inputs
        self.ratio = inputs.ratio
        self.command = command
        self.in_sync = False
        k, row = group.kernel, slave.row
        self.state = KinematicState(float(k.set_p[row]), float(k.set_v[row]),
                                    float(k.set_a[row]))
        self.lock: float | None = None  #: slave position at the lock
        self.length = 0.0  #: path length since the lock [mm]
        self.speed = path_speed(group, inputs.coord_system)  #: path speed at the last step
        slave.state = AxisState.SYNCHRONIZED_MOTION

    def step(self, now: float, dt: float) -> None:
        slave, k = self.slave, self.group.kernel
        if slave.has_job or slave.state is not AxisState.SYNCHRONIZED_MOTION:
            self.command.end(CommandStatus.ABORTED, now,
                              message=f"{slave.name} got a command of its own (§6.3)")
            return
        previous, self.speed = self.speed, path_speed(self.group, self.inputs.coord_system)
        if self.lock is None:
            p, v, a = self._ramp(dt)
        else:
            self.length += 0.5 * (previous + self.speed) * dt
            p = self.lock + self.ratio * self.length
            v, a = self.ratio * self.speed, self.ratio * (self.speed - previous) / dt
        self.state = KinematicState(p, v, a)
        row = slave.row
        k.set_p[row], k.set_v[row], k.set_a[row], k.set_j[row] = p, v, a, 0.0
        k.segments.install(row, Profile.hold(KinematicState(p, v)), k.sample_time)

    def _ramp(self, dt: float) -> tuple[float, float, float]:
        """One cycle of the ramp-in towards ratio x path speed; the lock when it is reached."""
        target = self.ratio * self.speed
        inputs = self.inputs
        top = max(self.slave.parameters.max_velocity, abs(target), abs(self.state.velocity))
        profile = plan_velocity(self.state, target, Limits(top, inputs.acceleration,
                                                           inputs.deceleration, inputs.jerk))
        p, v, a, _ = profile.at(dt)
        if profile.duration <= dt * (1.0 + LOCK_SLACK):  # reached within this cycle
            self.lock, self.length = p, 0.0
            self.in_sync = True
            self.command.in_velocity = True
            return p, target, 0.0
        return p, v, a

    def end(self, now: float, reason: str) -> None:
        if self.command.busy:
            self.command.end(CommandStatus.ABORTED, now, message=reason)
