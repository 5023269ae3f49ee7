"""Gymnasium environments over trustcbr's simulated robot (needs the ``gym`` extra:
``pip install ./python[gym]``).

Importing this module registers ``trustcbr/Movement-v0`` and ``trustcbr/Patrol-v0``, so
``gymnasium.make("trustcbr/Patrol-v0")`` works after ``import trustcbr.gym``; each is
capped at :data:`MAX_EPISODE_STEPS` behaviors an episode by Gymnasium's ``TimeLimit``
(a truncation).

One episode is one operator (drawn from the scenario's built-in operators, or the ones
given); an action is a behavior, one value index per component (``MultiDiscrete``); a
step runs the behavior's commands in front of the operator, each recorded in the
library's trust estimate (the paper's thresholds, +5 and -5), until the operator trusts
it (the episode terminates) or stops trusting it (the step ends and the agent picks
another behavior). A behavior still undecided after ``max_commands`` commands truncates
the episode. The loop runs natively (``trustcbr._native.Episodes``): a step costs
microseconds, not the simulator's Python round trips.

The observation is a ``Box`` of float32: the behavior's number of commands, how many
ended completed, failed and interrupted, how many perceived each declared observation,
then the action just taken (its value indices; -1 before the first step) and the trust
estimate it ended with. The reward is minus the behavior's untrustworthy commands
(failed or interrupted). ``render_mode="rgb_array"`` draws one run of the last behavior
under the episode's operator (the scenario's map drawing, as ``trustcbr render``).
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple

import gymnasium
import numpy as np
from gymnasium import spaces

import trustcbr
from trustcbr import TrustcbrError

KINDS = ("completed", "failed", "interrupted")

MAX_EPISODE_STEPS = 100
"""Behaviors an episode may try before it is truncated (the registered environments'
``max_episode_steps``, and ``TrustEnv``'s ``max_behaviors`` by default)."""


TRUST_BOUND = 1e6
"""The trust estimate in the observation is clipped to plus or minus this (a step ends
within one command of a threshold, +5 or -5, so only an extreme weight comes near it)."""


def _svg_to_rgb(svg: str) -> "np.ndarray[Any, np.dtype[np.uint8]]":
    rendered: Any = trustcbr._native.rasterize(svg)
    width, height, pixels = rendered
    return np.frombuffer(pixels, dtype=np.uint8).reshape(height, width, 4)[:, :, :3].copy()


class TrustEnv(gymnasium.Env[Any, Any]):
    """Find a behavior the operator trusts, with as few untrustworthy commands as possible.

    ``scenario`` is a scenario of the catalog (built in: ``movement``, ``patrol``);
    ``operators`` names the operators an episode draws from (built-in names or operator
    files, a non-empty list; default: every built-in one); ``max_commands`` (1 to
    1,000,000) ends a behavior's step when its trust stays between the thresholds that
    long (the episode is then truncated); ``max_behaviors`` truncates an episode after
    that many steps (``None``: no cap, as for the registered ids, which ``TimeLimit``
    caps); ``catalog`` is another catalog's extension module; ``attention`` (0 to 1, default
    1: the paper's attentive operator) is the operators' attention, below 1 only in a
    scenario whose domain models it (they then overlook some of what they would stop).

    A step's commands are simulated as every experiment's and mission's are: the
    operator's attention applies, and its feedback channel states reasons
    (``info["stated"]``: the step's commands the operator said why it stopped or failed).
    """

    metadata: Dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 1}

    def __init__(
        self,
        scenario: str = "movement",
        operators: Optional[Sequence[str]] = None,
        max_commands: int = 500,
        max_behaviors: Optional[int] = MAX_EPISODE_STEPS,
        render_mode: Optional[str] = None,
        catalog: Any = None,
        attention: float = 1.0,
    ) -> None:
        super().__init__()
        if render_mode not in (None, "rgb_array"):
            raise TrustcbrError(f"render_mode: None or 'rgb_array', got {render_mode!r}")
        if isinstance(operators, str):
            raise TrustcbrError(
                f"operators: a list of operator names, not a str (write operators=[{operators!r}])"
            )
        if operators is not None and len(operators) == 0:
            raise TrustcbrError(
                "operators: an empty list; name at least one operator, or give None for "
                "every built-in one"
            )
        if isinstance(max_commands, bool) or not isinstance(max_commands, int):
            raise TrustcbrError(f"max_commands: a whole number, got {max_commands!r}")
        if not 1 <= max_commands <= 1_000_000:
            raise TrustcbrError(f"max_commands: must be 1 to 1000000, got {max_commands}")
        if max_behaviors is not None and (
            isinstance(max_behaviors, bool)
            or not isinstance(max_behaviors, int)
            or max_behaviors < 1
        ):
            raise TrustcbrError(
                f"max_behaviors: a whole number from 1, or None, got {max_behaviors!r}"
            )
        if isinstance(attention, bool) or not isinstance(attention, (int, float)):
            raise TrustcbrError(f"attention: a share from 0 to 1, got {attention!r}")
        module: Any = trustcbr._native if catalog is None else catalog
        described = trustcbr.space(scenario, catalog=catalog)
        self.scenario = scenario
        self.operators: List[str] = (
            list(operators)
            if operators is not None
            else trustcbr.operators(scenario, catalog=catalog)
        )
        if not self.operators:
            raise TrustcbrError(f"scenario `{scenario}` has no built-in operators: name them")
        self.components = described["components"]
        self.observations: List[str] = list(described.get("observations", []))
        self.max_commands = max_commands
        self.max_behaviors = max_behaviors
        self.render_mode = render_mode
        # Every operator is loaded now: an unknown one is refused here, not at reset.
        self._episodes: Any = module.episodes(
            scenario, self.operators, max_commands, float(attention)
        )
        self.attention = float(attention)
        sizes = [len(c["values"]) for c in self.components]
        self.action_space = spaces.MultiDiscrete(sizes)
        counts = 1 + len(KINDS) + len(self.observations)
        low = np.concatenate([np.zeros(counts), -np.ones(len(sizes)), [-TRUST_BOUND]]).astype(
            np.float32
        )
        high = np.concatenate(
            [np.full(counts, float(max_commands)), np.array(sizes) - 1, [TRUST_BOUND]]
        ).astype(np.float32)
        self.observation_space = spaces.Box(low=low, high=high, dtype=np.float32)
        self._shape = low.shape
        self._counts = counts
        self.operator = self.operators[0]
        self._ended: Optional[str] = "call reset() before step()"
        self._steps = 0
        self._last: Optional[List[int]] = None
        self._render_seed = 0

    def _action(self, action: Any) -> List[int]:
        """The action as value indices, or a refusal naming what is wrong."""
        names = ", ".join(c["name"] for c in self.components)
        array = np.asarray(action)
        if array.dtype == np.bool_ or not np.issubdtype(array.dtype, np.integer):
            raise TrustcbrError(
                f"action: value indices (integers), one per component ({names}), got "
                f"{array.dtype} {action!r}"
            )
        if array.ndim != 1 or array.shape[0] != len(self.components):
            raise TrustcbrError(
                f"action: {len(self.components)} value indices, one per component "
                f"({names}), got shape {array.shape}"
            )
        indices = [int(i) for i in array]
        for c, i in zip(self.components, indices):
            if not 0 <= i < len(c["values"]):
                raise TrustcbrError(
                    f"action: {i} is not a value index of `{c['name']}` "
                    f"(0 to {len(c['values']) - 1})"
                )
        return indices

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[Any, Dict[str, Any]]:
        """Starts an episode with an operator drawn from ``operators`` (or
        ``options["operator"]``, a built-in name or an operator file); the first
        observation is zeros, with no action yet (-1)."""
        super().reset(seed=seed)
        if options and "operator" in options:
            self.operator = str(options["operator"])
        else:
            self.operator = self.operators[int(self.np_random.integers(len(self.operators)))]
        episode_seed = int(self.np_random.integers(2**63))
        self._episodes.reset(self.operator, episode_seed)
        self._render_seed = episode_seed
        self._ended = None
        self._steps = 0
        self._last = None
        observation = np.zeros(self._shape, dtype=np.float32)
        observation[self._counts : self._counts + len(self.components)] = -1.0
        return observation, {"operator": self.operator}

    def step(self, action: Any) -> Tuple[Any, float, bool, bool, Dict[str, Any]]:
        """Uses the behavior ``action`` until the operator trusts it or gives it up."""
        if self._ended is not None:
            raise TrustcbrError(f"step() after the episode ended ({self._ended}): call reset()")
        indices = self._action(action)
        result = self._episodes.step(indices)
        completed, failed, interrupted = result["kinds"]
        observation = np.empty(self._shape, dtype=np.float32)
        observation[0] = completed + failed + interrupted
        observation[1:4] = result["kinds"]
        observation[4 : self._counts] = result["observed"]
        observation[self._counts : self._counts + len(indices)] = indices
        observation[-1] = min(TRUST_BOUND, max(-TRUST_BOUND, result["trust"]))
        self._steps += 1
        self._last = indices
        end = result["end"]
        terminated = end == "trusted"
        truncated = end == "undecided" or (
            not terminated and self.max_behaviors is not None and self._steps >= self.max_behaviors
        )
        if terminated:
            self._ended = "the operator trusted the last behavior"
        elif truncated:
            self._ended = (
                "a behavior stayed undecided for max_commands"
                if end == "undecided"
                else "max_behaviors behaviors were tried"
            )
        behavior = {c["name"]: c["values"][i] for c, i in zip(self.components, indices)}
        info = {
            "operator": self.operator,
            "behavior": behavior,
            "trusted": terminated,
            "end": end,
            "trust": result["trust"],
            "stated": result["stated"],
        }
        return observation, -float(failed + interrupted), terminated, truncated, info

    def render(self) -> Any:
        """With ``render_mode="rgb_array"``: one run of the last behavior under the
        episode's operator, as an RGB array (a white frame before the first step)."""
        if self.render_mode != "rgb_array":
            return None
        action = self._last if self._last is not None else [0] * len(self.components)
        svg = self._episodes.render(action, self._render_seed)
        if svg is None:
            raise TrustcbrError(f"scenario `{self.scenario}` has no drawing of its runs")
        frame = _svg_to_rgb(svg)
        if self._last is None:
            frame[:] = 255
        return frame

    def close(self) -> None:
        """Nothing to release (the episodes live in memory)."""
        super().close()


for _id, _scenario in (("trustcbr/Movement-v0", "movement"), ("trustcbr/Patrol-v0", "patrol")):
    if _id not in gymnasium.registry:
        gymnasium.register(
            id=_id,
            entry_point="trustcbr.gym:TrustEnv",
            kwargs={"scenario": _scenario, "max_behaviors": None},
            max_episode_steps=MAX_EPISODE_STEPS,
        )
