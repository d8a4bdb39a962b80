"""Path commands of an axes group: what they build, how they queue, blend and end.

A motion FB becomes a ``PathCommand``: its geometry (lines, arcs, contours, or an ACS line for
MC_MoveDirect*), its dynamics and its BufferMode / TransitionMode (§7). ``PathMotion`` keeps
one time law (timing.py) for the path that runs now; every geometry element is one piece of
it, and every piece knows its command, so a command is Active while the TCP is on its pieces
and Done when the TCP has left them (the next command took over) or the path came to rest.

Buffering (§7.3): Aborting brakes the running path along itself with the new command's
deceleration and jerk and starts the new path from the rest point (the new command is Active
at once, the old ones show CommandAborted in the same cycle); Buffered appends with a stop
at the corner; the Blending modes append with a contour (geometry/blend.py) where the
TransitionMode asks for one and a contour still fits, else with a stop (decisions D-110).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.axis.commands import Command, CommandStatus
from openmotion.coordinated.evaluate import evaluate
from openmotion.coordinated.inputs import CoordSystem, TransitionMode
from openmotion.coordinated.limits_bridge import caps_for, caps_for_many, dense_path
from openmotion.coordinated.states import ExecutionMode
from openmotion.coordinated.timing import Piece, TimeLaw
from openmotion.coordinated.tolerances import JOIN_SLACK, MIN_CORNER_DISTANCE, TAKE_OVER_TOLERANCE
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.geometry.blend import Blend, corner_distance_blend, max_corner_deviation_blend
from openmotion.geometry.path import Arc, Line

if TYPE_CHECKING:
    from openmotion.coordinated.group import AxesGroup

ACS, MCS, PCS = "ACS", "MCS", "PCS"  #: the space a piece is evaluated in
_SPACE_ID = {ACS: 0, MCS: 1, PCS: 2}
_TRANSITION_SPEED: dict[BufferMode, Callable[[float, float], float]] = {
    BufferMode.BLENDING_LOW: min,
    BufferMode.BLENDING_PREVIOUS: lambda v1, _v2: v1,
    BufferMode.BLENDING_NEXT: lambda _v1, v2: v2,
    BufferMode.BLENDING_HIGH: max,
}
_JOIN_LENGTH = 1e-3  #: [mm] added to a lead-out (D-195), so that it is never empty
_CONTOURS = (TransitionMode.TM_START_VELOCITY, TransitionMode.TM_CONSTANT_VELOCITY,
             TransitionMode.TM_CORNER_DISTANCE, TransitionMode.TM_MAX_CORNER_DEVIATION)


@dataclass
class PathCommand:
    """One motion FB's request, as the group queues it."""

    command: Command
    coord_system: CoordSystem
    build: Callable[[np.ndarray, np.ndarray], list[Any]]  #: (start, reference) -> geometry;
    #: both in ``space``: start is where the path begins, reference what relative inputs add
    #: to (the TCP when the FB was accepted, or the end of the queue, §5.21, Fig. 19)
    dynamics: tuple[float, float, float, float]  #: velocity, acceleration, deceleration, jerk
    buffer_mode: BufferMode = BufferMode.ABORTING
    transition: TransitionMode = TransitionMode.TM_NONE
    parameter: float = 0.0
    space: str = MCS
    first: int = -1  #: its first piece in the time law (-1: none yet)
    last: int = -1  #: its last piece
    end: np.ndarray | None = None  #: where it ends, in ``space``
    extra: dict[str, Any] = field(default_factory=dict)


@dataclass
class _Entry:
    geometry: Any
    space: str
    owner: PathCommand


