"""Every track's curve in one flat table: the frames of all riders in one compiled pass.

The traffic writes x, y and c of every moving rider each cycle. One lookup per track
(``MC_PlanarTrack.frame_at``) costs a call overhead of a few µs each, which on a network of
ten tracks was most of the setpoint stage. The atlas concatenates the flat tables of the
tracks (``geometry.track_kernels.TrackTable``) and evaluates each rider on its own track in
one pass, with the same formulas in the same order as ``track_kernels.frames`` and the part
placement of ``MC_PlanarTrack.frame_at``, so the frames are the same bit for bit.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from openmotion.core.compiled import compiled, search_right
from openmotion.core.errors import ConfigError
from openmotion.geometry.track_elements import TABLE_PIECES
from openmotion.geometry.track_kernels import (
    ARC,
    LINE,
    _first,
    _parameter,
    _point,
    _second,
    _wrapped,
)
from openmotion.planar.frames import Pose, cos_sin

_ORIGIN = Pose()  #: the placement of a track without a part (MC_PlanarTrack.frame_at)


class Atlas:
    """The flat tables of ``tracks`` (rails with a ``path``) side by side; a track's place
    in ``tracks`` is its atlas id. Built again when a table changes (``matches``)."""

    def __init__(self, tracks: list[Any]) -> None:
        self.tracks = list(tracks)
        #: kept: ``matches`` compares identity; None for a track without a geometry
        self.sources = [None if t.path.empty else t.path.table for t in tracks]
        count = len(tracks)
        self.start_at = np.zeros(count, dtype=np.int64)  #: first entry of a track in starts
        self.piece_at = np.zeros(count, dtype=np.int64)  #: ... in kinds and rows
        self.transition_at = np.zeros(count, dtype=np.int64)  #: ... in the transition arrays
        self.closed = np.zeros(count, dtype=np.bool_)
        starts, pieces, transitions = 0, 0, 0
        present = [t for t in self.sources if t is not None]
        #: [1/mm] the largest |curvature| of each track (0 without a geometry)
        self.max_curvature = np.array([0.0 if t.path.empty else t.path.max_curvature
                                       for t in tracks])
        for i, t in enumerate(self.sources):
            self.start_at[i], self.piece_at[i], self.transition_at[i] = starts, pieces, transitions
            if t is not None:
                self.closed[i] = t.closed
                starts += t.starts.size
                pieces += t.kinds.size
                transitions += t.origins.shape[0]
        width = TABLE_PIECES + 1

        def joined(name: str, shape: tuple[int, ...]) -> NDArray[np.float64]:
            parts = [getattr(t, name).reshape(-1, *shape) for t in present]
            return np.ascontiguousarray(np.concatenate([np.zeros((0, *shape)), *parts]))

        self.starts = np.concatenate([np.zeros(0), *(t.starts for t in present)])
        self.kinds = np.concatenate([np.zeros(0, dtype=np.int64),
                                     *(t.kinds for t in present)]).astype(np.int64)
        self.rows = joined("rows", (6,))
        self.origins = joined("origins", (2,))
        self.coefficients = joined("coefficients", (6, 2))
        self.first = joined("first", (5, 2))
        self.second = joined("second", (4, 2))
        self.lookup = joined("tables", (width,))
        self.speeds = joined("speeds", (width,))
        self._unplaced: tuple | None = None  #: ``tables`` where no part places a track

    def matches(self, tracks: list[Any]) -> bool:
        """Whether the atlas holds exactly these tracks with their current tables."""
        return len(tracks) == len(self.tracks) and all(
            a is b and (None if a.path.empty else a.path.table) is t
            for a, b, t in zip(tracks, self.tracks, self.sources, strict=True))

    def frames(self, ids: NDArray[np.int64], s: NDArray[np.float64], clamp: bool = False
               ) -> tuple[NDArray[np.float64], ...]:
        """x, y [mm], heading [rad] and curvature [1/mm] at the arc lengths ``s`` on the
        tracks ``ids``, in the coordinate system of each track's part (``frame_at``);
        ``clamp``: each arc length clamped to its track first (as numpy.clip)."""
        out = frames_on(ids, np.ascontiguousarray(s, dtype=float), clamp, self.tables())
        return out[0], out[1], out[2], out[3]

    def along(self, ids: NDArray[np.int64], bases: NDArray[np.float64],
              q: NDArray[np.float64], tables: tuple | None = None
              ) -> tuple[NDArray[np.float64], ...]:
        """x, y [mm] and heading [rad] at the odometer positions ``q`` of a route whose legs
        are the tracks ``ids`` starting at the odometer ``bases`` (each position on its leg,
        clamped to the route), and the largest |curvature| of the legs they fall on.
        ``tables``: ``tables()`` when the caller has them."""
        out, curvature = _along(ids, bases, q, self.max_curvature,
                                self.tables() if tables is None else tables)
        return out[0], out[1], out[2], curvature

    def along_routes(self, ids: NDArray[np.int64], bases: NDArray[np.float64],
                     route_at: NDArray[np.int64], q: NDArray[np.float64],
                     q_at: NDArray[np.int64], tables: tuple
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``along`` for several routes at once: route r has the legs ``ids`` and ``bases``
        from ``route_at[r]`` to ``route_at[r + 1]`` and the positions ``q`` from ``q_at[r]``
        to ``q_at[r + 1]``. Returns x, y, heading (3, len(q)) and each route's curvature."""
        return _along_routes(ids, bases, route_at, q, q_at, self.max_curvature, tables)

    def tables(self, parts: bool = True) -> tuple:
        """The kernels' arguments: the flat tables and each track's placement now (``parts``:
        whether there are parts that can place a track at all; without, every track lies
        where its geometry says and nothing is asked)."""
        count = len(self.tracks)
        placed = np.zeros(count, dtype=np.bool_)
        pose = np.zeros((count, 5))
        if not parts:
            if self._unplaced is None:
                self._unplaced = self._arguments(placed, pose)
            return self._unplaced
        for i, track in enumerate(self.tracks):
            place = track.placement()
            if place != _ORIGIN:
                cos, sin = cos_sin(place.c)
                placed[i] = True
                pose[i] = place.x, place.y, cos, sin, math.radians(place.c)
        return self._arguments(placed, pose)

    def _arguments(self, placed: NDArray[np.bool_], pose: NDArray[np.float64]) -> tuple:
        return (self.start_at, self.piece_at, self.transition_at, self.closed, placed, pose,
                self.starts, self.kinds, self.rows, self.origins, self.coefficients, self.first,
                self.second, self.lookup, self.speeds)


