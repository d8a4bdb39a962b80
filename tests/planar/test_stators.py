"""Stators and the stator surface (TF5430 §5.1, §6.4.2, §6.7.2)."""

from __future__ import annotations

import math

import pytest
import shapely

from openmotion.core.errors import ConfigError
from openmotion.planar.stators import STATOR_SIZE, StatorField


def test_four_by_four_field_surface_and_info() -> None:
    field = StatorField.rectangular(4, 4)
    assert len(field) == 16
    assert field.surface.equals(shapely.box(0.0, 0.0, 960.0, 960.0))
    assert len(field.surface.exterior.coords) == 5  # the joints between stators are dropped
    info = field.info
    assert (info.stator_count, info.boundary_element_count) == (16, 16)
    assert info.bounds == (0.0, 0.0, 960.0, 960.0)
    assert field.boundary.length == pytest.approx(4 * 960.0)


def test_manual_642_two_by_two_gives_eight_boundary_elements() -> None:
    """§6.4.2: AddStator at (0,0), (240,0), (0,240), (240,240); CreateBoundary."""
    field = StatorField([(0.0, 0.0), (240.0, 0.0), (0.0, 240.0), (240.0, 240.0)])
    boundary = field.create_boundary()
    assert boundary.element_count == 8  # outer sides, not merged
    assert all(e.length == pytest.approx(STATOR_SIZE) for e in boundary.elements)
    assert field.info.bounds == (0.0, 0.0, 480.0, 480.0)


def test_manual_672_single_stator_at_minus_120() -> None:
    """§6.7.2: one stator whose lower-left corner is (-120, -120) covers [-120, 120]²."""
    field = StatorField([(-120.0, -120.0)])
    assert field.info.bounds == (-120.0, -120.0, 120.0, 120.0)
    assert field.info.boundary_element_count == 4


def test_overlapping_stator_is_rejected_naming_it() -> None:
    field = StatorField.rectangular(2, 1)
    with pytest.raises(ConfigError, match=r"stators\[2\] \(240\.0, 0\.0\): overlaps stators\[1\]"):
        field.add_stator(240.0, 0.0)
    assert len(field) == 2


@pytest.mark.parametrize("corner", [(100.0, 0.0), (240.0, 0.5), (-120.0, 0.0)])
def test_off_grid_stator_is_rejected_naming_it(corner: tuple[float, float]) -> None:
    field = StatorField([(0.0, 0.0)])
    with pytest.raises(ConfigError, match=r"stators\[1\] .*off the 240 mm stator grid"):
        field.add_stator(*corner)


def test_grid_anchor_is_the_first_stator_unless_an_origin_is_given() -> None:
    StatorField([(-120.0, -120.0), (120.0, -120.0)])  # anchored at the first corner
    with pytest.raises(ConfigError, match="off the 240 mm stator grid anchored at"):
        StatorField([(-120.0, -120.0)], origin=(0.0, 0.0))


def test_corner_within_a_micrometre_snaps_to_the_grid() -> None:
    stator = StatorField([(0.0, 0.0)]).add_stator(240.0 + 1e-7, 0.0)
    assert stator.lower_x == 240.0


@pytest.mark.parametrize("corner", [(math.nan, 0.0), (0.0, math.inf)])
def test_non_finite_corner_is_rejected(corner: tuple[float, float]) -> None:
    with pytest.raises(ConfigError, match="must be a finite number"):
        StatorField([corner])


def test_rectangular_needs_at_least_one_stator() -> None:
    with pytest.raises(ConfigError, match="columns and rows"):
        StatorField.rectangular(0, 3)


def test_boundary_is_a_snapshot_like_create_boundary() -> None:
    """§6.4: stators added after CreateBoundary count only at the next CreateBoundary."""
    field = StatorField.rectangular(1, 1)
    boundary = field.create_boundary()
    field.add_stator(240.0, 0.0)
    assert boundary.element_count == 4
    assert not boundary.covers(shapely.box(200.0, 0.0, 300.0, 100.0))
    assert field.create_boundary().covers(shapely.box(200.0, 0.0, 300.0, 100.0))


def test_boundary_covers_an_area_touching_the_edge() -> None:
    boundary = StatorField.rectangular(2, 2).create_boundary()
    assert boundary.covers(shapely.box(0.0, 0.0, 155.0, 155.0))
    assert not boundary.covers(shapely.box(-1.0, 0.0, 154.0, 155.0))


def test_islands_and_holes_are_allowed() -> None:
    islands = StatorField([(0.0, 0.0), (480.0, 0.0)])
    assert islands.surface.geom_type == "MultiPolygon"
    assert islands.info.boundary_element_count == 8
    ring = StatorField(c for c in ((x * 240.0, y * 240.0) for y in range(3) for x in range(3))
                       if c != (240.0, 240.0))
    assert len(ring.surface.interiors) == 1
    assert ring.info.boundary_element_count == 16  # 12 outer sides + 4 around the hole


def test_clear_removes_stators_and_the_anchor() -> None:
    field = StatorField([(10.0, 10.0)])
    field.clear()
    assert field.info.stator_count == 0 and field.info.bounds is None
    assert field.surface.is_empty
    field.add_stator(0.0, 0.0)  # a new anchor: no longer off the old grid
    assert field.info.bounds == (0.0, 0.0, 240.0, 240.0)
