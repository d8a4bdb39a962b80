"""Run a benchmark by name, judge it against its goals (docs/benchmarks.md), render a table.

The CLI (``openmotion bench NAME [--json]``) calls ``run_benchmark`` and ``render`` and holds
no logic of its own. Every result is one JSON-serialisable dict: the figures, the machine,
the goals with their verdicts, and ``passed``.
"""

from __future__ import annotations

import importlib.metadata
import math
import os
import platform
import sys
from collections.abc import Callable
from contextvars import ContextVar
from typing import Any

import numpy as np
import ruckig

from openmotion.bench.axes import run_axes
from openmotion.bench.ca import run_ca
from openmotion.bench.envs import QUICK_COUNTS as ENVS_QUICK_COUNTS
from openmotion.bench.envs import run_envs
from openmotion.bench.fbcall import run_fbcall
from openmotion.bench.otg import ORACLE_GRACE as OTG_ORACLE_GRACE
from openmotion.bench.otg import run_otg
from openmotion.bench.path import run_path
from openmotion.bench.planar import run_planar
from openmotion.bench.startup import run_startup
from openmotion.bench.sweep import run_sweep_bench
from openmotion.bench.trace import FLAT_MB, MEMORY_CYCLES, run_trace
from openmotion.bench.tracks import run_tracks

Progress = Callable[[str], None] | None

#: the goals of docs/benchmarks.md
AXES_GOAL_N = 1000
AXES_GOAL_US = 0.5
AXES_STEP_GOAL_US = 2.0  #: issue #24: step() of one moving axis, the fixed cost per cycle
AXES_STEPPED_RATIO_FROM_N = 100  #: issue #24: stepped at most pyplcopen's cost from this N on
AXES_RATIO_GOAL = 1.0  #: issue #24: ours / pyplcopen, stepped from N = 100, bulk at every N
FBCALL_GOAL_US = 2.0
CA_GOAL_N = 1000
CA_GOAL_P99_US = 500.0  #: in every gap control mode (Standard, Fast, mixed)
CA_FAST_GOAL_N = 50
CA_FAST_GOAL_P99_US = 1000.0  #: issue #19: Fast gap control within the 1 ms cycle
CA_RUCKIG_P50_RATIO = 0.7  #: 250 us cycle, N=CA_GOAL_N: p50 at most this times the ruckig loop's
CA_RUCKIG_P99_RATIO = 1.0  #: ... and p99 at most this times the ruckig loop's
CA_SMALL_N = 10
CA_SMALL_P50_US = 30.0  #: 250 us cycle: a 10-mover rail's cycle p50
PLANAR_GOAL_N = 100
PLANAR_ADMISSION_GOAL_US = 50.0
PLANAR_GOAL_P99_US = 250.0
PLANAR_LARGE_N = 1000  #: issue #24: 1000 planar movers in one group
PLANAR_LARGE_P99_US = 1000.0  #: ... within the 1 ms cycle
PATH_GOAL_SEGMENTS = 10_000
PATH_GOAL_P99_US = 100.0  #: issue #24 (#7: 200): planner work per cycle, 10 000 segments
PATH_GOAL_PREPARE_S = 1.5  #: issue #24: MC_PathSelect and the MovePath start together
PATH_GOAL_SPEED_SHARE = 0.95  #: issue #24: mean path speed over the axes' steady bound
TRACKS_GOAL_N = 100
TRACKS_GOAL_P99_US = 500.0  #: issue #8: 100 movers on a network with 4 switches
TRACKS_LARGE_N = 1000  #: issue #24: 1000 movers on tracks (ten ovals, D-285)
TRACKS_LARGE_P99_US = 1000.0  #: ... within the 1 ms cycle
QUICK_MEMORY_CYCLES = 20_000  #: samples of the trace memory part with --quick
TRACE_GOAL_US = 1000.0  #: 100 axes, 100 signals recorded every 1 ms cycle: faster than real time
STARTUP_CHECK_GOAL_S = 1.0  #: issue #18: warm `openmotion check` of the default example
STARTUP_RUN_GOAL_S = 1.5  #: warm `openmotion run` of the default example
STARTUP_LARGE_GOAL_S = 2.0  #: warm `openmotion check` of a 1 MB scenario
STARTUP_FIRST_GOAL_S = 10.0  #: first run of any shipped example, with the package's cache
SWEEP_POOL_GOAL_EFFICIENCY = 0.5  #: issue #23: the pool's points/s per worker over serial's
SWEEP_RAY_GOAL_EFFICIENCY = 0.25  #: the same on Ray, whose tasks cost more to dispatch
QUICK_SWEEP_POINTS = 20  #: --quick: points, and no Ray cluster
ENVS_QUICK_SECONDS = 0.3  #: --quick: timing budget per environment and mover count [s]


def _axes(quick: bool, progress: Progress) -> dict[str, Any]:
    if quick:
        return run_axes(counts=(1, 10, 100), cycles=200, trace=True, repeats=1,
                        progress=progress)
    return run_axes(trace=True, progress=progress)


def _otg(quick: bool, progress: Progress) -> dict[str, Any]:
    if quick:
        return run_otg(samples=25, asymmetric_samples=10, progress=progress)
    return run_otg(samples=2000, progress=progress)


def _fbcall(quick: bool, progress: Progress) -> dict[str, Any]:
    if progress is not None:
        progress("fbcall: timing MC_MoveAbsolute and Runtime.step")
    return run_fbcall(calls=2000 if quick else 200_000)


def _ca(quick: bool, progress: Progress) -> dict[str, Any]:
    if quick:
        return run_ca(counts=(10, CA_FAST_GOAL_N), cycles=300, progress=progress)
    return run_ca(progress=progress)


def _planar(quick: bool, progress: Progress) -> dict[str, Any]:
    if quick:
        return run_planar(counts=(4, 12), cycles=400, commands=100, progress=progress)
    return run_planar(progress=progress)


def _path(quick: bool, progress: Progress) -> dict[str, Any]:
    return run_path(segments=200 if quick else PATH_GOAL_SEGMENTS, progress=progress)


def _tracks(quick: bool, progress: Progress) -> dict[str, Any]:
    if quick:
        return run_tracks(counts=(12,), cycles=300, progress=progress)
    return run_tracks(progress=progress)


def _trace(quick: bool, progress: Progress, cycles: int | None = None) -> dict[str, Any]:
    """``cycles``: samples of the memory part (default MEMORY_CYCLES, quick 20 000)."""
    if quick:
        return run_trace(samples=200, counts=(10, 100), cycles=200, progress=progress,
                         memory_cycles=cycles or QUICK_MEMORY_CYCLES)
    return run_trace(progress=progress, memory_cycles=cycles or MEMORY_CYCLES)


def _startup(quick: bool, progress: Progress, cold_examples: bool = True) -> dict[str, Any]:
    if quick:
        return run_startup(repeats=1, cold_repeats=1, every_example=False, progress=progress)
    return run_startup(progress=progress, cold_examples=cold_examples)


