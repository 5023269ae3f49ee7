"""The shapes trustcbr's values take in Python: behaviors, outcomes, spaces, decisions and
the protocol a search strategy written in Python follows."""

from __future__ import annotations

import random
import sys
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Union

if sys.version_info >= (3, 11):  # pragma: no cover - depends on the interpreter
    from typing import NotRequired, Protocol, TypedDict
else:  # pragma: no cover
    from typing import Protocol

    from typing_extensions import NotRequired, TypedDict

Behavior = Dict[str, Union[float, str]]
"""A behavior: component name to value in real units (a number, or a label)."""


class Evaluated(TypedDict):
    """A behavior given up in the episode and how long it resisted (task seconds)."""

    behavior: Behavior
    time: float


class Outcome(TypedDict):
    """How a command ended, as the adapter is told it (``confidence``: the robot's own, in
    ``[0, 1]``, when it assesses itself)."""

    outcome: str
    weight: float
    duration_s: float
    observed: List[str]
    stated: Optional[str]
    confidence: NotRequired[float]


class SimulatedOutcome(Outcome):
    """A simulated command's outcome, with the operator's true reason (evaluation only)
    and the seed it was drawn from (the same seed gives the same command)."""

    truth: Optional[str]
    seed: int


class Strategy(TypedDict):
    """A registered search strategy (:func:`trustcbr.strategies`): its name (the arm of it
    alone), what it does, the arm of it after case reuse (``None``: not offered so) and
    whether what it learns carries from one episode to the next."""

    name: str
    description: str
    case_based: Optional[str]
    learns_across_episodes: bool


class Component(TypedDict):
    """One component of a behavior space and its values in real units."""

    name: str
    unit: str
    values: List[Union[float, str]]


class Space(TypedDict):
    """A behavior space (as :func:`trustcbr.space` describes a scenario's)."""

    components: List[Component]
    behaviors: int
    causes: NotRequired[List[str]]
    observations: NotRequired[List[str]]


class Decision:
    """What the adapter says after an outcome: ``kind`` is ``keep``, ``switch``,
    ``settled`` or, in mission mode, ``alert`` and (a robot judging its own competence)
    ``overtrust``; ``behavior`` is the behavior to use from now on (the one settled on, the
    one kept by an alert); ``explanation`` says why, for a switch and an end; ``sentence``
    says it in one plain sentence (an alert's asks the operator to supervise, an
    overtrust's to choose); ``trust`` is the estimate it was made on; ``short`` lists the
    parts of the robot's own assessment above its standard (``overtrust``); ``reply`` is
    the whole reply (trust estimate, source of a switch, counts at the end, an alert's own
    record, an overtrust's competence estimate)."""

    __slots__ = ("reply",)

    def __init__(self, reply: Dict[str, Any]) -> None:
        self.reply = reply

    @property
    def kind(self) -> str:
        """``keep``, ``switch``, ``settled``, ``alert`` or ``overtrust``."""
        return str(self.reply["ok"])

    @property
    def short(self) -> List[str]:
        """The parts the robot judges surely above its standard (``overtrust``), else
        empty."""
        return [str(part) for part in self.reply.get("short", [])]

    @property
    def offer(self) -> Optional[Behavior]:
        """The safer behavior an ``overtrust`` decision offers (one an operator trusted
        before that the robot judges competent; take it with ``Adapter.accept_offer``),
        else ``None``."""
        offer: Optional[Behavior] = self.reply.get("offer")
        return offer

    @property
    def behavior(self) -> Behavior:
        """The behavior in use from now on."""
        behavior: Behavior = self.reply["behavior"]
        return behavior

    @property
    def explanation(self) -> Optional[Dict[str, Any]]:
        """Why the behavior was given up and why the next one (a switch, an end)."""
        explanation: Optional[Dict[str, Any]] = self.reply.get("explanation")
        return explanation

    @property
    def sentence(self) -> Optional[str]:
        """The explanation as one plain sentence, or an alert's request for supervision,
        when there is one."""
        source = self.reply if self.explanation is None else self.explanation
        sentence = source.get("sentence")
        return None if sentence is None else str(sentence)

    @property
    def trust(self) -> float:
        """The trust estimate the decision was made on: the behavior in use's after the
        outcome (``keep``, ``alert``), the given-up behavior's last (``switch``: the new
        behavior starts at 0), the settled behavior's (``settled``)."""
        if "trust" in self.reply:
            return float(self.reply["trust"])
        explanation = self.explanation or {}
        given_up = explanation.get("given_up")
        if self.kind == "switch" and given_up is not None:
            return float(given_up["trust"])
        kept = explanation.get("next") or {}
        if "trust" in kept:
            return float(kept["trust"])
        if given_up is not None:
            return float(given_up["trust"])
        return 0.0

    def __repr__(self) -> str:
        return f"Decision(kind={self.kind!r}, behavior={self.behavior!r}, trust={self.trust:+.2f})"


@dataclass(frozen=True)
class ContextSwitch:
    """What a robot on a mission did when told its context switched
    (``Adapter.switch_context``): ``behavior`` is the behavior to use from now on;
    ``origin`` says where it comes from: ``kept`` (the watched behavior, still watched),
    ``resumed`` (the behavior last settled on, trusted, in the new context since the
    operator began, and not given up there since: an episode begins from it),
    ``restarted`` (the episode under way begins again, in the new context, from the
    behavior in use); ``gave_up_watch`` whether a
    watched behavior was given up; ``context`` the robot's context now, its defaults left
    out."""

    behavior: Behavior
    origin: str
    gave_up_watch: bool
    context: Dict[str, str]


class Searcher(Protocol):
    """A search strategy written in Python (only ``propose`` is required).

    Optional: ``enter_context(context)`` (the robot's context, a dict of the variables
    away from their defaults, told between episodes), ``begin_episode(initial)``,
    ``hear(stated)`` (what the episode's operator stated up front, right after
    ``begin_episode``: a list of ``{"name": ..., "minds": bool}``, possibly empty,
    incomplete or wrong), ``observe(behavior, outcome)``,
    ``end_episode(evaluated, settled)``, ``rationale(proposed)`` (a str, one plain line
    saying how it explores, or a dict ``{"expects": what, "confidence": p}`` saying what it
    expects of the proposal, ``p`` a probability or ``None``),
    ``doubts(evaluated, behavior)`` (true when it expects ``behavior`` to be found
    untrustworthy: an arm that reuses cases then passes over every case proposing it),
    and ``learns_across_episodes = True`` for a strategy that carries anything from one
    episode into the next.
    """

    def propose(self, evaluated: List[Evaluated], rng: random.Random) -> Optional[Behavior]:
        """The next behavior to try, given the episode's evaluated behaviors in order and a
        random source seeded from the trial's search stream (draw only from it); ``None``
        when every behavior has been tried (the one that resisted longest is kept)."""
        ...


SearcherFactory = Callable[[Space], Searcher]
"""Builds a fresh searcher for a behavior space."""
