"""Gear-in on tracks: GearInPosOnTrack, GearInPosOnTrackWithMasterMover, MC_PlanarTrackTrail
(TF5430 §6.1.9, §6.2.8, §6.2.9, §6.2.12, §6.8, §7.2.2.8.5-6, §7.2.2.11).

The slave synchronises to its master 1:1 in the master's frame: once in sync its arc-length
position is ``slave sync + (master - master sync)`` on the master's set values of the same
cycle. The synchronisation itself is the CA gear's (``transport.gear.GearSync``, through its
public interface) with the Early strategy: the sync error is brought to 0 as fast as the
command's dynamics allow, so the slave is in sync at the latest when the master reaches its
sync position, earlier where it can (§6.2.8). Gap keeping has priority: a slave the gap
filter brakes loses sync and synchronises again (§6.2.8).

Master positions. An axis master gives its set position. A master mover gives its path
coordinate: its arc length summed over the tracks it has travelled (§6.1.9), which the
traffic keeps as odometer minus the shifts of its new routes.

Where the slave may go: the tracks of the trail (or its own track without one), or with
``follow_mover`` the shortest way to the master's sync track and then the master's way
(§6.2.12). A path that ends in a closed loop goes on round it lap by lap; a follower's way
grows as its master's does, each new track admitted first (in a group: its band) through
the mover (D-148, D-149). A slave that would leave that path stops exactly at its end (or
the start of its track), loses sync and the command ends in error (§6.2.8).

Sync positions: on a closed loop the modulo options place them as MoveC places its target,
with the loop's length as modulus, from where the mover stands (D-148).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from openmotion.core.enums import ModuloDirection, convert_enum
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.modulo import mc3_modulo_target
from openmotion.planar.enums import SyncDirections
from openmotion.planar.options import (
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    command_dynamics,
)
from openmotion.planar.positions import finite
from openmotion.planar.riders import Leg, Rider, ahead_legs
from openmotion.planar.states import MoverCommand, check_track_accepts
from openmotion.planar.track import MC_PlanarTrack
from openmotion.rail.enums import SyncStrategy
from openmotion.rail.gear import GearSync

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis
    from openmotion.planar.feedback import PlanarCommand
    from openmotion.planar.mover import MC_PlanarMover

_C = MoverCommand


class MC_PlanarTrackTrail:
    """An ordered list of tracks, each starting where the one before ends (§6.8): the way a
    geared slave may take through the network. A PLC container: no Update, no feedback; a
    track that does not fit is refused with ``error`` and ``message`` set."""

    def __init__(self) -> None:
        self.tracks: list[MC_PlanarTrack] = []
        self.error = False
        self.error_id = ErrorId.NO_ERROR
        self.message = ""

    def clear(self) -> None:
        self.tracks.clear()
        self.error, self.error_id, self.message = False, ErrorId.NO_ERROR, ""

    def add_track(self, track: MC_PlanarTrack) -> bool:
        """Append ``track``; False (and ``error``) when it is in the trail already or does
        not start at the end vertex of the last one."""
        if not isinstance(track, MC_PlanarTrack):
            raise TypeError(f"a trail holds MC_PlanarTrack objects, got {type(track).__name__}")
        why = ""
        if any(t is track for t in self.tracks):
            why = f"{track.name} is in the trail already (§6.8)"
        elif self.tracks and track.oid not in self.tracks[-1].subsequent_tracks:
            why = f"{track.name} does not start where {self.tracks[-1].name} ends (§6.8)"
        if why:
            self.error, self.error_id, self.message = True, ErrorId.PLANAR_INVALID_INPUT, why
            return False
        self.tracks.append(track)
        return True


@dataclass
class Coupling:
    """A geared rider: its master, its sync and the stretch of its route it may use."""

    sync: GearSync
    axis: Axis | None = None
    master: Rider | None = None
    follow: bool = False
    tolerance: float = 0.0  #: inSyncToleranceDistance [mm]
    low: float = 0.0  #: odometer bounds of the path the slave may use
    high: float = 0.0
    stopping: bool = False  #: braking to a path end, the command then fails
    #: error id, message (and the collision partner) the command ends with once at rest
    failed: tuple[ErrorId, str] | tuple[ErrorId, str, Any] | None = None
    #: followMover: a master leg lies at its path coordinate + offset on the slave's odometer,
    #: from ``joined`` on (where the slave's way reaches the master's sync track)
    offset: float = 0.0
    joined: float = 0.0
    seen: tuple[Any, ...] = ()  #: the master's way as last looked at (``_extend_follow``)
    blocked: CommandRejected | None = None  #: why the way does not go on (D-149)
    directions: SyncDirections = SyncDirections.POSITIVE  #: allowed while synchronising
    planned_v: float | None = None  #: master velocity the sync was planned for [mm/s]
    resync: bool = False  #: plan the sync again after this cycle
    #: the gap filter or a switch zone braked it last cycle (with gap control's brake)
    braked: bool = False


def gear_in_pos_on_track(mover: MC_PlanarMover, command: PlanarCommand) -> None:
    axis, trail, master_sync, slave_sync, slave_track, constraint, options = command.args
    options = options or ST_GearInPosOnTrackOptions()
    options.check()
    if not hasattr(axis, "set_position"):
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, "GearInPosOnTrack: the master must "
                              "be an axis of this runtime")
    rider, traffic = _slave(mover, _C.GEAR_IN_POS_ON_TRACK)
    legs = _trail_legs(rider, trail, slave_track, traffic)
    slave_at = _slave_sync_at(traffic, rider, legs, slave_track, slave_sync,
                              options.direction_slave_sync_position,
                              options.modulo_tolerance_slave_sync_position)
    coupling = _coupling(mover, command, legs, finite(master_sync, "masterSyncPosition"),
                         slave_at, constraint, options.in_sync_tolerance_distance,
                         options.allowed_slave_sync_directions)
    coupling.axis = axis
    admit_way(mover, [leg.track for leg in legs], _C.GEAR_IN_POS_ON_TRACK)
    _prime(coupling, traffic)
    traffic.gear(rider, legs, coupling, options.gap, command)


def gear_in_pos_on_track_with_master_mover(mover: MC_PlanarMover, command: PlanarCommand
                                           ) -> None:
    (master_mover, trail, master_sync, master_track, slave_sync, slave_track, constraint,
     options) = command.args
    options = options or ST_GearInPosOnTrackWithMasterMoverOptions()
    options.check()
    rider, traffic = _slave(mover, _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER)
    master_rider = getattr(master_mover, "rider", None)
    if master_mover is mover or master_rider is None:
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE,
                              "GearInPosOnTrackWithMasterMover: the master must be another "
                              "mover on a track (§6.2.9)")
    master_at = _master_sync_at(traffic, master_rider, master_track,
                                finite(master_sync, "masterSyncPosition"),
                                options.direction_master_sync_position,
                                options.modulo_tolerance_master_sync_position)
    if options.follow_mover:
        legs = _follow_legs(rider, trail, master_rider, master_track, traffic)
    else:
        legs = _trail_legs(rider, trail, slave_track, traffic)
    slave_at = _slave_sync_at(traffic, rider, legs, slave_track, slave_sync,
                              options.direction_slave_sync_position,
                              options.modulo_tolerance_slave_sync_position)
    coupling = _coupling(mover, command, legs, master_at, slave_at, constraint,
                         options.in_sync_tolerance_distance,
                         options.allowed_slave_sync_directions)
    coupling.master, coupling.follow = master_rider, options.follow_mover
    if options.follow_mover:  # where the master's legs lie on the slave's odometer
        coupling.joined = next(leg.base for leg in legs if leg.track is master_track)
        start = traffic.path_coordinate(master_rider, master_track, 0.0)
        coupling.offset = coupling.joined - start
    admit_way(mover, [leg.track for leg in legs], _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER)
    _prime(coupling, traffic)
    traffic.gear(rider, legs, coupling, options.gap, command)


def admit_way(mover: MC_PlanarMover, tracks: list[MC_PlanarTrack], kind: MoverCommand
              ) -> None:
    """The gear path is a way the slave may move on like a MoveOnTrack route: its tracks
    must take the motion (§4.3), and in a group they hold their bands while it is geared,
    so the group's collision avoidance keeps other movers off them (§6.5); the bands go back
    when the gear ends (riding.release_bands). Refused with PLANAR_COLLISION naming the
    member in the way. Asked at the start for the whole path, and by the traffic for each
    track a follower's way goes on to later (``MotionPort.admit_way``, D-149)."""
    from openmotion.planar.riding import _reserve_bands, check_route_accepts

    check_route_accepts(tracks, kind)
    _reserve_bands(mover, tracks, str(kind))