def _sweep(quick: bool, progress: Progress) -> dict[str, Any]:
    from openmotion.sweep import require_extra

    require_extra(ray=not quick)
    if quick:
        return run_sweep_bench(points=QUICK_SWEEP_POINTS, ray=False, progress=progress)
    return run_sweep_bench(progress=progress)


def _routing(quick: bool, progress: Progress) -> dict[str, Any]:
    from openmotion.bench.routing import run_routing

    if quick:
        return run_routing(seeds=1, big=(12,), big_seeds=1, progress=progress)
    return run_routing(progress=progress)


def _serve(quick: bool, progress: Progress) -> dict[str, Any]:
    from openmotion.bench.serve import run_serve

    if quick:
        return run_serve(axes=10, seconds=2.0, progress=progress)
    return run_serve(progress=progress)


def _envs(quick: bool, progress: Progress) -> dict[str, Any]:
    if quick:
        return run_envs(counts=ENVS_QUICK_COUNTS, seconds=ENVS_QUICK_SECONDS, progress=progress)
    return run_envs(progress=progress)


#: the benchmarks that take ``cycles`` (the length of their long run)
LONG_RUNS = ("trace",)
#: what ``bench all`` changes in a benchmark to keep the whole run within about 15 minutes
#: on a 2-core machine (D-295): startup without the empty-cache run of every example
IN_SUITE: dict[str, dict[str, Any]] = {"startup": {"cold_examples": False}}
BENCHMARKS: dict[str, Callable[..., dict[str, Any]]] = {
    "axes": _axes,
    "otg": _otg,
    "fbcall": _fbcall,
    "ca": _ca,
    "planar": _planar,
    "path": _path,
    "tracks": _tracks,
    "trace": _trace,
    "startup": _startup,
    "sweep": _sweep,
    "serve": _serve,
    "envs": _envs,
    "routing": _routing,
}


def machine() -> dict[str, Any]:
    """What the figures were measured on (absolute times drift between machines)."""
    try:
        plc: str | None = importlib.metadata.version("pyplcopen")
    except importlib.metadata.PackageNotFoundError:
        plc = None
    return {
        "cpu_count": os.cpu_count(),
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "numpy": np.__version__,
        "ruckig": ruckig.__version__,
        "pyplcopen": plc,
    }


def _goal(goal: str, value: Any, passed: bool | None) -> dict[str, Any]:
    """One goal line; ``passed`` None means it could not be judged (shown, not passed)."""
    return {"goal": goal, "value": value, "passed": passed}


def _rounded(ratio: float | None) -> float | None:
    """A ratio as a goal line shows it (by N, three decimals)."""
    return None if ratio is None else round(ratio, 3)


def goals_axes(results: dict[str, Any]) -> dict[str, Any]:
    by_n = results["by_n"]
    row = by_n.get(str(AXES_GOAL_N))
    violations = sum(r["violations"] for r in by_n.values())
    rejected = sum(r["check"]["rejected"] for r in by_n.values())
    goals = {
        "violations": _goal("no setpoint beyond the command's limits (all N)", violations,
                            violations == 0),
        "rejected": _goal("no command rejected (all N)", rejected, rejected == 0),
    }
    step = results.get("step_one_axis")
    if step is not None:
        goals["step_one_axis"] = _goal(
            f"step() of 1 moving axis <= {AXES_STEP_GOAL_US} us", step["ours_us"],
            step["ours_us"] <= AXES_STEP_GOAL_US)
    stepped = {n: _rounded(r["ratio_pyplcopen"]) for n, r in by_n.items()
               if int(n) >= AXES_STEPPED_RATIO_FROM_N}
    if stepped:
        goals["stepped_ratio_pyplcopen"] = _goal(
            f"stepped: ours / pyplcopen <= {AXES_RATIO_GOAL} for N >= "
            f"{AXES_STEPPED_RATIO_FROM_N} (trace off)", stepped,
            None if None in stepped.values() else
            all(ratio <= AXES_RATIO_GOAL for ratio in stepped.values()))
    bulk = {n: _rounded(r.get("ratio_bulk_pyplcopen")) for n, r in by_n.items()}
    if bulk:
        goals["bulk_ratio_pyplcopen"] = _goal(
            f"bulk: ours / pyplcopen (cycle(n)) <= {AXES_RATIO_GOAL} at every N (trace off)",
            bulk, None if None in bulk.values() else
            all(ratio <= AXES_RATIO_GOAL for ratio in bulk.values()))
        unequal = [int(n) for n, r in by_n.items() if not r.get("bulk_equal", False)]
        goals["bulk_equal"] = _goal("bulk runs end on the stepped runs' setpoints bit for bit "
                                    "(all N)", unequal or "all equal", not unequal)
    if row is None:
        return goals
    ours, plc = row["ours_us"], row["pyplcopen_us"]
    goals["us_per_axis_cycle"] = _goal(
        f"N={AXES_GOAL_N}: <= {AXES_GOAL_US} us/axis-cycle (trace off)", ours,
        ours <= AXES_GOAL_US)
    goals["ratio_pyplcopen"] = _goal(
        f"N={AXES_GOAL_N}: below pyplcopen (ratio < 1, trace off)", row["ratio_pyplcopen"],
        None if plc is None else ours < plc)
    return goals


def goals_otg(results: dict[str, Any]) -> dict[str, Any]:
    n = results["samples"]
    asym = results["acc_ne_dec"]
    return {
        "reached": _goal("every sample reaches its target bit-exactly", results["reached"],
                         results["reached"] == n),
        "time_ok": _goal("acc == dec: cycles <= ceil(ruckig duration) + 1",
                         f"{results['time_ok']}/{results['time_judged']}",
                         results["time_ok"] == results["time_judged"]),
        "violations": _goal("no |v|, |a|, |j| beyond the limits (1e-9 rel.)",
                            results["violations"], results["violations"] == 0),
        "command_errors": _goal("no target move rejected", results["command_errors"],
                                results["command_errors"] == 0),
        "slower_than_min": _goal("acc != dec: none slower than min(acc, dec) + 1 cycle",
                                 asym["slower_than_min"], asym["slower_than_min"] == 0),
        "oracle_p99": _goal("acc != dec: p99 within 1 % + 1 cycle of the oracle (D-201)",
                            asym["oracle_graced_p99"],
                            asym["oracle_graced_p99"] is None
                            or asym["oracle_graced_p99"] <= 1.0 + OTG_ORACLE_GRACE),
        "direction_violations": _goal(
            "acc != dec: |a| <= dec while |v| falls, <= acc otherwise, every sample",
            asym["violations"], asym["violations"] == 0),
    }


def goals_fbcall(results: dict[str, Any]) -> dict[str, Any]:
    value = results["fb_call_us"]
    return {"fb_call_us": _goal(f"MC_MoveAbsolute, unchanged inputs: <= {FBCALL_GOAL_US} us",
                                value, value <= FBCALL_GOAL_US)}


