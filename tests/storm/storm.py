"""Command storms: random PLCopen FB sequences on several axes, invariants checked every cycle.

Issue 19 asks for a storm in the suite: seeded, random FB operations through the public API
only (openmotion.plcopen), invalid inputs included (NaN, infinities, negative or zero
dynamics, MC_INVALID where a value is needed, unknown enum values), with superposition,
override, feed enables, gearing and every buffer mode. After every cycle of every axis:

* limits: |v| <= max_velocity, |a| <= max(max_acceleration, max_deceleration),
  |j| <= max_jerk, each times (1 + ``REL``) (D-020: the maximum velocity is a hard limit;
  TcMC §6.1 parameters 1003/PLCopen 12-16);
* continuity: from one cycle to the next |Δv| <= a_max·dt, |Δa| <= j_max·dt and
  |Δp - (v₀+v₁)·dt/2| <= j_max·dt³/12, plus ruckig's precision (``openmotion.testing``);
* state/motion agreement: StandStill and Disabled only with zero set velocity and acceleration
  (PLCopen Part 1 state diagram, TcMC digest §1.2);
* handshake (TcMC §7.1, digest §1.3, D-013): at most one of Done/CommandAborted/Error, never
  with Busy, Active only while Busy, ErrorID only with Error; Busy falls only with a result
  (or on a new edge); a result shown while Execute stays TRUE stays, one shown with Execute
  FALSE lasts one call;
* no hanging command: no block stays Busy once its axis has been at rest, with nothing
  pending (override > 0, both feed enables, no jog key, not coupled), for ``HANG_CYCLES``.

The documented exceptions are the table ``EXCEPTIONS`` (one place, each with its reason and
citation). A violation carries a reproduction: the seed and operation index that replay the
storm, and the FB calls on the axis since it last stood still, replayed on a fresh runtime
(``replay``) to confirm that they alone reproduce it.

Run it by hand: ``python tests/storm/storm.py --seed 1 --operations 20000``.
"""

from __future__ import annotations

import argparse
import enum
import math
import random
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import openmotion as om
from openmotion import MC_DEFAULT, MC_INVALID, AxisState, BufferMode, Direction, DriveModel
from openmotion.plcopen import (
    FunctionBlock,
    JogMode,
    MC_AbortSuperposition,
    MC_GearIn,
    MC_GearInFloat,
    MC_GearOut,
    MC_Halt,
    MC_Jog,
    MC_MoveAbsolute,
    MC_MoveRelative,
    MC_MoveSuperImposed,
    MC_MoveVelocity,
    MC_Power,
    MC_Reset,
    MC_SetOverride,
    MC_Stop,
)
from openmotion.testing import REL, RUCKIG_PRECISION

CYCLE_TIME = 0.001  #: [s]
TINY = 1e-12  #: rounding, relative to the signal's scale (as openmotion.testing.assert_continuous)
HANG_CYCLES = 1000  #: a block Busy this long on an idle axis with nothing pending hangs
SETTLE_EVERY = 250  #: operations between two settle phases (everything released, brought to rest)
SETTLE_CYCLES = 4000  #: the longest a settle phase waits for every axis to come to rest
MAX_SHOWN = 40  #: calls listed for a violation that does not reproduce alone
SHRINK_REPLAYS = 150  #: the most replays one shrink may use
SUPERPOSITION_MEMORY = 2  #: cycles an ended overlay stays in a violation's context
REPLAY_MARGIN = 5  #: cycles a replay may run past the violation's cycle
DEFAULT_OPERATIONS = 4000  #: the suite's size (about 20 s here); OPENMOTION_STORM_OPS scales it

#: name -> (AxisParameters overrides, drive). x: the defaults; y: slow and soft; z: issue 19's
#: point-1 axis (default jerk 10 000, max jerk 1e6); u: a lagging drive with a tight lag limit
#: (following-error faults, MC_Reset taking the actual position).
AXES: dict[str, tuple[dict[str, float], DriveModel]] = {
    "x": ({}, DriveModel()),
    "y": ({"max_velocity": 500.0, "acceleration": 2000.0, "deceleration": 3000.0,
           "jerk": 20000.0, "max_acceleration": 8000.0, "max_deceleration": 8000.0,
           "max_jerk": 2.0e5}, DriveModel()),
    "z": ({"acceleration": 10000.0, "deceleration": 10000.0, "jerk": 10000.0},
          DriveModel()),
    "u": ({"max_velocity": 800.0, "max_position_lag": 2.0},
          DriveModel("lag", time_constant=0.002, dead_time=0.001)),
}

NAN, INF = math.nan, math.inf
RESULTS = ("done", "command_aborted", "error")
AT_REST_STATES = (AxisState.STANDSTILL, AxisState.DISABLED)


# -- the documented exceptions ----------------------------------------------------------------

@dataclass(frozen=True)
class Cycle:
    """What happened to one axis in one cycle, for the exceptions to look at."""

    axis: str
    powered_before: bool
    powered: bool
    state_before: AxisState
    state: AxisState


@dataclass(frozen=True)
class Waiver:
    """An invariant that does not hold in a cycle, by a documented rule."""

    name: str
    waives: frozenset[str]  #: invariant names (Violation.invariant)
    applies: Callable[[Cycle], bool]
    reason: str
    citation: str


