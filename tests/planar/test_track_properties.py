"""Properties of movers on random track networks (TF5430 §6.2.2, §6.1.9, §6.2.8, §6.2.9,
§6.2.10; digest-planar-concepts §3.5, §4.4-4.6).

A scenario is a network, movers joined on it and a few rounds of commands.

Networks are lines and arcs with the automatic transitions between them, in five layouts,
scaled by 1-3 and turned by a random angle:

* a fork: a trunk and 2-3 branches that start from its end (StartFromTrack), lines or arcs;
* a bypass: a fork whose branches end at one track again (EndAtTrack), a switch that merges
  2-3 tracks, optionally closed into a loop by a return track (StartFromTrack and EndAtTrack);
* a merge: 2-3 feeders, lines or arcs, that end at one track;
* one closed track (CloseLoop: a rounded rectangle, a stadium of lines and arcs, a circle),
  optionally with a branch that starts from it and a feeder that ends at it;
* a loop of two tracks (the second starts from the first and ends at it, §6.2.10), optionally
  with more branches at the end of the first and feeders into its start.

Exclusions: situations the manual does not protect (§6.2.2, digest §4.6) are not generated.

* Tracks apart except at switches: two points of the network closer than 2R + ``CLEARANCE``
  (R the largest mover radius, the hose of §6.2.2) are either on one path within
  ``NEAR_PATH`` of each other (a curve, a track transition), or both in the stretch where two
  tracks that start (or end) at the same switch have not yet left each other's hose; a track
  that leaves the hose and comes back is a track passing close to another and is refused.
* Gaps too short for the mover or the curve: a gap is an arc length, centre to centre. Each
  network gets a floor, the longest path distance at which two footprints turned along the
  track still overlap (found on a ``SAMPLE`` grid) plus one step, and at least ``MIN_GAP``
  (160 mm: 155 mm footprints on a straight do not touch); a mover's gap is the floor plus one
  of ``EXTRA_GAPS``. Networks whose curves need more than ``MAX_GAP_FLOOR`` are not drawn.

Movers join where they stand, turned along the track (``C_LOW``/``C_HIGH``: JoinTrack is a
move of zero length), on a grid along the tracks: footprints apart and at least max(200,
both gaps) apart along every path (200 mm is the gap JoinTrack leaves in force). Two movers
may join inside the collision ranges of one switch: §6.2.2 has every mover whose braking
interval is within its range at a switch coordinate with every other such mover (they keep
their footprints apart, D-136).

Commands: MoveOnTrack to a random point of a track the mover can reach (its own or one
downstream; on its own closed track also with a modulo direction and additional turns, so
that movers go round either way over the seam, D-147), Halt, GearInPosOnTrackWithMasterMover
with followMover to another mover, and GearInPosOnTrack to an axis that then moves. Each
mover uses one gap for all its commands.

Checked at every cycle:

1. Gaps along shared paths: for a mover m and a mover o ahead of it on its path (its route,
   then the one way on while there is only one, or on round a closed track), d = the arc
   length from m to o summed over the track transitions. The movers that moved towards each
   other in a cycle (m forwards, o backwards: each is the follower in its direction of
   travel, §6.1.9) leave d at least the larger of their gaps; one that was closer than its
   gap already (the other came closer with a smaller gap) does not close in at all.
   Tolerances ``GAP_TOLERANCE`` and ``MOTION_NOISE``.
2. Footprints: no two 155 x 155 mm footprints turned by c overlap with positive area
   (separating axes; an overlap deeper than ``OVERLAP_TOLERANCE`` on every axis counts).

Checked when the commands have ended and nothing has moved for ``AT_REST_CYCLES`` (within
``SETTLE_TIMEOUT``):

3. Every command ended Done, Aborted (only by a later command of its mover), Error with an
   error id and a message, or waits as documented: a gear-in stays Active (§6.2.8); a
   MoveOnTrack waits behind a mover standing within the gap on its way (§6.2.4), head on
   for a mover behind it that waits to go forwards (D-120) or that reverses over the seam
   of a loop towards it (D-147), at its last safe stop before a switch another mover
   holds (§6.2.2), or inside its zone at a switch where a mover on a conflicting track is
   inside its own (they keep their footprints apart, and at a merge both go through, their
   gap as if on one way already; D-136). Waits form a graph; a cycle in it with a wait at a
   last safe stop is a deadlock and fails, unless the mover waited for there is stuck
   anyway: in the program's own deadlock, or behind a mover that stands for good (idle, or
   geared to a master that stands). A ring of movers queued behind each other, two movers
   head on, or two movers inside the zones of one switch that each want to go where the
   other stands, is the program's own deadlock (movers never pass each other) and passes,
   as do the movers waiting for it.

And on the networks themselves:

4. Curvature continuity: along every track and across every connection of the network the
   curvature from finite differences of the heading matches ``frame_at``'s, and position,
   heading and curvature do not jump at a joint (tests/geometry covers single random
   tracks; this adds the connections between tracks).

The failures the properties found are reproduced at the end of the file as plain tests.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.enums import ModuloDirection
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.geometry.track import TrackPath
from openmotion.planar import (
    MC_PlanarMover,
    MC_PlanarTrack,
    MoverVector,
    PlanarMoverParameters,
    PlanarState,
    PositionXYC,
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    ST_MoveOnTrackOptions,
)
from openmotion.planar.feedback import CommandPhase, PlanarCommand
from openmotion.planar.riders import Rider, ahead_legs, backwards
from openmotion.planar.track import traffic_of

SIDE = 155.0  #: [mm] mover width and height (the defaults)
HALF = SIDE / 2
RADIUS = math.hypot(HALF, HALF)  #: [mm] the largest mover radius
HOSE = 2 * RADIUS  #: [mm] centres farther apart than this never overlap
CLEARANCE = 10.0  #: [mm] tracks stay this much beyond the hose apart outside switches
NEAR_PATH = 400.0  #: [mm] points this close along a path may come close in the plane
SAMPLE = 10.0  #: [mm] the arc-length grid of the network checks
JOIN_GAP = 200.0  #: [mm] the gap JoinTrack leaves in force (ST_MoveOnTrackOptions default)
MIN_GAP = 160.0  #: [mm] the smallest gap drawn
MAX_GAP_FLOOR = 320.0  #: [mm] networks whose curves need a longer gap are not drawn
GAP_TOLERANCE = 1e-6  #: [mm]
#: [mm] a mover that moved less than this in a cycle stands (round-off, and the dip of a
#: jerk-limited brake step that ends at rest)
MOTION_NOISE = 1e-5
OVERLAP_TOLERANCE = 1e-6  #: [mm] footprints may touch; a deeper overlap counts
#: [mm] a distance along a path that changes this much more than the two movers moved is a
#: new pair: the one ahead came round a closed track onto the other's path (a forward pass of
#: the seam of a loop that a feeder ends at: a lap nearer at once)
LAP_JUMP = 1.0
AT_REST_CYCLES = 200  #: the scenario has settled when nothing moved for this many cycles
SETTLE_TIMEOUT = 30.0  #: [s] of virtual time after the last round
CYCLE = 0.001  #: [s]
#: [rad] the heading may turn this much at a joint: a straight connector to a start within
#: the geometry's point tolerance (1e-6 mm) of the straight line ahead leaves such a kink
KINK = 1e-7
#: C position limits of ±45°: the four C windows (§4.2) cover every orientation, so a mover
#: stands turned along the track where it joins and JoinTrack is a move of zero length
C_LOW = MoverVector(-math.inf, -math.inf, 0.0, -5.0, -5.0, -45.0)
C_HIGH = MoverVector(math.inf, math.inf, 6.0, 5.0, 5.0, 45.0)


# -- the network -------------------------------------------------------------------------------
#
# A layout is a tuple of tracks in build order; a track is a tuple of operations:
# ("line", x0, y0, x1, y1), ("circle", sx, sy, ex, ey, cx, cy, clockwise), ("close",),
# ("from", k) and ("end", k) with k an earlier track. Coordinates in mm.

START, END = 0, 1


class Network:
    """A layout built with ``TrackPath`` (the curves MC_PlanarTrack uses): its links,
    successors and path distances, for the generator and the checks."""

    def __init__(self, layout: tuple[tuple[tuple, ...], ...]) -> None:
        self.layout = layout
        self.paths: list[TrackPath] = []
        parent: dict[tuple[int, int], tuple[int, int]] = {}

        def root(e: tuple[int, int]) -> tuple[int, int]:
            while parent.get(e, e) != e:
                e = parent[e]
            return e

        def link(a: tuple[int, int], b: tuple[int, int]) -> None:
            ra, rb = root(a), root(b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)

        for index, ops in enumerate(layout):
            path = TrackPath()
            for op in ops:
                _apply(path, op, self.paths)
                if op[0] == "from":
                    link((op[1], END), (index, START))
                elif op[0] == "end":
                    link((index, END), (op[1], START))
                elif op[0] == "close":
                    link((index, END), (index, START))
            self.paths.append(path)
        n = len(layout)
        self.lengths = np.array([p.length for p in self.paths])
        self.vertex = [[root((k, side)) for side in (START, END)] for k in range(n)]
        self.successors = [[j for j in range(n) if self.vertex[j][START] == self.vertex[k][END]]
                           for k in range(n)]
        self.ends = {}  #: vertex -> [(track, side)]
        for k in range(n):
            for side in (START, END):
                self.ends.setdefault(self.vertex[k][side], []).append((k, side))
        # between[a, b]: the shortest sum of whole tracks from the end of a to the start of b
        between = np.full((n, n), np.inf)
        for a in range(n):
            for b in self.successors[a]:
                between[a, b] = 0.0
        for c in range(n):
            between = np.minimum(between, between[:, [c]] + self.lengths[c] + between[[c], :])
        self.between = between

    def __repr__(self) -> str:
        return f"Network({self.layout!r})"

    def forward(self, a: np.ndarray, sa: np.ndarray, b: np.ndarray, sb: np.ndarray
                ) -> np.ndarray:
        """The shortest arc length from (track a, sa) forwards to (track b, sb)."""
        through = self.lengths[a] - sa + self.between[a, b] + sb
        same = np.where((a == b) & (sb >= sa), sb - sa, np.inf)
        return np.minimum(same, through)

    def reachable(self, track: int) -> list[int]:
        """``track`` and every track a mover on it can reach, in index order."""
        seen, queue = {track}, deque([track])
        while queue:
            for nxt in self.successors[queue.popleft()]:
                if nxt not in seen:
                    seen.add(nxt)
                    queue.append(nxt)
        return sorted(seen)

    def samples(self) -> tuple[np.ndarray, ...]:
        """Track, arc length, x, y and heading on the ``SAMPLE`` grid of every track."""
        out = []
        for k, path in enumerate(self.paths):
            count = max(2, math.ceil(path.length / SAMPLE) + 1)
            s = np.linspace(0.0, path.length, count)
            if path.closed:
                s = s[:-1]
            x, y, heading, _ = path.frame_at(s)
            out.append((np.full(s.size, k), s, x, y, heading))
        return tuple(np.concatenate(column) for column in zip(*out, strict=True))


def _apply(path: TrackPath, op: tuple, built: list[TrackPath]) -> None:
    kind = op[0]
    if kind == "line":
        path.append_line(op[1:3], op[3:5])
    elif kind == "circle":
        path.append_circle(op[1:3], op[3:5], op[5:7], op[7])
    elif kind == "close":
        path.close_loop()
    elif kind == "from":
        path.start_from(built[op[1]])
    else:
        path.end_at(built[op[1]])


def overlaps(x1, y1, c1, x2, y2, c2, tolerance: float = OVERLAP_TOLERANCE) -> np.ndarray:
    """Whether squares of side ``SIDE`` centred at (x, y) and turned by c [rad] overlap by
    more than ``tolerance`` on every separating axis (arrays of pairs)."""
    dx, dy = np.asarray(x2) - x1, np.asarray(y2) - y1
    axes = [(np.cos(c1), np.sin(c1)), (-np.sin(c1), np.cos(c1)),
            (np.cos(c2), np.sin(c2)), (-np.sin(c2), np.cos(c2))]
    u1, v1, u2, v2 = axes
    inside = np.ones(np.broadcast(dx, c1, c2).shape, dtype=bool)
    for nx, ny in axes:
        reach = HALF * (np.abs(u1[0] * nx + u1[1] * ny) + np.abs(v1[0] * nx + v1[1] * ny)
                        + np.abs(u2[0] * nx + u2[1] * ny) + np.abs(v2[0] * nx + v2[1] * ny))
        inside &= reach - np.abs(dx * nx + dy * ny) > tolerance
    return inside


def check_apart(net: Network) -> float | None:
    """None if the network has tracks too close outside switches (or a track close to
    itself); else the gap floor [mm] its curves need (module docstring)."""
    track, s, x, y, heading = net.samples()
    n = track.size
    i, j = np.triu_indices(n, 1)
    dist = np.hypot(x[j] - x[i], y[j] - y[i])
    near = dist < HOSE + CLEARANCE
    i, j, dist = i[near], j[near], dist[near]
    along = np.minimum(net.forward(track[i], s[i], track[j], s[j]),
                       net.forward(track[j], s[j], track[i], s[i]))
    ok = along <= NEAR_PATH
    hose = _hose_regions(net, track, s, x, y)
    for (a, b), (in_a, in_b) in hose.items():
        ok |= (track[i] == a) & (track[j] == b) & in_a[i] & in_b[j]
        ok |= (track[i] == b) & (track[j] == a) & in_b[i] & in_a[j]
    if not ok.all():
        return None
    path_close = (along <= NEAR_PATH) & (dist < HOSE)
    hit = overlaps(x[i][path_close], y[i][path_close], heading[i][path_close],
                   x[j][path_close], y[j][path_close], heading[j][path_close], 0.0)
    worst = float(np.max(along[path_close][hit], initial=0.0))
    return max(MIN_GAP, worst + SAMPLE)


def _hose_regions(net: Network, track, s, x, y) -> dict:
    """For two tracks that start (or end) at the same switch: the samples of each from that
    switch until it first leaves the other's hose (2R + ``CLEARANCE``)."""
    regions = {}
    for ends in net.ends.values():
        for p, (a, side_a) in enumerate(ends):
            for b, side_b in ends[p + 1:]:
                if a == b or side_a != side_b:
                    continue
                in_a = _until_apart(net, track, s, x, y, a, b, side_a)
                in_b = _until_apart(net, track, s, x, y, b, a, side_a)
                old = regions.get((a, b))
                if old is not None:
                    in_a, in_b = in_a | old[0], in_b | old[1]
                regions[(a, b)] = (in_a, in_b)
    return regions


