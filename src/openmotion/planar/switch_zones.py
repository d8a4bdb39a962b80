"""Switch zones (§6.2.2, Collision Ranges): who holds a switch, who must stop short of it,
and how riders that hold one switch together keep their footprints apart (traffic.py).

Near a vertex where more than two track ends meet, movers on different tracks may meet
although neither is on the other's path. Each rider has a *zone* at each switch of its
track: the stretch within max(collision range, gap) of the switch. A rider whose brake
envelope (where it could still stop) reaches into its zone *holds* the switch. A rider that
wants to enter its zone while another rider holds the same switch from a track that is not
on its path ahead is stopped at its zone boundary: the last safe stop point (§6.2.2, the two
examples where mover 2 waits at the start of the collision range or one gap before the end
of its track). Riders that hold one switch from conflicting tracks at once (they joined
there, or a new route made them conflict) keep their footprints apart. A rider that passes
a switch backwards on a route back over a loop's seam (D-147) meets the riders that would
pass onto its track at its start there rather than follow them. docs/planar-tracks.md has
the argument and the choices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import accumulate
from typing import TYPE_CHECKING

import numpy as np

from openmotion.planar.riders import IDLE, ascending
from openmotion.planar.traffic_kernels import (
    conflicts,
    contested_pairs,
    out_of_bounds,
    stretch_hits,
    stretch_samples,
    zone_entries,
    zone_holders,
    zone_lines,
)
from openmotion.rail.gap_control import TOLERANCE

if TYPE_CHECKING:
    from openmotion.planar.traffic import Traffic

#: [mm] riders this close to a zone get its stop line (held riders plan their goal with it);
#: further away they cannot reach the zone within a cycle
_ZONE_LOOKAHEAD = 1000.0
_CLEAR_STEP = 2.0  #: [mm] footprints of riders holding one switch together are sampled so
_CLEAR_SAMPLES = 32  #: ... this many steps on each side of an envelope (the horizon)
_CLASH_MEMORY = 64  #: sets of contested holders (``SwitchZones.holding``) kept at most

#: Stop lines: the riders kept out of a switch zone and the odometer bounds of each (riders,
#: lows, highs), as the rooms kernel takes them
StopLines = tuple[np.ndarray, np.ndarray, np.ndarray]


@dataclass
class Holding:
    """Who holds which switch at the start of a cycle (``SwitchZones.holding``)."""

    end_line: np.ndarray  #: per rider: where its end zone starts on the odometer
    start_line: np.ndarray  #: ... and where its start zone ends
    in_end: np.ndarray  #: per rider: its envelope reaches into its end zone
    in_start: np.ndarray  #: ... into its start zone
    riders: np.ndarray  #: the holders, those at the end of their track first
    at_end: np.ndarray  #: per holder: it holds the switch at the end of its track
    switch: np.ndarray  #: per holder: the switch id
    #: the holders that hold a switch together with riders of conflicting tracks, each with
    #: those riders
    contested: dict[int, set[int]]

    @classmethod
    def nobody(cls) -> Holding:
        """Nobody holds a switch (before the first cycle)."""
        ints, floats, bools = (np.empty(0, dtype=np.int64), np.empty(0),
                               np.empty(0, dtype=bool))
        return cls(floats, floats, bools, bools, ints, bools, ints, {})


class SwitchZones:
    """The switch rule over the traffic's riders, and the stop lines it leaves."""

    def __init__(self, traffic: Traffic) -> None:
        self.traffic = traffic
        self.tables = traffic.cycle_tables
        #: odometer bounds of the riders kept out of a switch zone last cycle
        self.stop_lines: StopLines = no_lines()
        self.widening = False  #: a rider's zones may widen to its gap (``_widen``)
        self.held = Holding.nobody()  #: who holds which switch this cycle (``holding``)

    def renumber(self, moved: dict[int, int]) -> None:
        """New rider slots (a coupling or uncoupling): the stop lines move with their
        riders (``moved``: old slot to new); a leaving rider's go."""
        riders, lows, highs = self.stop_lines
        keep = [i for i, k in enumerate(riders.tolist()) if k in moved]
        self.stop_lines = (np.array([moved[k] for k in riders[keep].tolist()], dtype=np.int64),
                           lows[keep].copy(), highs[keep].copy())

    def holding(self) -> None:
        """Who holds which switch at the start of the cycle (``held``): the riders whose
        envelope reaches into a zone, and among them those that hold one switch together
        with a rider of a conflicting track (``contested``, each with those riders).

        A rider is in its zone at the switch at the end of its track when its envelope
        reaches within max(collision range at end, gap) of the track end, and at the switch
        at its start within max(collision range at start, gap) of the start (the gap of its
        zones, ``Rider.zone_gap``), or anywhere on the track when the zone covers all of it
        (no point of the track is safe then)."""
        t, tables = self.traffic, self.tables
        geometry = tables.geometry_now()
        lo_now, hi_now = tables.envelope()
        if self.widening:
            self._widen(geometry.length, geometry.start_range, geometry.end_range,
                        geometry.start_switch >= 0, geometry.end_switch >= 0, lo_now, hi_now)
        end_line, start_line, in_end, in_start, holders, at_end, switch = zone_holders(
            t.base, geometry.length, geometry.start_range, geometry.end_range, t.zone_gap,
            geometry.start_switch, geometry.end_switch, lo_now, hi_now)
        contested: dict[int, set[int]] = {}
        if holders.size > 1:  # placed there, or a new route turned a pair into a conflict
            key = ("contested", holders.tobytes(), at_end.tobytes())
            found = tables.clashes.get(key)  # kept while the holders stay
            if found is None:
                first, second = contested_pairs(holders, at_end, switch, *tables.route_arrays)
                for i, j in zip(first.tolist(), second.tolist(), strict=True):
                    contested.setdefault(int(holders[i]), set()).add(int(holders[j]))
                if len(tables.clashes) > _CLASH_MEMORY:
                    tables.clashes.clear()
                tables.clashes[key] = found = contested
            contested = found
        self.held = Holding(end_line, start_line, in_end, in_start, holders, at_end, switch,
                            contested)

    def keep_out(self, proposal: list[np.ndarray], lo: np.ndarray, hi: np.ndarray,
                 braking: np.ndarray) -> np.ndarray:
        """The switch rule (§6.2.2): a rider whose next step would take its brake envelope
        into a switch zone that another rider holds from a track off its path brakes
        instead (its brake stays behind the zone boundary: the envelope of a brake is
        inside the envelope it starts from); riders that hold one switch from conflicting
        tracks at once keep their footprints apart (``_apart``). Writes the brakes into
        ``proposal``, ``lo`` and ``hi``; returns the riders it braked."""
        lines, contested = self._lines(lo, hi)
        self.stop_lines = lines  # (riders, lows, highs): the rooms of the next cycle
        skip = np.zeros(self.traffic.p.size, dtype=bool)
        skip[list(contested)] = True
        slots = out_of_bounds(*lines, skip, braking, lo, hi)
        self.traffic.brake(slots, proposal, lo, hi)
        if contested:  # their stop lines narrow to where their footprints stay clear
            bounds = _lines_dict(lines)
            slots = np.concatenate((slots, self._apart(contested, bounds, proposal, lo, hi,
                                                       braking)))
            self.stop_lines = _lines_arrays(bounds)
        return slots

    def _lines(self, lo: np.ndarray, hi: np.ndarray) -> tuple[StopLines, dict[int, set[int]]]:
        """Odometer bounds of the riders kept out of a switch zone this cycle (riders, lows,
        highs), and the contested holders (``holding``). Holders keep the switch; riders that
        enter a zone are decided in rider order: the first whom no holder from a track off
        its path blocks becomes a holder too."""
        tables = self.tables
        geometry = tables.geometry_now()
        start_switch, end_switch = geometry.start_switch, geometry.end_switch
        held = self.held
        if not held.riders.size:
            return no_lines(), held.contested
        riders, lows, highs, entering = zone_lines(
            start_switch, end_switch, held.in_end, held.in_start, held.end_line,
            held.start_line, lo, hi, _ZONE_LOOKAHEAD, held.riders, held.at_end, held.switch,
            *tables.route_arrays)
        if entering.size <= 1:
            return (riders, lows, highs), held.contested
        k, at_end, switch, low, high, _ = zone_entries(  # the entries, as zone_lines saw them
            start_switch, end_switch, held.in_end, held.in_start, held.end_line,
            held.start_line, lo, hi, _ZONE_LOOKAHEAD)
        lines = _lines_dict((riders, lows, highs))
        # decided in rider order: the first of a conflict enters
        entering = entering[np.lexsort((k[entering], switch[entering]))]
        granted: dict[int, list[int]] = {}
        for i in entering.tolist():
            mine = granted.setdefault(int(switch[i]), [])
            if mine and self.conflicts(k[i:i + 1], at_end[i:i + 1], k[mine],
                                       at_end[mine]).any():
                _narrow(lines, int(k[i]), float(low[i]), float(high[i]))
            else:
                mine.append(i)
        return _lines_arrays(lines), held.contested

    def _widen(self, length: np.ndarray, start_range: np.ndarray, end_range: np.ndarray,
               has_start: np.ndarray, has_end: np.ndarray, lo_now: np.ndarray,
               hi_now: np.ndarray) -> None:
        """A rider whose gap grew measures its zones with the larger gap once its envelope
        is outside them: inside, it would hold the switch at once, past the entry check."""
        if not self.widening:
            return
        t = self.traffic
        k = np.flatnonzero(t.zone_gap < t.gap)
        self.widening = bool(k.size)
        if not k.size:
            return
        base, gap = t.base[k], t.gap[k]
        end = base + length[k] - np.maximum(end_range[k], gap)
        start = base + np.maximum(start_range[k], gap)
        inside = (has_end[k] & ((hi_now[k] > end + TOLERANCE) | (end <= base + TOLERANCE))) | \
            (has_start[k] & ((lo_now[k] < start - TOLERANCE)
                             | (start >= base + length[k] - TOLERANCE)))
        for slot in k[~inside].tolist():
            t.zone_gap[slot] = t.riders[slot].zone_gap = t.gap[slot]

    def _apart(self, contested: dict[int, set[int]], lines: dict[int, tuple[float, float]],
               proposal: list[np.ndarray], lo: np.ndarray, hi: np.ndarray,
               braking: np.ndarray) -> np.ndarray:
        """Riders that hold a switch from conflicting tracks at once (§6.2.2: every rider
        within its range there is part of the others' planning): in rider order, each may
        move only where its footprint stays clear of where the others can still be (their
        envelopes; for the ones decided this cycle, old and new). Safe by induction: a
        brake stays inside its old envelope, which was clear. Returns the riders it braked.
        """
        t, tables = self.traffic, self.tables
        lo_now, hi_now = (x.tolist() for x in tables.envelope())
        turns = {k: self.turn(k) for k in contested}
        seen: dict[int, tuple[float, float]] = {}
        out = []
        for k in sorted(contested):
            if t.mode[k] == IDLE:  # it stands: only in the others' way
                continue
            others = [(j, *seen.get(j, (lo_now[j], hi_now[j]))) for j in sorted(contested[k])]
            key = (lo_now[k], hi_now[k], turns[k], tuple((*o, turns[o[0]]) for o in others))
            cached = tables.stretches.get(k)
            if cached is None or cached[0] != key:  # standing riders ask again and again
                cached = tables.stretches[k] = (key, self.clear_stretch(k, *key[:2], others))
            scan, room = cached[1]
            _narrow(lines, k, *room)
            low, high = lines[k]
            low, high = max(low, scan[0]), min(high, scan[1])
            if not braking[k] and (hi[k] > high + TOLERANCE or lo[k] < low - TOLERANCE):
                out.append(k)
                t.brake(np.array([k]), proposal, lo, hi)
            seen[k] = (min(lo_now[k], float(lo[k])), max(hi_now[k], float(hi[k])))
        return np.array(out, dtype=np.int64)

    def clear_stretch(self, k: int, low: float, high: float,
                      others: list[tuple[int, float, float]]
                      ) -> tuple[tuple[float, float], tuple[float, float]]:
        """The stretch of rider ``k``'s way around its envelope [low, high] on which its
        footprint stays clear of the footprints of ``others`` (rider, envelope) anywhere in
        their envelopes: searched ``_CLEAR_SAMPLES`` steps of ``_CLEAR_STEP`` on each side,
        footprints grown by what they can move between two samples. Returns the stretch
        searched and the stretch for planning (infinite on a side found clear to the
        horizon); both are the envelope itself where it is not clear already."""
        t = self.traffic
        route = ascending(t.riders[k].route)
        start, end = route[0].base, route[-1].base + route[-1].track.length
        count, own = _CLEAR_SAMPLES, _sample_count(low, high)
        _, lows, highs = zip(*others, strict=True) if others else ((), (), ())
        q, at = stretch_samples(low, high, start, end, _CLEAR_STEP, count, own,
                                np.array(lows, dtype=float), np.array(highs, dtype=float),
                                np.array([_sample_count(*o[1:]) for o in others],
                                         dtype=np.int64))
        riders = [k, *(o[0] for o in others)]
        legs = [ascending(t.riders[r].route) for r in riders]
        xyc, curvature = self.tables.atlas_now().along_routes(
            np.array([leg.track.index for route in legs for leg in route], dtype=np.int64),
            np.array([leg.base for route in legs for leg in route], dtype=float),
            np.array([0, *accumulate(len(route) for route in legs)], dtype=np.int64), q, at,
            self.tables.placed_tables())
        c = xyc[2]
        hx, hy, radius = np.empty(len(riders)), np.empty(len(riders)), np.empty(len(riders))
        for i, r in enumerate(riders):  # half sides grown by what a footprint can move
            # between two samples: half a step, and the turn of a corner along a curve
            bend = float(curvature[i])
            if not t.oriented[r]:  # c stands where its own commands left it
                c[at[i]:at[i + 1]] = math.radians(self.turn(r))
                bend = 0.0
            half_x, half_y = t.riders[r].half
            margin = 0.5 * _CLEAR_STEP * (1.0 + math.hypot(half_x, half_y) * bend)
            hx[i], hy[i] = half_x + margin, half_y + margin
            radius[i] = math.hypot(half_x + margin, half_y + margin)
        on_envelope, first_f, first_b = stretch_hits(xyc[0], xyc[1], np.cos(c), np.sin(c), at,
                                                     hx, hy, radius, own, count)
        if on_envelope:
            return (low, high), (low, high)
        top = float(q[own + first_f - 1]) if first_f else high
        bottom = float(q[own + count + first_b - 1]) if first_b else low
        return (bottom, top), (bottom if first_b < count else -math.inf,
                               top if first_f < count else math.inf)

    def turn(self, k: int) -> float:
        """C [deg] of a rider whose c does not follow the track (0 for one whose does)."""
        t = self.traffic
        if t.oriented[k]:
            return 0.0
        return float(t.values[0][self.tables.geometry_now().c_rows[k]])

    def conflicts(self, riders: np.ndarray, at_end: np.ndarray, holders: np.ndarray,
                  holder_ends: np.ndarray) -> np.ndarray:
        """Whether each of ``riders`` may meet each of ``holders`` at their switch, a matrix;
        ``at_end``: at the end of its track (else at its start). Riders of two tracks meet
        unless one passes the switch onto the other's track where the other is (it keeps its
        gap to it as a pair): at the end of its track, the other's being the next on its
        route, the other at its start (not at the end of a closed one) and not on a route
        back over the seam there (it comes back to the switch and past it onto the loop's
        end, beside the one that would follow it; D-147). Riders of one closed track meet at
        the switch at its seam when one at its end leaves the track there (it turns off
        beside the one just past the seam)."""
        return conflicts(riders, at_end, holders, holder_ends, *self.tables.route_arrays)


