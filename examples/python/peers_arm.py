"""Vowpal Wabbit's contextual bandit and scikit-optimize as arms of trustcbr's experiments.

Two arms, each a trustcbr searcher written in Python (docs/python.md), both learning
across episodes (one learner per experiment, fed every episode of its chain of trials):

- ``vw``: Vowpal Wabbit's contextual bandit (``--cb_explore_adf``). The context is the
  episode's evidence: the component values of every behavior given up so far (namespace
  ``r``) and of the one that resisted longest (namespace ``b``). The actions are a pool of
  untried behaviors drawn afresh for each proposal: 64 drawn uniformly, the untried
  neighbours of the longest-resisting behavior (one component one value away), and the
  untried ones among the last 16 behaviors episodes settled on; each action's features are its
  component values, one categorical feature per component (namespace ``a``). Interactions
  ``ra`` and ``ba`` let the evidence change what a value is worth; ``aa`` lets the learner
  value pairs of values (on movement's two components, whole behaviors). The cost
  of a proposal, learned with the probability VW gave it, is 1 when the operator gave it
  up and 0 when the episode settled on it. Exploration is epsilon-greedy with
  ``--epsilon 0.05``, VW's default for ``cb_explore_adf``, chosen before any run: the pool
  already brings 64 fresh random behaviors to every proposal and an episode never repeats
  one, so the learner meets new actions without being told to explore, while every
  exploratory proposal costs the operator untrustworthy commands; ``--squarecb``, whose
  exploration grows with the number of actions, would spread its choices over a pool of
  some 80 behaviors nearly uniformly for hundreds of proposals, and a chain has a few
  hundred to a few thousand.
- ``skopt``: scikit-optimize's ``Optimizer``, warm across episodes as ``tpe-warm`` is
  (examples/python/optuna_arm.py): one optimizer fed every episode's evaluations, the
  behaviors given up with how long they resisted and the behavior each episode settled on
  scored above any time seen; it minimises minus that time. Each component is an integer
  dimension (its value's index, so the model sees the order). A proposal is the
  optimizer's ``ask``; one already evaluated in the episode is told its known value and the
  optimizer asked again, and after 8 repeats an untried behavior is drawn, as
  ``tpe-warm`` does (chosen on the development populations over proposing the untried
  behavior of highest expected improvement: docs/peers.md). skopt's own refusal to
  propose a point told before is turned off (``avoid_duplicates=False``): it would
  replace every behavior an earlier operator trusted by a random one, and proposing those
  again is what a warm optimizer is for. The optimizer refits its surrogate at every
  ``tell``, so once per ``ask``, and on movement a proposal takes 3 to 6 asks, the
  optimizer holding hundreds to thousands of points; hence skopt's extra-trees forest
  (``"ET"``, ``forest_minimize``'s) with 10 trees instead of its 100
  (``min_samples_leaf=3`` as its own), expected improvement (``forest_minimize``'s
  default) maximised over 1,000 random points (``acq_optimizer="sampling"``, against its
  10,000), and scikit-learn's input checks skipped (most of a small forest's fitting
  time): an ask takes 12 to 21 ms. skopt's Gaussian process, refitted with its
  hyperparameters at every ask, took 2.2 s an ask on 300 movement points and 12 s on
  1,000. 4 random points before the first fit, as ``tpe-warm``'s 4 start-up trials.

Every proposal is untried in its episode, as the searcher conformance kit demands, and
every random draw (VW's choice from its distribution, the pool, skopt's seed) comes from
the trial's ``rng``. Like the built-in arms they learn from outcomes only.

Usage::

    pip install ./python vowpalwabbit==9.11.9 scikit-optimize==0.10.2
    python examples/python/peers_arm.py --suite domains/experiments/benchmark-movement.ron \\
        --trials 50 --arms case-based+reliable,case-based+hedged,vw,skopt --out results-peers

prints, for a benchmark suite, each arm's geometric mean ratio to the populations'
known-operator limits (else behaviors evaluated per trial, mean and 95% CI, per
experiment), and writes the report folder. ``tpe-warm`` and ``tpe-cold`` may be named in
``--arms`` too (they come from optuna_arm.py, beside this file, and need optuna).
"""

from __future__ import annotations

import random
import warnings
from typing import Any, Dict, List, Optional, Tuple

import sklearn  # type: ignore[import-untyped]
import vowpalwabbit  # type: ignore[import-untyped]
from arm_script import Indexed, Params, run_arms  # beside this file
from skopt import Optimizer  # type: ignore[import-untyped]
from skopt.learning import ExtraTreesRegressor  # type: ignore[import-untyped]
from skopt.space import Integer  # type: ignore[import-untyped]

import trustcbr

# The pool of actions a proposal of `vw` chooses from: uniform draws, and the untried
# behaviors the most recent episodes settled on.
POOL = 64
REMEMBERED = 16
VW_ARGS = "--cb_explore_adf --epsilon 0.05 -q ra -q ba -q aa --quiet"

# skopt: points before the first fit, trees of the forest, random points the acquisition
# is maximised over, and how often a repeated proposal is told its value and the optimizer
# asked again.
STARTUP = 4
TREES = 10
ACQUISITION_POINTS = 1000
RETRIES = 8


