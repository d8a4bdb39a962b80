"""The track commands of a mover: JoinTrack, LeaveTrack, MoveOnTrack, Halt on a track
(TF5430 §4.2, §6.1.9, §6.2.4, §7.2.2.8.2-4).

JoinTrack is a free move onto the track point nearest to the mover (the manual does not say
where a mover joins; every example fits the nearest point, docs/decisions.md) and couples
the mover there: its x, y (and c, with ``use_orientation``) then follow the track (traffic.py).
LeaveTrack uncouples at once and is a free move to its target. MoveOnTrack plans one
profile along the route to its target and leaves gap keeping and switches to the traffic.
They start and place the mover's motion through its ``MotionPort`` (``mover.port``, D-239).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from openmotion.core.enums import ModuloDirection
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.enums import PlanarObjectType
from openmotion.planar.motion import plan_move_to_position
from openmotion.planar.options import (
    ST_JoinTrackOptions,
    ST_LeaveTrackOptions,
    ST_MoveOnTrackOptions,
    command_dynamics,
)
from openmotion.planar.positions import finite
from openmotion.planar.states import MoverCommand, check_track_accepts
from openmotion.planar.traffic import Leg, Rider
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import Profile

if TYPE_CHECKING:
    from openmotion.planar.feedback import PlanarCommand
    from openmotion.planar.mover import MC_PlanarMover
    from openmotion.planar.reservation import MemberId, ReservationRegistry
    from openmotion.planar.track import MC_PlanarTrack

_C = MoverCommand


def join_track(mover: MC_PlanarMover, command: PlanarCommand) -> None:
    from openmotion.planar.track import MC_PlanarTrack, traffic_of

    track, constraint, options = command.args
    if not isinstance(track, MC_PlanarTrack) or track.system is not mover.system:
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              "JoinTrack: the target must be a track of this runtime")
    options = options or ST_JoinTrackOptions()
    options.check()
    check_track_accepts(track.states.current, track.operation_mode, _C.JOIN_TRACK)
    p = mover.parameters
    limits = command_dynamics(constraint, p.default_dynamic_xy, p.maximum_dynamic_xy,
                              command.warnings)
    pose = mover.port.set_pose()
    s = track.arc_length_closest_to_pose(pose, mover.coordinate_system)
    x, y, heading, _ = track.frame_at(np.array([s]))
    c = pose.c
    if options.use_orientation:  # the track's heading, the nearest way round
        c += (math.degrees(float(heading[0])) - c + 180.0) % 360.0 - 180.0
    motion = _free_move(mover, (float(x[0]), float(y[0]), c), limits,
                        options.use_orientation)

    def coupled(done: bool) -> None:
        track.configuring.discard(mover.oid)
        mover.modes.ended(_C.JOIN_TRACK, done=done, c=mover.port.set_pose().c)
        if not done:
            return
        row = mover.port.odometer_row(s)
        rows = (mover.port.rows["x"], mover.port.rows["y"], mover.port.rows["c"])
        brake = p.maximum_dynamic_xy
        rider = Rider(mover, track, s, row, rows, ST_MoveOnTrackOptions().gap,
                      (brake.deceleration, brake.jerk), options.use_orientation,
                      mover.port.set_pose().c, half=(p.mover_width / 2, p.mover_height / 2))
        traffic_of(mover.system).couple(rider)
        mover.port.couple(rider)

    mover.port.begin(command, motion, "the join", on_end=coupled)
    track.configuring.add(mover.oid)
    mover.modes.started(_C.JOIN_TRACK)


def leave_track(mover: MC_PlanarMover, command: PlanarCommand) -> None:
    from openmotion.planar.track import traffic_of

    target, constraint, options = command.args
    rider = _rider(mover)
    track = rider.track
    check_track_accepts(track.states.current, track.operation_mode, _C.LEAVE_TRACK)
    options = options or ST_LeaveTrackOptions()
    options.check()
    p = mover.parameters
    limits = command_dynamics(constraint, p.default_dynamic_xy, p.maximum_dynamic_xy,
                              command.warnings)
    _, pose = mover.port.resolve(target)
    goal = (pose.x, pose.y, pose.c) if options.use_orientation else (pose.x, pose.y)
    motion = _free_move(mover, goal, limits, options.use_orientation)
    # before the mover lets go of the track: a refused leave leaves it coupled (D-163)
    mover.port.check_carried(motion, None, mover.system.previous, "the leave")
    traffic = traffic_of(mover.system)
    traffic.uncouple(rider, mover.system.previous)
    mover.port.couple(None)

    def left(done: bool) -> None:
        track.configuring.discard(mover.oid)
        mover.modes.ended(_C.LEAVE_TRACK, done=done, c=mover.port.set_pose().c)

    mover.port.begin(command, motion, "the leave", on_end=left, check_carried=False)
    track.configuring.add(mover.oid)
    mover.modes.started(_C.LEAVE_TRACK)


def move_on_track(mover: MC_PlanarMover, command: PlanarCommand) -> None:
    from openmotion.planar.track import MC_PlanarTrack, traffic_of

    target_track, position, constraint, options = command.args
    rider = _rider(mover)
    options = options or ST_MoveOnTrackOptions()
    options.check()
    track = target_track or rider.track
    if not isinstance(track, MC_PlanarTrack) or track.system is not mover.system:
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              "MoveOnTrack: the target track must be a track of this runtime "
                              "(or 0 for the current one)")
    check_track_accepts(rider.track.states.current, rider.track.operation_mode,
                        _C.MOVE_ON_TRACK)
    if not track.usable:
        raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                              f"MoveOnTrack: {track.name} is not Enabled (§4.3)")
    position = finite(position, "targetPositionOnTrack")
    traffic = traffic_of(mover.system)
    here, s, _, _ = traffic.position(rider)
    passes = track is here and here.closed_loop and \
        options.direction is ModuloDirection.NON_MODULO  # laps allowed (§7.2.1.1.2)
    if not passes and not 0.0 <= position <= track.length:
        raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                              f"MoveOnTrack: {position:g} is off {track.name} "
                              f"(0 to {track.length:g} mm); movers never leave a track's ends "
                              "(§6.2.2)")
    p = mover.parameters
    limits = command_dynamics(constraint, p.default_dynamic_xy, p.maximum_dynamic_xy,
                              command.warnings)
    route, target = _route(here, s, track, position, options)
    check_route_accepts([leg.track for leg in route], _C.MOVE_ON_TRACK)
    limits = _curve_limits(limits, [leg.track for leg in route])
    _reserve_bands(mover, [leg.track for leg in route])
    traffic.ride(rider, route, target, limits, options.gap, command, mover.system.previous)


def check_route_accepts(tracks: list[MC_PlanarTrack], kind: MoverCommand) -> None:
    """Every track a command routes the mover onto must take it now, not only the one it is
    on: a track is Moving while movers are about to move onto it, so a mover joining it
    (Configuring) bars the way there as it bars motion on it (§4.3)."""
    for track in dict.fromkeys(tracks):
        try:
            check_track_accepts(track.states.current, track.operation_mode, kind)
        except CommandRejected as bad:
            raise CommandRejected(bad.error_id, f"{track.name}: {bad.message}") from None


def _reserve_bands(mover: MC_PlanarMover, tracks: list[MC_PlanarTrack],
                   what: str = "MoveOnTrack") -> None:
    """A mover in a group moves only on tracks of its group, and a track blocks its surface
    while a mover moves on it (§4.3, §6.5): the first motion over a track asks the group for
    the band the largest mover sweeps along it. The movers on those tracks do not block it;
    any other mover does, and the command is refused naming it. Other tracks and the
    environment block it only when the track checks static objects (§6.2.1, default off:
    connected tracks overlap at their joints, and a track near the stator edge is the
    user's layout)."""
    from openmotion.planar.mover import Collision
    from openmotion.planar.track import traffic_of

    group = mover.group
    if group is None:
        return
    for track in tracks:
        if track.group is not group:
            raise CommandRejected(ErrorId.PLANAR_NOT_IN_GROUP,
                                  f"{what}: {track.name} is not in the mover's group "
                                  f"16#{group.oid:08X}; collision avoidance needs it there "
                                  "(§4.3)")
    riders = [r.owner.member for r in traffic_of(mover.system).riders
              if any(r.track is t for t in tracks)]
    static = [m for m in group.registry.members
              if m.object_type in (PlanarObjectType.TRACK, PlanarObjectType.ENVIRONMENT)]
    needed = [t for t in dict.fromkeys(tracks) if not t.band]
    for track in needed:
        if track.check_collisions_against_static_objects:
            blocker = group.registry.blocker(track.member, track.surface(), riders)
        else:
            blocker = _moving_blocker(group.registry, track, riders + static)
        if blocker is not None:
            raise Collision(blocker, f"the surface of {track.name}")
    group.port.check_enabled(what)
    for track in needed:
        group.registry.settle(track.member, track.surface())
        track.band = True


def _moving_blocker(registry: ReservationRegistry, track: MC_PlanarTrack,
                    ignore: list[MemberId]) -> MemberId | None:
    """The first member other than ``ignore`` (the track's riders, the other tracks and the
    environment) whose area meets ``track``'s band."""
    return registry.blocker(track.member, track.surface(), ignore)


def release_bands(mover: MC_PlanarMover) -> None:
    """After a mover's track motion ended: it holds its footprint where it stands, and a
    track on which no mover moves any more gives its surface back (§4.3)."""
    from openmotion.planar.track import traffic_of

    group = mover.group
    if group is None:
        return
    group.registry.settle(mover.member, mover.port.standing_area(mover.port.set_pose()))
    traffic = traffic_of(mover.system)
    busy = {id(leg.track) for r in traffic.riders if traffic.moving(r) for leg in r.route}
    for track in traffic.network.tracks:
        if track.band and id(track) not in busy and track.group is not None:
            track.group.registry.vacate(track.member)
            track.band = False


def move_c_on_track(mover: MC_PlanarMover, command: PlanarCommand) -> None:
    """MoveC of a mover on a track: it must stand; its C no longer follows the track
    (Dependent -> Independent, §6.2.6, V3.1.10.51)."""
    from openmotion.planar.track import traffic_of

    rider = _rider(mover)
    _standing(mover, rider, "MoveC")
    traffic_of(mover.system).orient(rider, False)
    mover.port.move_c(command)


def adopt_track_orientation(mover: MC_PlanarMover, command: PlanarCommand) -> None:
    """Turn a standing mover on a track to the track's heading, then its C follows the track
    again (§6.2.7). A C motion like MoveC: the modulus, the modulo tolerance window and the
    options' direction and additional turns apply."""
    from openmotion.planar.motion import plan_move_c
    from openmotion.planar.options import ST_AdoptTrackOrientationOptions
    from openmotion.planar.track import traffic_of

    constraint, options = command.args
    rider = _rider(mover)
    _standing(mover, rider, "AdoptTrackOrientation")
    traffic = traffic_of(mover.system)
    traffic.orient(rider, False)  # the rotation drives C until it ends
    options = options or ST_AdoptTrackOrientationOptions()
    options.check()
    p = mover.parameters
    limits = command_dynamics(constraint, p.default_dynamic_c, p.maximum_dynamic_c,
                              command.warnings)
    track, s, _, _ = traffic.position(rider)
    _, _, heading, _ = track.frame_at(np.array([s]))
    profile = plan_move_c(mover.port.start_states("c")["c"], math.degrees(float(heading[0])),
                          limits, options.direction, options.additional_turns,
                          p.c_coordinate_modulus, p.c_coordinate_modulo_tolerance_window)

    def adopted(done: bool) -> None:
        if done:
            traffic.orient(rider, True, profile.end.position)

    mover.port.begin(command, {"c": profile}, "the rotation", c_motion=True, on_end=adopted)


def _standing(mover: MC_PlanarMover, rider: Rider, what: str) -> None:
    from openmotion.planar.track import traffic_of

    if traffic_of(mover.system).moving(rider):
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE,
                              f"{what} on a track needs the mover to stand; it moves on "
                              f"{rider.track.name} (§6.1.9)")


