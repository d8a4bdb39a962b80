"""What a trace can record: the signals of the machine model, found through a registry.

A signal is named ``<object>.<signal>``: ``x.set_position``, ``m2.gap``, ``m1.x``. Every kind
of object declares its signals once, next to its class (``MACHINE``, kernel/model.py,
D-226); this module derives the trace's vocabulary from those declarations and keeps no list
of its own. The recorder looks the object up by name and asks the source registered for its
type (``source_of``) for a reader. The built-in sources read the model:

- ``AxisSignals`` for ``Axis``: the axis's signals (``AXIS_SIGNALS``), and those of a CA
  mover (``MOVER_SIGNALS``: ``gap``, ``track_position``, ``tcp_position``), which are named on
  the axis and read NaN while the axis is in no CA group (D-227);
- ``PlanarMoverSignals`` for ``MC_PlanarMover`` (``PLANAR_MOVER_SIGNALS``);
- ``PlanarGroupSignals`` for ``MC_PlanarGroup`` (``state``);
- ``PlanarEnvironmentSignals`` for ``MC_PlanarEnvironment`` (no signals: it only describes
  the stators and parts a planar figure draws);
- ``AxesGroupSignals`` for a Part 4 ``AxesGroup`` (``GROUP_SIGNALS``);
- ``RoutePlansSource`` for a runtime's ``RoutePlans`` (no signals: the ways its routers
  planned and their obstacles, which the planar figure draws);
- ``ModelSignals`` of its kind for any other object of the model (a CA group, a planar track
  or part).

``register_source(kind, source)`` adds a kind of object the model does not know. A source
may also read all its objects' values of one signal in one numpy operation (``bulk``), and
``describe`` an object for the trace's ``layout``: what a figure needs beyond the columns
(stators, footprints, rails, gaps). Every value is a float64; a state is its enum number.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.axis.axis import Axis
from openmotion.coordinated.group import AxesGroup
from openmotion.kernel.model import Kind, SignalSpec, compact_index, kind_of
from openmotion.planar import MC_PlanarEnvironment, MC_PlanarGroup, MC_PlanarMover
from openmotion.planar.routing.plans import RoutePlans
from openmotion.planar.stators import STATOR_SIZE
from openmotion.transport.movers import Mover

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime

__all__ = ["AXIS_SIGNALS", "DEFAULT_AXIS_SIGNALS", "DEFAULT_GROUP_SIGNALS", "GROUP_SIGNALS",
           "MOVER_SIGNALS", "PLANAR_MOVER_SIGNALS", "AxesGroupSignals", "AxisSignals",
           "ModelSignals", "PlanarEnvironmentSignals", "PlanarGroupSignals",
           "PlanarMoverSignals", "RoutePlansSource", "SignalSource", "compact_index",
           "default_signals", "describe",
           "read_group_signal", "read_planar_signal", "read_signal", "register_source",
           "source_of", "split_signal"]

Reader = Callable[[], float]
BulkReader = Callable[[], np.ndarray]

_AXIS, _CA_MOVER = Axis.MACHINE, Mover.MACHINE
_PLANAR_MOVER, _GROUP = MC_PlanarMover.MACHINE, AxesGroup.MACHINE
#: the signals only members of a CA group have (NaN for other axes)
MOVER_SIGNALS = _CA_MOVER.signal_names
#: what a trace records of an axis: its own signals, then a CA mover's (D-227)
AXIS_SIGNALS = _AXIS.signal_names + MOVER_SIGNALS
#: what a scenario records when it names no signals: setpoint and actual position
DEFAULT_AXIS_SIGNALS = tuple(spec.name for spec in _AXIS.signals if spec.default)
#: a planar mover's signals (planar/kind.py)
PLANAR_MOVER_SIGNALS = _PLANAR_MOVER.signal_names
#: an axes group's signals (coordinated/kind.py)
GROUP_SIGNALS = _GROUP.signal_names
#: what a scenario records of each axes group when it names no signals
DEFAULT_GROUP_SIGNALS = tuple(spec.name for spec in _GROUP.signals if spec.default)
_SIGNAL = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\.([a-z_]+)$")
_AXIS_SPECS = {spec.name: spec for spec in (*_AXIS.signals, *_CA_MOVER.signals)}


def split_signal(name: str) -> tuple[str, str]:
    """``"x.set_position"`` -> ``("x", "set_position")``; ValueError for anything else."""
    match = _SIGNAL.match(name)
    if match is None or match.group(2) not in AXIS_SIGNALS:
        raise ValueError(f"{name!r} is not '<axis>.<signal>' with a signal among "
                         f"{', '.join(AXIS_SIGNALS)}")
    return match.group(1), match.group(2)


def read_signal(axis: Axis, prop: str) -> float:
    """One signal of ``axis`` as a float, as the model declares it (axis/kind.py; a CA
    mover's signals: transport/kind.py, NaN for an axis in no CA group)."""
    return _AXIS_SPECS[prop].read(axis)


def default_signals(axis_names: Iterable[str]) -> list[str]:
    return [f"{axis}.{prop}" for axis in axis_names for prop in DEFAULT_AXIS_SIGNALS]


def read_planar_signal(mover: MC_PlanarMover, prop: str) -> float:
    """One signal of a planar mover, as the model declares it (planar/kind.py)."""
    return _PLANAR_MOVER.signal(prop).read(mover)


def read_group_signal(group: AxesGroup, prop: str) -> float:
    """One signal of an axes group, as the model declares it (coordinated/kind.py)."""
    return _GROUP.signal(prop).read(group)


# -- the registry ------------------------------------------------------------------------------


class SignalSource:
    """What a recorder can read from one kind of object (subclass and register it)."""

    kind = "object"  #: the object's kind in the trace's layout (``objects``)
    signals: tuple[str, ...] = ()

    def read(self, obj: Any, prop: str) -> float:
        """The value of one signal now."""
        raise NotImplementedError

    def reader(self, obj: Any, prop: str) -> Reader:
        """A call that reads one signal (called once per sample)."""
        return lambda: self.read(obj, prop)

    def bulk(self, runtime: Runtime, objects: Sequence[Any], prop: str) -> BulkReader | None:
        """A call that reads ``prop`` of all ``objects`` as one array, or None (one reader
        per object is used then)."""
        return None

    def describe(self, obj: Any) -> dict[str, Any]:
        """What figures need to know of the object besides its name and kind, which
        ``describe`` (the function) adds (JSON-able)."""
        return {}


class ModelSignals(SignalSource):
    """The signals one or more kinds of the machine model declare: their readers and bulk
    readers are the model's (kernel/model.py)."""

    def __init__(self, *kinds: Kind) -> None:
        self.kind = kinds[0].name
        self._specs: dict[str, SignalSpec] = {
            spec.name: spec for kind in kinds for spec in kind.signals}
        self.signals = tuple(self._specs)

    def read(self, obj: Any, prop: str) -> float:
        return self._specs[prop].read(obj)

    def reader(self, obj: Any, prop: str) -> Reader:
        read = self._specs[prop].read
        return lambda: read(obj)

    def bulk(self, runtime: Runtime, objects: Sequence[Any], prop: str) -> BulkReader | None:
        """The model's bulk reader (the kernel's arrays hold the kinematic signals of every
        axis: one gather each), or None."""
        bulk = self._specs[prop].bulk
        return None if bulk is None else bulk(objects)


class AxisSignals(ModelSignals):
    """An axis (and a CA mover: an axis in a CA group, D-227)."""

    def __init__(self) -> None:
        super().__init__(_AXIS, _CA_MOVER)

    def describe(self, obj: Axis) -> dict[str, Any]:
        group: Any = obj.group
        if group is None or isinstance(group, AxesGroup):
            return {}
        parameters = group.parameters
        stations = [station for line in group.station_lines for station in line.layout()]
        return {"ca_groups": {group.name: {
            "rail_length": float(parameters.rail_length),
            "rail_is_ring": bool(parameters.rail_is_ring),
            "default_gap": float(parameters.default_gap),
            "movers": list(group.order),
            **({"stations": stations} if stations else {})}}}


class PlanarMoverSignals(ModelSignals):
    def __init__(self) -> None:
        super().__init__(_PLANAR_MOVER)

    def describe(self, obj: MC_PlanarMover) -> dict[str, Any]:
        parameters = obj.parameters
        return {"planar": {"movers": {obj.name: {"width": float(parameters.mover_width),
                                                 "height": float(parameters.mover_height)}}}}


class PlanarGroupSignals(ModelSignals):
    def __init__(self) -> None:
        super().__init__(MC_PlanarGroup.MACHINE)


class PlanarEnvironmentSignals(ModelSignals):
    """No signals: the stators (their lower-left corners) and, with parts, the coordinate
    systems and the outline of every part in each of its positions (``active``: the one it
    is in)."""

    def __init__(self) -> None:
        super().__init__(MC_PlanarEnvironment.MACHINE)

    def describe(self, obj: MC_PlanarEnvironment) -> dict[str, Any]:
        planar: dict[str, Any] = {
            "stator_size": STATOR_SIZE,
            "stators": [[stator.lower_x, stator.lower_y] for stator in obj.field.stators]}
        layout = obj.layout
        if layout is not None:  # every position of every part, in its coordinate system
            planar["coordinate_systems"] = list(layout.coordinate_systems)
            planar["parts"] = [
                {"name": part.name, "coordinate_system": position.coordinate_system,
                 "active": index == part.position_index,
                 "outline": [list(point) for point in part.surface(index).exterior.coords]}
                for part in layout.parts.values()
                for index, position in enumerate(part.positions, start=1)]
        return {"planar": planar}


class AxesGroupSignals(ModelSignals):
    """A Part 4 axes group: its members (IdentInGroup order) and MCS coordinates describe it
    for the path figure."""

    def __init__(self) -> None:
        super().__init__(_GROUP)

    def describe(self, obj: AxesGroup) -> dict[str, Any]:
        return {"axes_groups": {obj.name: {
            "axes": [axis.name for axis in obj.axes],
            "coordinates": list(obj.kinematics.coordinates)}}}


class RoutePlansSource(SignalSource):
    """No signals: every way the runtime's routers planned, with its time, and their
    obstacles (planar/routing/plans.py), for the planar figure."""

    kind = "route_plans"

    def describe(self, obj: RoutePlans) -> dict[str, Any]:
        return obj.layout()


_SOURCES: dict[type, SignalSource] = {}


def register_source(kind: type, source: SignalSource) -> None:
    """Let traces record objects of type ``kind`` (and its subclasses) through ``source``."""
    _SOURCES[kind] = source


def source_of(obj: object) -> SignalSource | None:
    """The source registered for the type of ``obj`` or its nearest base class; else the
    signals its kind declares in the machine model; else None."""
    for kind in type(obj).__mro__:
        source = _SOURCES.get(kind)
        if source is not None:
            return source
    declared = kind_of(obj)
    if declared is None:
        return None
    source = _MODEL_SOURCES.get(declared.name)
    if source is None:
        source = _MODEL_SOURCES[declared.name] = ModelSignals(declared)
    return source


_MODEL_SOURCES: dict[str, ModelSignals] = {}  #: by kind name, for kinds without a source


def describe(objects: Iterable[object]) -> dict[str, Any]:
    """The layout of ``objects``: ``objects`` maps each name to its source's kind, and the
    sources' descriptions are merged in, in object order."""
    layout: dict[str, Any] = {"objects": {}}
    for obj in objects:
        source = source_of(obj)
        if source is not None:
            layout["objects"][getattr(obj, "name", "")] = source.kind
            _merge(layout, source.describe(obj))
    return layout


def _merge(into: dict[str, Any], more: dict[str, Any]) -> None:
    for key, value in more.items():
        if isinstance(value, dict) and isinstance(into.get(key), dict):
            _merge(into[key], value)
        else:
            into[key] = value


register_source(Axis, AxisSignals())
register_source(MC_PlanarMover, PlanarMoverSignals())
register_source(MC_PlanarGroup, PlanarGroupSignals())
register_source(MC_PlanarEnvironment, PlanarEnvironmentSignals())
register_source(AxesGroup, AxesGroupSignals())
register_source(RoutePlans, RoutePlansSource())