class VwSearcher:
    """Vowpal Wabbit's contextual bandit choosing among a pool of untried behaviors."""

    learns_across_episodes = True

    def __init__(self, space: trustcbr.Space) -> None:
        self.space = Indexed(space)
        self.vw = vowpalwabbit.Workspace(VW_ARGS)
        # The proposal whose cost is not known yet: the behavior, the example it was
        # chosen from, its index there and the probability VW gave it.
        self.pending: Optional[Tuple[Params, List[str], int, float]] = None
        self.settled: List[Params] = []

    def begin_episode(self, initial: trustcbr.Behavior) -> None:
        self.pending = None

    @staticmethod
    def _features(params: Params) -> str:
        return " ".join(f"c{k}v{i}" for k, i in enumerate(params))

    def _learn(self, cost: float) -> None:
        assert self.pending is not None
        _, lines, chosen, probability = self.pending
        labelled = list(lines)
        labelled[chosen + 1] = f"0:{cost}:{probability} {lines[chosen + 1]}"
        self.vw.learn(labelled)
        self.pending = None

    def propose(
        self, evaluated: List[trustcbr.Evaluated], rng: random.Random
    ) -> Optional[trustcbr.Behavior]:
        given_up = [self.space.params(e["behavior"]) for e in evaluated]
        tried = set(given_up)
        if self.pending is not None:
            # The previous proposal was given up (if it was used at all).
            if self.pending[0] in tried:
                self._learn(1.0)
            self.pending = None
        if len(tried) >= self.space.size:
            return None
        pool: Dict[Params, None] = dict.fromkeys(self.space.untried(tried, POOL, rng))
        best: Optional[Params] = None
        if evaluated:
            best = given_up[max(range(len(evaluated)), key=lambda i: evaluated[i]["time"])]
            pool.update(dict.fromkeys(p for p in self.space.neighbours(best) if p not in tried))
        pool.update(dict.fromkeys(p for p in self.settled[::-1][:REMEMBERED] if p not in tried))
        actions = list(pool)
        rng.shuffle(actions)  # VW breaks ties by order
        shared = "shared |r " + " ".join(self._features(p) for p in given_up)
        if best is not None:
            shared += " |b " + self._features(best)
        lines = [shared] + ["|a " + self._features(p) for p in actions]
        pmf: List[float] = self.vw.predict(lines)
        u = rng.random() * sum(pmf)
        chosen = len(actions) - 1
        for i, p in enumerate(pmf):
            u -= p
            if u < 0:
                chosen = i
                break
        self.pending = (actions[chosen], lines, chosen, pmf[chosen])
        return self.space.behavior(actions[chosen])

    def end_episode(
        self, evaluated: List[trustcbr.Evaluated], settled: Optional[trustcbr.Behavior]
    ) -> None:
        kept = self.space.params(settled) if settled is not None else None
        if self.pending is not None:
            self._learn(0.0 if self.pending[0] == kept else 1.0)
        if kept is not None:
            if kept in self.settled:
                self.settled.remove(kept)
            self.settled.append(kept)

    def rationale(self, proposed: trustcbr.Behavior) -> str:
        return "Vowpal Wabbit's contextual bandit (epsilon-greedy over untried behaviors)"


class SkoptSearcher:
    """One scikit-optimize optimizer, warm-started with every earlier episode."""

    learns_across_episodes = True

    def __init__(self, space: trustcbr.Space) -> None:
        self.space = Indexed(space)
        # The optimizer's dimensions: the components with more than one value.
        self.free = [k for k, vs in enumerate(self.space.values) if len(vs) > 1]
        self.optimizer: Optional[Any] = None
        # Points not told the optimizer yet (it minimises: minus the time resisted).
        self.xs: List[List[int]] = []
        self.ys: List[float] = []
        self.told = 0
        self.best = 1.0

    def _record(self, params: Params, value: float) -> None:
        self.best = max(self.best, value)
        self.xs.append([params[k] for k in self.free])
        self.ys.append(-value)

    def _ask(self, rng: random.Random) -> Params:
        """Tells the optimizer what it has not heard yet (one fit of its forest) and asks
        it for a behavior."""
        if self.optimizer is None:
            self.optimizer = Optimizer(
                [Integer(0, len(self.space.values[k]) - 1) for k in self.free],
                base_estimator=ExtraTreesRegressor(
                    n_estimators=TREES, min_samples_leaf=3, random_state=rng.getrandbits(31)
                ),
                n_initial_points=STARTUP,
                acq_func="EI",
                acq_optimizer="sampling",
                acq_optimizer_kwargs={"n_points": ACQUISITION_POINTS},
                random_state=rng.getrandbits(32),
                avoid_duplicates=False,
            )
        # Validation is most of a small forest's fitting time; the points are ours.
        with sklearn.config_context(assume_finite=True, skip_parameter_validation=True):
            return self._tell_and_ask()

    def _tell_and_ask(self) -> Params:
        assert self.optimizer is not None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # skopt warns of every point asked twice
            if self.xs:
                self.optimizer.tell(self.xs, self.ys)
                self.xs, self.ys = [], []
            x = dict(zip(self.free, (int(i) for i in self.optimizer.ask())))
        return tuple(x.get(k, 0) for k in range(len(self.space.values)))

    def begin_episode(self, initial: trustcbr.Behavior) -> None:
        self.told = 0

    def propose(
        self, evaluated: List[trustcbr.Evaluated], rng: random.Random
    ) -> Optional[trustcbr.Behavior]:
        for e in evaluated[self.told :]:
            self._record(self.space.params(e["behavior"]), e["time"])
        self.told = len(evaluated)
        tried: Dict[Params, float] = {
            self.space.params(e["behavior"]): e["time"] for e in evaluated
        }
        if len(tried) >= self.space.size:
            return None
        for _ in range(RETRIES if self.free else 0):
            params = self._ask(rng)
            if params not in tried:
                return self.space.behavior(params)
            self._record(params, tried[params])
        return self.space.behavior(self.space.untried(tried, 1, rng)[0])

    def end_episode(
        self, evaluated: List[trustcbr.Evaluated], settled: Optional[trustcbr.Behavior]
    ) -> None:
        for e in evaluated[self.told :]:
            self._record(self.space.params(e["behavior"]), e["time"])
        given_up = {self.space.params(e["behavior"]) for e in evaluated}
        if settled is not None and self.space.params(settled) not in given_up:
            # Trusted: scored above any time a rejected behavior resisted.
            self._record(self.space.params(settled), 2.0 * self.best)
        self.told = 0

    def rationale(self, proposed: trustcbr.Behavior) -> str:
        return "scikit-optimize's extra-trees optimizer (warm-started)"