def _until_apart(net, track, s, x, y, a, b, side) -> np.ndarray:
    mine, other = np.flatnonzero(track == a), np.flatnonzero(track == b)
    order = mine if side == START else mine[::-1]
    gaps = np.hypot(x[order][:, None] - x[other][None, :],
                    y[order][:, None] - y[other][None, :]).min(axis=1)
    apart = np.flatnonzero(gaps >= HOSE + CLEARANCE)
    stop = apart[0] if apart.size else order.size
    region = np.zeros(track.size, dtype=bool)
    region[order[:stop]] = True
    return region


# -- layouts -----------------------------------------------------------------------------------


def _placed(layout: list[list[tuple]], angle: float, scale: float
            ) -> tuple[tuple[tuple, ...], ...]:
    """Every point of ``layout`` scaled by ``scale`` and turned by ``angle`` [rad] about the
    origin, rounded to 1e-6 mm so that the scenario prints short."""
    cos, sin = scale * math.cos(angle), scale * math.sin(angle)

    def turn(values: tuple) -> tuple:
        out = []
        for x, y in zip(values[::2], values[1::2], strict=True):
            out += [round(cos * x - sin * y, 6), round(sin * x + cos * y, 6)]
        return tuple(out)

    tracks = []
    for ops in layout:
        turned = []
        for op in ops:
            if op[0] == "line":
                turned.append(("line", *turn(op[1:5])))
            elif op[0] == "circle":
                turned.append(("circle", *turn(op[1:7]), op[7]))
            else:
                turned.append(op)
        tracks.append(tuple(turned))
    return tuple(tracks)


def _in_frame(pose: tuple[float, float, float], x: float, y: float) -> tuple[float, float]:
    """A point given in the frame of ``pose`` (x, y, heading)."""
    px, py, h = pose
    return px + math.cos(h) * x - math.sin(h) * y, py + math.sin(h) * x + math.cos(h) * y


def _branch(draw: st.DrawFn, side: int, frame: tuple[float, float, float],
            kinds: tuple[str, ...] = ("offset", "arc")) -> list[tuple]:
    """Operations after StartFromTrack of a branch leaving ``frame`` (a switch pose) straight
    on (side 0), to the left (1) or to the right (-1)."""
    if side == 0:
        g = draw(st.sampled_from([0.0, 60.0, 150.0]))
        length = draw(st.floats(250.0, 900.0))
        turn = 0.0 if g == 0.0 else draw(st.floats(-0.15, 0.15))
        end = (g + length * math.cos(turn), length * math.sin(turn))
        return [("line", *_in_frame(frame, g, 0.0), *_in_frame(frame, *end))]
    if draw(st.sampled_from(kinds)) == "offset":
        offset, g = draw(st.floats(250.0, 450.0)), draw(st.floats(300.0, 700.0))
        turn, length = draw(st.floats(0.0, 0.6)), draw(st.floats(200.0, 800.0))
        start = (g, side * offset)
        end = (g + length * math.cos(turn), side * (offset + length * math.sin(turn)))
        return [("line", *_in_frame(frame, *start), *_in_frame(frame, *end))]
    radius, sweep = draw(st.floats(300.0, 900.0)), draw(st.floats(0.5, 1.6))
    angle = -side * math.pi / 2 + side * sweep
    end = (radius * math.cos(angle), side * radius + radius * math.sin(angle))
    return [("circle", *_in_frame(frame, 0.0, 0.0), *_in_frame(frame, *end),
             *_in_frame(frame, 0.0, side * radius), side < 0)]


def _feeder(draw: st.DrawFn, side: int, frame: tuple[float, float, float]) -> list[tuple]:
    """Operations before EndAtTrack of a track that ends at the switch pose ``frame``,
    coming in straight (side 0), from the left (1) or from the right (-1)."""
    if side == 0:
        g = draw(st.sampled_from([0.0, 60.0, 150.0]))
        length = draw(st.floats(250.0, 900.0))
        return [("line", *_in_frame(frame, -g - length, 0.0), *_in_frame(frame, -g, 0.0))]
    if draw(st.booleans()):
        offset, g = draw(st.floats(250.0, 450.0)), draw(st.floats(300.0, 700.0))
        length = draw(st.floats(200.0, 800.0))
        return [("line", *_in_frame(frame, -g - length, side * offset),
                 *_in_frame(frame, -g, side * offset))]
    radius, sweep = draw(st.floats(300.0, 900.0)), draw(st.floats(0.5, 1.6))
    angle = -side * math.pi / 2 - side * sweep
    start = (radius * math.cos(angle), side * radius + radius * math.sin(angle))
    return [("circle", *_in_frame(frame, *start), *_in_frame(frame, 0.0, 0.0),
             *_in_frame(frame, 0.0, side * radius), side < 0)]


def _sides(draw: st.DrawFn) -> list[int]:
    """Two or three distinct directions out of a switch."""
    return sorted(draw(st.sampled_from([(-1, 0), (0, 1), (-1, 1), (-1, 0, 1)])))


def _fork(draw: st.DrawFn) -> list[list[tuple]]:
    trunk = draw(st.floats(300.0, 900.0))
    layout = [[("line", -trunk, 0.0, 0.0, 0.0)]]
    for side in _sides(draw):
        layout.append([("from", 0), *_branch(draw, side, (0.0, 0.0, 0.0))])
    return layout


def _bypass(draw: st.DrawFn) -> list[list[tuple]]:
    """T, branches from its end that end at U again, maybe a return from U to T."""
    trunk = draw(st.floats(300.0, 900.0))
    sides = _sides(draw)
    offset = {side: draw(st.floats(250.0, 450.0)) for side in sides if side}
    out = {side: draw(st.floats(300.0, 600.0)) for side in sides}
    middle = {side: draw(st.floats(150.0, 600.0)) for side in sides}
    back = draw(st.floats(300.0, 600.0))
    merge = max(out[side] + middle[side] for side in sides) + back
    length = draw(st.floats(300.0, 900.0))
    layout = [[("line", -trunk, 0.0, 0.0, 0.0)], [("line", merge, 0.0, merge + length, 0.0)]]
    for side in sides:
        y = side * offset[side] if side else 0.0
        start = 0.0 if side == 0 and out[side] < 400 else out[side]
        layout.append([("from", 0), ("line", start, y, out[side] + middle[side], y), ("end", 1)])
    if draw(st.booleans()):  # the return above or below the outer branch
        up = draw(st.sampled_from([-1, 1]))
        height = offset.get(up, 0.0) + draw(st.floats(350.0, 600.0))
        q = draw(st.floats(120.0, min(250.0, height / 2 - 30.0)))
        right, left = merge + length, -trunk
        layout.append([("from", 1), ("line", right + q, up * q, right + q, up * (height - q)),
                       ("line", right, up * height, left, up * height),
                       ("line", left - q, up * (height - q), left - q, up * q), ("end", 0)])
    return layout


def _merge(draw: st.DrawFn) -> list[list[tuple]]:
    length = draw(st.floats(300.0, 900.0))
    layout = [[("line", 0.0, 0.0, length, 0.0)]]
    for side in _sides(draw):
        layout.append([*_feeder(draw, side, (0.0, 0.0, 0.0)), ("end", 0)])
    return layout


def _closed(draw: st.DrawFn) -> list[list[tuple]]:
    """One closed track; maybe a branch from its start and a feeder into it, outside."""
    shape = draw(st.sampled_from(["rectangle", "stadium", "circle"]))
    if shape == "rectangle":
        w, h = draw(st.floats(600.0, 1400.0)), draw(st.floats(500.0, 1000.0))
        q = draw(st.floats(120.0, 250.0))
        loop = [("line", q, 0.0, w - q, 0.0), ("line", w, q, w, h - q),
                ("line", w - q, h, q, h), ("line", 0.0, h - q, 0.0, q)]
    elif shape == "stadium":
        w, r = draw(st.floats(300.0, 1200.0)), draw(st.floats(250.0, 500.0))
        loop = [("line", 0.0, 0.0, w, 0.0), ("circle", w, 0.0, w, 2 * r, w, r, False),
                ("line", w, 2 * r, 0.0, 2 * r), ("circle", 0.0, 2 * r, 0.0, 0.0, 0.0, r, False)]
    else:
        r = draw(st.floats(300.0, 600.0))
        loop = [("circle", 0.0, 0.0, 0.0, 0.0, 0.0, r, False)]
    layout = [[*loop, ("close",)]]
    try:
        pose = Network((tuple(layout[0]),)).paths[0].start_pose
    except ConfigError:
        assume(False)
    frame = (pose.x, pose.y, pose.heading)
    if draw(st.booleans()):
        layout.append([("from", 0), *_branch(draw, -1, frame)])
    if draw(st.booleans()):
        layout.append([*_feeder(draw, -1, frame), ("end", 0)])
    return layout


