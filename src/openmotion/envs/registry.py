"""The layouts an environment can be made on, by name.

``B0`` .. ``B9`` are MagBotSim's planning layouts with their mover counts
(``openmotion.planar.layouts``); ``random`` is a random connected field sized for the mover
count asked for. A name the registry does not know is a ``ConfigError`` that lists the known
ones.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.planar.layouts import MAGBOTSIM_LAYOUTS, Layout, random_layout

RANDOM = "random"
DEFAULT_RANDOM_MOVERS = 5  #: movers of a random field when none are asked for


def _fixed(layout: Layout) -> Callable[[int | None, int], Layout]:
    def build(movers: int | None, seed: int) -> Layout:
        if movers is None or movers == layout.movers:
            return layout
        return Layout(layout.name, layout.tiles, movers, layout.mover_size, layout.source)
    return build


def _random(movers: int | None, seed: int) -> Layout:
    return random_layout(DEFAULT_RANDOM_MOVERS if movers is None else movers,
                         np.random.default_rng(seed))


#: name -> builder(movers or None for the layout's own count, layout seed)
LAYOUTS: dict[str, Callable[[int | None, int], Layout]] = {
    **{layout.name: _fixed(layout) for layout in MAGBOTSIM_LAYOUTS}, RANDOM: _random}


def make_layout(name: str | Layout, movers: int | None = None, seed: int = 0) -> Layout:
    """The layout ``name`` (or ``name`` itself when it is a ``Layout``), with ``movers``
    movers when given; ``seed`` draws a random field."""
    if isinstance(name, Layout):
        return _fixed(name)(movers, seed)
    if name not in LAYOUTS:
        raise ConfigError(f"unknown layout {name!r}; known: {', '.join(LAYOUTS)}")
    return LAYOUTS[name](movers, seed)
