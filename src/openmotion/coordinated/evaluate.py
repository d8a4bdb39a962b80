"""Point, unit tangent and curvature vector of one path element at one arc length.

The geometry classes answer one question per call and accept arrays, which costs numpy's
per-call overhead three times per cycle (position, tangent, curvature) and, for a blend
contour, three arc-length inversions. The cycle needs all three at a single s: this module
gets them with scalar arithmetic for lines and arcs and one inversion for a contour. Results
equal the classes' own (a contour's to about 1e-14 of its length, see ``_parameter``); ends
are returned exactly (the stored end points).
"""

from __future__ import annotations

import bisect
import math
from typing import Any

import numpy as np

from openmotion.coordinated.limits import DirectLine
from openmotion.geometry.blend import Contour, _bernstein
from openmotion.geometry.path import Arc, Line

_ZERO3 = np.zeros(3)
_ZERO3.flags.writeable = False


def evaluate(element: Any, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(point, unit tangent, curvature vector) of ``element`` at ``s`` (clamped)."""
    kind = type(element)
    if kind is Line or kind is DirectLine:
        if s >= element.length:
            point = element.end
        elif s <= 0.0:
            point = element.start
        else:
            point = element.start + s * element.direction
        zero = _ZERO3 if kind is Line else np.zeros_like(element.direction)
        return point, element.direction, zero
    if kind is Arc:
        phi = min(max(s, 0.0), element.length) / element.radius
        c, d = math.cos(phi), math.sin(phi)
        radial = c * element._u + d * element._v
        if s >= element.length:
            point = element.end
        elif s <= 0.0:
            point = element.start
        else:
            point = element.center + element.radius * radial
        return point, -d * element._u + c * element._v, -radial / element.radius
    if kind is Contour:
        u_row = np.array([_parameter(element, s)])
        if s >= element.length:
            point = element.end
        elif s <= 0.0:
            point = element.start
        else:
            point = element.start + (_bernstein(5, u_row) @ element._local)[0]
        first = element._derivative(u_row)[0]
        curvature = element._curvature_vector_at(u_row)[0]
        return point, first / math.sqrt(float(first @ first)), curvature
    return (element.position(s), element.tangent(s),
            getattr(element, "curvature_vector", lambda _s: np.zeros(3))(s))


def _parameter(contour: Contour, s: float) -> float:
    """The curve parameter at arc length ``s``: Hermite interpolation of u(s) of degree 7
    between the nodes of the contour's arc-length table, with the exact derivatives there:
    du/ds = 1/σ, d²u/ds² = -(r'·r'')/σ⁴ and d³u/ds³ = (4(r'·r'')²/σ² - r''·r'' - r'·r''')/σ⁵
    (σ = |r'(u)|). The point stays on the curve whatever u is; the interpolation only decides
    how far along it s lands: within about 1e-14 of the contour's length of the exact arc
    length, and the speed along the curve within about 1e-11 of ds/dt (turns of 0-179.9°).
    A cubic through u and du/ds alone was 1e5 times less accurate: the setpoints ran up to
    5e-6 faster than the time law, and so above the caps that keep the axes within their
    limits (tests/coordinated/test_properties.py)."""
    table = contour.__dict__.get("_openmotion_u_of_s")
    if table is None:
        s_nodes = np.asarray(contour._cumulative, dtype=float)
        u_nodes = np.linspace(0.0, 1.0, len(s_nodes))
        r = np.vander(u_nodes, 5, increasing=True) @ contour._derivatives_in_powers
        r1, r2, r3 = r[:, 0:3], r[:, 3:6], r[:, 6:9]  # r', r'', r''' (the caps built them)
        speed2 = np.einsum("ij,ij->i", r1, r1)
        along = np.einsum("ij,ij->i", r1, r2)
        bend = np.einsum("ij,ij->i", r2, r2) + np.einsum("ij,ij->i", r1, r3)
        speed = np.sqrt(speed2)
        first = 1.0 / speed
        second = -along / (speed2 * speed2)
        third = (4.0 * along * along / speed2 - bend) / (speed2 * speed2 * speed)
        table = (s_nodes.tolist(), u_nodes.tolist(), first.tolist(), second.tolist(),
                 third.tolist())
        contour.__dict__["_openmotion_u_of_s"] = table
    s_nodes, u_nodes, first, second, third = table
    if s <= 0.0:
        return 0.0
    if s >= s_nodes[-1]:
        return 1.0
    k = min(bisect.bisect_right(s_nodes, s) - 1, len(s_nodes) - 2)
    h = s_nodes[k + 1] - s_nodes[k]
    t = (s - s_nodes[k]) / h
    t2 = t * t
    t3 = t2 * t
    t4 = t2 * t2
    t5, t6, t7 = t4 * t, t4 * t2, t4 * t3
    rise = 35 * t4 - 84 * t5 + 70 * t6 - 20 * t7  # the Hermite basis of degree 7 on [0, 1]
    return (u_nodes[k] + rise * (u_nodes[k + 1] - u_nodes[k])
            + h * ((t - 20 * t4 + 45 * t5 - 36 * t6 + 10 * t7) * first[k]
                   + (-15 * t4 + 39 * t5 - 34 * t6 + 10 * t7) * first[k + 1])
            + h * h * ((0.5 * t2 - 5 * t4 + 10 * t5 - 7.5 * t6 + 2 * t7) * second[k]
                       + (2.5 * t4 - 7 * t5 + 6.5 * t6 - 2 * t7) * second[k + 1])
            + h * h * h * ((t3 - 4 * t4 + 6 * t5 - 4 * t6 + t7) * third[k]
                           + (-t4 + 3 * t5 - 3 * t6 + t7) * third[k + 1]) / 6.0)
