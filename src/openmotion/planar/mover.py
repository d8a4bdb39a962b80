"""MC_PlanarMover (TF5430 §7.2.2.8): a maglev mover with six coordinates x, y, z, a, b, c.

Methods record commands (system.py runs them in call order in the motion phase). A command
drives some coordinates: MoveToPosition x and y (and c with ``use_orientation``), MoveC c,
MoveZ/A/B one auxiliary axis, Halt all of them. Commands on different coordinates run side by
side, as the manual's examples issue MoveZ, MoveA, MoveB and MoveC in one cycle (§6.1.5); a
command on a coordinate another command drives aborts that command.

In a planar group every motion of x, y or c first asks the group for the area it sweeps
(``reservation.swept_area``); a refused command ends with PLANAR_COLLISION and the blocker in
``object_info``, and the mover goes on as before (§6.3, §6.7.2). While it moves, the area
behind it is released piece by piece; when it stands it keeps its footprint.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

import numpy as np

from openmotion.axis.axis import Axis
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.kernel.model import Kind
from openmotion.planar import gearing, riding
from openmotion.planar.enums import (
    CoordinateMode,
    ExternalSetPositionMode,
    MoverCommandMode,
    PlanarObjectType,
    PlanarState,
)
from openmotion.planar.feedback import (
    ExternalSetpointStream,
    MC_PlanarFeedbackBase,
    PlanarCommand,
    PlanarObjectInfo,
)
from openmotion.planar.frames import Pose
from openmotion.planar.gearing import MC_PlanarTrackTrail, admit_way
from openmotion.planar.group import MC_PlanarGroup, planar_group
from openmotion.planar.kind import PLANAR_MOVER
from openmotion.planar.motion import (
    PositionLimits,
    plan_axis_move,
    plan_halt,
    plan_move_c,
    plan_move_to_position,
    running,
    sample_path,
)
from openmotion.planar.options import (
    CDT_MCTOPLC_PLANAR_MOVER,
    CDT_MCTOPLC_PLANAR_MOVER_ACT,
    CDT_MCTOPLC_PLANAR_MOVER_COORDMODE,
    CDT_MCTOPLC_PLANAR_MOVER_SET,
    CDT_MCTOPLC_PLANAR_MOVER_STD,
    CDT_MCTOPLC_PLANAR_MOVER_TRACK,
    IPlcDynamicConstraint,
    MoverBusy,
    MoverVector,
    PlanarMoverParameters,
    ST_AdoptTrackOrientationOptions,
    ST_ExternalSetpointGenerationOptions,
    ST_GearInPosOnTrackOptions,
    ST_GearInPosOnTrackWithMasterMoverOptions,
    ST_JoinTrackOptions,
    ST_LeaveTrackOptions,
    ST_MoveCOptions,
    ST_MoveOnTrackOptions,
    ST_MoveToPositionOptions,
    command_dynamics,
)
from openmotion.planar.positions import PositionXYC, finite, reference_id
from openmotion.planar.reservation import (
    MemberId,
    SweptArea,
    footprint,
    footprint_area,
    straight_run_area,
    straight_run_pieces,
    straight_sweep,
    swept_area,
)
from openmotion.planar.riding import halt_on_track, move_c_on_track, release_bands
from openmotion.planar.rotation import monotonic
from openmotion.planar.states import (
    CommandModes,
    ErrorReaction,
    MoverCommand,
    PlanarStateMachine,
    StateCommand,
    check_accepts,
)
from openmotion.planar.system import ObjectPort, PlanarSystem, StatefulObject
from openmotion.planar.tolerances import VELOCITY_PRECISION
from openmotion.planar.track import MC_PlanarTrack
from openmotion.planar.traffic import Rider, traffic_of
from openmotion.trajectory.plan import Limits
from openmotion.trajectory.segments import KinematicState, Profile

if TYPE_CHECKING:
    from openmotion.planar.environment import MC_PlanarEnvironment
    from openmotion.runtime.runtime import Runtime

COORDINATES = ("x", "y", "z", "a", "b", "c")
_GROUP_OF = {"x": "xy", "y": "xy", "z": "z", "a": "a", "b": "b", "c": "c"}
_AREA = frozenset("xyc")  #: coordinates whose motion changes the footprint
_XY = frozenset("xy")
_STATE_COMMANDS = frozenset(StateCommand)
_SAMPLE_CYCLES = 10  #: a path is sampled every this many cycles for its swept area
_C = MoverCommand
_T = TypeVar("_T")


class Collision(CommandRejected):
    """A command refused by the group: PLANAR_COLLISION with the blocking object (§6.7.2)."""

    def __init__(self, blocker: MemberId, what: str) -> None:
        info, meets = _blocked_by(blocker)
        super().__init__(ErrorId.PLANAR_COLLISION, what + meets)
        self.object_info = info


@lru_cache(maxsize=4096)
def _blocked_by(blocker: MemberId) -> tuple[PlanarObjectInfo, str]:
    """The ``object_info`` of a rejection by ``blocker`` and the end of its message, made
    once per blocker: many commands meet the same neighbours, and formatting the message
    anew cost a tenth of a rejected command."""
    info = PlanarObjectInfo(PlanarObjectType(blocker.object_type), blocker.id)
    return info, (f" meets the area of {info.object_type.name.lower()} "
                  f"16#{info.id:08X} (§6.3)")
#: MoveToPosition without options (frozen, so one instance serves every command)
_MOVE_TO_POSITION_DEFAULTS = ST_MoveToPositionOptions()


@dataclass
class _Motion:
    """Profiles the mover follows for one command (or, without one, for a brake)."""

    command: PlanarCommand | None
    coordinates: set[str]
    end: float  #: absolute time when every profile of the motion rests [s]
    start: float = 0.0
    samples: np.ndarray | None = None  #: times [s] after ``start`` of the swept-area samples
    c_motion: bool = False  #: a C move that may end a CRotation mode
    releases: list[float] = field(default_factory=list)  #: [s] when a piece of area is behind
    on_end: Callable[[bool], None] | None = None  #: told whether the motion ended or was cut


@dataclass(frozen=True)
class MotionPort(ObjectPort):
    """A mover's motion as its track commands, the environment, the traffic and the system
    use it.

    The track commands (riding.py, gearing.py) are functions of their own modules; they
    start, check and place the mover's motion only through this port, which the mover makes
    with its own operations (D-239). Nothing here is a PLC method: a program calls the
    mover's commands, never the port.
    """

    #: start profiles for a command: admitted in a group, the motions they replace aborted
    begin: Callable[..., None]
    #: x, y, c [mm, mm, °] of the last published setpoint
    set_pose: Callable[[], Pose]
    #: the kinematic states new plans start from, by coordinate name
    start_states: Callable[..., dict[str, KinematicState]]
    #: refuse a motion whose centre path leaves the stator surface (D-163)
    check_carried: Callable[[dict[str, Profile], Profile | None, float, str], None]
    #: a PositionXYC target as (coordinate system OID, pose in it)
    resolve: Callable[[PositionXYC], tuple[int, Pose]]
    #: MoveC off a track
    move_c: Callable[[PlanarCommand], None]
    #: the footprint as a group holds it, at a pose (default: where it stands)
    standing_area: Callable[..., SweptArea]
    #: (profile, start time) of x, y and c from a time on, with new profiles
    future_plans: Callable[[dict[str, Profile], float], list[tuple[Profile, float]]]
    #: stand at a pose (a new coordinate system, a part that carried the mover)
    place: Callable[[Pose], None]
    #: the table row of its arc length on a track (made on the first join)
    odometer_row: Callable[[float], int]
    #: couple to a track's rider, or uncouple (None)
    couple: Callable[[Rider | None], None]
    #: the table rows of x, y, z, a, b, c
    rows: Mapping[str, int]
    #: the system: a motion ended, a piece of area is behind, or external setpoints run
    after_motion: Callable[[float], None]
    #: the traffic (``Owner``): its track command ended at its target, or its halt did
    track_finished: Callable[[PlanarCommand | None], None]
    #: the traffic: may its geared way go on over these tracks (raises if not, D-149)
    admit_way: Callable[[list[MC_PlanarTrack]], None]


class MC_PlanarMover(StatefulObject):
    """A planar mover. ``MC_PlanarMover(rt)`` makes one with the manual's default init
    parameters (``PlanarMoverParameters``); it starts Disabled at ``initial_position``.

    Every command method takes ``feedback`` (None is the PLC's 0) and returns the
    ``PlanarCommand``, which a Python script may poll (``command.done``).
    """

    MACHINE: ClassVar[Kind] = PLANAR_MOVER  #: its signals and commands in the machine model

    def __init__(self, runtime: Runtime, parameters: PlanarMoverParameters | None = None,
                 name: str | None = None) -> None:
        if parameters is not None and not isinstance(parameters, PlanarMoverParameters):
            raise ConfigError(f"parameters: must be a PlanarMoverParameters, got "
                              f"{type(parameters).__name__}")
        system = PlanarSystem.of(runtime)
        super().__init__(system, system.next_oid("mover"))
        self.parameters = parameters or PlanarMoverParameters()
        self.name = name or f"mover{len(system.movers) + 1}"
        start = self.parameters.initial_position
        rows = system.add_rows([getattr(start, name) for name in COORDINATES])
        self._rows = dict(zip(COORDINATES, rows, strict=True))
        self._xyc_rows = [self._rows[name] for name in "xyc"]  #: where MoveToPosition starts
        self._position_limits: tuple[PlanarMoverParameters, PositionLimits, PositionLimits] \
            | None = None  #: x and y limits of ``parameters`` (``_xy_position_limits``)
        self._row0 = rows[0]  #: the six rows are consecutive: x, y, z, a, b, c
        self._profiles: dict[str, tuple[Profile, float]] = {}  #: last plan per coordinate
        self.states = PlanarStateMachine(transition_done=self._transition_done,
                                          on_enter=self._on_enter)
        self.modes = CommandModes(self.parameters.c_windows)
        self._motions: list[_Motion] = []
        self._group: MC_PlanarGroup | None = None
        self._joining: MC_PlanarGroup | None = None
        self.coordinate_system = 0  #: OID of the coordinate system it is in (0: no parts)
        self._offset = np.zeros(6)  #: relative external setpoints (§4.2)
        self._stream: ExternalSetpointStream | None = None
        self._external_command: PlanarCommand | None = None
        self._fed = False  #: an external setpoint came this cycle
        self._started_external = False
        self._status: tuple[int, CDT_MCTOPLC_PLANAR_MOVER] | None = None
        self._event_index = -1  #: its place in the system's ``next_events``
        self.next_event = math.inf  #: [s] when ``port.after_motion`` has work
        self._member = MemberId(PlanarObjectType.MOVER, self.oid)
        self._rider: Rider | None = None  #: coupled to a track (traffic.py)
        self._odometer: int | None = None  #: table row of the arc length on a track
        #: what track commands, the environment and the system use of its motion
        self.port = MotionPort(
            self._run, self._publish, begin=self._begin, set_pose=self._set_pose,
            start_states=self._start_states, check_carried=self._check_carried,
            resolve=self._resolve, move_c=self._move_c, standing_area=self._standing_area,
            future_plans=self._future_plans, place=self._place,
            odometer_row=self._odometer_row, couple=self._couple,
            rows=MappingProxyType(self._rows), after_motion=self._after_motion,
            track_finished=self._on_track_finished, admit_way=self._admit_way)
        self._event_index = system.add_mover(self)
        self.next_event = self._next_event
        self._rank = system.register(self)
        environment = system.environment()
        if environment is not None:
            environment.port.place(self)

    def __repr__(self) -> str:
        return f"<MC_PlanarMover {self.name} 16#{self.oid:08X} {self.mc_to_plc.std.state.name}>"

    # -- the manual's methods (§7.2.2.8) -------------------------------------------------------

    def move_to_position(self, target: PositionXYC,
                         constraint: IPlcDynamicConstraint | None = None,
                         options: ST_MoveToPositionOptions | None = None,
                         feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """A straight move to ``target`` (x, y; and c with ``options.use_orientation``)."""
        return self._send(_C.MOVE_TO_POSITION, feedback, _copy(target), _constraint(constraint),
                          _options(options, ST_MoveToPositionOptions))

    def move_c(self, target_position: float, constraint: IPlcDynamicConstraint | None = None,
               options: ST_MoveCOptions | None = None,
               feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(_C.MOVE_C, feedback, target_position, _constraint(constraint),
                          _options(options, ST_MoveCOptions))

    def move_z(self, target_position: float, constraint: IPlcDynamicConstraint | None = None,
               feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(_C.MOVE_Z, feedback, target_position, _constraint(constraint))

    def move_a(self, target_position: float, constraint: IPlcDynamicConstraint | None = None,
               feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(_C.MOVE_A, feedback, target_position, _constraint(constraint))

    def move_b(self, target_position: float, constraint: IPlcDynamicConstraint | None = None,
               feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(_C.MOVE_B, feedback, target_position, _constraint(constraint))

    def halt(self, constraint: IPlcDynamicConstraint | None = None,
             feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Brake every coordinate to rest; the constraint limits x and y (§7.2.2.8.12)."""
        return self._send(_C.HALT, feedback, _constraint(constraint))

    def join_track(self, track: MC_PlanarTrack, constraint: IPlcDynamicConstraint | None = None,
                   options: ST_JoinTrackOptions | None = None,
                   feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """A free move onto the nearest point of ``track``, coupled to it at the end (§4.2)."""
        return self._send(_C.JOIN_TRACK, feedback, _track(track), _constraint(constraint),
                          _options(options, ST_JoinTrackOptions))

    def leave_track(self, target: PositionXYC, constraint: IPlcDynamicConstraint | None = None,
                    options: ST_LeaveTrackOptions | None = None,
                    feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Uncouple from the track and move freely to ``target`` (§4.2)."""
        return self._send(_C.LEAVE_TRACK, feedback, _copy(target), _constraint(constraint),
                          _options(options, ST_LeaveTrackOptions))

    def move_on_track(self, target_track: MC_PlanarTrack | None, target_position: float,
                      constraint: IPlcDynamicConstraint | None = None,
                      options: ST_MoveOnTrackOptions | None = None,
                      feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Travel along the network to ``target_position`` [mm of arc length] on
        ``target_track`` (None or 0: the current track), keeping ``options.gap`` to the
        mover ahead (§6.1.9, §6.2.2)."""
        return self._send(_C.MOVE_ON_TRACK, feedback,
                          _track(target_track, current=True), target_position,
                          _constraint(constraint), _options(options, ST_MoveOnTrackOptions))

    def gear_in_pos_on_track(self, master_axis: Axis, track_trail: MC_PlanarTrackTrail | None,
                             master_sync_position: float, slave_sync_position: float,
                             slave_sync_position_track: MC_PlanarTrack,
                             constraint: IPlcDynamicConstraint | None = None,
                             options: ST_GearInPosOnTrackOptions | None = None,
                             feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Couple 1:1 to an axis: at ``slave_sync_position`` on ``slave_sync_position_track``
        when the axis is at ``master_sync_position``, then follow it (§6.2.8). The master is
        the Axis object (the manual passes its object id). Stays Active until another
        command or an error; ``feedback.in_sync`` shows the sync."""
        if not isinstance(master_axis, Axis):
            raise TypeError(f"the master must be an Axis, got {type(master_axis).__name__}")
        return self._send(_C.GEAR_IN_POS_ON_TRACK, feedback, master_axis, _trail(track_trail),
                          master_sync_position, slave_sync_position,
                          _track(slave_sync_position_track),
                          _constraint(constraint), _options(options, ST_GearInPosOnTrackOptions))

    def gear_in_pos_on_track_with_master_mover(
            self, master_mover: MC_PlanarMover, track_trail: MC_PlanarTrackTrail | None,
            master_sync_position: float, master_sync_position_track: MC_PlanarTrack,
            slave_sync_position: float, slave_sync_position_track: MC_PlanarTrack,
            constraint: IPlcDynamicConstraint | None = None,
            options: ST_GearInPosOnTrackWithMasterMoverOptions | None = None,
            feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Couple 1:1 to another mover on a track (§6.2.9, §6.2.12)."""
        if not isinstance(master_mover, MC_PlanarMover):
            raise TypeError(f"the master must be an MC_PlanarMover, got "
                            f"{type(master_mover).__name__}")
        return self._send(_C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER, feedback, master_mover,
                          _trail(track_trail), master_sync_position,
                          _track(master_sync_position_track), slave_sync_position,
                          _track(slave_sync_position_track),
                          _constraint(constraint),
                          _options(options, ST_GearInPosOnTrackWithMasterMoverOptions))

    def adopt_track_orientation(self, constraint: IPlcDynamicConstraint | None = None,
                                options: ST_AdoptTrackOrientationOptions | None = None,
                                feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Turn a standing mover on a track to the track's heading; C then follows the track
        again (§6.2.7)."""
        return self._send(_C.ADOPT_TRACK_ORIENTATION, feedback, _constraint(constraint),
                          _options(options, ST_AdoptTrackOrientationOptions))

    def set_position(self, position: PositionXYC,
                     feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """Overwrite x, y and c; only while Disabled (§7.2.2.8.17)."""
        return self._send(_C.SET_POSITION, feedback, _copy(position))

    def add_to_group(self, group: MC_PlanarGroup,
                     feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(_C.ADD_TO_GROUP, feedback, planar_group(group))

    def remove_from_group(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(_C.REMOVE_FROM_GROUP, feedback)

    def start_external_setpoint_generation(
            self, options: ST_ExternalSetpointGenerationOptions | None = None,
            feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """From this cycle on a setpoint must come every cycle (§6.1.6). Absolute: the mover
        follows only them; Relative: they are offsets to whatever else moves it (§4.2)."""
        options = _options(options, ST_ExternalSetpointGenerationOptions) \
            or ST_ExternalSetpointGenerationOptions()
        kind = (_C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION
                if options.mode == ExternalSetPositionMode.RELATIVE
                else _C.START_EXTERNAL_SETPOINT_GENERATION)
        return self._send(kind, feedback, options)

    def set_external_setpoint(self, set_position: MoverVector, set_velocity: MoverVector,
                              set_acceleration: MoverVector) -> None:
        """One setpoint, in the mover's coordinate system (reference id 0)."""
        self._send(_C.SET_EXTERNAL_SETPOINT, None, set_position, set_velocity, set_acceleration,
                   None, None)

    def set_external_setpoint_reference_id(self, feedback: MC_PlanarFeedbackBase | None,
                                           set_position: MoverVector, set_velocity: MoverVector,
                                           set_acceleration: MoverVector,
                                           reference_system_oid: int) -> None:
        """One setpoint in the frame ``reference_system_oid``; pass the same feedback every
        call: its errors show after the next call (§6.1.7)."""
        self._send(_C.SET_EXTERNAL_SETPOINT, None, set_position, set_velocity, set_acceleration,
                   reference_id(reference_system_oid), feedback)

    def stop_external_setpoint_generation(
            self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        """End the setpoints; the mover brakes with its maximum dynamics (§6.1.6)."""
        return self._send(_C.STOP_EXTERNAL_SETPOINT_GENERATION, feedback)

    def get_position_on_current_part(self) -> PositionXYC:
        """The set position in the frame of the part under the mover (§5.2)."""
        environment = self.system.environment()
        pose = self.pose
        if environment is None or environment.layout is None:
            return PositionXYC(*pose, self.coordinate_system)
        part, local = environment.layout.position_on_current_part(self.coordinate_system, pose)
        return PositionXYC(*local, part)

    def get_planar_object_info(self) -> PlanarObjectInfo:
        return PlanarObjectInfo(PlanarObjectType.MOVER, self.oid)

    # -- Python conveniences ---------------------------------------------------------------------

    @property
    def state(self) -> PlanarState:
        return self.mc_to_plc.std.state

    @property
    def command_mode(self) -> MoverCommandMode:
        return self.mc_to_plc.std.command_mode

    @property
    def position(self) -> MoverVector:
        """The published set position (x, y, z [mm]; a, b, c [°])."""
        return MoverVector(*self._vector(0))

    @property
    def velocity(self) -> MoverVector:
        """The published set velocity (x, y, z [mm/s]; a, b, c [°/s]): ``mc_to_plc.set.set_velo``
        without building the whole status (learning environments read it every step)."""
        return MoverVector(*self._vector(1))

    @property
    def pose(self) -> Pose:
        x, y, _, _, _, c = self._vector(0)
        return Pose(x, y, c)

    def _vector(self, which: int) -> list[float]:
        """Set position (0), velocity (1) or acceleration (2) of the six coordinates."""
        values = self.system.values(which, self._row0, 6)
        return (values + self._offset if which == 0 else values).tolist()

    @property
    def member(self) -> MemberId:
        return self._member

    @property
    def group(self) -> MC_PlanarGroup | None:
        """The planar group it is in (AddToGroup done); None for none."""
        return self._group

    @property
    def rider(self) -> Rider | None:
        """Its place in the traffic while it is coupled to a track (JoinTrack); else None."""
        return self._rider

    @property
    def next_event(self) -> float:
        """[s] when ``port.after_motion`` has work: an end, a release, or every cycle."""
        return self._next_event

    @next_event.setter
    def next_event(self, value: float) -> None:
        self._next_event = value
        if self._event_index >= 0:  # the system scans them all at once (D-286)
            self.system.next_events[self._event_index] = value

    @property
    def in_motion(self) -> bool:
        """A motion of its own runs (a brake too); riding a track or being fed is not one."""
        return bool(self._motions)

    def footprint(self, pose: Pose | None = None):  # noqa: ANN201 - a shapely Polygon
        x, y, c = pose or self.pose
        return footprint(x, y, c, self.parameters.mover_width, self.parameters.mover_height)

    def _standing_area(self, pose: Pose | None = None) -> SweptArea:
        """The footprint as the group holds it (its polygon built only when a check needs
        it)."""
        x, y, c = pose or self.pose
        return footprint_area(x, y, c, self.parameters.mover_width, self.parameters.mover_height)

    # -- execution (motion phase) ---------------------------------------------------------------

    def _execute(self, command: PlanarCommand) -> None:
        kind = command.kind
        if kind in _STATE_COMMANDS:
            environment = self.system.environment()
            if kind == StateCommand.RESET and environment is not None:
                environment.port.reset_parts(self.coordinate_system)  # §6.6: parts first
            if kind == StateCommand.ENABLE and environment is not None and \
                    self.states.current is PlanarState.DISABLED and not environment.carries(
                        self.coordinate_system, np.array([self.pose[:2]])):
                raise _off_stators(environment, "Enable: the mover stands off the stator "
                                   "surface")
            self.states.request(command)
            return
        if type(kind) is not MoverCommand:
            kind = MoverCommand(kind)
        if kind is _C.SET_EXTERNAL_SETPOINT:
            self._feed(command)
            return
        check_accepts(self.states.current, self.modes.mode, kind,
                      external=self.modes.external)
        self._HANDLERS[kind](self, command)

    def _move_to_position(self, command: PlanarCommand) -> None:
        target, constraint, options = command.args
        options = options or _MOVE_TO_POSITION_DEFAULTS
        options.check()
        parameters = self.parameters
        limits = command_dynamics(constraint, parameters.default_dynamic_xy,
                                  parameters.maximum_dynamic_xy, command.warnings)
        system, pose = self._resolve(target)
        del system  # one coordinate system per mover until parts move it (§6.6)
        start = self.system.table.states(self._xyc_rows, self.system.previous)
        c = start[2]
        turn = options.use_orientation and not (pose.c == c.position and c.velocity == 0.0
                                                 and c.acceleration == 0.0)
        goal = (pose.x, pose.y, pose.c) if turn else (pose.x, pose.y)
        x_limits, y_limits = self._xy_position_limits()
        sweep = None  # in a group: the area's numbers from the planner's pass, when it can
        if turn and self._group is not None:
            sweep = straight_sweep(self.system.previous,
                                   self.system.cycle_time * _SAMPLE_CYCLES,
                                   parameters.mover_width, parameters.mover_height)
        motion = plan_move_to_position(
            start, goal, limits, parameters.default_dynamic_c, x_limits=x_limits,
            y_limits=y_limits, c_windows=parameters.c_windows if turn else None, sweep=sweep)
        profiles = {"x": motion.x, "y": motion.y}
        if motion.c is not None:
            profiles["c"] = motion.c
        elif options.use_orientation:  # c is at its target already: the move still holds it
            profiles["c"] = Profile.hold(c)
        self._begin(command, profiles, "the move", straight=motion.s, swept=motion.swept)

    def _move_c(self, command: PlanarCommand) -> None:
        target, constraint, options = command.args
        options = options or ST_MoveCOptions()
        options.check()
        p = self.parameters
        limits = command_dynamics(constraint, p.default_dynamic_c, p.maximum_dynamic_c,
                                  command.warnings)
        profile = plan_move_c(self._start_states("c")["c"], finite(target, "c"), limits,
                              options.direction, options.additional_turns, p.c_coordinate_modulus,
                              p.c_coordinate_modulo_tolerance_window)
        if any(m.coordinates & _XY for m in self._motions) \
                and not p.c_windows.contains_motion(profile):
            raise CommandRejected(ErrorId.PLANAR_WRONG_MODE,
                                  "MoveC would turn the mover out of its C window while x and y "
                                  "move; X and Y stand still outside the windows (§4.2)")
        self._begin(command, {"c": profile}, "the rotation", c_motion=True)

    def _move_aux(self, command: PlanarCommand) -> None:
        target, constraint = command.args
        name = {_C.MOVE_Z: "z", _C.MOVE_A: "a", _C.MOVE_B: "b"}[MoverCommand(command.kind)]
        p = self.parameters
        limits = command_dynamics(constraint, getattr(p, f"default_dynamic_{name}"),
                                  getattr(p, f"maximum_dynamic_{name}"), command.warnings)
        bounds = PositionLimits(getattr(p.minimum_position, name),
                                getattr(p.maximum_position, name))
        profile = plan_axis_move(self._start_states(name)[name], finite(target, name), limits,
                                 bounds, name)
        self._begin(command, {name: profile}, "the move")

    def _halt(self, command: PlanarCommand) -> None:
        (constraint,) = command.args
        p = self.parameters
        if self._rider is not None:
            halt_on_track(self, command, command_dynamics(
                constraint, p.default_dynamic_xy, p.maximum_dynamic_xy, command.warnings))
            self._halt_own_coordinates()
            return
        limits = self._limits("default")
        limits["xy"] = command_dynamics(constraint, p.default_dynamic_xy, p.maximum_dynamic_xy,
                                        command.warnings)
        if self.modes.external is not ExternalSetPositionMode.NONE:  # the halt ends them
            self._end_external(self._external_kind(), brake=False, aborted=True)
        profiles = plan_halt(self._start_states(), limits)
        # a halt is never refused (D-084): without collision avoidance in force (a group
        # not Enabled) it keeps to the area the mover holds
        admit = self._group is None or self._group.state is PlanarState.ENABLED
        try:
            self._begin(command, profiles, "the halt", admit=admit, check_carried=False)
        except Collision:  # the hardest brake stays on the path the mover has reserved
            command.warnings.append("the halt's stop would leave the reserved area: it brakes "
                                    "with the mover's maximum dynamics")
            self._begin(command, plan_halt(self._start_states(), self._limits("maximum")),
                        "the halt", admit=False, check_carried=False)

    def _halt_own_coordinates(self) -> None:
        """A Halt on a track: the track brakes x and y; what runs on c (a MoveC), z, a or b
        brakes too, with the default dynamics, and its command is aborted (§7.2.2.8.12)."""
        running = {name for motion in self._motions for name in motion.coordinates} \
            - {"x", "y"}
        if not running:
            return
        previous = self.system.previous
        names = sorted(running, key=COORDINATES.index)
        profiles = plan_halt(dict(zip(names, self.system.table.states(
            [self._rows[name] for name in names], previous), strict=True)),
            self._limits("default"))
        self._abort(running)
        for name, profile in profiles.items():
            self._install(name, profile, previous)
        end = previous + max(profile.duration for profile in profiles.values())
        self._motions.append(_Motion(None, running, end, previous, c_motion="c" in running))
        self._reschedule()

    def _set_position(self, command: PlanarCommand) -> None:
        (target,) = command.args
        _, pose = self._resolve(target)
        start = {"x": pose.x, "y": pose.y, "c": pose.c}
        if self._group is not None:
            blocker = self._group.registry.request(self._member, self._standing_area(pose))
            if blocker is not None:
                raise Collision(blocker, "the new position")
        for name, value in start.items():
            self._install(name, Profile.hold(KinematicState(value)), self.system.previous)
        command.finish()

    def _add_to_group(self, command: PlanarCommand) -> None:
        (group,) = command.args
        if self._group is not None:
            raise CommandRejected(ErrorId.PLANAR_WRONG_STATE,
                                  f"{self.name} is in group 16#{self._group.oid:08X} already: "
                                  "RemoveFromGroup first (§6.3)")
        moving = any(m.coordinates & _AREA for m in self._motions)
        area = self._future_area({}, self.system.previous, None)[1] if moving \
            else self._standing_area()
        group.port.admit(self, area, self._member)  # a moving mover holds its whole way on
        self._group = group
        command.finish()

    def _remove_from_group(self, command: PlanarCommand) -> None:
        if self._group is None:
            raise CommandRejected(ErrorId.PLANAR_NOT_IN_GROUP, f"{self.name} is in no group")
        self._group.port.leave(self._member)
        self._group = None
        command.finish()

    def _start_external(self, command: PlanarCommand) -> None:
        (options,) = command.args
        options.check()
        kind = MoverCommand(command.kind)
        if kind is _C.START_EXTERNAL_SETPOINT_GENERATION:
            self._abort_all()  # external setpoints take over
        self.modes.started(kind)
        self._stream = ExternalSetpointStream(self.system.clock)
        self._started_external = True
        command.start()
        self._external_command = command
        self._reschedule()

    def _feed(self, command: PlanarCommand) -> None:
        position, velocity, acceleration, reference, feedback = command.args
        stream = self._stream
        command.finish()  # SetExternalSetpoint has no feedback of its own
        if self.modes.external is ExternalSetPositionMode.NONE:
            if stream is not None:  # the stream ended (Stop or an error): it keeps its result
                stream.call(feedback)
            elif feedback is not None:
                other = ExternalSetpointStream(self.system.clock)
                other.report(ErrorId.PLANAR_WRONG_MODE, "no external setpoint generation runs "
                             "(§6.1.6)")
                other.call(feedback)
                other.call(feedback)
            return
        if stream is not None and feedback is not None:
            stream.call(feedback)
        try:
            values = [np.array([getattr(v, k) for k in COORDINATES], dtype=float)
                      for v in (position, velocity, acceleration)]
            if reference is not None and self.modes.external is ExternalSetPositionMode.RELATIVE:
                self._turn_offset(values, reference)
            elif reference is not None:  # SetExternalSetpointReferenceId: 0 follows §5.3 too
                pose = self._resolve(PositionXYC(values[0][0], values[0][1], values[0][5],
                                                 reference))[1]
                values[0][0], values[0][1], values[0][5] = pose
            self._check_setpoint(values)
            if self.modes.external is ExternalSetPositionMode.RELATIVE:
                self._cover_offset(values[0])
        except (CommandRejected, TypeError, AttributeError) as bad:
            error_id = getattr(bad, "error_id", ErrorId.PLANAR_EXT_SETPOINT)
            message = getattr(bad, "message", str(bad))
            if stream is not None:
                stream.report(error_id, message)
            self._end_external(self._external_kind(), (error_id, message))
            self.states.fail(error_id, ErrorReaction.QUICK_STOP, message)
            return
        self._fed = True
        now = self.system.now
        if self.modes.external is ExternalSetPositionMode.ABSOLUTE:
            for k, name in enumerate(COORDINATES):
                state = (values[0][k], values[1][k], values[2][k])
                self._install(name, Profile(np.zeros(1), [state[0]], [state[1]], [state[2]],
                                            np.zeros(1)), now)
            if self._group is not None:
                self._group.registry.settle(self._member, self._standing_area(
                    Pose(values[0][0], values[0][1], values[0][5])))
        else:
            self._offset = values[0]

    def _cover_offset(self, offset: np.ndarray) -> None:
        """Relative setpoints keep the mover in its mode, so collision avoidance holds
        (§4.2): the footprint the offset moves must be free, and the group holds it for the
        mover besides the path its commands reserved (D-141)."""
        group = self._group
        if group is None or group.state is not PlanarState.ENABLED:
            return
        now = self.system.now
        x, y, c = (self._state_at(name, now).position for name in "xyc")
        pose = Pose(x + offset[0], y + offset[1], c + offset[5])
        blocker = group.registry.cover(self._member, self._standing_area(pose))
        if blocker is not None:
            raise Collision(blocker, "the offset setpoint")

    def _turn_offset(self, values: list[np.ndarray], reference: int) -> None:
        """Relative setpoints given in the frame ``reference`` names: offsets, so they turn
        with the frame but do not move with its origin, and need not lie on a part (§4.2)."""
        environment = self.system.environment()
        layout = None if environment is None else environment.layout
        if layout is None:
            if reference != 0:
                raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                      f"reference id 16#{reference:08X} names no part or "
                                      "coordinate system: there are none (§5.3)")
            return
        system, origin = layout.to_coordinate_system(reference, Pose(0.0, 0.0, 0.0))
        if self.coordinate_system and system != self.coordinate_system:
            raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                  f"reference id 16#{reference:08X} lies in coordinate system "
                                  f"16#{system:08X}, not the mover's (§5.1)")
        for row in range(3):  # position, velocity, acceleration offsets turn alike
            vector = values[row]
            _, moved = layout.to_coordinate_system(reference, Pose(vector[0], vector[1], 0.0))
            vector[0], vector[1] = moved.x - origin.x, moved.y - origin.y

    def _hold_shifted_way(self, now: float) -> None:
        """After relative setpoints end, the group holds where the offset left the mover:
        its footprint, or the rest of its shifted way (refused: the mover stops with
        PLANAR_COLLISION)."""
        if self._group is None:
            return
        if not any(m.coordinates & _AREA for m in self._motions):
            x, y, c = (self._state_at(name, now).position for name in "xyc")  # shifted
            self._group.registry.settle(self._member, self._standing_area(Pose(x, y, c)))
            return
        _, area = self._future_area({}, now, None)
        blocker = self._group.registry.request(self._member, area)
        if blocker is not None:
            message = Collision(blocker, "the way left by the offset").message
            self.states.fail(ErrorId.PLANAR_COLLISION, ErrorReaction.QUICK_STOP, message)

    def _stop_external(self, command: PlanarCommand) -> None:
        self._end_external(self._external_kind())
        command.finish()

    def _external_kind(self) -> MoverCommand:
        """The start command of the external setpoint generation that runs."""
        return (_C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION
                if self.modes.external is ExternalSetPositionMode.RELATIVE
                else _C.START_EXTERNAL_SETPOINT_GENERATION)

    def _end_external(self, kind: MoverCommand, failure: tuple[ErrorId, str] | None = None,
                      *, brake: bool = True, aborted: bool = False) -> None:
        """Stop external setpoints; ``failure`` ends the start command with an error,
        ``aborted`` with CommandAborted (a Halt took over, which also does the braking when
        not ``brake``)."""
        now = self.system.now
        if kind is _C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION:
            for k, name in enumerate(COORDINATES):  # the offset stays where it is
                if self._offset[k]:
                    self.system.table.shift(self._rows[name], float(self._offset[k]))
                    if name in self._profiles:
                        profile, start = self._profiles[name]
                        data = profile.data.copy()
                        data[1] += float(self._offset[k])
                        self._profiles[name] = (Profile.from_data(data), start)
            self._offset = np.zeros(6)
            self._hold_shifted_way(now)
        elif brake:  # brake to rest with the maximum dynamics (§6.1.6)
            states = {name: self._state_at(name, now) for name in COORDINATES}
            profiles = plan_halt(states, self._limits("maximum"))
            for name, profile in profiles.items():
                self._install(name, profile, now)
            end = now + max(p.duration for p in profiles.values())
            self._motions.append(_Motion(None, set(COORDINATES), end, now))
        self._reschedule()
        self.modes.ended(kind, done=True, c=self._state_at("c", now).position)
        command = self._external_command
        if command is not None:
            if aborted:
                command.abort()
            elif failure is None:
                command.finish()
            else:
                command.reject(*failure)
            self._external_command = None

    def _check_setpoint(self, values: list[np.ndarray]) -> None:
        p = self.parameters
        for k, name in enumerate(COORDINATES):
            top: Limits = getattr(p, f"maximum_dynamic_{_GROUP_OF[name]}")
            if not all(math.isfinite(v[k]) for v in values):
                raise CommandRejected(ErrorId.PLANAR_EXT_SETPOINT,
                                      f"external setpoint {name} is not finite")
            if abs(values[1][k]) > top.velocity * (1 + VELOCITY_PRECISION):
                raise CommandRejected(ErrorId.PLANAR_EXT_SETPOINT,
                                      f"external setpoint velocity {name} {values[1][k]:g} above "
                                      f"the maximum {top.velocity:g} (§6.1.6)")

    # -- motions ---------------------------------------------------------------------------------

    def _begin(self, command: PlanarCommand, profiles: dict[str, Profile], what: str, *,
               c_motion: bool = False, admit: bool = True, straight: Profile | None = None,
               on_end: Callable[[bool], None] | None = None,
               check_carried: bool = True, swept: tuple | None = None) -> None:
        """Admit (in a group) and start ``profiles`` for ``command``: the commands on the same
        coordinates are aborted. ``straight``: the arc length of x and y when they run forward
        on one line from the start (``PlanarMotion.s``). ``check_carried``: refuse a path
        off the stators (D-163); a halt is never refused (D-084). ``swept``: the numbers of
        the swept area of ``profiles`` (x, y and c) from the planner (``PlanarMotion.swept``)."""
        previous = self.system.previous
        group = self._group
        if check_carried and (group is None or not group.registry.checks_surface) \
                and _XY & profiles.keys():  # a group with the surface checks it itself
            self._check_carried(profiles, straight, previous, what)
        samples, releases = None, []
        if group is not None and _AREA & profiles.keys():
            found = None if swept is None else straight_run_pieces(
                swept, self.parameters.mover_width / 2, self.parameters.mover_height / 2)
            samples, area = found or self._future_area(profiles, previous, straight)
            if admit:
                group.port.check_enabled(what)
                blocker = group.registry.request(self._member, area)
                if blocker is not None:
                    raise Collision(blocker, what)
            else:
                group.registry.settle(self._member, area)
            # a piece is behind the mover once the sample after its last one is reached
            times, count = samples.tolist(), samples.size
            releases = [previous + times[k + 1] for k in area.until[:-1].tolist()
                        if k + 1 < count]
            for motion in self._motions:  # the new area replaces theirs
                if motion.coordinates & _AREA:
                    motion.samples, motion.releases = None, []
        if self._motions:  # the new command takes over its coordinates (rescheduled below)
            self._abort(set(profiles))
        table, rows, plans = self.system.table, self._rows, self._profiles
        for name, profile in profiles.items():  # ``_install`` each
            table.install(rows[name], profile, previous)
            plans[name] = (profile, previous)
        end = previous + max(p.duration for p in profiles.values())
        self._motions.append(_Motion(command, set(profiles), end, previous, samples, c_motion,
                                     releases, on_end))
        if c_motion:
            self.modes.c_motion_started(profiles["c"])
        command.start()
        self._reschedule()

    def _check_carried(self, profiles: dict[str, Profile], straight: Profile | None,
                       start: float, what: str) -> None:
        """A motion whose centre path leaves the stator surface is refused (D-163): no
        stator would carry the mover there. A group holding the environment checks the
        whole footprint already (§6.3); halts and stops are never refused (D-084)."""
        environment = self.system.environment()
        if environment is None or environment.boundary is None or (
                self._group is not None and self._group.registry.checks_surface):
            return
        if straight is not None:  # one line from where the mover is to where x and y end
            x, y = self._state_at("x", start).position, self._state_at("y", start).position
            points = np.array([(x, y), (profiles["x"].p[-1], profiles["y"].p[-1])])
        else:
            _, path = sample_path(self._future_plans(profiles, start)[:2], start,
                                  self.system.cycle_time * _SAMPLE_CYCLES)
            points = path
        if not environment.carries(self.coordinate_system, points):
            raise _off_stators(environment, f"{what} leaves the stator surface")

    def _future_area(self, profiles: dict[str, Profile], start: float,
                     straight: Profile | None) -> tuple[np.ndarray, SweptArea]:
        """Sample times after ``start`` of the footprint's future, with the new ``profiles``
        and the plans still running on the other coordinates, and the area it sweeps
        (``swept_area`` of the samples). A straight path (``straight``, the arc length of x
        and y, ``PlanarMotion.s``) is cut into runs by its arc length and only the run ends
        are evaluated: the same pieces, without sampling x, y and c."""
        if profiles.keys() >= _AREA:  # ``_future_plans`` of new x, y and c
            plans = [(profiles["x"], start), (profiles["y"], start), (profiles["c"], start)]
        else:
            plans = self._future_plans(profiles, start)
        step = self.system.cycle_time * _SAMPLE_CYCLES
        width, height = self.parameters.mover_width, self.parameters.mover_height
        turning = running(plans[2], start)
        if straight is not None and ("c" in profiles or not turning or monotonic(plans[2][0])):
            # x and y have the corners of their arc length s
            found = straight_run_area(straight, plans, (running(plans[0], start),
                                                        running(plans[1], start), turning),
                                      turning, start, step, width, height)
            if found is not None:
                return found
        samples, path = sample_path(plans, start, step)
        return samples, swept_area(path, width, height)

    def _future_plans(self, profiles: dict[str, Profile], start: float
                      ) -> list[tuple[Profile, float]]:
        """(profile, start time) of x, y and c from ``start`` on: the new ``profiles`` and
        the plans still running on the other coordinates."""
        return [(profiles[name], start) if name in profiles else self._profiles.get(name)
                or (Profile.hold(self._state_at(name, start)), start) for name in "xyc"]

    def _place(self, pose: Pose) -> None:
        """Stand at ``pose`` (a new coordinate system, a part that carried the mover)."""
        for name, value in zip(("x", "y", "c"), pose, strict=True):
            self._install(name, Profile.hold(KinematicState(value)), self.system.previous)
            self.system.set_value(self._rows[name], value)
        self._status = None

    def _install(self, name: str, profile: Profile, time: float) -> None:
        self.system.table.install(self._rows[name], profile, time)
        self._profiles[name] = (profile, time)

    def _abort(self, coordinates: set[str]) -> None:
        """The motions on ``coordinates`` end: their commands are CommandAborted."""
        for motion in list(self._motions):
            if motion.coordinates & coordinates:
                if motion.command is not None:
                    motion.command.abort()
                motion.command = None
                if motion.on_end is not None:
                    motion.on_end(False)
                    motion.on_end = None
                motion.coordinates -= coordinates
                if not motion.coordinates:
                    self._motions.remove(motion)
        self._reschedule()

    def _abort_all(self) -> None:
        self._abort(set(COORDINATES))

    def _brake(self, dynamics: str) -> None:
        """Stop every coordinate (Disable, QuickStop): no command, no area to ask for, as the
        hardest brake stays on the reserved path. On a track the mover brakes along it."""
        self._abort_all()  # the mover stops
        if self._rider is not None:
            traffic_of(self.system).halt(self._rider, self._limits(dynamics)["xy"], None,
                                          self.system.previous)
        previous = self.system.previous
        profiles = plan_halt(self._start_states(), self._limits(dynamics))
        for name, profile in profiles.items():
            self._install(name, profile, previous)
        end = previous + max(p.duration for p in profiles.values())
        self._motions.append(_Motion(None, set(COORDINATES), end, previous))
        self._reschedule()

    def _freeze(self) -> None:
        """Abort reaction: the mover stops where it is (it lands, §4.1)."""
        self._abort_all()  # error
        now = self.system.now
        for name in COORDINATES:
            p, _, _ = self.system.value(self._rows[name])
            self._install(name, Profile.hold(KinematicState(p)), now)

    def _after_motion(self, now: float) -> None:
        """A motion ended, a piece of area is behind the mover, or external setpoints run."""
        self.awake = True
        if self.modes.external is not ExternalSetPositionMode.NONE:
            if not self._fed:
                message = "no external setpoint in this cycle (§6.1.6)"
                if self._stream is not None:
                    self._stream.report(ErrorId.PLANAR_EXT_SETPOINT, message)
                self._end_external(self._external_kind(), (ErrorId.PLANAR_EXT_SETPOINT, message))
                self.states.fail(ErrorId.PLANAR_EXT_SETPOINT, ErrorReaction.QUICK_STOP, message)
            self._fed = False
        for motion in list(self._motions):
            if motion.releases and now >= motion.releases[0] and self._group is not None:
                elapsed = now - motion.start
                reached = int(motion.samples.searchsorted(elapsed, side="right"))
                self._group.registry.release(self._member, reached - 1)
                while motion.releases and now >= motion.releases[0]:
                    motion.releases.pop(0)
            if now >= motion.end:
                self._motions.remove(motion)
                if motion.on_end is not None:
                    motion.on_end(True)
                if motion.command is not None:
                    motion.command.finish()
                if motion.c_motion or "c" in motion.coordinates:
                    self.modes.c_at_rest(self.system.value(self._rows["c"])[0])
                if motion.coordinates & _AREA and self._group is not None and \
                        not any(m.coordinates & _AREA for m in self._motions):
                    self._group.registry.settle(self._member, self._standing_area(self._set_pose()))
        self._reschedule()

    def _couple(self, rider: Rider | None) -> None:
        self._rider = rider

    def _odometer_row(self, s: float) -> int:
        """The table row of the mover's arc length on a track (made on its first join)."""
        if self._odometer is None:
            self._odometer = self.system.add_rows([s])[0]
        return self._odometer

    def _on_track_finished(self, command: PlanarCommand | None) -> None:
        """Told by the traffic (its ``Owner``): the mover's track command ended at its target
        (or its halt)."""
        self.awake = True
        release_bands(self)
        if command is not None:
            command.finish()

    def _admit_way(self, tracks: list[MC_PlanarTrack]) -> None:
        """Asked by the traffic (its ``Owner``): the mover's geared way goes on over ``tracks``
        it did not hold at the start (followMover, the master's later tracks): admitted as
        the gear path's tracks are at the start (their state, their bands in a group; D-149).
        Raises
        ``CommandRejected`` (a ``Collision`` naming the member in the way)."""
        admit_way(self, tracks, MoverCommand.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER)

    def _reschedule(self) -> None:
        """When ``_after_motion`` must run next: an end, a release, or every cycle."""
        if self.modes.external is not ExternalSetPositionMode.NONE:
            self.next_event = -math.inf
            return
        events = [m.end for m in self._motions]
        events += [m.releases[0] for m in self._motions if m.releases]
        self.next_event = min(events, default=math.inf)

    def _publish(self) -> bool:
        self.states.update()
        self.commands.publish()
        self._status = None
        return not self.states.settled

    @property
    def mc_to_plc(self) -> CDT_MCTOPLC_PLANAR_MOVER:
        """The cyclic interface as the last motion phase left it (§7.2.1.2.1)."""
        stamp = self.system.published
        if self._status is None or self._status[0] != stamp:
            self._status = (stamp, self._snapshot())
        return self._status[1]

    def _snapshot(self) -> CDT_MCTOPLC_PLANAR_MOVER:
        rider = self._rider
        riding = rider is not None and traffic_of(self.system).moving(rider)
        std = CDT_MCTOPLC_PLANAR_MOVER_STD(
            mover_oid=self.oid, group_oid=self._group.oid if self._group else 0,
            state=self.states.state, command_mode=self.modes.mode,
            busy=MoverBusy(bool(self._motions) or riding,
                           any(m.coordinates & _AREA for m in self._motions) or riding),
            error_code=int(self.states.error_id))
        vectors = [MoverVector(*self._vector(which)) for which in range(3)]
        on_track = CDT_MCTOPLC_PLANAR_MOVER_TRACK()
        modes = CDT_MCTOPLC_PLANAR_MOVER_COORDMODE()
        if rider is not None:
            track, s, v, a = traffic_of(self.system).position(rider)
            on_track = CDT_MCTOPLC_PLANAR_MOVER_TRACK(s, v, a, 0.0, track.oid)
            modes = CDT_MCTOPLC_PLANAR_MOVER_COORDMODE(
                xy_coordinate_mode=CoordinateMode.DEPENDENT,
                c_coordinate_mode=CoordinateMode.DEPENDENT if rider.oriented
                else CoordinateMode.INDEPENDENT)
        return CDT_MCTOPLC_PLANAR_MOVER(
            std=std,
            set=CDT_MCTOPLC_PLANAR_MOVER_SET(*vectors, physical_area_id=self.coordinate_system),
            act=CDT_MCTOPLC_PLANAR_MOVER_ACT(*vectors, physical_area_id=self.coordinate_system),
            coord_mode=modes, set_on_track=on_track)

    # -- state machine hooks ---------------------------------------------------------------------

    def _on_enter(self, state: PlanarState) -> None:
        if state is PlanarState.ENABLED and self.states.reaction is ErrorReaction.QUICK_STOP:
            if not self._motions:
                self.modes.enabled(self._set_pose().c)
        elif state is PlanarState.DISABLING:
            self._brake("maximum")
        elif state is PlanarState.ERROR_PENDING:
            if self.modes.external is not ExternalSetPositionMode.NONE:
                self.modes.external = ExternalSetPositionMode.NONE  # the stream keeps its error
            if self.states.reaction is ErrorReaction.ABORT:
                self._freeze()
            else:
                self._brake("maximum")

    def _transition_done(self, state: PlanarState) -> bool:
        if state in (PlanarState.DISABLING, PlanarState.ERROR_PENDING):
            riding = self._rider is not None and traffic_of(self.system).moving(self._rider)
            return not self._motions and not riding
        if state in (PlanarState.ENABLING, PlanarState.RESETTING):
            environment = self.system.environment()
            return environment is None or environment.port.part_ready(self)
        return True

    # -- helpers ---------------------------------------------------------------------------------

    def _limits(self, which: str) -> dict[str, Limits]:
        p = self.parameters
        return {g: getattr(p, f"{which}_dynamic_{g}") for g in ("xy", "z", "a", "b", "c")}

    def _state_at(self, name: str, time: float) -> KinematicState:
        return self.system.table.state(self._rows[name], time)

    def _start_states(self, *names: str) -> dict[str, KinematicState]:
        """The states new plans start from (all coordinates unless ``names`` are given)."""
        names = names or COORDINATES
        states = self.system.table.states([self._rows[name] for name in names],
                                           self.system.previous)
        return dict(zip(names, states, strict=True))

    def _xy_position_limits(self) -> tuple[PositionLimits, PositionLimits]:
        """The hidden x and y position limits of ``parameters`` (made once per parameters)."""
        known, p = self._position_limits, self.parameters
        if known is None or known[0] is not p:
            low, high = p.minimum_position, p.maximum_position
            known = self._position_limits = (p, PositionLimits(low.x, high.x),
                                             PositionLimits(low.y, high.y))
        return known[1], known[2]

    def _set_pose(self) -> Pose:
        x, y, _, _, _, c = self.system.values(0, self._row0, 6).tolist()  # rows x ... c
        return Pose(x, y, c)

    def _resolve(self, target: PositionXYC) -> tuple[int, Pose]:
        finite(target.x, "x")
        finite(target.y, "y")
        finite(target.c, "c")
        environment = self.system.environment()
        if environment is None:
            if target.reference_id != 0:
                raise CommandRejected(ErrorId.INVALID_REFERENCE_ID,
                                      f"reference id 16#{target.reference_id:08X} names no part "
                                      "or coordinate system: there are none (§5.3)")
            return 0, target.pose
        return environment.port.resolve(target, self.coordinate_system)

    def _move_c_anywhere(self, command: PlanarCommand) -> None:
        """MoveC: on a track (its C then no longer follows the track) or free."""
        if self._rider is not None:
            move_c_on_track(self, command)
        else:
            self._move_c(command)

    #: the handler of each motion command: a method of this class, or a track command of
    #: riding.py or gearing.py (which reach the mover through its ``port``)
    _HANDLERS: ClassVar[dict[MoverCommand, Callable[[Any, PlanarCommand], None]]] = {
        _C.MOVE_TO_POSITION: _move_to_position,
        _C.MOVE_C: _move_c_anywhere,
        _C.ADOPT_TRACK_ORIENTATION: riding.adopt_track_orientation,
        _C.MOVE_Z: _move_aux,
        _C.MOVE_A: _move_aux,
        _C.MOVE_B: _move_aux,
        _C.HALT: _halt,
        _C.SET_POSITION: _set_position,
        _C.JOIN_TRACK: riding.join_track,
        _C.LEAVE_TRACK: riding.leave_track,
        _C.MOVE_ON_TRACK: riding.move_on_track,
        _C.GEAR_IN_POS_ON_TRACK: gearing.gear_in_pos_on_track,
        _C.GEAR_IN_POS_ON_TRACK_WITH_MASTER_MOVER: gearing.gear_in_pos_on_track_with_master_mover,
        _C.ADD_TO_GROUP: _add_to_group,
        _C.REMOVE_FROM_GROUP: _remove_from_group,
        _C.START_EXTERNAL_SETPOINT_GENERATION: _start_external,
        _C.START_RELATIVE_EXTERNAL_SETPOINT_GENERATION: _start_external,
        _C.STOP_EXTERNAL_SETPOINT_GENERATION: _stop_external,
    }



def _off_stators(environment: MC_PlanarEnvironment, problem: str) -> CommandRejected:
    """PLANAR_COLLISION with the environment as objectInfo, as a group answers a move over
    the edge (§6.7.2), for a mover that no stator would carry (D-163)."""
    rejection = CommandRejected(ErrorId.PLANAR_COLLISION,
                                f"{problem} of environment 16#{environment.oid:08X}: no stator "
                                "carries the mover there (§6.4)")
    rejection.object_info = environment.get_planar_object_info()
    return rejection


def _copy(position: PositionXYC) -> PositionXYC:
    """The PLC passes targets IN_OUT but the command keeps the values of the call."""
    if not isinstance(position, PositionXYC):
        raise TypeError(f"a target must be a PositionXYC, got {type(position).__name__}")
    return PositionXYC(position.x, position.y, position.c, reference_id(position.reference_id))


def _track(value: MC_PlanarTrack | None, current: bool = False) -> MC_PlanarTrack | None:
    """A track argument; with ``current`` None or 0 name the mover's current track."""
    if current and (value is None or (value == 0 and not isinstance(value, bool))):
        return value
    if not isinstance(value, MC_PlanarTrack):
        raise TypeError(f"a track must be an MC_PlanarTrack, got {type(value).__name__}")
    return value


def _trail(value: MC_PlanarTrackTrail | None) -> MC_PlanarTrackTrail | None:
    if value is not None and not isinstance(value, MC_PlanarTrackTrail):
        raise TypeError(f"a track trail must be an MC_PlanarTrackTrail or None, got "
                        f"{type(value).__name__}")
    return value


def _constraint(value: IPlcDynamicConstraint | None) -> IPlcDynamicConstraint | None:
    if value is not None and not isinstance(value, IPlcDynamicConstraint):
        raise TypeError(f"a constraint must be a DynamicConstraint_... object or None, got "
                        f"{type(value).__name__}")
    return value


def _options(value: _T | None, kind: type[_T]) -> _T | None:
    if value is not None and not isinstance(value, kind):
        raise TypeError(f"options must be a {kind.__name__} or None, got "
                        f"{type(value).__name__}")
    return value


