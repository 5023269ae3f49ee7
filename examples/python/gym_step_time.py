"""The cost of one step of the Gymnasium environment: a random agent on patrol.

Run against a release build of the package (``pip install ./python[gym]`` builds one):

    python examples/python/gym_step_time.py --episodes 200

Prints the median time of a step (one behavior's commands until the operator trusts it,
gives it up, or ``max_commands`` pass), the mean behaviors an episode and the machine.
docs/python.md quotes its output.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import gymnasium

import trustcbr.gym  # noqa: F401  (registers trustcbr/Patrol-v0)


def cpu() -> str:
    """The processor's model name (Linux), else the architecture."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--env", default="trustcbr/Patrol-v0")
    args = parser.parse_args()
    env = gymnasium.make(args.env)
    env.action_space.seed(0)
    times = []
    steps_per_episode = []
    for episode in range(args.episodes):
        env.reset(seed=episode)
        done, steps = False, 0
        while not done:
            action = env.action_space.sample()
            started = time.perf_counter()
            _, _, terminated, truncated, _ = env.step(action)
            times.append(time.perf_counter() - started)
            done = terminated or truncated
            steps += 1
        steps_per_episode.append(steps)
    env.close()
    median_ms = statistics.median(times) * 1000
    print(
        f"{args.env}: {len(times)} steps in {args.episodes} episodes "
        f"({statistics.mean(steps_per_episode):.1f} behaviors an episode); "
        f"median step {median_ms:.3f} ms, mean {statistics.mean(times) * 1000:.3f} ms"
    )
    print(f"machine: {cpu()}, {os.cpu_count()} cores, Python {platform.python_version()}")


if __name__ == "__main__":
    main()
