"""A runtime that follows the wall clock, for live viewers and protocol servers.

Only ``step`` differs from ``Runtime`` (SimPy's ``RealtimeEnvironment`` shape): it waits until
the wall clock has caught up with virtual time. Virtual time and the trace stay exactly those
of the unpaced runtime; only the pacing touches the wall clock.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from openmotion.core.checks import flag, positive_number
from openmotion.runtime.runtime import Runtime


class FallingBehindError(RuntimeError):
    """A strict paced runtime could not keep up with the wall clock."""


class PacedRuntime(Runtime):
    """``factor`` > 1 runs faster than real time; ``strict`` raises when it falls behind."""

    def __init__(self, cycle_time: float = 0.001, factor: float = 1.0, strict: bool = False,
                 clock: Callable[[], float] = time.monotonic,
                 sleep: Callable[[float], None] = time.sleep) -> None:
        super().__init__(cycle_time)
        self.factor = positive_number(factor, "factor")
        self.strict = flag(strict, "strict")
        self._clock = clock
        self._sleep = sleep
        self._origin: float | None = None
        self.late_cycles = 0  #: cycles that started after their wall-clock slot

    def step(self) -> None:
        if self._origin is None:
            self._origin = self._clock() - self.now / self.factor
        due = self._origin + (self.now + self.cycle_time) / self.factor
        lag = self._clock() - due
        if lag > 0.0:
            self.late_cycles += 1
            if self.strict and lag > self.cycle_time / self.factor:
                raise FallingBehindError(
                    f"{lag * 1e3:.3f} ms behind the wall clock at t={self.now}"
                )
        else:
            self._sleep(-lag)
        super().step()
