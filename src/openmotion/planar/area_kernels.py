"""Compiled loops of the planar group's admission (numba): a straight move's runs, its pieces,
and the exact test of two convex pieces.

A MoveToPosition asks the group for its swept area in the cycle it is executed; a hundred movers
send several per cycle. In numpy and shapely the cost of that request is the number of calls on
arrays of a few dozen numbers, not the arithmetic, so these loops do the arithmetic in one
compiled pass each (docs/planar.md, "Speed"). They compute what ``motion.sample_times``,
``motion.sample_path``, ``reservation.travel_runs`` and shapely's ``intersects`` / ``touches``
do, with the same formulas in the same order (the tests hold them to it, bit for bit).

Exact test. Two convex polygons, vertices counter-clockwise, meet (share interior points, not
only boundary) unless one of the edges of either has every vertex of the other on its outer
side or on its line: convex sets with disjoint interiors are separated by a line through an edge
of one of them. The side of a vertex is the sign of a cross product of coordinate differences;
it is exactly zero where a vertex lies on an axis-parallel edge, the case of footprints that
stand edge to edge on the stator grid. Elsewhere shapely's robust predicates and these agree
except within rounding of the coordinates themselves (~1e-13 mm).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from openmotion.core.compiled import compiled, search_right, sort_in_place
from openmotion.planar.tolerances import SAMPLE_TIME_PRECISION


@compiled
def _position(data: NDArray[np.float64], time: float) -> float:
    """Position of profile ``data`` (t, p, v, a, j rows) at ``time`` after its start."""
    t = data[0]
    k = search_right(t, time) - 1
    if k < 0:
        k = 0
    dt = time - t[k]
    return data[1, k] + dt * (data[2, k] + dt * (data[3, k] / 2.0 + dt * data[4, k] / 6.0))


@compiled
def _plan_position(data: NDArray[np.float64], t0: float, running: bool, time: float) -> float:
    """One plan started at ``t0``, as ``motion.sample_path`` evaluates it: its position at the
    absolute ``time`` (its start position before t0), or its end when it is not ``running``."""
    if not running:
        return data[1, data.shape[1] - 1]
    dt = time - t0
    return _position(data, dt if dt > 0.0 else 0.0)


@compiled
def straight_runs(s: NDArray[np.float64], x: NDArray[np.float64], x_t0: float, x_running: bool,
                  y: NDArray[np.float64], y_t0: float, y_running: bool, c: NDArray[np.float64],
                  c_t0: float, c_running: bool, c_in_grid: bool, start: float, step: float,
                  release_step: float
                  ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
    """Sample times after ``start`` [s], the last sample of each run of ``release_step`` [mm]
    of travel, and the poses at sample 0 and at each run's end, of a centre that runs forward
    on a line with arc length ``s`` (profile data: t, p, v, a, j rows) started at ``start``.

    The samples are ``sample_times`` of s (and of ``c`` when ``c_in_grid``); the runs are
    ``travel_runs`` of s at the samples; the poses come from the ``x``, ``y`` and ``c``
    profiles started at their ``t0``, each resting at its end unless ``running``."""
    end = start + s[0, s.shape[1] - 1]
    if c_in_grid:
        end = max(end, c_t0 + c[0, c.shape[1] - 1])
    span = end - start
    if span < 0.0:
        span = 0.0
    count = int(math.ceil(span / step)) + 1
    extra = s.shape[1] + (c.shape[1] if c_in_grid else 0) + 1
    times = np.empty(count + extra)
    n = 0
    for i in range(count):
        times[n] = start + i * step
        n += 1
    for i in range(s.shape[1]):
        value = start + s[0, i]
        if value > start:
            times[n] = value
            n += 1
    if c_in_grid:
        for i in range(c.shape[1]):
            value = c_t0 + c[0, i]
            if value > start:
                times[n] = value
                n += 1
    times[n] = end
    n += 1
    times = times[:n]
    sort_in_place(times)  # sorted runs, values >= start >= 0 or NaN: as numpy.sort
    n = search_right(times, end)
    samples = np.empty(n)
    kept = 0
    for i in range(n):
        if i == 0 or times[i] - times[i - 1] > SAMPLE_TIME_PRECISION:
            samples[kept] = times[i] - start
            kept += 1
    samples = samples[:kept]
    marks = np.empty(kept, dtype=np.int64)
    runs = 0
    previous = math.floor(_position(s, samples[0]) / release_step)
    for i in range(1, kept):
        piece = math.floor(_position(s, samples[i]) / release_step)
        if piece != previous:
            marks[runs] = i
            runs += 1
        previous = piece
    if runs == 0 or marks[runs - 1] != kept - 1:
        marks[runs] = kept - 1
        runs += 1
    ends = marks[:runs]
    poses = np.empty((runs + 1, 3))
    for row in range(runs + 1):
        time = start + (samples[0] if row == 0 else samples[ends[row - 1]])
        poses[row, 0] = _plan_position(x, x_t0, x_running, time)
        poses[row, 1] = _plan_position(y, y_t0, y_running, time)
        poses[row, 2] = _plan_position(c, c_t0, c_running, time)
    return samples, ends, poses


@compiled
def straight_area_numbers(s: NDArray[np.float64], x: NDArray[np.float64], x_t0: float,
                          x_running: bool, y: NDArray[np.float64], y_t0: float,
                          y_running: bool, c: NDArray[np.float64], c_t0: float,
                          c_running: bool, c_in_grid: bool, start: float, step: float,
                          release_step: float, span: float, hx: float, hy: float,
                          noise: float):  # noqa: ANN201 - the two tuples below, joined
    """``straight_runs`` and then ``straight_pieces`` of its poses, in one call (the swept
    area of a MoveToPosition in the cycle it starts): samples, ends, poses, and fits, low,
    high, bounds, keys, key."""
    samples, ends, poses = straight_runs(s, x, x_t0, x_running, y, y_t0, y_running, c, c_t0,
                                         c_running, c_in_grid, start, step, release_step)
    fits, low, high, bounds, keys, key = straight_pieces(poses, span, hx, hy, noise)
    return samples, ends, poses, fits, low, high, bounds, keys, key


@compiled
def _quarter_cos_sin(c: float) -> tuple[float, float]:
    """``core.angles.cos_sin``: exact at multiples of 90 degrees."""
    turns = math.floor(c / 90.0)
    rest = c - turns * 90.0
    if rest == 0.0:
        quarter = int(turns) % 4
        if quarter == 0:
            return 1.0, 0.0
        if quarter == 1:
            return 0.0, 1.0
        if quarter == 2:
            return -1.0, 0.0
        return 0.0, -1.0
    radians = math.radians(c)
    return math.cos(radians), math.sin(radians)


@compiled
def _reach(c: float, hx: float, hy: float) -> tuple[float, float]:
    cos, sin = _quarter_cos_sin(c)
    cos, sin = abs(cos), abs(sin)
    return cos * hx + sin * hy, sin * hx + cos * hy


@compiled
def line_piece_bounds(points: NDArray[np.float64], low: NDArray[np.float64],
                      high: NDArray[np.float64], hx: float, hy: float, noise: float
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(m, 4) bounds of the m pieces of ``reservation._line_pieces`` (run j from
    ``points[j]`` to ``points[j + 1]`` turning within [``low[j]``, ``high[j]``] degrees), their
    query keys (max x, max y, -min x, -min y) and the key of all of them (``SweptArea``)."""
    runs = low.shape[0]
    bounds = np.empty((runs, 4))
    keys = np.empty((runs, 4))
    key = np.full(4, -np.inf)
    for j in range(runs):
        a, b = low[j], high[j]
        ax, ay = _reach(a, hx, hy)
        if a != b:
            bx, by = _reach(b, hx, hy)
            if b - a > noise:
                out = math.cos(math.radians(b - a) / 2.0)
                mx, my = _reach((a + b) / 2.0, hx, hy)
                ax, ay = max(ax, mx / out), max(ay, my / out)
            ax, ay = max(ax, bx), max(ay, by)
        x0, y0, x1, y1 = points[j, 0], points[j, 1], points[j + 1, 0], points[j + 1, 1]
        bounds[j, 0] = min(x0, x1) - ax
        bounds[j, 1] = min(y0, y1) - ay
        bounds[j, 2] = max(x0, x1) + ax
        bounds[j, 3] = max(y0, y1) + ay
        keys[j, 0], keys[j, 1] = bounds[j, 2], bounds[j, 3]
        keys[j, 2], keys[j, 3] = -bounds[j, 0], -bounds[j, 1]
        for k in range(4):
            key[k] = max(key[k], keys[j, k])
    return bounds, keys, key


