"""Touch-probe signals and the position latch behind MC_TouchProbe (TcMC §4.21, §4.22, §6.3).

A ``ProbeSignal`` is the digital input wired to the axis' encoder hardware (TouchProbe1). It
is TRUE while the axis is inside given position intervals (a cam or light barrier), or during
given time intervals (an external event). The simulated hardware latch records the position
where the edge happens, interpolated linearly between the two cycle samples around it: for a
position-defined edge that is the edge position itself, for a time-defined edge the position
at that instant. The latch therefore does not depend on the cycle time, as the manual says of
the real hardware. ``TouchProbeSource.PLC_EVENT`` instead records the actual position at the
end of the cycle in which ``InputRef.plc_event`` rose (cycle resolution, §6.3).

Intervals of a ``ProbeSignal`` are machine coordinates (the position with ``raw_offset``
removed): the sensor does not move when MC_SetActualPosition shifts the displayed coordinates.
Recorded positions are displayed coordinates.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import TYPE_CHECKING

from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.checks import limit_number
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis

#: a second probe cycle on an InputRef whose cycle is still armed (TcMC §4.21 note). ErrorId has
#: no own id for it; the latch is a one-slot buffer that is taken (see the decision record).
PROBE_ALREADY_ARMED = ErrorId.PROBE_ALREADY_ARMED


class TouchProbeSource(IntEnum):
    """E_TouchProbe (§6.3). Only TOUCH_PROBE_1 and PLC_EVENT are supported."""

    TOUCH_PROBE_1 = 1
    TOUCH_PROBE_2 = 2
    TOUCH_PROBE_3 = 3
    TOUCH_PROBE_4 = 4
    PLC_EVENT = 10


class SignalEdge(IntEnum):
    """E_SignalEdge (§6.3)."""

    RISING = 0
    FALLING = 1


class TouchProbeState(IntEnum):
    """E_TouchProbeState (§6.3): the sequence state kept in the InputRef."""

    INACTIVE = 0
    ACTIVATED = 1
    ABORTED = 2


@dataclass(eq=False)
class InputRef:
    """MC_InputRef (§6.3). Compared by identity: MC_AbortTrigger needs the same object."""

    encoder_id: int = 1  #: kept for fidelity; the axis is the encoder
    touch_probe: TouchProbeSource = TouchProbeSource.TOUCH_PROBE_1
    edge: SignalEdge = SignalEdge.RISING
    plc_event: bool = False  #: the PLC trigger when touch_probe is PLC_EVENT (rising edge)
    probe_state: TouchProbeState = TouchProbeState.INACTIVE  #: internal, do not write
    modulo_positions: bool = False  #: First/Last/RecordedPosition as modulo values


# -- the signal source -------------------------------------------------------------------------

_SIGNALS: weakref.WeakKeyDictionary[Axis, ProbeSignal] = weakref.WeakKeyDictionary()


def _intervals(name: str, spans: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    result: list[tuple[float, float]] = []
    for span in spans:
        if isinstance(span, str | bytes) or not hasattr(span, "__len__") or len(span) != 2:
            raise ConfigError(f"{name}: each entry must be a pair (from, to), got {span!r}")
        lo, hi = (limit_number(v, f"{name}: {span!r}") for v in span)  # inf: an open end
        if not lo < hi:
            raise ConfigError(f"{name}: need from < to, got {span!r}")
        result.append((lo, hi))
    result.sort()
    for (_, hi), (lo, _) in zip(result, result[1:], strict=False):
        if lo <= hi:
            raise ConfigError(f"{name}: intervals overlap or touch at {lo!r}")
    return result


class ProbeSignal:
    """The TouchProbe1 input of ``axis``: TRUE while inside ``positions`` or ``times``.

    ``positions``: intervals ``(from, to)`` of the machine position where the input is TRUE,
    ``from <= p < to`` (use ``math.inf`` for an open end). ``times``: intervals of virtual time
    ``from <= t < to``. Give one of the two. A new signal on the same axis replaces the old one.
    """

    def __init__(self, axis: Axis, positions: Sequence[tuple[float, float]] = (),
                 times: Sequence[tuple[float, float]] = ()) -> None:
        if positions and times:
            raise ConfigError("ProbeSignal: give positions or times, not both")
        self.axis = axis
        self.positions = _intervals("positions", positions)
        self.times = _intervals("times", times)
        self._t = axis.kernel.sample_time  # the instant the current actual position belongs to
        self._p = self._machine()
        self._edges: list[tuple[float, float, SignalEdge]] = []
        self.level = self._level(self._t, self._p)
        old = _SIGNALS.get(axis)
        if old is not None:
            old.detach()
        _SIGNALS[axis] = self
        self._attached = True
        axis.system.watch(axis, self._tick)

    def detach(self) -> None:
        """Unwire the input: no more edges."""
        self._attached = False
        if _SIGNALS.get(self.axis) is self:
            del _SIGNALS[self.axis]

    def _machine(self) -> float:
        return self.axis.position - self.axis.raw_offset

    def _level(self, t: float, p: float) -> bool:
        if self.times:
            return any(lo <= t < hi for lo, hi in self.times)
        return any(lo <= p < hi for lo, hi in self.positions)

    def _tick(self, now: float) -> bool:
        self.edges(now)
        return self._attached

    def edges(self, now: float) -> list[tuple[float, float, SignalEdge]]:
        """Edges of the last cycle, ``(time, displayed position, edge)``, in time order."""
        if now != self._t:
            self._sample(now)
        return self._edges

    def _sample(self, now: float) -> None:
        t0, p0 = self._t, self._p
        t1, p1 = now, self._machine()
        found: list[tuple[float, float, SignalEdge]] = []  # (fraction, machine position, edge)
        if self.times:
            for lo, hi in self.times:
                for t, kind in ((lo, SignalEdge.RISING), (hi, SignalEdge.FALLING)):
                    if t0 < t <= t1:
                        f = (t - t0) / (t1 - t0)
                        found.append((f, p0 + f * (p1 - p0), kind))
        elif p1 != p0:
            forward = p1 > p0
            for lo, hi in self.positions:
                for b, kind in ((lo, SignalEdge.RISING), (hi, SignalEdge.FALLING)):
                    if p0 < b <= p1 if forward else p1 < b <= p0:
                        if not forward:
                            kind = SignalEdge(1 - kind)
                        found.append(((b - p0) / (p1 - p0), b, kind))
        found.sort(key=lambda item: item[0])
        offset = self.axis.raw_offset
        self._edges = [(t0 + f * (t1 - t0), p + offset, kind) for f, p, kind in found]
        self._t, self._p = t1, p1
        self.level = self._level(t1, p1)


def probe_signal(axis: Axis) -> ProbeSignal | None:
    """The signal wired to ``axis``' TouchProbe1 input, if any."""
    return _SIGNALS.get(axis)


