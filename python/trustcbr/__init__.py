"""trustcbr for Python: trust-guided behavior adaptation with case-based reasoning.

A robot estimates its operator's trust from how commands end, switches behavior when the
estimate falls to a threshold, and stores each successful search as a case (after Floyd,
Drinkwater & Aha, ICCBR 2014). This package is the Rust library itself, compiled as one
extension module, with:

- :class:`Adapter`: the online adapter, ask/tell, over a built-in or RON-declared domain and
  a case base (SQLite, PostgreSQL or a read-only RON file), exactly as ``trustcbr serve``;
- :func:`simulate` and :func:`landscape`: the simulated ground robot, one command at a time,
  and every behavior's completion rate as a numpy array;
- :func:`run`: a suite of experiments, as ``trustcbr run``, with per-trial records, the
  summary, ``to_pandas()`` and the report folder;
- strategies written in Python as arms of those experiments (``python_arms=``), checked
  with :func:`check_searcher`;
- :mod:`trustcbr.gym`: a Gymnasium environment (with the ``gym`` extra).

Behaviors are plain dicts of component name to value in real units, e.g.
``{"speed": 3.5, "padding": 0.4}``. Every error is a :class:`TrustcbrError` carrying the
message the command-line tool prints.
"""

from __future__ import annotations

import importlib
import json
import math
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from trustcbr import _native
from trustcbr._native import TrustcbrError
from trustcbr._types import (
    Behavior,
    Decision,
    Evaluated,
    Outcome,
    Searcher,
    SearcherFactory,
    SimulatedOutcome,
    Space,
)

__version__: str = _native.__version__

__all__ = [
    "Adapter",
    "Behavior",
    "Decision",
    "Evaluated",
    "Landscape",
    "Outcome",
    "PythonArm",
    "Results",
    "Searcher",
    "SearcherFactory",
    "SimulatedOutcome",
    "Space",
    "TrustcbrError",
    "builtin_arms",
    "check_searcher",
    "default_suite",
    "landscape",
    "operators",
    "run",
    "scenarios",
    "simulate",
    "space",
]


def _dumps(value: Mapping[str, Any]) -> str:
    """JSON text of a request; JSON has no NaN or infinity, so they are refused."""
    try:
        return json.dumps(value, allow_nan=False)
    except ValueError:
        bad = [k for k, v in value.items() if isinstance(v, float) and not math.isfinite(v)]
        raise TrustcbrError(
            f"field `{bad[0] if bad else '?'}`: a finite number is required"
        ) from None


class Adapter:
    """The online trust adapter for one robot, ask/tell (``trustcbr serve`` in-process).

    ``domain`` is a built-in scenario (``"movement"``, ``"patrol"``) or a RON domain file;
    ``cases`` is the case base: an SQLite file (created when absent), a ``postgres://`` URL,
    or a ``.ron`` file (read-only). ``seed`` drives the search and the behaviors the
    adapter draws; ``arm`` serves a built-in arm's strategy instead of the domain's.
    With ``mission`` (``trustcbr serve --mission``) outcomes keep coming after an episode
    settles: the settled behavior is watched, a fall of its trust starts a new episode
    with a ``switch``, and an ``alert`` asks the operator to supervise.
    Several adapters (processes, robots) may share one SQLite or PostgreSQL case base.

    Every method sends one request of the protocol (docs/protocol.md) and returns its
    reply as a dict; a refused request raises :class:`TrustcbrError` and changes nothing.
    """

    def __init__(
        self,
        domain: str,
        cases: Union[str, os.PathLike[str]],
        *,
        seed: int = 0,
        arm: Optional[str] = None,
        mission: bool = False,
    ) -> None:
        self._session = _native.Session(str(domain), os.fspath(cases), seed, arm, mission)

    def _request(self, request: Mapping[str, Any]) -> Dict[str, Any]:
        reply: Dict[str, Any] = json.loads(self._session.request(_dumps(request)))
        return reply

    @property
    def location(self) -> str:
        """Where the cases are kept."""
        return self._session.location

    @property
    def writable(self) -> bool:
        """Whether retained cases are stored (a ``.ron`` case file is read-only)."""
        return self._session.writable

    def begin(self, behavior: Optional[Behavior] = None) -> Behavior:
        """Starts an episode with ``behavior``, or one drawn uniformly at random; returns it."""
        request: Dict[str, Any] = {"request": "begin"}
        if behavior is not None:
            request["behavior"] = dict(behavior)
        started: Behavior = self._request(request)["behavior"]
        return started

    def tell(
        self,
        outcome: str,
        *,
        weight: float = 1.0,
        duration_s: float = 0.0,
        observed: Sequence[str] = (),
        stated: Optional[str] = None,
        confidence: Optional[float] = None,
    ) -> Decision:
        """Reports how the last command ended and returns what to do next.

        ``outcome`` is ``"completed"``, ``"failed"`` or ``"interrupted"``; ``observed`` lists
        what the robot perceived itself (observations the domain declares); ``stated`` is
        the reason the operator gave, if any (a cause the domain declares); ``confidence``
        is the robot's own confidence in ``[0, 1]`` that the command went as it should, when
        it assesses itself. The decision is ``keep``, ``switch`` (use ``behavior`` from now
        on), ``settled`` (the episode is over), with the explanation of a switch or an end,
        or in mission mode ``alert`` (keep the behavior and ask the operator to supervise).
        """
        if isinstance(observed, str):
            raise TrustcbrError("field `observed`: a list of observation names, not a str")
        request: Dict[str, Any] = {
            "outcome": outcome,
            "weight": weight,
            "duration_s": duration_s,
            "observed": list(observed),
        }
        if stated is not None:
            request["stated"] = stated
        if confidence is not None:
            request["confidence"] = confidence
        return Decision(self._request(request))

    def tell_outcome(self, outcome: Mapping[str, Any]) -> Decision:
        """Reports an outcome given as a dict, such as :func:`simulate` returns (its
        ``truth`` is left out: a robot is never told it)."""
        request = {k: v for k, v in outcome.items() if k != "truth"}
        return Decision(self._request(request))

    def abandon(self) -> Dict[str, Any]:
        """Ends the episode under way without retaining a case (in mission mode, or the
        watch of a settled behavior)."""
        return self._request({"request": "abandon"})

    def state(self) -> Dict[str, Any]:
        """The episode under way (or ``None``), in mission mode the behavior watched between
        episodes (``watching``, or ``None``), and the number of cases."""
        return self._request({"request": "state"})

    def config(self) -> Dict[str, Any]:
        """The domain, its causes and observations, the space and the adapter config."""
        return self._request({"request": "config"})

    def explain(self) -> Dict[str, Any]:
        """The explanation of the episode so far."""
        return self._request({"request": "explain"})

    def cases(self) -> List[Dict[str, Any]]:
        """Every case of the case base, in real units, with its store id."""
        listed: List[Dict[str, Any]] = self._request({"request": "cases"})["cases"]
        return listed


