"""Track rules found in review: a used track keeps its geometry (D-119), directions of
MoveOnTrack (§6.1.9) and moves back over a loop's seam (D-147), the static-object check of
a track's band (§6.2.1), gear-in under the group's collision avoidance (§6.5) and the
operation mode of tracks on a route (§4.3)."""

from __future__ import annotations

import numpy as np
import pytest

import openmotion as om
from openmotion.core.enums import ModuloDirection
from openmotion.core.errors import ConfigError, ErrorId
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarFeedbackGearInPosOnTrack,
    MC_PlanarGroup,
    MC_PlanarMover,
    PlanarObjectInfo,
    PlanarObjectType,
    PlanarState,
    PositionXYC,
    TrackOperationMode,
)
from openmotion.planar.options import ST_MoveOnTrackOptions
from openmotion.planar.track import MC_PlanarTrack, traffic_of
from openmotion.testing import enabled_line as _line
from openmotion.testing import enabled_loop
from openmotion.testing import enabled_movers as _movers
from openmotion.testing import join_all as _joined


def _run_until(rt: om.Runtime, *commands: object, timeout: float = 20.0) -> None:
    assert rt.run_until(lambda: all(c.done for c in commands), timeout=timeout), \
        [(c.kind, c.busy, c.error, c.message) for c in commands]


def _s(mover: MC_PlanarMover) -> float:
    return mover.mc_to_plc.set_on_track.set_pos


def _v(mover: MC_PlanarMover) -> float:
    return mover.mc_to_plc.set_on_track.set_velo


def _group(rt: om.Runtime, *members: object) -> MC_PlanarGroup:
    group = MC_PlanarGroup(rt)
    group.enable()
    rt.run(0.005)
    adds = [m.add_to_group(group) for m in members]  # type: ignore[attr-defined]
    rt.run(0.005)
    assert all(a.done for a in adds), [a.message for a in adds]
    return group


# -- A: a used track keeps its geometry (D-119) --------------------------------------------------


def test_disable_is_refused_while_a_mover_moves_on_the_track_and_its_move_ends():
    """Review t14/t15b: Disable then Clear under a moving mover. Both are refused (the track
    stays Enabled with its 600 mm), no cycle raises, and the move ends at 500."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    track = _line(rt, (0.0, 0.0), (600.0, 0.0))
    _joined(rt, track, mover)
    move = mover.move_on_track(None, 500.0)
    rt.run(0.05)
    disable = track.disable()
    rt.step()
    rt.step()
    clear = track.clear()
    rt.step()
    rt.step()
    assert disable.error and disable.error_id == ErrorId.PLANAR_WRONG_STATE
    assert "1 mover" in disable.message
    assert clear.error and clear.error_id == ErrorId.PLANAR_WRONG_STATE
    assert track.state is PlanarState.ENABLED and track.get_length() == pytest.approx(600.0)
    _run_until(rt, move)
    assert (mover.position.x, mover.position.y) == pytest.approx((500.0, 0.0), abs=1e-9)


def test_the_geometry_under_a_standing_mover_is_not_replaced():
    """Review t15c: Disable, Clear, AppendLine at y = 300, Enable under a standing mover:
    Disable is refused, so the edits are too; the next MoveOnTrack stays on y = 0."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    track = _line(rt, (0.0, 0.0), (600.0, 0.0))
    _joined(rt, track, mover)
    disable = track.disable()
    rt.step()
    rt.step()
    clear = track.clear()
    append = track.append_line(PositionXYC(0.0, 300.0), PositionXYC(600.0, 300.0))
    rt.run(0.01)
    assert disable.error_id == ErrorId.PLANAR_WRONG_STATE
    assert clear.error_id == append.error_id == ErrorId.PLANAR_WRONG_STATE
    move = mover.move_on_track(None, 200.0)
    _run_until(rt, move)
    assert (mover.position.x, mover.position.y) == pytest.approx((200.0, 0.0), abs=1e-9)