# -- the latch ---------------------------------------------------------------------------------

_ARMED: weakref.WeakKeyDictionary[InputRef, _ProbeCycle] = weakref.WeakKeyDictionary()


@dataclass(frozen=True)
class ProbeWindow:
    """Accepted positions: [first, last]; modulo windows with first > last wrap through 0."""

    first: float
    last: float
    period: float | None = None  #: None: absolute window

    def contains(self, position: float) -> bool:
        if self.period is None or self.first <= self.last:
            return self.first <= position <= self.last
        return position >= self.first or position <= self.last


class _ProbeCycle:
    """One armed latch: waits for an edge, filters it through the window, re-arms."""

    def __init__(self, axis: Axis, ref: InputRef, window: ProbeWindow | None,
                 command: Command) -> None:
        self.axis = axis
        self.ref = ref
        self.window = window
        self.command = command
        self.source = TouchProbeSource(ref.touch_probe)
        self.edge = SignalEdge(ref.edge)
        self.period = axis.parameters.modulo_period if ref.modulo_positions else None
        self.last_event = bool(ref.plc_event)
        self.rejected: list[float] = []  #: positions outside the window, in order

    def step(self, now: float) -> bool:
        if self.command.finished:
            return False
        if self.source is TouchProbeSource.PLC_EVENT:
            event = bool(self.ref.plc_event)
            candidates = [self.axis.position] if event and not self.last_event else []
            self.last_event = event
        else:
            signal = probe_signal(self.axis)
            edges = signal.edges(now) if signal is not None else []
            candidates = [p for _, p, kind in edges if kind is self.edge]
        for position in candidates:
            if self.period is not None:
                position %= self.period
            if self.window is None or self.window.contains(position):
                self.command.value = position
                self.end(CommandStatus.DONE, now, TouchProbeState.INACTIVE)
                return False
            self.rejected.append(position)  # the latch re-arms at once
        return True

    def end(self, status: CommandStatus, now: float, state: TouchProbeState) -> None:
        """Finish the cycle's command, show ``state`` on the TriggerInput and disarm."""
        self.command.end(status, now)
        self.ref.probe_state = state
        if _ARMED.get(self.ref) is self:
            del _ARMED[self.ref]