def goals_ca(results: dict[str, Any]) -> dict[str, Any]:
    by_n, modes = results["by_n"], results["modes"]
    fine = results.get("by_n_250us", {})
    rows = [r[mode] for table in (by_n, fine) for r in table.values() for mode in modes]
    gaps = sum(r["gap_violations"] for r in rows)
    limits = sum(r["limit_violations"] for r in rows)
    goals = {
        "gap_violations": _goal("no setpoint gap below the gap (all N, every mode, both "
                                "cycle times)", gaps, gaps == 0),
        "limit_violations": _goal("no mover beyond its own limits (all N, every mode, both "
                                  "cycle times)", limits, limits == 0),
    }
    row = fine.get(str(CA_GOAL_N))
    if row is not None:  # every mode against the plain ruckig loop of the same movers
        for mode in modes:
            for key, bound in (("p50", CA_RUCKIG_P50_RATIO), ("p99", CA_RUCKIG_P99_RATIO)):
                ratio = row[f"{mode}_over_ruckig"][key]
                goals[f"cycle_{key}_250us_{mode}_over_ruckig"] = _goal(
                    f"N={CA_GOAL_N}, 250 us, {mode}: cycle {key} <= {bound:g} x the ruckig "
                    "loop's", ratio, ratio <= bound)
    row = fine.get(str(CA_SMALL_N))
    if row is not None:
        for mode in modes:
            p50 = row[mode]["cycle_us_p50"]
            goals[f"cycle_p50_250us_small_{mode}"] = _goal(
                f"N={CA_SMALL_N}, 250 us, {mode}: cycle p50 <= {CA_SMALL_P50_US:g} us", p50,
                p50 <= CA_SMALL_P50_US)
    row = by_n.get(str(CA_GOAL_N))
    if row is not None:  # every mode meets Standard's goal
        for mode in modes:
            p99 = row[mode]["cycle_us_p99"]
            key = "cycle_p99" if mode == "standard" else f"cycle_p99_{mode}"
            goals[key] = _goal(f"N={CA_GOAL_N}, {mode}: cycle p99 < {CA_GOAL_P99_US:g} us", p99,
                               p99 < CA_GOAL_P99_US)
    row = by_n.get(str(CA_FAST_GOAL_N))
    if row is not None and "fast" in row:
        p99 = row["fast"]["cycle_us_p99"]
        goals["cycle_p99_fast_small"] = _goal(
            f"N={CA_FAST_GOAL_N}, fast: cycle p99 < {CA_FAST_GOAL_P99_US:g} us (the 1 ms cycle)",
            p99, p99 < CA_FAST_GOAL_P99_US)
    return goals


def goals_planar(results: dict[str, Any]) -> dict[str, Any]:
    rows = [*results["by_n"].values(), *results["translation"].values()]
    overlaps = sum(r["overlaps"] for r in rows)
    off = sum(r["off_surface"] for r in rows)
    admissions = [r["admission"] for r in results["by_n"].values()]
    wrong = sum(a["mismatches"] + a["overlaps"] for a in admissions)
    goals = {
        "overlaps": _goal("no two footprints overlap (all N, every cycle)", overlaps,
                          overlaps == 0),
        "off_surface": _goal("no footprint leaves the stator surface (all N, every cycle)", off,
                             off == 0),
        "admission_checked": _goal("admissions agree with the shapely reference, no reserved "
                                   "areas overlap (all N)", wrong, wrong == 0),
    }
    row = results["by_n"].get(str(PLANAR_GOAL_N))
    if row is not None:
        admission = row["admission"]["admission_us_p50"]
        goals["admission_us"] = _goal(
            f"N={PLANAR_GOAL_N}: admission check p50 < {PLANAR_ADMISSION_GOAL_US:g} us",
            admission, admission < PLANAR_ADMISSION_GOAL_US)
        p99 = row["cycle_us_p99"]
        goals["cycle_p99"] = _goal(f"N={PLANAR_GOAL_N}: cycle p99 < {PLANAR_GOAL_P99_US:g} us "
                                   "(moves with c)", p99, p99 < PLANAR_GOAL_P99_US)
    large = results["by_n"].get(str(PLANAR_LARGE_N))
    if large is not None:
        admission = large["admission"]["admission_us_p50"]
        goals["admission_us_large"] = _goal(
            f"N={PLANAR_LARGE_N}: admission check p50 < {PLANAR_ADMISSION_GOAL_US:g} us",
            admission, admission < PLANAR_ADMISSION_GOAL_US)
        p99 = large["cycle_us_p99"]
        goals["cycle_p99_large"] = _goal(
            f"N={PLANAR_LARGE_N}: cycle p99 < {PLANAR_LARGE_P99_US:g} us (moves with c)", p99,
            p99 < PLANAR_LARGE_P99_US)
    if row is not None and large is not None:
        growth = _growth(row["cycle_us_mean"], large["cycle_us_mean"],
                         PLANAR_LARGE_N / PLANAR_GOAL_N)
        goals["cycle_linear"] = _goal(
            f"mean cycle grows no faster than N from {PLANAR_GOAL_N} to {PLANAR_LARGE_N} "
            "(ratio of the growth to N's, < 1)", growth, growth < 1.0)
        growth = _growth(row["admission"]["admission_us_p50"],
                         large["admission"]["admission_us_p50"], PLANAR_LARGE_N / PLANAR_GOAL_N)
        goals["admission_linear"] = _goal(
            f"admission p50 grows no faster than N from {PLANAR_GOAL_N} to {PLANAR_LARGE_N} "
            "(ratio of the growth to N's, < 1)", growth, growth < 1.0)
    return goals


def _growth(small: float, large: float, factor: float) -> float:
    """How much faster than ``factor`` (the growth of N) a cost grew from ``small`` to
    ``large``: below 1, no faster than linearly."""
    return large / small / factor


def goals_path(results: dict[str, Any]) -> dict[str, Any]:
    goals = {
        "limit_violations": _goal("no axis beyond its velocity, acceleration or jerk limit",
                                  results["limit_violations"], results["limit_violations"] == 0),
        "end": _goal("the path ends at its last point (< 1e-9 mm)", results["end_error_mm"],
                     results["done"] and results["end_error_mm"] < 1e-9),
    }
    if results["segments"] >= PATH_GOAL_SEGMENTS:
        p99 = results["planner_us_p99"]
        goals["planner_p99"] = _goal(f"{PATH_GOAL_SEGMENTS} segments: planner work per cycle "
                                     f"p99 <= {PATH_GOAL_P99_US:g} us", p99,
                                     p99 is not None and p99 <= PATH_GOAL_P99_US)
        prepare = results["select_ms"] / 1e3 + results["start_us"] / 1e6
        goals["prepare"] = _goal(f"{PATH_GOAL_SEGMENTS} segments: MC_PathSelect and the start "
                                 f"together <= {PATH_GOAL_PREPARE_S:g} s", prepare,
                                 prepare <= PATH_GOAL_PREPARE_S)
        share = results["mean_path_velocity"] / results["steady_bound_velocity"]
        goals["speed"] = _goal(f"mean path speed >= {PATH_GOAL_SPEED_SHARE:.0%} of the axes' "
                               "steady bound", share, share >= PATH_GOAL_SPEED_SHARE)
    return goals


