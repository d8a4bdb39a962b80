"""A PettingZoo parallel environment with one agent per mover of a planar field.

Agent ``mover_i`` observes its own row of the field's observation (``episode.py``) and acts
with a Box (2,) in [-1, 1], the increment of its move target (D-311); its reward is its own
(D-313); its info adds ``refused`` and ``error_id``: whether the group refused its command
this step, and why (PLANAR_COLLISION, 33158). All agents end together: when every mover has
arrived or one has failed (terminated), or after ``max_steps`` (truncated); then ``agents``
is empty until ``reset``.
"""

from __future__ import annotations

import functools
from typing import Any

import gymnasium as gym
import numpy as np
from pettingzoo import ParallelEnv

from openmotion.envs.episode import OBSERVATION_DTYPE, Episode, EpisodeConfig
from openmotion.envs.single import ACTION_DTYPE
from openmotion.planar.layouts import Layout

AgentId = str


class PlanarFieldParallelEnv(ParallelEnv[AgentId, np.ndarray, np.ndarray]):
    """One agent per mover; see the module docstring."""

    metadata = {"name": "openmotion_planar_field_v0", "render_modes": []}  # noqa: RUF012

    def __init__(self, layout: str | Layout = "B0", movers: int | None = None,
                 layout_seed: int = 0, **options: Any) -> None:
        self.episode = Episode(EpisodeConfig(layout, movers, layout_seed, **options))
        self.possible_agents = [f"mover_{i}" for i in range(self.episode.count)]
        self.agents: list[AgentId] = []
        self._low, self._high = self.episode.bounds()
        self._rng = np.random.default_rng()

    @property
    def layout(self) -> Layout:
        return self.episode.layout

    @functools.cache  # noqa: B019 - one space per agent, as PettingZoo asks
    def observation_space(self, agent: AgentId) -> gym.spaces.Box:
        return gym.spaces.Box(self._low, self._high, dtype=OBSERVATION_DTYPE)

    @functools.cache  # noqa: B019
    def action_space(self, agent: AgentId) -> gym.spaces.Box:
        return gym.spaces.Box(-1.0, 1.0, shape=(2,), dtype=ACTION_DTYPE)

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[AgentId, np.ndarray], dict[AgentId, dict[str, Any]]]:
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        rows = self.episode.reset(self._rng)
        self.agents = list(self.possible_agents)
        return ({agent: rows[i] for i, agent in enumerate(self.agents)},
                {agent: {} for agent in self.agents})

    def step(self, actions: dict[AgentId, np.ndarray]) -> tuple[
            dict[AgentId, np.ndarray], dict[AgentId, float], dict[AgentId, bool],
            dict[AgentId, bool], dict[AgentId, dict[str, Any]]]:
        """Agents missing from ``actions`` send no command this step."""
        if not self.agents:
            return {}, {}, {}, {}, {}
        matrix = np.zeros((self.episode.count, 2))
        for i, agent in enumerate(self.possible_agents):
            if agent in actions:
                matrix[i] = actions[agent]
        rows, rewards, terminated, truncated, info = self.episode.step(matrix)
        agents = self.agents
        self.agents = [] if terminated or truncated else list(agents)
        index = {agent: i for i, agent in enumerate(self.possible_agents)}
        return ({a: rows[index[a]] for a in agents},
                {a: float(rewards[index[a]]) for a in agents},
                {a: terminated for a in agents}, {a: truncated for a in agents},
                {a: {**info, "refused": bool(self.episode.refused[index[a]]),
                     "error_id": int(self.episode.error_ids[index[a]])} for a in agents})
