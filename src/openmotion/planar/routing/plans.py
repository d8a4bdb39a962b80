"""The ways the routers of a runtime planned, for the edges that draw them.

``RoutePlans.of(runtime)`` is one log per runtime: ``watch(router)`` adds a router to it, and
as a runtime observer it notes every planned way that changed (a new ``route`` call, a
re-plan, D-303) with the time it was first seen. What it gives out is plain data:

- ``layout()``: every way planned so far, with its time, and the routers' obstacles; the
  trace's layout takes it (trace/signals.py), so that the planar plot draws the plans also
  from a trace written to disk;
- ``current()``: the way of every mover that has not arrived yet, for the live viewer.

A runtime without a router has no log (``of(runtime, create=False)`` is None), so the other
edges pay nothing for it.
"""

from __future__ import annotations

import math
import weakref
from typing import TYPE_CHECKING, Any

import shapely

if TYPE_CHECKING:
    from openmotion.kernel.runtime import CyclicRuntime
    from openmotion.planar.routing.router import Router

ARRIVED = 0.5  #: a mover this close to its way's last point is no longer on its way [mm]
DIGITS = 1  #: decimals of the coordinates given out [mm]

Points = list[list[float]]
_LOGS: weakref.WeakKeyDictionary[Any, RoutePlans] = weakref.WeakKeyDictionary()


class RoutePlans:
    """Every way the watched routers planned, in the order they were first seen."""

    name = "route plans"  #: how a trace's layout lists it

    def __init__(self, runtime: CyclicRuntime) -> None:
        self.runtime = runtime
        self.routers: list[Router] = []
        #: {"mover", "time" [s], "points" [[x, y] ...] [mm]} in the order they were seen
        self.history: list[dict[str, Any]] = []
        self._last: dict[tuple[int, str], Points] = {}
        runtime.add_observer(self)

    @classmethod
    def of(cls, runtime: CyclicRuntime, create: bool = True) -> RoutePlans | None:
        """The log of ``runtime``, made on first use (None without one when not ``create``)."""
        log = _LOGS.get(runtime)
        if log is None and create:
            log = _LOGS[runtime] = cls(runtime)
        return log

    def watch(self, router: Router) -> None:
        """Note the ways ``router`` plans from now on (its current ones at once)."""
        if router not in self.routers:
            self.routers.append(router)
            self.note()

    def __call__(self, runtime: CyclicRuntime) -> None:
        self.note()

    def note(self) -> None:
        """Note the ways that changed since the last look, at the runtime's time now (called
        after every cycle; a caller of ``route`` may call it at once)."""
        now = self.runtime.now
        for k, router in enumerate(self.routers):
            for mover, route in router.routes.items():
                points = _points(route)
                if self._last.get((k, mover)) != points:
                    self._last[(k, mover)] = points
                    self.history.append({"mover": mover, "time": now, "points": points})

    def current(self) -> list[dict[str, Any]]:
        """The planned way of every mover still on it ({"mover", "points"}): a mover that
        stands on its way's last point has arrived and is left out, and so is every mover
        of a router whose routes have all ended."""
        found = []
        for router in self.routers:
            if not router.busy:  # every route ended: nothing is on its way
                continue
            position = {mover.name: mover.position for mover in router.system.movers}
            for mover, route in router.routes.items():
                where = position.get(mover)
                if not route or where is not None and math.hypot(
                        where.x - route[-1][0], where.y - route[-1][1]) <= ARRIVED:
                    continue
                found.append({"mover": mover, "points": _points(route)})
        return found

    def obstacles(self) -> list[dict[str, Any]]:
        """The routers' static obstacles: {"name", "rings"} (outer ring and holes)."""
        return [{"name": name, "rings": rings(geometry)} for router in self.routers
                for name, geometry in zip(router.obstacle_names, router.obstacles, strict=True)]

    def layout(self) -> dict[str, Any]:
        """What a trace's layout keeps: the planned ways and the obstacles (JSON-able)."""
        return {"planar": {"planned_routes": list(self.history),
                           "obstacles": self.obstacles()}}


def _points(route: list[tuple[float, float]]) -> Points:
    return [[round(float(x), DIGITS), round(float(y), DIGITS)] for x, y in route]


def rings(geometry: Any) -> list[Points]:
    """Every ring (outer and holes) of the polygons in ``geometry``, coordinates rounded."""
    found: list[Points] = []
    for polygon in shapely.get_parts(geometry).tolist():
        if polygon.geom_type != "Polygon":
            found += rings(polygon) if hasattr(polygon, "geoms") else []
            continue
        for ring in (polygon.exterior, *polygon.interiors):
            found.append([[round(x, DIGITS), round(y, DIGITS)] for x, y in ring.coords])
    return found