def goals_tracks(results: dict[str, Any]) -> dict[str, Any]:
    rows = list(results["by_n"].values())
    overlaps = sum(r["overlaps"] for r in rows)
    gaps = sum(r["gap_violations"] for r in rows)
    goals = {
        "overlaps": _goal("no two footprints overlap (switches included, every cycle)",
                          overlaps, overlaps == 0),
        "gaps": _goal("no two movers on a track closer than the gap (every cycle)", gaps,
                      gaps == 0),
    }
    row = results["by_n"].get(str(TRACKS_GOAL_N))
    if row is not None:
        p99 = row["cycle_us_p99"]
        goals["cycle_p99"] = _goal(f"N={TRACKS_GOAL_N}, 4 switches: cycle p99 < "
                                   f"{TRACKS_GOAL_P99_US:g} us", p99, p99 < TRACKS_GOAL_P99_US)
    large = results["by_n"].get(str(TRACKS_LARGE_N))
    if large is not None:
        p99 = large["cycle_us_p99"]
        goals["cycle_p99_large"] = _goal(
            f"N={TRACKS_LARGE_N}, {large['switches']} switches: cycle p99 < "
            f"{TRACKS_LARGE_P99_US:g} us", p99, p99 < TRACKS_LARGE_P99_US)
    if row is not None and large is not None:
        growth = _growth(row["cycle_us_mean"], large["cycle_us_mean"],
                         TRACKS_LARGE_N / TRACKS_GOAL_N)
        goals["cycle_linear"] = _goal(
            f"mean cycle grows no faster than N from {TRACKS_GOAL_N} to {TRACKS_LARGE_N} "
            "(ratio of the growth to N's, < 1)", growth, growth < 1.0)
    return goals


def goals_trace(results: dict[str, Any]) -> dict[str, Any]:
    goal = results["goal"]
    cycle = goal["cycle_us"]["every_cycle"]
    return {"real_time": _goal(f"{goal['axes']} axes + {goal['signals']} signals recorded "
                               f"every cycle: cycle < {TRACE_GOAL_US:g} us (faster than real "
                               "time)", cycle, cycle < TRACE_GOAL_US),
            **{f"memory_{row['mode']}": _goal(
                f"{row['mode']}: RSS grows < {FLAT_MB:g} MiB after the first tenth of "
                f"{row['samples']} samples of {row['signals']} signals (memory flat)",
                row["growth_mb"], row["flat"])
               for row in results["memory"] if row["mode"] != "unbounded"}}


def goals_startup(results: dict[str, Any]) -> dict[str, Any]:
    warm = results["warm"]
    check, run = warm["check"]["median_s"], warm["run"]["median_s"]
    large = warm["check_1mb"]["median_s"]
    firsts = results["first"]
    slowest = max(firsts, key=firsts.__getitem__)
    return {
        "check": _goal(f"warm `openmotion check`: <= {STARTUP_CHECK_GOAL_S:g} s (median)", check,
                       check <= STARTUP_CHECK_GOAL_S),
        "run": _goal(f"warm `openmotion run`: <= {STARTUP_RUN_GOAL_S:g} s (median)", run,
                     run <= STARTUP_RUN_GOAL_S),
        "check_1mb": _goal(f"warm `openmotion check` of a 1 MB scenario: <= "
                           f"{STARTUP_LARGE_GOAL_S:g} s (median)", large,
                           large <= STARTUP_LARGE_GOAL_S),
        "first": _goal(f"first run of every example, the package's kernel cache: <= "
                       f"{STARTUP_FIRST_GOAL_S:g} s (slowest: {slowest})", firsts[slowest],
                       firsts[slowest] <= STARTUP_FIRST_GOAL_S),
    }


def goals_sweep(results: dict[str, Any]) -> dict[str, Any]:
    workers = results["workers"]
    pool = results["pool"]["efficiency_per_worker"]
    goals = {"pool": _goal(f"process pool, {workers} workers: efficiency per worker >= "
                           f"{SWEEP_POOL_GOAL_EFFICIENCY:g} (points/s over {workers} x "
                           "serial)", pool, pool >= SWEEP_POOL_GOAL_EFFICIENCY)}
    ray = results["ray"]
    if ray is not None:
        efficiency = ray["next"]["efficiency_per_worker"]
        goals["ray"] = _goal(f"Ray, {workers} CPUs, the next sweep on a standing cluster: "
                             f"efficiency per worker >= {SWEEP_RAY_GOAL_EFFICIENCY:g}",
                             efficiency, efficiency >= SWEEP_RAY_GOAL_EFFICIENCY)
        goals["same_table"] = _goal("Ray's table equals the pool's (timing columns aside)",
                                    ray["same_table"], ray["same_table"])
    return goals


SERVE_GOAL_LATE_P99_MS = 1.0  #: issue 22: p99 motion-cycle lateness under load by two clients


def goals_serve(results: dict[str, Any]) -> dict[str, Any]:
    """Judged on the kernel process (what ``serve`` runs); the kernel thread is shown."""
    late = results["late_p99_ms"]
    lost = results["opcua"]["lost"]
    return {"lateness": _goal(f"p99 motion-cycle lateness < {SERVE_GOAL_LATE_P99_MS:g} ms "
                              f"({results['axes']} axes, 1 ms cycle, both clients reading, "
                              "the kernel in its own process)",
                              late, late < SERVE_GOAL_LATE_P99_MS),
            "lost": _goal("0 lost OPC UA notifications", lost, lost == 0)}


def goals_envs(results: dict[str, Any]) -> dict[str, Any]:
    rows = results["by_n"]
    measured = [n for n, r in rows.items() if r["ours"]["steps"] > 0]
    goals = {"measured": _goal("environment steps/s measured at every N", ", ".join(measured),
                               len(measured) == len(rows))}
    if results["magbotsim"]["version"] is None:
        goals["magbotsim"] = _goal("beside MagBotSim's environment step, same run",
                                   results["magbotsim"]["unavailable"], None)
        return goals
    slower = [n for n, r in rows.items() if r["ratio_steps_per_s"] < 1.0]
    goals["magbotsim"] = _goal(
        f"env steps/s at least MagBotSim {results['magbotsim']['version']}'s at every N "
        "(same run, same field)", ", ".join(f"{n}: {r['ratio_steps_per_s']:.2f}x"
                                            for n, r in rows.items()), not slower)
    return goals


ROUTING_GOAL_FIRST_PLAN_MS = 200.0  #: first plan at 78 movers [ms]
ROUTING_GOAL_RATIO_LAYOUTS = 1.3  #: makespan / lower bound on MagBotSim's layouts
ROUTING_GOAL_RATIO_BIG = 1.5  #: makespan / lower bound at 78 movers