def _slave_sync_at(traffic: Any, rider: Rider, legs: list[Leg], track: MC_PlanarTrack,
                   position: float, direction: ModuloDirection, tolerance: float) -> float:
    """The slave sync position on the slave's odometer. NonModulo: ``position`` on the
    first leg of ``track`` in ``legs``. A modulo direction needs ``track`` to be a closed
    loop (§6.2.8: the modulus is its length) and reads as MoveC's from where the slave
    stands on it: Positive the next occurrence ahead, Negative the last one behind,
    ShortestWay the nearer one, a distance within ``tolerance`` the nearer one whatever the
    direction. A loop the slave is not on yet lies ahead of it: its first occurrence there,
    and Negative finds none (D-148)."""
    position = finite(position, "slaveSyncPosition")
    if not 0.0 <= position <= track.length:
        raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                              f"slaveSyncPosition {position:g} is off {track.name} "
                              f"(0 to {track.length:g} mm)")
    base = next((leg.base for leg in legs if leg.track is track), None)
    if base is None:  # a follower's way does not pass it (no trail, §6.2.12)
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"slaveSyncPositionTrack {track.name} is not on the "
                              "slave's way along its master (§6.2.9)")
    here, s, _, _ = traffic.position(rider)
    return base + _modulo(track, here, s, position, direction, tolerance, "slave")


