"""A Gymnasium environment over trustcbr's simulated robot (needs the ``gym`` extra:
``pip install ./python[gym]``).

One episode is one operator (drawn from the scenario's built-in operators, or the ones
given); an action is a behavior, one value index per component (``MultiDiscrete``); the
environment runs the behavior's commands in front of the operator and tells the trust
adapter (:class:`trustcbr.Adapter`, the library's own estimate and thresholds) each
outcome until the operator trusts it (the episode ends) or stops trusting it (the step
ends and the agent picks another behavior). The observation is what the robot perceived
over the behavior's commands: the number of commands, then how many ended completed,
failed and interrupted, then how many perceived each declared observation. The reward is
minus the behavior's untrustworthy commands (failed or interrupted).
"""

from __future__ import annotations

import os
import tempfile
from typing import Any, Dict, List, Optional, Sequence, Tuple

import gymnasium
import numpy as np
from gymnasium import spaces

import trustcbr

KINDS = ("completed", "failed", "interrupted")


class TrustEnv(gymnasium.Env[Any, Any]):
    """Find a behavior the operator trusts, with as few untrustworthy commands as possible.

    ``scenario`` is a built-in scenario; ``operators`` names the operators an episode
    draws from (built-in names or operator files; default: every built-in one);
    ``max_commands`` ends a behavior's step when its trust stays between the thresholds
    that long (the episode is then truncated).
    """

    metadata: Dict[str, Any] = {"render_modes": []}

    def __init__(
        self,
        scenario: str = "movement",
        operators: Optional[Sequence[str]] = None,
        max_commands: int = 500,
    ) -> None:
        super().__init__()
        described = trustcbr.space(scenario)
        self.scenario = scenario
        self.operators: List[str] = list(operators or trustcbr.operators(scenario))
        if not self.operators:
            raise trustcbr.TrustcbrError(f"scenario `{scenario}` has no operators")
        self.components = described["components"]
        self.observations: List[str] = list(described.get("observations", []))
        self.max_commands = max_commands
        self.action_space = spaces.MultiDiscrete([len(c["values"]) for c in self.components])
        self._shape = (1 + len(KINDS) + len(self.observations),)
        self.observation_space = spaces.Box(
            low=0.0, high=float(max_commands), shape=self._shape, dtype=np.float32
        )
        self._dir = tempfile.TemporaryDirectory(prefix="trustcbr-gym-")
        self._cases = os.path.join(self._dir.name, "cases.db")
        self._adapter: Optional[trustcbr.Adapter] = None
        self.operator = self.operators[0]

    def _behavior(self, action: Any) -> trustcbr.Behavior:
        index = np.asarray(action, dtype=np.int64).reshape(-1)
        return {c["name"]: c["values"][int(i)] for c, i in zip(self.components, index)}

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[Any, Dict[str, Any]]:
        """Starts an episode with an operator drawn from ``operators`` (or
        ``options["operator"]``); the first observation is all zeros."""
        super().reset(seed=seed)
        if options and "operator" in options:
            self.operator = str(options["operator"])
        else:
            self.operator = self.operators[int(self.np_random.integers(len(self.operators)))]
        adapter_seed = int(self.np_random.integers(2**63))
        self._adapter = trustcbr.Adapter(self.scenario, self._cases, seed=adapter_seed)
        observation = np.zeros(self._shape, dtype=np.float32)
        return observation, {"operator": self.operator}

    def step(self, action: Any) -> Tuple[Any, float, bool, bool, Dict[str, Any]]:
        """Uses the behavior ``action`` until the operator trusts it or gives it up."""
        if self._adapter is None:
            raise trustcbr.TrustcbrError("call reset() before step()")
        adapter = self._adapter
        behavior = self._behavior(action)
        if adapter.state()["episode"] is not None:
            adapter.abandon()
        adapter.begin(behavior)
        counts = np.zeros(self._shape, dtype=np.float32)
        untrustworthy = 0
        decision = "keep"
        for _ in range(self.max_commands):
            seed = int(self.np_random.integers(2**63))
            outcome = trustcbr.simulate(self.scenario, behavior, self.operator, seed)
            counts[0] += 1
            counts[1 + KINDS.index(outcome["outcome"])] += 1
            for name in outcome["observed"]:
                counts[1 + len(KINDS) + self.observations.index(name)] += 1
            untrustworthy += outcome["outcome"] != "completed"
            decision = adapter.tell_outcome(outcome).kind
            if decision != "keep":
                break
        terminated = decision == "settled"
        truncated = decision == "keep"
        info = {"operator": self.operator, "behavior": behavior, "trusted": terminated}
        return counts, -float(untrustworthy), terminated, truncated, info

    def close(self) -> None:
        """Removes the environment's scratch case base."""
        self._adapter = None
        self._dir.cleanup()
        super().close()