def goals_routing(results: dict[str, Any]) -> dict[str, Any]:
    small, big = results["summary"]["magbotsim"], results["summary"].get("big") or {}
    parts = [p for p in (small, big) if p]
    success = min(p["success_rate"] for p in parts)
    rejected = sum(p["rejected"] for p in parts)
    overlaps = sum(p["overlaps"] + p["off_surface"] for p in parts)
    goals = {
        "success": _goal("every mover arrives (all instances)", success, success == 1.0),
        "rejected": _goal("no command refused by the group", rejected, rejected == 0),
        "overlaps": _goal("no footprints overlap or leave the surface (every cycle)", overlaps,
                          overlaps == 0),
        "ratio_layouts": _goal(f"MagBotSim layouts: makespan <= {ROUTING_GOAL_RATIO_LAYOUTS:g} x "
                               "lower bound (worst instance)", small["ratio_max"],
                               _at_most(small["ratio_max"], ROUTING_GOAL_RATIO_LAYOUTS)),
    }
    if big:
        goals["first_plan_big"] = _goal(
            f"{BIG_GOAL_N} movers: first plan <= {ROUTING_GOAL_FIRST_PLAN_MS:g} ms",
            big["first_plan_ms_max"], _at_most(big["first_plan_ms_max"],
                                               ROUTING_GOAL_FIRST_PLAN_MS))
        goals["ratio_big"] = _goal(f"{BIG_GOAL_N} movers: makespan <= "
                                   f"{ROUTING_GOAL_RATIO_BIG:g} x lower bound", big["ratio_max"],
                                   _at_most(big["ratio_max"], ROUTING_GOAL_RATIO_BIG))
    return goals


BIG_GOAL_N = 78  #: the Planar-Motor-scale case of the routing benchmark


def _at_most(value: float | None, goal: float) -> bool:
    """A figure that could not be measured (None: no plan, or not every mover arrived)
    misses its goal."""
    return value is not None and value <= goal


GOALS: dict[str, Callable[[dict[str, Any]], dict[str, Any]]] = {
    "axes": goals_axes,
    "otg": goals_otg,
    "fbcall": goals_fbcall,
    "ca": goals_ca,
    "planar": goals_planar,
    "path": goals_path,
    "tracks": goals_tracks,
    "trace": goals_trace,
    "startup": goals_startup,
    "sweep": goals_sweep,
    "serve": goals_serve,
    "envs": goals_envs,
    "routing": goals_routing,
}


def run_benchmark(name: str, quick: bool = False, progress: Progress = None,
                  cycles: int | None = None, in_suite: bool = False) -> dict[str, Any]:
    """Run benchmark ``name``; ``quick`` uses tiny sizes (a smoke test of a few seconds);
    ``cycles`` sets the length of the long run of the benchmarks in LONG_RUNS; ``in_suite``
    applies IN_SUITE (``bench all``)."""
    if name not in BENCHMARKS:
        raise KeyError(f"unknown benchmark {name!r}; choose one of {sorted(BENCHMARKS)}")
    if cycles is not None and name not in LONG_RUNS:
        raise ValueError(f"cycles: only for {', '.join(LONG_RUNS)}, not {name!r}")
    options: dict[str, Any] = {} if cycles is None else {"cycles": cycles}
    if in_suite:
        options.update(IN_SUITE.get(name, {}))
    results = BENCHMARKS[name](quick, progress, **options)
    goals = GOALS[name](results)
    return {
        "benchmark": name,
        "quick": quick,
        "machine": machine(),
        "results": results,
        "goals": goals,
        "passed": all(g["passed"] is True for g in goals.values()),
    }


# -- rendering -------------------------------------------------------------------------------


def _fmt(value: Any, digits: int = 3) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if value.is_integer() and abs(value) < 1e9:
            return str(int(value))
        return f"{value:.{digits}g}" if abs(value) >= 1e4 or 0 < abs(value) < 1e-3 \
            else f"{value:.{digits}f}"
    return str(value)


#: set by render_figures: the renderers' tables come out as GitHub markdown (the docs' figures)
_MARKDOWN: ContextVar[bool] = ContextVar("markdown tables", default=False)


def _table(header: list[str], rows: list[list[Any]]) -> list[str]:
    if _MARKDOWN.get():  # blank lines around it: a table must not continue a paragraph
        cells = [[_fmt(c).replace("|", "\\|") for c in row] for row in rows]
        return ["", f"| {' | '.join(header)} |", "|" + "---|" * len(header),
                *(f"| {' | '.join(row)} |" for row in cells), ""]
    cells = [header] + [[_fmt(c) for c in row] for row in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) if i == 0 and not c.lstrip("-").isdigit() else c.rjust(w)
                       for i, (c, w) in enumerate(zip(r, widths, strict=True))).rstrip()
             for r in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return lines


def _render_axes(results: dict[str, Any]) -> list[str]:
    trace = results["trace"]
    header = ["N", "cycles", "commands", "ours", *(["ours+trace"] if trace else []),
              "pyplcopen", "ruckig", "ours/plc", "ours/ruckig", "cycle p50", "cycle p99",
              "violations", "rejected"]
    rows = []
    for n, r in results["by_n"].items():
        rows.append([int(n), r["cycles"], r["commands"], r["ours_us"],
                     *([r["ours_trace_us"]] if trace else []),
                     r["pyplcopen_us"], r["ruckig_us"], r["ratio_pyplcopen"],
                     r["ratio_ruckig"], r["ours"]["cycle_us_p50"], r["ours"]["cycle_us_p99"],
                     r["violations"], r["check"]["rejected"]])
    lines = []
    step = results.get("step_one_axis")
    if step is not None:
        lines += [f"step() of 1 moving axis: {_fmt(step['ours_us'])} us (median), "
                  f"{_fmt(step['ours_best_us'])} us (fastest)", ""]
    lines += [f"stepped: us per axis-cycle (wall loop time / (N * cycles)), median of "
              f"{results.get('repeats', 1)} repeats; cycle p50/p99 in us (ours, trace off)"]
    lines += _table(header, rows)
    bulk = [[int(n), r["ours_bulk_us"], *([r["ours_bulk_trace_us"]] if trace else []),
             r["pyplcopen_bulk_us"], r["ratio_bulk_pyplcopen"], r["ours_bulk_best_us"],
             r["pyplcopen_bulk_best_us"], r["ratio_best_bulk_pyplcopen"],
             "yes" if r["bulk_equal"] else "NO"]
            for n, r in results["by_n"].items() if "ours_bulk_us" in r]
    if bulk:
        lines += ["", "bulk: the stretch between two commands in one call (ours Runtime.run, "
                  "pyplcopen cycle(n)); us per axis-cycle, median; best = fastest repeat"]
        lines += _table(["N", "ours", *(["ours+trace"] if trace else []), "pyplcopen",
                         "ours/plc", "ours best", "plc best", "best ratio", "= stepped"], bulk)
    best = [[int(n), r["ours_spread"], r["ours_cpu_us"], r["ours_best_us"],
             *([r["ours_trace_best_us"]] if trace else []), r["pyplcopen_best_us"],
             r["ruckig_best_us"], r["ratio_best_pyplcopen"], r["ratio_best_ruckig"]]
            for n, r in results["by_n"].items()]
    lines += ["", "fastest repeat (least disturbed by other load); spread = (max - min) / median; "
              "ours cpu = thread CPU time, median"]
    lines += _table(["N", "ours spread", "ours cpu", "ours", *(["ours+trace"] if trace else []),
                     "pyplcopen", "ruckig", "ours/plc", "ours/ruckig"], best)
    for n, r in results["by_n"].items():
        check = r["check"]
        forced = check["forced_overshoot"]
        if check["jerk_raise_allowed"]:
            lines.append(f"N={n}: {check['jerk_raise_allowed']} commands whose jerk may be raised "
                         f"to keep max_velocity (D-020)")
        if forced["axis_cycles"]:
            lines.append(f"N={n}: {forced['axis_cycles']} axis-cycles above max_velocity, forced "
                         f"even with max_jerk (peak {forced['peak_velocity']:.1f})")
        if r.get("ruckig_error"):
            lines.append(f"N={n}: ruckig peer failed: {r['ruckig_error'][:160]}")
    return lines


