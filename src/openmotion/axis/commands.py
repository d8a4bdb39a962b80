"""The axis' internal job record; the command handle itself is the kernel's (kernel/command.py)."""

from __future__ import annotations

from dataclasses import dataclass, field

from openmotion.core.enums import BufferMode
from openmotion.kernel.command import Command, CommandStatus
from openmotion.trajectory.plan import Limits

__all__ = ["Command", "CommandStatus", "Job"]


@dataclass
class Job:
    """One motion the axis runs or has buffered."""

    kind: str  #: "position", "velocity", "halt", "stop", "home", "hold"
    command: Command
    limits: Limits
    target: float | None = None  #: absolute end position of a position job [mm]
    velocity: float = 0.0  #: signed cruise velocity of a velocity job [mm/s]
    buffer_mode: BufferMode = BufferMode.ABORTING
    end_velocity: float = 0.0  #: signed velocity at the target when the next one blends
    soft_limit_stop: bool = False  #: a velocity move turned into a stop at a software limit
    settle_time: float = 0.0  #: time spent inside the target window after the profile [s]
    settling_for: float = 0.0  #: time since the profile ended [s]
    extra: dict = field(default_factory=dict)
