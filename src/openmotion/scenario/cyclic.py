"""Timeline entries that a function block carries out rather than one Axis method call.

Most of them start a block that the run then calls every cycle, as a PLC program would
(scenario/programs.py): MC_Jog while its key is held, the feed of external setpoints, the
override filter and MC_PowerStepper with its simulated terminal. The others call a block once
(MC_SetReferenceFlag, MC_ReadAxisComponents, MC_MoveAbsoluteOrRestart, and the reads and
parameter blocks, whose outputs the row keeps: scenario/queries.py) or act on the stepper
terminal (a stall).

schema.py puts these models into its ``COMMANDS`` and ``TimelineEntry``; they share its value
types, conditions and name checks.
"""

from __future__ import annotations

import dataclasses
from typing import Annotated, Any, ClassVar, Literal

from pydantic import AfterValidator, Field, StrictBool, StrictInt, StrictStr, model_validator

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command
from openmotion.axis.parameters import AxisParameters
from openmotion.core.enums import BufferMode, ReadMode, TargetPositionType
from openmotion.core.special_values import MC_DEFAULT, MC_INVALID
from openmotion.plcopen.jog import JogMode
from openmotion.plcopen.parameters import (
    MC_ReadBoolParameter,
    MC_ReadParameter,
    MC_ReadParameterSet,
    MC_WriteBoolParameter,
    MC_WriteParameter,
)
from openmotion.plcopen.read import MC_ReadActualPosition, MC_ReadAxisError, MC_ReadStatus
from openmotion.plcopen.stepper import DestallDetectMode, DestallMode, PowerStepperParams
from openmotion.plcopen.version import F_GetVersionTcMC
from openmotion.scenario.queries import Query, block_query, query_command
from openmotion.scenario.schema import (
    BufferModeName,
    ConditionText,
    Entry,
    InputValue,
    Number,
    PositiveSeconds,
    Seconds,
    _check_axis,
    _check_id_of,
    _enum_by_name,
    _Model,
)


class BlockEntry(Entry):
    """An entry carried out by a function block (programs.py), not by an Axis method."""

    method: ClassVar[str] = ""  #: none: the run starts the entry's program instead
    block: ClassVar[str]  #: the function block behind the entry

    def arguments(self) -> dict[str, Any]:
        """The block's keyword inputs that the entry sets."""
        return {}


# -- MC_Jog --------------------------------------------------------------------------------