def test_disable_is_refused_while_a_mover_joins_or_is_routed_onto_the_track():
    """A joining mover (Configuring) and a mover on track a routed onto track b hold the
    track too; once the movers are off, Disable and Clear go through."""
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (100.0, 0.0), (900.0, 400.0))
    a = _line(rt, (0.0, 0.0), (600.0, 0.0))
    b = _line(rt, (700.0, 0.0), (1500.0, 0.0), after=a)
    join = two.join_track(b)
    rt.step()
    rt.step()
    assert b.operation_mode is TrackOperationMode.CONFIGURING
    refused = b.disable()
    rt.step()
    assert refused.error_id == ErrorId.PLANAR_WRONG_STATE
    _run_until(rt, join)
    leave = two.leave_track(PositionXYC(900.0, 400.0))
    _run_until(rt, leave)
    _joined(rt, a, one)
    move = one.move_on_track(b, 300.0)
    rt.run(0.05)
    assert b.mover_count_on_track == 0  # mover one is still on a
    refused = b.disable()
    rt.step()
    assert refused.error_id == ErrorId.PLANAR_WRONG_STATE
    _run_until(rt, move)
    leave = one.leave_track(PositionXYC(1000.0, 300.0))
    _run_until(rt, leave)
    disable = b.disable()
    rt.run(0.005)
    clear = b.clear()
    rt.run(0.005)
    assert disable.done and clear.done and b.get_length() == 0.0


# -- B: directions of MoveOnTrack (§6.1.9) --------------------------------------------------------


def test_positive_on_an_open_track_moves_forwards_to_a_target_ahead():
    """Review t2: on an open 600 mm line, Positive from 100 to 300 runs (forwards)."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    track = _line(rt, (0.0, 0.0), (600.0, 0.0))
    _joined(rt, track, mover)
    move = mover.move_on_track(None, 300.0, options=ST_MoveOnTrackOptions(
        direction=ModuloDirection.POSITIVE))
    rt.run(0.05)
    assert move.busy and _v(mover) > 0.0
    _run_until(rt, move)
    assert _s(mover) == pytest.approx(300.0, abs=1e-9)


def test_a_direction_against_the_only_way_on_an_open_track_is_refused():
    """Positive to a target behind, Negative to one ahead or on the next track are refused
    with INVALID_DIRECTION and the mover stays; Negative to a target behind runs backwards;
    additional turns without a loop are INVALID_MODULO_OPTIONS."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (300.0, 0.0))
    a = _line(rt, (0.0, 0.0), (600.0, 0.0))
    b = _line(rt, (700.0, 0.0), (1200.0, 0.0), after=a)
    _joined(rt, a, mover)
    pos, neg = ModuloDirection.POSITIVE, ModuloDirection.NEGATIVE
    for track, target, direction, turns, error in (
            (None, 100.0, pos, 0, ErrorId.INVALID_DIRECTION),
            (None, 500.0, neg, 0, ErrorId.INVALID_DIRECTION),
            (b, 100.0, neg, 0, ErrorId.INVALID_DIRECTION),
            (None, 500.0, pos, 1, ErrorId.INVALID_MODULO_OPTIONS),
            (b, 100.0, pos, 2, ErrorId.INVALID_MODULO_OPTIONS)):
        move = mover.move_on_track(track, target, options=ST_MoveOnTrackOptions(
            direction=direction, additional_turns=turns))
        rt.step()
        rt.step()
        assert move.error and move.error_id == error, (target, direction, move.message)
        assert _s(mover) == pytest.approx(300.0, abs=1e-9) and _v(mover) == 0.0
    back = mover.move_on_track(None, 100.0, options=ST_MoveOnTrackOptions(direction=neg))
    rt.run(0.05)
    assert back.busy and _v(mover) < 0.0
    _run_until(rt, back)
    assert _s(mover) == pytest.approx(100.0, abs=1e-9)


# -- B2: moves back over a loop's seam (§6.1.9, §6.2.2, D-147) ----------------------------------


def _at(loop: MC_PlanarTrack, s: float) -> tuple[float, float]:
    point = loop.get_position_at(s)
    return point.x, point.y


