"""The MC side of planar motion: one ``PlanarSystem`` per runtime runs every planar object.

The PLC-side objects (MC_PlanarMover, MC_PlanarGroup, MC_PlanarEnvironment) record method
calls as commands. In the motion phase of the cycle (Runtime phase 2) the system takes the
commands of all objects in call order, so that two movers commanded in one cycle are decided
first come, first served (§6.3.2). Then it evaluates the profiles of all movers at once (one
``SegmentTable`` row per mover coordinate), lets the movers end their motions and release area,
advances the state machines and publishes every status. A program therefore reads the result
of a call in the next cycle, as the manual's examples do (§6.7.1), and the runtime is what
calls ``update()`` of every object: a user who calls it as well sees nothing new.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.planar.feedback import CommandQueue, MC_PlanarFeedbackBase, PlanarCommand
from openmotion.planar.states import PlanarStateMachine, StateCommand
from openmotion.trajectory.evaluate import SegmentTable
from openmotion.trajectory.segments import KinematicState

if TYPE_CHECKING:
    from openmotion.planar.environment import MC_PlanarEnvironment
    from openmotion.planar.mover import MC_PlanarMover
    from openmotion.runtime.runtime import Runtime

_MOVER_OIDS = 0x05110000  #: movers count up from 16#05110010 (§6.1.8 watch window)
_OBJECT_OIDS = 0x05120000  #: tracks, groups and environments share 16#0512xxxx (§6.2, §6.7.2)
_OID_STEP = 0x10
_FLAG_CAPACITY = 64  #: first size of the per-object flag arrays (doubled as objects come)
#: below this many movers the cycle visits every mover and object in a plain loop; from it
#: on, numpy finds the few that have work (the same calls in the same order, D-286)
_SCAN_BELOW = 64


@dataclass(frozen=True)
class ObjectPort:
    """What the ``PlanarSystem`` calls on a planar object (D-239). The object makes it from its
    own operations; it is no PLC method (programs call the manual's methods only)."""

    run: Callable[[PlanarCommand], None]  #: execute one command; a rejection ends it
    publish: Callable[[], bool]  #: show the new status; returns whether to stay awake


class PlanarObject:
    """What every planar object has: an OID, a command queue and the cyclic hooks.

    Its contract with the ``PlanarSystem``: the system queues calls on ``commands``, hands
    each to ``port.run`` in call order and calls ``port.publish`` while the object is
    ``awake``. An object is *awake* while it has something to publish (a command ran, a
    motion ended, a state transition runs); the system publishes only awake objects, so that
    a hundred standing movers cost next to nothing per cycle.
    """

    _rank = -1  #: its place in the system's creation order, once registered

    def __init__(self, system: PlanarSystem, oid: int) -> None:
        self.system = system  #: the PlanarSystem that runs it
        self.oid = oid
        self.commands = CommandQueue(system.clock)
        self.awake = True
        #: what the system (and, for some kinds, the other planar objects) call on it
        self.port = ObjectPort(self._run, self._publish)

    def _send(self, kind: str, feedback: MC_PlanarFeedbackBase | None,
              *args: Any) -> PlanarCommand:
        """Record a method call; the system executes it in this cycle's motion phase."""
        return self.system.send(self, kind, feedback, *args)

    def _run(self, command: PlanarCommand) -> None:
        """Execute one command; a rejection ends it with its error id, never raises."""
        self.awake = True
        try:
            self._execute(command)
        except CommandRejected as rejected:
            command.reject(rejected.error_id, rejected.message,
                           getattr(rejected, "object_info", None))

    def _execute(self, command: PlanarCommand) -> None:
        raise NotImplementedError

    def _publish(self) -> bool:
        """Show the new status (read in the next cycle); returns whether to stay awake."""
        self.commands.publish()
        return False

    @property
    def awake(self) -> bool:
        """Whether the system publishes it after this motion phase (``_publish``)."""
        return self._awake

    @awake.setter
    def awake(self, value: bool) -> None:
        self._awake = value
        if self._rank >= 0:  # the system finds the awake ones without visiting every object
            self.system.awake_flags[self._rank] = value

    def update(self) -> None:
        """The manual's Update(): the runtime exchanges the data of every planar object each
        cycle, so calling it changes nothing; PLC-style programs may keep the call."""



class StatefulObject(PlanarObject):
    """A planar object with the planar state machine (§4.1): Enable, Disable, Reset, and the
    FB outputs Error and ErrorId (with openmotion's readable ``message``)."""

    states: PlanarStateMachine  #: its planar state machine (§4.1)

    @property
    def error(self) -> bool:
        return self.states.error

    @property
    def error_id(self) -> ErrorId:
        return self.states.error_id

    @property
    def message(self) -> str:
        return self.states.message

    def enable(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(StateCommand.ENABLE, feedback)

    def disable(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(StateCommand.DISABLE, feedback)

    def reset(self, feedback: MC_PlanarFeedbackBase | None = None) -> PlanarCommand:
        return self._send(StateCommand.RESET, feedback)

class PlanarSystem:
    """All planar objects of one runtime, their setpoint table and the cycle that runs them."""

    def __init__(self, runtime: Runtime) -> None:
        self.runtime = runtime
        self.cycle_time = runtime.cycle_time
        self.table = SegmentTable(capacity=48)
        self._values = [np.zeros(48) for _ in range(4)]  # p, v, a, j of every row
        self._objects: list[PlanarObject] = []  #: in creation order
        self.movers: list[MC_PlanarMover] = []
        self.environments: list[MC_PlanarEnvironment] = []
        self._sent: list[tuple[PlanarObject, PlanarCommand]] = []
        self._counts = {"mover": 0, "object": 0}
        self.published = 0  #: counts motion phases: cached statuses older than this are stale
        #: per object (creation order): ``awake``; per mover: ``next_event`` (D-286)
        self.awake_flags = np.zeros(_FLAG_CAPACITY, dtype=bool)
        self.next_events = np.full(_FLAG_CAPACITY, np.inf)
        self.network: Any = None  #: the TrackNetwork, made with the first track (track.py)
        self.traffic: Any = None  #: the movers on tracks (traffic.py)
        runtime.add_system(self)

    name = "planar"

    def objects(self) -> tuple[PlanarObject, ...]:
        """Environments, groups, movers, tracks and parts in creation order."""
        return tuple(self._objects)

    @classmethod
    def of(cls, runtime: Runtime) -> PlanarSystem:
        """The planar system of ``runtime``, made on first use."""
        for system in runtime.systems:
            if isinstance(system, cls):
                return system
        return cls(runtime)

    @property
    def now(self) -> float:
        return self.runtime.now

    def clock(self) -> float:
        """The runtime's time: the commands' ``issued_at`` and ``ended_at`` (feedback.py)."""
        return self.runtime.now

    @property
    def previous(self) -> float:
        """Time of the last published setpoints: new plans start there (docs D-001)."""
        return self.runtime.now - self.cycle_time if self.runtime.cycle else 0.0

    def register(self, obj: PlanarObject) -> int:
        """``obj`` joins the objects; returns its place in creation order (its index in
        ``awake_flags``)."""
        rank = len(self._objects)
        self._objects.append(obj)
        if rank >= self.awake_flags.size:
            self.awake_flags = np.concatenate([self.awake_flags,
                                               np.zeros_like(self.awake_flags)])
        self.awake_flags[rank] = obj.awake
        return rank

    def add_mover(self, mover: MC_PlanarMover) -> int:
        """``mover`` joins the movers; returns its index in ``next_events``."""
        index = len(self.movers)
        self.movers.append(mover)
        if index >= self.next_events.size:
            self.next_events = np.concatenate([self.next_events,
                                               np.full(self.next_events.size, np.inf)])
        return index

    def next_oid(self, kind: str) -> int:
        """OIDs as TwinCAT hands them out: 16#05110010, 16#05110020, ... for movers."""
        self._counts[kind] += 1
        base = _MOVER_OIDS if kind == "mover" else _OBJECT_OIDS
        return base + _OID_STEP * self._counts[kind]

    def add_rows(self, positions: list[float]) -> list[int]:
        """One table row per coordinate, standing at ``positions``."""
        rows = [self.table.add(KinematicState(p), self.previous) for p in positions]
        if self.table.capacity > self._values[0].size:
            grown = [np.zeros(self.table.capacity) for _ in range(4)]
            for new, old in zip(grown, self._values, strict=True):
                new[:old.size] = old
            self._values = grown
        for row, position in zip(rows, positions, strict=True):
            self._values[0][row] = position
        return rows

    def value(self, row: int) -> tuple[float, float, float]:
        """Position, velocity and acceleration of ``row`` at the last evaluation."""
        p, v, a, _ = self._values
        return float(p[row]), float(v[row]), float(a[row])

    def values(self, which: int, first: int, count: int) -> np.ndarray:
        """Position (0), velocity (1) or acceleration (2) of ``count`` consecutive rows from
        ``first`` at the last evaluation (a view: read it before the next cycle)."""
        return self._values[which][first:first + count]

    def set_value(self, row: int, position: float) -> None:
        """Show ``row`` standing at ``position`` before the next evaluation (a relocation)."""
        p, v, a, _ = self._values
        p[row], v[row], a[row] = position, 0.0, 0.0

    def send(self, obj: PlanarObject, kind: str, feedback: MC_PlanarFeedbackBase | None,
             *args: Any) -> PlanarCommand:
        command = obj.commands.send(kind, feedback, *args)
        self._sent.append((obj, command))
        return command

    def environment(self) -> MC_PlanarEnvironment | None:
        """The environment that describes the stators and parts (the first one made)."""
        return self.environments[0] if self.environments else None

    def advance(self, now: float) -> None:
        """The motion phase: run the commands sent, evaluate, move on tracks, publish."""
        sent, self._sent = self._sent, []
        for obj, _ in sent:
            obj.commands.take()
        for obj, command in sent:  # call order across all objects (§6.3.2)
            obj.port.run(command)
        if self.table.size:
            self.table.evaluate(now, *self._values)
        if self.traffic is not None:
            self.traffic.advance(now, self._values)
        if len(self.movers) < _SCAN_BELOW:
            for mover in self.movers:
                if mover.next_event <= now:
                    mover.port.after_motion(now)
            for obj in self._objects:
                if obj.awake:
                    obj.awake = obj.port.publish()
        else:
            self._after_motions(now)
            self._publish_awake()
        self.published += 1

    def _after_motions(self, now: float) -> None:
        """``for mover in movers: if mover.next_event <= now: after_motion(now)`` with the
        search for the next mover due in numpy (D-286): the same movers in the same order,
        a mover made due by an earlier one's call included."""
        movers, count, k = self.movers, len(self.movers), 0
        while k < count:
            due = self.next_events[k:count] <= now
            i = int(due.argmax())
            if not due[i]:
                return
            k += i
            movers[k].port.after_motion(now)
            k += 1

    def _publish_awake(self) -> None:
        """``for obj in objects: if obj.awake: obj.awake = obj.port.publish()`` with the
        search for the next awake object in numpy (D-286), in the same order."""
        objects, count, k = self._objects, len(self._objects), 0
        while k < count:
            flags = self.awake_flags[k:count]
            i = int(flags.argmax())
            if not flags[i]:
                return
            k += i
            obj = objects[k]
            obj.awake = obj.port.publish()
            k += 1
