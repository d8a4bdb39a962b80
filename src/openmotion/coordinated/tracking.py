"""Moving coordinate systems and synchronisation with axes (Part 4 §6).

- ``ConveyorFrame`` / ``RotaryTableFrame``: the PCS of MC_TrackConveyorBelt and
  MC_TrackRotaryTable, placed every cycle from the set position of the belt or table axis
  (§6.6, §6.7). The belt carries the PCS along the x axis of ``origin``; the table turns it
  about the z axis of ``origin``.
- ``GroupFrame``: the PCS of a slave group riding on the TCP of a master group
  (MC_SetDynCoordTransform, §6.5).
- ``AxisSync``: MC_SyncAxisToGroup, an axis whose velocity follows the path speed (§6.3).

The frames hold the command of the FB that made them: a transform FB that replaces the PCS
ends it with CommandAborted (§6.6, rule 122).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.coordinated.frames import Frame, FrameMotion
from openmotion.coordinated.inputs import CoordSystem
from openmotion.core.enums import AxisState
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
            acs = self.master._k.set_p[rows]
            mcs_v = self.master.kinematics.forward_velocity(acs, self.master._k.set_v[rows])
            velocity = self.master.spaces.xyz(mcs_v)
        return FrameMotion(frame, velocity, np.zeros(3))


class AxisSync:
    """MC_SyncAxisToGroup (§6.3): ``slave`` runs at ratio x path speed of ``group``.

    The slave's velocity approaches the target with at most ``acceleration``; InSync the
    first time it is reached. The group writes the slave's setpoint after its own axes
    every cycle; a single-axis command to the slave ends the coupling (CommandAborted).
    """

    def __init__(self, group: AxesGroup, slave: Axis, ratio: float, acceleration: float,
                 command: Command) -> None:
        self.group, self.slave, self.ratio = group, slave, ratio
        self.acceleration = acceleration
        self.command = command
        self.in_sync = False
        k, row = group._k, slave.row
        self.velocity = float(k.set_v[row])
        self.position = float(k.set_p[row])
        slave.state = AxisState.SYNCHRONIZED_MOTION

    def step(self, now: float, dt: float) -> None:
        slave, k = self.slave, self.group._k
        if slave.has_job or slave.state is not AxisState.SYNCHRONIZED_MOTION:
            self.command._end(CommandStatus.ABORTED, now,
                              message=f"{slave.name} got a command of its own (§6.3)")
            return
        target = self.ratio * self.group.motion.path_velocity
        step = self.acceleration * dt
        previous = self.velocity
        self.velocity = target if abs(target - previous) <= step else \
            previous + math.copysign(step, target - previous)
        if not self.in_sync and abs(self.velocity - target) <= 1e-12 * max(1.0, abs(target)):
            self.in_sync = True
            self.command.in_velocity = True
        self.position += 0.5 * (previous + self.velocity) * dt
        row = slave.row
        k.set_p[row], k.set_v[row] = self.position, self.velocity
        k.set_a[row] = (self.velocity - previous) / dt
        k.set_j[row] = 0.0
        k.segments.install(row, Profile.hold(KinematicState(self.position, self.velocity)),
                           k.sample_time)

    def end(self, now: float, reason: str) -> None:
        if self.command.busy:
            self.command._end(CommandStatus.ABORTED, now, message=reason)