def _check_window(ref: InputRef, axis: Axis, first: object, last: object) -> ProbeWindow:
    values = []
    for name, value in (("first_position", first), ("last_position", last)):
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(
                value):
            raise CommandRejected(ErrorId.INVALID_POSITION, f"{name}: not a finite number")
        values.append(float(value))
    lo, hi = values
    if ref.modulo_positions:
        period = axis.parameters.modulo_period
        for name, value in (("first_position", lo), ("last_position", hi)):
            if not 0.0 <= value <= period:
                raise CommandRejected(ErrorId.INVALID_POSITION,
                                      f"{name}: {value} outside the modulo range 0..{period}")
        return ProbeWindow(lo, hi, period)
    if lo > hi:
        raise CommandRejected(ErrorId.INVALID_POSITION,
                              f"absolute window {lo}..{hi} is empty (first > last)")
    return ProbeWindow(lo, hi)


def arm_probe(axis: Axis, ref: InputRef, window_only: bool = False,
              first_position: float = 0.0, last_position: float = 0.0) -> Command:
    """Start a probe cycle; the command ends DONE with ``value`` = the recorded position."""
    rt = axis.runtime
    command = Command("touch_probe", rt.now)
    try:
        if ref.touch_probe not in TouchProbeSource.__members__.values():
            raise CommandRejected(ErrorId.INVALID_MODE, f"touch_probe: {ref.touch_probe!r}")
        if ref.touch_probe not in (TouchProbeSource.TOUCH_PROBE_1, TouchProbeSource.PLC_EVENT):
            raise CommandRejected(ErrorId.INVALID_MODE,
                                  f"{TouchProbeSource(ref.touch_probe).name} is not supported "
                                  "(only TouchProbe1 and PlcEvent, TcMC §6.3)")
        if ref.edge not in SignalEdge.__members__.values():
            raise CommandRejected(ErrorId.INVALID_MODE, f"edge: {ref.edge!r}")
        if ref.modulo_positions and not axis.parameters.modulo_period > 0:
            raise CommandRejected(ErrorId.INVALID_MODULO_PERIOD, "modulo period not > 0")
        window = (_check_window(ref, axis, first_position, last_position)
                  if window_only else None)
        running = _ARMED.get(ref)
        if running is not None and not running.command.finished:
            raise CommandRejected(PROBE_ALREADY_ARMED,
                                  "a probe cycle is armed on this TriggerInput: "
                                  "MC_AbortTrigger first (TcMC §4.21)")
    except CommandRejected as rejected:
        command.end(CommandStatus.ERROR, rt.now, rejected.error_id, rejected.message)
        return command
    cycle = _ProbeCycle(axis, ref, window, command)
    command.start()
    ref.probe_state = TouchProbeState.ACTIVATED
    _ARMED[ref] = cycle
    axis.system.watch(axis, cycle.step)
    return command


def abort_probe(ref: InputRef, now: float) -> bool:
    """Disarm the cycle armed on ``ref`` (MC_AbortTrigger); False if none was armed."""
    cycle = _ARMED.get(ref)
    if cycle is None or cycle.command.finished:
        return False
    cycle.end(CommandStatus.ABORTED, now, TouchProbeState.ABORTED)
    return True


def armed_cycle(ref: InputRef) -> _ProbeCycle | None:
    """The armed cycle behind ``ref`` (diagnostics: ``rejected`` positions)."""
    return _ARMED.get(ref)
