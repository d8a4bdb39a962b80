"""Stators and the stator surface of a planar environment (TF5430 §5.1, §6.4).

The surface movers travel on is tiled with square stators, 240 mm a side (§5.1), each added
by its lower-left corner (``AddStator(lowerX, lowerY)``, §6.4.2, §7.2.2.1.2). A
``StatorField`` holds the stators of one environment and derives from them:

* ``surface``: the union of the stator squares, the area a mover's footprint must stay in
  when the environment is a member of a planar group (§6.3, §6.4);
* ``boundary``: the outline of that surface, merged (for drawing and distance queries);
* ``boundary_elements``: the manual's boundary elements, one per outer side of a stator,
  not merged. Four stators in a 2 x 2 block give eight (§6.4.2, ``BoundaryElementCount``).

Boundary creation (§6.4, §7.2.2.1.3): in the manual the environment computes its boundary
only when the PLC calls ``CreateBoundary()``, from the stators added so far (or, with the
processing-unit OID set, from the stator layout the hardware reports), and ``Clear()``
removes stators and boundary (§7.2.2.1.1). Our reading: stators added after the call count
from the next ``CreateBoundary()`` on. Here the field always knows its current surface;
``create_boundary()`` takes the snapshot (``Boundary``) that the environment keeps and hands
to the group, so the manual's two steps stay two steps.

Grid rule (decision, the manual is silent): all stators of a field lie on one 240 mm grid,
anchored at ``origin`` or, by default, at the first stator's corner. A corner off that grid
or a second stator in the same cell is a ``ConfigError`` naming the stator. Stators need not
be contiguous (a field with two islands is allowed; no motion can cross the gap).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import shapely
from shapely.geometry import LineString, MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

from openmotion.core.checks import finite_number, finite_pair
from openmotion.core.errors import ConfigError
from openmotion.planar.tolerances import GRID_TOLERANCE

STATOR_SIZE = 240.0  #: side of a square stator [mm] (§5.1, §6.4.2)

#: (di, dj) of the neighbour across each side, and the side's corners in cell units,
#: in the order bottom, right, top, left (counter-clockwise, so elements read deterministically)
_SIDES = (
    ((0, -1), ((0, 0), (1, 0))),
    ((1, 0), ((1, 0), (1, 1))),
    ((0, 1), ((1, 1), (0, 1))),
    ((-1, 0), ((0, 1), (0, 0))),
)


@dataclass(frozen=True)
class Stator:
    """One 240 mm stator, addressed by its lower-left corner [mm] (§6.4.2)."""

    lower_x: float  #: x of the lower-left corner [mm]
    lower_y: float  #: y of the lower-left corner [mm]

    @property
    def polygon(self) -> Polygon:
        return shapely.box(self.lower_x, self.lower_y,
                           self.lower_x + STATOR_SIZE, self.lower_y + STATOR_SIZE)


@dataclass(frozen=True)
class FieldInfo:
    """What the environment reports online (§6.4.1): counts, and the bounds of the surface."""

    stator_count: int
    boundary_element_count: int
    bounds: tuple[float, float, float, float] | None  #: (min x, min y, max x, max y) [mm]


@dataclass(frozen=True)
class Boundary:
    """The result of ``CreateBoundary()`` (§6.4): a frozen copy of the surface and its edges."""

    surface: Polygon | MultiPolygon  #: union of the stators, prepared for fast predicates
    elements: tuple[LineString, ...]  #: outer stator sides, not merged (§6.4.2)

    @property
    def element_count(self) -> int:
        return len(self.elements)

    def covers(self, area: BaseGeometry) -> bool:
        """True when ``area`` lies on the surface (its edge may touch the boundary)."""
        return bool(self.surface.covers(area))


class StatorField:
    """The stators of one environment on a common 240 mm grid, and the surface they form."""

    def __init__(self, stators: Iterable[tuple[float, float]] = (),
                 origin: tuple[float, float] | None = None) -> None:
        if origin is not None:
            origin = finite_pair(origin, "stator field: origin")
        self._origin = origin
        self._anchor = origin  # grid anchor: origin, else the first stator's corner
        self._stators: list[Stator] = []
        self._cells: dict[tuple[int, int], int] = {}  # grid cell -> index in _stators
        self._surface: Polygon | MultiPolygon | None = None
        for lower_x, lower_y in stators:
            self.add_stator(lower_x, lower_y)

    @classmethod
    def rectangular(cls, columns: int, rows: int,
                    origin: tuple[float, float] = (0.0, 0.0)) -> StatorField:
        """A ``columns`` x ``rows`` block of stators whose lower-left corner is ``origin``."""
        if isinstance(columns, bool) or isinstance(rows, bool) or not isinstance(columns, int) \
                or not isinstance(rows, int) or columns < 1 or rows < 1:
            raise ConfigError(f"stator field: columns and rows must be ints >= 1, got "
                              f"{columns!r}x{rows!r}")
        x0, y0 = origin = finite_pair(origin, "stator field: origin")
        return cls(((x0 + i * STATOR_SIZE, y0 + j * STATOR_SIZE)
                    for j in range(rows) for i in range(columns)), origin=origin)

    @property
    def stators(self) -> tuple[Stator, ...]:
        return tuple(self._stators)

    def __len__(self) -> int:
        return len(self._stators)

    def add_stator(self, lower_x: float, lower_y: float) -> Stator:
        """Add a stator by its lower-left corner (§6.4.2); off-grid or overlapping: ConfigError."""
        name = f"stators[{len(self._stators)}] ({lower_x!r}, {lower_y!r})"
        lower_x = finite_number(lower_x, f"{name}: lower_x")
        lower_y = finite_number(lower_y, f"{name}: lower_y")
        if self._anchor is None:
            self._anchor = (float(lower_x), float(lower_y))
        cell = self._cell(name, lower_x, lower_y)
        if cell in self._cells:
            other = self._cells[cell]
            raise ConfigError(f"{name}: overlaps stators[{other}] {self._corner(other)}")
        ox, oy = self._anchor
        stator = Stator(ox + cell[0] * STATOR_SIZE, oy + cell[1] * STATOR_SIZE)
        self._cells[cell] = len(self._stators)
        self._stators.append(stator)
        self._surface = None
        return stator

    def clear(self) -> None:
        """Remove every stator (``Clear()``, §7.2.2.1.1); the grid anchor is chosen anew."""
        self._stators.clear()
        self._cells.clear()
        self._surface = None
        self._anchor = self._origin

    @property
    def surface(self) -> Polygon | MultiPolygon:
        """Union of the stator squares; an empty polygon when there are no stators."""
        if self._surface is None:
            union = shapely.union_all([s.polygon for s in self._stators])
            # tolerance 0 drops only the collinear vertices where stators meet
            self._surface = Polygon() if union.is_empty else shapely.simplify(union, 0.0)
        return self._surface

    @property
    def boundary(self) -> BaseGeometry:
        """The merged outline of the surface (rings of every island and hole)."""
        return self.surface.boundary

    @property
    def boundary_elements(self) -> tuple[LineString, ...]:
        """One segment per stator side without a neighbouring stator, in stator order (§6.4.2)."""
        ox, oy = self._anchor or (0.0, 0.0)
        return tuple(
            LineString([(ox + (i + a) * STATOR_SIZE, oy + (j + b) * STATOR_SIZE)
                        for a, b in ends])
            for i, j in self._cells
            for (di, dj), ends in _SIDES
            if (i + di, j + dj) not in self._cells
        )

    @property
    def info(self) -> FieldInfo:
        surface = self.surface
        bounds = None if surface.is_empty else tuple(float(v) for v in surface.bounds)
        return FieldInfo(len(self._stators), len(self.boundary_elements), bounds)

    def create_boundary(self) -> Boundary:
        """Snapshot the surface and its boundary elements, as ``CreateBoundary()`` does (§6.4)."""
        surface = self.surface  # immutable: later add_stator() builds a new one
        shapely.prepare(surface)
        return Boundary(surface, self.boundary_elements)

    def _cell(self, name: str, lower_x: float, lower_y: float) -> tuple[int, int]:
        ox, oy = self._anchor
        fi, fj = (lower_x - ox) / STATOR_SIZE, (lower_y - oy) / STATOR_SIZE
        i, j = round(fi), round(fj)
        if max(abs(fi - i), abs(fj - j)) * STATOR_SIZE > GRID_TOLERANCE:
            raise ConfigError(f"{name}: off the {STATOR_SIZE:g} mm stator grid anchored at "
                              f"({ox}, {oy})")
        return i, j

    def _corner(self, index: int) -> tuple[float, float]:
        stator = self._stators[index]
        return stator.lower_x, stator.lower_y