_JUMPS = frozenset({"jump.position", "jump.velocity", "jump.acceleration"})

#: The one list of exceptions to the invariants. Nothing else is waived.
EXCEPTIONS: tuple[Waiver, ...] = (
    Waiver("power off", _JUMPS,
           lambda c: c.powered_before and not c.powered,
           "disabling aborts every command and freezes the setpoint at the actual position: "
           "the drive no longer follows a profile, so the setpoint stops at once",
           "D-019; PLCopen Part 1 Disabled"),
    Waiver("power on", frozenset({"jump.position"}),
           lambda c: c.powered and not c.powered_before,
           "enabling takes the actual position as set position (the following error vanishes)",
           "TcMC §3.5; D-019"),
    Waiver("reset", frozenset({"jump.position"}),
           lambda c: c.state_before is AxisState.ERROR_STOP
           and c.state is not AxisState.ERROR_STOP,
           "MC_Reset takes the actual position as set position once the error reaction has "
           "brought the axis to rest",
           "TcMC §3.5, §4.2; D-019"),
)


def waived(invariant: str, cycle: Cycle) -> Waiver | None:
    for waiver in EXCEPTIONS:
        if invariant in waiver.waives and waiver.applies(cycle):
            return waiver
    return None


# -- actions, violations, reproductions -------------------------------------------------------

@dataclass(frozen=True)
class Action:
    """New input values for one block, given in its call of ``cycle``."""

    cycle: int
    axis: str
    block: str  #: key in the axis' block table (``BLOCKS``)
    inputs: dict[str, Any]
    operation: int  #: index of the storm operation that made it

    def __str__(self) -> str:
        args = ", ".join(f"{k}={_show(v)}" for k, v in self.inputs.items())
        return f"cycle {self.cycle:>7}  {self.axis}.{self.block}({args})"


def _show(value: object) -> str:
    if isinstance(value, om.Axis):
        return value.name
    if isinstance(value, enum.Enum):
        return f"{type(value).__name__}.{value.name}"
    if isinstance(value, float) and not math.isfinite(value):
        return f"float('{value}')"
    return repr(value)


@dataclass
class Violation:
    invariant: str  #: limit.velocity, jump.position, state, handshake.<rule>, hang, exception
    axis: str
    cycle: int
    operation: int  #: index of the last operation issued before the violating cycle
    detail: str
    context: frozenset[str]  #: busy blocks and axis conditions: what was going on
    since: int  #: the cycle the axis last stood still with all its blocks idle
    history: list[Action]  #: the calls since then, on the axis and its masters
    start: dict[str, Snapshot]  #: those axes at that standstill
    minimal: list[Action] | None = None  #: the fewest calls that reproduce it (``shrink``)
    cycles: int = 1  #: consecutive cycles it lasted

    def report(self, seed: int) -> str:
        lines = [f"{self.invariant} on axis {self.axis} at cycle {self.cycle} for "
                 f"{self.cycles} cycle(s) (seed {seed}, operation {self.operation}): "
                 f"{self.detail}",
                 f"  context: {', '.join(sorted(self.context)) or '-'}",
                 f"  the whole storm: run_storm(seed={seed}, operations={self.operation + 1})"]
        if self.minimal is not None:
            lines.append("  minimal reproduction on a fresh runtime:")
            lines += ["    " + line for line in script(self).splitlines()]
        else:
            shown = self.history[-MAX_SHOWN:]
            lines.append(f"  not reproduced alone; the last {len(shown)} of "
                         f"{len(self.history)} calls since the standstill at cycle "
                         f"{self.since}:")
            lines += [f"    start {name}: {snap}" for name, snap in self.start.items()]
            lines += [f"    {action}" for action in shown]
        return "\n".join(lines)


@dataclass(frozen=True)
class Snapshot:
    """An axis at rest: enough to set it up again on a fresh runtime."""

    position: float
    powered: bool
    override: float  #: [%]
    enable_positive: bool
    enable_negative: bool

    def __str__(self) -> str:
        return (f"position={self.position!r}, powered={self.powered}, "
                f"override={self.override!r}, feed=({self.enable_positive}, "
                f"{self.enable_negative})")


# -- the blocks of one axis -------------------------------------------------------------------

BLOCKS: dict[str, type[FunctionBlock]] = {
    "power": MC_Power,
    "move_absolute": MC_MoveAbsolute,
    "move_absolute_2": MC_MoveAbsolute,
    "move_relative": MC_MoveRelative,
    "move_velocity": MC_MoveVelocity,
    "move_velocity_2": MC_MoveVelocity,
    "halt": MC_Halt,
    "stop": MC_Stop,
    "jog": MC_Jog,
    "superimposed": MC_MoveSuperImposed,
    "abort_superposition": MC_AbortSuperposition,
    "set_override": MC_SetOverride,
    "gear_in": MC_GearIn,
    "gear_in_float": MC_GearInFloat,
    "gear_out": MC_GearOut,
    "reset": MC_Reset,
}


