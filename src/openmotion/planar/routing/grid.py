"""The roadmap a planar router plans on: a grid of cells over the environment's surface.

A cell is a square place for one mover: its pitch is the largest footprint side of the
routed movers plus ``CLEARANCE``, stretched so that a whole number of cells spans the
surface's bounds. Two movers standing at the centres of different cells cannot meet, and a
straight move between neighbouring centres sweeps only the cells it joins (and, for a
diagonal move, the two cells beside it). A cell is free when a mover at its centre lies on
the stator surface and meets no static obstacle (parts in their current positions are part
of the surface, docs/planar-routing.md).

Which cells a motion touches (``touched``): the cells whose rectangle meets the segment
between the two centres grown by the mover's half extents, a superset of the true swept
area of any footprint on that segment, so that the plan reserves at least what the group
will.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from openmotion.core.errors import ConfigError

CLEARANCE = 2.0  #: the smallest gap between two movers at neighbouring cell centres [mm]
EDGE_TOLERANCE = 1e-6  #: rectangles that only touch do not meet [mm]

#: the eight moves between neighbouring cells, straight ones first
MOVES = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1))


def half_extents(width: float, height: float, c: float) -> tuple[float, float]:
    """Half extents along x and y of a width x height footprint turned by c [°]."""
    cos, sin = abs(math.cos(math.radians(c))), abs(math.sin(math.radians(c)))
    return (width * cos + height * sin) / 2.0, (width * sin + height * cos) / 2.0


@dataclass
class RoutingGrid:
    """Cells over ``bounds`` with ``nx`` x ``ny`` cells; ``free`` marks the usable ones."""

    bounds: tuple[float, float, float, float]  #: min x, min y, max x, max y [mm]
    nx: int
    ny: int
    free: np.ndarray  #: (nx * ny,) bool: a mover may stand at the centre
    surface: BaseGeometry | None
    obstacles: tuple[BaseGeometry, ...]
    _touch: dict[tuple[float, float, int, int], tuple[int, ...]] = field(default_factory=dict)
    _diagonal_ok: dict[tuple[int, int], bool] = field(default_factory=dict)
    _near: dict[int, list[int]] = field(default_factory=dict)

    @property
    def pitch(self) -> tuple[float, float]:
        low_x, low_y, high_x, high_y = self.bounds
        return (high_x - low_x) / self.nx, (high_y - low_y) / self.ny

    @property
    def size(self) -> int:
        return self.nx * self.ny

    def centre(self, cell: int) -> tuple[float, float]:
        px, py = self.pitch
        i, j = cell % self.nx, cell // self.nx
        return self.bounds[0] + (i + 0.5) * px, self.bounds[1] + (j + 0.5) * py

    def cell_at(self, x: float, y: float) -> int | None:
        """The cell holding (x, y), or None outside the bounds."""
        px, py = self.pitch
        i = math.floor((x - self.bounds[0]) / px)
        j = math.floor((y - self.bounds[1]) / py)
        if 0 <= i < self.nx and 0 <= j < self.ny:
            return j * self.nx + i
        return None

    def neighbours(self, cell: int) -> list[int]:
        """The free cells one move from ``cell`` (a diagonal only when both cells beside it
        are free and no obstacle meets the move); cached: ``free`` is fixed once built."""
        near = self._near.get(cell)
        if near is None:
            near = self._near[cell] = self._neighbours(cell)
        return near

    def _neighbours(self, cell: int) -> list[int]:
        i, j = cell % self.nx, cell // self.nx
        out = []
        for di, dj in MOVES:
            a, b = i + di, j + dj
            if not (0 <= a < self.nx and 0 <= b < self.ny):
                continue
            other = b * self.nx + a
            if not self.free[other]:
                continue
            if di and dj:
                side1, side2 = j * self.nx + a, b * self.nx + i
                if not (self.free[side1] and self.free[side2]) or not self._diagonal(cell, other):
                    continue
            out.append(other)
        return out

    def _diagonal(self, u: int, v: int) -> bool:
        key = (min(u, v), max(u, v))
        ok = self._diagonal_ok.get(key)
        if ok is None:
            ok = True
            if self.obstacles:
                line = shapely.linestrings([self.centre(u), self.centre(v)])
                px, py = self.pitch
                grown = shapely.buffer(line, min(px, py) / 2.0 - CLEARANCE / 2.0)
                ok = not any(meets(grown, o) for o in self.obstacles)
            self._diagonal_ok[key] = ok
        return ok

    def touched(self, a: tuple[float, float], b: tuple[float, float], hx: float,
                hy: float) -> tuple[int, ...]:
        """The cells whose rectangle meets the segment a-b grown by (hx, hy)."""
        low_x = min(a[0], b[0]) - hx
        high_x = max(a[0], b[0]) + hx
        low_y = min(a[1], b[1]) - hy
        high_y = max(a[1], b[1]) + hy
        px, py = self.pitch
        x0, y0 = self.bounds[0], self.bounds[1]
        i0 = max(0, math.floor((low_x - x0) / px))
        i1 = min(self.nx - 1, math.floor((high_x - x0) / px))
        j0 = max(0, math.floor((low_y - y0) / py))
        j1 = min(self.ny - 1, math.floor((high_y - y0) / py))
        out = []
        for j in range(j0, j1 + 1):
            for i in range(i0, i1 + 1):
                box = (x0 + i * px - hx, y0 + j * py - hy, x0 + (i + 1) * px + hx,
                       y0 + (j + 1) * py + hy)
                if _segment_meets_box(a, b, box):
                    out.append(j * self.nx + i)
        return tuple(out)

    def touched_cells(self, u: int, v: int, hx: float, hy: float) -> tuple[int, ...]:
        """``touched`` between two cell centres, cached."""
        key = (hx, hy, u, v)
        cells = self._touch.get(key)
        if cells is None:
            cells = self.touched(self.centre(u), self.centre(v), hx, hy)
            self._touch[key] = cells
        return cells


def _segment_meets_box(a: tuple[float, float], b: tuple[float, float],
                       box: tuple[float, float, float, float]) -> bool:
    """Whether the segment a-b meets the open rectangle ``box`` (slab test)."""
    t0, t1 = 0.0, 1.0
    for k in range(2):
        d = b[k] - a[k]
        low, high = box[k] + EDGE_TOLERANCE, box[k + 2] - EDGE_TOLERANCE
        if abs(d) < 1e-12:
            if a[k] <= low or a[k] >= high:
                return False
            continue
        s0, s1 = (low - a[k]) / d, (high - a[k]) / d
        if s0 > s1:
            s0, s1 = s1, s0
        t0, t1 = max(t0, s0), min(t1, s1)
        if t0 >= t1:
            return False
    return True


def meets(a: BaseGeometry, b: BaseGeometry) -> bool:
    """Interiors meet: touching edges do not count (as in the group, §6.3)."""
    return bool(shapely.intersects(a, b)) and not bool(shapely.touches(a, b))


def build_grid(surface: BaseGeometry, side: float, obstacles: Sequence[BaseGeometry] = (),
               pitch: float | None = None) -> RoutingGrid:
    """Cells of pitch at least ``side + CLEARANCE`` (or ``pitch``) over ``surface``'s
    bounds; a cell is free when the ``side`` square at its centre is on ``surface`` and meets
    no obstacle."""
    if surface is None or surface.is_empty:
        raise ConfigError("routing: the environment has no stator surface (CreateBoundary)")
    low_x, low_y, high_x, high_y = surface.bounds
    if pitch is not None and not (math.isfinite(pitch) and pitch >= side):
        raise ConfigError(f"routing pitch {pitch!r}: must be a finite number of at least the "
                          f"mover's side {side:g} mm")
    pitch = pitch if pitch is not None else side + CLEARANCE
    nx = max(1, math.floor((high_x - low_x) / pitch))
    ny = max(1, math.floor((high_y - low_y) / pitch))
    grid = RoutingGrid((low_x, low_y, high_x, high_y), nx, ny, np.zeros(nx * ny, bool),
                       surface, tuple(obstacles))
    centres = np.array([grid.centre(c) for c in range(grid.size)])
    half = side / 2.0
    boxes = shapely.box(centres[:, 0] - half, centres[:, 1] - half, centres[:, 0] + half,
                        centres[:, 1] + half)
    grown = shapely.buffer(surface, 1e-6, join_style="mitre")
    free = shapely.covers(grown, boxes)
    for obstacle in obstacles:
        free &= ~(shapely.intersects(boxes, obstacle) & ~shapely.touches(boxes, obstacle))
    grid.free = np.asarray(free, dtype=bool)
    return grid
