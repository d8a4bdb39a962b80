"""External setpoints for planar movers in scenario files (TF5430 §6.1.6, §6.1.7).

``start_external_setpoint_generation`` calls StartExternalSetpointGeneration and starts a feed
that, as the manual's programs do, sends one setpoint in the firing cycle and one in every
cycle after it: SetExternalSetpoint, or SetExternalSetpointReferenceId with a
``reference_id``. ``stop_external_setpoint_generation`` ends the generation after that cycle's
setpoint. Each coordinate has its own source: a raised-cosine stroke, a linear ramp or the
set values of an axis; the others hold still (absolute) or add nothing (relative). This follows
the single-axis ``enable_external_setpoints`` entry (cyclic.py); planar_machine.py runs the
feeds.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import AfterValidator, StrictStr, model_validator

from openmotion.planar import ExternalSetPositionMode, ST_ExternalSetpointGenerationOptions
from openmotion.scenario.cyclic import SineFeed
from openmotion.scenario.planar import PlanarEntry
from openmotion.scenario.planar_parts import ReferenceId
from openmotion.scenario.schema import Number, Seconds, _check_axis, _Model

COORDINATES = ("x", "y", "z", "a", "b", "c")


class RampFeed(_Model):
    """offset + velocity τ, τ the time since the first setpoint: a constant velocity from the
    first setpoint on, acceleration 0."""

    velocity: Number
    """[mm/s or °/s]; negative runs the other way."""
    offset: Number | None = None
    """Position at τ = 0 [mm or °]; default: where the coordinate stands at the start
    (absolute), 0 (relative)."""


class CoordinateFeed(_Model):
    """The source of one coordinate's setpoints: exactly one of ``sine``, ``ramp``, ``axis``."""

    sine: SineFeed | None = None
    """offset + amplitude (1 - cos(2π τ / period)) / 2; ``offset`` defaults as ramp's does."""
    ramp: RampFeed | None = None
    """offset + velocity τ."""
    axis: Annotated[StrictStr, AfterValidator(_check_axis)] | None = None
    """Copy this axis' set position, velocity and acceleration of the cycle before."""

    @model_validator(mode="after")
    def _one_source(self) -> CoordinateFeed:
        if sum(source is not None for source in (self.sine, self.ramp, self.axis)) != 1:
            raise ValueError("give exactly one of 'sine', 'ramp' or 'axis' (an axis name)")
        return self


class PlanarFeedSpec(_Model):
    """A source per coordinate; coordinates without one hold (absolute) or add 0 (relative)."""

    x: CoordinateFeed | None = None
    """[mm]."""
    y: CoordinateFeed | None = None
    """[mm]."""
    z: CoordinateFeed | None = None
    """[mm]."""
    a: CoordinateFeed | None = None
    """[°]."""
    b: CoordinateFeed | None = None
    """[°]."""
    c: CoordinateFeed | None = None
    """[°]."""


class StartExternalSetpointGeneration(PlanarEntry):
    """StartExternalSetpointGeneration (§7.2.2.8.18), then one setpoint per cycle (§6.1.6).

    The row is busy while the mover takes the fed setpoints; done when
    stop_external_setpoint_generation ends them; an error with the mover's error id when the
    mover errs (PLANAR_EXT_SETPOINT once ``feed_for`` is over, or for a setpoint above the
    maximum velocity; INVALID_REFERENCE_ID for a setpoint off the part of ``reference_id``);
    rejected when the mover refuses the start. While it feeds, the run goes on.
    """

    method = "start_external_setpoint_generation"
    #: each cycle, with the reference system id when the feed names one
    blocks = ("MC_PlanarMover.set_external_setpoint",
              "MC_PlanarMover.set_external_setpoint_reference_id")
    command: Literal["start_external_setpoint_generation"]
    mode: Literal["absolute", "relative"] = "absolute"
    """ST_ExternalSetpointGenerationOptions: absolute (the mover follows only the setpoints,
    command mode ExternalSetpointGeneration) or relative (offsets added to its other motion)."""
    feed: PlanarFeedSpec = PlanarFeedSpec()
    """Sources by coordinate: ``{x: {ramp: {velocity: 100}}, c: {sine: {amplitude: 10,
    period: 1}}}``; default: every coordinate holds."""
    feed_for: Seconds | None = None
    """Stop feeding after this many seconds [s]; default: until the generation ends."""
    reference_id: ReferenceId = 0
    """The frame of the setpoints (§6.1.7): a part or a coordinate system; 0: the mover's
    coordinate system, with SetExternalSetpoint."""

    def arguments(self) -> tuple[Any, ...]:
        return (ST_ExternalSetpointGenerationOptions(ExternalSetPositionMode[self.mode.upper()]),)

    def sources(self) -> dict[str, CoordinateFeed]:
        """The coordinates that have a source."""
        return {name: source for name in COORDINATES
                if (source := getattr(self.feed, name)) is not None}


class StopExternalSetpointGeneration(PlanarEntry):
    """StopExternalSetpointGeneration (§7.2.2.8.19): after this cycle's setpoint the feed
    ends; absolute: the mover brakes with its maximum dynamics; relative: the offset stays."""

    method = "stop_external_setpoint_generation"
    command: Literal["stop_external_setpoint_generation"]
