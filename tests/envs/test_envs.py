"""The Gymnasium and PettingZoo environments: their APIs, determinism, and real refusals."""

from __future__ import annotations

import re
import runpy
from pathlib import Path

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test

from openmotion.core.errors import ConfigError, ErrorId
from openmotion.envs import PlanarField, PlanarFieldEnv, PlanarFieldParallelEnv, make_layout
from openmotion.envs.episode import REJECTION_PENALTY
from openmotion.planar.layouts import Layout

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
STRIP = Layout("strip", ("#", "#", "#"), 2)  #: three stators in a row along x, two movers


def test_the_single_agent_environment_passes_gymnasium_s_checker() -> None:
    check_env(PlanarFieldEnv("B0"), skip_render_check=True)
    check_env(PlanarFieldEnv("random", movers=6, layout_seed=2), skip_render_check=True)


def test_gymnasium_make_finds_the_environment_by_its_id() -> None:
    import gymnasium

    from openmotion.envs import GYMNASIUM_ID

    env = gymnasium.make(GYMNASIUM_ID, layout="B7", max_steps=3)
    observation, _ = env.reset(seed=1)
    assert observation.shape == (4, 12) and env.unwrapped.layout.name == "B7"


def test_the_parallel_environment_passes_pettingzoo_s_api_test() -> None:
    parallel_api_test(PlanarFieldParallelEnv("B3"), num_cycles=40)


def _rollout(seed: int, steps: int = 25) -> list[tuple[bytes, float, bool, bool, dict]]:
    env = PlanarFieldEnv("B1", max_steps=steps)
    observation, _ = env.reset(seed=seed)
    env.action_space.seed(seed)
    record = [(observation.tobytes(), 0.0, False, False, {})]
    for _ in range(steps):
        observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
        record.append((observation.tobytes(), reward, terminated, truncated, info))
    return record


def test_same_seed_same_episode_bit_for_bit() -> None:
    first, again = _rollout(11), _rollout(11)
    assert first == again
    assert sum(info.get("rejected", 0) for *_, info in first) > 0  # the episode did something
    assert first[-1][3] is True  # truncated after max_steps
    assert _rollout(12)[0][0] != first[0][0]  # another seed: other starts and goals


def test_the_parallel_environment_is_deterministic_too() -> None:
    def run(seed: int) -> list[bytes]:
        env = PlanarFieldParallelEnv("B5", max_steps=15)
        observations, _ = env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        out = [b"".join(o.tobytes() for o in observations.values())]
        while env.agents:
            observations, rewards, *_ = env.step(
                {agent: rng.uniform(-1, 1, 2) for agent in env.agents})
            out.append(b"".join(o.tobytes() for o in observations.values())
                       + np.array(list(rewards.values())).tobytes())
        return out
    assert run(5) == run(5) and len(run(5)) == 16


def _adjacent_reset(env: PlanarFieldParallelEnv) -> dict[str, np.ndarray]:
    """Reset until the two movers of STRIP stand on neighbouring stators."""
    for seed in range(50):
        observations, _ = env.reset(seed=seed)
        if abs(observations["mover_0"][6]) < 0.25:  # dx to the neighbour [m]
            return observations
    raise AssertionError("no seed puts the movers side by side")


def test_a_move_onto_another_mover_is_refused_by_the_group_and_penalised() -> None:
    env = PlanarFieldParallelEnv(STRIP)
    observations = _adjacent_reset(env)
    towards = np.sign(observations["mover_0"][6])
    start = observations["mover_0"][:2].copy()
    observations, rewards, _, _, infos = env.step({"mover_0": np.array([towards, 0.0])})
    assert infos["mover_0"]["refused"] is True
    assert infos["mover_0"]["error_id"] == ErrorId.PLANAR_COLLISION
    assert rewards["mover_0"] == pytest.approx(-REJECTION_PENALTY)
    assert np.array_equal(observations["mover_0"][:2], start)  # it did not move
    assert infos["mover_1"]["refused"] is False and rewards["mover_1"] == 0.0
    # still usable: a move away from the neighbour onto free stator (or none) is admitted
    _, _, _, _, infos = env.step({"mover_0": np.array([-towards * 0.1, 0.0])})
    assert infos["mover_0"]["refused"] is False


def test_a_move_off_the_stators_is_refused_too() -> None:
    field = PlanarField(STRIP, np.array([[120.0, 120.0], [600.0, 120.0]]),
                        np.array([[360.0, 120.0], [120.0, 120.0]]))
    result = field.step(np.array([[0.0, 1.0], [0.0, 0.0]]))  # 240 mm up: no stator there
    assert result.rejected.tolist() == [True, False]
    assert result.error_ids[0] == ErrorId.PLANAR_COLLISION
    assert result.commanded.tolist() == [True, False]
    result = field.step(np.array([[1.0, 0.0], [0.0, 0.0]]))  # to the free middle stator
    assert not result.rejected.any()


def test_a_mover_that_heads_for_its_goal_arrives_and_the_episode_terminates() -> None:
    env = PlanarFieldEnv("B0", movers=1, max_steps=400)
    observation, _ = env.reset(seed=0)
    total, terminated, truncated = 0.0, False, False
    while not (terminated or truncated):
        row = observation[0]
        action = np.clip((row[4:6] - row[0:2]) / 0.24, -1.0, 1.0)[None, :]
        observation, reward, terminated, truncated, info = env.step(action)
        total += reward
    assert terminated and not truncated and info["arrived"] == 1
    distance = np.hypot(*(observation[0, 4:6] - observation[0, 0:2]))
    assert distance <= 0.005
    assert total > 1.0  # the arrival reward and the progress, no refusals


def test_bad_configuration_is_a_config_error_and_a_good_one_works_after() -> None:
    with pytest.raises(ConfigError, match="unknown layout 'B11'; known: B0"):
        PlanarFieldEnv("B11")
    with pytest.raises(ConfigError, match="max_steps must be an int >= 1"):
        PlanarFieldParallelEnv("B0", max_steps=0)
    with pytest.raises(ConfigError, match="call reset"):
        PlanarFieldEnv("B0").step(np.zeros((3, 2), dtype=np.float32))
    assert make_layout("B2").movers == 4 and make_layout("B2", movers=2).movers == 2
    assert PlanarFieldEnv("B2").reset(seed=1)[0].shape == (4, 12)


def test_the_example_rollout_prints_its_golden_summary(capsys: pytest.CaptureFixture[str]
                                                       ) -> None:
    runpy.run_path(str(EXAMPLES / "envs_rollout.py"), run_name="__main__")
    assert capsys.readouterr().out == (EXAMPLES / "envs_rollout.out").read_text()


def test_the_docs_session_prints_what_its_comments_say(capsys: pytest.CaptureFixture[str]
                                                       ) -> None:
    text = (EXAMPLES.parent / "docs" / "envs.md").read_text()
    (block,) = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    expected = re.findall(r"^print\(.*\n# (.*)$", block, flags=re.M)
    exec(compile(block, "docs/envs.md", "exec"), {})  # noqa: S102 - the page must run
    assert capsys.readouterr().out.splitlines() == expected and len(expected) == 3
