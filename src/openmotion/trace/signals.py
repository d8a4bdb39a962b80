"""What a trace can record: one ``SignalSource`` per kind of object, found through a registry.

A signal is named ``<object>.<signal>``: ``x.set_position``, ``m2.gap``, ``m1.x``. The
recorder looks the object up by name and asks the source registered for its type
(``source_of``) for a reader; it knows no kind of object itself. The built-in sources:

- ``AxisSignals`` for ``Axis`` (``AXIS_SIGNALS``; a CA mover is an axis and adds ``gap``,
  ``track_position``, ``tcp_position``);
- ``PlanarMoverSignals`` for ``MC_PlanarMover`` (``PLANAR_MOVER_SIGNALS``);
- ``PlanarGroupSignals`` for ``MC_PlanarGroup`` (``state``);
- ``PlanarEnvironmentSignals`` for ``MC_PlanarEnvironment`` (no signals: it only describes
  the stators and parts a planar figure draws);
- ``AxesGroupSignals`` for a Part 4 ``AxesGroup`` (``GROUP_SIGNALS``).

``register_source(kind, source)`` adds a kind of object. A source may also read all its
objects' values of one signal in one numpy operation (``bulk``), and ``describe`` an object
for the trace's ``layout``: what a figure needs beyond the columns (stators, footprints,
rails, gaps). Every value is a float64; a state is its enum number.
"""

from __future__ import annotations

import math
import re
import weakref
from collections.abc import Callable, Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.axis.axis import Axis
from openmotion.coordinated.group import AxesGroup
from openmotion.core.errors import CommandRejected
from openmotion.planar import MC_PlanarEnvironment, MC_PlanarGroup, MC_PlanarMover
from openmotion.planar.stators import STATOR_SIZE
from openmotion.planar.traffic import network_of

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime

Reader = Callable[[], float]
BulkReader = Callable[[], np.ndarray]

#: Axis properties a trace can record, in the order ``default_signals`` lists them.
AXIS_SIGNALS = ("set_position", "set_velocity", "set_acceleration", "set_jerk", "position",
                "velocity", "following_error", "state", "override", "homed", "axis_error_id",
                "gap", "track_position", "tcp_position")
#: The signals only members of a CA group have (NaN for other axes).
MOVER_SIGNALS = ("gap", "track_position", "tcp_position")
#: What a scenario records when it names no signals: setpoint and actual position.
DEFAULT_AXIS_SIGNALS = ("set_position", "set_velocity", "set_acceleration", "position")
#: A planar mover's signals: its published set position, path velocity, PlanarState, the
#: coordinate system its position is in (with parts), the track it is on and its arc length.
PLANAR_MOVER_SIGNALS = ("x", "y", "z", "a", "b", "c", "velocity", "state", "coordinate_system",
                        "track", "s")
#: An axes group's signals (Part 4): its TCP's set position x, y, z in the MCS [mm], the path
#: velocity and acceleration of its time law [mm/s, mm/s²] and its AxesGroupState number.
GROUP_SIGNALS = ("x", "y", "z", "path_velocity", "path_acceleration", "state", "blocker_id")
#: What a scenario records of each axes group when it names no signals.
DEFAULT_GROUP_SIGNALS = ("x", "y", "z", "path_velocity")
_WHOLE_SIGNALS = frozenset({"state", "homed", "axis_error_id"})
_SIGNAL = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\.([a-z_]+)$")
#: signals kept in the axis kernel's arrays, read for all axes at once
_KERNEL_FIELDS = {"set_position": "set_p", "set_velocity": "set_v",
                  "set_acceleration": "set_a", "set_jerk": "set_j", "position": "act_p",
                  "velocity": "act_v"}


def split_signal(name: str) -> tuple[str, str]:
    """``"x.set_position"`` -> ``("x", "set_position")``; ValueError for anything else."""
    match = _SIGNAL.match(name)
    if match is None or match.group(2) not in AXIS_SIGNALS:
        raise ValueError(f"{name!r} is not '<axis>.<signal>' with a signal among "
                         f"{', '.join(AXIS_SIGNALS)}")
    return match.group(1), match.group(2)