def _two_track_loop(draw: st.DrawFn) -> list[list[tuple]]:
    """A from (0, 0) to (a, 0), B from A's end round back to A's start (§6.2.10), maybe
    branches from A's end and feeders into A's start, below the loop."""
    a, h = draw(st.floats(400.0, 1200.0)), draw(st.floats(500.0, 1000.0))
    q = draw(st.floats(120.0, 250.0))
    layout = [[("line", 0.0, 0.0, a, 0.0)],
              [("from", 0), ("line", a + q, q, a + q, h - q), ("line", a, h, 0.0, h),
               ("line", -q, h - q, -q, q), ("end", 0)]]
    for side in draw(st.sampled_from([(), (-1,), (0,), (-1, 0)])):
        layout.append([("from", 0), *_branch(draw, side, (a, 0.0, 0.0))])
    for side in draw(st.sampled_from([(), (-1,), (0,), (-1, 0)])):
        layout.append([*_feeder(draw, side, (0.0, 0.0, 0.0)), ("end", 0)])
    return layout


LAYOUTS = {"fork": _fork, "bypass": _bypass, "merge": _merge, "closed": _closed,
           "two-track loop": _two_track_loop}


@st.composite
def networks(draw: st.DrawFn) -> tuple[Network, float]:
    """A valid network (module docstring) and the gap floor its curves need."""
    make = LAYOUTS[draw(st.sampled_from(sorted(LAYOUTS)))]
    turned = _placed(make(draw), draw(st.floats(-math.pi, math.pi)),
                     draw(st.sampled_from([1.0, 1.5, 2.0, 3.0])))
    try:
        net = Network(turned)
    except ConfigError:
        assume(False)
    floor = check_apart(net)
    assume(floor is not None and floor <= MAX_GAP_FLOOR)
    return net, floor


# -- scenarios ---------------------------------------------------------------------------------
#
# Commands, with mover and choice indices taken modulo what exists when they are sent:
# ("move", mover, target pick, fraction of the target track[, direction, laps]: a modulo
# move where the target is the mover's own closed track), ("halt", mover),
# ("gear mover", mover, master pick, master sync fraction, slave sync fraction),
# ("gear axis", mover, axis target [mm], axis velocity [mm/s], master sync [mm],
#  slave sync fraction).


@dataclass(frozen=True)
class Scenario:
    layout: tuple[tuple[tuple, ...], ...]
    movers: tuple[tuple[int, float, float], ...]  #: (track, arc length, gap) per mover
    rounds: tuple[tuple[int, tuple[tuple, ...]], ...]  #: (cycles to wait, commands)


EXTRA_GAPS = (0.0, 0.0, 20.0, 60.0, 120.0)  #: [mm] drawn on top of the network's gap floor


def place_movers(net: Network, floor: float, draws: list[tuple[int, int]]
                 ) -> tuple[tuple[int, float, float], ...]:
    """Movers on the drawn points of a grid along every track, spaced by the largest gap
    that can be drawn, each with the drawn gap; a point whose footprint overlaps a placed
    mover's, or which lies closer along a path than max(``JOIN_GAP``, both gaps), is left
    out."""
    step = max(JOIN_GAP, math.ceil(floor) + max(EXTRA_GAPS))
    grid = [(k, round(float(s), 3)) for k, length in enumerate(net.lengths)
            for s in np.arange(0.0, length - (step if net.paths[k].closed else 0.0) + 1e-9,
                               step)]
    placed: list[tuple[int, float, float]] = []
    taken: set[int] = set()
    for pick, extra in draws:
        point = pick % len(grid)
        if point in taken:
            continue
        track, s = grid[point]
        gap = float(math.ceil(floor) + EXTRA_GAPS[extra])
        if placed and not _fits(net, placed, track, s, gap):
            continue
        taken.add(point)
        placed.append((track, s, gap))
    return tuple(placed)


def _fits(net: Network, placed: list[tuple[int, float, float]], track: int, s: float,
          gap: float) -> bool:
    tracks = np.array([p[0] for p in placed])
    arcs = np.array([p[1] for p in placed])
    gaps = np.array([p[2] for p in placed])
    me_t, me_s = np.full(tracks.size, track), np.full(tracks.size, s)
    along = np.minimum(net.forward(me_t, me_s, tracks, arcs), net.forward(tracks, arcs, me_t, me_s))
    if np.any(along < np.maximum(np.maximum(gaps, gap), JOIN_GAP)):
        return False
    x, y, heading = _frames(net, tracks, arcs)
    mx, my, mh = _frames(net, me_t[:1], me_s[:1])
    return not overlaps(mx[0], my[0], mh[0], x, y, heading, -1.0).any()


def _frames(net: Network, tracks: np.ndarray, arcs: np.ndarray) -> tuple[np.ndarray, ...]:
    x, y, h = np.empty(tracks.size), np.empty(tracks.size), np.empty(tracks.size)
    for k in np.unique(tracks):
        here = tracks == k
        x[here], y[here], h[here], _ = net.paths[k].frame_at(arcs[here])
    return x, y, h


MODULO = (ModuloDirection.POSITIVE, ModuloDirection.SHORTEST_WAY, ModuloDirection.NEGATIVE,
          ModuloDirection.NEGATIVE)  #: the directions a modulo move draws from


def _commands(max_movers: int) -> st.SearchStrategy[tuple]:
    mover = st.integers(0, max_movers - 1)
    fraction = st.floats(0.0, 1.0)
    return st.one_of(
        st.tuples(st.just("move"), mover, st.integers(0, 9), fraction),
        st.tuples(st.just("move"), mover, st.integers(0, 9), fraction),
        st.tuples(st.just("move"), mover, st.integers(0, 9), fraction,
                  st.integers(0, len(MODULO) - 1), st.integers(0, 1)),
        st.tuples(st.just("halt"), mover),
        st.tuples(st.just("gear mover"), mover, st.integers(0, max_movers - 1), fraction,
                  fraction),
        st.tuples(st.just("gear axis"), mover, st.floats(0.0, 2000.0),
                  st.floats(100.0, 800.0), st.floats(0.0, 1000.0), fraction),
    )


@st.composite
def scenarios(draw: st.DrawFn, max_movers: int = 30, max_rounds: int = 4) -> Scenario:
    net, floor = draw(networks())
    count = draw(st.integers(1, 2 * max_movers))
    draws = draw(st.lists(st.tuples(st.integers(0, 999), st.integers(0, len(EXTRA_GAPS) - 1)),
                          min_size=count, max_size=count))
    movers = place_movers(net, floor, draws)[:max_movers]
    rounds = draw(st.lists(st.tuples(st.integers(0, 1200),
                                     st.lists(_commands(max_movers), min_size=1, max_size=8)
                                     .map(tuple)),
                           min_size=1, max_size=max_rounds))
    return Scenario(net.layout, movers, tuple(rounds))


# -- running a scenario ------------------------------------------------------------------------

GEARS = ("GearInPosOnTrack", "GearInPosOnTrackWithMasterMover")


@dataclass
class Sent:
    """One command sent to a mover."""

    mover: int
    command: PlanarCommand
    cycle: int
    target: tuple[int, float] | None = None  #: MoveOnTrack: (track, arc length)


