"""Stations and routes: movers visit stations in order, stay their process time, go on.

A machine builder sizing a transport asks how many movers, at what speed, give the parts
per minute needed, and where the line saturates. A ``StationLine`` answers it on the real
motion: it is a system (kernel/system.py) added after the movers' own system, and in every
cycle it looks at what this cycle's motion did and sends the next moves, which shape the
setpoints from the next cycle on, as a PLC program that reads Done and sets the next Execute.

It never moves a mover itself. Every move goes through the mover's own system by a
``MoverPort`` (a CA group's MC_MoveAbsoluteCA, a planar mover's MC_MoveOnTrack), so
collision avoidance does the queueing: a mover sent to a busy station stops behind the one
in it at the gap, and its move ends Done only once it stands in its slot. Nothing here can
make two movers overtake or touch; the line only decides where each goes next (D-257).

A station has ``capacity`` slots, the first at ``position``, the others ``pitch`` behind it
against the direction of travel. Slots fill from the front, first come first served: a mover
gets the frontmost slot it can reach (every slot from there back to the station's entry free
and promised to nobody), else the last slot, where it queues. When a slot frees, the movers
still on their way move up: each is sent on to the frontmost slot it can now reach. The
metrics are those a line builder reads: parts per minute, utilisation (the share of slot
time spent processing), waiting (time standing while on the way to a station, i.e. queued,
not counting the cycles in which a move just sent is starting) and the queue length over
time.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any, Protocol

from openmotion.core.errors import ConfigError
from openmotion.kernel.model import Kind, SignalSpec

__all__ = ["FlowState", "MoverPort", "MoverRow", "Route", "Station", "StationLine",
           "StationRow", "StationState"]

#: a process time ends in the cycle whose time reaches it within this [s] (float residue of
#: adding cycle times)
TIME_TOLERANCE = 1e-9
#: cycles after a move is sent in which a standing mover is starting, not queued: the system
#: takes the command in the next cycle and its first setpoint may still be the start
START_CYCLES = 2


@dataclass(frozen=True)
class Station:
    """One station: where a mover stops, how long it stays, how many at once."""

    name: str
    position: float  #: where the first slot stops a mover [mm along its rail or track]
    process_time: float  #: time a mover stays in a slot [s]
    capacity: int = 1  #: movers processed at once, one per slot
    pitch: float = 0.0  #: distance between two slots [mm]; needed with capacity > 1
    path: str = ""  #: the planar track the station stands on; "" on a CA rail

    def __post_init__(self) -> None:
        if not self.name:
            raise ConfigError("a station needs a name")
        if not math.isfinite(self.position):
            raise ConfigError(f"station {self.name!r}: position must be finite")
        if not (math.isfinite(self.process_time) and self.process_time >= 0.0):
            raise ConfigError(f"station {self.name!r}: process_time must be >= 0 s, not "
                              f"{self.process_time}")
        if isinstance(self.capacity, bool) or not isinstance(self.capacity, int) \
                or self.capacity < 1:
            raise ConfigError(f"station {self.name!r}: capacity must be a whole number >= 1, "
                              f"not {self.capacity!r}")
        if self.capacity > 1 and not (math.isfinite(self.pitch) and self.pitch > 0.0):
            raise ConfigError(f"station {self.name!r}: {self.capacity} slots need a pitch > 0 "
                              "(the distance between two slots)")

    def slot_position(self, slot: int) -> float:
        """Where slot ``slot`` stops a mover: slot 0 at ``position``, the others behind it."""
        return self.position - slot * self.pitch


@dataclass(frozen=True)
class Route:
    """The stations a mover visits, in order; after the last, the first again."""

    stations: tuple[str, ...]
    laps: int | None = None  #: rounds through the route, then the mover stays; None: forever

    def __post_init__(self) -> None:
        if not self.stations:
            raise ConfigError("a route names at least one station")
        if self.laps is not None and (isinstance(self.laps, bool) or
                                      not isinstance(self.laps, int) or self.laps < 1):
            raise ConfigError(f"route laps must be a whole number >= 1 or none, not "
                              f"{self.laps!r}")


class MoverPort(Protocol):
    """What a station line needs of one mover; each system offers its own."""

    name: str

    def go(self, station: Station, position: float) -> Any:
        """Send the mover forward to ``position`` at ``station``: a command handle
        (``busy``, ``done``, ``error``, ``message``)."""

    def queued(self) -> bool:
        """The mover stands short of where it was last sent: held up by the one ahead."""

    def ready(self) -> bool:
        """The mover may take the line's first move now (a planar mover: once on a track);
        a port without ``ready`` is ready at once."""


class FlowState(IntEnum):
    """Where a mover is in its route."""

    HEADING = 1  #: on the way to a station (moving or queued)
    PROCESSING = 2  #: in a slot, for the process time
    FINISHED = 3  #: its laps are done: it stays in the slot of its last station
    FAILED = 4  #: a move ended in an error; the line leaves it alone


class StationState:
    """A station while the line runs: its slots, queue and counters (a machine object)."""

    def __init__(self, station: Station, number: int) -> None:
        self.station = station
        self.number = number  #: 1, 2, ... in the order the line lists its stations
        self.slots: list[str | None] = [None] * station.capacity  #: who is processed where
        self.assigned: list[list[str]] = [[] for _ in range(station.capacity)]
        self.queue_length = 0  #: movers on the way here that stand (queued), this cycle
        self.processed = 0  #: visits ended
        self.busy_time = 0.0  #: slot-seconds spent processing [s]
        self.wait_time = 0.0  #: mover-seconds spent queued on the way here [s]
        self.arrivals = 0
        self.queue_area = 0.0  #: the integral of the queue length over time [s]
        self.max_queue = 0
        self.elapsed = 0.0  #: time the line has run [s]

    @property
    def name(self) -> str:
        return self.station.name

    @property
    def occupied(self) -> int:
        """Slots processing a mover now."""
        return sum(slot is not None for slot in self.slots)

    @property
    def utilisation(self) -> float:
        """The share of slot time spent processing since the line started (0 at the start)."""
        total = self.elapsed * self.station.capacity
        return self.busy_time / total if total > 0.0 else 0.0

    @property
    def parts_per_minute(self) -> float:
        return 60.0 * self.processed / self.elapsed if self.elapsed > 0.0 else 0.0

    def assign(self, mover: str) -> int:
        """The slot ``mover`` goes to: the frontmost one with every slot behind it free and
        promised to nobody; the last one (to queue) when there is none."""
        last = self.station.capacity - 1
        chosen = last if self.slots[last] is not None or self.assigned[last] \
            else self._ahead(last)
        self.assigned[chosen].append(mover)
        return chosen

    def reachable(self, slot: int, mover: str) -> int:
        """The frontmost slot ``mover``, promised ``slot``, can reach now: none while a mover
        stands in ``slot`` or was promised it first; else every slot from there back to
        ``slot`` must be free and promised to nobody."""
        if self.slots[slot] is not None or self.assigned[slot][0] != mover:
            return slot
        return self._ahead(slot)

    def _ahead(self, slot: int) -> int:
        chosen = slot
        for ahead in range(slot - 1, -1, -1):
            if self.slots[ahead] is not None or self.assigned[ahead]:
                break
            chosen = ahead
        return chosen

    def move_up(self, mover: str, slot: int, ahead: int) -> None:
        self.assigned[slot].remove(mover)
        self.assigned[ahead].append(mover)

    def arrive(self, mover: str, slot: int) -> None:
        self.assigned[slot].remove(mover)
        self.slots[slot] = mover
        self.arrivals += 1

    def leave(self, slot: int, stays: bool = False) -> None:
        """A visit in ``slot`` ended; the mover goes on, or ``stays`` there (its route is
        done), holding the slot for good."""
        if not stays:
            self.slots[slot] = None
        self.processed += 1


def _count(name: str, doc: str, read: Any) -> SignalSpec:
    return SignalSpec(name, "", int, lambda state: float(read(state)), doc)


StationState.MACHINE = Kind(  # type: ignore[attr-defined]
    "station",
    signals=(
        _count("queue_length", "movers on their way here that stand, queued",
               lambda s: s.queue_length),
        _count("occupied", "slots processing a mover", lambda s: s.occupied),
        _count("processed", "visits ended since the line started", lambda s: s.processed),
        SignalSpec("utilisation", "", float, lambda s: float(s.utilisation),
                   "share of slot time spent processing since the line started"),
    ),
    identify=lambda state: state.number,
)


@dataclass
class _Flow:
    """One mover on its route."""

    port: MoverPort
    route: Route
    stop: int = 0  #: index into the route of the station it heads to or is at
    state: FlowState = FlowState.HEADING
    slot: int = 0
    handle: Any = None
    until: float = 0.0  #: [s] end of its process time
    laps: int = 0
    visits: int = 0
    wait_time: float = 0.0
    message: str = ""
    sent: int = 0  #: when it was sent to its station: the order of the queue
    starting: int = 0  #: cycles left in which standing counts as starting (START_CYCLES)


def _ready(port: MoverPort) -> bool:
    ready = getattr(port, "ready", None)
    return True if ready is None else bool(ready())


@dataclass(frozen=True)
class StationRow:
    """One station after a run."""

    name: str
    processed: int
    parts_per_minute: float
    utilisation: float  #: share of slot time spent processing
    mean_wait: float  #: [s] queued time per arrival
    mean_queue: float  #: time-average of the queue length
    max_queue: int


@dataclass(frozen=True)
class MoverRow:
    """One mover on a route after a run."""

    mover: str
    state: str  #: a ``FlowState`` name
    laps: int
    visits: int
    wait_time: float  #: [s] time queued in all
    message: str = ""


@dataclass
class StationLine:
    """Stations and the movers that visit them; a system of the runtime (``advance``)."""

    stations: Sequence[Station]
    movers: Sequence[tuple[MoverPort, Route]]
    cycle_time: float
    name: str = "stations"
    _states: dict[str, StationState] = field(init=False, repr=False)
    _flows: list[_Flow] = field(init=False, repr=False)
    _sends: int = field(default=0, init=False, repr=False)

    def __post_init__(self) -> None:
        names = [station.name for station in self.stations]
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise ConfigError(f"station {repeated[0]!r} is defined twice")
        self._states = {station.name: StationState(station, number)
                        for number, station in enumerate(self.stations, 1)}
        movers = [port.name for port, _ in self.movers]
        repeated = sorted({name for name in movers if movers.count(name) > 1})
        if repeated:
            raise ConfigError(f"mover {repeated[0]!r} is on two routes")
        for port, route in self.movers:
            for name in route.stations:
                if name not in self._states:
                    raise ConfigError(f"route of {port.name!r}: no station {name!r}; one of "
                                      f"{', '.join(self._states) or 'none'}")
        self._flows = [_Flow(port, route) for port, route in self.movers]

    # -- the System contract ---------------------------------------------------------------

    def objects(self) -> tuple[StationState, ...]:
        return tuple(self._states.values())

    def start(self) -> None:
        """Send every mover that is ready to the first station of its route (in the order
        given); the others go once they are ready."""
        for flow in self._flows:
            if flow.handle is None and _ready(flow.port):
                self._send(flow)

    def advance(self, now: float) -> None:
        """Take arrivals, end process times, send movers on, count the queues."""
        dt = self.cycle_time
        for state in self._states.values():
            state.queue_length = 0
        for flow in self._flows:
            if flow.handle is None:
                if _ready(flow.port):
                    self._send(flow)
            elif flow.state is FlowState.HEADING:
                self._heading(flow, now, dt)
            elif flow.state is FlowState.PROCESSING:
                station = self._station_of(flow)
                station.busy_time += dt
                if now >= flow.until - TIME_TOLERANCE:
                    self._leave(flow)
        for state in self._states.values():
            state.elapsed += dt
            state.queue_area += state.queue_length * dt
            state.max_queue = max(state.max_queue, state.queue_length)

    # -- results ---------------------------------------------------------------------------

    def layout(self) -> list[dict[str, Any]]:
        """The stations as plain data for figures and the viewer: name, slot positions."""
        return [{"name": s.name, "slots": [s.slot_position(k) for k in range(s.capacity)]}
                for s in self.stations]

    def station(self, name: str) -> StationState:
        found = self._states.get(name)
        if found is None:
            raise ConfigError(f"no station {name!r}; one of {', '.join(self._states)}")
        return found

    def station_rows(self) -> list[StationRow]:
        return [StationRow(s.name, s.processed, s.parts_per_minute, s.utilisation,
                           s.wait_time / s.arrivals if s.arrivals else 0.0,
                           s.queue_area / s.elapsed if s.elapsed > 0.0 else 0.0, s.max_queue)
                for s in self._states.values()]

    def mover_rows(self) -> list[MoverRow]:
        return [MoverRow(f.port.name, f.state.name, f.laps, f.visits, f.wait_time, f.message)
                for f in self._flows]

    @property
    def busy(self) -> bool:
        """A mover is still on its route (heading to a station or in one)."""
        return any(flow.state <= FlowState.PROCESSING for flow in self._flows)

    def state_of(self, mover: str) -> FlowState:
        for flow in self._flows:
            if flow.port.name == mover:
                return flow.state
        raise ConfigError(f"mover {mover!r} is on no route")

    # -- one mover -------------------------------------------------------------------------

    def _station_of(self, flow: _Flow) -> StationState:
        return self._states[flow.route.stations[flow.stop]]

    def _send(self, flow: _Flow) -> None:
        station = self._station_of(flow)
        flow.slot = station.assign(flow.port.name)
        flow.state = FlowState.HEADING
        self._sends += 1
        flow.sent = self._sends
        flow.starting = START_CYCLES
        flow.handle = flow.port.go(station.station, station.station.slot_position(flow.slot))

    def _move_up(self, station: StationState) -> None:
        """A slot of ``station`` freed: the movers on their way move up, in queue order."""
        coming = sorted((flow for flow in self._flows if flow.state is FlowState.HEADING
                         and self._station_of(flow) is station), key=lambda flow: flow.sent)
        for flow in coming:
            ahead = station.reachable(flow.slot, flow.port.name)
            if ahead < flow.slot:
                station.move_up(flow.port.name, flow.slot, ahead)
                flow.slot = ahead
                flow.starting = START_CYCLES
                flow.handle = flow.port.go(station.station, station.station.slot_position(ahead))

    def _heading(self, flow: _Flow, now: float, dt: float) -> None:
        handle, station = flow.handle, self._station_of(flow)
        if handle.error:
            flow.state, flow.message = FlowState.FAILED, str(handle.message)
            station.assigned[flow.slot].remove(flow.port.name)
        elif handle.done:
            station.arrive(flow.port.name, flow.slot)
            flow.state = FlowState.PROCESSING
            flow.until = now + station.station.process_time
            flow.visits += 1
            if now >= flow.until - TIME_TOLERANCE:
                self._leave(flow)  # no process time: on at once
        elif flow.starting:
            flow.starting -= 1
        elif flow.port.queued():
            flow.wait_time += dt
            station.wait_time += dt
            station.queue_length += 1

    def _leave(self, flow: _Flow) -> None:
        station = self._station_of(flow)
        last = flow.stop + 1 == len(flow.route.stations)
        finished = last and flow.route.laps is not None and flow.laps + 1 >= flow.route.laps
        station.leave(flow.slot, stays=finished)
        if station.station.capacity > 1 and not finished:
            self._move_up(station)
        if last:
            flow.laps += 1
        if finished:
            flow.state = FlowState.FINISHED  # it stays in its slot, which stays taken
            return
        flow.stop = 0 if last else flow.stop + 1
        self._send(flow)