class _Watched:
    """One block and what its previous call showed."""

    __slots__ = ("key", "block", "jog", "level", "busy", "result", "pending", "busy_since",
                 "initiator", "keys")

    def __init__(self, key: str, block: FunctionBlock) -> None:
        self.key, self.block = key, block
        self.jog = isinstance(block, MC_Jog)
        self.initiator = "jog_forward"  #: MC_Jog: the key whose edge was accepted
        self.keys = (False, False)  #: MC_Jog: the keys at the previous call
        self.level = False
        self.busy = False
        self.result: str | None = None
        self.pending: dict[str, Any] = {}
        self.busy_since = -1

    def live(self) -> bool:
        """Calling an idle block with nothing to show changes nothing: it may be skipped."""
        return bool(self.pending) or self.level or self.busy or self.result is not None \
            or self._input_level()

    def _input_level(self) -> bool:
        b = self.block
        if self.jog:
            return bool(b.jog_forward or b.jog_backwards)
        return bool(getattr(b, "execute", False))


# -- the storm --------------------------------------------------------------------------------

class Storm:
    """A runtime with ``AXES``, their blocks, the invariant checks and an action log."""

    def __init__(self, seed: int, start: dict[str, Snapshot] | None = None) -> None:
        self.seed = seed
        self.rng = random.Random(seed)
        self.rt = om.Runtime(CYCLE_TIME)
        self.axes: dict[str, om.Axis] = {}
        for name, (overrides, drive) in AXES.items():
            if start is not None and name not in start:
                continue
            position = start[name].position if start else 0.0
            self.axes[name] = self.rt.add_axis(name, drive=drive, position=position,
                                               **overrides)
        self.blocks = {name: {key: _Watched(key, cls(axis)) for key, cls in BLOCKS.items()}
                       for name, axis in self.axes.items()}
        self.log: list[Action] = []
        self.violations: list[Violation] = []
        self.operation = -1
        self._releases: dict[int, list[tuple[str, str, dict[str, Any]]]] = {}
        self._previous = {name: self._sample(axis) for name, axis in self.axes.items()}
        self._powered = {name: False for name in self.axes}
        self._state = {name: axis.state for name, axis in self.axes.items()}
        self._quiet = dict.fromkeys(self.axes, 0)
        self._master: dict[str, om.Axis] = {}  #: the master of each axis' latest coupling
        self._superimposed = dict.fromkeys(self.axes, 0)  #: cycles since an overlay, counted down
        #: log index and cycle of each axis' last standstill (all its blocks idle)
        self._rest_mark = dict.fromkeys(self.axes, (0, 0))
        self._rest_snap: dict[str, dict[str, Snapshot]] = {}
        self._reported_hangs: set[tuple[str, str, int]] = set()
        self._episodes: dict[tuple[str, str], Violation] = {}
        self._seen: set[tuple[str, str]] = set()
        for name in self.axes:
            self._rest_snap[name] = self._snapshots()
        if start is not None:  # replay: power and override as at the start
            for name, snap in start.items():
                self.give(name, "power", enable=snap.powered, override=snap.override,
                          enable_positive=snap.enable_positive,
                          enable_negative=snap.enable_negative)

    # -- giving inputs -----------------------------------------------------------------------

    def give(self, axis: str, key: str, **inputs: Any) -> None:
        """New inputs for a block, used in its call of the next cycle (and logged)."""
        self.blocks[axis][key].pending.update(inputs)
        self.log.append(Action(self.rt.cycle + 1, axis, key, dict(inputs), self.operation))

    def release_later(self, cycles: int, axis: str, key: str, **inputs: Any) -> None:
        self._releases.setdefault(self.rt.cycle + 1 + cycles, []).append((axis, key, inputs))

    # -- one cycle ---------------------------------------------------------------------------

    def step(self) -> None:
        for axis, key, inputs in self._releases.pop(self.rt.cycle + 1, ()):
            self.give(axis, key, **inputs)
        cycle = self.rt.cycle + 1
        for name, table in self.blocks.items():
            for watched in table.values():
                if watched.live():
                    self._call(name, watched, cycle)
        try:
            self.rt.step()
        except Exception as exc:  # noqa: BLE001 - any exception out of step() is a finding
            self._violate("exception", next(iter(self.axes)), f"step() raised {exc!r}")
        for name, axis in self.axes.items():
            self._check_axis(name, axis)
        self._end_episodes()

    def _call(self, name: str, watched: _Watched, cycle: int) -> None:
        inputs, watched.pending = watched.pending, {}
        block = watched.block
        try:
            block(**inputs)
        except Exception as exc:  # noqa: BLE001
            self._violate("exception", name, f"{watched.key}{inputs} raised {exc!r}")
            return
        if isinstance(block, MC_Power):
            return
        self._check_handshake(name, watched, cycle)

    # -- handshake ---------------------------------------------------------------------------

    def _check_handshake(self, name: str, w: _Watched, cycle: int) -> None:
        b = w.block
        if w.jog:  # an edge counts only if the block was not busy (TcMC §3.13); the result
            keys = (bool(b.jog_forward), bool(b.jog_backwards))  # follows the initiating key
            rising = [k and not was for k, was in zip(keys, w.keys, strict=True)]
            edge = any(rising) and not w.busy
            if edge:
                w.initiator = "jog_forward" if rising[0] else "jog_backwards"
            w.keys = keys
            level = bool(getattr(b, w.initiator))
        else:
            level = bool(b.execute)
            edge = level and not w.level
        results = [r for r in RESULTS if getattr(b, r)]
        result = results[0] if results else None
        busy = bool(b.busy)
        active = bool(getattr(b, "active", busy))
        label = f"{w.key} ({type(b).__name__})"
        if len(results) > 1:
            self._violate("handshake.exclusive", name, f"{label}: {results} together")
        if busy and result:
            self._violate("handshake.busy_with_result", name, f"{label}: busy and {result}")
        if active and not busy:
            self._violate("handshake.active_not_busy", name, f"{label}: active without busy")
        if bool(b.error) != (b.error_id != 0):
            self._violate("handshake.error_id", name,
                          f"{label}: error={b.error} with error_id={b.error_id!r}")
        if w.busy and not busy and not result and not edge:
            self._violate("handshake.silent_end", name,
                          f"{label}: Busy fell with no Done, CommandAborted or Error")
        if w.result and not edge:
            if w.level and level and result != w.result:
                self._violate("handshake.persistence", name,
                              f"{label}: {w.result} dropped while the input stayed TRUE")
            if not w.level and not level and result is not None:
                self._violate("handshake.pulse", name,
                              f"{label}: {result} shown for more than one call with the input "
                              "FALSE")
        if busy and not w.busy:
            w.busy_since = cycle
            if isinstance(b, MC_GearIn | MC_GearInFloat):  # the coupling this edge made
                self._master[name] = b.master
        w.level, w.busy, w.result = level, busy, result

    # -- axis invariants ---------------------------------------------------------------------

    @staticmethod
    def _sample(axis: om.Axis) -> tuple[float, float, float, float]:
        return axis.set_position, axis.set_velocity, axis.set_acceleration, axis.set_jerk

    def _check_axis(self, name: str, axis: om.Axis) -> None:
        p0, v0, a0, _ = self._previous[name]
        p1, v1, a1, j1 = now = self._sample(axis)
        self._previous[name] = now
        par = axis.parameters
        v_max, j_max = par.max_velocity, par.max_jerk
        a_max = max(par.max_acceleration, par.max_deceleration)
        cycle = Cycle(name, self._powered[name], axis.powered, self._state[name], axis.state)
        self._powered[name], self._state[name] = axis.powered, axis.state
        dt = CYCLE_TIME
        eps_p, eps_v, eps_a = RUCKIG_PRECISION
        checks = (
            ("limit.velocity", abs(v1), v_max * (1 + REL)),
            ("limit.acceleration", abs(a1), a_max * (1 + REL)),
            ("limit.jerk", abs(j1), j_max * (1 + REL)),
            ("jump.velocity", abs(v1 - v0),
             a_max * dt * (1 + REL) + TINY * max(abs(v0), abs(v1)) + eps_v),
            ("jump.acceleration", abs(a1 - a0),
             j_max * dt * (1 + REL) + TINY * max(abs(a0), abs(a1)) + eps_a),
            ("jump.position", abs(p1 - p0 - (v0 + v1) * dt / 2.0),
             j_max * dt**3 / 12.0 * (1 + REL) + TINY * (abs(p1) + v_max * dt) + eps_p),
        )
        for invariant, value, bound in checks:
            if not value <= bound and waived(invariant, cycle) is None:
                self._violate(invariant, name, f"{value!r} > {bound!r} "
                              f"(p {p0!r}->{p1!r}, v {v0!r}->{v1!r}, a {a0!r}->{a1!r})")
        state = axis.state
        if state in AT_REST_STATES and (v1 != 0.0 or a1 != 0.0):
            self._violate("state", name, f"{state.name} at v={v1!r}, a={a1!r}")
        self._check_hang(name, axis, v1, a1)
        # a peek, for the context only: no FB shows an overlay that still brakes after its
        # block ended, nor one that a fault ended (its reaction starts in the next cycle)
        if axis.kernel.superimposed[axis.row]:
            self._superimposed[name] = SUPERPOSITION_MEMORY
        elif self._superimposed[name]:
            self._superimposed[name] -= 1

    def _check_hang(self, name: str, axis: om.Axis, v: float, a: float) -> None:
        table = self.blocks[name]
        jog = table["jog"].block
        idle = (v == 0.0 and a == 0.0 and not axis.has_job
                and axis.state is not AxisState.SYNCHRONIZED_MOTION and axis.override > 0.0
                and axis.enable_positive and axis.enable_negative
                and not (jog.jog_forward or jog.jog_backwards))
        self._quiet[name] = self._quiet[name] + 1 if idle else 0
        if not idle:
            return
        busy = [w for w in table.values() if w.busy]
        if not busy and axis.state in AT_REST_STATES:
            self._rest_mark[name] = (len(self.log), self.rt.cycle)
            self._rest_snap[name] = self._snapshots()
        if self._quiet[name] < HANG_CYCLES:
            return
        for w in busy:
            key = (name, w.key, w.busy_since)
            if self.rt.cycle - w.busy_since >= HANG_CYCLES and key not in self._reported_hangs:
                self._reported_hangs.add(key)
                self._violate("hang", name, f"{w.key} ({type(w.block).__name__}) Busy since "
                              f"cycle {w.busy_since}; the axis has been at rest with nothing "
                              f"pending for {self._quiet[name]} cycles")

    def _snapshots(self) -> dict[str, Snapshot]:
        return {name: Snapshot(axis.set_position, axis.powered, axis.override * 100.0,
                               axis.enable_positive, axis.enable_negative)
                for name, axis in self.axes.items()}

    def _context(self, name: str) -> frozenset[str]:
        axis = self.axes[name]
        tags = {f"state:{axis.state.name}"}
        if axis.state is AxisState.ERROR_STOP:
            tags.add(f"axis error:{axis.axis_error_id.name}")
        tags |= {f"busy:{w.key}" for w in self.blocks[name].values() if w.busy}
        if self._superimposed[name] or axis.kernel.superimposed[axis.row]:  # now or just before
            tags.add("superimposed")
        master = self._master.get(name)
        if axis.state is AxisState.SYNCHRONIZED_MOTION and master is not None \
                and not master.powered:
            tags.add("master disabled")
        if axis.override < 1.0:
            tags.add("override<100")
        if not (axis.enable_positive and axis.enable_negative):
            tags.add("feed disabled")
        for other, table in self.blocks.items():
            for key in ("gear_in", "gear_in_float"):
                w = table[key]
                if w.busy and getattr(w.block, "master", None) is axis:
                    tags.add(f"master of {other}")

        return frozenset(tags)

    def _violate(self, invariant: str, name: str, detail: str) -> None:
        """Record a violation; the same invariant on the same axis in consecutive cycles is
        one violation (an episode) that counts its cycles."""
        episode = (name, invariant)
        if episode in self._episodes:
            self._episodes[episode].cycles += 1
            self._seen.add(episode)
            return
        index, since = self._rest_mark[name]
        history = self.log[index:]
        involved, grown = set(), {name}
        while grown:  # the axis, its masters, their masters ...
            involved |= grown
            grown = {v.name for a in history if a.axis in involved
                     for v in a.inputs.values() if isinstance(v, om.Axis)} - involved
        violation = Violation(invariant, name, self.rt.cycle, self.operation, detail,
                              self._context(name), since,
                              [a for a in history if a.axis in involved],
                              {n: s for n, s in self._rest_snap[name].items() if n in involved})
        self.violations.append(violation)
        self._episodes[episode] = violation
        self._seen.add(episode)

    def _end_episodes(self) -> None:
        """After a cycle: an episode whose invariant held again in it is over."""
        for episode in [e for e in self._episodes if e not in self._seen]:
            del self._episodes[episode]
        self._seen.clear()

    # -- running -----------------------------------------------------------------------------

    def run(self, cycles: int) -> None:
        for _ in range(cycles):
            self.step()