class PathMotion:
    """The running path of one group: its time law, pieces, commands and the axis output."""

    def __init__(self, group: AxesGroup) -> None:
        self.group = group
        self.law: TimeLaw | None = None
        self.entries: dict[int, _Entry] = {}
        self.commands: list[PathCommand] = []  #: with pieces in the law, in path order
        self.waiting: PathCommand | None = None  #: an aborting command, starts at rest
        self.halt_command: Command | None = None
        self.interrupt_command: Command | None = None
        self.interrupted = False
        self.follow: np.ndarray | None = None  #: PCS point held in a moving PCS (§2.2)
        self.path_velocity = 0.0
        self.path_acceleration = 0.0
        self._next_piece = 0
        self._last_acs_v: np.ndarray | None = None
        self._acs_start: np.ndarray | None = None  #: the axes where the path began
        self._orientation: np.ndarray | None = None
        self._sampled: tuple[float, int, float] | None = None  #: last sample: time, piece, local

    # -- reading -------------------------------------------------------------------------------

    @property
    def running(self) -> bool:
        return self.law is not None or self.waiting is not None or self.follow is not None

    @property
    def finished(self) -> bool:
        """Nothing runs, waits or is kept for MC_GroupContinue: the group may rest."""
        return not self.running and self.halt_command is None

    @property
    def active(self) -> PathCommand | None:
        return next((c for c in self.commands if c.command.busy), self.waiting)

    def commands_to_wait(self, mode: ExecutionMode) -> list[Command]:
        """§3.3: the motion commands an ExecutionMode waits for."""
        busy = [c.command for c in self.commands if c.command.busy]
        if self.waiting is not None:
            busy.append(self.waiting.command)
        if mode is ExecutionMode.IMMEDIATELY or not busy:
            return []
        return busy[:1] if mode is ExecutionMode.DELAYED else busy

    @staticmethod
    def all_ended(commands: list[Command]) -> bool:
        return all(c.finished for c in commands)

    # -- commands ------------------------------------------------------------------------------

    def submit(self, request: PathCommand) -> Command:
        """Queue or start ``request`` by its BufferMode; rejections come back as errors."""
        now = self.group.runtime.now
        command = request.command
        quiet = self.law is None and self.waiting is None
        cam = self.law is not None and not isinstance(self.law, TimeLaw)  # SyncGroupToAxis
        if request.buffer_mode is BufferMode.ABORTING or quiet or self.interrupted or cam:
            if request.buffer_mode is not BufferMode.ABORTING and self.interrupted:
                raise CommandRejected(ErrorId.GROUP_MOVING,
                                      "the group is interrupted: MC_GroupContinue first, or "
                                      "abort (§5.15)")
            start = self._start_point(request)
            request.extra["reference"] = start
            takes_over = self._takes_over_halt(request, start)
            joins = None if takes_over is not None else self._join_plan(request, start)
            self._abort_queue(f"aborted by {command.kind}")
            self.follow = None
            if takes_over is not None:
                self._begin(request, start, moving=takes_over)
                return command
            if joins is not None:
                self._join(request, start, *joins)
                return command
            if self.law is not None and not self.law.standing:
                _, _, dec, jerk = request.dynamics
                self.law.stop(now, dec, jerk, keep=False)
                self.waiting = request
                command.status = CommandStatus.ACTIVE
                return command
            self.law = None
            self._begin(request, start)
            return command
        self._append(request)
        return command

    def _takes_over_halt(self, request: PathCommand, start: np.ndarray
                         ) -> tuple[float, float, float] | None:
        """§5.14: a motion issued while MC_GroupHalt brakes aborts it and runs on without
        standstill, where its path leaves the TCP as it moves now (same tangent and curvature)
        and the speed and braking rate lie within its first piece's caps (decisions D-132).
        Returns (time, path velocity, path acceleration) of the last sample to start from,
        or None: then it starts from rest (D-110)."""
        law, sampled = self.law, self._sampled
        if self.halt_command is None or law is None or law.standing or sampled is None \
                or self.interrupted or "couple" in request.extra:
            return None
        time, piece, local = sampled
        entry = self.entries.get(piece)
        if entry is None or entry.space != request.space or request.space == ACS:
            return None
        geometry = request.build(start, request.extra["reference"])
        if not geometry:
            return None
        _, tangent, curvature = evaluate(entry.geometry, local)
        _, new_tangent, new_curvature = evaluate(geometry[0], 0.0)
        if np.linalg.norm(new_tangent - tangent) > TAKE_OVER_TOLERANCE \
                or np.linalg.norm(new_curvature - curvature) > TAKE_OVER_TOLERANCE:
            return None
        v, a = self.path_velocity, self.path_acceleration
        try:
            first = self._pieces(request, geometry, exit_last=0.0)[0]
        except CommandRejected:  # refused from rest too, where the old path stops
            return None
        if v <= 0.0 or v > first.velocity or -a > first.deceleration or a > first.acceleration:
            return None
        return time, v, a

    def _join_plan(self, request: PathCommand, start: np.ndarray
                   ) -> tuple[tuple[float, float, float], list[Any], list[Piece]] | None:
        """§7.4.2, §7.4.3: an Aborting command with TMStartVelocity or TMConstantVelocity
        joins its path at speed instead of stopping (decisions D-195). The TCP runs on along
        a lead-out that continues its motion (same tangent and curvature: a line or an arc),
        its speed falling to the contour's; the lead-out's end is the corner the new path is
        built from (relative inputs still add to the TCP when the FB was accepted), and the
        contour of the transition mode joins the two as for a Blending command: for
        TMStartVelocity it starts once the speed has fallen to p % of the aborted command's
        Velocity, for TMConstantVelocity it runs at p % of the new command's Velocity (the
        transition velocity of Aborting). Returns the law's start state, the geometry and its
        pieces, or None where that cannot be done within the new command's dynamics (ACS,
        a reversal, a cam, a standing path): then the path stops first (D-110)."""
        law, sampled = self.law, self._sampled
        if request.transition not in (TransitionMode.TM_START_VELOCITY,
                                      TransitionMode.TM_CONSTANT_VELOCITY) \
                or not isinstance(law, TimeLaw) or law.standing or sampled is None \
                or self.interrupted or "couple" in request.extra:
            return None
        time, piece, local = sampled
        entry = self.entries.get(piece)
        v, a = self.path_velocity, self.path_acceleration
        if entry is None or entry.space != request.space or request.space == ACS or v <= 0.0:
            return None
        previous = entry.owner
        v2, a2, d2, j2 = request.dynamics
        speed = request.parameter / 100.0 * (
            previous.dynamics[0] if request.transition is TransitionMode.TM_START_VELOCITY
            else v2)
        point, tangent, curvature = evaluate(entry.geometry, local)
        reach = _speed_change_distance(v, speed, d2, j2) if v > speed else 0.0
        room = 2.0 * speed * speed / min(a2, previous.dynamics[1])  # a contour's radius
        try:
            lead = _lead_out(point, tangent, curvature, 2.0 * (reach + room) + _JOIN_LENGTH)
            corner = self.group.spaces.with_xyz(start, lead.end)
            geometry = request.build(corner, request.extra["reference"])
            if not geometry:
                return None
            blend = self._contour(request, lead, geometry[0], previous, v2)
            if blend is None:
                return None
            kept = [blend.before, blend.contour, blend.after, *geometry[1:]]
            first = caps_for(self.group, blend.before, request.space,
                             (v * (1.0 + JOIN_SLACK), a2, d2, j2))
            joint = self._piece(blend.contour, request.space, request, math.inf,
                                speed_cap=speed, other=previous)
            rest = self._pieces(request, kept[2:], exit_last=0.0)
        except CommandRejected:  # a reversal, a degenerate lead-out or corner: stop first
            return None
        lead_piece = Piece(blend.before.length, *first, exit_velocity=math.inf,
                           space=_SPACE_ID[request.space])
        slow = _speed_change_distance(v, min(speed, joint.velocity), d2, j2) \
            if v > min(speed, joint.velocity) else 0.0
        slow += v * abs(a) / j2  # while the acceleration it has now ramps out
        if v > lead_piece.velocity * (1.0 + JOIN_SLACK) or -a > lead_piece.deceleration \
                or a > lead_piece.acceleration or blend.before.length < slow:
            return None
        return (time, v, a), kept, [lead_piece, joint, *rest]

    def _join(self, request: PathCommand, start: np.ndarray,
              moving: tuple[float, float, float], geometry: list[Any],
              pieces: list[Piece]) -> None:
        """Start the joined path of ``_join_plan`` from the last sample's state."""
        group = self.group
        last_acs_v = self._last_acs_v
        self.clear()
        self._last_acs_v = last_acs_v
        self._orientation = start.copy()
        self._acs_start = group.acs_set()
        self.law = TimeLaw(*moving)
        if group.factors != (1.0, 1.0, 1.0):
            self.law.set_factors(group.runtime.now, *group.factors)
        request.command.status = CommandStatus.ACTIVE
        request.end = self._end_of(request, geometry, start)
        self._push(request, geometry, pieces)

    def halt(self, command: Command, deceleration: float, jerk: float) -> None:
        now = self.group.runtime.now
        self._abort_queue("aborted by MC_GroupHalt")
        self.follow = None
        self.interrupted = False
        if self.law is None:  # nothing runs (a buffered halt, or one at rest): at rest now
            command.end(CommandStatus.DONE, now)
            return
        command.status = CommandStatus.ACTIVE
        self.halt_command = command
        self.law.stop(now, deceleration, jerk, keep=False)

    def interrupt(self, command: Command, deceleration: float, jerk: float) -> None:
        active = self.active
        if self.law is None or active is None:
            command.end(CommandStatus.ERROR, self.group.runtime.now, ErrorId.NOTHING_TO_DO,
                         "no path motion to interrupt (§5.15)")
            return
        self.law.stop(self.group.runtime.now, deceleration, jerk, keep=True)
        self.interrupted = True
        active.command.status = CommandStatus.BUFFERED  # Busy, not Active (§5.15)
        command.status = CommandStatus.ACTIVE
        self.interrupt_command = command

    def resume(self) -> None:
        if not self.interrupted or self.law is None:
            raise CommandRejected(ErrorId.NOTHING_TO_DO, "no interrupted motion to continue "
                                                         "(§5.16)")
        if self.interrupt_command is not None and self.interrupt_command.busy:
            self.interrupt_command.end(CommandStatus.ABORTED, self.group.runtime.now,
                                        message="continued before standstill")
        self.interrupt_command = None
        self.interrupted = False
        self.law.resume(self.group.runtime.now)
        active = self.active
        if active is not None:
            active.command.status = CommandStatus.ACTIVE  # at Continue.Done (§5.16)
        if self.group.factors[0] == 0.0:
            self.law.set_factors(self.group.runtime.now, *self.group.factors)

    def brake(self, deceleration: float, jerk: float, reason: str) -> None:
        """MC_GroupStop: brake along the path, abort every command (§5.13)."""
        self._abort_queue(reason)
        self.follow = None
        self.interrupted = False
        if self.halt_command is not None:
            self.halt_command.end(CommandStatus.ABORTED, self.group.runtime.now, message=reason)
            self.halt_command = None
        if self.law is not None:
            self.law.stop(self.group.runtime.now, deceleration, jerk, keep=False)

    def set_factors(self, velocity: float, acceleration: float, jerk: float) -> None:
        if self.law is not None and not self.interrupted:
            self.law.set_factors(self.group.runtime.now, velocity, acceleration, jerk)

    def abort_all(self, reason: str, error: tuple[ErrorId, str] | None = None) -> None:
        """Everything ends now: disable, ungroup, power loss, group error."""
        now = self.group.runtime.now
        self.group.end_table(reason, error)  # a path table ends with it (path_table.py)
        ended = [c.command for c in self.commands]
        if self.waiting is not None:
            ended.append(self.waiting.command)
        for extra in (self.halt_command, self.interrupt_command):
            if extra is not None:
                ended.append(extra)
        for command in ended:
            if error is None:
                command.end(CommandStatus.ABORTED, now, message=reason)
            else:
                command.end(CommandStatus.ERROR, now, error[0], error[1])
        self.clear()

    def end_tracking(self, reason: str) -> None:
        """A transform FB replaced the moving PCS: stop following it (§6.6)."""
        tracker = self.group.spaces.dynamic
        self.group.spaces.dynamic = None
        command = getattr(tracker, "command", None)
        if isinstance(command, Command):
            command.end(CommandStatus.ABORTED, self.group.runtime.now, message=reason)
        if self.follow is not None:  # hold where the frame carried the TCP last
            self.follow = None
            self.group.members.settle(self.group.members.last_setpoints()[0])

    # -- the cycle -----------------------------------------------------------------------------

    def advance(self, now: float) -> None:
        group = self.group
        if self.law is not None:
            s, v, a, _ = self.law.sample(now)
            self.path_velocity, self.path_acceleration = v, a
            piece, local = self.law.locate(s)
            self._sampled = (now, piece, local)
            entry = self.entries[piece]
            try:
                self._output(entry, local, v, a, now)
            except CommandRejected as rejected:  # the axes cannot follow: a group error
                group.fault(rejected.error_id, rejected.message)
                return
            self._update_statuses(piece, now)
            if self.law.done:
                self._at_rest(now)
            elif self.interrupted and self.law.standing and self.interrupt_command is not None:
                self.interrupt_command.end(CommandStatus.DONE, now)
                self.interrupt_command = None
        elif self.follow is not None:
            self._output_follow(now)
        if self.law is None and self.waiting is not None:
            request, self.waiting = self.waiting, None
            try:
                self._begin(request, self._start_point(request))
            except CommandRejected as rejected:
                request.command.end(CommandStatus.ERROR, now, rejected.error_id,
                                     rejected.message)
        del group

    def _at_rest(self, now: float) -> None:
        group = self.group
        if not self.interrupted:
            for request in self.commands:
                if request.command.busy:
                    request.command.end(CommandStatus.DONE, now)
            last = self.commands[-1] if self.commands else None
            dynamic = group.spaces.dynamic is not None
            if last is not None and last.space == PCS and dynamic and last.command.done \
                    and last.end is not None:
                self.follow = np.array(last.end)
            self.commands = []
            self.entries = {}
            self.law = None
            self.path_velocity = self.path_acceleration = 0.0
            if self.follow is None:
                group.members.settle(group.acs_set())
            if self.halt_command is not None:
                self.halt_command.end(CommandStatus.DONE, now)
                self.halt_command = None

    def _update_statuses(self, piece: int, now: float) -> None:
        for request in self.commands:  # the next one is Active in the cycle this is Done
            if request.command.finished:
                continue
            if request.last < piece:
                request.command.end(CommandStatus.DONE, now)
                continue
            if request.first <= piece and not self.interrupted:
                request.command.status = CommandStatus.ACTIVE
            break

    # -- building ------------------------------------------------------------------------------

    def _start_point(self, request: PathCommand) -> np.ndarray:
        """The TCP's set position in the request's space, now (Aborting, or from rest)."""
        group = self.group
        acs = group.acs_set()
        return self._convert_from_acs(acs, request.space)

    def _convert_from_acs(self, acs: np.ndarray, space: str) -> np.ndarray:
        if space == ACS:
            return acs
        spaces = self.group.spaces
        mcs = spaces.to_mcs(acs)
        if space == MCS:
            return mcs
        return spaces.pcs_of(mcs, self.group.runtime.now)

    def _tail(self, space: str) -> np.ndarray:
        """Where the queued path ends, in ``space``."""
        last = self.commands[-1]
        assert last.end is not None
        if last.space == space:
            return np.array(last.end)
        spaces, now = self.group.spaces, self.group.runtime.now
        if last.space == ACS:
            acs = last.end
        else:
            end = last.end if last.space == MCS else spaces.mcs_of(last.end, now)
            near = self._axes_at_end() if space == ACS and not spaces.linear else None
            acs = spaces.to_acs(end, near=near)
        return self._convert_from_acs(np.asarray(acs), space)

    def _axes_at_end(self) -> np.ndarray:
        """Where the axes will be at the end of the queued path, turns counted: an axis that
        may take whole turns (a SCARA's base) runs on past ±180° (``_write_mcs``), so an ACS
        move buffered after the path must start on the turn the path leaves it on, not on the
        principal angle. Every element is sampled, and from one sample to the next each such
        axis keeps the turn nearest to the one before, starting from the path's start."""
        spaces, now = self.group.spaces, self.group.runtime.now
        acs = self._acs_start if self._acs_start is not None else self.group.acs_set()
        for index in sorted(self.entries):
            entry = self.entries[index]
            element = entry.geometry
            if entry.space == ACS:
                acs = np.array(element.end, dtype=float)
                continue
            points = element.position(np.linspace(0.0, element.length, 9)[1:])
            mcs = np.array([spaces.with_xyz(self._orientation, p) for p in points])
            if entry.space == PCS:
                mcs = np.array([spaces.mcs_of(m, now) for m in mcs])
            principal = spaces.to_acs(mcs)
            # whole turns between neighbours, added up: the nearest turn at every sample
            turns = spaces.to_acs(mcs, near=np.vstack([acs, principal[:-1]])) - principal
            acs = principal[-1] + turns.sum(axis=0)
        return acs

    def _begin(self, request: PathCommand, start: np.ndarray,
               moving: tuple[float, float, float] | None = None) -> None:
        """Start a new path from rest (at ``start``) with ``request`` alone; ``moving``: from
        the last sample's (time, path velocity, path acceleration) instead (§5.14)."""
        group = self.group
        geometry = request.build(start, request.extra["reference"])
        last_acs_v = self._last_acs_v
        self.clear()
        couple = request.extra.get("couple")  # MC_SyncGroupToAxis: the law becomes a cam
        if not geometry and couple is not None:
            raise CommandRejected(ErrorId.GROUP_MOVING, "the path could not start: the TCP "
                                  "is at its end already")
        if not geometry:  # already there: Done without motion
            request.end = start
            request.command.end(CommandStatus.DONE, group.runtime.now)
            group.members.settle(group.acs_set())
            return
        self._orientation = start.copy() if request.space != ACS else None
        # the path starts from rest: the first difference quotient of the axis velocities
        # (_write_mcs) is taken from zero, not left out, else the published acceleration
        # reads 0 in the first cycle and jumps by up to 1.5 times the jerk limit in the next
        self._last_acs_v = np.zeros(len(group.members))
        if moving is not None and last_acs_v is not None:
            self._last_acs_v = last_acs_v
        self._acs_start = group.acs_set()
        now = group.runtime.now
        pieces = self._pieces(request, geometry, exit_last=0.0)  # may reject: nothing changed
        self.law = TimeLaw(now) if moving is None else TimeLaw(*moving)
        if group.factors != (1.0, 1.0, 1.0):
            self.law.set_factors(now, *group.factors)
        request.command.status = CommandStatus.ACTIVE
        request.end = self._end_of(request, geometry, start)
        self._push(request, geometry, pieces)
        if couple is not None:
            couple(start)

    def _append(self, request: PathCommand) -> None:
        """Buffered or blending: after the last queued command (§7.3.2, §7.3.3)."""
        start = self._tail(request.space)
        request.extra["reference"] = start
        geometry = request.build(start, start)
        if request.space != ACS and self._orientation is None:  # after a MoveDirect
            self._orientation = start.copy()
        request.end = start if not geometry else self._end_of(request, geometry, start)
        previous = self.commands[-1] if self.commands else None
        blend = None
        if previous is not None and geometry and request.buffer_mode in _TRANSITION_SPEED \
                and request.transition in _CONTOURS and previous.space == request.space \
                and request.space != ACS and previous.last >= 0:
            blend = self._blend(previous, request, geometry)
        if blend is not None:
            assert previous is not None and self.law is not None
            contour, trimmed, blended, speed = blend
            pieces = self._pieces(request, blended, exit_last=0.0)
            joint = self._piece(contour, request.space, request, math.inf, speed_cap=speed,
                                other=previous)
            if self.law.trim_last(trimmed.length, math.inf):
                self.entries[previous.last].geometry = trimmed
                self.law.append([joint])
                self.entries[self._next_piece] = _Entry(contour, request.space, request)
                request.first = self._next_piece
                self._next_piece += 1
                self._push(request, blended, pieces)
                return
            # too late for a contour: the TCP already brakes for the corner (as Buffered)
        self._push(request, geometry, self._pieces(request, geometry, exit_last=0.0))

    def _end_of(self, request: PathCommand, geometry: list[Any], start: np.ndarray
                ) -> np.ndarray:
        end = np.array(start, dtype=float)
        last = geometry[-1]
        if request.space == ACS:
            return np.array(last.end, dtype=float)
        return self.group.spaces.with_xyz(end, np.asarray(last.end))

    def _blend(self, previous: PathCommand, request: PathCommand, geometry: list[Any]
               ) -> tuple[Any, Any, list[Any], float] | None:
        law = self.law
        if law is None:
            return None
        last_entry = self.entries[previous.last]
        before, after = last_entry.geometry, geometry[0]
        if not isinstance(before, Line | Arc) or not isinstance(after, Line | Arc):
            return None
        v1, v2 = previous.dynamics[0], request.dynamics[0]
        speed = _TRANSITION_SPEED[request.buffer_mode](v1, v2)
        try:
            blend = self._contour(request, before, after, previous, speed)
        except CommandRejected:
            return None  # a reversal or a degenerate corner: stop there (as Buffered)
        if blend is None:
            return None
        if request.transition is TransitionMode.TM_START_VELOCITY:
            speed = request.parameter / 100.0 * v1
        elif request.transition is TransitionMode.TM_CONSTANT_VELOCITY:
            speed = request.parameter / 100.0 * speed
        return blend.contour, blend.before, [blend.after, *geometry[1:]], speed

    def _contour(self, request: PathCommand, before: Any, after: Any, previous: PathCommand,
                 speed: float) -> Blend | None:
        mode, p = request.transition, request.parameter
        if mode is TransitionMode.TM_CORNER_DISTANCE:
            return corner_distance_blend(before, after, p)
        if mode is TransitionMode.TM_MAX_CORNER_DEVIATION:
            return max_corner_deviation_blend(before, after, p)
        widest = corner_distance_blend(before, after, 1e12)
        if mode is TransitionMode.TM_START_VELOCITY:
            v1 = previous.dynamics[0]
            _, _, dec, jerk = previous.dynamics
            d = _speed_change_distance(v1, p / 100.0 * v1, dec, jerk)
            if d >= widest.corner_distance:
                return widest
            return corner_distance_blend(before, after, max(d, MIN_CORNER_DISTANCE))
        # TM_CONSTANT_VELOCITY: the largest contour, smaller only if its curvature allows
        target = p / 100.0 * speed
        acc = min(previous.dynamics[1], request.dynamics[1])
        needed = acc / (2.0 * target * target)  # v²κ within half the acceleration
        kappa = widest.contour.max_curvature
        if kappa <= needed:
            return widest
        return corner_distance_blend(before, after, widest.corner_distance * kappa / needed) \
            if kappa * widest.corner_distance > 0 else widest

    def _pieces(self, request: PathCommand, geometry: list[Any], exit_last: float
                ) -> list[Piece]:
        """The time-law pieces of ``geometry`` with their caps (limits.py); rejects what the
        axes cannot follow (TARGET_UNREACHABLE, KINEMATICS_SINGULAR) before anything moves."""
        exits = request.extra.get("exits", {})
        caps = caps_for_many(self.group, geometry, request.space, request.dynamics)
        space = _SPACE_ID[request.space]
        last = len(geometry) - 1
        return [Piece(element.length, *cap, exit_velocity=exit_last if index == last
                      else exits.get(index, math.inf), space=space)
                for index, (element, cap) in enumerate(zip(geometry, caps, strict=True))]

    def _push(self, request: PathCommand, geometry: list[Any], pieces: list[Piece]) -> None:
        assert self.law is not None
        self.commands.append(request)
        if not geometry:
            if request.first < 0:
                request.first = request.last = self._next_piece - 1
            return
        for index, element in enumerate(geometry):
            self.entries[self._next_piece + index] = _Entry(element, request.space, request)
        if request.first < 0:
            request.first = self._next_piece
        self._next_piece += len(geometry)
        request.last = self._next_piece - 1
        self.law.append(pieces, dense=dense_path(self.group, geometry, request.space))

    def _piece(self, element: Any, space: str, request: PathCommand, exit_cap: float,
               speed_cap: float | None = None, other: PathCommand | None = None) -> Piece:
        v, a, d, j = request.dynamics
        if other is not None:
            v = max(v, other.dynamics[0])
            a, d, j = (min(a, other.dynamics[1]), min(d, other.dynamics[2]),
                       min(j, other.dynamics[3]))
        if speed_cap is not None:
            v = speed_cap
        caps = caps_for(self.group, element, space, (v, a, d, j))
        return Piece(element.length, *caps, exit_velocity=exit_cap, space=_SPACE_ID[space])

    # -- output --------------------------------------------------------------------------------

    def _output(self, entry: _Entry, local: float, v: float, a: float, now: float) -> None:
        group = self.group
        spaces = group.spaces
        point, tangent, curvature = evaluate(entry.geometry, local)
        if entry.space == ACS:
            self._last_acs_v = tangent * v  # what the next MCS piece differences against
            group.members.write_setpoints(point, self._last_acs_v, tangent * a)
            return
        x_v, x_a = tangent * v, tangent * a + curvature * v * v
        assert self._orientation is not None
        template = self._orientation
        if entry.space == PCS and spaces.dynamic is not None:
            motion = spaces.dynamic(now)
            mcs_point = motion.frame.apply(point)
            x_v = motion.point_velocity(point, x_v)
            x_a = motion.frame.rotate(x_a)
            self._write_mcs(spaces.with_xyz(template, mcs_point), x_v, x_a, exact_a=False)
            return
        self._write_mcs(spaces.with_xyz(template, point), x_v, x_a, exact_a=spaces.linear)

    def _write_mcs(self, mcs: np.ndarray, x_v: np.ndarray, x_a: np.ndarray,
                   exact_a: bool) -> None:
        group, spaces = self.group, self.group.spaces
        # the turn nearest to the last setpoints: a SCARA's base runs on past ±180° (the
        # principal angle would make it jump a whole turn within one cycle)
        acs = spaces.to_acs(mcs, near=group.members.last_setpoints()[0])
        zero = np.zeros(spaces.size)
        acs_v = spaces.acs_rates(acs, spaces.with_xyz(zero, x_v))
        if exact_a:
            acs_a = spaces.acs_rates(acs, spaces.with_xyz(zero, x_a))
        else:  # the Jacobian changes along the path: the setpoint's own difference quotient
            previous = self._last_acs_v
            dt = group.runtime.cycle_time
            acs_a = np.zeros_like(acs_v) if previous is None else (acs_v - previous) / dt
        self._last_acs_v = acs_v
        group.members.write_setpoints(acs, acs_v, acs_a)

    def _output_follow(self, now: float) -> None:
        spaces = self.group.spaces
        assert self.follow is not None
        if spaces.dynamic is None:
            self.follow = None
            self.group.members.settle(self.group.acs_set())
            return
        motion = spaces.dynamic(now)
        point = spaces.xyz(self.follow)
        mcs = spaces.with_xyz(self.follow, motion.frame.apply(point))
        x_v = motion.point_velocity(point)
        self._write_mcs(mcs, x_v, np.zeros(3), exact_a=False)

    # -- ending --------------------------------------------------------------------------------

    def _abort_queue(self, reason: str) -> None:
        now = self.group.runtime.now
        for request in self.commands:
            request.command.end(CommandStatus.ABORTED, now, message=reason)
        if self.waiting is not None:
            self.waiting.command.end(CommandStatus.ABORTED, now, message=reason)
            self.waiting = None
        if self.halt_command is not None:
            self.halt_command.end(CommandStatus.ABORTED, now, message=reason)
            self.halt_command = None
        if self.interrupt_command is not None:
            self.interrupt_command.end(CommandStatus.ABORTED, now, message=reason)
            self.interrupt_command = None
        self.interrupted = False

    def clear(self) -> None:
        """Forget the path and its commands (they have ended): the group holds still."""
        self.law = None
        self.entries = {}
        self.commands = []
        self.waiting = None
        self.halt_command = None
        self.interrupt_command = None
        self.interrupted = False
        self.follow = None
        self.path_velocity = self.path_acceleration = 0.0
        self._next_piece = 0
        self._last_acs_v = None
        self._acs_start = None
        self._sampled = None


def _lead_out(point: np.ndarray, tangent: np.ndarray, curvature: np.ndarray,
              length: float) -> Line | Arc:
    """The path a TCP at ``point`` would run on for ``length`` [mm] keeping its tangent and
    curvature vector: a line, or an arc of at most a quarter turn on its osculating circle."""
    kappa = float(np.linalg.norm(curvature))
    if kappa * length <= TAKE_OVER_TOLERANCE:
        return Line(point, point + length * tangent)
    radius = 1.0 / kappa
    inward = curvature / kappa
    center = point + radius * inward
    sweep = min(length / radius, 0.5 * math.pi)
    end = center + radius * (-math.cos(sweep) * inward + math.sin(sweep) * tangent)
    return Arc(point, end, center, np.cross(tangent, inward))


def _speed_change_distance(v1: float, v2: float, acceleration: float, jerk: float) -> float:
    """Path length a jerk-limited change from ``v1`` to ``v2`` takes (zero acceleration at
    both ends): the mean speed times the duration."""
    dv = abs(v2 - v1)
    if dv >= acceleration * acceleration / jerk:
        duration = dv / acceleration + acceleration / jerk
    else:
        duration = 2.0 * math.sqrt(dv / jerk)
    return 0.5 * (v1 + v2) * duration
