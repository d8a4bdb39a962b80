"""MC_Home's reference search on a simulated cam and encoder sync pulse (TcMC §3.14).

The manual leaves the reference mode to the encoder configuration and reports the progress in
nCalibrationState without giving its values. Ours (docs/decisions.md D-010):

    1 started  2 searching the cam  3 cam found, reversing  4 leaving the cam
    5 off the cam, waiting for the sync pulse  6 reference taken, stopping  7 finished

so the manual's hint for homing on the sync pulse alone - hold bCalibrationCam TRUE at the start
and release it once nCalibrationState >= 4 - works as written.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from openmotion.axis import jobs
from openmotion.axis.commands import CommandStatus
from openmotion.axis.tolerances import MIN_SPEED
from openmotion.core.enums import AxisState, Direction, ReferenceMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.trajectory.plan import Limits, plan_velocity

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis


class HomingSequence:
    def __init__(self, axis: Axis, home_position: float) -> None:
        p = axis.parameters
        self.axis = axis
        self.home_position = home_position
        self.mode = ReferenceMode(p.reference_mode)
        self.toward = -1 if p.homing_direction == Direction.NEGATIVE else 1
        needs_cam = self.mode in (ReferenceMode.CAM_AND_SYNC_PULSE, ReferenceMode.CAM)
        if needs_cam and axis.cam_input is None and p.reference_cam is None:
            raise CommandRejected(ErrorId.HOMING_FAILED,
                                  "no reference cam: wire bCalibrationCam or set reference_cam")
        self._previous_raw = axis.position - axis.raw_offset

    # the axis calls step() every cycle while homing; False ends the watch
    def step(self, now: float) -> bool:
        axis = self.axis
        job = axis.queue.active
        if job is None or job.kind != "home" or job.command.finished:
            return False
        raw = axis.position - axis.raw_offset
        state = axis.calibration_state
        cam = self._cam(raw)
        if state == 0:
            self._begin()
        elif state == 2 and cam:
            axis.calibration_state = 3
            self._travel(-self.toward, axis.parameters.calibration_velocity_backward)
            axis.calibration_state = 4
        elif state == 4 and not cam:
            if self.mode is ReferenceMode.CAM:
                self._reference(raw)
            else:
                axis.calibration_state = 5
        elif state == 5:
            pulse = self._sync_pulse(self._previous_raw, raw)
            if pulse is not None:
                self._reference(pulse)
        elif state == 6 and not axis.has_job and axis.set_velocity == 0.0:
            axis.calibration_state = 7
            axis.homed = True
            job.command.end(CommandStatus.DONE, now)
            axis.queue.active = None
            axis.state = AxisState.STANDSTILL
            axis.queue.start_next(now)
            self._previous_raw = raw
            return False
        self._previous_raw = raw
        return True

    def _begin(self) -> None:
        axis = self.axis
        axis.calibration_state = 1
        if self.mode is ReferenceMode.DIRECT:
            self._reference(axis.position - axis.raw_offset)
        elif self.mode is ReferenceMode.SYNC_PULSE:
            self._travel(self.toward, axis.parameters.calibration_velocity_backward)
            axis.calibration_state = 5
        else:
            self._travel(self.toward, axis.parameters.calibration_velocity_forward)
            axis.calibration_state = 2

    def _cam(self, raw: float) -> bool:
        axis = self.axis
        if axis.cam_input is not None:
            return bool(axis.cam_input)
        cam = axis.parameters.reference_cam
        return cam is not None and min(cam) <= raw <= max(cam)

    def _sync_pulse(self, previous: float, current: float) -> float | None:
        """Raw position of a sync pulse passed between two samples (a hardware latch)."""
        p = self.axis.parameters
        before = math.floor((previous - p.sync_pulse_offset) / p.sync_pulse_distance)
        after = math.floor((current - p.sync_pulse_offset) / p.sync_pulse_distance)
        if before == after:
            return None
        crossed = max(before, after)
        return p.sync_pulse_offset + crossed * p.sync_pulse_distance

    def _travel(self, direction: int, speed: float) -> None:
        axis = self.axis
        p = axis.parameters
        limits = Limits(max(speed, MIN_SPEED), p.acceleration, p.deceleration, p.jerk)
        axis.queue.install(plan_velocity(axis.kernel.state(axis.row), direction * speed, limits),
                           has_job=False)

    def _reference(self, raw: float) -> None:
        """The reference event: the machine position ``raw`` now reads ``home_position``."""
        axis = self.axis
        axis.shift_coordinates(self.home_position - (raw + axis.raw_offset))
        p = axis.parameters
        brake = jobs.plan_brake(axis.kernel.state(axis.row), p.deceleration, p.jerk, p)
        axis.queue.install(brake, has_job=False)
        axis.calibration_state = 6
