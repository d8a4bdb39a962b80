"""The single axes of one runtime as a System (kernel/system.py): their kernel arrays, the
events that end profiles and overlays, the geared-sample checks, the drives and the
watchers of running commands."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from openmotion.axis.axis import Axis
from openmotion.axis.drive import DriveModel
from openmotion.axis.kernel import AxisKernel
from openmotion.axis.parameters import PARAMETER_FIELDS, AxisParameters
from openmotion.core.checks import finite_number
from openmotion.core.errors import ConfigError, ErrorId

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime

Watcher = Callable[[float], bool]


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
        """Motion phase: end what ends now, evaluate the setpoints, fault bad geared samples."""
        kernel = self.kernel
        if kernel.size:  # a machine of planar movers only has no single axes to advance
            for row in kernel.overlay_ended(now).tolist():
                self._rows[row].superposition.ended()
            ended = kernel.ended(now)
            if ended.size:
                end = kernel.segments.end
                for row in ended.tolist():
                    self._rows[row].queue.profile_ended(float(end[row]))
        kernel.evaluate(now)  # also without axes: the sample time an axis added later starts at
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
        kernel.simulate_drives()
        alarms = kernel.lag_alarms()
        if alarms.size:
            for row in alarms.tolist():
                axis = self._rows[row]
                axis.fault(ErrorId.FOLLOWING_ERROR,
                           f"following error {axis.following_error:.6g} beyond "
                           f"{axis.parameters.max_position_lag}")
        if self._watchers:
            watchers, self._watchers = sorted(self._watchers), []
            keep = [item for item in watchers if item[2](now)]
            self._watchers = sorted(keep + self._watchers)
