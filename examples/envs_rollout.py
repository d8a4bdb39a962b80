"""Roll out two policies on MagBotSim's layout B3 rebuilt on our stators (docs/envs.md).

A random policy through the Gymnasium environment, then a greedy one through the PettingZoo
environment (each mover heads for its goal along one axis at a time, and tries a random move
after a refusal). Every action becomes a TF5430 MoveToPosition the planar group admits or
refuses, so refusals show in the counts.
Run: ``python examples/envs_rollout.py`` (needs ``pip install openmotion[envs]``); the
tests compare its output with ``envs_rollout.out``.
"""

from __future__ import annotations

import numpy as np

from openmotion.envs import PlanarFieldEnv, PlanarFieldParallelEnv

STEPS = 300
SEED = 7


def random_policy() -> None:
    env = PlanarFieldEnv("B3", max_steps=STEPS)
    env.reset(seed=SEED)
    env.action_space.seed(SEED)
    total, rejected, steps = 0.0, 0, 0
    while True:
        _, reward, terminated, truncated, info = env.step(env.action_space.sample())
        total, rejected, steps = total + reward, rejected + info["rejected"], steps + 1
        if terminated or truncated:
            break
    print(f"random  B3 movers={env.layout.movers} steps={steps} return={total:.4f} "
          f"refused={rejected} arrived={info['arrived']} truncated={truncated}")


def lane(row: np.ndarray) -> np.ndarray:
    """Towards the goal along the axis with the longer way left (lanes between stators)."""
    way = row[4:6] - row[0:2]
    axis = int(abs(way[1]) > abs(way[0]))
    action = np.zeros(2)
    action[axis] = np.clip(way[axis] / 0.24, -1.0, 1.0)
    if abs(way[axis]) < 1e-3:  # arrived on that axis: finish the other
        action[1 - axis] = np.clip(way[1 - axis] / 0.24, -1.0, 1.0)
    return action


def greedy_policy() -> None:
    env = PlanarFieldParallelEnv("B3", max_steps=STEPS)
    observations, _ = env.reset(seed=SEED)
    returns = dict.fromkeys(env.possible_agents, 0.0)
    refused = dict.fromkeys(env.possible_agents, False)
    rng = np.random.default_rng(SEED)
    rejected, steps = 0, 0
    while env.agents:
        # the row is x, y, vx, vy, goal x, goal y, ... [m]; an action of 1 is one stator;
        # a mover whose last move was refused tries a random one instead
        actions = {agent: rng.uniform(-1.0, 1.0, 2) if refused[agent] else lane(row)
                   for agent, row in observations.items()}
        observations, rewards, _, truncations, infos = env.step(actions)
        refused = {agent: info["refused"] for agent, info in infos.items()}
        for agent, reward in rewards.items():
            returns[agent] += reward
        steps += 1
        rejected += next(iter(infos.values()))["rejected"]
    info = next(iter(infos.values()))
    print(f"greedy  B3 movers={len(returns)} steps={steps} refused={rejected} "
          f"arrived={info['arrived']} truncated={any(truncations.values())}")
    for agent, value in returns.items():
        print(f"  {agent} return={value:.4f}")


if __name__ == "__main__":
    random_policy()
    greedy_policy()
