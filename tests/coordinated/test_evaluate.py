"""The cycle's evaluation of path elements equals the geometry classes' (coordinated/evaluate.py).

Equivalence of two paths: ``evaluate`` answers point, tangent and curvature vector at one arc
length with scalar arithmetic and cached coefficients; the classes answer each with numpy over
arrays. Contours cover turns from nearly straight to nearly reversing, between lines and arcs.
The two invert the arc length differently (Hermite interpolation of u(s) against Newton on the
arc-length integral): on contours into arcs they place s up to ~1e-11 of the length apart.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from openmotion.coordinated.evaluate import evaluate
from openmotion.geometry.blend import corner_distance_blend
from openmotion.geometry.path import Arc, Line


def corners(count: int, seed: int) -> list[tuple[Line | Arc, Line | Arc]]:
    """Random corners in the x-y plane: a line or an arc in, a line or an arc out."""
    rng = np.random.default_rng(seed)
    result = []
    for _ in range(count):
        turn = rng.uniform(1e-4, math.pi - 1e-2) * rng.choice([-1.0, 1.0])
        t_out = np.array([math.cos(turn), math.sin(turn), 0.0])
        size = rng.uniform(0.1, 50.0, 2)
        before: Line | Arc = Line([-size[0], 0.0, 0.0], [0.0, 0.0, 0.0])
        after: Line | Arc = Line([0.0, 0.0, 0.0], size[1] * t_out)
        if rng.random() < 0.5:
            normal = np.array([0.0, 0.0, rng.choice([-1.0, 1.0])])
            center = size[1] * np.cross(normal, t_out)
            sweep = rng.uniform(0.2, 2.0)
            radial = -center
            end = center + math.cos(sweep) * radial + math.sin(sweep) * np.cross(normal, radial)
            after = Arc([0.0, 0.0, 0.0], end, center, normal)
        result.append((before, after))
    return result


@pytest.mark.parametrize("seed", range(4))
def test_contours_evaluate_as_the_class_does(seed):
    for before, after in corners(25, seed):
        limit = min(before.length, after.length) / 2.0
        contour = corner_distance_blend(before, after, 0.7 * limit).contour
        scale = max(1.0, contour.max_curvature * contour.length)
        for s in [0.0, contour.length, *np.linspace(0.0, contour.length, 13)[1:-1]]:
            point, tangent, curvature = evaluate(contour, float(s))
            assert np.abs(point - contour.position(s)).max() <= 1e-10 * contour.length
            assert np.abs(tangent - contour.tangent(s)).max() <= 1e-10 * scale
            assert np.abs(curvature - contour.curvature_vector(s)).max() \
                <= 1e-9 * scale * contour.max_curvature
        assert np.array_equal(evaluate(contour, 0.0)[0], contour.start)
        assert np.array_equal(evaluate(contour, contour.length)[0], contour.end)


def test_lines_and_arcs_evaluate_as_the_classes_do():
    for before, after in corners(20, 7):
        for element in (before, after):
            for s in np.linspace(0.0, element.length, 7):
                point, tangent, curvature = evaluate(element, float(s))
                assert np.allclose(point, element.position(s), rtol=0.0, atol=1e-12)
                assert np.allclose(tangent, element.tangent(s), rtol=0.0, atol=1e-12)
                assert np.allclose(curvature, element.curvature_vector(s), rtol=0.0, atol=1e-12)
