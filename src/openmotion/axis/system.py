"""The single axes of one runtime as a System (kernel/system.py): their kernel arrays, the
events that end profiles and overlays, the geared-sample checks, the drives and the
watchers of running commands."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.axis.axis import Axis
from openmotion.axis.drive import DriveModel
from openmotion.axis.kernel import AxisKernel
from openmotion.axis.parameters import PARAMETER_FIELDS, AxisParameters
from openmotion.core.checks import finite_number
from openmotion.core.errors import ConfigError, ErrorId

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime

Watcher = Callable[[float], bool]


@dataclass(frozen=True)
class AxisBlock:
    """The samples of a quiet stretch of cycles (``AxisSystem.advance_quietly``): row ``k``
    of each (cycles, axes) array is what the kernel arrays held after the cycle at
    ``times[k]``, columns by kernel row. Read-only: the actual values are the set values
    themselves (ideal drives follow exactly)."""

    times: np.ndarray
    set_p: np.ndarray
    set_v: np.ndarray
    set_a: np.ndarray
    set_j: np.ndarray
    act_p: np.ndarray
    act_v: np.ndarray


class AxisSystem:
    """Every axis of a runtime; the runtime makes it first, so it runs first in each phase."""

    name = "axes"

    def __init__(self, runtime: Runtime) -> None:
        self.runtime = runtime
        self.kernel = AxisKernel(runtime.cycle_time)  #: the axes' setpoints and drives, by row
        self.axes: dict[str, Axis] = {}
        self._rows: list[Axis] = []  #: by kernel row
        self._watchers: list[tuple[int, int, Watcher]] = []
        self._watch_serial = 0
        self._followed = False  #: this cycle's drive phase was done with the motion phase

    def objects(self) -> tuple[Axis, ...]:
        return tuple(self._rows)

    def add(self, name: str, parameters: AxisParameters | None = None,
            drive: DriveModel | None = None, position: float = 0.0, **overrides: Any) -> Axis:
        """Create an axis (``Runtime.add_axis``); a bad value is a ``ConfigError`` naming it."""
        if not isinstance(name, str):
            raise ConfigError(f"axes: an axis name must be a str, got {name!r}")
        if name in self.axes:
            raise ConfigError(f"axes: an axis named {name!r} exists already")
        unknown = set(overrides) - PARAMETER_FIELDS
        if unknown:
            raise ConfigError(f"axis {name!r}: unknown parameter(s) {sorted(unknown)}")
        if parameters is not None and not isinstance(parameters, AxisParameters):
            raise ConfigError(f"axis {name!r}: parameters must be an AxisParameters, got "
                              f"{type(parameters).__name__}")
        if drive is not None and not isinstance(drive, DriveModel):
            raise ConfigError(f"axis {name!r}: drive must be a DriveModel, got "
                              f"{type(drive).__name__}")
        start = finite_number(position, f"axis {name!r}: position")
        try:
            if parameters is None:
                parameters = AxisParameters(**overrides)
            elif overrides:  # a copy: a refused override leaves the caller's object as it was
                parameters = replace(parameters, **overrides)
            else:
                parameters.validate()
        except (TypeError, ValueError) as exc:
            raise ConfigError(f"axis {name!r}: {exc}") from None
        drive = drive or DriveModel()
        alpha, dead = drive.coefficients(self.runtime.cycle_time)
        row = self.kernel.add(start, alpha, dead)
        axis = Axis(self, name, row, parameters, drive)
        self.axes[name] = axis
        self._rows.append(axis)
        return axis

    def watch(self, axis: Axis, watcher: Watcher) -> None:
        """Call ``watcher(now)`` after each drive phase until it returns False; watchers run
        by axis row, then in the order they were set."""
        self._watch_serial += 1
        self._watchers.append((axis.row, self._watch_serial, watcher))

    def rewind(self) -> None:
        """The runtime's clock goes back to 0: so does the instant of the last sample, where
        the first plan of an axis starts. Axes made before would keep profiles placed in the
        old time: refused (D-231)."""
        if self.kernel.size:
            raise ConfigError(f"rewind: the clock goes back only before the first axis is "
                              f"made; there are {', '.join(self.axes)}")
        self.kernel.sample_time = 0.0

    # -- the cycle -----------------------------------------------------------------------------

    def advance(self, now: float) -> None:
        """Motion phase: end what ends now, evaluate the setpoints, fault bad geared samples.

        The events are looked for only from the kernel's ``next_event`` on: before it no
        profile can have ended (a cached bound, not a look at every row in every cycle)."""
        kernel = self.kernel
        if kernel.size and now >= kernel.next_event():  # planar movers only: no single axes
            for row in kernel.overlay_ended(now).tolist():
                self._rows[row].superposition.ended()
            ended = kernel.ended(now)
            if ended.size:
                end = kernel.segments.end
                for row in ended.tolist():
                    self._rows[row].queue.profile_ended(float(end[row]))
            kernel.forget_events()
        # alone, no other system corrects the setpoints before the drive phase: ideal drives
        # follow in the same pass
        self._followed = len(self.runtime.systems) == 1 and kernel.evaluate_and_follow(now)
        if self._followed:
            return
        kernel.evaluate(now)  # also without axes: the sample time an axis added later starts at
        if not kernel.couplings.slaves.size:
            return
        for _ in range(kernel.size):  # a faulted master changes its slaves' samples too
            bad = kernel.slave_violations()
            if not bad.size:
                break
            for row in bad.tolist():
                self._rows[row].gearing.limit_fault()
            kernel.evaluate(now, again=True)

    def monitor(self, now: float) -> None:
        """Drive phase: the drives follow, lag alarms fault, watchers look at the result."""
        kernel = self.kernel
        if not kernel.size:
            return
        if self._followed:  # ideal drives, followed in the motion phase: no lag to alarm
            self._followed = False
            if self._watchers:
                self._watch(now)
            return
        kernel.simulate_drives()
        alarms = kernel.lag_alarms()
        if alarms.size:
            for row in alarms.tolist():
                axis = self._rows[row]
                axis.fault(ErrorId.FOLLOWING_ERROR,
                           f"following error {axis.following_error:.6g} beyond "
                           f"{axis.parameters.max_position_lag}")
        if self._watchers:
            self._watch(now)

    def _watch(self, now: float) -> None:
        """Each watcher looks once; those that return False are dropped."""
        watchers, self._watchers = sorted(self._watchers), []
        keep = [item for item in watchers if item[2](now)]
        self._watchers = sorted(keep + self._watchers)

    # -- quiet stretches (kernel/system.py "Quiet stretches") ------------------------------------

    def quiet_until(self) -> float:
        """The first instant whose cycle must run phase by phase: the next end of a profile
        or superimposed motion; -inf (the next cycle) while a watcher runs (Done windows,
        homing, stalls, resets ...) or the kernel integrates something every cycle (lag
        drives, geared slaves, fed setpoints); +inf when nothing is ahead. A watcher that
        can say when its next look matters (``quiet_until``, the Done window of a position
        job at rest) does not stop the stretch before that."""
        kernel = self.kernel
        if not kernel.quiet:
            return -math.inf
        until = kernel.next_event() if kernel.size else math.inf
        for _, _, watcher in self._watchers:  # a Done window knows its end ahead
            look = getattr(watcher, "quiet_until", None)
            if look is None:
                return -math.inf
            until = min(until, look())
        return until

    def advance_quietly(self, now: float, cycles: int,
                        times: np.ndarray | None) -> AxisBlock | None:
        """Both phases of the ``cycles`` cycles up to the one at ``now``, all before
        ``quiet_until``: nothing ends and the drives follow exactly, so the state after them
        is the state after the last one, a pure function of its time (one evaluation), and
        the Done windows add up their times. ``times``: every cycle's time when an observer
        wants the samples; then they are evaluated in one compiled pass over time, bit for
        bit what each cycle would have given."""
        kernel = self.kernel
        n = kernel.size
        for _, _, watcher in self._watchers:  # the looks the stretch made no step for
            watcher.skip(cycles)  # type: ignore[attr-defined]
        if times is None:
            if not kernel.evaluate_and_follow(now):  # ideal drives: in the same pass
                kernel.evaluate(now)
                kernel.simulate_drives()
            return None
        p, v, a, j = (np.empty((times.shape[0], n)) for _ in range(4))
        if kernel.has_overlays:  # added row by row: the cycle's own evaluation, each time
            for k, time in enumerate(times.tolist()):
                kernel.evaluate(time)
                p[k], v[k], a[k], j[k] = (kernel.set_p[:n], kernel.set_v[:n],
                                          kernel.set_a[:n], kernel.set_j[:n])
        else:
            kernel.segments.evaluate_many(times, p, v, a, j)
            kernel.evaluate(now)  # the last sample again: the kernel arrays and sample time
        kernel.simulate_drives()
        return AxisBlock(times, p, v, a, j, p, v)
