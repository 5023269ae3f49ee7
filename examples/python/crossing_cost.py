"""What one proposal of a search strategy written in Python costs over a built-in one.

Runs the same patrol experiment with the built-in ``uniform`` arm and with the same
strategy written in Python (an untried behavior uniformly at random), single-threaded
both, and divides the difference in run time by the number of proposals the Python arm
made. A benchmark, not a test: numbers depend on the machine (docs/benchmarks.md).

Usage: ``python examples/python/crossing_cost.py [--trials 200]``
"""

from __future__ import annotations

import argparse
import random
import time
from typing import Dict, List, Optional, Tuple

import trustcbr


class PythonUniform:
    """An untried behavior uniformly at random, by rejection."""

    def __init__(self, space: trustcbr.Space) -> None:
        self.components = [(c["name"], c["values"]) for c in space["components"]]

    def propose(
        self, evaluated: List[trustcbr.Evaluated], rng: random.Random
    ) -> Optional[trustcbr.Behavior]:
        tried = {tuple(e["behavior"].values()) for e in evaluated}
        while True:
            behavior: Dict[str, float | str] = {n: rng.choice(v) for n, v in self.components}
            if tuple(behavior.values()) not in tried:
                return behavior


def timed(arm: str, trials: int) -> Tuple[float, int]:
    """Seconds to run the experiment with ``arm`` alone, and its proposals."""
    suite = {
        "seed": 1,
        "trials": trials,
        "arms": [arm],
        "landscape_runs": 0,
        "limit": {"runs": 0},
        "experiments": [{"scenario": "patrol", "operator": "detection-focused"}],
    }
    started = time.perf_counter()
    results = trustcbr.run(suite, threads=1, python_arms={"python-uniform": PythonUniform})
    elapsed = time.perf_counter() - started
    return elapsed, sum(t["searched"] for t in results.trials)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=200)
    args = parser.parse_args()
    builtin, builtin_proposals = min(timed("uniform", args.trials) for _ in range(3))
    python, python_proposals = min(timed("python-uniform", args.trials) for _ in range(3))
    per_builtin = builtin / builtin_proposals * 1e6
    per_python = python / python_proposals * 1e6
    print(f"built-in uniform: {builtin:.3f} s, {builtin_proposals} proposals")
    print(f"python uniform:   {python:.3f} s, {python_proposals} proposals")
    print(f"trial time per proposal: built-in {per_builtin:.0f} us, Python {per_python:.0f} us")
    print(f"a Python proposal adds about {per_python - per_builtin:.0f} us")


if __name__ == "__main__":
    main()
