"""``openmotion bench envs``: environment steps per second, ours beside MagBotSim's.

For each mover count N (5, 50, 500) both environments get the same square field of about
``STATORS_PER_MOVER`` stators (tiles) per mover, 240 mm each, and a random policy; an
environment step is ``CYCLES_PER_STEP`` 1 ms cycles in both. Only ``step`` calls are timed
(a reset after an episode ends is not), for at most ``seconds`` per side and count.

* ours: ``PlanarFieldEnv`` (every action row a MoveToPosition the planar group admits or
  refuses, docs/envs.md);
* MagBotSim: its long-horizon trajectory planning environment (MuJoCo), rendering off, with
  ``num_cycles`` equal to ours. Its own published scaling figures time one ``mj_step`` (one
  1 ms physics step), so the run also times ``mujoco.mj_step`` on its model, the figure to
  set beside them.

MagBotSim is a benchmark-only extra (``pip install openmotion[envs-peer]``, it pulls in
MuJoCo). Without it the peer columns are None with the reason, and the published figures
stand in.
"""

from __future__ import annotations

import importlib.metadata
import math
import time
import warnings
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

DEFAULT_COUNTS = (5, 50, 500)
QUICK_COUNTS = (5, 20)
CYCLES_PER_STEP = 10  #: 1 ms cycles per environment step, both sides
STATORS_PER_MOVER = 3.0  #: MagBotSim places starts at random: it needs room to find them
SECONDS = 5.0  #: timing budget per side and count [s]
MIN_STEPS = 3  #: steps timed at least, whatever the budget
MJ_STEPS = 200  #: bare physics steps timed on MagBotSim's model
#: MagBotSim's published scaling: one 1 ms physics step [ms] by movers, on its authors' machine
PUBLISHED_MS_PER_CYCLE = {50: 0.15, 100: 0.23, 500: 1.17, 1000: 2.7}

Progress = Callable[[str], None] | None


def side_for(movers: int) -> int:
    return max(2, math.ceil(math.sqrt(STATORS_PER_MOVER * movers)))


def _time_steps(step: Callable[[], bool], reset: Callable[[], None], seconds: float
                ) -> tuple[int, float]:
    """Steps taken and the seconds spent inside them; ``step`` returns True at an episode
    end, after which ``reset`` runs untimed."""
    spent, steps = 0.0, 0
    while steps < MIN_STEPS or spent < seconds:
        start = time.perf_counter()
        ended = step()
        spent += time.perf_counter() - start
        steps += 1
        if ended:
            reset()
    return steps, spent


def _row(steps: int, spent: float) -> dict[str, Any]:
    per_step = spent / steps
    return {"steps": steps, "steps_per_s": 1.0 / per_step, "ms_per_step": per_step * 1e3,
            "ms_per_cycle": per_step * 1e3 / CYCLES_PER_STEP}


def run_ours(movers: int, seconds: float = SECONDS, seed: int = 0) -> dict[str, Any]:
    from openmotion.envs import PlanarFieldEnv
    from openmotion.planar.layouts import Layout

    side = side_for(movers)
    layout = Layout(f"square-{side}", tuple("#" * side for _ in range(side)), movers)
    env = PlanarFieldEnv(layout, cycles_per_step=CYCLES_PER_STEP, max_steps=10**9)
    env.reset(seed=seed)
    env.action_space.seed(seed)
    counts = {"rejected": 0, "commanded": 0}

    def step() -> bool:
        _, _, terminated, truncated, info = env.step(env.action_space.sample())
        counts["rejected"] += info["rejected"]
        counts["commanded"] += info["commanded"]
        return terminated or truncated

    steps, spent = _time_steps(step, lambda: env.reset(), seconds)
    return {**_row(steps, spent), "stators": side * side, **counts,
            "rejected_share": counts["rejected"] / max(1, counts["commanded"])}


def magbotsim_version() -> tuple[str | None, str | None]:
    """(version, None) when MagBotSim and MuJoCo import, else (None, why not)."""
    try:
        version = importlib.metadata.version("magbotsim")
        import mujoco  # noqa: F401 - MagBotSim's physics
        from magbotsim.rl_envs.trajectory_planning import (  # noqa: F401
            long_horizon_global_trajectory_planning_env,
        )
    except (importlib.metadata.PackageNotFoundError, ImportError) as missing:
        return None, f"not installed ({missing}); pip install openmotion[envs-peer]"
    return version, None


def run_magbotsim(movers: int, seconds: float = SECONDS, seed: int = 0) -> dict[str, Any]:
    import mujoco
    from magbotsim.rl_envs.trajectory_planning.long_horizon_global_trajectory_planning_env import (
        LongHorizonGlobalTrajectoryPlanningEnv,
    )

    side = side_for(movers)
    with warnings.catch_warnings():  # it warns while it searches start positions
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        env = LongHorizonGlobalTrajectoryPlanningEnv(
            layout_tiles=np.ones((side, side), dtype=np.int8), num_movers=movers,
            show_2D_plot=False, render_mode=None, num_cycles=CYCLES_PER_STEP,
            timeout_steps=None)
        env.reset(seed=seed)
        build = time.perf_counter() - start
        env.action_space.seed(seed)

        def step() -> bool:
            _, _, terminated, truncated, _ = env.step(env.action_space.sample())
            return bool(terminated or truncated)

        steps, spent = _time_steps(step, lambda: env.reset(), seconds)
        start = time.perf_counter()
        for _ in range(MJ_STEPS):
            mujoco.mj_step(env.model, env.data)
        physics = (time.perf_counter() - start) / MJ_STEPS
        env.close()
    return {**_row(steps, spent), "tiles": side * side, "build_s": build,
            "mj_step_ms": physics * 1e3}


def require_envs_extra() -> None:
    """An ``ImportError`` naming the extra when gymnasium or pettingzoo is missing (the CLI
    reports it and exits 2)."""
    try:
        import gymnasium  # noqa: F401
        import pettingzoo  # noqa: F401
    except ImportError as missing:
        raise ImportError(f"bench envs needs the environments' extra ({missing}): "
                          "pip install 'openmotion[envs]'") from None


def run_envs(counts: Sequence[int] = DEFAULT_COUNTS, seconds: float = SECONDS,
             peer: bool = True, progress: Progress = None) -> dict[str, Any]:
    require_envs_extra()
    version, why = magbotsim_version() if peer else (None, "not asked for (peer=False)")
    by_n: dict[str, Any] = {}
    for n in counts:
        if progress is not None:
            progress(f"envs: {n} movers, ours")
        row: dict[str, Any] = {"movers": n, "ours": run_ours(n, seconds), "magbotsim": None}
        if version is not None:
            if progress is not None:
                progress(f"envs: {n} movers, MagBotSim {version}")
            row["magbotsim"] = theirs = run_magbotsim(n, seconds)
            row["ratio_steps_per_s"] = row["ours"]["steps_per_s"] / theirs["steps_per_s"]
        by_n[str(n)] = row
    return {"counts": list(counts), "cycles_per_step": CYCLES_PER_STEP,
            "stators_per_mover": STATORS_PER_MOVER, "seconds": seconds,
            "magbotsim": {"version": version, "unavailable": why},
            "published_magbotsim_ms_per_cycle": {str(k): v
                                                 for k, v in PUBLISHED_MS_PER_CYCLE.items()},
            "by_n": by_n}
