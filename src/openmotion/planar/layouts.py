"""Stator layouts as plain data: MagBotSim's ten planning layouts and random fields.

MagBotSim (Bergmann et al., the MuJoCo maglev simulator researchers use) benchmarks motion
planning on ten tile masks B0..B9 with 3 to 5 movers. Here each is rebuilt on our 240 mm
stators (the same size as its tiles) with the same tile mask and mover count, so a planner or
a learning environment can be compared layout by layout. The masks are data, typed in our own
notation: ``tiles[i][j]`` is ``"#"`` where the stator of x index ``i`` and y index ``j``
stands, ``"."`` where there is none (MagBotSim indexes its arrays x first too).

Start and goal rule (D-310): every mover starts on the centre of its own stator and gets a
goal on the centre of another stator, all starts distinct, all goals distinct, each goal
differs from its mover's start. A 155 mm mover on a 240 mm stator leaves 85 mm between
neighbours, so any such assignment is collision-free at rest.

A ``Layout`` knows nothing of runtimes; ``openmotion.envs`` and the routing benchmark build
their fields from it.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.planar.stators import STATOR_SIZE, StatorField

MOVER_SIZE = 155.0  #: side of the default mover, as PlanarMoverParameters has it [mm]
RANDOM_HOLE_FRACTION = 0.1  #: a random field lacks up to this share of its stators
STATORS_PER_MOVER = 2.0  #: a random field has about this many stators per mover


@dataclass(frozen=True)
class Layout:
    """One stator layout with its mover count (plain data; see the module docstring)."""

    name: str
    tiles: tuple[str, ...]  #: ``tiles[i][j]``: "#" a stator at x index i, y index j; "." none
    movers: int  #: how many movers the layout is benchmarked with
    mover_size: float = MOVER_SIZE  #: square mover side [mm]
    source: str = ""  #: where the layout comes from

    def __post_init__(self) -> None:
        widths = {len(row) for row in self.tiles}
        if not self.tiles or len(widths) != 1 or set("".join(self.tiles)) - set("#."):
            raise ConfigError(f"layout {self.name}: tiles must be equal rows of '#' and '.'")
        if not 1 <= self.movers <= self.stator_count - 1:
            raise ConfigError(f"layout {self.name}: {self.movers} movers need at least "
                              f"{self.movers + 1} stators, it has {self.stator_count}")

    @property
    def shape(self) -> tuple[int, int]:
        """(x cells, y cells) of the mask."""
        return len(self.tiles), len(self.tiles[0])

    @property
    def cells(self) -> tuple[tuple[int, int], ...]:
        """The (i, j) grid cells that hold a stator, x index first, in mask order."""
        return tuple((i, j) for i, row in enumerate(self.tiles)
                     for j, tile in enumerate(row) if tile == "#")

    @property
    def stator_count(self) -> int:
        return sum(row.count("#") for row in self.tiles)

    def stators(self) -> list[tuple[float, float]]:
        """Lower-left corners [mm] of the stators, for ``MC_PlanarEnvironment.add_stator``."""
        return [(i * STATOR_SIZE, j * STATOR_SIZE) for i, j in self.cells]

    def centres(self) -> np.ndarray:
        """Stator centres [mm], shape (stators, 2): the places movers start and end on."""
        return np.array(self.stators(), dtype=float).reshape(-1, 2) + STATOR_SIZE / 2

    def field(self) -> StatorField:
        return StatorField(self.stators(), origin=(0.0, 0.0))

    def starts_and_goals(self, rng: np.random.Generator,
                         movers: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Start and goal centres [mm], shape (movers, 2) each, by the rule of D-310."""
        n = self.movers if movers is None else movers
        centres = self.centres()
        if not 1 <= n <= len(centres) - 1:
            raise ConfigError(f"layout {self.name}: {n} movers need at least {n + 1} stators")
        starts = rng.choice(len(centres), size=n, replace=False)
        goals = rng.permutation(len(centres))[:n]
        while np.any(goals == starts):  # a derangement by rejection: cheap for n << stators
            goals = rng.permutation(len(centres))[:n]
        return centres[starts], centres[goals]


def _mask(*rows: str) -> tuple[str, ...]:
    return tuple(rows)


_MAGBOTSIM = "MagBotSim benchmark planning layout"