class Run:
    """A scenario in a runtime, checked at every cycle (module docstring)."""

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.net = Network(scenario.layout)
        self.rt = rt = om.Runtime(CYCLE)
        self.tracks = [MC_PlanarTrack(rt, f"t{k}") for k in range(len(scenario.layout))]
        self.index = {id(t): k for k, t in enumerate(self.tracks)}
        built = [self._op(track, op) for track, ops in zip(self.tracks, scenario.layout,
                                                           strict=True) for op in ops]
        built += [track.enable() for track in self.tracks]
        rt.step()
        rt.step()
        refused = [(c.kind, c.message) for c in built if not c.done]
        assert not refused, f"the runtime refused a network TrackPath built: {refused}"
        assert all(t.state is PlanarState.ENABLED for t in self.tracks)
        self.movers = []
        for k, s, _ in scenario.movers:
            x, y, heading, _ = self.tracks[k].frame_at(np.array([s]))
            start = MoverVector(float(x[0]), float(y[0]), c=math.degrees(float(heading[0])))
            self.movers.append(MC_PlanarMover(rt, PlanarMoverParameters(
                initial_position=start, minimum_position=C_LOW, maximum_position=C_HIGH)))
        for mover in self.movers:
            mover.enable()
        rt.run(0.005)
        joins = [m.join_track(self.tracks[k]) for m, (k, _, _) in zip(
            self.movers, scenario.movers, strict=True)]
        rt.run_until(lambda: all(not j.busy for j in joins), timeout=2.0)
        assert all(j.done for j in joins), [(j.kind, j.message) for j in joins if not j.done]
        self.gaps = [gap for _, _, gap in scenario.movers]
        self.system = self.tracks[0].system
        self.traffic = traffic_of(self.system) if self.movers else None
        self.rows = np.array([[m._row0, m._row0 + 1, m._row0 + 5] for m in self.movers],
                             dtype=np.int64).reshape(-1, 3)
        self.offsets = np.array([m._offset[[0, 1, 5]] for m in self.movers]).reshape(-1, 3)
        if self.movers:
            assert all(tuple(self.system._values[0][self.rows[i]] + self.offsets[i])
                       == (m.position.x, m.position.y, m.position.c)
                       for i, m in enumerate(self.movers))
        self.axis = rt.add_axis("master")
        self.axis.power()
        rt.run(0.01)
        self.sent: list[Sent] = []
        self.pairs: dict[tuple[int, int], tuple[float, tuple[int, ...]]] = {}
        self._paths: dict[int, tuple[tuple, list]] = {}  #: ``_legs``
        self.v = np.zeros(len(self.movers))
        self.last = [self.where(i) for i in range(len(self.movers))]
        self.cycle = 0
        self.observe()

    def _op(self, track: MC_PlanarTrack, op: tuple) -> PlanarCommand:
        kind = op[0]
        if kind == "line":
            return track.append_line(PositionXYC(*op[1:3]), PositionXYC(*op[3:5]))
        if kind == "circle":
            return track.append_circle(PositionXYC(*op[1:3]), PositionXYC(*op[3:5]),
                                       PositionXYC(*op[5:7]), op[7])
        if kind == "close":
            return track.close_loop()
        if kind == "from":
            return track.start_from_track(self.tracks[op[1]])
        return track.end_at_track(self.tracks[op[1]])

    # -- the scenario ------------------------------------------------------------------------

    def play(self) -> None:
        for wait, commands in self.scenario.rounds:
            for _ in range(wait):
                self.step()
            if self.movers:
                for command in commands:
                    self.send(command)
            self.step()
        self.settle()
        _check_endings(self)

    def step(self) -> None:
        self.rt.step()
        self.cycle += 1
        self.observe()

    def _everywhere(self) -> list[tuple[int, float, float]]:
        """``where`` of every mover, read from the traffic's arrays at once."""
        traffic = self.traffic
        riders = [m._rider for m in self.movers]
        slots = [r.slot for r in riders]
        s = (traffic.p[slots] - traffic.base[slots]).tolist()
        v = traffic.v[slots].tolist()
        return [(self.index[id(r.track)], s[n], v[n]) for n, r in enumerate(riders)]

    def where(self, i: int) -> tuple[int, float, float]:
        """Track, arc length and velocity of mover ``i``."""
        track, s, v, _ = self.traffic.position(self.movers[i]._rider)
        return self.index[id(track)], s, v

    def send(self, raw: tuple) -> None:
        kind, i = raw[0], raw[1] % len(self.movers)
        mover, gap = self.movers[i], self.gaps[i]
        here = self.where(i)[0]
        target = None
        if kind == "move":
            reach = self.net.reachable(here)
            track = reach[raw[2] % len(reach)]
            target = (track, round(float(raw[3] * self.net.lengths[track]), 3))
            options = ST_MoveOnTrackOptions(gap=gap)
            if len(raw) > 4 and track == here and self.net.paths[here].closed:
                direction = MODULO[raw[4] % len(MODULO)]
                laps = raw[5] if direction is not ModuloDirection.SHORTEST_WAY else 0
                options = ST_MoveOnTrackOptions(gap=gap, direction=direction,
                                                additional_turns=laps)
            command = mover.move_on_track(self.tracks[track], target[1], options=options)
        elif kind == "halt":
            command = mover.halt()
        elif kind == "gear mover":
            j = raw[2] % len(self.movers)
            if j == i or self._geared(j) or self._masters(i):
                return
            there = self.where(j)[0]
            options = ST_GearInPosOnTrackWithMasterMoverOptions(gap=gap, follow_mover=True)
            command = mover.gear_in_pos_on_track_with_master_mover(
                self.movers[j], None, round(float(raw[3] * self.net.lengths[there]), 3),
                self.tracks[there], round(float(raw[4] * self.net.lengths[here]), 3),
                self.tracks[here], options=options)
        else:
            self.axis.move_absolute(raw[2], raw[3])
            command = mover.gear_in_pos_on_track(
                self.axis, None, raw[4], round(float(raw[5] * self.net.lengths[here]), 3),
                self.tracks[here], options=ST_GearInPosOnTrackOptions(gap=gap))
        self.sent.append(Sent(i, command, self.cycle, target))

    def _latest(self, i: int) -> Sent | None:
        return next((s for s in reversed(self.sent) if s.mover == i), None)

    def _geared(self, i: int) -> bool:
        latest = self._latest(i)
        return latest is not None and latest.command.kind in GEARS

    def _masters(self, i: int) -> bool:
        """Mover ``i`` is the master of a gear-in (it does not become a slave: no cycles)."""
        master = self.movers[i]
        return any(s.command.kind == GEARS[1] and s.command.args[0] is master
                   for s in self.sent)

    def settle(self) -> None:
        """Run until nothing has moved for ``AT_REST_CYCLES`` cycles."""
        quiet = 0
        for _ in range(round(SETTLE_TIMEOUT / CYCLE)):
            self.step()
            moving = np.any(self.v != 0.0) or self.axis.moving
            quiet = 0 if moving else quiet + 1
            if quiet >= AT_REST_CYCLES:
                return
        raise AssertionError(f"still moving {SETTLE_TIMEOUT} s after the last round: movers "
                             f"{np.flatnonzero(self.v).tolist()}\n{self.scenario}")

    # -- the checks at every cycle -----------------------------------------------------------

    def observe(self) -> None:
        if not self.movers:
            return
        where = self._everywhere()
        moved = np.array([self._moved(w, old) if w != old else 0.0
                          for w, old in zip(where, self.last, strict=True)])
        if moved.any():  # else every distance and footprint is as it was
            self._check_gaps(where, moved)
            self._check_footprints()
        self.v = np.array([w[2] for w in where])
        self.last = where

    def _moved(self, now: tuple[int, float, float], before: tuple[int, float, float]
               ) -> float:
        """How far a mover went forwards along its way since the last cycle [mm]."""
        (k, s, _), (k0, s0, _) = now, before
        if k == k0:
            step = s - s0
            length = self.net.lengths[k]
            if self.net.paths[k].closed and abs(step) > length / 2:  # once round the loop
                step -= math.copysign(length, step)
            return step
        return self.net.lengths[k0] - s0 + s  # on to the next track

    def ahead(self, i: int, where: list[tuple[int, float, float]],
              on: dict[int, list[int]] | None = None
              ) -> dict[int, tuple[float, tuple[int, ...]]]:
        """Movers ahead of mover ``i`` on its path: its route, then the one way on while there
        is only one, or round a closed track (up to ``NEAR_PATH`` + 400 mm past the route):
        the arc length to each and the tracks from here to it. ``on``: the movers on each
        track."""
        legs = self._legs(self.movers[i]._rider)
        on = on if on is not None else _on_tracks(where)
        found: dict[int, tuple[float, tuple[int, ...]]] = {}
        s_i = where[i][1]
        for k, offset, path in legs:
            for j in on.get(k, ()):
                d = offset + where[j][1] - s_i
                if j != i and j not in found and d > 0.0:
                    found[j] = (d, path)
        return found

    def _legs(self, rider: Rider) -> list[tuple[int, float, tuple[int, ...]]]:
        """(track, offset from the start of the rider's track, tracks up to it) of the legs
        of its path: its route, then the one way on (``ahead``); kept while its route
        stays."""
        key = tuple((id(leg.track), leg.base) for leg in rider.route)
        cached = self._paths.get(id(rider))
        if cached is not None and cached[0] == key:
            return cached[1]
        base = rider.route[0].base
        legs = [(self.index[id(leg.track)], leg.base - base) for leg in ahead_legs(rider.route)]
        last, offset = legs[-1]
        end = route_end = offset + self.net.lengths[last]
        while end - route_end < NEAR_PATH + 400.0:
            if self.net.paths[last].closed:  # a loop runs on into itself, switch or not
                pass
            elif len(self.net.successors[last]) == 1:
                last = self.net.successors[last][0]
            else:
                break
            legs.append((last, end))
            end += self.net.lengths[last]
        tracks = [k for k, _ in legs]
        out = [(k, offset, tuple(tracks[:n + 1])) for n, (k, offset) in enumerate(legs)]
        self._paths[id(rider)] = (key, out)
        return out

    def behind(self, i: int, where: list[tuple[int, float, float]]
               ) -> dict[int, float]:
        """Movers behind mover ``i`` on its way back over the seam of its closed track (its
        route's legs, which descend, D-147): the arc length to each. Empty unless its route
        goes back."""
        rider = self.movers[i]._rider
        if not backwards(rider.route):
            return {}
        on = _on_tracks(where)
        base, s_i = rider.route[0].base, where[i][1]
        found: dict[int, float] = {}
        for leg in rider.route:
            for j in on.get(self.index[id(leg.track)], ()):
                d = s_i - (leg.base - base + where[j][1])
                if j != i and j not in found and d > 0.0:
                    found[j] = d
        return found

    def _check_gaps(self, where: list[tuple[int, float, float]], moved: np.ndarray) -> None:
        """Property 1 for each pair m, o ahead of it: the movers that moved towards each other
        this cycle (m forwards, o backwards) keep the larger of their gaps; one that was
        closer than its gap already does not close in at all."""
        pairs = {}
        on = _on_tracks(where)
        still = [step == 0.0 for step in moved.tolist()]
        for i in range(len(self.movers)):
            for j, (d, path) in self.ahead(i, where, on).items():
                pairs[i, j] = (d, path)
                if still[i] and still[j]:
                    continue  # as it was
                old = self.pairs.get((i, j))
                if old is None or not _same_path(old[1], path) or \
                        abs(d - old[0] - moved[j] + moved[i]) > LAP_JUMP:
                    continue  # new to the path, or it came round a loop onto it (a lap)
                steps = ((i, moved[i]), (j, -moved[j]))
                closing = {x: step for x, step in steps if step > MOTION_NOISE}
                noise = sum(step for _, step in steps if 0.0 < step <= MOTION_NOISE)
                within = [x for x in closing if self.gaps[x] > old[0] + GAP_TOLERANCE]
                crept = within if d < old[0] - GAP_TOLERANCE - noise else []
                keep = [self.gaps[x] for x in closing if x not in within]
                floor = max(keep) if keep else old[0] if not within else -math.inf
                if not crept and d >= floor - GAP_TOLERANCE - noise:
                    continue
                raise AssertionError(
                    f"cycle {self.cycle}: mover {i} (gap {self.gaps[i]}, moved {moved[i]:.6g}) "
                    f"and mover {j} ahead on its path (gap {self.gaps[j]}, moved "
                    f"{moved[j]:.6g}) came from {old[0]:.9g} to {d:.9g} mm apart along tracks "
                    f"{path}" + (f"; mover {crept[0]} closed in within its gap" if crept else "")
                    + f"; (track, s, v) {[where[i], where[j]]}\n{self.scenario}")
        self.pairs = pairs

    def _check_footprints(self) -> None:
        """Property 2, on the published set positions (``MC_PlanarMover.position``, read
        from the planar system's rows for all movers at once)."""
        pose = self.system._values[0][self.rows] + self.offsets
        x, y, c = pose[:, 0], pose[:, 1], np.radians(pose[:, 2])
        i, j = np.triu_indices(len(self.movers), 1)
        near = np.hypot(x[j] - x[i], y[j] - y[i]) < HOSE
        i, j = i[near], j[near]
        hit = overlaps(x[i], y[i], c[i], x[j], y[j], c[j])
        if hit.any():
            a, b = int(i[hit][0]), int(j[hit][0])
            raise AssertionError(
                f"cycle {self.cycle}: footprints of movers {a} and {b} overlap: "
                f"{self.where(a)} at {tuple(pose[a])}, {self.where(b)} at {tuple(pose[b])} "
                f"(track, s, v; x, y, c)\n{self.scenario}")


    # -- documented waiting ------------------------------------------------------------------

    def blockers(self, sent: Sent) -> list[tuple[int, str]]:
        """The movers a standing MoveOnTrack waits for: one standing within its gap on its
        way ("queue", §6.2.4; going backwards also one behind it that waits to go forwards:
        head on, the forward one goes first, D-120; behind it on a way back over a loop's
        seam too, and going forwards one that comes back so towards it, D-147), one that
        holds the switch ahead of it
        from a track off its way ("switch": it stands at its last safe stop, §6.2.2), or,
        standing inside its zone at a switch (ahead or behind), one inside its own zone
        there on a track off its way and close enough to be in the way ("footprints": the
        two keep their footprints apart, §6.2.2), or nearer a merge that both go on
        through, within their gap ("merge": a pair through it, D-136)."""
        i = sent.mover
        where = [self.where(k) for k in range(len(self.movers))]
        k, s, _ = where[i]
        rider = self.movers[i]._rider
        assert rider.gap == self.gaps[i], (rider.gap, self.gaps[i], sent.command.kind)
        forward = self._forwards(i)
        out: list[tuple[int, str]] = []

        def near(j: int, d: float) -> bool:
            return d <= max(self.gaps[i], self.movers[j]._rider.gap) + 1e-3

        if forward:  # the larger gap: the other may have come closer while reversing
            out += [(j, "queue") for j, (d, _) in self.ahead(i, where).items() if near(j, d)]
            # or one reversing over a loop's seam towards it: head on (D-147)
            out += [(j, "queue") for j in range(len(self.movers)) if j != i
                    and (d := self.behind(j, where).get(i)) is not None and near(j, d)]
        else:  # within a gap of the mover behind, or head on with it (D-120)
            out += [(j, "queue") for j in range(len(self.movers)) if j != i
                    and (d := self.ahead(j, where).get(i)) is not None
                    and (near(j, d[0]) or self._wants_forwards(j))]
            out += [(j, "queue") for j, d in self.behind(i, where).items()
                    if near(j, d) or self._wants_forwards(j)]
        ahead_side = END if forward else START
        centres = (self.system._values[0][self.rows] + self.offsets)[:, :2]
        for side in (START, END):
            vertex = self._switch(k, side)
            if vertex is None:
                continue
            line = self._zone_line(k, side, rider.zone_gap)
            inside = self._inside(k, side, s, line)
            at = (s >= line - 1e-3) if side == END else (s <= line + 1e-3)
            if not (inside or (at and side == ahead_side)):
                continue
            why = "footprints" if inside else "switch"
            for j, (kj, sj, _) in enumerate(where):
                other = self.movers[j]._rider
                if inside and side == END and self._merges_behind((k, s, rider), (kj, sj, other),
                                                                  vertex):
                    out.append((j, "merge"))
                if why == "footprints" and math.dist(centres[i], centres[j]) > HOSE + CLEARANCE:
                    continue  # too far from each other for their footprints to be in the way
                for side_j in (START, END):
                    if j == i or self._switch(kj, side_j) != vertex or \
                            self._related((k, side, rider), (kj, side_j, other)):
                        continue
                    if self._inside(kj, side_j, sj, self._zone_line(kj, side_j, other.zone_gap)):
                        out.append((j, why))  # inside its zone: it holds the switch
        return out

    def _related(self, a: tuple[int, int, Rider], b: tuple[int, int, Rider]) -> bool:
        """Whether two movers at one switch (track, side of it, rider) keep their gap as a
        pair there: one passes it from the end of its track onto the other's, at whose start
        the other is, unless that one goes back over the seam there (D-147); on one track
        always, except round the seam of a closed one, where one at its end leaves it."""
        (ka, side_a, ra), (kb, side_b, rb) = a, b
        na, nb = self._next_track(ra), self._next_track(rb)
        if ka != kb:
            return (side_a == END and na == kb and side_b == START
                    and not backwards(rb.route)) or \
                (side_b == END and nb == ka and side_a == START and not backwards(ra.route))
        leaves = (side_a == END and na not in (None, ka)) or \
            (side_b == END and nb not in (None, kb))
        return not (self.net.paths[ka].closed and leaves)

    def _merges_behind(self, a: tuple[int, float, Rider], b: tuple[int, float, Rider],
                       vertex: object) -> bool:
        """Whether mover a, inside its zone at the end of its track, follows mover b through
        the merge ``vertex`` within their gap: b is inside its zone at the end of its own
        track there, nearer the switch, and both go on the same way (traffic.py keeps the
        two as a pair through it)."""
        (ka, sa, ra), (kb, sb, rb) = a, b
        if ka == kb or self._switch(kb, END) != vertex or \
                not self._inside(kb, END, sb, self._zone_line(kb, END, rb.zone_gap)):
            return False
        way = self._path_next(ka, ra)
        if way is None or way != self._path_next(kb, rb):
            return False
        da, db = self.net.lengths[ka] - sa, self.net.lengths[kb] - sb
        return db <= da <= db + max(ra.gap, rb.gap) + 1e-3

    def _path_next(self, k: int, rider: Rider) -> int | None:
        """The next track of the mover's path: of its route, else the one way on."""
        following = self.net.successors[k]
        if len(rider.route) > 1:
            return self._next_track(rider)
        if self.net.paths[k].closed:
            return k
        return following[0] if len(following) == 1 else None

    def _next_track(self, rider: Rider) -> int | None:
        """The next track on the rider's route (from the end of its track: none on a way
        back over a loop's seam)."""
        legs = ahead_legs(rider.route)
        return self.index[id(legs[1].track)] if len(legs) > 1 else None

    def _wants_forwards(self, j: int) -> bool:
        """Mover ``j`` waits with a MoveOnTrack to a point ahead of it."""
        latest = self._latest(j)
        if latest is None or latest.target is None or not latest.command.busy:
            return False
        return self._forwards(j)

    def _forwards(self, j: int) -> bool:
        """Whether the running command of mover ``j`` goes forwards: its target on its
        odometer (the traffic's) is not behind it (a modulo move to a point of its own
        closed track may go either way)."""
        slot = self.movers[j]._rider.slot
        return not self.traffic.target[slot] < self.traffic.p[slot]

    def _switch(self, k: int, side: int) -> object:
        track = self.tracks[k]
        return track.network.switches(track)[side]

    def _inside(self, k: int, side: int, s: float, line: float) -> bool:
        """Whether arc length ``s`` on track ``k`` is inside its zone at ``side`` beyond
        ``line``: anywhere on the track when the zone covers all of it (traffic.py)."""
        if side == END:
            return s > line + 1e-6 or line <= 1e-9
        return s < line - 1e-6 or line >= self.net.lengths[k] - 1e-9

    def _zone_line(self, k: int, side: int, gap: float) -> float:
        """Where the zone of track ``k`` at its start (end) switch begins (traffic.py), for a
        rider whose zones are measured with ``gap`` (its ``zone_gap``: a larger gap of a new
        command counts only once it is outside the wider zones, D-136)."""
        reach = max(self.tracks[k].collision_ranges[side], gap)
        return reach if side == START else self.net.lengths[k] - reach