def halt_on_track(mover: MC_PlanarMover, command: PlanarCommand, limits: Limits) -> None:
    from openmotion.planar.track import traffic_of

    traffic_of(mover.system).halt(_rider(mover), limits, command, mover.system.previous)


def _rider(mover: MC_PlanarMover) -> Rider:
    if mover.rider is None:
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE, "the mover is on no track: JoinTrack "
                              "first (§4.2)")
    return mover.rider


def _free_move(mover: MC_PlanarMover, goal: tuple[float, ...], limits: Limits,
               turn: bool) -> dict[str, Profile]:
    """Profiles of a straight move to ``goal`` (x, y[, c]) from where the mover stands."""
    start = mover.port.start_states("x", "y", "c")
    p = mover.parameters
    motion = plan_move_to_position((start["x"], start["y"], start["c"]), goal, limits,
                                   p.default_dynamic_c)
    profiles = {"x": motion.x, "y": motion.y}
    if motion.c is not None:
        profiles["c"] = motion.c
    elif turn:
        profiles["c"] = Profile.hold(start["c"])
    return profiles


def _route(here: MC_PlanarTrack, s: float, track: MC_PlanarTrack, position: float,
           options: ST_MoveOnTrackOptions) -> tuple[list[Leg], float]:
    """The legs to ``position`` on ``track`` and the odometer target (the current track
    starts at 0). §6.1.9: Positive never moves backwards and Negative never forwards; on a
    closed loop they pick the way round (with whole extra laps, either way over the seam,
    D-147), ShortestWay the shorter one; on an open track or to another track there is one
    way only, and a direction that does not fit it refuses the command (D-144)."""
    direction = options.direction
    if track is here and here.closed_loop:
        if direction is ModuloDirection.NON_MODULO:  # absolute: passes over the seam either
            return _laps(here, s, position - s)  # way as far as the target lies (§7.2.1.1.2)
        return _loop_route(here, s, position, options)
    if options.additional_turns:
        raise CommandRejected(ErrorId.INVALID_MODULO_OPTIONS,
                              f"MoveOnTrack: additional turns ({options.additional_turns}) "
                              f"need a closed loop; the way to {track.name} is open (§6.1.9)")
    if track is here:
        legs, target = [Leg(here, 0.0)], position
        back = s - position
        if back > 0.0 and (direction is ModuloDirection.SHORTEST_WAY or (
                direction is ModuloDirection.POSITIVE and back > options.modulo_tolerance)):
            # forwards to a point behind: round a loop of several tracks, if the network
            # has one (§6.1.9, §6.2.10); ShortestWay takes it when it is the shorter way
            found = here.network.route(here, s, here, position)
            if found is not None and (direction is ModuloDirection.POSITIVE
                                      or found[-1].base + position - s < back):
                legs, target = found, found[-1].base + position
    else:
        found = here.network.route(here, s, track, position)
        if found is None:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"MoveOnTrack: {track.name} cannot be reached from "
                                  f"{here.name} (movers change track only from an end to a "
                                  "start, §6.2.2)")
        legs, target = found, found[-1].base + position
    way = target - s
    tolerance = options.modulo_tolerance
    if direction is ModuloDirection.POSITIVE and way < -tolerance or \
            direction is ModuloDirection.NEGATIVE and way > tolerance:
        raise CommandRejected(ErrorId.INVALID_DIRECTION,
                              f"MoveOnTrack: the target lies {abs(way):g} mm "
                              f"{'behind' if way < 0 else 'ahead'}; {direction.name.title()} "
                              "never moves the other way, and this way has no loop round "
                              "(§6.1.9)")
    return legs, target