def scenarios() -> List[str]:
    """The built-in scenarios (``movement``, ``patrol``)."""
    return list(_native.scenarios())


def operators(scenario: str) -> List[str]:
    """The built-in operators of ``scenario``."""
    return list(_native.operators(scenario))


def space(scenario: str) -> Space:
    """The behavior space of a built-in scenario: components (name, unit, values in real
    units), the number of behaviors, the declared causes and observations."""
    described: Dict[str, Any] = _native.space(scenario)
    return Space(
        components=described["components"],
        behaviors=int(described["behaviors"]),
        causes=[c["name"] for c in described["causes"]],
        observations=list(described["observations"]),
    )


def simulate(scenario: str, behavior: Behavior, operator: str, seed: int = 0) -> SimulatedOutcome:
    """Runs one command of a built-in scenario with ``behavior`` in front of ``operator``
    (a built-in name or an operator file), every random draw from ``seed``.

    Returns the outcome as the adapter is told it (``outcome``, ``weight``, ``duration_s``,
    ``observed``: what the robot perceived, ``stated``: the reason the operator gave, if
    any, and ``confidence`` when the robot assesses itself) and ``truth``, the operator's
    true reason, for evaluation only.
    """
    result: SimulatedOutcome = _native.simulate(scenario, dict(behavior), operator, seed)
    return result


@dataclass(frozen=True)
class Landscape:
    """The share of commands an operator lets complete, for every behavior.

    ``p_complete[i, j, ...]`` is the behavior whose components take ``values[0][i]``,
    ``values[1][j]``, ...; ``components`` names the axes.
    """

    p_complete: "np.ndarray[Any, np.dtype[np.float64]]"
    components: List[str]
    values: List[List[Union[float, str]]]
    runs: int

    def behavior(self, index: Sequence[int]) -> Behavior:
        """The behavior at an index of :attr:`p_complete`."""
        return {name: self.values[k][i] for k, (name, i) in enumerate(zip(self.components, index))}


def landscape(scenario: str, operator: str, runs: int = 100, seed: int = 0) -> Landscape:
    """Estimates every behavior's completion rate under ``operator`` from ``runs`` commands
    each (``trustcbr landscape``'s estimate), on every core."""
    shares, lengths, names = _native.landscape(scenario, operator, runs, seed)
    values = [c["values"] for c in space(scenario)["components"]]
    array = np.asarray(shares, dtype=np.float64).reshape(tuple(lengths))
    return Landscape(p_complete=array, components=list(names), values=values, runs=runs)


def default_suite() -> str:
    """The embedded suite (the paper's seven experiments) as RON, as ``trustcbr config``."""
    return str(_native.default_suite())


