"""One episode on a planar field: observations, rewards and the end, shared by both APIs.

Per mover the observation is one float32 row, in metres and metres per second (D-312):

    x, y, vx, vy, goal x, goal y, then (dx, dy) to each of the ``neighbours`` nearest other
    movers, nearest first (ties by mover index).

The reward of a mover per step (D-313) is its progress towards its goal [m], plus
``ARRIVAL_REWARD`` the first time it arrives, minus ``REJECTION_PENALTY`` for every command
of it the group refused. The episode terminates when every mover has arrived or when a mover
has left the Enabled state (an error); it is truncated after ``max_steps`` steps.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.envs.field import ARRIVAL_TOLERANCE, CYCLES_PER_STEP, REACH, PlanarField
from openmotion.envs.registry import make_layout
from openmotion.planar.layouts import Layout
from openmotion.planar.stators import STATOR_SIZE

NEIGHBOURS = 4  #: nearest other movers in each observation (fewer when there are fewer)
MAX_STEPS = 500  #: steps before truncation (5 s at 10 ms a step)
ARRIVAL_REWARD = 1.0
REJECTION_PENALTY = 0.1
MM = 1e-3  #: observations are in metres
VELOCITY_BOUND = 5.0  #: [m/s], above every mover's maximum dynamics (4 m/s by default)
OBSERVATION_DTYPE = np.float32
BASE_FEATURES = 6  #: x, y, vx, vy, goal x, goal y


@dataclass(frozen=True)
class EpisodeConfig:
    """What both environments take: the layout and how an episode runs."""

    layout: str | Layout = "B0"
    movers: int | None = None  #: None: the layout's own count
    layout_seed: int = 0  #: draws a random field once, when the environment is made
    cycles_per_step: int = CYCLES_PER_STEP
    reach: float = REACH  #: [mm] how far an action of 1 moves the target
    neighbours: int = NEIGHBOURS
    max_steps: int = MAX_STEPS

    def __post_init__(self) -> None:
        for name in ("neighbours", "max_steps"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0 + (
                    name == "max_steps"):
                raise ConfigError(f"planar environment: {name} must be an int >= "
                                  f"{int(name == 'max_steps')}, got {value!r}")


class Episode:
    """The field of the current episode and what the environments report of it."""

    def __init__(self, config: EpisodeConfig) -> None:
        self.config = config
        self.layout = make_layout(config.layout, config.movers, config.layout_seed)
        self.count = self.layout.movers
        self.neighbours = min(config.neighbours, self.count - 1)
        self.features = BASE_FEATURES + 2 * self.neighbours
        extent = np.array(self.layout.shape, dtype=float) * STATOR_SIZE * MM
        self.extent = extent
        self.field: PlanarField | None = None
        self.steps = 0
        self._distances = np.zeros(self.count)
        self.arrived = np.zeros(self.count, dtype=bool)
        self.refused = np.zeros(self.count, dtype=bool)  #: per mover: its last command refused
        self.error_ids = np.zeros(self.count, dtype=np.int64)  #: and the refusal's error id

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Low and high of one mover's observation row (the field's extent with a margin of
        one reach, so a set position on the surface always lies inside)."""
        margin = self.config.reach * MM
        span = float(self.extent.max()) + margin
        low = [-margin, -margin, -VELOCITY_BOUND, -VELOCITY_BOUND, -margin, -margin]
        high = [self.extent[0] + margin, self.extent[1] + margin, VELOCITY_BOUND,
                VELOCITY_BOUND, self.extent[0] + margin, self.extent[1] + margin]
        low += [-span] * 2 * self.neighbours
        high += [span] * 2 * self.neighbours
        return (np.array(low, dtype=OBSERVATION_DTYPE), np.array(high, dtype=OBSERVATION_DTYPE))

    def reset(self, rng: np.random.Generator) -> np.ndarray:
        starts, goals = self.layout.starts_and_goals(rng)
        self.field = PlanarField(self.layout, starts, goals, self.config.cycles_per_step,
                                 self.config.reach)
        self.steps = 0
        positions = self.field.positions()
        self._distances = self.field.distances(positions)
        self.arrived = self._distances <= ARRIVAL_TOLERANCE
        self.refused[:] = False
        self.error_ids[:] = 0
        return self.observe(positions, self.field.velocities())

    def observe(self, positions: np.ndarray, velocities: np.ndarray) -> np.ndarray:
        assert self.field is not None
        rows = np.empty((self.count, self.features), dtype=float)
        rows[:, 0:2] = positions
        rows[:, 2:4] = velocities
        rows[:, 4:6] = self.field.goals
        if self.neighbours:
            offsets = positions[None, :, :] - positions[:, None, :]  # [i, j] = p_j - p_i
            distances = np.hypot(offsets[..., 0], offsets[..., 1])
            np.fill_diagonal(distances, np.inf)
            nearest = np.argsort(distances, axis=1, kind="stable")[:, :self.neighbours]
            picked = np.take_along_axis(offsets, nearest[..., None], axis=1)
            rows[:, BASE_FEATURES:] = picked.reshape(self.count, -1)
        return (rows * MM).astype(OBSERVATION_DTYPE)

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool, bool,
                                                 dict[str, Any]]:
        """Observations (movers, features), rewards (movers,), terminated, truncated, info."""
        if self.field is None:
            raise ConfigError("planar environment: call reset() before step()")
        result = self.field.step(actions)
        self.steps += 1
        self.refused, self.error_ids = result.rejected, result.error_ids
        positions = self.field.positions()
        distances = self.field.distances(positions)
        reached = distances <= ARRIVAL_TOLERANCE
        first = reached & ~self.arrived
        rewards = ((self._distances - distances) * MM + ARRIVAL_REWARD * first
                   - REJECTION_PENALTY * result.rejected)
        self._distances = distances
        self.arrived |= reached
        failed = self.field.failed()
        terminated = bool(reached.all() or failed.any())
        truncated = not terminated and self.steps >= self.config.max_steps
        info = {"rejected": int(result.rejected.sum()), "commanded": int(result.commanded.sum()),
                "arrived": int(reached.sum()), "failed": int(failed.sum()),
                "time": self.field.runtime.now}
        return (self.observe(positions, self.field.velocities()), rewards.astype(float),
                terminated, truncated, info)
