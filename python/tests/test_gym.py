"""The Gymnasium environments: Gymnasium's own checker, registered ids with a per-episode
cap, episodes ending at trust, the observation, refused actions and operators, rendering."""

from __future__ import annotations

import threading
from typing import Any, List

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import trustcbr  # noqa: E402
from trustcbr.gym import MAX_EPISODE_STEPS, TrustEnv  # noqa: E402


def test_gymnasiums_checker_passes() -> None:
    env = gymnasium.make("trustcbr/Movement-v0", render_mode="rgb_array")
    check_env(env.unwrapped)
    env.close()


def run_episode(env: Any, seed: int) -> List[Any]:
    env.reset(seed=seed)
    env.action_space.seed(seed)
    steps = []
    while True:
        step = env.step(env.action_space.sample())
        steps.append(step)
        if step[2] or step[3]:
            return steps


def test_an_episode_ends_when_the_operator_trusts_a_behavior() -> None:
    env = TrustEnv("movement", operators=["balanced"])
    observation, info = env.reset(seed=5)
    assert info["operator"] == "balanced"
    assert observation.shape == env.observation_space.shape
    # Before any step: no commands, no action (-1 per component), trust 0.
    assert list(observation[:-3]) == [0] * (4 + len(env.observations))
    assert list(observation[-3:]) == [-1, -1, 0]
    steps = run_episode(env, 5)
    observation, reward, terminated, truncated, info = steps[-1]
    assert terminated and info["trusted"] and info["end"] == "trusted"
    for observation, reward, _, _, info in steps:
        commands, completed, failed, interrupted = observation[:4]
        assert commands == completed + failed + interrupted >= 1
        assert reward == -(failed + interrupted)
        # The action just taken and the estimate it ended with are in the observation.
        values = [c["values"] for c in env.components]
        indices = [int(i) for i in observation[-3:-1]]
        assert {c["name"]: v[i] for c, v, i in zip(env.components, values, indices)} == info[
            "behavior"
        ]
        assert observation[-1] == pytest.approx(info["trust"])
    # A trusted behavior's estimate reached +5; a given-up one's fell to -5.
    assert steps[-1][0][-1] >= 5.0
    assert all(s[0][-1] <= -5.0 for s in steps[:-1])


def test_step_after_the_end_is_refused() -> None:
    env = TrustEnv("movement", operators=["balanced"])
    with pytest.raises(trustcbr.TrustcbrError, match=r"call reset\(\)"):
        env.step([0, 0])
    run_episode(env, 1)
    with pytest.raises(trustcbr.TrustcbrError, match=r"after the episode ended .*call reset\(\)"):
        env.step([0, 0])
    env.reset(seed=2)
    env.step([0, 0])


def test_the_same_seed_gives_the_same_episode() -> None:
    def rewards() -> List[float]:
        return [s[1] for s in run_episode(TrustEnv("patrol"), 3)]

    assert rewards() == rewards()


def test_the_registered_ids_are_capped_per_episode() -> None:
    env = gymnasium.make("trustcbr/Patrol-v0")
    assert env.spec is not None and env.spec.max_episode_steps == MAX_EPISODE_STEPS
    assert gymnasium.make("trustcbr/Movement-v0").unwrapped.scenario == "movement"
    # An agent that keeps trying the behavior no operator trusts (the fastest, widest
    # scan) is cut off after the cap, as a truncation.
    env.reset(seed=0)
    worst = [n - 1 for n in env.action_space.nvec]
    steps = 0
    truncated = terminated = False
    while not (terminated or truncated):
        _, _, terminated, truncated, _ = env.step(worst)
        steps += 1
    assert truncated and not terminated
    assert steps <= MAX_EPISODE_STEPS
    # Constructed directly, the environment caps itself.
    direct = TrustEnv("movement", max_behaviors=2)
    direct.reset(seed=0)
    direct.step([19, 0])
    assert direct.step([19, 0])[3] is True


