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
from openmotion.geometry.blend import Contour, _monomial
from openmotion.geometry.path import Arc, Line

_ZERO3 = np.zeros(3)
_ZERO3.flags.writeable = False
_MONOMIAL5 = _monomial(5)  #: Bézier control points to coefficients of powers of u


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
        radial = c * element.u + d * element.v
        if s >= element.length:
            point = element.end
        elif s <= 0.0:
            point = element.start
        else:
            point = element.center + element.radius * radial
        return point, -d * element.u + c * element.v, -radial / element.radius
    if kind is Contour:
        return _contour_frame(element, s)
    return (element.position(s), element.tangent(s),
            getattr(element, "curvature_vector", lambda _s: np.zeros(3))(s))


def _contour_frame(contour: Contour, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(point, unit tangent, curvature vector) of a contour at ``s``: the curve parameter
    from ``_parameter``, then the point and the first two derivatives of the curve in one
    product with their coefficients in powers of u (``_tables``)."""
    frame, nodes = _tables(contour)
    u = _parameter(nodes, s)
    u2 = u * u
    row = np.array([1.0, u, u2, u2 * u, u2 * u2, u2 * u2 * u])
    x, y, z, d1x, d1y, d1z, d2x, d2y, d2z = (row @ frame).tolist()
    speed2 = d1x * d1x + d1y * d1y + d1z * d1z
    along = (d1x * d2x + d1y * d2y + d1z * d2z) / speed2
    speed = math.sqrt(speed2)
    if s >= nodes[0][-1]:
        point = contour.end
    elif s <= 0.0:
        point = contour.start
    else:
        point = contour.start + np.array([x, y, z])
    return (point, np.array([d1x / speed, d1y / speed, d1z / speed]),
            np.array([d2x - along * d1x, d2y - along * d1y, d2z - along * d1z]) / speed2)


def _tables(contour: Contour) -> tuple[np.ndarray, tuple[list[float], np.ndarray]]:
    """Per contour, built at its first sample: the point (from the start), B' and B'' in
    powers of u, (6, 9); the arc lengths of the curve parameters k/64 (the contour's own
    table) and B', B'', B''' in powers of u, (5, 9), for ``_parameter``."""
    cached = contour.__dict__.get("_openmotion_tables")
    if cached is None:
        derivatives = contour.derivatives_in_powers  # the caps built it already
        frame = np.zeros((6, 9))
        frame[:, 0:3] = _MONOMIAL5 @ contour.control_offsets
        frame[:5, 3:9] = derivatives[:, 0:6]
        cached = (frame, (np.asarray(contour.arc_length_table, dtype=float).tolist(), derivatives))
        contour.__dict__["_openmotion_tables"] = cached
    return cached


def _parameter(nodes: tuple[list[float], np.ndarray], s: float) -> float:
    """The curve parameter at arc length ``s``: Hermite interpolation of u(s) of degree 7
    between the nodes of the contour's arc-length table, with the exact derivatives there:
    du/ds = 1/σ, d²u/ds² = -(r'·r'')/σ⁴ and d³u/ds³ = (4(r'·r'')²/σ² - r''·r'' - r'·r''')/σ⁵
    (σ = |r'(u)|), evaluated at the two nodes around ``s`` only. The point stays on the curve
    whatever u is; the interpolation only decides how far along it s lands: within about
    1e-14 of the contour's length of the exact arc length, and the speed along the curve
    within about 1e-11 of ds/dt (turns of 0-179.9°). A cubic through u and du/ds alone was
    1e5 times less accurate: the setpoints ran up to 5e-6 faster than the time law, and so
    above the caps that keep the axes within their limits (tests/coordinated/
    test_properties.py)."""
    s_nodes, derivatives = nodes
    if s <= 0.0:
        return 0.0
    if s >= s_nodes[-1]:
        return 1.0
    last = len(s_nodes) - 1
    k = min(bisect.bisect_right(s_nodes, s) - 1, last - 1)
    u0, u1 = k / last, (k + 1) / last
    powers = np.array([[1.0, u0, u0 * u0, u0**3, u0**4], [1.0, u1, u1 * u1, u1**3, u1**4]])
    at0, at1 = (powers @ derivatives).tolist()
    first0, second0, third0 = _rates(at0)
    first1, second1, third1 = _rates(at1)
    h = s_nodes[k + 1] - s_nodes[k]
    t = (s - s_nodes[k]) / h
    t2 = t * t
    t3 = t2 * t
    t4 = t2 * t2
    t5, t6, t7 = t4 * t, t4 * t2, t4 * t3
    rise = 35 * t4 - 84 * t5 + 70 * t6 - 20 * t7  # the Hermite basis of degree 7 on [0, 1]
    return (u0 + rise * (u1 - u0)
            + h * ((t - 20 * t4 + 45 * t5 - 36 * t6 + 10 * t7) * first0
                   + (-15 * t4 + 39 * t5 - 34 * t6 + 10 * t7) * first1)
            + h * h * ((0.5 * t2 - 5 * t4 + 10 * t5 - 7.5 * t6 + 2 * t7) * second0
                       + (2.5 * t4 - 7 * t5 + 6.5 * t6 - 2 * t7) * second1)
            + h * h * h * ((t3 - 4 * t4 + 6 * t5 - 4 * t6 + t7) * third0
                           + (-t4 + 3 * t5 - 3 * t6 + t7) * third1) / 6.0)


def _rates(r: list[float]) -> tuple[float, float, float]:
    """du/ds, d²u/ds², d³u/ds³ from r', r'', r''' at one curve parameter (``_parameter``)."""
    x1, y1, z1, x2, y2, z2, x3, y3, z3 = r
    speed2 = x1 * x1 + y1 * y1 + z1 * z1
    along = x1 * x2 + y1 * y2 + z1 * z2
    bend = x2 * x2 + y2 * y2 + z2 * z2 + x1 * x3 + y1 * y3 + z1 * z3
    speed = math.sqrt(speed2)
    return (1.0 / speed, -along / (speed2 * speed2),
            (4.0 * along * along / speed2 - bend) / (speed2 * speed2 * speed))
