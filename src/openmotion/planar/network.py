"""The track network: which track ends meet where, routes, switches (TF5430 §6.2.2).

Tracks are linked end to start (StartFromTrack, EndAtTrack, CloseLoop). Linked ends are one
*vertex*; a vertex where more than two track ends meet is a *switch*. A mover changes track
only from the end of one to the start of another (§6.2.2), so routes run forward through
vertices; on one track a mover may also move backwards.
"""

from __future__ import annotations

import heapq
import itertools
from typing import TYPE_CHECKING

from openmotion.planar.traffic import Leg

if TYPE_CHECKING:
    from openmotion.planar.track import MC_PlanarTrack

START, END = 0, 1
Endpoint = tuple[int, int]  #: (track index, START or END)


class TrackNetwork:
    """The tracks of one planar system and the links between their ends."""

    def __init__(self) -> None:
        self.tracks: list[MC_PlanarTrack] = []
        self._parent: dict[Endpoint, Endpoint] = {}

    def add(self, track: MC_PlanarTrack) -> int:
        self.tracks.append(track)
        return len(self.tracks) - 1

    # -- links -----------------------------------------------------------------------------------

    def link(self, a: Endpoint, b: Endpoint) -> None:
        """``a`` and ``b`` are one vertex from now on."""
        ra, rb = self._root(a), self._root(b)
        if ra != rb:
            self._parent[max(ra, rb)] = min(ra, rb)

    def unlink(self, index: int) -> None:
        """Forget every link of track ``index`` (Clear): the vertices are rebuilt from the
        links of the other tracks, which the tracks keep themselves."""
        self._parent.clear()
        for track in self.tracks:
            if track.index != index:
                for a, b in track._links:
                    if index not in (a[0], b[0]):
                        self.link(a, b)

    def _root(self, e: Endpoint) -> Endpoint:
        parent = self._parent.get(e, e)
        if parent == e:
            return e
        root = self._root(parent)
        self._parent[e] = root
        return root

    def vertex(self, e: Endpoint) -> Endpoint:
        return self._root(e)

    def _ends_at(self, vertex: Endpoint, side: int) -> list[MC_PlanarTrack]:
        return [t for t in self.tracks if t.length > 0.0 and self._root((t.index, side)) == vertex]

    def successors(self, track: MC_PlanarTrack) -> list[MC_PlanarTrack]:
        """Usable tracks that start where ``track`` ends (a closed loop: itself)."""
        vertex = self._root((track.index, END))
        return [t for t in self._ends_at(vertex, START) if t.usable]

    def subsequent(self, track: MC_PlanarTrack) -> list[int]:
        """OIDs of the tracks that start at this track's end vertex (online parameter)."""
        vertex = self._root((track.index, END))
        return [t.oid for t in self._ends_at(vertex, START)]

    def previous(self, track: MC_PlanarTrack) -> list[int]:
        """OIDs of the tracks that end at this track's start vertex (online parameter)."""
        vertex = self._root((track.index, START))
        return [t.oid for t in self._ends_at(vertex, END)]

    def closed_loop(self, track: MC_PlanarTrack) -> bool:
        return self._root((track.index, END)) == self._root((track.index, START))

    def switches(self, track: MC_PlanarTrack) -> tuple[Endpoint | None, Endpoint | None]:
        """The vertex at the start and at the end of ``track`` where it is a switch."""
        out = []
        for side in (START, END):
            vertex = self._root((track.index, side))
            ends = len(self._ends_at(vertex, START)) + len(self._ends_at(vertex, END))
            out.append(vertex if ends > 2 else None)
        return out[0], out[1]

    def collision_ranges(self, track: MC_PlanarTrack) -> tuple[float, float]:
        return track.collision_ranges

    # -- routes ----------------------------------------------------------------------------------

    def route(self, track: MC_PlanarTrack, s: float, target: MC_PlanarTrack,
              target_s: float) -> list[Leg] | None:
        """The shortest forward route from ``s`` on ``track`` to ``target_s`` on ``target``
        through other tracks (Dijkstra over the vertices, end to start only): its legs with
        odometer bases, the current track first at base 0. None: not reachable."""
        counter = itertools.count()
        queue = [(track.length - s, next(counter), [track], False)]
        best: dict[int, float] = {}
        while queue:
            cost, _, path, arrived = heapq.heappop(queue)
            if arrived:
                legs, base = [], 0.0
                for t in path:
                    legs.append(Leg(t, base))
                    base += t.length
                return legs
            for nxt in self.successors(path[-1]):
                if nxt is target:
                    heapq.heappush(queue, (cost + target_s, next(counter), [*path, nxt], True))
                reach = cost + nxt.length
                if reach < best.get(nxt.index, float("inf")):
                    best[nxt.index] = reach
                    heapq.heappush(queue, (reach, next(counter), [*path, nxt], False))
        return None