def no_lines() -> StopLines:
    """No stop lines: (riders, lows, highs)."""
    return np.empty(0, dtype=np.int64), np.empty(0), np.empty(0)


def _lines_dict(lines: StopLines) -> dict[int, tuple[float, float]]:
    """Stop lines as (riders, lows, highs) arrays to a dict rider: (low, high)."""
    riders, lows, highs = (x.tolist() for x in lines)
    return dict(zip(riders, zip(lows, highs, strict=True), strict=True))


def _lines_arrays(lines: dict[int, tuple[float, float]]) -> StopLines:
    """``_lines_dict`` back: (riders, lows, highs) in the dict's order."""
    return (np.fromiter(lines, np.int64, len(lines)),
            np.fromiter((b[0] for b in lines.values()), float, len(lines)),
            np.fromiter((b[1] for b in lines.values()), float, len(lines)))


def _narrow(lines: dict[int, tuple[float, float]], k: int, low: float, high: float) -> None:
    """Rider ``k`` stays within [low, high] too."""
    old = lines.get(k, (-math.inf, math.inf))
    lines[k] = (max(old[0], low), min(old[1], high))


def _sample_count(low: float, high: float) -> int:
    """How many odometer positions from ``low`` to ``high`` are no more than ``_CLEAR_STEP``
    apart (``traffic_kernels.stretch_samples`` spaces them evenly)."""
    return max(1, math.ceil((high - low) / _CLEAR_STEP) + 1)
