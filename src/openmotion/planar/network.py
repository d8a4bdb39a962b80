"""The track network: which track ends meet where, routes, switches (TF5430 §6.2.2).

Tracks are linked end to start (StartFromTrack, EndAtTrack, CloseLoop). Linked ends are one
*vertex*; a vertex where more than two track ends meet is a *switch*. A mover changes track
only from the end of one to the start of another (§6.2.2), so routes run forward through
vertices; on one track a mover may also move backwards.
"""

from __future__ import annotations

import heapq
import itertools
import math
from typing import TYPE_CHECKING

from openmotion.planar.riders import Leg
from openmotion.planar.tolerances import MEET_DISTANCE

if TYPE_CHECKING:
    from openmotion.planar.track import MC_PlanarTrack

START, END = 0, 1
Endpoint = tuple[int, int]  #: (track index, START or END)


class TrackNetwork:
    """The tracks of one planar system and the links between their ends."""

    def __init__(self) -> None:
        self.tracks: list[MC_PlanarTrack] = []
        self._parent: dict[Endpoint, Endpoint] | None = None
        self._positions: tuple[int, ...] | None = None
        self._ends: dict[tuple[Endpoint, int], list[MC_PlanarTrack]] | None = None
        self._switches: dict[int, tuple[Endpoint | None, Endpoint | None]] = {}
        self._successors: dict[int, list[MC_PlanarTrack]] = {}
        self._ways_on: dict[tuple[int, int], list[MC_PlanarTrack]] = {}
        self.version = 0  #: counts ``touch``: what was derived from an older one is stale
        self._ranges: dict[int, tuple[float, float]] = {}  #: automatic collision ranges
        self._hoses: dict[tuple, float] = {}  #: ``_hose_reach``'s answers (kept)

    def add(self, track: MC_PlanarTrack) -> int:
        self.tracks.append(track)
        self.touch()
        return len(self.tracks) - 1

    def touch(self) -> None:
        """Links, a geometry or a track state changed: forget what was derived from them
        (the cycle asks for switches and successors of every rider, so they are cached)."""
        self.version += 1
        self._ends = None
        self._switches.clear()
        self._successors.clear()
        self._ways_on.clear()
        self._ranges.clear()
        self._parent = None
        self._positions = None

    def refresh(self) -> None:
        """Forget the vertices when a part changed position: links across parts hold only
        where the parts meet (§6.2.3). Called once per cycle by the traffic."""
        if self._positions is not None and self._positions != self._part_positions():
            self.touch()

    def placed(self) -> bool:
        """Whether parts can place the tracks (there is a layout of parts): without, every
        track lies where its geometry says."""
        return self._layout() is not None

    def _part_positions(self) -> tuple[int, ...]:
        layout = self._layout()
        return () if layout is None else tuple(p.position_index for p in layout.parts.values())

    def _layout(self) -> object:
        for track in self.tracks:
            environment = track.system.environment()
            return None if environment is None else environment.layout
        return None

    def _vertices(self) -> dict[Endpoint, Endpoint]:
        """Union-find of the links that hold now: on one part always; across parts where
        the parts are in the linked positions, or (unless only those) where the two ends
        meet in one coordinate system."""
        if self._parent is None:
            self._parent = {}
            self._positions = self._part_positions()
            for track in self.tracks:
                for a, b, link in track.links:
                    ta, tb = self.tracks[a[0]], self.tracks[b[0]]
                    if ta.path.empty or tb.path.empty:
                        continue  # cleared since
                    if link is None or _holds(ta, a[1], tb, b[1], link, track):
                        self._union(a, b)
        return self._parent

    # -- links -----------------------------------------------------------------------------------

    def _union(self, a: Endpoint, b: Endpoint) -> None:
        ra, rb = self._root(a), self._root(b)
        if ra != rb:
            self._vertices()[max(ra, rb)] = min(ra, rb)

    def _root(self, e: Endpoint) -> Endpoint:
        parent_of = self._vertices()
        parent = parent_of.get(e, e)
        if parent == e:
            return e
        root = self._root(parent)
        parent_of[e] = root
        return root

    def vertex(self, e: Endpoint) -> Endpoint:
        return self._root(e)

    def _ends_at(self, vertex: Endpoint, side: int) -> list[MC_PlanarTrack]:
        """Tracks with a geometry whose ``side`` (START or END) is at ``vertex``."""
        if self._ends is None:
            ends: dict[tuple[Endpoint, int], list[MC_PlanarTrack]] = {}
            for t in self.tracks:
                if t.length > 0.0:
                    for end in (START, END):
                        ends.setdefault((self._root((t.index, end)), end), []).append(t)
            self._ends = ends
        return self._ends.get((vertex, side), [])

    def successors(self, track: MC_PlanarTrack) -> list[MC_PlanarTrack]:
        """Usable tracks that start where ``track`` ends (a closed loop: itself)."""
        found = self._successors.get(track.index)
        if found is None:
            vertex = self._root((track.index, END))
            found = self._successors[track.index] = [
                t for t in self._ends_at(vertex, START) if t.usable]
        return found

    def way_on(self, track: MC_PlanarTrack, limit: int) -> list[MC_PlanarTrack]:
        """The tracks after ``track`` while the network leaves a single way on (a closed
        track goes on into itself, switch or not), ``limit`` of them at most. The traffic
        looks along it for the rider ahead of the front rider of a track."""
        found = self._ways_on.get((track.index, limit))
        if found is None:
            found, last = [], track
            for _ in range(limit):
                following = self.successors(last)
                if last in following:
                    following = [last]
                if len(following) != 1:
                    break
                last = following[0]
                found.append(last)
            self._ways_on[(track.index, limit)] = found
        return found

    def subsequent(self, track: MC_PlanarTrack) -> list[int]:
        """OIDs of the tracks that start at this track's end vertex (online parameter)."""
        self.refresh()
        vertex = self._root((track.index, END))
        return [t.oid for t in self._ends_at(vertex, START)]

    def previous(self, track: MC_PlanarTrack) -> list[int]:
        """OIDs of the tracks that end at this track's start vertex (online parameter)."""
        self.refresh()
        vertex = self._root((track.index, START))
        return [t.oid for t in self._ends_at(vertex, END)]

    def closed_loop(self, track: MC_PlanarTrack) -> bool:
        self.refresh()
        return self._root((track.index, END)) == self._root((track.index, START))

    def switches(self, track: MC_PlanarTrack) -> tuple[Endpoint | None, Endpoint | None]:
        """The vertex at the start and at the end of ``track`` where it is a switch."""
        found = self._switches.get(track.index)
        if found is None:
            out = []
            for side in (START, END):
                vertex = self._root((track.index, side))
                ends = len(self._ends_at(vertex, START)) + len(self._ends_at(vertex, END))
                out.append(vertex if ends > 2 else None)
            found = self._switches[track.index] = (out[0], out[1])
        return found

    def collision_ranges(self, track: MC_PlanarTrack) -> tuple[float, float]:
        """The track's collision ranges (start, end) [mm]: the manual ones as given, else the
        automatic ones from the tracks that meet it now (§6.2.2, the 2R hose). Which tracks
        meet at a vertex depends on where the parts stand (§6.2.3), so automatic ranges are
        kept only until the network changes."""
        manual = track.manual_collision_ranges
        if manual is not None:
            return manual
        found = self._ranges.get(track.index)
        if found is None:
            found = self._ranges[track.index] = self._automatic_ranges(track)
        return found

    def _automatic_ranges(self, track: MC_PlanarTrack) -> tuple[float, float]:
        """At each end where other tracks meet this one from the same side (they start at
        its start, or end at its end), the arc length within which its centre line stays
        closer than twice the largest mover radius to one of them; 0 where none does."""
        radius = math.hypot(track.max_mover_width, track.max_mover_height) / 2.0
        out = []
        for side in (START, END):
            vertex = self._root((track.index, side))
            out.append(max((self._hose_reach(track, other, side, 2.0 * radius)
                            for other in self._ends_at(vertex, side) if other is not track),
                           default=0.0))
        return out[0], out[1]

    def _hose_reach(self, track: MC_PlanarTrack, other: MC_PlanarTrack, side: int,
                    distance: float) -> float:
        """``TrackPath.hose_reach`` of ``track`` around ``other`` with the two part frames
        where the parts stand now; kept per placement (parts move between a few positions,
        and the ranges are asked again after every change of the network)."""
        mine, theirs = track.placement(), other.placement()
        placement = None if mine == theirs else theirs.inverse().compose(mine)
        key = (track.index, other.index, side, distance, track.length, other.length,
               None if placement is None else tuple(round(v, 9) for v in placement))
        found = self._hoses.get(key)
        if found is None:
            found = self._hoses[key] = track.path.hose_reach(
                other.path, distance, from_end=side == END,
                placement=None if placement is None else (placement.x, placement.y,
                                                          placement.c))
        return found

    # -- routes ----------------------------------------------------------------------------------

    def route(self, track: MC_PlanarTrack, s: float, target: MC_PlanarTrack,
              target_s: float) -> list[Leg] | None:
        """The shortest forward route from ``s`` on ``track`` to ``target_s`` on ``target``
        through other tracks (Dijkstra over the vertices, end to start only): its legs with
        odometer bases, the current track first at base 0. None: not reachable."""
        self.refresh()
        lengths: dict[int, float] = {}  # each track's length asked once (a few µs each)

        def length(t: MC_PlanarTrack) -> float:
            found = lengths.get(t.index)
            if found is None:
                found = lengths[t.index] = t.length
            return found

        counter = itertools.count()
        queue = [(length(track) - s, next(counter), [track], False)]
        best: dict[int, float] = {}
        while queue:
            cost, _, path, arrived = heapq.heappop(queue)
            if arrived:
                legs, base = [], 0.0
                for t in path:
                    legs.append(Leg(t, base))
                    base += length(t)
                return legs
            for nxt in self.successors(path[-1]):
                if nxt is target:
                    heapq.heappush(queue, (cost + target_s, next(counter), [*path, nxt], True))
                reach = cost + length(nxt)
                if reach < best.get(nxt.index, float("inf")):
                    best[nxt.index] = reach
                    heapq.heappush(queue, (reach, next(counter), [*path, nxt], False))
        return None




def _holds(a: MC_PlanarTrack, a_side: int, b: MC_PlanarTrack, b_side: int, link: object,
           owner: MC_PlanarTrack) -> bool:
    """A link across parts holds in the parts' active positions (§6.2.3, §6.2.13)."""
    mine, theirs = owner.part(), (b if owner is a else a).part()
    assert mine is not None and theirs is not None
    this_index, other_index = link.this_index, link.other_index  # type: ignore[attr-defined]
    if link.only:  # type: ignore[attr-defined]
        return (this_index in (0, mine.position_index)
                and other_index in (0, theirs.position_index))
    if mine.active_position.coordinate_system != theirs.active_position.coordinate_system:
        return False
    ax, ay, _, _ = a.frame_at(_at(a, a_side))
    bx, by, _, _ = b.frame_at(_at(b, b_side))
    return abs(float(ax[0] - bx[0])) <= MEET_DISTANCE and abs(float(ay[0] - by[0])) <= MEET_DISTANCE


def _at(track: MC_PlanarTrack, side: int) -> object:
    import numpy as np

    return np.array([0.0 if side == START else track.length])
