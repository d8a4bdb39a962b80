"""MC_OverrideFilter: a raw analog override, quantised and rate-limited (TcMC §4.19).

The block has neither Execute nor Enable: every call evaluates it. Time comes from the runtime
that the block is built with (``MC_OverrideFilter(rt)`` reads ``rt.now``), or from any callable
returning seconds, so a run is deterministic and never looks at the wall clock.

Rules (digest §4, rules 120-125):

* ``override_value_raw`` is clamped to ``[lower_override_threshold, upper_override_threshold]``
  and mapped onto ``override_steps`` steps, rounded to the *nearest* step, halves up (Open Q29,
  docs/decisions.md). Exact integer arithmetic: no float drift at the step boundaries.
* After each change of the output, a further change waits until ``override_recovery_time``
  [s] has passed since that change. The input is re-read on every call, so once the time is up
  the output catches up with the *latest* raw value, not with a value remembered from earlier.
* A change to exactly 0 % or 100 % is applied in the same call, whatever the recovery time
  (the manual: "for safety reasons"). Such a change also restarts the recovery time.
* The first valid evaluation (and the first after an error) applies its value at once: no
  output change has happened yet that a recovery time could follow.
* ``override_value_filtered`` (0...1 000 000, the PlcToNc DWORD) is
  ``override_percent_filtered`` x 10 000, rounded to an integer.

Errors: ``override_steps <= 1`` or ``lower_override_threshold >= upper_override_threshold``
give the manual's MC_ERROR_PARAMETER_NOT_CORRECT. Its number is not given (Open Q28), so the
block reports ``ErrorId.INVALID_PARAMETER_VALUE`` (0x7013, openmotion's own range). The same id
is given for inputs that are not whole numbers (DINT/UDINT) or a recovery time that is negative
or not finite. While in error both outputs are 0 (a misconfigured filter stops the feed rather
than pass on a stale or unfiltered override); the block recovers as soon as the inputs are
valid again.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from numbers import Integral, Real
from typing import Any, ClassVar, Protocol

from openmotion.core.errors import ErrorId
from openmotion.core.override import DWORD_FULL_SCALE, PERCENT
from openmotion.kernel.handshake import FunctionBlock

_TIME_TOLERANCE = 1e-9  #: [s] absorbs float noise in ``now`` (cycle * cycle_time)


class _HasNow(Protocol):
    now: float


def _whole(value: Any) -> int | None:
    """``value`` as an int if it is a whole number (DINT / UDINT inputs), else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, Integral):
        return int(value)
    if isinstance(value, Real) and math.isfinite(value) and float(value).is_integer():
        return int(value)
    return None


class MC_OverrideFilter(FunctionBlock):
    """Filtered override from a raw value; call it every cycle (TcMC §4.19).

    ``MC_OverrideFilter(rt)`` or ``MC_OverrideFilter(clock)`` with ``clock() -> seconds``; then
    ``f(override_value_raw=16384)`` each cycle and read ``override_percent_filtered`` (0...100)
    or ``override_value_filtered`` (0...1 000 000). ``override_recovery_time`` is in seconds
    (TwinCAT TIME T#150ms = 0.150).

    MC_ERROR_PARAMETER_NOT_CORRECT is reported as ``ErrorId.INVALID_PARAMETER_VALUE`` (Open Q28).
    """

    INPUTS: ClassVar[dict[str, Any]] = {
        "override_value_raw": 0,
        "lower_override_threshold": 0,
        "upper_override_threshold": 32767,
        "override_steps": 200,
        "override_recovery_time": 0.150,
    }

    def __init__(self, clock: _HasNow | Callable[[], float], **inputs: Any) -> None:
        if callable(clock):
            self._clock: Callable[[], float] = clock
        elif hasattr(clock, "now"):
            self._clock = lambda: clock.now
        else:
            raise TypeError("MC_OverrideFilter needs a runtime (with .now) or a clock callable")
        super().__init__(None, **inputs)

    def _reset_outputs(self) -> None:
        super()._reset_outputs()
        self.override_value_filtered = 0
        self.override_percent_filtered = 0.0
        self._step: int | None = None  #: the step on the output; None before the first value
        self._changed_at: float | None = None  #: when the output last changed [s]

    def __call__(self, **inputs: Any) -> None:
        if inputs:
            self._set_inputs(inputs)
        self._evaluate(float(self._clock()))
        if self.strict:
            self._check_invariants()

    # -- evaluation ----------------------------------------------------------------------------

    def _evaluate(self, now: float) -> None:
        raw = _whole(self.override_value_raw)
        lower = _whole(self.lower_override_threshold)
        upper = _whole(self.upper_override_threshold)
        steps = _whole(self.override_steps)
        recovery = self.override_recovery_time
        problem = ""
        if raw is None or lower is None or upper is None or steps is None:
            problem = "raw value, thresholds and steps must be whole numbers"
        elif steps <= 1:
            problem = f"override_steps must be > 1, got {steps}"
        elif lower >= upper:
            problem = (f"lower_override_threshold ({lower}) must be below "
                       f"upper_override_threshold ({upper})")
        elif (isinstance(recovery, bool) or not isinstance(recovery, Real)
              or not (math.isfinite(recovery) and recovery >= 0)):
            problem = f"override_recovery_time must be a finite number >= 0 s, got {recovery!r}"
        if problem:
            self._fail(problem)
            return
        assert raw is not None and lower is not None and upper is not None and steps is not None
        self.error, self.error_id, self.message = False, ErrorId.NO_ERROR, ""
        target = quantise(raw, lower, upper, steps)
        if target == self._step:
            return
        immediate = (self._step is None or target in (0, steps) or self._changed_at is None
                     or now - self._changed_at >= float(recovery) - _TIME_TOLERANCE)
        if immediate:
            self._apply(target, steps, now)

    def _apply(self, step: int, steps: int, now: float) -> None:
        self._step = step
        self._changed_at = now
        self.override_percent_filtered = step * PERCENT / steps
        self.override_value_filtered = (2 * step * DWORD_FULL_SCALE + steps) // (2 * steps)

    def _fail(self, message: str) -> None:
        self.error, self.error_id, self.message = True, ErrorId.INVALID_PARAMETER_VALUE, message
        self.override_value_filtered = 0
        self.override_percent_filtered = 0.0
        self._step = None
        self._changed_at = None

    def _check_invariants(self) -> None:
        assert self.error or self.error_id == ErrorId.NO_ERROR, "error_id without error"
        assert 0 <= self.override_value_filtered <= DWORD_FULL_SCALE
        assert 0.0 <= self.override_percent_filtered <= 100.0


def quantise(raw: int, lower: int, upper: int, steps: int) -> int:
    """Step (0...steps) nearest to ``raw`` clamped to [lower, upper]; halves round up.

    Integer arithmetic: ``floor((2 (raw - lower) steps + span) / (2 span))``.
    """
    span = upper - lower
    clamped = min(max(raw, lower), upper) - lower
    return (2 * clamped * steps + span) // (2 * span)