@pytest.mark.parametrize(
    "action, message",
    [
        ([-1, -1], r"-1 is not a value index of `speed` \(0 to 19\)"),
        ([0, 20], r"20 is not a value index of `padding` \(0 to 19\)"),
        ([1.5, 2.0], "value indices \\(integers\\)"),
        ([1, 2, 3], r"2 value indices, one per component \(speed, padding\), got shape \(3,\)"),
        ([True, False], "value indices \\(integers\\)"),
    ],
)
def test_invalid_actions_are_refused(action: Any, message: str) -> None:
    env = TrustEnv("movement")
    env.reset(seed=0)
    with pytest.raises(trustcbr.TrustcbrError, match=message):
        env.step(action)
    # A refused action changes nothing: the episode goes on.
    env.step(np.array([3, 4]))


def test_operators_are_checked_at_construction_and_reset() -> None:
    with pytest.raises(trustcbr.TrustcbrError, match="operators: an empty list"):
        TrustEnv("movement", operators=[])
    with pytest.raises(trustcbr.TrustcbrError, match="not a str"):
        TrustEnv("movement", operators="balanced")
    with pytest.raises(trustcbr.TrustcbrError, match="`nobody` is neither an operator of movement"):
        TrustEnv("movement", operators=["balanced", "nobody"])
    env = TrustEnv("movement", operators=["balanced"])
    with pytest.raises(trustcbr.TrustcbrError, match="`ghost` is neither an operator"):
        env.reset(seed=0, options={"operator": "ghost"})
    assert (
        env.reset(seed=0, options={"operator": "speed-focused"})[1]["operator"] == "speed-focused"
    )


def test_rgb_array_draws_the_last_behavior() -> None:
    env = TrustEnv("movement", render_mode="rgb_array")
    env.reset(seed=0)
    assert (env.render() == 255).all()
    env.step([4, 4])
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert frame.shape[0] > 100 and frame.shape[1] > 100
    # Not blank: the map has more than one colour.
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 10


def test_another_thread_is_refused_with_a_sentence() -> None:
    env = TrustEnv("movement")
    env.reset(seed=0)
    raised: List[BaseException] = []

    def use() -> None:
        try:
            env.step([1, 1])
        except BaseException as e:  # noqa: BLE001 - the test looks at what was raised
            raised.append(e)

    thread = threading.Thread(target=use)
    thread.start()
    thread.join()
    assert len(raised) == 1 and isinstance(raised[0], trustcbr.TrustcbrError)
    assert "belongs to the thread that made it" in str(raised[0])


def total(env: Any, behavior: List[int], seeds: range) -> Any:
    """The step results of `behavior`, one step per episode seeded by each of `seeds`."""
    kinds = np.zeros(3)
    stated = 0
    for seed in seeds:
        env.reset(seed=seed)
        observation, _, _, _, info = env.step(np.array(behavior))
        kinds += observation[1:4]
        stated += info["stated"]
    return kinds, stated


def test_a_step_states_reasons_through_the_operator_s_feedback_channel(tmp_path: Any) -> None:
    # The balanced operator, made to say why every time it stops or fails a command.
    talkative = tmp_path / "talkative.ron"
    talkative.write_text(
        '(name: "talkative", t_complete: 15.0, p_deadline: 0.95, p_collision: 0.95,'
        " feedback: (explains: 1.0, wrong: 0.0))"
    )
    fast = [len(c["values"]) - 1 for c in trustcbr.space("movement")["components"]]
    kinds, stated = total(TrustEnv("movement", operators=[str(talkative)]), fast, range(20))
    assert kinds[1] + kinds[2] > 0, "the fastest behavior draws untrustworthy commands"
    assert stated == kinds[1] + kinds[2], "every one explained"
    silent, said = total(TrustEnv("movement", operators=["balanced"]), fast, range(20))
    assert said == 0 and silent[1] + silent[2] > 0


def test_a_step_s_operator_pays_the_attention_it_is_given() -> None:
    # The fastest speed with no padding: an attentive operator stops the robot before it
    # hits someone; one paying no attention stops nothing, and the collisions happen.
    speed = len(trustcbr.space("movement")["components"][0]["values"]) - 1
    reckless = [speed, 0]
    attentive, _ = total(TrustEnv("movement", operators=["balanced"]), reckless, range(20))
    distracted, _ = total(
        TrustEnv("movement", operators=["balanced"], attention=0.0), reckless, range(20)
    )
    assert attentive[2] > 0 and distracted[2] == 0
    assert distracted[1] > attentive[1], "failures no one stopped"
    with pytest.raises(trustcbr.TrustcbrError, match="attention: a share from 0 to 1"):
        TrustEnv("movement", attention=1.5)
