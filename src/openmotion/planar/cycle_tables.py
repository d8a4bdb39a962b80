"""The traffic's cycle tables: what its cycle derives from the riders and the network and
keeps while they stay (traffic.py), in one object with one rule for forgetting.

Three lifetimes:

* per cycle: the tracks' placements for the atlas and each rider's room (``new_cycle``);
* until a rider moves otherwise than its proposal (a new origin, a coupling): the brake
  envelopes of the riders' states (``forget_motion``);
* until a rider changes track or route, couples or uncouples, or the network changes: the
  geometry of the riders' tracks, the pair list and what the switch zones derive from
  the routes (``forget_routes``; a new :class:`Geometry` forgets the zones' answers).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.planar.track_atlas import Atlas
from openmotion.planar.traffic_kernels import group_by_track
from openmotion.rail.braking import brake_envelope

if TYPE_CHECKING:
    from openmotion.planar.riders import Rail
    from openmotion.planar.traffic import Traffic
    from openmotion.rail.gap_control import Pairs


@dataclass
class Geometry:
    """Per rider, what changes only with a track transition or a coupling."""

    rows: np.ndarray  #: the table row of its odometer profile
    x_rows: np.ndarray  #: ... and of x, y and c
    y_rows: np.ndarray
    c_rows: np.ndarray
    length: np.ndarray  #: its track's length [mm]
    start_switch: np.ndarray  #: the switch id at its track's start (-1: none)
    end_switch: np.ndarray  #: ... and at its end
    start_range: np.ndarray  #: the collision range at its track's start [mm]
    end_range: np.ndarray  #: ... and at its end


@dataclass
class TrackInfo:
    """The network's answers about one track, kept until its version changes."""

    start_switch: Any  #: the switch at its start (None: none)
    end_switch: Any  #: ... and at its end
    closed: bool  #: it ends where it starts
    way_on: int  #: the index of the one track after it (-1: none or several)


@dataclass
class TrackArrays:
    """``TrackInfo``, length and collision ranges of the network's tracks by track index,
    filled in as riders come onto them and kept until the network's version changes: a
    geometry gathers its riders' from them in numpy (at 1000 riders a Python loop over
    their tracks was a third of a rebuild)."""

    length: np.ndarray  #: [mm]
    start_range: np.ndarray  #: the collision range at its start [mm]
    end_range: np.ndarray  #: ... and at its end
    start_switch: np.ndarray  #: the switch at its start, numbered in the network (-1: none)
    end_switch: np.ndarray  #: ... and at its end
    closed: np.ndarray  #: it ends where it starts
    way_on: np.ndarray  #: the index of the one track after it (-1: none or several)
    known: np.ndarray  #: the entries filled in (the tracks asked for)
    switch_ids: dict[Any, int]  #: the network's switches (vertices) by the numbers given