def vw_searcher(space: trustcbr.Space) -> VwSearcher:
    """Vowpal Wabbit's contextual bandit, one learner for the whole chain of trials."""
    return VwSearcher(space)


def skopt_searcher(space: trustcbr.Space) -> SkoptSearcher:
    """A scikit-optimize optimizer warm-started with every earlier episode's evaluations."""
    return SkoptSearcher(space)


PEER_ARMS: Dict[str, trustcbr.SearcherFactory] = {"vw": vw_searcher, "skopt": skopt_searcher}

ARMS = ["uniform", "case-based+hedged", "case-based+reliable", "vw", "skopt"]


def python_arms(arms: List[str]) -> Dict[str, trustcbr.SearcherFactory]:
    """The factories of the Python arms named in ``arms``: this file's, and optuna_arm.py's
    when a TPE arm is named."""
    factories: Dict[str, trustcbr.SearcherFactory] = {
        name: factory for name, factory in PEER_ARMS.items() if name in arms
    }
    if any(arm.startswith("tpe-") for arm in arms):
        import optuna_arm  # beside this file

        factories.update(optuna_arm.tpe_arms(arms))
    return factories


def main() -> None:
    run_arms(__doc__.split("\n\n")[0], ARMS, 100, python_arms, table)


def ratio(r: Optional[Dict[str, Any]]) -> str:
    """A geometric mean ratio with its bootstrap interval, ``1.59 [1.13, 2.25]``."""
    if r is None:
        return "-"
    return f"{r['geometric_mean']:.2f} [{r['ci95_low']:.2f}, {r['ci95_high']:.2f}]"


def table(results: trustcbr.Results, arms: List[str]) -> str:
    """A benchmark suite's geometric mean ratios to the known-operator limit per scenario
    and arm (behaviors, untrustworthy commands, and the untrustworthy ratio in each window
    of trials); another suite's behaviors evaluated per trial, mean ± 95% CI."""
    benchmark = results.summary.get("benchmark")
    if not benchmark:
        rows = ["| experiment | " + " | ".join(arms) + " |", "|---|" + "---:|" * len(arms)]
        for experiment in results.summary["experiments"]:
            strategies: Dict[str, Any] = experiment["strategies"]
            cells = [f"{strategies[a]['mean']:.2f} ± {strategies[a]['ci95']:.2f}" for a in arms]
            rows.append(f"| {experiment['name']} | " + " | ".join(cells) + " |")
        return "\n".join(rows)
    rows = []
    for scenario in benchmark:
        windows = " / ".join(f"{a}-{b}" for a, b in scenario["windows"])
        count = len(scenario["populations"])
        rows.append(f"\n{scenario['scenario']} ({count} populations)\n")
        rows.append(f"| arm | behaviors | untrustworthy | untrustworthy, trials {windows} |")
        rows.append("|---|---:|---:|---:|")
        for arm in arms:
            a = scenario["arms"][arm]
            over = " / ".join(
                f"{w['untrustworthy']:.2f}" if w["untrustworthy"] is not None else "-"
                for w in a["ratio_to_limit_over_trials"]
            )
            to_limit = a["ratio_to_limit"]
            rows.append(
                f"| `{arm}` | {ratio(to_limit['behaviors'])} | "
                f"{ratio(to_limit['untrustworthy'])} | {over} |"
            )
    return "\n".join(rows)


if __name__ == "__main__":
    main()