def _on_tracks(where: list[tuple[int, float, float]]) -> dict[int, list[int]]:
    on: dict[int, list[int]] = {}
    for j, (k, _, _) in enumerate(where):
        on.setdefault(k, []).append(j)
    return on


def _same_path(old: tuple[int, ...], new: tuple[int, ...]) -> bool:
    """Whether ``new`` is ``old`` after the follower or the one ahead (or both) moved on to
    the next track: the two distances are measured along the same way."""
    for cut in (0, 1):
        rest = old[cut:]
        if rest and new[:len(rest)] == rest and len(new) - len(rest) in (0, 1):
            return True
    return False


# -- how commands ended ------------------------------------------------------------------------

def _check_endings(run: Run) -> None:
    """Property 3 (module docstring), once every mover stands."""
    waits: dict[int, list[tuple[int, str]]] = {}
    for n, sent in enumerate(run.sent):
        command = sent.command
        what = f"{command.kind} of mover {sent.mover} sent at cycle {sent.cycle}"
        if command.phase is CommandPhase.ABORTED:
            assert any(s.mover == sent.mover for s in run.sent[n + 1:]), \
                f"{what} was aborted, but by no later command of its mover\n{run.scenario}"
        elif command.error:
            assert command.error_id != ErrorId.NO_ERROR and command.message, \
                f"{what} ended in Error without a reason\n{run.scenario}"
        elif command.busy:
            if command.kind in GEARS and command.active:
                continue  # coupled until another command (§6.2.8)
            assert command.kind == "MoveOnTrack" and command.active, \
                f"{what} is still {command.phase.name}\n{run.scenario}"
            blockers = run.blockers(sent)
            assert blockers, (f"{what} to {sent.target} waits at {run.where(sent.mover)} "
                              f"(track, s, v) for no mover\n{run.scenario}")
            waits[sent.mover] = blockers
    own = {i: [(j, why) for j, why in blockers if why != "switch"]
           for i, blockers in waits.items()}
    for i, blockers in waits.items():
        for j, why in blockers:
            if why == "switch" and _reaches(waits, j, i) and not _stuck(own, j, waits):
                raise AssertionError(f"deadlock: mover {i} waits at a switch for mover {j}, "
                                     f"which waits for mover {i} in turn: {waits}\n"
                                     f"{run.scenario}")


def _stuck(own: dict[int, list[tuple[int, str]]], start: int,
           waits: dict[int, list[tuple[int, str]]]) -> bool:
    """Whether mover ``start`` waits, through the program's own waits (queues, head on,
    footprints), for a ring of them or for a mover that stands for good (one with no busy
    MoveOnTrack: idle, or geared to a master that stands): stuck whatever the switches
    do, so the mover that waits for it at a switch waits in a chain, not a deadlock."""
    return any(m not in waits or any(_reaches(own, j, m) for j, _ in own.get(m, ()))
               for m in _waited_for(own, start))


def _waited_for(own: dict[int, list[tuple[int, str]]], start: int) -> set[int]:
    """The movers ``start`` waits for through ``own``, itself included."""
    seen, queue = {start}, deque([start])
    while queue:
        for j, _ in own.get(queue.popleft(), ()):
            if j not in seen:
                seen.add(j)
                queue.append(j)
    return seen


def _reaches(waits: dict[int, list[tuple[int, str]]], start: int, goal: int) -> bool:
    seen, queue = {start}, deque([start])
    while queue:
        i = queue.popleft()
        if i == goal:
            return True
        for j, _ in waits.get(i, ()):
            if j not in seen:
                seen.add(j)
                queue.append(j)
    return False


# -- the properties ----------------------------------------------------------------------------

SLOW = [HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large]


@settings(max_examples=15, deadline=None, suppress_health_check=SLOW,
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(scenario=scenarios())
def test_random_networks_keep_gaps_and_footprints_apart_and_commands_end(scenario: Scenario):
    """Properties 1-3 (module docstring), 15 scenarios of up to 30 movers. No shrinking:
    one run takes up to seconds, so shrinking a failure can take many minutes; the failure
    names the cycle and the movers and prints the scenario, which the slow variant (or a
    plain ``Run(scenario).play()``) replays."""
    Run(scenario).play()


@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=SLOW)
@given(scenario=scenarios())
def test_random_networks_many(scenario: Scenario):
    """The same with 300 scenarios, shrinking failures."""
    Run(scenario).play()


@settings(max_examples=40, deadline=None, suppress_health_check=SLOW)
@given(drawn=networks())
def test_random_networks_stay_curvature_continuous_across_connections(drawn):
    """Property 4: along every track and from each track into each of its successors the
    heading turns at the rate ``frame_at`` gives as curvature, and position, heading and
    curvature run on across every joint and every connection (the heading to ``KINK``)."""
    net, _ = drawn
    step = 1e-2  #: [mm] finite-difference step
    for k, path in enumerate(net.paths):
        dense = np.linspace(0.0, path.length, 2001)
        rate = np.max(np.abs(np.diff(path.curvatures_at(dense)))) / (dense[1] - dense[0])
        tolerance = 1e-6 + 2 * rate * step + KINK / (2 * step)
        s = np.concatenate([[p.start for p in path.pieces[1:]],
                            np.linspace(step, path.length - step, 101)])
        _assert_turn_rate(path, s - step, path, s + step, path.curvatures_at(s), tolerance,
                          step)
        for b in [p.start for p in path.pieces[1:]]:
            x, y, heading, curvature = path.frame_at(np.array([b - 1e-9, b + 1e-9]))
            assert math.hypot(x[1] - x[0], y[1] - y[0]) <= 3e-9
            assert abs(math.remainder(heading[1] - heading[0], math.tau)) <= KINK
            assert abs(curvature[1] - curvature[0]) <= 1e-7
        end = path.end_pose
        for j in net.successors[k]:
            start = net.paths[j].start_pose
            where = f"from track {k} into track {j} at ({end.x:.3f}, {end.y:.3f})"
            assert math.hypot(end.x - start.x, end.y - start.y) <= 1e-9, where
            assert abs(math.remainder(end.heading - start.heading, math.tau)) <= KINK, where
            assert abs(end.curvature - start.curvature) <= 1e-9, where
            _assert_turn_rate(path, np.array([path.length - step]), net.paths[j],
                              np.array([step]), np.array([end.curvature]), tolerance, step)


