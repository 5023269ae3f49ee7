"""Optuna's TPE sampler as arms of trustcbr's experiments, beside the built-in arms.

Two arms, each a trustcbr searcher written in Python (docs/python.md):

- ``tpe-cold``: a fresh TPE study every episode, told how long each behavior of the
  episode resisted before the operator stopped trusting it;
- ``tpe-warm``: one study for the whole experiment, warm-started with every earlier
  episode's evaluations (the behaviors given up, with their times, and the behavior each
  episode settled on, scored above any time seen).

A behavior is one integer parameter per component (the index of its value, so TPE sees
the values' order); TPE maximises the time a behavior resisted. A proposal TPE repeats
within an episode is told its known value and asked again, and after a few repeats an
untried behavior is drawn instead, so every proposal is untried, as the searcher
conformance kit demands.

Usage::

    pip install ./python optuna
    python examples/python/optuna_arm.py --trials 500 --out results-optuna

prints the table of every arm (behaviors evaluated per trial, mean and 95% CI), each
arm's ratio to the known-operator limit, and writes the report folder.
"""

from __future__ import annotations

import random
from typing import Any, Dict, List, Optional

import optuna
from arm_script import Indexed, Params, run_arms  # beside this file

import trustcbr

# TPE draws its first behaviors of a study at random; fewer than Optuna's default of 10,
# because an episode rarely tries ten.
STARTUP = 4
# How often a repeated proposal is told its value and TPE asked again.
RETRIES = 8


class TpeSearcher:
    """A TPE study proposing behaviors; ``warm`` keeps one study across episodes."""

    def __init__(self, space: trustcbr.Space, warm: bool) -> None:
        self.space = Indexed(space)
        self.warm = warm
        self.learns_across_episodes = warm
        self.distributions: Dict[str, optuna.distributions.BaseDistribution] = {
            name: optuna.distributions.IntDistribution(0, len(values) - 1)
            for name, values in zip(self.space.names, self.space.values)
        }
        self.study: Optional[optuna.Study] = None
        self.best = 1.0

    def _record(self, params: Params, value: float) -> None:
        assert self.study is not None
        self.best = max(self.best, value)
        self.study.add_trial(
            optuna.trial.create_trial(
                params=dict(zip(self.space.names, params)),
                distributions=self.distributions,
                value=value,
            )
        )

    def begin_episode(self, initial: trustcbr.Behavior) -> None:
        self.told = 0
        if not self.warm:
            self.study = None

    def _study(self, rng: random.Random) -> optuna.Study:
        if self.study is None:
            sampler = optuna.samplers.TPESampler(
                n_startup_trials=STARTUP, seed=rng.getrandbits(32), multivariate=True
            )
            self.study = optuna.create_study(direction="maximize", sampler=sampler)
        return self.study

    def propose(
        self, evaluated: List[trustcbr.Evaluated], rng: random.Random
    ) -> Optional[trustcbr.Behavior]:
        study = self._study(rng)
        # Tell the study what it has not heard yet: the behaviors given up since.
        for e in evaluated[self.told :]:
            self._record(self.space.params(e["behavior"]), e["time"])
        self.told = len(evaluated)
        tried: Dict[Params, float] = {
            self.space.params(e["behavior"]): e["time"] for e in evaluated
        }
        if len(tried) >= self.space.size:
            return None
        for _ in range(RETRIES):
            trial = study.ask(self.distributions)
            params = tuple(trial.params[n] for n in self.space.names)
            if params not in tried:
                study.tell(trial, state=optuna.trial.TrialState.FAIL)
                return self.space.behavior(params)
            study.tell(trial, tried[params])
        untried = [p for p in self.space.every() if p not in tried]
        return self.space.behavior(rng.choice(untried))

    def end_episode(
        self, evaluated: List[trustcbr.Evaluated], settled: Optional[trustcbr.Behavior]
    ) -> None:
        if not self.warm or self.study is None:
            return
        for e in evaluated[self.told :]:
            self._record(self.space.params(e["behavior"]), e["time"])
        trusted = {self.space.params(e["behavior"]) for e in evaluated}
        if settled is not None and self.space.params(settled) not in trusted:
            # Trusted: scored above any time a rejected behavior resisted.
            self._record(self.space.params(settled), 2.0 * self.best)
        self.told = 0

    def rationale(self, proposed: trustcbr.Behavior) -> str:
        return "Optuna's TPE sampler" + (" (warm-started)" if self.warm else "")


def cold(space: trustcbr.Space) -> TpeSearcher:
    """A TPE searcher starting afresh every episode."""
    return TpeSearcher(space, warm=False)


def warm(space: trustcbr.Space) -> TpeSearcher:
    """A TPE searcher warm-started with every earlier episode's evaluations."""
    return TpeSearcher(space, warm=True)


TPE_ARMS = {"tpe-cold": cold, "tpe-warm": warm}

ARMS = [
    "random-walk",
    "case-based",
    "uniform",
    "cause-aware",
    "model-based",
    "conditioned",
    "case-based+model-based",
    "case-based+conditioned",
    "tpe-cold",
    "tpe-warm",
]


def tpe_arms(arms: List[str]) -> Dict[str, trustcbr.SearcherFactory]:
    """The factories of the TPE arms named in ``arms``."""
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    return {name: factory for name, factory in TPE_ARMS.items() if name in arms}


def main() -> None:
    run_arms(__doc__.split("\n\n")[0], ARMS, 500, tpe_arms, table)


def table(results: trustcbr.Results, arms: List[str]) -> str:
    """Behaviors evaluated per trial (mean ± 95% CI) and the ratio to the known-operator
    limit, one row per experiment, one column per arm."""
    rows = ["| experiment | limit | " + " | ".join(arms) + " |"]
    rows.append("|---|---:|" + "---:|" * len(arms))
    for experiment in results.summary["experiments"]:
        strategies: Dict[str, Any] = experiment["strategies"]
        limit = experiment.get("limit") or {}
        known = limit.get("paper_protocol", {}).get("behaviors")
        cells = []
        for arm in arms:
            s = strategies[arm]
            ratio = (s.get("ratio_to_limit") or {}).get("behaviors")
            cells.append(
                f"{s['mean']:.2f} ± {s['ci95']:.2f}"
                + (f" ({ratio:.1f}x)" if ratio is not None else "")
            )
        rows.append(
            f"| {experiment['name']} | {known:.2f} | " + " | ".join(cells) + " |"
            if known is not None
            else f"| {experiment['name']} | - | " + " | ".join(cells) + " |"
        )
    return "\n".join(rows)


if __name__ == "__main__":
    main()