def _ride(rt: om.Runtime, *watched: MC_PlanarMover, until: object = None,
          timeout: float = 20.0) -> list[list[tuple[float, float, float, float]]]:
    """Cycles until ``until`` (a command) is no longer busy (or ``timeout``): per cycle and
    mover, its path coordinate, velocity and acceleration (``path_state``: the arc length
    summed over its way, §6.1.9) and its arc length on the track."""
    traffic = traffic_of(watched[0].system)
    log = []
    for _ in range(round(timeout / 0.001)):
        rt.step()
        log.append([(*traffic.path_state(m._rider)[:3], _s(m)) for m in watched])
        if until is not None and not until.busy:  # type: ignore[attr-defined]
            break
    return log


def _seam_crossings(arcs: list[float], length: float) -> tuple[int, int]:
    """How often the arc lengths jumped back over the seam (from near 0 to near the length)
    and forwards over it."""
    steps = list(zip(arcs[:-1], arcs[1:], strict=True))
    back = sum(1 for a, b in steps if a < length / 4 and b > 3 * length / 4)
    ahead = sum(1 for a, b in steps if a > 3 * length / 4 and b < length / 4)
    return back, ahead


def _check_limits(rt: om.Runtime, mover: MC_PlanarMover,
                  log: list[tuple[float, float, float, float]]) -> None:
    """Velocity and acceleration along the path stay within the command's limits, and the
    path coordinate runs on without a jump."""
    limits = traffic_of(mover.system).limits[:, mover._rider.slot]
    q, v, a = (np.array(column) for column in list(zip(*log, strict=True))[:3])
    assert np.abs(v).max() <= limits[0] * (1 + 1e-9)
    assert np.abs(a).max() <= max(limits[1], limits[2]) * (1 + 1e-9)
    assert np.abs(np.diff(q)).max() <= limits[0] * rt.cycle_time * (1 + 1e-6)


def test_negative_moves_back_over_a_loops_seam_to_its_target():
    """Review t1, now built: on a closed loop Negative from 100 to length - 200 runs back
    over the seam (s = 0): 300 mm along the path, never forwards, Done at the target. It
    was refused (D-144); the traffic now goes on to the loop's previous lap below its
    start (D-147)."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    loop = enabled_loop(rt)
    length = loop.get_length()
    _joined(rt, loop, mover)
    start = traffic_of(mover.system).path_state(mover._rider)[0]
    move = mover.move_on_track(None, length - 200.0, options=ST_MoveOnTrackOptions(
        direction=ModuloDirection.NEGATIVE))
    log = [row[0] for row in _ride(rt, mover, until=move)]
    assert move.done, move.message
    assert _s(mover) == pytest.approx(length - 200.0, abs=1e-9)
    assert (mover.position.x, mover.position.y) == pytest.approx(_at(loop, length - 200.0),
                                                                 abs=1e-6)
    assert log[-1][0] - start == pytest.approx(-300.0, abs=1e-9)
    assert max(v for _, v, _, _ in log) <= 0.0
    assert _seam_crossings([s for *_, s in log], length) == (1, 0)
    _check_limits(rt, mover, log)
    assert len(mover._rider.route) == 1  # cut to the lap it ends on


@pytest.mark.parametrize("turns", [1, 2])
def test_negative_with_additional_turns_travels_the_extra_laps_back(turns: int):
    """Review t1: Negative with additional turns from 100 to 50 went 50 mm back and dropped
    the laps (then it was refused, D-144). It travels 50 mm plus the laps back, over the
    seam once per lap, and ends at 50 (D-147)."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    loop = enabled_loop(rt)
    length = loop.get_length()
    _joined(rt, loop, mover)
    start = traffic_of(mover.system).path_state(mover._rider)[0]
    move = mover.move_on_track(None, 50.0, options=ST_MoveOnTrackOptions(
        direction=ModuloDirection.NEGATIVE, additional_turns=turns))
    log = [row[0] for row in _ride(rt, mover, until=move, timeout=30.0)]
    assert move.done, move.message
    assert _s(mover) == pytest.approx(50.0, abs=1e-9)
    assert log[-1][0] - start == pytest.approx(-(50.0 + turns * length), abs=1e-9)
    assert max(v for _, v, _, _ in log) <= 0.0
    assert _seam_crossings([s for *_, s in log], length) == (turns, 0)
    _check_limits(rt, mover, log)