@compiled
def straight_pieces(poses: NDArray[np.float64], span: float, hx: float, hy: float,
                    noise: float) -> tuple[bool, NDArray[np.float64], NDArray[np.float64],
                                           NDArray[np.float64], NDArray[np.float64],
                                           NDArray[np.float64]]:
    """``run_turns`` and ``line_piece_bounds`` of the runs between ``poses`` in one call:
    whether every run turns at most ``span``, each run's lowest and highest c, and (when it
    does) the pieces' bounds, keys and key."""
    low, high, fits = run_turns(poses, span)
    if not fits:
        empty = np.empty((0, 4))
        return False, low, high, empty, empty, np.empty(4)
    bounds, keys, key = line_piece_bounds(poses[:, :2], low, high, hx, hy, noise)
    return True, low, high, bounds, keys, key


@compiled
def run_turns(poses: NDArray[np.float64], span: float
              ) -> tuple[NDArray[np.float64], NDArray[np.float64], bool]:
    """Lowest and highest c [deg] of each run between consecutive ``poses`` (x, y, c rows),
    and whether every run turns at most ``span``."""
    runs = poses.shape[0] - 1
    low, high = np.empty(runs), np.empty(runs)
    fits = True
    for j in range(runs):
        a, b = poses[j, 2], poses[j + 1, 2]
        low[j], high[j] = min(a, b), max(a, b)
        if high[j] - low[j] > span:
            fits = False
    return low, high, fits


