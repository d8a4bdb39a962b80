"""The runtime users make: the kernel's cyclic runtime with its single axes.

``Runtime`` is ``CyclicRuntime`` (kernel/runtime.py: time, phases, the System contract)
plus one ``AxisSystem`` added first, so that ``add_axis`` and ``axes`` work as a PLC user
expects; every other system (axes groups, CA groups, the planar objects) joins through
``add_system``.
"""

from __future__ import annotations

from typing import Any

from openmotion.axis.axis import Axis
from openmotion.axis.drive import DriveModel
from openmotion.axis.parameters import AxisParameters
from openmotion.axis.system import AxisSystem
from openmotion.kernel.runtime import CyclicRuntime, Observer, Program

__all__ = ["Observer", "Program", "Runtime"]


class Runtime(CyclicRuntime):
    """Virtual-time cyclic runtime. ``cycle_time`` in seconds (default 1 ms)."""

    def __init__(self, cycle_time: float = 0.001) -> None:
        super().__init__(cycle_time)
        self.axis_system = AxisSystem(self)  #: added first: runs first in every phase
        self.add_system(self.axis_system)

    @property
    def axes(self) -> dict[str, Axis]:
        """The axes by name, in creation order."""
        return self.axis_system.axes

    def add_axis(self, name: str, parameters: AxisParameters | None = None,
                 drive: DriveModel | None = None, position: float = 0.0, **overrides: Any) -> Axis:
        """Create an axis; keyword ``overrides`` set AxisParameters fields by name.

        ``position`` is where the axis stands [mm or °]. A value that is no finite number,
        here or in the parameters, is a ``ConfigError`` naming the field."""
        return self.axis_system.add(name, parameters, drive, position, **overrides)
