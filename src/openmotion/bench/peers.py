"""Peer workloads for ``openmotion bench axes``: pyplcopen ``AxisSim`` and a plain ruckig loop.

Both peers get the same random MoveAbsolute / MoveVelocity stream as openmotion and do the same
per-cycle work: at every cycle first issue that cycle's commands, then advance *every* axis by
exactly one cycle with one call per axis. Only that stepped loop is timed; construction, power-on,
unit conversion of the stream and indexing the stream by cycle are setup and are not timed.

How pyplcopen 0.21 is driven (found by introspection and experiment, see tests/bench):

* Units. The core runs in per-cycle units: position [mm], velocity [mm/cycle], acceleration
  [mm/cycle^2], jerk [mm/cycle^3]. ``move_*`` arguments are *always* per-cycle, also after
  ``configure_si`` (which only stores limits), so stream values are converted once at setup with
  ``CycleConfig.from_period_ns``. The ``AxisSiConfig`` limits are configured to the stream's upper
  bounds like a real setup would, but 0.21 does not clamp moves with them (a 200 mm/s move under a
  100 mm/s ``max_velocity`` still reaches 200 mm/s).
* ``move_absolute(..., max_cycles=k)`` issues the command and then runs up to ``k`` cycles
  internally waiting for Done, raising ``RuntimeError("move_absolute timed out")`` if it is not
  done. With ``max_cycles=0`` the command is latched (status DISCRETE_MOTION), no cycle is run and
  the timeout is raised; we swallow exactly that error (any "... failed: ..." error propagates).
  That is the only non-blocking way to issue it; the C++->Python exception makes an issue cost
  ~12 us instead of ~4 us, i.e. ~0.02 us per axis-cycle at 2 commands/axis/s and 1 ms, which is
  kept in the timing as part of pyplcopen's API cost.
* ``move_velocity(..., cycles=k)`` issues and runs exactly ``k`` cycles and never raises for not
  reaching the velocity; ``cycles=0`` just issues. Caveat: 0.21 jumps to the target velocity in a
  single cycle and ignores acceleration/deceleration/jerk, so velocity-commanded axes are cheaper
  for pyplcopen than the jerk-limited ramps computed by ruckig and openmotion.
* ``cycle()`` advances that one axis by one cycle: issuing with ``max_cycles=0`` then calling
  ``cycle()`` gives the same sample as ``max_cycles=1``; a 10 mm move (100 mm/s, 1000 mm/s^2,
  10000 mm/s^3) reaches STANDSTILL at 10.0 after 392 ``cycle()`` calls, the same end point as the
  run-to-completion call; cycling one instance leaves the others untouched.
* A command issued mid-motion aborts the running move immediately: the trajectory diverges from
  the uninterrupted one in the very next cycle and ends at the new target.
* Rejections. A mid-motion MoveAbsolute whose limits cannot absorb the axis's current
  acceleration (seen when its deceleration is below the current |acceleration|) fails with
  "move_absolute failed: infeasible: ..." (about 4-5 % of a random stream's absolute commands
  at 1000 axes x 2000 cycles), and afterwards ``cycle()`` leaves the axis frozen
  (position, velocity and acceleration stay as they were, status DISCRETE_MOTION). Ruckig and
  openmotion take such commands over and move on, so the driver issues the move again, once, with
  acceleration/deceleration raised just above the current |acceleration|; that always succeeded in
  our runs. The retry is inside the timed loop (pyplcopen's cost) and counted in
  ``PeerRun.reissued``.

So the pyplcopen peer is a genuine per-cycle stepped simulation through the same stream, not a
per-command run to completion, which makes µs per axis-cycle directly comparable.

The ruckig peer uses one ``Ruckig(1, cycle_time)`` OTG per axis (``Ruckig(1)`` alone has
``delta_time == -1`` and ``update`` returns garbage). Absolute commands use the position interface,
velocity commands the velocity interface; deceleration is mapped to ``min_acceleration = -dec``
(ruckig bounds acceleration by sign, not by |v| decrease, so this is an approximation). ``update``
raises ``RuckigError`` instead of returning an error code, so the loop only has a try block (free
in Python 3.11 unless raised). Rarely (about 1 in 4000 random commands) the velocity interface
raises when the current acceleration lies outside the new bounds; like pyplcopen's rejections,
the bounds are then widened just enough and the update repeated; if ruckig still fails (its
numerical step 1), every limit is lowered by 1e-12 ... 1e-6 relative, as openmotion's planner
does. Both are counted in ``PeerRun.reissued``.
"""

from __future__ import annotations

import importlib
import time
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np
import ruckig

