"""Stator layouts as plain data: MagBotSim's ten trajectory-planning benchmark layouts.

MagBotSim (Bergmann et al., Bielefeld University; docs "Benchmarks Trajectory Planning")
defines ten planning benchmarks B0-B9: a tile mask and a mover count each. The masks are
facts about their benchmark, rebuilt here as our own data: one string per first index
(x = 0, 1, ...), one character per second index (y = 0, 1, ...), ``#`` a 240 mm stator
and ``.`` none, the same indexing as MagBotSim's ``layout_tiles[x, y]``. The router's
benchmark (bench/routing.py) and the environments (openmotion.envs) both read this module,
so that the layouts live in one place.
"""

from __future__ import annotations

from dataclasses import dataclass

from openmotion.planar.stators import STATOR_SIZE


@dataclass(frozen=True)
class StatorLayout:
    """A field of stators: ``rows[x][y]`` is ``#`` where a stator lies."""

    name: str
    rows: tuple[str, ...]
    movers: int  #: how many movers the benchmark puts on it

    @property
    def shape(self) -> tuple[int, int]:
        """Stators along x and along y (the bounding box)."""
        return len(self.rows), len(self.rows[0])

    def stators(self) -> list[tuple[float, float]]:
        """Lower-left corners [mm] of the stators, for ``MC_PlanarEnvironment.add_stator``."""
        return [(STATOR_SIZE * x, STATOR_SIZE * y) for x, row in enumerate(self.rows)
                for y, mark in enumerate(row) if mark == "#"]

    def centres(self) -> list[tuple[float, float]]:
        """Centres [mm] of the stators, in the order of ``stators``."""
        half = STATOR_SIZE / 2.0
        return [(x + half, y + half) for x, y in self.stators()]


def _layout(name: str, movers: int, *rows: str) -> StatorLayout:
    if len({len(r) for r in rows}) != 1:
        raise ValueError(f"{name}: rows of different lengths")
    return StatorLayout(name, tuple(rows), movers)


#: MagBotSim's planning benchmarks B0-B9 (3 to 5 movers on 12 to 64 tile positions)
MAGBOTSIM_PLANNING: tuple[StatorLayout, ...] = (
    _layout("B0", 3, "###", "###", "###", "###"),
    _layout("B1", 3, "###", "###", ".##", "###"),
    _layout("B2", 4, "#####", "#####", "...##", "#####", "#####", "##...", "#####",
            "#####"),
    _layout("B3", 4, "..###..", "..###..", "#######", "###.###", "#######", "..###..",
            "..###.."),
    _layout("B4", 4, "######", "######", "######", "#...##", "##...#", "######", "######",
            "######"),
    _layout("B5", 3, "######", "######", "######", "..##..", "..##..", "..##..", "..##..",
            "..##..", "######", "######", "######"),
    _layout("B6", 4, "...###", "...###", "...###", "######", "######", "###...", "###...",
            "###..."),
    _layout("B7", 4, "###.###", "###.###", "##...##", "##...##", "##...##", "#######",
            "#######"),
    _layout("B8", 5, "######", "######", "####..", "####..", "######", "#.####", "..####",
            "...#.."),
    _layout("B9", 5, "#####...", "######..", "..#####.", "..######", "#..##.##", "#####.##",
            "########", "#######."),
)

LAYOUTS: dict[str, StatorLayout] = {layout.name: layout for layout in MAGBOTSIM_PLANNING}


def square(side: int, movers: int = 0, name: str | None = None) -> StatorLayout:
    """A full ``side`` x ``side`` field."""
    return StatorLayout(name or f"square{side}", tuple("#" * side for _ in range(side)), movers)