@pytest.mark.parametrize(("target", "way"), [(-100.0, -200.0), (250.0, 150.0)])
def test_shortest_way_takes_the_shorter_way_round_the_seam_or_not(target: float, way: float):
    """ShortestWay from 100: to length - 100 the way back over the seam (200 mm) is the
    shorter one and taken; to 250 the way ahead (150 mm)."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (100.0, 0.0))
    loop = enabled_loop(rt)
    length = loop.get_length()
    _joined(rt, loop, mover)
    start = traffic_of(mover.system).path_state(mover._rider)[0]
    position = target % length
    move = mover.move_on_track(None, position, options=ST_MoveOnTrackOptions(
        direction=ModuloDirection.SHORTEST_WAY))
    log = [row[0] for row in _ride(rt, mover, until=move)]
    assert move.done, move.message
    assert _s(mover) == pytest.approx(position, abs=1e-9)
    assert log[-1][0] - start == pytest.approx(way, abs=1e-9)
    _check_limits(rt, mover, log)


@pytest.mark.parametrize(("turns", "way"), [(0, -8.0), (1, None)])
def test_positive_within_the_modulo_tolerance_takes_the_near_way_back_over_the_seam(
        turns: int, way: float | None):
    """§6.1.9: a target within the modulo tolerance is taken the short way whatever the
    direction. Positive from 5 to length - 3 (tolerance 10) goes 8 mm back over the seam;
    with one additional turn it goes the lap forwards from there (length - 8)."""
    rt = om.Runtime(0.001)
    (mover,) = _movers(rt, (5.0, 0.0))
    loop = enabled_loop(rt)
    length = loop.get_length()
    _joined(rt, loop, mover)
    assert _s(mover) == pytest.approx(5.0)
    start = traffic_of(mover.system).path_state(mover._rider)[0]
    move = mover.move_on_track(None, length - 3.0, options=ST_MoveOnTrackOptions(
        direction=ModuloDirection.POSITIVE, additional_turns=turns, modulo_tolerance=10.0))
    log = [row[0] for row in _ride(rt, mover, until=move)]
    assert move.done, move.message
    assert _s(mover) == pytest.approx(length - 3.0, abs=1e-9)
    travelled = log[-1][0] - start
    assert travelled == pytest.approx(length - 8.0 if way is None else way, abs=1e-9)


def test_a_mover_reversing_over_the_seam_stops_one_gap_from_a_standing_mover():
    """Mover b stands at length - 300 on the loop; mover a moves Negative from 100 to
    length - 500 with gap 250: back over the seam, then b is in its way. It stops 250 mm
    from b (along the path, never closer) and waits; when b has moved on back (to length -
    900), a goes on to its target."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt)
    length = loop.get_length()
    a, b = _movers(rt, (100.0, 0.0), _at(loop, length - 300.0))
    _joined(rt, loop, a, b)
    move = a.move_on_track(None, length - 500.0, options=ST_MoveOnTrackOptions(
        gap=250.0, direction=ModuloDirection.NEGATIVE))
    log = _ride(rt, a, b, timeout=3.0)
    apart = [(sa - sb) % length for (*_, sa), (*_, sb) in log]
    assert min(apart) >= 250.0 - 1e-6
    assert move.busy and _v(a) == 0.0
    assert _s(a) == pytest.approx(length - 50.0, abs=1e-6)
    away = b.move_on_track(None, length - 900.0)
    log = _ride(rt, a, b, until=move)
    _run_until(rt, away)
    assert move.done, move.message
    assert _s(a) == pytest.approx(length - 500.0, abs=1e-9)
    assert min((sa - sb) % length for (*_, sa), (*_, sb) in log) >= 250.0 - 1e-6


