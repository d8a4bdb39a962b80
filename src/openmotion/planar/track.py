"""MC_PlanarTrack (TF5430 §4.3, §6.2, §7.2.2.10): a path on the stator surface for movers.

The geometry commands (AppendLine, AppendCircle, AppendPosition, CloseLoop, StartFromTrack,
EndAtTrack) build the curve in ``geometry.track``, which blends every corner so that the
track is continuous in direction and curvature. Links between track ends make the network
(network.py). Like every planar command they run in the motion phase in call order, so
AppendLine and Enable may come in the same cycle (§6.2.4).

Operation mode (§4.3), derived from the movers on the track: Uninitialized until the track is
Enabled with a geometry; Configuring while a mover joins or leaves it; Moving while a mover on
it, or one whose running command routes it onto it, has a motion command; Standing otherwise.
A track with movers on it, joining it or routed onto it keeps its geometry: it cannot be
disabled, and its geometry changes only without any (D-119).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, ClassVar, NamedTuple

import numpy as np

from openmotion.core.checks import non_negative_number, positive_number
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.geometry.track import TrackPath
from openmotion.geometry.track_elements import TrackPose
from openmotion.kernel.model import Kind
from openmotion.planar.enums import PlanarObjectType, PlanarState, TrackOperationMode
from openmotion.planar.feedback import MC_PlanarFeedbackBase, PlanarCommand, PlanarObjectInfo
from openmotion.planar.frames import Pose, cos_sin
from openmotion.planar.group import planar_group
from openmotion.planar.kind import PLANAR_TRACK
from openmotion.planar.network import END, START
from openmotion.planar.options import (
    CDT_MCTOPLC_PLANAR_TRACK_STD,
    ST_EndAtTrackAdvancedOptions,
    ST_StartFromTrackAdvancedOptions,
)
from openmotion.planar.positions import PositionXYC, finite, reference_id
from openmotion.planar.reservation import MemberId
from openmotion.planar.states import PlanarStateMachine
from openmotion.planar.system import PlanarSystem, StatefulObject
from openmotion.planar.traffic import Traffic, network_of, traffic_of

if TYPE_CHECKING:
    from openmotion.planar.group import MC_PlanarGroup
    from openmotion.planar.parts import Part
    from openmotion.runtime.runtime import Runtime

TRACK_COLLISION_RANGE = 250.0  #: [mm] default collision range at start and at end (§6.2.1)
MAX_MOVER_SIZE = 155.0  #: [mm] default maximal mover width and height (§6.2.1)


class MC_PlanarTrack(StatefulObject):
    """A planar track. ``collision_ranges`` = None computes them from the network as it is
    (mode Automatic, §6.2.2); a pair (start, end) in mm is mode Manual.
    ``check_collisions_against_static_objects`` (default False, §6.2.1): in a group, the
    band the track holds while movers move on it is checked against other tracks and the
    environment too; without it only movers can block the band (§6.5)."""

    MACHINE: ClassVar[Kind] = PLANAR_TRACK  #: its signals and commands in the machine model

    def __init__(self, runtime: Runtime, name: str | None = None, *,
                 max_mover_width: float = MAX_MOVER_SIZE,
                 max_mover_height: float = MAX_MOVER_SIZE,
                 collision_ranges: tuple[float, float] | None = None,
                 part_oid: int = 0,
                 check_collisions_against_static_objects: bool = False) -> None:
        system = PlanarSystem.of(runtime)
        super().__init__(system, system.next_oid("object"))
        self.name = name or f"track{len(network_of(system).tracks) + 1}"
        self.max_mover_width = positive_number(max_mover_width, f"{self.name}: max_mover_width")
        self.max_mover_height = positive_number(max_mover_height,
                                                f"{self.name}: max_mover_height")
        if collision_ranges is not None and not (
                isinstance(collision_ranges, tuple | list) and len(collision_ranges) == 2):
            raise ConfigError(f"{self.name}: collision ranges must be two numbers >= 0 (at "
                              f"the start, at the end) [mm], got {collision_ranges!r}")
        self.manual_collision_ranges = None if collision_ranges is None else tuple(
            non_negative_number(value, f"{self.name}: collision_ranges[{k}]")
            for k, value in enumerate(collision_ranges))
        if isinstance(part_oid, bool) or not isinstance(part_oid, int) or \
                not 0 <= part_oid <= 0xFFFF_FFFF:
            raise ConfigError(f"{self.name}: part_oid must be an object id (an int, 0: none), "
                              f"got {part_oid!r}")
        if not isinstance(check_collisions_against_static_objects, bool):
            raise ConfigError(f"{self.name}: check_collisions_against_static_objects must be a "
                              f"bool, got {check_collisions_against_static_objects!r}")
        self.check_collisions_against_static_objects = check_collisions_against_static_objects
        self.part_oid = part_oid  #: the part the track belongs to (0: the only one, or none)
        self.network = network_of(system)
        self.index = self.network.add(self)
        self.path = TrackPath()
        #: (end, start, condition): condition None for a link on one part, else
        #: (this part position, other part position, only those) across parts (§6.2.3)
        self.links: list[tuple[tuple[int, int], tuple[int, int], Link | None]] = []
        self._blocked = ""  #: why the geometry may not change any more ("" : it may)
        self._starts_from: MC_PlanarTrack | None = None
        self._group: MC_PlanarGroup | None = None
        self.band = False  #: the track holds its surface in its group (while Moving, §4.3)
        self.configuring: set[int] = set()  #: OIDs of movers joining or leaving
        self.states = PlanarStateMachine()
        self._rank = system.register(self)

    def __repr__(self) -> str:
        return f"<MC_PlanarTrack {self.name} 16#{self.oid:08X} {self.state.name}>"

    # -- the manual's methods (§7.2.2.10) --------------------------------------------------------

    def clear(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("Clear", feedback)

    def append_position(self, position: PositionXYC,
                        feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("AppendPosition", feedback, _point(position))

    def append_line(self, start: PositionXYC, end: PositionXYC,
                    feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("AppendLine", feedback, _point(start), _point(end))

    def append_circle(self, start: PositionXYC, end: PositionXYC, center: PositionXYC,
                      clockwise: bool, feedback: MC_PlanarFeedbackBase | None = None
                      ) -> PlanarCommand:
        return self._send("AppendCircle", feedback, _point(start), _point(end), _point(center),
                          bool(clockwise))

    def close_loop(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("CloseLoop", feedback)

    def start_from_track(self, track: MC_PlanarTrack,
                         feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("StartFromTrack", feedback, track, None)

    def end_at_track(self, track: MC_PlanarTrack,
                     feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("EndAtTrack", feedback, track, None)

    def start_from_track_advanced(self, track: MC_PlanarTrack,
                                  options: ST_StartFromTrackAdvancedOptions | None = None,
                                  feedback: MC_PlanarFeedbackBase | None = None
                                  ) -> PlanarCommand:
        return self._send("StartFromTrack", feedback, track, options)

    def end_at_track_advanced(self, track: MC_PlanarTrack,
                              options: ST_EndAtTrackAdvancedOptions | None = None,
                              feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("EndAtTrack", feedback, track, options)

    def add_to_group(self, group: MC_PlanarGroup,
                     feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("AddToGroup", feedback, planar_group(group))

    def remove_from_group(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send("RemoveFromGroup", feedback)

    @property
    def collision_ranges(self) -> tuple[float, float]:
        """(start, end) [mm]: the manual ones, or the automatic ones of the network as it is
        now (where the parts stand decides which tracks meet, §6.2.3); the default 250 mm
        while the track has no geometry."""
        if self.manual_collision_ranges is not None:
            return self.manual_collision_ranges
        if self.path.empty:
            return (TRACK_COLLISION_RANGE, TRACK_COLLISION_RANGE)
        self.network.refresh()
        return self.network.collision_ranges(self)

    def get_length(self) -> float:
        """The track length [mm] (0 while it has no geometry)."""
        return self.length

    def get_position_at(self, arc_length: float) -> PositionXYC:
        """The point at ``arc_length`` with the track's heading as c [deg]."""
        s = finite(arc_length, "arc_length")
        if self.length <= 0.0:
            raise ConfigError(f"{self.name} has no geometry")
        x, y, heading, _ = self.frame_at(np.array([min(max(s, 0.0), self.length)]))
        return PositionXYC(float(x[0]), float(y[0]), math.degrees(float(heading[0])),
                           self._system_oid())

    def get_arc_length_closest_to(self, position: PositionXYC) -> float:
        """The arc length where the track comes closest to ``position``'s centre point."""
        if self.length <= 0.0:
            raise ConfigError(f"{self.name} has no geometry")
        try:
            local = self._local(position)
        except CommandRejected as bad:
            raise ConfigError(f"{self.name}: {bad.message}") from None
        return float(self.path.arc_length_closest_to(local))

    def arc_length_closest_to_pose(self, pose: Pose, coordinate_system: int) -> float:
        """The arc length nearest a mover's centre (``pose`` in ``coordinate_system``, 0:
        without parts): the track's curve lies in its part's frame, which stands where the
        part's active position puts it (§6.2.3). A track in another coordinate system
        cannot be joined (PLANAR_INVALID_INPUT)."""
        system = self._system_oid()
        if coordinate_system != system:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"{self.name} lies in coordinate system 16#{system:08X}, the "
                                  f"mover in 16#{coordinate_system:08X} (§6.2.3)")
        local = self.placement().inverse().compose(Pose(pose.x, pose.y))
        return float(self.path.arc_length_closest_to((local.x, local.y)))

    def get_planar_object_info(self) -> PlanarObjectInfo:
        return PlanarObjectInfo(PlanarObjectType.TRACK, self.oid)

    # -- state -----------------------------------------------------------------------------------

    @property
    def group(self) -> MC_PlanarGroup | None:
        """The planar group it is in (AddToGroup done); None for none."""
        return self._group

    @property
    def state(self) -> PlanarState:
        return self.states.state

    @property
    def length(self) -> float:
        return float(self.path.length) if not self.path.empty else 0.0

    @property
    def usable(self) -> bool:
        """Enabled with a geometry: movers may join and travel on it."""
        return self.states.current is PlanarState.ENABLED and self.length > 0.0

    @property
    def operation_mode(self) -> TrackOperationMode:
        if not self.usable:
            return TrackOperationMode.UNINITIALIZED
        if self.configuring:
            return TrackOperationMode.CONFIGURING
        if self.moving_mover_count:
            return TrackOperationMode.MOVING
        return TrackOperationMode.STANDING

    def _check_unused(self, kind: str) -> None:
        """A track keeps its geometry while movers are on it, join it or are routed onto it:
        changing it under them would move them off their setpoints (D-119)."""
        users = self._traffic.riders_on(self, moving=False) + len(self.configuring)
        if users:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{kind}: {users} mover(s) are on {self.name}, join it or are "
                                  "routed onto it; LeaveTrack them first (§4.3)")

    @property
    def mover_count_on_track(self) -> int:
        return self._traffic.riders_at(self)

    @property
    def moving_mover_count(self) -> int:
        """Movers with a motion planned over this track: on it, or routed onto it (§4.3)."""
        return self._traffic.riders_on(self, moving=True)

    @property
    def previous_tracks(self) -> list[int]:
        return self.network.previous(self)

    @property
    def subsequent_tracks(self) -> list[int]:
        return self.network.subsequent(self)

    @property
    def closed_loop(self) -> bool:
        return self.network.closed_loop(self)

    @property
    def mc_to_plc_std(self) -> CDT_MCTOPLC_PLANAR_TRACK_STD:
        return CDT_MCTOPLC_PLANAR_TRACK_STD(
            track_oid=self.oid, group_oid=self._group.oid if self._group else 0,
            state=self.states.state, operation_mode=self.operation_mode,
            mover_count_on_track=self.mover_count_on_track,
            moving_mover_count=self.moving_mover_count)

    @property
    def member(self) -> MemberId:
        return MemberId(PlanarObjectType.TRACK, self.oid)

    @property
    def _traffic(self) -> Traffic:
        return traffic_of(self.system)

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """x, y [mm], heading [rad] and curvature [1/mm] at the arc lengths ``s``, in the
        coordinate system of its part's active position (§6.2.3: the track moves with it)."""
        x, y, heading, curvature = self.path.frame_at(s)
        place = self.placement()
        if place == _ORIGIN:
            return x, y, heading, curvature
        cos, sin = cos_sin(place.c)
        return (place.x + cos * x - sin * y, place.y + sin * x + cos * y,
                heading + math.radians(place.c), curvature)

    # -- parts (§6.2.3) ----------------------------------------------------------------------------

    def part(self) -> Part | None:
        """The part the track is on: its PartOID, or the only part; None without parts."""
        environment = self.system.environment()
        layout = None if environment is None else environment.layout
        if layout is None:
            return None
        if self.part_oid:
            return layout.part(self.part_oid)
        if len(layout.parts) == 1:
            return next(iter(layout.parts.values()))
        raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                              f"{self.name}: PartOID is needed with more than one part "
                              "(§6.2.3)")

    def placement(self, position_index: int = 0) -> Pose:
        """Where the track's part frame lies: in position ``position_index`` (1-based; 0:
        the active one); the identity without parts."""
        try:
            part = self.part()
        except CommandRejected:
            return _ORIGIN
        if part is None:
            return _ORIGIN
        if position_index:
            return part.positions[position_index - 1].pose
        return part.active_position.pose

    def _system_oid(self) -> int:
        part = self.part() if self.system.environment() is not None else None
        return 0 if part is None else part.active_position.coordinate_system

    def _local(self, position: PositionXYC) -> tuple[float, float]:
        """A point given with a ReferenceId in the track's part frame (§6.2.3: a part, or a
        coordinate system through the part's active position)."""
        finite(position.x, "x"), finite(position.y, "y")
        part = self.part()
        if part is None or position.reference_id == part.oid:
            return position.x, position.y
        environment = self.system.environment()
        assert environment is not None and environment.layout is not None
        system, pose = environment.layout.to_coordinate_system(position.reference_id,
                                                               Pose(position.x, position.y))
        active = part.active_position
        if system != active.coordinate_system:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                  f"{self.name}: the point is in coordinate system "
                                  f"16#{system:08X}, its part in 16#{active.coordinate_system:08X}")
        local = active.pose.inverse().compose(pose)
        return local.x, local.y

    def _pose_from(self, other: MC_PlanarTrack, at_end: bool, this_index: int,
                   other_index: int) -> TrackPose:
        """``other``'s end (or start) pose in this track's part frame, with the two parts in
        the given positions (0: active)."""
        pose = other.path.end_pose if at_end else other.path.start_pose
        there = other.placement(other_index)
        cos, sin = cos_sin(there.c)
        x, y = there.x + cos * pose.x - sin * pose.y, there.y + sin * pose.x + cos * pose.y
        here = self.placement(this_index).inverse()
        cos, sin = cos_sin(here.c)
        return TrackPose(here.x + cos * x - sin * y, here.y + sin * x + cos * y,
                         pose.heading + math.radians(there.c + here.c), pose.curvature)

    # -- execution -------------------------------------------------------------------------------

    def _execute(self, command: PlanarCommand) -> None:
        kind = command.kind
        if kind in ("Enable", "Disable", "Reset"):
            if kind == "Enable" and self.path.empty:
                raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                      f"{self.name} has no geometry to enable (§6.2.4)")
            if kind == "Disable":
                self._check_unused(kind)
            self.states.request(command)
            return
        if kind == "AddToGroup":
            self._add_to_group(command.args[0])
        elif kind == "RemoveFromGroup":
            if self._group is None:
                raise CommandRejected(ErrorId.PLANAR_NOT_IN_GROUP, f"{self.name} is in no group")
            self._group.port.leave(self.member)
            self._group, self.band = None, False
        else:
            self._edit(kind, command.args)
        command.finish()

    def _edit(self, kind: str, args: tuple) -> None:
        """A geometry command. Only a track that is not Enabled changes (movers may be on an
        enabled one), and not after a link froze it (§7.2.2.10)."""
        self.network.touch()
        if kind == "Clear":
            self._check_editable("Clear", frozen_ok=True)
            self.path = TrackPath()
            self._blocked = ""
            self.links.clear()
            self.network.touch()
            return
        self._check_editable(kind)
        try:
            if kind == "AppendPosition":
                self.path.append_position(self._local(args[0]))
            elif kind == "AppendLine":
                self.path.append_line(self._local(args[0]), self._local(args[1]))
            elif kind == "AppendCircle":
                start, end, center, clockwise = args
                self.path.append_circle(self._local(start), self._local(end),
                                        self._local(center), clockwise)
            elif kind == "CloseLoop":
                self.path.close_loop()
                self._link((self.index, END), (self.index, START))
                self._blocked = "it is a closed loop"
            elif kind == "StartFromTrack":
                other: MC_PlanarTrack = args[0]
                self._check_other(other, kind)
                if not self.path.empty:
                    raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                          f"StartFromTrack: {self.name} has a geometry already; "
                                          "StartFromTrack comes first (§6.2.10)")
                link = self._link_options(other, args[1])
                self.path.start_from(other.path if link is None else
                                     self._pose_from(other, True, link.this_index,
                                                     link.other_index))
                self._link((other.index, END), (self.index, START), link)
                other._blocked = other._blocked or f"{self.name} starts from it"
            elif kind == "EndAtTrack":
                other = args[0]
                self._check_other(other, kind)
                link = self._link_options(other, args[1])
                self.path.end_at(other.path if link is None else
                                 self._pose_from(other, False, link.this_index,
                                                 link.other_index))
                self._link((self.index, END), (other.index, START), link)
                self._blocked = f"it ends at {other.name}"
        except ConfigError as bad:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, f"{kind}: {bad}") from None

    def _check_editable(self, kind: str, frozen_ok: bool = False) -> None:
        if self.states.current is not PlanarState.DISABLED:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{kind}: {self.name} is {self.states.current.name.title()}; "
                                  "its geometry changes only while it is Disabled")
        self._check_unused(kind)
        if self._blocked and not frozen_ok:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{kind}: {self.name} is frozen because {self._blocked}; "
                                  "Clear it first (§7.2.2.10)")

    def _check_other(self, other: object, kind: str) -> None:
        if not isinstance(other, MC_PlanarTrack) or other.system is not self.system:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"{kind}: the other track must be a track of this runtime")
        if other is self:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"{kind}: a track links to itself with CloseLoop")
        if other.path.empty:
            raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                  f"{kind}: {other.name} has no geometry yet")

    def _link_options(self, other: MC_PlanarTrack, options: object) -> Link | None:
        """None for two tracks on one part; else the part positions of the link (§6.2.13)."""
        mine, theirs = self.part(), other.part()
        if mine is None or theirs is None or mine is theirs:
            return None
        if options is not None:
            options.check()  # type: ignore[attr-defined]
        this = getattr(options, "this_track_part_position_index", 0)
        that = getattr(options, "other_track_part_position_index", 0)
        for part, index in ((mine, this), (theirs, that)):
            if index > len(part.positions):
                raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                                      f"part 16#{part.oid:08X} has no position {index}")
        return Link(mine.oid, this, theirs.oid, that,
                    bool(getattr(options, "link_only_in_specified_part_positions", False)))

    def _link(self, a: tuple[int, int], b: tuple[int, int], link: Link | None = None) -> None:
        self.links.append((a, b, link))
        self.network.touch()

    def _add_to_group(self, group: MC_PlanarGroup) -> None:
        if self._group is not None:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{self.name} is in group 16#{self._group.oid:08X} already")
        group.port.admit(self, None, self.member)
        self._group = group

    def surface(self):  # noqa: ANN201 - a shapely Polygon
        """The band the largest mover sweeps along the track (what it blocks while Moving)."""
        import shapely

        s = np.linspace(0.0, self.length, max(2, int(self.length / 5.0) + 1))
        x, y, _, _ = self.frame_at(s)
        half = math.hypot(self.max_mover_width, self.max_mover_height) / 2.0
        return shapely.LineString(np.column_stack((x, y))).buffer(half)

    def _publish(self) -> bool:
        self.states.update()
        self.commands.publish()
        self.network.touch()  # a state change makes the track usable or not
        return not self.states.settled


def _point(position: PositionXYC) -> PositionXYC:
    """A copy of a track point as called (the PLC passes it IN_OUT); its numbers are checked
    when the command runs (``_local``), so that a bad one is the command's error id."""
    if not isinstance(position, PositionXYC):
        raise TypeError(f"a track point must be a PositionXYC, got {type(position).__name__}")
    return PositionXYC(position.x, position.y, 0.0, reference_id(position.reference_id))


_ORIGIN = Pose()


class Link(NamedTuple):
    """A link between tracks on two parts: valid in the given part positions (1-based; 0:
    any), and, unless ``only``, in every other position pair where the ends meet (§6.2.13)."""

    this_part: int
    this_index: int
    other_part: int
    other_index: int
    only: bool