# -- the generator ----------------------------------------------------------------------------

class Generator:
    """Random operations with random, often invalid, inputs (the weights are ``KINDS``)."""

    def __init__(self, storm: Storm) -> None:
        self.s = storm
        self.rng = storm.rng
        self.kinds, self.weights = zip(*KINDS.items(), strict=True)

    # values ----------------------------------------------------------------------------------

    def _invalid(self) -> Any:
        return self.rng.choice((NAN, INF, -INF, -1.0, -250.0, MC_INVALID))

    def velocity(self, axis: om.Axis) -> Any:
        r, v_max = self.rng.random(), axis.parameters.max_velocity
        if r < 0.70:
            return self.rng.uniform(1.0, 1.3 * v_max)
        if r < 0.78:
            return v_max
        if r < 0.82:
            return 1e-6
        return self.rng.choice((0.0, MC_DEFAULT, self._invalid()))

    def dynamic(self, axis: om.Axis, jerk: bool = False) -> Any:
        r, p = self.rng.random(), axis.parameters
        if r < 0.30:
            return MC_DEFAULT
        if r < 0.40:
            return 0.0
        if r < 0.85:
            if jerk:
                return 10 ** self.rng.uniform(3.0, math.log10(1.5 * p.max_jerk))
            return self.rng.uniform(100.0, 1.3 * max(p.max_acceleration, p.max_deceleration))
        return self._invalid()

    def position(self, axis: om.Axis) -> Any:
        r = self.rng.random()
        if r < 0.85:
            return self.rng.uniform(-2000.0, 2000.0)
        if r < 0.90:
            return axis.set_position
        return self.rng.choice((NAN, INF, MC_INVALID))

    def distance(self) -> Any:
        r = self.rng.random()
        if r < 0.85:
            return self.rng.uniform(-800.0, 800.0)
        if r < 0.90:
            return self.rng.choice((0.0, 1e-9, -1e-9))
        return self.rng.choice((NAN, INF, MC_INVALID))

    def buffer_mode(self) -> Any:
        r = self.rng.random()
        if r < 0.40:
            return BufferMode.ABORTING
        if r < 0.95:
            return self.rng.choice(tuple(BufferMode))
        return self.rng.choice((7, -1))

    def hold(self) -> int:
        """Cycles Execute stays TRUE: a pulse, a short hold or a long one."""
        r = self.rng.random()
        if r < 0.5:
            return 1
        if r < 0.8:
            return self.rng.randint(2, 30)
        return self.rng.randint(31, 600)

    def wait(self) -> int:
        r = self.rng.random()
        if r < 0.25:
            return 0
        if r < 0.75:
            return self.rng.randint(1, 5)
        if r < 0.97:
            return self.rng.randint(6, 60)
        return self.rng.randint(61, 400)

    # operations ------------------------------------------------------------------------------

    def operate(self) -> None:
        """One random operation on a random axis, then a random wait."""
        s = self.s
        s.operation += 1
        name = self.rng.choice(tuple(s.axes))
        if s.operation and s.operation % SETTLE_EVERY == 0:
            self.settle()
            return
        kind = self.rng.choices(self.kinds, self.weights)[0]
        if s.axes[name].state is AxisState.ERROR_STOP and self.rng.random() < 0.5:
            kind = "reset"
        getattr(self, kind)(name, s.axes[name])
        s.run(self.wait())

    def _execute(self, name: str, key: str, **inputs: Any) -> None:
        """A rising edge with ``inputs``; Execute falls after ``hold()`` cycles."""
        s = self.s
        watched = s.blocks[name][key]
        if watched.block.execute or watched.pending.get("execute"):
            s.give(name, key, execute=False)  # the edge needs a FALSE call first
            s.run(1)
        s.give(name, key, execute=True, **inputs)
        s.release_later(self.hold(), name, key, execute=False)

    def _free(self, name: str, *keys: str) -> str:
        for key in keys:
            if not self.s.blocks[name][key].block.execute:
                return key
        return self.rng.choice(keys)

    def move_absolute(self, name: str, axis: om.Axis) -> None:
        self._execute(name, self._free(name, "move_absolute", "move_absolute_2"),
                      position=self.position(axis), velocity=self.velocity(axis),
                      acceleration=self.dynamic(axis), deceleration=self.dynamic(axis),
                      jerk=self.dynamic(axis, jerk=True), buffer_mode=self.buffer_mode())

    def move_relative(self, name: str, axis: om.Axis) -> None:
        self._execute(name, "move_relative", distance=self.distance(),
                      velocity=self.velocity(axis), acceleration=self.dynamic(axis),
                      deceleration=self.dynamic(axis), jerk=self.dynamic(axis, jerk=True),
                      buffer_mode=self.buffer_mode())

    def move_velocity(self, name: str, axis: om.Axis) -> None:
        direction = self.rng.choice((Direction.POSITIVE, Direction.NEGATIVE,
                                     Direction.POSITIVE, Direction.NEGATIVE,
                                     Direction.CURRENT, Direction.SHORTEST_WAY))
        self._execute(name, self._free(name, "move_velocity", "move_velocity_2"),
                      velocity=self.velocity(axis), direction=direction,
                      acceleration=self.dynamic(axis), deceleration=self.dynamic(axis),
                      jerk=self.dynamic(axis, jerk=True), buffer_mode=self.buffer_mode())

    def halt(self, name: str, axis: om.Axis) -> None:
        self._execute(name, "halt", deceleration=self.dynamic(axis),
                      jerk=self.dynamic(axis, jerk=True), buffer_mode=self.buffer_mode())

    def stop(self, name: str, axis: om.Axis) -> None:
        keep = self.rng.random() < 0.4  # 0: the running move's dynamics (TcMC §3.15)
        self._execute(name, "stop", deceleration=0.0 if keep else self.dynamic(axis),
                      jerk=0.0 if keep else self.dynamic(axis, jerk=True))

    def jog(self, name: str, axis: om.Axis) -> None:
        s = self.s
        watched = s.blocks[name]["jog"]
        jog, pending = watched.block, watched.pending
        if (pending.get("jog_forward", jog.jog_forward)
                or pending.get("jog_backwards", jog.jog_backwards)):
            s.give(name, "jog", jog_forward=False, jog_backwards=False)
            return
        key = self.rng.choice(("jog_forward", "jog_backwards"))
        mode = self.rng.choice((*JogMode, 7))
        step = self.rng.choice((MC_DEFAULT, self.rng.uniform(0.1, 50.0), NAN))
        s.give(name, "jog", mode=mode, position=step, velocity=self.velocity(axis),
               acceleration=self.dynamic(axis), deceleration=self.dynamic(axis),
               jerk=self.dynamic(axis, jerk=True), **{key: True})
        s.release_later(self.hold(), name, "jog", **{key: False})

    def superimposed(self, name: str, axis: om.Axis) -> None:
        v_max = axis.parameters.max_velocity
        distance = self.rng.choice((self.rng.uniform(-300.0, 300.0),
                                    self.rng.uniform(-50.0, 50.0), NAN, 0.0))
        self._execute(name, "superimposed", distance=distance,
                      velocity_diff=self.rng.choice((self.rng.uniform(1.0, v_max),
                                                     self.velocity(axis))),
                      velocity_process=self.rng.choice((abs(axis.set_velocity) or 1.0,
                                                        self.velocity(axis))),
                      max_distance=self.rng.choice((self.rng.uniform(1.0, 2000.0),
                                                    self.distance())),
                      acceleration=self.dynamic(axis), deceleration=self.dynamic(axis))

    def abort_superposition(self, name: str, axis: om.Axis) -> None:
        self._execute(name, "abort_superposition")

    def set_override(self, name: str, axis: om.Axis) -> None:
        self._execute(name, "set_override", override=self.override())

    def override(self) -> Any:
        r = self.rng.random()
        if r < 0.70:
            return self.rng.uniform(0.0, 100.0)
        if r < 0.80:
            return 0.0
        if r < 0.90:
            return 100.0
        return self.rng.choice((-5.0, 150.0, NAN))

    def power_override(self, name: str, axis: om.Axis) -> None:
        self.s.give(name, "power", override=self.override())

    def feed_enable(self, name: str, axis: om.Axis) -> None:
        self.s.give(name, "power", enable_positive=self.rng.random() < 0.7,
                    enable_negative=self.rng.random() < 0.7)

    def power_off(self, name: str, axis: om.Axis) -> None:
        self.s.give(name, "power", enable=False)
        self.s.release_later(self.rng.randint(1, 50), name, "power", enable=True)

    def gear_in(self, name: str, axis: om.Axis) -> None:
        master = self.s.axes[self.rng.choice([n for n in self.s.axes if n != name])]
        if self.rng.random() < 0.5:
            self._execute(name, "gear_in", master=master,
                          ratio_numerator=self.rng.randint(-3, 3),
                          ratio_denominator=self.rng.choice((1, 1, 2, 3, 0)))
        else:
            self._execute(name, "gear_in_float", master=master,
                          gear_ratio=self.rng.choice((self.rng.uniform(-2.5, 2.5), NAN)))

    def gear_out(self, name: str, axis: om.Axis) -> None:
        self._execute(name, "gear_out")

    def reset(self, name: str, axis: om.Axis) -> None:
        self._execute(name, "reset")

    def settle(self) -> None:
        """Release every input, power on at 100 %, decouple, halt, reset: the axes come to
        rest and every block must end (the hang check watches)."""
        s = self.s
        for name, table in s.blocks.items():
            for key, watched in table.items():
                block = watched.block
                if watched.jog:
                    s.give(name, key, jog_forward=False, jog_backwards=False)
                elif key != "power" and block.execute:
                    s.give(name, key, execute=False)
            s.give(name, "power", enable=True, enable_positive=True, enable_negative=True)
        s.run(1)
        for name, axis in s.axes.items():
            if axis.state is AxisState.SYNCHRONIZED_MOTION:
                s.give(name, "gear_out", execute=True)
            s.give(name, "set_override", execute=True, override=100.0)
        s.run(1)
        for name, axis in s.axes.items():
            s.give(name, "gear_out", execute=False)
            s.give(name, "set_override", execute=False)
            if axis.state is AxisState.ERROR_STOP:
                s.give(name, "reset", execute=True)
            else:
                s.give(name, "halt", execute=True, deceleration=MC_DEFAULT, jerk=MC_DEFAULT,
                       buffer_mode=BufferMode.ABORTING)
        s.run(1)
        for name in s.axes:
            s.give(name, "halt", execute=False)
            s.give(name, "reset", execute=False)
        for _ in range(SETTLE_CYCLES):
            s.step()
            if all(ax.state in AT_REST_STATES and not any(w.busy for w in s.blocks[n].values())
                   for n, ax in s.axes.items()):
                break


