"""The planar machine of one run: built and set up before t = 0, fed by the timeline, read.

The run builds the ``planar`` block (scenario/planar.py) in its order, so the OIDs are those
TwinCAT hands out: movers 16#05110010, 16#05110020, ...; the environment, then the groups,
then the tracks, 16#05120010, ... ``set_up`` then gives the environment its stators and
boundary, builds the tracks (planar_tracks.py) and enables them, enables the groups and movers
with ``enable`` and lets each enabled group take the environment, its movers and its tracks
(AddToGroup, in the listed order). The planar API decides a call in the motion phase of
the next cycle, so the setup takes three cycles; they run before anything else is on the
runtime, and the clock then starts again at 0, so that every object is ready at t = 0, as an
enabled CA group is (docs/scenarios.md). Only standing planar objects saw those cycles.

With parts (§5.2) the environment takes a new ``PartLayout`` and the run initialises one
MC_PlanarPart per part; the setup then only creates the boundary, and a mover must start on a
part in its active position.

A timeline entry's row is a ``Command`` that follows the method's PlanarCommand once per cycle
(observer phase): BUSY while sent or active, then DONE, ABORTED or ERROR; a refused command
says ``rejected (33158) by mover 16#05110010``: the error number and the blocking object. A
start_external_setpoint_generation entry is a ``SetpointFeed``: ``feed`` sends its setpoint in
the program phase of every cycle (run.py calls it before the entries fire), its row follows the
generation and the mover's errors. A move_on_track row whose mover stands queued on its
track is ``waiting``: it stays BUSY but does not keep an open-ended run going.

With ``planar.router`` or a ``route`` entry the run adds the router after the setup
(``add_router``); a route entry's row follows the RouteCommands of its movers (``route``,
planar_routing.py) and the runtime's ``RoutePlans`` notes the ways planned.

Entries name their tracks, axes, movers and trails; ``_resolve`` passes the objects (a trail is
an MC_PlanarTrackTrail built for the call). A gear-in gets its specialised feedback, which
``in_sync`` reads for ``<id>.in_sync``; the row's detail says when it was first in sync.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.planar import (
    CommandPhase,
    MC_PlanarEnvironment,
    MC_PlanarFeedback,
    MC_PlanarGroup,
    MC_PlanarMover,
    MC_PlanarPart,
    MC_PlanarTrackTrail,
    MoverVector,
    PlanarCommand,
    PlanarObjectType,
    PlanarState,
    Pose,
)
from openmotion.planar.feedback import MC_PlanarFeedbackInSync
from openmotion.planar.kind import PLANAR_MOVER
from openmotion.planar.routing import RouteCommand, Router
from openmotion.planar.routing.plans import RoutePlans
from openmotion.planar.track import MC_PlanarTrack
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.planar import (
    AddToGroup,
    Loc,
    PlanarEntry,
    PlanarGroupEntry,
    PlanarSpec,
)
from openmotion.scenario.planar_gearing import AxisRef, MoverRef, TrailRef, _GearIn
from openmotion.scenario.planar_objects import EnvironmentEntry, GroupRef, TrackEntry
from openmotion.scenario.planar_parts import PartEntry, oid_text
from openmotion.scenario.planar_riding import MoveOnTrack
from openmotion.scenario.planar_routing import Route, RouterSpec, follow_route, router_group
from openmotion.scenario.planar_setpoints import COORDINATES, StartExternalSetpointGeneration
from openmotion.scenario.planar_tracks import PlanarTrackRow, TrackRef, build_order
from openmotion.scenario.programs import _motion_cycle, cycle_of
from openmotion.scenario.queries import Query

if TYPE_CHECKING:
    from rich.table import Table

SETUP_CYCLES = 10  #: the setup must be over within this many cycles (it takes three)


@dataclass(frozen=True)
class PlanarMoverRow:
    """One planar mover at the end of a run: its published set values."""

    mover: str
    oid: int  #: its object id (16#05110010 ...)
    group: str  #: the planar group it is in; "" for none
    state: str  #: PlanarState name in lower case
    x: float  #: [mm]
    y: float  #: [mm]
    z: float  #: [mm]
    a: float  #: [°]
    b: float  #: [°]
    c: float  #: [°]
    coordinate_system: int  #: OID of the coordinate system x, y, c are in; 0 without parts
    track: str = ""  #: the track it is on; "" for none
    s: float | None = None  #: its arc length there [mm]; None on no track


class PlanarMachine:
    """The planar objects of one run: built, set up, fed by the timeline, read by signals."""

    def __init__(self, rt: Runtime, spec: PlanarSpec | None) -> None:
        self.rt = rt
        self.spec = spec
        self.environment: MC_PlanarEnvironment | None = None
        self.movers: dict[str, MC_PlanarMover] = {}
        self.groups: dict[str, MC_PlanarGroup] = {}
        self.parts: dict[int, MC_PlanarPart] = {}  #: by part OID
        self.tracks: dict[str, MC_PlanarTrack] = {}
        self._group_names: dict[int, str] = {}  #: OID -> name, for the rows
        self._open: list[tuple[PlanarCommand, Command]] = []  #: issued, not yet ended
        #: move_on_track and gear-in rows: their mover
        self._riding: dict[Command, MC_PlanarMover] = {}
        self._sync: dict[Command, MC_PlanarFeedbackInSync] = {}  #: gear-in rows: their feedback
        self._masters: dict[Command, Axis | MC_PlanarMover] = {}  #: gear-in rows: their master
        self._feeds: list[SetpointFeed] = []  #: external setpoints being fed
        self.router: Router | None = None  #: made by ``add_router`` (planar_routing.py)
        #: route rows with their movers' handles, not yet ended
        self._routes: list[tuple[Command, dict[str, RouteCommand]]] = []
        self._route_handles: dict[Command, dict[str, RouteCommand]] = {}
        if spec is None:
            return
        if spec.environment is not None:
            self.environment = MC_PlanarEnvironment(rt, layout=spec.environment.layout())
            for oid in spec.environment.part_oids():
                self.parts[oid] = MC_PlanarPart()
                self.parts[oid].initialize(oid, self.environment)
        for group in spec.groups:
            self.groups[group.name] = MC_PlanarGroup(rt, group.name)
            self._group_names[self.groups[group.name].oid] = group.name
        for mover in spec.movers:
            self.movers[mover.name] = MC_PlanarMover(rt, mover.build(), mover.name)
        for track in spec.tracks:  # object OIDs after the environment's and the groups'
            self.tracks[track.name] = track.build(rt)

    def set_up(self) -> list[tuple[Loc, str]]:
        """Stators, boundary, Enable, AddToGroup, in the cycles before t = 0; returns what
        failed as (field path, message). Call it before anything else is on the runtime."""
        spec, rt = self.spec, self.rt
        if spec is None:
            return []
        placement = self._placement_problems()
        steps: list[tuple[Loc, str, PlanarCommand]] = []
        if self.environment is not None and spec.environment is not None:
            for index, corner in enumerate(spec.environment.corners()):
                steps.append((("environment",), f"stator {index}",
                              self.environment.add_stator(*corner)))
            steps.append((("environment",), "boundary", self.environment.create_boundary()))
        for index, group in enumerate(spec.groups):
            if group.enable:
                steps.append((("groups", index), "enable", self.groups[group.name].enable()))
        for index, mover in enumerate(spec.movers):
            if mover.enable:
                steps.append((("movers", index), "enable", self.movers[mover.name].enable()))
        tracks = self._build_tracks()
        self._settle(steps + tracks)
        for index, group in enumerate(spec.groups):
            target = self.groups[group.name]
            if group.enable and self.environment is not None and spec.has_environment(index):
                steps.append((("groups", index, "environment"), f"joining group {group.name}",
                              self.environment.add_to_group(target)))
            for loc, name in spec.members(index) if group.enable else []:
                steps.append((loc, f"joining group {group.name}",
                              self.movers[name].add_to_group(target)))
            for loc, name in spec.track_members(index):
                steps.append((loc, f"joining group {group.name}",
                              self.tracks[name].add_to_group(target)))
        self._settle(steps)
        rt.rewind()  # the setup happened before t = 0 (module docstring)
        failed: set[Loc] = set()  # tracks with a failed command: only the first one counts
        problems = []
        for loc, what, command in tracks + steps:
            if command.done or loc[:2] in failed:
                continue
            if loc[0] == "tracks":
                failed.add(loc[:2])
            problems.append((loc, f"{what}: {self._failure(command)}" if what
                             else self._failure(command)))
        return placement + problems

    def _build_tracks(self) -> list[tuple[Loc, str, PlanarCommand]]:
        """The tracks' links and geometry in ``build_order``, then Enable for each, so that
        the automatic collision ranges see the whole network (planar_tracks.py)."""
        specs = self.spec.tracks if self.spec is not None else []
        steps: list[tuple[Loc, str, PlanarCommand]] = []
        order, _ = build_order(specs)  # the schema refused tracks that cannot be built
        for index, stage in order:
            steps += [(("tracks", index, *loc), "", command)
                      for loc, command in specs[index].stage(stage, self.tracks)]
        steps += [(("tracks", index), "enable", self.tracks[spec.name].enable())
                  for index, spec in enumerate(specs)]
        return steps

    def _placement_problems(self) -> list[tuple[Loc, str]]:
        """With parts: each mover starts on a part in its active position (on its ``part``)."""
        layout = self.environment.layout if self.environment is not None else None
        if layout is None or self.spec is None:
            return []
        problems: list[tuple[Loc, str]] = []
        for index, spec in enumerate(self.spec.movers):
            mover = self.movers[spec.name]
            try:
                part, _ = layout.position_on_current_part(mover.coordinate_system, mover.pose,
                                                          spec.part)
            except CommandRejected as exc:  # "(500, 120) in coordinate system ... on no part"
                part, problem = 0, f"the start {exc.message}"
            else:
                problem = ""
            if spec.part is not None and part != spec.part:
                problem = f"({spec.x:g}, {spec.y:g}) lies off part {oid_text(spec.part)}: x " \
                          "and y are in the part frame"
            if problem:
                problems.append((("movers", index), problem))
        return problems

    def _failure(self, command: PlanarCommand) -> str:
        """Why a setup command did not end Done, naming the blocking object."""
        if not command.error:
            return f"still {command.phase.name.lower()} after {SETUP_CYCLES} cycles"
        error = f"{command.error_id.name} ({int(command.error_id)})"
        info = command.object_info
        if info.object_type is PlanarObjectType.INVALID:
            return f"{error}: {command.message}"
        if info.object_type is PlanarObjectType.ENVIRONMENT:
            return f"{error}: the footprint is not on the stators"
        kind = info.object_type.name.lower()
        objects = self.movers if info.object_type is PlanarObjectType.MOVER else self.tracks
        name = next((name for name, obj in objects.items() if obj.oid == info.id), "")
        return f"{error}: the footprint meets {kind} {name} (16#{info.id:08X})"

    def _settle(self, steps: list[tuple[Loc, str, PlanarCommand]]) -> None:
        for _ in range(SETUP_CYCLES):
            if not any(command.busy for _, _, command in steps):
                return
            self.rt.step()

    def add_router(self, spec: RouterSpec) -> Router:
        """The router of ``route`` entries, on its group, after the setup (its program runs
        before the timeline's); its plans go to the runtime's ``RoutePlans``."""
        assert self.spec is not None and self.environment is not None  # route_problems
        group = router_group(self.spec)
        assert group is not None
        self.router = Router(
            self.groups[group], self.environment,
            obstacles=[obstacle.geometry() for obstacle in spec.obstacles],
            obstacle_names=[obstacle.name for obstacle in spec.obstacles],
            constraint=spec.constraint(), time_budget=spec.time_budget, pitch=spec.pitch,
            seed=spec.seed)
        plans = RoutePlans.of(self.rt)
        assert plans is not None
        plans.watch(self.router)
        return self.router

    def route(self, entry: Route) -> Command:
        """One Router.route call for the entry's movers; the row follows their handles."""
        row = Command(entry.command, self.rt.now)
        assert self.router is not None  # the run made it for a file with route entries
        targets = {}
        for name, target in entry.targets.items():
            mover = self.movers[name]
            targets[mover] = (target.x, target.y, mover.pose.c if target.c is None
                              else target.c)
        try:
            handles = self.router.route(targets, entry.time_budget)
        except ConfigError as exc:  # refused before planning (checked by the file's schema)
            row.end(CommandStatus.ERROR, self.rt.now, ErrorId.PLANAR_INVALID_INPUT, str(exc))
            return row
        plans = RoutePlans.of(self.rt)
        assert plans is not None
        plans.note()  # the plan as of the call, at its time
        by_name = {mover.name: handle for mover, handle in handles.items()}
        self._route_handles[row] = by_name
        self._routes.append((row, by_name))
        follow_route(row, by_name, self.rt.now)
        return row

    def route_handles(self, row: Command) -> dict[str, RouteCommand]:
        """The handles of a route row, by mover name (empty for any other row)."""
        return self._route_handles.get(row, {})

    # -- the timeline ------------------------------------------------------------------------

    def issue(self, entry: PlanarEntry | PlanarGroupEntry | PartEntry) -> Command:
        """Call the entry's method now; the row follows its PlanarCommand (``watch``)."""
        if isinstance(entry, Route):
            return self.route(entry)
        if isinstance(entry, StartExternalSetpointGeneration):
            feed = SetpointFeed(self, entry)
            self._feeds.append(feed)
            return feed.row
        if isinstance(entry, Query):  # a Get method: its row keeps what it returned
            return entry.call(self, self.rt.now)
        target = self.target_of(entry)
        command = Command(entry.command, self.rt.now)
        if target is None:  # an environment entry without planar.environment
            command.end(CommandStatus.ERROR, self.rt.now, ErrorId.PLANAR_INVALID_INPUT,
                         "there is no planar.environment")
            return command
        try:
            arguments = tuple(self.groups[name] for name in entry.arguments()) \
                if isinstance(entry, AddToGroup) else tuple(map(self._resolve, entry.arguments()))
        except CommandRejected as exc:  # a trail whose links do not hold (parts moved)
            command.end(CommandStatus.ERROR, self.rt.now, exc.error_id,
                         f"rejected ({int(exc.error_id)}): {exc.message}")
            return command
        extra: dict[str, Any] = {"feedback": MC_PlanarFeedback()}  # as a PLC program passes
        if isinstance(entry, _GearIn):  # its feedback shows in_sync
            extra["feedback"] = self._sync[command] = entry.feedback()
        planar = getattr(target, entry.method)(*arguments, **extra)
        self._open.append((planar, command))
        if isinstance(entry, MoveOnTrack | _GearIn):
            self._riding[command] = target
        if isinstance(entry, _GearIn):
            self._masters[command] = arguments[0]
        return command

    def target_of(self, entry: Any) -> Any:
        """The object whose method a planar entry calls; None for an environment entry
        without planar.environment."""
        return self.groups[entry.group] if isinstance(entry, PlanarGroupEntry) \
            else self.parts[entry.part] if isinstance(entry, PartEntry) \
            else self.tracks[entry.track] if isinstance(entry, TrackEntry) \
            else self.environment if isinstance(entry, EnvironmentEntry) \
            else self.movers[entry.mover]

    def _resolve(self, argument: Any) -> Any:
        """An entry's argument with a reference by name replaced by its object; a trail is
        built anew (AddTrack), CommandRejected when a track of it does not follow (§6.8)."""
        if isinstance(argument, TrackRef):
            return self.tracks[argument.name]
        if isinstance(argument, GroupRef):
            return self.groups[argument.name]
        if isinstance(argument, AxisRef):
            return self.rt.axes[argument.name]
        if isinstance(argument, MoverRef):
            return self.movers[argument.name]
        if isinstance(argument, TrailRef):
            trail = MC_PlanarTrackTrail()
            trail.clear()  # a PLC program empties its trail before it adds the tracks
            for name in argument.tracks:
                if not trail.add_track(self.tracks[name]):
                    raise CommandRejected(trail.error_id, f"trail: {trail.message}")
            return trail
        return argument

    def in_sync(self, command: Command) -> bool:
        """A gear-in row's feedback shows InSync (as of the last cycle); False for others."""
        feedback = self._sync.get(command)
        return feedback is not None and feedback.in_sync

    def feed(self) -> None:
        """Send this cycle's external setpoints (program phase, before the entries fire)."""
        for feed in self._feeds:
            feed.feed()

    def watch(self) -> None:
        """Let every row follow the command its method returned (observer phase): both are
        kernel ``Command``s, so the row takes its status (``follow``)."""
        self._feeds = [feed for feed in self._feeds if feed.watch()]
        for row, handles in self._routes:
            follow_route(row, handles, self.rt.now)
        self._routes = [(row, handles) for row, handles in self._routes if not row.finished]
        still = []
        for planar, command in self._open:
            command.warnings = list(planar.warnings)
            if command.value is None and self.in_sync(command):  # the row says when
                command.value = f"in sync at {self.rt.now:.3f} s"
            follow(command, planar, self.rt.now, self.outcome(planar, command.active))
            if planar.busy:
                still.append((planar, command))
        self._open = still

    def outcome(self, planar: PlanarCommand, accepted: bool) -> str:
        """An error as the rows show it: ``rejected (33158) by mover 16#05110010``; without
        a blocking object, the reason."""
        if not planar.error:
            return ""
        verb = "failed" if accepted else "rejected"
        info = planar.object_info
        if info.object_type is PlanarObjectType.INVALID:
            return f"{verb} ({int(planar.error_id)}): {planar.message}"
        return f"{verb} ({int(planar.error_id)}) by {info.object_type.name.lower()} " \
               f"16#{info.id:08X}"

    @property
    def busy(self) -> bool:
        """A mover moves (or brakes), a feed runs or a transition runs: the run goes on. A
        mover that stands in a queue on a track does not count (``waiting``)."""
        return bool(self._feeds) or self.router is not None and self.router.busy or any(
            mover.mc_to_plc.std.busy.busy_mover and not _queued(mover)
            or mover.state in _TRANSITIONAL for mover in self.movers.values()) or any(
            group.state in _TRANSITIONAL for group in self.groups.values())

    def waiting(self, command: Command) -> bool:
        """A busy move_on_track whose mover stands on its track: queued behind another mover
        or at a switch, it may stay Busy for ever (Done only at its target, §6.2.2); it does
        not keep an open-ended run going, as a queued CA mover does not. Nor does a gear-in
        whose slave and master both stand; a slave waiting for a moving master (its product
        still to come, or room ahead) does, as one that moves does through ``busy``: a run
        with a gear-in left coupled needs a ``duration``."""
        mover = self._riding.get(command)
        if mover is None or not command.busy or not _queued(mover):
            return False
        master = self._masters.get(command)
        return master is None or _stands(master)

    # -- the summary ---------------------------------------------------------------------------

    def _track_name(self, number: float) -> str:
        """The name of the track with this ``track`` signal value; "" for 0."""
        names = list(self.tracks)
        return names[int(number) - 1] if 1 <= number <= len(names) else ""

    def rows(self) -> list[PlanarMoverRow]:
        rows = []
        for name, mover in self.movers.items():
            p = mover.position
            track = self._track_name(_TRACK.read(mover))
            rows.append(PlanarMoverRow(name, mover.oid,
                                       self._group_names.get(mover.mc_to_plc.std.group_oid, ""),
                                       mover.state.name.lower(), p.x, p.y, p.z, p.a, p.b, p.c,
                                       mover.mc_to_plc.set.physical_area_id, track,
                                       mover.mc_to_plc.set_on_track.set_pos if track else None))
        return rows

    def track_rows(self) -> list[PlanarTrackRow]:
        """Each track at the end of a run, with the movers on it by their arc length."""
        on: dict[int, list[tuple[float, str]]] = {}
        for name, mover in self.movers.items():
            on_track = mover.mc_to_plc.set_on_track
            if on_track.track_oid:
                on.setdefault(on_track.track_oid, []).append((on_track.set_pos, name))
        rows = []
        for name, track in self.tracks.items():
            std = track.mc_to_plc_std
            rows.append(PlanarTrackRow(
                name, track.oid, self._group_names.get(std.group_oid, ""), track.length,
                std.state.name.lower(), std.operation_mode.name.lower(), track.closed_loop,
                track.collision_ranges, tuple(mover for _, mover in sorted(on.get(track.oid, [])))))
        return rows


class SetpointFeed:
    """A start_external_setpoint_generation entry at run time (§6.1.6, §6.1.7): the start,
    one setpoint per cycle from the entry's sources, and the row that follows the generation.

    The firing cycle's setpoint is sent right after the start; ``feed`` sends the later ones in
    the program phase, before the entries fire, so that a stop entry comes after its cycle's
    setpoint (§7.2.2.8.19). τ counts whole cycles from the first setpoint.
    """

    def __init__(self, machine: PlanarMachine, entry: StartExternalSetpointGeneration) -> None:
        rt = machine.rt
        self.machine, self.entry, self.rt = machine, entry, rt
        self.mover = machine.movers[entry.mover]
        #: where each coordinate holds and what the offsets default to: the start position in
        #: the frame of ``reference_id`` (absolute), 0 (relative)
        self.hold = self._start() if entry.mode == "absolute" else [0.0] * len(COORDINATES)
        self.start = self.mover.start_external_setpoint_generation(*entry.arguments())
        self.row = Command(entry.command, rt.now)
        self.first = _motion_cycle(rt)  #: the cycle of the first setpoint
        self.until = None if entry.feed_for is None \
            else self.first + cycle_of(entry.feed_for, rt.cycle_time)
        self.fed = 0  #: the cycle of the last setpoint
        self.feedback = MC_PlanarFeedback() if entry.reference_id else None
        self.feed()

    def _start(self) -> list[float]:
        p = self.mover.position
        values = [p.x, p.y, p.z, p.a, p.b, p.c]
        environment = self.machine.environment
        layout = environment.layout if environment is not None else None
        if layout is not None and self.entry.reference_id:
            try:
                _, frame = layout.to_coordinate_system(self.entry.reference_id, Pose())
            except CommandRejected:
                return values  # the first setpoint fails with INVALID_REFERENCE_ID
            values[0], values[1], values[5] = frame.inverse().compose(self.mover.pose)
        return values

    def feed(self) -> None:
        """This cycle's setpoint, unless sent already or the generation is over."""
        cycle = _motion_cycle(self.rt)
        if self.row.finished or cycle == self.fed or not self.start.busy or self.mover.error \
                or self.until is not None and cycle >= self.until:
            return
        self.fed = cycle
        tau = (cycle - self.first) * self.rt.cycle_time
        columns = zip(*(self._setpoint(k, name, tau) for k, name in enumerate(COORDINATES)),
                      strict=True)
        position, velocity, acceleration = (MoverVector(*column) for column in columns)
        if self.feedback is None:
            self.mover.set_external_setpoint(position, velocity, acceleration)
        else:
            self.mover.set_external_setpoint_reference_id(
                self.feedback, position, velocity, acceleration, self.entry.reference_id)

    def _setpoint(self, k: int, name: str, tau: float) -> tuple[float, float, float]:
        """Position, velocity, acceleration of one coordinate at τ."""
        source, hold = getattr(self.entry.feed, name), self.hold[k]
        if source is None:
            return hold, 0.0, 0.0
        if source.axis is not None:  # the set values of the cycle before
            axis = self.rt.axes[source.axis]
            return axis.set_position, axis.set_velocity, axis.set_acceleration
        if source.ramp is not None:
            ramp = source.ramp
            offset = hold if ramp.offset is None else ramp.offset
            return offset + ramp.velocity * tau, ramp.velocity, 0.0
        sine = source.sine
        assert sine is not None  # one source each (CoordinateFeed)
        offset = hold if sine.offset is None else sine.offset
        omega = 2.0 * math.pi / sine.period
        half, phase = sine.amplitude / 2.0, omega * tau
        return (offset + half * (1.0 - math.cos(phase)), half * omega * math.sin(phase),
                half * omega * omega * math.cos(phase))

    def watch(self) -> bool:
        """Let the row follow the generation (observer phase); False once the row ended.

        A mover error ends the row with the mover's error id and message (a missing or
        refused setpoint also ends the start command with that error).
        """
        start, row, mover, now = self.start, self.row, self.mover, self.rt.now
        if mover.error and start.phase is not CommandPhase.SENT:
            row.end(CommandStatus.ERROR, now, mover.error_id, mover.message)
        else:
            follow(row, start, now, self.machine.outcome(start, row.active))
        return not row.finished


def _stands(master: Axis | MC_PlanarMover) -> bool:
    """A gear-in's master is at rest: an axis without motion, a mover without set velocity
    or acceleration."""
    if isinstance(master, MC_PlanarMover):
        status = master.mc_to_plc.set
        return not any(getattr(vector, name) for vector in (status.set_velo, status.set_acc)
                       for name in COORDINATES)
    return not master.moving


def _queued(mover: MC_PlanarMover) -> bool:
    """On a track and standing: every set velocity and acceleration is 0."""
    status = mover.mc_to_plc
    return bool(status.set_on_track.track_oid) and not any(
        getattr(vector, name) for vector in (status.set.set_velo, status.set.set_acc)
        for name in COORDINATES)


_TRACK = PLANAR_MOVER.signal("track")  #: the number of a mover's track, for its row


def follow(row: Command, command: Command, now: float, message: str = "") -> None:
    """Show ``command``'s status on its scenario row: Active once it runs, then its end at
    ``now`` with its error id and ``message``. One rule for every handle type (D-238)."""
    if command.active:
        row.start()
    elif command.finished:
        row.end(command.status, now, command.error_id, message)


_TRANSITIONAL = (PlanarState.ENABLING, PlanarState.DISABLING, PlanarState.RESETTING,
                 PlanarState.ERROR_PENDING)


def planar_table(rows: list[PlanarMoverRow], number: Callable[[float], str]) -> Table:
    """The summary's ``Planar movers`` table: each mover's final set position."""
    from rich import box
    from rich.table import Table
    from rich.text import Text

    table = Table(box=box.SIMPLE, title_justify="left", title="Planar movers")
    for name in ("mover", "oid", "group", "state", "x [mm]", "y [mm]", "z [mm]", "a [°]",
                 "b [°]", "c [°]"):
        table.add_column(Text(name), justify="left" if name in ("mover", "oid", "group",
                                                                "state") else "right",
                         no_wrap=True)
    for row in rows:
        table.add_row(row.mover, f"16#{row.oid:08X}", row.group or "-", row.state,
                      *(number(value) for value in (row.x, row.y, row.z, row.a, row.b, row.c)))
    return table