ABSOLUTE = "absolute"
VELOCITY = "velocity"

# Stream parameter ranges (SI: mm, mm/s, mm/s^2, mm/s^3); shared by the generator and peer setup.
POSITION_RANGE = (-500.0, 500.0)
VELOCITY_RANGE = (50.0, 500.0)
ACCELERATION_RANGE = (500.0, 5000.0)
JERK_RANGE = (5000.0, 50000.0)
ABSOLUTE_FRACTION = 0.7

_TIMEOUT_SUFFIX = "timed out"
_INFEASIBLE = "infeasible"


@dataclass(frozen=True)
class PeerRun:
    """Outcome of one peer run: timed loop seconds plus state used to check the peer did work."""

    seconds: float
    final_positions: list[float]
    reissued: int = 0  # commands the peer rejected and that were retried with raised acc limits


@dataclass(frozen=True)
class StreamCommand:
    """One command of the benchmark stream, in SI units (mm based)."""

    cycle: int  # cycle index at which the command is issued (0-based)
    axis: int  # axis index
    kind: str  # "absolute" or "velocity"
    value: float  # target position [mm] (absolute) or signed target velocity [mm/s] (velocity)
    velocity: float  # max velocity [mm/s] (>0); equals abs(value) for velocity commands
    acceleration: float  # [mm/s^2] >0
    deceleration: float  # [mm/s^2] >0
    jerk: float  # [mm/s^3] >0


def random_command_stream(
    n_axes: int,
    cycles: int,
    seed: int = 0,
    rate: float = 2.0,
    cycle_time: float = 0.001,
) -> list[StreamCommand]:
    """Deterministic random command stream, sorted by (cycle, axis).

    Per axis the number of commands is Poisson(rate * cycles * cycle_time) with uniformly drawn
    cycles, so the generator is O(commands) rather than O(axes * cycles) and stays cheap at
    10000 axes. At most one command per (cycle, axis) is kept so the order is unambiguous.
    """
    if n_axes < 0 or cycles < 0:
        raise ValueError("n_axes and cycles must be >= 0")
    if rate < 0 or cycle_time <= 0:
        raise ValueError("rate must be >= 0 and cycle_time > 0")
    rng = np.random.default_rng(seed)
    if n_axes == 0 or cycles == 0:
        return []
    counts = rng.poisson(rate * cycles * cycle_time, size=n_axes)
    axes = np.repeat(np.arange(n_axes, dtype=np.int64), counts)
    at = rng.integers(0, cycles, size=axes.size, dtype=np.int64)
    keys = np.unique(at * n_axes + axes)  # sorted by cycle, then axis; duplicates dropped
    at, axes = np.divmod(keys, n_axes)
    n = keys.size

    absolute = rng.random(n) < ABSOLUTE_FRACTION
    position = rng.uniform(*POSITION_RANGE, size=n)
    velocity = rng.uniform(*VELOCITY_RANGE, size=n)
    sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
    acceleration = rng.uniform(*ACCELERATION_RANGE, size=n)
    deceleration = rng.uniform(*ACCELERATION_RANGE, size=n)
    jerk = rng.uniform(*JERK_RANGE, size=n)
    value = np.where(absolute, position, sign * velocity)

    return [
        StreamCommand(
            cycle=int(c),
            axis=int(a),
            kind=ABSOLUTE if is_abs else VELOCITY,
            value=float(val),
            velocity=float(v),
            acceleration=float(acc),
            deceleration=float(dec),
            jerk=float(j),
        )
        for c, a, is_abs, val, v, acc, dec, j in zip(
            at.tolist(),
            axes.tolist(),
            absolute.tolist(),
            value.tolist(),
            velocity.tolist(),
            acceleration.tolist(),
            deceleration.tolist(),
            jerk.tolist(),
            strict=True,
        )
    ]


def _by_cycle(stream: list[StreamCommand], n_axes: int, cycles: int) -> list[list[StreamCommand]]:
    """Index the stream by cycle so the timed loop does no searching; late commands are dropped."""
    slots: list[list[StreamCommand]] = [[] for _ in range(cycles)]
    for cmd in stream:
        if not 0 <= cmd.axis < n_axes:
            raise ValueError(f"command for axis {cmd.axis} but only {n_axes} axes")
        if cmd.kind not in (ABSOLUTE, VELOCITY):
            raise ValueError(f"unknown command kind {cmd.kind!r}")
        if 0 <= cmd.cycle < cycles:
            slots[cmd.cycle].append(cmd)
    return slots


def _import_pyplcopen() -> ModuleType | None:
    """Import the optional peer lazily so openmotion works without it."""
    try:
        return importlib.import_module("pyplcopen")
    except ImportError:
        return None


