"""What the example arm scripts share (optuna_arm.py, peers_arm.py): a space's behaviors
as tuples of value indices, and the command line.

The command line runs the paper's seven experiments or a suite with the named arms, some
of them searchers written in Python, prints the script's table of the results and how long
the run took, and writes the report folder when asked.
"""

from __future__ import annotations

import argparse
import random
import time
from typing import Callable, Collection, Dict, List, Tuple

import trustcbr

Params = Tuple[int, ...]


class Indexed:
    """A space's behaviors as tuples of value indices."""

    def __init__(self, space: trustcbr.Space) -> None:
        self.names = [c["name"] for c in space["components"]]
        self.values = [c["values"] for c in space["components"]]
        self.size = space["behaviors"]

    def params(self, behavior: trustcbr.Behavior) -> Params:
        return tuple(vs.index(behavior[n]) for n, vs in zip(self.names, self.values))

    def behavior(self, params: Params) -> trustcbr.Behavior:
        return {n: vs[i] for n, vs, i in zip(self.names, self.values, params)}

    def draw(self, rng: random.Random) -> Params:
        return tuple(rng.randrange(len(vs)) for vs in self.values)

    def untried(self, tried: Collection[Params], count: int, rng: random.Random) -> List[Params]:
        """Up to ``count`` distinct untried behaviors drawn uniformly (every untried one, in
        a random order, when there are no more than ``count``)."""
        if self.size - len(tried) <= count:
            out = [p for p in self.every() if p not in tried]
            rng.shuffle(out)
            return out
        drawn: Dict[Params, None] = {}
        while len(drawn) < count:
            p = self.draw(rng)
            if p not in tried:
                drawn[p] = None
        return list(drawn)

    def neighbours(self, params: Params) -> List[Params]:
        """The behaviors one value away from ``params`` in one component."""
        out = []
        for k, values in enumerate(self.values):
            for step in (-1, 1):
                i = params[k] + step
                if 0 <= i < len(values):
                    out.append(params[:k] + (i,) + params[k + 1 :])
        return out

    def every(self) -> List[Params]:
        out: List[Params] = [()]
        for values in self.values:
            out = [p + (i,) for p in out for i in range(len(values))]
        return out


def run_arms(
    description: str,
    default_arms: List[str],
    default_trials: int,
    python_arms: Callable[[List[str]], Dict[str, trustcbr.SearcherFactory]],
    table: Callable[[trustcbr.Results, List[str]], str],
) -> None:
    """Parses the command line, runs the arms (``python_arms`` gives the factories of the
    Python arms among those named) and prints ``table`` of the results."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--trials", type=int, default=default_trials)
    parser.add_argument("--suite", help="a suite file (default: the paper's seven experiments)")
    parser.add_argument("--out", help="write the report folder here")
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument(
        "--arms",
        help="the arms to run, separated by commas (default: "
        + ", ".join(default_arms)
        + "); every trial is paired across arms whichever run",
    )
    args = parser.parse_args()
    arms = args.arms.split(",") if args.arms else default_arms
    factories = python_arms(arms)
    started = time.perf_counter()
    results = trustcbr.run(
        args.suite,
        trials=args.trials,
        seed=args.seed,
        arms=arms,
        out=args.out,
        python_arms=factories,
    )
    elapsed = time.perf_counter() - started
    print(table(results, arms))
    print(f"\n{args.trials} trials per experiment and arm in {elapsed:.0f} s")