#: MagBotSim's ten planning layouts B0..B9: tile masks and mover counts, on our stators
MAGBOTSIM_LAYOUTS: tuple[Layout, ...] = (
    Layout("B0", _mask("###", "###", "###", "###"), 3, source=f"{_MAGBOTSIM} B0"),
    Layout("B1", _mask("###", "###", ".##", "###"), 3, source=f"{_MAGBOTSIM} B1"),
    Layout("B2", _mask("#####", "#####", "...##", "#####", "#####", "##...", "#####",
                       "#####"), 4, source=f"{_MAGBOTSIM} B2"),
    Layout("B3", _mask("..###..", "..###..", "#######", "###.###", "#######", "..###..",
                       "..###.."), 4, source=f"{_MAGBOTSIM} B3"),
    Layout("B4", _mask("######", "######", "######", "#...##", "##...#", "######", "######",
                       "######"), 4, source=f"{_MAGBOTSIM} B4"),
    Layout("B5", _mask("######", "######", "######", "..##..", "..##..", "..##..", "..##..",
                       "..##..", "######", "######", "######"), 3, source=f"{_MAGBOTSIM} B5"),
    Layout("B6", _mask("...###", "...###", "...###", "######", "######", "###...", "###...",
                       "###..."), 4, source=f"{_MAGBOTSIM} B6"),
    Layout("B7", _mask("###.###", "###.###", "##...##", "##...##", "##...##", "#######",
                       "#######"), 4, source=f"{_MAGBOTSIM} B7"),
    Layout("B8", _mask("######", "######", "####..", "####..", "######", "#.####", "..####",
                       "...#.."), 5, source=f"{_MAGBOTSIM} B8"),
    Layout("B9", _mask("#####...", "######..", "..#####.", "..######", "#..##.##", "#####.##",
                       "########", "#######."), 5, source=f"{_MAGBOTSIM} B9"),
)


def _connected(cells: set[tuple[int, int]]) -> bool:
    """Whether the stators form one island (movers pass only across shared edges)."""
    if not cells:
        return False
    start = next(iter(cells))
    seen, todo = {start}, deque([start])
    while todo:
        i, j = todo.popleft()
        for step in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if step in cells and step not in seen:
                seen.add(step)
                todo.append(step)
    return len(seen) == len(cells)


def random_layout(movers: int, rng: np.random.Generator,
                  stators_per_mover: float = STATORS_PER_MOVER,
                  hole_fraction: float = RANDOM_HOLE_FRACTION,
                  name: str | None = None) -> Layout:
    """A random connected field for ``movers`` movers: a near-square block of about
    ``stators_per_mover * movers`` stators (one spare at least) with up to ``hole_fraction``
    of them removed at random where the rest stays one island."""
    if isinstance(movers, bool) or not isinstance(movers, int) or movers < 1:
        raise ConfigError(f"random layout: movers must be an int >= 1, got {movers!r}")
    if not stators_per_mover >= 1.0 or not 0.0 <= hole_fraction < 1.0:
        raise ConfigError("random layout: stators_per_mover must be >= 1 and hole_fraction "
                          "in [0, 1)")
    wanted = max(movers + 1, int(np.ceil(stators_per_mover * movers)))
    side_x = max(2, int(np.ceil(np.sqrt(wanted / (1.0 - hole_fraction)))))
    side_y = max(2, int(np.ceil(wanted / (1.0 - hole_fraction) / side_x)))
    cells = {(i, j) for i in range(side_x) for j in range(side_y)}
    for index in rng.permutation(len(cells)):
        if len(cells) <= wanted:
            break
        cell = (int(index) // side_y, int(index) % side_y)
        cells.discard(cell)
        if not _connected(cells):
            cells.add(cell)
    tiles = tuple("".join("#" if (i, j) in cells else "." for j in range(side_y))
                  for i in range(side_x))
    return Layout(name or f"random-{movers}", tiles, movers, source="random field")


def layout_names() -> tuple[str, ...]:
    return tuple(layout.name for layout in MAGBOTSIM_LAYOUTS)


def magbotsim_layout(name: str) -> Layout:
    """One of B0..B9; a ``ConfigError`` naming the known ones otherwise."""
    for layout in MAGBOTSIM_LAYOUTS:
        if layout.name == name:
            return layout
    raise ConfigError(f"unknown layout {name!r}; known: {', '.join(layout_names())}")


def square(side: int, movers: int = 0, name: str | None = None) -> Layout:
    """A full ``side`` x ``side`` field (the routing benchmark's Planar-Motor-scale case)."""
    return Layout(name or f"square{side}", tuple("#" * side for _ in range(side)), movers,
                  source="full square field")