def _master_sync_at(traffic: Any, master: Rider, track: MC_PlanarTrack, position: float,
                    direction: ModuloDirection, tolerance: float) -> float:
    """The master sync position as a path coordinate of the master (§6.1.9): NonModulo on
    the first leg of ``track`` on its way; a modulo direction as for the slave
    (``_slave_sync_at``), along the master's way from where it stands (D-148)."""
    at = traffic.path_coordinate(master, track, position)
    if at is None:
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"GearInPosOnTrackWithMasterMover: {track.name} is neither "
                              "the master's track nor on its commanded way (§6.1.9)")
    here, s, _, _ = traffic.position(master)
    return at - position + _modulo(track, here, s, position, direction, tolerance, "master")


def _modulo(track: MC_PlanarTrack, here: MC_PlanarTrack, s: float, position: float,
            direction: ModuloDirection, tolerance: float, whose: str) -> float:
    """Arc length on ``track``'s first leg of the mover's way (it may be negative: a lap
    behind) where the sync position ``position`` lies with the modulo ``direction``; the
    mover stands at ``s`` on ``here``."""
    direction = convert_enum(ModuloDirection, direction)
    if direction is ModuloDirection.NON_MODULO:
        return position
    name = "".join(word.title() for word in direction.name.split("_"))
    option = f"direction{whose.title()}SyncPosition {name}"
    if not track.closed_loop:
        raise CommandRejected(ErrorId.INVALID_MODULO_OPTIONS,
                              f"{option}: modulo sync positions need a closed-loop track; "
                              f"{track.name} is open (§7.2.1.2.7)")
    if here is not track:  # the loop lies ahead on the way
        if direction is ModuloDirection.NEGATIVE:
            raise CommandRejected(ErrorId.INVALID_DIRECTION,
                                  f"{option}: the {whose} is not on {track.name} yet, so no "
                                  "occurrence of the sync position lies behind it on its way "
                                  "(D-148)")
        return position
    return mc3_modulo_target(s, position, direction, 0, track.length, tolerance)


def _slave(mover: MC_PlanarMover, kind: MoverCommand) -> tuple[Rider, Any]:
    from openmotion.planar.riding import _rider
    from openmotion.planar.track import traffic_of

    rider = _rider(mover)
    check_track_accepts(rider.track.states.current, rider.track.operation_mode, kind)
    return rider, traffic_of(mover.system)