def test_a_mover_coming_to_the_seam_keeps_the_larger_gap_to_one_reversing_over_it():
    """Mover b drives forwards from length - 600 towards the seam (target length - 10, gap
    200) while mover a reverses over it from 100 (Negative to length - 300, gap 250): they
    meet head on. b is the follower of a, which goes back: the larger gap (250) holds
    between them along the path at every cycle, and they stop there."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt)
    length = loop.get_length()
    a, b = _movers(rt, (100.0, 0.0), _at(loop, length - 600.0))
    _joined(rt, loop, a, b)
    back = a.move_on_track(None, length - 300.0, options=ST_MoveOnTrackOptions(
        gap=250.0, direction=ModuloDirection.NEGATIVE))
    ahead = b.move_on_track(None, length - 10.0)
    log = _ride(rt, a, b, timeout=4.0)
    apart = [(sa - sb) % length for (*_, sa), (*_, sb) in log]
    assert min(apart) >= 250.0 - 1e-6
    assert apart[-1] == pytest.approx(250.0, abs=1e-6)
    assert back.busy and ahead.busy and _v(a) == _v(b) == 0.0  # head on: both wait


# -- C: the static-object check of a track's band (§6.2.1) ----------------------------------------


@pytest.mark.parametrize("check", [False, True])
def test_connected_tracks_in_a_group_block_each_other_only_when_checked(check: bool):
    """Review t9: movers on tracks a -> b of one group. By default (§6.2.1 FALSE) both
    MoveOnTracks run; with b checking static objects b's band meets a's and b's move is
    refused naming track a."""
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (100.0, 0.0), (900.0, 0.0))
    a = _line(rt, (0.0, 0.0), (600.0, 0.0))
    b = _line(rt, (700.0, 0.0), (1500.0, 0.0), after=a,
              check_collisions_against_static_objects=check)
    _group(rt, one, two, a, b)
    _joined(rt, a, one)
    _joined(rt, b, two)
    first = one.move_on_track(None, 300.0)
    rt.step()
    second = two.move_on_track(None, 700.0)
    rt.step()
    rt.step()
    assert first.busy
    if check:
        assert second.error and second.error_id == ErrorId.PLANAR_COLLISION
        assert second.object_info == PlanarObjectInfo(PlanarObjectType.TRACK, a.oid)
    else:
        _run_until(rt, first, second)
        assert _s(two) == pytest.approx(700.0, abs=1e-9)


@pytest.mark.parametrize("check", [False, True])
def test_a_track_near_the_stator_edge_is_checked_against_the_environment_only_on_request(
        check: bool):
    """Review t10: a track 80 mm from the edge of a 4 x 2 stator surface (the mover, 77.5
    mm half width, fits; the band of the largest mover's diagonal does not). By default the
    move runs to x = 700; with the check it is refused naming the environment."""
    rt = om.Runtime(0.001)
    env = MC_PlanarEnvironment(rt)
    for x in (0.0, 240.0, 480.0, 720.0):
        env.add_stator(x, 0.0)
        env.add_stator(x, 240.0)
    env.create_boundary()
    rt.run(0.01)
    (mover,) = _movers(rt, (200.0, 80.0))
    track = _line(rt, (100.0, 80.0), (860.0, 80.0),
                  check_collisions_against_static_objects=check)
    _group(rt, env, mover, track)
    _joined(rt, track, mover)
    move = mover.move_on_track(None, 600.0)
    rt.step()
    rt.step()
    if check:
        assert move.error and move.error_id == ErrorId.PLANAR_COLLISION
        assert move.object_info.object_type is PlanarObjectType.ENVIRONMENT
    else:
        _run_until(rt, move)
        assert mover.position.x == pytest.approx(700.0, abs=1e-9)


def test_the_static_object_check_must_be_a_bool():
    rt = om.Runtime(0.001)
    with pytest.raises(ConfigError, match="check_collisions_against_static_objects"):
        MC_PlanarTrack(rt, check_collisions_against_static_objects=1)  # type: ignore[arg-type]


# -- D: gear-in under the group's collision avoidance (§6.5) -------------------------------------


def test_gear_in_in_a_group_holds_the_track_band_and_is_refused_by_a_mover_on_it():
    """Review t19: a free mover stands on the track line at x = 600. The slave's gear-in
    is refused naming it (as a MoveOnTrack is), instead of driving through it; with the
    free mover gone the gear-in holds the band until its Halt."""
    rt = om.Runtime(0.001)
    slave, free = _movers(rt, (100.0, 0.0), (600.0, 0.0))
    track = _line(rt, (0.0, 0.0), (1200.0, 0.0))
    _group(rt, slave, free, track)
    _joined(rt, track, slave)
    axis = rt.add_axis("master")
    axis.power()
    rt.run(0.01)
    feedback = MC_PlanarFeedbackGearInPosOnTrack()
    gear = slave.gear_in_pos_on_track(axis, None, 0.0, 100.0, track, feedback=feedback)
    rt.step()
    rt.step()
    assert gear.error and gear.error_id == ErrorId.PLANAR_COLLISION
    assert gear.object_info == PlanarObjectInfo(PlanarObjectType.MOVER, free.oid)
    away = free.move_to_position(PositionXYC(600.0, 400.0))
    _run_until(rt, away)
    gear = slave.gear_in_pos_on_track(axis, None, 0.0, 100.0, track)
    rt.step()
    rt.step()
    assert gear.busy and track.band
    halt = slave.halt()
    _run_until(rt, halt)
    rt.step()
    assert not track.band


# -- E: tracks on a route are Moving (§4.3) -------------------------------------------------------


def test_a_join_onto_the_target_track_of_a_route_is_refused():
    """Review t8b: mover one on a moves to 300 on b; b is Moving from the start, so mover
    two's JoinTrack onto b is refused and mover one ends at (900, 0) (b starts at a's end,
    x = 600)."""
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (100.0, 0.0), (900.0, 240.0))
    a = _line(rt, (0.0, 0.0), (600.0, 0.0))
    b = _line(rt, (700.0, 0.0), (1500.0, 0.0), after=a)
    _joined(rt, a, one)
    move = one.move_on_track(b, 300.0)
    rt.run(0.01)
    assert b.operation_mode is TrackOperationMode.MOVING
    assert (b.mover_count_on_track, b.moving_mover_count) == (0, 1)
    join = two.join_track(b)
    rt.step()
    rt.step()
    assert join.error and join.error_id == ErrorId.PLANAR_WRONG_MODE
    _run_until(rt, move)
    assert (one.position.x, one.position.y) == pytest.approx((900.0, 0.0), abs=1e-9)
    assert (two.position.x, two.position.y) == pytest.approx((900.0, 240.0), abs=1e-9)


def test_a_move_onto_a_configuring_track_is_refused():
    """Review t8c: mover two joins b; mover one's MoveOnTrack from a onto b is refused
    (WRONG_MODE, naming b) and it stays at 100."""
    rt = om.Runtime(0.001)
    one, two = _movers(rt, (100.0, 0.0), (900.0, 400.0))
    a = _line(rt, (0.0, 0.0), (600.0, 0.0))
    b = _line(rt, (700.0, 0.0), (1500.0, 0.0), after=a)
    _joined(rt, a, one)
    join = two.join_track(b)
    rt.run(0.01)
    assert b.operation_mode is TrackOperationMode.CONFIGURING
    move = one.move_on_track(b, 300.0)
    rt.step()
    rt.step()
    assert move.error and move.error_id == ErrorId.PLANAR_WRONG_MODE
    assert b.name in move.message
    _run_until(rt, join)
    assert _s(one) == pytest.approx(100.0, abs=1e-9)


# -- review findings (session 8) ------------------------------------------------------------------


def _travel(rt: om.Runtime, mover: MC_PlanarMover, length: float, command) -> float:
    """The signed arc length a mover on a loop travels until ``command`` ends."""
    travelled, last = 0.0, _s(mover)
    while command.busy:
        rt.step()
        now = _s(mover)
        assert 0.0 <= now < length  # SETONTRACK stays on the loop
        step = (now - last) % length
        travelled += step if step < length / 2 else step - length
        last = now
    return travelled


@pytest.mark.parametrize(("direction", "turns", "target", "way"), [
    (0, 0, 200.0, 100.0), (1, 0, 200.0, 100.0), (2, 0, 200.0, 100.0),
    (1, 2, 200.0, 100.0 + 2 * 3475.7966208946273), (3, 1, 50.0, -50.0 - 3475.7966208946273),
])
def test_a_direction_given_as_its_number_is_that_direction(direction, turns, target, way):
    """§7.2.1.1.2: MC_DIRECTION is a UINT; 1 = Positive with two turns goes 100 mm and two
    laps (an int was compared by identity and driven 3375.8 mm backwards)."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt)
    (mover,) = _movers(rt, (100.0, 0.0))
    _joined(rt, loop, mover)
    move = mover.move_on_track(None, target, options=ST_MoveOnTrackOptions(
        direction=direction, additional_turns=turns))
    assert _travel(rt, mover, loop.get_length(), move) == pytest.approx(way, abs=1e-6)
    assert move.done and _s(mover) == pytest.approx(target, abs=1e-6)