@compiled
def frames_on(ids: NDArray[np.int64], s: NDArray[np.float64], clamp: bool, tables: tuple
               ) -> NDArray[np.float64]:
    """track_kernels.frames of each arc length on its own track, then the track's placement
    (MC_PlanarTrack.frame_at): (4, n) rows x, y, heading, curvature. ``tables``: the
    atlas's arrays (``Atlas.tables``). One loop body: a helper taking the arrays would
    count references to each of them for every point, ten times the arithmetic."""
    (start_at, piece_at, transition_at, closed, placed, pose, starts, kinds, rows, origins,
     coefficients, first, second, lookup, speeds) = tables
    out = np.empty((4, s.size))
    for i in range(s.size):
        t = ids[i]
        p0 = piece_at[t]
        m = (kinds.size if t + 1 == piece_at.size else piece_at[t + 1]) - p0
        a = start_at[t]  # the track's starts are starts[a:a + m + 1]
        here = s[i]
        if clamp:  # numpy.clip to [0, length] (MC_PlanarTrack.length: 0 without a geometry)
            here = min(max(here, 0.0), starts[a + m] if m else 0.0)
        if not math.isfinite(here):
            raise ConfigError("arc lengths must be finite numbers [mm]")
        if m == 0:
            raise ConfigError("the track has no geometry yet")
        si = _wrapped(here, starts[a + m], closed[t])
        k = 0  # track_kernels._piece: the piece holding si (the last one for si = length)
        hi = m - 1
        while k < hi:
            mid = (k + hi + 1) // 2
            if starts[a + mid] <= si:
                k = mid
            else:
                hi = mid - 1
        local = min(si - starts[a + k], starts[a + k + 1] - starts[a + k])
        r = p0 + k
        if kinds[r] == LINE:
            x = rows[r, 0] + local * rows[r, 2]
            y = rows[r, 1] + local * rows[r, 3]
            heading = rows[r, 4]
            curvature = 0.0
        elif kinds[r] == ARC:
            radius, sense = rows[r, 2], rows[r, 4]
            phi = rows[r, 3] + sense * local / radius
            x = rows[r, 0] + radius * math.cos(phi)
            y = rows[r, 1] + radius * math.sin(phi)
            turned = phi + sense * 0.5 * math.pi
            heading = math.atan2(math.sin(turned), math.cos(turned))
            curvature = sense / radius
        else:
            j = int(rows[r, 0]) + transition_at[t]
            u = _parameter(first, second, lookup, speeds, j, local)
            bx, by = _point(coefficients, j, u)
            dx, dy = _first(first, j, u)
            ddx, ddy = _second(second, j, u)
            speed2 = dx * dx + dy * dy
            x = origins[j, 0] + bx
            y = origins[j, 1] + by
            heading = math.atan2(dy, dx)
            curvature = (dx * ddy - dy * ddx) / (speed2 * math.sqrt(speed2))
        if placed[t]:
            px, py, cos, sin, turn = pose[t, 0], pose[t, 1], pose[t, 2], pose[t, 3], pose[t, 4]
            x, y = px + cos * x - sin * y, py + sin * x + cos * y
            heading = heading + turn
        out[0, i], out[1, i], out[2, i], out[3, i] = x, y, heading, curvature
    return out