def _trail_legs(rider: Rider, trail: MC_PlanarTrackTrail | None, slave_track: MC_PlanarTrack,
                traffic: Any) -> list[Leg]:
    """The slave's path: its own track, then the trail's tracks after it (§6.8)."""
    here = traffic.position(rider)[0]
    tracks = [here]
    if trail:
        names = [t.name for t in trail.tracks]
        if here not in trail.tracks:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"the trail {names} does not hold the slave's track "
                                  f"{here.name} (§6.8)")
        tracks = trail.tracks[trail.tracks.index(here):]
    if slave_track not in tracks:
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"the slave sync track {slave_track.name} is not on the slave's "
                              "path (its track or its trail, §6.2.8)")
    return _legs(tracks)


def _follow_legs(rider: Rider, trail: MC_PlanarTrackTrail | None, master: Rider,
                 master_track: MC_PlanarTrack, traffic: Any) -> list[Leg]:
    """followMover: the trail (if any; it leads only to the master's sync track), the
    shortest way on to that track, then the master's way from there (§6.2.12)."""
    here, s, _, _ = traffic.position(rider)
    tracks = [here]
    if trail:
        if here not in trail.tracks:  # as without followMover: the trail starts here
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"the trail {[t.name for t in trail.tracks]} does not hold "
                                  f"the slave's track {here.name} (§6.8, §6.2.12)")
        tracks = trail.tracks[trail.tracks.index(here):]
    if master_track in tracks:
        tracks = tracks[:tracks.index(master_track) + 1]
    else:
        route = here.network.route(tracks[-1], 0.0 if len(tracks) > 1 else s, master_track, 0.0)
        if route is None:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"the master's sync track {master_track.name} cannot be "
                                  "reached from the slave's track (§6.2.12)")
        tracks += [leg.track for leg in route[1:]]
    master_way = [leg.track for leg in ahead_legs(master.route)]
    if master_track in master_way:
        tracks += master_way[master_way.index(master_track) + 1:]
    return _legs(tracks)


def _legs(tracks: list[MC_PlanarTrack]) -> list[Leg]:
    legs, base = [], 0.0
    for track in tracks:
        legs.append(Leg(track, base))
        base += track.length
    return legs


def _coupling(mover: MC_PlanarMover, command: PlanarCommand, legs: list[Leg],
              master_at: float, slave_at: float, constraint: Any, tolerance: float,
              directions: SyncDirections) -> Coupling:
    p = mover.parameters
    limits = command_dynamics(constraint, p.default_dynamic_xy, p.maximum_dynamic_xy,
                              command.warnings)
    sync = GearSync(master_row=-1, ratio=1.0, master_sync_position=master_at,
                    slave_sync_position=slave_at, strategy=SyncStrategy.EARLY,
                    start_distance=None, limits=limits, after_sync=limits)
    end = legs[-1].base + legs[-1].track.length
    return Coupling(sync, tolerance=tolerance, low=0.0, high=end, directions=directions)


def _prime(coupling: Coupling, traffic: Any) -> None:
    """The sync is planned from the slave's state of the last cycle, so it needs the master's
    of the last cycle too (GearSync otherwise takes this cycle's for both, and a slave gearing
    in to a moving master jumps by the master's travel in one cycle). A master mover has not
    moved yet this cycle; an axis has (axes run before the planar system): its values one
    cycle back along its jerk."""
    mp, mv, ma, mj = master_state(coupling, traffic)
    if coupling.axis is not None:
        cycle_time = traffic.cycle_time
        mp, mv, ma = (mp - cycle_time * (mv - cycle_time * (ma / 2.0 - cycle_time * mj / 6.0)),
                      mv - cycle_time * (ma - cycle_time * mj / 2.0), ma - cycle_time * mj)
    coupling.sync.prime((mp, mv, ma, mj))


def master_state(coupling: Coupling, traffic: Any) -> tuple[float, float, float, float]:
    """The master's set values this cycle: an axis's, or a master mover's path coordinate."""
    if coupling.axis is not None:
        axis = coupling.axis
        return (axis.set_position, axis.set_velocity, axis.set_acceleration, axis.set_jerk)
    assert coupling.master is not None
    return traffic.path_state(coupling.master)