def _render_otg(results: dict[str, Any]) -> list[str]:
    r = results
    rows = [
        ["samples (1-DoF)", r["samples"]],
        ["reached exactly", r["reached"]],
        ["acc == dec, time judged", r["time_judged"]],
        ["  within ceil(ruckig) + 1 cycle", r["time_ok"]],
        ["  worst excess over ceil(ruckig) [cycles]", r["worst_excess_cycles"]],
        ["  worst plan duration vs ruckig (relative)", r["worst_duration_excess_relative"]],
        ["acc != dec samples", r["asymmetric"]],
        ["  reached", r["asymmetric_reached"]],
        ["  duration / ruckig mapped, median", r["asymmetric_duration_ratio_median"]],
        ["  duration / ruckig mapped, max", r["asymmetric_duration_ratio_max"]],
    ]
    for name, key in (("acc != dec", "acc_ne_dec"), ("reversals", "reversals")):
        a = r[key]
        rows += [
            [f"{name}: cases (judged by the oracle)", f"{a['cases']} ({a['judged']})"],
            ["  slower than min(acc, dec) + 1 cycle", a["slower_than_min"]],
            ["  duration / oracle: median / p99 / max",
             f"{_fmt(a['oracle_ratio_median'], 5)} / {_fmt(a['oracle_ratio_p99'], 5)} / "
             f"{_fmt(a['oracle_ratio_max'], 5)}"],
            ["  (duration - 1 cycle) / oracle, p99", _fmt(a["oracle_graced_p99"], 5)],
            ["  beyond oracle x 1.01 + 1 cycle", a["beyond_oracle_grace"]],
            ["  faster than the oracle (its misses)", a["below_oracle"]],
            ["  duration / min(acc, dec) plan: median / max",
             f"{_fmt(a['min_ratio_median'], 5)} / {_fmt(a['min_ratio_max'], 5)}"],
            ["  samples with a limit violation", a["violations"]],
        ]
    rows += [
        ["samples with a limit violation", r["violations"]],
        ["target moves rejected", r["command_errors"]],
        ["pre-moves rejected (start from rest)", r["pre_move_errors"]],
        ["ruckig needed limits lowered by <= 1e-8 rel.", r["oracle_retried"]],
        ["ruckig failed on the start state (not judged)", r["oracle_errors"]],
        ["move cycles median / max", f"{_fmt(r['move_cycles_median'])} / "
                                     f"{_fmt(r['move_cycles_max'])}"],
        ["plan us: ruckig calculate (in situ / warm)", f"{_fmt(r['ruckig_plan_us_median'])} / "
                                                        f"{_fmt(r['ruckig_plan_us_warm_median'])}"],
        ["plan us: our move_absolute (first call)", r["our_plan_us_median"]],
        ["plan us: our move_absolute (warm)", r["our_plan_us_warm_median"]],
        ["plan us: our move_absolute, reversals (warm)", r["reversal_plan_us_warm_median"]],
    ]
    lines = _table(["figure", "value"], rows)
    for f in r["failures"]:
        lines.append(f"FAIL sample {f['sample']['index']}: reached={f['reached']} "
                     f"cycles={f['cycles']} bound={f['bound_cycles']} "
                     f"violations={f['violations']} start={f['start']} "
                     f"target={f['sample']['target']!r} error={f['command_error'][:80]}")
    return lines


def _render_fbcall(results: dict[str, Any]) -> list[str]:
    r = results
    rows = [
        ["MC_MoveAbsolute(axis, execute=True, ...) us/call", r["fb_call_us"]],
        ["MC_MoveAbsolute() on stored inputs us/call", r["fb_call_bare_us"]],
        ["empty Python call us (loop floor)", r["empty_call_us"]],
        ["Runtime.step(), 1 moving axis, us", r["step_1_axis_us"]],
    ]
    return _table(["figure", "value"], rows)


def _render_ca(results: dict[str, Any]) -> list[str]:
    header = ["N", "mode", "cycles", "commands", "done", "cycle p50", "cycle p99", "cpu p50",
              "cpu p99", "p50 / std", "p99 / std", "p50 / ruckig", "p99 / ruckig", "min gap",
              "gap viol.", "limit viol."]

    def rows_of(by_n: dict[str, Any]) -> list[list[Any]]:
        rows = []
        for n, by_mode in by_n.items():
            for mode in [*results["modes"], "ruckig"]:
                r = by_mode.get(mode)
                if r is None:  # a result of a version without the reference
                    continue
                ratio = by_mode.get(f"{mode}_over_standard", {})
                reference = by_mode.get(f"{mode}_over_ruckig", {})
                rows.append([int(n), mode, r["cycles"], r["commands"], r["done"],
                             r["cycle_us_p50"], r["cycle_us_p99"], r["cpu_us_p50"],
                             r["cpu_us_p99"], ratio.get("p50"), ratio.get("p99"),
                             reference.get("p50"), reference.get("p99"), r.get("min_gap"),
                             r.get("gap_violations"), r.get("limit_violations")])
        return rows

    lines = [f"N movers on a ring of {_fmt(results['spacing'])} mm per mover, gap "
             f"{_fmt(results['gap'])} mm, random modulo targets; the commands' gap control "
             "Standard, Fast, or mixed (every second mover Fast), the three groups and the "
             "reference (ruckig: one ruckig OTG per mover, no collision avoidance) stepped in "
             "turn; cycle time in us (Runtime.step with gap control: wall, and the thread's "
             "cpu time); / std, / ruckig: ratios in the same run", "",
             "1 ms cycle", *_table(header, rows_of(results["by_n"]))]
    if "by_n_250us" in results:
        lines += ["", "250 us cycle", *_table(header, rows_of(results["by_n_250us"]))]
    return lines