def _loop_route(here: MC_PlanarTrack, s: float, position: float,
                options: ST_MoveOnTrackOptions) -> tuple[list[Leg], float]:
    """A modulo move on a closed loop (§6.1.9): the signed way to ``position`` (the near
    way within the modulo tolerance or for ShortestWay, else the way the direction asks
    for) plus whole laps in the commanded direction, as MC3 modulo moves count them. Its
    route is the loop once per lap it enters, forwards at bases L, 2L, ... and backwards
    over the seam at bases -L, -2L, ... (D-147); the odometer target lies on the last leg."""
    length = here.length
    direction = options.direction
    ahead = (position - s) % length
    behind = (s - position) % length
    if min(ahead, behind) <= options.modulo_tolerance or \
            direction is ModuloDirection.SHORTEST_WAY:
        way = ahead if ahead <= behind else -behind
    elif direction is ModuloDirection.POSITIVE:
        way = ahead
    else:
        way = -behind
    laps = options.additional_turns * length
    way += laps if direction is ModuloDirection.POSITIVE else \
        -laps if direction is ModuloDirection.NEGATIVE else 0.0
    return _laps(here, s, way)


def _laps(loop: MC_PlanarTrack, s: float, way: float) -> tuple[list[Leg], float]:
    """The legs of a closed loop from arc length ``s`` over the signed distance ``way``:
    the loop once per lap entered, forwards at bases L, 2L, ... and backwards over the seam
    at bases -L, -2L, ... (D-147); and the odometer target, on the last leg."""
    length = loop.length
    target = s + way
    count = max(0, math.floor(target / length) * (1 if way >= 0.0 else -1)) + 1
    step = length if way >= 0.0 else -length
    return [Leg(loop, k * step) for k in range(count)], target