def _assert_turn_rate(before: TrackPath, s0: np.ndarray, after: TrackPath, s1: np.ndarray,
                      curvature: np.ndarray, tolerance: float, step: float) -> None:
    """The heading turns from ``before`` at ``s0`` to ``after`` at ``s1`` (two steps on) at
    the rate ``curvature``."""
    turned = np.remainder(after.headings_at(s1) - before.headings_at(s0) + math.pi,
                          math.tau) - math.pi
    np.testing.assert_allclose(turned / (2 * step), curvature, rtol=0, atol=tolerance)


# -- failures found, as plain reproducers ------------------------------------------------------


def _joined(rt: om.Runtime, *places: tuple[MC_PlanarTrack, float]) -> list[MC_PlanarMover]:
    """Movers joined where they stand: on ``track`` at arc length s, turned along it."""
    movers = []
    for track, s in places:
        p = track.get_position_at(s)
        movers.append(MC_PlanarMover(rt, PlanarMoverParameters(
            initial_position=MoverVector(p.x, p.y, c=p.c), minimum_position=C_LOW,
            maximum_position=C_HIGH)))
    for mover in movers:
        mover.enable()
    rt.run(0.005)
    joins = [m.join_track(track) for m, (track, _) in zip(movers, places, strict=True)]
    rt.run_until(lambda: all(j.done for j in joins), timeout=1.0)
    return movers


def _geared_on_a_line(rt: om.Runtime, length: float) -> tuple[MC_PlanarMover, MC_PlanarMover,
                                                               om.Axis, Any]:
    """Movers a at 0 and b at 500 on a line track of ``length``; b geared 1:1 (gap 300) to
    an axis standing at 500, 0.1 s after the gear-in."""
    track = MC_PlanarTrack(rt)
    track.append_line(PositionXYC(0.0, 0.0), PositionXYC(length, 0.0))
    _enabled(rt, track)
    a, b = _joined(rt, (track, 0.0), (track, 500.0))
    axis = rt.add_axis("master")
    axis.power()
    axis.move_absolute(500.0, 500.0)
    rt.run(2.0)
    gear = b.gear_in_pos_on_track(axis, None, 500.0, 500.0, track,
                                  options=ST_GearInPosOnTrackOptions(gap=300.0))
    rt.run(0.1)
    return a, b, axis, gear


def _enabled(rt: om.Runtime, *tracks: MC_PlanarTrack) -> None:
    for track in tracks:
        track.enable()
    rt.run(0.003)
    assert all(t.state is PlanarState.ENABLED for t in tracks)


def _overlap(a: MC_PlanarMover, b: MC_PlanarMover) -> bool:
    pa, pb = a.position, b.position
    return bool(overlaps(pa.x, pa.y, math.radians(pa.c), pb.x, pb.y, math.radians(pb.c)))


def test_two_movers_standing_in_the_collision_ranges_of_one_switch_do_not_collide():
    """A trunk and two branches from its end: a straight one and a left arc that stays in
    the straight's hose (automatic collision ranges: both branches whole). Mover a joins at
    100 on the straight, mover b at 300 on the arc: both inside their collision ranges of
    the switch, 200 mm apart. Mover a alone moves on along its branch, towards b; b stands.
    §6.2.2: a mover whose braking interval is within its range coordinates with every other
    such mover at the switch, so a must stop short of b. It drove into b: holders were
    never stopped. Fixed (D-136): conflicting holders keep their footprints apart."""
    rt = om.Runtime(CYCLE)
    trunk, straight, curve = (MC_PlanarTrack(rt, n) for n in ("trunk", "straight", "curve"))
    trunk.append_line(PositionXYC(-400.0, 0.0), PositionXYC(0.0, 0.0))
    straight.start_from_track(trunk)
    straight.append_line(PositionXYC(0.0, 0.0), PositionXYC(300.0, 0.0))
    curve.start_from_track(trunk)
    r, sweep = 330.0, 1.2
    curve.append_circle(PositionXYC(0.0, 0.0),
                        PositionXYC(r * math.sin(sweep), r - r * math.cos(sweep)),
                        PositionXYC(0.0, r), False)
    _enabled(rt, trunk, straight, curve)
    assert straight.collision_ranges[0] == pytest.approx(straight.get_length())
    a, b = _joined(rt, (straight, 100.0), (curve, 300.0))
    assert not _overlap(a, b)
    move = a.move_on_track(None, 250.0)
    for _ in range(1000):
        rt.step()
        assert not _overlap(a, b), (a.position, b.position, move.phase)


def test_a_larger_gap_does_not_let_a_mover_skip_the_entry_to_a_switch():
    """Two feeders end at U (a merge; automatic collision ranges 302 mm at their ends).
    Mover a, on the left feeder, enters its zone and drives through the switch onto U.
    Mover b stands on the right feeder 327 mm before its end: outside its zone with the
    200 mm of JoinTrack, and with gap 200 its MoveOnTrack waits at the zone boundary until a
    is through. With gap 369 its zone reaches 369 mm: it was inside at once, held the switch
    together with a, and drove into a at the merge (§6.2.2: it must wait). Fixed (D-136):
    its zones keep the smaller gap until it is outside the wider ones."""
    rt = om.Runtime(CYCLE)
    p = PositionXYC
    merge, left, right = MC_PlanarTrack(rt, "U"), MC_PlanarTrack(rt, "left"), \
        MC_PlanarTrack(rt, "right")
    merge.append_line(p(0.0, 0.0), p(800.0, 0.0))
    left.append_line(p(-1200.0, 400.0), p(-500.0, 400.0))
    left.end_at_track(merge)
    right.append_line(p(-1200.0, -400.0), p(-500.0, -400.0))
    right.end_at_track(merge)
    _enabled(rt, merge, left, right)
    assert 200.0 < right.collision_ranges[1] < 327.0
    a, b = _joined(rt, (left, left.get_length() - 600.0), (right, right.get_length() - 327.0))
    a.move_on_track(merge, 400.0)
    rt.run(0.3)
    b.move_on_track(merge, 100.0, options=ST_MoveOnTrackOptions(gap=369.0))
    for _ in range(3000):
        rt.step()
        assert not _overlap(a, b), (a.position, b.position)


def _braking_hard(rt: om.Runtime) -> MC_PlanarMover:
    """Mover a runs at 2000 mm/s towards 1900 behind mover b at 1200, and gap control brakes
    it with the mover's maximum dynamics (20000 mm/s², more than the command's 10000) to stop
    one gap behind b: a, caught while it brakes so."""
    track = MC_PlanarTrack(rt)
    track.append_line(PositionXYC(0.0, 0.0), PositionXYC(2000.0, 0.0))
    _enabled(rt, track)
    a, _ = _joined(rt, (track, 0.0), (track, 1200.0))
    a.move_on_track(None, 1900.0)
    rt.run_until(lambda: a.mc_to_plc.set_on_track.set_acc < -10000.5, timeout=2.0)
    rt.run(0.075)
    s = a.mc_to_plc.set_on_track
    assert s.set_velo > 0.0 and s.set_acc < -15000.0
    return a


def _lowest(rt: om.Runtime, mover: MC_PlanarMover, cycles: int = 2000) -> float:
    lowest = mover.mc_to_plc.set_on_track.set_pos
    for _ in range(cycles):
        rt.step()
        lowest = min(lowest, mover.mc_to_plc.set_on_track.set_pos)
    return lowest


def test_a_move_on_track_to_a_point_ahead_never_drives_the_mover_back():
    """While gap control brakes mover a hard (``_braking_hard``), the same MoveOnTrack is
    sent again. The mover must go on forwards (or stand); it turned round and drove back
    38 mm at up to 480 mm/s, towards whoever follows it (found by the properties: a mover
    behind it undercut its gap so). Fixed (D-137): it brakes on with gap control's brake
    first."""
    rt = om.Runtime(CYCLE)
    a = _braking_hard(rt)
    start = a.mc_to_plc.set_on_track.set_pos
    a.move_on_track(None, 1900.0)
    assert _lowest(rt, a) >= start - GAP_TOLERANCE


def test_a_halt_while_gap_control_brakes_hard_never_drives_the_mover_back():
    """As above with a Halt (its deceleration is the command's 10000 mm/s²): planned from
    that state with the Halt's jerk, the stop turned the mover round by 39 mm. It stops with
    gap control's brake instead (D-137)."""
    rt = om.Runtime(CYCLE)
    a = _braking_hard(rt)
    start = a.mc_to_plc.set_on_track.set_pos
    halt = a.halt()
    assert _lowest(rt, a) >= start - GAP_TOLERANCE
    assert halt.done


def test_a_mover_moving_backwards_keeps_its_own_gap_to_the_mover_behind():
    """§6.1.9/§6.2.2: a mover keeps its gap to the mover in front of it in its direction of
    travel. Mover b moves backwards with gap 300 towards mover a, which stands at 0 (gap 200
    from JoinTrack): b stops 300 mm from a. Found by the properties: a pair kept the gap of
    the mover behind it (fixed in 6976c58)."""
    rt = om.Runtime(CYCLE)
    track = MC_PlanarTrack(rt)
    track.append_line(PositionXYC(0.0, 0.0), PositionXYC(1200.0, 0.0))
    _enabled(rt, track)
    a, b = _joined(rt, (track, 0.0), (track, 500.0))
    back = b.move_on_track(None, 0.0, options=ST_MoveOnTrackOptions(gap=300.0))
    closest = math.inf
    for _ in range(3000):
        rt.step()
        closest = min(closest, b.mc_to_plc.set_on_track.set_pos - a.mc_to_plc.set_on_track.set_pos)
    assert back.busy  # waits behind a: documented
    assert closest >= 300.0 - GAP_TOLERANCE


def test_a_geared_slave_moving_backwards_keeps_its_own_gap_to_the_mover_behind():
    """As above with a slave: mover b, geared 1:1 to an axis with gap 300 and in sync, follows
    the axis back from 500 to 0 towards mover a at 0 (gap 200 from JoinTrack). It must stay
    300 mm from a (and lose sync, §6.2.8). Found by the properties: first it came to 200
    (the pair kept a's gap for a geared leader, fixed in 2b4c8fe); now the gap holds it at
    300, but at rest (v = 0) the pair had a's 200 for a cycle, the sync stepped back, the
    next cycle braked it: 6e-5 mm closer every three cycles, 0.16 mm inside its gap in 4 s.
    Fixed (D-137): a proposal that goes back counts as going back."""
    rt = om.Runtime(CYCLE)
    a, b, axis, gear = _geared_on_a_line(rt, 1200.0)
    assert gear.in_sync
    axis.move_absolute(0.0, 200.0)
    closest = math.inf
    for _ in range(4000):
        rt.step()
        closest = min(closest, b.mc_to_plc.set_on_track.set_pos - a.mc_to_plc.set_on_track.set_pos)
    assert gear.active
    assert closest >= 300.0 - GAP_TOLERANCE


