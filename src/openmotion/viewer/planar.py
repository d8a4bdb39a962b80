"""The planar field: stators, parts, tracks with their switches and collision ranges, movers
with their footprints and the reserved areas; with a router, its obstacles and the planned
way of every mover still on it (``RoutePlans``).

Everything is drawn in one plane. Parts in other coordinate systems than the first are drawn
where their active positions put them in their own system (the manual's systems are unrelated
frames, §5.1), so a layout with several systems may overlap on the page.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.planar.enums import PlanarObjectType
from openmotion.planar.group import MC_PlanarGroup
from openmotion.planar.mover import MC_PlanarMover
from openmotion.planar.parts import STATOR_SIZE
from openmotion.planar.routing.plans import RoutePlans
from openmotion.planar.system import PlanarSystem
from openmotion.viewer.layers import Layer, Row, error_text, number

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from openmotion.runtime.runtime import Runtime

DIGITS = 1  #: decimals of the coordinates sent to the page [mm]


class PlanarLayer(Layer):
    """The planar system of a runtime: its environments, groups and movers."""

    kind = "planar"

    def __init__(self, system: PlanarSystem) -> None:
        self.name = "planar"
        self._system = system

    def _groups(self) -> list[MC_PlanarGroup]:
        return [obj for obj in self._system.objects() if isinstance(obj, MC_PlanarGroup)]

    def panel(self) -> dict[str, Any]:
        system = self._system
        stators = [[stator.lower_x, stator.lower_y] for environment in system.environments
                   for stator in environment.field.stators]
        parts = [{"name": part.name, "state": part.state.name, "rings": rings(part.surface())}
                 for environment in system.environments if environment.layout is not None
                 for part in environment.layout.parts.values()]
        tracks = self._tracks()
        plans = RoutePlans.of(system.runtime, create=False)
        return {"stator_size": STATOR_SIZE, "stators": stators, "parts": parts,
                "tracks": [_track(track) for track in tracks],
                "switches": _switches(tracks),
                "movers": [_mover(mover) for mover in system.movers],
                "reserved": self._reserved(),
                "obstacles": [] if plans is None else plans.obstacles(),
                "routes": [] if plans is None else plans.current()}

    def _tracks(self) -> list[Any]:
        network = self._system.network
        return [] if network is None else [t for t in network.tracks if t.length > 0.0]

    def _reserved(self) -> list[dict[str, Any]]:
        names = {mover.oid: mover.name for mover in self._system.movers}
        areas = []
        for group in self._groups():
            for member in group.members:
                if member.object_type is PlanarObjectType.MOVER:
                    area = rings(group.reserved(member))
                    if area:
                        areas.append({"mover": names.get(member.id, ""), "rings": area})
        return areas

    def rows(self) -> list[Row]:
        rows = [Row("environment", environment.name, "-",
                    detail=f"{len(environment.field)} stators"
                    + ("" if environment.boundary is None else ", boundary"),
                    error=error_text(environment.error_id, ""))
                for environment in self._system.environments]
        rows += [Row("planar group", group.name, group.state.name.lower(),
                     detail=f"{len(group.members)} members",
                     error=error_text(group.error_id, "")) for group in self._groups()]
        rows += [Row("planar track", track.name, track.state.name.lower(),
                     detail=f"{track.operation_mode.name.lower()}, {track.length:.0f} mm, "
                     f"{track.mover_count_on_track} movers",
                     error=error_text(track.error_id, "")) for track in self._tracks()]
        return rows + [_mover_row(mover) for mover in self._system.movers]


TRACK_STEP = 10.0  #: [mm] between the points of a drawn track


def _track(track: Any) -> dict[str, Any]:
    """A track as a polyline, with the stretches of its collision ranges (§6.2.2)."""
    length = track.length
    s = np.linspace(0.0, length, max(2, math.ceil(length / TRACK_STEP) + 1))
    x, y, _, _ = track.frame_at(s)
    points = [[round(a, DIGITS), round(b, DIGITS)] for a, b in zip(x.tolist(), y.tolist(),
                                                                   strict=True)]
    ranges = []
    start, end = track.collision_ranges
    starts, ends = track.network.switches(track)
    for near, reach in ((starts, (0.0, min(start, length))),
                        (ends, (max(length - end, 0.0), length))):
        if near is not None and reach[1] > reach[0]:
            inside = (s >= reach[0]) & (s <= reach[1])
            ranges.append([points[i] for i in np.flatnonzero(inside).tolist()])
    return {"name": track.name, "state": track.state.name,
            "mode": track.operation_mode.name, "points": points, "ranges": ranges}


def _switches(tracks: list[Any]) -> list[list[float]]:
    """Where more than two track ends meet."""
    found: dict[Any, list[float]] = {}
    for track in tracks:
        starts, ends = track.network.switches(track)
        for vertex, s in ((starts, 0.0), (ends, track.length)):
            if vertex is not None and vertex not in found:
                x, y, _, _ = track.frame_at(np.array([s]))
                found[vertex] = [round(float(x[0]), DIGITS), round(float(y[0]), DIGITS)]
    return list(found.values())


def _mover(mover: MC_PlanarMover) -> dict[str, Any]:
    position, parameters = mover.position, mover.parameters
    return {"name": mover.name, "x": round(position.x, DIGITS), "y": round(position.y, DIGITS),
            "z": round(position.z, DIGITS), "c": round(position.c, 2),
            "width": parameters.mover_width, "height": parameters.mover_height,
            "state": mover.state.name, "error": mover.error,
            "busy": mover.mc_to_plc.std.busy.busy_mover}


def _mover_row(mover: MC_PlanarMover) -> Row:
    position, status = mover.position, mover.mc_to_plc
    busy = status.std.busy
    return Row("planar mover", mover.name, mover.state.name.lower(),
               f"{number(position.x, 1)}, {number(position.y, 1)}",
               number(_speed(mover)), "moving" if busy.busy_xyc else
               "busy" if busy.busy_mover else "",
               f"z {number(position.z, 1)}, c {number(position.c, 1)}°",
               error_text(mover.error_id, mover.message))


def _speed(mover: MC_PlanarMover) -> float:
    velocity = mover.mc_to_plc.set.set_velo
    return math.hypot(velocity.x, velocity.y)


def rings(geometry: BaseGeometry) -> list[list[list[float]]]:
    """Every ring (outer and holes) of the polygons in ``geometry``, coordinates rounded; the
    page fills them with the even-odd rule."""
    found: list[list[list[float]]] = []
    for polygon in _polygons(geometry):
        for ring in (polygon.exterior, *polygon.interiors):
            found.append([[round(x, DIGITS), round(y, DIGITS)] for x, y in ring.coords])
    return found


def _polygons(geometry: BaseGeometry) -> list[Any]:
    if geometry.is_empty:
        return []
    if geometry.geom_type == "Polygon":
        return [geometry]
    if hasattr(geometry, "geoms"):  # MultiPolygon, GeometryCollection
        return [polygon for part in geometry.geoms for polygon in _polygons(part)]
    return []  # points and lines hold no area


def planar_layers(runtime: Runtime) -> list[Layer]:
    """The planar layer, when the runtime has a planar system (never makes one)."""
    return [PlanarLayer(system) for system in runtime.systems
            if isinstance(system, PlanarSystem)]