@pytest.mark.parametrize(("laps", "way"), [(1.0, 1.0), (1.5, 1.5), (-0.5, -0.5), (2.25, 2.25)])
def test_non_modulo_on_a_closed_loop_passes_the_seam_as_often_as_the_target_says(laps, way):
    """§7.2.1.1.2: NonModulo on a looped track goes to the absolute target, passing the
    seam as often as it takes: from 0, a target of 1.5 L ends at L / 2 after 1.5 L; L ends
    at 0, not at L (both were refused or off the track's range)."""
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt)
    length = loop.get_length()
    (mover,) = _movers(rt, (0.0, 0.0))
    _joined(rt, loop, mover)
    move = mover.move_on_track(None, laps * length)
    assert _travel(rt, mover, length, move) == pytest.approx(way * length, abs=1e-6)
    assert move.done and _s(mover) == pytest.approx((laps * length) % length, abs=1e-6)


def test_a_target_off_an_open_track_or_modulo_off_a_loop_is_still_refused():
    rt = om.Runtime(0.001)
    loop = enabled_loop(rt)
    line = _line(rt, (0.0, 1200.0), (800.0, 1200.0))
    a, b = _movers(rt, (0.0, 0.0), (100.0, 1200.0))
    _joined(rt, loop, a)
    _joined(rt, line, b)
    refused = [a.move_on_track(None, 1.5 * loop.get_length(), options=ST_MoveOnTrackOptions(
        direction=ModuloDirection.POSITIVE)), b.move_on_track(None, 900.0)]
    rt.step()
    assert [c.error_id for c in refused] == [ErrorId.PLANAR_POSITION_LIMIT] * 2


