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
(§6.2.12). A slave that would leave that path stops exactly at its end (or its start), loses
sync and the command ends in error (§6.2.8).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.enums import SyncDirections
from openmotion.planar.options import (
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    command_dynamics,
)
from openmotion.planar.positions import finite
from openmotion.planar.states import MoverCommand, check_track_accepts
from openmotion.planar.track import MC_PlanarTrack
from openmotion.planar.traffic import Leg, Rider, ahead_legs
from openmotion.transport.enums import SyncStrategy
from openmotion.transport.gear import GearSync

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
    failed: tuple[ErrorId, str] | None = None
    followed: list[Any] = field(default_factory=list)  #: master legs appended so far
    directions: SyncDirections = SyncDirections.POSITIVE  #: allowed while synchronising
    planned_v: float | None = None  #: master velocity the sync was planned for [mm/s]
    resync: bool = False  #: plan the sync again after this cycle


def gear_in_pos_on_track(mover: MC_PlanarMover, command: PlanarCommand) -> None:
    axis, trail, master_sync, slave_sync, slave_track, constraint, options = command.args
    options = options or ST_GearInPosOnTrackOptions()
    options.check()
    if not hasattr(axis, "set_position"):
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, "GearInPosOnTrack: the master must "
                              "be an axis of this runtime")
    rider, traffic = _slave(mover, _C.GEAR_IN_POS_ON_TRACK)
    legs = _trail_legs(rider, trail, slave_track, traffic)
    coupling = _coupling(mover, command, legs, finite(master_sync, "masterSyncPosition"),
                         slave_track, slave_sync, constraint, options.in_sync_tolerance_distance,
                         options.allowed_slave_sync_directions)
    coupling.axis = axis
    _admit_path(mover, legs, _C.GEAR_IN_POS_ON_TRACK)
    _prime(coupling, traffic)
    traffic.gear(rider, legs, coupling, options.gap, command)


def gear_in_pos_on_track_with_master_mover(mover: MC_PlanarMover, command: PlanarCommand
                                           ) -> None:
    (master_mover, trail, master_sync, master_track, slave_sync, slave_track, constraint,
     options) = command.args
    options = options or ST_GearInPosOnTrackWithMasterMoverOptions()
    options.check()
    rider, traffic = _slave(mover, _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER)
    master_rider = getattr(master_mover, "_rider", None)
    if master_mover is mover or master_rider is None:
        raise CommandRejected(ErrorId.PLANAR_WRONG_MODE,
                              "GearInPosOnTrackWithMasterMover: the master must be another "
                              "mover on a track (§6.2.9)")
    master_at = traffic.path_coordinate(master_rider, master_track,
                                        finite(master_sync, "masterSyncPosition"))
    if master_at is None:
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"GearInPosOnTrackWithMasterMover: {master_track.name} is neither "
                              "the master's track nor on its commanded way (§6.1.9)")
    if options.follow_mover:
        legs = _follow_legs(rider, trail, master_rider, master_track, traffic)
    else:
        legs = _trail_legs(rider, trail, slave_track, traffic)
    coupling = _coupling(mover, command, legs, master_at, slave_track, slave_sync,
                         constraint, options.in_sync_tolerance_distance,
                         options.allowed_slave_sync_directions)
    coupling.master, coupling.follow = master_rider, options.follow_mover
    _admit_path(mover, legs, _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER)
    _prime(coupling, traffic)
    traffic.gear(rider, legs, coupling, options.gap, command)


def _admit_path(mover: MC_PlanarMover, legs: list[Leg], kind: MoverCommand) -> None:
    """The gear path is a way the slave may move on like a MoveOnTrack route: its tracks
    must take the motion (§4.3), and in a group they hold their bands while it is geared,
    so the group's collision avoidance keeps other movers off them (§6.5); the bands go back
    when the gear ends (riding.release_bands). Refused with PLANAR_COLLISION naming the
    member in the way."""
    from openmotion.planar.riding import _reserve_bands, check_route_accepts

    tracks = [leg.track for leg in legs]
    check_route_accepts(tracks, kind)
    _reserve_bands(mover, tracks, str(kind))


def _slave(mover: MC_PlanarMover, kind: MoverCommand) -> tuple[Rider, Any]:
    from openmotion.planar.riding import _rider
    from openmotion.planar.track import traffic_of

    rider = _rider(mover)
    check_track_accepts(rider.track._states.current, rider.track.operation_mode, kind)
    return rider, traffic_of(mover._system)


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
    """followMover: the trail (if any), the shortest way on to the master's sync track,
    then the master's way from there (§6.2.12)."""
    here, s, _, _ = traffic.position(rider)
    tracks = [here]
    if trail and here in trail.tracks:
        tracks = trail.tracks[trail.tracks.index(here):]
    if master_track not in tracks:
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
              master_at: float, slave_track: MC_PlanarTrack, slave_sync: float,
              constraint: Any, tolerance: float, directions: SyncDirections) -> Coupling:
    slave_sync = finite(slave_sync, "slaveSyncPosition")
    if not 0.0 <= slave_sync <= slave_track.length:
        raise CommandRejected(ErrorId.PLANAR_POSITION_LIMIT,
                              f"slaveSyncPosition {slave_sync:g} is off {slave_track.name} "
                              f"(0 to {slave_track.length:g} mm)")
    base = next((leg.base for leg in legs if leg.track is slave_track), None)
    if base is None:  # a follower's way does not pass it (no trail, §6.2.12)
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"slaveSyncPositionTrack {slave_track.name} is not on the "
                              "slave's way along its master (§6.2.9)")
    p = mover.parameters
    limits = command_dynamics(constraint, p.default_dynamic_xy, p.maximum_dynamic_xy,
                              command.warnings)
    sync = GearSync(master_row=-1, ratio=1.0, master_sync_position=master_at,
                    slave_sync_position=base + slave_sync, strategy=SyncStrategy.EARLY,
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
        dt = traffic.dt
        mp, mv, ma = (mp - dt * (mv - dt * (ma / 2.0 - dt * mj / 6.0)),
                      mv - dt * (ma - dt * mj / 2.0), ma - dt * mj)
    coupling.sync.prime((mp, mv, ma, mj))


def master_state(coupling: Coupling, traffic: Any) -> tuple[float, float, float, float]:
    """The master's set values this cycle: an axis's, or a master mover's path coordinate."""
    if coupling.axis is not None:
        axis = coupling.axis
        return (axis.set_position, axis.set_velocity, axis.set_acceleration, axis.set_jerk)
    assert coupling.master is not None
    return traffic.path_state(coupling.master)