def _render_planar(results: dict[str, Any]) -> list[str]:
    header = ["N", "stators", "cycles", "commands", "accepted", "rejected", "cycle p50",
              "cycle p99", "idle p99", "cmd cycle p50", "request p50", "overlaps",
              "off surface"]

    def cycle_rows(by_n: dict[str, Any]) -> list[list[Any]]:
        return [[int(n), r["stators"], r["cycles"], r["commands"], r["accepted"], r["rejected"],
                 r["cycle_us_p50"], r["cycle_us_p99"], r["idle_cycle_us_p99"],
                 r["command_cycle_us_p50"], r["request_us_p50"], r["overlaps"],
                 r["off_surface"]] for n, r in by_n.items()]

    admission = [[int(n), a["stators"], a["commands"], a["accepted"], a["rejected"],
                  a["area_us_p50"], a["admission_us_p50"], a["admission_us_p99"],
                  a["release_us_p50"], a["mismatches"]]
                 for n, a in ((n, r["admission"]) for n, r in results["by_n"].items())]
    reads = ", ".join(f"N={n}: {_fmt(r['status_read_us_p50'])}"
                      for n, r in results["by_n"].items())
    return [
        "admission check (planar_admission: ReservationRegistry.request alone), us",
        *_table(["N", "stators", "commands", "accepted", "rejected", "area p50",
                 "admission p50", "admission p99", "release p50", "mismatches"], admission),
        "",
        f"Runtime.step in us, one group with the environment, MoveToPosition to random free "
        f"stators (c in +-{_fmt(results['c_range'])} deg); idle: cycles without a new command, "
        "cmd cycle: cycles with one; request: admission inside the runtime",
        *_table(header, cycle_rows(results["by_n"])),
        "",
        "the same with translations only (target c kept: the exact, cheap swept area)",
        *_table(header, cycle_rows(results["translation"])),
        "",
        f"reading every mover's published position after a cycle, us p50: {reads}",
    ]


def _render_tracks(results: dict[str, Any]) -> list[str]:
    header = ["N", "ovals", "tracks", "switches", "cycles", "commands", "done", "errors",
              "cycle p50", "cycle p99", "cycle max", "overlaps", "gap violations", "closest"]
    rows = [[int(n), r.get("ovals", 1), r["tracks"], r["switches"], r["cycles"],
             r["commands"], r["done"], r["errors"], r["cycle_us_p50"], r["cycle_us_p99"],
             r["cycle_us_max"], r["overlaps"], r["gap_violations"], r["closest_centres_mm"]]
            for n, r in results["by_n"].items()]
    return [f"Runtime.step in us: movers on ovals with two sidings (4 switches each, up to "
            f"{results.get('oval_movers', 100)} movers an oval), random "
            f"MoveOnTrack targets, gap {_fmt(results['gap'])} mm; closest: mm between two "
            "mover centres", *_table(header, rows)]


def _render_trace(results: dict[str, Any]) -> list[str]:
    sampling = [[r["kind"], r["signals"], r["samples"], r["sample_us"], r["signal_sample_us"]]
                for r in results["sampling"]]
    goal = results["goal"]
    variants = [[name, goal["cycle_us"][name], goal["real_time_factor"][name]]
                for name in goal["cycle_us"]]
    return [
        "TraceRecorder.sample alone, us (kernel: one numpy gather per signal name; axis "
        "state and planar: one reader per signal)",
        *_table(["kind", "signals", "samples", "per sample", "per signal-sample"], sampling),
        "",
        f"{goal['axes']} axes, random commands, {goal['cycles']} cycles of "
        f"{_fmt(goal['cycle_time_us'])} us; {goal['signals']} signals recorded (off, every "
        "cycle, every 10th); Runtime.step wall time per cycle, us",
        *_table(["recording", "cycle", "real-time factor"], variants),
        f"recorder in that run: {_fmt(goal['sample_us'])} us per sample, "
        f"{_fmt(goal['signal_sample_us'])} us per signal-sample",
        "",
        "memory of a long run: TraceRecorder.sample called directly; RSS in MiB above the "
        "start, after the first tenth and at the end",
        *_table(["mode", "samples", "rows held", "RSS warm", "RSS end", "growth", "disk MiB",
                 "us per sample"],
                [[r["mode"], r["samples"], r["allocated_rows"], r["rss_mb_warm"],
                  r["rss_mb_end"], r["growth_mb"], r["disk_mb"], r["sample_us"]]
                 for r in results["memory"]]),
    ]


def _render_path(results: dict[str, Any]) -> list[str]:
    r = results
    return _table(
        ["segments", "cycles", "select ms", "start us", "planner p50", "planner p99",
         "planner max", "mean v", "caps bound v", "steady bound v", "commanded v", "at v",
         "duration s", "1-profile s", "violations"],
        [[r["segments"], r["cycles"], r["select_ms"], r["start_us"], r["planner_us_p50"],
          r["planner_us_p99"], r["planner_us_max"], r["mean_path_velocity"],
          r["caps_bound_velocity"], r["steady_bound_velocity"], r["commanded_velocity"],
          r["time_at_commanded_speed"], r["duration_s"], r["single_profile_s"],
          r["limit_violations"]]])


def _render_startup(results: dict[str, Any]) -> list[str]:
    def row(label: str, stats: dict[str, Any], ratio: float | None = None) -> list[Any]:
        return [label, stats["min_s"], stats["median_s"], stats["max_s"], stats["runs"], ratio]

    rows = [row("python -c pass (floor)", results["floors"]["python"]),
            row("import numpy, numba (floor)", results["floors"]["numpy_numba"])]
    rows += [row(f"warm: {label}", results["warm"][name], results["over_python"][name])
             for name, label in (("import", "import openmotion"),
                                 ("import_runtime", "from openmotion import Runtime"),
                                 ("check", "openmotion check"),
                                 ("check_1mb", "openmotion check, 1 MB scenario"),
                                 ("run", "openmotion run"))]
    rows.append(row("cold: openmotion run", results["cold"]["run"]))
    lines = [f"whole processes, wall seconds; warm = bytecode and kernels cached, cold = empty "
             f"kernel cache; scenario: {results['scenario']}; x python = median over the floor",
             *_table(["figure", "min", "median", "max", "runs", "x python"], rows)]
    cold = results["cold"]["examples"]
    lines += ["", "first run of each shipped example, s: with the package's kernel cache (as "
              "installed), and with an empty one (compiling every loop it uses)",
              *_table(["example", "first run", "empty cache"],
                      [[n, s, cold.get(n)] for n, s in results["first"].items()])]
    return lines