def _curve_limits(limits: Limits, tracks: list[MC_PlanarTrack]) -> Limits:
    """Slow enough for the tightest curve of the route: the centripetal acceleration v²κ
    stays within the acceleration limit (§6.2.2 warns that tight curves limit dynamics;
    docs/decisions.md)."""
    curvature = max(_max_curvature(t) for t in tracks)
    if curvature <= 0.0:
        return limits
    cap = math.sqrt(min(limits.acceleration, limits.deceleration) / curvature)
    return limits if cap >= limits.velocity else limits.scaled_velocity(cap / limits.velocity)


#: per track path: (its table, its largest |curvature|); a new table is a new geometry
_CURVATURES: dict[int, tuple[object, float]] = {}
_CURVATURES_KEPT = 4096  #: entries before the cache starts afresh (tracks rebuilt often)


def _max_curvature(track: MC_PlanarTrack) -> float:
    """``track.path.max_curvature``, computed once per geometry: every MoveOnTrack asks it of
    each track on its route, and a blend's peak takes a search (D-287)."""
    path = track.path
    table = path.table
    known = _CURVATURES.get(id(path))
    if known is not None and known[0] is table:
        return known[1]
    if len(_CURVATURES) >= _CURVATURES_KEPT:
        _CURVATURES.clear()
    curvature = path.max_curvature
    _CURVATURES[id(path)] = (table, curvature)
    return curvature
