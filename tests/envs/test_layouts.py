"""The layout data: MagBotSim's ten planning layouts on our stators, and random fields."""

from __future__ import annotations

import numpy as np
import pytest

from openmotion.core.errors import ConfigError
from openmotion.planar.layouts import (
    MAGBOTSIM_LAYOUTS,
    Layout,
    _connected,
    magbotsim_layout,
    random_layout,
)
from openmotion.planar.stators import STATOR_SIZE

#: name: (x cells, y cells, stators, movers), counted from MagBotSim's benchmark masks
MAGBOTSIM_COUNTS = {
    "B0": (4, 3, 12, 3), "B1": (4, 3, 11, 3), "B2": (8, 5, 34, 4), "B3": (7, 7, 32, 4),
    "B4": (8, 6, 42, 4), "B5": (11, 6, 46, 3), "B6": (8, 6, 30, 4), "B7": (7, 7, 38, 4),
    "B8": (8, 6, 36, 5), "B9": (8, 8, 49, 5),
}


@pytest.mark.parametrize("layout", MAGBOTSIM_LAYOUTS, ids=lambda layout: layout.name)
def test_magbotsim_layouts_keep_their_tile_and_mover_counts(layout: Layout) -> None:
    assert (*layout.shape, layout.stator_count, layout.movers) == MAGBOTSIM_COUNTS[layout.name]
    assert _connected(set(layout.cells))
    field = layout.field()
    assert len(field.stators) == layout.stator_count
    assert field.surface.area == pytest.approx(layout.stator_count * STATOR_SIZE ** 2)


def test_the_masks_equal_magbotsim_s_own_when_it_is_installed() -> None:
    benchmark = pytest.importorskip("magbotsim.utils.benchmark_utils")
    for ours, theirs, movers in zip(MAGBOTSIM_LAYOUTS, benchmark.BENCHMARK_PLANNING_LAYOUTS,
                                    benchmark.BENCHMARK_PLANNING_NUM_MOVERS, strict=True):
        mask = np.array([[tile == "#" for tile in row] for row in ours.tiles], dtype=np.int8)
        assert np.array_equal(mask, theirs), ours.name
        assert ours.movers == movers


def test_starts_and_goals_are_distinct_stator_centres() -> None:
    layout = magbotsim_layout("B8")
    centres = {tuple(c) for c in layout.centres()}
    for seed in range(20):
        starts, goals = layout.starts_and_goals(np.random.default_rng(seed))
        assert starts.shape == goals.shape == (5, 2)
        assert len({tuple(s) for s in starts}) == len({tuple(g) for g in goals}) == 5
        assert {tuple(s) for s in starts} <= centres and {tuple(g) for g in goals} <= centres
        assert not np.any(np.all(starts == goals, axis=1))


def test_a_random_field_is_connected_seeded_and_large_enough() -> None:
    first = random_layout(50, np.random.default_rng(3))
    again = random_layout(50, np.random.default_rng(3))
    other = random_layout(50, np.random.default_rng(4))
    assert first == again and first.tiles != other.tiles
    assert first.stator_count >= 100 and _connected(set(first.cells))
    assert "." in "".join(first.tiles)  # some stators are missing


def test_bad_layouts_are_config_errors_naming_the_problem() -> None:
    with pytest.raises(ConfigError, match="unknown layout 'B10'; known: B0, B1"):
        magbotsim_layout("B10")
    with pytest.raises(ConfigError, match="3 movers need at least 4 stators"):
        Layout("tiny", ("##", "#."), 3)
    with pytest.raises(ConfigError, match="equal rows"):
        Layout("ragged", ("##", "#"), 1)
    with pytest.raises(ConfigError, match="movers must be an int >= 1"):
        random_layout(0, np.random.default_rng(0))
    assert magbotsim_layout("B9").movers == 5  # still usable
