"""Pairs of riders on tracks: each rider with the rider ahead of it on its path, the gap it
keeps to it, and the gap filter over those pairs (traffic.py).

Pairs are measured along the path, centre to centre: the rider ahead may be on a later track
of the route, and its position is shifted into the follower's odometer by the difference of
the two bases. On a route back over the seam of a closed track (D-147) the rider going back
is the leader of the rider that comes first behind it along its legs, so that rider keeps
the larger gap to it before it crosses the seam. Riders that hold a merge together from the
ends of their tracks are paired as if on the way after it already (§6.1.9).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from openmotion.planar.riders import IDLE, Rider, ahead_legs
from openmotion.planar.traffic_kernels import (
    gap_filter,
    neighbours,
    pair_gaps,
    riders_ahead,
    rooms,
    track_pairs,
)
from openmotion.rail.gap_control import TOLERANCE, Pairs

if TYPE_CHECKING:
    from openmotion.planar.traffic import Traffic

_HORIZON_TRACKS = 8  #: a path ahead is searched this many tracks beyond the route at most


class RiderPairs:
    """The pairs of the traffic's riders and what gap control asks of them."""

    def __init__(self, traffic: Traffic) -> None:
        self.traffic = traffic
        self.tables = traffic.cycle_tables

    def pair_list(self, going: np.ndarray) -> Pairs:
        """Each rider with the rider ahead on its path (cached until a rider changes track or
        route): on its track the next one by arc length; the front rider of a track looks
        along its route (then along the one way on, if the network leaves one) for the first
        rider of each track. Their gaps: ``pair_gaps`` with ``going``."""
        tables = self.tables
        if tables.pairs is None:
            t = self.traffic
            tables.geometry_now()
            ranked, succ, pred, offset, heads, tails = track_pairs(
                t.p - t.base, *tables.grouped, tables.place, t.base)
            looks = tables.looks_for(ranked[tails - 1], self._look)
            fronts, leaders, shifts = riders_ahead(ranked, heads, tails, t.track_index,
                                                   len(t.network.tracks), t.base, *looks)
            if t.back.any():
                fronts, leaders, shifts = fronts.tolist(), leaders.tolist(), shifts.tolist()
                self._pairs_back(ranked.tolist(), heads.tolist(), tails.tolist(), fronts,
                                 leaders, shifts)
            sa = np.concatenate((succ, np.array(fronts, dtype=np.int64)))
            pa = np.concatenate((pred, np.array(leaders, dtype=np.int64)))
            tables.pairs = Pairs(sa, pa, np.concatenate((offset, np.array(shifts, dtype=float))),
                                 t.gap[sa], np.zeros(sa.size, dtype=bool), True)
        self.pair_gaps(tables.pairs, going)
        return tables.pairs

    def pair_gaps(self, pairs: Pairs, going: np.ndarray) -> None:
        """Each keeps its own gap to the mover in front of it in its direction of travel
        (§6.1.9): a leader that moves back onto its follower keeps the larger of the two
        gaps. Back: a MoveOnTrack behind it, or ``going`` (``traffic_kernels.going_back``,
        of its state and, once they are known, of this cycle's proposals: a geared slave held
        at rest by the gap goes back whenever its master still does)."""
        t = self.traffic
        pairs.gap = pair_gaps(pairs.succ, pairs.pred, t.mode, IDLE, t.target, t.p, going, t.gap)

    def _look(self, k: int) -> tuple[list[int], list[float]]:
        """Where rider ``k`` looks for the rider ahead when it is the front rider of its
        track: the tracks after its own along its route, then along the one way on (if the
        network leaves one; ``_HORIZON_TRACKS`` at most), each with its base on ``k``'s
        odometer. A route back has no legs ahead. Kept until its route changes
        (``CycleTables.looks_for``)."""
        legs = ahead_legs(self.traffic.riders[k].route)
        tracks = [leg.track.index for leg in legs[1:]]
        bases = [leg.base for leg in legs[1:]]
        last = legs[-1].track
        base = legs[-1].base + last.length
        for track in self.traffic.network.way_on(last, _HORIZON_TRACKS):
            tracks.append(track.index)
            bases.append(base)
            base += track.length
        return tracks, bases

    def _pairs_back(self, order: list[int], heads: list[int], tails: list[int],
                    fronts: list[int], leaders: list[int], shifts: list[float]) -> None:
        """The pairs of the riders on a route back over a loop's seam (D-147), added to
        ``fronts``, ``leaders`` and ``shifts``: the first rider of a track (by arc length)
        whose route goes back leads the first rider behind it along its legs. That one may be
        paired with it already (its own way runs on round the loop), or not (it leaves the
        loop at the seam): then it keeps the gap only through this pair, before the rider
        going back crosses the seam towards it."""
        t = self.traffic
        last: dict[int, list[int]] = {}  #: per track, its last two riders, the last first
        for head, tail in zip(heads, tails, strict=True):
            last[t.riders[order[head]].track.index] = order[max(head, tail - 2):tail][::-1]
        known = set(zip(fronts, leaders, strict=True))
        for head in heads:
            k = order[head]
            if not t.back[k]:
                continue
            behind = self._behind(t.riders[k], last)
            if behind is not None and (behind[0], k) not in known:
                fronts.append(behind[0])
                leaders.append(k)
                shifts.append(behind[1])

    def _behind(self, m: Rider, last: dict[int, list[int]]) -> tuple[int, float] | None:
        """The first rider behind ``m`` along its route back (on its legs after the first;
        the route ends at its target, so it looks no further), and the shift of ``m``'s
        odometer into that rider's. ``last``: the last two riders of each track."""
        for leg in m.route[1:]:
            for k in last.get(leg.track.index, ()):
                if k != m.slot:
                    return k, float(self.traffic.base[k]) - leg.base
        return None

    def merging(self, pairs: Pairs, going: np.ndarray) -> Pairs:
        """``pairs`` and, for riders that hold a merge together from the ends of their
        tracks with one way on after it, a pair as if they were on that way already (the
        one nearer the switch ahead, unless it goes back): once the first passes the switch
        they are one, and the gap must be there then (§6.1.9)."""
        held = self.traffic.zones.held
        contested = held.contested
        if not contested:
            return pairs
        t, tables = self.traffic, self.tables
        holders, at_end, switch = held.riders, held.at_end, held.switch
        key = (holders.tobytes(), at_end.tobytes())
        groups = tables.merges.get(key)
        if groups is None:  # the same riders hold for many cycles: grouped once
            path_next = tables.path_next
            found: dict[tuple[int, int], list[int]] = {}
            for i in np.flatnonzero(at_end).tolist():
                r = int(holders[i])
                if r in contested and path_next[r] >= 0:
                    found.setdefault((int(switch[i]), int(path_next[r])), []).append(r)
            groups = tables.merges[key] = [g for g in found.values() if len(g) > 1]
        if not groups:
            return pairs
        exit_at = t.base + tables.geometry_now().length  # the odometer of a track's end switch
        ahead = (exit_at - t.p).tolist()
        # a leader going back, away from the switch, is free of it: only the footprints
        back = ((t.mode != IDLE) & ((t.target < t.p) | going)).tolist()
        succ, pred = [], []
        for riders in groups:
            riders = sorted(riders, key=lambda r: (ahead[r], r))
            for f, lead in zip(riders[1:], riders[:-1], strict=True):
                if not back[lead]:
                    succ.append(f)
                    pred.append(lead)
        if not succ:
            return pairs
        order = (id(pairs), tuple(succ), tuple(pred))
        if tables.merged is None or tables.merged[0] != order:
            sa, pa = np.array(succ, dtype=np.int64), np.array(pred, dtype=np.int64)
            tables.merged = (order, Pairs(
                np.concatenate((pairs.succ, sa)), np.concatenate((pairs.pred, pa)),
                np.concatenate((pairs.offset, exit_at[sa] - exit_at[pa])),
                np.concatenate((pairs.gap, t.gap[sa])),
                np.zeros(pairs.succ.size + sa.size, dtype=bool), True))
        merged = tables.merged[1]
        self.pair_gaps(merged, going)
        return merged

    def neighbours(self, pairs: Pairs) -> tuple[np.ndarray, np.ndarray]:
        """The rider ahead of and behind each rider on its path (-1: none); kept with the
        pair list they come from."""
        tables = self.tables
        if tables.neighbours is None or tables.neighbours[0] is not pairs:
            tables.neighbours = (pairs, *neighbours(self.traffic.p.size, pairs.succ,
                                                    pairs.pred))
        return tables.neighbours[1], tables.neighbours[2]

    def room(self, pairs: Pairs) -> tuple[np.ndarray, np.ndarray]:
        """Where each rider may stop given its neighbours' brake envelopes now (once per
        cycle: ``CycleTables.new_cycle`` forgets it)."""
        tables = self.tables
        if tables.rooms is None:
            lo, hi = tables.envelope()
            tables.rooms = rooms(self.traffic.p.size, pairs.succ, pairs.pred, pairs.offset,
                                 pairs.gap, lo, hi, *self.traffic.zones.stop_lines)
        return tables.rooms

    def filter(self, proposal: list[np.ndarray], pairs: Pairs,
               known: tuple[np.ndarray, np.ndarray, np.ndarray]
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The CA group's gap filter (``filter_steps``) on ``proposal``, compiled for the
        traffic's pairs (``traffic_kernels.gap_filter``): the riders that brake instead and
        the envelopes of ``proposal``."""
        t = self.traffic
        lo_now, hi_now = self.tables.envelope()
        return gap_filter(t.p, t.v, t.a, lo_now, hi_now, *proposal, t.cycle_time,
                          t.brake_deceleration, t.brake_jerk, pairs.succ, pairs.pred,
                          pairs.offset, pairs.gap, *known)

    def no_turning_back(self, pairs: Pairs, turning: np.ndarray, proposal: list[np.ndarray],
                        lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """A leader closer to its follower than their gap does not start to go back: one
        whose next step would (``turning``: ``going_back`` now, not before) brakes instead,
        and its brake from a state that does not turn round never does (§6.1.9). The filter
        lets such a step through while it keeps the envelope where it was, but the motion
        inside the envelope would still take the leader back towards a follower it is too
        close to already. Writes the brakes into ``proposal``, ``lo`` and ``hi``; returns the
        riders."""
        if not turning.any() or not pairs.succ.size:
            return np.empty(0, dtype=np.int64)
        s, k = pairs.succ, pairs.pred
        unsafe = hi[s] + pairs.gap > lo[k] + pairs.offset + TOLERANCE
        slots = np.unique(k[unsafe & turning[k]])
        self.traffic.brake(slots, proposal, lo, hi)
        return slots
