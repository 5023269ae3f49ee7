"""A simple agent trained on the Gymnasium environment, against the random agent and the
known-operator limit.

    python examples/python/gym_agent.py --train 300 --test 100

The agent remembers which behaviors operators came to trust (a count per behavior, over
every episode so far) and tries them in that order, untried ones at random, exploring at
random a tenth of the time while it trains: a behavior many operators trust is a good
first try for the next, unknown one. An episode's return is minus its untrustworthy
commands. The known-operator limit is what an agent that knew the episode's operator
would pay (nothing: it starts with a behavior that operator trusts); the population's
operators share behaviors every one of them trusts, so an agent that learns them
approaches it.
"""

from __future__ import annotations

import argparse
import random
import statistics
from collections import Counter
from typing import Any, Callable, List, Optional, Set, Tuple

import gymnasium

import trustcbr
import trustcbr.gym  # noqa: F401  (registers trustcbr/Patrol-v0)

Action = Tuple[int, ...]


class TrustMemory:
    """Behaviors ranked by how many episodes ended trusting them."""

    def __init__(self, sizes: List[int], rng: random.Random) -> None:
        self.sizes = sizes
        self.rng = rng
        self.trusted: Counter[Action] = Counter()

    def act(self, tried: Set[Action], explore: float) -> Action:
        if self.rng.random() >= explore:
            for action, _ in self.trusted.most_common():
                if action not in tried:
                    return action
        while True:
            action = tuple(self.rng.randrange(n) for n in self.sizes)
            if action not in tried:
                return action

    def learn(self, action: Action) -> None:
        self.trusted[action] += 1


def episode(
    env: Any, seed: int, choose: Callable[[Set[Action]], Action]
) -> Tuple[float, Optional[Action]]:
    """One episode's return, and the behavior trusted at its end (if any)."""
    env.reset(seed=seed)
    tried: Set[Action] = set()
    total, done, action = 0.0, False, None
    while not done:
        action = choose(tried)
        tried.add(action)
        _, reward, terminated, truncated, info = env.step(list(action))
        total += reward
        done = terminated or truncated
    return total, action if info["trusted"] else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--train", type=int, default=300, help="training episodes")
    parser.add_argument("--test", type=int, default=100, help="test episodes (new seeds)")
    args = parser.parse_args()
    env = gymnasium.make("trustcbr/Patrol-v0")
    sizes = [int(n) for n in env.action_space.nvec]
    rng = random.Random(0)

    def random_choice(tried: Set[Action]) -> Action:
        while True:
            action = tuple(rng.randrange(n) for n in sizes)
            if action not in tried:
                return action

    test_seeds = range(10_000, 10_000 + args.test)
    random_returns = [episode(env, s, random_choice)[0] for s in test_seeds]

    memory = TrustMemory(sizes, random.Random(1))
    for seed in range(args.train):
        _, trusted = episode(env, seed, lambda tried: memory.act(tried, explore=0.1))
        if trusted is not None:
            memory.learn(trusted)
    learned_returns = [episode(env, s, lambda tried: memory.act(tried, 0.0))[0] for s in test_seeds]
    env.close()

    # The limit of an agent that knows the operator (the report's "free first choice"),
    # estimated for the environment's operators by the library, as a report does.
    limits = trustcbr.run(
        {
            "seed": 1,
            "trials": 1,
            "arms": ["uniform"],
            "landscape_runs": 0,
            "experiments": [
                {"scenario": "patrol", "operator": name} for name in trustcbr.operators("patrol")
            ],
        },
        progress=False,
    )
    known = statistics.mean(
        e["limit"]["free_first_choice"]["untrustworthy"] for e in limits.summary["experiments"]
    )
    print(f"mean return over {args.test} test episodes (minus untrustworthy commands):")
    print(f"  random agent:                       {statistics.mean(random_returns):8.1f}")
    print(f"  trust memory after {args.train} episodes: {statistics.mean(learned_returns):8.1f}")
    print(f"  known-operator limit:               {-known:8.1f}")


if __name__ == "__main__":
    main()
