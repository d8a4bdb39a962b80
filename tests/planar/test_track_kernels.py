"""The compiled loops of the traffic (planar/traffic_kernels.py, planar/track_atlas.py) give
what the numpy and per-track formulations they replaced give, bit for bit."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.planar import PlanarState, Pose, PositionXYC
from openmotion.planar.cycle_tables import _switch_ids
from openmotion.planar.track import MC_PlanarTrack
from openmotion.planar.track_atlas import Atlas
from openmotion.planar.traffic_kernels import (
    conflicts,
    contested_pairs,
    gap_filter,
    group_by_track,
    in_order,
    neighbours,
    pair_gaps,
    riders_ahead,
    rooms,
    stretch_samples,
    touching,
    track_pairs,
    zone_entries,
    zone_lines,
    zone_stops,
)
from openmotion.rail.braking import brake_envelope
from openmotion.rail.gap_control import Pairs, filter_steps

p = PositionXYC


def _network(rt: om.Runtime) -> list[MC_PlanarTrack]:
    """Lines, arcs, the transitions between them, a closed loop and links."""
    loop, line, branch, arc = (MC_PlanarTrack(rt, n) for n in ("loop", "line", "branch", "arc"))
    loop.append_line(p(0.0, 0.0), p(1000.0, 0.0))
    loop.append_line(p(1000.0, 400.0), p(0.0, 400.0))
    loop.close_loop()
    line.append_line(p(0.0, -900.0), p(700.0, -900.0))
    branch.start_from_track(line)
    branch.append_circle(p(1000.0, -800.0), p(1100.0, -700.0), p(1000.0, -700.0), False)
    arc.append_circle(p(2000.0, 0.0), p(2000.0, 0.0), p(2300.0, 0.0), True)
    for track in (loop, line, branch, arc):
        track.enable()
    rt.run(0.003)
    assert all(t.state is PlanarState.ENABLED for t in (loop, line, branch, arc))
    return [loop, line, branch, arc]


@pytest.mark.parametrize("placed", [False, True])
def test_the_atlas_gives_each_tracks_own_frames(placed: bool):
    rt = om.Runtime(0.001)
    tracks = _network(rt)
    if placed:  # a part's placement moves the frames (MC_PlanarTrack.frame_at)
        tracks[2].placement = lambda position_index=0: Pose(120.5, -33.25, 27.0)
        tracks[3].placement = lambda position_index=0: Pose(-5.0, 8.0, 90.0)
    rng = np.random.default_rng(3)
    ids = rng.integers(0, len(tracks), 400)
    s = rng.uniform(-100.0, 4000.0, ids.size)
    atlas = Atlas(tracks)
    got = atlas.frames(ids, s, clamp=True)
    for k, track in enumerate(tracks):
        here = ids == k
        want = track.frame_at(np.clip(s[here], 0.0, track.length))
        for a, b in zip(got, want, strict=True):
            assert np.array_equal(a[here], b)
    assert atlas.matches(tracks) and not atlas.matches(tracks[:2])


def test_the_atlas_follows_a_route_over_its_legs():
    rt = om.Runtime(0.001)
    loop, line, branch, _ = _network(rt)
    atlas = Atlas([loop, line, branch])
    ids = np.array([1, 2])
    bases = np.array([0.0, line.length])
    q = np.linspace(-50.0, line.length + branch.length + 50.0, 300)
    x, y, heading, curvature = atlas.along(ids, bases, q)
    on_branch = q >= line.length
    for track, here, base in ((line, ~on_branch, 0.0), (branch, on_branch, line.length)):
        want = track.frame_at(np.clip(q[here] - base, 0.0, track.length))
        for a, b in zip((x, y, heading), want[:3], strict=True):
            assert np.array_equal(a[here], b)
    assert curvature == max(line.path.max_curvature, branch.path.max_curvature)


def _touch_reference(a: tuple, b: tuple) -> np.ndarray:
    """The numpy formulation of the footprint test the kernel replaced."""
    ax, ay, ac, ahx, ahy = a
    bx, by, bc, bhx, bhy = b
    dx, dy = bx[None, :] - ax[:, None], by[None, :] - ay[:, None]
    near = np.hypot(dx, dy) < math.hypot(ahx, ahy) + math.hypot(bhx, bhy)
    if not near.any():
        return np.zeros(ax.size, dtype=bool)
    i, j = np.nonzero(near)
    dx, dy = dx[i, j], dy[i, j]
    ca, sa, cb, sb = np.cos(ac[i]), np.sin(ac[i]), np.cos(bc[j]), np.sin(bc[j])
    overlap = np.ones(i.size, dtype=bool)
    for nx, ny in ((ca, sa), (-sa, ca), (cb, sb), (-sb, cb)):
        reach = (ahx * np.abs(ca * nx + sa * ny) + ahy * np.abs(-sa * nx + ca * ny)
                 + bhx * np.abs(cb * nx + sb * ny) + bhy * np.abs(-sb * nx + cb * ny))
        overlap &= np.abs(dx * nx + dy * ny) < reach
    out = np.zeros(ax.size, dtype=bool)
    out[i[overlap]] = True
    return out


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), spread=st.sampled_from([100.0, 200.0, 400.0, 3000.0]),
       grid=st.booleans())
def test_footprints_touch_as_the_numpy_test_says(seed: int, spread: float, grid: bool):
    rng = np.random.default_rng(seed)
    n, m = int(rng.integers(1, 60)), int(rng.integers(0, 60))
    ax, ay, bx, by = (rng.uniform(-spread, spread, k) for k in (n, n, m, m))
    ac, bc = rng.uniform(-math.pi, math.pi, n), rng.uniform(-math.pi, math.pi, m)
    if grid:  # edge to edge on a grid, turned by quarter turns: the touching cases
        ax, ay, bx, by = (np.round(v / 155.0) * 155.0 for v in (ax, ay, bx, by))
        ac, bc = (np.round(v / (math.pi / 2)) * (math.pi / 2) for v in (ac, bc))
    ahx, ahy, bhx, bhy = (float(v) for v in rng.uniform(60.0, 90.0, 4))
    want = _touch_reference((ax, ay, ac, ahx, ahy), (bx, by, bc, bhx, bhy))
    got = touching(ax, ay, np.cos(ac), np.sin(ac), ahx, ahy, bx, by, np.cos(bc), np.sin(bc),
                   bhx, bhy, math.hypot(ahx, ahy) + math.hypot(bhx, bhy))
    assert np.array_equal(got, want)


@settings(max_examples=100, deadline=None)
@given(low=st.floats(-1e4, 1e4), width=st.floats(0.0, 300.0), others=st.integers(0, 3),
       seed=st.integers(0, 2**32 - 1))
def test_stretch_samples_are_numpys_linspace(low: float, width: float, others: int, seed: int):
    rng = np.random.default_rng(seed)
    high = low + width
    own = max(1, math.ceil((high - low) / 2.0) + 1)
    lows = rng.uniform(-1e4, 1e4, others)
    highs = lows + rng.uniform(0.0, 200.0, others)
    sizes = np.array([max(1, math.ceil((h - lo) / 2.0) + 1) for lo, h in zip(
        lows, highs, strict=True)], dtype=np.int64)
    start, end = low - 40.0, high + 50.0
    q, at = stretch_samples(low, high, start, end, 2.0, 32, own, lows, highs, sizes)
    steps = 2.0 * np.arange(1, 33)
    want = [np.linspace(low, high, own), np.minimum(high + steps, end),
            np.maximum(low - steps, start)]
    want += [np.linspace(lo, h, k) for lo, h, k in zip(lows, highs, sizes, strict=True)]
    assert np.array_equal(q, np.concatenate(want))
    assert at.tolist() == np.cumsum([0, own + 64, *sizes]).tolist()


def _pairs(rng: np.random.Generator, n: int) -> Pairs:
    """Movers in a row, some in a second row that merges into the first."""
    succ = list(range(n - 1))
    pred = list(range(1, n))
    for _ in range(n // 5):  # a second follower of one leader, and one follower twice
        succ.append(int(rng.integers(0, n)))
        pred.append(int(rng.integers(0, n)))
    count = len(succ)
    return Pairs(np.array(succ, dtype=np.int64), np.array(pred, dtype=np.int64),
                 rng.uniform(-5.0, 5.0, count),
                 rng.uniform(150.0, 250.0, count), np.zeros(count, dtype=bool), True)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 40))
def test_the_compiled_gap_filter_is_the_groups(seed: int, n: int):
    rng = np.random.default_rng(seed)
    pairs = _pairs(rng, n)
    p = np.cumsum(rng.uniform(150.0, 260.0, n))
    v, a = rng.uniform(-300.0, 1500.0, n), rng.uniform(-8000.0, 8000.0, n)
    dec, jerk = rng.uniform(5000.0, 20000.0, n), rng.uniform(5e4, 5e5, n)
    dt = 0.001
    proposal = [p + v * dt + rng.uniform(-0.5, 2.0, n), v + rng.uniform(-20.0, 20.0, n),
                a + rng.uniform(-100.0, 100.0, n), np.zeros(n)]
    known = rng.random(n) < 0.5
    lo, hi = brake_envelope(*proposal[:3], dec, jerk)
    known_lo, known_hi = np.where(known, lo, np.nan), np.where(known, hi, np.nan)
    envelope = brake_envelope(p, v, a, dec, jerk)
    want_nxt = [x.copy() for x in proposal]
    want = filter_steps((p, v, a), envelope, want_nxt, dt, dec, jerk, pairs,
                        (known, known_lo, known_hi))
    got_nxt = [x.copy() for x in proposal]
    got = gap_filter(p, v, a, *envelope, *got_nxt, dt, dec, jerk, pairs.succ, pairs.pred,
                     pairs.offset, pairs.gap, known, known_lo, known_hi)
    for x, y in zip((*got, *got_nxt), (*want, *want_nxt), strict=True):
        assert np.array_equal(x, y)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 40))
def test_rooms_neighbours_and_pair_gaps_are_the_numpy_ones(seed: int, n: int):
    rng = np.random.default_rng(seed)
    pairs = _pairs(rng, n)
    s, k = pairs.succ, pairs.pred
    lo = rng.uniform(0.0, 1e4, n)
    hi = lo + rng.uniform(0.0, 500.0, n)
    stopped = np.unique(rng.integers(0, n, n // 3))
    low, high = rng.uniform(0.0, 1e4, stopped.size), rng.uniform(0.0, 1e4, stopped.size)
    room_hi, room_lo = np.full(n, np.inf), np.full(n, -np.inf)
    np.minimum.at(room_hi, s, lo[k] + pairs.offset - pairs.gap)
    np.maximum.at(room_lo, k, hi[s] + pairs.gap - pairs.offset)
    for r, b, t in zip(stopped.tolist(), low.tolist(), high.tolist(), strict=True):
        room_lo[r], room_hi[r] = max(room_lo[r], b), min(room_hi[r], t)
    got_lo, got_hi = rooms(n, s, k, pairs.offset, pairs.gap, lo, hi, stopped, low, high)
    assert np.array_equal(got_lo, room_lo) and np.array_equal(got_hi, room_hi)
    ahead, behind = np.full(n, -1), np.full(n, -1)
    ahead[s], behind[k] = k, s
    got_ahead, got_behind = neighbours(n, s, k)
    assert np.array_equal(got_ahead, ahead) and np.array_equal(got_behind, behind)
    mode, target, position = rng.integers(0, 4, n), rng.uniform(0, 1e4, n), rng.uniform(0, 1e4, n)
    going, gap = rng.random(n) < 0.3, rng.uniform(150.0, 300.0, n)
    back = (mode[k] != 0) & ((target[k] < position[k]) | going[k])
    want = np.where(back, np.maximum(gap[s], gap[k]), gap[s])
    assert np.array_equal(pair_gaps(s, k, mode, 0, target, position, going, gap), want)


def _riders_on_tracks(rng: np.random.Generator, n: int, tracks: int) -> tuple:
    """``n`` riders on ``tracks`` tracks: track index, arc length (some equal) and base."""
    track_of = rng.integers(0, tracks, n)
    s = np.round(rng.uniform(0.0, 3000.0, n), 0 if rng.random() < 0.5 else 3)
    base = np.round(rng.uniform(-5e3, 5e3, n), 2)
    return track_of, s, base


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(0, 60), tracks=st.integers(1, 12))
def test_pairs_on_tracks_are_the_numpy_ones(seed: int, n: int, tracks: int):
    """``track_pairs``: the pair list's riders on one track as numpy's masks made them."""
    rng = np.random.default_rng(seed)
    track_of, s, base = _riders_on_tracks(rng, n, tracks)
    place, grouped, tails = group_by_track(track_of)
    ranked = in_order(s, grouped, tails)
    same = place[ranked[:-1]] == place[ranked[1:]]
    heads = np.flatnonzero(np.concatenate(([ranked.size > 0], ~same)))
    want = (ranked, ranked[:-1][same], ranked[1:][same],
            base[ranked[:-1][same]] - base[ranked[1:][same]], heads,
            np.append(heads[1:], ranked.size) if heads.size else heads)
    got = track_pairs(s, grouped, tails, place, base)
    for x, y in zip(got, want, strict=True):
        assert np.array_equal(x, y)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(0, 60), tracks=st.integers(1, 12))
def test_the_rider_ahead_of_a_front_rider_is_the_dict_searchs(seed: int, n: int, tracks: int):
    """``riders_ahead``: the first of a track's first two riders other than the front rider
    itself, on the tracks it looks along, as the search over a dict of them found it."""
    rng = np.random.default_rng(seed)
    track_of, s, base = _riders_on_tracks(rng, n, tracks)
    place, grouped, tails = group_by_track(track_of)
    ranked, _, _, _, heads, ends = track_pairs(s, grouped, tails, place, base)
    width = 6
    count = rng.integers(0, width + 1, n)
    look_tracks = rng.integers(0, tracks, (n, width))
    look_bases = rng.uniform(-1e4, 1e4, (n, width))
    order = ranked.tolist()
    first = {int(track_of[order[h]]): order[h:min(h + 2, e)]
             for h, e in zip(heads.tolist(), ends.tolist(), strict=True)}
    want = []
    for e in ends.tolist():
        m = order[e - 1]
        for j in range(count[m]):
            found = [k for k in first.get(int(look_tracks[m, j]), ()) if k != m]
            if found:
                want.append((m, found[0], float(look_bases[m, j]) - float(base[found[0]])))
                break
    fronts, leaders, shifts = riders_ahead(ranked, heads, ends, track_of, tracks, base,
                                           look_tracks, look_bases, count)
    assert list(zip(fronts.tolist(), leaders.tolist(), shifts.tolist(), strict=True)) == want


def _holders(rng: np.random.Generator, n: int, switches: int) -> tuple:
    """Random route arrays of ``n`` riders and holders among them at ``switches`` switches."""
    track_of = rng.integers(0, 6, n)
    next_of = np.where(rng.random(n) < 0.6, rng.integers(0, 6, n), -1)
    seam, back = rng.random(n) < 0.2, rng.random(n) < 0.1
    count = int(rng.integers(0, 2 * n + 1))
    holders = rng.integers(0, n, count)
    return (holders, rng.random(count) < 0.5, rng.integers(0, switches, count),
            (track_of, next_of, seam, back))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 30), switches=st.integers(1, 8))
def test_contested_holders_are_the_conflict_matrixs(seed: int, n: int, switches: int):
    """``contested_pairs``: the holders that conflict at one switch, in the order of numpy's
    nonzero of the conflict matrix masked by equal switches."""
    rng = np.random.default_rng(seed)
    holders, at_end, switch, route = _holders(rng, n, switches)
    clash = conflicts(holders, at_end, holders, at_end, *route) & \
        (switch[:, None] == switch[None, :])
    first, second = contested_pairs(holders, at_end, switch, *route)
    want_first, want_second = np.nonzero(clash)
    assert np.array_equal(first, want_first) and np.array_equal(second, want_second)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 30), switches=st.integers(1, 8))
def test_zone_lines_block_as_every_holder_asked(seed: int, n: int, switches: int):
    """``zone_lines`` asks only the holders of an entry's switch: the stop lines are those of
    asking every holder."""
    rng = np.random.default_rng(seed)
    holders, holder_ends, holder_switches, route = _holders(rng, n, switches)
    start_switch = np.where(rng.random(n) < 0.7, rng.integers(0, switches, n), -1)
    end_switch = np.where(rng.random(n) < 0.7, rng.integers(0, switches, n), -1)
    in_end, in_start = rng.random(n) < 0.3, rng.random(n) < 0.3
    end_line, start_line = rng.uniform(0.0, 1e3, n), rng.uniform(0.0, 1e3, n)
    lo = rng.uniform(0.0, 1e3, n)
    hi = lo + rng.uniform(0.0, 500.0, n)
    entries = (start_switch, end_switch, in_end, in_start, end_line, start_line, lo, hi, 400.0)
    k, end, switch, low, high, wanting = zone_entries(*entries)
    clash = conflicts(k, end, holders, holder_ends, *route) & \
        (switch[:, None] == holder_switches[None, :])
    want = zone_stops(n, k, low, high, wanting, clash.any(axis=1))
    got = zone_lines(*entries, holders, holder_ends, holder_switches, *route)
    for x, y in zip(got, want, strict=True):
        assert np.array_equal(x, y)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(0, 40), tracks=st.integers(1, 10))
def test_switch_ids_are_numbered_in_the_order_met(seed: int, n: int, tracks: int):
    """The riders' switch ids: the network's switches numbered as met along the tracks with
    riders (each one's start before its end), as a dict numbered them track by track."""
    rng = np.random.default_rng(seed)
    track_of = rng.integers(0, tracks, n)
    start = np.where(rng.random(tracks) < 0.6, rng.integers(0, 7, tracks), -1)
    end = np.where(rng.random(tracks) < 0.6, rng.integers(0, 7, tracks), -1)
    place, ranked, tails = group_by_track(track_of)
    on = track_of[ranked[tails - 1]]
    ids: dict[int, int] = {}
    by_place = np.full((2, on.size), -1)
    for i, track in enumerate(on.tolist()):
        for side, switch in enumerate((start[track], end[track])):
            if switch >= 0:
                by_place[side, i] = ids.setdefault(int(switch), len(ids))
    got_start, got_end = _switch_ids(start, end, on, place)
    assert np.array_equal(got_start, by_place[0][place])
    assert np.array_equal(got_end, by_place[1][place])


def _clear_stretch_reference(traffic, k: int, low: float, high: float,
                             others: list[tuple[int, float, float]]) -> tuple:
    """``SwitchZones.clear_stretch`` as numpy and one ``frame_at`` per leg computed it."""
    step, count = 2.0, 32

    def samples(lo: float, hi: float) -> np.ndarray:
        return np.linspace(lo, hi, max(1, math.ceil((hi - lo) / step) + 1))

    def footprints(j: int, q: np.ndarray) -> tuple:
        rider = traffic.riders[j]
        x, y, c = np.empty(q.size), np.empty(q.size), np.empty(q.size)
        bases = np.array([leg.base for leg in rider.route])
        leg_of = np.clip(np.searchsorted(bases, q, side="right") - 1, 0, bases.size - 1)
        curvature = 0.0
        for i in np.unique(leg_of).tolist():
            track = rider.route[i].track
            here = leg_of == i
            x[here], y[here], c[here], _ = track.frame_at(
                np.clip(q[here] - bases[i], 0.0, track.length))
            curvature = max(curvature, track.path.max_curvature)
        if not traffic.oriented[j]:
            c[:] = math.radians(traffic.zones.turn(j))
            curvature = 0.0
        hx, hy = rider.half
        margin = 0.5 * step * (1.0 + math.hypot(hx, hy) * curvature)
        return x, y, c, hx + margin, hy + margin

    rider = traffic.riders[k]
    start, end = float(traffic.base[k]), rider.route[-1].base + rider.route[-1].track.length
    own = samples(low, high)
    ahead = np.minimum(high + step * np.arange(1, count + 1), end)
    behind = np.maximum(low - step * np.arange(1, count + 1), start)
    mine = footprints(k, np.concatenate((own, ahead, behind)))
    hit = np.zeros(own.size + 2 * count, dtype=bool)
    for j, lo_j, hi_j in others:
        hit |= _touch_reference(mine, footprints(j, samples(lo_j, hi_j)))
    if hit[:own.size].any():
        return (low, high), (low, high)
    fwd, back = hit[own.size:own.size + count], hit[own.size + count:]
    first_f = int(np.argmax(fwd)) if fwd.any() else count
    first_b = int(np.argmax(back)) if back.any() else count
    top = float(ahead[first_f - 1]) if first_f else high
    bottom = float(behind[first_b - 1]) if first_b else low
    return (bottom, top), (bottom if back.any() else -math.inf, top if fwd.any() else math.inf)


def test_the_footprint_search_at_a_switch_answers_as_numpy_did(monkeypatch):
    """Two movers inside the collision ranges of one switch (test_track_properties: a straight
    branch and an arc that stays in its hose): one moves towards the other, so the search
    of the stretch it may use runs every cycle, with footprints that meet."""
    from openmotion.planar import MC_PlanarMover, MoverVector, PlanarMoverParameters
    from openmotion.planar.switch_zones import SwitchZones

    rt = om.Runtime(0.001)
    trunk, straight, curve = (MC_PlanarTrack(rt, n) for n in ("trunk", "straight", "curve"))
    trunk.append_line(p(-400.0, 0.0), p(0.0, 0.0))
    straight.start_from_track(trunk)
    straight.append_line(p(0.0, 0.0), p(300.0, 0.0))
    curve.start_from_track(trunk)
    r, sweep = 330.0, 1.2
    curve.append_circle(p(0.0, 0.0), p(r * math.sin(sweep), r - r * math.cos(sweep)),
                        p(0.0, r), False)
    for track in (trunk, straight, curve):
        track.enable()
    rt.run(0.003)
    movers = []
    for track, s in ((straight, 100.0), (curve, 300.0)):
        at = track.get_position_at(s)
        movers.append(MC_PlanarMover(rt, PlanarMoverParameters(
            initial_position=MoverVector(at.x, at.y, c=at.c),
            minimum_position=MoverVector(-math.inf, -math.inf, 0.0, -5.0, -5.0, -45.0),
            maximum_position=MoverVector(math.inf, math.inf, 6.0, 5.0, 5.0, 45.0))))
        movers[-1].enable()
    rt.run(0.005)
    joins = [m.join_track(t) for m, t in zip(movers, (straight, curve), strict=True)]
    assert rt.run_until(lambda: all(j.done for j in joins), timeout=1.0)
    searched = []
    compiled = SwitchZones.clear_stretch

    def both(self, k, low, high, others):
        got = compiled(self, k, low, high, others)
        assert got == _clear_stretch_reference(self.traffic, k, low, high, others)
        searched.append(got)
        return got

    monkeypatch.setattr(SwitchZones, "clear_stretch", both)
    movers[0].move_on_track(None, 250.0)
    rt.run(1.0)
    assert len(searched) > 10
    assert any(math.isfinite(room[1]) for _, room in searched)  # found the other's footprint