def test_a_geared_slave_turning_back_does_not_close_in_on_the_mover_behind_within_its_gap():
    """Mover b, geared 1:1 to an axis with gap 300, runs forwards at 300 mm/s; mover a
    follows it with its own gap 200, about 209 mm behind. The axis turns back (20000
    mm/s²): b must not move back towards a, which is within b's gap already (§6.1.9: each
    keeps its own gap in its direction of travel). Found by the properties: b's pair got
    its gap only once its sync stepped back, from a state in which even its hardest brake
    turns it round, so it crept 7 µm back into its gap. Fixed (D-137): it brakes before it
    starts back."""
    rt = om.Runtime(CYCLE)
    a, b, axis, _ = _geared_on_a_line(rt, 2000.0)
    a.move_on_track(None, 1900.0)
    axis.move_absolute(1500.0, 300.0)
    rt.run(1.0)
    assert 200.0 < b.mc_to_plc.set_on_track.set_pos - a.mc_to_plc.set_on_track.set_pos < 300.0
    axis.move_absolute(0.0, 200.0, acceleration=20000.0, deceleration=20000.0)
    last = b.mc_to_plc.set_on_track.set_pos
    for _ in range(3000):
        rt.step()
        now = b.mc_to_plc.set_on_track.set_pos
        assert now >= last - MOTION_NOISE, (now - last, now - a.mc_to_plc.set_on_track.set_pos)
        last = now


def test_a_slave_synchronises_after_its_master_mover_stopped():
    """§6.2.9 with both movers at their default dynamics: the master cruises at 2000 mm/s
    when the slave gears in (sync positions 1000 and 1000: coupled 1:1), then stops at 1900;
    the slave synchronises and stands at 1900 too (§6.2.8; Early: as early as its dynamics
    allow). Found by the properties: a sync planned while the master ran at the slave's
    velocity limit got a relative velocity limit of 2 mm/s (1e-3 of it) and was never
    planned again, so the slave crept after the master for minutes (fixed in 6976c58)."""
    rt = om.Runtime(CYCLE)
    master_track, slave_track = MC_PlanarTrack(rt), MC_PlanarTrack(rt)
    master_track.append_line(PositionXYC(0.0, 600.0), PositionXYC(2000.0, 600.0))
    slave_track.append_line(PositionXYC(0.0, 0.0), PositionXYC(2000.0, 0.0))
    _enabled(rt, master_track, slave_track)
    master, slave = _joined(rt, (master_track, 100.0), (slave_track, 100.0))
    move = master.move_on_track(None, 1900.0)
    rt.run(0.45)
    assert master.mc_to_plc.set_on_track.set_velo == pytest.approx(2000.0)
    gear = slave.gear_in_pos_on_track_with_master_mover(master, None, 1000.0, master_track,
                                                        1000.0, slave_track)
    rt.run(5.0)
    assert move.done and gear.active
    assert slave.mc_to_plc.set_on_track.set_pos == pytest.approx(1900.0, abs=1e-6)


def _stadium_with_branch(rt: om.Runtime) -> tuple[MC_PlanarTrack, MC_PlanarTrack]:
    """A closed stadium (its seam at (250, 0) after the corner rounding) and a branch that
    starts from it: the seam is a switch."""
    loop, branch = MC_PlanarTrack(rt, "loop"), MC_PlanarTrack(rt, "branch")
    loop.append_line(PositionXYC(0.0, 0.0), PositionXYC(1000.0, 0.0))
    loop.append_circle(PositionXYC(1000.0, 0.0), PositionXYC(1000.0, 800.0),
                       PositionXYC(1000.0, 400.0), False)
    loop.append_line(PositionXYC(1000.0, 800.0), PositionXYC(0.0, 800.0))
    loop.append_circle(PositionXYC(0.0, 800.0), PositionXYC(0.0, 0.0), PositionXYC(0.0, 400.0),
                       False)
    loop.close_loop()
    branch.start_from_track(loop)
    branch.append_line(PositionXYC(500.0, -400.0), PositionXYC(1200.0, -400.0))
    _enabled(rt, loop, branch)
    return loop, branch


def test_a_mover_keeps_its_gap_across_the_seam_of_a_closed_track_with_a_switch():
    """On a closed track s = length is s = 0 (§6.1.9 modulo positions). Mover a stands at
    100, just past the seam; mover b moves to length - 10, 110 mm behind a round the loop.
    It stops one gap (200) behind a. Found by the properties: the path ahead ended at the
    seam because it is a switch, and riders of one track never conflict there, so b drove
    into a (fixed in 2b4c8fe)."""
    rt = om.Runtime(CYCLE)
    loop, _ = _stadium_with_branch(rt)
    length = loop.get_length()
    a, b = _joined(rt, (loop, 100.0), (loop, length - 700.0))
    b.move_on_track(None, length - 10.0)
    for _ in range(2000):
        rt.step()
        assert not _overlap(a, b), (a.position, b.position)
    assert b.mc_to_plc.set_on_track.set_pos == pytest.approx(length + 100.0 - 200.0, abs=1e-6)


def test_a_mover_leaving_a_closed_track_at_its_seam_keeps_clear_of_one_just_past_it():
    """The stadium with a branch from its seam: mover a stands at 100 on the loop, just past
    the seam and inside the loop's collision range there. Mover b comes round the loop and
    turns onto the branch at the seam: a is not on b's way, so b must wait at its last safe
    stop (§6.2.2) until a has gone; it passed 100 mm from a's centre, because riders of one
    track never conflicted. Fixed (D-136)."""
    rt = om.Runtime(CYCLE)
    loop, branch = _stadium_with_branch(rt)
    assert loop.collision_ranges[0] > 100.0
    a, b = _joined(rt, (loop, 100.0), (loop, loop.get_length() - 700.0))
    b.move_on_track(branch, 300.0)
    for _ in range(3000):
        rt.step()
        assert not _overlap(a, b), (a.position, b.position)


def test_a_mover_leaving_at_the_seam_keeps_its_gap_to_one_reversing_over_it():
    """The stadium with a branch from its seam: mover h at length - 700 drives onto the
    branch, mover r at 100 reverses over the seam (Negative to length - 1000, gap 500). The
    two meet head on across the seam; r, going back, is h's leader with the larger gap
    (§6.1.9), although h's own way turns off at the seam: the gap holds along the loop at
    every cycle and both wait (D-147). Paired only once r had crossed, h stood 446 mm
    from it then, inside r's gap."""
    rt = om.Runtime(CYCLE)
    loop, branch = _stadium_with_branch(rt)
    length = loop.get_length()
    h, r = _joined(rt, (loop, length - 700.0), (loop, 100.0))
    turn_off = h.move_on_track(branch, 300.0)
    back = r.move_on_track(None, length - 1000.0, options=ST_MoveOnTrackOptions(
        gap=500.0, direction=ModuloDirection.NEGATIVE))
    closest = math.inf
    for _ in range(5000):
        rt.step()
        assert not _overlap(h, r), (h.position, r.position)
        closest = min(closest, (r.mc_to_plc.set_on_track.set_pos
                                - h.mc_to_plc.set_on_track.set_pos) % length)
    assert closest >= 500.0 - GAP_TOLERANCE
    assert turn_off.busy and back.busy  # head on
    assert r.mc_to_plc.set_on_track.set_pos > length - 700.0  # r crossed the seam


def _stadium_with_feeder(rt: om.Runtime) -> tuple[MC_PlanarTrack, MC_PlanarTrack]:
    """The closed stadium and a feeder that ends at its seam (a switch)."""
    p = PositionXYC
    loop, feeder = MC_PlanarTrack(rt, "loop"), MC_PlanarTrack(rt, "feeder")
    loop.append_line(p(0.0, 0.0), p(1000.0, 0.0))
    loop.append_circle(p(1000.0, 0.0), p(1000.0, 800.0), p(1000.0, 400.0), False)
    loop.append_line(p(1000.0, 800.0), p(0.0, 800.0))
    loop.append_circle(p(0.0, 800.0), p(0.0, 0.0), p(0.0, 400.0), False)
    loop.close_loop()
    feeder.append_line(p(-900.0, -400.0), p(-500.0, -400.0))
    feeder.end_at_track(loop)
    _enabled(rt, loop, feeder)
    return loop, feeder


def test_a_feeder_does_not_follow_a_mover_that_reverses_over_the_seam():
    """The stadium with a feeder that ends at its seam: mover g, 500 mm before the end of
    the feeder, drives onto the loop; mover r at 100, just past the seam, reverses over it
    (Negative to length - 600). r does not go where g would follow it: it comes back over
    the switch onto the loop's end, beside the feeder, so the two meet there (D-147). g
    waits at its last safe stop until r has gone on back, and both arrive. As g's leader
    (the way onto the loop) r let g into the switch zone behind it; crossing, r met g
    there and the two stood locked ~193 mm apart."""
    rt = om.Runtime(CYCLE)
    loop, feeder = _stadium_with_feeder(rt)
    length = loop.get_length()
    g, r = _joined(rt, (feeder, feeder.get_length() - 500.0), (loop, 100.0))
    onto = g.move_on_track(loop, 400.0)
    back = r.move_on_track(None, length - 600.0, options=ST_MoveOnTrackOptions(
        direction=ModuloDirection.NEGATIVE))
    for _ in range(6000):
        rt.step()
        assert not _overlap(g, r), (g.position, r.position)
    assert onto.done and back.done
    assert r.mc_to_plc.set_on_track.set_pos == pytest.approx(length - 600.0, abs=1e-9)
    assert g.mc_to_plc.set_on_track.set_pos == pytest.approx(400.0, abs=1e-9)


def test_a_holder_whose_route_loops_back_still_keeps_the_switch():
    """A loop with a bypass: T splits into O (an S-bend aside) and S (straight on), both end
    at U, and R leads from U back to T. Mover a stands at 310 on O, inside O's collision
    range at the switch (it waits behind b with gap 250 on its way round to T). Mover c
    then drives from T onto S. a holds the switch and c's track is off a's way near it
    (§6.2.2): c waits at its last safe stop. Found by the properties: c drove past a and
    into it, because a's route, round the loop, also holds T and a holder whose route holds
    the other's track counted as its pair (fixed in 2b4c8fe)."""
    rt = om.Runtime(CYCLE)
    p = PositionXYC
    trunk, merge, aside, straight, back = (MC_PlanarTrack(rt, n) for n in "TUOSR")
    trunk.append_line(p(-900.0, 0.0), p(0.0, 0.0))
    merge.append_line(p(1400.0, 0.0), p(1700.0, 0.0))
    aside.start_from_track(trunk)
    aside.append_line(p(500.0, -430.0), p(1000.0, -430.0))
    aside.end_at_track(merge)
    straight.start_from_track(trunk)
    straight.append_line(p(500.0, 0.0), p(900.0, 0.0))
    straight.end_at_track(merge)
    back.start_from_track(merge)
    back.append_line(p(1940.0, -240.0), p(1940.0, -690.0))
    back.append_line(p(1700.0, -930.0), p(-900.0, -930.0))
    back.append_line(p(-1140.0, -690.0), p(-1140.0, -240.0))
    back.end_at_track(trunk)
    _enabled(rt, trunk, merge, aside, straight, back)
    a, b, c = _joined(rt, (aside, 110.0), (aside, 560.0), (trunk, 440.0))
    round_ = a.move_on_track(trunk, 300.0, options=ST_MoveOnTrackOptions(gap=250.0))
    rt.run(0.5)
    assert round_.busy and a.mc_to_plc.set_on_track.set_pos == pytest.approx(310.0)
    assert aside.collision_ranges[0] > 310.0
    c.move_on_track(straight, 300.0)
    for _ in range(3000):
        rt.step()
        assert not _overlap(a, c), (a.position, c.position)