def builtin_arms() -> List[str]:
    """The built-in arms, in report order."""
    return list(_native.builtin_arms())


@dataclass(frozen=True)
class PythonArm:
    """An arm whose search strategy is written in Python.

    ``factory(space)`` builds one searcher per chain of trials (an experiment's trials for
    this arm, in order), or one per trial when the trials are independent (no case reuse,
    ``learns_across_episodes`` false, no operator states a reason); see :class:`Searcher`
    for its methods. With ``reuses_cases`` the
    arm reuses cases first (Algorithm 1, the suite's retriever) and falls back on the
    searcher, as ``case-based+NAME`` arms do.
    """

    factory: SearcherFactory
    reuses_cases: bool = False


@dataclass
class Results:
    """What a suite run returns: one record per trial (``trials.jsonl``), the summary
    (``summary.json``), the results table (Markdown) and the config that ran."""

    trials: List[Dict[str, Any]]
    summary: Dict[str, Any]
    table: str
    config: Dict[str, Any]
    out: Optional[str] = field(default=None)

    def to_pandas(self) -> Any:
        """The per-trial records as a ``pandas.DataFrame``, one row per trial (needs pandas)."""
        try:
            pd = importlib.import_module("pandas")
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("to_pandas() needs pandas: pip install pandas") from e
        return pd.DataFrame.from_records(self.trials)

    def arms(self, experiment: int = 0) -> Dict[str, Dict[str, Any]]:
        """The summary of every arm of an experiment, by arm name."""
        strategies: Dict[str, Dict[str, Any]] = self.summary["experiments"][experiment][
            "strategies"
        ]
        return strategies


def run(
    suite: Union[None, str, os.PathLike[str], Mapping[str, Any]] = None,
    *,
    text: Optional[str] = None,
    out: Union[None, str, os.PathLike[str]] = None,
    trials: Optional[int] = None,
    seed: Optional[int] = None,
    arms: Optional[Sequence[str]] = None,
    landscape_runs: Optional[int] = None,
    threads: Optional[int] = None,
    python_arms: Optional[Mapping[str, Union[PythonArm, SearcherFactory]]] = None,
    save_cases: Union[None, str, os.PathLike[str]] = None,
    cases: Union[None, str, os.PathLike[str]] = None,
) -> Results:
    """Runs a suite of experiments as ``trustcbr run`` does.

    ``suite`` is a RON file's path, a dict with the file's fields, or ``None`` for the
    embedded suite; ``text`` gives RON text instead. ``trials``, ``seed``, ``arms``,
    ``landscape_runs``, ``threads``, ``save_cases`` and ``cases`` are ``run``'s options.
    ``python_arms`` maps arm names to :class:`PythonArm` (or a bare factory); name them in
    ``arms`` (or the suite's) to run them, paired trial by trial with the built-in arms.
    With Python arms the run is single-threaded (Python runs one thread at a time).
    ``out`` writes the report folder (``report.html``, ``table.md``, ``summary.json``,
    ``trials.jsonl``, ...) as ``trustcbr run --out`` does.
    """
    if text is not None:
        if suite is not None:
            raise TrustcbrError("give a suite or its text, not both")
        kind, body, origin = "ron", text, "<text>"
    elif suite is None:
        kind, body, origin = "embedded", "", ""
    elif isinstance(suite, Mapping):
        kind, body, origin = "json", _dumps(suite), "<dict>"
    else:
        kind, body, origin = "file", "", os.fspath(suite)
    added = []
    for name, arm in (python_arms or {}).items():
        if not isinstance(arm, PythonArm):
            arm = PythonArm(arm)
        added.append((name, arm.factory, arm.reuses_cases))
    trials_jsonl, summary, table, config = _native.run_suite(
        kind,
        body,
        origin,
        out=None if out is None else os.fspath(out),
        trials=trials,
        seed=seed,
        landscape_runs=landscape_runs,
        arms=None if arms is None else list(arms),
        threads=threads,
        python_arms=added,
        save_cases=None if save_cases is None else os.fspath(save_cases),
        cases=None if cases is None else os.fspath(cases),
    )
    return Results(
        trials=[json.loads(line) for line in trials_jsonl.splitlines() if line],
        summary=json.loads(summary),
        table=table,
        config=json.loads(config),
        out=None if out is None else os.fspath(out),
    )


def check_searcher(factory: SearcherFactory) -> None:
    """Runs the searcher conformance kit over searchers built by ``factory(space)`` on
    random small spaces: proposals in the space, never an evaluated behavior while one is
    untried, ``None`` only when every behavior was tried, the same proposals for the same
    seed, and no change after an episode unless ``learns_across_episodes``. Raises
    :class:`TrustcbrError` naming the property broken, or the searcher's own exception."""
    _native.check_searcher(factory)
