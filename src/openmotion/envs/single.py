"""A Gymnasium environment in which one agent drives every mover of a planar field.

Observation: a Box of shape (movers, features), float32 (``episode.py``). Action: a Box of
shape (movers, 2) in [-1, 1]: per mover the increment of its move target, ``reach`` mm at 1
(D-311). Reward: the sum of the movers' rewards. Same seed, same actions: the same episode,
bit for bit (the field has no randomness of its own; the seed draws starts and goals).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from openmotion.envs.episode import OBSERVATION_DTYPE, Episode, EpisodeConfig
from openmotion.planar.layouts import Layout

ACTION_DTYPE = np.float32


class PlanarFieldEnv(gym.Env[np.ndarray, np.ndarray]):
    """Every mover of a planar field under one policy; see the module docstring."""

    metadata = {"render_modes": []}  # noqa: RUF012 - Gymnasium's class attribute

    def __init__(self, layout: str | Layout = "B0", movers: int | None = None,
                 layout_seed: int = 0, **options: Any) -> None:
        self.episode = Episode(EpisodeConfig(layout, movers, layout_seed, **options))
        low, high = self.episode.bounds()
        count = self.episode.count
        self.observation_space = gym.spaces.Box(np.tile(low, (count, 1)),
                                                np.tile(high, (count, 1)),
                                                dtype=OBSERVATION_DTYPE)
        self.action_space = gym.spaces.Box(-1.0, 1.0, shape=(count, 2), dtype=ACTION_DTYPE)

    @property
    def layout(self) -> Layout:
        return self.episode.layout

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        observation = self.episode.reset(self.np_random)
        return observation, {"arrived": int(self.episode.arrived.sum())}

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        observation, rewards, terminated, truncated, info = self.episode.step(
            np.asarray(action).reshape(self.episode.count, 2))
        return observation, float(rewards.sum()), terminated, truncated, info