#: operation -> weight
KINDS: dict[str, float] = {
    "move_absolute": 14, "move_relative": 9, "move_velocity": 12, "halt": 6, "stop": 4,
    "jog": 6, "superimposed": 11, "abort_superposition": 2, "set_override": 5,
    "power_override": 4, "feed_enable": 4, "power_off": 1, "gear_in": 6, "gear_out": 3,
    "reset": 3,
}


# -- entry points -----------------------------------------------------------------------------

@dataclass
class Report:
    seed: int
    operations: int
    cycles: int
    seconds: float  #: wall time of the operations
    cpu_seconds: float  #: processor time of the operations (a busy machine inflates the wall)
    violations: list[Violation]

    def by_invariant(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for v in self.violations:
            counts[v.invariant] = counts.get(v.invariant, 0) + 1
        return dict(sorted(counts.items()))


def run_storm(seed: int, operations: int, shrink_violations: int = 0) -> Report:
    """``operations`` random operations (settles included) from ``seed``; the first
    ``shrink_violations`` violations get a minimal reproduction (``shrink``)."""
    strict, FunctionBlock.strict = FunctionBlock.strict, False  # we check, not assert
    try:
        storm = Storm(seed)
        for name in storm.axes:
            storm.give(name, "power", enable=True)
        storm.run(2)
        generator = Generator(storm)
        started, cpu = time.perf_counter(), time.process_time()
        for _ in range(operations):
            generator.operate()
        seconds, cpu = time.perf_counter() - started, time.process_time() - cpu
        for violation in storm.violations[:shrink_violations]:
            violation.minimal = shrink(violation)
    finally:
        FunctionBlock.strict = strict
    return Report(seed, operations, storm.rt.cycle, seconds, cpu, storm.violations)


def replays(violation: Violation, actions: list[Action]) -> bool:
    """Do ``actions`` alone, on a fresh runtime whose axes stand as in ``violation.start``,
    break the same invariant on the same axis (by the same cycle, give or take a few)?"""
    storm = Storm(seed=0, start=violation.start)
    storm.run(1)  # the power and override of the start
    origin = _origin(violation, actions)
    by_cycle: dict[int, list[Action]] = {}
    for action in actions:
        by_cycle.setdefault(action.cycle, []).append(action)
    for cycle in range(origin + 1, violation.cycle + REPLAY_MARGIN):
        for action in by_cycle.get(cycle, ()):
            storm.give(action.axis, action.block, **_rebind(action.inputs, storm))
        storm.step()
        if any(v.invariant == violation.invariant and v.axis == violation.axis
               and abs(v.cycle + origin - 1 - violation.cycle) <= REPLAY_MARGIN
               for v in storm.violations):
            return True
    return False


def _origin(violation: Violation, actions: list[Action]) -> int:
    """The storm cycle a replay's cycle 1 stands for: just before the first call (the
    axes stand still until then, so waiting longer would change nothing)."""
    return max(violation.since, min((a.cycle for a in actions), default=violation.cycle) - 2)


def _rebind(inputs: dict[str, Any], storm: Storm) -> dict[str, Any]:
    """A gear block's master is an axis of the new runtime (one of the same name)."""
    return {k: storm.axes[v.name] if isinstance(v, om.Axis) else v for k, v in inputs.items()}


def shrink(violation: Violation) -> list[Action] | None:
    """The fewest calls since the standstill that still reproduce ``violation`` (delta
    debugging, at most ``SHRINK_REPLAYS`` replays); None when the history alone does not."""
    strict, FunctionBlock.strict = FunctionBlock.strict, False
    try:
        actions = [a for a in violation.history if a.cycle <= violation.cycle]
        if not replays(violation, actions):
            return None
        parts, budget = 2, SHRINK_REPLAYS
        while len(actions) >= 2 and budget > 0:
            size = math.ceil(len(actions) / parts)
            for i in range(0, len(actions), size):
                candidate = actions[:i] + actions[i + size:]
                budget -= 1
                if replays(violation, candidate):
                    actions, parts = candidate, max(parts - 1, 2)
                    break
                if budget <= 0:
                    break
            else:
                if parts >= len(actions):
                    break
                parts = min(2 * parts, len(actions))
        return actions
    finally:
        FunctionBlock.strict = strict


def script(violation: Violation) -> str:
    """Python that replays ``violation.minimal`` with the public API alone."""
    actions = violation.minimal or []
    named = {violation.axis} | {a.axis for a in actions} | {
        v.name for a in actions for v in a.inputs.values() if isinstance(v, om.Axis)}
    start = {n: snap for n, snap in violation.start.items() if n in named}
    lines = ["import openmotion as om", "from openmotion.plcopen import *  # noqa",
             "from openmotion import *  # noqa", "rt = om.Runtime(0.001)"]
    for name, snap in start.items():
        overrides, drive = AXES[name]
        args = "".join(f", {k}={v!r}" for k, v in overrides.items())
        lines.append(f"{name} = rt.add_axis({name!r}, position={snap.position!r}, "
                     f"drive=om.{drive!r}{args})")
        lines.append(f"{name}_power = MC_Power({name}, enable={snap.powered}, "
                     f"override={snap.override!r}, enable_positive={snap.enable_positive}, "
                     f"enable_negative={snap.enable_negative})")
    used = sorted({(a.axis, a.block) for a in actions} - {(n, "power") for n in start})
    for name, key in used:
        lines.append(f"{name}_{key} = {BLOCKS[key].__name__}({name})")
    blocks = [f"{n}_power" for n in start] + [f"{n}_{k}" for n, k in used]
    lines.append(f"blocks = [{', '.join(blocks)}]")
    lines.append("calls = {  # cycle -> block -> inputs")
    origin = _origin(violation, actions)
    by_cycle: dict[int, list[Action]] = {}
    for action in actions:
        by_cycle.setdefault(action.cycle - origin + 1, []).append(action)
    for cycle, group in sorted(by_cycle.items()):
        items = ", ".join(f"{a.axis}_{a.block}: dict("
                          + ", ".join(f"{k}={_show(v)}" for k, v in a.inputs.items()) + ")"
                          for a in group)
        lines.append(f"    {cycle}: {{{items}}},")
    lines.append("}")
    lines.append(f"for cycle in range(1, {violation.cycle - origin + 2}):")
    lines.append("    for block in blocks:")
    lines.append("        block(**calls.get(cycle, {}).get(block, {}))")
    lines.append("    rt.step()")
    lines.append(f"axis = {violation.axis}  # {violation.invariant}: {violation.detail[:60]}")
    lines.append("print(axis.state, axis.set_position, axis.set_velocity, "
                 "axis.set_acceleration, axis.set_jerk)")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--operations", type=int, default=DEFAULT_OPERATIONS)
    parser.add_argument("--show", type=int, default=5, help="violations to print in full")
    args = parser.parse_args(argv)
    report = run_storm(args.seed, args.operations, shrink_violations=args.show)
    print(f"seed {report.seed}: {report.operations} operations, {report.cycles} cycles, "
          f"{report.seconds:.1f} s, {report.cpu_seconds:.1f} s of processor time "
          f"({report.operations / report.cpu_seconds:.0f} operations/s, "
          f"{report.cycles / report.cpu_seconds:.0f} cycles/s)")
    print(f"violations: {len(report.violations)} {report.by_invariant()}")
    for violation in report.violations[:args.show]:
        print(violation.report(report.seed))
    return 1 if report.violations else 0


if __name__ == "__main__":
    sys.exit(main())