def read_signal(axis: Axis, prop: str) -> float:
    """One signal of ``axis`` as a float: the state as its AxisState number, the override in
    percent (0-100), homed as 0 or 1, the axis error as its ErrorId number (0: none). The
    signals of a CA mover (transport/; NaN for an axis in no CA group):

    - ``gap``: the setpoint gap [mm] to the predecessor in the group (inf: no predecessor);
    - ``track_position``: the set position on the active track, as MC_ReadTrackPositions
      gives it; the absolute set position without one; NaN once off an (open) track;
    - ``tcp_position``: the TCP arc length [mm] of the set position on the path of the
      registered mover template (MC_TransformPosition from 0 to it); NaN without one.
    """
    if prop in MOVER_SIGNALS:
        group = axis.group
        return math.nan if group is None or isinstance(group, AxesGroup) \
            else _mover_signal(group, axis, prop)
    value = getattr(axis, prop)
    if prop == "override":
        return float(value) * 100.0
    return float(int(value)) if prop in _WHOLE_SIGNALS else float(value)


def _mover_signal(group: Any, axis: Axis, prop: str) -> float:
    if prop == "gap":
        return float(group.gaps()[group.mover_of(axis).slot])
    if prop == "track_position":
        try:
            return float(group.tracks.read_track_positions(axis).track_position)
        except CommandRejected:  # NOT_ON_TRACK: the mover left its open track
            return math.nan
    geo = group.tracks.geo
    template = geo.registered(axis)
    return math.nan if template is None else geo.to_tcp(template, axis.set_position)


def default_signals(axis_names: Iterable[str]) -> list[str]:
    return [f"{axis}.{prop}" for axis in axis_names for prop in DEFAULT_AXIS_SIGNALS]


def read_planar_signal(mover: MC_PlanarMover, prop: str) -> float:
    """One signal of a planar mover: x, y, z [mm], a, b, c [°] (its published set position),
    ``velocity`` (path velocity |(vx, vy)| [mm/s]), ``state`` (the PlanarState number),
    ``coordinate_system`` (the OID of the coordinate system x, y, c are in; 0 without parts:
    PhysicalAreaID), ``track`` (the number of the track it is coupled to: 1 for the first
    track made on the runtime, 2 for the next ...; 0 on none) and ``s`` (its set arc length
    on that track [mm]; NaN on none)."""
    if prop == "state":
        return float(mover.state)
    if prop in ("track", "s"):
        return _track_signal(mover, prop)
    if prop == "velocity":
        velocity = mover.mc_to_plc.set.set_velo
        return math.hypot(velocity.x, velocity.y)
    if prop == "coordinate_system":
        return float(mover.mc_to_plc.set.physical_area_id)
    return float(getattr(mover.position, prop))


def _track_signal(mover: MC_PlanarMover, prop: str) -> float:
    on_track = mover.mc_to_plc.set_on_track
    if not on_track.track_oid:
        return 0.0 if prop == "track" else math.nan
    if prop == "s":
        return float(on_track.set_pos)
    tracks = network_of(mover._system).tracks  # creation order, as the numbers count
    return float(next(k for k, track in enumerate(tracks, start=1)
                      if track.oid == on_track.track_oid))


def read_group_signal(group: AxesGroup, prop: str) -> float:
    """One signal of an axes group: ``x``, ``y``, ``z`` (the TCP's set position in the MCS;
    0 for a coordinate its kinematics lacks, NaN without members), ``path_velocity`` and
    ``path_acceleration`` (of its time law, along the path in the frame the path runs in:
    0 while the TCP only rides on a moving PCS), ``state`` (the AxesGroupState number),
    ``blocker_id`` (MC_GroupReadBlockerStatus: the blocker the path stands at, 0: none)."""
    if prop == "state":
        return float(group.state)
    if prop == "blocker_id":
        return float(group.blocker_status()[1])
    if prop in ("path_velocity", "path_acceleration"):
        return float(getattr(group.motion, prop))
    if not group.members:
        return math.nan
    return float(_tcp(group)["xyz".index(prop)])


#: group -> (set positions, kinematics, MCS offset, TCP) of its last TCP reading
_TCP_CACHE: weakref.WeakKeyDictionary[AxesGroup, tuple[bytes, Any, bytes, np.ndarray]] = \
    weakref.WeakKeyDictionary()