#: Scenarios the random networks found whose fixes have no smaller reproducer, as drawn
#: (D-136); each with what went wrong (each fails without its fix).
FOUND = {
    # a mover just past the seam of a closed track, whose route goes round onto the
    # branch, counted as the pair of a mover on the branch and drove into it: a
    # route relates two movers only where one leaves its track
    "lap_later": Scenario(
        layout=((('circle', 0.0, 0.0, 0.0, 0.0, 1318.454871, 931.507233, False), ('close',)),
                (('from', 0), ('line', 181.597214, -1556.797047, 597.05711, -2144.838776)),
                (('line', -2861.226876, 2052.628711, -2070.876867, 933.967704), ('end', 0))),
        movers=((2, 2790.0, 190.0), (2, 930.0, 190.0), (0, 3100.0, 210.0), (1, 930.0, 210.0),
                (0, 2790.0, 210.0), (2, 1240.0, 190.0), (0, 620.0, 250.0), (0, 0.0, 250.0),
                (0, 3410.0, 190.0), (0, 5580.0, 190.0), (0, 1550.0, 190.0), (1, 620.0, 250.0),
                (1, 310.0, 310.0), (0, 9610.0, 250.0), (0, 6820.0, 310.0), (0, 4960.0, 310.0),
                (0, 930.0, 210.0), (1, 1860.0, 310.0), (0, 4650.0, 310.0), (0, 8370.0, 190.0),
                (2, 1550.0, 190.0)),
        rounds=((162,
                 (('move', 28, 9, 0.6017821843885626), ('move', 16, 8, 5e-324), ('halt', 16),
                  ('move', 16, 1, 0.7515015191575565),
                  ('gear mover', 29, 15, 0.32828573561960434, 4.891991630799652e-162))),)),
    # a mover at the far end of a feeder whose collision range is all of it was
    # no holder, and a mover on another feeder drove into it
    "whole_track_zone": Scenario(
        layout=((('line', 0.0, 0.0, 561.10691, -0.0),),
                (('line', -500.0, -250.0, -300.0, -250.0), ('end', 0)),
                (('line', -250.0, 0.0, 0.0, 0.0), ('end', 0)),
                (('circle', -200.221444, 51.124928, 0.0, 0.0, 0.0, 417.627823, False), ('end', 0))),
        movers=((3, 0.0, 237.0), (1, 357.0, 257.0), (0, 357.0, 297.0), (1, 0.0, 297.0)),
        rounds=((130,
                 (('halt', 29),
                  ('gear axis', 22, 1640.4208648530102, 800.0, 354.56182864661594,
                   0.8940537512672224),
                  ('gear axis', 12, 1768.117948655286, 120.18932606433157, 2.5182486390013208e-284,
                   0.9210668034879235),
                  ('move', 3, 3, 0.9406459497697335), ('move', 8, 0, 0.4531910980671513),
                  ('move', 25, 4, 1.8500229903046734e-109),
                  ('gear mover', 29, 24, 0.8356756590458765, 1e-10), ('halt', 29))),
                (1024,
                 (('move', 25, 5, 0.2511848333625704), ('move', 29, 6, 0.0),
                  ('move', 22, 9, 0.3841754237318339))),
                (105,
                 (('move', 29, 0, 0.3515380616490165), ('move', 25, 4, 1.8500229903046734e-109),
                  ('gear mover', 5, 9, 0.4483928859324934, 0.8124519097599747),
                  ('gear mover', 25, 5, 0.7483812224892988, 4.2624453998909074e-27),
                  ('move', 28, 8, 0.9305624125335585),
                  ('gear axis', 20, 274.4695347851374, 727.4813217306295, 461.0684251554483,
                   0.7712552786024713),
                  ('gear axis', 8, 490.37157602002344, 720.0, 279.1892760242221,
                   2.5182486390013208e-284))),
                (265,
                 (('move', 29, 0, 0.3515380616490165), ('move', 25, 4, 1.8500229903046734e-109),
                  ('gear mover', 5, 9, 0.4483928859324934, 0.8124519097599747),
                  ('gear mover', 25, 5, 0.7483812224892988, 4.2624453998909074e-27),
                  ('move', 28, 8, 0.9305624125335585),
                  ('gear axis', 20, 274.4695347851374, 727.4813217306295, 461.0684251554483,
                   0.7712552786024713),
                  ('gear axis', 8, 490.37157602002344, 720.0, 279.1892760242221,
                   2.5182486390013208e-284))))),
    # two movers placed in the zones of a merge drove side by side; when the
    # first passed onto the merged track, the other was inside its gap
    "merge_gap": Scenario(
        layout=((('line', -518.450289, -807.438486, 0.0, 0.0),),
                (('line', 990.554507, 1542.697241, 1282.317752, 1997.091572),),
                (('from', 0), ('line', 766.844917, 398.91087, 978.907135, 729.178206), ('end', 1)),
                (('from', 0), ('line', 353.362071, 550.328819, 645.125316, 1004.723151),
                 ('end', 1)),
                (('from', 0), ('line', -147.459692, 985.979109, 145.127876, 1441.657247),
                 ('end', 1))),
        movers=((2, 1750.0, 350.0), (4, 2100.0, 230.0), (3, 1750.0, 250.0), (2, 700.0, 250.0),
                (1, 350.0, 350.0), (4, 700.0, 290.0), (0, 350.0, 290.0), (3, 700.0, 350.0),
                (3, 1050.0, 290.0), (2, 350.0, 250.0), (4, 1750.0, 290.0), (2, 1050.0, 290.0)),
        rounds=((128,
                 (('move', 22, 9, 0.6272875362704694),
                  ('gear mover', 26, 19, 0.8429284101924013, 0.10322306306565479),
                  ('gear mover', 12, 10, 0.8684883612966239, 0.3586871446183422), ('halt', 10))),
                (121,
                 (('gear axis', 23, 74.84895431682449, 504.95229767787725, 83.57216184603278,
                   0.7985652306948245),)),
                (235,
                 (('gear axis', 1, 381.1766034079304, 145.28293137713098, 632.0148901856722,
                   0.3563919892986776),
                  ('move', 9, 3, 0.177922060255201), ('move', 0, 5, 0.9592799336282503),
                  ('halt', 15), ('move', 13, 9, 0.04495768215728214),
                  ('gear axis', 8, 634.2677500684318, 429.15548705087645, 569.9942400413468,
                   2.2250738585e-313),
                  ('gear mover', 23, 28, 0.19639351130699773, 9.862092016116455e-177),
                  ('move', 26, 4, 0.39481555914122624))))),
    #: Mover 2 waits at its last safe stop for mover 6 inside the switch zone; mover 6 waits
    #: to go back behind mover 5, which stands geared (allowed sync direction positive, the
    #: master behind): a chain, not a deadlock (an earlier oracle, blind to movers standing
    #: for good, called it one).
    "switch_wait_behind_geared_movers": Scenario(
        layout=((('line', 0.0, 0.0, 736.372167, -0.0),),
                (('from', 0), ('line', 936.372167, 200.0, 936.372167, 663.41552),
                 ('line', 736.372167, 863.41552, 0.0, 863.41552),
                 ('line', -200.0, 663.41552, -200.0, 200.0), ('end', 0)),
                (('line', -727.663499, 0.0, -150.0, 0.0), ('end', 0))),
        movers=((1, 1800.0, 240.0), (1, 1080.0, 260.0), (2, 0.0, 240.0), (1, 0.0, 240.0),
                (1, 720.0, 360.0), (1, 2520.0, 360.0), (1, 2880.0, 240.0), (1, 2160.0, 360.0),
                (1, 360.0, 300.0), (0, 360.0, 240.0), (1, 1440.0, 300.0)),
        rounds=((464, (('move', 12, 2, 0.7510515584815229),)),
                (222, (('move', 26, 7, 1.1754943508222875e-38),
                       ('gear axis', 18, 1779.787308596115, 509.3607323611755,
                        878.3030493529723, 0.16711839778470042),
                       ('move', 21, 3, 1.0), ('move', 16, 2, 0.7693318141478167),
                       ('move', 6, 3, 0.697111010849815), ('move', 8, 8, 1.0), ('halt', 24),
                       ('gear axis', 16, 5.036042926440941e-178, 299.1059812750516,
                        778.6488322279656, 0.6006446735562198))),
                (1042, (('move', 0, 8, 0.15245205015848498), ('move', 2, 6, 0.75),
                        ('move', 11, 6, 9.397703404031574e-86))),
                (319, (('halt', 26), ('halt', 0),
                       ('gear axis', 16, 1398.6757270808935, 333.60771368410724,
                        349.24007495430146, 0.5527283407219074))))),
    #: Mover 0 goes round the closed track forwards (Positive, a lap) and passes its seam,
    #: where the feeder of mover 2 ends: ahead of mover 2 round the whole loop one cycle, a
    #: lap nearer the next. The oracle took that for closing in; the distance now has to
    #: follow the movers' steps to count as the same pair (``LAP_JUMP``).
    "lap_nearer_at_the_seam": Scenario(
        layout=((('line', -346.616524, -212.771072, -1569.015219, -963.142339),
                 ('line', -1702.860671, -1522.529935, -572.703571, -3363.62197),
                 ('line', -13.315975, -3497.467422, 1209.08272, -2747.096154),
                 ('line', 1342.928172, -2187.708559, 212.771072, -346.616524), ('close',)),
                (('circle', 580.06187, 2288.117049, -346.616524, -212.771072, -1476.619238,
                  1628.069461, True), ('end', 0))),
        movers=((0, 2560.0, 320.0), (0, 1280.0, 220.0), (1, 960.0, 260.0)),
        rounds=((1031, (('move', 0, 2, 1.1403755935090097e-273, 2, 1),
                        ('gear mover', 0, 3, 1.1125369292536007e-308, 0.23651903104837918),
                        ('move', 1, 2, 0.9195496550596096), ('halt', 0),
                        ('gear axis', 3, 520.5567915475485, 198.9440795554766, 4.0,
                         1.752955247319909e-234))),
                (174, (('move', 1, 9, 0.28860453137558656, 1, 1),
                       ('move', 0, 4, 0.10529322982648795),
                       ('move', 0, 6, 0.7142865147940188, 0, 1),
                       ('move', 2, 9, 0.5, 2, 0))))),
}


@pytest.mark.parametrize("name", sorted(FOUND))
def test_a_scenario_the_random_networks_found(name: str):
    """Properties 1-3 (module docstring) on a scenario of ``FOUND``."""
    Run(FOUND[name]).play()


def test_the_deadlock_check_tells_a_deadlock_from_a_chain():
    """A mover waiting at a switch for one that waits only for it is a deadlock; when that
    one also waits for a mover standing for good (no busy MoveOnTrack), it is a chain."""
    ring = {2: [(6, "switch")], 6: [(2, "queue")]}
    chain = {2: [(6, "switch")], 6: [(2, "queue"), (5, "queue")]}
    own = {i: [(j, why) for j, why in w if why != "switch"] for i, w in ring.items()}
    assert not _stuck(own, 6, ring)
    own = {i: [(j, why) for j, why in w if why != "switch"] for i, w in chain.items()}
    assert _stuck(own, 6, chain)
    queues = {1: [(2, "queue")], 2: [(1, "queue")], 3: [(1, "switch")]}
    own = {i: [(j, why) for j, why in w if why != "switch"] for i, w in queues.items()}
    assert _stuck(own, 1, queues)  # the program's own ring
