"""Dense paths: many short lines with rounded corners, prepared in bulk (D-290).

MC_PathSelect (paths.py) rounds every corner of a path with geometry/blend.py, one corner
at a time: a few hundred microseconds of numpy calls per corner, seconds for the 10 000
chords of a CAM contour. Here a run of lines with the same TMCornerDistance or
TMMaxCornerDeviation is done in one pass: the corner distances (each corner's depends on the
trim of the line before it, a scalar recurrence), then the trimmed lines and the contours as
arrays, their arc-length tables, cusp tests and corner deviations in compiled loops
(dense_kernels.py). Equal to the corner-by-corner result to round-off. A corner where the
widest contour deviates more than asked (a root search), or that the checks refuse, goes
the corner-by-corner way, and the batch goes on after it.

The caps of many contours (``contour_caps``) come the same way at MC_MovePath's start.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from openmotion.coordinated import dense_kernels as kernels
from openmotion.coordinated.inputs import TransitionMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.geometry.blend import (
    _BEND,
    _CANDIDATES,
    _HANDLE,
    _MAX_ZOOMS,
    _PEAKS_SAMPLES,
    _PIECES,
    _REGULAR,
    _SAMPLES,
    _ZOOMS,
    BOUND_MARGIN,
    REVERSAL_ANGLE,
    Contour,
)
from openmotion.geometry.path import TOLERANCE, Line

Array = NDArray[np.float64]

DENSE_MIN = 16  #: lines in a run before the batch route pays; shorter runs go corner by corner
_CHUNK_FIRST, _CHUNK_MAX = 64, 4096  #: corners per batch: start small after a fallback, double
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(8)
#: Bernstein (degree 4) to powers of u, as blend.py's ``_monomial(4)``
_TO_POWERS = np.array([[math.comb(4, i) * math.comb(4 - i, k - i) * (-1) ** (k - i)
                        if i <= k else 0.0 for i in range(5)] for k in range(5)], dtype=float)
#: Bernstein (degree 3 and 2) to powers of u, as blend.py's ``_monomial(3)``, ``_monomial(2)``
_TO_POWERS3, _TO_POWERS2 = (np.array([[math.comb(n, i) * math.comb(n - i, k - i) * (-1) ** (k - i)
                                       if i <= k else 0.0 for i in range(n + 1)]
                                      for k in range(n + 1)], dtype=float) for n in (3, 2))
_BLENDED = (TransitionMode.TM_CORNER_DISTANCE, TransitionMode.TM_MAX_CORNER_DEVIATION)


def blendable(transition: tuple[TransitionMode, float]) -> bool:
    """Whether a run of lines with this corner transition goes the batch way."""
    return transition[0] in _BLENDED


def _line(start: Array, end: Array, length: float, direction: Array) -> Line:
    """A Line from values computed in bulk, as ``Line(start, end)`` computes them."""
    line = Line.__new__(Line)
    line.start, line.end, line.length, line.direction = start, end, length, direction
    line.max_curvature = 0.0
    return line


def _rows_norm(values: Array) -> Array:
    return np.sqrt(np.einsum("ij,ij->i", values, values))


def blend_lines(elements: list[Any], exits: list[float], ends: Array, first_index: int,
                transition: tuple[TransitionMode, float],
                one_corner: Callable[[Any, Any, tuple[TransitionMode, float]], Any]) -> None:
    """Append the lines to ``ends`` (m, 3) to ``elements`` (whose last is a Line ending at
    the first corner), each corner rounded by ``transition``, as paths.py's loop would:
    ``elements[-1]`` trimmed, then contour, trimmed line, ...; ``exits`` alike (inf, or 0
    where a corner stops). ``one_corner(before, after, transition)`` is that loop's
    corner-by-corner contour (a Blend or None), for the corners the batch leaves to it.
    ``first_index`` numbers the first line in the description (for error messages)."""
    mode, value = transition
    points = np.vstack([elements[-1].end[None, :], ends])
    chord = points[1:] - points[:-1]
    length = _rows_norm(chord)
    bad = np.flatnonzero(~(length > TOLERANCE))
    if bad.size:
        raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY,
                              f"element {first_index + int(bad[0])}: line: start and end "
                              "coincide")
    direction = chord / length[:, None]
    j, chunk = 0, _CHUNK_FIRST
    while j < len(ends):
        stop = min(len(ends), j + chunk)
        done = _chunk(elements, exits, points[j:stop + 1], length[j:stop],
                      direction[j:stop], mode, value)
        j += done
        if j < stop:  # corner j needs the corner-by-corner way
            before = elements[-1]
            after = Line(points[j], points[j + 1])
            blend = one_corner(before, after, transition)
            if blend is None:
                exits[-1] = 0.0
                elements.append(after)
            else:
                elements[-1] = blend.before
                elements.extend((blend.contour, blend.after))
                exits.append(math.inf)
            exits.append(math.inf)
            j += 1
            chunk = _CHUNK_FIRST
        else:
            chunk = min(2 * chunk, _CHUNK_MAX)


def _chunk(elements: list[Any], exits: list[float], points: Array, length: Array,
           direction: Array, mode: TransitionMode, value: float) -> int:
    """Corners at ``points[:-1]`` (lines to ``points[1:]``) in one batch; how many were
    done before the first that needs the corner-by-corner way (all: ``len(length)``)."""
    current: Line = elements[-1]
    k = len(length)
    tangents = np.vstack([current.direction[None, :], direction])
    turn_back = (np.einsum("ij,ij->i", tangents[:-1], tangents[1:])
                 <= -math.cos(REVERSAL_ANGLE)).tolist()
    # the corner distances: half of each line at most, of the line before as trimmed
    distances = [0.0] * k
    before = current.length
    for q, (after, back) in enumerate(zip(length.tolist(), turn_back, strict=True)):
        if back:
            before = after
            continue
        d = min(0.5 * before, 0.5 * after)
        if mode is TransitionMode.TM_CORNER_DISTANCE:
            d = min(d, value)
        distances[q] = d
        before = after - d
    d = np.array(distances)
    corner, target = points[:-1], points[1:]
    tail_start = corner + d[:, None] * direction  # where each trimmed line begins
    head_start = np.vstack([current.start[None, :], tail_start[:-1]])
    head_chord = corner - head_start
    head_full = _rows_norm(head_chord)
    head_end = head_start + ((head_full - d) / head_full)[:, None] * head_chord
    head_vector = head_end - head_start
    head_length = _rows_norm(head_vector)
    tail_vector = target - tail_start
    tail_length = _rows_norm(tail_vector)
    t0 = head_vector / head_length[:, None]
    t1 = tail_vector / tail_length[:, None]
    c = np.sqrt(np.maximum(0.0, 0.5 * (1.0 + np.einsum("ij,ij->i", t0, t1))))
    gap = tail_start - head_end
    handle = _HANDLE * _rows_norm(gap) / (1.0 + c)
    u0 = t0 / _rows_norm(t0)[:, None]
    u1 = t1 / _rows_norm(t1)[:, None]
    step = np.empty((k, 5, 3))
    step[:, 0] = handle[:, None] * u0
    step[:, 1] = step[:, 0]
    step[:, 4] = handle[:, None] * u1
    step[:, 3] = step[:, 4]
    step[:, 2] = gap - step[:, 0] - step[:, 1] - step[:, 3] - step[:, 4]
    offsets = np.concatenate([np.zeros((k, 1, 3)), np.cumsum(step, axis=1)], axis=1)
    first = 5.0 * step
    second = 20.0 * np.diff(step, axis=1)
    second[:, 0] = second[:, 3] = 0.0  # 20 x the curvature terms: lines have none
    power = np.einsum("ij,njk->nik", _TO_POWERS, first)
    derivatives = np.zeros((k, 5, 9))  # the three derivatives in powers of u, as the property
    derivatives[:, :, 0:3] = power
    derivatives[:, :4, 3:6] = np.einsum("ij,njk->nik", _TO_POWERS3, second)
    derivatives[:, :3, 6:9] = np.einsum("ij,njk->nik", _TO_POWERS2,
                                        3.0 * np.diff(second, axis=1))
    with np.errstate(invalid="ignore", divide="ignore"):
        fine = (np.isfinite(handle) & (handle > 0.0) & (head_length > 2.0 * TOLERANCE)
                & (tail_length > 2.0 * TOLERANCE))
    back = np.array(turn_back, dtype=bool)
    fine &= ~back
    fine &= ~kernels.cusps(power, _SAMPLES, _REGULAR)
    if mode is TransitionMode.TM_MAX_CORNER_DEVIATION:
        deviation = kernels.corner_distances(offsets, corner - head_end, _SAMPLES, _ZOOMS)
        fine &= deviation <= value
    ok = fine | back
    done = k if ok.all() else int(np.argmin(ok))
    if done == 0:
        return 0
    tables = kernels.arc_tables(power[:done], _PIECES, _NODES, _WEIGHTS)
    for q in range(done):
        if back[q]:
            exits[-1] = 0.0
            elements.append(_line(corner[q], target[q], float(length[q]), direction[q]))
            exits.append(math.inf)
            continue
        elements[-1] = _line(head_start[q], head_end[q], float(head_length[q]), t0[q])
        elements.append(Contour.from_arrays(head_end[q], tail_start[q], offsets[q], first[q],
                                            second[q], power[q], tables[q],
                                            derivatives[q]))
        elements.append(_line(tail_start[q], target[q], float(tail_length[q]), t1[q]))
        exits.extend((math.inf, math.inf))
    return done


def derivative_bounds(contours: list[Contour]) -> Array:
    """(n, 3, 3): ``Contour.derivative_bounds`` of many contours in one compiled pass; each
    contour keeps its bounds, so that it need not sample itself again."""
    table = np.array([c.derivatives_in_powers for c in contours])
    peaks = kernels.derivative_peaks(table, _PEAKS_SAMPLES, _CANDIDATES, _MAX_ZOOMS, _BEND)
    bounds = ((1.0 + BOUND_MARGIN) * peaks).reshape(len(contours), 3, 3)
    for contour, bound in zip(contours, bounds, strict=True):
        contour.keep_derivative_bounds(bound)
    return bounds
