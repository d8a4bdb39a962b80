"""What the viewer shows of one subsystem: a canvas panel, rows of the objects table, and
the signals its scope offers.

A *layer factory* looks at a runtime and returns the layers of its subsystem (none when the
runtime has none of it). The factories of the shipped subsystems (axes.py, rails.py,
planar.py) are registered when ``openmotion.viewer`` is imported, in drawing order; a new
subsystem plugs in with ``@register_layer``. Layers are read only by the session's kernel
thread, between two cycles, so they need no locks.

The scope offers the signals of the machine model (kernel/model.py, D-228): every signal
its kind declares for a live scope (``scope``), under its ``<object>.<signal>`` name
(``scope_signals``); a layer adds signals only for what the model does not know. The table
lists every object of the model: a layer's rows, then a plain row (kind, name, state) for
each object no layer shows (``model_rows``).

Every number a layer hands out must be JSON: finite floats or None (``finite``).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING, Any, ClassVar

from openmotion.kernel.model import MachineModel, MachineObject, Signal

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime

Reader = Callable[[], float]  #: reads one scope signal now
LayerFactory = Callable[["Runtime"], Iterable["Layer"]]

_FACTORIES: list[LayerFactory] = []


@dataclass(frozen=True)
class Row:
    """One line of the objects table; every field is already text."""

    kind: str  #: "axis", "CA mover", "planar mover", ...
    name: str
    state: str
    position: str = ""
    velocity: str = ""
    command: str = ""  #: what the object is busy with; "" when idle
    detail: str = ""  #: a gap, a lift, a member count ...
    error: str = ""  #: error id and message; "" when there is none


class Layer(ABC):
    """One subsystem's part of a frame. ``kind`` names the page's drawing function."""

    kind: ClassVar[str]
    name: str

    @abstractmethod
    def panel(self) -> dict[str, Any]:
        """What the canvas draws now, as JSON-ready data."""

    def rows(self) -> list[Row]:
        """The table rows of the layer's objects."""
        return []

    def signals(self) -> dict[str, Reader]:
        """Scope signals by name (``object.property``) beyond the machine model's, read only
        while selected."""
        return {}


def register_layer(factory: LayerFactory) -> LayerFactory:
    """Show a subsystem in every session made from now on (usable as a decorator)."""
    if factory not in _FACTORIES:
        _FACTORIES.append(factory)
    return factory


def registered_layers() -> tuple[LayerFactory, ...]:
    """The layer factories in drawing order."""
    return tuple(_FACTORIES)


def scope_signals(model: MachineModel) -> dict[str, Signal]:
    """The signals of every object of the machine model that a live scope offers, by
    qualified name, in model order (an object's in the order its kind declares them)."""
    found: dict[str, Signal] = {}
    for obj in model:
        for signal in obj.signals:
            if signal.scope:
                found.setdefault(f"{obj.name}.{signal.name}", signal)
    return found


def model_rows(model: MachineModel, shown: Iterable[str]) -> list[Row]:
    """A row of kind, name and state for every object of the model that no layer shows (an
    axes group, its axes, a part): the table lists every object of the machine (D-228)."""
    seen = set(shown)
    return [Row(obj.kind.replace("_", " "), obj.name, _state(obj))
            for obj in model if obj.name not in seen]


def _state(obj: MachineObject) -> str:
    """The object's state signal as the enum member's name, "-" without one."""
    for signal in obj.signals:
        if signal.name == "state" and issubclass(signal.dtype, Enum):
            return signal.dtype(int(signal.read())).name.lower()
    return "-"


def first_scope(signals: dict[str, Signal]) -> list[str]:
    """What the scope shows when the machine names nothing: the first signal and the actual
    value its kind declares for it (set position and position), else the first two."""
    names = list(signals)
    if not names:
        return []
    first = signals[names[0]]
    actual = f"{names[0].rpartition('.')[0]}.{first.spec.actual}"
    return [names[0], actual] if first.spec.actual and actual in signals else names[:2]


def finite(value: float) -> float | None:
    """``value`` as JSON allows it: None for NaN and infinities."""
    value = float(value)
    return value if math.isfinite(value) else None


def number(value: float, digits: int = 3) -> str:
    """A value for the table: fixed decimals, "-" for NaN and infinities."""
    if not math.isfinite(value):
        return "-"
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0.0 else text


def error_text(error_id: Any, message: str) -> str:
    """``NAME: message`` of an error id that is set, else ""."""
    if not int(error_id):
        return ""
    return f"{error_id.name}: {message}" if message else error_id.name