@pytest.mark.parametrize(("direction", "forwards"), [
    (ModuloDirection.POSITIVE, True), (ModuloDirection.SHORTEST_WAY, False),
    (ModuloDirection.NEGATIVE, False), (ModuloDirection.NON_MODULO, False),
])
def test_positive_to_a_point_behind_goes_round_a_loop_of_two_tracks(direction, forwards):
    """§6.1.9, §6.2.10: tracks one and two make a loop (one -> two -> one). From 600 on one,
    Positive to 100 on one goes forwards round through two (1184.1 mm; it was refused as
    if the way had no loop); ShortestWay takes the 500 mm back, as do Negative and
    NonModulo."""
    rt = om.Runtime(0.001)
    one, two = MC_PlanarTrack(rt), MC_PlanarTrack(rt)
    one.append_line(PositionXYC(250.0, 120.0), PositionXYC(650.0, 120.0))
    one.append_line(PositionXYC(700.0, 170.0), PositionXYC(700.0, 450.0))
    one.append_line(PositionXYC(650.0, 500.0), PositionXYC(250.0, 500.0))
    two.start_from_track(one)
    two.append_line(PositionXYC(200.0, 450.0), PositionXYC(200.0, 170.0))
    two.end_at_track(one)
    one.enable()
    two.enable()
    rt.run(0.005)
    assert not one.closed_loop and one.subsequent_tracks == [two.oid]
    (mover,) = _movers(rt, _at(one, 600.0))
    _joined(rt, one, mover)
    move = mover.move_on_track(None, 100.0, options=ST_MoveOnTrackOptions(direction=direction))
    velocities, tracks = [], set()
    while move.busy:
        rt.step()
        velocities.append(_v(mover))
        tracks.add(mover.mc_to_plc.set_on_track.track_oid)
    assert move.done and _s(mover) == pytest.approx(100.0, abs=1e-6)
    if forwards:
        assert min(velocities) >= 0.0 and two.oid in tracks
    else:
        assert max(velocities) <= 0.0 and tracks == {one.oid}