def _plc_move_absolute(ax: Any, args: tuple[float, ...]) -> int:
    """Issue a pyplcopen MoveAbsolute without blocking; return 1 if it had to be re-issued.

    ``max_cycles=0`` latches the command and always reports a timeout, which is the expected
    outcome. A move whose limits cannot absorb the axis's current acceleration is rejected as
    infeasible and would leave the axis frozen, so it is re-issued once with acceleration and
    deceleration raised just above the current |acceleration| (per-cycle units, like ``args``).
    """
    try:
        ax.move_absolute(*args, max_cycles=0)
        return 0
    except RuntimeError as exc:
        message = str(exc)
        if message.endswith(_TIMEOUT_SUFFIX):
            return 0
        if _INFEASIBLE not in message:
            raise
    position, velocity, acceleration, deceleration, jerk = args
    floor = abs(ax.command_acceleration()) * (1.0 + 1e-3)
    try:
        ax.move_absolute(
            position,
            velocity,
            max(acceleration, floor),
            max(deceleration, floor),
            jerk,
            max_cycles=0,
        )
    except RuntimeError as exc:
        if not str(exc).endswith(_TIMEOUT_SUFFIX):
            raise
    return 1


def _drive_pyplcopen(
    n_axes: int, stream: list[StreamCommand], cycles: int, cycle_time: float = 0.001,
    bulk: bool = False,
) -> PeerRun | None:
    """Step N pyplcopen axes through the stream (None when pyplcopen is not installed).

    ``bulk``: between two cycles with commands, every axis advances the whole stretch in one
    ``cycle(n)`` call (its C++ loop), as ``openmotion bench axes`` lets ours run it in bulk.
    """
    plc = _import_pyplcopen()
    if plc is None:
        return None
    cfg = plc.CycleConfig.from_period_ns(round(cycle_time * 1e9))
    vel, acc, jerk = cfg.velocity_to_cycle, cfg.acceleration_to_cycle, cfg.jerk_to_cycle

    limits = plc.AxisSiConfig()
    limits.max_velocity = VELOCITY_RANGE[1]
    limits.max_acceleration = ACCELERATION_RANGE[1]
    limits.max_deceleration = ACCELERATION_RANGE[1]
    limits.max_jerk = JERK_RANGE[1]
    axes: list[Any] = []
    for _ in range(n_axes):
        ax = plc.AxisSim()
        ax.configure_si(cfg, limits)
        ax.power_on()
        axes.append(ax)

    def plc_args(c: StreamCommand) -> tuple[float, ...]:
        ramp = (acc(c.acceleration), acc(c.deceleration), jerk(c.jerk))
        if c.kind == ABSOLUTE:
            return (c.value, vel(c.velocity), *ramp)
        return (vel(c.value), *ramp)

    # (axis object, is_absolute, per-cycle args) prepared outside the timed loop.
    plan: list[list[tuple[Any, bool, tuple[float, ...]]]] = [
        [(axes[c.axis], c.kind == ABSOLUTE, plc_args(c)) for c in slot]
        for slot in _by_cycle(stream, n_axes, cycles)
    ]
    steps = [ax.cycle for ax in axes]
    reissued = 0
    if bulk:
        return _bulk_pyplcopen(axes, steps, plan, cycles)

    start = time.perf_counter()
    for issued in plan:
        for ax, is_abs, args in issued:
            if is_abs:
                reissued += _plc_move_absolute(ax, args)
            else:
                ax.move_velocity(*args, cycles=0)
        for step in steps:
            step()
    elapsed = time.perf_counter() - start
    return PeerRun(elapsed, [ax.command_position() for ax in axes], reissued)


def _bulk_pyplcopen(axes: list[Any], steps: list[Any],
                    plan: list[list[tuple[Any, bool, tuple[float, ...]]]],
                    cycles: int) -> PeerRun:
    """The timed loop of ``_drive_pyplcopen(bulk=True)``: the cycles with commands, and in
    between one ``cycle(n)`` per axis."""
    busy = [(index, issued) for index, issued in enumerate(plan) if issued]
    reissued = 0
    start = time.perf_counter()
    done = 0
    for index, issued in busy:
        if index > done:
            gap = index - done
            for step in steps:
                step(gap)
        done = index
        for ax, is_abs, args in issued:
            if is_abs:
                reissued += _plc_move_absolute(ax, args)
            else:
                ax.move_velocity(*args, cycles=0)
    if cycles > done:
        gap = cycles - done
        for step in steps:
            step(gap)
    elapsed = time.perf_counter() - start
    return PeerRun(elapsed, [ax.command_position() for ax in axes], reissued)