def _tcp(group: AxesGroup) -> np.ndarray:
    """The TCP's set position in the MCS; x, y and z read in one sample share one forward
    transform (the cache is keyed by all it depends on)."""
    spaces = group.spaces
    acs = group.acs_set()
    acs_key, offset_key = acs.tobytes(), spaces.mcs_offset.tobytes()
    cached = _TCP_CACHE.get(group)
    if cached is None or cached[0] != acs_key or cached[1] is not spaces.kinematics \
            or cached[2] != offset_key:
        cached = acs_key, spaces.kinematics, offset_key, spaces.xyz(spaces.to_mcs(acs))
        _TCP_CACHE[group] = cached
    return cached[3]


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


class AxisSignals(SignalSource):
    """An axis (and a CA mover: an axis in a CA group)."""

    kind = "axis"
    signals = AXIS_SIGNALS

    def read(self, obj: Axis, prop: str) -> float:
        return read_signal(obj, prop)

    def bulk(self, runtime: Runtime, objects: Sequence[Axis], prop: str) -> BulkReader | None:
        """The kernel's arrays hold the kinematic signals of every axis: one gather each."""
        kernel = runtime.axis_system.kernel  # the observer phase reads it, as the cycle does
        rows = compact_index([axis.row for axis in objects])
        if prop == "following_error":
            return lambda: kernel.set_p[rows] - kernel.act_p[rows]
        field = _KERNEL_FIELDS.get(prop)
        if field is None:
            return None
        return lambda: getattr(kernel, field)[rows]  # arrays are replaced when they grow

    def describe(self, obj: Axis) -> dict[str, Any]:
        group: Any = obj.group
        if group is None or isinstance(group, AxesGroup):
            return {}
        parameters = group.parameters
        return {"ca_groups": {group.name: {
            "rail_length": float(parameters.rail_length),
            "rail_is_ring": bool(parameters.rail_is_ring),
            "default_gap": float(parameters.default_gap),
            "movers": list(group.order)}}}


class PlanarMoverSignals(SignalSource):
    kind = "planar_mover"
    signals = PLANAR_MOVER_SIGNALS

    def read(self, obj: MC_PlanarMover, prop: str) -> float:
        return read_planar_signal(obj, prop)

    def describe(self, obj: MC_PlanarMover) -> dict[str, Any]:
        parameters = obj.parameters
        return {"planar": {"movers": {obj.name: {"width": float(parameters.mover_width),
                                                 "height": float(parameters.mover_height)}}}}


class PlanarGroupSignals(SignalSource):
    kind = "planar_group"
    signals = ("state",)

    def read(self, obj: MC_PlanarGroup, prop: str) -> float:
        return float(obj.state)


class PlanarEnvironmentSignals(SignalSource):
    """No signals: the stators (their lower-left corners) and, with parts, the coordinate
    systems and the outline of every part in each of its positions (``active``: the one it
    is in)."""

    kind = "planar_environment"

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


class AxesGroupSignals(SignalSource):
    """A Part 4 axes group: its members (IdentInGroup order) and MCS coordinates describe it
    for the path figure."""

    kind = "axes_group"
    signals = GROUP_SIGNALS

    def read(self, obj: AxesGroup, prop: str) -> float:
        return read_group_signal(obj, prop)

    def describe(self, obj: AxesGroup) -> dict[str, Any]:
        return {"axes_groups": {obj.name: {
            "axes": [axis.name for axis in obj.axes],
            "coordinates": list(obj.kinematics.coordinates)}}}


_SOURCES: dict[type, SignalSource] = {}


def register_source(kind: type, source: SignalSource) -> None:
    """Let traces record objects of type ``kind`` (and its subclasses) through ``source``."""
    _SOURCES[kind] = source


def source_of(obj: object) -> SignalSource | None:
    """The source registered for the type of ``obj`` or its nearest base class."""
    for kind in type(obj).__mro__:
        source = _SOURCES.get(kind)
        if source is not None:
            return source
    return None


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


def compact_index(positions: list[int]) -> slice | np.ndarray:
    """A slice for consecutive positions (a view, no gather), else an index array."""
    if positions and positions == list(range(positions[0], positions[0] + len(positions))):
        return slice(positions[0], positions[0] + len(positions))
    return np.array(positions, dtype=np.intp)


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