@compiled(inline=True)  # called with constants: one copy, not one per constant
def _turned_corners(c: float, hx: float, hy: float, scale: float,
                    out: NDArray[np.float64], row: int) -> None:
    """The four corners (ccw from (-hx, -hy)) of a footprint about the origin turned by c
    [deg], times ``scale``, into ``out[row:row + 4]`` (``reservation._turned_corners``)."""
    cos, sin = _quarter_cos_sin(c)
    cu, cv, su, sv = cos * hx, cos * hy, sin * hx, sin * hy
    out[row, 0], out[row, 1] = (-cu + sv) / scale, (-su - cv) / scale
    out[row + 1, 0], out[row + 1, 1] = (cu + sv) / scale, (su - cv) / scale
    out[row + 2, 0], out[row + 2, 1] = (cu - sv) / scale, (su + cv) / scale
    out[row + 3, 0], out[row + 3, 1] = (-cu - sv) / scale, (-su + cv) / scale


@compiled
def line_piece_hull(x0: float, y0: float, x1: float, y1: float, a: float, b: float,
                    hx: float, hy: float, noise: float) -> NDArray[np.float64]:
    """Vertices (ccw) of a piece of ``_line_pieces``: the hull of the footprint's corners at
    the lowest and highest c and the apexes between, at both ends of the run."""
    shape = np.empty((12, 2))
    _turned_corners(a, hx, hy, 1.0, shape, 0)
    count = 4
    if a != b:
        _turned_corners(b, hx, hy, 1.0, shape, 4)
        count = 8
        if b - a > noise:
            _turned_corners((a + b) / 2.0, hx, hy, math.cos(math.radians(b - a) / 2.0),
                            shape, 8)
            count = 12
    cloud = np.empty((2 * count, 2))
    for i in range(count):
        cloud[i, 0], cloud[i, 1] = shape[i, 0] + x0, shape[i, 1] + y0
        cloud[count + i, 0], cloud[count + i, 1] = shape[i, 0] + x1, shape[i, 1] + y1
    return convex_hull(cloud)


@compiled
def line_piece_meets(points: NDArray[np.float64], low: NDArray[np.float64],
                     high: NDArray[np.float64], i: int, hx: float, hy: float, noise: float,
                     other: NDArray[np.float64]) -> tuple[NDArray[np.float64], bool]:
    """``line_piece_hull`` of run ``i`` (from ``points[i]`` to ``points[i + 1]``, turning
    within [``low[i]``, ``high[i]``]) and whether it meets the convex ``other`` (ccw,
    ``interiors_meet``): the first exact test of a new piece in one call."""
    hull = line_piece_hull(points[i, 0], points[i, 1], points[i + 1, 0], points[i + 1, 1],
                           low[i], high[i], hx, hy, noise)
    return hull, interiors_meet(hull, other)


