"""``openmotion bench otg``: random point-to-point moves through the axis API, ruckig as oracle.

Samples mirror ruckig's own ``random_1`` test: positions ~ N(0, 4), velocities ~ N(0, 0.8),
limits ~ U(0.08, 16), one in twenty from the high-limit distribution U(10, 1e6). Our axes
start at rest, so a non-rest start state is *produced*: a velocity or absolute pre-move with
the sample's limits is cut off after a random number of cycles, and the set position, velocity
and acceleration the axis really has then are the oracle's input. The target move aborts the
pre-move.

Each sample is then scaled: lengths by L = 10^U(-2, 0) and time by a factor in [1, 10] that
aims the rest-to-rest duration at a log-uniform wish in [0.5 ms, 2 s]. Velocity, acceleration
and jerk scale as L/T, L/T^2, L/T^3, which keeps the problem's shape (every dimensionless
ratio) and changes only how many 1 ms cycles it spans: moves range from below one cycle to
five thousand. The bounds keep magnitudes where ruckig 0.19 itself is reliable: compressed
100x or stretched 100x in length it fails step 1 on a few percent of these inputs, which
would test ruckig rather than us. Samples longer than 5 s are redrawn (run time), as ruckig's
tests redraw invalid input.

Time optimality is judged only where ruckig's problem is ours: acc == dec (four samples in
five). With acc != dec ruckig has no exact counterpart (see trajectory/plan.py), so those
samples are checked for reaching the target and for limits, and their time is reported apart.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import ruckig

import openmotion as om

CYCLE_TIME = 0.001
RELATIVE_TOLERANCE = 1e-9
HIGH_LIMIT_FRACTION = 0.05
SYMMETRIC_FRACTION = 0.8
DURATION_RANGE = (0.0005, 2.0)  #: [s] wished rest-to-rest duration after time scaling
MAX_COMPRESSION = 10.0  #: time compression bound (module docstring: ruckig's reliability)
LENGTH_DECADES = (-2.0, 0.0)
MAX_DURATION = 5.0  #: [s] longer samples are redrawn
MAX_PRE_CYCLES = 3000
ORACLE_RETRY_FACTORS = (1.0, 1.0 - 1e-12, 1.0 - 1e-10, 1.0 - 1e-8)


@dataclass(frozen=True)
class Sample:
    """One move: axis limits, a pre-move that produces the start state, and the target.

    All values are already scaled (mm, s). ``pre_kind`` is "rest", "velocity" or "absolute";
    ``pre_value`` the signed velocity or the target of the pre-move, ``pre_speed`` the
    velocity of an absolute pre-move. To reproduce a sample, ``run_sample(sample)``.
    """

    index: int
    velocity: float
    acceleration: float
    deceleration: float
    jerk: float
    start_position: float
    target: float
    pre_kind: str
    pre_value: float
    pre_speed: float
    pre_fraction: float  #: where in the pre-move's profile it is cut off (0..1.25)
    high_limits: bool

    @property
    def symmetric(self) -> bool:
        return self.acceleration == self.deceleration


def ruckig_duration(position: float, velocity: float, acceleration: float, target: float,
                    limits: tuple[float, float, float, float]) -> tuple[float, float, float]:
    """ruckig's time-optimal duration to rest at ``target``, the seconds ``calculate`` took,
    and the factor the limits had to be lowered by.

    Uses our acc/dec mapping (trajectory/plan.py). ruckig 0.19 fails step 1 on a few inputs
    that solve with every limit lowered a hair (factor 1 - 1e-12 ...); a duration from lowered
    limits is a slightly *looser* bound, by about the same relative amount, far below a cycle.
    The duration is NaN when ruckig returns no result; the last ``RuckigError`` propagates.
    """
    vmax, acc, dec, jerk = limits
    sign = (target > position) - (target < position) or (velocity > 0) - (velocity < 0)
    inp = ruckig.InputParameter(1)
    inp.current_position = [position]
    inp.current_velocity = [velocity]
    inp.current_acceleration = [acceleration]
    inp.target_position = [target]
    inp.target_velocity = [0.0]
    inp.target_acceleration = [0.0]
    trajectory = ruckig.Trajectory(1)
    error: ruckig.RuckigError | None = None
    for factor in ORACLE_RETRY_FACTORS:
        inp.max_velocity = [vmax * factor]
        inp.max_acceleration = [(acc if sign >= 0 else dec) * factor]
        inp.min_acceleration = [-(dec if sign >= 0 else acc) * factor]
        inp.max_jerk = [jerk * factor]
        start = time.perf_counter()
        try:
            result = _ORACLE.calculate(inp, trajectory)
        except ruckig.RuckigError as exc:
            error = exc
            continue
        seconds = time.perf_counter() - start
        if result not in (ruckig.Result.Working, ruckig.Result.Finished):
            return math.nan, seconds, factor
        return float(trajectory.duration), seconds, factor
    assert error is not None
    raise error


_ORACLE = ruckig.Ruckig(1)


def draw_samples(count: int, seed: int = 0) -> list[Sample]:
    """Deterministic samples (see the module docstring for the distributions)."""
    rng = np.random.default_rng(seed)
    samples: list[Sample] = []
    while len(samples) < count:
        sample = _draw(rng, len(samples))
        if sample is not None:
            samples.append(sample)
    return samples


def _draw(rng: np.random.Generator, index: int) -> Sample | None:
    high = bool(rng.random() < HIGH_LIMIT_FRACTION)
    low, top = (10.0, 1e6) if high else (0.08, 16.0)
    vmax, acc, jerk = (float(x) for x in rng.uniform(low, top, size=3))
    dec = acc if rng.random() < SYMMETRIC_FRACTION else float(rng.uniform(low, top))
    start, target = (float(x) for x in rng.normal(0.0, 4.0, size=2))
    pre_kind = str(rng.choice(["rest", "velocity", "absolute"], p=[0.1, 0.6, 0.3]))
    speed = min(abs(float(rng.normal(0.0, 0.8))), vmax) or vmax
    pre_value = speed if rng.random() < 0.5 else -speed
    pre_speed = vmax * float(rng.uniform(0.1, 1.0))
    if pre_kind == "absolute":
        pre_value = float(rng.normal(0.0, 4.0))
    fraction = float(rng.uniform(0.0, 1.25))
    duration = 10.0 ** float(rng.uniform(*np.log10(DURATION_RANGE)))
    length = 10.0 ** float(rng.uniform(*LENGTH_DECADES))
    try:
        natural = ruckig_duration(start, 0.0, 0.0, target, (vmax, acc, dec, jerk))[0]
    except ruckig.RuckigError:
        natural = math.nan
    if not math.isfinite(natural) or natural <= 0.0:
        return None  # the oracle cannot plan even the rest-to-rest move: redraw
    k = min(max(natural / duration, 1.0), MAX_COMPRESSION)  # time compression
    if natural / k > MAX_DURATION:
        return None
    return Sample(
        index=index,
        velocity=vmax * length * k,
        acceleration=acc * length * k**2,
        deceleration=dec * length * k**2,
        jerk=jerk * length * k**3,
        start_position=start * length,
        target=target * length,
        pre_kind=pre_kind,
        pre_value=pre_value * length * (k if pre_kind == "velocity" else 1.0),
        pre_speed=pre_speed * length * k,
        pre_fraction=fraction,
        high_limits=high,
    )


def _axis_for(sample: Sample) -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime(cycle_time=CYCLE_TIME)
    axis = rt.add_axis(
        "x", position=sample.start_position, max_velocity=sample.velocity,
        acceleration=sample.acceleration, deceleration=sample.deceleration, jerk=sample.jerk,
        max_acceleration=sample.acceleration, max_deceleration=sample.deceleration,
        max_jerk=sample.jerk,
    )
    axis.power()
    return rt, axis


def _pre_move(rt: om.Runtime, axis: om.Axis, sample: Sample) -> tuple[int, str]:
    """Run the pre-move for its share of cycles; the cycles run and any rejection."""
    s = sample
    if s.pre_kind == "rest":
        return 0, ""
    if s.pre_kind == "velocity":
        direction = om.Direction.POSITIVE if s.pre_value > 0 else om.Direction.NEGATIVE
        command = axis.move_velocity(abs(s.pre_value), direction, s.acceleration,
                                     s.deceleration, s.jerk)
    else:
        command = axis.move_absolute(s.pre_value, s.pre_speed, s.acceleration,
                                     s.deceleration, s.jerk)
    if command.error:  # the sample then starts at rest; counted and reported
        return 0, f"{command.error_id.name}: {' '.join(command.message.split()[:8])}"
    cycles = min(int(s.pre_fraction * axis.remaining_time / CYCLE_TIME), MAX_PRE_CYCLES)
    for _ in range(cycles):
        rt.step()
    return cycles, ""


def run_sample(sample: Sample) -> dict[str, Any]:
    """Execute one sample; every figure needed to judge it and to reproduce it."""
    s = sample
    limits = (s.velocity, s.acceleration, s.deceleration, s.jerk)
    rt, axis = _axis_for(s)
    pre_cycles, pre_error = _pre_move(rt, axis, s)
    p0, v0, a0 = axis.set_position, axis.set_velocity, axis.set_acceleration
    out: dict[str, Any] = {
        "sample": asdict(s), "pre_cycles": pre_cycles, "pre_error": pre_error,
        "start": {"position": p0, "velocity": v0, "acceleration": a0},
        "symmetric": s.symmetric,
    }
    try:
        reference, seconds, factor = ruckig_duration(p0, v0, a0, s.target, limits)
        out["oracle_error"] = "" if math.isfinite(reference) else "no result"
        out["oracle_factor"] = factor
        out["ruckig_plan_us"] = seconds * 1e6
        out["ruckig_plan_us_warm"] = min(
            ruckig_duration(p0, v0, a0, s.target, limits)[1] for _ in range(3)) * 1e6
    except ruckig.RuckigError as exc:
        reference = math.nan
        out["oracle_error"] = " ".join(str(exc).split()[:6])
        out["oracle_factor"] = None
        out["ruckig_plan_us"] = out["ruckig_plan_us_warm"] = None
    start = time.perf_counter()
    command = axis.move_absolute(s.target, s.velocity, s.acceleration, s.deceleration, s.jerk)
    out["our_plan_us"] = (time.perf_counter() - start) * 1e6
    warm = []
    for _ in range(3):  # no step in between: each re-issue replans from the same state
        start = time.perf_counter()
        command = axis.move_absolute(s.target, s.velocity, s.acceleration, s.deceleration,
                                     s.jerk)
        warm.append((time.perf_counter() - start) * 1e6)
    out["our_plan_us_warm"] = min(warm)
    ours = axis.remaining_time  # duration of our profile, from the sample it starts at
    out.update(ruckig_duration=reference if math.isfinite(reference) else None,
               our_duration=ours)
    out["command_error"] = f"{command.error_id.name}: {command.message}" if command.error else ""
    bound = math.ceil(reference / CYCLE_TIME) + 1 if math.isfinite(reference) else None
    cap = math.ceil(max(ours, 0.0 if bound is None else reference) / CYCLE_TIME) * 2 + 100
    peaks = _step_to_target(rt, axis, s.target, cap)
    cycles = peaks.pop("cycles")
    tolerance = 1 + RELATIVE_TOLERANCE
    violations = [
        name for name, peak, limit in (
            ("velocity", peaks["velocity"], s.velocity),
            ("acceleration", peaks["acceleration"], max(s.acceleration, s.deceleration)),
            ("jerk", peaks["jerk"], s.jerk),
        ) if peak > limit * tolerance
    ]
    reached = cycles is not None and not command.error
    out.update(
        cycles=cycles, bound_cycles=bound, reached=reached, peaks=peaks,
        violations=violations,
        time_ok=reached and bound is not None and cycles <= bound,
        excess_cycles=None if not reached or bound is None else cycles - (bound - 1),
    )
    return out


def _step_to_target(rt: om.Runtime, axis: om.Axis, target: float,
                    cap: int) -> dict[str, Any]:
    """Step until the setpoint is bit-equal to the target at rest; peak |v|, |a|, |j|."""
    kernel, row = rt.axis_system.kernel, axis.row
    set_p, set_v, set_a, set_j = kernel.set_p, kernel.set_v, kernel.set_a, kernel.set_j
    v_peak = a_peak = j_peak = 0.0
    for cycle in range(1, cap + 1):
        rt.step()
        v, a, j = abs(float(set_v[row])), abs(float(set_a[row])), abs(float(set_j[row]))
        v_peak, a_peak, j_peak = max(v_peak, v), max(a_peak, a), max(j_peak, j)
        if float(set_p[row]) == target and v == 0.0:
            return {"cycles": cycle, "velocity": v_peak, "acceleration": a_peak,
                    "jerk": j_peak}
    return {"cycles": None, "velocity": v_peak, "acceleration": a_peak, "jerk": j_peak}


def run_otg(samples: int = 1000, seed: int = 0, keep: int = 10,
            progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Counts over ``samples`` 1-DoF moves, plus up to ``keep`` failing samples in full."""
    runs = []
    for i, sample in enumerate(draw_samples(samples, seed)):
        if progress is not None and i % 200 == 0:
            progress(f"otg: sample {i}/{samples}")
        runs.append(run_sample(sample))
    symmetric = [r for r in runs if r["symmetric"]]
    judged = [r for r in symmetric if r["bound_cycles"] is not None]
    failures = [r for r in runs if not r["reached"] or r["violations"]
                or (r["symmetric"] and r["bound_cycles"] is not None and not r["time_ok"])]
    excess = [r["excess_cycles"] for r in judged if r["excess_cycles"] is not None]
    relative = [(r["our_duration"] - r["ruckig_duration"]) / r["ruckig_duration"]
                for r in judged if r["ruckig_duration"] > 0.0 and not r["command_error"]]
    asymmetric = [r for r in runs if not r["symmetric"]]
    asym_time = [r["our_duration"] / r["ruckig_duration"] for r in asymmetric
                 if r["ruckig_duration"] and not r["command_error"]]
    cycles = [r["cycles"] for r in runs if r["cycles"] is not None]
    return {
        "seed": seed,
        "cycle_time": CYCLE_TIME,
        "samples": len(runs),
        "reached": sum(r["reached"] for r in runs),
        "symmetric": len(symmetric),
        "time_judged": len(judged),
        "time_ok": sum(r["time_ok"] for r in judged),
        "violations": sum(bool(r["violations"]) for r in runs),
        "command_errors": sum(bool(r["command_error"]) for r in runs),
        "pre_move_errors": sum(bool(r["pre_error"]) for r in runs),
        "oracle_errors": sum(bool(r["oracle_error"]) for r in runs),
        "oracle_retried": sum(r["oracle_factor"] not in (None, 1.0) for r in runs),
        "worst_excess_cycles": max(excess) if excess else None,
        "worst_duration_excess_relative": max(relative) if relative else None,
        "asymmetric": len(asymmetric),
        "asymmetric_reached": sum(r["reached"] for r in asymmetric),
        "asymmetric_violations": sum(bool(r["violations"]) for r in asymmetric),
        "asymmetric_duration_ratio_median": float(np.median(asym_time)) if asym_time else None,
        "asymmetric_duration_ratio_max": max(asym_time) if asym_time else None,
        "move_cycles_median": float(np.median(cycles)) if cycles else None,
        "move_cycles_max": max(cycles) if cycles else None,
        "ruckig_plan_us_median": _median(r["ruckig_plan_us"] for r in runs),
        "ruckig_plan_us_warm_median": _median(r["ruckig_plan_us_warm"] for r in runs),
        "our_plan_us_median": _median(r["our_plan_us"] for r in runs),
        "our_plan_us_warm_median": _median(r["our_plan_us_warm"] for r in runs),
        "failures": failures[:keep],
    }


def _median(values: Iterable[float | None]) -> float | None:
    kept = [v for v in values if v is not None]
    return float(np.median(kept)) if kept else None