def run_pyplcopen(
    n_axes: int, stream: list[StreamCommand], cycles: int, cycle_time: float = 0.001,
    bulk: bool = False,
) -> float | None:
    """Wall seconds of the pyplcopen loop (``bulk``: the stretches between commands in one
    ``cycle(n)`` per axis), or None when pyplcopen is not installed."""
    result = _drive_pyplcopen(n_axes, stream, cycles, cycle_time, bulk)
    return None if result is None else result.seconds


def _widen_ruckig_acceleration(inp: Any) -> None:
    """Raise the acceleration bounds just above the current |acceleration| after a RuckigError.

    Mirrors the pyplcopen re-issue: ruckig's velocity interface rejects a new command whose
    acceleration bounds are exceeded by the current acceleration.
    """
    floor = abs(inp.current_acceleration[0]) * (1.0 + 1e-3)
    inp.max_acceleration = [max(inp.max_acceleration[0], floor)]
    inp.min_acceleration = [min(inp.min_acceleration[0], -floor)]


_RUCKIG_RETRY_FACTORS = (1.0 - 1e-12, 1.0 - 1e-10, 1.0 - 1e-8, 1.0 - 1e-6)


def _retry_ruckig(otg: Any, inp: Any, out: Any) -> bool:
    """After a RuckigError: widen the acceleration bounds, then lower every limit a hair (the
    retries openmotion's planner makes, decisions D-021). False when nothing plans."""
    _widen_ruckig_acceleration(inp)
    limits = (inp.max_velocity[0], inp.max_acceleration[0], inp.min_acceleration[0],
              inp.max_jerk[0])
    for factor in (1.0, *_RUCKIG_RETRY_FACTORS):
        inp.max_velocity = [limits[0] * factor]
        inp.max_acceleration = [limits[1] * factor]
        inp.min_acceleration = [limits[2] * factor]
        inp.max_jerk = [limits[3] * factor]
        try:
            otg.update(inp, out)
        except ruckig.RuckigError:
            continue
        return True
    return False


def _drive_ruckig(
    n_axes: int, stream: list[StreamCommand], cycles: int, cycle_time: float = 0.001
) -> PeerRun:
    """Step one ruckig OTG per axis through the stream."""
    otgs = [ruckig.Ruckig(1, cycle_time) for _ in range(n_axes)]
    inps = [ruckig.InputParameter(1) for _ in range(n_axes)]
    outs = [ruckig.OutputParameter(1) for _ in range(n_axes)]
    for inp in inps:  # valid idle state: hold position 0 until the first command
        inp.max_velocity = [VELOCITY_RANGE[1]]
        inp.max_acceleration = [ACCELERATION_RANGE[1]]
        inp.max_jerk = [JERK_RANGE[1]]

    position_if, velocity_if = ruckig.ControlInterface.Position, ruckig.ControlInterface.Velocity
    plan: list[list[tuple[Any, bool, float, float, float, float, float]]] = [
        [
            (
                inps[c.axis],
                c.kind == ABSOLUTE,
                c.value,
                c.velocity,
                c.acceleration,
                -c.deceleration,
                c.jerk,
            )
            for c in slot
        ]
        for slot in _by_cycle(stream, n_axes, cycles)
    ]
    triples = list(zip(otgs, inps, outs, strict=True))
    reissued = 0

    start = time.perf_counter()
    for issued in plan:
        for inp, is_abs, value, vmax, amax, amin, jmax in issued:
            if is_abs:
                inp.control_interface = position_if
                inp.target_position = [value]
                inp.target_velocity = [0.0]
            else:
                inp.control_interface = velocity_if
                inp.target_velocity = [value]
            inp.target_acceleration = [0.0]
            inp.max_velocity = [vmax]
            inp.max_acceleration = [amax]
            inp.min_acceleration = [amin]
            inp.max_jerk = [jmax]
        for otg, inp, out in triples:
            try:
                otg.update(inp, out)
            except ruckig.RuckigError:  # zero-cost in 3.11 unless raised
                reissued += 1
                if not _retry_ruckig(otg, inp, out):
                    continue  # no plan at all this cycle: the axis holds its state
            out.pass_to_input(inp)
    elapsed = time.perf_counter() - start
    return PeerRun(elapsed, [inp.current_position[0] for inp in inps], reissued)


def run_ruckig_loop(
    n_axes: int, stream: list[StreamCommand], cycles: int, cycle_time: float = 0.001
) -> float:
    """Wall seconds of the per-axis ruckig loop (setup excluded)."""
    return _drive_ruckig(n_axes, stream, cycles, cycle_time).seconds
