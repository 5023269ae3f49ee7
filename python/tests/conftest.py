"""Shared fixtures of the Python tests: small suites and a simple Python searcher."""

from __future__ import annotations

import random
from typing import Any, Dict, List, Optional

import pytest

import trustcbr


class UniformSearcher:
    """An untried behavior drawn uniformly at random (the `uniform` arm, in Python)."""

    def __init__(self, space: trustcbr.Space) -> None:
        self.components = [(c["name"], c["values"]) for c in space["components"]]
        self.size = space["behaviors"]
        self.observed: List[Dict[str, Any]] = []

    def propose(
        self, evaluated: List[trustcbr.Evaluated], rng: random.Random
    ) -> Optional[trustcbr.Behavior]:
        tried = {tuple(sorted(e["behavior"].items())) for e in evaluated}
        if len(tried) >= self.size:
            return None
        untried = []
        for k in range(self.size):
            behavior: Dict[str, Any] = {}
            for name, values in reversed(self.components):
                behavior[name] = values[k % len(values)]
                k //= len(values)
            if tuple(sorted(behavior.items())) not in tried:
                untried.append(behavior)
        return rng.choice(untried)

    def observe(self, behavior: trustcbr.Behavior, outcome: Dict[str, Any]) -> None:
        self.observed.append(outcome)

    def rationale(self, proposed: trustcbr.Behavior) -> str:
        return "an untried behavior uniformly at random"


def small_suite(**overrides: Any) -> Dict[str, Any]:
    """One movement experiment, few trials, no landscapes or limit: seconds to run."""
    suite: Dict[str, Any] = {
        "seed": 7,
        "trials": 12,
        "arms": ["random-walk", "case-based"],
        "landscape_runs": 0,
        "limit": {"runs": 0},
        "experiments": [{"scenario": "movement", "operator": "balanced"}],
    }
    suite.update(overrides)
    return suite


@pytest.fixture
def uniform_factory() -> Any:
    return UniformSearcher