class CycleTables:
    """What the traffic's cycle keeps between cycles, and when it forgets it."""

    def __init__(self, traffic: Traffic) -> None:
        self.traffic = traffic
        self.geometry: Geometry | None = None  #: (``geometry_now``)
        #: what a geometry takes from the riders' tracks alone (``_on_tracks``)
        self.on_tracks: tuple[np.ndarray, TrackArrays, tuple[np.ndarray, ...]] | None = None
        #: the riders' table rows: odometer, x, y, c (fixed from the coupling on)
        self.table_rows: tuple[np.ndarray, ...] | None = None
        self.track_infos: dict[int, TrackInfo] = {}  #: ``track_info`` of the version ...
        self.track_infos_version = -1  #: ... this
        self.tracks: TrackArrays | None = None  #: ``track_arrays`` of the version ...
        self.tracks_version = -1  #: ... this
        self.network_version = -1  #: the network's version the geometry was built for
        #: per rider, its track's place (the tracks with riders in the order first met)
        self.place = np.empty(0, dtype=np.int64)
        #: the riders grouped by ``place`` and where each group ends
        self.grouped = (np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64))
        #: per rider: its track's index, the next track of its route (-1: none), whether its
        #: track is closed (a seam) and whether its route goes back over that seam (D-147);
        #: the switch-conflict kernels take them in this order
        self.route_arrays: tuple[np.ndarray, ...] = ()
        self.path_next = np.empty(0, dtype=np.int64)  #: next track of each path (or -1)
        self.atlas: Atlas | None = None  #: the curves of the network's tracks (``atlas_now``)
        self.atlas_version = -1  #: the network's version the atlas was checked at
        self.atlas_tables: tuple | None = None  #: the atlas's kernel arguments this cycle
        #: the brake envelopes (lo, hi) of the riders' states
        self.envelopes: tuple[np.ndarray, np.ndarray] | None = None
        self.rooms: tuple[np.ndarray, np.ndarray] | None = None  #: this cycle's rooms
        #: the pair list the neighbours came from, the rider ahead of and behind each
        self.neighbours: tuple[Pairs, np.ndarray, np.ndarray] | None = None
        self.pairs: Pairs | None = None  #: each rider with the one ahead on its path
        #: per rider, where it looks for the rider ahead (``RiderPairs._look``): tracks and
        #: bases, one row each, and how many (-1: to be asked), kept until its route changes
        #: (``forget_look``) or the network's version ...
        self.looks: tuple[np.ndarray, np.ndarray, np.ndarray] = _no_looks(0)
        self.looks_version = -1  #: ... this
        self.merges: dict[tuple, list[list[int]]] = {}  #: riders holding one merge together
        self.merged: tuple[tuple, Pairs] | None = None  #: and the pair list with them
        #: the contested holders of ``SwitchZones.holding``, by the holders
        self.clashes: dict[tuple, Any] = {}
        #: per rider holding a switch with others: the question asked and
        #: ``SwitchZones.clear_stretch``'s answer
        self.stretches: dict[int, tuple[tuple, tuple]] = {}

    # -- forgetting ------------------------------------------------------------------------------

    def renew(self) -> None:
        """New rider arrays (a coupling or uncoupling): nothing derived stays."""
        self.geometry = None
        self.on_tracks = None
        self.table_rows = None
        self.track_infos, self.track_infos_version = {}, -1
        self.looks = _no_looks(0)

    def forget(self) -> None:
        """A rider starts, stops or leaves a profile: envelopes, pairs and geometry go."""
        self.pairs = None
        self.envelopes = None
        self.geometry = None

    def forget_routes(self) -> None:
        """A rider's track or route changed: its pairs and its geometry go."""
        self.pairs = None
        self.geometry = None

    def forget_look(self, k: int) -> None:
        """Rider ``k``'s route changed: where it looks for the rider ahead goes."""
        count = self.looks[2]
        if k < count.size:
            count[k] = -1

    def forget_motion(self) -> None:
        """A rider's odometer has a new origin: envelopes and pair offsets go."""
        self.envelopes = None
        self.pairs = None

    def new_cycle(self) -> None:
        """What holds for one cycle only."""
        self.rooms = None
        self.atlas_tables = None

    # -- the tables ------------------------------------------------------------------------------

    def envelope(self) -> tuple[np.ndarray, np.ndarray]:
        """The brake envelopes (lo, hi) of the riders' states."""
        if self.envelopes is None:
            t = self.traffic
            self.envelopes = brake_envelope(t.p, t.v, t.a, t.brake_deceleration, t.brake_jerk)
        return self.envelopes

    def geometry_now(self) -> Geometry:
        """The riders' :class:`Geometry` (built again after ``forget_routes``)."""
        if self.geometry is None:
            t = self.traffic
            riders = t.riders
            if self.table_rows is None:  # fixed from the coupling on (``Traffic._rebuild``)
                xyc = np.array([r.rows for r in riders], dtype=np.int64).reshape(-1, 3)
                self.table_rows = (np.array([r.row for r in riders], dtype=np.int64),
                                   *(np.ascontiguousarray(x) for x in xyc.T))
            rows, x_rows, y_rows, c_rows = self.table_rows
            track_of, arrays, (start_switch, end_switch, length, start_range, end_range) = \
                self._on_tracks()
            # the next track of each rider's route (-1: none): a rider that passes a switch
            # onto another rider's track keeps its gap to it as a pair (a route that comes
            # round a loop to that track much later does not relate them there); seam: the
            # rider's track is closed, so its riders meet at its switch when one leaves it;
            # back: its route goes back over that seam (it leaves at its start, D-147)
            next_of = t.next_index.copy()
            seam = arrays.closed[track_of]
            back = t.back.copy()
            path_next = np.where(next_of >= 0, next_of, arrays.way_on[track_of])  #: or on
            path_next[back] = -1  # it goes back: no way on from the end of its track
            self.route_arrays = (track_of, next_of, seam, back)
            self.path_next = path_next
            self.stretches, self.clashes, self.merges, self.merged = {}, {}, {}, None
            self.geometry = Geometry(rows, x_rows, y_rows, c_rows, length, start_switch,
                                     end_switch, start_range, end_range)
        return self.geometry

    def _on_tracks(self) -> tuple[np.ndarray, TrackArrays, tuple[np.ndarray, ...]]:
        """The part of a geometry that depends only on the riders' tracks: each rider's
        track index, the network's ``track_arrays`` and per rider its track's switch ids,
        length and collision ranges; sets ``place`` and ``grouped``. Kept while no rider
        changes track and the network's version stays: a new command changes a rider's
        route, not its track, and rebuilt all of it (at 1000 riders the most of a cycle
        that carries one)."""
        t = self.traffic
        kept = self.on_tracks
        if kept is not None and kept[1] is self.tracks \
                and self.tracks_version == t.network.version \
                and kept[1].length.size == len(t.network.tracks) \
                and np.array_equal(kept[0], t.track_index):
            return kept
        # what belongs to a track, from the network's per-track arrays (``track_arrays``)
        track_of = t.track_index.copy()
        mine, ranked, ends = group_by_track(track_of)  # mine: each rider's track's place
        on = track_of[ranked[ends - 1]]  # the tracks with riders, in place order
        arrays = self.track_arrays(on)
        start_switch, end_switch = _switch_ids(arrays.start_switch, arrays.end_switch, on, mine)
        self.place, self.grouped = mine, (ranked, ends)
        self.on_tracks = (track_of, arrays, (start_switch, end_switch, arrays.length[track_of],
                                             arrays.start_range[track_of],
                                             arrays.end_range[track_of]))
        return self.on_tracks

    def looks_for(self, riders: np.ndarray, look: Callable[[int], tuple[list[int], list[float]]]
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The rows of ``looks`` with those of ``riders`` filled in (``look``: a rider's
        tracks and bases, asked for those not known), kept until a rider's route changes
        (``forget_look``) or the network's version does."""
        n = self.traffic.p.size
        version = self.traffic.network.version
        if self.looks[2].size != n or self.looks_version != version:
            self.looks, self.looks_version = _no_looks(n), version
        tracks, bases, count = self.looks
        for k in riders[count[riders] < 0].tolist():
            ids, at = look(k)
            if len(ids) > tracks.shape[1]:  # a longer route than any before: wider rows
                wider = max(len(ids), 2 * tracks.shape[1])
                tracks = np.pad(tracks, ((0, 0), (0, wider - tracks.shape[1])))
                bases = np.pad(bases, ((0, 0), (0, wider - bases.shape[1])))
                self.looks = (tracks, bases, count)
            tracks[k, :len(ids)], bases[k, :len(ids)] = ids, at
            count[k] = len(ids)
        return self.looks

    def track_arrays(self, on: np.ndarray) -> TrackArrays:
        """``track_info``, length and collision ranges of the tracks ``on`` (indices) and of
        those asked before, by track index (the switches numbered in the order met), kept
        until the network's version changes."""
        network = self.traffic.network
        count = len(network.tracks)
        arrays = self.tracks
        if arrays is None or self.tracks_version != network.version \
                or arrays.length.size != count:
            arrays = self.tracks = TrackArrays(
                np.empty(count), np.empty(count), np.empty(count),
                np.full(count, -1, dtype=np.int64), np.full(count, -1, dtype=np.int64),
                np.zeros(count, dtype=bool), np.full(count, -1, dtype=np.int64),
                np.zeros(count, dtype=bool), {})
            self.tracks_version = network.version
        ids = arrays.switch_ids
        for i in on[~arrays.known[on]].tolist():
            track = network.tracks[i]
            arrays.length[i] = track.length
            info = self.track_info(track)
            arrays.closed[i], arrays.way_on[i] = info.closed, info.way_on
            if info.start_switch is not None:
                arrays.start_switch[i] = ids.setdefault(info.start_switch, len(ids))
            if info.end_switch is not None:
                arrays.end_switch[i] = ids.setdefault(info.end_switch, len(ids))
            arrays.start_range[i], arrays.end_range[i] = network.collision_ranges(track)
            arrays.known[i] = True
        return arrays

    def track_info(self, track: Rail) -> TrackInfo:
        """The switches at the start and at the end of ``track``, whether it is closed, and
        the one way on after it: the network's answers, kept until its version changes."""
        network = self.traffic.network
        if self.track_infos_version != network.version:
            self.track_infos, self.track_infos_version = {}, network.version
        found = self.track_infos.get(track.index)
        if found is None:
            start, end = network.switches(track)
            following = network.successors(track)
            if track in following:
                following = [track]
            found = self.track_infos[track.index] = TrackInfo(
                start, end, network.closed_loop(track),
                following[0].index if len(following) == 1 else -1)
        return found

    def atlas_now(self) -> Atlas:
        """The atlas of the network's tracks (atlas id: the track's index), built again when
        a track or a table changed (a geometry changes only with the network's version)."""
        network = self.traffic.network
        if self.atlas is None or self.atlas_version != network.version:
            if self.atlas is None or not self.atlas.matches(network.tracks):
                self.atlas = Atlas(network.tracks)
            self.atlas_version = network.version
        return self.atlas

    def placed_tables(self) -> tuple:
        """The atlas's kernel arguments with the tracks' placements of this cycle (parts
        change position only between cycles; ``new_cycle`` forgets them)."""
        if self.atlas_tables is None:
            self.atlas_tables = self.atlas_now().tables(self.traffic.network.placed())
        return self.atlas_tables


def _switch_ids(start_switch: np.ndarray, end_switch: np.ndarray, on: np.ndarray,
                mine: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The switch ids at the start and at the end of each rider's track: the network's
    switch numbers (``TrackArrays``) renumbered in the order met along ``on`` (the tracks
    with riders, in place order; each one's start before its end), as the riders' tables
    number them; ``mine``: each rider's place."""
    seq = np.empty(2 * on.size, dtype=np.int64)
    seq[0::2], seq[1::2] = start_switch[on], end_switch[on]
    present = seq >= 0
    keys, first = np.unique(seq[present], return_index=True)
    top = max(int(start_switch.max(initial=-1)), int(end_switch.max(initial=-1)))
    renumber = np.full(top + 2, -1, dtype=np.int64)  # the last stays -1: for seq's -1
    renumber[keys[np.argsort(first, kind="stable")]] = np.arange(keys.size)
    ids = renumber[seq]
    return ids[0::2][mine], ids[1::2][mine]


def _no_looks(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``CycleTables.looks`` of ``n`` riders, none known yet."""
    return (np.zeros((n, 16), dtype=np.int64), np.zeros((n, 16)),
            np.full(n, -1, dtype=np.int64))
