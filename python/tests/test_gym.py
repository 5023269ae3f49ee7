"""The Gymnasium environment: Gymnasium's own checker, episodes ending at trust, rewards."""

from __future__ import annotations

import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from trustcbr.gym import TrustEnv  # noqa: E402


def test_gymnasiums_checker_passes() -> None:
    env = TrustEnv("movement")
    check_env(env, skip_render_check=True)
    env.close()


def test_an_episode_ends_when_the_operator_trusts_a_behavior() -> None:
    env = TrustEnv("movement", operators=["balanced"])
    observation, info = env.reset(seed=5)
    assert info["operator"] == "balanced"
    assert observation.shape == env.observation_space.shape
    total, steps, terminated, truncated = 0.0, 0, False, False
    while not (terminated or truncated) and steps < 400:
        observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert reward <= 0.0
        assert observation[0] >= 1
        total += reward
        steps += 1
    assert terminated and info["trusted"]
    env.close()


def test_the_same_seed_gives_the_same_episode() -> None:
    def episode() -> list[float]:
        env = TrustEnv("patrol")
        env.reset(seed=3)
        env.action_space.seed(3)
        rewards = [env.step(env.action_space.sample())[1] for _ in range(3)]
        env.close()
        return rewards

    assert episode() == episode()