def _render_sweep(results: dict[str, Any]) -> list[str]:
    rows = [[name, results[name]["wall_s"], results[name]["points_per_s"],
             results[name]["s_per_point"] * 1000, results[name]["overhead_s_per_point"] * 1000,
             results[name]["efficiency_per_worker"],
             results[name].get("cpu_s_per_point", math.nan) * 1000]
            for name in ("serial", "pool", "ray") if results[name] is not None]
    if results["ray"] is not None and "next" in results["ray"]:
        ray = results["ray"]["next"]
        rows.append(["ray, next sweep", ray["wall_s"], ray["points_per_s"],
                     ray["s_per_point"] * 1000, ray["overhead_s_per_point"] * 1000,
                     ray["efficiency_per_worker"], math.nan])
    lines = [f"{results['points']} short points; pool and Ray with {results['workers']} "
             "workers; overhead = worker ms per point beyond the serial ms; load average "
             f"{_fmt(results['load_average'], 2)} at the start",
             *_table(["executor", "wall s", "points/s", "ms/point", "overhead ms",
                      "efficiency/worker", "cpu ms/point"], rows)]
    if results["ray"] is not None:
        lines.append(f"Ray cluster start (not in its wall time): {_fmt(results['ray']['start_s'])}"
                     " s; ray: the first sweep, whose workers start and load openmotion; ray, "
                     "next sweep: the same points again on the same cluster")
    return lines


def _render_serve(results: dict[str, Any]) -> list[str]:
    lines = []
    for run in (results, results.get("thread")):
        if run:
            lines += _render_serve_run(run)
    return lines


def _render_serve_run(results: dict[str, Any]) -> list[str]:
    opcua, ads = results["opcua"], results["ads"]
    return [
        f"kernel in a {results.get('kernel', 'thread')}: {results['axes']} axes, 1 ms cycle "
        f"paced by the wall clock, {results['seconds']:g} s with both clients: late p99 "
        f"{_fmt(results['late_p99_ms'])} ms, max {_fmt(results['late_max_ms'])} ms, time "
        f"slipped {results['slips']}x",
        *_table(["client", "what", "figure"], [
            ["asyncua", f"{opcua['subscribed']} values at 10 ms",
             f"{opcua['notifications']} notifications, {_fmt(opcua['per_value_per_second'])}"
             f"/value/s, {_fmt(opcua.get('messages_per_second', 0.0))} messages/s, "
             f"lost {opcua['lost']}"],
            ["asyncua", "read one value [µs]",
             f"p50 {_fmt(opcua['read_us']['p50'])}, p99 {_fmt(opcua['read_us']['p99'])}"],
            ["pyads", f"sum read of {ads['symbols']} every 10 ms [ms]",
             f"p50 {_fmt(ads['sum_read_ms']['p50'])}, p99 {_fmt(ads['sum_read_ms']['p99'])}"
             f", {ads['sum_reads']} reads, {ads['late_polls']} late"],
            ["pyads", "read by name [µs]", f"p50 {_fmt(ads['read_by_name_us']['p50'])}, "
             f"p99 {_fmt(ads['read_by_name_us']['p99'])}"],
            ["pyads", "read by handle [µs]", f"p50 {_fmt(ads['read_by_handle_us']['p50'])}, "
             f"p99 {_fmt(ads['read_by_handle_us']['p99'])}"],
        ]),
    ]


def _render_envs(results: dict[str, Any]) -> list[str]:
    header = ["N", "stators", "ours steps/s", "ours ms/cycle", "refused", "MagBotSim steps/s",
              "MagBotSim ms/cycle", "mj_step ms", "ratio"]
    rows = []
    for n, r in results["by_n"].items():
        ours, theirs = r["ours"], r["magbotsim"] or {}
        rows.append([int(n), ours["stators"], ours["steps_per_s"], ours["ms_per_cycle"],
                     ours["rejected_share"], theirs.get("steps_per_s"),
                     theirs.get("ms_per_cycle"), theirs.get("mj_step_ms"),
                     r.get("ratio_steps_per_s")])
    peer = results["magbotsim"]
    published = ", ".join(f"{n}: {v:g} ms" for n, v in
                          results["published_magbotsim_ms_per_cycle"].items())
    return [f"environment steps of {results['cycles_per_step']} cycles of 1 ms, random policy, "
            f"square fields of {results['stators_per_mover']:g} stators per mover; refused: "
            "share of commands the group refused; MagBotSim "
            f"{peer['version'] or 'unavailable: ' + str(peer['unavailable'])}",
            *_table(header, rows),
            f"MagBotSim's published mj_step by movers (its authors' machine): {published}"]


def _render_routing(results: dict[str, Any]) -> list[str]:
    rows = [[r["layout"], r["movers"], f"{r['arrived']}/{r['movers']}",
             _fmt(r["first_plan_ms"]),
             _fmt(r["plan_ms"]), _fmt(r["makespan_s"]), _fmt(r["lower_bound_s"]),
             _fmt(r.get("straight_bound_s")), _fmt(r["ratio"]), r["rejected"],
             r["overlaps"] + r["off_surface"]]
            for r in results["magbotsim"] + results["big"]]
    return ["bound: the slowest mover's own time-optimal move over the shortest way round the "
            "field's holes (D-355); straight: over the straight line, which may cross them",
            *_table(["layout", "movers", "arrived", "first plan [ms]", "plan [ms]",
                     "makespan [s]", "bound [s]", "straight [s]", "ratio", "rejected",
                     "overlaps"], rows)]


_RENDER = {"axes": _render_axes, "otg": _render_otg, "fbcall": _render_fbcall,
           "ca": _render_ca, "planar": _render_planar, "path": _render_path,
           "tracks": _render_tracks, "trace": _render_trace, "startup": _render_startup,
           "sweep": _render_sweep, "serve": _render_serve, "envs": _render_envs,
           "routing": _render_routing}


def render_figures(name: str, results: dict[str, Any], markdown: bool = False) -> list[str]:
    """The figure lines of benchmark ``name`` (KeyError if it has no renderer); ``markdown``
    makes its tables GitHub tables, for docs/benchmarks.md (bench.report)."""
    token = _MARKDOWN.set(markdown)
    try:
        return _RENDER[name](results)
    finally:
        _MARKDOWN.reset(token)


def markdown_table(header: list[str], rows: list[list[Any]]) -> list[str]:
    """A GitHub table in the renderers' number format (bench.report's own tables)."""
    token = _MARKDOWN.set(True)
    try:
        return _table(header, rows)
    finally:
        _MARKDOWN.reset(token)


def format_value(value: Any, digits: int = 3) -> str:
    """A figure as the renderers write it: None as "-", whole floats without decimals."""
    return _fmt(value, digits)


def render(result: dict[str, Any]) -> str:
    """Plain-text report: machine, figures, goals and the verdict."""
    name = result["benchmark"]
    m = result["machine"]
    lines = [
        f"openmotion bench {name}{' (quick)' if result.get('quick') else ''}",
        f"machine: {m['cpu_count']} cpu, python {m['python']}, {m['platform']}",
        f"numpy {m['numpy']}, ruckig {m['ruckig']}, pyplcopen {m['pyplcopen'] or 'missing'}",
        "",
        *_RENDER[name](result["results"]),
        "",
        "goals (docs/benchmarks.md):",
    ]
    for g in result["goals"].values():
        verdict = {True: "ok  ", False: "FAIL", None: "n/a "}[g["passed"]]
        lines.append(f"  [{verdict}] {g['goal']}: {_fmt(g['value'])}")
    lines.append(f"passed: {'yes' if result['passed'] else 'no'}")
    return "\n".join(lines)