class Jog(BlockEntry):
    """MC_Jog (TcMC §3.13): press a jog key at the entry's time, release it after ``hold``.

    The run calls the block every cycle from the firing cycle on, the key TRUE while held,
    until the block is no longer busy; the entry's result is the block's (done, aborted,
    error).
    """

    block = "MC_Jog"
    command: Literal["jog"]
    mode: _enum_by_name(JogMode) = JogMode.STANDARD_SLOW  # type: ignore[valid-type]
    """standard_slow, standard_fast (the axis' manual velocities), continuous (``velocity``),
    inching (a step of ``position``)."""
    direction: Literal["forward", "backwards"] = "forward"
    """The key pressed: jog_forward or jog_backwards."""
    position: InputValue = MC_DEFAULT
    """Inching step [mm or °]; MC_DEFAULT = the axis' jog increment."""
    velocity: InputValue = MC_INVALID
    """[mm/s], > 0, for continuous and inching."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]; 0 or MC_DEFAULT = axis default (continuous and inching)."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]; also brakes the released key in continuous mode."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    hold: Seconds = 0.0
    """How long the key is held [s]: released in the first cycle at or after the firing time
    + hold; 0 = pressed for one cycle."""
    release_when: ConditionText | None = None
    """Instead of ``hold``: release the key in the first cycle after the firing one in which
    this condition holds."""

    @model_validator(mode="after")
    def _one_release(self) -> Jog:
        if self.release_when is not None and "hold" in self.model_fields_set:
            raise ValueError("give 'hold' or 'release_when', not both")
        return self

    @property
    def key(self) -> str:
        """The MC_Jog input of the key: jog_forward or jog_backwards."""
        return f"jog_{self.direction}"

    def arguments(self) -> dict[str, Any]:
        return {"mode": self.mode, "position": self.position, "velocity": self.velocity,
                "acceleration": self.acceleration, "deceleration": self.deceleration,
                "jerk": self.jerk}


# -- external setpoints --------------------------------------------------------------------


class SineFeed(_Model):
    """A raised cosine that starts at rest: offset + amplitude (1 - cos(2π τ / period)) / 2.

    τ is the time since the enable; the fed velocity and acceleration are its derivatives, so
    the feed starts with velocity and acceleration 0 and swings between offset and offset +
    amplitude.
    """

    amplitude: Number
    """Peak-to-peak stroke [mm or °]; negative swings the other way."""
    period: PositiveSeconds
    """[s]."""
    offset: Number | None = None
    """Start position [mm or °]; default: the set position at the enable."""


class FeedSpec(_Model):
    """Where the fed setpoints come from: another axis, or a sine."""

    axis: Annotated[StrictStr, AfterValidator(_check_axis)] | None = None
    """Copy this axis' set position, velocity and acceleration (a virtual generator axis
    driven by ordinary moves); the fed value is the one of the cycle before."""
    sine: SineFeed | None = None
    """A raised-cosine stroke."""

    @model_validator(mode="after")
    def _one_source(self) -> FeedSpec:
        if (self.axis is None) == (self.sine is None):
            raise ValueError("give exactly one of 'axis' (an axis name) or 'sine'")
        return self


class EnableExternalSetpoints(BlockEntry):
    """MC_ExtSetPointGenEnable (TcMC §4.16), then MC_ExtSetPointGenFeed every cycle (§4.18).

    The run feeds the axis from ``feed`` in every cycle from the firing one on, until
    ``feed_for`` has passed or the axis leaves external setpoints. A cycle without a feed is
    EXT_SETPOINT_MISSING (D-040). While it feeds, the run goes on.
    """

    block = "MC_ExtSetPointGenEnable"
    blocks = ("MC_ExtSetPointGenFeed",)  #: every cycle while it feeds
    command: Literal["enable_external_setpoints"]
    position: InputValue = MC_INVALID
    """Watched target [mm or °] (``in_external_target``); the axis does not go there itself."""
    position_type: _enum_by_name(TargetPositionType) = (  # type: ignore[valid-type]
        TargetPositionType.ABSOLUTE)
    """absolute, relative (to the set position at the enable) or modulo."""
    feed: FeedSpec
    """The setpoint source: ``{axis: name}`` or ``{sine: {amplitude, period, offset}}``."""
    feed_for: Seconds | None = None
    """Stop feeding after this many seconds [s]; default: while the axis takes setpoints."""

    @model_validator(mode="after")
    def _other_axis(self) -> EnableExternalSetpoints:
        if self.feed.axis is not None and self.feed.axis == self.axis:
            raise ValueError("feed: the axis cannot feed itself; name another axis")
        return self

    def arguments(self) -> dict[str, Any]:
        return {"position": self.position, "position_type": self.position_type}


class DisableExternalSetpoints(Entry):
    """MC_ExtSetPointGenDisable (TcMC §4.17): stop taking fed values; a moving axis brakes.

    The feed of the axis' enable_external_setpoints entry stops with it.
    """

    method = "disable_external_setpoints"
    command: Literal["disable_external_setpoints"]


# -- MC_OverrideFilter ---------------------------------------------------------------------

RawStep = tuple[Seconds, Number]


class OverrideFilter(BlockEntry):
    """MC_OverrideFilter (TcMC §4.19) on a stepped raw value, applied as the axis override.

    The run calls the block every cycle from the entry's firing and the first ``raw`` time on,
    to the end of the run, and applies its filtered percent with MC_SetOverride whenever it
    changes. The entry stays busy with the last filtered percent as its value; a block error
    (bad thresholds or steps) ends it with the block's error id. It does not keep the run
    going.
    """

    block = "MC_OverrideFilter"
    command: Literal["override_filter"]
    raw: Annotated[list[RawStep], Field(min_length=1)]
    """[time, raw value] steps: the potentiometer value from that run time [s] on, times
    ascending. Before the first time the block is not called (the override is left alone)."""
    lower_override_threshold: Number = 0.0
    """Raw value of 0 % (a whole number)."""
    upper_override_threshold: Number = 32767.0
    """Raw value of 100 % (a whole number)."""
    override_steps: Number = 200.0
    """Number of steps between 0 and 100 % (a whole number > 1)."""
    override_recovery_time: Number = 0.150
    """[s] between two changes of the output (0 % and 100 % are applied at once)."""

    @model_validator(mode="after")
    def _ascending(self) -> OverrideFilter:
        times = [time for time, _ in self.raw]
        if any(later < earlier for earlier, later in zip(times, times[1:], strict=False)):
            raise ValueError("raw: the times must be ascending")
        return self

    def arguments(self) -> dict[str, Any]:
        return {"lower_override_threshold": self.lower_override_threshold,
                "upper_override_threshold": self.upper_override_threshold,
                "override_steps": self.override_steps,
                "override_recovery_time": self.override_recovery_time}


# -- MC_PowerStepper and its terminal ------------------------------------------------------


class PowerStepper(BlockEntry):
    """MC_PowerStepper (TcMC §4.23) with Enable TRUE, called every cycle to the end of the run.

    The run attaches a simulated KL2531/KL2541 terminal to the axis (one per axis) and passes
    its status byte and word to the block. The entry is busy while the block runs (active once
    its Status is TRUE); a block error ends it. It does not keep the run going.
    """

    block = "MC_PowerStepper"
    command: Literal["power_stepper"]
    override: Number = 100.0
    """Velocity override [%], 0-100 (MC_Power's Override)."""
    enable_positive: StrictBool = True
    """Feed enable in positive direction."""
    enable_negative: StrictBool = True
    """Feed enable in negative direction."""
    destall_enable: StrictBool = False
    """Stall detection and handling on."""
    destall_detect_mode: _enum_by_name(DestallDetectMode) = (  # type: ignore[valid-type]
        DestallDetectMode.NONE)
    """none, encoderless (terminal stall bits 1-3) or lagging (following error beyond
    max_position_lag for longer than position_lag_filter_time)."""
    destall_mode: _enum_by_name(DestallMode) = DestallMode.NONE  # type: ignore[valid-type]
    """none, set_error (axis error STEPPER_STALL), set_err_non_ref (also not homed) or
    use_override (override 0 until the following error recovers)."""
    status_mon_enable: StrictBool = False
    """Terminal errors are axis errors (DRIVE_NOT_READY)."""

    def arguments(self) -> dict[str, Any]:
        params = PowerStepperParams(self.destall_detect_mode, self.destall_mode,
                                    self.destall_enable, self.status_mon_enable)
        return {"enable": True, "enable_positive": self.enable_positive,
                "enable_negative": self.enable_negative, "override": self.override,
                "destall_params": params}


class InjectStall(BlockEntry):
    """Stall the motor on the axis' simulated stepper terminal (axis/stepper.py).

    The mechanics block (the actual position stops following) and the stall bits 1-3 are set.
    A stall with a ``duration`` keeps the run going until it ends.
    """

    block = "StepperTerminal.inject_stall"
    command: Literal["inject_stall"]
    duration: Seconds | None = None
    """[s]; default: until a release_stall entry."""


class ReleaseStall(BlockEntry):
    """End a stall of the axis' stepper terminal (Done also when none is in force)."""

    block = "StepperTerminal.release"
    command: Literal["release_stall"]


# -- reference flag and axis components ----------------------------------------------------


class SetReferenceFlag(BlockEntry):
    """MC_SetReferenceFlag (TcMC §4.15): set the axis' homed flag without moving it."""

    block = "MC_SetReferenceFlag"
    command: Literal["set_reference_flag"]
    reference_flag: StrictBool
    """true: homed; false: not homed."""

    def arguments(self) -> dict[str, Any]:
        return {"reference_flag": self.reference_flag}


class ReadAxisComponents(BlockEntry):
    """MC_ReadAxisComponents (TcMC §4.9): the summary shows the encoder, drive and controller."""

    block = "MC_ReadAxisComponents"
    command: Literal["read_axis_components"]


# -- MC_MoveAbsoluteOrRestart -------------------------------------------------------------


class MoveAbsoluteOrRestart(BlockEntry):
    """MC_MoveAbsoluteOrRestart (TcMC §3.6): a move_absolute whose block a later entry may
    trigger again (``restart``), retargeting the running move with its start dynamics.

    The run keeps the block of each entry with an id; an entry with ``restart`` gives that
    block a new rising edge with its own position and velocity (the rest of its inputs are
    the block's, as on a PLC). While the move runs the restart is the same command, so both
    rows end with it; once it has ended the edge starts a new move.
    """

    block = "MC_MoveAbsoluteOrRestart"
    command: Literal["move_absolute_or_restart"]
    position: InputValue
    """Target position [mm or °]."""
    velocity: InputValue
    """[mm/s]; MC_MAXIMUM = axis maximum."""
    acceleration: InputValue = MC_DEFAULT
    """[mm/s²]; 0 or MC_DEFAULT = axis default."""
    deceleration: InputValue = MC_DEFAULT
    """[mm/s²]."""
    jerk: InputValue = MC_DEFAULT
    """[mm/s³]."""
    buffer_mode: BufferModeName = BufferMode.ABORTING
    """As for moves."""
    restart: Annotated[StrictStr, _check_id_of("move_absolute_or_restart", "restart")] | None \
        = None
    """The id of an earlier move_absolute_or_restart entry on the same axis whose block
    this entry triggers again; default: a block of its own."""

    def arguments(self) -> dict[str, Any]:
        return {name: getattr(self, name) for name in ("position", "velocity", "acceleration",
                                                       "deceleration", "jerk", "buffer_mode")}


# -- read and parameter blocks (TcMC §4.3-§4.11, §5.1): called once --------------------------


class _Call(BlockEntry):
    """A block called once with ``trigger`` TRUE: its row records its error or outputs."""

    block_type: ClassVar[Any]  #: the block class
    trigger: ClassVar[str] = "enable"

    def call(self, axis: Axis | None, now: float) -> Command:
        block = self.block_type(axis)
        block(**{self.trigger: True}, **self.arguments())
        return block_query(self.command, now, block, self.outputs)


class ReadActualPosition(_Call, Query):
    """MC_ReadActualPosition (TcMC §4.3): output ``position``, the actual position."""

    block = "MC_ReadActualPosition"
    block_type = MC_ReadActualPosition
    command: Literal["read_actual_position"]
    outputs = ("position",)


class ReadStatus(_Call, Query):
    """MC_ReadStatus (TcMC §4.4): the state flags, 1 or 0 (``homing``: referenced, D-192)."""

    block = "MC_ReadStatus"
    block_type = MC_ReadStatus
    command: Literal["read_status"]
    outputs = MC_ReadStatus.FLAGS


class ReadAxisError(_Call, Query):
    """MC_ReadAxisError (TcMC §4.5): ``axis_error_id`` (its number) and its message."""

    block = "MC_ReadAxisError"
    block_type = MC_ReadAxisError
    command: Literal["read_axis_error"]
    outputs = ("axis_error_id", "axis_error_message")


class ReadParameter(_Call, Query):
    """MC_ReadParameter (TcMC §4.6): output ``value`` of an LREAL parameter (MC_AxisPara)."""

    block = "MC_ReadParameter"
    block_type = MC_ReadParameter
    command: Literal["read_parameter"]
    outputs = ("value",)
    parameter_number: StrictInt
    """The MC_AxisPara number, e.g. 1004 (acceleration)."""
    read_mode: _enum_by_name(ReadMode) = ReadMode.CYCLIC  # type: ignore[valid-type]
    """once or cyclic; one call reads the same in both."""

    def arguments(self) -> dict[str, Any]:
        return {"parameter_number": self.parameter_number, "read_mode": self.read_mode}


class ReadBoolParameter(ReadParameter):
    """MC_ReadBoolParameter (TcMC §4.7): output ``value`` of a BOOL parameter, 1 or 0."""

    block = "MC_ReadBoolParameter"
    block_type = MC_ReadBoolParameter
    command: Literal["read_bool_parameter"]  # type: ignore[assignment]


class WriteParameter(_Call):
    """MC_WriteParameter (TcMC §4.9): write ``value`` to an LREAL parameter; Done, or an
    error for an unknown or read-only number."""

    block = "MC_WriteParameter"
    block_type = MC_WriteParameter
    command: Literal["write_parameter"]
    parameter_number: StrictInt
    """The MC_AxisPara number."""
    value: Number
    """The new value."""

    def arguments(self) -> dict[str, Any]:
        return {"parameter_number": self.parameter_number, "value": self.value}


class WriteBoolParameter(_Call):
    """MC_WriteBoolParameter (TcMC §4.10): write a BOOL parameter."""

    block = "MC_WriteBoolParameter"
    block_type = MC_WriteBoolParameter
    command: Literal["write_bool_parameter"]
    parameter_number: StrictInt
    """The MC_AxisPara number, e.g. 1015."""
    value: StrictBool
    """The new value."""

    def arguments(self) -> dict[str, Any]:
        return {"parameter_number": self.parameter_number, "value": self.value}


class ReadParameterSet(_Call, Query):
    """MC_ReadParameterSet (TcMC §4.11): every AxisParameters field as an output."""

    block = "MC_ReadParameterSet"
    block_type = MC_ReadParameterSet
    trigger = "execute"
    command: Literal["read_parameter_set"]
    outputs = tuple(field.name for field in dataclasses.fields(AxisParameters))

    def call(self, axis: Axis | None, now: float) -> Command:
        block = self.block_type(axis)
        block(execute=True)
        if block.error:
            return block_query(self.command, now, block)
        return query_command(self.command, now, block.parameter)


class GetVersion(_Call, Query):
    """F_GetVersionTcMC (TcMC §5.1): output ``version``, one element of the library version.

    The function reads no axis: the entry names none.
    """

    block = "F_GetVersionTcMC"
    command: Literal["get_version"]
    axis: Literal[""] = ""  # type: ignore[assignment]
    outputs = ("version",)
    version_element: StrictInt
    """1: major, 2: minor, 3: revision; any other number reads 0."""

    def call(self, axis: Axis | None, now: float) -> Command:
        return query_command(self.command, now,
                             {"version": F_GetVersionTcMC(self.version_element)})


BLOCK_ENTRIES: tuple[type[BlockEntry], ...] = (
    Jog, EnableExternalSetpoints, DisableExternalSetpoints, OverrideFilter, PowerStepper,
    InjectStall, ReleaseStall, SetReferenceFlag, ReadAxisComponents, MoveAbsoluteOrRestart,
    ReadActualPosition, ReadStatus, ReadAxisError, ReadParameter, ReadBoolParameter,
    WriteParameter, WriteBoolParameter, ReadParameterSet, GetVersion)
#: the entries that call a block once (MC_MoveAbsoluteOrRestart, the reads, the parameters)
CALL_ENTRIES: tuple[type[BlockEntry], ...] = (
    MoveAbsoluteOrRestart, ReadActualPosition, ReadStatus, ReadAxisError, ReadParameter,
    ReadBoolParameter, WriteParameter, WriteBoolParameter, ReadParameterSet, GetVersion)
