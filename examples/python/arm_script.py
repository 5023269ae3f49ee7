"""The command line the example arm scripts share (optuna_arm.py, peers_arm.py).

It runs the paper's seven experiments or a suite with the named arms, some of them
searchers written in Python, prints the script's table of the results and how long the
run took, and writes the report folder when asked.
"""

from __future__ import annotations

import argparse
import time
from typing import Callable, Dict, List

import trustcbr


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