@compiled
def _along(ids: NDArray[np.int64], bases: NDArray[np.float64], q: NDArray[np.float64],
           max_curvature: NDArray[np.float64], tables: tuple
           ) -> tuple[NDArray[np.float64], float]:
    """``Atlas.along``: the leg of each odometer position is the last one starting at or
    before it (the first for positions before the route), its arc length there clamped to
    the leg's track."""
    track, s = np.empty(q.size, dtype=np.int64), np.empty(q.size)
    curvature = 0.0
    for i in range(q.size):
        leg = search_right(bases, q[i]) - 1
        leg = min(max(leg, 0), bases.size - 1)
        track[i], s[i] = ids[leg], q[i] - bases[leg]
        curvature = max(curvature, max_curvature[ids[leg]])
    return frames_on(track, s, True, tables)[:3], curvature


@compiled
def _along_routes(ids: NDArray[np.int64], bases: NDArray[np.float64],
                  route_at: NDArray[np.int64], q: NDArray[np.float64], q_at: NDArray[np.int64],
                  max_curvature: NDArray[np.float64], tables: tuple
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``Atlas.along_routes``: ``_along`` for each route's positions."""
    track, s = np.empty(q.size, dtype=np.int64), np.empty(q.size)
    curvature = np.zeros(route_at.size - 1)
    for r in range(route_at.size - 1):
        legs, offsets = ids[route_at[r]:route_at[r + 1]], bases[route_at[r]:route_at[r + 1]]
        for i in range(q_at[r], q_at[r + 1]):
            leg = search_right(offsets, q[i]) - 1
            leg = min(max(leg, 0), offsets.size - 1)
            track[i], s[i] = legs[leg], q[i] - offsets[leg]
            curvature[r] = max(curvature[r], max_curvature[legs[leg]])
    return frames_on(track, s, True, tables)[:3], curvature