@compiled
def _cross(ox: float, oy: float, ax: float, ay: float, bx: float, by: float) -> float:
    return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox)


@compiled
def convex_hull(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Vertices of the convex hull of ``points`` (k, 2), counter-clockwise, without collinear
    points (Andrew's monotone chain)."""
    sorted_points = points.copy()
    n = sorted_points.shape[0]
    for i in range(1, n):  # insertion sort by x, then y: a few dozen points
        px, py = sorted_points[i, 0], sorted_points[i, 1]
        j = i - 1
        while j >= 0 and (sorted_points[j, 0] > px
                          or (sorted_points[j, 0] == px and sorted_points[j, 1] > py)):
            sorted_points[j + 1, 0], sorted_points[j + 1, 1] = \
                sorted_points[j, 0], sorted_points[j, 1]
            j -= 1
        sorted_points[j + 1, 0], sorted_points[j + 1, 1] = px, py
    hull = np.empty((2 * n, 2))
    k = 0
    for i in range(n):
        px, py = sorted_points[i, 0], sorted_points[i, 1]
        while k >= 2 and _cross(hull[k - 2, 0], hull[k - 2, 1], hull[k - 1, 0], hull[k - 1, 1],
                                px, py) <= 0.0:
            k -= 1
        hull[k, 0], hull[k, 1] = px, py
        k += 1
    lower = k + 1
    for i in range(n - 2, -1, -1):
        px, py = sorted_points[i, 0], sorted_points[i, 1]
        while k >= lower and _cross(hull[k - 2, 0], hull[k - 2, 1], hull[k - 1, 0],
                                    hull[k - 1, 1], px, py) <= 0.0:
            k -= 1
        hull[k, 0], hull[k, 1] = px, py
        k += 1
    return hull[:k - 1].copy()


@compiled
def _separates(edges: NDArray[np.float64], others: NDArray[np.float64]) -> bool:
    """Whether the line of an edge of ``edges`` (ccw) has every vertex of ``others`` on its
    outer side or on it."""
    n = edges.shape[0]
    for i in range(n):
        ox, oy = edges[i, 0], edges[i, 1]
        ax, ay = edges[(i + 1) % n, 0], edges[(i + 1) % n, 1]
        outside = True
        for q in range(others.shape[0]):
            if _cross(ox, oy, ax, ay, others[q, 0], others[q, 1]) > 0.0:
                outside = False
                break
        if outside:
            return True
    return False


@compiled
def interiors_meet(first: NDArray[np.float64], second: NDArray[np.float64]) -> bool:
    """Whether two convex polygons (vertices ccw) share interior points: shapely's
    ``intersects and not touches`` for convex polygons."""
    return not (_separates(first, second) or _separates(second, first))


@compiled
def near_slots(boxes: NDArray[np.float64], key: NDArray[np.float64], ranks: NDArray[np.int64],
               skip: NDArray[np.int64]) -> NDArray[np.int64]:
    """Slots whose stored box (min x, min y, -max x, -max y) lies below ``key`` in all four
    (the boxes overlap with positive area), in slot order, leaving out the slots of the
    members whose ranks are in ``skip``: row 0 the slots, row 1 their members' ranks. A free
    slot's box is +inf: never near."""
    near = np.empty((2, boxes.shape[0]), dtype=np.int64)
    count = 0
    for slot in range(boxes.shape[0]):
        if boxes[slot, 0] < key[0] and boxes[slot, 1] < key[1] and boxes[slot, 2] < key[2] \
                and boxes[slot, 3] < key[3]:
            rank = ranks[slot]
            skipped = False
            for other in skip:
                if rank == other:
                    skipped = True
                    break
            if not skipped:
                near[0, count] = slot
                near[1, count] = rank
                count += 1
    return near[:, :count]


@compiled
def meeting_pairs(boxes: NDArray[np.float64], key: NDArray[np.float64],
                  piece_keys: NDArray[np.float64], ranks: NDArray[np.int64],
                  skip: NDArray[np.int64]) -> NDArray[np.int64]:
    """The candidate pairs of an admission check: (rank, piece, slot) of every stored box
    that overlaps a piece's box (``piece_keys``, one row per piece; with one piece, every
    slot ``near_slots`` finds), in rank order, then piece order, then slot order: row 0 the
    ranks, row 1 the pieces, row 2 the slots. The boxes near the whole area (``key``) come
    from one pass over all slots; only they are compared with each piece."""
    near = near_slots(boxes, key, ranks, skip)
    count, pieces = near.shape[1], piece_keys.shape[0]
    pairs = np.empty((3, count * pieces), dtype=np.int64)
    found = 0
    for i in range(pieces):
        k0, k1, k2, k3 = piece_keys[i, 0], piece_keys[i, 1], piece_keys[i, 2], piece_keys[i, 3]
        for c in range(count):
            slot = near[0, c]
            if pieces == 1 or (boxes[slot, 0] < k0 and boxes[slot, 1] < k1
                               and boxes[slot, 2] < k2 and boxes[slot, 3] < k3):
                pairs[0, found], pairs[1, found], pairs[2, found] = near[1, c], i, slot
                found += 1
    # stable insertion sort on the rank: the pairs came in piece order, then slot order
    for a in range(1, found):
        rank, piece, slot = pairs[0, a], pairs[1, a], pairs[2, a]
        b = a - 1
        while b >= 0 and pairs[0, b] > rank:
            pairs[0, b + 1], pairs[1, b + 1], pairs[2, b + 1] = \
                pairs[0, b], pairs[1, b], pairs[2, b]
            b -= 1
        pairs[0, b + 1], pairs[1, b + 1], pairs[2, b + 1] = rank, piece, slot
    return pairs[:, :found]


@compiled
def write_slots(boxes: NDArray[np.float64], ranks: NDArray[np.int64], until: NDArray[np.int64],
                slots: NDArray[np.int64], bounds: NDArray[np.float64],
                piece_until: NDArray[np.int64], rank: int) -> None:
    """Store piece i (``bounds[i]``: min x, min y, max x, max y; last sample
    ``piece_until[i]``) of the member ranked ``rank`` in slot ``slots[i]``: its box as
    ``near_slots`` reads it (min x, min y, -max x, -max y)."""
    for i in range(slots.shape[0]):
        slot = slots[i]
        boxes[slot, 0], boxes[slot, 1] = bounds[i, 0], bounds[i, 1]
        boxes[slot, 2], boxes[slot, 3] = -bounds[i, 2], -bounds[i, 3]
        ranks[slot] = rank
        until[slot] = piece_until[i]


@compiled
def clear_slots(boxes: NDArray[np.float64], ranks: NDArray[np.int64],
                slots: NDArray[np.int64]) -> None:
    """Free ``slots``: a box of +inf meets none, rank -1 belongs to nobody."""
    for i in range(slots.shape[0]):
        slot = slots[i]
        for k in range(4):
            boxes[slot, k] = np.inf
        ranks[slot] = -1


@compiled
def footprint_outline(x: float, y: float, c: float, hx: float, hy: float
                      ) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                 NDArray[np.float64], NDArray[np.float64]]:
    """A footprint's corners (ccw from (-hx, -hy), as ``reservation.footprint`` builds
    them), its bounds (1, 4), query keys (1, 4) and key (4,): a standing mover's
    reservation, renewed whenever a motion ends."""
    cos, sin = _quarter_cos_sin(c)
    outline = np.empty((4, 2))
    for i in range(4):
        u = hx if i == 1 or i == 2 else -hx
        v = hy if i >= 2 else -hy
        outline[i, 0] = x + cos * u - sin * v
        outline[i, 1] = y + sin * u + cos * v
    bounds = np.empty((1, 4))
    for axis in range(2):  # outline[:, axis].min() and .max(): the first NaN wins
        low = high = outline[0, axis]
        for i in range(1, 4):
            value = outline[i, axis]
            if math.isnan(low):
                break
            if math.isnan(value):
                low = high = value
                break
            low, high = (value if value < low else low), (value if value > high else high)
        bounds[0, axis], bounds[0, 2 + axis] = low, high
    keys = np.empty((1, 4))
    keys[0, 0], keys[0, 1], keys[0, 2], keys[0, 3] = \
        bounds[0, 2], bounds[0, 3], -bounds[0, 0], -bounds[0, 1]
    return outline, bounds, keys, keys[0].copy()
